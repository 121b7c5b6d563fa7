//! `Scene.add_inlet` and `Scene.add_outlet` (issue 28): an `[[inlet]]` or
//! `[[outlet]]` added from Python before the first step, its arguments the
//! scene file's keys (a dict per table), checked by the scene file's own
//! validation, so a bad value is a `ValueError` naming the argument, the
//! value and the allowed range.

use super::Scene;
use crate::errors::Failure;
use dembound_scene::io::config::{InletSection, Particles, Region};

/// The arguments of `add_inlet`, in the order of its signature.
pub(super) const INLET_ARGUMENTS: [&str; 10] = [
    "region",
    "rate",
    "size",
    "material",
    "velocity",
    "start",
    "end",
    "seed",
    "every",
    "max_attempts",
];

/// `what` read from `table` (the arguments as a TOML table), a
/// deserialisation error naming the argument's key path.
fn read<T: serde::de::DeserializeOwned>(call: &str, table: toml::Table) -> Result<T, Failure> {
    serde_path_to_error::deserialize(toml::Value::Table(table)).map_err(|e| {
        let path = e.path().to_string();
        let inner = e.inner().to_string();
        let argument = path.split(['.', '[']).next().unwrap_or("");
        if argument.is_empty() || argument == "." {
            Failure::Input(format!("{call}: {}", inner.trim_end()))
        } else {
            Failure::Input(format!(
                "{call}: argument `{argument}`: `{path}`: {}",
                inner.trim_end()
            ))
        }
    })
}

/// The message of a validation error of entry `entry` (e.g. `inlet[2]`)
/// led by the argument it names (`inlet[2].rate.number` → `rate`).
fn named(call: &str, entry: &str, message: String, arguments: &[&str]) -> Failure {
    let prefix = format!("{entry}.");
    let argument = message.find(&prefix).and_then(|i| {
        let rest = &message[i + prefix.len()..];
        arguments
            .iter()
            .filter(|a| rest.starts_with(**a))
            .max_by_key(|a| a.len())
    });
    match argument {
        Some(a) => Failure::Input(format!("{call}: argument `{a}`: {message}")),
        None => Failure::Input(format!("{call}: {message}")),
    }
}

impl Scene {
    /// Adds the inlet of `table` (its keys `INLET_ARGUMENTS`): validated
    /// with the scene, appended to the file and the setup, the simulation
    /// rebuilt; on any error nothing changes.
    pub(super) fn add_inlet_table(&mut self, table: toml::Table) -> Result<(), Failure> {
        let section: InletSection = read("add_inlet", table)?;
        let k = self.file.inlets.len();
        let entry = format!("inlet[{k}]");
        let mut file = self.file.clone();
        file.inlets.push(section);
        file.validate_with(Particles::Later)
            .map_err(|e| named("add_inlet", &entry, e.to_string(), &INLET_ARGUMENTS))?;
        // The file's materials come first in the setup, in file order
        // (`resolve`); the name is known (validated).
        let material = file
            .materials
            .iter()
            .position(|m| m.name == file.inlets[k].material)
            .unwrap_or(0);
        let setup = file.inlet_setup(k, material);
        let (old_file, before) = (
            std::mem::replace(&mut self.file, file),
            self.setup.inlets.len(),
        );
        self.setup.inlets.push(setup);
        if let Err(e) = self.rebuild("add_inlet") {
            self.setup.inlets.truncate(before);
            self.file = old_file;
            return Err(match e {
                Failure::Input(m) => named("add_inlet", &entry, m, &INLET_ARGUMENTS),
                other => other,
            });
        }
        Ok(())
    }

    /// Adds the outlet of region `table` (`{ box = … }` or `{ cylinder =
    /// … }`): validated, appended, the simulation rebuilt; on any error
    /// nothing changes.
    pub(super) fn add_outlet_table(&mut self, table: toml::Table) -> Result<(), Failure> {
        #[derive(serde::Deserialize)]
        #[serde(deny_unknown_fields)]
        struct Arguments {
            region: Region,
        }
        let Arguments { region } = read("add_outlet", table)?;
        region
            .validate("region")
            .map_err(|e| Failure::Input(format!("add_outlet: argument `region`: {e}")))?;
        self.file
            .outlets
            .push(dembound_scene::io::config::OutletSection { region });
        self.setup.outlets.push(region.normalized());
        if let Err(e) = self.rebuild("add_outlet") {
            self.file.outlets.pop();
            self.setup.outlets.pop();
            return Err(e);
        }
        Ok(())
    }
}

/// A scene runs once it has spheres or an inlet that brings them.
pub(super) fn runnable(setup: &dembound_scene::setup::SceneSetup) -> bool {
    !setup.spheres.is_empty() || !setup.inlets.is_empty()
}

/// The arguments given (not None) as a dict with the scene file's
/// structure.
pub(super) fn arguments<'py>(
    py: pyo3::Python<'py>,
    given: &[(&str, Option<&pyo3::Bound<'py, pyo3::PyAny>>)],
) -> pyo3::PyResult<pyo3::Bound<'py, pyo3::types::PyDict>> {
    use pyo3::types::{PyAnyMethods, PyDictMethods};
    let d = pyo3::types::PyDict::new(py);
    for (name, value) in given {
        if let Some(v) = value.filter(|v| !v.is_none()) {
            d.set_item(*name, v)?;
        }
    }
    Ok(d)
}
