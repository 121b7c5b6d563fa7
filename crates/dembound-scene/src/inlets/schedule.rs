//! When an inlet inserts and how many (module doc of `crate::inlets`:
//! **When**, **Region capacity**): the events resolved against Δt, the
//! spheres due at each, what each inlet has inserted so far.

use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

use super::{InletRate, InletSetup, DEFAULT_EVENT_FRACTION, MAX_EVENT_FRACTION};
use crate::error::SceneError;

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
    /// Radius (m), mass (kg) and material index of every sphere placed so
    /// far, in placement order (input ids from the scene's sphere count
    /// on): what a checkpoint needs to restore them ([`super::restart`]).
    pub placed: Vec<(f64, f64, u32)>,
}

impl Inlets {
    /// The run's inlets, their schedules resolved against `dt` (s) and a
    /// run of `run_time` (s); a rate the region cannot hold refused,
    /// naming `inlet[K].rate`.
    pub fn new(
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
            placed: Vec::new(),
        })
    }

    /// The event number of inlet `k` at `step`, if it has one there
    /// (public for the deck writers, which replay the schedule).
    pub fn event_at(&self, k: usize, step: u64) -> Option<u64> {
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
    pub fn due_after(&self, k: usize, e: u64) -> u64 {
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
