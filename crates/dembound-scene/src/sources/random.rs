//! Random non-overlapping insertion of spheres in a box region, seeded and
//! reproducible (ChaCha8 from a `u64` seed: the same seed gives the same
//! spheres on every platform and run).
//!
//! Sequential random addition: each sphere draws its radius, then up to
//! `max_attempts` centres uniformly in the region shrunk by its radius, and
//! takes the first that overlaps neither an earlier sphere of this source
//! nor one of the `existing` spheres. Overlap tests go through a uniform
//! hash grid of cell size 2·R_max, so insertion is O(N) on average.

use super::{distance_squared, SourceSphere};
use crate::SceneError;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::collections::HashMap;

/// Default bound on the centres tried per sphere.
pub const DEFAULT_MAX_ATTEMPTS: u64 = 1000;

/// Random insertion of `count` spheres in the box `lower`–`upper`.
#[derive(Debug, Clone, PartialEq)]
pub struct RandomInsertion {
    pub count: usize,
    /// Radius range, m: `[R, R]` for equal spheres, else uniform in it.
    pub radius: [f64; 2],
    /// Region corners, m.
    pub lower: [f64; 3],
    pub upper: [f64; 3],
    /// Velocity given to every sphere, m/s.
    pub velocity: [f64; 3],
    pub seed: u64,
    /// Centres tried per sphere before giving up.
    pub max_attempts: u64,
}

impl RandomInsertion {
    /// Checks the numbers; `key` names the source in messages.
    pub fn validate(&self, key: &str) -> Result<(), SceneError> {
        let [r_min, r_max] = self.radius;
        if !(r_min > 0.0 && r_min <= r_max && r_max.is_finite()) {
            return Err(SceneError::input(format!(
                "`{key}.radius` = {:?}: must be a radius > 0 m or a range [min, max] with 0 < min ≤ max",
                self.radius
            )));
        }
        if self.count > super::lattice::MAX_SPHERES {
            return Err(SceneError::input(format!(
                "`{key}.count` = {}: at most {}",
                self.count,
                super::lattice::MAX_SPHERES
            )));
        }
        if self.max_attempts == 0 {
            return Err(SceneError::input(format!(
                "`{key}.max_attempts` = 0: must be at least 1"
            )));
        }
        for k in 0..3 {
            if !(self.lower[k].is_finite() && self.upper[k].is_finite())
                || self.upper[k] - self.lower[k] < 2.0 * r_max
            {
                return Err(SceneError::input(format!(
                    "`{key}`: region lower = {:?}, upper = {:?} m must be finite and at least one \
                     largest diameter ({:e} m) wide along each axis",
                    self.lower,
                    self.upper,
                    2.0 * r_max
                )));
            }
        }
        if self.velocity.iter().any(|v| !v.is_finite()) {
            return Err(SceneError::input(format!(
                "`{key}.velocity` = {:?}: must be finite (m/s)",
                self.velocity
            )));
        }
        Ok(())
    }

    /// The spheres, avoiding `existing` ones too. Fails with a message
    /// naming the region, how many were placed and the packing fraction
    /// asked for when a sphere finds no free place in `max_attempts` tries.
    pub fn spheres(
        &self,
        key: &str,
        existing: &[SourceSphere],
    ) -> Result<Vec<SourceSphere>, SceneError> {
        self.validate(key)?;
        let mut rng = ChaCha8Rng::seed_from_u64(self.seed);
        let r_max_all = existing
            .iter()
            .map(|s| s.radius)
            .fold(self.radius[1], f64::max);
        let cell = 2.0 * r_max_all;
        let mut grid = Grid::new(cell);
        for (i, s) in existing.iter().enumerate() {
            grid.insert(s.position, Slot::Existing(i));
        }
        let mut placed: Vec<SourceSphere> = Vec::with_capacity(self.count);
        for n in 0..self.count {
            let radius = if self.radius[0] == self.radius[1] {
                self.radius[0]
            } else {
                rng.gen_range(self.radius[0]..=self.radius[1])
            };
            let mut found = None;
            for _ in 0..self.max_attempts {
                // x, then y, then z: the order fixes the sequence per seed.
                let p: [f64; 3] = std::array::from_fn(|k| {
                    let (lo, hi) = (self.lower[k] + radius, self.upper[k] - radius);
                    if lo < hi {
                        rng.gen_range(lo..hi)
                    } else {
                        lo
                    }
                });
                let free = grid.neighbours(p).all(|slot| {
                    let other = match slot {
                        Slot::Existing(i) => &existing[i],
                        Slot::Placed(i) => &placed[i],
                    };
                    let d = radius + other.radius;
                    distance_squared(p, other.position) >= d * d
                });
                if free {
                    found = Some(p);
                    break;
                }
            }
            let Some(position) = found else {
                let volume: f64 = (0..3).map(|k| self.upper[k] - self.lower[k]).product();
                let mean_r = 0.5 * (self.radius[0] + self.radius[1]);
                let fraction =
                    self.count as f64 * 4.0 / 3.0 * std::f64::consts::PI * mean_r.powi(3) / volume;
                return Err(SceneError::input(format!(
                    "`{key}`: placed only {n} of {} spheres in the region {:?}–{:?} m: sphere {} found no \
                     free place in {} attempts (`max_attempts`). The request fills about {:.1} % of the \
                     region; random insertion rarely exceeds ~30 %: enlarge the region or lower `count`",
                    self.count,
                    self.lower,
                    self.upper,
                    n + 1,
                    self.max_attempts,
                    100.0 * fraction
                )));
            };
            grid.insert(position, Slot::Placed(placed.len()));
            placed.push(SourceSphere {
                position,
                velocity: self.velocity,
                radius,
            });
        }
        Ok(placed)
    }
}

