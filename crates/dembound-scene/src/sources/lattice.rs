//! A lattice of equal spheres: square layers stacked along z, odd layers
//! shifted by half a cell in x and y so that their spheres sit above the
//! hollows of the layer below (the lattice-drop benchmark's initial state,
//! `peers/lattice-drop/make_lattice.py`).

use super::SourceSphere;
use crate::SceneError;

/// The lattice: `counts[0] × counts[1]` spheres per layer, `counts[2]`
/// layers.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Lattice {
    /// Spheres along x and y in a layer, and the number of layers.
    pub counts: [usize; 3],
    /// Cell size along x and y, and the layer spacing along z, m.
    pub spacing: [f64; 3],
    /// Centre of the first sphere of layer 0, m.
    pub origin: [f64; 3],
    /// Sphere radius, m.
    pub radius: f64,
    /// Shift odd layers by half a cell in x and y (default true).
    pub stagger: bool,
}

/// More spheres than this from one source is refused (memory, not physics).
pub const MAX_SPHERES: usize = 100_000_000;

impl Lattice {
    /// Checks the counts, sizes and that no two spheres overlap; `key` names
    /// the lattice in messages (e.g. `particles[0].lattice`).
    pub fn validate(&self, key: &str) -> Result<(), SceneError> {
        let total = self
            .counts
            .iter()
            .try_fold(1usize, |n, &c| n.checked_mul(c));
        let too_many = !matches!(total, Some(n) if n <= MAX_SPHERES);
        if self.counts.contains(&0) || too_many {
            return Err(SceneError::input(format!(
                "`{key}.counts` = {:?}: each count must be at least 1 and their product at most {MAX_SPHERES}",
                self.counts
            )));
        }
        if !(self.radius > 0.0 && self.radius.is_finite()) {
            return Err(SceneError::input(format!(
                "`{key}.radius` = {}: must be a finite length > 0 m",
                self.radius
            )));
        }
        if self.spacing.iter().any(|s| !(*s > 0.0 && s.is_finite()))
            || self.origin.iter().any(|o| !o.is_finite())
        {
            return Err(SceneError::input(format!(
                "`{key}`: spacing {:?} must be finite lengths > 0 m and origin {:?} finite",
                self.spacing, self.origin
            )));
        }
        let diameter = 2.0 * self.radius;
        let [ax, ay, c] = self.spacing;
        // Nearest neighbours: within a layer (ax, ay) and across layers
        // (straight above, or above the hollow when staggered).
        let across = if self.stagger {
            (0.25 * ax * ax + 0.25 * ay * ay + c * c).sqrt()
        } else {
            c
        };
        let mut nearest = f64::INFINITY;
        if self.counts[0] > 1 {
            nearest = nearest.min(ax);
        }
        if self.counts[1] > 1 {
            nearest = nearest.min(ay);
        }
        if self.counts[2] > 1 {
            nearest = nearest.min(across);
        }
        if nearest < diameter {
            return Err(SceneError::input(format!(
                "`{key}.spacing` = {:?}: neighbouring spheres would overlap (nearest centres {nearest:e} m \
                 apart, the diameter is {diameter:e} m); the spacing must keep them at least 2·radius apart",
                self.spacing
            )));
        }
        Ok(())
    }

    /// Number of spheres.
    pub fn len(&self) -> usize {
        self.counts.iter().product()
    }

    /// Whether the lattice is empty.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The spheres, at rest, layer by layer, each layer row by row (y), each
    /// row along x: the order of make_lattice.py. Written with the same
    /// floating-point operations as that script
    /// (`origin + i·a + shift`, `shift = 0.5·a·(k mod 2)`), so a lattice
    /// whose origin is half a cell gives the script's positions bit for bit
    /// before its 9-digit printing.
    pub fn spheres(&self) -> Vec<SourceSphere> {
        self.sites(0..self.len())
    }

    /// The spheres of indices `range` (of [`Self::spheres`]'s order), each
    /// computed from its index alone with the same operations: a part of
    /// the lattice without the rest (one MPI rank's share).
    pub fn sites(&self, range: std::ops::Range<usize>) -> Vec<SourceSphere> {
        let range = range.start.min(self.len())..range.end.min(self.len());
        range.map(|q| self.site(q)).collect()
    }

