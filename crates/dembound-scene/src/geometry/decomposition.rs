//! Spatial domain decomposition (issue 16): the box cut into a grid of
//! sub-domains, one per rank, as LAMMPS's `comm brick` and `processors`
//! do. Pure geometry, no MPI: which rank owns a point, which ranks a body
//! must be copied to (its halo), and the grid chosen from the number of
//! ranks and the box's shape.

use super::domain::Domain;
use crate::SceneError;

/// A region cut into `grid[0] × grid[1] × grid[2]` equal sub-domains; rank
/// r sits at grid coordinates (r mod gx, (r / gx) mod gy, r / (gx gy))
/// (x fastest, like LAMMPS's default `processors` map). The region is the
/// box, or on non-periodic axes the bodies' extent at the start (a bed at
/// the bottom of a tall box is cut where the bodies are); the edge
/// sub-domains reach past it without bound.
#[derive(Debug, Clone, PartialEq)]
pub struct Decomposition {
    pub domain: Domain,
    pub grid: [usize; 3],
    /// The region cut, m.
    pub lower: [f64; 3],
    pub upper: [f64; 3],
    /// Along each axis the grid[a] + 1 cut positions, m, lower to upper:
    /// even at first (lower + k L / g), moved by [`Self::set_cuts`] when
    /// the load is re-balanced (the grid stays).
    cuts: [Vec<f64>; 3],
}

impl Decomposition {
    /// `grid` given (`parallel.grid`) or chosen for `ranks` (preferring
    /// sub-domains at least `min_width` m wide, so that a body's copies go
    /// to the neighbouring sub-domains only; narrower ones work, the copies
    /// then reach further); checks that the grid has `ranks` cells and
    /// splits no periodic axis.
    ///
    /// `extent`: the bodies' bounding box (used on non-periodic axes where
    /// it is not flat).
    pub fn new(
        domain: Domain,
        ranks: usize,
        grid: Option<[usize; 3]>,
        min_width: f64,
        extent: Option<([f64; 3], [f64; 3])>,
    ) -> Result<Self, SceneError> {
        let (mut lower, mut upper) = (domain.lower, domain.upper);
        if let Some((lo, hi)) = extent {
            for a in 0..3 {
                if !domain.periodic[a] && lo[a].is_finite() && hi[a].is_finite() && hi[a] > lo[a] {
                    lower[a] = lo[a];
                    upper[a] = hi[a];
                }
            }
        }
        let len = [0, 1, 2].map(|a| upper[a] - lower[a]);
        let grid = match grid {
            Some(g) => {
                if g.contains(&0) || g[0] * g[1] * g[2] != ranks {
                    return Err(SceneError::invalid(
                        "parallel.grid",
                        format!("{g:?}"),
                        format!("three counts ≥ 1 whose product is the number of ranks, {ranks}"),
                    ));
                }
                g
            }
            None => choose_grid(ranks, len, domain.periodic, min_width),
        };
        for a in 0..3 {
            if grid[a] > 1 && domain.periodic[a] {
                return Err(SceneError::invalid(
                    "parallel.grid",
                    format!("{grid:?}"),
                    format!(
                        "1 sub-domain along periodic axis {a} (periodic axes are not split yet)"
                    ),
                ));
            }
        }
        let cuts = [0, 1, 2].map(|a| {
            let l = upper[a] - lower[a];
            (0..=grid[a])
                .map(|k| lower[a] + l * (k as f64) / (grid[a] as f64))
                .collect()
        });
        Ok(Self {
            domain,
            grid,
            lower,
            upper,
            cuts,
        })
    }

    /// The `grid[a]` + 1 cut positions along axis a, m.
    pub fn cuts(&self, a: usize) -> &[f64] {
        &self.cuts[a]
    }

    /// Moves the `grid[a]` − 1 inner cuts along axis a to `inner` (m,
    /// non-decreasing; an empty sub-domain is allowed). The outer cuts
    /// stay, widened if an inner one passes them (the edge sub-domains
    /// reach past the region anyway). Returns false (nothing changed) if
    /// `inner` has the wrong length, is not finite or decreases.
    pub fn set_cuts(&mut self, a: usize, inner: &[f64]) -> bool {
        let g = self.grid[a];
        let ok = inner.len() + 1 == g
            && inner.iter().all(|x| x.is_finite())
            && inner.windows(2).all(|w| w[0] <= w[1]);
        if !ok {
            return false;
        }
        let c = &mut self.cuts[a];
        c[1..g].copy_from_slice(inner);
        if let (Some(&first), Some(&last)) = (inner.first(), inner.last()) {
            c[0] = c[0].min(first);
            c[g] = c[g].max(last);
        }
        true
    }

