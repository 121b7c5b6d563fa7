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

use super::events::{time_to_surface, Crossing};
use super::schedule::{graded_step, GradedSteps, Grading};
use super::{
    plan, simulate, ContactRecord, Problem, RunOutcome, Scenario, SimulationError, StepRule,
    Stepping,
};
use crate::contact::{ContactLawKind, DampingKind, Hertz, LinearSpring, NormalContactLaw, Onset};
use crate::integrate::{pascal, Gear5, Gear5State, Integrator, Kinematics, Scheme};
use crate::material::ContactPair;
use locate::{Located, Steps, MAX_STEPS};
use rayon::prelude::*;
#[cfg(target_arch = "x86_64")]
use simd::{Avx2, Avx512, Sse2};
use simd::{Simd, V};
use std::sync::{Mutex, OnceLock};

mod locate;
mod simd;

/// Rows of the step-size ring (a power of two).
const RING: usize = 64;
/// A lane's run of sizes longer than the ring is continued once the ring
/// holds no more than this many of them.
const REFILL: u64 = 8;
/// Graded regions of up to this many steps take their sizes from a table.
const MAX_TABLE: u64 = 1 << 14;

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
pub fn simulate_batch(scenarios: &[Scenario]) -> Vec<Result<RunOutcome, SimulationError>> {
    simulate_batch_with(scenarios, Isa::detect())
}

/// [`simulate_batch`] with a chosen instruction set (falls back to the
/// baseline if the CPU lacks it): for tests and benchmarks.
pub fn simulate_batch_with(
    scenarios: &[Scenario],
    isa: Isa,
) -> Vec<Result<RunOutcome, SimulationError>> {
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
    let placeholders = |n: usize| -> Vec<Slot> {
        (0..n)
            .map(|_| Err(SimulationError::NeverReachesBoundary))
            .collect()
    };
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

/// A run's result.
type Slot = Result<RunOutcome, SimulationError>;

/// Cases a kernel takes from its queue at a time.
const CHUNK: usize = 32;

/// Cases of one law (indices into the batch) and their result slots,
/// handed out a chunk at a time to the kernels of all threads.
struct Queue<'a> {
    scenarios: &'a [Scenario],
    len: usize,
    #[allow(clippy::type_complexity)]
    chunks: Mutex<std::iter::Zip<std::slice::Chunks<'a, usize>, std::slice::ChunksMut<'a, Slot>>>,
}

impl<'a> Queue<'a> {
    fn new(scenarios: &'a [Scenario], indices: &'a [usize], out: &'a mut [Slot]) -> Self {
        Queue {
            scenarios,
            len: indices.len(),
            chunks: Mutex::new(indices.chunks(CHUNK).zip(out.chunks_mut(CHUNK))),
        }
    }

    fn len(&self) -> usize {
        self.len
    }

    /// The next chunk of cases, if any is left.
    fn take(&self) -> Option<Chunk<'a>> {
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
struct Chunk<'a> {
    indices: &'a [usize],
    out: &'a mut [Slot],
    /// The next case to start.
    next: usize,
}

/// Where a case's result goes: (chunk, position) in the kernel's chunks.
type SlotId = (usize, usize);

/// One case, resolved.
struct Case {
    slot: SlotId,
    problem: Problem,
    /// The law's stiffness and that of the law scaled by 1/m.
    stiffness: f64,
    accel_stiffness: f64,
    inv_mass: f64,
    budget: u64,
}

/// Resolves a case as [`plan`] does (same checks, same errors, same bits),
/// with the law built once and its contact-time estimate's constant factor
/// computed once per law ([`LaneLaw::estimate`]).
fn plan_case<L: LaneLaw>(slot: SlotId, s: &Scenario) -> Result<Case, SimulationError> {
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

/// A batched law for [`Problem::new`]: the law itself, with its
/// contact-time estimate from [`LaneLaw::estimate`].
#[derive(Debug, Clone, Copy)]
struct Planned<L>(L);

impl<L: LaneLaw> NormalContactLaw for Planned<L> {
    type History = ();
    fn name(&self) -> &'static str {
        self.0.name()
    }
    fn force(&self, overlap: f64, overlap_rate: f64, history: &()) -> f64 {
        self.0.force(overlap, overlap_rate, history)
    }
    fn scaled(&self, factor: f64) -> Self {
        Planned(self.0.scaled(factor))
    }
    fn depends_on_rate(&self) -> bool {
        self.0.depends_on_rate()
    }
    fn contact_time_estimate(&self, mass: f64, impact_speed: f64) -> f64 {
        self.0.estimate(mass, impact_speed)
    }
    fn onset(&self) -> Onset {
        self.0.onset()
    }
    fn onset_derivatives(&self, mass: f64, overlap_rate: f64, overlap_accel: f64) -> [f64; 3] {
        self.0.onset_derivatives(mass, overlap_rate, overlap_accel)
    }
}

/// A law the kernel runs: its force in lanes, the same arithmetic as
/// [`NormalContactLaw::force`], which must be nondecreasing in the overlap
/// (also in floating point) for the peak force to be the deepest step's.
trait LaneLaw: NormalContactLaw<History = ()> + Copy {
    const GRADING: Grading;
    fn for_pair(pair: &ContactPair) -> Self;
    fn with_stiffness(k: f64) -> Self;
    fn stiffness(&self) -> f64;
    /// [`NormalContactLaw::contact_time_estimate`], bit for bit (checked by
    /// a test), with the factors that depend on the law alone computed once.
    fn estimate(&self, mass: f64, impact_speed: f64) -> f64;
    fn lanes_force<S: Simd, const G: usize>(k: V<S, G>, overlap: V<S, G>) -> V<S, G>;
}

