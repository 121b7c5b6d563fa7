//! The damped contact model of the bounce: the physics crate's normal
//! sub-model plus its damping sub-model, combined by one model object that
//! applies the no-attraction clamp, as LAMMPS GRANULAR's
//! `GranularModel::calculate_forces` does (`Fntot = Fne + Fdamp`, then
//! `if (limit_damping && Fntot < 0) Fntot = 0`).
//!
//! The force formulas are the physics sub-models' own (one implementation
//! of each, shared with the many-particle engine). What is added here is
//! the event-resolved bounce's extension ([`NormalContactLaw`]): scaling,
//! the smoothness at the onset and the onset derivatives of the combined
//! force. The clamp is a type parameter, so that the time loop is
//! monomorphised for it (it locates where the clamped force returns to
//! zero: [`NormalContactLaw::NON_ATTRACTIVE`]).

use super::{NormalContactLaw, Onset};
use dembound_physics::contact::damping::{
    none::NoDamping, tsuji::Tsuji, viscoelastic::Viscoelastic, viscous::Viscous, DampingSubModel,
};
use dembound_physics::contact::normal::NormalSubModel;
use dembound_physics::contact::peak::{self, Linearization};
use dembound_physics::contact::ContactHistory;

/// What the bounce needs of a damping sub-model beyond the physics trait.
pub trait BounceDamping: DampingSubModel + Send + Sync {
    /// How smooth the damping leaves the overlap at the contact onset.
    const ONSET: Onset;

    /// True when the damping force depends on the overlap rate.
    const RATE_DEPENDENT: bool = true;

    /// c of a damping force c ḣ, linear in the rate and independent of the
    /// overlap (then the onset derivatives have a closed recursion); `None`
    /// otherwise.
    fn linear_rate(&self) -> Option<f64>;
}

impl BounceDamping for NoDamping {
    const ONSET: Onset = Onset::Smooth;
    const RATE_DEPENDENT: bool = false;

    fn linear_rate(&self) -> Option<f64> {
        Some(0.0)
    }
}

/// F_d = c ḣ is analytic in (h, ḣ).
impl BounceDamping for Viscous {
    const ONSET: Onset = Onset::Smooth;

    fn linear_rate(&self) -> Option<f64> {
        Some(self.coefficient)
    }
}

/// F_d = γ h^(1/4) ḣ: h''' ∝ h^(−3/4) at the onset.
impl BounceDamping for Tsuji {
    const ONSET: Onset = Onset::Singular;

    fn linear_rate(&self) -> Option<f64> {
        None
    }
}

/// F_d = (3/2) k A h^(1/2) ḣ: h''' ∝ h^(−1/2) at the onset.
impl BounceDamping for Viscoelastic {
    const ONSET: Onset = Onset::Singular;

    fn linear_rate(&self) -> Option<f64> {
        None
    }
}

/// Normal law `N` plus damping `D`; F = max(F, 0) when `CLAMPED` (LAMMPS
/// `limit_damping`, LIGGGHTS `limitForce`), else the force may pull.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Damped<N, D, const CLAMPED: bool> {
    /// The normal sub-model (physics crate).
    pub normal: N,
    /// The damping sub-model (physics crate).
    pub damping: D,
}

