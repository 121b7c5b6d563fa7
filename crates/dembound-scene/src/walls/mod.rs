//! Walls other than boundary particles: one interface ([`Wall`]), one
//! record per wall ([`Surface`]), and the sparse per-body list of the wall
//! elements each sphere is near ([`near::WallContacts`]).
//!
//! A wall answers, for a sphere near it, its contact points: one per
//! element (a plane has one; a cylinder with caps three; a triangle mesh
//! one per triangle), each with overlap, unit normal, overlap rate and
//! the wall's surface velocity there, keyed by (wall, element) so that
//! each keeps its contact history, springs and collision track. The
//! force, the friction and every observable of a wall contact are then
//! the same code for every wall type (`dynamics::walls`,
//! `dynamics::friction`). The force pass records, per touching entry,
//! the force and torque the wall takes from that contact
//! ([`WallLoad::of_contact`], about [`Wall::torque_point`]); the
//! observation sums them per wall (`pipeline::wall_loads`).
//!
//! Memory is per near (body, element) entry, never per (body × element):
//! the list is rebuilt with the pair list, from each wall's
//! [`Wall::near_elements`], and carried across rebuilds, reordering,
//! migration and checkpoints by (input id, wall, element).
//!
//! Every wall type, boundary particles included, is one file here
//! implementing [`WallType`] (its `[[wall]]` entry and checks, its
//! resolution to SI, its placement checks, its law rows, its engine
//! record and a few words for the summary and the exporter) and, when the
//! force loops meet it as a surface, [`Wall`]; `registry.rs` holds one
//! row per type, from which [`WallSetup`], [`WallSection`], [`Surface`]
//! and every dispatch are generated. The scene file, the resolution, the
//! build, the setup checks, the time-step rule, the wall study, the CLI's
//! summary and key table and the exporter's refusal go through them and
//! name no type.
//!
//! Adding a wall type takes two files of this crate: its file here and
//! one row in `registry.rs` (one line, with its `Surface` record: the
//! variant and its four inlined match arms are generated), plus its
//! tests; none of the force, friction, observable, collision-log,
//! checkpoint or MPI code, and nothing outside the crate (the CLI and the
//! exporter take it from the registry; Python needs a constructor only to
//! offer one). Before the registry (the cylinder, issue 25) it took nine
//! files of the crate and three outside.

pub mod gate;
pub mod motion;
pub mod near;
pub mod registry;
pub mod servo;
registry::wall_modules!();

pub use cylinder::CylinderWall;
pub use mesh::MeshWall;
pub use near::{WallContacts, WallContactsMut, WallElement};
pub use plane::{plane_overlap, PlaneWall};
pub use registry::{Surface, WallSection, WallSetup, WallType};

use dembound_physics::contact::Geometry;

/// One contact point of a sphere with a wall element.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WallPoint {
    /// Overlap h (m): positive in contact.
    pub overlap: f64,
    /// Overlap rate ḣ (m/s) of the sphere's centre relative to the
    /// wall's surface velocity there.
    pub rate: f64,
    /// Unit normal from the wall into the sphere (the direction of the
    /// wall's push).
    pub normal: [f64; 3],
}

impl WallPoint {
    /// The contact's geometry as the contact law reads it
    /// (`dembound_physics::contact::model`): the sphere is body 1, the
    /// wall body 2, so the normal n runs from the sphere to the wall, the
    /// reverse of [`Self::normal`].
    #[inline(always)]
    pub fn geometry(&self) -> Geometry {
        Geometry {
            overlap: self.overlap,
            overlap_rate: self.rate,
            normal: self.normal.map(|x| -x),
        }
    }
}

/// How a wall element curves, for the contact law's effective radius.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Curvature {
    /// Flat: R_eff = R (an elastic half-space).
    Flat,
    /// A sphere of this signed radius (m) as seen by the contact law:
    /// R_eff = R ρ/(ρ + R); negative ρ is concave (the inside of a tube:
    /// ρ = −R_c gives R R_c/(R_c − R), LAMMPS `wall/gran` cylinders).
    Radius(f64),
}

