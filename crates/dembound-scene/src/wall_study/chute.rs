//! The floor as a chute base (issue 13, wall-study's third part): a bed
//! flowing down an inclined floor, periodic along the flow (x) and across
//! it (y), gravity g = 9.81 (sin θ, 0, −cos θ) m/s² with θ above the bed's
//! angle of repose. The engine has no moving walls, so a tilted chute is
//! the shear flow: steady when the floor holds the bed back, accelerating
//! when it cannot (a smooth floor: the bed slides as a block).
//!
//! Measured over the second half of the run: the velocity profile v_x(z)
//! in slabs of one particle radius, the slip velocity at the wall (the mean
//! v_x of the first layer, centres less than 1.5 R above the floor's
//! contact plane, hollows included: 1.5 R lies between a first layer
//! resting on a plane, z = R, and any second layer, z ≥ R + √3 R), the
//! floor's shear and normal force against the bed's weight components
//! N m g (sin θ, cos θ), and whether the flow is steady.
//!
//! The periodic cell holds a whole number of tiling periods along each
//! axis (the tiling must tile the period, [`crate::sources::tiling`]), at
//! least `min_cell` particle radii. A floor whose cell needs more than
//! `max_particles` particles, or whose touching boundary spheres leave a
//! hole a particle passes through (the square tiling's gap between four
//! spheres has radius (√2 − 1) R_b, the hexagonal one's between three
//! (2/√3 − 1) R_b: r > 2.414 and r > 6.464), or whose boundary spheres are
//! larger than the engine's periodic cells take (r > 4), is not run, and
//! the reason is returned instead.

use std::f64::consts::PI;

use super::{add_floor, base_setup, cell, insert_at_rest, Floor, StudyConfig};
use crate::simulation::LARGE_FACTOR;
use crate::{SceneError, Simulation};

/// Gravitational acceleration, m/s² (the bed study's).
const G: f64 = 9.81;

/// Solid fraction the bed's particle count is chosen for.
const PACKING: f64 = 0.58;

/// What the chute runs.
#[derive(Debug, Clone, PartialEq)]
pub struct ChuteConfig {
    /// Inclination θ of the floor, degrees.
    pub angle: f64,
    /// Bed depth in particle diameters (at a solid fraction of 0.58).
    pub layers: f64,
    /// Smallest cell along the flow (x) and across it (y), particle radii.
    pub min_cell: [f64; 2],
    /// Simulated time, s; the second half is averaged.
    pub duration: f64,
    /// Floors whose cell needs more particles are not run.
    pub max_particles: usize,
}

impl ChuteConfig {
    /// Checks the numbers; an error names the option, the value and the range.
    pub fn validate(&self) -> Result<(), SceneError> {
        let bad = |k: &str, v: f64, allowed: &str| Err(SceneError::invalid(k, v, allowed));
        if !(self.angle > 0.0 && self.angle < 90.0) {
            return bad("--chute-angle", self.angle, "0 < θ < 90 degrees");
        }
        if !(1.0..=100.0).contains(&self.layers) {
            return bad("--chute-layers", self.layers, "1 ≤ layers ≤ 100 diameters");
        }
        for v in self.min_cell {
            if !(4.0..=1.0e4).contains(&v) {
                return bad("--chute-cell", v, "4 ≤ cell ≤ 10000 particle radii");
            }
        }
        if !(self.duration.is_finite() && self.duration > 0.0 && self.duration <= 1.0e3) {
            return bad("--chute-time", self.duration, "0 < t ≤ 1000 s");
        }
        if self.max_particles == 0 || self.max_particles > 200_000 {
            return Err(SceneError::invalid(
                "--chute-max-particles",
                self.max_particles,
                "1 ≤ n ≤ 200000",
            ));
        }
        Ok(())
    }
}

/// A chute's cell and particle count, before running.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ChutePlan {
    /// Cell along x and y, m.
    pub cell: [f64; 2],
    pub particles: usize,
}

