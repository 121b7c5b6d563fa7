//! The time step: how Δt follows from `integration.dt` or `integration.eta`,
//! and the bound that refuses a step the scheme cannot integrate stably,
//! before anything is computed (issue 24).
//!
//! The bound is Δt ≤ c × T_b, with T_b the smallest pair contact-time
//! estimate of the scene (every free sphere class against every other
//! class, fixed spheres and plane walls: the stiffest pair and the
//! smallest mass) at the bounding speed [`bounding_speed`], and c per
//! scheme. The bound refuses the steps that certainly fail (a single
//! contact, or the measured scenes, unstable there); what goes wrong
//! below it (several stiff contacts per sphere, strong damping under
//! Gear5) is caught by the energy guard (`energy_guard`), which stops the
//! run as soon as it creates energy. The existing examples and tests
//! reach 0.33 T_b (Verlet) and 0.31 T_b (Gear5: bit-identity tests of a
//! collapsing lattice) and stay accepted.
//!
//! - **Verlet, c = [`VERLET_MAX_STEP_RATIO`] = 0.35.** Velocity Verlet on a
//!   linear oscillator is stable for ω Δt < 2; with a damping ratio ζ for
//!   ω Δt < 2(√(1 + ζ²) − ζ). A Hertz contact's tangent stiffness at its
//!   largest overlap gives ω_max T_c = 1.369 × 2.943 = 4.03 (1.28 π), so
//!   one contact is stable up to Δt ≈ 0.5 T_c. At 0.35 T_c, ω_max Δt =
//!   1.41: stable up to ζ = 0.36 (Tsuji e ≈ 0.3). Measured with `dembound
//!   scene` (T_b as defined here, 5.95e-5 s on both scenes):
//!   `settling_bed.toml` (Tsuji e = 0.3) runs at Δt = 2e-5 s (0.34 T_b) and
//!   blows up at 3e-5 s (0.50 T_b); the dense, undamped `lattice_drop.toml`
//!   creates 2.4e-4 of its energy scale at 2e-5 s (0.34 T_b, within the
//!   guard's 1e-3), 5e-3 at 2.5e-5 s (0.42 T_b: stopped by the guard) and
//!   none at 1e-5 s (0.17 T_b).
//! - **Gear5, c = [`GEAR5_MAX_STEP_RATIO`] = 0.32 elastic,
//!   [`GEAR5_DAMPED_MAX_STEP_RATIO`] = 0.08 with a rate-dependent force.**
//!   The predictor–corrector's interval is shorter than Verlet's: on one
//!   Hertz contact (`dembound run`, `limits::MAX_ETA` of dembound-core) e
//!   is 5 % off at η = 0.125, e = 1.6 at 0.2 and 242 at 0.5; the undamped
//!   `lattice_drop.toml` runs at 1e-5 s (0.17 T_b) and blows up at 2e-5 s
//!   (0.34 T_b). Damping shortens it further: `settling_bed.toml` under
//!   Gear5 with Tsuji e = 0.6 or 0.9 ran at 2e-6 s (0.034 T_b) and blew
//!   up at 5e-6 s (0.084 T_b), with e = 0.3 even at 0.034 T_b: measured
//!   before session 37, when a damped onset just before a step's end
//!   handed the predictor unbounded derivatives (`dynamics::kinks`). Since
//!   that fix e = 0.6 and 0.9 run at 4.7e-6 s (0.079 T_b; they blew up
//!   at 4e-6 s before) and e = 0.3 at 2e-6 s; c is kept. With friction (μ = 0.5) e = 0.3 still blows up at
//!   2e-6 s (runs at 1e-6 s): there the energy guard stops it (exit 2). The
//!   Gear5 tests reach 0.31 T_b elastic and 0.077 T_b damped. For accuracy
//!   rather than stability keep Gear5 at η ≤ 0.1 (`dembound run`'s bound).
//!   On top of c, each damped pair must satisfy Gear5's closed-form bound
//!   (ωΔt/0.840)² + βΔt/0.163 ≤ 1 at its largest overlap at the bounding
//!   speed (`setup_checks::check_damped_gear5`, session 37): a strong
//!   damping breaks one contact far below 0.08 T_b (Tsuji e = 0.01 with
//!   attraction: e = 0.081 at 0.05 T_c, exit 0 before), and that error
//!   creates no energy, so the guard cannot see it.
//!
//! `integration.eta` is bounded the same way: Δt = η T_c(v_impact) must
//! satisfy the bound, so η ≤ c T_b / T_c(v_impact) (≤ c when the impact
//! speed is at most the bounding speed).

