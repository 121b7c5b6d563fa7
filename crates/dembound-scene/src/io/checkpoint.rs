//! Checkpoint files: the engine's whole state ([`Checkpoint`], with the
//! [`Fingerprint`](crate::fingerprint::Fingerprint) of the scene that
//! wrote it) and the resolved scene file, in CBOR (`ciborium`: binary,
//! every f64 kept bit for bit, so a restart continues exactly as the run
//! would have).
//!
//! The file is [`MAGIC`], the format version (u32, little-endian), the
//! payload (the CBOR of [`CheckpointFile`]), then the payload's length
//! (u64, little-endian) and its SHA-256 (the payload is streamed to the
//! file and hashed on the way, never held twice in memory). A file whose
//! checksum or length does not
//! match is refused before anything in it is used: any change to its
//! bytes (a flipped bit, a cut) is an error, never a different run. A
//! restart also refuses a scene whose fingerprint or Δt differs from the
//! checkpoint's (`Simulation::restore`), and a run length shorter than
//! the steps the checkpoint has done ([`check_run_length`]).

use super::config::SceneFile;
use crate::setup::{RunLength, SceneSetup};
use crate::simulation::Checkpoint;
use crate::SceneError;
use serde::{Deserialize, Serialize};
use sha2::{Digest, Sha256};
use std::io::{Read, Write};
use std::path::Path;

/// What identifies a dembound scene checkpoint.
pub const FORMAT: &str = "dembound-scene checkpoint";
/// The first bytes of a checkpoint file (version 2 on).
pub const MAGIC: &[u8] = b"dembound-scene checkpoint\n";
/// Bumped whenever the file layout, [`CheckpointFile`] or [`Checkpoint`]
/// changes shape. 2: checksum and scene fingerprint. 3: the completed
/// collisions in columns of fixed-width values rather than a map a row
/// (`simulation::collision_columns`). 4: the collision log's tracks in
/// columns likewise (`simulation::keyed_columns`).
pub const VERSION: u32 = 4;
/// The versions this dembound reads (2's collisions are read as rows, 2's
/// and 3's tracks as triples).
pub const READS: [u32; 3] = [2, 3, VERSION];
/// Bytes before the payload: magic, version.
const HEADER: usize = MAGIC.len() + 4;
/// Bytes after the payload: its length and SHA-256.
const TRAILER: usize = 8 + 32;

/// The file's content.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CheckpointFile {
    pub format: String,
    pub version: u32,
    /// The resolved scene of the run (for the record; a restart takes the
    /// scene file it is given).
    pub scene: SceneFile,
    pub state: Checkpoint,
    /// A checkpoint written in parts (format [`super::checkpoint_parts::FORMAT_PARTS`]):
    /// its parts, `state` holding the run's shared figures and no bodies.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub parts: Option<super::checkpoint_parts::PartsIndex>,
}

impl CheckpointFile {
    pub fn new(scene: SceneFile, state: Checkpoint) -> Self {
        Self {
            format: FORMAT.into(),
            version: VERSION,
            scene,
            state,
            parts: None,
        }
    }
}

/// Writes `file`: header, CBOR payload, length and checksum.
pub fn write(w: &mut dyn Write, file: &CheckpointFile) -> Result<(), String> {
    write_plain(w, file)
}

/// [`write`], returning the SHA-256 of every byte written (the whole
/// file's).
pub fn write_hashed(w: &mut dyn Write, file: &CheckpointFile) -> Result<[u8; 32], String> {
    let mut whole = Hashing {
        inner: w,
        hash: Sha256::new(),
        length: 0,
    };
    write_plain(&mut whole, file)?;
    Ok(whole.hash.finalize().into())
}

fn write_plain(w: &mut dyn Write, file: &CheckpointFile) -> Result<(), String> {
    let fail = |e: std::io::Error| e.to_string();
    w.write_all(MAGIC).map_err(fail)?;
    w.write_all(&VERSION.to_le_bytes()).map_err(fail)?;
    let mut hashed = Hashing {
        inner: w,
        hash: Sha256::new(),
        length: 0,
    };
    ciborium::into_writer(file, &mut hashed).map_err(|e| e.to_string())?;
    let (length, digest) = (hashed.length, hashed.hash.finalize());
    w.write_all(&length.to_le_bytes()).map_err(fail)?;
    w.write_all(&digest).map_err(fail)
}

/// Passes bytes on to `inner`, hashing and counting them.
struct Hashing<'a> {
    inner: &'a mut dyn Write,
    hash: Sha256,
    length: u64,
}

impl Write for Hashing<'_> {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        let n = self.inner.write(buf)?;
        self.hash.update(&buf[..n]);
        self.length += n as u64;
        Ok(n)
    }

    fn flush(&mut self) -> std::io::Result<()> {
        self.inner.flush()
    }
}

/// The version-1 file (before checksums), to say what an old file is.
#[derive(Deserialize)]
struct LegacyHeader {
    format: String,
    version: u32,
}

/// Reads a checkpoint from `reader`; `name` is named in errors.
pub fn read_from(mut reader: impl Read, name: &str) -> Result<CheckpointFile, SceneError> {
    let mut bytes = Vec::new();
    reader
        .read_to_end(&mut bytes)
        .map_err(|e| SceneError::input(format!("`{name}`: cannot read the checkpoint: {e}")))?;
    decode(&bytes, name)
}