/// The cell and particle count on `floor`, or why the floor is not run.
pub fn plan(c: &StudyConfig, cc: &ChuteConfig, floor: Floor) -> Result<ChutePlan, String> {
    let r = c.radius;
    if let Some(why) = floor.not_a_wall() {
        return Err(why);
    }
    if let Floor::Particles { radius_ratio, .. } = floor {
        if radius_ratio > LARGE_FACTOR {
            return Err(format!(
                "the engine's periodic cells take boundary spheres up to {LARGE_FACTOR} R (r = \
                 {radius_ratio})"
            ));
        }
    }
    let period = cell(floor, r);
    // The engine's shortest periodic box: 2 × (largest diameter + skin),
    // the skin 0.2 R by default.
    let largest = match floor {
        Floor::Particles { radius_ratio, .. } => radius_ratio.max(1.0) * r,
        _ => r,
    };
    let shortest = 2.0 * (2.0 * largest + 0.2 * r) * (1.0 + 1e-9);
    let side = |k: usize| {
        let min = (cc.min_cell[k] * r).max(shortest);
        if period[k] > 0.0 {
            (min / period[k]).ceil().max(1.0) * period[k]
        } else {
            min
        }
    };
    let cell = [side(0), side(1)];
    let volume = 4.0 / 3.0 * PI * r * r * r;
    let count = PACKING * cell[0] * cell[1] * cc.layers * 2.0 * r / volume;
    let particles = count.round().max(1.0);
    if particles > cc.max_particles as f64 {
        return Err(format!(
            "the periodic cell ({:.4e} × {:.4e} m, whole tiling periods) needs {particles} \
             particles, above the cap of {} (--chute-max-particles)",
            cell[0], cell[1], cc.max_particles
        ));
    }
    Ok(ChutePlan {
        cell,
        particles: particles as usize,
    })
}

/// The flow on one floor.
#[derive(Debug, Clone, PartialEq)]
pub struct Chute {
    /// θ, degrees.
    pub angle: f64,
    pub particles: usize,
    /// Cell along x and y, m.
    pub cell: [f64; 2],
    /// Simulated time, s; averages are over [`Self::window`].
    pub duration: f64,
    /// Start and end of the averaging window, s.
    pub window: [f64; 2],
    /// (mean centre height z, m; mean v_x, m/s; particle-samples) per slab
    /// of one radius above the floor's contact plane, from the bottom (the
    /// lowest slab holds every centre below the plane).
    pub profile: Vec<(f64, f64, usize)>,
    /// Mean v_x of the first layer (centres below 1.5 R), m/s.
    pub slip_velocity: f64,
    /// The profile's lower part fitted by a line and extrapolated to the
    /// floor's contact plane ([`fit_slip`] over slabs with mean centre
    /// height 0 ≤ z ≤ min(5 R, half the bed height)); `None` when fewer
    /// than two slabs lie there.
    pub slip_fit: Option<SlipFit>,
    /// Mean v_x of the bed, m/s.
    pub mean_velocity: f64,
    /// Mean v_x of the bed over the first and second half of the window, m/s.
    pub velocity_halves: [f64; 2],
    /// (mean v_x at the window's end − at its start)/window, m/s².
    pub acceleration: f64,
    /// Mean force of the bed on the floor along the flow, N.
    pub floor_shear_force: f64,
    /// Mean force of the bed on the floor into it (−F_z), N.
    pub floor_normal_force: f64,
    /// N m g sin θ and N m g cos θ, N.
    pub weight_components: [f64; 2],
    /// 95th percentile of the particle tops above the floor plane at the end, m.
    pub bed_height: f64,
    /// Mean force on the floor over every step of the window (N), from the
    /// bed's momentum change: N m (g sin θ − acceleration) along x.
    pub momentum_shear_force: f64,
}

impl Chute {
    /// Area of the cell, m².
    pub fn area(&self) -> f64 {
        self.cell[0] * self.cell[1]
    }

    /// Is the flow steady: the bed's mean acceleration over the window
    /// below `tolerance` × g sin θ, so that the floor carries that share
    /// of the weight component or more (momentum balance).
    pub fn steady(&self, tolerance: f64) -> bool {
        self.acceleration.abs() <= tolerance * G * self.angle.to_radians().sin()
    }
}

/// The top of the profile's lower part fitted for the slip, particle radii.
pub const SLIP_FIT_TOP: f64 = 5.0;

/// A straight line v_x = slip_velocity + shear_rate z through the lower
/// part of a velocity profile, z from the floor's contact plane.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SlipFit {
    /// The line's value at z = 0, m/s: the slip velocity extrapolated to
    /// the wall.
    pub slip_velocity: f64,
    /// dv_x/dz, 1/s.
    pub shear_rate: f64,
    /// Slip length b = slip_velocity/shear_rate, m: the depth below the
    /// contact plane where the line reaches zero (Navier's slip
    /// condition v = b dv/dz at the wall); infinite (signed) for a flat
    /// profile, a block sliding.
    pub slip_length: f64,
    /// Slabs fitted, and the height range of their mean centres, m.
    pub slabs: usize,
    pub range: [f64; 2],
}