use std::collections::HashMap;

use dembound_physics::contact::PairLaw;
use dembound_physics::material::PairProperties;

use crate::error::SceneError;
use crate::setup::{SceneSetup, Scheme, TimeStep};
use crate::walls::LawSlot;

/// The largest Δt / T_b under velocity Verlet (module doc).
pub const VERLET_MAX_STEP_RATIO: f64 = 0.35;
/// The largest Δt / T_b under Gear5 with an elastic contact law (module doc).
pub const GEAR5_MAX_STEP_RATIO: f64 = 0.32;
/// The largest Δt / T_b under Gear5 with damping or a viscous law.
pub const GEAR5_DAMPED_MAX_STEP_RATIO: f64 = 0.08;

/// The step chosen for a scene and how it came about.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct StepChoice {
    /// s.
    pub dt: f64,
    /// The contact-time estimate Δt came from (with η), s.
    pub contact_time: Option<f64>,
    /// m/s (with η).
    pub impact_speed: Option<f64>,
}

/// The stability bound of a scene: Δt ≤ `ratio` × `contact_time`.
#[derive(Debug, Clone)]
pub(crate) struct StepBound {
    /// T_b, s.
    pub contact_time: f64,
    /// The speed T_b is estimated at, m/s.
    pub speed: f64,
    /// c of the scheme.
    pub ratio: f64,
    /// The pair that gives T_b.
    pub pair: String,
}

impl StepBound {
    /// The largest Δt allowed, s.
    pub fn max_dt(&self) -> f64 {
        self.ratio * self.contact_time
    }
}

/// Δt from the setup, refused when not finite and positive or above the
/// scheme's stability bound; colliding rigid bodies refused too.
pub(crate) fn choose(setup: &SceneSetup) -> Result<StepChoice, SceneError> {
    refuse_rigid_pairs(setup)?;
    let choice = match setup.integration.time_step {
        TimeStep::Fixed(dt) => {
            if !(dt.is_finite() && dt > 0.0) {
                return Err(SceneError::invalid(
                    "integration.dt",
                    dt,
                    "finite and > 0 s",
                ));
            }
            StepChoice {
                dt,
                contact_time: None,
                impact_speed: None,
            }
        }
        TimeStep::Eta { eta, impact_speed } => {
            if !(eta.is_finite() && eta > 0.0) {
                return Err(SceneError::invalid(
                    "integration.eta",
                    eta,
                    "finite and > 0",
                ));
            }
            if !(impact_speed.is_finite() && impact_speed > 0.0) {
                return Err(SceneError::invalid(
                    "integration.impact_speed",
                    impact_speed,
                    "finite and > 0 m/s",
                ));
            }
            let tc = smallest_contact_time(setup, impact_speed);
            if !(tc.is_finite() && tc > 0.0) {
                return Err(SceneError::invalid(
                    "integration.eta",
                    eta,
                    "a scene with at least one pair of finite stiffness (use integration.dt)",
                ));
            }
            StepChoice {
                dt: eta * tc,
                contact_time: Some(tc),
                impact_speed: Some(impact_speed),
            }
        }
    };
    if let Some(bound) = step_bound(setup) {
        if choice.dt > bound.max_dt() {
            return Err(too_large(setup, &choice, &bound));
        }
    }
    // Walton–Braun's unloading line resolved by this step (its own bound).
    let speed = bounding_speed(setup);
    let pairs = pair_laws(setup, 2.0 * speed, speed);
    crate::setup_checks::check_unloading(setup, choice.dt, &pairs)?;
    // Gear5's closed-form bound on a damped contact (its own bound).
    crate::setup_checks::check_damped_gear5(setup, choice.dt, &pairs)?;
    Ok(choice)
}

