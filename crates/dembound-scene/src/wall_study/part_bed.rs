//! The bed and the flow on the user's part (issue 29 item 4, `dembound
//! wall-study --wall SURFACE`): the plane study's pour ([`super::pour`])
//! dropped into the part, settled, measured, and where the part has an
//! outlet (an open bottom) discharged through it; the same spheres for
//! the mesh wall and for each covering, so the deviations are paired.
//!
//! **The region** (gravity along −z: the part is given upright, the
//! particles on its normals' side, or the other with `flip`):
//! - side walls: four frictionless planes on the part's bounding box in x
//!   and y (they keep the pour over the part; a hopper or a cylinder lies
//!   inside them);
//! - the pour: the plane study's loose random packing (solid fraction
//!   0.18) in a box from 2 R above the part's top, over the part's box in
//!   x and y scaled about its centre by the largest f of 1, 0.9, …, 0.1
//!   whose four corner columns (inset by R) lie inside the part just below
//!   its top (at z = max(top − 2 R, bottom + R) the nearest triangle sees
//!   the point on the particles' side, at least R away): a flat part
//!   takes its whole box, a round hopper or cylinder the box inscribed in
//!   its rim (f = 0.7 for `hopper.stl`: ±14 mm in its 20 mm bin);
//! - settling: the fall from the box's top to the part's bottom, then
//!   `settle_time`;
//! - the outlet: mesh edges of one triangle only (open edges) at the
//!   part's lowest z whose triangle rises from them. With one, a plug (a
//!   plane at that z, normal +z, of the reference material) closes it
//!   while the bed settles, then drops 39 R in 10 ms (faster than a grain
//!   falls: it leaves them at once); an outlet box from 40 R below the
//!   outlet to 10 R below it removes the discharged spheres. The domain
//!   reaches 40 R below the outlet (without one, 2.5 R_b below the part,
//!   as the plane study's).
//!
//! **The quantities** (in the settled bed, before the opening):
//! - the bed height: the 95th percentile of the spheres' tops above the
//!   part's bottom (the plane study's, whose floor is at z = 0);
//! - the packing at the wall: the solid fraction of the free spheres in
//!   the shell within 2 R of the surface on the particles' side, from
//!   seeded random points: a point of the surface (triangle ∝ area, then
//!   uniform on it) no higher than the bed's top less 2 R, moved a
//!   uniform 0–2 R along the face normal. On a flat part this samples
//!   the plane study's slab 0 ≤ z ≤ 2 R uniformly; on a curved one the
//!   shell's volume element differs by 1 ± d κ (κ the curvature, d ≤ 2 R)
//!   and concave folds are sampled twice, the same for every wall. For a
//!   covering the same shell: its spheres' tops lie on the surface.
//! - the discharge rate (with an outlet): the mass removed by the outlet
//!   box from `skip` s after the opening to the end, over that time; its
//!   standard error from the rates of 5 consecutive batches (sd/√5).

use dembound_physics::material::Material;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::collections::HashMap;

use super::part::{CoveringSpec, PartConfig};
use super::part_fill::{capacity, Interior, LOOSE_PACKING, OUTSIDE_FRACTION, SURVEY_COLUMNS};
use super::pour::Pour;
use crate::region::Region;
use crate::setup::{BoundaryParticles, NamedMaterial, Plane, SceneSetup, SphereInit, WallSetup};
use crate::sources::mesh_tiling::Covering;
use crate::walls::mesh::geometry::{closest_on_triangle, cross, dot, norm, scale, sub};
use crate::walls::mesh::{Mesh, MeshGeometry};
use crate::walls::motion::WallMotion;
use crate::{SceneError, Simulation};

/// The plug drops this many particle radii …
pub const PLUG_DROP_RADII: f64 = 39.0;
/// … in this time, s.
pub const PLUG_DROP_TIME: f64 = 0.01;
/// The domain reaches this many radii below an outlet …
pub const BELOW_OUTLET_RADII: f64 = 40.0;
/// … and the outlet box's top is this many below it.
pub const OUTLET_BOX_TOP_RADII: f64 = 10.0;
/// Batches of the rate's standard error.
pub const RATE_BATCHES: usize = 5;

/// The bed and the flow of a part study.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PartBedConfig {
    /// Spheres poured.
    pub particles: usize,
    /// Settling after the fall, s.
    pub settle_time: f64,
    /// Discharge after the opening (parts with an outlet), s.
    pub discharge_time: f64,
    /// The rate is taken from this long after the opening, s.
    pub skip: f64,
    /// Random points of the packing at the wall.
    pub packing_points: usize,
}