impl<N, D, const CLAMPED: bool> NormalContactLaw for Damped<N, D, CLAMPED>
where
    N: NormalContactLaw + NormalSubModel,
    D: BounceDamping,
{
    type History = N::History;

    const NON_ATTRACTIVE: bool = CLAMPED || N::NON_ATTRACTIVE;

    fn name(&self) -> &'static str {
        NormalContactLaw::name(&self.normal)
    }

    /// The normal force plus the damping force, then the clamp. The
    /// continuation to h < 0 is the sub-models' own (each is odd in h or
    /// uses |h|).
    #[inline(always)]
    fn force(&self, overlap: f64, overlap_rate: f64, history: &Self::History) -> f64 {
        let f = NormalContactLaw::force(&self.normal, overlap, overlap_rate, history)
            + self.damping.force(overlap, overlap_rate);
        if CLAMPED {
            f.max(0.0)
        } else {
            f
        }
    }

    #[inline(always)]
    fn unclamped_force(&self, overlap: f64, overlap_rate: f64, history: &Self::History) -> f64 {
        self.normal.unclamped_force(overlap, overlap_rate, history)
            + self.damping.force(overlap, overlap_rate)
    }

    #[inline(always)]
    fn update_history(&self, overlap: f64, overlap_rate: f64, history: &mut Self::History) {
        self.normal.update_history(overlap, overlap_rate, history)
    }

    fn scaled(&self, factor: f64) -> Self {
        Self {
            normal: self.normal.scaled(factor),
            damping: self.damping.scaled(factor),
        }
    }

    fn depends_on_rate(&self) -> bool {
        self.normal.depends_on_rate() || D::RATE_DEPENDENT
    }

    /// The normal law's elastic time times the damping's factor
    /// ([`DampingSubModel::time_factor`]).
    fn contact_time_estimate(&self, mass: f64, impact_speed: f64) -> f64 {
        NormalContactLaw::contact_time_estimate(&self.normal, mass, impact_speed)
            * self.damping.time_factor(mass, impact_speed)
    }

    /// The normal law's energy and stiffness and the damping's coefficient
    /// at the largest overlap ([`peak`]); `None` without a rate-dependent
    /// damping.
    fn damped_peak(&self, mass: f64, impact_speed: f64, gravity: f64) -> Option<Linearization> {
        if !D::RATE_DEPENDENT {
            return None;
        }
        let history = ContactHistory::default();
        let overlap = peak::largest_overlap(
            |h| self.normal.elastic_energy(h, &history),
            mass,
            impact_speed,
            gravity,
        );
        Some(peak::linearize(
            |h| NormalSubModel::force(&self.normal, h, 0.0, &history),
            |h| self.damping.force(h, 1.0),
            overlap,
            mass,
        ))
    }

    /// The rougher of the two.
    fn onset(&self) -> Onset {
        match (self.normal.onset(), D::ONSET) {
            (Onset::Singular, _) | (_, Onset::Singular) => Onset::Singular,
            (Onset::NonSmooth, _) | (_, Onset::NonSmooth) => Onset::NonSmooth,
            _ => Onset::Smooth,
        }
    }

    /// For a smooth linear law with a damping c ḣ (the spring–dashpot):
    /// from ḧ = g − ω² h − (c/m) ḣ, each further derivative is
    /// h⁽ⁿ⁺¹⁾ = −ω² h⁽ⁿ⁻¹⁾ − (c/m) h⁽ⁿ⁾. Otherwise 0 (unknown or infinite
    /// at h = 0⁺: the honest seed).
    fn onset_derivatives(&self, mass: f64, overlap_rate: f64, overlap_accel: f64) -> [f64; 3] {
        match self.damping.linear_rate() {
            Some(c) if self.onset() == Onset::Smooth => {
                let (p2, q) = (NormalSubModel::stiffness(&self.normal) / mass, c / mass);
                let h3 = -p2 * overlap_rate - q * overlap_accel;
                let h4 = -p2 * overlap_accel - q * h3;
                [h3, h4, -p2 * h3 - q * h4]
            }
            _ => [0.0; 3],
        }
    }

    fn at_max_overlap(&self, overlap: f64, history: &mut Self::History) -> bool {
        self.normal.at_max_overlap(overlap, history)
    }

    fn branch_derivatives(
        &self,
        mass: f64,
        overlap: f64,
        overlap_rate: f64,
        overlap_accel: f64,
        history: &Self::History,
    ) -> [f64; 3] {
        self.normal
            .branch_derivatives(mass, overlap, overlap_rate, overlap_accel, history)
    }
}
