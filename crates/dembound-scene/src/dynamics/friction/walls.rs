//! Wall friction: the per-body pass that adds each wall contact's force
//! and torques (the composer's contact, the wall as side 2) and records
//! what the wall took from it (`WallContacts::load`).

use dembound_physics::contact::{ContactForces, ContactHistory, ContactState, Geometry, Side};

use super::row_laws::{HertzMindlin, Variants};
use super::springs::split;
use super::{add, FrictionLaw, FrictionTable, WallShear};
use crate::bodies::Bodies;
use crate::dynamics::contacts::{LawTable, NO_HISTORY};
use crate::walls::{Surface, WallContactsMut, WallLoad};

/// What the per-body friction pass reads.
#[derive(Clone, Copy)]
pub struct BodyForceInput<'a> {
    pub bodies: &'a Bodies,
    pub surfaces: &'a [Surface],
    pub laws: &'a LawTable,
    pub friction: &'a FrictionTable,
    pub gravity: [f64; 3],
    /// The step whose forces these are (see [`WallShear`]).
    pub step: u64,
    /// Time since the last evaluation, s (0: do not move the springs).
    pub dt: f64,
}

/// Gravity and plane-wall forces (with friction) and the plane-wall
/// torques of body i at position `x`, velocity `v` and spin `w`: the
/// frictionless `walls::body_force` with the tangential force, its torque
/// and the rolling torque added.
///
/// # Safety
/// Body i's entries of `walls` and `shear` are touched by no other thread.
#[inline(always)]
pub unsafe fn body_force(
    c: &BodyForceInput,
    i: usize,
    (x, v, w): ([f64; 3], [f64; 3], [f64; 3]),
    walls: &WallContactsMut,
) -> ([f64; 3], [f64; 3]) {
    let bodies = c.bodies;
    if bodies.fixed[i] {
        return ([0.0; 3], [0.0; 3]);
    }
    let mut acc = gravity_force(c, i);
    let mut torque = [0.0; 3];
    add_plane_forces::<false>(c, i, (x, v, w), walls, &mut acc, &mut torque);
    (acc, torque)
}

/// The composer's whole contact (`ContactLaw::calculate_forces`) for a
/// law whose tangential spring stores its force
/// (`TangentialPair::stores_force`), not inlined into the wall loops.
#[inline(never)]
fn calculate_forces_storing(
    fl: &FrictionLaw,
    g: &Geometry,
    a: &Side,
    b: &Side,
    state: ContactState,
    dt: f64,
) -> ContactForces {
    fl.calculate_forces_known(true, g, a, b, state, dt)
}

/// Body i's weight m g, N.
#[inline(always)]
pub fn gravity_force(c: &BodyForceInput, i: usize) -> [f64; 3] {
    let m = c.bodies.mass[i];
    let g = c.gravity;
    [m * g[0], m * g[1], m * g[2]]
}

