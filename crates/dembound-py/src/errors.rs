//! How failures reach Python: bad input is a `ValueError` with the CLI's
//! message (it names the key, the value and the allowed range), a run that
//! fails is a `RuntimeError`, and a panic, should one happen, is caught
//! here and becomes a `RuntimeError` too (never an abort or a
//! `PanicException`).

use dembound::cli::CliError;
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::PyErr;
use std::panic::{catch_unwind, AssertUnwindSafe};

/// A failure, before it is turned into a Python exception (which needs
/// the GIL).
#[derive(Debug)]
pub enum Failure {
    /// Bad input: `ValueError`.
    Input(String),
    /// A failed run: `RuntimeError`.
    Failed(String),
}

impl From<Failure> for PyErr {
    fn from(f: Failure) -> PyErr {
        match f {
            Failure::Input(msg) => PyValueError::new_err(msg),
            Failure::Failed(msg) => PyRuntimeError::new_err(msg),
        }
    }
}

impl From<CliError> for Failure {
    fn from(e: CliError) -> Failure {
        // `{:#}`: the message with its context chain, as the CLI prints it.
        let msg = format!("{:#}", e.error());
        match e {
            CliError::Input(_) => Failure::Input(msg),
            CliError::Failed(_) => Failure::Failed(msg),
        }
    }
}

/// A clap usage error as the CLI prints it, without the leading `error: `
/// and the closing hint about `--help`.
pub fn usage(e: &clap::Error) -> Failure {
    let text = e.render().to_string();
    let text = text.trim();
    let text = text.strip_prefix("error: ").unwrap_or(text);
    let text = match text.find("\n\nFor more information") {
        Some(i) => &text[..i],
        None => text,
    };
    let text = match text.find("\n\nUsage:") {
        Some(i) => &text[..i],
        None => text,
    };
    Failure::Input(text.trim().to_string())
}

/// Runs `f`, turning a panic into [`Failure::Failed`]. The last line of
/// defence: inputs are validated before anything runs.
pub fn guarded<T>(f: impl FnOnce() -> Result<T, Failure>) -> Result<T, Failure> {
    match catch_unwind(AssertUnwindSafe(f)) {
        Ok(result) => result,
        Err(panic) => {
            let what = panic
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| panic.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "unknown panic".into());
            Err(Failure::Failed(format!(
                "internal error in dembound (please report it): {what}"
            )))
        }
    }
}
