//! The list of all spheres of a scene ([`crate::setup::SceneSetup::spheres`]):
//! spheres in input order, read by value. Kept behind its own type so that
//! a generated source (a lattice) can later be stored as its formula rather
//! than as one [`SphereInit`] per sphere (issue 31 item 4).

use crate::setup::SphereInit;

/// All spheres of a scene, free and fixed, in input order.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Spheres {
    listed: Vec<SphereInit>,
}

impl Spheres {
    /// No spheres.
    pub fn new() -> Self {
        Self::default()
    }

    /// The number of spheres.
    pub fn len(&self) -> usize {
        self.listed.len()
    }

    /// No spheres at all.
    pub fn is_empty(&self) -> bool {
        self.listed.is_empty()
    }

    /// The spheres in input order, by value.
    pub fn iter(&self) -> impl ExactSizeIterator<Item = SphereInit> + Clone + '_ {
        self.listed.iter().copied()
    }

    /// Sphere `k`, or `None` past the end.
    pub fn get(&self, k: usize) -> Option<SphereInit> {
        self.listed.get(k).copied()
    }

    /// Spheres `range` in input order, or `None` if the range runs past the end.
    pub fn range(
        &self,
        range: std::ops::Range<usize>,
    ) -> Option<impl ExactSizeIterator<Item = SphereInit> + '_> {
        self.listed.get(range).map(|s| s.iter().copied())
    }

    /// Append a sphere.
    pub fn push(&mut self, sphere: SphereInit) {
        self.listed.push(sphere);
    }

    /// Put `sphere` at input index `k` (0 ≤ k ≤ len), moving later ones on.
    pub fn insert(&mut self, k: usize, sphere: SphereInit) {
        self.listed.insert(k, sphere);
    }

    /// Keep the first `len` spheres.
    pub fn truncate(&mut self, len: usize) {
        self.listed.truncate(len);
    }

    /// Remove every sphere.
    pub fn clear(&mut self) {
        self.listed.clear();
    }

    /// Room for `additional` more spheres.
    pub fn reserve(&mut self, additional: usize) {
        self.listed.reserve(additional);
    }

    /// The last sphere, if any.
    pub fn last_mut(&mut self) -> Option<&mut SphereInit> {
        self.listed.last_mut()
    }

    /// Sphere `k` for editing (a listed sphere).
    pub fn get_mut(&mut self, k: usize) -> Option<&mut SphereInit> {
        self.listed.get_mut(k)
    }

    /// Every sphere for editing, in input order.
    pub fn iter_mut(&mut self) -> impl Iterator<Item = &mut SphereInit> {
        self.listed.iter_mut()
    }

    /// The spheres as one list, in input order.
    pub fn to_vec(&self) -> Vec<SphereInit> {
        self.listed.clone()
    }
}

impl From<Vec<SphereInit>> for Spheres {
    fn from(listed: Vec<SphereInit>) -> Self {
        Self { listed }
    }
}

impl FromIterator<SphereInit> for Spheres {
    fn from_iter<I: IntoIterator<Item = SphereInit>>(iter: I) -> Self {
        Self {
            listed: iter.into_iter().collect(),
        }
    }
}

impl Extend<SphereInit> for Spheres {
    fn extend<I: IntoIterator<Item = SphereInit>>(&mut self, iter: I) {
        self.listed.extend(iter);
    }
}

impl<'a> IntoIterator for &'a Spheres {
    type Item = SphereInit;
    type IntoIter = std::iter::Copied<std::slice::Iter<'a, SphereInit>>;
    fn into_iter(self) -> Self::IntoIter {
        self.listed.iter().copied()
    }
}

impl<'a> IntoIterator for &'a mut Spheres {
    type Item = &'a mut SphereInit;
    type IntoIter = std::slice::IterMut<'a, SphereInit>;
    fn into_iter(self) -> Self::IntoIter {
        self.listed.iter_mut()
    }
}
