//! Reading a triangle mesh from a file into a triangle soup (three
//! vertices per triangle, in file order), and the mesh's typed errors.
//!
//! - STL, binary or ASCII (`stl_io`, which stores coordinates as f32, the
//!   precision of binary STL itself). A file is binary when its length is
//!   exactly 84 + 50 N bytes with N the count in its header, else ASCII:
//!   many exporters start binary files with the word `solid`, so the word
//!   alone does not decide. An ASCII file whose first line is a bare
//!   `solid` (no name, legal) is read as `solid ` + name-less.
//! - Wavefront OBJ (`tobj`, f64 coordinates), every polygon triangulated
//!   as a fan; points and lines ignored; every object of the file read.
//!
//! No input panics: any parse failure, a truncated file, a face index out
//! of range or a non-finite coordinate is a [`MeshError`] naming the file.

use std::fmt;
use std::path::{Path, PathBuf};

/// A triangle: its three vertices (m, before any transform).
pub type Triangle = [[f64; 3]; 3];

/// Why a mesh could not be made.
#[derive(Debug, Clone, PartialEq)]
pub enum MeshError {
    /// The file could not be opened or read.
    Unreadable { file: PathBuf, reason: String },
    /// The file was read but is not a valid STL or OBJ.
    Malformed { file: PathBuf, reason: String },
    /// The file's extension is neither `.stl` nor `.obj`.
    UnknownFormat { file: PathBuf },
    /// A vertex coordinate is NaN or infinite (after the transform).
    NonFinite { file: PathBuf, triangle: usize },
    /// No triangle is left after cleaning (`read` triangles were in the
    /// file, all degenerate or duplicates, or none at all).
    Empty { file: PathBuf, read: usize },
    /// The placed mesh is too large for f64 arithmetic: a flat patch's
    /// normal or area, or the mesh's area or centroid, is not a finite
    /// number (squares of areas overflow, above ~1.8e308 m⁴).
    TooLarge { file: PathBuf },
    /// A transform value out of its range.
    Transform {
        key: &'static str,
        value: String,
        allowed: &'static str,
    },
}

impl fmt::Display for MeshError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            MeshError::Unreadable { file, reason } => {
                write!(f, "mesh file {}: cannot be read: {reason}", file.display())
            }
            MeshError::Malformed { file, reason } => {
                write!(
                    f,
                    "mesh file {}: not a valid mesh: {reason}",
                    file.display()
                )
            }
            MeshError::UnknownFormat { file } => write!(
                f,
                "mesh file {}: unknown format (allowed: .stl, binary or ASCII, and .obj)",
                file.display()
            ),
            MeshError::NonFinite { file, triangle } => write!(
                f,
                "mesh file {}: triangle {triangle} has a non-finite vertex coordinate",
                file.display()
            ),
            MeshError::Empty { file, read } => write!(
                f,
                "mesh file {}: no triangle left ({read} read, every one degenerate or a duplicate)",
                file.display()
            ),
            MeshError::TooLarge { file } => write!(
                f,
                "mesh file {}: too large for f64 arithmetic once placed: the square of a flat \
                 patch's area overflows, so its normal, area or the mesh's centroid is not a \
                 finite number (allowed: a mesh below about 1e76 m across; check the scale and \
                 the file's units)",
                file.display()
            ),
            MeshError::Transform {
                key,
                value,
                allowed,
            } => write!(f, "mesh transform: {key} = {value} (allowed: {allowed})"),
        }
    }
}

impl std::error::Error for MeshError {}

/// The mesh file's format, from its extension (case-insensitive).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Format {
    Stl,
    Obj,
}

impl Format {
    pub fn of(path: &Path) -> Option<Format> {
        let ext = path.extension()?.to_str()?.to_ascii_lowercase();
        match ext.as_str() {
            "stl" => Some(Format::Stl),
            "obj" => Some(Format::Obj),
            _ => None,
        }
    }
}

/// Reads the triangles of `path` (STL or OBJ by extension).
pub fn read_triangles(path: &Path) -> Result<Vec<Triangle>, MeshError> {
    let format = Format::of(path).ok_or_else(|| MeshError::UnknownFormat {
        file: path.to_path_buf(),
    })?;
    let bytes = std::fs::read(path).map_err(|e| MeshError::Unreadable {
        file: path.to_path_buf(),
        reason: e.to_string(),
    })?;
    let malformed = |reason: String| MeshError::Malformed {
        file: path.to_path_buf(),
        reason,
    };
    match format {
        Format::Stl => stl_triangles(&bytes).map_err(malformed),
        Format::Obj => obj_triangles(&bytes).map_err(malformed),
    }
}

/// Is `bytes` a binary STL: 80-byte header, a u32 count N, then exactly
/// N records of 50 bytes.
fn is_binary_stl(bytes: &[u8]) -> bool {
    if bytes.len() < 84 {
        return false;
    }
    let n = u32::from_le_bytes([bytes[80], bytes[81], bytes[82], bytes[83]]) as u64;
    bytes.len() as u64 == 84 + 50 * n
}

