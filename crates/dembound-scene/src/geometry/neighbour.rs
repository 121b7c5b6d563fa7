//! Verlet half lists with a skin, built from linked cells.
//!
//! After the bodies are sorted by cell, body i lists every j > i of its own
//! cell and of the 13 "forward" cells of its 26 neighbours (the half
//! stencil: forward cells have a larger linear index, so j > i always);
//! LAMMPS's `half/bin/newtoff` instead scans the full stencil and keeps
//! j > i, which lists the same pairs. Two fixed bodies are never listed.
//!
//! Bodies too large for the cells (boundary spheres many times a grain's
//! size) and ghost images are paired in a separate, serial "extra" list.
//!
//! The list also fixes the force loop's blocks ([`PairList::blocks`]):
//! contiguous ranges of bodies such that the pairs of block k reach no
//! further than block k + 1. Even blocks, then odd blocks, can then add
//! their forces in parallel without two threads ever writing one body,
//! and the order of additions into each body is set by the blocks alone,
//! never by the number of threads.

use super::cells::CellGrid;
use super::ghosts::Ghosts;
use crate::balance::Shares;
use crate::parallel::Workers;

/// Body chunk of the parallel list build (fixed: the list does not depend
/// on the thread count).
const BUILD_CHUNK: usize = 1024;
/// Smallest block of the force loop, bodies.
const MIN_BLOCK: usize = 512;
/// What the search needs of the bodies (sorted by cell).
pub struct SearchInput<'a> {
    pub position: &'a [[f64; 3]],
    pub radius: &'a [f64],
    pub fixed: &'a [bool],
    /// Bodies `0..celled` are in cells (sorted by cell); `celled..n` are
    /// the large ones.
    pub celled: usize,
    pub grid: &'a CellGrid,
    /// Start of each cell in the body order.
    pub cell_start: &'a [u32],
    pub ghosts: &'a Ghosts,
    /// m.
    pub skin: f64,
}

/// A half list in compressed rows, plus the serial extra pairs.
#[derive(Debug, Clone, Default)]
pub struct PairList {
    /// Row starts, n + 1 entries: the partners of i are `j[start[i]..start[i+1]]`.
    pub start: Vec<u32>,
    pub j: Vec<u32>,
    /// Extra pairs (i, j): j an extended index (≥ n: ghost j − n).
    pub extra: Vec<(u32, u32)>,
    /// Force-loop block boundaries: block k is bodies `blocks[k]..blocks[k+1]`.
    pub blocks: Vec<u32>,
    /// The force loop runs the rows in body order on one thread (a domain
    /// decomposition: each body's additions then come in its partners'
    /// order, whatever the blocks).
    pub sequential: bool,
    /// Which blocks (and so which bodies) each worker takes, in the force
    /// loop and the per-body stages: scheduling only, the results do not
    /// depend on it.
    pub shares: Shares,
}

#[inline]
fn within(a: [f64; 3], b: [f64; 3], range: f64) -> bool {
    let d = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
    d[0] * d[0] + d[1] * d[1] + d[2] * d[2] < range * range
}

/// The 13 forward neighbour offsets.
fn forward_offsets() -> Vec<[i64; 3]> {
    let mut v = Vec::with_capacity(13);
    for dz in -1i64..=1 {
        for dy in -1i64..=1 {
            for dx in -1i64..=1 {
                if (dz, dy, dx) > (0, 0, 0) {
                    v.push([dx, dy, dz]);
                }
            }
        }
    }
    v
}

