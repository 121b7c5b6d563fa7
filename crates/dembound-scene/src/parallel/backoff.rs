//! How a thread of the team waits for another: spin while the wait is
//! likely short, then yield the core.
//!
//! A spin (`spin_loop`, one PAUSE) took 25.9 ns on the AMD EPYC these
//! figures were taken on. How long to spin before `sched_yield` depends
//! on who else wants the core:
//!
//! - **The team has a core per thread** (the usual case): a long spin,
//!   [`LONG_SPINS`] (~210 µs, about a step of 10,000 spheres). A yield
//!   hands the core to any other runnable process for a whole time slice
//!   (Linux's EEVDF: ~0.75–3 ms), and a background job at the lowest
//!   priority is enough: with one `nice -n 19` job running, two threads
//!   of the 10k frictionless lattice drop took 2.4–3.3 s of stepping
//!   after 26 µs spins against 1.9–2.2 s after 210 µs spins (one thread:
//!   3.5–4.0 s); with a normal-priority job on one core, 4.9–5.3 s
//!   against 3.9–4.0 s. Quiet, the same (1.8–2.2 s either way).
//! - **More threads than the cores this process may use**
//!   (`available_parallelism`: the affinity mask and the cgroup's CPU
//!   quota): a short spin, [`SPINS`] (~26 µs), since the thread waited
//!   for may be waiting for this very core. Two threads held on one core
//!   (`taskset -c 0`): 3.5 s after 26 µs spins, 4.4 s after 210 µs (one
//!   thread 3.4 s). (Spinning without yielding there: 25 s.)
//!
//! (BENCHMARKS.md, "Session 33: how the team's threads wait".)

use std::cell::Cell;

/// Spins before a yield when the team has more threads than cores.
pub(crate) const SPINS: u32 = 1 << 10;
/// Spins before a yield when each thread of the team has a core.
pub(crate) const LONG_SPINS: u32 = 1 << 13;

thread_local! {
    /// This thread's spins before it yields (set by the team for each of
    /// its threads; a thread outside a team spins the short budget).
    static BUDGET: Cell<u32> = const { Cell::new(SPINS) };
}

/// The spins before a yield for a team of `threads` threads on a process
/// that may use `cores` cores.
pub(crate) fn budget_for(threads: usize, cores: usize) -> u32 {
    if threads <= cores {
        LONG_SPINS
    } else {
        SPINS
    }
}

/// Sets the calling thread's spins before a yield.
pub(crate) fn set_budget(spins: u32) {
    BUDGET.with(|b| b.set(spins));
}

/// The calling thread's spins before a yield.
pub(crate) fn budget() -> u32 {
    BUDGET.with(Cell::get)
}

/// One wait: `snooze` spins the calling thread's budget, then yields.
pub(crate) struct Backoff {
    spins: u32,
    budget: u32,
}

impl Backoff {
    pub(crate) fn new() -> Self {
        Backoff {
            spins: 0,
            budget: budget(),
        }
    }

    pub(crate) fn snooze(&mut self) {
        if self.spins < self.budget {
            std::hint::spin_loop();
            self.spins += 1;
        } else {
            std::thread::yield_now();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The long spin only where each thread has a core: 2 threads on 1,
    /// 2 and 4 cores, 3 threads on 2.
    #[test]
    fn long_spins_only_with_a_core_per_thread() {
        assert_eq!(budget_for(2, 1), SPINS);
        assert_eq!(budget_for(2, 2), LONG_SPINS);
        assert_eq!(budget_for(2, 4), LONG_SPINS);
        assert_eq!(budget_for(3, 2), SPINS);
    }

    /// A thread's budget is its own: set on one thread, another keeps the
    /// short default.
    #[test]
    fn the_budget_is_per_thread() {
        set_budget(LONG_SPINS);
        assert_eq!(budget(), LONG_SPINS);
        let other = std::thread::spawn(budget).join().expect("thread runs");
        assert_eq!(other, SPINS);
        set_budget(SPINS);
    }
}
