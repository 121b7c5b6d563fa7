//! Many independent bouncing cases at once: [`simulate_batch`].
//!
//! Independent cases share no data, so this path advances [`LANES`] cases
//! together in structure-of-arrays form: one vector instruction does the
//! same operation for every lane (the lanes step in lockstep, so an
//! iteration keeps one step's dependency chain; the gain is in the work per
//! step, see BENCHMARKS.md: ~2× per thread).
//!
//! What is batched: Gear5, event stepping, the elastic Hertz and linear
//! laws (any particle, boundary, motion, Δt rule). Each lane runs one case
//! contact by contact exactly as [`super::simulate`] does: flight in closed
//! form, the contact integrated on the same step mesh (graded at both ends
//! for Hertz), events located on the step's polynomial. The per-step work
//! (mesh, rescaling, prediction, force, correction, peak force) is vector
//! code; the rare per-lane events (onset, maximum overlap, rebound) run the
//! scalar path's own functions on that lane. A lane whose case ends takes
//! the next case of its chunk, so lanes stay busy whatever the cases'
//! lengths. Chunks of cases run in parallel with rayon (in the current
//! rayon pool).
//!
//! The vector code performs the scalar path's operations in the same order
//! (no fused multiply–add, no reassociation), so every [`ContactRecord`]
//! is identical to the last bit to the scalar path's (tested in
//! `tests/batch.rs` for all instruction sets available).
//!
//! Instruction sets are chosen at run time: AVX-512, AVX2 (both with FMA
//! enabled for the compiler, which does not contract on its own), or the
//! baseline SSE2 build.

use super::events::{locate, time_to_surface, Crossing};
use super::schedule::{GradedSteps, Grading, GRADING_EXPONENT};
use super::{
    plan, simulate, ContactRecord, Problem, RunOutcome, Scenario, SimulationError, Stepping,
};
use crate::contact::{ContactLawKind, DampingKind, Hertz, LinearSpring, NormalContactLaw};
use crate::integrate::{Gear5, Gear5State, Integrator, Scheme};
use rayon::prelude::*;
use std::ops::{Add, Div, Mul, Neg, Sub};

/// Cases advanced together by one thread.
pub const LANES: usize = 8;
/// Cases per parallel task.
const CHUNK: usize = 256;

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
}

/// Runs every scenario, the batchable ones (Gear5, event stepping, elastic
/// Hertz or linear law) in SIMD lanes, the others one by one with
/// [`simulate`]; results in the order of `scenarios`, each as
/// `simulate(s, &mut ())` would give it.
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
    let mut results: Vec<Option<Result<RunOutcome, SimulationError>>> =
        (0..scenarios.len()).map(|_| None).collect();
    for (index, s) in scenarios.iter().enumerate() {
        match batch_law(s) {
            Some(kind) => match plan(s) {
                Ok(problem) => {
                    let case = Case::new(index, s, problem, kind);
                    match kind {
                        ContactLawKind::Hertz => hertz.push(case),
                        _ => linear.push(case),
                    }
                }
                Err(e) => results[index] = Some(Err(e)),
            },
            None => scalar.push(index),
        }
    }
    let batched: Vec<(usize, Result<RunOutcome, SimulationError>)> = hertz
        .par_chunks(CHUNK)
        .flat_map_iter(|chunk| run_chunk::<Hertz>(chunk, isa))
        .chain(
            linear
                .par_chunks(CHUNK)
                .flat_map_iter(|chunk| run_chunk::<LinearSpring>(chunk, isa)),
        )
        .chain(
            scalar
                .par_iter()
                .map(|&i| (i, simulate(&scenarios[i], &mut ()))),
        )
        .collect();
    for (index, result) in batched {
        results[index] = Some(result);
    }
    results
        .into_iter()
        .map(|r| r.unwrap_or(Err(SimulationError::NeverReachesBoundary)))
        .collect()
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

/// One case, resolved.
struct Case {
    index: usize,
    problem: Problem,
    /// The law's stiffness and that of the law scaled by 1/m.
    stiffness: f64,
    accel_stiffness: f64,
    inv_mass: f64,
    budget: u64,
}

