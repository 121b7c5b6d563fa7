//! Many independent bouncing cases at once: [`simulate_batch`].
//!
//! Independent cases share no data, so this path advances a group of
//! lanes (cases) together in structure-of-arrays form: one vector
//! instruction does the same operation for every lane. The lanes step in
//! lockstep; a group holds two registers' worth of lanes (16 with AVX-512),
//! so that an iteration has two independent dependency chains.
//!
//! What is batched: Gear5, event stepping, the elastic Hertz and linear
//! laws, fixed boundary (any particle, boundary, motion, Δt rule). Each
//! lane runs one case contact by contact exactly as [`super::simulate`]
//! does: flight in closed form, the contact integrated on the same step
//! mesh (graded at both ends for Hertz), events located on the step's
//! polynomial. The per-step work (rescaling, prediction, force,
//! correction) is vector code written with explicit instructions
//! (`simd`), the lanes' state held in registers; the events (onset,
//! maximum overlap, rebound) run the scalar path's functions per lane, but
//! for the location of the event inside its step, which runs for all the
//! lanes with an event at once (`locate`; cases of similar length keep
//! their events in step).
//!
//! - The step sizes of the mesh depend on the case alone (and on the
//!   maximum overlap, once it is found), so the vector loop does not
//!   compute them: each lane's sizes wait in a ring of `RING` rows,
//!   written by scalar code a run at a time (the graded onset when a
//!   contact starts, the planned end when the maximum overlap is found;
//!   the graded sizes from a table per region size, the same bits as
//!   [`super::schedule`]); after the run the size is the lane's Δt.
//! - The next step's sizes, ratio powers and gain are computed at the end
//!   of the iteration before, off the state's latency chain.
//! - A lane's events are two comparisons with per-lane thresholds (the
//!   velocity against 0 until the maximum overlap is found, the position
//!   against 0 after; +∞ otherwise), so the loop has no masks to keep.
//! - The peak force is the force at the deepest step (the elastic laws'
//!   force is monotonic in the overlap, also when rounded), so the loop
//!   keeps one minimum per lane, not a force.
//!
//! A lane whose case ends takes the next case from a queue shared by all
//! threads, so lanes stay busy whatever the cases' lengths and both cores
//! finish together; results go straight into their slots. Each case is
//! resolved ([`super::plan`]) by the thread that takes it, with the law's
//! constant factors computed once.
//!
//! The vector code performs the scalar path's operations in the same order
//! (no fused multiply–add, no reassociation), so every [`RunOutcome`] is
//! identical to the last bit to the scalar path's (tested in
//! `tests/batch.rs` for all instruction sets available, and unit tests
//! here for the mesh and the event location).
//!
//! Instruction sets are chosen at run time: AVX-512, AVX2 (both with FMA
//! enabled for the compiler, which does not contract on its own), or the
//! baseline SSE2 build. Measurements: BENCHMARKS.md, `benches/batch.rs`.

use super::{simulate, RunOutcome, Scenario, Stepping};
use crate::contact::{ContactLawKind, DampingKind, Hertz, LinearSpring};
use crate::integrate::Scheme;
use crate::{Error, Result};
use kernel::run_kernel;
use queue::{Queue, Slot};
use rayon::prelude::*;

mod kernel;
mod lanes;
mod laws;
mod locate;
mod queue;
mod simd;
mod steps;

/// Instruction set of the batched kernel.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Isa {
    /// AVX-512F/DQ/VL with FMA (8 lanes in one register).
    Avx512,
    /// AVX2 with FMA (4 lanes per register).
    Avx2,
    /// The build's baseline (SSE2 on x86-64).
    Baseline,
}

impl Isa {
    /// The best instruction set this CPU has.
    pub fn detect() -> Self {
        [Isa::Avx512, Isa::Avx2]
            .into_iter()
            .find(|i| i.available())
            .unwrap_or(Isa::Baseline)
    }

    /// Whether this CPU can run the kernel built for `self`.
    pub fn available(self) -> bool {
        #[cfg(target_arch = "x86_64")]
        {
            match self {
                Isa::Avx512 => {
                    is_x86_feature_detected!("avx512f")
                        && is_x86_feature_detected!("avx512dq")
                        && is_x86_feature_detected!("avx512vl")
                        && is_x86_feature_detected!("avx2")
                        && is_x86_feature_detected!("fma")
                }
                Isa::Avx2 => is_x86_feature_detected!("avx2") && is_x86_feature_detected!("fma"),
                Isa::Baseline => true,
            }
        }
        #[cfg(not(target_arch = "x86_64"))]
        {
            self == Isa::Baseline
        }
    }

