//! Spheres inserted during the run (`[[inlet]]`, issue 28), the way
//! LIGGGHTS's `fix insert/rate/region` pours them.
//!
//! **When.** Insertion events come every `every` steps (the inlet's key, or
//! [`default_every`]), the first at the first step at or after `start`
//! (never step 0), the last before `end`. Event k (k = 0, 1, …) inserts
//! the spheres due up to the end of its interval: round(ṅ · min((k + 1) ·
//! every · Δt, end − start)) in all, less those of the earlier events
//! (placed or not), so the count never drifts from the rate by more than
//! half a sphere. A mass rate Q (kg/s) is the number rate ṅ = Q / m̄, m̄
//! the mean sphere mass of the size distribution (fractions by number).
//!
//! **Where.** Each sphere draws its radius from the size distribution,
//! then up to `max_attempts` centres uniformly in the region shrunk by its
//! radius (the sphere lies wholly inside the region); the first centre
//! that overlaps nothing is taken: no free, fixed or boundary sphere
//! (periodic images included), no sphere placed earlier in the same event
//! (of this inlet or an earlier one), and no wall (every element of every
//! plane, cylinder and mesh wall at overlap ≤ 0: distance ≥ R). Touching
//! (distance exactly R_i + R_j) is allowed. A sphere none of whose
//! centres fits is not placed: counted (`not_placed`), reported, never
//! silently lost.
//!
//! **Determinism.** The draws come from ChaCha8 seeded by the inlet's
//! `seed`, on stream (inlet index · 2⁴⁰ + event number): they depend on
//! nothing else, not on threads nor on the engine's order of the bodies.
//! The overlap test is exact (a hash grid only finds the candidates), so
//! the spheres placed are those of the scene's state. New spheres get the
//! input ids after every id the scene has had, in the order placed.
//!
//! **The engine.** An event forces a neighbour-list rebuild at its step
//! (`World::rebuild_budget`); the spheres are appended there, after the
//! removal of lost spheres (`crate::removal`) and before the lists are
//! built, mid-step: Verlet stores the half-step velocity v₀ − g Δt/2 (the
//! step's last half kick, by gravity alone since the sphere touches
//! nothing, completes it to v₀), Gear5 the predicted state (r₂ = g Δt²/2,
//! higher derivatives 0: exact for a free flight).
//!
//! **Energy.** Each inserted sphere brings in ½ m v₀² − m g·x (no spin):
//! booked as I, so that K + E + P + D − W + C − I = E₀ still closes and
//! the energy guard still judges D.
//!
//! **Region capacity.** Random sequential addition of equal spheres jams
//! at a solid fraction of about 0.38 in an unbounded space (Torquato,
//! Uche & Stillinger 2006, Phys Rev E 74 061308), less near walls; an
//! event whose volume ṅ · V̄ · every · Δt exceeds [`MAX_EVENT_FRACTION`] of
//! the region's volume cannot be placed by bounded attempts and is
//! refused (the error names the `rate`).

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};
use std::collections::HashMap;
use std::f64::consts::PI;

use crate::error::SceneError;
use crate::pipeline::World;
use crate::setup::Scheme;

/// Default bound on the centres tried per sphere.
pub const DEFAULT_MAX_ATTEMPTS: u64 = 100;
/// At most this many rows in a size table.
pub const MAX_TABLE_ROWS: usize = 1000;
/// The largest volume an event may insert, as a fraction of the region's
/// volume (module doc: about half the jamming fraction of random
/// sequential addition, 0.38).
pub const MAX_EVENT_FRACTION: f64 = 0.2;
/// The volume the default interval inserts per event, as a fraction of
/// the region's ([`default_every`]).
pub const DEFAULT_EVENT_FRACTION: f64 = 0.05;

/// An inlet's region, m.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum InletRegion {
    Box {
        lower: [f64; 3],
        upper: [f64; 3],
    },
    /// `axis` a unit vector; `center` the middle of the axis segment of
    /// `length`.
    Cylinder {
        center: [f64; 3],
        axis: [f64; 3],
        radius: f64,
        length: f64,
    },
}

