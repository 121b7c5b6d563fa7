//! Where the spheres of a scene come from: generators (a lattice, random
//! insertion), readers (LAMMPS data files, CSV) and the boundary-particle
//! walls ([`tiling`]). Each gives plain [`SourceSphere`]s; the scene file
//! ([`crate::io::config`]) attaches the material and the fixed flag.

pub mod csv;
pub mod lammps_data;
pub mod lammps_part;
pub mod lattice;
pub mod mesh_tiling;
pub mod random;
pub mod tiling;

/// One sphere as a source gives it, SI.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SourceSphere {
    /// Centre, m.
    pub position: [f64; 3],
    /// Velocity, m/s.
    pub velocity: [f64; 3],
    /// Radius, m.
    pub radius: f64,
}

impl SourceSphere {
    /// A sphere at rest.
    pub fn at_rest(position: [f64; 3], radius: f64) -> Self {
        Self {
            position,
            velocity: [0.0; 3],
            radius,
        }
    }
}

/// Squared distance between two points, m².
pub(crate) fn distance_squared(a: [f64; 3], b: [f64; 3]) -> f64 {
    (0..3).map(|k| (a[k] - b[k]) * (a[k] - b[k])).sum()
}

/// The largest data file (LAMMPS data, CSV) read, bytes: 4 GiB, some
/// 40 million atoms at ~100 bytes a line. A larger file, or an endless
/// one (`/dev/zero`), is refused instead of read until memory runs out.
pub const MAX_DATA_FILE_BYTES: u64 = 4 << 30;

/// Reads the data file `path` given by the scene key `key`: a regular
/// file (or a pipe) of at most [`MAX_DATA_FILE_BYTES`]. A missing or
/// unreadable file, a device or a directory, and a larger file are bad
/// input naming the key (the CLI exits 2).
pub fn read_data_file(path: &std::path::Path, key: &str) -> Result<Vec<u8>, crate::SceneError> {
    use std::io::Read;
    let shown = path.display();
    let refuse = |why: String| {
        Err(crate::SceneError::input(format!(
            "`{key}` = `{shown}`: {why}"
        )))
    };
    let meta = match std::fs::metadata(path) {
        Ok(m) => m,
        Err(e) => return refuse(format!("cannot read the file: {e}")),
    };
    let kind = meta.file_type();
    #[cfg(unix)]
    let pipe = std::os::unix::fs::FileTypeExt::is_fifo(&kind);
    #[cfg(not(unix))]
    let pipe = false;
    if !(kind.is_file() || pipe) {
        let what = if kind.is_dir() {
            "a directory"
        } else {
            "a device or other special file"
        };
        return refuse(format!("is {what}, not a data file (a regular file)"));
    }
    let limit = MAX_DATA_FILE_BYTES;
    let too_large = |size: u64| {
        refuse(format!(
            "the file has {size} bytes or more; at most {limit} bytes ({} GiB) are read",
            limit >> 30
        ))
    };
    if kind.is_file() && meta.len() > limit {
        return too_large(meta.len());
    }
    let file = match std::fs::File::open(path) {
        Ok(f) => f,
        Err(e) => return refuse(format!("cannot read the file: {e}")),
    };
    let mut bytes = Vec::new();
    if let Err(e) = bytes.try_reserve(if kind.is_file() {
        meta.len() as usize
    } else {
        0
    }) {
        return refuse(format!("cannot hold the file in memory: {e}"));
    }
    if let Err(e) = file.take(limit + 1).read_to_end(&mut bytes) {
        return refuse(format!("cannot read the file: {e}"));
    }
    if bytes.len() as u64 > limit {
        return too_large(bytes.len() as u64);
    }
    Ok(bytes)
}

/// The 1-based number of the last line of `text` when it does not end
/// with a line end and holds more than blanks and a `#` comment: the file
/// may have been cut inside that line (inside its last number, which then
/// still parses: `0.001045` cut to `0.0`), so the readers refuse it.
pub(crate) fn unterminated_last_line(text: &str) -> Option<usize> {
    if text.is_empty() || text.ends_with('\n') {
        return None;
    }
    let last = text.rsplit('\n').next().unwrap_or("");
    let content = last.split('#').next().unwrap_or("").trim();
    (!content.is_empty()).then(|| text.split('\n').count())
}