    /// Cases one thread advances together with this instruction set.
    pub fn lanes(self) -> usize {
        match self {
            Isa::Avx512 => LANES_AVX512,
            Isa::Avx2 => LANES_AVX2,
            Isa::Baseline => LANES_BASELINE,
        }
    }
}

/// Registers of lanes per kernel: two independent chains per iteration.
/// (Measured on Zen 4, AVX-512: 1 register 3% slower than 2; 3 no
/// better; AVX2: 4 registers 15% slower than 2, their spills.)
const GROUP_AVX512: usize = 2;
const GROUP_AVX2: usize = 2;
const GROUP_BASELINE: usize = 4;
const LANES_AVX512: usize = 8 * GROUP_AVX512;
const LANES_AVX2: usize = 4 * GROUP_AVX2;
const LANES_BASELINE: usize = 2 * GROUP_BASELINE;

/// Runs every scenario, the batchable ones (Gear5, event stepping, elastic
/// Hertz or linear law, fixed boundary) in SIMD lanes, the others one by
/// one with [`simulate`]; results in the order of `scenarios`, each as
/// `simulate(s, &mut ())` would give it. Runs in the current rayon pool.
pub fn simulate_batch(scenarios: &[Scenario]) -> Vec<Result<RunOutcome>> {
    simulate_batch_with(scenarios, Isa::detect())
}

/// [`simulate_batch`] with a chosen instruction set (falls back to the
/// baseline if the CPU lacks it): for tests and benchmarks.
pub fn simulate_batch_with(scenarios: &[Scenario], isa: Isa) -> Vec<Result<RunOutcome>> {
    let isa = if isa.available() { isa } else { Isa::Baseline };
    let mut hertz = Vec::new();
    let mut linear = Vec::new();
    let mut scalar = Vec::new();
    for (index, s) in scenarios.iter().enumerate() {
        match batch_law(s) {
            Some(ContactLawKind::Hertz) => hertz.push(index),
            Some(_) => linear.push(index),
            None => scalar.push(index),
        }
    }
    let placeholders =
        |n: usize| -> Vec<Slot> { (0..n).map(|_| Err(Error::NeverReachesBoundary)).collect() };
    let (mut hertz_out, mut linear_out) = (placeholders(hertz.len()), placeholders(linear.len()));
    let groups = (hertz.len() + linear.len()).div_ceil(isa.lanes());
    let tasks = rayon::current_num_threads().min(groups);
    let unbatched = {
        let hertz = Queue::new(scenarios, &hertz, &mut hertz_out);
        let linear = Queue::new(scenarios, &linear, &mut linear_out);
        rayon::join(
            || {
                (0..tasks).into_par_iter().for_each(|_| {
                    run_kernel::<Hertz>(&hertz, isa);
                    run_kernel::<LinearSpring>(&linear, isa);
                })
            },
            || {
                scalar
                    .par_iter()
                    .map(|&i| simulate(&scenarios[i], &mut ()))
                    .collect::<Vec<Slot>>()
            },
        )
        .1
    };
    // Every slot has been written; the placeholders are never seen.
    if linear.is_empty() && scalar.is_empty() {
        return hertz_out;
    }
    if hertz.is_empty() && scalar.is_empty() {
        return linear_out;
    }
    let mut results = placeholders(scenarios.len());
    for (indices, out) in [
        (hertz, hertz_out),
        (linear, linear_out),
        (scalar, unbatched),
    ] {
        for (i, result) in indices.into_iter().zip(out) {
            results[i] = result;
        }
    }
    results
}

/// The law a scenario is batched with, if it is batched: elastic Hertz or
/// linear, Gear5, event stepping, fixed boundary (a free boundary's
/// per-sphere velocities are recovered by the scalar path).
fn batch_law(s: &Scenario) -> Option<ContactLawKind> {
    let i = &s.integration;
    let c = &s.contact;
    let elastic = c.damping == DampingKind::None;
    (i.scheme == Scheme::Gear5 && i.stepping == Stepping::Event && elastic && s.boundary.fixed)
        .then_some(c.law)
        .filter(|law| matches!(law, ContactLawKind::Hertz | ContactLawKind::Linear))
}
