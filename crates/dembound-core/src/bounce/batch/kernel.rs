//! The kernel: a group of lanes stepping cases in lockstep (vector code
//! per step, the events per lane), one build per instruction set.

use super::lanes::{Geometry, Hot, Lanes, State, MAX_LANES};
use super::laws::LaneLaw;
use super::locate::{Located, Steps, MAX_STEPS};
use super::queue::{plan_case, Case, Chunk, Queue, Slot, SlotId};
#[cfg(not(target_arch = "x86_64"))]
use super::simd;
#[cfg(target_arch = "x86_64")]
use super::simd::{Avx2, Avx512, Sse2};
use super::simd::{Simd, V};
use super::steps::{Mesh, Tables};
use super::{Isa, GROUP_AVX2, GROUP_AVX512, GROUP_BASELINE};
use crate::bounce::events::{time_to_surface, Crossing};
use crate::bounce::schedule::{GradedSteps, Grading};
use crate::bounce::{ContactRecord, RunOutcome, Scenario};
use crate::integrate::{pascal, Gear5, Integrator, Kinematics};
use crate::{Error, Result};

/// Rows of the step-size ring (a power of two).
pub(super) const RING: usize = 64;
/// A lane's run of sizes longer than the ring is continued once the ring
/// holds no more than this many of them.
pub(super) const REFILL: u64 = 8;

/// What a lane is doing, beside its vector state.
pub(super) struct LaneCase {
    /// The case, None when the lane is idle.
    pub(super) case: Option<Case>,
    pub(super) contact: u32,
    /// Flight state after the last rebound.
    pub(super) t: f64,
    pub(super) x: f64,
    pub(super) v: f64,
    pub(super) t_contact: f64,
    pub(super) v_contact: f64,
    pub(super) found: bool,
    pub(super) max_overlap: (f64, f64),
    /// The peak force so far, but for the steps' (see [`Hot::min_position`]).
    pub(super) max_force: f64,
    pub(super) records: Vec<ContactRecord>,
    pub(super) total_steps: u64,
    /// Iteration of the contact's first step and the last it may take.
    pub(super) first: u64,
    pub(super) deadline: u64,
    pub(super) mesh: Mesh,
    /// The ring holds this lane's sizes up to this iteration (not
    /// included); Δt after.
    pub(super) filled: u64,
    /// Whether the sizes after `filled` are still to be written.
    pub(super) more: bool,
}

