//! Deterministic data parallelism: work is cut into chunks whose
//! boundaries depend on the data only, never on the thread count; each
//! chunk is done by one thread in a fixed order, and per-chunk results are
//! combined in chunk order. One thread runs the chunks in the caller's
//! thread, without a team (no hand-off cost per stage).
//!
//! The team is written here rather than taken from rayon (which this crate
//! used until session 5) because a step of 10,000 spheres is ~150 µs of
//! work in two parallel stages: rayon's workers park between stages and
//! take whatever chunk is free, so each stage paid a wake-up and each body
//! moved between the two cores' caches from stage to stage (measured: the
//! per-body stage ran *slower* on two threads than on one). The team's
//! workers spin between stages while a run is going (parking only after a
//! long idle spell), and worker t is the same OS thread in every stage, so
//! a body's data stays in one core's cache (see `PairList::shares`).
//!
//! With the environment variable `DEMBOUND_TEAM_TRACE` set, the team
//! times its stages and prints a table when it stops ([`trace`]).

pub mod trace;

use crate::error::SceneError;
use std::cell::UnsafeCell;
use std::ops::Range;
use std::panic::{catch_unwind, resume_unwind, AssertUnwindSafe};
use std::sync::atomic::{AtomicBool, AtomicU64, AtomicUsize, Ordering};
use std::sync::Arc;
use std::thread::JoinHandle;

/// Bodies per chunk of the per-body sums (fixes their order of additions:
/// changing it changes the bits of every reported sum).
pub const BODY_CHUNK: usize = 4096;

/// Bodies per chunk of the per-body loops within a step that add nothing
/// across bodies (each body's update is its own, a maximum is exact in any
/// order): small enough that two threads share 10,000 bodies evenly
/// (4096 gave chunks of 4096, 4096 and 1808: one thread did 59 %).
pub const STEP_CHUNK: usize = 1024;

/// Spins (`spin_loop`, one PAUSE) before a waiting worker yields its
/// core, then yields before it parks. A spin took 25.9 ns on the AMD EPYC
/// these figures were taken on, so 2^10 spins are ~26 µs: longer than
/// most hand-offs and waits inside a stage on a quiet machine (sub-µs to
/// a few µs), short next to a stage (~130 µs at 10k spheres). Past that
/// the worker yields: on a core of its own `sched_yield` returns at once
/// (0.6 µs, still a poll), and on a core it shares with the worker it
/// waits for (a busy machine: the other core taken) it hands that worker
/// the core. With 2^14 spins (424 µs here) each wait on a shared core
/// burnt the core for the rest of the spin: two threads on one core ran
/// 2000 steps of the 10k lattice drop in 7.84 s against one thread's
/// 0.36 s. Parking after ~2.5 ms of yields frees the core between runs.
pub(crate) const SPINS: u32 = 1 << 10;
const YIELDS: u32 = 1 << 12;

/// The worker threads of one simulation.
pub struct Workers {
    team: Option<Team>,
    threads: usize,
    /// Worker t's bodies `cuts[t]..cuts[t + 1]` in the force stage (set
    /// by the pipeline from the shares): the per-body passes give worker t
    /// the chunks that start there, so a body stays in one core's cache.
    /// Scheduling only: sums are combined in chunk order whatever the cuts.
    cuts: std::sync::RwLock<Vec<usize>>,
}

impl Workers {
    /// `threads` ≥ 1 workers (1: the caller's thread alone).
    pub fn new(threads: usize) -> Result<Self, SceneError> {
        let team = if threads > 1 {
            Some(Team::new(threads)?)
        } else {
            None
        };
        Ok(Self {
            team,
            threads: threads.max(1),
            cuts: std::sync::RwLock::new(Vec::new()),
        })
    }

    /// One worker, the caller's thread (cannot fail: starts no thread).
    pub fn serial() -> Self {
        Self {
            team: None,
            threads: 1,
            cuts: std::sync::RwLock::new(Vec::new()),
        }
    }

    pub fn threads(&self) -> usize {
        self.threads
    }

    /// Runs `f` (kept for the callers written for a pool: the team needs
    /// no entering).
    pub fn install<R: Send>(&self, f: impl FnOnce() -> R + Send) -> R {
        f()
    }

