//! LAMMPS GRANULAR's `hertz` normal model with its given stiffness:
//! F = k_n √R_eff h^(3/2) (`gran_sub_mod_normal.cpp`, `GranSubModNormalHertz`:
//! `Fne = k * contact_radius * delta` with `contact_radius = sqrt(dR)`),
//! k_n in Pa as LAMMPS takes it. With k_n = E_eff (the 4/3 included, eq 6)
//! it is this crate's `hertz`, so a LAMMPS input can be reproduced with its
//! own k_n, and a scene exported with its E_eff.

use super::NormalSubModel;
use crate::contact::{calibration::power_law_free_contact, ContactHistory};
use crate::material::PairProperties;

/// F = k h √|h| with k = k_n √R_eff (N/m^(3/2)).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HertzKn {
    /// k = k_n √R_eff, N/m^(3/2).
    pub stiffness: f64,
}

impl NormalSubModel for HertzKn {
    /// `params` = \[k_n\] (Pa); the pair's R_eff, not its E_eff.
    fn new(params: &[f64], pair: &PairProperties) -> Self {
        Self {
            stiffness: params[0] * pair.radius.sqrt(),
        }
    }

    #[inline(always)]
    fn force(&self, overlap: f64, _overlap_rate: f64, _history: &ContactHistory) -> f64 {
        self.stiffness * overlap * overlap.abs().sqrt()
    }

    /// (2/5) k h^(5/2).
    fn elastic_energy(&self, overlap: f64, _history: &ContactHistory) -> f64 {
        0.4 * self.stiffness * overlap * overlap * overlap.abs().sqrt()
    }

    fn stiffness(&self) -> f64 {
        self.stiffness
    }

    /// The Hertz time 0.8 B(2/5, 1/2) h_max/v (eq 30) for this k.
    fn contact_time_estimate(&self, mass: f64, impact_speed: f64) -> f64 {
        power_law_free_contact(self.stiffness, 1.5, mass, impact_speed).1
    }
}

#[cfg(test)]
mod tests {
    use crate::contact::{ContactHistory, ContactModel, DampingKind, NormalLaw};
    use crate::material::{Material, PairProperties};

    /// With k_n = E_eff the law is `hertz`, force and contact time to the
    /// last bits (√R_eff formed the same way), and a registry law like any
    /// other: built, validated and labelled from its row.
    #[test]
    fn with_the_pair_modulus_it_is_hertz() {
        let grain = Material {
            density: 2500.0,
            youngs_modulus: 7.0e10,
            poisson_ratio: 0.25,
        };
        let pair = PairProperties::spheres(1e-3, 1e-5, &grain, 2e-3, 8e-5, &grain);
        let given = ContactModel::elastic(NormalLaw::HertzKn {
            stiffness: pair.modulus,
        });
        assert!(given.validate().is_ok());
        assert_eq!(given.label(), format!("hertz-kn (k_n = {})", pair.modulus));
        let (a, b) = (
            given.pair(&pair),
            ContactModel::elastic(NormalLaw::Hertz).pair(&pair),
        );
        let h = ContactHistory::default();
        for overlap in [1e-9, 3.7e-7, 2e-5] {
            assert_eq!(a.force(overlap, 0.1, &h), b.force(overlap, 0.1, &h));
        }
        assert_eq!(a.contact_time_estimate(0.3), b.contact_time_estimate(0.3));
        // Its family is Hertzian: the Hertz dampings combine with it, a
        // linear one does not (the registry's table).
        use crate::contact::{Damping, Dissipation};
        let damped = |kind| {
            ContactModel::damped(
                NormalLaw::HertzKn { stiffness: 1e9 },
                Damping::new(kind, Dissipation::Coefficient(0.1)),
            )
        };
        assert!(damped(DampingKind::Tsuji).validate().is_ok());
        assert!(damped(DampingKind::Viscous).validate().is_err());
        // k_n must be positive: the error names the key and the range.
        let bad = ContactModel::elastic(NormalLaw::HertzKn { stiffness: -1.0 });
        assert_eq!(bad.validate().unwrap_err().key, "contact.stiffness");
    }
}
