//! VTK XML PolyData files of the mesh walls' loads (issue 26), one per
//! mesh wall per snapshot, `wall_K_NNNNNN.vtp` (K the wall's index in file
//! order, NNNNNN the snapshot's number, as `snapshot_NNNNNN.vtp`), listed
//! in the `.pvd` beside the spheres' snapshot of the same time as part
//! K + 1 (the spheres are part 0), so that ParaView shows the part with
//! its load where it is.
//!
//! Layout (what a reader can rely on), the particle snapshots' encoding
//! (`io::vtk`: base64 binary arrays, `UInt64` header, little-endian):
//! - FieldData `TIME` (Float64, s), `STEP` (UInt64);
//! - Points: the welded vertices of the cleaned mesh, placed in the world
//!   (m), Float64 × 3;
//! - Polys: one triangle per cell, cleaned-mesh order (the file's
//!   triangles in file order, degenerate and duplicate ones dropped),
//!   `connectivity` and `offsets` Int64, vertices ordered along the
//!   triangle's normal (outward for a closed part);
//! - CellData per triangle: `force` (Float64 × 3, N: the force the spheres
//!   exert on the triangle, on the wall), `pressure` (Float64, Pa: |F·n̂|/A,
//!   the normal push over the area, positive), `shear` (Float64, Pa:
//!   |F − (F·n̂) n̂|/A), `area` (Float64, m²), `triangle_id` (Int32, the
//!   cleaned-mesh id). An XML comment at the top repeats the units.
//!
//! Each contact's force goes to one triangle (`walls::mesh::loads`), so
//! the `force` array sums to the wall's force (`wall_forces`) up to the
//! round-off of summing in another grouping.

use std::io::{self, Write};

use super::vtk::{array, f64s, vectors};
use crate::walls::mesh::TriangleLoads;

/// The file name of mesh wall `wall`'s file of snapshot number `k`.
pub fn wall_name(wall: usize, k: usize) -> String {
    format!("wall_{wall}_{k:06}.vtp")
}

/// Writes one mesh wall's `.vtp` file: its triangles and their loads at
/// `time` (s), step `step`.
pub fn write_wall(
    w: &mut dyn Write,
    wall: usize,
    time: f64,
    step: u64,
    loads: &TriangleLoads,
) -> io::Result<()> {
    write_triangles(w, wall, time, step, loads, 0)
}

/// Writes one MPI rank's piece of a mesh wall's file (`[parallel]
/// vtk_per_rank`, listed by a `.pvtp` index, [`write_wall_index`]): the
/// triangles of `loads` ([`TriangleLoads::sum_range`]: the vertices they
/// use, numbered in the piece), the first of cleaned-mesh id `first`
/// (`triangle_id` counts on from it). The layout of [`write_wall`].
pub fn write_wall_piece(
    w: &mut dyn Write,
    wall: usize,
    time: f64,
    step: u64,
    loads: &TriangleLoads,
    first: usize,
) -> io::Result<()> {
    write_triangles(w, wall, time, step, loads, first)
}

/// The cell arrays of a wall's file, in the order written: (name, VTK
/// type, components).
const CELL_ARRAYS: [(&str, &str, usize); 5] = [
    ("force", "Float64", 3),
    ("pressure", "Float64", 1),
    ("shear", "Float64", 1),
    ("area", "Float64", 1),
    ("triangle_id", "Int32", 1),
];

/// Writes the `.pvtp` index of one mesh wall's file written in pieces:
/// the points' and the cells' arrays of [`write_wall_piece`] and each
/// piece's file (`pieces`, relative to the index), as VTK's XML parallel
/// PolyData format (`PPolyData`) has them.
pub fn write_wall_index(w: &mut dyn Write, wall: usize, pieces: &[String]) -> io::Result<()> {
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
    writeln!(w, "<!-- dembound mesh wall {wall} in pieces: {UNITS} -->")?;
    writeln!(
        w,
        "<VTKFile type=\"PPolyData\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">"
    )?;
    writeln!(w, "  <PPolyData GhostLevel=\"0\">")?;
    writeln!(w, "    <PPoints>")?;
    declare(w, ("position", "Float64", 3))?;
    writeln!(w, "    </PPoints>")?;
    writeln!(w, "    <PCellData Scalars=\"pressure\" Vectors=\"force\">")?;
    for a in CELL_ARRAYS {
        declare(w, a)?;
    }
    writeln!(w, "    </PCellData>")?;
    for p in pieces {
        writeln!(
            w,
            "    <Piece Source=\"{}\"/>",
            super::vtk::xml_attribute(p)
        )?;
    }
    writeln!(w, "  </PPolyData>")?;
    writeln!(w, "</VTKFile>")
}