    /// `f(t)` on every worker t in 0..threads, each call on the same OS
    /// thread every time (worker 0 is the caller): worker t's share of the
    /// bodies stays in its core's cache from stage to stage. Results in
    /// worker order.
    #[track_caller]
    pub fn broadcast<T: Send>(&self, f: impl Fn(usize) -> T + Sync + Send) -> Vec<T> {
        match &self.team {
            Some(team) => {
                let mut slots: Vec<Option<T>> = (0..self.threads).map(|_| None).collect();
                let out = SharedMut::new(&mut slots);
                // SAFETY: worker t writes slot t only.
                team.run(&|t| unsafe { *out.at(t) = Some(f(t)) });
                // Every slot is set: `run` returns only after every worker
                // finished (a panic is re-raised there).
                slots.into_iter().flatten().collect()
            }
            None => vec![f(0)],
        }
    }

    /// Runs `f(k)` for every chunk k in 0..chunks (worker t takes a
    /// contiguous run of chunks: the same bodies as in the other stages
    /// when the chunks are bodies).
    #[track_caller]
    pub fn run(&self, chunks: usize, f: impl Fn(usize) + Sync + Send) {
        self.run_split(chunks, |t| even_split(t, self.threads, chunks), f);
    }

    /// `f(k)` for every chunk, collected in chunk order.
    #[track_caller]
    pub fn map<T: Send>(&self, chunks: usize, f: impl Fn(usize) -> T + Sync + Send) -> Vec<T> {
        self.map_split(chunks, |t| even_split(t, self.threads, chunks), f)
    }

    /// Runs `f(k)` for every chunk k of `chunk` bodies of `n`, each on the
    /// worker whose share holds the chunk's first body.
    #[track_caller]
    pub fn run_bodies(&self, n: usize, chunk: usize, f: impl Fn(usize) + Sync + Send) {
        let chunks = n.div_ceil(chunk.max(1));
        self.run_split(chunks, |t| self.body_chunks(t, n, chunk), f);
    }

    /// `f(k)` for every chunk of `chunk` bodies of `n` (as
    /// [`Workers::run_bodies`]), collected in chunk order.
    #[track_caller]
    pub fn map_bodies<T: Send>(
        &self,
        n: usize,
        chunk: usize,
        f: impl Fn(usize) -> T + Sync + Send,
    ) -> Vec<T> {
        let chunks = n.div_ceil(chunk.max(1));
        self.map_split(chunks, |t| self.body_chunks(t, n, chunk), f)
    }

    /// Sets the workers' shares of the bodies (`threads + 1` cuts from 0
    /// to the body count; anything else: even shares of the chunks).
    pub fn set_body_cuts(&self, cuts: &[usize]) {
        if self.team.is_none() {
            return;
        }
        if let Ok(mut c) = self.cuts.write() {
            c.clear();
            c.extend_from_slice(cuts);
        }
    }

    /// The chunks of `chunk` bodies (of `n`) worker t takes: those that
    /// start in its share of the bodies, or an even split of the chunks.
    fn body_chunks(&self, t: usize, n: usize, chunk: usize) -> Range<usize> {
        let threads = self.threads;
        if let Ok(c) = self.cuts.read() {
            if c.len() == threads + 1 && c[threads] == n {
                return c[t].div_ceil(chunk)..c[t + 1].div_ceil(chunk);
            }
        }
        even_split(t, threads, n.div_ceil(chunk.max(1)))
    }

    /// Runs `f(k)` for every chunk k in 0..chunks, worker t the chunks
    /// `split(t)` (the splits cover 0..chunks once).
    #[track_caller]
    fn run_split(
        &self,
        chunks: usize,
        split: impl Fn(usize) -> Range<usize> + Sync,
        f: impl Fn(usize) + Sync + Send,
    ) {
        match &self.team {
            Some(team) if chunks > 1 => team.run(&|t| split(t).for_each(&f)),
            _ => (0..chunks).for_each(f),
        }
    }

    /// [`Self::run_split`], the results collected in chunk order.
    #[track_caller]
    fn map_split<T: Send>(
        &self,
        chunks: usize,
        split: impl Fn(usize) -> Range<usize> + Sync,
        f: impl Fn(usize) -> T + Sync + Send,
    ) -> Vec<T> {
        if self.team.is_none() || chunks <= 1 {
            return (0..chunks).map(f).collect();
        }
        let mut slots: Vec<Option<T>> = (0..chunks).map(|_| None).collect();
        let out = SharedMut::new(&mut slots);
        // SAFETY: chunk k is run once, by one worker, and writes slot k
        // only. Every slot is set when `run_split` returns (a panic is
        // re-raised there).
        self.run_split(chunks, split, |k| unsafe { *out.at(k) = Some(f(k)) });
        slots.into_iter().flatten().collect()
    }

