//! Load balance between the workers of one process: which blocks of the
//! force loop, and so which bodies, each worker takes. Scheduling only:
//! the results never depend on it (the force loop's order of additions is
//! set by the blocks, see `contacts::run_blocks_then`).
//!
//! A worker keeps its share from stage to stage (the bodies stay in its
//! core's cache). The shares start from an estimate (bodies and listed
//! pairs) and follow the measured cost of each block from step to step:
//! in a falling or settling bed the touching pairs, which cost most, sit
//! at one end of the cell order, and an estimate from listed pairs alone
//! gave one of two workers 70 % of the force loop.
//!
//! Two workers do without the measured shares: they take the force
//! blocks from both ends of the list until they meet
//! (`contacts::both_ends`), and the per-body stages cut the bodies where
//! they met last ([`Shares::meet`]).

use std::sync::atomic::{AtomicU64, AtomicUsize, Ordering};

/// What a body costs in the per-body stages (kick, drift, walls, its row
/// of the force loop), in listed pairs: on lattice-drop with one thread
/// the advance stage took 41 ns per body and the force loop 20 ns per
/// listed pair. Only the first step after a list build uses it.
const BODY_COST: f64 = 2.0;
/// Weight of the newest measurement in a block's smoothed cost.
const SMOOTHING: f64 = 0.1;
/// New shares are taken when they cut the predicted slowest worker's time
/// by more than this fraction (no flapping between near-equal cuts: each
/// move sends a block's bodies to the other core's cache). Measured on
/// lattice-drop 10k, 2 threads, quiet machine: 0.05 gave a median
/// 1.76× over one thread (1.64–1.94), 0.15 gave 1.91× (1.49–1.99).
const GAIN: f64 = 0.15;

/// The workers' shares of the blocks of one pair list.
#[derive(Debug, Default)]
pub struct Shares {
    /// Worker t takes blocks `cuts[t]..cuts[t + 1]` (in the order of
    /// [`share_order`]). Empty: one worker.
    cuts: Vec<u32>,
    /// Smoothed cost of each block (arbitrary units before the first
    /// measurement, ns after).
    cost: Vec<f64>,
    measured: bool,
    /// This step's time in the force loop per block, ns.
    block_ns: Vec<AtomicU64>,
    /// This step's time in the per-body stage per worker, ns.
    advance_ns: Vec<AtomicU64>,
    /// Two workers (`contacts::both_ends`): where they met in the last
    /// force loop, as the index of the even block there halved;
    /// `usize::MAX`: not yet (the estimate's cut serves).
    pub meet: AtomicUsize,
}

impl Clone for Shares {
    fn clone(&self) -> Self {
        let copy = |v: &[AtomicU64]| {
            v.iter()
                .map(|a| AtomicU64::new(a.load(Ordering::Relaxed)))
                .collect()
        };
        Shares {
            cuts: self.cuts.clone(),
            cost: self.cost.clone(),
            measured: self.measured,
            block_ns: copy(&self.block_ns),
            advance_ns: copy(&self.advance_ns),
            meet: AtomicUsize::new(self.meet.load(Ordering::Relaxed)),
        }
    }
}

impl Shares {
    /// Shares for `threads` workers of the blocks `blocks` (boundaries in
    /// bodies) of a list with row starts `start`, from the estimate.
    pub fn new(threads: usize, blocks: &[u32], start: &[u32]) -> Self {
        let count = blocks.len().saturating_sub(1);
        if threads < 2 || count == 0 {
            return Shares::default();
        }
        let cost: Vec<f64> = (0..count)
            .map(|b| {
                let (lo, hi) = (blocks[b] as usize, blocks[b + 1] as usize);
                (hi - lo) as f64 * BODY_COST + (start[hi] - start[lo]) as f64
            })
            .collect();
        Shares {
            cuts: cuts_for(&cost, threads),
            cost,
            measured: false,
            block_ns: (0..count).map(|_| AtomicU64::new(0)).collect(),
            advance_ns: (0..threads).map(|_| AtomicU64::new(0)).collect(),
            meet: AtomicUsize::new(usize::MAX),
        }
    }

