//! The work queue of the batch: cases of one law handed out a chunk at a
//! time to the kernels of all threads, each case resolved by the thread
//! that takes it.

use super::laws::{LaneLaw, Planned};
use crate::bounce::{plan, Problem, RunOutcome, Scenario, StepRule};
use crate::Result;
use std::sync::Mutex;

/// A run's result.
pub(super) type Slot = Result<RunOutcome>;

/// Cases a kernel takes from its queue at a time.
pub(super) const CHUNK: usize = 32;

/// Cases of one law (indices into the batch) and their result slots,
/// handed out a chunk at a time to the kernels of all threads.
pub(super) struct Queue<'a> {
    pub(super) scenarios: &'a [Scenario],
    pub(super) len: usize,
    #[allow(clippy::type_complexity)]
    pub(super) chunks:
        Mutex<std::iter::Zip<std::slice::Chunks<'a, usize>, std::slice::ChunksMut<'a, Slot>>>,
}

impl<'a> Queue<'a> {
    pub(super) fn new(
        scenarios: &'a [Scenario],
        indices: &'a [usize],
        out: &'a mut [Slot],
    ) -> Self {
        Queue {
            scenarios,
            len: indices.len(),
            chunks: Mutex::new(indices.chunks(CHUNK).zip(out.chunks_mut(CHUNK))),
        }
    }

    pub(super) fn len(&self) -> usize {
        self.len
    }

    /// The next chunk of cases, if any is left.
    pub(super) fn take(&self) -> Option<Chunk<'a>> {
        // A poisoned lock (a panic elsewhere) still holds a valid iterator.
        let mut chunks = self.chunks.lock().unwrap_or_else(|e| e.into_inner());
        let (indices, out) = chunks.next()?;
        Some(Chunk {
            indices,
            out,
            next: 0,
        })
    }
}

/// Cases a kernel has taken, and where their results go.
pub(super) struct Chunk<'a> {
    pub(super) indices: &'a [usize],
    pub(super) out: &'a mut [Slot],
    /// The next case to start.
    pub(super) next: usize,
}

/// Where a case's result goes: (chunk, position) in the kernel's chunks.
pub(super) type SlotId = (usize, usize);

/// One case, resolved.
pub(super) struct Case {
    pub(super) slot: SlotId,
    pub(super) problem: Problem,
    /// The law's stiffness and that of the law scaled by 1/m.
    pub(super) stiffness: f64,
    pub(super) accel_stiffness: f64,
    pub(super) inv_mass: f64,
    pub(super) budget: u64,
}

/// Resolves a case as [`plan`] does (same checks, same errors, same bits),
/// with the law built once and its contact-time estimate's constant factor
/// computed once per law ([`LaneLaw::estimate`]).
pub(super) fn plan_case<L: LaneLaw>(slot: SlotId, s: &Scenario) -> Result<Case> {
    s.validate()?;
    let law = L::for_pair(&s.pair());
    let problem = match s.step_rule() {
        // The pilot runs dominate; plan them exactly as the scalar path does.
        StepRule::Tolerance(_) => plan(s)?,
        _ => Problem::new(s, &Planned(law))?,
    };
    let inv_mass = 1.0 / problem.mass;
    Ok(Case {
        slot,
        problem,
        stiffness: law.stiffness(),
        accel_stiffness: law.scaled(inv_mass).stiffness(),
        inv_mass,
        budget: (100.0 * problem.contact_time_estimate / problem.dt) as u64 + 1_000_000,
    })
}