impl LaneLaw for Hertz {
    const GRADING: Grading = Grading::Power;
    fn for_pair(pair: &ContactPair) -> Self {
        pair.law::<Hertz>(&[])
    }
    fn with_stiffness(k: f64) -> Self {
        Hertz { stiffness: k }
    }
    fn stiffness(&self) -> f64 {
        self.stiffness
    }
    /// `power_law_free_contact(k, 1.5, m, v).1` with its Beta-function
    /// factor (three Γ calls) computed once.
    fn estimate(&self, mass: f64, speed: f64) -> f64 {
        static BETA_FACTOR: OnceLock<f64> = OnceLock::new();
        let beta = 1.5 + 1.0;
        let b = *BETA_FACTOR.get_or_init(|| {
            libm::tgamma(1.0 / beta) * libm::tgamma(0.5) / libm::tgamma(1.0 / beta + 0.5)
        });
        let max_overlap = (beta * mass * speed * speed / (2.0 * self.stiffness)).powf(1.0 / beta);
        2.0 * max_overlap / speed * b / beta
    }
    #[inline(always)]
    fn lanes_force<S: Simd, const G: usize>(k: V<S, G>, h: V<S, G>) -> V<S, G> {
        k * h * h.abs().sqrt()
    }
}

impl LaneLaw for LinearSpring {
    const GRADING: Grading = Grading::Uniform;
    fn for_pair(pair: &ContactPair) -> Self {
        pair.law::<LinearSpring>(&[])
    }
    fn with_stiffness(k: f64) -> Self {
        LinearSpring { stiffness: k }
    }
    fn stiffness(&self) -> f64 {
        self.stiffness
    }
    fn estimate(&self, mass: f64, speed: f64) -> f64 {
        self.contact_time_estimate(mass, speed)
    }
    #[inline(always)]
    fn lanes_force<S: Simd, const G: usize>(k: V<S, G>, h: V<S, G>) -> V<S, G> {
        k * h
    }
}

// ---------------------------------------------------------------------------
// Lanes.

/// Most lanes a kernel has.
const MAX_LANES: usize = 16;
/// One value per lane, in memory.
///
/// Aligned to 64 bytes, as is everything the step loop holds: a register
/// load or store across two cache lines (as a 64-byte value at a 16-byte
/// aligned address is, three times in four) made the loop up to 25%
/// slower, depending on where the stack happened to be.
#[derive(Debug, Clone, Copy, PartialEq)]
#[repr(C, align(64))]
struct Lanes([f64; MAX_LANES]);

impl Lanes {
    const fn splat(x: f64) -> Self {
        Lanes([x; MAX_LANES])
    }
}

impl std::ops::Deref for Lanes {
    type Target = [f64];
    fn deref(&self) -> &[f64] {
        &self.0
    }
}

impl std::ops::DerefMut for Lanes {
    fn deref_mut(&mut self) -> &mut [f64] {
        &mut self.0
    }
}

/// The lanes' state that every step reads and writes, in memory (for the
/// events; the step loop keeps it in registers, [`Hot`]).
#[derive(Clone, Copy)]
struct State {
    /// The corrected Nordsieck vector and the next prediction
    /// ([`Gear5State`]).
    r: [Lanes; 6],
    next: [Lanes; 6],
    /// The step size `r` is scaled for.
    dt: Lanes,
    /// The current step, in τ = t − t_c.
    tau_start: Lanes,
    tau_end: Lanes,
    /// The smallest (most negative) position at a step end of this contact.
    min_position: Lanes,
}

impl State {
    fn new() -> Self {
        let z = Lanes::splat(0.0);
        State {
            r: [z; 6],
            next: [z; 6],
            dt: Lanes::splat(1.0),
            tau_start: z,
            tau_end: z,
            min_position: z,
        }
    }

    /// Lane `l` as the scalar path's state.
    fn gear(&self, l: usize, gear: &Gear5) -> Gear5State {
        let dt = self.dt[l];
        let half_dt2 = 0.5 * dt * dt;
        let (mut r, mut next) = ([0.0; 6], [0.0; 6]);
        for k in 0..6 {
            r[k] = self.r[k][l];
            next[k] = self.next[k][l];
        }
        Gear5State {
            r,
            dt,
            half_dt2,
            inv_dt: 1.0 / dt,
            gain: gear.predicted_corrector[0] * half_dt2,
            next,
        }
    }

    /// Lane `l` idle: a state that stays put.
    fn set_idle(&mut self, l: usize) {
        for k in 0..6 {
            self.r[k][l] = 0.0;
            self.next[k][l] = 0.0;
        }
        self.dt[l] = 1.0;
        self.tau_start[l] = 0.0;
        self.tau_end[l] = 0.0;
        self.min_position[l] = 0.0;
    }
}

/// The sizes of a step and the factors that depend on them alone.
#[derive(Clone, Copy)]
struct Geometry<S: Simd, const G: usize> {
    tau_end: V<S, G>,
    len: V<S, G>,
    /// Where the size changes.
    resize: simd::Mask<S, G>,
    /// The size's ratio to the last one, to the powers 1 to 5.
    power: [V<S, G>; 5],
    half_dt2: V<S, G>,
    /// The law's stiffness over m times the gain.
    k_step: V<S, G>,
}

/// [`State`] in registers.
#[derive(Clone, Copy)]
struct Hot<S: Simd, const G: usize> {
    r: [V<S, G>; 6],
    next: [V<S, G>; 6],
    dt: V<S, G>,
    tau_start: V<S, G>,
    tau_end: V<S, G>,
    min_position: V<S, G>,
}

impl<S: Simd, const G: usize> Hot<S, G> {
    #[inline(always)]
    fn load(s: S, m: &State) -> Self {
        let v = |x: &Lanes| V::load(s, x);
        Hot {
            r: [
                v(&m.r[0]),
                v(&m.r[1]),
                v(&m.r[2]),
                v(&m.r[3]),
                v(&m.r[4]),
                v(&m.r[5]),
            ],
            next: [
                v(&m.next[0]),
                v(&m.next[1]),
                v(&m.next[2]),
                v(&m.next[3]),
                v(&m.next[4]),
                v(&m.next[5]),
            ],
            dt: v(&m.dt),
            tau_start: v(&m.tau_start),
            tau_end: v(&m.tau_end),
            min_position: v(&m.min_position),
        }
    }