    /// Two workers take the blocks from both ends of the list
    /// (`contacts::both_ends`): nothing to measure or rebalance.
    pub fn both_ends(&self) -> bool {
        self.advance_ns.len() == 2
    }

    /// Blocks `first..end` of worker `t`, if the shares are for `threads`
    /// (two workers: below and above where they met last).
    pub fn blocks(&self, t: usize, threads: usize) -> Option<(usize, usize)> {
        if self.cuts.len() != threads + 1 || t >= threads {
            return None;
        }
        let count = self.cost.len();
        let m = self.meet.load(Ordering::Relaxed);
        if threads == 2 && m != usize::MAX {
            // Where the two met: worker 0 below, worker 1 above.
            let cut = (2 * m).min(count);
            return Some(if t == 0 { (0, cut) } else { (cut, count) });
        }
        Some((self.cuts[t] as usize, self.cuts[t + 1] as usize))
    }

    /// Records block `b`'s time in the force loop this step.
    pub fn record_block(&self, b: usize, ns: u64) {
        if let Some(a) = self.block_ns.get(b) {
            a.fetch_add(ns, Ordering::Relaxed);
        }
    }

    /// Records worker `t`'s time in the per-body stage this step.
    pub fn record_advance(&self, t: usize, ns: u64) {
        if let Some(a) = self.advance_ns.get(t) {
            a.fetch_add(ns, Ordering::Relaxed);
        }
    }

    /// Folds this step's measurements into the blocks' costs and moves the
    /// cuts if that balances the workers better. `blocks`: the list's
    /// block boundaries in bodies.
    pub fn rebalance(&mut self, blocks: &[u32]) {
        let threads = self.advance_ns.len();
        let count = self.cost.len();
        if threads < 2 || blocks.len() != count + 1 || self.cuts.len() != threads + 1 {
            return;
        }
        let bodies = |b: usize| f64::from(blocks[b + 1] - blocks[b]);
        for t in 0..threads {
            let (first, end) = (self.cuts[t] as usize, self.cuts[t + 1] as usize);
            let n: f64 = (first..end).map(bodies).sum();
            let per_body = self.advance_ns[t].swap(0, Ordering::Relaxed) as f64 / n.max(1.0);
            for b in first..end {
                let now = self.block_ns[b].swap(0, Ordering::Relaxed) as f64 + per_body * bodies(b);
                self.cost[b] = if self.measured {
                    (1.0 - SMOOTHING) * self.cost[b] + SMOOTHING * now
                } else {
                    now
                };
            }
        }
        self.measured = true;
        let candidate = cuts_for(&self.cost, threads);
        if slowest(&self.cost, &candidate) < (1.0 - GAIN) * slowest(&self.cost, &self.cuts) {
            self.cuts = candidate;
        }
    }
}

/// Cuts giving each of `threads` workers about the same total cost.
fn cuts_for(cost: &[f64], threads: usize) -> Vec<u32> {
    let count = cost.len();
    let mut cumulative = Vec::with_capacity(count + 1);
    cumulative.push(0.0);
    for c in cost {
        let last = cumulative.last().copied().unwrap_or(0.0);
        cumulative.push(last + c);
    }
    let total = cumulative[count];
    let mut cuts = vec![0u32];
    for t in 1..threads {
        let target = total * t as f64 / threads as f64;
        // The cut nearest the target, not before the previous one.
        let previous = cuts.last().copied().unwrap_or(0) as usize;
        let mut best = previous;
        for k in previous..=count {
            if (cumulative[k] - target).abs() < (cumulative[best] - target).abs() {
                best = k;
            }
        }
        cuts.push(best as u32);
    }
    cuts.push(count as u32);
    cuts
}

