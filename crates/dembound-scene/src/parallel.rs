//! Deterministic data parallelism: work is cut into chunks whose
//! boundaries depend on the data only, never on the thread count; each
//! chunk is done by one thread in a fixed order, and per-chunk results are
//! combined in chunk order. One thread runs the chunks in the caller's
//! thread, without a pool (no hand-off cost per stage).

use rayon::prelude::*;

/// Bodies per chunk of the per-body sums (fixes their order of additions:
/// changing it changes the bits of every reported sum).
pub const BODY_CHUNK: usize = 4096;

/// Bodies per chunk of the per-body loops within a step that add nothing
/// across bodies (each body's update is its own, a maximum is exact in any
/// order): small enough that two threads share 10,000 bodies evenly
/// (4096 gave chunks of 4096, 4096 and 1808: one thread did 59 %).
pub const STEP_CHUNK: usize = 1024;

/// The worker threads of one simulation.
pub struct Workers {
    pool: Option<rayon::ThreadPool>,
    threads: usize,
}

impl Workers {
    /// `threads` ≥ 1 workers (1: the caller's thread alone).
    pub fn new(threads: usize) -> Result<Self, rayon::ThreadPoolBuildError> {
        let pool = if threads > 1 {
            Some(
                rayon::ThreadPoolBuilder::new()
                    .num_threads(threads)
                    .build()?,
            )
        } else {
            None
        };
        Ok(Self { pool, threads })
    }

    pub fn threads(&self) -> usize {
        self.threads
    }

    /// Runs `f` on one of the workers, so that the [`Workers::run`] and
    /// [`Workers::map`] calls inside it start from a worker of the pool:
    /// each is then a fork-join among the workers, instead of an injection
    /// from outside whose caller sleeps on a lock and must be woken up at
    /// the end (the cost of every parallel stage at small body counts).
    pub fn install<R: Send>(&self, f: impl FnOnce() -> R + Send) -> R {
        match &self.pool {
            Some(pool) => pool.install(f),
            None => f(),
        }
    }

    /// Runs `f(k)` for every chunk k in 0..chunks.
    pub fn run(&self, chunks: usize, f: impl Fn(usize) + Sync + Send) {
        match &self.pool {
            Some(pool) if chunks > 1 => pool.install(|| (0..chunks).into_par_iter().for_each(f)),
            _ => (0..chunks).for_each(f),
        }
    }

    /// `f(k)` for every chunk, collected in chunk order.
    pub fn map<T: Send>(&self, chunks: usize, f: impl Fn(usize) -> T + Sync + Send) -> Vec<T> {
        match &self.pool {
            Some(pool) if chunks > 1 => {
                pool.install(|| (0..chunks).into_par_iter().map(f).collect())
            }
            _ => (0..chunks).map(f).collect(),
        }
    }

    /// Σ f(k) over 0..n in chunks of [`BODY_CHUNK`], summed in chunk order.
    pub fn sum<const D: usize>(
        &self,
        n: usize,
        f: impl Fn(usize) -> [f64; D] + Sync + Send,
    ) -> [f64; D] {
        let partial = self.map(n.div_ceil(BODY_CHUNK), |c| {
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
