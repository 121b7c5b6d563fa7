//! The ranges of a scene's physical inputs, in one place (issue 24): the
//! scene file's validation ([`crate::io::config`]), the engine's setup
//! checks ([`crate::setup_checks`], run by `Simulation::prepare`, so under
//! MPI and from Python too) and `dembound keys --scene` all read these
//! constants, so the table cannot drift from what is enforced.
//!
//! Where a bounce-study range fits (`dembound_core::scenario::limits`,
//! which `dembound keys` prints), the value is the same; a test of the
//! `dembound` crate asserts the equality (this crate does not depend on
//! `dembound-core`).
//!
//! Why bounds at all: a value far outside them makes a derived quantity
//! (a mass, a stiffness, a contact time, a kinetic energy) overflow,
//! underflow or lose its digits, and the run then prints impossible numbers
//! (a velocity of 1e300 m/s gives a kinetic energy of `null`, a density of
//! 5e-324 kg/m³ a step "too large"). The ranges are far wider than any DEM
//! material or grain.

/// Radius of a sphere given in the scene (inline, lattice, random, CSV,
/// LAMMPS data, `add_particles`), and `boundary_particles.reference_radius`,
/// m. The bounce study's `particle.radius` range: 1 nm (below, a
/// continuum contact law means nothing) to 10 m.
pub const RADIUS: (f64, f64) = (1e-9, 10.0);

/// `material.density`, kg/m³: the bounce study's range (1e-3: an aerogel is
/// 1; 1e12: a million times osmium, kept for "fixed by mass" tests).
pub const DENSITY: (f64, f64) = (1e-3, 1e12);

/// `material.youngs_modulus` when finite, Pa (`inf`: rigid): the bounce
/// study's range (1 kPa, softer than any gel used in DEM, to 10 TPa, ten
/// times diamond).
pub const YOUNGS_MODULUS: (f64, f64) = (1e3, 1e13);

/// `material.poisson_ratio`: the thermodynamic range −1 < ν < 0.5, both
/// ends open (ν = 0.5 makes E* infinite for a finite E, ν = −1 makes G
/// infinite).
pub const POISSON_RATIO: (f64, f64) = (-1.0, 0.5);

/// |velocity| of a sphere (inline, lattice, random, CSV, LAMMPS data), m/s:
/// the bounce study's `motion.velocity` range, 10 km/s (above any DEM
/// impact; far beyond, ½ m v² and the energy balance lose their digits).
pub const MAX_SPEED: f64 = 1e4;

/// |`motion.gravity`| when not 0, m/s²: the bounce study's range (1e-6 to
/// 1e6, a hundred thousand g).
pub const GRAVITY: (f64, f64) = (1e-6, 1e6);

/// `boundary_particles.radius_ratio` r = R_b/R_ref.
///
/// Upper bound 1e6: the gap of a boundary contact is computed as
/// |x_i − x_b| − R_i − R_b, whose rounding error is about ε (r + 1) R_ref
/// (ε = 1.1e-16). At r = 1e6 that is 1.1e-10 R_ref, 1e-4 of a small
/// contact's overlap (1e-6 R_ref); at r = 1e15 it is 0.1 R_ref and the
/// contact creates energy (0.3117 m/s out of 0.3, issue 24), at 1e20 the
/// sphere passes through. A boundary sphere of r = 1e6 differs from a plane
/// by 1e-6 in R_eff = R r/(1 + r): beyond it use `plane`.
/// Lower bound 1e-2: a boundary sphere a hundredth of the particle's size
/// (the paper studies r ≥ 0.5); below, the tiling of the box needs
/// (L/(2 r R))² spheres, 10⁴ per particle footprint already at the bound.
pub const RADIUS_RATIO: (f64, f64) = (1e-2, 1e6);

/// `boundary_particles.modulus_ratio` ζ = E_b/E when finite (`inf`:
/// rigid): the bounce study's ratio range. E_b = ζ E only enters the
/// pair's 1/E* = (1 − ν²)/E + (1 − ν_b²)/E_b, finite at both ends.
pub const MODULUS_RATIO: (f64, f64) = (1e-6, 1e18);

/// Coulomb friction μ (`contact.friction`, `material.friction`,
/// `wall.friction`): 0 to 10. Real surfaces have μ ≲ 1.5; above a few
/// every contact sticks, so 10 is a typo guard, not physics.
pub const FRICTION: (f64, f64) = (0.0, 10.0);

/// Rolling friction μ_r (LIGGGHTS `epsd2`): 0 to 1. The rolling spring
/// k_r = 2.25 μ_r² R_eff² k_n acting on I = 2/5 m R² has the angular
/// frequency 2.37 μ_r ω_n (ω_n the normal contact's): at μ_r = 1 it is
/// already 2.4 times faster than the normal contact the step resolves;
/// beyond, a step chosen from the contact time no longer resolves it.
/// Measured values are 1e-3 to 0.1.
pub const ROLLING_FRICTION: (f64, f64) = (0.0, 1.0);

/// Initial overlap (of two spheres, or of a sphere and a plane) above
/// which a warning is printed, as a fraction of the smaller radius: 1 %.
/// The contact laws are small-strain theories (the contact radius
/// a = √(R h) is already 0.1 R at h = 1 % R), and an initial overlap is
/// stored elastic energy the first steps release as kinetic energy.
pub const OVERLAP_WARNING: f64 = 0.01;

/// Initial overlap above which the scene is refused, as a fraction of the
/// smaller radius: 50 %. At h = R/2 the contact radius √(R_eff h) is half a
/// radius (equal spheres): no contact law means anything there, and such
/// overlaps come from placement errors (a duplicated atom, a unit slip), not
/// intent. Coincident centres (100 % and more) have no contact normal and
/// exert no force at all. A sphere whose centre is behind a plane (on the
/// side its normal points away from) is refused whatever the overlap.
pub const OVERLAP_REFUSAL: f64 = 0.5;

/// A number for a message: as written when short (0.0005, 10000), else in
/// exponent form (1e-6, 1e300, 3.0000000000000003e-4).
pub fn show(x: f64) -> String {
    let plain = x.to_string();
    if plain.len() > 6 {
        format!("{x:e}")
    } else {
        plain
    }
}

/// A range for messages, e.g. "1e-9 to 10 m".
pub fn describe(range: (f64, f64), unit: &str) -> String {
    let text = format!("{} to {}", show(range.0), show(range.1));
    if unit.is_empty() {
        text
    } else {
        format!("{text} {unit}")
    }
}

/// Whether `x` is in `range` (both ends included; NaN is not).
pub fn within(x: f64, range: (f64, f64)) -> bool {
    x >= range.0 && x <= range.1
}

/// |v|, computed without overflow for any finite components.
pub fn norm(v: [f64; 3]) -> f64 {
    let scale = v.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
    if scale == 0.0 || !scale.is_finite() {
        return scale;
    }
    let u = [v[0] / scale, v[1] / scale, v[2] / scale];
    scale * (u[0] * u[0] + u[1] * u[1] + u[2] * u[2]).sqrt()
}

/// A length or a distance for a message: four significant digits.
pub fn metres(x: f64) -> String {
    format!("{x:.4e} m")
}
