//! The scene's energies, contact counts and wall forces
//! ([`Observation`], computed by `pipeline::observe`), and the energy
//! guard's check of them.

use super::{Observation, Simulation};
use crate::energy_guard::EnergyBalance;
use crate::error::SceneError;
use crate::pipeline::{observe, triangle_loads};
use crate::walls::mesh::{TriangleLoads, TriangleLoadsError};

impl Simulation {
    /// [`Self::observe`], checked by the energy guard: an error when the
    /// run has created energy beyond the integration error allowed
    /// (`energy_guard`) or its energies are not finite.
    pub fn observe_checked(&mut self) -> Result<Observation, SceneError> {
        let o = self.observe();
        self.energy_guard.check(&o, self.initial_energy)?;
        Ok(o)
    }

    /// The energy balance at observation `o` of this run, with the largest
    /// gain the guard has seen.
    pub fn energy_balance(&self, o: &Observation) -> EnergyBalance {
        self.energy_guard.balance(o, self.initial_energy)
    }

    /// Σ ½ m v² over free bodies, plus Σ ½ I ω² with friction, J.
    pub fn kinetic_energy(&self) -> f64 {
        observe::kinetic_energy(&self.world, &self.workers)
    }

    /// −Σ m g·x over free bodies, J.
    pub fn potential_energy(&self) -> f64 {
        observe::potential_energy(&self.world, &self.workers)
    }

    /// Energy stored in the contacts (pairs and plane walls), J, friction
    /// springs included ([`Observation::elastic_energy`]).
    pub fn elastic_energy(&self) -> f64 {
        self.observe().elastic_energy
    }

    /// Energy lost since the start, J: the initial kinetic + elastic +
    /// potential energy minus the current one (damping and integration
    /// error).
    pub fn dissipated_energy(&self) -> f64 {
        self.observe().dissipated_energy
    }

    pub(super) fn mechanical_energy(&self) -> f64 {
        let o = self.observe();
        o.kinetic_energy + o.elastic_energy + o.potential_energy
    }

    /// Sphere pairs in contact now (neither a boundary particle).
    pub fn particle_contacts(&self) -> usize {
        self.observe().particle_contacts
    }

    /// Sphere–wall contacts now (planes and boundary particles).
    pub fn wall_contacts(&self) -> usize {
        self.observe().wall_contacts
    }

    /// Force on each wall in file order, N (for a boundary-particle wall
    /// the sum over its spheres).
    pub fn wall_forces(&self) -> Vec<[f64; 3]> {
        self.observe().wall_forces
    }

    /// Torque on each wall in file order, N m, about its point
    /// ([`Self::wall_torque_points`]).
    pub fn wall_torques(&self) -> Vec<[f64; 3]> {
        self.observe().wall_torques
    }

    /// The point each wall's torque is taken about (file order), m: a
    /// plane's `point`, a cylinder's axis `point` (the middle of a capped
    /// tube), the centroid of a boundary-particle wall's spheres.
    pub fn wall_torque_points(&self) -> Vec<[f64; 3]> {
        observe::wall_torque_points(&self.world)
    }

    /// Every global observable at the current state.
    pub fn observe(&self) -> Observation {
        let tally = self.pipeline.pair_tally(&self.world);
        observe::observation(&self.world, &self.workers, self.initial_energy, &tally)
    }

    /// The contact observables pass by pass: pair counts and energy, wall
    /// contact counts and energy, spring energy (see [`Self::observe`]);
    /// for the test of the fused pass.
    #[cfg(test)]
    pub(crate) fn contact_observables(
        &self,
    ) -> crate::dynamics::friction_observables::ContactObservables {
        observe::contact_passes(&self.world, &self.workers, None, None)
    }

    /// The loads of mesh wall `wall` (file order) per triangle of its
    /// cleaned mesh: the forces the last force stage applied, each contact
    /// given to one triangle (`walls::mesh::loads`), with pressure and
    /// shear stress; the same bits on any thread count. An error when
    /// there is no such wall or it is not a mesh.
    pub fn wall_triangle_loads(&self, wall: usize) -> Result<TriangleLoads, TriangleLoadsError> {
        let mesh = triangle_loads::mesh_of(&self.world, wall)?;
        let records = triangle_loads::triangle_records(&self.world, wall)?;
        Ok(TriangleLoads::sum(mesh, &triangle_loads::forces(&records)))
    }

    /// The file indices of the mesh walls, ascending.
    pub fn mesh_walls(&self) -> Vec<usize> {
        triangle_loads::mesh_walls(&self.world)
    }

    /// Triangles of each wall's cleaned mesh (file order; `None` for a
    /// wall that is not a mesh).
    pub fn wall_triangle_counts(&self) -> Vec<Option<usize>> {
        (0..self.world.walls.len())
            .map(|k| {
                triangle_loads::mesh_of(&self.world, k)
                    .ok()
                    .map(|m| m.triangles.len())
            })
            .collect()
    }
}