/// Least-squares line through the slabs of `profile` ((mean centre z, m;
/// mean v_x, m/s; samples), as [`Chute::profile`]) whose mean centre lies
/// in [lo, hi], each slab weighted by its samples: a slab's mean velocity
/// is the mean over its samples, so this is the line through every sample
/// of the window's particles at their slab's mean height. Written out
/// (two sums) rather than taken from a crate: it is four lines.
/// `None` when fewer than two slabs, or slabs all at one height, lie there.
pub fn fit_slip(profile: &[(f64, f64, usize)], lo: f64, hi: f64) -> Option<SlipFit> {
    let used: Vec<(f64, f64, f64)> = profile
        .iter()
        .filter(|p| p.2 > 0 && p.0 >= lo && p.0 <= hi)
        .map(|&(z, v, k)| (z, v, k as f64))
        .collect();
    if used.len() < 2 {
        return None;
    }
    let w: f64 = used.iter().map(|p| p.2).sum();
    let zm = used.iter().map(|p| p.2 * p.0).sum::<f64>() / w;
    let vm = used.iter().map(|p| p.2 * p.1).sum::<f64>() / w;
    let szz: f64 = used.iter().map(|p| p.2 * (p.0 - zm) * (p.0 - zm)).sum();
    let szv: f64 = used.iter().map(|p| p.2 * (p.0 - zm) * (p.1 - vm)).sum();
    if szz <= 0.0 {
        return None;
    }
    let shear_rate = szv / szz;
    let slip_velocity = vm - shear_rate * zm;
    let z0 = used.iter().map(|p| p.0).fold(f64::INFINITY, f64::min);
    let z1 = used.iter().map(|p| p.0).fold(f64::NEG_INFINITY, f64::max);
    Some(SlipFit {
        slip_velocity,
        shear_rate,
        slip_length: slip_velocity / shear_rate,
        slabs: used.len(),
        range: [z0, z1],
    })
}

/// One sample of the running chute.
struct Sample {
    time: f64,
    mean_vx: f64,
}

/// Runs the chute on `floor` as `plan`ned.
pub fn run(
    c: &StudyConfig,
    cc: &ChuteConfig,
    floor: Floor,
    plan: &ChutePlan,
) -> Result<Chute, SceneError> {
    let mut sim = build(c, cc, floor, plan)?;
    let (n, floor_wall) = (plan.particles, sim_floor_wall(&sim));
    let r = c.radius;
    let dt = sim.dt();
    let steps = (cc.duration / dt).ceil() as u64;
    let samples = 400u64;
    let chunk = (steps / samples).max(1);
    let start = steps / 2;
    let mut done = 0u64;
    let mut trace: Vec<Sample> = Vec::new();
    let mut shear = Vec::new();
    let mut normal = Vec::new();
    // Slabs of one radius: index 0 holds z < 0, index k ≥ 1 holds
    // (k − 1) R ≤ z < k R. (Σz, Σv_x, count).
    let mut slabs: Vec<(f64, f64, usize)> = Vec::new();
    let (mut slip_sum, mut slip_count) = (0.0, 0usize);
    while done < steps {
        let k = chunk.min(steps - done);
        sim.step_guarded(k)?;
        done += k;
        if done < start {
            continue;
        }
        let x = sim.positions();
        let v = sim.velocities();
        let mut sum = 0.0;
        for i in 0..n {
            let (z, vx) = (x[i][2], v[i][0]);
            sum += vx;
            let slab = if z < 0.0 {
                0
            } else {
                (z / r).floor() as usize + 1
            };
            if slabs.len() <= slab {
                slabs.resize(slab + 1, (0.0, 0.0, 0));
            }
            let s = &mut slabs[slab];
            s.0 += z;
            s.1 += vx;
            s.2 += 1;
            if z < 1.5 * r {
                slip_sum += vx;
                slip_count += 1;
            }
        }
        trace.push(Sample {
            time: sim.time(),
            mean_vx: sum / n as f64,
        });
        let f = sim.wall_forces()[floor_wall];
        shear.push(f[0]);
        normal.push(-f[2]);
    }
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len().max(1) as f64;
    let half = trace.len() / 2;
    let means: Vec<f64> = trace.iter().map(|s| s.mean_vx).collect();
    let (first, last) = (trace.first(), trace.last());
    let (t0, t1, v0, v1) = match (first, last) {
        (Some(a), Some(b)) => (a.time, b.time, a.mean_vx, b.mean_vx),
        _ => (0.0, 0.0, 0.0, 0.0),
    };
    let acceleration = if t1 > t0 { (v1 - v0) / (t1 - t0) } else { 0.0 };
    let theta = cc.angle.to_radians();
    let mass = c.material.sphere_mass(r);
    let weight = n as f64 * mass * G;
    let x = sim.positions();
    let mut tops: Vec<f64> = x[..n].iter().map(|p| p[2] + r).collect();
    tops.sort_by(f64::total_cmp);
    let bed_height = tops.get(tops.len() * 95 / 100).copied().unwrap_or(0.0);
    let profile: Vec<(f64, f64, usize)> = slabs
        .iter()
        .filter(|s| s.2 > 0)
        .map(|&(z, vx, k)| (z / k as f64, vx / k as f64, k))
        .collect();
    let slip_fit = fit_slip(&profile, 0.0, (SLIP_FIT_TOP * r).min(0.5 * bed_height));
    Ok(Chute {
        angle: cc.angle,
        particles: n,
        cell: plan.cell,
        duration: sim.time(),
        window: [t0, t1],
        profile,
        slip_velocity: slip_sum / slip_count.max(1) as f64,
        slip_fit,
        mean_velocity: mean(&means),
        velocity_halves: [mean(&means[..half]), mean(&means[half..])],
        acceleration,
        floor_shear_force: mean(&shear),
        floor_normal_force: mean(&normal),
        weight_components: [weight * theta.sin(), weight * theta.cos()],
        bed_height,
        momentum_shear_force: n as f64 * mass * (G * theta.sin() - acceleration),
    })
}