/// The refusal of a step above `bound`, naming the key the user set.
fn too_large(setup: &SceneSetup, choice: &StepChoice, bound: &StepBound) -> SceneError {
    let scheme = scheme_name(setup.integration.scheme);
    let why = format!(
        "{c} × the smallest contact-time estimate T_c = {tc:.4e} s ({pair}, at {v:.4} m/s: the \
         fastest approach, from the fastest speed a body can reach √(v₀² + 2|g|H), H the box's \
         height along g, twice that for two free spheres) under {scheme}; {reason}",
        c = bound.ratio,
        tc = bound.contact_time,
        pair = bound.pair,
        v = bound.speed,
        reason = match setup.integration.scheme {
            Scheme::Verlet => {
                "velocity Verlet is unstable beyond ω Δt = 2 (one Hertz contact at ≈ 0.5 T_c, \
                 less with damping or several contacts per sphere)"
            }
            Scheme::Gear5 => {
                "Gear5's predictor–corrector is stable over a shorter interval than Verlet's \
                 (damping shortens it further; scheme = \"verlet\" allows 0.35 T_c)"
            }
        }
    );
    match setup.integration.time_step {
        TimeStep::Eta { eta, .. } => {
            let tc = choice.contact_time.unwrap_or(f64::NAN);
            SceneError::invalid(
                "integration.eta",
                eta,
                format!(
                    "η ≤ {:.4e}: Δt = η × {tc:.4e} s = {:.4e} s must be at most {:.4e} s = {why}; \
                     use a smaller integration.eta",
                    bound.max_dt() / tc,
                    choice.dt,
                    bound.max_dt()
                ),
            )
        }
        TimeStep::Fixed(dt) => SceneError::invalid(
            "integration.dt",
            format!("{dt:e} s"),
            format!(
                "0 < Δt ≤ {:.4e} s = {why}; use integration.dt ≤ {:.4e} or integration.eta ≤ {}",
                bound.max_dt(),
                bound.max_dt(),
                bound.ratio
            ),
        ),
    }
}

fn scheme_name(scheme: Scheme) -> &'static str {
    match scheme {
        Scheme::Verlet => "verlet",
        Scheme::Gear5 => "gear5",
    }
}

/// The fastest speed a body can reach without energy being created:
/// √(v₀² + 2 |g| H), v₀ the fastest initial speed and H the box's extent
/// along g, m/s. It bounds the approach speed on a wall or a fixed
/// sphere; twice it bounds two free bodies' (head-on), so T_b takes
/// pairs of free spheres at 2 × this (T_c falls with the speed for Hertz,
/// as v^(−1/5); speed-independent laws are unaffected).
pub(crate) fn bounding_speed(setup: &SceneSetup) -> f64 {
    let v0 = setup
        .spheres
        .iter()
        .filter(|s| !s.fixed)
        .map(|s| s.velocity.iter().map(|v| v * v).sum::<f64>())
        .fold(0.0, f64::max);
    let g = setup.gravity;
    let g_norm = (g[0] * g[0] + g[1] * g[1] + g[2] * g[2]).sqrt();
    let d = &setup.domain;
    let height = if g_norm > 0.0 {
        (0..3)
            .map(|a| (g[a] / g_norm).abs() * (d.upper[a] - d.lower[a]))
            .sum::<f64>()
    } else {
        0.0
    };
    (v0 + 2.0 * g_norm * height).sqrt()
}

/// The scheme's stability bound, or `None` when no pair has a finite,
/// positive contact-time estimate (nothing can collide, or no speed at
/// all: T_c is infinite for Hertz at rest).
pub(crate) fn step_bound(setup: &SceneSetup) -> Option<StepBound> {
    let speed = bounding_speed(setup);
    if !(speed.is_finite() && speed > 0.0) {
        return None;
    }
    let (contact_time, pair, damped, speed) = smallest_contact_time_of(setup, 2.0 * speed, speed);
    if !(contact_time.is_finite() && contact_time > 0.0) {
        return None;
    }
    let ratio = match setup.integration.scheme {
        Scheme::Verlet => VERLET_MAX_STEP_RATIO,
        Scheme::Gear5 if damped => GEAR5_DAMPED_MAX_STEP_RATIO,
        Scheme::Gear5 => GEAR5_MAX_STEP_RATIO,
    };
    Some(StepBound {
        contact_time,
        speed,
        ratio,
        pair,
    })
}

