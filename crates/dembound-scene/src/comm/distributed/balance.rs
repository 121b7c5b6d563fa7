//! Load re-balancing of a decomposed run (issue 16): the cuts of the
//! sub-domain grid move to where the particles are; the grid stays (as
//! LAMMPS's `balance … shift xyz` and `fix balance … shift`).
//!
//! - **Measure.** The imbalance is the largest over the mean of the
//!   ranks' owned *free* bodies (the bodies integrated and summed; a fixed
//!   boundary particle costs its rank almost nothing: its pairs are
//!   computed with the free partner). Counts rather than measured time
//!   per step: counts are the same on every run, so when a run
//!   re-partitions does not depend on the machine's load (this machine
//!   is shared; timings vary by 2× between runs), and they are exact to
//!   reduce. Time per step is still reported per rank.
//! - **When.** At the start of every list rebuild (every rank rebuilds
//!   on the same step), if the imbalance exceeds the threshold
//!   (`parallel.rebalance_threshold`, default 1.2): the cuts move, then
//!   the rebuild's migration takes each body to its new owner with its
//!   pair histories, as any other migration.
//! - **Where.** Along each split axis the inner cuts are put at the
//!   quantiles k/g of the free bodies' coordinates, found by bisection on
//!   global counts (one sum of g − 1 counts per bisection step, 50
//!   steps): the same cuts on every rank, and no coordinates gathered.
//!   Axes are balanced one at a time (the marginal counts), as LAMMPS's
//!   shift style.
//!
//! The trajectory does not depend on the decomposition (forces summed in
//! partner-id order), so a re-balanced run is the same bits as one that
//! never re-balances (tests/decomposition_balance.rs).

use super::{DistributedSimulation, RankComm};
use crate::comm::Transport;
use crate::pipeline::World;

/// Bisection steps per cut: the cut is then within 2⁻⁵⁰ of the bodies'
/// extent of the quantile (closer than any two distinct coordinates of a
/// bed).
const BISECTIONS: usize = 50;

/// Default of `parallel.rebalance_threshold` (LAMMPS's docs suggest 1.1–
/// 1.2 for `fix balance`; 1.2 leaves a settling bed alone until a fifth
/// of the mean has moved).
pub const DEFAULT_REBALANCE_THRESHOLD: f64 = 1.2;

/// One rank's re-partitioning state (the counts are gathered: the same
/// on every rank).
#[derive(Debug, Clone)]
pub(crate) struct Balance {
    threshold: f64,
    rebalances: u64,
    start: Vec<usize>,
    before: Vec<usize>,
}

impl Default for Balance {
    fn default() -> Self {
        Self {
            threshold: f64::INFINITY,
            rebalances: 0,
            start: Vec::new(),
            before: Vec::new(),
        }
    }
}

/// What the re-partitioning did (the same on every rank).
#[derive(Debug, Clone, PartialEq)]
pub struct BalanceReport {
    /// Re-partition above this imbalance (∞: never).
    pub threshold: f64,
    /// Re-partitions so far.
    pub rebalances: u64,
    /// Each rank's owned free bodies at the first list build.
    pub free_at_start: Vec<usize>,
    /// Each rank's owned free bodies just before the last re-partition
    /// (empty if none).
    pub free_before_last: Vec<usize>,
    /// The cut positions along x, y, z (grid + 1 each), m.
    pub cuts: [Vec<f64>; 3],
}

/// Largest over mean of `counts` (1 when all are zero).
pub fn imbalance(counts: &[usize]) -> f64 {
    let total: usize = counts.iter().sum();
    let max = counts.iter().copied().max().unwrap_or(0);
    if total == 0 {
        1.0
    } else {
        max as f64 * counts.len() as f64 / total as f64
    }
}

impl<T: Transport> DistributedSimulation<T> {
    /// Re-partition when the ranks' free-body imbalance exceeds
    /// `threshold` (> 1; ∞: never, the default of the library). Every
    /// rank sets the same.
    pub fn set_rebalance_threshold(&mut self, threshold: f64) {
        self.comm.balance.threshold = threshold;
    }

