//! Wall forces without friction, for every wall type of `crate::walls`
//! (planes: an elastic half-space of its own material, the paper's
//! r = ∞, ζ = E_wall/E), the same contact model as the sphere pairs.

use dembound_physics::contact::ContactHistory;

use super::contacts::{LawTable, NO_HISTORY};
use crate::bodies::Bodies;
use crate::parallel::{SharedMut, Workers, BODY_CHUNK};
pub use crate::walls::{
    plane_overlap, PlaneWall, Surface, WallContacts, WallContactsMut, WallLoad,
};

/// The force that starts body i's total: gravity (free bodies) plus its
/// wall forces at position `x` and velocity `v` ([`add_wall_forces`]).
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
    add_wall_forces(bodies, i, x, v, surfaces, walls, laws, &mut acc);
    acc
}

/// Adds to `acc` free body i's wall forces at position `x` and velocity
/// `v`, updating its wall near entries (touching flags, histories, and
/// each touching entry's [`WallLoad`]: what the wall takes from it).
/// Reads of `bodies`: radius, mass, class.
///
/// # Safety
/// Body i's entries of `walls` are touched by no other
/// thread meanwhile.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub unsafe fn add_wall_forces(
    bodies: &Bodies,
    i: usize,
    x: [f64; 3],
    v: [f64; 3],
    surfaces: &[Surface],
    walls: &WallContactsMut,
    laws: &LawTable,
    acc: &mut [f64; 3],
) {
    let none = SharedMut(std::ptr::null_mut());
    add_wall_forces_with::<false>(bodies, i, x, v, surfaces, walls, laws, acc, none);
}

/// [`add_wall_forces`], and each touching entry k's normal elastic energy
/// (J) into `energy[k]`: what [`plane_observables`] sums of it at this
/// state (the same law, overlap and history as the force left it), for
/// the series row ([`plane_observables_tallied`]). Entries not touching
/// are not written.
///
/// # Safety
/// As [`add_wall_forces`]; `energy` points to one value per entry of
/// `walls`, body i's touched by no other thread meanwhile.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub unsafe fn add_wall_forces_tallied(
    bodies: &Bodies,
    i: usize,
    x: [f64; 3],
    v: [f64; 3],
    surfaces: &[Surface],
    walls: &WallContactsMut,
    laws: &LawTable,
    acc: &mut [f64; 3],
    energy: SharedMut<f64>,
) {
    add_wall_forces_with::<true>(bodies, i, x, v, surfaces, walls, laws, acc, energy);
}

/// [`add_wall_forces`]; `TALLY`: [`add_wall_forces_tallied`].
///
/// # Safety
/// As [`add_wall_forces_tallied`] (`energy` unused without `TALLY`).
#[inline(always)]
#[allow(clippy::too_many_arguments)]
unsafe fn add_wall_forces_with<const TALLY: bool>(
    bodies: &Bodies,
    i: usize,
    x: [f64; 3],
    v: [f64; 3],
    surfaces: &[Surface],
    walls: &WallContactsMut,
    laws: &LawTable,
    acc: &mut [f64; 3],
    energy: SharedMut<f64>,
) {
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
            let on_sphere = [fw * c.normal[0], fw * c.normal[1], fw * c.normal[2]];
            acc[0] += on_sphere[0];
            acc[1] += on_sphere[1];
            acc[2] += on_sphere[2];
            // What the wall takes: the observables' wall loads.
            *walls.load.at(k) =
                WallLoad::of_contact(on_sphere, None, x, r, c.normal, surface.torque_point());
            if TALLY {
                // As `plane_observables`: the history as the force left
                // it (none kept: the default).
                let h = if walls.keep { &*hist } else { &NO_HISTORY };
                *energy.at(k) = laws.elastic_energy(&law, c.overlap, h);
            }
        } else if *touching {
            *hist = ContactHistory::default();
            *touching = false;
        }
    }
}

