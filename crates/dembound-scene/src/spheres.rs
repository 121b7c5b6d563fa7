//! The list of all spheres of a scene ([`crate::setup::SceneSetup::spheres`]):
//! spheres in input order, read by value. A lattice group is kept as its
//! formula ([`Lattice`] and the group's velocity, material, fixed flag and
//! wall), each sphere made when read, so that a scene of 10⁷ lattice spheres
//! never holds a list of them besides the engine's arrays (issue 31 item 4).
//! Every other source (random, CSV, data files, inline lists, walls) is
//! listed sphere by sphere.

use crate::setup::SphereInit;
use crate::sources::lattice::Lattice;

/// A lattice group of spheres: the lattice's sites in its order
/// ([`Lattice::site`]), each with the same velocity, material, fixed flag
/// and wall.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LatticeRun {
    /// The sites.
    pub lattice: Lattice,
    /// Every sphere's velocity, m/s.
    pub velocity: [f64; 3],
    /// Index into [`crate::setup::SceneSetup::materials`].
    pub material: usize,
    /// Fixed spheres (boundary particles).
    pub fixed: bool,
    /// The wall the spheres belong to, if any.
    pub group: Option<usize>,
}

impl LatticeRun {
    /// Sphere `q` of the run (q < the lattice's length).
    fn sphere(&self, q: usize) -> SphereInit {
        let site = self.lattice.site(q);
        SphereInit {
            position: site.position,
            velocity: self.velocity,
            radius: site.radius,
            material: self.material,
            fixed: self.fixed,
            group: self.group,
        }
    }
}

/// Consecutive spheres of the list: listed ones, or a lattice's.
#[derive(Debug, Clone, PartialEq)]
enum Run {
    Listed(Vec<SphereInit>),
    Lattice(LatticeRun),
}

impl Run {
    fn len(&self) -> usize {
        match self {
            Run::Listed(v) => v.len(),
            Run::Lattice(l) => l.lattice.len(),
        }
    }

    /// Sphere `q` of the run (q < its length).
    fn sphere(&self, q: usize) -> SphereInit {
        match self {
            Run::Listed(v) => v[q],
            Run::Lattice(l) => l.sphere(q),
        }
    }
}

/// All spheres of a scene, free and fixed, in input order.
#[derive(Debug, Clone, Default)]
pub struct Spheres {
    /// The runs in input order (an empty one holds no input index).
    runs: Vec<Run>,
    /// The input index of each run's first sphere, then the total:
    /// `runs.len() + 1` entries (one, 0, when there are no runs).
    starts: Vec<usize>,
}

impl Spheres {
    /// No spheres.
    pub fn new() -> Self {
        Self::default()
    }

    /// The number of spheres.
    pub fn len(&self) -> usize {
        self.starts.last().copied().unwrap_or(0)
    }