    #[inline(always)]
    fn store(&self, m: &mut State) {
        for k in 0..6 {
            self.r[k].store(&mut m.r[k]);
            self.next[k].store(&mut m.next[k]);
        }
        self.dt.store(&mut m.dt);
        self.tau_start.store(&mut m.tau_start);
        self.tau_end.store(&mut m.tau_end);
        self.min_position.store(&mut m.min_position);
    }
}

/// Graded step sizes of a region of n steps, per unit length:
/// `graded_step(1.0, n, j)`, so that `length * w[j]` is
/// `graded_step(length, n, j)` to the bit.
#[derive(Default)]
struct Tables(Vec<(u64, Vec<f64>)>);

impl Tables {
    /// Most tables a kernel keeps, and most sizes in all (a batch with
    /// many different Δt/T_c gets tables for the first ones only).
    const MAX_TABLES: usize = 256;
    const MAX_SIZES: usize = 1 << 20;

    /// The table of a region of `n` steps (None above [`MAX_TABLE`] steps
    /// or when the tables are full: the sizes are then computed).
    fn id(&mut self, n: u64) -> Option<usize> {
        if n > MAX_TABLE {
            return None;
        }
        if let Some(i) = self.0.iter().rposition(|(m, _)| *m == n) {
            return Some(i);
        }
        let held: usize = self.0.iter().map(|(_, w)| w.len()).sum();
        if self.0.len() >= Self::MAX_TABLES || held + n as usize > Self::MAX_SIZES {
            return None;
        }
        self.0
            .push((n, (0..n).map(|j| graded_step(1.0, n, j)).collect()));
        Some(self.0.len() - 1)
    }

    /// `graded_step(length, n, j)`.
    #[inline(always)]
    fn step(&self, id: Option<usize>, length: f64, n: u64, j: u64) -> f64 {
        match id {
            Some(i) => length * self.0[i].1[j as usize],
            None => graded_step(length, n, j),
        }
    }
}

/// Where a lane's steps come from: its [`GradedSteps`] and the number of
/// the next step (`GradedSteps::next` for the Power and Uniform gradings,
/// the graded sizes from [`Tables`]).
#[derive(Clone, Copy)]
struct Mesh {
    /// The unplanned mesh of the contact (to re-plan from).
    start: GradedSteps,
    steps: GradedSteps,
    j: u64,
    onset_table: Option<usize>,
    end_table: Option<usize>,
}

impl Mesh {
    fn new(start: GradedSteps, tables: &mut Tables) -> Self {
        Mesh {
            start,
            steps: start,
            j: 0,
            onset_table: if start.graded {
                tables.id(start.onset_steps)
            } else {
                None
            },
            end_table: None,
        }
    }

    /// `GradedSteps::next(self.j)` with the graded sizes from the tables,
    /// then j += 1.
    #[inline(always)]
    fn next(&mut self, tables: &Tables) -> f64 {
        let (onset_table, end_table) = (self.onset_table, self.end_table);
        let h = self.steps.next_with(self.j, |region, is_end, n, k| {
            let table = if is_end { end_table } else { onset_table };
            tables.step(table, region, n, k)
        });
        self.j += 1;
        h
    }

    /// `GradedSteps::plan_end(tau, tau_max)` found in step number `j`:
    /// the mesh from step j + 1 on.
    fn plan_end(&mut self, j: u64, tau: f64, tau_max: f64, tables: &mut Tables) {
        // The unplanned mesh depends on j alone but for the size of the
        // last step, which the plan may grow from.
        self.steps = self.start;
        self.j = j;
        self.next(tables);
        self.steps.plan_end(tau, tau_max);
        if self.steps.planned && self.steps.end_steps > 0 {
            self.end_table = tables.id(self.steps.end_steps);
        }
    }

    /// Whether every step from here on is Δt (until a re-plan).
    #[inline(always)]
    fn uniform_from_here(&self) -> bool {
        let g = &self.steps;
        !g.graded
            || (!g.planned && self.j >= g.onset_steps)
            || (g.planned && g.uniform_left == 0 && g.end_left == 0 && g.last == g.dt)
    }

    /// The step sizes that follow, through `put`, up to the first of a run
    /// of Δt to the end (the sizes [`Self::next`] gives) but at most
    /// `max`; returns how many, and whether that run of Δt was reached.
    #[inline(always)]
    fn explicit(&mut self, tables: &Tables, max: u64, mut put: impl FnMut(f64)) -> (u64, bool) {
        let mut done = 0;
        loop {
            if self.uniform_from_here() {
                return (done, true);
            }
            if done == max {
                return (done, false);
            }
            let g = &mut self.steps;
            let count = max - done;
            let k;
            if !g.planned {
                k = count.min(g.onset_steps - self.j);
                let (region, n) = (g.onset_region, g.onset_steps);
                match self.onset_table {
                    Some(t) => {
                        let w = &tables.0[t].1[self.j as usize..(self.j + k) as usize];
                        for &w in w {
                            put(region * w);
                        }
                    }
                    None => {
                        for j in self.j..self.j + k {
                            put(graded_step(region, n, j));
                        }
                    }
                }
                g.last = tables.step(self.onset_table, region, n, self.j + k - 1);
            } else if g.uniform_left > 0 {
                k = count.min(g.uniform_left);
                for _ in 0..k {
                    put(g.uniform_size);
                }
                g.uniform_left -= k;
                g.last = g.uniform_size;
            } else if g.end_left > 0 {
                k = count.min(g.end_left);
                let (region, n, left) = (g.end_region, g.end_steps, g.end_left);
                match self.end_table {
                    Some(t) => {
                        let w = &tables.0[t].1[(left - k) as usize..left as usize];
                        for &w in w.iter().rev() {
                            put(region * w);
                        }
                    }
                    None => {
                        for i in (left - k..left).rev() {
                            put(graded_step(region, n, i));
                        }
                    }
                }
                g.end_left -= k;
                g.last = tables.step(self.end_table, region, n, g.end_left);
            } else {
                // Past the planned rebound: grow until it is crossed, up to
                // Δt: min(2 last, Δt) again and again, that is min(2ⁱ h, Δt)
                // (doubling is exact), computed without the chain through
                // `last`; f64::min is the plain comparison for these
                // (positive, not NaN) values.
                let (h, dt) = (g.last, g.dt);
                let mut n = 0;
                let mut scale = 2.0;
                while n < count {
                    let grown = h * scale;
                    g.last = if grown < dt { grown } else { dt };
                    put(g.last);
                    n += 1;
                    if g.last == dt {
                        break;
                    }
                    scale *= 2.0;
                }
                k = n;
            }
            done += k;
            self.j += k;
        }
    }
}