/// `v` over its length (the zero vector stays zero).
pub fn unit(v: [f64; 3]) -> [f64; 3] {
    let n = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    if n > 0.0 {
        [v[0] / n, v[1] / n, v[2] / n]
    } else {
        v
    }
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// Two unit vectors perpendicular to the unit `a` and to each other.
fn perpendiculars(a: [f64; 3]) -> ([f64; 3], [f64; 3]) {
    let t = if a[0].abs() < 0.9 {
        [1.0, 0.0, 0.0]
    } else {
        [0.0, 1.0, 0.0]
    };
    let u = unit(cross(a, t));
    (u, cross(a, u))
}

impl InletRegion {
    /// The axis-aligned bounding box, m.
    pub fn bounds(&self) -> ([f64; 3], [f64; 3]) {
        match *self {
            InletRegion::Box { lower, upper } => (lower, upper),
            InletRegion::Cylinder {
                center,
                axis,
                radius,
                length,
            } => {
                let e = [0, 1, 2].map(|a| {
                    0.5 * length * axis[a].abs()
                        + radius * (1.0 - axis[a] * axis[a]).max(0.0).sqrt()
                });
                (
                    [0, 1, 2].map(|a| center[a] - e[a]),
                    [0, 1, 2].map(|a| center[a] + e[a]),
                )
            }
        }
    }

    /// m³.
    pub fn volume(&self) -> f64 {
        match *self {
            InletRegion::Box { lower, upper } => {
                (upper[0] - lower[0]) * (upper[1] - lower[1]) * (upper[2] - lower[2])
            }
            InletRegion::Cylinder { radius, length, .. } => PI * radius * radius * length,
        }
    }

    /// A sphere of radius `r` (m) fits wholly inside.
    pub fn fits(&self, r: f64) -> bool {
        match *self {
            InletRegion::Box { lower, upper } => (0..3).all(|a| upper[a] - lower[a] >= 2.0 * r),
            InletRegion::Cylinder { radius, length, .. } => radius >= r && length >= 2.0 * r,
        }
    }

    /// A centre uniform in the region shrunk by `r` (m): the sphere lies
    /// wholly inside.
    fn sample(&self, rng: &mut ChaCha8Rng, r: f64) -> [f64; 3] {
        match *self {
            InletRegion::Box { lower, upper } => [0, 1, 2].map(|a| {
                let (lo, hi) = (lower[a] + r, upper[a] - r);
                lo + (hi - lo) * rng.gen::<f64>()
            }),
            InletRegion::Cylinder {
                center,
                axis,
                radius,
                length,
            } => {
                // Uniform in the disc: radius √u (area element r dr).
                let (u, w) = perpendiculars(axis);
                let s = (radius - r) * rng.gen::<f64>().sqrt();
                let phi = 2.0 * PI * rng.gen::<f64>();
                let h = (0.5 * length - r) * (2.0 * rng.gen::<f64>() - 1.0);
                let (c, si) = (s * phi.cos(), s * phi.sin());
                [0, 1, 2].map(|a| center[a] + c * u[a] + si * w[a] + h * axis[a])
            }
        }
    }
}

/// The rate of an inlet.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum InletRate {
    /// Spheres/s.
    Number(f64),
    /// kg/s.
    Mass(f64),
}

/// The radius distribution of the inserted spheres, m.
#[derive(Debug, Clone, PartialEq)]
pub enum SizeDistribution {
    Fixed(f64),
    /// Uniform in [min, max].
    Uniform(f64, f64),
    /// Normal of `mean` and `std`, truncated to [min, max] (redrawn).
    Normal {
        mean: f64,
        std: f64,
        min: f64,
        max: f64,
    },
    /// (R, fraction by number); fractions normalised to their sum.
    Table(Vec<(f64, f64)>),
}

impl SizeDistribution {
    pub fn max_radius(&self) -> f64 {
        match self {
            SizeDistribution::Fixed(r) => *r,
            SizeDistribution::Uniform(_, hi) => *hi,
            SizeDistribution::Normal { max, .. } => *max,
            SizeDistribution::Table(rows) => rows
                .iter()
                .filter(|r| r.1 > 0.0)
                .map(|r| r.0)
                .fold(0.0, f64::max),
        }
    }