impl Case {
    fn new(index: usize, s: &Scenario, problem: Problem, kind: ContactLawKind) -> Self {
        let pair = s.pair();
        let inv_mass = 1.0 / problem.mass;
        let (stiffness, accel_stiffness) = match kind {
            ContactLawKind::Hertz => {
                let law = Hertz::for_pair(&pair);
                (law.stiffness, law.scaled(inv_mass).stiffness)
            }
            _ => {
                let law = LinearSpring::for_pair(&pair);
                (law.stiffness, law.scaled(inv_mass).stiffness)
            }
        };
        Case {
            index,
            problem,
            stiffness,
            accel_stiffness,
            inv_mass,
            budget: (100.0 * problem.contact_time_estimate / problem.dt) as u64 + 1_000_000,
        }
    }
}

/// A law the kernel runs: its force in lanes, the same arithmetic as
/// [`NormalContactLaw::force`].
trait LaneLaw: NormalContactLaw<History = ()> + Copy {
    const GRADING: Grading;
    fn with_stiffness(k: f64) -> Self;
    fn lanes_force(k: V, overlap: V) -> V;
}

impl LaneLaw for Hertz {
    const GRADING: Grading = Grading::Power;
    fn with_stiffness(k: f64) -> Self {
        Hertz { stiffness: k }
    }
    #[inline(always)]
    fn lanes_force(k: V, h: V) -> V {
        k * h * h.abs().sqrt()
    }
}

impl LaneLaw for LinearSpring {
    const GRADING: Grading = Grading::Uniform;
    fn with_stiffness(k: f64) -> Self {
        LinearSpring { stiffness: k }
    }
    #[inline(always)]
    fn lanes_force(k: V, h: V) -> V {
        k * h
    }
}

// ---------------------------------------------------------------------------
// Lanes of f64.

#[derive(Debug, Clone, Copy, PartialEq)]
struct V([f64; LANES]);

/// A lane mask: all ones (true) or zero per lane, as SIMD compares give it.
#[derive(Debug, Clone, Copy, PartialEq)]
struct M([i64; LANES]);

impl M {
    const NONE: M = M([0; LANES]);
    #[inline(always)]
    fn get(&self, l: usize) -> bool {
        self.0[l] != 0
    }
    #[inline(always)]
    fn set(&mut self, l: usize, on: bool) {
        self.0[l] = -i64::from(on);
    }
    #[inline(always)]
    fn any(&self) -> bool {
        self.0.iter().fold(0, |a, &b| a | b) != 0
    }
}

#[inline(always)]
fn and(a: M, b: M) -> M {
    let mut o = a.0;
    for (x, y) in o.iter_mut().zip(b.0) {
        *x &= y;
    }
    M(o)
}

#[inline(always)]
fn not(a: M) -> M {
    let mut o = a.0;
    for x in o.iter_mut() {
        *x = !*x;
    }
    M(o)
}

/// a where the mask is set, b elsewhere. Bitwise: written as a branch,
/// the compiler turns a select into a struct field into masked stores,
/// which are slower.
#[inline(always)]
fn select(m: M, a: V, b: V) -> V {
    V(std::array::from_fn(|l| {
        let (x, y) = (a.0[l].to_bits() as i64, b.0[l].to_bits() as i64);
        f64::from_bits(((x & m.0[l]) | (y & !m.0[l])) as u64)
    }))
}

impl V {
    #[inline(always)]
    fn splat(x: f64) -> V {
        V([x; LANES])
    }
    #[inline(always)]
    fn map(self, f: impl Fn(f64) -> f64) -> V {
        let mut o = self.0;
        for x in o.iter_mut() {
            *x = f(*x);
        }
        V(o)
    }
    #[inline(always)]
    fn zip(self, b: V, f: impl Fn(f64, f64) -> f64) -> V {
        let mut o = self.0;
        for (x, y) in o.iter_mut().zip(b.0) {
            *x = f(*x, y);
        }
        V(o)
    }
    #[inline(always)]
    fn sqrt(self) -> V {
        self.map(f64::sqrt)
    }
    #[inline(always)]
    fn abs(self) -> V {
        self.map(f64::abs)
    }
    #[inline(always)]
    fn min(self, b: V) -> V {
        self.zip(b, f64::min)
    }
    #[inline(always)]
    fn powi(self) -> V {
        self.map(|x| x.powi(GRADING_EXPONENT))
    }
    #[inline(always)]
    fn cmp(self, b: V, f: impl Fn(f64, f64) -> bool) -> M {
        M(std::array::from_fn(|l| -i64::from(f(self.0[l], b.0[l]))))
    }
}

