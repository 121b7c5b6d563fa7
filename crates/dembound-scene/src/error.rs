//! The crate's one error type.

use std::fmt;

/// Why a scene cannot be built or restored. The message names the field,
/// the value and the allowed range.
#[derive(Debug, Clone, PartialEq)]
pub enum SceneError {
    /// A setup value out of its allowed range.
    Invalid {
        /// The field, as a path (`spheres[3].radius`, `integration.dt`).
        key: String,
        /// The offending value, printed.
        value: String,
        /// What is allowed.
        allowed: String,
    },
    /// A checkpoint that does not fit the setup.
    Checkpoint(String),
    /// The thread pool could not be built.
    Threads(String),
    /// Bad input found by the scene file and the particle sources
    /// (`io`, `sources`): the message names the key or the file and
    /// line, the value and what is allowed.
    Input(String),
    /// The run blew up: a body's position, velocity or spin is no longer
    /// finite after `step` (the time step is too large for the contacts;
    /// input: the CLI exits 2).
    Unstable {
        /// The step after which the state was found not finite.
        step: u64,
        /// Its time, s.
        time: f64,
        /// The time step, s.
        dt: f64,
        /// The integration scheme (`verlet`, `gear5`).
        scheme: String,
        /// Inputs far out of range, blamed before the step when any
        /// (`energy_guard`).
        extreme_inputs: Vec<String>,
    },
    /// A file that could not be read or written.
    Io {
        path: std::path::PathBuf,
        message: String,
    },
}

impl SceneError {
    pub(crate) fn invalid(
        key: impl Into<String>,
        value: impl fmt::Display,
        allowed: impl Into<String>,
    ) -> Self {
        SceneError::Invalid {
            key: key.into(),
            value: value.to_string(),
            allowed: allowed.into(),
        }
    }
}

impl SceneError {
    /// Bad input with this message (`io`, `sources`).
    pub fn input(message: impl Into<String>) -> Self {
        SceneError::Input(message.into())
    }

    /// An I/O error on `path`.
    pub fn io(path: impl Into<std::path::PathBuf>, source: std::io::Error) -> Self {
        SceneError::Io {
            path: path.into(),
            message: source.to_string(),
        }
    }

    /// Whether the user's input is at fault (the CLI exits 2) rather than
    /// the machine (threads, files: exit 1).
    pub fn is_input(&self) -> bool {
        matches!(
            self,
            SceneError::Invalid { .. }
                | SceneError::Checkpoint(_)
                | SceneError::Input(_)
                | SceneError::Unstable { .. }
        )
    }
}

impl fmt::Display for SceneError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SceneError::Invalid {
                key,
                value,
                allowed,
            } => {
                write!(f, "{key} = {value} is out of range: {allowed}")
            }
            SceneError::Checkpoint(why) => write!(f, "checkpoint does not fit the scene: {why}"),
            SceneError::Threads(why) => write!(f, "cannot start the worker threads: {why}"),
            SceneError::Input(message) => f.write_str(message),
            SceneError::Unstable {
                step,
                time,
                dt,
                scheme,
                extreme_inputs,
            } if !extreme_inputs.is_empty() => write!(
                f,
                "the run became unstable by step {step} (t = {time:.6e} s, Δt = {dt:e} s, \
                 {scheme}): a position, velocity or spin is no longer finite; likely cause: an \
                 extreme input ({}), not the step",
                extreme_inputs.join("; ")
            ),
            SceneError::Unstable {
                step,
                time,
                dt,
                scheme,
                ..
            } => write!(
                f,
                "integration.dt = {dt:e} s is too large for this scene ({scheme}): the run became \
                 unstable by step {step} (t = {time:.6e} s), a position, velocity or spin is no \
                 longer finite; allowed: a smaller step (integration.dt or integration.eta){}",
                if scheme == "gear5" {
                    ", or scheme = \"verlet\" (its stable steps are several times longer than Gear5's)"
                } else {
                    ""
                }
            ),
            SceneError::Io { path, message } => write!(f, "`{}`: {message}", path.display()),
        }
    }
}

impl std::error::Error for SceneError {}
