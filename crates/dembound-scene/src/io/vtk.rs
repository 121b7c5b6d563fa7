//! VTK XML PolyData snapshots (`.vtp`) and their `.pvd` series, for
//! ParaView: one vertex per sphere with its radius, velocity, force, fixed
//! flag, material index and input index as point data.
//!
//! A small writer rather than a crate: the format needed here is a dozen
//! lines of XML around base64 arrays (`format="binary"`, `UInt64` header,
//! little-endian, uncompressed), and the `base64` crate does the encoding.
//! Arrays are in input order, so snapshots of the same run compare and
//! diff cleanly.

use base64::engine::general_purpose::STANDARD;
use base64::Engine;
use std::io::{self, Write};

/// One snapshot of every sphere, input order, SI.
#[derive(Debug, Clone, Copy)]
pub struct Snapshot<'a> {
    /// s.
    pub time: f64,
    pub step: u64,
    /// m.
    pub positions: &'a [[f64; 3]],
    /// m.
    pub radii: &'a [f64],
    /// m/s.
    pub velocities: &'a [[f64; 3]],
    /// N (contact forces; on a boundary particle, the force the particles
    /// exert on it).
    pub forces: &'a [[f64; 3]],
    pub fixed: &'a [bool],
    /// Index into the scene's material list.
    pub materials: &'a [usize],
    /// rad/s (issue 13; all 0 without friction).
    pub angular_velocities: &'a [[f64; 3]],
}

pub(crate) fn array(
    w: &mut dyn Write,
    name: &str,
    kind: &str,
    components: usize,
    bytes: &[u8],
) -> io::Result<()> {
    let mut block = Vec::with_capacity(8 + bytes.len());
    block.extend_from_slice(&(bytes.len() as u64).to_le_bytes());
    block.extend_from_slice(bytes);
    let comps = if components > 1 {
        format!(" NumberOfComponents=\"{components}\"")
    } else {
        String::new()
    };
    writeln!(
        w,
        "        <DataArray type=\"{kind}\" Name=\"{name}\"{comps} format=\"binary\">{}</DataArray>",
        STANDARD.encode(&block)
    )
}

pub(crate) fn f64s<'a>(values: impl Iterator<Item = &'a f64>) -> Vec<u8> {
    values.flat_map(|x| x.to_le_bytes()).collect()
}

pub(crate) fn vectors(values: &[[f64; 3]]) -> Vec<u8> {
    f64s(values.iter().flatten())
}

/// Writes the snapshot of `sim`'s current state (every per-sphere array
/// of [`Snapshot`], in input order): what the CLI and the bindings write.
pub fn write_simulation(w: &mut dyn Write, sim: &crate::Simulation) -> io::Result<()> {
    let (positions, velocities, forces) = (sim.positions(), sim.velocities(), sim.forces());
    let (radii, fixed, materials) = (sim.radii(), sim.fixed(), sim.material_indices());
    let spins = sim.angular_velocities();
    write_snapshot(
        w,
        &Snapshot {
            time: sim.time(),
            step: sim.steps_done(),
            positions: &positions,
            radii: &radii,
            velocities: &velocities,
            forces: &forces,
            fixed: &fixed,
            materials: &materials,
            angular_velocities: &spins,
        },
    )
}

/// Writes one `.vtp` file (the `id` of point k is k: input order).
pub fn write_snapshot(w: &mut dyn Write, s: &Snapshot) -> io::Result<()> {
    write_polydata(w, s, None)
}

/// Writes one MPI rank's piece of a snapshot (a `.vtp` file of the
/// spheres it owns, listed by a `.pvtp` index, [`write_parallel_index`]):
/// `ids`, the input index of each sphere of `s`, fill the `id` array.
pub fn write_piece(w: &mut dyn Write, s: &Snapshot, ids: &[u64]) -> io::Result<()> {
    if ids.len() != s.positions.len() {
        return Err(io::Error::other(format!(
            "{} ids for {} spheres",
            ids.len(),
            s.positions.len()
        )));
    }
    write_polydata(w, s, Some(ids))
}

/// The point arrays of a snapshot, in the order written: (name, VTK
/// type, components). `position` is the points' array.
const POINT_ARRAYS: [(&str, &str, usize); 8] = [
    ("position", "Float64", 3),
    ("radius", "Float64", 1),
    ("velocity", "Float64", 3),
    ("force", "Float64", 3),
    ("angular_velocity", "Float64", 3),
    ("fixed", "UInt8", 1),
    ("material", "Int32", 1),
    ("id", "Int64", 1),
];