    pub fn min_radius(&self) -> f64 {
        match self {
            SizeDistribution::Fixed(r) => *r,
            SizeDistribution::Uniform(lo, _) => *lo,
            SizeDistribution::Normal { min, .. } => *min,
            SizeDistribution::Table(rows) => rows
                .iter()
                .filter(|r| r.1 > 0.0)
                .map(|r| r.0)
                .fold(f64::INFINITY, f64::min),
        }
    }

    /// E[R³], m³ (by number).
    pub fn mean_cube(&self) -> f64 {
        match self {
            SizeDistribution::Fixed(r) => r * r * r,
            SizeDistribution::Uniform(a, b) => {
                if b > a {
                    (b.powi(4) - a.powi(4)) / (4.0 * (b - a))
                } else {
                    a * a * a
                }
            }
            SizeDistribution::Normal {
                mean,
                std,
                min,
                max,
            } => {
                if *std == 0.0 || max <= min {
                    return mean.clamp(*min, *max).powi(3);
                }
                // Simpson's rule over the truncated density (its
                // normalisation cancels): smooth, 2000 intervals.
                let n = 2000;
                let h = (max - min) / n as f64;
                let (mut num, mut den) = (0.0, 0.0);
                for i in 0..=n {
                    let r = min + h * i as f64;
                    let w = if i == 0 || i == n {
                        1.0
                    } else if i % 2 == 1 {
                        4.0
                    } else {
                        2.0
                    };
                    let p = (-0.5 * ((r - mean) / std).powi(2)).exp();
                    num += w * p * r * r * r;
                    den += w * p;
                }
                num / den
            }
            SizeDistribution::Table(rows) => {
                let total: f64 = rows.iter().map(|r| r.1).sum();
                rows.iter().map(|r| r.1 * r.0.powi(3)).sum::<f64>() / total
            }
        }
    }

    /// One radius, m.
    fn sample(&self, rng: &mut ChaCha8Rng) -> f64 {
        match self {
            SizeDistribution::Fixed(r) => *r,
            SizeDistribution::Uniform(a, b) => a + (b - a) * rng.gen::<f64>(),
            SizeDistribution::Normal {
                mean,
                std,
                min,
                max,
            } => {
                if *std == 0.0 || max <= min {
                    return mean.clamp(*min, *max);
                }
                // Box–Muller, redrawn outside [min, max]; the mean lies
                // inside, so a draw is kept with probability ≥ that of one
                // half-width, and the bound below is never reached in
                // practice (then the mean).
                for _ in 0..10_000 {
                    let u1: f64 = 1.0 - rng.gen::<f64>();
                    let u2: f64 = rng.gen();
                    let z = (-2.0 * u1.ln()).sqrt() * (2.0 * PI * u2).cos();
                    let r = mean + std * z;
                    if r >= *min && r <= *max {
                        return r;
                    }
                }
                *mean
            }
            SizeDistribution::Table(rows) => {
                let total: f64 = rows.iter().map(|r| r.1).sum();
                let mut u = total * rng.gen::<f64>();
                for &(r, f) in rows {
                    if u < f {
                        return r;
                    }
                    u -= f;
                }
                // Rounding at the top end: the last row of weight.
                rows.iter().rev().find(|r| r.1 > 0.0).map_or(0.0, |r| r.0)
            }
        }
    }
}

/// One `[[inlet]]` as the engine takes it (SI).
#[derive(Debug, Clone, PartialEq)]
pub struct InletSetup {
    pub region: InletRegion,
    pub rate: InletRate,
    pub size: SizeDistribution,
    /// Index into the setup's materials.
    pub material: usize,
    /// m/s.
    pub velocity: [f64; 3],
    /// s.
    pub start: f64,
    /// s; `None`: the run's end.
    pub end: Option<f64>,
    pub seed: u64,
    /// Steps between events; `None`: [`default_every`].
    pub every: Option<u64>,
    pub max_attempts: u64,
}