    /// Sphere `q`: layer k = q / (nx ny), row j, column i.
    pub fn site(&self, q: usize) -> SourceSphere {
        let [nx, ny, _] = self.counts;
        let [ax, ay, c] = self.spacing;
        let (k, j, i) = (q / (nx * ny), (q / nx) % ny, q % nx);
        let odd = if self.stagger { (k % 2) as f64 } else { 0.0 };
        let (sx, sy) = (0.5 * ax * odd, 0.5 * ay * odd);
        let z = self.origin[2] + k as f64 * c;
        let y = self.origin[1] + j as f64 * ay + sy;
        let x = self.origin[0] + i as f64 * ax + sx;
        SourceSphere::at_rest([x, y, z], self.radius)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// make_lattice.py's constants.
    const A: f64 = 1.2e-3;
    const C: f64 = 0.54e-3;
    const Z0: f64 = 0.505e-3;

    fn benchmark(n: usize, layers: usize) -> Lattice {
        Lattice {
            counts: [n, n, layers],
            spacing: [A, A, C],
            origin: [0.5 * A, 0.5 * A, Z0],
            radius: 0.5e-3,
            stagger: true,
        }
    }

    #[test]
    fn positions_follow_make_lattice_formula() {
        // make_lattice.py: x = 0.5a + i a + s, y = 0.5a + j a + s,
        // z = z0 + k c, s = 0.5 a (k mod 2); k outer, then j, then i.
        let lattice = benchmark(3, 4);
        lattice.validate("lattice").unwrap();
        let spheres = lattice.spheres();
        assert_eq!(spheres.len(), 36);
        let mut q = 0;
        for k in 0..4 {
            let s = 0.5 * A * (k % 2) as f64;
            for j in 0..3 {
                for i in 0..3 {
                    let expected = [
                        0.5 * A + i as f64 * A + s,
                        0.5 * A + j as f64 * A + s,
                        Z0 + k as f64 * C,
                    ];
                    assert_eq!(spheres[q].position, expected, "sphere {q}");
                    assert_eq!(spheres[q].radius, 0.5e-3);
                    assert_eq!(spheres[q].velocity, [0.0; 3]);
                    q += 1;
                }
            }
        }
        // Hand values: layer 1, i = j = 0 sits at (1.2, 1.2, 1.045) mm.
        let p = spheres[9].position;
        assert!((p[0] - 1.2e-3).abs() < 1e-18 && (p[2] - 1.045e-3).abs() < 1e-18);
    }

    #[test]
    fn a_part_is_the_same_spheres_as_the_whole() {
        let l = benchmark(5, 3);
        let whole = l.spheres();
        let mut parts = l.sites(0..31);
        parts.extend(l.sites(31..40));
        parts.extend(l.sites(40..1000));
        assert_eq!(parts, whole);
    }

    #[test]
    fn stacked_neighbours_are_the_scripts_gap_apart() {
        // The script's docstring: centre distance sqrt(2·0.6² + 0.54²) mm
        // = 1.00578 mm between a sphere and the one above its hollow.
        let s = benchmark(2, 2).spheres();
        let d = super::super::distance_squared(s[0].position, s[4].position).sqrt();
        assert!((d - (2.0 * 0.6e-3f64.powi(2) + 0.54e-3f64.powi(2)).sqrt()).abs() < 1e-15);
        assert!((d - 1.00578e-3).abs() < 1e-8);
    }

    #[test]
    fn overlapping_or_empty_lattices_are_refused() {
        let mut l = benchmark(2, 2);
        l.spacing[2] = 0.1e-3; // staggered: sqrt(0.36+0.36+0.01) mm < 1 mm
        let e = l.validate("particles[0].lattice").unwrap_err().to_string();
        assert!(e.contains("particles[0].lattice.spacing"), "{e}");
        let mut l = benchmark(2, 2);
        l.counts[1] = 0;
        let e = l.validate("lattice").unwrap_err().to_string();
        assert!(e.contains("lattice.counts"), "{e}");
        let mut l = benchmark(2, 2);
        l.radius = -1.0;
        assert!(l
            .validate("lattice")
            .unwrap_err()
            .to_string()
            .contains("radius"));
    }
}
