//! Walls that appear and vanish (`[[wall]] active = { from, to }`, issue
//! 28) in the LIGGGHTS scene deck: the run is written in segments, `run
//! N₁`, the switch (the wall's `fix wall/gran`, and for a mesh its `fix
//! mesh/surface`, written or `unfix`ed), `run N₂`. The steps are
//! dembound's: a wall acts on states `on..off`, `on` the first state n
//! with n Δt ≥ t₀ and `off` the first with n Δt ≥ t₁
//! (`ActiveWindow::steps`), as in the LAMMPS deck (`lammps_gates.rs`).
//!
//! **The half kick at a switch.** dembound switches a wall before the
//! forces of the state of the switch, so both half kicks around it use
//! the forces of the new set of walls. A `run` ending at that state has
//! already given every sphere the second half kick Δt/2 F_old/m of the
//! old set (velocity Verlet). The deck takes it back whole: v −= Δt/2
//! F/m with the forces the run left, the switch, `run 0` (LIGGGHTS's
//! setup computes the forces of the new set at the same positions),
//! v += Δt/2 F/m. This corrects an opening gate and a gate that closes
//! into an overlapping sphere alike. Not corrected: the angular half
//! kick of a frictional wall's torque (Δt/2 τ/I on the spheres touching
//! the gate at the switch; LIGGGHTS's atom-style variables do not read
//! the torque); a switch at the run's last state is not written (the
//! run ends before it acts).

use std::fmt::Write as _;

use dembound_scene::SceneSetup;

/// One wall's deck lines: written where it appears, and the lines that
/// remove it.
pub(crate) struct WallLines {
    /// The wall's index in `[[wall]]`.
    pub wall: usize,
    /// Its `fix` lines (comments included).
    pub add: String,
    /// Its `unfix` lines.
    pub remove: String,
}

/// The states (`on`, `off`) each wall acts on (`on..off`; (0, u64::MAX)
/// for a wall without `active`), at step `dt` (s).
pub(crate) fn windows(setup: &SceneSetup, dt: f64) -> Vec<(u64, u64)> {
    (0..setup.walls.len())
        .map(|w| match setup.wall_active.get(w).copied().flatten() {
            None => (0, u64::MAX),
            Some(window) => window.steps(dt),
        })
        .collect()
}

/// Whether a wall with window `(on, off)` acts at state 0.
pub(crate) fn on_at_start((on, off): (u64, u64)) -> bool {
    on == 0 && off > 0
}

/// The lines that take back (`sign` −1) or give (`sign` +1) the half kick
/// Δt/2 F/m of the forces LIGGGHTS holds, for every sphere.
fn half_kick(x: &mut String, dt: f64, sign: f64) {
    for c in ["x", "y", "z"] {
        writeln!(
            x,
            "variable     gate_v{c} atom v{c}+{}*f{c}/mass",
            crate::num(sign * 0.5 * dt)
        )
        .ok();
    }
    writeln!(
        x,
        "velocity     all set v_gate_vx v_gate_vy v_gate_vz\n\
         variable     gate_vx delete\nvariable     gate_vy delete\nvariable     gate_vz delete"
    )
    .ok();
}

/// The `run` commands of a run of `steps` steps of `dt` (s), with the
/// switches of the gated walls (`windows` per wall) in between; `walls`
/// the deck lines of every written wall.
/// With `outlets`, the spheres in the outlets are removed at every
/// multiple of `outlets::EVERY` steps (`outlets::run_lines`).
pub(crate) fn runs(
    steps: u64,
    dt: f64,
    windows: &[(u64, u64)],
    walls: &[WallLines],
    outlets: Option<&crate::outlets::Outlets>,
) -> String {
    let events = crate::lammps_gates::switch_events(steps, windows, walls, |l| l.wall);
    let mut x = String::new();
    let mut done = 0;
    let mut i = 0;
    while i < events.len() {
        let step = events[i].0;
        if step > done {
            x.push_str(&crate::outlets::run_lines(done, step - done, outlets));
            done = step;
        }
        writeln!(
            x,
            "# switch at step {step} (t = {} s): take back the half kick of the forces the run left\n\
             # (dembound's state {step} has the forces of the new set of walls only)",
            crate::num(step as f64 * dt)
        )
        .ok();
        half_kick(&mut x, dt, -1.0);
        while i < events.len() && events[i].0 == step {
            let (_, arrives, l) = events[i];
            let w = l.wall;
            if arrives {
                writeln!(x, "# wall[{w}] appears").ok();
                x.push_str(&l.add);
            } else {
                writeln!(x, "# wall[{w}] vanishes").ok();
                x.push_str(&l.remove);
            }
            i += 1;
        }
        writeln!(
            x,
            "# the forces of the new set at the same positions, and their half kick\nrun          0"
        )
        .ok();
        half_kick(&mut x, dt, 1.0);
    }
    x.push_str(&crate::outlets::run_lines(done, steps - done, outlets));
    x
}

#[cfg(test)]
mod tests {
    use super::*;

    fn wall(w: usize) -> WallLines {
        WallLines {
            wall: w,
            add: format!("fix          wall{w} all wall/gran\n"),
            remove: format!("unfix        wall{w}\n"),
        }
    }

    /// A gate that opens at state 200 of 400 and one that closes at 300:
    /// runs of 200, 100 and 100 steps, the removal after the first, the
    /// half kick taken back before each switch and given after `run 0`.
    #[test]
    fn runs_split_at_the_switches() {
        let x = runs(
            400,
            1e-6,
            &[(0, 200), (300, u64::MAX)],
            &[wall(0), wall(1)],
            None,
        );
        let runs: Vec<&str> = x.lines().filter(|l| l.starts_with("run ")).collect();
        assert_eq!(
            runs,
            [
                "run          200",
                "run          0",
                "run          100",
                "run          0",
                "run          100"
            ]
        );
        let unfix = x.find("unfix        wall0").expect("the gate leaves");
        let fix = x.find("fix          wall1").expect("the gate comes");
        assert!(unfix < fix);
        assert_eq!(x.matches("vx+-5e-7*fx/mass").count(), 2, "{x}");
        assert_eq!(x.matches("vx+5e-7*fx/mass").count(), 2, "{x}");
    }

    /// A window past the run's end and an empty one write no switch.
    #[test]
    fn switches_outside_the_run_are_not_written() {
        let x = runs(100, 1e-6, &[(0, 100), (50, 50)], &[wall(0), wall(1)], None);
        assert_eq!(x, "run          100\n");
    }
}