/// The default steps between events: the time in which the rate brings
/// [`DEFAULT_EVENT_FRACTION`] of the region's volume, at most a hundredth
/// of the insertion window (`window`, s, when finite), at least one step.
pub fn default_every(volume_rate: f64, region_volume: f64, window: f64, dt: f64) -> u64 {
    let mut t = DEFAULT_EVENT_FRACTION * region_volume / volume_rate;
    if window.is_finite() && window > 0.0 {
        t = t.min(window / 100.0);
    }
    let steps = (t / dt).floor();
    if steps.is_finite() && steps >= 1.0 {
        steps.min(1e9) as u64
    } else {
        1
    }
}

/// What one inlet has inserted so far (series.csv, `--json` `inlets`).
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct Inserted {
    /// Spheres placed.
    pub count: u64,
    /// Their mass, kg.
    pub mass: f64,
    /// Spheres due that found no free place (module doc).
    pub not_placed: u64,
    /// The kinetic and potential energy the placed spheres brought in, J.
    pub energy: f64,
}

/// The series.csv columns of inlet `k`: spheres inserted so far, their
/// mass.
pub fn inlet_columns(k: usize) -> [String; 2] {
    [format!("inlet{k}_inserted"), format!("inlet{k}_mass_kg")]
}

/// The series.csv column of the energy all inlets brought in so far.
pub const BROUGHT_IN_COLUMN: &str = "brought_in_energy_J";

/// What one inlet inserted over the run (`--json` `inlets`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct InletReport {
    /// Spheres placed.
    pub inserted: u64,
    /// Their mass, kg.
    pub mass: f64,
    /// Spheres due that found no free place in the region.
    pub not_placed: u64,
}

impl From<Inserted> for InletReport {
    fn from(i: Inserted) -> Self {
        Self {
            inserted: i.count,
            mass: i.mass,
            not_placed: i.not_placed,
        }
    }
}

/// One inlet in a run: its schedule resolved against Δt.
#[derive(Debug, Clone, PartialEq)]
pub struct Inlet {
    pub setup: InletSetup,
    /// Spheres/s.
    pub number_rate: f64,
    /// The step of event 0 (≥ 1).
    pub first_step: u64,
    pub every: u64,
    /// end − start, s (∞ without `end`).
    pub window: f64,
    /// Density of the material, kg/m³.
    pub density: f64,
    /// Spheres due so far (placed or not).
    pub due: u64,
    pub so_far: Inserted,
}

/// The inlets of a run.
#[derive(Debug, Clone, PartialEq)]
pub struct Inlets {
    pub inlets: Vec<Inlet>,
    /// The input id the next inserted sphere gets: after every id the
    /// scene has had.
    pub next_id: u32,
    /// Δt, s.
    pub dt: f64,
}

