//! Linked cells: a grid of cubes at least one interaction range wide, and
//! bodies sorted by cell (a counting sort, stable: deterministic).

/// A grid over a box; points outside are clamped into the edge cells
/// (a neighbour search stays correct, only slower, for strays).
#[derive(Debug, Clone, Default)]
pub struct CellGrid {
    pub origin: [f64; 3],
    pub inverse_size: [f64; 3],
    pub dims: [usize; 3],
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
                };
            }
            size *= 1.25;
        }
    }

    pub fn count(&self) -> usize {
        self.dims[0] * self.dims[1] * self.dims[2]
    }

    /// Cell coordinates of `x`, clamped into the grid.
    #[inline]
    pub fn coords(&self, x: [f64; 3]) -> [usize; 3] {
        let mut c = [0usize; 3];
        for a in 0..3 {
            let f = ((x[a] - self.origin[a]) * self.inverse_size[a]).floor();
            // NaN and negatives go to 0.
            c[a] = if f > 0.0 {
                (f as usize).min(self.dims[a] - 1)
            } else {
                0
            };
        }
        c
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
}
