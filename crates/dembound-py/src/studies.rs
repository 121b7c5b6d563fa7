//! The bounce studies: the CLI's `--json` commands, a run's trajectory and
//! the batched sweep.

use crate::errors::{guarded, usage, Failure};
use clap::Parser;
use dembound::cli::{capture_json, capture_warnings, dispatch, Cli};
use dembound::output::history::HistoryRecorder;
use dembound::scenario_file::ScenarioArgs;
use dembound_core::bounce::{simulate, simulate_batch, ContactRecord, Scenario};
use dembound_core::Error;
use numpy::{IntoPyArray, PyArray1, PyArrayMethods, PyReadonlyArray1};
use pyo3::exceptions::{PyRuntimeError, PyUserWarning};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::path::PathBuf;

/// Runs `dembound ARGV…` (a command with `--json`) in this process and
/// returns its JSON document as compact JSON text, which the Python layer
/// reads with `json.loads`: the same code as the binary, the same document
/// (serde_json writes each double as the shortest text that reads back as
/// it, and Python reads it correctly rounded, so the floats are the
/// CLI's bit for bit). Text and the C `json` module were a little faster
/// than building the objects from Rust with pythonize (10,000 sweep cases,
/// 21 MB: 1.04–1.29 s against 1.29–1.56 s including an extra parse, on a
/// loaded host). The GIL is released while it runs.
#[pyfunction]
pub fn cli_json(py: Python<'_>, argv: Vec<String>) -> PyResult<String> {
    let (text, warnings) = py.detach(|| {
        capture_warnings(|| {
            guarded(|| {
                let cli = Cli::try_parse_from(std::iter::once("dembound".to_string()).chain(argv))
                    .map_err(|e| usage(&e))?;
                capture_json(|| dispatch(&cli))
                    .map_err(Failure::from)?
                    .ok_or_else(|| Failure::Failed("the command printed no JSON document".into()))
            })
        })
    });
    // The CLI's `warning: …` lines on stderr, as Python warnings.
    for w in warnings {
        let text = std::ffi::CString::new(w.replace('\0', " "))
            .map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
        PyErr::warn(py, &py.get_type::<PyUserWarning>(), &text, 1)?;
    }
    Ok(text?)
}

/// The scenario of a file and `--set` overrides, validated (as loaded:
/// `run` and `simulate` treat an unset η as η = 1/50 alike, and
/// `Scenario::validate`, run again for every case of a batch, costs less
/// with fewer optional keys set).
fn scenario(path: Option<String>, sets: Vec<String>) -> Result<Scenario, Failure> {
    let args = ScenarioArgs {
        scenario: path.map(PathBuf::from),
        set: sets,
    };
    args.load().map_err(|e| Failure::Input(format!("{e:#}")))
}

fn simulation_failure(e: Error) -> Failure {
    match e {
        e @ Error::Input { .. } => Failure::Input(e.to_string()),
        e => Failure::Failed(format!("the run failed: {e}")),
    }
}

/// The trajectory of a run, at most `points` rows evenly decimated (as the
/// CLI's history.csv): t (s), x (m), v (m/s), a (m/s²), overlap (m),
/// force (N), in_contact (bool), each a NumPy array.
#[pyfunction]
#[pyo3(signature = (scenario, sets, points))]
pub fn history<'py>(
    py: Python<'py>,
    scenario: Option<String>,
    sets: Vec<String>,
    points: usize,
) -> PyResult<Bound<'py, PyDict>> {
    let rows = py.detach(|| {
        guarded(|| {
            let s = self::scenario(scenario, sets)?;
            let mut recorder = HistoryRecorder::new(
                points,
                HistoryRecorder::flight_samples_for(points, s.motion.contacts),
            );
            simulate(&s, &mut recorder).map_err(simulation_failure)?;
            Ok(recorder.rows().to_vec())
        })
    })?;
    let out = PyDict::new(py);
    let column =
        |f: fn(&dembound_core::bounce::Sample) -> f64| -> Vec<f64> { rows.iter().map(f).collect() };
    out.set_item("t", column(|s| s.t).into_pyarray(py))?;
    out.set_item("x", column(|s| s.x).into_pyarray(py))?;
    out.set_item("v", column(|s| s.v).into_pyarray(py))?;
    out.set_item("a", column(|s| s.a).into_pyarray(py))?;
    out.set_item("overlap", column(|s| s.overlap).into_pyarray(py))?;
    out.set_item("force", column(|s| s.force).into_pyarray(py))?;
    let in_contact: Vec<bool> = rows.iter().map(|s| s.in_contact).collect();
    out.set_item("in_contact", in_contact.into_pyarray(py))?;
    Ok(out)
}

/// A scenario key that can vary case by case in [`batch`]: (key, unit,
/// setter).
type Setter = (&'static str, &'static str, fn(&mut Scenario, f64));

const BATCH_KEYS: [Setter; 9] = [
    ("boundary.radius_ratio", "1", |s, x| {
        s.boundary.radius_ratio = x
    }),
    ("boundary.modulus_ratio", "1", |s, x| {
        s.boundary.modulus_ratio = x
    }),
    ("motion.gap", "m", |s, x| s.motion.gap = x),
    ("motion.velocity", "m/s", |s, x| s.motion.velocity = x),
    ("motion.gravity", "m/s²", |s, x| s.motion.gravity = x),
    ("particle.radius", "m", |s, x| s.particle.radius = x),
    ("particle.density", "kg/m³", |s, x| s.particle.density = x),
    ("particle.youngs_modulus", "Pa", |s, x| {
        s.particle.youngs_modulus = x
    }),
    ("particle.poisson_ratio", "1", |s, x| {
        s.particle.poisson_ratio = x
    }),
];

