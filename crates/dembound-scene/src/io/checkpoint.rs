//! Checkpoint files: the engine's whole state ([`Checkpoint`]) and the
//! resolved scene it belongs to, in CBOR (`ciborium`: binary, every f64
//! kept bit for bit, so a restart continues exactly as the run would
//! have). A restart rebuilds the scene from a scene file and refuses a
//! checkpoint whose bodies or Δt do not match it.

use super::config::SceneFile;
use crate::simulation::Checkpoint;
use crate::SceneError;
use serde::{Deserialize, Serialize};
use std::io::{Read, Write};
use std::path::Path;

/// What identifies a dembound scene checkpoint.
pub const FORMAT: &str = "dembound-scene checkpoint";
/// Bumped whenever [`CheckpointFile`] or [`Checkpoint`] changes shape.
pub const VERSION: u32 = 1;

/// The file's content.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CheckpointFile {
    pub format: String,
    pub version: u32,
    /// The resolved scene of the run (for the record; a restart takes the
    /// scene file it is given).
    pub scene: SceneFile,
    pub state: Checkpoint,
}

impl CheckpointFile {
    pub fn new(scene: SceneFile, state: Checkpoint) -> Self {
        Self {
            format: FORMAT.into(),
            version: VERSION,
            scene,
            state,
        }
    }
}

/// Writes `file` as CBOR.
pub fn write(w: &mut dyn Write, file: &CheckpointFile) -> Result<(), String> {
    ciborium::into_writer(file, w).map_err(|e| e.to_string())
}

/// Reads a checkpoint from `reader`; `name` is named in errors.
pub fn read_from(reader: impl Read, name: &str) -> Result<CheckpointFile, SceneError> {
    let file: CheckpointFile = ciborium::from_reader(reader).map_err(|e| {
        SceneError::input(format!("`{name}` is not a dembound scene checkpoint: {e}"))
    })?;
    if file.format != FORMAT || file.version != VERSION {
        return Err(SceneError::input(format!(
            "`{name}`: format \"{}\" version {}, expected \"{FORMAT}\" version {VERSION}",
            file.format, file.version
        )));
    }
    Ok(file)
}

/// Reads the checkpoint file `path`.
pub fn read(path: &Path) -> Result<CheckpointFile, SceneError> {
    let f = std::fs::File::open(path).map_err(|e| SceneError::io(path, e))?;
    read_from(std::io::BufReader::new(f), &path.display().to_string())
}