impl PartBedConfig {
    /// Checks the numbers; an error names the option, the value and the range.
    pub fn validate(&self) -> Result<(), SceneError> {
        let bad = |k: &str, v: f64, allowed: &str| Err(SceneError::invalid(k, v, allowed));
        if !(1..=200_000).contains(&self.particles) {
            return bad("--particles", self.particles as f64, "1 to 200000");
        }
        if !(self.settle_time.is_finite() && self.settle_time > 0.0) {
            return bad("--settle-time", self.settle_time, "finite and > 0 s");
        }
        if !(self.discharge_time.is_finite() && self.discharge_time > 0.0) {
            return bad("--discharge-time", self.discharge_time, "finite and > 0 s");
        }
        if !(self.skip.is_finite() && self.skip >= 0.0 && self.skip < 0.9 * self.discharge_time) {
            return bad(
                "--discharge-skip",
                self.skip,
                "0 ≤ skip < 0.9 × --discharge-time s",
            );
        }
        if !(1000..=10_000_000).contains(&self.packing_points) {
            return bad(
                "--packing-points",
                self.packing_points as f64,
                "1000 to 10000000",
            );
        }
        Ok(())
    }
}

/// The part's outlet: open bottom edges.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Outlet {
    /// Its plane, m.
    pub z: f64,
    /// The mean of its edges' vertices, m.
    pub centre: [f64; 2],
    /// The distance from the centre to the nearest open edge, m (the
    /// clear radius of a round outlet).
    pub radius: f64,
    /// Open edges at the bottom.
    pub edges: usize,
}

/// Where the bed goes in the part.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PartRegion {
    /// The pour for the mesh wall (domain for R_b = R below the part).
    pub pour: Pour,
    /// The scale f of the pour box.
    pub box_fraction: f64,
    pub outlet: Option<Outlet>,
    /// The part's bounding box, m.
    pub lo: [f64; 3],
    pub hi: [f64; 3],
}

impl PartRegion {
    /// The pour with the domain reaching 2.5 `rb` below the part (and the
    /// outlet's space).
    pub fn pour_for(&self, rb: f64) -> Pour {
        let mut p = self.pour;
        let below = match self.outlet {
            Some(_) => (self.lo[2] - BELOW_OUTLET_RADII * p.radius).min(self.lo[2] - 2.5 * rb),
            None => self.lo[2] - 2.5 * rb,
        };
        p.domain_lower[2] = below;
        p
    }

    /// The plug (closing the outlet) and its motion from `t_open`.
    pub fn plug(&self, t_open: f64) -> Option<(Plane, WallMotion)> {
        let o = self.outlet?;
        Some((
            Plane {
                point: [o.centre[0], o.centre[1], o.z],
                normal: [0.0, 0.0, 1.0],
                material: 1,
            },
            WallMotion {
                velocity: [
                    0.0,
                    0.0,
                    -PLUG_DROP_RADII * self.pour.radius / PLUG_DROP_TIME,
                ],
                angular_velocity: [0.0; 3],
                center: [0.0; 3],
                start: t_open,
                end: t_open + PLUG_DROP_TIME,
                oscillation: None,
            },
        ))
    }

    /// The outlet box (removing discharged spheres), m.
    pub fn outlet_box(&self, domain_lower_z: f64) -> Option<([f64; 3], [f64; 3])> {
        let o = self.outlet?;
        Some((
            [self.lo[0], self.lo[1], domain_lower_z],
            [
                self.hi[0],
                self.hi[1],
                o.z - OUTLET_BOX_TOP_RADII * self.pour.radius,
            ],
        ))
    }
}

/// The unit face normal of triangle `t` toward the particles.
fn particle_normal(mesh: &MeshGeometry, t: usize, flip: bool) -> [f64; 3] {
    let [a, b, c] = mesh.triangles[t].map(|v| mesh.vertices[v as usize]);
    let n = cross(sub(b, a), sub(c, a));
    scale(n, if flip { -1.0 } else { 1.0 } / norm(n))
}

/// Whether `p` is on the particles' side of the part, at least `r` from it.
fn inside(mesh: &MeshGeometry, flip: bool, p: [f64; 3], r: f64) -> bool {
    let mut best = (f64::INFINITY, 0.0);
    for (t, tri) in mesh.triangles.iter().enumerate() {
        let [a, b, c] = tri.map(|v| mesh.vertices[v as usize]);
        let q = closest_on_triangle(p, a, b, c);
        let d = norm(sub(p, q));
        if d < best.0 {
            best = (d, dot(sub(p, q), particle_normal(mesh, t, flip)));
        }
    }
    best.1 > 0.0 && best.0 >= r * (1.0 - 1e-9)
}

