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

mod backoff;
pub mod trace;

pub(crate) use backoff::Backoff;

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

/// Yields (`sched_yield`) of a worker waiting for the next stage, after
/// its spins ([`backoff`]), before it parks: ~2.5 ms of them free the core
/// between runs.
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
                team.run(&|t| unsafe { *out.at(t) = Some(f(t)) }, Entry::All);
                // Every slot is set: `run` returns only after every worker
                // finished (a panic is re-raised there).
                slots.into_iter().flatten().collect()
            }
            None => vec![f(0)],
        }
    }

    /// `f(t)` on worker 0 (the caller) and on each other worker that
    /// starts before worker 0 has finished its call: `f` must leave
    /// nothing undone when only worker 0 runs it (its units claimable by
    /// any worker). The results of the workers that ran, in worker order
    /// (worker 0's first). A worker kept off its core (a busy machine)
    /// then costs the stage nothing: worker 0 does its part and the stage
    /// ends without waiting for it to start.
    #[track_caller]
    pub fn broadcast_present<T: Send>(&self, f: impl Fn(usize) -> T + Sync + Send) -> Vec<T> {
        match &self.team {
            Some(team) => {
                let mut slots: Vec<Option<T>> = (0..self.threads).map(|_| None).collect();
                let out = SharedMut::new(&mut slots);
                // SAFETY: worker t writes slot t only.
                team.run(&|t| unsafe { *out.at(t) = Some(f(t)) }, Entry::Present);
                // The slots of the workers that ran are set: `run` returns
                // only after each worker that entered has finished.
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

    /// Runs `f(k)` once for every chunk k in 0..chunks (the splits cover
    /// 0..chunks once). Worker t takes the chunks `split(t)` first, in
    /// order, then those of the other workers' splits not yet taken, from
    /// their far ends: each chunk is claimed (one atomic swap), so a
    /// worker that starts late finds its chunks done and the stage does
    /// not wait for it ([`Workers::broadcast_present`]). Which worker runs
    /// a chunk does not change what it computes: the results are combined
    /// in chunk order by the callers. When every chunk is in worker 0's
    /// split, the caller's thread runs them without a hand-off.
    #[track_caller]
    fn run_split(
        &self,
        chunks: usize,
        split: impl Fn(usize) -> Range<usize> + Sync,
        f: impl Fn(usize) + Sync + Send,
    ) {
        let team = match &self.team {
            Some(team) if chunks > 1 && (1..self.threads).any(|t| !split(t).is_empty()) => team,
            _ => return (0..chunks).for_each(f),
        };
        let claimed: Vec<AtomicBool> = (0..chunks).map(|_| AtomicBool::new(false)).collect();
        let take = |k: usize| {
            if k < chunks && !claimed[k].swap(true, Ordering::Relaxed) {
                f(k);
            }
        };
        let threads = self.threads;
        team.run(
            &|t| {
                split(t).for_each(take);
                for d in 1..threads {
                    split((t + d) % threads).rev().for_each(take);
                }
            },
            Entry::Present,
        );
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

/// Whether a stage waits for every worker or only for those that started
/// before the leader finished its part.
#[derive(Clone, Copy, PartialEq)]
enum Entry {
    /// Every worker runs the job (each has a part no other takes).
    All,
    /// The leader's call alone leaves nothing undone; the workers that
    /// start before it has finished help.
    Present,
}

/// [`Shared::entry`]: the leader has finished its part of a
/// [`Entry::Present`] stage; no worker enters it any more.
const CLOSED: u64 = 1;
/// [`Shared::entry`]: an [`Entry::All`] stage (the worker counts itself
/// out in `pending` too).
const ALL: u64 = 2;
/// [`Shared::entry`]: one worker inside the stage.
const INSIDE: u64 = 4;
/// [`Shared::entry`]'s workers inside.
const INSIDE_MASK: u64 = 0xffff_fffc;

/// What the leader and the workers share.
struct Shared {
    /// Raised by one for every job; a worker runs each new value once.
    epoch: AtomicU64,
    /// Written by the leader before it raises `epoch`, read by the workers
    /// after they see it raised, not written again before `pending` is 0.
    job: UnsafeCell<Option<Job>>,
    /// Workers still running the current job ([`Entry::All`]).
    pending: AtomicUsize,
    /// The current stage's entry word: its epoch's low 32 bits above bit
    /// 32, [`CLOSED`], [`ALL`], and the workers inside it in units of
    /// [`INSIDE`]. A worker enters (one compare-and-swap) only a stage of
    /// the epoch it saw that is not closed, and reads the job only then.
    entry: AtomicU64,
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
    /// Spins before a yield, for each thread of the team
    /// ([`backoff::budget_for`]).
    spins: u32,
}

impl Team {
    fn new(threads: usize) -> Result<Self, SceneError> {
        let shared = Arc::new(Shared {
            epoch: AtomicU64::new(0),
            job: UnsafeCell::new(None),
            pending: AtomicUsize::new(0),
            entry: AtomicU64::new(0),
            sleeping: (1..threads).map(|_| AtomicBool::new(false)).collect(),
            panicked: AtomicBool::new(false),
            stop: AtomicBool::new(false),
            parts: (1..threads).map(|_| Default::default()).collect(),
            busy: AtomicBool::new(false),
        });
        trace::start();
        let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
        let spins = backoff::budget_for(threads, cores);
        let mut team = Team {
            shared: Arc::clone(&shared),
            trace: trace::on().then(trace::Trace::default),
            handles: Vec::with_capacity(threads - 1),
            threads,
            spins,
        };
        for t in 1..threads {
            let shared = Arc::clone(&shared);
            let handle = std::thread::Builder::new()
                .name(format!("dembound-worker-{t}"))
                .spawn(move || work(&shared, t, spins))
                .map_err(|e| SceneError::Threads(format!("cannot start worker thread {t}: {e}")))?;
            // Dropping `team` on an error stops the workers started so far.
            team.handles.push(handle);
        }
        Ok(team)
    }

    /// Runs `f(t)` for t in 0..threads, t ≥ 1 on the workers, and returns
    /// when all are done; with [`Entry::Present`], `f(0)` and `f(t)` of
    /// the workers that start before `f(0)` returns, when those are done.
    #[track_caller]
    fn run(&self, f: &(dyn Fn(usize) + Sync), entry: Entry) {
        let s = &*self.shared;
        if s.busy.swap(true, Ordering::Acquire) {
            (0..self.threads).for_each(f);
            return;
        }
        let raised = self.trace.as_ref().map(|_| std::time::Instant::now());
        if raised.is_some() {
            // A worker that does not enter leaves no part.
            for p in &s.parts {
                if let Ok(mut p) = p.lock() {
                    *p = trace::Part::default();
                }
            }
        }
        // SAFETY: the lifetime is erased only for the time of this call:
        // it returns after every worker that entered has finished with
        // the job, and no worker enters after it returns (the stage is
        // closed, or every worker has run it).
        let job: Job = unsafe { std::mem::transmute::<*const (dyn Fn(usize) + Sync + '_), Job>(f) };
        // SAFETY: no worker is inside a stage now (the last one's workers
        // inside are 0 and it is closed or all have run), and none enters
        // one before `entry` holds the new epoch (stored after this).
        unsafe { *s.job.get() = Some(job) };
        let all = entry == Entry::All;
        s.pending
            .store(if all { self.threads - 1 } else { 0 }, Ordering::Relaxed);
        let epoch = s.epoch.load(Ordering::Relaxed).wrapping_add(1);
        s.entry.store(
            ((epoch & 0xffff_ffff) << 32) | if all { ALL } else { 0 },
            Ordering::Release,
        );
        s.epoch.store(epoch, Ordering::SeqCst);
        for (k, sleeping) in s.sleeping.iter().enumerate() {
            if sleeping.load(Ordering::SeqCst) {
                self.handles[k].thread().unpark();
            }
        }
        // The leader may be any thread: its waits take the team's budget.
        backoff::set_budget(self.spins);
        let mut mine = Ok(());
        let part0 = if raised.is_some() {
            trace::part(|| mine = catch_unwind(AssertUnwindSafe(|| f(0))))
        } else {
            mine = catch_unwind(AssertUnwindSafe(|| f(0)));
            trace::Part::default()
        };
        let wait = |done: &dyn Fn() -> bool| {
            let mut backoff = Backoff::new();
            while !done() {
                backoff.snooze();
            }
        };
        if all {
            wait(&|| s.pending.load(Ordering::Acquire) == 0);
        } else {
            // No worker enters from now on; those inside finish.
            s.entry.fetch_or(CLOSED, Ordering::AcqRel);
            wait(&|| s.entry.load(Ordering::Acquire) & INSIDE_MASK == 0);
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

/// Worker t's loop: wait for a new job (spin `spins` times, yield, then
/// park), run it.
fn work(s: &Shared, t: usize, spins: u32) {
    backoff::set_budget(spins);
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
                if enter(s, e) {
                    break;
                }
                // The stage closed before this worker came: nothing of
                // it is left; wait for the next.
                waited = 0;
                continue;
            }
            waited = waited.saturating_add(1);
            if waited < spins {
                std::hint::spin_loop();
            } else if waited < spins.saturating_add(YIELDS) {
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
        let all = s.entry.load(Ordering::Relaxed) & ALL != 0;
        // SAFETY: the leader wrote the job before storing the entry word
        // this worker entered by (an Acquire compare-and-swap) and keeps
        // it alive until the workers inside are 0 (and, for an
        // [`Entry::All`] stage, `pending` is 0).
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
        // Out of the stage before `pending` lets the leader store the
        // next stage's word.
        s.entry.fetch_sub(INSIDE, Ordering::Release);
        if all {
            s.pending.fetch_sub(1, Ordering::Release);
        }
    }
}

/// Enters the stage of epoch `e` if it is still open (see
/// [`Shared::entry`]): false when the leader has closed it or moved on.
fn enter(s: &Shared, e: u64) -> bool {
    let tag = (e & 0xffff_ffff) << 32;
    let mut word = s.entry.load(Ordering::Acquire);
    loop {
        if word & !0xffff_ffff != tag || word & CLOSED != 0 {
            return false;
        }
        match s.entry.compare_exchange_weak(
            word,
            word + INSIDE,
            Ordering::AcqRel,
            Ordering::Acquire,
        ) {
            Ok(_) => return true,
            Err(seen) => word = seen,
        }
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

#[cfg(test)]
mod tests {
    use super::*;

    /// Every chunk runs once and the results come in chunk order, on 2 and
    /// 3 threads, for 0 to 19 chunks, with the body cuts giving worker 0
    /// all, none or part of the chunks, and with one worker slowed at
    /// its first chunk so that the others take the rest of its split.
    /// Reference: the chunk indices themselves (each result is its chunk).
    #[test]
    fn every_chunk_runs_once_whoever_takes_it() {
        for threads in [2usize, 3] {
            let workers = Workers::new(threads).expect("threads start");
            for chunks in 0usize..20 {
                for cut in [0, chunks / 3, chunks] {
                    let mut cuts = vec![0, cut];
                    cuts.extend(std::iter::repeat_n(chunks, threads - 1));
                    workers.set_body_cuts(&cuts);
                    for slow in [None, Some(1usize), Some(0)] {
                        let ran: Vec<AtomicUsize> =
                            (0..chunks).map(|_| AtomicUsize::new(0)).collect();
                        let got = workers.map_bodies(chunks, 1, |k| {
                            if Some(k) == slow.map(|t| cuts[t]) {
                                std::thread::sleep(std::time::Duration::from_millis(2));
                            }
                            ran[k].fetch_add(1, Ordering::SeqCst);
                            k
                        });
                        assert_eq!(got, (0..chunks).collect::<Vec<_>>());
                        for (k, r) in ran.iter().enumerate() {
                            assert_eq!(r.load(Ordering::SeqCst), 1, "chunk {k} of {chunks}");
                        }
                    }
                }
            }
        }
    }

    /// A stage that every worker must run (`broadcast`) after stages the
    /// workers may have missed (`broadcast_present`): each worker runs
    /// each `broadcast` once, and a `broadcast_present` runs worker 0
    /// always and no worker twice. Reference: counts per worker.
    #[test]
    fn present_stages_then_every_worker_stages() {
        let workers = Workers::new(3).expect("threads start");
        let runs: Vec<AtomicUsize> = (0..3).map(|_| AtomicUsize::new(0)).collect();
        for round in 0..2000 {
            let present = workers.broadcast_present(|t| t);
            assert_eq!(present.first(), Some(&0));
            assert!(present.windows(2).all(|w| w[0] < w[1]), "{present:?}");
            if round % 7 == 0 {
                let all = workers.broadcast(|t| {
                    runs[t].fetch_add(1, Ordering::SeqCst);
                    t
                });
                assert_eq!(all, vec![0, 1, 2]);
            }
        }
        for r in &runs {
            assert_eq!(r.load(Ordering::SeqCst), 2000usize.div_ceil(7));
        }
    }
}