    /// What the re-partitioning did so far.
    pub fn balance_report(&self) -> BalanceReport {
        let b = &self.comm.balance;
        BalanceReport {
            threshold: b.threshold,
            rebalances: b.rebalances,
            free_at_start: b.start.clone(),
            free_before_last: b.before.clone(),
            cuts: [0, 1, 2].map(|a| self.comm.decomposition.cuts(a).to_vec()),
        }
    }

    /// Each rank's owned free bodies, rank order. Collective.
    pub fn free_counts(&self) -> Vec<usize> {
        self.comm.free_counts(&self.sim.world)
    }
}

impl<T: Transport> RankComm<T> {
    /// Each rank's owned free bodies, rank order. Collective.
    fn free_counts(&self, world: &World) -> Vec<usize> {
        self.transport
            .all_gather(self.owned_free(world) as f64)
            .iter()
            .map(|&c| c as usize)
            .collect()
    }

    /// Owned free bodies of this rank.
    fn owned_free(&self, world: &World) -> usize {
        let fixed = &world.bodies.fixed;
        (0..fixed.len())
            .filter(|&k| !fixed[k] && !self.halo.get(k).copied().unwrap_or(false))
            .count()
    }

    /// The hook at the start of each list rebuild: moves the cuts if the
    /// imbalance exceeds the threshold (the rebuild then migrates).
    /// Collective.
    pub(super) fn rebalance(&mut self, world: &World) {
        let counts = self.free_counts(world);
        if self.balance.start.is_empty() {
            self.balance.start.clone_from(&counts);
        }
        if counts.len() < 2 || imbalance(&counts) <= self.balance.threshold {
            return;
        }
        let total: usize = counts.iter().sum();
        for a in 0..3 {
            if self.decomposition.grid[a] > 1 {
                let inner = self.quantile_cuts(world, a, total);
                self.decomposition.set_cuts(a, &inner);
            }
        }
        self.balance.before = counts;
        self.balance.rebalances += 1;
    }

    /// Inner cuts along axis a at the quantiles k/g of the `total` free
    /// bodies' coordinates (bisection on global counts). Collective.
    fn quantile_cuts(&self, world: &World, a: usize, total: usize) -> Vec<f64> {
        let g = self.decomposition.grid[a];
        let b = &world.bodies;
        let mut xs: Vec<f64> = (0..b.len())
            .filter(|&k| !b.fixed[k] && !self.halo.get(k).copied().unwrap_or(false))
            .map(|k| b.position[k][a])
            .collect();
        xs.sort_by(f64::total_cmp);
        let lo = -self
            .transport
            .max(-xs.first().copied().unwrap_or(f64::INFINITY));
        let hi = self
            .transport
            .max(xs.last().copied().unwrap_or(f64::NEG_INFINITY));
        if !(lo.is_finite() && hi.is_finite()) {
            return self.decomposition.cuts(a)[1..g].to_vec();
        }
        // Invariant: fewer than the target below lo[k], at least the
        // target below hi[k] (all of them are below next_up(hi)).
        let target: Vec<f64> = (1..g).map(|k| (k * total) as f64 / g as f64).collect();
        let mut low = vec![lo; g - 1];
        let mut high = vec![hi.next_up(); g - 1];
        for _ in 0..BISECTIONS {
            let mid: Vec<f64> = (0..g - 1).map(|k| 0.5 * (low[k] + high[k])).collect();
            let below: Vec<f64> = mid
                .iter()
                .map(|&m| xs.partition_point(|&x| x < m) as f64)
                .collect();
            let below = self.transport.sum(&below);
            for (k, (&count, &m)) in below.iter().zip(&mid).enumerate() {
                if count < target[k] {
                    low[k] = m;
                } else {
                    high[k] = m;
                }
            }
        }
        high
    }
}
