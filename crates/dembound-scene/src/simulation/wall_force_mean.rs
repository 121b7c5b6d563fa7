//! Each wall's force averaged over every step of an interval, not sampled
//! at its last step: what LAMMPS's `fix ave/time 1 N N` writes (the
//! exported deck's `walls_mean.txt`, docs/export-lammps.md, "Wall forces:
//! one step or every step"). In a flowing or vibrating bed the force of one
//! step scatters by tens of percent from row to row; the mean of every
//! step does not carry that sampling noise.

use super::Simulation;
use crate::pipeline::WallForceSum;

impl Simulation {
    /// Starts (or starts again, from zero) summing each wall's force after
    /// every step that follows, for [`Self::take_wall_force_mean`]: F_s, the
    /// force [`Self::wall_forces`] reports after step s (the force pass that
    /// ended it), component by component. The steps stay the same as
    /// without the sum to the bit: the stepping loop then leaves its Verlet
    /// steps unfused (the fused form does the same operations in the same
    /// order; the tests below check the bits). One process only (a rank of
    /// a decomposed scene holds its share of the loads).
    pub fn start_wall_force_mean(&mut self) {
        let walls = self.world.walls.len();
        self.pipeline.wall_force_sum = Some(WallForceSum {
            force: vec![[0.0; 3]; walls],
            steps: 0,
        });
    }

    /// Each wall's force (file order, N) averaged over every step since
    /// [`Self::start_wall_force_mean`]: (Σ F_s)/n over the n steps s taken
    /// since, however they were grouped into calls of [`Self::step`]. Stops
    /// the sum. `None` when no sum was started or no step was taken since
    /// (no step, no mean).
    pub fn take_wall_force_mean(&mut self) -> Option<Vec<[f64; 3]>> {
        let sum = self.pipeline.wall_force_sum.take()?;
        if sum.steps == 0 {
            return None;
        }
        let count = sum.steps as f64;
        Some(
            sum.force
                .into_iter()
                .map(|f| [f[0] / count, f[1] / count, f[2] / count])
                .collect(),
        )
    }

    /// Advances `n` steps and returns each wall's force averaged over them
    /// ([`Self::start_wall_force_mean`], [`Self::step`]`(n)`,
    /// [`Self::take_wall_force_mean`]): (Σ F_s)/n over the steps s = k+1 …
    /// k+n. `None` when `n` is 0 (no step, no mean).
    pub fn step_wall_force_mean(&mut self, n: u64) -> Option<Vec<[f64; 3]>> {
        if n == 0 {
            return None;
        }
        self.start_wall_force_mean();
        self.step(n);
        self.take_wall_force_mean()
    }
}

#[cfg(test)]
mod tests {
    use crate::io::{config, resolve::resolve};
    use crate::Simulation;

    /// A frictional Hertz–Tsuji bed of 27 spheres dropped on a plane floor
    /// between four planes, thrown sideways (+x, +y: the floor and the
    /// walls at x, y = 4.2 mm carry force).
    fn bed(steps: u64) -> Simulation {
        let text = format!(
            r#"
[domain]
lower = [0.0, 0.0, 0.0]
upper = [0.0042, 0.0042, 0.01]
[[material]]
name = "grain"
density = 1000.0
youngs_modulus = 1.0e7
poisson_ratio = 0.3
[contact]
law = "hertz"
damping = "tsuji"
restitution = 0.3
friction = 0.5
tangential_damping = false
[[particles]]
lattice = {{ counts = [3, 3, 3], spacing = [1.2e-3, 1.2e-3, 0.6e-3], origin = [0.6e-3, 0.6e-3, 0.52e-3], radius = 0.5e-3, velocity = [0.05, 0.03, -0.1] }}
material = "grain"
[[wall]]
plane = {{ point = [0.0, 0.0, 0.0], normal = [0.0, 0.0, 1.0] }}
material = "grain"
[[wall]]
plane = {{ point = [0.0, 0.0, 0.0], normal = [1.0, 0.0, 0.0] }}
material = "grain"
[[wall]]
plane = {{ point = [0.0042, 0.0, 0.0], normal = [-1.0, 0.0, 0.0] }}
material = "grain"
[[wall]]
plane = {{ point = [0.0, 0.0, 0.0], normal = [0.0, 1.0, 0.0] }}
material = "grain"
[[wall]]
plane = {{ point = [0.0, 0.0042, 0.0], normal = [0.0, -1.0, 0.0] }}
material = "grain"
[motion]
gravity = [0.0, 0.0, -9.81]
[integration]
scheme = "verlet"
dt = 2.0e-6
steps = {steps}
"#
        );
        let file = config::load(&text, "test", &[]).expect("a valid scene");
        let setup = resolve(&file, std::path::Path::new("."))
            .expect("resolves")
            .setup;
        Simulation::new(setup, 1).expect("builds")
    }

