//! Running one scene on several ranks (issue 16): spatial domain
//! decomposition over a message transport.
//!
//! - [`Transport`]: the few collective and point-to-point operations the
//!   decomposition needs; [`threads::ThreadTransport`] runs ranks as
//!   threads of one process (tests, no MPI), `mpi::MpiTransport` (feature
//!   `mpi`) over Open MPI through rsmpi.
//! - [`distributed::DistributedSimulation`]: one rank's share of a scene:
//!   its own bodies and a halo of copies of its neighbours', exchanged
//!   every step; bodies migrate at list rebuilds with their pair state.
//! - [`pack`]: the byte layout of what crosses ranks.

pub mod distributed;
#[cfg(feature = "mpi")]
pub mod mpi;
pub mod pack;
pub mod threads;

pub use distributed::{DistributedSimulation, RankReport};

/// What the decomposition needs from a message layer. Every rank calls the
/// same operations in the same order (each is collective over the ranks
/// named in it); messages between two ranks arrive in the order sent.
pub trait Transport {
    fn rank(&self) -> usize;
    fn size(&self) -> usize;
    /// Sends each `(rank, bytes)` of `sends` and receives one message from
    /// each rank of `from`, returned in the order of `from`.
    fn exchange(&self, sends: &[(usize, Vec<u8>)], from: &[usize]) -> Vec<Vec<u8>>;
    /// [`Self::exchange`] with `work` run while the messages are in
    /// flight (MPI: non-blocking sends and receives, completed after it);
    /// the message from `from[k]` lands in `got[k]`, whose length the
    /// caller has set to the message's exact length in bytes (the buffers
    /// are the caller's, kept from step to step: nothing is allocated or
    /// zeroed here). `work` may call its argument now and then to let the
    /// messages progress.
    fn exchange_during(
        &self,
        sends: &[(usize, Vec<u8>)],
        from: &[usize],
        got: &mut [Vec<u8>],
        work: &mut dyn FnMut(&mut dyn FnMut()),
    );
    /// `to[r]`: whether this rank will send to rank r; returns, for each
    /// rank r, whether r will send to this rank.
    fn who_sends(&self, to: &[bool]) -> Vec<bool>;
    /// The largest `x` over the ranks.
    fn max(&self, x: f64) -> f64;
    /// Element-wise sums over the ranks.
    fn sum(&self, x: &[f64]) -> Vec<f64>;
    /// Every rank's `x`, in rank order.
    fn all_gather(&self, x: f64) -> Vec<f64>;
    /// Every rank's bytes at rank 0, in rank order (`None` elsewhere).
    fn gather(&self, bytes: Vec<u8>) -> Option<Vec<Vec<u8>>>;
    /// Ends every rank with this exit code (MPI_Abort).
    fn abort(&self, code: i32) -> !;
}

/// A borrowed transport is a transport (the caller keeps MPI alive).
impl<T: Transport + ?Sized> Transport for &T {
    fn rank(&self) -> usize {
        (**self).rank()
    }
    fn size(&self) -> usize {
        (**self).size()
    }
    fn exchange(&self, sends: &[(usize, Vec<u8>)], from: &[usize]) -> Vec<Vec<u8>> {
        (**self).exchange(sends, from)
    }
    fn exchange_during(
        &self,
        sends: &[(usize, Vec<u8>)],
        from: &[usize],
        got: &mut [Vec<u8>],
        work: &mut dyn FnMut(&mut dyn FnMut()),
    ) {
        (**self).exchange_during(sends, from, got, work)
    }
    fn who_sends(&self, to: &[bool]) -> Vec<bool> {
        (**self).who_sends(to)
    }
    fn max(&self, x: f64) -> f64 {
        (**self).max(x)
    }
    fn sum(&self, x: &[f64]) -> Vec<f64> {
        (**self).sum(x)
    }
    fn all_gather(&self, x: f64) -> Vec<f64> {
        (**self).all_gather(x)
    }
    fn gather(&self, bytes: Vec<u8>) -> Option<Vec<Vec<u8>>> {
        (**self).gather(bytes)
    }
    fn abort(&self, code: i32) -> ! {
        (**self).abort(code)
    }
}
