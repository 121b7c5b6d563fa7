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
        }
    }
}

impl std::error::Error for SceneError {}