/// One row of the wall law tables: a material and a curvature of one
/// wall (a plane has one row; a capped cylinder two: tube and caps).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LawSlot {
    /// Material index of the wall.
    pub material: u32,
    /// Index of the wall in file order (its friction coefficients).
    pub wall: usize,
    pub curvature: Curvature,
}

impl LawSlot {
    /// The pair properties of a sphere of `radius` (m), `mass` (kg) and
    /// material `a` against this row's surface of material `w`.
    pub fn properties(
        &self,
        radius: f64,
        mass: f64,
        a: &dembound_physics::material::Material,
        w: &dembound_physics::material::Material,
    ) -> dembound_physics::material::PairProperties {
        use dembound_physics::material::PairProperties;
        let flat = PairProperties::sphere_plane(radius, mass, a, w);
        match self.curvature {
            Curvature::Flat => flat,
            Curvature::Radius(rho) => PairProperties {
                radius: radius * rho / (rho + radius),
                ..flat
            },
        }
    }
}

/// What a wall type implements.
pub trait Wall {
    /// Index of the wall in file order (the `[[wall]]` entry).
    fn file_index(&self) -> usize;
    /// Elements of the wall (1 for a plane).
    fn elements(&self) -> u32;
    /// Calls `found` with each element whose surface is within `range`
    /// (m) of the surface of a sphere at `x` of radius `r` (overlap
    /// > −range), ascending: the near test of a list build.
    fn near_elements(&self, x: [f64; 3], r: f64, range: f64, found: &mut dyn FnMut(u32));
    /// The contact point of element `element` with a sphere at `x`,
    /// velocity `v`, radius `r`.
    fn contact(&self, element: u32, x: [f64; 3], v: [f64; 3], r: f64) -> WallPoint;
    /// The wall's surface velocity at point `at` of element `element`,
    /// m/s (zero: fixed walls; a moving wall's rigid-body field,
    /// [`motion::WallState::velocity_at`]).
    fn surface_velocity(&self, _element: u32, at: [f64; 3]) -> [f64; 3] {
        self.moving().map_or([0.0; 3], |m| m.velocity_at(at))
    }
    /// The pose and velocities of a moving wall now (`None`: fixed).
    fn moving(&self) -> Option<&motion::WallState> {
        None
    }
    /// This wall, taken as its reference placement (the scene file's),
    /// moved to `state` (`None`: the type does not move).
    fn posed(&self, _state: &motion::WallState) -> Option<Surface> {
        None
    }
    /// Lower and upper corners of the wall's bounding box, m (infinite
    /// where it is unbounded).
    fn bounding_box(&self) -> ([f64; 3], [f64; 3]);
    /// The point its torque is taken about, m (the plane's `point`; a
    /// cylinder's axis `point`, the middle of a capped tube).
    fn torque_point(&self) -> [f64; 3];
    /// The row of the law tables of element `element` (`LawTable`,
    /// `FrictionTable`: one per material and curvature).
    fn law_slot(&self, element: u32) -> usize;
}

/// Force (N) and torque (N m, about the wall's torque point:
/// [`Wall::torque_point`], or the centroid of a boundary-particle wall's
/// spheres) a wall takes from the spheres: of one contact in a force pass
/// ([`Self::of_contact`]), or summed over a wall's contacts.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct WallLoad {
    pub force: [f64; 3],
    pub torque: [f64; 3],
}