/// Whether the segment from `p` to `q` crosses the part (a lid over a
/// closed part: the pour would land on its outside).
fn blocked(mesh: &MeshGeometry, p: [f64; 3], q: [f64; 3]) -> bool {
    mesh.triangles.iter().any(|t| {
        let [a, b, c] = t.map(|v| mesh.vertices[v as usize]);
        crate::walls::mesh::geometry::segment_meets_triangle(p, q, a, b, c).is_some()
    })
}

/// The open edges at the part's bottom whose triangle rises from them.
fn outlet(mesh: &MeshGeometry) -> Option<Outlet> {
    let diag = norm(sub(mesh.hi, mesh.lo));
    let eps = 1e-9 * diag + mesh.inside_tolerance;
    let bottom = mesh.lo[2];
    let mut uses: HashMap<(u32, u32), (usize, u32)> = HashMap::new();
    for tri in &mesh.triangles {
        for k in 0..3 {
            let (a, b) = (tri[k], tri[(k + 1) % 3]);
            let e = uses
                .entry((a.min(b), a.max(b)))
                .or_insert((0, tri[(k + 2) % 3]));
            e.0 += 1;
        }
    }
    let mut edges: Vec<([f64; 3], [f64; 3])> = uses
        .iter()
        .filter(|(_, (n, _))| *n == 1)
        .map(|(&(a, b), &(_, third))| {
            (
                mesh.vertices[a as usize],
                mesh.vertices[b as usize],
                mesh.vertices[third as usize],
            )
        })
        .filter(|(a, b, c)| a[2] - bottom <= eps && b[2] - bottom <= eps && c[2] - bottom > eps)
        .map(|(a, b, _)| (a, b))
        .collect();
    if edges.is_empty() {
        return None;
    }
    // The map's order is not fixed: sort for a deterministic centre.
    edges.sort_by(|x, y| {
        x.0.iter()
            .chain(&x.1)
            .zip(y.0.iter().chain(&y.1))
            .map(|(a, b)| a.total_cmp(b))
            .find(|o| o.is_ne())
            .unwrap_or(std::cmp::Ordering::Equal)
    });
    let n = 2.0 * edges.len() as f64;
    let centre = [
        edges.iter().map(|e| e.0[0] + e.1[0]).sum::<f64>() / n,
        edges.iter().map(|e| e.0[1] + e.1[1]).sum::<f64>() / n,
    ];
    let c3 = [centre[0], centre[1], bottom];
    let radius = edges
        .iter()
        .map(|&(a, b)| {
            let (q, _) = crate::walls::mesh::geometry::closest_on_segment(c3, a, b);
            norm(sub(q, c3))
        })
        .fold(f64::INFINITY, f64::min);
    Some(Outlet {
        z: bottom,
        centre,
        radius,
        edges: edges.len(),
    })
}

/// The largest scale f of 1, 0.9, …, 0.1 of the part's box in x and y
/// (about its centre) whose pour lands inside the part: the four corner
/// columns, inset by R, lie inside it just below its top (at z =
/// max(top − 2 R, bottom + R), on the particles' side at least R away)
/// reached from above without crossing it, and every column of a 5 × 5
/// grid over the inset box is interior ([`Interior::floor`]: it lands on
/// the part's inside or passes through the outlet).
fn pour_fraction(mesh: &MeshGeometry, flip: bool, r: f64, outlet: Option<Outlet>) -> Option<f64> {
    let (lo, hi) = (mesh.lo, mesh.hi);
    let centre = [0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1])];
    let half = [0.5 * (hi[0] - lo[0]), 0.5 * (hi[1] - lo[1])];
    let zt = (hi[2] - 2.0 * r).max(lo[2] + r);
    let interior = Interior::new(mesh, flip, r, outlet);
    (0..10).map(|k| 1.0 - 0.1 * k as f64).find(|&f| {
        let at = |sx: f64, sy: f64| {
            [
                centre[0] + sx * (f * half[0] - r),
                centre[1] + sy * (f * half[1] - r),
            ]
        };
        let corners = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)]
            .iter()
            .all(|&(sx, sy)| {
                let [x, y] = at(sx, sy);
                let p = [x, y, zt];
                let above = [x, y, hi[2] + 2.0 * r];
                inside(mesh, flip, p, r) && !blocked(mesh, above, p)
            });
        corners
            && (0..5).all(|i| {
                (0..5).all(|j| {
                    let [x, y] = at(-1.0 + 0.5 * i as f64, -1.0 + 0.5 * j as f64);
                    interior.floor(x, y).is_some()
                })
            })
    })
}

