//! Plausibility warnings for likely unit slips: printed on stderr, the run
//! still happens (exit 0). Inputs inside the accepted ranges
//! ([`dembound_core::bounce::limits`]) but unusual for a DEM particle.

use dembound_core::bounce::{ContactRecord, Scenario};

/// Particle radius above which a warning is printed, m.
pub const LARGE_RADIUS: f64 = 0.1;
/// Young's modulus below which a warning is printed, Pa.
pub const SOFT_MODULUS: f64 = 1e5;
/// h_max/R_eff above which a warning is printed: the Hertz and linear laws
/// are small-strain theories (contact radius a = √(R h), a/R = √(h/R) is
/// already 0.22 at h/R = 5 %).
pub const LARGE_STRAIN: f64 = 0.05;

/// Warnings about the inputs of `s`.
pub fn inputs(s: &Scenario) -> Vec<String> {
    let mut out = Vec::new();
    let p = &s.particle;
    if p.radius > LARGE_RADIUS {
        out.push(format!(
            "particle.radius = {} m is above {LARGE_RADIUS} m: a radius in mm or µm \
             entered as if it were in m? (all inputs are SI)",
            p.radius
        ));
    }
    if p.youngs_modulus < SOFT_MODULUS {
        out.push(format!(
            "particle.youngs_modulus = {} Pa is below {SOFT_MODULUS:e} Pa (softer than \
             rubber): a modulus in MPa or GPa entered as if it were in Pa? (all inputs are SI)",
            p.youngs_modulus
        ));
    }
    let e_b = p.youngs_modulus * s.boundary.modulus_ratio;
    if e_b < SOFT_MODULUS {
        out.push(format!(
            "the boundary's Young's modulus ζ E_m = {e_b:e} Pa is below {SOFT_MODULUS:e} Pa: \
             is boundary.modulus_ratio = {} meant?",
            s.boundary.modulus_ratio
        ));
    }
    out
}

/// Warnings about the contacts of a run of `s`: overlaps that leave the
/// small-strain range of the contact laws.
pub fn contacts(s: &Scenario, contacts: &[ContactRecord]) -> Vec<String> {
    let r_eff = s.pair().effective_radius();
    let worst = contacts
        .iter()
        .map(|c| c.max_overlap / r_eff)
        .fold(0.0, f64::max);
    if worst > LARGE_STRAIN {
        vec![format!(
            "the maximum overlap reaches {:.3} % of the effective radius R_eff = {r_eff:e} m \
             (above {} %): the contact laws are small-strain theories and lose their meaning \
             here; check the units of particle.radius, particle.youngs_modulus and motion.gap",
            100.0 * worst,
            100.0 * LARGE_STRAIN
        )]
    } else {
        Vec::new()
    }
}

/// Prints `warnings` on stderr.
pub fn print(warnings: &[String]) {
    for w in warnings {
        if !super::capture_warning(w) {
            eprintln!("warning: {w}");
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_validation_case_raises_no_warning() {
        assert!(inputs(&Scenario::default()).is_empty());
    }

    #[test]
    fn unit_slips_are_flagged() {
        let mut s = Scenario::default();
        s.particle.radius = 0.5; // 0.5 mm given as m
        s.particle.youngs_modulus = 63.0; // 63 GPa given in GPa
        assert_eq!(inputs(&s).len(), 3); // radius, E_m and E_b = 100 E_m
    }

    #[test]
    fn large_overlaps_are_flagged() {
        let s = Scenario::default();
        let r_eff = s.pair().effective_radius();
        let contact = |h: f64| ContactRecord {
            t_contact: 0.0,
            t_max_overlap: 0.0,
            t_rebound: 0.0,
            t_force_zero: None,
            duration: 0.0,
            max_overlap: h,
            max_force: 0.0,
            max_acceleration: 0.0,
            impact_velocity: -1.0,
            rebound_velocity: 1.0,
            restitution: 1.0,
            energy_dissipated: 0.0,
            apex_height: None,
            steps: 0,
            bodies: None,
        };
        assert!(contacts(&s, &[contact(0.04 * r_eff)]).is_empty());
        assert_eq!(contacts(&s, &[contact(0.06 * r_eff)]).len(), 1);
    }
}