/// The floor is the last wall of a chute scene.
fn sim_floor_wall(sim: &Simulation) -> usize {
    sim.wall_forces().len() - 1
}

/// The chute's scene, ready to step: the particles first (input indices
/// 0..N), poured at rest from a loose random packing above the floor.
pub fn build(
    c: &StudyConfig,
    cc: &ChuteConfig,
    floor: Floor,
    plan: &ChutePlan,
) -> Result<Simulation, SceneError> {
    let r = c.radius;
    let n = plan.particles;
    let [lx, ly] = plan.cell;
    let rb = match floor {
        Floor::Particles { radius_ratio, .. } => radius_ratio * r,
        _ => r,
    };
    let fill = 0.2;
    let height = n as f64 * 4.0 / 3.0 * PI * r * r * r / (fill * lx * ly) + 2.0 * r;
    let bottom = 2.0 * r;
    let mut s = base_setup(
        c,
        [0.0, 0.0, -2.5 * rb],
        [lx, ly, bottom + height + 4.0 * r],
        c.dt(),
    );
    s.domain.periodic = [true, true, false];
    let theta = cc.angle.to_radians();
    s.gravity = [G * theta.sin(), 0.0, -G * theta.cos()];
    // Inside [R, L − R] along the periodic axes: no overlap across a face.
    insert_at_rest(
        &mut s,
        c,
        "chute",
        n,
        r,
        [0.0, 0.0, bottom],
        [lx, ly, bottom + height],
    )?;
    let floor_wall = add_floor(&mut s, floor, [0.0, 0.0], [lx, ly], [0.0, 0.0], r, true)?;
    s.friction = c.friction_setup(&s, floor_wall, &[]);
    let threads = if n >= 5000 { 2 } else { 1 };
    Simulation::new(s, threads)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sources::tiling::Pattern;

    #[test]
    fn a_linear_profile_gives_its_intercept_and_slip_length() {
        // v = 0.3 m/s + 200 /s × z, sampled at uneven heights with uneven
        // counts, plus slabs outside the window that would bend the line:
        // the fit returns the line exactly (round-off: 1e-12).
        let line = |z: f64| 0.3 + 200.0 * z;
        let mut profile: Vec<(f64, f64, usize)> = [0.2e-3, 0.7e-3, 1.1e-3, 1.9e-3, 2.4e-3]
            .iter()
            .zip([5, 40, 17, 3, 60])
            .map(|(&z, k)| (z, line(z), k))
            .collect();
        profile.push((-0.4e-3, 0.0, 100));
        profile.push((4.0e-3, 9.0, 100));
        let f = fit_slip(&profile, 0.0, 2.5e-3).unwrap();
        assert_eq!(f.slabs, 5);
        assert!((f.slip_velocity - 0.3).abs() < 1e-12, "{f:?}");
        assert!((f.shear_rate - 200.0).abs() < 1e-9, "{f:?}");
        // b = 0.3/200 = 1.5 mm below the contact plane.
        assert!((f.slip_length - 1.5e-3).abs() < 1e-15, "{f:?}");
        assert_eq!(f.range, [0.2e-3, 2.4e-3]);
    }

    #[test]
    fn a_block_has_a_flat_profile_and_an_infinite_slip_length() {
        // Every slab at the block's velocity: the extrapolated slip is the
        // block's velocity, the shear rate zero, the slip length infinite.
        let profile = [(0.5e-3, 1.25, 10), (1.5e-3, 1.25, 30), (2.5e-3, 1.25, 7)];
        let f = fit_slip(&profile, 0.0, 3e-3).unwrap();
        assert_eq!(f.slip_velocity, 1.25);
        assert_eq!(f.shear_rate, 0.0);
        assert!(f.slip_length.is_infinite());
        // One slab, or none, in the window: no line.
        assert!(fit_slip(&profile, 0.0, 1e-3).is_none());
        assert!(fit_slip(&profile, 5e-3, 6e-3).is_none());
    }
    use dembound_physics::contact::tangential::TangentialKind;
    use dembound_physics::material::Material;

    fn study() -> StudyConfig {
        StudyConfig {
            material: Material {
                density: 1000.0,
                youngs_modulus: 1.0e7,
                poisson_ratio: 0.3,
            },
            radius: 0.5e-3,
            restitution: 0.5,
            friction: 0.5,
            tangential: TangentialKind::Mindlin,
            rolling_friction: 0.0,
            floors: vec![],
            impacts: 0,
            speed: 1.0,
            angles: vec![0.0],
            bed_particles: 0,
            eta: 0.05,
            settle_time: 0.1,
            seed: 1,
            floor_friction: None,
            chute: None,
        }
    }

    fn floor(radius_ratio: f64, pattern: Pattern) -> Floor {
        Floor::Particles {
            radius_ratio,
            modulus_ratio: 100.0,
            pattern,
        }
    }

    #[test]
    fn plans_whole_periods_and_refuses_floors_that_are_not_walls() {
        let c = study();
        let cc = ChuteConfig {
            angle: 24.0,
            layers: 5.0,
            min_cell: [20.0, 12.0],
            duration: 0.5,
            max_particles: 3000,
        };
        let r = c.radius;
        // The plane: the minimum cell, N = 0.58 × 20 R × 12 R × 10 R/(4/3 π R³).
        let p = plan(&c, &cc, Floor::Plane).unwrap();
        assert_eq!(p.cell, [20.0 * r, 12.0 * r]);
        assert_eq!(
            p.particles,
            (0.58 * 2400.0 / (4.0 / 3.0 * PI)).round() as usize
        );
        // r = 2 hexagonal: periods 4 R and 4√3 R: 5 and 2 of them.
        let p = plan(&c, &cc, floor(2.0, Pattern::Hexagonal)).unwrap();
        assert!((p.cell[0] / (20.0 * r) - 1.0).abs() < 1e-12);
        assert!((p.cell[1] / (8.0 * 3f64.sqrt() * r) - 1.0).abs() < 1e-12);
        // Gaps wider than a particle: r = 2.5 square (gap 1.036 R), 7
        // hexagonal (1.083 R), and the paper's r = 100.
        for f in [
            floor(2.5, Pattern::Square),
            floor(7.0, Pattern::Hexagonal),
            floor(100.0, Pattern::Square),
        ] {
            let why = plan(&c, &cc, f).unwrap_err();
            assert!(why.starts_with("not a wall"), "{why}");
        }
        // r = 2.4 square is a wall; r = 5 hexagonal too but beyond the
        // engine's periodic cells.
        assert!(plan(&c, &cc, floor(2.4, Pattern::Square)).is_ok());
        let why = plan(&c, &cc, floor(5.0, Pattern::Hexagonal)).unwrap_err();
        assert!(why.contains("periodic cells"), "{why}");
        // The cap.
        let small = ChuteConfig {
            max_particles: 100,
            ..cc
        };
        assert!(plan(&c, &small, Floor::Plane).unwrap_err().contains("cap"));
    }
}