macro_rules! binop {
    ($tr:ident, $f:ident, $op:tt) => {
        impl $tr for V {
            type Output = V;
            #[inline(always)]
            fn $f(self, b: V) -> V {
                self.zip(b, |x, y| x $op y)
            }
        }
        impl $tr<V> for f64 {
            type Output = V;
            #[inline(always)]
            fn $f(self, b: V) -> V {
                V::splat(self).zip(b, |x, y| x $op y)
            }
        }
    };
}
binop!(Add, add, +);
binop!(Sub, sub, -);
binop!(Mul, mul, *);
binop!(Div, div, /);

impl Neg for V {
    type Output = V;
    #[inline(always)]
    fn neg(self) -> V {
        self.map(|x| -x)
    }
}

/// `gear5::pascal` in every lane (same expression order).
#[inline(always)]
fn lanes_pascal(r: &[V; 6]) -> [V; 6] {
    [
        ((r[0] + r[1]) + (r[2] + r[3])) + (r[4] + r[5]),
        ((r[1] + 2.0 * r[2]) + (3.0 * r[3] + 4.0 * r[4])) + 5.0 * r[5],
        (r[2] + 3.0 * r[3]) + (6.0 * r[4] + 10.0 * r[5]),
        (r[3] + 4.0 * r[4]) + 10.0 * r[5],
        r[4] + 5.0 * r[5],
        r[5],
    ]
}

// ---------------------------------------------------------------------------
// The kernel.

/// Everything the per-step code touches, one value per lane.
#[derive(Clone, Copy)]
struct Lanes {
    // Gear5State.
    r: [V; 6],
    dt: V,
    half_dt2: V,
    inv_dt: V,
    gain: V,
    next: [V; 6],
    // Case constants.
    gravity: V,
    accel_stiffness: V,
    stiffness: V,
    budget: V,
    // Contact.
    tau_start: V,
    tau_end: V,
    steps: V,
    max_force: V,
    found: M,
    active: M,
    // GradedSteps (counts as exact f64 integers).
    mesh_dt: V,
    onset_region: V,
    onset_steps: V,
    planned: M,
    uniform_left: V,
    uniform_size: V,
    end_region: V,
    end_steps: V,
    end_left: V,
    last: V,
    j: V,
}

impl Lanes {
    fn idle() -> Self {
        let z = V::splat(0.0);
        let one = V::splat(1.0);
        Lanes {
            r: [z; 6],
            dt: one,
            half_dt2: V::splat(0.5),
            inv_dt: one,
            gain: z,
            next: [z; 6],
            gravity: z,
            accel_stiffness: z,
            stiffness: z,
            budget: V::splat(f64::INFINITY),
            tau_start: z,
            tau_end: one,
            steps: z,
            max_force: z,
            found: M::NONE,
            active: M::NONE,
            mesh_dt: one,
            onset_region: z,
            onset_steps: z,
            planned: M::NONE,
            uniform_left: z,
            uniform_size: one,
            end_region: z,
            end_steps: z,
            end_left: z,
            last: one,
            j: z,
        }
    }

    fn state(&self, l: usize) -> Gear5State {
        Gear5State {
            r: std::array::from_fn(|k| self.r[k].0[l]),
            dt: self.dt.0[l],
            half_dt2: self.half_dt2.0[l],
            inv_dt: self.inv_dt.0[l],
            gain: self.gain.0[l],
            next: std::array::from_fn(|k| self.next[k].0[l]),
        }
    }

    fn set_state(&mut self, l: usize, s: &Gear5State) {
        for k in 0..6 {
            self.r[k].0[l] = s.r[k];
        }
        self.dt.0[l] = s.dt;
        self.half_dt2.0[l] = s.half_dt2;
        self.inv_dt.0[l] = s.inv_dt;
        self.gain.0[l] = s.gain;
        for k in 0..6 {
            self.next[k].0[l] = s.next[k];
        }
    }