/// What a lane is doing, beside its vector state.
struct LaneCase {
    /// The case, None when the lane is idle.
    case: Option<Case>,
    contact: u32,
    /// Flight state after the last rebound.
    t: f64,
    x: f64,
    v: f64,
    t_contact: f64,
    v_contact: f64,
    found: bool,
    max_overlap: (f64, f64),
    /// The peak force so far, but for the steps' (see [`Hot::min_position`]).
    max_force: f64,
    records: Vec<ContactRecord>,
    total_steps: u64,
    /// Iteration of the contact's first step and the last it may take.
    first: u64,
    deadline: u64,
    mesh: Mesh,
    /// The ring holds this lane's sizes up to this iteration (not
    /// included); Δt after.
    filled: u64,
    /// Whether the sizes after `filled` are still to be written.
    more: bool,
}

impl LaneCase {
    fn idle() -> Self {
        let g = GradedSteps::new(1.0, 1.0, Grading::Uniform);
        LaneCase {
            case: None,
            contact: 0,
            t: 0.0,
            x: 0.0,
            v: 0.0,
            t_contact: 0.0,
            v_contact: 0.0,
            found: false,
            max_overlap: (0.0, 0.0),
            max_force: 0.0,
            records: Vec::new(),
            total_steps: 0,
            first: 0,
            deadline: u64::MAX,
            mesh: Mesh {
                start: g,
                steps: g,
                j: 0,
                onset_table: None,
                end_table: None,
            },
            filled: 0,
            more: false,
        }
    }
}

