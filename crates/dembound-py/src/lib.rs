//! Python bindings of dembound (`import dembound`; the package's Python
//! layer is `python/dembound/__init__.py`, this is its `dembound._native`).
//!
//! - `studies`: the CLI's commands with `--json` (run, exact, validate,
//!   sweep, recommend, restitution, scene), captured as values from the
//!   very code the binary runs, so the same documents bit for bit; the
//!   trajectory of a run and a batched SIMD sweep as NumPy arrays.
//! - `scene`: the many-particle engine as the `Scene` class.
//! - `args`, `dict`: arguments and scene dicts checked by hand, so that
//!   any bad value (None, bytes, NumPy scalars and arrays of any dtype,
//!   negative or huge integers, deep nesting) is a `ValueError` naming
//!   the argument or key.
//! - `errors`: bad input → `ValueError`, a failed run → `RuntimeError`;
//!   every call runs inside `catch_unwind`, so no panic reaches Python.
//!
//! Every call that computes releases the GIL.

mod args;
mod dict;
mod errors;
mod scene;
mod studies;

use pyo3::prelude::*;

#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(studies::cli_json, m)?)?;
    m.add_function(wrap_pyfunction!(studies::history, m)?)?;
    m.add_function(wrap_pyfunction!(studies::batch, m)?)?;
    m.add_function(wrap_pyfunction!(studies::batch_keys, m)?)?;
    m.add_class::<scene::Scene>()?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
