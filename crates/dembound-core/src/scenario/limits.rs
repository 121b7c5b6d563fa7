//! The ranges of the scenario's physical and numerical inputs: what the
//! numerics handle and the tool can vouch for. [`super::Scenario::validate`]
//! checks them and `dembound keys` prints them, from these constants.
//!
//! How each was chosen (measured with `dembound run`, Gear5, event stepping):
//!
//! - **η ≤ 0.1** ([`MAX_ETA`]): the first contact's e, h_max and T_c at
//!   η = 0.1 are within 0.4 % (Hertz), 0.45 % (power 3), 0.9 % (Tsuji,
//!   e = 0.5) and 0.3 % (viscoelastic) of the reference, and within 2.6 %
//!   with velocity Verlet (Walton–Braun); at η = 0.125 Gear5 on Hertz is
//!   already 5 % off in e, at 0.15 19 %, at 0.2 e = 1.6 and at 0.5 e = 242
//!   (the predictor–corrector is unstable when a few steps span the
//!   contact). The same bound holds for `integration.dt`, as Δt ≤ 0.1 T_c
//!   with T_c the law's contact-time estimate.
//! - **g T_c/|v_c| ≤ 10** ([`MAX_GRAVITY_SHARE`]): when gravity changes the
//!   velocity during the contact by much more than the impact speed itself
//!   (a tiny drop, a huge or very soft particle) the contact is a
//!   gravity-loaded oscillation and e = v_r/|v_c| is ill-conditioned: the
//!   Hertz error in e grows from 5e−7 at g T_c/|v_c| = 1.6 to 2.3e−6 at
//!   6.4, 1.1e−5 at 13, 4.5e−5 at 26 and 1.5 % at 240 (R = 1000 m), 690 %
//!   at 3000 (a 1e−15 m drop). Refused above 10 (an error ~5e−6).
//! - **ω₂ Δt ≤ 0.9 (Gear5), ≤ 0.5 (velocity Verlet)**
//!   ([`MAX_UNLOADING_STEP_GEAR5`], [`MAX_UNLOADING_STEP_VERLET`];
//!   Walton–Braun): the unloading line k₂ = k₁/e² oscillates at ω₂ =
//!   ω₁/e, far faster than the contact-time estimate's scale for a small
//!   e, so Δt = η T_c can leave it unresolved. Gravity-free impacts at
//!   1 m/s (session 34), the error in e against the exact e, over e =
//!   0.01–0.3 and η = 0.005–0.1: Gear5, event stepping, 0.006 % at ω₂Δt =
//!   0.35, 0.14 % at 0.66–0.69, 0.64–0.76 % at 0.78–0.95, 7 % at 1.6, 20 %
//!   at 2.7, e = 2.09 for a target 0.001 at 31 (energy created, printed
//!   with exit 0 before this bound); velocity Verlet 1.5 % at 0.35, 0.5–0.75
//!   % at 0.50, 2.4–4.3 % at 0.66–0.69, 4–11 % at 0.78–0.95. The bounds
//!   keep each scheme within its error at η = 0.1 (above). Refused beyond,
//!   naming contact.restitution with the smallest e the step resolves and
//!   the step this e needs.
//! - **Gear5 on a damped contact: (ωΔt/W)² + βΔt/B ≤ 1** (W = 0.840,
//!   B = 0.163; `bounce::check_damped_step`,
//!   `dembound_physics::integrate::gear5_stability`): ω and β the
//!   contact's frequency and damping rate at its largest overlap. Beyond
//!   it a parasitic root of the predictor–corrector passes −1 and the
//!   rebound is wrong (the bound is not fitted: det(I + A) = 0 of the
//!   scheme's amplification matrix). Session 36, `run` against `exact`,
//!   one contact, linear+viscous, Hertz+Tsuji, Hertz+viscoelastic,
//!   attraction on and off, e = 0.01–0.9, η = 0.02–0.1, gravity-free
//!   and under g = 9.81 m/s² at 0.001, 0.313 and 3 m/s, event and fixed
//!   stepping (4 240 runs): the largest accepted error in e is 2.2e−4
//!   (spring–dashpot), 2.3e−3 (Tsuji, e = 0.5 at η = 0.08) and 8.5e−4
//!   (viscoelastic); every accepted run's numbers are unchanged. Refused
//!   beyond, where the error had reached +2400 % (spring–dashpot),
//!   +4800 % (Tsuji) and +5800 % (viscoelastic, e = 0.59 for a target
//!   0.01 at η = 0.1, with attraction) with exit 0. The largest accepted
//!   η is 0.026 (spring–dashpot, e ≤ 0.05 with attraction), 0.031
//!   (Tsuji, e ≤ 0.1), 0.044 (spring–dashpot, e = 0.3, no attraction),
//!   0.087 (e = 0.5), 0.22 (e = 0.9, so η ≤ 0.1 decides). Velocity Verlet
//!   is not refused: its error grows smoothly with the step (README).
//! - The physical ranges keep every derived quantity (masses, stiffnesses,
//!   times, step counts) finite in double precision with room to spare;
//!   they are far wider than any DEM material.