    pub fn ranks(&self) -> usize {
        self.grid[0] * self.grid[1] * self.grid[2]
    }

    /// Grid coordinates of rank r.
    pub fn coords(&self, r: usize) -> [usize; 3] {
        let [gx, gy, _] = self.grid;
        [r % gx, (r / gx) % gy, r / (gx * gy)]
    }

    /// Lower and upper corner of rank r's sub-domain, m: between its cuts
    /// (the same numbers as [`Self::owner`] compares with).
    pub fn bounds(&self, r: usize) -> ([f64; 3], [f64; 3]) {
        let c = self.coords(r);
        let mut lo = [0.0; 3];
        let mut hi = [0.0; 3];
        for a in 0..3 {
            lo[a] = self.cut(a, c[a]);
            hi[a] = self.cut(a, c[a] + 1);
        }
        (lo, hi)
    }

    fn cut(&self, a: usize, k: usize) -> f64 {
        self.cuts[a][k]
    }

    /// Rank owning point x: the sub-domain containing it, points outside
    /// the box (or not finite) going to the nearest edge sub-domain.
    pub fn owner(&self, x: [f64; 3]) -> usize {
        let c = [self.slab(0, x[0]), self.slab(1, x[1]), self.slab(2, x[2])];
        self.rank_at(c)
    }

    fn rank_at(&self, c: [usize; 3]) -> usize {
        c[0] + self.grid[0] * (c[1] + self.grid[1] * c[2])
    }

    /// Grid index along axis a of coordinate x: from the cuts themselves
    /// (not a division), so that owner and bounds agree at every cut.
    fn slab(&self, a: usize, x: f64) -> usize {
        let g = self.grid[a];
        let mut k = 0;
        while k + 1 < g && x >= self.cut(a, k + 1) {
            k += 1;
        }
        k
    }

    /// Ranks other than `x`'s owner whose sub-domain lies closer than
    /// `width` m to `x` (the ranks that need a copy of a body at x whose
    /// pairs reach `width`), in rank order.
    pub fn ranks_within(&self, x: [f64; 3], width: f64) -> Vec<usize> {
        let own = self.owner(x);
        let lo = [0, 1, 2].map(|a| self.slab(a, x[a] - width));
        let hi = [0, 1, 2].map(|a| self.slab(a, x[a] + width));
        let mut out = Vec::new();
        for cz in lo[2]..=hi[2] {
            for cy in lo[1]..=hi[1] {
                for cx in lo[0]..=hi[0] {
                    let r = self.rank_at([cx, cy, cz]);
                    if r != own && self.distance(r, x) < width {
                        out.push(r);
                    }
                }
            }
        }
        out.sort_unstable();
        out
    }

    /// Distance (m) from point x to rank r's sub-domain (0 inside).
    /// Edge sub-domains extend without bound past the box faces, as
    /// [`Self::owner`] gives them the points beyond.
    pub fn distance(&self, r: usize, x: [f64; 3]) -> f64 {
        let c = self.coords(r);
        let (lo, hi) = self.bounds(r);
        let mut d2 = 0.0;
        for a in 0..3 {
            let below = if c[a] == 0 { f64::NEG_INFINITY } else { lo[a] };
            let above = if c[a] + 1 == self.grid[a] {
                f64::INFINITY
            } else {
                hi[a]
            };
            let d = if x[a] < below {
                below - x[a]
            } else if x[a] > above {
                x[a] - above
            } else {
                0.0
            };
            d2 += d * d;
        }
        d2.sqrt()
    }
}