impl Inlets {
    /// The run's inlets, their schedules resolved against `dt` (s) and a
    /// run of `run_time` (s); a rate the region cannot hold refused,
    /// naming `inlet[K].rate`.
    pub(crate) fn new(
        setups: &[InletSetup],
        densities: &[f64],
        spheres: usize,
        dt: f64,
        run_time: f64,
    ) -> Result<Self, SceneError> {
        let mut inlets = Vec::with_capacity(setups.len());
        for (k, s) in setups.iter().enumerate() {
            let density = densities.get(s.material).copied().unwrap_or(f64::NAN);
            if !(density.is_finite() && density > 0.0) {
                return Err(SceneError::invalid(
                    format!("inlet[{k}].material"),
                    s.material,
                    "a material of finite density > 0 kg/m³",
                ));
            }
            let mean_volume = 4.0 / 3.0 * PI * s.size.mean_cube();
            let number_rate = match s.rate {
                InletRate::Number(n) => n,
                InletRate::Mass(q) => q / (density * mean_volume),
            };
            let (rate_key, rate_value, rate_unit) = match s.rate {
                InletRate::Number(n) => ("rate.number", n, "spheres/s"),
                InletRate::Mass(q) => ("rate.mass", q, "kg/s"),
            };
            if !(number_rate.is_finite() && number_rate > 0.0) {
                return Err(SceneError::invalid(
                    format!("inlet[{k}].{rate_key}"),
                    rate_value,
                    format!("finite and > 0 {rate_unit}"),
                ));
            }
            let window = match s.end {
                Some(e) => e - s.start,
                None => f64::INFINITY,
            };
            let region_volume = s.region.volume();
            let volume_rate = number_rate * mean_volume;
            let every = match s.every {
                Some(e) => e,
                None => default_every(
                    volume_rate,
                    region_volume,
                    window.min(run_time - s.start),
                    dt,
                ),
            };
            let per_event = volume_rate * every as f64 * dt;
            if per_event > MAX_EVENT_FRACTION * region_volume {
                return Err(SceneError::invalid(
                    format!("inlet[{k}].{rate_key}"),
                    format!("{rate_value} {rate_unit}"),
                    format!(
                        "a rate whose sphere volume per insertion event ({per_event:.4e} m³ every \
                         {every} steps of {dt:e} s) is at most {MAX_EVENT_FRACTION} of the region's \
                         volume ({region_volume:.4e} m³): random sequential insertion cannot place \
                         more (its jamming fraction is about 0.38); lower the rate, enlarge the \
                         region or give a smaller inlet[{k}].every"
                    ),
                ));
            }
            let first_step = ((s.start / dt) * (1.0 - 1e-12)).ceil().max(1.0);
            inlets.push(Inlet {
                setup: s.clone(),
                number_rate,
                first_step: first_step.min(1e18) as u64,
                every,
                window,
                density,
                due: 0,
                so_far: Inserted::default(),
            });
        }
        Ok(Self {
            inlets,
            next_id: u32::try_from(spheres).unwrap_or(u32::MAX),
            dt,
        })
    }

    /// The event number of inlet `k` at `step`, if it has one there.
    fn event_at(&self, k: usize, step: u64) -> Option<u64> {
        let i = &self.inlets[k];
        let since = step.checked_sub(i.first_step)?;
        if since % i.every != 0 {
            return None;
        }
        let e = since / i.every;
        let elapsed = (e * i.every) as f64 * self.dt;
        (elapsed < i.window * (1.0 - 1e-12)).then_some(e)
    }

    /// Some inlet has an event at `step`.
    pub fn due_at(&self, step: u64) -> bool {
        (0..self.inlets.len()).any(|k| self.event_at(k, step).is_some())
    }

    /// Spheres due so far after event `e` of inlet `k` (module doc).
    fn due_after(&self, k: usize, e: u64) -> u64 {
        let i = &self.inlets[k];
        let t = (((e + 1) * i.every) as f64 * self.dt).min(i.window);
        let n = (i.number_rate * t).round();
        if n.is_finite() && n >= 0.0 {
            n.min(1e15) as u64
        } else {
            0
        }
    }

    /// Each inlet's figures so far (file order).
    pub fn inserted(&self) -> Vec<Inserted> {
        self.inlets.iter().map(|i| i.so_far).collect()
    }
}

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

/// The bodies of `world` near the box `lower..upper` grown by `reach`
/// (m), with their periodic images across periodic faces: the spheres a
/// new one there may touch.
fn nearby(world: &World, (lower, upper): ([f64; 3], [f64; 3]), reach: f64) -> Vec<([f64; 3], f64)> {
    let b = &world.bodies;
    let d = &world.domain;
    let near = |x: [f64; 3], r: f64| {
        (0..3).all(|a| x[a] + r >= lower[a] - reach && x[a] - r <= upper[a] + reach)
    };
    let mut out = Vec::new();
    for k in 0..b.len() {
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
                        out.push((y, r));
                    }
                }
            }
        }
    }
    out
}