    /// The mean over 100 steps equals the mean, computed here, of the 100
    /// forces `wall_forces()` reports after each single step (another
    /// path: the whole observation, one `step(1)` at a time). Stepping one
    /// at a time splits Verlet's fused half kicks, so the two runs part at
    /// round-off (~1e-16 a step): 1e-9 of the largest force is far above
    /// that and far below the difference one sampled step would make (the
    /// force of one step differs from the interval's mean by percents).
    /// Also: the stepped state and forces are the same to the bit as
    /// `step(n)`'s, and a sum started once and taken after the interval's
    /// steps in uneven calls (37 + 63, as `dembound scene` steps between
    /// rows) gives the same bits as the one call.
    #[test]
    fn the_mean_is_the_mean_of_every_steps_force() {
        let (rows, every) = (20u64, 100u64);
        let mut by_mean = bed(rows * every);
        let mut by_step = bed(rows * every);
        let mut plain = bed(rows * every);
        let mut in_calls = bed(rows * every);
        let mut touched = [false; 5];
        assert_eq!(in_calls.take_wall_force_mean(), None, "not started");
        for _ in 0..rows {
            let mean = by_mean.step_wall_force_mean(every).expect("n > 0");
            in_calls.start_wall_force_mean();
            in_calls.step(37);
            in_calls.step(every - 37);
            assert_eq!(in_calls.take_wall_force_mean().as_ref(), Some(&mean));
            let mut sum = vec![[0.0f64; 3]; 5];
            for _ in 0..every {
                by_step.step(1);
                for (s, f) in sum.iter_mut().zip(by_step.wall_forces()) {
                    for (x, v) in s.iter_mut().zip(f) {
                        *x += v;
                    }
                }
            }
            let scale = sum
                .iter()
                .flatten()
                .map(|v| (v / every as f64).abs())
                .fold(0.0, f64::max);
            for (w, (m, s)) in mean.iter().zip(&sum).enumerate() {
                for (a, (got, total)) in m.iter().zip(s).enumerate() {
                    let expected = total / every as f64;
                    assert!(
                        (got - expected).abs() <= 1e-9 * scale.max(1e-12),
                        "wall {w} axis {a}: {got} vs {expected}"
                    );
                    touched[w] |= *got != 0.0;
                }
            }
            plain.step(every);
            assert_eq!(plain.positions(), by_mean.positions());
            assert_eq!(plain.wall_forces(), by_mean.wall_forces());
        }
        // Not vacuous: the floor and the two walls thrown at carried force.
        assert!(
            touched[0] && touched[2] && touched[4],
            "a wall never touched: {touched:?}"
        );
        assert_eq!(by_mean.step_wall_force_mean(0), None);
        // Started, no step since: no mean.
        in_calls.start_wall_force_mean();
        assert_eq!(in_calls.take_wall_force_mean(), None);
    }

    /// One sphere resting on the floor under gravity, released in contact
    /// at its static overlap and damped to rest: the mean force on the
    /// floor over the last 1000 steps is its weight m g (ρ 4/3 π R³ g,
    /// computed here), pointing down, to 1e-6 (the residual oscillation of
    /// a Tsuji-damped contact after 40000 steps with e = 0.3 is far below).
    #[test]
    fn a_resting_sphere_loads_the_floor_with_its_weight() {
        let (rho, r, g) = (1000.0f64, 0.5e-3f64, 9.81f64);
        let text = r#"
[domain]
lower = [0.0, 0.0, 0.0]
upper = [0.004, 0.004, 0.004]
[[material]]
name = "grain"
density = 1000.0
youngs_modulus = 1.0e7
poisson_ratio = 0.3
[contact]
law = "hertz"
damping = "tsuji"
restitution = 0.3
[[particles]]
spheres = [ { position = [0.002, 0.002, 0.0005], radius = 0.5e-3 } ]
material = "grain"
[[wall]]
plane = { point = [0.0, 0.0, 0.0], normal = [0.0, 0.0, 1.0] }
material = "grain"
[motion]
gravity = [0.0, 0.0, -9.81]
[integration]
scheme = "verlet"
dt = 2.0e-6
steps = 41000
"#;
        let file = config::load(text, "test", &[]).expect("a valid scene");
        let setup = resolve(&file, std::path::Path::new("."))
            .expect("resolves")
            .setup;
        let mut sim = Simulation::new(setup, 1).expect("builds");
        sim.step(40000);
        let mean = sim.step_wall_force_mean(1000).expect("n > 0");
        let weight = rho * 4.0 / 3.0 * std::f64::consts::PI * r.powi(3) * g;
        assert!(
            (mean[0][2] / -weight - 1.0).abs() < 1e-6,
            "floor {:?} N, weight {weight} N",
            mean[0]
        );
        assert!(mean[0][0].abs() < 1e-12 * weight && mean[0][1].abs() < 1e-12 * weight);
    }
}
