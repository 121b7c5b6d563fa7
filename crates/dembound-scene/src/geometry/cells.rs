//! Linked cells: a grid of cubes at least one interaction range wide, and
//! bodies sorted by cell (a counting sort, stable: deterministic).

/// A grid over a box; points outside are clamped into the edge cells
/// (a neighbour search stays correct, only slower, for strays).
///
/// A grid may be a crop of a larger one ([`CellGrid::crop`]): the cells
/// are the same (same origin and size, coordinates computed on the whole
/// grid, then shifted by an integer offset), so a body falls in the same
/// cell of the whole grid whatever part of it a process holds: the cell
/// order is the same on every rank of a domain decomposition.
#[derive(Debug, Clone, Default)]
pub struct CellGrid {
    pub origin: [f64; 3],
    pub inverse_size: [f64; 3],
    pub dims: [usize; 3],
    /// The crop's first cell in the whole grid (0 when not cropped).
    pub offset: [usize; 3],
    /// The whole grid's dimensions (`dims` when not cropped).
    pub whole: [usize; 3],
}

impl CellGrid {
    /// Cells of edge ≥ `min_size` over [lower, upper], at most about
    /// `max_cells` of them (the cells grow when the box is large).
    pub fn new(lower: [f64; 3], upper: [f64; 3], min_size: f64, max_cells: usize) -> Self {
        let mut size = min_size;
        loop {
            let mut dims = [1usize; 3];
            for a in 0..3 {
                let len = (upper[a] - lower[a]).max(0.0);
                dims[a] = ((len / size).floor() as usize).max(1);
            }
            let total = dims[0].saturating_mul(dims[1]).saturating_mul(dims[2]);
            if total <= max_cells.max(1) {
                let mut inverse_size = [0.0; 3];
                for a in 0..3 {
                    let len = (upper[a] - lower[a]).max(0.0);
                    inverse_size[a] = if len > 0.0 { dims[a] as f64 / len } else { 0.0 };
                }
                return Self {
                    origin: lower,
                    inverse_size,
                    dims,
                    offset: [0; 3],
                    whole: dims,
                };
            }
            size *= 1.25;
        }
    }

    pub fn count(&self) -> usize {
        self.dims[0] * self.dims[1] * self.dims[2]
    }

    /// Cell coordinates of `x` in the whole grid, clamped into it.
    #[inline]
    pub fn whole_coords(&self, x: [f64; 3]) -> [usize; 3] {
        let mut c = [0usize; 3];
        for a in 0..3 {
            let f = ((x[a] - self.origin[a]) * self.inverse_size[a]).floor();
            // NaN and negatives go to 0.
            c[a] = if f > 0.0 {
                (f as usize).min(self.whole[a] - 1)
            } else {
                0
            };
        }
        c
    }

    /// Cell coordinates of `x`, clamped into the grid (the crop).
    #[inline]
    pub fn coords(&self, x: [f64; 3]) -> [usize; 3] {
        let mut c = self.whole_coords(x);
        for ((c, offset), dims) in c.iter_mut().zip(self.offset).zip(self.dims) {
            *c = c.saturating_sub(offset).min(dims - 1);
        }
        c
    }

    /// The cells `lower..=upper` (whole-grid coordinates, clamped into
    /// it) of this grid, as a grid of their own with the same cells.
    pub fn crop(&self, lower: [usize; 3], upper: [usize; 3]) -> Self {
        let mut g = self.clone();
        for a in 0..3 {
            let hi = upper[a].min(self.whole[a] - 1);
            let lo = lower[a].min(hi);
            g.offset[a] = lo;
            g.dims[a] = hi - lo + 1;
        }
        g
    }

    #[inline]
    pub fn index(&self, c: [usize; 3]) -> usize {
        (c[2] * self.dims[1] + c[1]) * self.dims[0] + c[0]
    }
}

/// Counting sort of bodies by cell (`cell[k]` ≤ `cells`, the value `cells`
/// being a bucket after all cells). Returns the order (new k ← old
/// `order[k]`) and the start of each cell in the new order (`cells + 2`
/// entries).
pub fn sort_by_cell(cell: &[u32], cells: usize) -> (Vec<u32>, Vec<u32>) {
    let mut start = vec![0u32; cells + 2];
    for &c in cell {
        start[c as usize + 1] += 1;
    }
    for k in 1..start.len() {
        start[k] += start[k - 1];
    }
    let mut next = start.clone();
    let mut order = vec![0u32; cell.len()];
    for (old, &c) in cell.iter().enumerate() {
        let slot = &mut next[c as usize];
        order[*slot as usize] = old as u32;
        *slot += 1;
    }
    (order, start)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sort_is_stable_and_complete() {
        let (order, start) = sort_by_cell(&[2, 0, 2, 1, 0, 3], 3);
        assert_eq!(order, vec![1, 4, 3, 0, 2, 5]);
        assert_eq!(start, vec![0, 2, 3, 5, 6]);
    }

    #[test]
    fn grid_clamps_and_caps() {
        let g = CellGrid::new([0.0; 3], [1.0, 1.0, 1.0], 0.1, 1000);
        assert_eq!(g.dims, [10, 10, 10]);
        assert_eq!(g.coords([-5.0, 0.55, 7.0]), [0, 5, 9]);
        let capped = CellGrid::new([0.0; 3], [1.0, 1.0, 1.0], 0.01, 1000);
        assert!(capped.count() <= 1000);
    }

    #[test]
    fn a_crop_keeps_the_cells_and_their_order() {
        let g = CellGrid::new([0.0; 3], [1.0, 1.0, 1.0], 0.1, 1000);
        let c = g.crop([2, 3, 4], [5, 3, 9]);
        assert_eq!(c.dims, [4, 1, 6]);
        // A point's cell is the whole grid's, shifted (no float rounding
        // of a shifted origin can move it across a face).
        for x in [[0.25, 0.35, 0.45], [0.5, 0.3, 0.9999], [0.2, 0.3, 0.4]] {
            let (w, k) = (g.coords(x), c.coords(x));
            assert_eq!([k[0] + 2, k[1] + 3, k[2] + 4], w);
        }
        // The crop's linear order is the whole grid's order restricted.
        let mut last = None;
        for z in 4..=9 {
            for y in 3..=3 {
                for x in 2..=5 {
                    let (whole, crop) = (g.index([x, y, z]), c.index([x - 2, y - 3, z - 4]));
                    if let Some((w0, c0)) = last {
                        assert!(whole > w0 && crop > c0);
                    }
                    last = Some((whole, crop));
                }
            }
        }
    }
}