/// The triangles of an STL file's bytes.
pub fn stl_triangles(bytes: &[u8]) -> Result<Vec<Triangle>, String> {
    let owned;
    let data: &[u8] = if is_binary_stl(bytes) {
        bytes
    } else {
        // ASCII. stl_io wants "solid " with a space: a bare "solid" line
        // is legal STL, give it an empty name.
        let bare = bytes.starts_with(b"solid\n") || bytes.starts_with(b"solid\r\n");
        if bare {
            let mut v = b"solid ".to_vec();
            v.extend_from_slice(&bytes[5..]);
            owned = v;
            &owned
        } else if bytes.starts_with(b"solid ") {
            bytes
        } else {
            return Err(format!(
                "neither binary STL (length {} bytes is not 84 + 50 N) nor ASCII STL \
                 (does not start with \"solid\")",
                bytes.len()
            ));
        }
    };
    let mut cursor = std::io::Cursor::new(data);
    let mut reader = stl_io::create_stl_reader(&mut cursor).map_err(|e| e.to_string())?;
    let mut out = Vec::new();
    for t in &mut reader {
        let t = t.map_err(|e| format!("triangle {}: {e}", out.len()))?;
        out.push(t.vertices.map(|v| v.0.map(f64::from)));
    }
    Ok(out)
}

/// The triangles of an OBJ file's bytes: every object, polygons as fans.
pub fn obj_triangles(bytes: &[u8]) -> Result<Vec<Triangle>, String> {
    let options = tobj::LoadOptions {
        triangulate: true,
        single_index: false,
        ignore_points: true,
        ignore_lines: true,
    };
    let mut reader = std::io::BufReader::new(bytes);
    // Materials are not read (a wall's material is the scene's).
    let (models, _) = tobj::load_obj_buf(&mut reader, &options, |_| {
        Err(tobj::LoadError::GenericFailure)
    })
    .map_err(|e| e.to_string())?;
    let mut out = Vec::new();
    for model in &models {
        let m = &model.mesh;
        let vertex = |i: u32| -> Option<[f64; 3]> {
            let k = 3 * i as usize;
            Some([
                *m.positions.get(k)?,
                *m.positions.get(k + 1)?,
                *m.positions.get(k + 2)?,
            ])
        };
        for (f, ids) in m.indices.chunks(3).enumerate() {
            let [a, b, c] = ids else {
                return Err(format!(
                    "object {:?}: face {f} is not a triangle",
                    model.name
                ));
            };
            match (vertex(*a), vertex(*b), vertex(*c)) {
                (Some(a), Some(b), Some(c)) => out.push([a, b, c]),
                _ => {
                    return Err(format!(
                        "object {:?}: face {f} refers to a vertex that does not exist",
                        model.name
                    ))
                }
            }
        }
    }
    Ok(out)
}

/// Writes `triangles` as a binary STL (f32 coordinates, normals from the
/// vertex order): for tests and the example scripts' meshes.
pub fn write_binary_stl(path: &Path, triangles: &[Triangle]) -> std::io::Result<()> {
    let mut bytes = Vec::with_capacity(84 + 50 * triangles.len());
    let mut header = [b' '; 80];
    header[..16].copy_from_slice(b"dembound mesh   ");
    bytes.extend_from_slice(&header);
    bytes.extend_from_slice(&(triangles.len() as u32).to_le_bytes());
    for t in triangles {
        let n = unit_normal(t);
        for v in std::iter::once(&n).chain(t.iter()) {
            for c in v {
                bytes.extend_from_slice(&(*c as f32).to_le_bytes());
            }
        }
        bytes.extend_from_slice(&[0, 0]);
    }
    std::fs::write(path, bytes)
}

/// Writes `triangles` as an ASCII STL (shortest round-trip decimals of
/// the f32 coordinates, so ASCII and binary files read back the same).
pub fn write_ascii_stl(path: &Path, triangles: &[Triangle]) -> std::io::Result<()> {
    let mut s = String::from("solid dembound\n");
    let f = |v: &[f64; 3]| format!("{} {} {}", v[0] as f32, v[1] as f32, v[2] as f32);
    for t in triangles {
        s += &format!("  facet normal {}\n    outer loop\n", f(&unit_normal(t)));
        for v in t {
            s += &format!("      vertex {}\n", f(v));
        }
        s += "    endloop\n  endfacet\n";
    }
    s += "endsolid dembound\n";
    std::fs::write(path, s)
}

fn unit_normal(t: &Triangle) -> [f64; 3] {
    let n = super::geometry::cross(
        super::geometry::sub(t[1], t[0]),
        super::geometry::sub(t[2], t[0]),
    );
    let l = super::geometry::norm(n);
    if l > 0.0 {
        n.map(|c| c / l)
    } else {
        [0.0; 3]
    }
}