/// The region of `count` spheres of radius `r` in the part (module doc).
pub fn region(
    mesh: &MeshGeometry,
    flip: bool,
    r: f64,
    count: usize,
    name: &str,
) -> Result<PartRegion, SceneError> {
    let (lo, hi) = (mesh.lo, mesh.hi);
    let centre = [0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1])];
    let half = [0.5 * (hi[0] - lo[0]), 0.5 * (hi[1] - lo[1])];
    let outlet = outlet(mesh);
    let Some(f) = pour_fraction(mesh, flip, r, outlet) else {
        if pour_fraction(mesh, !flip, r, outlet).is_some() {
            return Err(SceneError::input(format!(
                "--flip {}: the pour over --wall `{name}` lands on the part's outside or goes \
                 around it (no pour box, the part's box in x and y scaled by 1 to 0.1, has its \
                 columns landing on the particles' side); the other side takes the grains: \
                 {} --flip",
                if flip { "given" } else { "not given" },
                if flip { "leave out" } else { "give" }
            )));
        }
        return Err(SceneError::input(format!(
            "--wall `{name}`: no pour column fits inside the part (the corners of its box, scaled \
             by 1 to 0.1 about its centre, are outside it 2 R below its top, or the columns from \
             above land on its outside; is the part upright, z up, with its particles on the \
             normals' side (else --flip)?)"
        )));
    };
    let interior = Interior::new(mesh, flip, r, outlet);
    let volume = interior.volume([lo[0], lo[1]], [hi[0], hi[1]]);
    let fits = capacity(volume, r);
    if count as f64 > fits {
        return Err(SceneError::invalid(
            "--particles",
            count,
            format!(
                "1 to {fits} for --wall `{name}` and --radius {r:e} m: its interior below the \
                 rim, {:.4e} m³ (surveyed by {SURVEY_COLUMNS}² columns), holds at most that many \
                 grains at a loose packing of {LOOSE_PACKING}",
                volume
            ),
        ));
    }
    let lower_xy = [centre[0] - f * half[0], centre[1] - f * half[1]];
    let upper_xy = [centre[0] + f * half[0], centre[1] + f * half[1]];
    let height = Pour::fill_height(
        count,
        r,
        upper_xy[0] - lower_xy[0],
        upper_xy[1] - lower_xy[1],
    );
    let bottom = hi[2] + 2.0 * r;
    let top = bottom + height;
    if upper_xy[0] - lower_xy[0] < 2.0 * r || upper_xy[1] - lower_xy[1] < 2.0 * r {
        return Err(SceneError::input(format!(
            "--wall `{name}`: the pour box inside the part is narrower than a particle ({:e} × {:e} m)",
            upper_xy[0] - lower_xy[0],
            upper_xy[1] - lower_xy[1]
        )));
    }
    let pour = Pour {
        count,
        radius: r,
        lower: [lower_xy[0], lower_xy[1], bottom],
        upper: [upper_xy[0], upper_xy[1], top],
        sides: [[lo[0], hi[0]], [lo[1], hi[1]]],
        domain_lower: [lo[0], lo[1], lo[2] - 2.5 * r],
        domain_upper: [hi[0], hi[1], top + r],
        base: lo[2],
    };
    Ok(PartRegion {
        pour,
        box_fraction: f,
        outlet,
        lo,
        hi,
    })
}

/// The settled bed and the flow on one wall of the part.
#[derive(Debug, Clone, PartialEq)]
pub struct PartBed {
    /// Free spheres in the settled bed.
    pub particles: usize,
    /// Bed height above the part's bottom, m.
    pub height: f64,
    /// Packing at the wall and its binomial standard error.
    pub wall_packing: f64,
    pub wall_packing_error: f64,
    /// Random points that fell in the shell.
    pub packing_points: usize,
    /// Discharge rate and its standard error, kg/s (with an outlet).
    pub rate: Option<(f64, f64)>,
    /// (time after the opening, s; mass discharged, kg).
    pub discharge: Vec<(f64, f64)>,
    /// Mass of the bed, kg.
    pub mass: f64,
    /// Mean speed of its spheres at the opening (the end of settling), m/s.
    pub mean_speed: f64,
    /// Time of the opening (or the end of settling), s.
    pub t_open: f64,
    /// Steps between discharge rows.
    pub row_steps: u64,
    /// Settling steps (the opening's step).
    pub settle_steps: u64,
    /// Discharge steps.
    pub discharge_steps: u64,
}

/// The wall the bed settles on.
pub enum BedWall<'a> {
    Mesh(&'a Mesh),
    Covering(&'a Covering, &'a CoveringSpec),
}