/// `particle.radius`, m.
pub const RADIUS: (f64, f64) = (1e-9, 10.0);
/// `particle.density` and `boundary.density`, kg/m³ (a boundary 1e6 times
/// denser than the particle stands in for a fixed one in the tests).
pub const DENSITY: (f64, f64) = (1e-3, 1e12);
/// `particle.youngs_modulus`, Pa.
pub const YOUNGS_MODULUS: (f64, f64) = (1e3, 1e13);
/// `boundary.radius_ratio` and `boundary.modulus_ratio` when finite ("inf" also allowed).
pub const RATIO: (f64, f64) = (1e-6, 1e18);
/// `motion.gap`, m (0 allowed).
pub const GAP: (f64, f64) = (0.0, 1e4);
/// |`motion.velocity`| and |`boundary.velocity`|, m/s.
pub const MAX_SPEED: f64 = 1e4;
/// `motion.gravity`, m/s², when not 0.
pub const GRAVITY: (f64, f64) = (1e-6, 1e6);
/// `integration.eta`.
pub const ETA: (f64, f64) = (1e-9, MAX_ETA);
/// The largest Δt/T_c (see the module doc).
pub const MAX_ETA: f64 = 0.1;
/// The largest ω₂ Δt of a Walton–Braun unloading line with Gear5 (see
/// the module doc).
pub const MAX_UNLOADING_STEP_GEAR5: f64 =
    dembound_physics::contact::normal::walton_braun::MAX_UNLOADING_STEP_GEAR5;
/// The same with velocity Verlet.
pub const MAX_UNLOADING_STEP_VERLET: f64 =
    dembound_physics::contact::normal::walton_braun::MAX_UNLOADING_STEP_VERLET;
/// The largest g T_c/|v_c| (see the module doc).
pub const MAX_GRAVITY_SHARE: f64 = 10.0;

/// A number for a message: as written when short, else in exponent form
/// (1e-308, not 0.000…0001).
pub fn show(x: f64) -> String {
    Shown(x).to_string()
}

/// A range for messages, e.g. "1e-9 to 10 m".
pub fn describe(range: (f64, f64), unit: &str) -> String {
    Described(range, unit).to_string()
}

/// [`show`], formatted only when displayed (validation builds its
/// messages only for a value that fails).
#[derive(Debug, Clone, Copy)]
pub struct Shown(pub f64);

impl std::fmt::Display for Shown {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let plain = self.0.to_string();
        if plain.len() > 10 {
            write!(f, "{:e}", self.0)
        } else {
            f.write_str(&plain)
        }
    }
}

/// [`describe`], formatted only when displayed.
#[derive(Debug, Clone, Copy)]
pub struct Described<'a>(pub (f64, f64), pub &'a str);

impl std::fmt::Display for Described<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{} to {}", Shown(self.0 .0), Shown(self.0 .1))?;
        if !self.1.is_empty() {
            write!(f, " {}", self.1)?;
        }
        Ok(())
    }
}