/// Free spheres that can touch a body of infinite modulus with an
/// infinite modulus of their own have no finite stiffness: the force is
/// infinite at the first touch. Refused naming the material.
fn refuse_rigid_pairs(setup: &SceneSetup) -> Result<(), SceneError> {
    let mats = &setup.materials;
    let rigid = |m: usize| {
        mats.get(m)
            .is_some_and(|m| m.material.youngs_modulus == f64::INFINITY)
    };
    let mut free_rigid: Option<usize> = None;
    let mut free_rigid_count = 0usize;
    let mut fixed_rigid = false;
    for s in &setup.spheres {
        if rigid(s.material) {
            if s.fixed {
                fixed_rigid = true;
            } else {
                free_rigid.get_or_insert(s.material);
                free_rigid_count += 1;
            }
        }
    }
    let Some(m) = free_rigid else {
        return Ok(());
    };
    let rigid_plane = setup.walls.iter().any(|w| w.material().is_some_and(rigid));
    if free_rigid_count >= 2 || fixed_rigid || rigid_plane {
        let partner = if free_rigid_count >= 2 {
            "another free sphere of infinite modulus".to_string()
        } else if fixed_rigid {
            "a fixed sphere of infinite modulus".to_string()
        } else {
            format!(
                "a rigid {} wall",
                crate::walls::registry::surface_kinds_or()
            )
        };
        return Err(SceneError::invalid(
            format!("materials[{m}].youngs_modulus"),
            "inf",
            format!(
                "a finite modulus for free spheres (material `{}`) that can touch {partner}: \
                 two rigid bodies in contact have no finite stiffness, no contact time and no \
                 step that resolves it; give one of them a finite youngs_modulus",
                mats[m].name
            ),
        ));
    }
    Ok(())
}

/// Distinct (radius, material, fixed) classes of the scene, at most a few
/// hundred (beyond: the extreme radii of each material and kind).
fn classes(setup: &SceneSetup) -> Vec<(f64, usize, bool)> {
    let mut out: Vec<(f64, usize, bool)> = Vec::new();
    for s in &setup.spheres {
        let key = (s.radius, s.material, s.fixed);
        if !out.contains(&key) {
            out.push(key);
            if out.len() > 256 {
                break;
            }
        }
    }
    if out.len() <= 256 {
        return out;
    }
    let mut ext: HashMap<(usize, bool), (f64, f64)> = HashMap::new();
    for s in &setup.spheres {
        let e = ext
            .entry((s.material, s.fixed))
            .or_insert((s.radius, s.radius));
        e.0 = e.0.min(s.radius);
        e.1 = e.1.max(s.radius);
    }
    let mut v: Vec<_> = ext
        .into_iter()
        .flat_map(|((m, f), (lo, hi))| [(lo, m, f), (hi, m, f)])
        .collect();
    v.sort_by(|a, b| a.partial_cmp(b).unwrap_or(std::cmp::Ordering::Equal));
    v.dedup();
    v
}

/// The smallest pair contact-time estimate of the scene at
/// `impact_speed`, s (infinite when no pair has a positive one).
pub(crate) fn smallest_contact_time(setup: &SceneSetup, impact_speed: f64) -> f64 {
    smallest_contact_time_of(setup, impact_speed, impact_speed).0
}

/// What a free sphere class meets in [`pair_laws`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Partner {
    /// A sphere class (radius, material, fixed).
    Sphere(f64, usize, bool),
    /// Wall `k` (each of its law rows).
    Wall(usize),
}

/// One pair of the scene's classes and its resolved law.
#[derive(Debug, Clone, Copy)]
pub(crate) struct ClassPair {
    /// The free sphere class (radius, material).
    pub free: (f64, usize),
    pub partner: Partner,
    pub law: PairLaw,
    /// The speed its contact time is estimated at, m/s.
    pub speed: f64,
}

impl ClassPair {
    /// "a free sphere of R = … m, `grain` on wall 2".
    pub fn describe(&self, setup: &SceneSetup) -> String {
        let mats = &setup.materials;
        let sphere = |r: f64, m: usize, fixed: bool| {
            format!(
                "{} sphere of R = {r:e} m, `{}`",
                if fixed { "a fixed" } else { "a free" },
                mats[m].name
            )
        };
        let (ra, ma) = self.free;
        match self.partner {
            Partner::Sphere(rb, mb, fb) => {
                format!("{} on {}", sphere(ra, ma, false), sphere(rb, mb, fb))
            }
            Partner::Wall(k) => format!("{} on wall {k}", sphere(ra, ma, false)),
        }
    }
}