/// The scene of the bed on `wall`: the pour, the side walls (0–3), the
/// part (wall 4), the plug (wall 5) and the outlet box when the part has
/// an outlet; Δt `dt`. Also returns the settling and discharge steps and
/// the rows' spacing.
pub fn scene(
    c: &PartConfig,
    bed: &PartBedConfig,
    region: &PartRegion,
    wall: &BedWall,
    dt: f64,
) -> Result<(SceneSetup, [u64; 3]), SceneError> {
    let st = &c.study;
    let rb = match wall {
        BedWall::Mesh(_) => st.radius,
        BedWall::Covering(_, spec) => spec.radius_ratio * st.radius,
    };
    let pour = region.pour_for(rb);
    let mut s = pour.scene(st, dt)?;
    let part_wall = s.walls.len();
    match wall {
        BedWall::Mesh(m) => {
            s.materials.push(NamedMaterial {
                name: "reference".into(),
                material: c.reference,
            });
            let mut m = (*m).clone();
            m.material = 1;
            s.walls.push(WallSetup::Mesh(m));
        }
        BedWall::Covering(cov, spec) => {
            s.materials.push(NamedMaterial {
                name: "boundary".into(),
                material: c.boundary_material(spec),
            });
            let first = s.spheres.len();
            for b in &cov.spheres {
                s.spheres.push(SphereInit {
                    position: b.position,
                    velocity: [0.0; 3],
                    radius: b.radius,
                    material: 1,
                    fixed: true,
                    group: Some(part_wall),
                });
            }
            s.walls
                .push(WallSetup::BoundaryParticles(BoundaryParticles {
                    first_body: first,
                    count: cov.spheres.len(),
                }));
        }
    }
    let settle = pour.settle_steps(bed.settle_time, dt);
    let mut steps = [settle, 0, 1];
    if region.outlet.is_some() {
        // Rows about 60 over the discharge; the opening on a row.
        let every = ((bed.discharge_time / 60.0 / dt).ceil() as u64).max(1);
        let settle = settle.div_ceil(every) * every;
        let discharge = ((bed.discharge_time / dt).ceil() as u64).div_ceil(every) * every;
        steps = [settle, discharge, every];
        let t_open = settle as f64 * dt;
        if let Some((mut plug, motion)) = region.plug(t_open) {
            if matches!(wall, BedWall::Covering(..)) {
                // The plug is of the reference material.
                s.materials.push(NamedMaterial {
                    name: "reference".into(),
                    material: c.reference,
                });
                plug.material = s.materials.len() - 1;
            }
            s.walls.push(WallSetup::Plane(plug));
            s.wall_motions = vec![None; s.walls.len()];
            s.wall_motions[s.walls.len() - 1] = Some(motion);
        }
        if let Some((lower, upper)) = region.outlet_box(pour.domain_lower[2]) {
            s.outlets.push(Region::Box { lower, upper });
        }
    }
    s.friction = st.friction_setup(&s, part_wall, &[0, 1, 2, 3]);
    Ok((s, steps))
}