impl PairList {
    /// Every main entry as (row i, entry k), in list order.
    pub fn entries(&self) -> impl Iterator<Item = (usize, usize)> + '_ {
        self.start
            .windows(2)
            .enumerate()
            .flat_map(|(i, w)| (w[0] as usize..w[1] as usize).map(move |k| (i, k)))
    }

    pub fn pair_count(&self) -> usize {
        self.j.len() + self.extra.len()
    }

    /// Builds the lists.
    pub fn build(input: &SearchInput, workers: &Workers) -> Self {
        let n = input.position.len();
        let grid = input.grid;
        let offsets = forward_offsets();
        let cell_of_body = |x: [f64; 3]| grid.coords(x);
        let rows: Vec<(Vec<u32>, Vec<u32>)> =
            workers.map(input.celled.div_ceil(BUILD_CHUNK), |chunk| {
                let lo = chunk * BUILD_CHUNK;
                let hi = (lo + BUILD_CHUNK).min(input.celled);
                let mut counts = Vec::with_capacity(hi - lo);
                let mut js = Vec::with_capacity((hi - lo) * 8);
                for i in lo..hi {
                    let before = js.len();
                    let xi = input.position[i];
                    let ri = input.radius[i] + input.skin;
                    let fi = input.fixed[i];
                    let c = cell_of_body(xi);
                    let own = grid.index(c);
                    let end = input.cell_start[own + 1] as usize;
                    for j in i + 1..end {
                        if !(fi && input.fixed[j])
                            && within(xi, input.position[j], ri + input.radius[j])
                        {
                            js.push(j as u32);
                        }
                    }
                    for o in &offsets {
                        let cx = c[0] as i64 + o[0];
                        let cy = c[1] as i64 + o[1];
                        let cz = c[2] as i64 + o[2];
                        if cx < 0
                            || cy < 0
                            || cz < 0
                            || cx >= grid.dims[0] as i64
                            || cy >= grid.dims[1] as i64
                            || cz >= grid.dims[2] as i64
                        {
                            continue;
                        }
                        let k = grid.index([cx as usize, cy as usize, cz as usize]);
                        for j in input.cell_start[k] as usize..input.cell_start[k + 1] as usize {
                            if !(fi && input.fixed[j])
                                && within(xi, input.position[j], ri + input.radius[j])
                            {
                                js.push(j as u32);
                            }
                        }
                    }
                    // Ascending j within a row: better locality in the force loop.
                    js[before..].sort_unstable();
                    counts.push((js.len() - before) as u32);
                }
                (counts, js)
            });
        let mut start = Vec::with_capacity(n + 1);
        start.push(0u32);
        let total: usize = rows.iter().map(|r| r.1.len()).sum();
        let mut j = Vec::with_capacity(total);
        for (counts, js) in rows {
            for c in counts {
                let last = *start.last().unwrap_or(&0);
                start.push(last + c);
            }
            j.extend_from_slice(&js);
        }
        // Large bodies have empty rows.
        while start.len() < n + 1 {
            let last = *start.last().unwrap_or(&0);
            start.push(last);
        }
        let mut extra = Vec::new();
        // Large bodies against every body (two large ones once).
        for l in input.celled..n {
            for i in 0..n {
                if i == l || (i >= input.celled && i < l) {
                    continue;
                }
                if input.fixed[i] && input.fixed[l] {
                    continue;
                }
                if within(
                    input.position[i],
                    input.position[l],
                    input.radius[i] + input.radius[l] + input.skin,
                ) {
                    extra.push((i.min(l) as u32, i.max(l) as u32));
                }
            }
        }
        // Ghosts against real bodies of a smaller index than their owner
        // (each physical pair once: exactly one of its two images qualifies).
        let ghosts = input.ghosts;
        for g in 0..ghosts.len() {
            let owner = ghosts.owner[g] as usize;
            let xg = ghosts.position[g];
            let rg = input.radius[owner] + input.skin;
            let fg = input.fixed[owner];
            let c = cell_of_body(xg);
            for dz in -1i64..=1 {
                for dy in -1i64..=1 {
                    for dx in -1i64..=1 {
                        let cx = c[0] as i64 + dx;
                        let cy = c[1] as i64 + dy;
                        let cz = c[2] as i64 + dz;
                        if cx < 0
                            || cy < 0
                            || cz < 0
                            || cx >= grid.dims[0] as i64
                            || cy >= grid.dims[1] as i64
                            || cz >= grid.dims[2] as i64
                        {
                            continue;
                        }
                        let k = grid.index([cx as usize, cy as usize, cz as usize]);
                        for i in input.cell_start[k] as usize..input.cell_start[k + 1] as usize {
                            if i < owner
                                && !(fg && input.fixed[i])
                                && within(xg, input.position[i], rg + input.radius[i])
                            {
                                extra.push((i as u32, (n + g) as u32));
                            }
                        }
                    }
                }
            }
            for i in input.celled..owner.max(input.celled) {
                if !(fg && input.fixed[i]) && within(xg, input.position[i], rg + input.radius[i]) {
                    extra.push((i as u32, (n + g) as u32));
                }
            }
        }
        let blocks = Self::blocks_for(&start, &j, n);
        if crate::parallel::trace::on() {
            crate::parallel::trace::note_blocks(&blocks, &start);
        }
        let shares = Shares::new(workers.threads(), &blocks, &start);
        PairList {
            start,
            j,
            extra,
            blocks,
            sequential: false,
            shares,
        }
    }

    /// Bodies `lo..hi` of worker `t`'s share, if the list has one per worker.
    pub fn share(&self, t: usize, threads: usize) -> Option<(usize, usize)> {
        let (first, end) = self.shares.blocks(t, threads)?;
        Some((self.blocks[first] as usize, self.blocks[end] as usize))
    }

    /// Each worker's share of the force loop now, (blocks, bodies), for
    /// tests that must show the work is split; empty when the loop is not
    /// shared among `threads` workers (one thread, a decomposed run).
    pub fn worker_shares(&self, threads: usize) -> Vec<(usize, usize)> {
        if self.sequential {
            return Vec::new();
        }
        (0..threads)
            .map(|t| {
                let (first, end) = self.shares.blocks(t, threads)?;
                let (lo, hi) = self.share(t, threads)?;
                Some((end - first, hi - lo))
            })
            .collect::<Option<Vec<_>>>()
            .unwrap_or_default()
    }

    /// Folds the step's measured costs into the shares.
    pub fn rebalance(&mut self) {
        self.shares.rebalance(&self.blocks);
    }

    /// Blocks such that block k's pairs reach at most into block k + 1:
    /// b₀ = 0, b₁ = MIN_BLOCK, b_{k+2} = max(b_{k+1} + MIN_BLOCK, 1 + the
    /// largest j of block k). Depends on the list only.
    fn blocks_for(start: &[u32], j: &[u32], n: usize) -> Vec<u32> {
        let reach = |lo: usize, hi: usize| -> usize {
            let mut r = hi;
            for i in lo..hi {
                let (a, b) = (start[i] as usize, start[i + 1] as usize);
                if b > a {
                    // Rows are sorted: the last entry is the largest.
                    r = r.max(j[b - 1] as usize + 1);
                }
            }
            r
        };
        let mut blocks = vec![0u32];
        let mut lo = 0usize;
        let mut hi = MIN_BLOCK.min(n);
        while lo < n {
            blocks.push(hi as u32);
            if hi >= n {
                break;
            }
            let next = (hi + MIN_BLOCK).max(reach(lo, hi)).min(n);
            lo = hi;
            hi = next;
        }
        blocks
    }
}