#[derive(Debug, Clone, Copy)]
enum Slot {
    Existing(usize),
    Placed(usize),
}

/// A hash grid: spheres by the cell of their centre; two spheres that
/// overlap are in the same or adjacent cells when the cell is ≥ 2·R_max.
struct Grid {
    cell: f64,
    cells: HashMap<[i64; 3], Vec<Slot>>,
}

impl Grid {
    fn new(cell: f64) -> Self {
        Self {
            cell,
            cells: HashMap::new(),
        }
    }

    fn key(&self, p: [f64; 3]) -> [i64; 3] {
        p.map(|x| (x / self.cell).floor() as i64)
    }

    fn insert(&mut self, p: [f64; 3], slot: Slot) {
        let key = self.key(p);
        self.cells.entry(key).or_default().push(slot);
    }

    fn neighbours(&self, p: [f64; 3]) -> impl Iterator<Item = Slot> + '_ {
        let [cx, cy, cz] = self.key(p);
        (-1..=1).flat_map(move |dx| {
            (-1..=1).flat_map(move |dy| {
                (-1..=1).flat_map(move |dz| {
                    self.cells
                        .get(&[cx + dx, cy + dy, cz + dz])
                        .into_iter()
                        .flatten()
                        .copied()
                })
            })
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn region(count: usize, seed: u64) -> RandomInsertion {
        RandomInsertion {
            count,
            radius: [0.4e-3, 0.6e-3],
            lower: [0.0; 3],
            upper: [10e-3, 10e-3, 10e-3],
            velocity: [0.0, 0.0, -0.1],
            seed,
            max_attempts: DEFAULT_MAX_ATTEMPTS,
        }
    }

    /// Every pair checked directly, O(N²): independent of the grid.
    fn assert_no_overlap(s: &[SourceSphere]) {
        for i in 0..s.len() {
            for j in 0..i {
                let d = s[i].radius + s[j].radius;
                assert!(
                    distance_squared(s[i].position, s[j].position) >= d * d,
                    "spheres {i} and {j} overlap"
                );
            }
        }
    }

    #[test]
    fn spheres_are_inside_apart_and_reproducible() {
        let r = region(300, 7); // ~16 % of the volume
        let a = r.spheres("random", &[]).unwrap();
        assert_eq!(a.len(), 300);
        assert_no_overlap(&a);
        for s in &a {
            assert!((0.4e-3..=0.6e-3).contains(&s.radius));
            for k in 0..3 {
                assert!(s.position[k] - s.radius >= 0.0 && s.position[k] + s.radius <= 10e-3);
            }
            assert_eq!(s.velocity, [0.0, 0.0, -0.1]);
        }
        assert_eq!(
            a,
            r.spheres("random", &[]).unwrap(),
            "same seed, same spheres"
        );
        assert_ne!(a, region(300, 8).spheres("random", &[]).unwrap());
    }

    #[test]
    fn existing_spheres_are_avoided() {
        let existing: Vec<_> = region(200, 1).spheres("a", &[]).unwrap();
        let more = region(200, 2).spheres("b", &existing).unwrap();
        let all: Vec<_> = existing.iter().chain(&more).copied().collect();
        assert_no_overlap(&all);
    }

    #[test]
    fn an_impossible_request_fails_with_a_clear_message() {
        // 10,000 spheres of ~1 mm³·(4/3)π·0.125 in 1e-6 m³: ~52 % > any
        // random packing.
        let mut r = region(10_000, 3);
        r.max_attempts = 50;
        let e = r
            .spheres("particles[2].random", &[])
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("particles[2].random") && e.contains("placed only"),
            "{e}"
        );
        assert!(e.contains("max_attempts"), "{e}");
    }

    #[test]
    fn bad_numbers_are_refused() {
        let mut r = region(1, 0);
        r.radius = [0.6e-3, 0.4e-3];
        assert!(r
            .validate("random")
            .unwrap_err()
            .to_string()
            .contains("random.radius"));
        let mut r = region(1, 0);
        r.upper[1] = 0.5e-3;
        assert!(r.validate("random").is_err());
    }
}
