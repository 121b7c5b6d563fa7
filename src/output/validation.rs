//! STUB of the validation report (Tables 1–2 and the convergence study).
//! The real module is written on another branch and replaces this file at
//! merge; only the signatures matter here.

use anyhow::Result;
use dembound_core::study::validation::{ConvergencePoint, ValidationTable};
use std::path::{Path, PathBuf};

/// Tables 1–2 as markdown (placeholder).
pub fn tables_markdown(tables: &[ValidationTable]) -> String {
    format!(
        "_Tables 1–2: {} tables computed; their markdown rendering is not on this branch yet._\n",
        tables.len()
    )
}

/// The convergence study as markdown (placeholder).
pub fn convergence_markdown(points: &[ConvergencePoint]) -> String {
    format!(
        "_Convergence in Δt: {} points computed; their markdown rendering is not on this branch yet._\n",
        points.len()
    )
}

/// The convergence figures (placeholder: none).
pub fn convergence_figures(points: &[ConvergencePoint], dir: &Path) -> Result<Vec<PathBuf>> {
    let _ = (points, dir);
    Ok(Vec::new())
}