    fn graded(&self, l: usize, grading: Grading) -> GradedSteps {
        GradedSteps {
            dt: self.mesh_dt.0[l],
            grading,
            graded: grading == Grading::Power,
            onset_region: self.onset_region.0[l],
            onset_steps: self.onset_steps.0[l] as u64,
            uniform_left: self.uniform_left.0[l] as u64,
            uniform_size: self.uniform_size.0[l],
            end_region: self.end_region.0[l],
            end_steps: self.end_steps.0[l] as u64,
            end_left: self.end_left.0[l] as u64,
            planned: self.planned.get(l),
            last: self.last.0[l],
        }
    }

    fn set_graded(&mut self, l: usize, g: &GradedSteps) {
        self.mesh_dt.0[l] = g.dt;
        self.onset_region.0[l] = g.onset_region;
        self.onset_steps.0[l] = g.onset_steps as f64;
        self.uniform_left.0[l] = g.uniform_left as f64;
        self.uniform_size.0[l] = g.uniform_size;
        self.end_region.0[l] = g.end_region;
        self.end_steps.0[l] = g.end_steps as f64;
        self.end_left.0[l] = g.end_left as f64;
        self.planned.set(l, g.planned);
        self.last.0[l] = g.last;
    }

    /// `GradedSteps::next(j)` in every lane (then j += 1), as step sizes.
    #[inline(always)]
    fn next_step(&mut self, grading: Grading) -> V {
        let h = match grading {
            Grading::Power => {
                let zero = V::splat(0.0);
                let ul = self.uniform_left.cmp(zero, |a, b| a > b);
                let el = self.end_left.cmp(zero, |a, b| a > b);
                let end_j = self.end_left - V::splat(1.0);
                let p = self.planned;
                let (len, n, j) = (
                    select(p, self.end_region, self.onset_region),
                    select(p, self.end_steps, self.onset_steps),
                    select(p, end_j, self.j),
                );
                let (a, b) = (j / n, (j + V::splat(1.0)) / n);
                let graded = len * (b.powi() - a.powi());
                let planned_h = select(
                    ul,
                    self.uniform_size,
                    select(el, graded, (2.0 * self.last).min(self.mesh_dt)),
                );
                let onset = self.j.cmp(self.onset_steps, |a, b| a < b);
                let h = select(p, planned_h, select(onset, graded, self.mesh_dt));
                self.uniform_left = select(
                    and(p, ul),
                    self.uniform_left - V::splat(1.0),
                    self.uniform_left,
                );
                self.end_left = select(and(p, and(not(ul), el)), end_j, self.end_left);
                h
            }
            _ => self.mesh_dt,
        };
        self.last = h;
        self.j = self.j + V::splat(1.0);
        h
    }
}

/// What a lane is doing, beside its vector state.
#[derive(Default)]
struct LaneCase {
    /// Index into the chunk.
    case: usize,
    contact: u32,
    /// Flight state after the last rebound.
    t: f64,
    x: f64,
    v: f64,
    t_contact: f64,
    v_contact: f64,
    max_overlap: (f64, f64),
    records: Vec<ContactRecord>,
    total_steps: u64,
}

type Output = Vec<(usize, Result<RunOutcome, SimulationError>)>;