/// The keys [`batch`] can vary per case, with their units.
#[pyfunction]
pub fn batch_keys() -> Vec<(&'static str, &'static str)> {
    BATCH_KEYS.iter().map(|(k, u, _)| (*k, *u)).collect()
}

/// A per-contact quantity of [`batch`]'s result: (name, field).
type Quantity = (&'static str, fn(&ContactRecord) -> f64);

const BATCH_QUANTITIES: [Quantity; 11] = [
    ("t_contact", |c| c.t_contact),
    ("t_max_overlap", |c| c.t_max_overlap),
    ("t_rebound", |c| c.t_rebound),
    ("duration", |c| c.duration),
    ("max_overlap", |c| c.max_overlap),
    ("max_force", |c| c.max_force),
    ("max_acceleration", |c| c.max_acceleration),
    ("impact_velocity", |c| c.impact_velocity),
    ("rebound_velocity", |c| c.rebound_velocity),
    ("restitution", |c| c.restitution),
    ("energy_dissipated", |c| c.energy_dissipated),
];

/// Runs one scenario per row of `columns` (each a key of [`BATCH_KEYS`]
/// and a 1-D array, all of one length) over the base scenario, in SIMD
/// lanes where the scenario allows (`simulate_batch`: Gear5, event
/// stepping, elastic Hertz or linear, fixed boundary; the others one by
/// one), with the GIL released. Returns `steps` and `dt` (n,) and every
/// per-contact quantity as an (n, contacts) array, SI.
#[pyfunction]
#[pyo3(signature = (scenario, sets, columns))]
pub fn batch<'py>(
    py: Python<'py>,
    scenario: Option<String>,
    sets: Vec<String>,
    columns: Vec<(String, PyReadonlyArray1<'py, f64>)>,
) -> PyResult<Bound<'py, PyDict>> {
    let mut setters = Vec::new();
    let mut n = None;
    for (key, array) in &columns {
        let Some(&(_, _, set)) = BATCH_KEYS.iter().find(|(k, _, _)| k == key) else {
            let keys: Vec<&str> = BATCH_KEYS.iter().map(|(k, _, _)| *k).collect();
            return Err(Failure::Input(format!(
                "`{key}` cannot vary case by case in batch(); the keys that can: {}",
                keys.join(", ")
            ))
            .into());
        };
        let values = array.as_slice()?.to_vec();
        match n {
            None => n = Some(values.len()),
            Some(len) if len != values.len() => {
                return Err(Failure::Input(format!(
                    "`{key}` has {} values, the other arrays {len}: every array needs one value per case",
                    values.len()
                ))
                .into())
            }
            _ => {}
        }
        setters.push((key.clone(), set, values));
    }
    let n = n.unwrap_or(1);
    let (outcomes, contacts) = py.detach(|| {
        guarded(|| {
            let base = self::scenario(scenario, sets)?;
            let scenarios: Vec<Scenario> = (0..n)
                .map(|i| {
                    let mut s = base;
                    for (_, set, values) in &setters {
                        set(&mut s, values[i]);
                    }
                    s
                })
                .collect();
            let outcomes = simulate_batch(&scenarios);
            let contacts = base.motion.contacts as usize;
            let mut steps = Vec::with_capacity(n);
            let mut dt = Vec::with_capacity(n);
            let mut quantities = vec![vec![f64::NAN; n * contacts]; BATCH_QUANTITIES.len()];
            for (i, outcome) in outcomes.into_iter().enumerate() {
                let outcome = outcome.map_err(|e| {
                    let case: Vec<String> = setters
                        .iter()
                        .map(|(k, _, v)| format!("{k}={:?}", v[i]))
                        .collect();
                    match simulation_failure(e) {
                        Failure::Input(m) => {
                            Failure::Input(format!("case {i} ({}): {m}", case.join(", ")))
                        }
                        Failure::Failed(m) => {
                            Failure::Failed(format!("case {i} ({}): {m}", case.join(", ")))
                        }
                    }
                })?;
                steps.push(outcome.steps);
                dt.push(outcome.dt);
                for (k, c) in outcome.contacts.iter().take(contacts).enumerate() {
                    for (q, (_, field)) in quantities.iter_mut().zip(&BATCH_QUANTITIES) {
                        q[i * contacts + k] = field(c);
                    }
                }
            }
            Ok(((steps, dt, quantities), contacts))
        })
    })?;
    let (steps, dt, quantities) = outcomes;
    let out = PyDict::new(py);
    out.set_item("steps", steps.into_pyarray(py))?;
    out.set_item("dt", dt.into_pyarray(py))?;
    for ((name, _), values) in BATCH_QUANTITIES.iter().zip(quantities) {
        let array: Bound<'py, PyArray1<f64>> = values.into_pyarray(py);
        out.set_item(*name, array.reshape([n, contacts])?)?;
    }
    Ok(out)
}
