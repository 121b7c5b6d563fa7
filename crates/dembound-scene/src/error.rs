//! The one error type of the crate.

use std::fmt;
use std::path::PathBuf;

/// Why building or running a scene failed.
#[derive(Debug)]
pub enum SceneError {
    /// Bad input: a scene-file key, a value out of range, a malformed data
    /// file. The message names the key or the file and line, the value and
    /// what is allowed (the CLI exits 2).
    Input(String),
    /// A file that could not be read or written.
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
}

impl SceneError {
    /// Bad input with this message.
    pub fn input(message: impl Into<String>) -> Self {
        SceneError::Input(message.into())
    }

    /// An I/O error on `path`.
    pub fn io(path: impl Into<PathBuf>, source: std::io::Error) -> Self {
        SceneError::Io {
            path: path.into(),
            source,
        }
    }

    /// Whether the error is the user's input (exit 2) rather than a failure.
    pub fn is_input(&self) -> bool {
        matches!(self, SceneError::Input(_))
    }
}

impl fmt::Display for SceneError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SceneError::Input(message) => f.write_str(message),
            SceneError::Io { path, source } => write!(f, "`{}`: {source}", path.display()),
        }
    }
}

impl std::error::Error for SceneError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            SceneError::Io { source, .. } => Some(source),
            SceneError::Input(_) => None,
        }
    }
}
