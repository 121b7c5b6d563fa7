//! Yade script (placeholder until written).
use crate::plan::Plan;
use crate::ExportError;

pub fn deck(_plan: &Plan) -> Result<String, ExportError> {
    Err(ExportError("yade export is not written yet".into()))
}