    /// No spheres at all.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The spheres in input order, by value.
    pub fn iter(&self) -> Iter<'_> {
        Iter {
            spheres: self,
            run: 0,
            next: 0,
            end: self.len(),
        }
    }

    /// Sphere `k`, or `None` past the end.
    pub fn get(&self, k: usize) -> Option<SphereInit> {
        if k >= self.len() {
            return None;
        }
        // The last run starting at or before k.
        let r = self.starts.partition_point(|&s| s <= k) - 1;
        Some(self.runs[r].sphere(k - self.starts[r]))
    }

    /// Spheres `range` in input order, or `None` if the range runs past the
    /// end or is reversed.
    pub fn range(&self, range: std::ops::Range<usize>) -> Option<Iter<'_>> {
        if range.start > range.end || range.end > self.len() {
            return None;
        }
        let run = self.starts.partition_point(|&s| s <= range.start);
        Some(Iter {
            spheres: self,
            run: run.saturating_sub(1),
            next: range.start,
            end: range.end,
        })
    }

    /// Append the spheres of a lattice (held as its formula, not listed).
    pub fn push_lattice(&mut self, run: LatticeRun) {
        if run.lattice.is_empty() {
            return;
        }
        self.start_run();
        // An empty trailing listed run (room reserved for listed spheres)
        // moves after the lattice, for the spheres listed next.
        let reserved = match self.runs.last() {
            Some(Run::Listed(v)) if v.is_empty() => {
                self.starts.pop();
                self.runs.pop()
            }
            _ => None,
        };
        let end = self.len() + run.lattice.len();
        self.runs.push(Run::Lattice(run));
        self.starts.push(end);
        if let Some(r) = reserved {
            self.runs.push(r);
            self.starts.push(end);
        }
    }

    /// Append a sphere.
    pub fn push(&mut self, sphere: SphereInit) {
        self.listed_tail().push(sphere);
        self.close_tail();
    }

    /// Put `sphere` at input index `k` (0 ≤ k ≤ len), moving later ones on.
    pub fn insert(&mut self, k: usize, sphere: SphereInit) {
        self.listed().insert(k, sphere);
        self.close_tail();
    }

    /// Keep the first `len` spheres.
    pub fn truncate(&mut self, len: usize) {
        if len >= self.len() {
            return;
        }
        // The runs wholly below `len` stay as they are; the one holding
        // sphere `len` is cut (a lattice's listed first).
        let r = self.starts.partition_point(|&s| s <= len) - 1;
        let keep = len - self.starts[r];
        self.runs.truncate(r + 1);
        // Run r's start, and those before it.
        self.starts.truncate(r + 1);
        let cut = match self.runs.pop() {
            Some(Run::Listed(mut v)) => {
                v.truncate(keep);
                v
            }
            Some(Run::Lattice(l)) => (0..keep).map(|q| l.sphere(q)).collect(),
            None => Vec::new(),
        };
        if cut.is_empty() {
            // Run r (now gone) started at `len`: that start is the total.
        } else {
            self.runs.push(Run::Listed(cut));
            self.starts.push(len);
        }
    }

    /// Remove every sphere.
    pub fn clear(&mut self) {
        self.runs.clear();
        self.starts.clear();
    }

    /// Room for `additional` more listed spheres.
    pub fn reserve(&mut self, additional: usize) {
        self.listed_tail().reserve(additional);
        self.close_tail();
    }

    /// Room for `additional` more listed spheres, or the allocator's error.
    pub fn try_reserve(
        &mut self,
        additional: usize,
    ) -> Result<(), std::collections::TryReserveError> {
        let r = self.listed_tail().try_reserve(additional);
        self.close_tail();
        r
    }

    /// The last sphere for editing, if any (every sphere listed first).
    pub fn last_mut(&mut self) -> Option<&mut SphereInit> {
        self.listed().last_mut()
    }

    /// Sphere `k` for editing (every sphere listed first).
    pub fn get_mut(&mut self, k: usize) -> Option<&mut SphereInit> {
        self.listed().get_mut(k)
    }

    /// Every sphere for editing, in input order (every sphere listed first).
    pub fn iter_mut(&mut self) -> std::slice::IterMut<'_, SphereInit> {
        self.listed().iter_mut()
    }

    /// The spheres as one list, in input order.
    pub fn to_vec(&self) -> Vec<SphereInit> {
        self.iter().collect()
    }

    /// `starts` holds its leading 0 (a list with no run yet).
    fn start_run(&mut self) {
        if self.starts.is_empty() {
            self.starts.push(0);
        }
    }

    /// The trailing listed run (made if the last run is a lattice or there
    /// is none); [`Self::close_tail`] afterwards restores `starts`.
    fn listed_tail(&mut self) -> &mut Vec<SphereInit> {
        self.start_run();
        if !matches!(self.runs.last(), Some(Run::Listed(_))) {
            let end = self.len();
            self.runs.push(Run::Listed(Vec::new()));
            self.starts.push(end);
        }
        match self.runs.last_mut() {
            Some(Run::Listed(v)) => v,
            _ => unreachable!("a listed run was just pushed"),
        }
    }

    /// After an edit of the trailing listed run: its end is the total.
    fn close_tail(&mut self) {
        let n = self.runs.len();
        let Some(last) = self.runs.last().map(Run::len) else {
            return;
        };
        self.starts[n] = self.starts[n - 1] + last;
    }

    /// Every sphere listed, as one run (lattices made sphere by sphere);
    /// callers that change the length call [`Self::close_tail`] after.
    fn listed(&mut self) -> &mut Vec<SphereInit> {
        if !(self.runs.len() == 1 && matches!(self.runs[0], Run::Listed(_))) {
            let all = self.to_vec();
            self.starts = vec![0, all.len()];
            self.runs = vec![Run::Listed(all)];
        }
        match &mut self.runs[0] {
            Run::Listed(v) => v,
            Run::Lattice(_) => unreachable!("the runs were just listed"),
        }
    }
}