/// At a list rebuild of a step with an insertion event (call after the
/// removal, before the lists are built): places every inlet's spheres due
/// at this step and appends them to the bodies (module doc).
pub(crate) fn insert_due(world: &mut World) {
    let Some(mut inlets) = world.inlets.take() else {
        return;
    };
    let step = world.steps_done + 1;
    let first_new = world.bodies.len();
    for k in 0..inlets.inlets.len() {
        let Some(e) = inlets.event_at(k, step) else {
            continue;
        };
        let due = inlets.due_after(k, e);
        let n = due.saturating_sub(inlets.inlets[k].due);
        inlets.inlets[k].due = due.max(inlets.inlets[k].due);
        if n == 0 {
            continue;
        }
        let setup = inlets.inlets[k].setup.clone();
        let r_max = setup.size.max_radius();
        let mut obstacles = Obstacles::new(nearby(world, setup.region.bounds(), r_max), r_max);
        let surfaces = &world.surfaces;
        let walls_clear = |x: [f64; 3], r: f64| {
            surfaces.iter().all(|s| {
                let mut clear = true;
                s.wall().near_elements(x, r, 0.0, &mut |el| {
                    if clear && s.wall().contact(el, x, [0.0; 3], r).overlap > 0.0 {
                        clear = false;
                    }
                });
                clear
            })
        };
        let mut rng = event_rng(setup.seed, k, e);
        let (placed, missed) = place_event(&setup, n, &mut rng, &mut obstacles, &walls_clear);
        let density = inlets.inlets[k].density;
        let material = world.laws.materials.get(setup.material).copied();
        let mut so_far = inlets.inlets[k].so_far;
        so_far.not_placed += missed;
        for (x, r) in placed {
            let m = material.map_or(4.0 / 3.0 * PI * density * r * r * r, |mat| {
                mat.sphere_mass(r)
            });
            let id = inlets.next_id;
            inlets.next_id = inlets.next_id.saturating_add(1);
            let energy = push_sphere(world, x, r, m, setup.velocity, setup.material as u32, id);
            so_far.count += 1;
            so_far.mass += m;
            so_far.energy += energy;
        }
        inlets.inlets[k].so_far = so_far;
    }
    world.inlets = Some(inlets);
    if world.bodies.len() > first_new {
        assign_classes(world, first_new);
    }
}

/// Appends a free sphere at `x` (m) of radius `r` (m), mass `m` (kg),
/// velocity `v` (m/s) at the rebuild's time (module doc: Verlet's
/// half-step velocity, Gear5's predicted state); returns the energy it
/// brings in, ½ m v² − m g·x (J).
fn push_sphere(
    world: &mut World,
    x: [f64; 3],
    r: f64,
    m: f64,
    v: [f64; 3],
    material: u32,
    id: u32,
) -> f64 {
    let g = world.gravity;
    let dt = world.dt;
    let b = &mut world.bodies;
    let stored = match world.scheme {
        Scheme::Verlet => [0, 1, 2].map(|a| v[a] - 0.5 * dt * g[a]),
        Scheme::Gear5 => v,
    };
    b.position.push(x);
    b.velocity.push(stored);
    b.force.push([0.0; 3]);
    b.radius.push(r);
    b.mass.push(m);
    b.inverse_mass.push(1.0 / m);
    b.material.push(material);
    b.fixed.push(false);
    b.id.push(id);
    b.group.push(crate::bodies::NO_GROUP);
    if !b.higher.is_empty() {
        // r₂ = Δt² x''/2 with x'' = g (a free flight), the rest 0.
        let r2 = [0, 1, 2].map(|a| 0.5 * dt * dt * g[a]);
        b.higher.push([r2, [0.0; 3], [0.0; 3], [0.0; 3]]);
    }
    b.angular_velocity.push([0.0; 3]);
    b.torque.push([0.0; 3]);
    b.inverse_inertia.push(1.0 / (0.4 * m * r * r));
    if !b.angular_higher.is_empty() {
        b.angular_higher.push([[0.0; 3]; 4]);
    }
    world.wall_contacts.push_body(&[]);
    0.5 * m * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2])
        - m * (g[0] * x[0] + g[1] * x[1] + g[2] * x[2])
}