/// Writes the `.pvtp` index of one snapshot written in pieces: the
/// arrays of [`write_piece`] and each piece's file (`pieces`, relative
/// to the index), as VTK's XML parallel PolyData format (`PPolyData`)
/// has them.
pub fn write_parallel_index(w: &mut dyn Write, pieces: &[String]) -> io::Result<()> {
    let declare = |w: &mut dyn Write, (name, kind, components): (&str, &str, usize)| {
        let comps = if components > 1 {
            format!(" NumberOfComponents=\"{components}\"")
        } else {
            String::new()
        };
        writeln!(
            w,
            "      <PDataArray type=\"{kind}\" Name=\"{name}\"{comps}/>"
        )
    };
    writeln!(w, "<?xml version=\"1.0\"?>")?;
    writeln!(
        w,
        "<VTKFile type=\"PPolyData\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">"
    )?;
    writeln!(w, "  <PPolyData GhostLevel=\"0\">")?;
    writeln!(w, "    <PPoints>")?;
    declare(w, POINT_ARRAYS[0])?;
    writeln!(w, "    </PPoints>")?;
    writeln!(
        w,
        "    <PPointData Scalars=\"radius\" Vectors=\"velocity\">"
    )?;
    for a in &POINT_ARRAYS[1..] {
        declare(w, *a)?;
    }
    writeln!(w, "    </PPointData>")?;
    for p in pieces {
        writeln!(w, "    <Piece Source=\"{}\"/>", xml_attribute(p))?;
    }
    writeln!(w, "  </PPolyData>")?;
    writeln!(w, "</VTKFile>")
}