/// The spheres of a [`Spheres`] (or of a range of it) in input order.
#[derive(Debug, Clone)]
pub struct Iter<'a> {
    spheres: &'a Spheres,
    /// The run holding sphere `next` (when next < end).
    run: usize,
    /// The next sphere's input index.
    next: usize,
    /// One past the last sphere.
    end: usize,
}

impl Iterator for Iter<'_> {
    type Item = SphereInit;

    fn next(&mut self) -> Option<SphereInit> {
        if self.next >= self.end {
            return None;
        }
        let s = &self.spheres.starts;
        while s[self.run + 1] <= self.next {
            self.run += 1;
        }
        let sphere = self.spheres.runs[self.run].sphere(self.next - s[self.run]);
        self.next += 1;
        Some(sphere)
    }

    fn size_hint(&self) -> (usize, Option<usize>) {
        let n = self.end - self.next;
        (n, Some(n))
    }
}

impl ExactSizeIterator for Iter<'_> {}

impl PartialEq for Spheres {
    /// Sphere by sphere: a lattice equals its spheres listed.
    fn eq(&self, other: &Self) -> bool {
        self.len() == other.len() && self.iter().eq(other.iter())
    }
}

impl From<Vec<SphereInit>> for Spheres {
    fn from(listed: Vec<SphereInit>) -> Self {
        let mut s = Self::new();
        s.extend(listed);
        s
    }
}

impl FromIterator<SphereInit> for Spheres {
    fn from_iter<I: IntoIterator<Item = SphereInit>>(iter: I) -> Self {
        Self::from(iter.into_iter().collect::<Vec<_>>())
    }
}

impl Extend<SphereInit> for Spheres {
    fn extend<I: IntoIterator<Item = SphereInit>>(&mut self, iter: I) {
        self.listed_tail().extend(iter);
        self.close_tail();
    }
}

impl<'a> IntoIterator for &'a Spheres {
    type Item = SphereInit;
    type IntoIter = Iter<'a>;
    fn into_iter(self) -> Self::IntoIter {
        self.iter()
    }
}

