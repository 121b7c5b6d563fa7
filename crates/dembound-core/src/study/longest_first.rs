//! Independent jobs of very unequal cost on every thread of the current
//! rayon pool, longest first (LPT scheduling, Graham 1969): each thread
//! takes the costliest job not yet started, so the threads finish
//! together unless one job alone outlasts the rest.
//!
//! Why not `par_iter`: rayon splits a list into halves and steals at that
//! granularity, so a list whose first jobs are 10⁴ times longer than its
//! last (the convergence study's fixed-step runs at η = 1/2000 against its
//! event-stepping runs) leaves a thread idle while the other works through
//! the long half. Results are returned in the jobs' order whatever the
//! order they ran in, so a caller's output does not depend on scheduling.

use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Mutex, PoisonError};

/// Runs `run` on every job, longest `cost` first, on every thread of the
/// current rayon pool; the results in the order of `jobs`.
pub fn run_longest_first<J, R, C, F>(jobs: &[J], cost: C, run: F) -> Vec<R>
where
    J: Sync,
    R: Send,
    C: Fn(&J) -> f64,
    F: Fn(&J) -> R + Sync,
{
    let mut order: Vec<usize> = (0..jobs.len()).collect();
    // Stable: equal costs keep the jobs' order.
    order.sort_by(|&a, &b| cost(&jobs[b]).total_cmp(&cost(&jobs[a])));
    let next = AtomicUsize::new(0);
    let slots: Vec<Mutex<Option<R>>> = jobs.iter().map(|_| Mutex::new(None)).collect();
    let workers = rayon::current_num_threads().min(jobs.len());
    rayon::scope(|scope| {
        for _ in 0..workers {
            scope.spawn(|_| loop {
                let taken = next.fetch_add(1, Ordering::Relaxed);
                let Some(&index) = order.get(taken) else {
                    break;
                };
                let result = run(&jobs[index]);
                *slots[index].lock().unwrap_or_else(PoisonError::into_inner) = Some(result);
            });
        }
    });
    slots
        .into_iter()
        .map(|slot| {
            slot.into_inner()
                .unwrap_or_else(PoisonError::into_inner)
                // Every index of `order` was taken by one worker, and
                // `scope` returns after every worker has finished.
                .expect("every job ran")
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn results_come_back_in_the_jobs_order_whatever_the_costs() {
        // Costs reversed against the order: the jobs run last-to-first, the
        // results must still be each job's own square at its own index.
        let jobs: Vec<u64> = (0..100).collect();
        let out = run_longest_first(&jobs, |&j| j as f64, |&j| j * j);
        assert_eq!(out, jobs.iter().map(|j| j * j).collect::<Vec<_>>());
    }

    #[test]
    fn the_costliest_job_starts_first() {
        // On a one-thread pool the jobs run exactly in decreasing cost.
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .expect("a one-thread pool");
        let started = Mutex::new(Vec::new());
        let costs = [3.0, 9.0, 1.0, 9.0, 5.0];
        pool.install(|| {
            run_longest_first(
                &[0usize, 1, 2, 3, 4],
                |&j| costs[j],
                |&j| started.lock().expect("not poisoned").push(j),
            )
        });
        // 9 (job 1, then job 3: equal costs keep their order), 5, 3, 1.
        assert_eq!(started.into_inner().expect("not poisoned"), [1, 3, 4, 0, 2]);
    }

    #[test]
    fn no_jobs_no_results() {
        let out: Vec<u8> = run_longest_first(&[] as &[u8], |_| 0.0, |&j| j);
        assert!(out.is_empty());
    }
}