/// Pours, settles, measures and discharges the bed on `wall`.
pub fn run(
    c: &PartConfig,
    bed: &PartBedConfig,
    region: &PartRegion,
    mesh: &MeshGeometry,
    wall: &BedWall,
    dt: f64,
) -> Result<PartBed, SceneError> {
    let r = c.study.radius;
    let (s, [settle, discharge, every]) = scene(c, bed, region, wall, dt)?;
    let pour = region.pour;
    let mut sim = Simulation::new(s, pour.threads())?;
    // The plane study's chunks for a bed without outlet; rows otherwise.
    let chunk = if region.outlet.is_some() {
        every
    } else {
        (settle / 200).max(1)
    };
    let mut done = 0;
    while done < settle {
        let k = chunk.min(settle - done);
        sim.step_guarded(k)?;
        done += k;
    }
    let t_open = sim.time();
    let free: Vec<[f64; 3]> = sim
        .positions()
        .iter()
        .zip(sim.fixed())
        .filter(|(_, f)| !*f)
        .map(|(p, _)| *p)
        .collect();
    // A grain touching the mesh from inside has its centre above the
    // floor; one in the hollows of a covering of R_b sits up to 2 R_b
    // below the surface (the covering's tops lie on it). Half a grain more.
    let depth = match wall {
        BedWall::Mesh(_) => 0.5 * r,
        BedWall::Covering(cov, _) => 2.0 * cov.options.radius + 0.5 * r,
    };
    let outside = Interior::new(mesh, c.flip, r, region.outlet).outside(&free, depth);
    if outside as f64 > OUTSIDE_FRACTION * free.len() as f64 {
        return Err(SceneError::input(format!(
            "--wall `{}`: {outside} of the {} settled grains on the {} ended outside the part's \
             interior or above its rim (z = {:.4e} m); at most {} % may (a grain on the rim's \
             edge): the bed is not the part's. Fewer --particles, or the part's other side \
             (--flip)",
            c.name,
            free.len(),
            match wall {
                BedWall::Mesh(_) => "mesh wall".to_string(),
                BedWall::Covering(_, spec) => spec.label(),
            },
            region.hi[2],
            100.0 * OUTSIDE_FRACTION
        )));
    }
    let mut tops: Vec<f64> = free.iter().map(|p| p[2] + r - region.lo[2]).collect();
    tops.sort_by(f64::total_cmp);
    let height = tops.get((tops.len() * 95) / 100).copied().unwrap_or(0.0);
    let (wall_packing, wall_packing_error, packing_points) = packing_at_wall(
        mesh,
        c.flip,
        &free,
        r,
        region.lo[2] + height - 2.0 * r,
        bed.packing_points,
        c.study.seed,
    );
    let mass = free.len() as f64 * c.study.material.sphere_mass(r);
    let speeds: Vec<f64> = sim
        .velocities()
        .iter()
        .zip(sim.fixed())
        .filter(|(_, f)| !*f)
        .map(|(v, _)| norm(*v))
        .collect();
    let mean_speed = speeds.iter().sum::<f64>() / speeds.len().max(1) as f64;
    let mut rows = vec![(0.0, 0.0)];
    let mut rate = None;
    if region.outlet.is_some() {
        let mut done = 0;
        while done < discharge {
            sim.step_guarded(every)?;
            done += every;
            let o = sim.observe();
            let m = o.outlets.first().map_or(0.0, |x| x.mass);
            rows.push((o.time - t_open, m));
        }
        rate = discharge_rate(&rows, bed.skip);
    }
    Ok(PartBed {
        particles: free.len(),
        height,
        wall_packing,
        wall_packing_error,
        packing_points,
        rate,
        discharge: rows,
        mass,
        mean_speed,
        t_open,
        row_steps: every,
        settle_steps: settle,
        discharge_steps: discharge,
    })
}

/// The rate from the first row at t ≥ `skip` to the last, kg/s, and its
/// standard error from [`RATE_BATCHES`] batches; `None` with fewer rows
/// than batches after `skip`.
pub fn discharge_rate(rows: &[(f64, f64)], skip: f64) -> Option<(f64, f64)> {
    let i0 = rows.iter().position(|r| r.0 >= skip)?;
    let window = &rows[i0..];
    let intervals = window.len().checked_sub(1)?;
    if intervals < RATE_BATCHES {
        return None;
    }
    let (first, last) = (window[0], window[intervals]);
    let rate = (last.1 - first.1) / (last.0 - first.0);
    let batch: Vec<f64> = (0..RATE_BATCHES)
        .map(|b| {
            let (a, z) = (
                window[b * intervals / RATE_BATCHES],
                window[(b + 1) * intervals / RATE_BATCHES],
            );
            (z.1 - a.1) / (z.0 - a.0)
        })
        .collect();
    let mean = batch.iter().sum::<f64>() / RATE_BATCHES as f64;
    let var =
        batch.iter().map(|x| (x - mean) * (x - mean)).sum::<f64>() / (RATE_BATCHES - 1) as f64;
    Some((rate, (var / RATE_BATCHES as f64).sqrt()))
}

