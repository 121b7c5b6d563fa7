//! Plane walls: an elastic half-space of its own material (the paper's
//! r = ∞, ζ = E_wall/E, `PairProperties::sphere_plane`), the same contact
//! model as the sphere pairs.

use dembound_physics::contact::ContactHistory;
use rayon::prelude::*;

use super::contacts::LawTable;
use super::{SharedMut, SUM_CHUNK};
use crate::bodies::Bodies;

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

/// Per body and plane: the contact history, and a bit mask of the planes a
/// body touches. Permuted with the bodies.
#[derive(Debug, Clone, Default)]
pub struct WallContacts {
    pub planes: usize,
    /// `history[i * planes + p]`.
    pub history: Vec<ContactHistory>,
    pub touching: Vec<u64>,
}

impl WallContacts {
    pub fn new(bodies: usize, planes: usize) -> Self {
        Self {
            planes,
            history: vec![ContactHistory::default(); bodies * planes],
            touching: vec![0; bodies],
        }
    }

    pub fn permute(&mut self, order: &[u32]) {
        let p = self.planes;
        if p == 0 {
            return;
        }
        let mut h = Vec::with_capacity(self.history.len());
        for &o in order {
            h.extend_from_slice(&self.history[o as usize * p..(o as usize + 1) * p]);
        }
        self.history = h;
        self.touching = order.iter().map(|&o| self.touching[o as usize]).collect();
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

/// Sets every body's force to gravity (free bodies) plus its plane-wall
/// forces, updating the wall histories. Per body, so parallel and exact.
pub fn start_forces(
    bodies: &Bodies,
    planes: &[PlaneWall],
    walls: &mut WallContacts,
    laws: &LawTable,
    gravity: [f64; 3],
    force: &mut [[f64; 3]],
    pool: &rayon::ThreadPool,
) {
    let np = planes.len();
    let hist_ptr = SharedMut(walls.history.as_mut_ptr());
    let mask_ptr = SharedMut(walls.touching.as_mut_ptr());
    pool.install(|| {
        force.par_iter_mut().enumerate().for_each(|(i, f)| {
            let (hist_ptr, mask_ptr) = (hist_ptr, mask_ptr);
            let mut acc = if bodies.fixed[i] {
                [0.0; 3]
            } else {
                let m = bodies.mass[i];
                [m * gravity[0], m * gravity[1], m * gravity[2]]
            };
            for (p, plane) in planes.iter().enumerate() {
                let (h, rate) = plane_overlap(
                    plane,
                    bodies.position[i],
                    bodies.velocity[i],
                    bodies.radius[i],
                );
                let bit = 1u64 << p;
                // SAFETY: body i's mask and histories are touched by this
                // iteration only.
                let mask = unsafe { &mut *mask_ptr.0.add(i) };
                let hist = unsafe { &mut *hist_ptr.0.add(i * np + p) };
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
            *f = acc;
        });
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
    pool: &rayon::ThreadPool,
) -> (Vec<[f64; 3]>, usize, f64) {
    let np = planes.len();
    let n = bodies.len();
    if np == 0 {
        return (Vec::new(), 0, 0.0);
    }
    // Layout of a partial sum: 3 per plane, then count, then energy.
    let width = 3 * np + 2;
    let partial: Vec<Vec<f64>> = pool.install(|| {
        (0..n.div_ceil(SUM_CHUNK))
            .into_par_iter()
            .map(|c| {
                let mut s = vec![0.0; width];
                for i in c * SUM_CHUNK..((c + 1) * SUM_CHUNK).min(n) {
                    for (p, plane) in planes.iter().enumerate() {
                        let (h, rate) = plane_overlap(
                            plane,
                            bodies.position[i],
                            bodies.velocity[i],
                            bodies.radius[i],
                        );
                        if h > 0.0 {
                            let law = laws.plane(bodies, i, p);
                            let hist = &walls.history[i * np + p];
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
            })
            .collect()
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
