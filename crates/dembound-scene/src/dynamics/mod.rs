//! Forces and motion: pair contacts, plane walls, the integrators and the
//! collision log.

pub mod collisions;
pub mod contacts;
pub mod integrate;
pub mod walls;

/// A raw pointer that may cross threads; every use states why the writes
/// through it are disjoint.
#[derive(Clone, Copy)]
pub(crate) struct SharedMut<T>(pub *mut T);
unsafe impl<T> Send for SharedMut<T> {}
unsafe impl<T> Sync for SharedMut<T> {}

/// Chunk of the deterministic sums (fixed: independent of the thread count).
pub(crate) const SUM_CHUNK: usize = 4096;

/// Σ f(k) over 0..n, in chunks of [`SUM_CHUNK`] summed in chunk order:
/// the same bits for any number of threads.
pub(crate) fn deterministic_sum<const D: usize>(
    pool: &rayon::ThreadPool,
    n: usize,
    f: impl Fn(usize) -> [f64; D] + Sync,
) -> [f64; D] {
    use rayon::prelude::*;
    let partial: Vec<[f64; D]> = pool.install(|| {
        (0..n.div_ceil(SUM_CHUNK))
            .into_par_iter()
            .map(|c| {
                let mut s = [0.0; D];
                for k in c * SUM_CHUNK..((c + 1) * SUM_CHUNK).min(n) {
                    let v = f(k);
                    for d in 0..D {
                        s[d] += v[d];
                    }
                }
                s
            })
            .collect()
    });
    let mut s = [0.0; D];
    for p in partial {
        for d in 0..D {
            s[d] += p[d];
        }
    }
    s
}