/// Checks and decodes the bytes of a checkpoint file.
fn decode(bytes: &[u8], name: &str) -> Result<CheckpointFile, SceneError> {
    let refuse = |why: String| Err(SceneError::input(format!("`{name}`: {why}")));
    if !bytes.starts_with(MAGIC) {
        if let Ok(old) = ciborium::from_reader::<LegacyHeader, _>(bytes) {
            if old.format == FORMAT {
                return refuse(format!(
                    "a dembound scene checkpoint of format version {}, this dembound reads \
                     versions 2 to {VERSION} (with a checksum and the scene's fingerprint): run \
                     the scene again to write a new checkpoint",
                    old.version
                ));
            }
        }
        return refuse(
            "not a dembound scene checkpoint (its first bytes are not the format's)".into(),
        );
    }
    if bytes.len() < HEADER + TRAILER {
        return refuse(format!(
            "the checkpoint is cut short: {} bytes, its header and trailer alone have {}",
            bytes.len(),
            HEADER + TRAILER
        ));
    }
    let at = MAGIC.len();
    let version = u32::from_le_bytes(bytes[at..at + 4].try_into().unwrap_or([0; 4]));
    if !READS.contains(&version) {
        return refuse(format!(
            "checkpoint format version {version}, this dembound reads versions 2 to {VERSION}"
        ));
    }
    let end = bytes.len() - TRAILER;
    let payload = &bytes[HEADER..end];
    let length = u64::from_le_bytes(bytes[end..end + 8].try_into().unwrap_or([0; 8]));
    if length != payload.len() as u64 {
        return refuse(format!(
            "the checkpoint is damaged or cut: its trailer says {length} bytes of data, the \
             file holds {}",
            payload.len()
        ));
    }
    if Sha256::digest(payload).as_slice() != &bytes[end + 8..] {
        return refuse(
            "the checkpoint is damaged: its SHA-256 checksum does not match its content".into(),
        );
    }
    let file: CheckpointFile = ciborium::from_reader(payload).map_err(|e| {
        // A check of the content's own (the collision columns') says why
        // in words; ciborium's other errors print as they are.
        let why = match e {
            ciborium::de::Error::Semantic(_, why) => why,
            e => e.to_string(),
        };
        SceneError::input(format!(
            "`{name}` is not a dembound scene checkpoint: {why}"
        ))
    })?;
    let parts = super::checkpoint_parts::FORMAT_PARTS;
    if (file.format != FORMAT && file.format != parts)
        || file.version != version
        || (file.format == parts) != file.parts.is_some()
    {
        return refuse(format!(
            "format \"{}\" version {}, expected \"{FORMAT}\" version {version} (its header's)",
            file.format, file.version
        ));
    }
    Ok(file)
}

/// Reads the checkpoint file `path` (a regular file), a whole checkpoint
/// (an index of one written in parts is refused by name: read it with
/// [`super::checkpoint_parts::read_whole`]).
pub fn read(path: &Path) -> Result<CheckpointFile, SceneError> {
    let file = read_any(path)?;
    if file.parts.is_some() {
        return Err(SceneError::input(format!(
            "`{}` is the index of a checkpoint written in parts (`[parallel] \
             checkpoint_per_rank = true`): continue it with `dembound scene --restart`",
            path.display()
        )));
    }
    Ok(file)
}

/// Reads the checkpoint file `path` (a regular file): a whole checkpoint
/// or the index of one written in parts.
pub fn read_any(path: &Path) -> Result<CheckpointFile, SceneError> {
    // A missing or unreadable checkpoint is the user's input (exit 2).
    let meta = std::fs::metadata(path).map_err(|e| {
        SceneError::input(format!(
            "`{}`: cannot read the checkpoint: {e}",
            path.display()
        ))
    })?;
    if !meta.is_file() {
        return Err(SceneError::input(format!(
            "`{}` is not a regular file: a checkpoint is a file written by --out",
            path.display()
        )));
    }
    let bytes = std::fs::read(path).map_err(|e| SceneError::io(path, e))?;
    decode(&bytes, &path.display().to_string())
}

/// Refuses a restart whose run length (`integration.steps`, or
/// `integration.duration` / Δt) ends before the `done` steps of the
/// checkpoint: it would run nothing.
pub fn check_run_length(setup: &SceneSetup, total: u64, done: u64) -> Result<(), SceneError> {
    if total >= done {
        return Ok(());
    }
    let (key, value) = match setup.integration.length {
        RunLength::Steps(s) => ("integration.steps", s.to_string()),
        RunLength::Duration(t) => ("integration.duration", format!("{t} s ({total} steps)")),
    };
    Err(SceneError::Invalid {
        key: key.into(),
        value,
        allowed: format!(
            "at least the {done} steps the checkpoint has done (a restart continues the run to \
             its end: raise {key} to go on)"
        ),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_version_1_file_is_named_as_such() {
        // Version 1 was the bare CBOR of the file struct.
        let mut old = Vec::new();
        let header = std::collections::BTreeMap::from([
            ("format", ciborium::Value::Text(FORMAT.into())),
            ("version", ciborium::Value::Integer(1.into())),
        ]);
        ciborium::into_writer(&header, &mut old).unwrap();
        let e = decode(&old, "old.cbor").unwrap_err().to_string();
        assert!(
            e.contains("version 1") && e.contains("versions 2 to 4"),
            "{e}"
        );
        let e = decode(b"hello", "x").unwrap_err().to_string();
        assert!(e.contains("not a dembound scene checkpoint"), "{e}");
    }
}