/// The file name of the `.pvtp` index of mesh wall `wall`'s file of
/// snapshot number `k` written in pieces.
pub fn wall_index_name(wall: usize, k: usize) -> String {
    format!("wall_{wall}_{k:06}.pvtp")
}

/// Rank `rank`'s piece of mesh wall `wall`'s file of snapshot number `k`.
pub fn wall_piece_name(wall: usize, k: usize, rank: usize) -> String {
    format!("wall_{wall}_{k:06}_rank_{rank}.vtp")
}

/// The units of a wall's file, for its comment.
const UNITS: &str = "points m; per triangle (cell): force N (on the wall), pressure Pa \
                     (|force.normal|/area), shear Pa (|tangential force|/area), area m2, \
                     triangle_id (cleaned-mesh order)";

/// A wall's `.vtp` file of the triangles of `loads`, the first of
/// cleaned-mesh id `first`.
fn write_triangles(
    w: &mut dyn Write,
    wall: usize,
    time: f64,
    step: u64,
    loads: &TriangleLoads,
    first: usize,
) -> io::Result<()> {
    let (points, cells) = (loads.vertices.len(), loads.triangles.len());
    writeln!(w, "<?xml version=\"1.0\"?>")?;
    writeln!(w, "<!-- dembound mesh wall {wall}: {UNITS} -->")?;
    writeln!(
        w,
        "<VTKFile type=\"PolyData\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">"
    )?;
    writeln!(w, "  <PolyData>")?;
    writeln!(w, "    <FieldData>")?;
    array(w, "TIME", "Float64", 1, &time.to_le_bytes())
        .and_then(|_| array(w, "STEP", "UInt64", 1, &step.to_le_bytes()))?;
    writeln!(w, "    </FieldData>")?;
    writeln!(
        w,
        "    <Piece NumberOfPoints=\"{points}\" NumberOfVerts=\"0\" NumberOfLines=\"0\" NumberOfStrips=\"0\" NumberOfPolys=\"{cells}\">"
    )?;
    writeln!(w, "      <Points>")?;
    array(w, "position", "Float64", 3, &vectors(&loads.vertices))?;
    writeln!(w, "      </Points>")?;
    writeln!(w, "      <CellData Scalars=\"pressure\" Vectors=\"force\">")?;
    array(w, "force", "Float64", 3, &vectors(&loads.force))?;
    array(w, "pressure", "Float64", 1, &f64s(loads.pressure.iter()))?;
    array(w, "shear", "Float64", 1, &f64s(loads.shear.iter()))?;
    array(w, "area", "Float64", 1, &f64s(loads.area.iter()))?;
    let ids: Vec<u8> = (first..first + cells)
        .flat_map(|i| (i as i32).to_le_bytes())
        .collect();
    array(w, "triangle_id", "Int32", 1, &ids)?;
    writeln!(w, "      </CellData>")?;
    writeln!(w, "      <Polys>")?;
    let connectivity: Vec<u8> = loads
        .triangles
        .iter()
        .flatten()
        .flat_map(|&v| i64::from(v).to_le_bytes())
        .collect();
    array(w, "connectivity", "Int64", 1, &connectivity)?;
    let offsets: Vec<u8> = (1..=cells as i64)
        .flat_map(|i| (3 * i).to_le_bytes())
        .collect();
    array(w, "offsets", "Int64", 1, &offsets)?;
    writeln!(w, "      </Polys>")?;
    writeln!(w, "    </Piece>")?;
    writeln!(w, "  </PolyData>")?;
    writeln!(w, "</VTKFile>")
}
