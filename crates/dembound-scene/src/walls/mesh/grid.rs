//! A uniform grid over the mesh's bounding box: each triangle listed in
//! every cell its bounding box (grown by a pad) overlaps; a query visits
//! the cells a box overlaps.
//!
//! Cell size: the mean over triangles of their bounding box's largest
//! side (so a triangle overlaps a few cells), grown until the cell count
//! is at most 2 × triangles + 64 (a surface mesh fills few cells of its
//! box; the cap keeps the cell table within 8 bytes per triangle).
//! Storage: compressed rows, a u32 start per cell and a u32 triangle index
//! per (cell, triangle) overlap.

#[derive(Debug, Clone, PartialEq)]
pub struct Grid {
    /// Lower corner, m.
    pub lo: [f64; 3],
    /// Cell side, m.
    pub cell: f64,
    /// Cells along each axis.
    pub dims: [usize; 3],
    /// Triangles of cell c: `items[start[c]..start[c + 1]]`.
    pub start: Vec<u32>,
    pub items: Vec<u32>,
}

impl Grid {
    /// A grid of the triangles' boxes (`boxes[t]` = (lo, hi)), each grown
    /// by `pad` (m) on every side; in each cell the triangles are ordered
    /// by `group[t]` (their patch), then index.
    pub fn build(boxes: &[([f64; 3], [f64; 3])], group: &[u32], pad: f64) -> Grid {
        let mut lo = [f64::INFINITY; 3];
        let mut hi = [f64::NEG_INFINITY; 3];
        let mut mean = 0.0;
        for (a, b) in boxes {
            for k in 0..3 {
                lo[k] = lo[k].min(a[k] - pad);
                hi[k] = hi[k].max(b[k] + pad);
            }
            mean += (0..3).map(|k| b[k] - a[k]).fold(0.0, f64::max);
        }
        let n = boxes.len().max(1);
        mean /= n as f64;
        let extent = [0, 1, 2].map(|k| (hi[k] - lo[k]).max(0.0));
        let largest = extent.iter().cloned().fold(0.0, f64::max);
        let mut cell = mean.max(largest * 1e-6).max(f64::MIN_POSITIVE);
        let cap = (2 * n + 64) as f64;
        let count =
            |cell: f64| -> f64 { extent.iter().map(|e| (e / cell).floor() + 1.0).product() };
        while count(cell) > cap {
            cell *= (count(cell) / cap).cbrt().max(1.01);
        }
        let dims = extent.map(|e| (e / cell).floor() as usize + 1);
        let mut grid = Grid {
            lo,
            cell,
            dims,
            start: Vec::new(),
            items: Vec::new(),
        };
        let cells = dims[0] * dims[1] * dims[2];
        let mut counts = vec![0u32; cells + 1];
        let ranges: Vec<Option<[[usize; 2]; 3]>> = boxes
            .iter()
            .map(|(a, b)| grid.range(a.map(|c| c - pad), b.map(|c| c + pad)))
            .collect();
        for r in ranges.iter().flatten() {
            grid.each_cell(r, |c| counts[c + 1] += 1);
        }
        for c in 0..cells {
            counts[c + 1] += counts[c];
        }
        let mut fill = counts.clone();
        let mut items = vec![0u32; counts[cells] as usize];
        for (t, r) in ranges.iter().enumerate() {
            if let Some(r) = r {
                grid.each_cell(r, |c| {
                    items[fill[c] as usize] = t as u32;
                    fill[c] += 1;
                });
            }
        }
        for c in 0..cells {
            items[counts[c] as usize..counts[c + 1] as usize]
                .sort_unstable_by_key(|&t| (group.get(t as usize).copied().unwrap_or(0), t));
        }
        grid.start = counts;
        grid.items = items;
        grid
    }

    /// The cell index range [first, last] per axis of the box (a, b), or
    /// None if it misses the grid (or is not a number). Truncation, not
    /// `floor` (a library call on the baseline x86-64 target): the
    /// coordinates are clamped at 0 first, where both agree.
    #[inline]
    pub fn range(&self, a: [f64; 3], b: [f64; 3]) -> Option<[[usize; 2]; 3]> {
        let mut r = [[0usize; 2]; 3];
        for k in 0..3 {
            let i = (a[k] - self.lo[k]) / self.cell;
            let j = (b[k] - self.lo[k]) / self.cell;
            let top = self.dims[k] - 1;
            // `!(x >= y)` also refuses NaN.
            if !(j >= 0.0 && i < (top + 1) as f64) {
                return None;
            }
            r[k] = [(i.max(0.0) as usize).min(top), (j as usize).min(top)];
        }
        Some(r)
    }

    /// Calls `f` with each cell index of the range.
    #[inline]
    pub fn each_cell(&self, r: &[[usize; 2]; 3], mut f: impl FnMut(usize)) {
        for i in r[0][0]..=r[0][1] {
            for j in r[1][0]..=r[1][1] {
                for k in r[2][0]..=r[2][1] {
                    f((i * self.dims[1] + j) * self.dims[2] + k);
                }
            }
        }
    }

    /// The triangles of cell c.
    #[inline]
    pub fn cell_items(&self, c: usize) -> &[u32] {
        &self.items[self.start[c] as usize..self.start[c + 1] as usize]
    }

    /// Does the range cover every cell?
    pub fn covers_all(&self, r: &[[usize; 2]; 3]) -> bool {
        (0..3).all(|k| r[k][0] == 0 && r[k][1] == self.dims[k] - 1)
    }

    /// Bytes held.
    pub fn bytes(&self) -> usize {
        4 * (self.start.capacity() + self.items.capacity())
    }
}
