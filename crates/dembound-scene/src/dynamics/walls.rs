//! Plane walls: an elastic half-space of its own material (the paper's
//! r = ∞, ζ = E_wall/E, `PairProperties::sphere_plane`), the same contact
//! model as the sphere pairs.

use dembound_physics::contact::ContactHistory;

use super::contacts::{LawTable, NO_HISTORY};
use crate::bodies::Bodies;
use crate::parallel::{SharedMut, Workers, BODY_CHUNK};

/// Most plane walls a scene may have (a bit mask per body).
pub const MAX_PLANES: usize = 64;

/// A plane wall.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlaneWall {
    /// Index of the wall in file order.
    pub wall: usize,
    /// A point of the plane, m.
    pub point: [f64; 3],
    /// Unit normal into the domain.
    pub normal: [f64; 3],
}

/// Per body and plane: the contact history; bit masks of the planes a body
/// touches and of those it is near (within R + skin at the last list
/// build, so that it cannot touch any other before the next one). Permuted
/// with the bodies.
#[derive(Debug, Clone, Default)]
pub struct WallContacts {
    pub planes: usize,
    /// `history[i * planes + p]`.
    pub history: Vec<ContactHistory>,
    pub touching: Vec<u64>,
    pub near: Vec<u64>,
}

/// Keeps the per-(body, plane) records `v[i * planes + p]` of bodies
/// `order` (new body k ← old `order[k]`): plane histories, springs and
/// collision tracks move with their bodies. Nothing to do without planes
/// or records.
pub fn permute_per_plane<T: Copy>(v: &mut Vec<T>, planes: usize, order: &[u32]) {
    if planes == 0 || v.is_empty() {
        return;
    }
    let mut out = Vec::with_capacity(order.len() * planes);
    for &o in order {
        out.extend_from_slice(&v[o as usize * planes..(o as usize + 1) * planes]);
    }
    *v = out;
}

impl WallContacts {
    /// `history`: whether the law keeps one (else none is stored).
    pub fn new(bodies: usize, planes: usize, history: bool) -> Self {
        Self {
            planes,
            history: if history {
                vec![ContactHistory::default(); bodies * planes]
            } else {
                Vec::new()
            },
            touching: vec![0; bodies],
            near: vec![
                if planes > 0 {
                    u64::MAX >> (64 - planes)
                } else {
                    0
                };
                bodies
            ],
        }
    }

    pub fn permute(&mut self, order: &[u32]) {
        permute_per_plane(&mut self.history, self.planes, order);
        if !self.touching.is_empty() {
            self.touching = order.iter().map(|&o| self.touching[o as usize]).collect();
        }
    }

    /// Marks the planes within R + `skin` of each free body.
    pub fn update_near(&mut self, bodies: &Bodies, planes: &[PlaneWall], skin: f64) {
        self.near = (0..bodies.len())
            .map(|i| {
                let mut m = 0u64;
                if !bodies.fixed[i] {
                    for (p, plane) in planes.iter().enumerate() {
                        let (h, _) =
                            plane_overlap(plane, bodies.position[i], [0.0; 3], bodies.radius[i]);
                        if h > -skin {
                            m |= 1 << p;
                        }
                    }
                }
                m
            })
            .collect();
    }
}

/// Overlap (m) and overlap rate (m/s) of a sphere against a plane.
#[inline(always)]
pub fn plane_overlap(plane: &PlaneWall, x: [f64; 3], v: [f64; 3], radius: f64) -> (f64, f64) {
    let n = plane.normal;
    let d = (x[0] - plane.point[0]) * n[0]
        + (x[1] - plane.point[1]) * n[1]
        + (x[2] - plane.point[2]) * n[2];
    let rate = -(v[0] * n[0] + v[1] * n[1] + v[2] * n[2]);
    (radius - d, rate)
}

