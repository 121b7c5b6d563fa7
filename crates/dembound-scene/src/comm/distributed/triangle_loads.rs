//! The per-triangle loads of a mesh wall on a decomposed scene
//! (`pipeline::triangle_loads`): every rank names its owned bodies'
//! touching contacts on the wall by triangle; rank 0 gathers the records
//! (rank order), merges them by input id with a stable sort (a body's
//! records come from its one owner, in entry order) and sums them as one
//! process does: the same records in the same order, so the same bits as
//! one process on any number of ranks. Written in pieces (`[parallel]
//! vtk_per_rank`), each record goes instead to the rank of its triangle's
//! slice, which sums that slice's triangles alone: no gather.

use std::collections::BTreeMap;

use super::{input, DistributedSimulation};
use crate::comm::pack::{self, Writer};
use crate::comm::Transport;
use crate::pipeline::triangle_loads::{self, TriangleRecord};
use crate::walls::mesh::{TriangleLoads, TriangleLoadsError};

impl<T: Transport> DistributedSimulation<T> {
    /// The loads of mesh wall `wall` per triangle
    /// ([`crate::Simulation::wall_triangle_loads`]) at rank 0 (`Ok(None)`
    /// elsewhere). Collective; every rank returns the same error for a
    /// wall that does not exist or is not a mesh (the scene is the same
    /// on every rank), before any communication.
    pub fn wall_triangle_loads(
        &self,
        wall: usize,
    ) -> Result<Option<TriangleLoads>, TriangleLoadsError> {
        let world = &self.sim.world;
        let mesh = triangle_loads::mesh_of(world, wall)?;
        let mine = triangle_loads::triangle_records(world, wall)?;
        let Some(parts) = self.comm.transport.gather(pack::encode(&mine)) else {
            return Ok(None);
        };
        let mut all: Vec<TriangleRecord> = parts
            .iter()
            .filter_map(|b| pack::decode::<Vec<TriangleRecord>>(b))
            .flatten()
            .collect();
        // Stable: a body's records keep their entry order.
        all.sort_by_key(|r| r.id);
        Ok(Some(TriangleLoads::sum(
            mesh,
            &triangle_loads::forces(&all),
        )))
    }

    /// This rank's piece of mesh wall `wall`'s loads per triangle
    /// (`[parallel] vtk_per_rank`): the triangles are cut into equal
    /// consecutive slices, one a rank ([`super::input::slice_start`]);
    /// each rank sends its records to the ranks of their triangles' slices
    /// and sums its own slice's triangles from the records merged by input
    /// id as [`Self::wall_triangle_loads`] merges them at rank 0 (a body's
    /// records come from its one owner): each triangle's values the same
    /// bits as in the gathered loads. No rank gathers the records. Returns
    /// the slice's first triangle id and its loads
    /// ([`TriangleLoads::sum_range`]). Collective; every rank returns the
    /// same error before any communication.
    pub fn wall_triangle_loads_piece(
        &self,
        wall: usize,
    ) -> Result<(usize, TriangleLoads), TriangleLoadsError> {
        let world = &self.sim.world;
        let mesh = triangle_loads::mesh_of(world, wall)?;
        let mine = triangle_loads::triangle_records(world, wall)?;
        let t = &self.comm.transport;
        let (rank, size) = (t.rank(), t.size());
        let n = mesh.triangles.len();
        let mut out: BTreeMap<usize, Vec<TriangleRecord>> = BTreeMap::new();
        let mut kept: Vec<TriangleRecord> = Vec::new();
        for r in mine {
            // A record naming no triangle is dropped by the sum.
            if r.triangle as usize >= n {
                continue;
            }
            match input::slice_of(r.triangle as usize, n, size) {
                s if s == rank => kept.push(r),
                s => out.entry(s).or_default().push(r),
            }
        }
        let out = out
            .into_iter()
            .map(|(s, records)| (s, Writer(pack::encode(&records))))
            .collect();
        for bytes in input::send_all(t, out) {
            kept.extend(pack::decode::<Vec<TriangleRecord>>(&bytes).unwrap_or_default());
        }
        // Stable: a body's records keep their entry order.
        kept.sort_by_key(|r| r.id);
        let range = input::slice_start(n, rank, size)..input::slice_start(n, rank + 1, size);
        let first = range.start;
        Ok((
            first,
            TriangleLoads::sum_range(mesh, &triangle_loads::forces(&kept), range),
        ))
    }

    /// The file indices of the mesh walls, ascending.
    pub fn mesh_walls(&self) -> Vec<usize> {
        self.sim.mesh_walls()
    }

    /// Triangles of each wall's cleaned mesh ([`crate::Simulation::wall_triangle_counts`]).
    pub fn wall_triangle_counts(&self) -> Vec<Option<usize>> {
        self.sim.wall_triangle_counts()
    }
}