impl LaneCase {
    pub(super) fn idle() -> Self {
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
pub(super) fn run_kernel<L: LaneLaw>(queue: &Queue<'_>, isa: Isa) {
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
pub(super) unsafe fn kernel_avx512<L: LaneLaw>(queue: &Queue<'_>, s: Avx512) {
    Kernel::<L, Avx512, { GROUP_AVX512 }>::new(queue, s).run()
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
pub(super) unsafe fn kernel_avx2<L: LaneLaw>(queue: &Queue<'_>, s: Avx2) {
    Kernel::<L, Avx2, { GROUP_AVX2 }>::new(queue, s).run()
}

/// A threshold t with r₁ ≥ t wherever `r₁ * (1.0 / Δt) >= 0.0` for the
/// step sizes Δt of a contact with `dt` (they are below 2 dt): r₁ ≥ 0, or
/// r₁ < 0 so small that the product rounds to −0, |r₁| < 2⁻¹⁰⁷⁴ Δt. A
/// normal number, so that nothing in the step loop is subnormal.
pub(super) fn velocity_threshold(dt: f64) -> f64 {
    -f64::MIN_POSITIVE * (2.0 * dt).max(1.0)
}

#[repr(align(64))]
pub(super) struct Kernel<'a, 'q, L, S: Simd, const G: usize> {
    pub(super) s: S,
    pub(super) queue: &'a Queue<'q>,
    /// The chunks of cases taken; the last is being started.
    pub(super) chunks: Vec<Chunk<'q>>,
    /// The lanes' state between steps (see [`Hot`]).
    pub(super) mem: State,
    /// Per-lane constants of the step: −g and the law's stiffness over m.
    pub(super) c: Lanes,
    pub(super) accel_stiffness: Lanes,
    /// Event thresholds: a lane's event is r₁ ≥ `velocity_event` or
    /// position ≥ `position_event`. The maximum overlap is sought where the
    /// velocity r₁/Δt ≥ 0; that is tested on r₁ alone, against a tiny
    /// negative threshold (see [`velocity_threshold`]), the position is
    /// tested against 0 after it; +∞ disables either. The events recheck
    /// the scalar path's conditions exactly.
    pub(super) velocity_event: Lanes,
    pub(super) position_event: Lanes,
    /// Step sizes: row `i % RING` holds every lane's size for iteration
    /// i < `until` (as f64); the lane's Δt, `dt`, is the size after.
    pub(super) ring: Box<[Lanes; RING]>,
    pub(super) until: Lanes,
    pub(super) dt: Lanes,
    pub(super) lane: Vec<LaneCase>,
    pub(super) tables: Tables,
    /// The iteration whose step is being taken (the first is 1).
    pub(super) now: u64,
    /// The iteration at which some lane needs its ring refilled, and the
    /// earliest lane deadline.
    pub(super) refill_at: u64,
    pub(super) deadline: u64,
    pub(super) active: usize,
    pub(super) gear: Gear5,
    pub(super) _law: std::marker::PhantomData<L>,
}

impl<'a, 'q, L: LaneLaw, S: Simd, const G: usize> Kernel<'a, 'q, L, S, G> {
    /// Lanes of the kernel.
    pub(super) const N: usize = S::W * G;

    #[inline(always)]
    pub(super) fn new(queue: &'a Queue<'q>, s: S) -> Self {
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
    pub(super) fn run(mut self) {
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
    pub(super) fn sizes(&self, at: u64) -> V<S, G> {
        let s = self.s;
        let row = V::load(s, &self.ring[at as usize & (RING - 1)]);
        V::splat(s, at as f64)
            .lt(V::load(s, &self.until))
            .select(row, V::load(s, &self.dt))
    }

    /// The step of iteration `now + 1` with sizes `h`: its end and the
    /// factors of `set_step` and `step_scaled` that depend on the sizes alone.
    #[inline(always)]
    pub(super) fn geometry(&self, hot: &Hot<S, G>, h: V<S, G>) -> Geometry<S, G> {
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
    pub(super) fn pop(&mut self) -> Option<(SlotId, &'q Scenario)> {
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
    pub(super) fn put(&mut self, (chunk, i): SlotId, result: Slot) {
        if let Some(slot) = self.chunks.get_mut(chunk).and_then(|c| c.out.get_mut(i)) {
            *slot = result;
        }
    }

    /// Gives every lane its first case.
    #[inline(never)]
    pub(super) fn start(&mut self) {
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
    pub(super) fn refill(&mut self, at: u64) {
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
    pub(super) fn write_run(&mut self, l: usize, at: u64) {
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
    pub(super) fn restart_run(&mut self, l: usize, from: u64) {
        self.lane[l].filled = from;
        self.write_run(l, from);
    }

    pub(super) fn update_marks(&mut self) {
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
    pub(super) fn events(&mut self, bits: u32) {
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
                let error = Error::NoRebound {
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
    pub(super) fn take_case(&mut self, l: usize) {
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
    pub(super) fn start_contact(&mut self, l: usize) -> Result<()> {
        let lc = &mut self.lane[l];
        let Some(c) = &lc.case else {
            return Ok(());
        };
        let p = &c.problem;
        let g = p.gravity;
        let tau = time_to_surface(lc.x, lc.v, g).ok_or(Error::NeverReachesBoundary)?;
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
    pub(super) fn max_overlap(&mut self, l: usize, theta: f64, at: &Kinematics) {
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
    pub(super) fn rebound(&mut self, l: usize, theta: f64, at: &Kinematics) {
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