/// Every pair of the scene's classes that can touch: each free sphere
/// class against every other class (with itself only when two bodies
/// share it), pairs of free spheres at `free_speed`, and against fixed
/// spheres and each wall's law rows at `fixed_speed` (m/s).
pub(crate) fn pair_laws(setup: &SceneSetup, free_speed: f64, fixed_speed: f64) -> Vec<ClassPair> {
    let cl = classes(setup);
    let mats = &setup.materials;
    let mass = |r: f64, m: usize, fixed: bool| {
        if fixed {
            f64::INFINITY
        } else {
            mats[m].material.sphere_mass(r)
        }
    };
    // A class paired with itself only when two bodies share it.
    let count = |c: (f64, usize, bool)| {
        setup
            .spheres
            .iter()
            .filter(|s| (s.radius, s.material, s.fixed) == c)
            .take(2)
            .count()
    };
    let mut out = Vec::new();
    for &(ra, ma, fa) in cl.iter() {
        if fa {
            continue;
        }
        for &(rb, mb, fb) in &cl[..] {
            if (rb, mb, fb) == (ra, ma, fa) && count((ra, ma, fa)) < 2 {
                continue;
            }
            let p = PairProperties::spheres(
                ra,
                mass(ra, ma, fa),
                &mats[ma].material,
                rb,
                mass(rb, mb, fb),
                &mats[mb].material,
            );
            out.push(ClassPair {
                free: (ra, ma),
                partner: Partner::Sphere(rb, mb, fb),
                law: setup.contact.pair(&p),
                speed: if fb { fixed_speed } else { free_speed },
            });
        }
        for (k, wall) in setup.walls.iter().enumerate() {
            // The wall's law rows (a plane's one; a cylinder's tube and
            // caps, curved and flat: `walls::cylinder`).
            for (material, curvature) in wall.law_rows() {
                let row = LawSlot {
                    material: material as u32,
                    wall: k,
                    curvature,
                };
                let p = row.properties(
                    ra,
                    mass(ra, ma, fa),
                    &mats[ma].material,
                    &mats[material].material,
                );
                out.push(ClassPair {
                    free: (ra, ma),
                    partner: Partner::Wall(k),
                    law: setup.contact.pair(&p),
                    speed: fixed_speed,
                });
            }
        }
    }
    out
}

/// [`smallest_contact_time`] with pairs of free spheres at `free_speed` and
/// the rest (fixed spheres, walls) at `fixed_speed`, m/s: the time, the
/// pair that gives it, whether its force depends on the overlap rate
/// (damping, a viscous law), and the speed it was estimated at.
fn smallest_contact_time_of(
    setup: &SceneSetup,
    free_speed: f64,
    fixed_speed: f64,
) -> (f64, String, bool, f64) {
    let mut best = f64::INFINITY;
    let mut pair = String::new();
    let mut damped = false;
    let mut at_speed = f64::NAN;
    for p in pair_laws(setup, free_speed, fixed_speed) {
        let t = p.law.contact_time_estimate(p.speed);
        if t > 0.0 && t < best {
            best = t;
            pair = p.describe(setup);
            damped = p.law.depends_on_rate();
            at_speed = p.speed;
        }
    }
    (best, pair, damped, at_speed)
}

/// The smallest Rayleigh time of a free sphere,
/// π R √(ρ/G)/(0.1631 ν + 0.8766), s.
pub(crate) fn rayleigh_time(setup: &SceneSetup) -> Option<f64> {
    let mut best: Option<f64> = None;
    for (r, m, fixed) in classes(setup) {
        if fixed {
            continue;
        }
        let mat = &setup.materials[m].material;
        if !mat.youngs_modulus.is_finite() {
            continue;
        }
        let nu = mat.poisson_ratio;
        let shear = mat.youngs_modulus / (2.0 * (1.0 + nu));
        let t = std::f64::consts::PI * r * (mat.density / shear).sqrt() / (0.1631 * nu + 0.8766);
        best = Some(best.map_or(t, |b: f64| b.min(t)));
    }
    best
}