/// The solid fraction of the spheres `free` (radius `r`) in the shell
/// within 2 R of the surface on the particles' side, for surface points
/// no higher than `top`: (fraction, binomial standard error, points).
fn packing_at_wall(
    mesh: &MeshGeometry,
    flip: bool,
    free: &[[f64; 3]],
    r: f64,
    top: f64,
    points: usize,
    seed: u64,
) -> (f64, f64, usize) {
    let tri: Vec<([[f64; 3]; 3], [f64; 3])> = mesh
        .triangles
        .iter()
        .enumerate()
        .map(|(t, v)| {
            (
                v.map(|i| mesh.vertices[i as usize]),
                particle_normal(mesh, t, flip),
            )
        })
        .collect();
    let mut cumulative = Vec::with_capacity(tri.len());
    let mut total = 0.0;
    for (t, _) in &tri {
        total += 0.5 * norm(cross(sub(t[1], t[0]), sub(t[2], t[0])));
        cumulative.push(total);
    }
    let cell = 2.0 * r;
    let key = |p: [f64; 3]| p.map(|x| (x / cell).floor() as i64);
    let mut grid: HashMap<[i64; 3], Vec<usize>> = HashMap::new();
    for (i, p) in free.iter().enumerate() {
        grid.entry(key(*p)).or_default().push(i);
    }
    let mut rng = ChaCha8Rng::seed_from_u64(seed ^ 0x7061_636b_696e_6721);
    let (mut solid, mut taken) = (0usize, 0usize);
    for _ in 0..points {
        let pick = rng.gen::<f64>() * total;
        let k = cumulative.partition_point(|&c| c < pick).min(tri.len() - 1);
        let ([a, b, c], n) = tri[k];
        let (u, w) = (rng.gen::<f64>().sqrt(), rng.gen::<f64>());
        let d = rng.gen::<f64>() * 2.0 * r;
        let q: [f64; 3] =
            std::array::from_fn(|i| (1.0 - u) * a[i] + u * (1.0 - w) * b[i] + u * w * c[i]);
        if q[2] > top {
            continue;
        }
        let p: [f64; 3] = std::array::from_fn(|i| q[i] + d * n[i]);
        taken += 1;
        let kp = key(p);
        let mut hit = false;
        'cells: for dx in -1..=1 {
            for dy in -1..=1 {
                for dz in -1..=1 {
                    if let Some(ids) = grid.get(&[kp[0] + dx, kp[1] + dy, kp[2] + dz]) {
                        if ids.iter().any(|&i| norm(sub(free[i], p)) < r) {
                            hit = true;
                            break 'cells;
                        }
                    }
                }
            }
        }
        solid += usize::from(hit);
    }
    if taken == 0 {
        return (f64::NAN, f64::NAN, 0);
    }
    let phi = solid as f64 / taken as f64;
    (phi, (phi * (1.0 - phi) / taken as f64).sqrt(), taken)
}