fn run_chunk<L: LaneLaw>(cases: &[Case], isa: Isa) -> Output {
    match isa {
        #[cfg(target_arch = "x86_64")]
        // SAFETY: `simulate_batch_with` checked that the CPU has these features.
        Isa::Avx512 => unsafe { kernel_avx512::<L>(cases) },
        #[cfg(target_arch = "x86_64")]
        // SAFETY: as above.
        Isa::Avx2 => unsafe { kernel_avx2::<L>(cases) },
        _ => kernel::<L>(cases),
    }
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f,avx512dq,avx512vl,avx2,fma")]
unsafe fn kernel_avx512<L: LaneLaw>(cases: &[Case]) -> Output {
    kernel::<L>(cases)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
unsafe fn kernel_avx2<L: LaneLaw>(cases: &[Case]) -> Output {
    kernel::<L>(cases)
}

struct Kernel<'a, L> {
    cases: &'a [Case],
    lanes: Lanes,
    lane: [LaneCase; LANES],
    next_case: usize,
    out: Output,
    gear: Gear5,
    _law: std::marker::PhantomData<L>,
}

#[inline(always)]
fn kernel<L: LaneLaw>(cases: &[Case]) -> Output {
    let mut k = Kernel::<L> {
        cases,
        lanes: Lanes::idle(),
        lane: Default::default(),
        next_case: 0,
        out: Vec::with_capacity(cases.len()),
        gear: Gear5::POSITION_DEPENDENT,
        _law: std::marker::PhantomData,
    };
    for l in 0..LANES {
        k.take_case(l);
    }
    while k.lanes.active.any() {
        k.iterate();
    }
    k.out
}

impl<L: LaneLaw> Kernel<'_, L> {
    /// Gives lane `l` the next case that starts a contact (cases that fail
    /// at once are reported), or makes it idle.
    fn take_case(&mut self, l: usize) {
        loop {
            if self.next_case == self.cases.len() {
                let idle = Lanes::idle();
                self.lanes.set_state(l, &idle.state(0));
                self.lanes.set_graded(l, &idle.graded(0, L::GRADING));
                for (dst, src) in [
                    (&mut self.lanes.gravity, idle.gravity),
                    (&mut self.lanes.accel_stiffness, idle.accel_stiffness),
                    (&mut self.lanes.stiffness, idle.stiffness),
                    (&mut self.lanes.budget, idle.budget),
                    (&mut self.lanes.tau_start, idle.tau_start),
                    (&mut self.lanes.tau_end, idle.tau_end),
                    (&mut self.lanes.j, idle.j),
                ] {
                    dst.0[l] = src.0[l];
                }
                self.lanes.active.set(l, false);
                return;
            }
            let c = &self.cases[self.next_case];
            self.lane[l] = LaneCase {
                case: self.next_case,
                contact: 1,
                t: 0.0,
                x: c.problem.gap,
                v: c.problem.velocity,
                records: Vec::with_capacity(c.problem.contacts as usize),
                ..Default::default()
            };
            self.next_case += 1;
            self.lanes.gravity.0[l] = c.problem.gravity;
            self.lanes.accel_stiffness.0[l] = c.accel_stiffness;
            self.lanes.stiffness.0[l] = c.stiffness;
            self.lanes.budget.0[l] = c.budget as f64;
            self.lanes.active.set(l, true);
            match self.start_contact(l) {
                Ok(()) => return,
                Err(e) => self.out.push((c.index, Err(e))),
            }
        }
    }

    /// The flight to the next onset and the contact's first step
    /// (`Run::event_stepping` and the start of `Run::contact`).
    fn start_contact(&mut self, l: usize) -> Result<(), SimulationError> {
        let lc = &mut self.lane[l];
        let c = &self.cases[lc.case];
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
        let mut graded = GradedSteps::new(p.dt, p.contact_time_estimate, L::GRADING);
        let tau_end = 0.0 + graded.next(0);
        let state = self
            .gear
            .start([0.0, v_c, -overlap_accel, -h3, -h4, -h5], tau_end);
        let lanes = &mut self.lanes;
        lanes.set_state(l, &state);
        lanes.set_graded(l, &graded);
        lanes.j.0[l] = 1.0;
        lanes.tau_start.0[l] = 0.0;
        lanes.tau_end.0[l] = tau_end;
        lanes.steps.0[l] = 0.0;
        lanes.max_force.0[l] = onset_force;
        lanes.found.set(l, false);
        Ok(())
    }

    /// One step in every lane, then the lanes' events.
    #[inline(always)]
    fn iterate(&mut self) {
        let gear = self.gear;
        let s = &mut self.lanes;
        // Step size: `set_step` where it changes. Where it does not, the
        // ratio is 1 and every recomputed field but `next` comes out with
        // the bits it has (the same expressions of the same values), so
        // only `next` needs a select.
        let len = s.tau_end - s.tau_start;
        let resize = len.cmp(s.dt, |a, b| a != b);
        let ratio = len / s.dt;
        let mut power = ratio;
        for rk in s.r.iter_mut().skip(1) {
            *rk = *rk * power;
            power = power * ratio;
        }
        s.dt = len;
        s.half_dt2 = 0.5 * len * len;
        s.inv_dt = 1.0 / len;
        let pc = gear.predicted_corrector;
        s.gain = pc[0] * s.half_dt2;
        let rescaled_next = lanes_pascal(&s.r);
        s.next = std::array::from_fn(|k| select(resize, rescaled_next[k], s.next[k]));
        // `Gear5::step_scaled` with the law scaled by the gain, as
        // `Run::contact_step` does, and c = −g; the same expressions in the
        // same order. Predict:
        s.r = s.next;
        s.next = lanes_pascal(&s.r);
        let x = s.r[0];
        let c = -s.gravity;
        let base = c * s.half_dt2 - s.r[2];
        let next_x_base = s.next[0] + pc[0] * base;
        let scaled = L::lanes_force(s.accel_stiffness * s.gain, -x);
        let delta = scaled * V::splat(gear.inverse_sum) + base;
        s.r = std::array::from_fn(|k| s.r[k] + gear.corrector[k] * delta);
        s.next = std::array::from_fn(|k| {
            if k == 0 {
                next_x_base + scaled
            } else {
                s.next[k] + pc[k] * delta
            }
        });
        s.steps = s.steps + V::splat(1.0);
        // Events.
        let position = s.r[0];
        let velocity = s.r[1] * s.inv_dt;
        let zero = V::splat(0.0);
        let turn = and(
            and(s.active, not(s.found)),
            velocity.cmp(zero, |a, b| a >= b),
        );
        if turn.any() {
            for l in 0..LANES {
                if turn.get(l) {
                    self.max_overlap(l);
                }
            }
        }
        let s = &mut self.lanes;
        let inside = position.cmp(zero, |a, b| a < b);
        let force = L::lanes_force(s.stiffness, -position);
        s.max_force = select(
            and(inside, force.cmp(s.max_force, |a, b| a > b)),
            force,
            s.max_force,
        );
        let rebound = and(and(s.active, s.found), not(inside));
        let tau_step = s.tau_start;
        s.tau_start = s.tau_end;
        s.tau_end = s.tau_start + s.next_step(L::GRADING);
        let over = and(not(rebound), s.steps.cmp(s.budget, |a, b| a > b));
        if !and(
            s.active,
            M(std::array::from_fn(|l| rebound.0[l] | over.0[l])),
        )
        .any()
        {
            return;
        }
        for l in 0..LANES {
            if rebound.get(l) {
                self.rebound(l, tau_step.0[l]);
            } else if over.get(l) && self.lanes.active.get(l) {
                let lc = &self.lane[l];
                let error = SimulationError::NoRebound {
                    contact: lc.contact,
                    steps: self.lanes.steps.0[l] as u64,
                };
                self.out.push((self.cases[lc.case].index, Err(error)));
                self.take_case(l);
            }
        }
    }

    /// The step of lane `l` crossed the maximum overlap.
    fn max_overlap(&mut self, l: usize) {
        let s = &mut self.lanes;
        let state = s.state(l);
        let h = state.dt;
        let (theta, at) = locate(&self.gear.dense(&state, &state), Crossing::Velocity);
        let overlap = -at.position;
        let tau_max = s.tau_start.0[l] + theta * h;
        self.lane[l].max_overlap = (tau_max, overlap);
        s.found.set(l, true);
        let law = L::with_stiffness(s.stiffness.0[l]);
        s.max_force.0[l] = s.max_force.0[l].max(law.force(overlap, -at.velocity, &()));
        let mut graded = s.graded(l, L::GRADING);
        graded.plan_end(s.tau_end.0[l], tau_max);
        s.set_graded(l, &graded);
    }

    /// The step of lane `l`, which started at `tau_step`, crossed the rebound.
    fn rebound(&mut self, l: usize, tau_step: f64) {
        let s = &self.lanes;
        let state = s.state(l);
        let h = state.dt;
        let (theta, at) = locate(&self.gear.dense(&state, &state), Crossing::Position);
        let lc = &mut self.lane[l];
        let c = &self.cases[lc.case];
        let (m, g) = (c.problem.mass, c.problem.gravity);
        let duration = tau_step + theta * h;
        let t_c = lc.t_contact;
        let v_c = lc.v_contact;
        let t_rebound = t_c + duration;
        let rebound_velocity = at.velocity;
        let steps = s.steps.0[l] as u64;
        let max_force = s.max_force.0[l];
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
            };
            self.out.push((c.index, Ok(outcome)));
            self.take_case(l);
            return;
        }
        lc.contact += 1;
        (lc.t, lc.x, lc.v) = (t_rebound, 0.0, rebound_velocity);
        if let Err(e) = self.start_contact(l) {
            let index = self.cases[self.lane[l].case].index;
            self.out.push((index, Err(e)));
            self.take_case(l);
        }
    }
}