/// Sets every body's force to gravity plus its wall forces; with
/// `energy`, also each touching entry's elastic energy into it
/// ([`add_wall_forces_tallied`]; resized to one value per entry).
#[allow(clippy::too_many_arguments)]
pub fn start_forces(
    bodies: &Bodies,
    surfaces: &[Surface],
    walls: &mut WallContacts,
    laws: &LawTable,
    gravity: [f64; 3],
    force: &mut [[f64; 3]],
    workers: &Workers,
    energy: Option<&mut Vec<f64>>,
) {
    let n = bodies.len();
    assert!(walls.bodies() == n);
    let tally = energy.map(|e| {
        e.resize(walls.key.len(), 0.0);
        SharedMut::new(e)
    });
    let w = walls.shared();
    let f = SharedMut::new(force);
    workers.run_bodies(n, BODY_CHUNK, |c| {
        for i in c * BODY_CHUNK..((c + 1) * BODY_CHUNK).min(n) {
            // SAFETY: chunks are disjoint ranges of bodies; the energies
            // are one per entry (resized), body i's entries its own.
            unsafe {
                let (x, v) = (bodies.position[i], bodies.velocity[i]);
                *f.at(i) = match tally {
                    None => body_force(bodies, i, x, v, surfaces, &w, laws, gravity),
                    Some(e) if !bodies.fixed[i] => {
                        let m = bodies.mass[i];
                        let mut acc = [m * gravity[0], m * gravity[1], m * gravity[2]];
                        add_wall_forces_tallied(bodies, i, x, v, surfaces, &w, laws, &mut acc, e);
                        acc
                    }
                    Some(_) => [0.0; 3],
                };
            }
        }
    });
}

/// The wall contacts at the bodies' current state: how many touch, and
/// their elastic energy (J). Chunked sums in chunk order: deterministic.
/// (The walls' loads are the force pass's: `WallContacts::load`.)
pub fn plane_observables(
    bodies: &Bodies,
    surfaces: &[Surface],
    walls: &WallContacts,
    laws: &LawTable,
    workers: &Workers,
) -> (usize, f64) {
    let n = bodies.len();
    if surfaces.is_empty() || walls.bodies() != n {
        return (0, 0.0);
    }
    let partial: Vec<[f64; 2]> = workers.map_bodies(n, BODY_CHUNK, |c| {
        // Count, then energy.
        let mut s = [0.0; 2];
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
                    let law = laws.wall(bodies, i, surface.law_slot(key.element));
                    let hist = walls.history.get(k).unwrap_or(&NO_HISTORY);
                    s[0] += 1.0;
                    s[1] += laws.elastic_energy(&law, c.overlap, hist);
                }
            }
        }
        s
    });
    let mut total = [0.0; 2];
    for p in partial {
        total[0] += p[0];
        total[1] += p[1];
    }
    (total[0] as usize, total[1])
}

/// [`plane_observables`] from what the force pass at this state tallied
/// ([`add_wall_forces_tallied`]): its touching flags and each touching
/// entry's `energy`, summed in the same chunks and order (the contacts
/// not evaluated again: the same bits). `None` when `energy` is not one
/// value per entry.
pub fn plane_observables_tallied(
    bodies: &Bodies,
    surfaces: &[Surface],
    walls: &WallContacts,
    workers: &Workers,
    energy: &[f64],
) -> Option<(usize, f64)> {
    let n = bodies.len();
    if surfaces.is_empty() || walls.bodies() != n {
        return Some((0, 0.0));
    }
    if energy.len() != walls.key.len() || walls.touching.len() != walls.key.len() {
        return None;
    }
    let (start, fixed, touching) = (&walls.start[..], &bodies.fixed[..], &walls.touching[..]);
    let partial: Vec<[f64; 2]> = workers.map_bodies(n, BODY_CHUNK, |c| {
        // Count, then energy.
        let mut s = [0.0; 2];
        let (first, end) = (c * BODY_CHUNK, ((c + 1) * BODY_CHUNK).min(n));
        // Body i's entries are start[i]..start[i + 1], the ranges ascending
        // with the body: a run of bodies a..b none of which is fixed has its
        // entries in start[a]..start[b], body by body, each body's in order.
        // Fixed bodies are skipped, as in `plane_observables` (their flags
        // are not this pass's).
        // One test over the chunk's flags (vectorised) before the runs.
        let any_fixed = fixed[first..end].iter().fold(false, |any, &f| any | f);
        let mut i = first;
        while i < end {
            let run_end = if any_fixed {
                fixed[i..end].iter().position(|&f| f).map_or(end, |k| i + k)
            } else {
                end
            };
            let (lo, hi) = (start[i] as usize, start[run_end] as usize);
            for (&t, &e) in touching[lo..hi].iter().zip(&energy[lo..hi]) {
                // Touching: the force pass found overlap > 0.
                if t {
                    s[0] += 1.0;
                    s[1] += e;
                }
            }
            i = run_end + 1;
        }
        s
    });
    let mut total = [0.0; 2];
    for p in partial {
        total[0] += p[0];
        total[1] += p[1];
    }
    Some((total[0] as usize, total[1]))
}