/// The grid for `ranks` sub-domains of a box of edge lengths `len`: of all
/// factorisations g₀ g₁ g₂ = ranks that split no periodic axis and keep
/// sub-domains at least `min_width` wide, the one of least total
/// sub-domain surface (the halo volume, hence the bytes exchanged; LAMMPS's
/// `procs2box` criterion). Falls back to the least surface without the
/// width condition (then [`Decomposition::new`] explains the refusal).
pub fn choose_grid(ranks: usize, len: [f64; 3], periodic: [bool; 3], min_width: f64) -> [usize; 3] {
    let mut best: Option<(bool, f64, [usize; 3])> = None;
    for gx in 1..=ranks {
        if !ranks.is_multiple_of(gx) {
            continue;
        }
        for gy in 1..=ranks / gx {
            if !(ranks / gx).is_multiple_of(gy) {
                continue;
            }
            let g = [gx, gy, ranks / gx / gy];
            if (0..3).any(|a| g[a] > 1 && periodic[a]) {
                continue;
            }
            let fits = (0..3).all(|a| g[a] == 1 || len[a] / g[a] as f64 >= min_width);
            let s = [len[0] / gx as f64, len[1] / gy as f64, len[2] / g[2] as f64];
            let surface = s[0] * s[1] + s[1] * s[2] + s[0] * s[2];
            let better = match best {
                None => true,
                Some((bf, bs, _)) => (fits && !bf) || (fits == bf && surface < bs),
            };
            if better {
                best = Some((fits, surface, g));
            }
        }
    }
    best.map_or([1, 1, ranks.max(1)], |b| b.2)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unit_box(periodic: [bool; 3]) -> Domain {
        Domain {
            lower: [0.0; 3],
            upper: [1.0, 1.0, 2.0],
            periodic,
        }
    }

    /// The lattice-drop box (24.6 × 24.6 × 30 mm): 2 and 3 ranks cut the
    /// longest axis (least surface), 8 a 2 × 2 × 2 grid (hand sums below).
    #[test]
    fn grid_of_least_surface() {
        let len = [0.0246, 0.0246, 0.03];
        assert_eq!(choose_grid(2, len, [false; 3], 1.1e-3), [1, 1, 2]);
        assert_eq!(choose_grid(3, len, [false; 3], 1.1e-3), [1, 1, 3]);
        // 8 ranks: 2 × 2 × 2 has 12.3² + 2 · 12.3 · 15 = 520.29 mm² per
        // sub-domain, 1 × 1 × 8 has 24.6² + 2 · 24.6 · 3.75 = 789.66 mm².
        assert_eq!(choose_grid(8, len, [false; 3], 1.1e-3), [2, 2, 2]);
        // A periodic z is never split.
        assert_eq!(choose_grid(2, len, [false, false, true], 1.1e-3)[2], 1);
        // Too thin to split z 64 ways at 1 mm: another grid.
        let g = choose_grid(64, len, [false; 3], 1.0e-3);
        assert!((0..3).all(|a| len[a] / g[a] as f64 >= 1.0e-3), "{g:?}");
    }

    #[test]
    fn owner_and_bounds_agree() {
        let d = Decomposition::new(unit_box([false; 3]), 6, Some([1, 2, 3]), 0.1, None).unwrap();
        for r in 0..6 {
            let (lo, hi) = d.bounds(r);
            let mid = [
                0.5 * (lo[0] + hi[0]),
                0.5 * (lo[1] + hi[1]),
                0.5 * (lo[2] + hi[2]),
            ];
            assert_eq!(d.owner(mid), r);
            // The lower corner belongs to r, the upper to the next.
            assert_eq!(d.owner(lo), r);
            assert_eq!(d.distance(r, mid), 0.0);
        }
        // Outside the box: the nearest edge sub-domain.
        assert_eq!(d.owner([0.5, -3.0, 5.0]), d.owner([0.5, 0.0, 1.99]));
        assert_eq!(d.owner([f64::NAN, f64::NAN, f64::NAN]), 0);
        // Rank 0 is y < 0.5, z < 2/3: a point at y = 0.6 is 0.1 away.
        let x = [0.5, 0.6, 0.1];
        assert!((d.distance(0, x) - 0.1).abs() < 1e-15);
        // Its owner is rank 1 (y ≥ 0.5, z < 2/3); within 0.15 of it:
        // rank 0 only; within 0.6: also rank 3 (z ≥ 2/3, 0.5667 away) and
        // rank 2 (y < 0.5, z ≥ 2/3: √(0.1² + 0.5667²) = 0.575 away).
        assert_eq!(d.owner(x), 1);
        assert_eq!(d.ranks_within(x, 0.15), vec![0]);
        assert_eq!(d.ranks_within(x, 0.6), vec![0, 2, 3]);
        assert_eq!(d.ranks_within(x, 0.57), vec![0, 3]);
    }

    #[test]
    fn bad_grids_are_refused() {
        let err = |g| Decomposition::new(unit_box([false; 3]), 4, Some(g), 0.1, None).unwrap_err();
        assert!(err([1, 1, 3]).to_string().contains("parallel.grid"));
        assert!(err([0, 2, 2]).to_string().contains("product"));
        // Sub-domains 1/40 wide, narrower than 0.1: allowed, a body's
        // copies then reach further than the next sub-domain (x = 0.5 is
        // owned by slab 20, [0.5, 0.525); within 0.06 are slabs 17–19,
        // 0.05, 0.025 and 0 away, and 21, 22, 0.025 and 0.05 away).
        let d = Decomposition::new(unit_box([false; 3]), 40, Some([40, 1, 1]), 0.1, None).unwrap();
        assert_eq!(
            d.ranks_within([0.5, 0.5, 0.5], 0.06),
            vec![17, 18, 19, 21, 22]
        );
        let e = Decomposition::new(
            unit_box([true, false, false]),
            2,
            Some([2, 1, 1]),
            0.1,
            None,
        )
        .unwrap_err();
        assert!(e.to_string().contains("periodic"), "{e}");
    }

    /// Moved cuts: owner, bounds and the halo follow them; bad cuts are
    /// refused and change nothing.
    #[test]
    fn moved_cuts() {
        let mut d =
            Decomposition::new(unit_box([false; 3]), 3, Some([1, 1, 3]), 0.01, None).unwrap();
        assert_eq!(d.cuts(2), &[0.0, 2.0 / 3.0, 4.0 / 3.0, 2.0]);
        assert!(d.set_cuts(2, &[0.1, 0.3]));
        assert_eq!(d.cuts(2), &[0.0, 0.1, 0.3, 2.0]);
        assert_eq!(d.owner([0.5, 0.5, 0.05]), 0);
        assert_eq!(d.owner([0.5, 0.5, 0.1]), 1);
        assert_eq!(d.owner([0.5, 0.5, 0.29]), 1);
        assert_eq!(d.owner([0.5, 0.5, 1.5]), 2);
        assert_eq!(d.bounds(1), ([0.0, 0.0, 0.1], [1.0, 1.0, 0.3]));
        // 0.25 reaches both neighbours of the middle slab (0.15 and 0.05
        // away), 0.1 only the upper one.
        assert_eq!(d.ranks_within([0.5, 0.5, 0.25], 0.16), vec![0, 2]);
        assert_eq!(d.ranks_within([0.5, 0.5, 0.25], 0.1), vec![2]);
        // An empty middle slab; a cut below the region widens it.
        assert!(d.set_cuts(2, &[-0.5, -0.5]));
        assert_eq!(d.cuts(2), &[-0.5, -0.5, -0.5, 2.0]);
        assert_eq!(d.owner([0.5, 0.5, -0.5]), 2);
        assert_eq!(d.owner([0.5, 0.5, -0.6]), 0);
        for bad in [&[0.3, 0.1][..], &[0.1][..], &[0.1, f64::NAN][..]] {
            assert!(!d.set_cuts(2, bad));
        }
        assert_eq!(d.cuts(2), &[-0.5, -0.5, -0.5, 2.0]);
    }

    /// A bed in the bottom tenth of a tall box: cut where the bodies are.
    #[test]
    fn cuts_follow_the_bodies() {
        let extent = Some(([0.0, 0.0, 0.0], [1.0, 1.0, 0.2]));
        let d = Decomposition::new(unit_box([false; 3]), 2, None, 0.01, extent).unwrap();
        // 1 × 1 × 0.2: halving x or y leaves 0.5·1 + 1·0.2 + 0.5·0.2 = 0.8,
        // halving z 1 + 2·0.1 = 1.2.
        assert_eq!(d.grid, [2, 1, 1]);
        assert_eq!(d.bounds(0).1[0], 0.5);
        assert_eq!(d.owner([0.7, 0.5, 1.9]), 1);
    }
}