/// Adds the walls' forces (with friction) onto `acc` and their torques
/// onto `torque`, for free body i at (x, v, w) ([`body_force`] without
/// the weight), over its near entries.
///
/// `HERTZ_MINDLIN`: every class–plane law of the table has the variants
/// of [`HertzMindlin`] ([`planes_are_hertz_mindlin`]), stated to the
/// compiler at each lookup as the pair kernel does (`row_laws`): the same
/// sub-model methods on the same values, without the dispatch on their
/// variants.
///
/// # Safety
/// As [`body_force`]; with `HERTZ_MINDLIN`, `planes_are_hertz_mindlin(c.friction)`.
#[inline(always)]
pub unsafe fn add_plane_forces<const HERTZ_MINDLIN: bool>(
    c: &BodyForceInput,
    i: usize,
    (x, v, w): ([f64; 3], [f64; 3], [f64; 3]),
    walls: &WallContactsMut,
    acc: &mut [f64; 3],
    torque: &mut [f64; 3],
) {
    let bodies = c.bodies;
    let (s, e) = walls.range(i);
    let r = bodies.radius[i];
    for k in s..e {
        let key = *walls.key.at(k);
        let surface = c.surfaces.get_unchecked(key.wall as usize);
        let p = surface.contact(key.element, x, v, r);
        let h = p.overlap;
        let touching = walls.touching.at(k);
        let mut scratch = NO_HISTORY;
        let hist = if walls.keep {
            walls.history.at(k)
        } else {
            &mut scratch
        };
        let sh = walls.shear.at(k);
        if h > 0.0 {
            let mut computed = None;
            let slot = surface.law_slot(key.element);
            let fl = c.friction.plane(c.laws, bodies, i, slot, &mut computed);
            if HERTZ_MINDLIN {
                // SAFETY: every row of the table has these variants (the
                // caller's), and with a table `plane` returns a row.
                unsafe { HertzMindlin::assume(fl) };
            }
            *touching = true;
            if sh.stamp != c.step {
                sh.before = sh.shear;
                sh.stamp = c.step;
            }
            let mut d = sh.before;
            let (ds, dr) = split(&mut d);
            // The sphere is body 1, the wall body 2 (n from the sphere to
            // the wall): the composer's whole contact.
            let g = p.geometry();
            let sphere = Side {
                velocity: v,
                spin: w,
                arm: r,
                inverse_inertia: bodies.inverse_inertia[i],
            };
            let wall = surface.side(key.element, &p, x, r);
            let state = ContactState {
                history: hist,
                tangential: ds,
                rolling: c.friction.rolling.then_some(dr),
            };
            // A spring that stores its force (`mindlin_force`; never a
            // Hertz–Mindlin table's) out of line: the displacement springs'
            // code of this loop stays as it was.
            let f = if !HERTZ_MINDLIN && fl.friction.tangential().stores_force() {
                calculate_forces_storing(fl, &g, &sphere, &wall, state, c.dt)
            } else {
                fl.calculate_forces_known(false, &g, &sphere, &wall, state, c.dt)
            };
            sh.shear = d;
            // −F_n n + F_t = F_n (wall normal) + F_t, and the two torque
            // parts added one after the other.
            let on_sphere = f.on_body1(g.normal);
            add(acc, on_sphere);
            add(torque, f.tangential_torque1);
            if let Some(rolling) = f.rolling {
                add(torque, rolling);
            }
            // What the wall takes: the observables' wall loads.
            *walls.load.at(k) =
                WallLoad::of_contact(on_sphere, f.rolling, x, r, p.normal, surface.torque_point());
        } else if *touching {
            *hist = ContactHistory::default();
            *sh = WallShear::default();
            *touching = false;
        }
    }
}

/// Whether every class–plane law of `table` is read from its table and
/// has the variants of [`HertzMindlin`] (then
/// `add_plane_forces::<true>` applies).
pub fn planes_are_hertz_mindlin(table: &FrictionTable) -> bool {
    table.classes > 0 && table.planes.iter().all(HertzMindlin::matches)
}

/// [`prefetch_wall_springs`] for bodies lo..hi together: the entries of
/// consecutive bodies are consecutive, so one loop over lo's first to
/// (hi − 1)'s last entry asks for the same lines, with one test for bodies
/// that have none.
///
/// # Safety
/// lo ≤ hi ≤ the body count of `walls` (`start` holds one more).
#[inline(always)]
pub unsafe fn prefetch_wall_springs_of(lo: usize, hi: usize, walls: &WallContactsMut) {
    #[cfg(target_arch = "x86_64")]
    {
        let (s, e) = (*walls.start.at(lo) as usize, *walls.start.at(hi) as usize);
        for k in s..e {
            prefetch_entry(k, walls);
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = (lo, hi, walls);
}

/// The prefetches of wall entry k (its spring's lines, its history).
///
/// # Safety
/// k < the entry count of `walls`.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
unsafe fn prefetch_entry(k: usize, walls: &WallContactsMut) {
    use std::arch::x86_64::{_mm_prefetch, _MM_HINT_T0};
    let at = walls.shear.0.add(k) as *const i8;
    // Its first and last byte: the lines it spans (≤ 3 of 64 B).
    _mm_prefetch::<_MM_HINT_T0>(at);
    _mm_prefetch::<_MM_HINT_T0>(at.add(64));
    _mm_prefetch::<_MM_HINT_T0>(at.add(std::mem::size_of::<WallShear>() - 1));
    if walls.keep {
        _mm_prefetch::<_MM_HINT_T0>(walls.history.0.add(k) as *const i8);
    }
}

/// Asks the processor to fetch body i's wall springs (and histories), so
/// that [`body_force`] a few bodies later finds them in cache: only the
/// few bodies near a wall read theirs, too sparse a pattern for the
/// hardware prefetcher. A hint only: nothing is read or written.
///
/// # Safety
/// i < the body count of `walls`.
#[inline(always)]
pub unsafe fn prefetch_wall_springs(i: usize, walls: &WallContactsMut) {
    // SAFETY: i + 1 ≤ the body count (the caller's i < it).
    unsafe { prefetch_wall_springs_of(i, i + 1, walls) }
}