impl WallLoad {
    /// What the wall takes from one contact whose force on the sphere is
    /// `on_sphere` (N), applied at the contact point p = x − r n̂ (x the
    /// sphere's centre, r its radius, n̂ the wall's unit normal into the
    /// sphere), with `rolling` (N m) the rolling-resistance torque on the
    /// sphere; the torque about `about` (m).
    ///
    /// Action and reaction: the wall takes F_w = −F. The sphere's torque
    /// about its centre is (p − x) × F + τ_roll (the tangential force's
    /// lever arm plus the rolling couple), so about c the contact gives
    /// the sphere (x − c) × F + (p − x) × F + τ_roll = (p − c) × F + τ_roll.
    /// A contact changes the total angular momentum of sphere and wall by
    /// nothing, so the wall takes τ_w = −(p − c) × F − τ_roll (the rolling
    /// torque is a couple between the two surfaces: it acts on the wall
    /// reversed, whatever the point).
    #[inline(always)]
    pub fn of_contact(
        on_sphere: [f64; 3],
        rolling: Option<[f64; 3]>,
        x: [f64; 3],
        r: f64,
        normal: [f64; 3],
        about: [f64; 3],
    ) -> Self {
        let arm = [
            x[0] - r * normal[0] - about[0],
            x[1] - r * normal[1] - about[1],
            x[2] - r * normal[2] - about[2],
        ];
        let f = on_sphere;
        let mut torque = [
            -(arm[1] * f[2] - arm[2] * f[1]),
            -(arm[2] * f[0] - arm[0] * f[2]),
            -(arm[0] * f[1] - arm[1] * f[0]),
        ];
        if let Some(t) = rolling {
            for a in 0..3 {
                torque[a] -= t[a];
            }
        }
        Self {
            force: [-f[0], -f[1], -f[2]],
            torque,
        }
    }

    /// Adds `other` component by component.
    #[inline(always)]
    pub fn add(&mut self, other: &WallLoad) {
        for a in 0..3 {
            self.force[a] += other.force[a];
            self.torque[a] += other.torque[a];
        }
    }
}

#[cfg(test)]
mod tests {
    use super::WallLoad;

    fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
        [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ]
    }

    /// A contact pushing the sphere (centre x = (1, 0, 2), r = 0.5, wall
    /// normal +z: contact point p = (1, 0, 1.5)) with F = (1, 2, 3) N and
    /// a rolling torque τ = (0.1, 0, 0) N m: by hand, the wall takes −F and
    /// −(p × F) − τ = −(−3, −1.5, 2) − τ = (2.9, 1.5, −2) about the origin;
    /// and sphere plus wall gain no angular momentum about any point
    /// (the sphere's (x − c) × F + (p − x) × F + τ cancels the wall's).
    #[test]
    fn a_contact_gives_the_wall_the_reaction_and_its_moment() {
        let (f, tau, x) = ([1.0, 2.0, 3.0], [0.1, 0.0, 0.0], [1.0, 0.0, 2.0]);
        let l = WallLoad::of_contact(f, Some(tau), x, 0.5, [0.0, 0.0, 1.0], [0.0; 3]);
        assert_eq!(l.force, [-1.0, -2.0, -3.0]);
        assert_eq!(l.torque, [2.9, 1.5, -2.0]);
        let c = [0.3, -2.0, 0.7];
        let l = WallLoad::of_contact(f, Some(tau), x, 0.5, [0.0, 0.0, 1.0], c);
        let arm = [x[0] - c[0], x[1] - c[1], x[2] - c[2]];
        let lever = cross([0.0, 0.0, -0.5], f);
        let on_sphere = cross(arm, f);
        for a in 0..3 {
            let total = on_sphere[a] + lever[a] + tau[a] + l.torque[a];
            assert!(total.abs() < 1e-14, "{a}: {total}");
        }
        // Frictionless: no rolling torque, a normal force through the
        // centre: the moment of F at the centre.
        let n = WallLoad::of_contact([0.0, 0.0, 2.0], None, x, 0.5, [0.0, 0.0, 1.0], c);
        let expected = cross(arm, [0.0, 0.0, 2.0]).map(|t| -t);
        assert_eq!(n.torque, expected);
    }
}