/// `text` with XML's special characters escaped, for an attribute value.
pub(crate) fn xml_attribute(text: &str) -> String {
    text.replace('&', "&amp;")
        .replace('"', "&quot;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}

/// A `.vtp` file of `s`; `ids`: the `id` array (`None`: 0..n).
fn write_polydata(w: &mut dyn Write, s: &Snapshot, ids: Option<&[u64]>) -> io::Result<()> {
    let n = s.positions.len();
    writeln!(w, "<?xml version=\"1.0\"?>")?;
    writeln!(
        w,
        "<VTKFile type=\"PolyData\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">"
    )?;
    writeln!(w, "  <PolyData>")?;
    writeln!(w, "    <FieldData>")?;
    array(w, "TIME", "Float64", 1, &s.time.to_le_bytes())
        .and_then(|_| array(w, "STEP", "UInt64", 1, &s.step.to_le_bytes()))?;
    writeln!(w, "    </FieldData>")?;
    writeln!(
        w,
        "    <Piece NumberOfPoints=\"{n}\" NumberOfVerts=\"{n}\" NumberOfLines=\"0\" NumberOfStrips=\"0\" NumberOfPolys=\"0\">"
    )?;
    writeln!(w, "      <Points>")?;
    array(w, "position", "Float64", 3, &vectors(s.positions))?;
    writeln!(w, "      </Points>")?;
    writeln!(
        w,
        "      <PointData Scalars=\"radius\" Vectors=\"velocity\">"
    )?;
    array(w, "radius", "Float64", 1, &f64s(s.radii.iter()))?;
    array(w, "velocity", "Float64", 3, &vectors(s.velocities))?;
    array(w, "force", "Float64", 3, &vectors(s.forces))?;
    array(
        w,
        "angular_velocity",
        "Float64",
        3,
        &vectors(s.angular_velocities),
    )?;
    let fixed: Vec<u8> = s.fixed.iter().map(|f| u8::from(*f)).collect();
    array(w, "fixed", "UInt8", 1, &fixed)?;
    let materials: Vec<u8> = s
        .materials
        .iter()
        .flat_map(|m| (*m as i32).to_le_bytes())
        .collect();
    array(w, "material", "Int32", 1, &materials)?;
    let points: Vec<u8> = (0..n as i64).flat_map(|i| i.to_le_bytes()).collect();
    let ids =
        ids.map(|ids| -> Vec<u8> { ids.iter().flat_map(|&i| (i as i64).to_le_bytes()).collect() });
    array(w, "id", "Int64", 1, ids.as_deref().unwrap_or(&points))?;
    writeln!(w, "      </PointData>")?;
    // One vertex cell per point, so that ParaView draws them as they are.
    writeln!(w, "      <Verts>")?;
    array(w, "connectivity", "Int64", 1, &points)?;
    let offsets: Vec<u8> = (1..=n as i64).flat_map(|i| i.to_le_bytes()).collect();
    array(w, "offsets", "Int64", 1, &offsets)?;
    writeln!(w, "      </Verts>")?;
    writeln!(w, "    </Piece>")?;
    writeln!(w, "  </PolyData>")?;
    writeln!(w, "</VTKFile>")
}

/// Writes the `.pvd` collection of `(time in s, file name)` entries, all
/// part 0 (the spheres).
pub fn write_series(w: &mut dyn Write, entries: &[(f64, String)]) -> io::Result<()> {
    let parts: Vec<(f64, String, usize)> =
        entries.iter().map(|(t, f)| (*t, f.clone(), 0)).collect();
    write_series_parts(w, &parts)
}

/// Writes the `.pvd` collection of `(time in s, file name, part)` entries
/// (part 0: the spheres; part K + 1: mesh wall K, `io::vtk_walls`).
pub fn write_series_parts(w: &mut dyn Write, entries: &[(f64, String, usize)]) -> io::Result<()> {
    writeln!(w, "<?xml version=\"1.0\"?>")?;
    writeln!(
        w,
        "<VTKFile type=\"Collection\" version=\"1.0\" byte_order=\"LittleEndian\">"
    )?;
    writeln!(w, "  <Collection>")?;
    for (t, file, part) in entries {
        writeln!(
            w,
            "    <DataSet timestep=\"{t:e}\" group=\"\" part=\"{part}\" file=\"{file}\"/>"
        )?;
    }
    writeln!(w, "  </Collection>")?;
    writeln!(w, "</VTKFile>")
}

/// The file name of snapshot number `k`.
pub fn snapshot_name(k: usize) -> String {
    format!("snapshot_{k:06}.vtp")
}

/// The `.pvtp` index of snapshot number `k` written in pieces.
pub fn parallel_snapshot_name(k: usize) -> String {
    format!("snapshot_{k:06}.pvtp")
}

/// Rank `rank`'s piece of snapshot number `k`.
pub fn piece_name(k: usize, rank: usize) -> String {
    format!("snapshot_{k:06}_rank_{rank}.vtp")
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Decodes the array `name` of a written file (the reading side a
    /// VTK reader does: base64, 8-byte length, little-endian values).
    fn decode(text: &str, name: &str) -> Vec<u8> {
        let tag = format!("Name=\"{name}\"");
        let line = text.lines().find(|l| l.contains(&tag)).unwrap();
        let data = &line[line.find('>').unwrap() + 1..line.rfind("</").unwrap()];
        let block = STANDARD.decode(data).unwrap();
        let len = u64::from_le_bytes(block[..8].try_into().unwrap()) as usize;
        assert_eq!(len, block.len() - 8);
        block[8..].to_vec()
    }

    /// (name, type, components) of each `<DataArray>` (`<PDataArray>`)
    /// of `text` under `<Points>`/`<PointData>` (their parallel tags), in
    /// order: read from the XML, independent of [`POINT_ARRAYS`].
    fn declared(text: &str, tag: &str) -> Vec<(String, String, usize)> {
        let attr = |l: &str, key: &str| -> Option<String> {
            let at = l.find(&format!(" {key}=\""))? + key.len() + 3;
            Some(l[at..at + l[at..].find('"')?].to_string())
        };
        text.lines()
            .filter(|l| l.trim_start().starts_with(&format!("<{tag} ")))
            .filter_map(|l| {
                let name = attr(l, "Name")?;
                let comps = attr(l, "NumberOfComponents").map_or(1, |c| c.parse().unwrap());
                Some((name, attr(l, "type")?, comps))
            })
            .filter(|(name, _, _)| !["TIME", "STEP", "connectivity", "offsets"].contains(&&**name))
            .collect()
    }

    /// A piece holds its spheres' input indices in `id` and local point
    /// numbers in the vertices; the index declares the piece's arrays
    /// and lists every piece.
    #[test]
    fn a_piece_and_its_index_agree() {
        let s = Snapshot {
            time: 0.5,
            step: 9,
            positions: &[[1.0, 2.0, 3.0], [4.0, 5.0, 6.0]],
            radii: &[1e-3, 2e-3],
            velocities: &[[0.0; 3]; 2],
            forces: &[[0.0; 3]; 2],
            fixed: &[false, false],
            materials: &[0, 0],
            angular_velocities: &[[0.0; 3]; 2],
        };
        let mut piece = Vec::new();
        write_piece(&mut piece, &s, &[7, 42]).unwrap();
        let piece = String::from_utf8(piece).unwrap();
        let ints = |name: &str| -> Vec<i64> {
            decode(&piece, name)
                .chunks(8)
                .map(|c| i64::from_le_bytes(c.try_into().unwrap()))
                .collect()
        };
        assert_eq!(ints("id"), vec![7, 42]);
        assert_eq!(ints("connectivity"), vec![0, 1]);
        assert_eq!(ints("offsets"), vec![1, 2]);
        assert!(write_piece(&mut Vec::new(), &s, &[7]).is_err());
        let names = [piece_name(3, 0), piece_name(3, 1)];
        let mut index = Vec::new();
        write_parallel_index(&mut index, &names).unwrap();
        let index = String::from_utf8(index).unwrap();
        let arrays = declared(&piece, "DataArray");
        assert_eq!(arrays.len(), 8, "{arrays:?}");
        assert_eq!(declared(&index, "PDataArray"), arrays);
        assert!(index.contains("<Piece Source=\"snapshot_000003_rank_0.vtp\"/>"));
        assert!(index.contains("<Piece Source=\"snapshot_000003_rank_1.vtp\"/>"));
        assert_eq!(xml_attribute("a\"<&>"), "a&quot;&lt;&amp;&gt;");
        // The whole snapshot is the one piece of ids 0..n.
        let mut whole = Vec::new();
        write_snapshot(&mut whole, &s).unwrap();
        let mut one = Vec::new();
        write_piece(&mut one, &s, &[0, 1]).unwrap();
        assert_eq!(whole, one);
    }

    #[test]
    fn arrays_decode_to_the_values_written() {
        let positions = [[1.0, 2.0, 3.0], [-4.0, 5.5, 1e-3]];
        let s = Snapshot {
            time: 0.25,
            step: 7,
            positions: &positions,
            radii: &[0.5e-3, 0.05],
            velocities: &[[0.0, 0.0, -1.0], [0.0; 3]],
            forces: &[[0.0; 3], [0.0, 0.0, 9.81e-3]],
            fixed: &[false, true],
            materials: &[0, 2],
            angular_velocities: &[[0.0, 7.0, 0.0], [0.0; 3]],
        };
        let mut out = Vec::new();
        write_snapshot(&mut out, &s).unwrap();
        let text = String::from_utf8(out).unwrap();
        assert!(text.contains("NumberOfPoints=\"2\""));
        let pos: Vec<f64> = decode(&text, "position")
            .chunks(8)
            .map(|c| f64::from_le_bytes(c.try_into().unwrap()))
            .collect();
        assert_eq!(pos, vec![1.0, 2.0, 3.0, -4.0, 5.5, 1e-3]);
        assert_eq!(decode(&text, "fixed"), vec![0, 1]);
        let w: Vec<f64> = decode(&text, "angular_velocity")
            .chunks(8)
            .map(|c| f64::from_le_bytes(c.try_into().unwrap()))
            .collect();
        assert_eq!(w, vec![0.0, 7.0, 0.0, 0.0, 0.0, 0.0]);
        let m: Vec<i32> = decode(&text, "material")
            .chunks(4)
            .map(|c| i32::from_le_bytes(c.try_into().unwrap()))
            .collect();
        assert_eq!(m, vec![0, 2]);
        let t = f64::from_le_bytes(decode(&text, "TIME").try_into().unwrap());
        assert_eq!(t, 0.25);
        let mut pvd = Vec::new();
        write_series(
            &mut pvd,
            &[(0.0, snapshot_name(0)), (0.25, snapshot_name(1))],
        )
        .unwrap();
        let pvd = String::from_utf8(pvd).unwrap();
        assert!(
            pvd.contains("timestep=\"2.5e-1\"") && pvd.contains("snapshot_000001.vtp"),
            "{pvd}"
        );
    }
}
