//! Normal sub-models (LAMMPS GRANULAR `gran_sub_mod_normal.cpp`): one file
//! per law, each a small `Copy` type with the same few methods
//! ([`NormalSubModel`]). Which laws exist, their names, parameters and
//! capabilities are rows of [`super::registry`]; nothing here lists them.

use super::ContactHistory;
use crate::material::PairProperties;

// One `pub mod` per registry row, named by the row (`hooke::Hooke` is
// `normal/hooke.rs`): a new law is its file and its row, nothing here.
super::registry::normal_modules!();

/// A normal law resolved for one pair of bodies.
pub trait NormalSubModel: Copy + std::fmt::Debug {
    /// The law for `pair` with its parameters `params`, in the order of its
    /// registry row (already checked against the row's ranges).
    fn new(params: &[f64], pair: &PairProperties) -> Self;

    /// Normal force, N, repulsive positive, at overlap h > 0 (m) and overlap
    /// rate ḣ (m/s, positive approaching), before damping and clamp.
    fn force(&self, overlap: f64, overlap_rate: f64, history: &ContactHistory) -> f64;

    /// Updates the contact's history after an accepted step ending at
    /// (`overlap`, `overlap_rate`), the pair still in contact. History-free
    /// laws keep the default (nothing).
    #[inline(always)]
    fn update(&self, _overlap: f64, _overlap_rate: f64, _history: &mut ContactHistory) {}

    /// Elastic energy stored in the contact at overlap h (J): the work of
    /// the force along its current branch, ∫ F dh from where it vanishes
    /// (for an energy balance; a hysteretic law's lost work is not in it).
    fn elastic_energy(&self, overlap: f64, history: &ContactHistory) -> f64;

    /// The stiffness a damping scales with: k of the loading branch
    /// F = k h^α, N/m^α.
    fn stiffness(&self) -> f64;

    /// Duration (s) of a gravity-free impact at `impact_speed` (m/s) of the
    /// effective `mass` (kg), without damping: the time-step scale.
    fn contact_time_estimate(&self, mass: f64, impact_speed: f64) -> f64;
}