/// The law classes of the bodies `first_new..`: an existing class of the
/// same radius, mass and material, else the tables made again over every
/// body (the laws of a pair are computed from those three alone: the same
/// bits whichever table, or none, holds them).
fn assign_classes(world: &mut World, first_new: usize) {
    use crate::dynamics::contacts::{LawTable, NO_CLASS};
    let b = &mut world.bodies;
    let key = |k: usize| (b.radius[k].to_bits(), b.mass[k].to_bits(), b.material[k]);
    b.class.truncate(first_new);
    let tabulated = world.laws.classes() > 0;
    if !tabulated && b.class.contains(&NO_CLASS) {
        // Too many classes already: every law computed per contact.
        b.class.resize(b.len(), NO_CLASS);
        return;
    }
    let mut known: HashMap<(u64, u64, u32), u16> = HashMap::new();
    if tabulated {
        for k in 0..first_new {
            known.entry(key(k)).or_insert(b.class[k]);
        }
    }
    let found: Option<Vec<u16>> = (first_new..b.len())
        .map(|k| known.get(&key(k)).copied())
        .collect();
    if let Some(classes) = found {
        b.class.extend(classes);
        return;
    }
    let laws = LawTable::new(
        world.laws.model,
        world.laws.materials.clone(),
        &mut world.bodies,
        world.laws.slots.clone(),
    );
    world.laws = laws;
    if let Some(f) = world.friction.as_ref() {
        let table = crate::dynamics::friction::FrictionTable::new(
            f.setup.clone(),
            &world.laws,
            &world.bodies,
        );
        world.friction = Some(table);
    }
}

/// The smallest and largest radius each inlet inserts (m; empty without
/// inlets): the neighbour skin and cells are chosen for them too.
pub(crate) fn radii(setup: &crate::setup::SceneSetup) -> Vec<f64> {
    setup
        .inlets
        .iter()
        .flat_map(|i| [i.size.min_radius(), i.size.max_radius()])
        .collect()
}

/// `setup` with, per inlet, a sphere of its smallest and one of its
/// largest radius at its region's centre moving at its velocity: the scene
/// the time-step rule judges (the inserted spheres' contacts bound Δt as
/// the others' do). The same setup without inlets.
pub(crate) fn with_probes(
    setup: &crate::setup::SceneSetup,
) -> std::borrow::Cow<'_, crate::setup::SceneSetup> {
    if setup.inlets.is_empty() {
        return std::borrow::Cow::Borrowed(setup);
    }
    let mut probed = setup.clone();
    for i in &setup.inlets {
        let (lo, hi) = i.region.bounds();
        let centre = [0, 1, 2].map(|a| 0.5 * (lo[a] + hi[a]));
        for radius in [i.size.min_radius(), i.size.max_radius()] {
            probed.spheres.push(crate::setup::SphereInit {
                position: centre,
                velocity: i.velocity,
                radius,
                material: i.material,
                fixed: false,
                group: None,
            });
        }
    }
    std::borrow::Cow::Owned(probed)
}

/// The energy the inserted spheres brought in by observation `o`, J
/// (`None` without inlets).
pub(crate) fn brought_in(o: &crate::simulation::Observation) -> Option<f64> {
    (!o.inlets.is_empty()).then(|| o.inlets.iter().map(|i| i.energy).sum())
}

/// A checkpoint of a scene with inlets cannot be restarted yet (it does
/// not record the inserted spheres' radii and materials).
pub(crate) fn refuse_restart(setups: &[InletSetup]) -> Result<(), SceneError> {
    if setups.is_empty() {
        return Ok(());
    }
    Err(SceneError::Checkpoint(
        "the scene has [[inlet]] sections (inlet[0]): a restart of a scene with inlets is not \
         supported yet (the checkpoint does not record the inserted spheres' radii and \
         materials); run it in one go"
            .into(),
    ))
}

/// Refuses inlets where they are not supported yet (a decomposed run),
/// naming the first inlet's key.
pub fn refuse_under_mpi(setups: &[InletSetup]) -> Result<(), SceneError> {
    if setups.is_empty() {
        return Ok(());
    }
    Err(SceneError::invalid(
        "inlet[0]",
        format!("{} [[inlet]] section(s)", setups.len()),
        "no [[inlet]] in a run on several MPI ranks (insertion is single-process for now: run \
         without mpirun, on threads)",
    ))
}

#[cfg(test)]
mod tests;