/// The force that starts body i's total: gravity (free bodies) plus its
/// plane-wall forces at position `x` and velocity `v`, updating its wall
/// histories and mask. Reads of `bodies`: radius, mass, fixed flag, class.
///
/// # Safety
/// Body i's entries of `walls` (mask, histories) are touched by no other
/// thread meanwhile.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub unsafe fn body_force(
    bodies: &Bodies,
    i: usize,
    x: [f64; 3],
    v: [f64; 3],
    planes: &[PlaneWall],
    walls: &WallContactsMut,
    laws: &LawTable,
    gravity: [f64; 3],
) -> [f64; 3] {
    let mut acc = if bodies.fixed[i] {
        return [0.0; 3];
    } else {
        let m = bodies.mass[i];
        [m * gravity[0], m * gravity[1], m * gravity[2]]
    };
    let mask = walls.touching.at(i);
    let mut todo = *walls.near.at(i) | *mask;
    while todo != 0 {
        let p = todo.trailing_zeros() as usize;
        todo &= todo - 1;
        let plane = &planes[p];
        let (h, rate) = plane_overlap(plane, x, v, bodies.radius[i]);
        let bit = 1u64 << p;
        let mut scratch = NO_HISTORY;
        let hist = if walls.keep {
            walls.history.at(i * walls.planes + p)
        } else {
            &mut scratch
        };
        if h > 0.0 {
            let law = laws.plane(bodies, i, p);
            let fw = law.force(h, rate, hist);
            law.update(h, rate, hist);
            *mask |= bit;
            acc[0] += fw * plane.normal[0];
            acc[1] += fw * plane.normal[1];
            acc[2] += fw * plane.normal[2];
        } else if *mask & bit != 0 {
            *hist = ContactHistory::default();
            *mask &= !bit;
        }
    }
    acc
}

/// Shared pointers into a [`WallContacts`] for per-body parallel access.
#[derive(Clone, Copy)]
pub struct WallContactsMut {
    pub planes: usize,
    /// Histories are kept.
    pub keep: bool,
    pub history: SharedMut<ContactHistory>,
    pub touching: SharedMut<u64>,
    pub near: SharedMut<u64>,
}

impl WallContacts {
    pub fn shared(&mut self) -> WallContactsMut {
        WallContactsMut {
            planes: self.planes,
            keep: !self.history.is_empty(),
            history: SharedMut::new(&mut self.history),
            touching: SharedMut::new(&mut self.touching),
            near: SharedMut::new(&mut self.near),
        }
    }
}

/// Sets every body's force to gravity plus its plane-wall forces.
pub fn start_forces(
    bodies: &Bodies,
    planes: &[PlaneWall],
    walls: &mut WallContacts,
    laws: &LawTable,
    gravity: [f64; 3],
    force: &mut [[f64; 3]],
    workers: &Workers,
) {
    let n = bodies.len();
    let w = walls.shared();
    let f = SharedMut::new(force);
    workers.run_bodies(n, BODY_CHUNK, |c| {
        for i in c * BODY_CHUNK..((c + 1) * BODY_CHUNK).min(n) {
            // SAFETY: chunks are disjoint ranges of bodies.
            unsafe {
                *f.at(i) = body_force(
                    bodies,
                    i,
                    bodies.position[i],
                    bodies.velocity[i],
                    planes,
                    &w,
                    laws,
                    gravity,
                )
            };
        }
    });
}

/// Per plane, at the bodies' current state: the force on the wall (N, the
/// opposite of the force on the spheres), contact count and elastic energy
/// (J). Chunked sums in chunk order: deterministic.
pub fn plane_observables(
    bodies: &Bodies,
    planes: &[PlaneWall],
    walls: &WallContacts,
    laws: &LawTable,
    workers: &Workers,
) -> (Vec<[f64; 3]>, usize, f64) {
    let np = planes.len();
    let n = bodies.len();
    if np == 0 {
        return (Vec::new(), 0, 0.0);
    }
    // Layout of a partial sum: 3 per plane, then count, then energy.
    let width = 3 * np + 2;
    let partial: Vec<Vec<f64>> = workers.map_bodies(n, BODY_CHUNK, |c| {
        let mut s = vec![0.0; width];
        for i in c * BODY_CHUNK..((c + 1) * BODY_CHUNK).min(n) {
            // Fixed bodies never touch a plane (both are fixed), as in
            // the forces (`update_near`).
            if bodies.fixed[i] {
                continue;
            }
            for (p, plane) in planes.iter().enumerate() {
                let (h, rate) = plane_overlap(
                    plane,
                    bodies.position[i],
                    bodies.velocity[i],
                    bodies.radius[i],
                );
                if h > 0.0 {
                    let law = laws.plane(bodies, i, p);
                    let hist = walls.history.get(i * np + p).unwrap_or(&NO_HISTORY);
                    let fw = law.force(h, rate, hist);
                    for a in 0..3 {
                        s[3 * p + a] -= fw * plane.normal[a];
                    }
                    s[3 * np] += 1.0;
                    s[3 * np + 1] += laws.elastic_energy(&law, h, hist);
                }
            }
        }
        s
    });
    let mut total = vec![0.0; width];
    for p in partial {
        for k in 0..width {
            total[k] += p[k];
        }
    }
    let forces = (0..np)
        .map(|p| [total[3 * p], total[3 * p + 1], total[3 * p + 2]])
        .collect();
    (forces, total[3 * np] as usize, total[3 * np + 1])
}