impl<'a> IntoIterator for &'a mut Spheres {
    type Item = &'a mut SphereInit;
    type IntoIter = std::slice::IterMut<'a, SphereInit>;
    fn into_iter(self) -> Self::IntoIter {
        self.iter_mut()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A listed sphere with distinct fields (`k` makes it unique).
    fn listed(k: usize) -> SphereInit {
        SphereInit {
            position: [k as f64, 0.5 * k as f64, -(k as f64)],
            velocity: [0.1, 0.0, k as f64],
            radius: 0.25 + k as f64 * 1e-3,
            material: k % 3,
            fixed: k.is_multiple_of(2),
            group: k.is_multiple_of(4).then_some(k),
        }
    }

    fn lattice(counts: [usize; 3], stagger: bool) -> LatticeRun {
        LatticeRun {
            lattice: Lattice {
                counts,
                spacing: [1.2e-3, 1.3e-3, 0.54e-3],
                origin: [0.6e-3, 0.65e-3, 0.505e-3],
                radius: 0.5e-3,
                stagger,
            },
            velocity: [0.2, -0.1, -0.3],
            material: 2,
            fixed: true,
            group: Some(1),
        }
    }

    /// The run's spheres written out by hand: layer k outer, row j, column
    /// i inner; x = x0 + i a + s, y = y0 + j b + s', z = z0 + k c, odd
    /// layers shifted by half a cell when staggered (make_lattice.py).
    fn by_hand(run: &LatticeRun) -> Vec<SphereInit> {
        let l = &run.lattice;
        let [nx, ny, nz] = l.counts;
        let [a, b, c] = l.spacing;
        let mut out = Vec::new();
        for k in 0..nz {
            let odd = if l.stagger && k % 2 == 1 { 1.0 } else { 0.0 };
            for j in 0..ny {
                for i in 0..nx {
                    out.push(SphereInit {
                        position: [
                            l.origin[0] + i as f64 * a + 0.5 * a * odd,
                            l.origin[1] + j as f64 * b + 0.5 * b * odd,
                            l.origin[2] + k as f64 * c,
                        ],
                        velocity: run.velocity,
                        radius: l.radius,
                        material: run.material,
                        fixed: run.fixed,
                        group: run.group,
                    });
                }
            }
        }
        out
    }

    /// Every field's bits (f64 `==` would let -0.0 and 0.0 pass).
    fn bits(s: SphereInit) -> ([u64; 7], usize, bool, Option<usize>) {
        let p = s.position.map(f64::to_bits);
        let v = s.velocity.map(f64::to_bits);
        (
            [p[0], p[1], p[2], v[0], v[1], v[2], s.radius.to_bits()],
            s.material,
            s.fixed,
            s.group,
        )
    }

    fn same_bits(a: impl IntoIterator<Item = SphereInit>, b: &[SphereInit]) {
        let a: Vec<_> = a.into_iter().map(bits).collect();
        let b: Vec<_> = b.iter().copied().map(bits).collect();
        assert_eq!(a, b);
    }

    #[test]
    fn a_lattice_run_is_its_spheres_listed_bit_for_bit() {
        for stagger in [true, false] {
            for counts in [[3, 5, 7], [1, 1, 1], [4, 2, 3], [5, 1, 2]] {
                let run = lattice(counts, stagger);
                let mut s = Spheres::new();
                s.push_lattice(run);
                let expected = by_hand(&run);
                assert_eq!(s.len(), counts.iter().product::<usize>());
                same_bits(s.iter(), &expected);
                // By index too.
                same_bits((0..s.len()).map(|k| s.get(k).expect("k < len")), &expected);
            }
        }
    }

    /// Listed, lattice, listed, lattice, listed: the reference is the
    /// concatenation of the parts.
    fn mixed() -> (Spheres, Vec<SphereInit>) {
        let (a, b) = (lattice([3, 2, 3], true), lattice([2, 3, 1], false));
        let mut s = Spheres::new();
        let mut reference = Vec::new();
        s.extend((0..4).map(listed));
        reference.extend((0..4).map(listed));
        s.push_lattice(a);
        reference.extend(by_hand(&a));
        s.push(listed(4));
        s.push(listed(5));
        reference.extend([listed(4), listed(5)]);
        s.push_lattice(b);
        reference.extend(by_hand(&b));
        s.push(listed(6));
        reference.push(listed(6));
        (s, reference)
    }

    #[test]
    fn get_and_range_across_run_boundaries() {
        let (s, reference) = mixed();
        assert_eq!(s.len(), reference.len());
        same_bits(s.iter(), &reference);
        for k in 0..reference.len() {
            same_bits(s.get(k), &reference[k..=k]);
        }
        assert!(s.get(reference.len()).is_none());
        for start in 0..=reference.len() {
            for end in start..=reference.len() {
                let r = s.range(start..end).expect("within the list");
                assert_eq!(r.len(), end - start);
                same_bits(r, &reference[start..end]);
            }
        }
        assert!(s.range(0..reference.len() + 1).is_none());
        // A reversed range.
        let (start, end) = (3, 2);
        assert!(s.range(start..end).is_none());
    }

    #[test]
    fn truncate_and_edit_keep_the_order() {
        let (s, reference) = mixed();
        // Cut inside the first lattice, at its end, inside the listed run.
        for len in [0, 3, 4, 9, 22, 23, 24, reference.len()] {
            let mut t = s.clone();
            t.truncate(len);
            assert_eq!(t.len(), len);
            same_bits(t.iter(), &reference[..len]);
            t.push(listed(9));
            same_bits(t.iter().last(), &[listed(9)]);
            assert_eq!(t.len(), len + 1);
        }
        let mut t = s.clone();
        t.get_mut(10).expect("k < len").radius = 9.0;
        let mut edited = reference.clone();
        edited[10].radius = 9.0;
        same_bits(t.iter(), &edited);
        assert_eq!(Spheres::from(reference), s);
    }

    #[test]
    fn room_reserved_before_a_lattice_serves_the_spheres_after_it() {
        let mut s = Spheres::new();
        s.try_reserve(3).expect("three spheres fit");
        let run = lattice([2, 2, 2], true);
        s.push_lattice(run);
        s.extend((0..3).map(listed));
        let mut reference = by_hand(&run);
        reference.extend((0..3).map(listed));
        same_bits(s.iter(), &reference);
        same_bits(s.range(6..10).expect("within"), &reference[6..10]);
    }
}