/// The mesh wall's bed scene as a `dembound scene` file (the part read
/// from `file`, absolute): the same spheres, walls, plug, outlet and Δt,
/// for a run of `settle + discharge` steps with series rows every
/// `every` steps.
pub fn mesh_scene_toml(
    c: &PartConfig,
    region: &PartRegion,
    file: &std::path::Path,
    dt: f64,
    [settle, discharge, every]: [u64; 3],
) -> String {
    use std::fmt::Write as _;
    let st = &c.study;
    let pour = region.pour_for(st.radius);
    let m = |x: &Material| {
        format!(
            "density = {:?}\nyoungs_modulus = {:?}\npoisson_ratio = {:?}",
            x.density, x.youngs_modulus, x.poisson_ratio
        )
    };
    let v = |x: [f64; 3]| format!("[{:?}, {:?}, {:?}]", x[0], x[1], x[2]);
    let mut s = String::new();
    let _ = writeln!(
        s,
        "# The mesh wall's bed{} of `dembound wall-study --wall`, as a scene.\n",
        if region.outlet.is_some() {
            " and discharge"
        } else {
            ""
        }
    );
    let _ = writeln!(
        s,
        "[domain]\nlower = {}\nupper = {}\nperiodic = [false, false, false]\n",
        v(pour.domain_lower),
        v(pour.domain_upper)
    );
    let _ = writeln!(
        s,
        "[[material]]\nname = \"particle\"\n{}\n\n[[material]]\nname = \"reference\"\n{}\n",
        m(&st.material),
        m(&c.reference)
    );
    let _ = writeln!(
        s,
        "[contact]\nlaw = \"hertz\"\ndamping = \"tsuji\"\nrestitution = {:?}\nfriction = {:?}\n\
         tangential = \"{}\"\nrolling_friction = {:?}\n",
        st.restitution,
        st.friction,
        st.tangential.row().name,
        st.rolling_friction
    );
    let _ = writeln!(
        s,
        "[[particles]]\nrandom = {{ count = {}, radius = {:?}, lower = {}, upper = {}, seed = {} }}\n\
         material = \"particle\"\n",
        pour.count,
        pour.radius,
        v(pour.lower),
        v(pour.upper),
        st.seed
    );
    let [[x0, x1], [y0, y1]] = pour.sides;
    for (point, normal) in [
        ([x0, 0.0, 0.0], [1.0, 0.0, 0.0]),
        ([x1, 0.0, 0.0], [-1.0, 0.0, 0.0]),
        ([0.0, y0, 0.0], [0.0, 1.0, 0.0]),
        ([0.0, y1, 0.0], [0.0, -1.0, 0.0]),
    ] {
        let _ = writeln!(
            s,
            "[[wall]]\nplane = {{ point = {}, normal = {} }}\nmaterial = \"particle\"\n\
             friction = 0.0\nrolling_friction = 0.0\n",
            v(point),
            v(normal)
        );
    }
    let _ = writeln!(
        s,
        "[[wall]]\nmesh = {{ file = {:?} }}\nmaterial = \"reference\"",
        file.display().to_string()
    );
    if let Some(mu) = st.floor_friction {
        let _ = writeln!(
            s,
            "friction = {mu:?}\nrolling_friction = {:?}",
            st.rolling_friction
        );
    }
    let _ = writeln!(s);
    if let Some((plug, motion)) = region.plug(settle as f64 * dt) {
        let _ = writeln!(
            s,
            "[[wall]]\nplane = {{ point = {}, normal = {} }}\nmaterial = \"reference\"\n\
             motion = {{ velocity = {}, start = {:?}, end = {:?} }}\n",
            v(plug.point),
            v(plug.normal),
            v(motion.velocity),
            motion.start,
            motion.end
        );
    }
    if let Some((lower, upper)) = region.outlet_box(pour.domain_lower[2]) {
        let _ = writeln!(
            s,
            "[[outlet]]\nregion = {{ box = {{ lower = {}, upper = {} }} }}\n",
            v(lower),
            v(upper)
        );
    }
    let _ = writeln!(
        s,
        "[motion]\ngravity = [0.0, 0.0, {:?}]\n\n[integration]\nscheme = \"verlet\"\ndt = {dt:?}\n\
         steps = {}\n\n[output]\nevery = {}\nseries_every = {every}",
        -super::pour::GRAVITY,
        settle + discharge,
        settle + discharge,
    );
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sources::mesh_tiling::shapes;
    use crate::walls::mesh::{MeshOptions, Transform};
    use std::path::Path;

    fn geometry(t: &[crate::walls::mesh::Triangle]) -> MeshGeometry {
        MeshGeometry::from_triangles(
            Path::new("t"),
            t,
            &Transform::default(),
            &MeshOptions::default(),
        )
        .unwrap()
    }

    #[test]
    fn a_flat_square_has_no_outlet_and_takes_its_whole_box() {
        let m = geometry(&shapes::square(0.01));
        let r = region(&m, false, 1e-3, 100, "square").unwrap();
        assert_eq!(r.outlet, None);
        assert_eq!(r.box_fraction, 1.0);
        assert_eq!(r.pour.lower, [0.0, 0.0, 2e-3]);
        assert_eq!([r.pour.upper[0], r.pour.upper[1]], [0.01, 0.01]);
    }

    #[test]
    fn an_open_cylinder_has_its_bottom_rim_as_outlet() {
        // An open tube (shapes::hopper with equal radii, normals inward),
        // 96 facets of radius 5 mm: the clear radius is the polygon's
        // inscribed radius 5 cos(π/96) mm, the outlet at z = 0.
        let m = geometry(&shapes::hopper(5e-3, 5e-3, 10e-3, 10e-3, 96));
        let r = region(&m, false, 0.5e-3, 100, "tube").unwrap();
        let o = r.outlet.unwrap();
        assert_eq!(o.z, 0.0);
        assert_eq!(o.edges, 96);
        let inscribed = 5e-3 * (std::f64::consts::PI / 96.0).cos();
        assert!((o.radius - inscribed).abs() < 1e-12, "{}", o.radius);
        // Box corners inset by R inside the circle: f half-width − R ≤
        // 5 mm / √2 → f = 0.7 (0.7 × 5 − 0.5 = 3.0 mm; 0.8: 3.5 mm > 3.54 − R).
        assert!((r.box_fraction - 0.7).abs() < 1e-12, "{}", r.box_fraction);
    }

    #[test]
    fn a_closed_part_has_no_pour_column_inside() {
        // The closed cylinder (caps, normals outward), the particles inside
        // it (flip): every column from above crosses the lid. Refused,
        // naming --wall.
        let m = geometry(&shapes::cylinder(5e-3, 20e-3, 96, 1));
        let e = region(&m, true, 0.5e-3, 100, "cylinder").unwrap_err();
        assert!(e.to_string().contains("--wall"), "{e}");
    }

    #[test]
    fn batch_rates_of_a_steady_discharge() {
        // 1 kg/s from t = 0: the rate is exact, the batches agree.
        let rows: Vec<(f64, f64)> = (0..=20)
            .map(|k| (0.01 * k as f64, 0.01 * k as f64))
            .collect();
        let (rate, se) = discharge_rate(&rows, 0.05).unwrap();
        assert!((rate - 1.0).abs() < 1e-12);
        assert!(se < 1e-12);
        assert!(discharge_rate(&rows[..8], 0.05).is_none());
    }
}
