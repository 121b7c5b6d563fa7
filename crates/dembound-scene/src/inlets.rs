//! Spheres inserted during the run (`[[inlet]]`, issue 28), the way
//! LIGGGHTS's `fix insert/rate/region` pours them.
//!
//! **When.** Insertion events come every `every` steps (the inlet's key, or
//! [`default_every`]), the first at the first step at or after `start`
//! (never step 0), the last before `end`. Event k (k = 0, 1, …) inserts
//! the spheres due up to the end of its interval: round(ṅ · min((k + 1) ·
//! every · Δt, end − start)) in all, less those of the earlier events
//! (placed or not), so the count never drifts from the rate by more than
//! half a sphere. A mass rate Q (kg/s) is the number rate ṅ = Q / m̄, m̄
//! the mean sphere mass of the size distribution (fractions by number).
//!
//! **Where.** Each sphere draws its radius from the size distribution,
//! then up to `max_attempts` centres uniformly in the region shrunk by its
//! radius (the sphere lies wholly inside the region); the first centre
//! that overlaps nothing is taken: no free, fixed or boundary sphere
//! (periodic images included), no sphere placed earlier in the same event
//! (of this inlet or an earlier one), and no wall acting at the insertion
//! step (every element of every plane, cylinder and mesh wall at overlap
//! ≤ 0: distance ≥ R; a wall with `active = { from, to }` outside its
//! window is no obstacle, `crate::walls::gate`). A gate that switches on
//! later over spheres inserted in its volume closes into their overlaps:
//! the normal law's energy of those overlaps is booked as the gate energy
//! G at the switch, as for any gate closing on an overlap. Touching
//! (distance exactly R_i + R_j) is allowed. A sphere none of whose
//! centres fits is not placed: counted (`not_placed`), reported, never
//! silently lost.
//!
//! **Determinism.** The draws come from ChaCha8 seeded by the inlet's
//! `seed`, on stream (inlet index · 2⁴⁰ + event number): they depend on
//! nothing else, not on threads, MPI ranks nor the engine's order of the bodies.
//! The overlap test is exact (a hash grid only finds the candidates), so
//! the spheres placed are those of the scene's state. New spheres get the
//! input ids after every id the scene has had, in the order placed.
//!
//! **The engine.** An event forces a neighbour-list rebuild at its step
//! (`World::rebuild_budget`); the spheres are appended there, after the
//! removal of lost spheres (`crate::removal`) and before the lists are
//! built, mid-step: Verlet stores the half-step velocity v₀ − g Δt/2 (the
//! step's last half kick, by gravity alone since the sphere touches
//! nothing, completes it to v₀), Gear5 the predicted state (r₂ = g Δt²/2,
//! higher derivatives 0: exact for a free flight).
//!
//! **Energy.** Each inserted sphere brings in ½ m v₀² − m g·x (no spin):
//! booked as I, so that K + E + P + D − W + C − I = E₀ still closes and
//! the energy guard still judges D.
//!
//! **Region capacity.** Random sequential addition of equal spheres jams
//! at a solid fraction of about 0.38 in an unbounded space (Torquato,
//! Uche & Stillinger 2006, Phys Rev E 74 061308), less near walls; an
//! event whose volume ṅ · V̄ · every · Δt exceeds [`MAX_EVENT_FRACTION`] of
//! the region's volume cannot be placed by bounded attempts and is
//! refused (the error names the `rate`).

use crate::error::SceneError;

mod engine;
mod placement;
mod restart;
mod schedule;
mod size;

pub use crate::region::unit;
use crate::region::Region;
pub(crate) use engine::{insert_due, InsertHooks, OneProcess};
pub(crate) use placement::nearby;
pub use placement::{event_rng, place_event, Obstacles};
pub(crate) use restart::{record, restore};
pub use restart::{InletRecord, InletsRecord};
pub use schedule::{
    default_every, inlet_columns, Inlet, InletReport, Inlets, Inserted, BROUGHT_IN_COLUMN,
};
pub use size::SizeDistribution;

/// Default bound on the centres tried per sphere.
pub const DEFAULT_MAX_ATTEMPTS: u64 = 100;
/// At most this many rows in a size table.
pub const MAX_TABLE_ROWS: usize = 1000;
/// The largest volume an event may insert, as a fraction of the region's
/// volume (module doc: about half the jamming fraction of random
/// sequential addition, 0.38).
pub const MAX_EVENT_FRACTION: f64 = 0.2;
/// The volume the default interval inserts per event, as a fraction of
/// the region's ([`default_every`]).
pub const DEFAULT_EVENT_FRACTION: f64 = 0.05;

/// The rate of an inlet.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum InletRate {
    /// Spheres/s.
    Number(f64),
    /// kg/s.
    Mass(f64),
}

/// One `[[inlet]]` as the engine takes it (SI).
#[derive(Debug, Clone, PartialEq)]
pub struct InletSetup {
    /// Its cylinder's axis a unit vector.
    pub region: Region,
    pub rate: InletRate,
    pub size: SizeDistribution,
    /// Index into the setup's materials.
    pub material: usize,
    /// m/s.
    pub velocity: [f64; 3],
    /// s.
    pub start: f64,
    /// s; `None`: the run's end.
    pub end: Option<f64>,
    pub seed: u64,
    /// Steps between events; `None`: [`default_every`].
    pub every: Option<u64>,
    pub max_attempts: u64,
}

/// The smallest and largest radius each inlet inserts (m; empty without
/// inlets): the neighbour skin and cells are chosen for them too.
pub(crate) fn radii(setup: &crate::setup::SceneSetup) -> Vec<f64> {
    setup
        .inlets
        .iter()
        .flat_map(|i| <[f64; 2]>::from(i.size.radius_range()))
        .collect()
}

/// `setup` with, per inlet, a sphere of its smallest and one of its
/// largest radius at its region's centre moving at its velocity: the scene
/// the time-step rule judges (the inserted spheres' contacts bound Δt as
/// the others' do). The same setup without inlets.
pub(crate) fn with_probes(
    setup: &crate::setup::SceneSetup,
) -> std::borrow::Cow<'_, crate::setup::SceneSetup> {
    if setup.inlets.is_empty() {
        return std::borrow::Cow::Borrowed(setup);
    }
    let mut probed = setup.clone();
    for i in &setup.inlets {
        let (lo, hi) = i.region.bounds();
        let centre = [0, 1, 2].map(|a| 0.5 * (lo[a] + hi[a]));
        for radius in <[f64; 2]>::from(i.size.radius_range()) {
            probed.spheres.push(crate::setup::SphereInit {
                position: centre,
                velocity: i.velocity,
                radius,
                material: i.material,
                fixed: false,
                group: None,
            });
        }
    }
    std::borrow::Cow::Owned(probed)
}

/// The energy the inserted spheres brought in by observation `o`, J
/// (`None` without inlets).
pub(crate) fn brought_in(o: &crate::simulation::Observation) -> Option<f64> {
    (!o.inlets.is_empty()).then(|| o.inlets.iter().map(|i| i.energy).sum())
}

/// A checkpoint of a scene with inlets is not restarted on several MPI
/// ranks yet (each rank would have to take the inserted spheres of its
/// sub-domain); without mpirun it is.
pub(crate) fn refuse_restart_under_mpi(setups: &[InletSetup]) -> Result<(), SceneError> {
    if setups.is_empty() {
        return Ok(());
    }
    Err(SceneError::Checkpoint(
        "the scene has [[inlet]] sections (inlet[0]): a restart of a scene with inlets runs          without mpirun for now"
            .into(),
    ))
}

#[cfg(test)]
mod tests;
