//! Hooke's law with a given constant stiffness, F = k_n h, k_n in N/m,
//! independent of the materials and radii: the `hooke` normal model of
//! LAMMPS GRANULAR (`gran_sub_mod_normal.cpp`, `hooke` with k_n given) and
//! LIGGGHTS (`model hooke/stiffness`), the usual choice when a DEM user
//! picks the stiffness for the time step rather than from E. It is
//! linear, so viscous damping combines with it (c = 2ξ√(k_n m)).

use super::NormalSubModel;
use crate::contact::ContactHistory;
use crate::material::PairProperties;

/// F = k_n h.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Hooke {
    /// k_n, N/m.
    pub stiffness: f64,
}

impl NormalSubModel for Hooke {
    /// `params` = \[k_n\] (N/m); the pair's E_eff and R_eff are not used.
    fn new(params: &[f64], _pair: &PairProperties) -> Self {
        Self {
            stiffness: params[0],
        }
    }

    #[inline(always)]
    fn force(&self, overlap: f64, _overlap_rate: f64, _history: &ContactHistory) -> f64 {
        self.stiffness * overlap
    }

    /// k_n h²/2.
    fn elastic_energy(&self, overlap: f64, _history: &ContactHistory) -> f64 {
        0.5 * self.stiffness * overlap * overlap
    }

    fn stiffness(&self) -> f64 {
        self.stiffness
    }

    /// π √(m/k_n), half a period of the oscillator.
    fn contact_time_estimate(&self, mass: f64, _impact_speed: f64) -> f64 {
        std::f64::consts::PI * (mass / self.stiffness).sqrt()
    }
}

#[cfg(test)]
mod tests {
    use crate::contact::{ContactHistory, ContactModel, ContactSpec};
    use crate::material::{Material, PairProperties};

    #[test]
    fn hooke_is_a_given_stiffness_with_viscous_damping() {
        let m = Material {
            density: 2500.0,
            youngs_modulus: 7.0e10,
            poisson_ratio: 0.25,
        };
        let pair = PairProperties::sphere_plane(1e-3, m.sphere_mass(1e-3), &m, &m);
        // Elastic: F = k_n h whatever the material.
        let model = ContactModel::from_spec(&ContactSpec::law_with_value("hooke", 1.0e5)).unwrap();
        let law = model.pair(&pair);
        let none = ContactHistory::default();
        assert_eq!(law.force(1e-6, 0.0, &none), 1.0e5 * 1e-6);
        let t = law.contact_time_estimate(1.0);
        // One rounding apart.
        assert!((t / (std::f64::consts::PI * (pair.mass / 1.0e5).sqrt()) - 1.0).abs() < 1e-15);
        // With viscous damping, c = 2ξ√(k_n m) at the published ξ(e).
        let spec = ContactSpec {
            damping: "viscous".into(),
            restitution: Some(0.5),
            attractive: true,
            ..ContactSpec::law_with_value("hooke", 1.0e5)
        };
        let law = ContactModel::from_spec(&spec).unwrap().pair(&pair);
        let xi = crate::contact::restitution_to_damping_ratio(0.5);
        let c = 2.0 * xi * (1.0e5 * pair.mass).sqrt();
        let f = law.force(1e-6, 0.01, &none);
        assert!((f / (1.0e5 * 1e-6 + c * 0.01) - 1.0).abs() < 1e-14);
        // k_n must be given and > 0.
        let err = ContactModel::from_spec(&ContactSpec::law("hooke")).unwrap_err();
        assert_eq!(
            (err.key.as_str(), err.value.as_str()),
            ("contact.stiffness", "missing")
        );
        let err = ContactModel::from_spec(&ContactSpec::law_with_value("hooke", 0.0)).unwrap_err();
        assert!(err.allowed.contains("N/m"), "{err}");
    }
}
