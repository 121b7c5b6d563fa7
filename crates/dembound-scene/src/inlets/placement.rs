//! Where an inlet's spheres go (module doc of `crate::inlets`: **Where**,
//! **Determinism**): seeded candidates in the region and the exact overlap
//! tests against the spheres and walls in the way.

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use std::collections::HashMap;

use super::InletSetup;
use crate::pipeline::World;

/// Spheres in the way of new ones, found through a hash grid (exact
/// tests; the grid only narrows the candidates).
#[derive(Debug, Clone)]
pub struct Obstacles {
    /// Centre (m) and radius (m).
    spheres: Vec<([f64; 3], f64)>,
    /// Cell edge, m: ≥ R_new + R of every gridded sphere.
    cell: f64,
    grid: HashMap<[i64; 3], Vec<u32>>,
    /// Spheres too large for the grid, tested one by one.
    large: Vec<u32>,
    /// The largest radius of a new sphere, m.
    new_max: f64,
}

impl Obstacles {
    /// `spheres` (centre, radius in m), for new spheres of radius at most
    /// `new_max` (m).
    pub fn new(spheres: Vec<([f64; 3], f64)>, new_max: f64) -> Self {
        let limit = 4.0 * new_max;
        let small_max = spheres
            .iter()
            .map(|s| s.1)
            .filter(|&r| r <= limit)
            .fold(new_max, f64::max);
        let mut me = Self {
            spheres: Vec::new(),
            cell: new_max + small_max,
            grid: HashMap::new(),
            large: Vec::new(),
            new_max,
        };
        for (x, r) in spheres {
            me.add(x, r);
        }
        me
    }

    fn key(&self, x: [f64; 3]) -> [i64; 3] {
        x.map(|c| (c / self.cell).floor() as i64)
    }

    /// Adds a sphere at `x` (m) of radius `r` (m).
    pub fn add(&mut self, x: [f64; 3], r: f64) {
        let k = self.spheres.len() as u32;
        self.spheres.push((x, r));
        if r > self.cell - self.new_max {
            self.large.push(k);
        } else {
            let key = self.key(x);
            self.grid.entry(key).or_default().push(k);
        }
    }

    /// A sphere at `x` (m) of radius `r` ≤ `new_max` (m) overlaps none:
    /// every distance ≥ the sum of the radii.
    pub fn clear(&self, x: [f64; 3], r: f64) -> bool {
        let free = |k: u32| {
            let (y, ry) = self.spheres[k as usize];
            let d2 = (x[0] - y[0]).powi(2) + (x[1] - y[1]).powi(2) + (x[2] - y[2]).powi(2);
            d2 >= (r + ry) * (r + ry)
        };
        if !self.large.iter().all(|&k| free(k)) {
            return false;
        }
        let c = self.key(x);
        for dx in -1..=1 {
            for dy in -1..=1 {
                for dz in -1..=1 {
                    if let Some(list) = self.grid.get(&[c[0] + dx, c[1] + dy, c[2] + dz]) {
                        if !list.iter().all(|&k| free(k)) {
                            return false;
                        }
                    }
                }
            }
        }
        true
    }
}

/// Places up to `n` spheres of inlet `setup` drawing from `rng`: each
/// radius, then up to `max_attempts` centres, the first clear of
/// `obstacles` (to which each placed sphere is added) and of the walls
/// (`walls_clear(x, r)`) taken. Returns the spheres placed (centre,
/// radius; m) in order and the number not placed.
pub fn place_event(
    setup: &InletSetup,
    n: u64,
    rng: &mut ChaCha8Rng,
    obstacles: &mut Obstacles,
    walls_clear: &dyn Fn([f64; 3], f64) -> bool,
) -> (Vec<([f64; 3], f64)>, u64) {
    let mut placed = Vec::new();
    let mut missed = 0;
    for _ in 0..n {
        let r = setup.size.sample(rng);
        let mut found = None;
        for _ in 0..setup.max_attempts {
            let x = setup.region.sample(rng, r);
            if obstacles.clear(x, r) && walls_clear(x, r) {
                found = Some(x);
                break;
            }
        }
        match found {
            Some(x) => {
                obstacles.add(x, r);
                placed.push((x, r));
            }
            None => missed += 1,
        }
    }
    (placed, missed)
}

/// The generator of event `e` of inlet `k` of seed `seed` (module doc).
pub fn event_rng(seed: u64, k: usize, e: u64) -> ChaCha8Rng {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    rng.set_stream(((k as u64) << 40) | (e & ((1 << 40) - 1)));
    rng
}

/// The bodies `k` of `world` for which `include(k)` holds near the box
/// `lower..upper` grown by `reach` (m), with their periodic images across
/// periodic faces: the spheres a new one there may touch, as (input id,
/// centre, radius; m), each body's images together.
pub(crate) fn nearby(
    world: &World,
    (lower, upper): ([f64; 3], [f64; 3]),
    reach: f64,
    include: &dyn Fn(usize) -> bool,
) -> Vec<(u32, [f64; 3], f64)> {
    let b = &world.bodies;
    let d = &world.domain;
    let near = |x: [f64; 3], r: f64| {
        (0..3).all(|a| x[a] + r >= lower[a] - reach && x[a] - r <= upper[a] + reach)
    };
    let mut out = Vec::new();
    for k in (0..b.len()).filter(|&k| include(k)) {
        let (x, r) = (b.position[k], b.radius[k]);
        // Every image across the periodic axes (shifts −L, 0, +L).
        let shifts = |a: usize| -> Vec<f64> {
            if d.periodic[a] {
                let len = d.upper[a] - d.lower[a];
                vec![0.0, -len, len]
            } else {
                vec![0.0]
            }
        };
        for sx in shifts(0) {
            for sy in shifts(1) {
                for sz in shifts(2) {
                    let y = [x[0] + sx, x[1] + sy, x[2] + sz];
                    if near(y, r) {
                        out.push((b.id[k], y, r));
                    }
                }
            }
        }
    }
    out
}
