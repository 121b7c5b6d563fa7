//! Per-pair contact models, after LAMMPS GRANULAR's 2022 design
//! (`granular_model.cpp`): small sub-models with the same few methods, one
//! registry row per sub-model, and one model object that combines the
//! normal law with damping and applies the no-attraction clamp.
//!
//! Two levels:
//! - [`ContactModel`]: what the user configures (law, damping, restitution,
//!   clamp). Material-independent.
//! - [`PairLaw`]: the model for one pair of bodies, its coefficients
//!   computed once from the pair's [`PairProperties`]
//!   ([`ContactModel::pair`]). `force` and `update` are all a time loop
//!   needs; the law keeps its own [`ContactHistory`] correct from those two
//!   calls alone (no event location required), so any loop can drive it.
//!
//! Sign conventions: overlap h ≥ 0 (m) while in contact, overlap rate ḣ
//! (m/s) positive while the bodies approach, normal force F (N) repulsive
//! positive.

use crate::material::PairProperties;

/// Which normal law (eq 4: F = E_eff R_eff^(2−α) h^α).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum NormalLaw {
    /// α = 1: F = E_eff R_eff h.
    Linear,
    /// α = 3/2: F = E_eff √R_eff h^(3/2).
    Hertz,
}

/// What a pair remembers of its current contact. One type for every law so
/// that a many-body store keeps one plain record per contacting pair; a new
/// contact starts from `Default`.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct ContactHistory {
    /// Largest overlap of this contact so far, m (hysteretic laws).
    pub max_overlap: f64,
}

/// A configured contact model (normal law, damping, clamp).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactModel {
    pub normal: NormalLaw,
    /// `false`: F = max(F, 0), the force never pulls (LAMMPS
    /// `limit_damping`, LIGGGHTS `limitForce`).
    pub attractive: bool,
}

impl ContactModel {
    /// An elastic model of `normal` law.
    pub fn elastic(normal: NormalLaw) -> Self {
        Self {
            normal,
            attractive: false,
        }
    }

    /// The model for one pair: its coefficients from the pair's properties.
    pub fn pair(&self, pair: &PairProperties) -> PairLaw {
        let stiffness = match self.normal {
            NormalLaw::Linear => pair.modulus * pair.radius,
            NormalLaw::Hertz => pair.modulus * pair.radius.sqrt(),
        };
        PairLaw {
            normal: self.normal,
            stiffness,
            mass: pair.mass,
            attractive: self.attractive,
        }
    }
}

/// The contact model of one pair, coefficients resolved. `Copy`, small: a
/// many-body loop may cache it per pair or per pair of material classes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PairLaw {
    normal: NormalLaw,
    /// Stiffness k of F = k h^α, N/m^α.
    stiffness: f64,
    /// Effective mass, kg.
    mass: f64,
    attractive: bool,
}

impl PairLaw {
    /// Normal force (N, repulsive positive) at overlap `overlap` > 0 (m)
    /// and overlap rate `overlap_rate` (m/s), given the contact's history.
    /// Callers evaluate it only in contact (h > 0).
    #[inline(always)]
    pub fn force(&self, overlap: f64, _overlap_rate: f64, _history: &ContactHistory) -> f64 {
        let f = match self.normal {
            NormalLaw::Linear => self.stiffness * overlap,
            NormalLaw::Hertz => self.stiffness * overlap * overlap.sqrt(),
        };
        if self.attractive {
            f
        } else {
            f.max(0.0)
        }
    }

    /// Updates the history after an accepted step that ends at
    /// (`overlap`, `overlap_rate`) with the pair still in contact.
    #[inline(always)]
    pub fn update(&self, overlap: f64, _overlap_rate: f64, history: &mut ContactHistory) {
        history.max_overlap = history.max_overlap.max(overlap);
    }

    /// Duration (s) of a gravity-free impact of this pair at
    /// `impact_speed` (m/s): the time-step scale Δt = η T_c.
    pub fn contact_time_estimate(&self, impact_speed: f64) -> f64 {
        match self.normal {
            // Half a period of the harmonic oscillator, π √(m/k) (eq 27).
            NormalLaw::Linear => std::f64::consts::PI * (self.mass / self.stiffness).sqrt(),
            // T_c = 2.9432… h_max/v with h_max = (5 m v²/(4 k))^(2/5)
            // (eqs 29–30; the constant is 0.8 B(2/5, 1/2)).
            NormalLaw::Hertz => {
                let h_max =
                    (1.25 * self.mass * impact_speed * impact_speed / self.stiffness).powf(0.4);
                HERTZ_CONTACT_TIME_FACTOR * h_max / impact_speed
            }
        }
    }

    /// True when the force depends on the overlap rate (damping).
    pub fn depends_on_rate(&self) -> bool {
        false
    }
}

/// 0.8 B(2/5, 1/2) = 2.9432751843…: the gravity-free Hertz contact time in
/// units of h_max/v (eq 30).
pub const HERTZ_CONTACT_TIME_FACTOR: f64 = 2.943_275_184_3;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::{Material, PairProperties};

    fn paper_pair() -> PairProperties {
        // The paper's validation pair (section 4.2): r = ζ = 100.
        let m = Material {
            density: 1000.0,
            youngs_modulus: 1.0e10,
            poisson_ratio: 0.3,
        };
        let b = Material {
            youngs_modulus: 1.0e12,
            ..m
        };
        let r = 0.5e-3;
        PairProperties::spheres(r, m.sphere_mass(r), &m, 100.0 * r, f64::INFINITY, &b)
    }

    #[test]
    fn linear_contact_time_is_848_ns() {
        // Paper section 4.2: T_cL = 848.3 ns.
        let law = ContactModel::elastic(NormalLaw::Linear).pair(&paper_pair());
        let t = law.contact_time_estimate(0.3132092);
        assert!((t * 1e9 - 848.3).abs() < 0.05, "{t}");
    }

    #[test]
    fn hertz_contact_time_is_4_926_us() {
        // The exact gravity-free T_c of the validation case at the
        // paper's impact speed v_c = 0.3132092 m/s is 4.925789 µs (the
        // bounce study's exact reference, 1e-15); gravity is absent here
        // and shifts the with-gravity value by < 1e-4.
        let law = ContactModel::elastic(NormalLaw::Hertz).pair(&paper_pair());
        let t = law.contact_time_estimate(0.3132092);
        assert!((t / 4.925789e-6 - 1.0).abs() < 1e-4, "{t}");
    }
}
