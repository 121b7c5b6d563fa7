//! Stage "observe", the per-triangle loads of a mesh wall
//! (`walls::mesh::loads`): computed when asked (a VTK snapshot, Python),
//! from what the force pass already recorded (each touching near entry's
//! `WallLoad`) and the spheres' positions; the force pass is unchanged.
//!
//! Records are the touching entries of the free bodies this process holds
//! on the wall, each named by its triangle (`MeshGeometry::triangle_of`),
//! ordered by the sphere's input id, a sphere's entries in (wall, element)
//! order: the order `pipeline::wall_loads` sums the wall's total in. The
//! same records in the same order on any number of threads, and on any
//! number of ranks once each rank's records (its owned bodies') are
//! merged by id (`comm::distributed`): the per-triangle running sums have
//! the same bits.

use super::{WallKind, World};
use crate::walls::mesh::{MeshGeometry, TriangleForce, TriangleLoadsError};
use crate::walls::Surface;

/// One touching contact's force on a mesh wall and its triangle, with the
/// sphere's input id (the merge key).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub(crate) struct TriangleRecord {
    pub id: u32,
    pub triangle: u32,
    pub force: [f64; 3],
}

/// The mesh of wall `wall` (file order), or why it has none.
pub(crate) fn mesh_of(world: &World, wall: usize) -> Result<&MeshGeometry, TriangleLoadsError> {
    let walls = world.walls.len();
    match world.walls.get(wall) {
        None => Err(TriangleLoadsError::NoSuchWall { wall, walls }),
        Some(WallKind::Surface(s)) => match world.surfaces.get(*s) {
            Some(Surface::Mesh(m)) => Ok(&m.mesh),
            _ => Err(TriangleLoadsError::NotMesh { wall }),
        },
        Some(WallKind::Particles { .. }) => Err(TriangleLoadsError::NotMesh { wall }),
    }
}

/// The file indices of the mesh walls, ascending.
pub(crate) fn mesh_walls(world: &World) -> Vec<usize> {
    (0..world.walls.len())
        .filter(|&k| mesh_of(world, k).is_ok())
        .collect()
}

/// The triangle records of mesh wall `wall` from the free bodies this
/// process holds: ascending by input id, a body's in entry order.
pub(crate) fn triangle_records(
    world: &World,
    wall: usize,
) -> Result<Vec<TriangleRecord>, TriangleLoadsError> {
    let mesh = mesh_of(world, wall)?;
    let surface = match world.walls[wall] {
        WallKind::Surface(s) => s as u32,
        WallKind::Particles { .. } => return Err(TriangleLoadsError::NotMesh { wall }),
    };
    let (b, wc) = (&world.bodies, &world.wall_contacts);
    if wc.bodies() != b.len() || wc.load.len() != wc.key.len() {
        return Ok(Vec::new());
    }
    // Touching entries on this wall, with their body (fixed bodies, halo
    // copies, are not forced here: their flags are not this step's).
    let mut touching: Vec<(u32, usize, usize)> = Vec::new();
    for i in 0..b.len() {
        if b.fixed[i] {
            continue;
        }
        for k in wc.range(i) {
            if wc.touching[k] && wc.key[k].wall == surface {
                touching.push((b.id[i], k, i));
            }
        }
    }
    touching.sort_unstable();
    // A moving mesh stays in its reference placement: the centre is taken
    // there (`walls::motion`).
    let moving = world.surfaces[surface as usize].moving().copied();
    let at = |x: [f64; 3]| moving.map_or(x, |m| m.unplace(x));
    Ok(touching
        .into_iter()
        .map(|(id, k, i)| TriangleRecord {
            id,
            // Every listed element is a patch of this mesh; the fallback
            // (none) cannot be reached and is dropped by the sum.
            triangle: mesh
                .triangle_of(wc.key[k].element, at(b.position[i]), b.radius[i])
                .unwrap_or(u32::MAX),
            force: wc.load[k].force,
        })
        .collect())
}

/// `records` (ascending by id, a body's in entry order) as the sums take
/// them.
pub(crate) fn forces(records: &[TriangleRecord]) -> Vec<TriangleForce> {
    records
        .iter()
        .map(|r| TriangleForce {
            triangle: r.triangle,
            force: r.force,
        })
        .collect()
}