/// The order in which a worker runs blocks `first..end` of `count`: even
/// blocks before the odd blocks between them (an odd block waits for both
/// even neighbours), and first the even block at each end of the share
/// that a neighbouring share's odd block waits for. A wait across workers
/// is then for a block the other worker runs first: short, and never a
/// cycle.
pub fn share_order(first: usize, end: usize, count: usize) -> Vec<usize> {
    let mut order = Vec::with_capacity(end.saturating_sub(first));
    let mut taken = vec![false; end.saturating_sub(first)];
    let mut take = |b: usize, order: &mut Vec<usize>| {
        if (first..end).contains(&b) && !taken[b - first] {
            taken[b - first] = true;
            order.push(b);
        }
    };
    if first > 0 && first.is_multiple_of(2) {
        // The previous share's last block (odd) waits for it.
        take(first, &mut order);
    }
    if end < count && end % 2 == 1 {
        // The next share's first block (odd) waits for it.
        take(end - 1, &mut order);
    }
    for b in first..end {
        if b % 2 == 0 {
            take(b, &mut order);
            if b > first {
                take(b - 1, &mut order);
            }
        }
    }
    for b in first..end {
        take(b, &mut order);
    }
    order
}

/// The largest worker's total cost under `cuts`.
fn slowest(cost: &[f64], cuts: &[u32]) -> f64 {
    cuts.windows(2)
        .map(|w| cost[w[0] as usize..w[1] as usize].iter().sum::<f64>())
        .fold(0.0, f64::max)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cuts_balance_a_uniform_cost() {
        assert_eq!(cuts_for(&[1.0; 10], 2), vec![0, 5, 10]);
        assert_eq!(cuts_for(&[1.0; 12], 3), vec![0, 4, 8, 12]);
        // All the cost in the first block: one worker takes it alone.
        assert_eq!(cuts_for(&[9.0, 1.0, 1.0, 1.0], 2)[1], 1);
    }

    /// Runs the shares' orders as workers taking turns one block at a time
    /// (a block runs only when its even neighbours are done, as in
    /// `contacts::run_blocks_then`): every block runs once, no worker is stuck.
    fn schedule(cuts: &[usize], count: usize) -> Vec<usize> {
        let orders: Vec<Vec<usize>> = cuts
            .windows(2)
            .map(|w| share_order(w[0], w[1], count))
            .collect();
        let mut next = vec![0usize; orders.len()];
        let mut done = vec![false; count];
        let mut ran = Vec::new();
        while ran.len() < count {
            let mut progressed = false;
            for (w, order) in orders.iter().enumerate() {
                if let Some(&b) = order.get(next[w]) {
                    let ready = b % 2 == 0 || (done[b - 1] && (b + 1 >= count || done[b + 1]));
                    if ready {
                        done[b] = true;
                        ran.push(b);
                        next[w] += 1;
                        progressed = true;
                    }
                }
            }
            assert!(progressed, "workers stuck at {next:?} with cuts {cuts:?}");
        }
        ran
    }

    #[test]
    fn shares_run_every_block_once_for_odd_and_even_cuts() {
        for count in 1..12 {
            for c1 in 0..=count {
                for c2 in c1..=count {
                    let mut ran = schedule(&[0, c1, c2, count], count);
                    ran.sort_unstable();
                    assert_eq!(ran, (0..count).collect::<Vec<_>>());
                }
            }
        }
        // A share's boundary evens come first.
        assert_eq!(share_order(3, 8, 10), vec![4, 3, 6, 5, 7]);
        assert_eq!(share_order(4, 9, 12), vec![4, 8, 6, 5, 7]);
    }

    #[test]
    fn measured_cost_moves_the_cut_toward_the_expensive_end() {
        // 12 blocks of 100 bodies, a uniform estimate: the cut at 6. Then
        // the first 4 blocks are measured 5× as costly as the rest: total
        // 28 µs, half 14; the cuts around it give 10 : 18 (at 2), 15 : 13
        // (at 3) and 20 : 8 (at 4): 3, whose slowest worker (15) beats the
        // old cut's (22).
        let blocks: Vec<u32> = (0..=12).map(|b| b * 100).collect();
        let start: Vec<u32> = (0..=1200).collect();
        let mut shares = Shares::new(2, &blocks, &start);
        assert_eq!(shares.blocks(0, 2), Some((0, 6)));
        for b in 0..12 {
            shares.record_block(b, if b < 4 { 5000 } else { 1000 });
        }
        shares.rebalance(&blocks);
        assert_eq!(shares.blocks(0, 2), Some((0, 3)));
        assert_eq!(shares.blocks(1, 2), Some((3, 12)));
        // The wrong thread count: no shares.
        assert_eq!(shares.blocks(0, 3), None);
    }
}