    /// Σ f(k) over 0..n in chunks of [`BODY_CHUNK`], summed in chunk order.
    #[track_caller]
    pub fn sum<const D: usize>(
        &self,
        n: usize,
        f: impl Fn(usize) -> [f64; D] + Sync + Send,
    ) -> [f64; D] {
        let partial = self.map_bodies(n, BODY_CHUNK, |c| {
            let mut s = [0.0; D];
            for k in c * BODY_CHUNK..((c + 1) * BODY_CHUNK).min(n) {
                let v = f(k);
                for d in 0..D {
                    s[d] += v[d];
                }
            }
            s
        });
        let mut s = [0.0; D];
        for p in partial {
            for d in 0..D {
                s[d] += p[d];
            }
        }
        s
    }
}

/// The job of the current stage: a closure on the leader's stack, its
/// lifetime erased (the leader waits for every worker before it returns).
type Job = *const (dyn Fn(usize) + Sync + 'static);

/// What the leader and the workers share.
struct Shared {
    /// Raised by one for every job; a worker runs each new value once.
    epoch: AtomicU64,
    /// Written by the leader before it raises `epoch`, read by the workers
    /// after they see it raised, not written again before `pending` is 0.
    job: UnsafeCell<Option<Job>>,
    /// Workers still running the current job.
    pending: AtomicUsize,
    /// Worker t (index t − 1) is parked or about to park.
    sleeping: Vec<AtomicBool>,
    /// A worker's job panicked (re-raised by the leader).
    panicked: AtomicBool,
    stop: AtomicBool,
    /// Worker t's part of the current stage (index t − 1), when traced.
    parts: Vec<std::sync::Mutex<trace::Part>>,
    /// The leader is running a job (a call from inside a job, or from
    /// another thread meanwhile, runs serially instead).
    busy: AtomicBool,
}

// SAFETY: `job` is written only by the leader while no worker reads it
// (between `pending` reaching 0 and the next raise of `epoch`).
unsafe impl Sync for Shared {}
unsafe impl Send for Shared {}

/// Threads 1..threads of a simulation (the caller is thread 0).
struct Team {
    shared: Arc<Shared>,
    /// The stages timed (`trace`), when asked.
    trace: Option<trace::Trace>,
    handles: Vec<JoinHandle<()>>,
    threads: usize,
}

impl Team {
    fn new(threads: usize) -> Result<Self, SceneError> {
        let shared = Arc::new(Shared {
            epoch: AtomicU64::new(0),
            job: UnsafeCell::new(None),
            pending: AtomicUsize::new(0),
            sleeping: (1..threads).map(|_| AtomicBool::new(false)).collect(),
            panicked: AtomicBool::new(false),
            stop: AtomicBool::new(false),
            parts: (1..threads).map(|_| Default::default()).collect(),
            busy: AtomicBool::new(false),
        });
        trace::start();
        let mut team = Team {
            shared: Arc::clone(&shared),
            trace: trace::on().then(trace::Trace::default),
            handles: Vec::with_capacity(threads - 1),
            threads,
        };
        for t in 1..threads {
            let shared = Arc::clone(&shared);
            let handle = std::thread::Builder::new()
                .name(format!("dembound-worker-{t}"))
                .spawn(move || work(&shared, t))
                .map_err(|e| SceneError::Threads(format!("cannot start worker thread {t}: {e}")))?;
            // Dropping `team` on an error stops the workers started so far.
            team.handles.push(handle);
        }
        Ok(team)
    }

    /// Runs `f(t)` for t in 0..threads, t ≥ 1 on the workers, and returns
    /// when all are done.
    #[track_caller]
    fn run(&self, f: &(dyn Fn(usize) + Sync)) {
        let s = &*self.shared;
        if s.busy.swap(true, Ordering::Acquire) {
            (0..self.threads).for_each(f);
            return;
        }
        let raised = self.trace.as_ref().map(|_| std::time::Instant::now());
        // SAFETY: the lifetime is erased only for the time of this call:
        // it returns after every worker has finished with the job.
        let job: Job = unsafe { std::mem::transmute::<*const (dyn Fn(usize) + Sync + '_), Job>(f) };
        // SAFETY: no worker reads `job` now (the last job's `pending` is 0).
        unsafe { *s.job.get() = Some(job) };
        s.pending.store(self.threads - 1, Ordering::Relaxed);
        s.epoch.fetch_add(1, Ordering::SeqCst);
        for (k, sleeping) in s.sleeping.iter().enumerate() {
            if sleeping.load(Ordering::SeqCst) {
                self.handles[k].thread().unpark();
            }
        }
        let mut mine = Ok(());
        let part0 = if raised.is_some() {
            trace::part(|| mine = catch_unwind(AssertUnwindSafe(|| f(0))))
        } else {
            mine = catch_unwind(AssertUnwindSafe(|| f(0)));
            trace::Part::default()
        };
        let mut spins = 0u32;
        while s.pending.load(Ordering::Acquire) != 0 {
            if spins < SPINS {
                std::hint::spin_loop();
                spins += 1;
            } else {
                std::thread::yield_now();
            }
        }
        if let (Some(tr), Some(raised)) = (&self.trace, raised) {
            let done = std::time::Instant::now();
            let mut parts = vec![part0];
            parts.extend(
                s.parts
                    .iter()
                    .map(|p| p.lock().map(|p| *p).unwrap_or_default()),
            );
            tr.record(std::panic::Location::caller(), raised, done, &parts);
        }
        s.busy.store(false, Ordering::Release);
        if let Err(payload) = mine {
            resume_unwind(payload);
        }
        if s.panicked.swap(false, Ordering::AcqRel) {
            panic!("a worker thread panicked");
        }
    }
}

impl Drop for Team {
    fn drop(&mut self) {
        if let Some(tr) = &self.trace {
            tr.print();
        }
        self.shared.stop.store(true, Ordering::SeqCst);
        self.shared.epoch.fetch_add(1, Ordering::SeqCst);
        for h in &self.handles {
            h.thread().unpark();
        }
        for h in self.handles.drain(..) {
            let _ = h.join();
        }
    }
}

/// Worker t's loop: wait for a new job (spin, yield, then park), run it.
fn work(s: &Shared, t: usize) {
    let mut seen = 0u64;
    loop {
        let mut waited = 0u32;
        loop {
            let e = s.epoch.load(Ordering::Acquire);
            if s.stop.load(Ordering::Acquire) {
                return;
            }
            if e != seen {
                seen = e;
                break;
            }
            waited = waited.saturating_add(1);
            if waited < SPINS {
                std::hint::spin_loop();
            } else if waited < SPINS + YIELDS {
                std::thread::yield_now();
            } else {
                let sleeping = &s.sleeping[t - 1];
                sleeping.store(true, Ordering::SeqCst);
                if s.epoch.load(Ordering::SeqCst) == seen && !s.stop.load(Ordering::SeqCst) {
                    std::thread::park();
                }
                sleeping.store(false, Ordering::SeqCst);
            }
        }
        // SAFETY: the leader wrote the job before raising `epoch` (read
        // above with Acquire) and keeps it alive until `pending` is 0.
        if let Some(job) = unsafe { *s.job.get() } {
            let f = unsafe { &*job };
            let mut ok = true;
            if trace::on() {
                let part = trace::part(|| ok = catch_unwind(AssertUnwindSafe(|| f(t))).is_ok());
                if let Ok(mut p) = s.parts[t - 1].lock() {
                    *p = part;
                }
            } else {
                ok = catch_unwind(AssertUnwindSafe(|| f(t))).is_ok();
            }
            if !ok {
                s.panicked.store(true, Ordering::Release);
            }
        }
        s.pending.fetch_sub(1, Ordering::Release);
    }
}

/// Worker t's even share of `chunks` chunks among `threads`.
fn even_split(t: usize, threads: usize, chunks: usize) -> Range<usize> {
    chunks * t / threads..chunks * (t + 1) / threads
}

/// A raw pointer that may cross threads; every use states why the accesses
/// through it are disjoint.
#[derive(Clone, Copy)]
pub struct SharedMut<T>(pub *mut T);
unsafe impl<T> Send for SharedMut<T> {}
unsafe impl<T> Sync for SharedMut<T> {}

impl<T> SharedMut<T> {
    pub fn new(v: &mut [T]) -> Self {
        SharedMut(v.as_mut_ptr())
    }

    /// # Safety
    /// `k` in bounds, and no other thread touches element `k` meanwhile.
    #[inline(always)]
    #[allow(clippy::mut_from_ref)]
    pub unsafe fn at(&self, k: usize) -> &mut T {
        &mut *self.0.add(k)
    }
}
