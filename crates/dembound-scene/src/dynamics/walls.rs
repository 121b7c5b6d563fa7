//! Wall forces without friction, for every wall type of `crate::walls`
//! (planes: an elastic half-space of its own material, the paper's
//! r = ∞, ζ = E_wall/E), the same contact model as the sphere pairs.

use dembound_physics::contact::ContactHistory;

use super::contacts::{LawTable, NO_HISTORY};
use crate::bodies::Bodies;
use crate::parallel::{SharedMut, Workers, BODY_CHUNK};
pub use crate::walls::{plane_overlap, PlaneWall, Surface, WallContacts, WallContactsMut};

/// The force that starts body i's total: gravity (free bodies) plus its
/// wall forces at position `x` and velocity `v`, updating its wall
/// near entries (touching flags, histories). Reads of `bodies`: radius, mass, fixed flag, class.
///
/// # Safety
/// Body i's entries of `walls` are touched by no other
/// thread meanwhile.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub unsafe fn body_force(
    bodies: &Bodies,
    i: usize,
    x: [f64; 3],
    v: [f64; 3],
    surfaces: &[Surface],
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
    let (s, e) = walls.range(i);
    let r = bodies.radius[i];
    for k in s..e {
        let key = *walls.key.at(k);
        let surface = surfaces.get_unchecked(key.wall as usize);
        let c = surface.contact(key.element, x, v, r);
        let touching = walls.touching.at(k);
        let mut scratch = NO_HISTORY;
        let hist = if walls.keep {
            walls.history.at(k)
        } else {
            &mut scratch
        };
        if c.overlap > 0.0 {
            let law = laws.wall(bodies, i, surface.law_slot(key.element));
            // The composer's normal stage (a frictionless contact is that
            // stage alone): the force on the sphere is F_n along the
            // wall's normal.
            let fw = law.normal_stage(c.overlap, c.rate, hist);
            *touching = true;
            acc[0] += fw * c.normal[0];
            acc[1] += fw * c.normal[1];
            acc[2] += fw * c.normal[2];
        } else if *touching {
            *hist = ContactHistory::default();
            *touching = false;
        }
    }
    acc
}

/// Sets every body's force to gravity plus its wall forces.
pub fn start_forces(
    bodies: &Bodies,
    surfaces: &[Surface],
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
                    surfaces,
                    &w,
                    laws,
                    gravity,
                )
            };
        }
    });
}

/// Per wall (surface index), at the bodies' current state: the force on
/// the wall (N, the opposite of the force on the spheres), contact count
/// and elastic energy (J). Chunked sums in chunk order: deterministic.
pub fn plane_observables(
    bodies: &Bodies,
    surfaces: &[Surface],
    walls: &WallContacts,
    laws: &LawTable,
    workers: &Workers,
) -> (Vec<[f64; 3]>, usize, f64) {
    let np = surfaces.len();
    let n = bodies.len();
    if np == 0 {
        return (Vec::new(), 0, 0.0);
    }
    if walls.bodies() != n {
        return (vec![[0.0; 3]; np], 0, 0.0);
    }
    // Layout of a partial sum: 3 per wall, then count, then energy.
    let width = 3 * np + 2;
    let partial: Vec<Vec<f64>> = workers.map_bodies(n, BODY_CHUNK, |c| {
        let mut s = vec![0.0; width];
        for i in c * BODY_CHUNK..((c + 1) * BODY_CHUNK).min(n) {
            // Fixed bodies never touch a wall (both are fixed), as in
            // the forces (`WallContacts::refresh`).
            if bodies.fixed[i] {
                continue;
            }
            for k in walls.range(i) {
                let key = walls.key[k];
                let surface = &surfaces[key.wall as usize];
                let c = surface.contact(
                    key.element,
                    bodies.position[i],
                    bodies.velocity[i],
                    bodies.radius[i],
                );
                if c.overlap > 0.0 {
                    let p = key.wall as usize;
                    let law = laws.wall(bodies, i, surface.law_slot(key.element));
                    let hist = walls.history.get(k).unwrap_or(&NO_HISTORY);
                    let fw = law.force(c.overlap, c.rate, hist);
                    for a in 0..3 {
                        s[3 * p + a] -= fw * c.normal[a];
                    }
                    s[3 * np] += 1.0;
                    s[3 * np + 1] += laws.elastic_energy(&law, c.overlap, hist);
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