/// Runs the cases of `queue` (with the other kernels that share it) into
/// their slots.
fn run_kernel<L: LaneLaw>(queue: &Queue<'_>, isa: Isa) {
    if queue.len() == 0 {
        return;
    }
    #[cfg(target_arch = "x86_64")]
    {
        match isa {
            Isa::Avx512 => {
                if let Some(s) = Avx512::detect() {
                    // SAFETY: the token proves the CPU has these features.
                    return unsafe { kernel_avx512::<L>(queue, s) };
                }
            }
            Isa::Avx2 => {
                if let Some(s) = Avx2::detect() {
                    // SAFETY: as above.
                    return unsafe { kernel_avx2::<L>(queue, s) };
                }
            }
            Isa::Baseline => {}
        }
        if let Some(s) = Sse2::detect() {
            Kernel::<L, Sse2, { GROUP_BASELINE }>::new(queue, s).run();
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        let _ = isa;
        if let Some(s) = simd::Scalar::detect() {
            Kernel::<L, simd::Scalar, 8>::new(queue, s).run();
        }
    }
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f,avx512dq,avx512vl,avx2,fma")]
unsafe fn kernel_avx512<L: LaneLaw>(queue: &Queue<'_>, s: Avx512) {
    Kernel::<L, Avx512, { GROUP_AVX512 }>::new(queue, s).run()
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
unsafe fn kernel_avx2<L: LaneLaw>(queue: &Queue<'_>, s: Avx2) {
    Kernel::<L, Avx2, { GROUP_AVX2 }>::new(queue, s).run()
}

/// A threshold t with r₁ ≥ t wherever `r₁ * (1.0 / Δt) >= 0.0` for the
/// step sizes Δt of a contact with `dt` (they are below 2 dt): r₁ ≥ 0, or
/// r₁ < 0 so small that the product rounds to −0, |r₁| < 2⁻¹⁰⁷⁴ Δt. A
/// normal number, so that nothing in the step loop is subnormal.
fn velocity_threshold(dt: f64) -> f64 {
    -f64::MIN_POSITIVE * (2.0 * dt).max(1.0)
}

#[repr(align(64))]
struct Kernel<'a, 'q, L, S: Simd, const G: usize> {
    s: S,
    queue: &'a Queue<'q>,
    /// The chunks of cases taken; the last is being started.
    chunks: Vec<Chunk<'q>>,
    /// The lanes' state between steps (see [`Hot`]).
    mem: State,
    /// Per-lane constants of the step: −g and the law's stiffness over m.
    c: Lanes,
    accel_stiffness: Lanes,
    /// Event thresholds: a lane's event is r₁ ≥ `velocity_event` or
    /// position ≥ `position_event`. The maximum overlap is sought where the
    /// velocity r₁/Δt ≥ 0; that is tested on r₁ alone, against a tiny
    /// negative threshold (see [`velocity_threshold`]), the position is
    /// tested against 0 after it; +∞ disables either. The events recheck
    /// the scalar path's conditions exactly.
    velocity_event: Lanes,
    position_event: Lanes,
    /// Step sizes: row `i % RING` holds every lane's size for iteration
    /// i < `until` (as f64); the lane's Δt, `dt`, is the size after.
    ring: Box<[Lanes; RING]>,
    until: Lanes,
    dt: Lanes,
    lane: Vec<LaneCase>,
    tables: Tables,
    /// The iteration whose step is being taken (the first is 1).
    now: u64,
    /// The iteration at which some lane needs its ring refilled, and the
    /// earliest lane deadline.
    refill_at: u64,
    deadline: u64,
    active: usize,
    gear: Gear5,
    _law: std::marker::PhantomData<L>,
}

impl<'a, 'q, L: LaneLaw, S: Simd, const G: usize> Kernel<'a, 'q, L, S, G> {
    /// Lanes of the kernel.
    const N: usize = S::W * G;

    #[inline(always)]
    fn new(queue: &'a Queue<'q>, s: S) -> Self {
        const { assert!(S::W * G <= MAX_LANES && MAX_LANES <= MAX_STEPS) };
        Kernel {
            s,
            queue,
            chunks: Vec::new(),
            mem: State::new(),
            c: Lanes::splat(0.0),
            accel_stiffness: Lanes::splat(0.0),
            velocity_event: Lanes::splat(f64::INFINITY),
            position_event: Lanes::splat(f64::INFINITY),
            ring: Box::new([Lanes::splat(1.0); RING]),
            until: Lanes::splat(0.0),
            dt: Lanes::splat(1.0),
            lane: (0..Self::N).map(|_| LaneCase::idle()).collect(),
            tables: Tables::default(),
            now: 0,
            refill_at: u64::MAX,
            deadline: u64::MAX,
            active: 0,
            gear: Gear5::POSITION_DEPENDENT,
            _law: std::marker::PhantomData,
        }
    }

    /// Runs the lanes until the queue is empty.
    #[inline(always)]
    fn run(mut self) {
        self.start();
        let s = self.s;
        let gear = self.gear;
        let pc = gear.predicted_corrector;
        let cc = gear.corrector;
        let inverse_sum = V::splat(s, gear.inverse_sum);
        let mut hot = Hot::<S, G>::load(s, &self.mem);
        if 1 >= self.refill_at {
            self.refill(1);
        }
        let mut geo = self.geometry(&hot, self.sizes(1));
        // The sizes of the step after next, loaded an iteration ahead.
        // The iteration count in a register; `self.now` is written for the
        // events and refills only.
        let mut now = self.now;
        let (mut deadline, mut refill_at) = (self.deadline, self.refill_at);
        while self.active > 0 {
            now += 1;
            hot.tau_start = hot.tau_end;
            hot.tau_end = geo.tau_end;
            // The step's size: `set_step` where it changes. Where it does
            // not, the ratio is 1 and every recomputed value comes out
            // with the bits it had (the same expressions of the same
            // values), so only the prediction needs a select.
            let mut r = hot.r;
            for (rk, power) in r.iter_mut().skip(1).zip(geo.power) {
                *rk = *rk * power;
            }
            let rescaled = pascal(&r);
            let mut p = hot.next;
            for k in 0..6 {
                p[k] = geo.resize.select(rescaled[k], p[k]);
            }
            // `Gear5::step_scaled` with the law scaled by the gain, as
            // `Run::contact_step` does, and c = −g; the same expressions in
            // the same order.
            let mut next = pascal(&p);
            let base = V::load(s, &self.c) * geo.half_dt2 - p[2];
            let next_x_base = next[0] + pc[0] * base;
            let scaled = L::lanes_force(geo.k_step, -p[0]);
            let delta = scaled * inverse_sum + base;
            for k in 0..6 {
                r[k] = p[k] + cc[k] * delta;
            }
            for k in 1..6 {
                next[k] = next[k] + pc[k] * delta;
            }
            next[0] = next_x_base + scaled;
            hot.r = r;
            hot.next = next;
            hot.dt = geo.len;
            // Events.
            let position = r[0];
            hot.min_position = position
                .lt(hot.min_position)
                .select(position, hot.min_position);
            let events = r[1].ge(V::load(s, &self.velocity_event))
                | position.ge(V::load(s, &self.position_event));
            let bits = events.bits();
            if bits != 0 || now >= deadline {
                self.now = now;
                hot.store(&mut self.mem);
                self.events(bits);
                hot = Hot::load(s, &self.mem);
                (deadline, refill_at) = (self.deadline, self.refill_at);
            }
            // The next step's geometry, ahead of its state (it depends on
            // the mesh alone, so it overlaps this step's latency chain).
            if now + 1 >= refill_at {
                self.now = now;
                self.refill(now + 1);
                refill_at = self.refill_at;
            }
            geo = self.geometry(&hot, self.sizes(now + 1));
        }
    }

    /// Every lane's step size for iteration `at`: from the ring or Δt.
    #[inline(always)]
    fn sizes(&self, at: u64) -> V<S, G> {
        let s = self.s;
        let row = V::load(s, &self.ring[at as usize & (RING - 1)]);
        V::splat(s, at as f64)
            .lt(V::load(s, &self.until))
            .select(row, V::load(s, &self.dt))
    }

    /// The step of iteration `now + 1` with sizes `h`: its end and the
    /// factors of `set_step` and `step_scaled` that depend on the sizes alone.
    #[inline(always)]
    fn geometry(&self, hot: &Hot<S, G>, h: V<S, G>) -> Geometry<S, G> {
        let s = self.s;
        let tau_end = hot.tau_end + h;
        let len = tau_end - hot.tau_end;
        let ratio = len / hot.dt;
        let mut power = [ratio; 5];
        for k in 1..5 {
            power[k] = power[k - 1] * ratio;
        }
        let half_dt2 = 0.5 * len * len;
        let gain = self.gear.predicted_corrector[0] * half_dt2;
        Geometry {
            tau_end,
            len,
            resize: len.ne(hot.dt),
            power,
            half_dt2,
            k_step: V::load(s, &self.accel_stiffness) * gain,
        }
    }

    /// The next case to start: its slot and scenario.
    fn pop(&mut self) -> Option<(SlotId, &'q Scenario)> {
        loop {
            let id = self.chunks.len().wrapping_sub(1);
            if let Some(c) = self.chunks.last_mut() {
                if let Some(&index) = c.indices.get(c.next) {
                    c.next += 1;
                    return Some(((id, c.next - 1), &self.queue.scenarios[index]));
                }
            }
            let chunk = self.queue.take()?;
            self.chunks.push(chunk);
        }
    }

    /// Stores a case's result.
    fn put(&mut self, (chunk, i): SlotId, result: Slot) {
        if let Some(slot) = self.chunks.get_mut(chunk).and_then(|c| c.out.get_mut(i)) {
            *slot = result;
        }
    }

    /// Gives every lane its first case.
    #[inline(never)]
    fn start(&mut self) {
        for l in 0..Self::N {
            self.take_case(l);
        }
        self.update_marks();
        // The events wrote single lanes (8-byte stores) of what the step
        // loop reads back next as whole registers (the lanes' state, the
        // ring's next row). A load that cannot be forwarded from such
        // stores stalls far longer on this CPU (Zen 4) than draining the
        // stores first, here, outside the step loop (where a fence would
        // also pin the loop's registers): measured 1.55 → 1.35 µs/case.
        std::sync::atomic::fence(std::sync::atomic::Ordering::SeqCst);
    }

    /// Continues the runs of sizes of the lanes that have at most
    /// [`REFILL`] left before iteration `at` (whose row has not been read).
    #[inline(never)]
    fn refill(&mut self, at: u64) {
        for l in 0..Self::N {
            let lc = &self.lane[l];
            if lc.more && lc.filled <= at + REFILL {
                self.write_run(l, at);
            }
        }
        self.update_marks();
    }

    /// Writes lane `l`'s sizes from `filled` on, for as far as the ring
    /// reaches from iteration `at` (whose row has not been read) or to the
    /// start of a run of Δt.
    fn write_run(&mut self, l: usize, at: u64) {
        let lc = &mut self.lane[l];
        let mut row = lc.filled as usize;
        let ring = &mut self.ring;
        let limit = at + RING as u64;
        let (done, ended) = lc
            .mesh
            .explicit(&self.tables, limit.saturating_sub(lc.filled), |h| {
                ring[row & (RING - 1)][l] = h;
                row += 1;
            });
        lc.filled += done;
        lc.more = !ended;
        // Exact: iteration numbers stay far below 2⁵³.
        self.until[l] = lc.filled as f64;
    }

    /// Lane `l`'s sizes from iteration `from` (the one after the current)
    /// on.
    fn restart_run(&mut self, l: usize, from: u64) {
        self.lane[l].filled = from;
        self.write_run(l, from);
    }

    fn update_marks(&mut self) {
        let active = self.lane.iter().filter(|lc| lc.case.is_some());
        let (mut filled, mut deadline) = (u64::MAX, u64::MAX);
        for lc in active {
            if lc.more {
                filled = filled.min(lc.filled);
            }
            deadline = deadline.min(lc.deadline);
        }
        self.refill_at = filled.saturating_sub(REFILL);
        self.deadline = deadline;
    }

    /// The events of the lanes in `bits` and of the lanes past their step
    /// budget, at the end of the step of iteration `now`.
    #[inline(never)]
    fn events(&mut self, bits: u32) {
        let now = self.now;
        // The scalar path's tests, lane by lane: the maximum overlap first,
        // then the rebound (possibly in the same step), else the budget.
        // Events of the same kind are located together.
        let mut lanes = [0usize; MAX_LANES];
        let mut kinematics = [Kinematics::default(); MAX_LANES];
        let mut rebounded = [false; MAX_LANES];
        for (l, k) in kinematics.iter_mut().enumerate().take(Self::N) {
            if bits & (1 << l) != 0 {
                *k = self.gear.kinematics(&self.mem.gear(l, &self.gear));
            }
        }
        let mut steps = Steps::new();
        let mut located = Located::new();
        for crossing in [Crossing::Velocity, Crossing::Position] {
            steps.n = 0;
            for l in (0..Self::N).filter(|&l| bits & (1 << l) != 0) {
                let (found, k) = (self.lane[l].found, &kinematics[l]);
                let event = match crossing {
                    Crossing::Velocity => !found && k.velocity >= 0.0,
                    Crossing::Position => found && k.position >= 0.0,
                };
                if event {
                    lanes[steps.n] = l;
                    steps.push(std::array::from_fn(|k| self.mem.r[k][l]), self.mem.dt[l]);
                }
            }
            if steps.n == 0 {
                continue;
            }
            steps.pad();
            // Written lane by lane, read as registers (see the end).
            std::sync::atomic::fence(std::sync::atomic::Ordering::SeqCst);
            self.s.locate(crossing, &steps, &mut located);
            for (i, &l) in lanes.iter().enumerate().take(steps.n) {
                let (theta, at) = located.get(i);
                match crossing {
                    Crossing::Velocity => self.max_overlap(l, theta, &at),
                    Crossing::Position => {
                        self.rebound(l, theta, &at);
                        rebounded[l] = true;
                    }
                }
            }
        }
        for (l, &rebounded) in rebounded.iter().enumerate().take(Self::N) {
            if rebounded || now < self.lane[l].deadline {
                continue;
            }
            let lc = &self.lane[l];
            if let Some(c) = &lc.case {
                let error = SimulationError::NoRebound {
                    contact: lc.contact,
                    steps: now + 1 - lc.first,
                };
                self.put(c.slot, Err(error));
            }
            self.take_case(l);
        }
        self.update_marks();
        // The events wrote single lanes (8-byte stores) of what the step
        // loop reads back next as whole registers (the lanes' state, the
        // ring's next row). A load that cannot be forwarded from such
        // stores stalls far longer on this CPU (Zen 4) than draining the
        // stores first, here, outside the step loop (where a fence would
        // also pin the loop's registers): measured 1.55 → 1.35 µs/case.
        std::sync::atomic::fence(std::sync::atomic::Ordering::SeqCst);
    }

    /// Gives lane `l` the next case that starts a contact (cases that fail
    /// at once are reported), or makes it idle.
    fn take_case(&mut self, l: usize) {
        if self.lane[l].case.take().is_some() {
            self.active -= 1;
        }
        while let Some((slot, s)) = self.pop() {
            let case = match plan_case::<L>(slot, s) {
                Ok(case) => case,
                Err(e) => {
                    self.put(slot, Err(e));
                    continue;
                }
            };
            let p = &case.problem;
            self.c[l] = -p.gravity;
            self.accel_stiffness[l] = case.accel_stiffness;
            let lc = &mut self.lane[l];
            lc.contact = 1;
            (lc.t, lc.x, lc.v) = (0.0, p.gap, p.velocity);
            lc.records = Vec::with_capacity(p.contacts as usize);
            lc.total_steps = 0;
            lc.case = Some(case);
            self.active += 1;
            match self.start_contact(l) {
                Ok(()) => return,
                Err(e) => {
                    self.put(slot, Err(e));
                    self.lane[l].case = None;
                    self.active -= 1;
                }
            }
        }
        // Idle: a state that stays put and never has an event.
        self.mem.set_idle(l);
        self.c[l] = 0.0;
        self.accel_stiffness[l] = 0.0;
        self.velocity_event[l] = f64::INFINITY;
        self.position_event[l] = f64::INFINITY;
        self.dt[l] = 1.0;
        self.lane[l].mesh = LaneCase::idle().mesh;
        self.restart_run(l, self.now + 1);
        self.lane[l] = LaneCase::idle();
    }

    /// The flight to the next onset and the contact's first step
    /// (`Run::event_stepping` and the start of `Run::contact`); the step
    /// is taken in the next iteration.
    fn start_contact(&mut self, l: usize) -> Result<(), SimulationError> {
        let lc = &mut self.lane[l];
        let Some(c) = &lc.case else {
            return Ok(());
        };
        let p = &c.problem;
        let g = p.gravity;
        let tau = time_to_surface(lc.x, lc.v, g).ok_or(SimulationError::NeverReachesBoundary)?;
        let t_c = lc.t + tau;
        let v_c = lc.v - g * tau;
        lc.t_contact = t_c;
        lc.v_contact = v_c;
        let law = L::with_stiffness(c.stiffness);
        let overlap_rate = -v_c;
        let onset_force = law.force(0.0, overlap_rate, &());
        let overlap_accel = g - onset_force * c.inv_mass;
        let [h3, h4, h5] = law.onset_derivatives(p.mass, overlap_rate, overlap_accel);
        let graded = GradedSteps::new(p.dt, p.contact_time_estimate, L::GRADING);
        lc.mesh = Mesh::new(graded, &mut self.tables);
        let h0 = {
            let mut mesh = lc.mesh;
            mesh.next(&self.tables)
        };
        let tau_end = 0.0 + h0;
        let state = self
            .gear
            .start([0.0, v_c, -overlap_accel, -h3, -h4, -h5], tau_end);
        lc.found = false;
        lc.max_force = onset_force;
        lc.first = self.now + 1;
        // The scalar path gives up after a step with `steps > budget`.
        lc.deadline = lc.first + c.budget;
        self.dt[l] = p.dt;
        let m = &mut self.mem;
        for k in 0..6 {
            m.r[k][l] = state.r[k];
            m.next[k][l] = state.next[k];
        }
        m.dt[l] = state.dt;
        // The next iteration advances τ from 0 by its row: h0.
        m.tau_end[l] = 0.0;
        m.min_position[l] = 0.0;
        self.velocity_event[l] = velocity_threshold(p.dt);
        self.position_event[l] = f64::INFINITY;
        self.restart_run(l, self.now + 1);
        Ok(())
    }

    /// The step of lane `l` crossed the maximum overlap, at `theta` where
    /// the kinematics are `at`.
    fn max_overlap(&mut self, l: usize, theta: f64, at: &Kinematics) {
        let h = self.mem.dt[l];
        let overlap = -at.position;
        let tau_max = self.mem.tau_start[l] + theta * h;
        let lc = &mut self.lane[l];
        let Some(c) = &lc.case else {
            return;
        };
        lc.max_overlap = (tau_max, overlap);
        lc.found = true;
        let law = L::with_stiffness(c.stiffness);
        lc.max_force = lc.max_force.max(law.force(overlap, -at.velocity, &()));
        let j = self.now - lc.first;
        lc.mesh
            .plan_end(j, self.mem.tau_end[l], tau_max, &mut self.tables);
        self.restart_run(l, self.now + 1);
        self.velocity_event[l] = f64::INFINITY;
        self.position_event[l] = 0.0;
    }

    /// The step of lane `l` crossed the rebound, at `theta` where the
    /// kinematics are `at`.
    fn rebound(&mut self, l: usize, theta: f64, at: &Kinematics) {
        let h = self.mem.dt[l];
        let steps = self.now + 1 - self.lane[l].first;
        let lc = &mut self.lane[l];
        let Some(c) = &lc.case else {
            return;
        };
        let (m, g) = (c.problem.mass, c.problem.gravity);
        let law = L::with_stiffness(c.stiffness);
        let deepest = self.mem.min_position[l];
        let mut max_force = lc.max_force;
        if deepest < 0.0 {
            max_force = max_force.max(law.force(-deepest, 0.0, &()));
        }
        let duration = self.mem.tau_start[l] + theta * h;
        let t_c = lc.t_contact;
        let v_c = lc.v_contact;
        let t_rebound = t_c + duration;
        let rebound_velocity = at.velocity;
        let (tau_max, overlap) = lc.max_overlap;
        lc.total_steps += steps;
        lc.records.push(ContactRecord {
            bodies: None,
            t_contact: t_c,
            t_max_overlap: t_c + tau_max,
            t_rebound,
            t_force_zero: None,
            duration,
            max_overlap: overlap,
            max_force,
            max_acceleration: max_force * c.inv_mass - g,
            impact_velocity: v_c,
            rebound_velocity,
            restitution: rebound_velocity / -v_c,
            energy_dissipated: 0.5 * m * (v_c * v_c - rebound_velocity * rebound_velocity),
            apex_height: (g > 0.0).then(|| rebound_velocity * rebound_velocity / (2.0 * g)),
            steps,
        });
        if lc.contact == c.problem.contacts {
            let outcome = RunOutcome {
                contacts: std::mem::take(&mut lc.records),
                steps: lc.total_steps,
                dt: c.problem.dt,
                contact_time_estimate: c.problem.contact_time_estimate,
                error_estimate: c.problem.error_estimate,
                pilot_steps: c.problem.pilot_steps,
            };
            let slot = c.slot;
            self.put(slot, Ok(outcome));
            self.take_case(l);
            return;
        }
        let slot = c.slot;
        lc.contact += 1;
        (lc.t, lc.x, lc.v) = (t_rebound, 0.0, rebound_velocity);
        if let Err(e) = self.start_contact(l) {
            self.put(slot, Err(e));
            self.take_case(l);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::{Boundary, Particle};

    #[test]
    fn cached_estimates_equal_the_laws_to_the_bit() {
        let mut checked = 0;
        for i in 0..200 {
            let u = |k: u32| ((i * k) % 997) as f64 / 997.0;
            let pair = ContactPair::new(
                Particle::PAPER,
                Boundary {
                    radius_ratio: 10f64.powf(-0.3 + 4.0 * u(7)),
                    modulus_ratio: 10f64.powf(-1.0 + 4.0 * u(13)),
                    poisson_ratio: None,
                },
            );
            let mass = 10f64.powf(-9.0 + 3.0 * u(17));
            let speed = 10f64.powf(-3.0 + 4.0 * u(19));
            let hertz = <Hertz as LaneLaw>::for_pair(&pair);
            let linear = <LinearSpring as LaneLaw>::for_pair(&pair);
            assert_eq!(
                hertz.estimate(mass, speed).to_bits(),
                hertz.contact_time_estimate(mass, speed).to_bits()
            );
            assert_eq!(
                linear.estimate(mass, speed).to_bits(),
                linear.contact_time_estimate(mass, speed).to_bits()
            );
            checked += 1;
        }
        assert_eq!(checked, 200);
    }

    #[test]
    fn tabled_graded_steps_equal_the_schedules() {
        let mut tables = Tables::default();
        for (dt, t) in [(1.0, 50.0), (0.02, 1.0), (3e-9, 1.1e-7), (1.0, 1e5)] {
            let g = GradedSteps::new(dt, t, Grading::Power);
            let mut reference = g;
            let mut mesh = Mesh::new(g, &mut tables);
            let mut tau = 0.0;
            for j in 0..(g.onset_steps + 10) {
                let (a, b) = (reference.next(j), mesh.next(&tables));
                assert_eq!(a.to_bits(), b.to_bits(), "onset step {j}");
                tau += a;
            }
            // Re-plan after the step j = onset + 9 and compare the rest.
            let j = g.onset_steps + 9;
            reference.plan_end(tau, 0.55 * tau);
            mesh.plan_end(j, tau, 0.55 * tau, &mut tables);
            for k in 0..(reference.uniform_left + reference.end_steps + 5) {
                let (a, b) = (reference.next(j + 1 + k), mesh.next(&tables));
                assert_eq!(a.to_bits(), b.to_bits(), "planned step {k}");
            }
        }
    }

    #[test]
    fn filled_runs_equal_the_schedules() {
        let mut tables = Tables::default();
        for (dt, t, grading) in [
            (1.0, 50.0, Grading::Power),
            (3e-9, 1.1e-7, Grading::Power),
            (1.0, 1e5, Grading::Power),
            (0.5, 50.0, Grading::Uniform),
        ] {
            for plan_at in [3, 40, 80] {
                let g = GradedSteps::new(dt, t, grading);
                let mut reference = g;
                let mut expected = Vec::new();
                let mut tau = 0.0;
                for j in 0..plan_at {
                    expected.push(reference.next(j));
                    tau += expected[j as usize];
                }
                reference.plan_end(tau, 0.52 * tau);
                for j in plan_at..plan_at + 200 {
                    expected.push(reference.next(j));
                }
                // The same in runs of 1 to 13 steps, re-planned alike, Δt
                // after the explicit sizes.
                let mut mesh = Mesh::new(g, &mut tables);
                let mut got = Vec::new();
                let mut run = 1;
                let mut ended = false;
                while (got.len() as u64) < plan_at {
                    let count = run.min(plan_at - got.len() as u64);
                    if ended {
                        got.extend((0..count).map(|_| dt));
                    } else {
                        ended = mesh.explicit(&tables, count, |h| got.push(h)).1;
                    }
                    run = run % 13 + 4;
                }
                mesh.plan_end(plan_at - 1, tau, 0.52 * tau, &mut tables);
                ended = false;
                while got.len() < expected.len() {
                    if ended {
                        got.push(dt);
                    } else {
                        ended = mesh.explicit(&tables, run, |h| got.push(h)).1;
                    }
                    run = run % 13 + 4;
                }
                got.truncate(expected.len());
                let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
                assert_eq!(
                    bits(&got),
                    bits(&expected),
                    "{dt} {t} {grading:?} {plan_at}"
                );
            }
        }
    }
}
