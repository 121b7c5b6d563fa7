//! The per-triangle loads of a mesh wall on a decomposed scene
//! (`pipeline::triangle_loads`): every rank names its owned bodies'
//! touching contacts on the wall by triangle; rank 0 gathers the records
//! (rank order), merges them by input id with a stable sort (a body's
//! records come from its one owner, in entry order) and sums them as one
//! process does: the same records in the same order, so the same bits as
//! one process on any number of ranks.

use super::DistributedSimulation;
use crate::comm::pack;
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

    /// The file indices of the mesh walls, ascending.
    pub fn mesh_walls(&self) -> Vec<usize> {
        self.sim.mesh_walls()
    }

    /// Triangles of each wall's cleaned mesh ([`crate::Simulation::wall_triangle_counts`]).
    pub fn wall_triangle_counts(&self) -> Vec<Option<usize>> {
        self.sim.wall_triangle_counts()
    }
}
