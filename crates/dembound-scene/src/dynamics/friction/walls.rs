//! Wall friction: the per-body pass that adds each wall contact's force
//! and torques (the composer's contact, the wall as side 2) and records
//! what the wall took from it (`WallContacts::load`).

use dembound_physics::contact::{ContactHistory, ContactState, Side};

use super::springs::split;
use super::{add, FrictionTable, WallShear};
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
    add_plane_forces(c, i, (x, v, w), walls, &mut acc, &mut torque);
    (acc, torque)
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
/// # Safety
/// As [`body_force`].
#[inline(always)]
pub unsafe fn add_plane_forces(
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
            let f = fl.calculate_forces(
                &g,
                &sphere,
                &surface.side(key.element, &p, x, r),
                ContactState {
                    history: hist,
                    tangential: ds,
                    rolling: c.friction.rolling.then_some(dr),
                },
                c.dt,
            );
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

/// Asks the processor to fetch body i's wall springs (and histories), so
/// that [`body_force`] a few bodies later finds them in cache: only the
/// few bodies near a wall read theirs, too sparse a pattern for the
/// hardware prefetcher. A hint only: nothing is read or written.
///
/// # Safety
/// i < the body count of `walls`.
#[inline(always)]
pub unsafe fn prefetch_wall_springs(i: usize, walls: &WallContactsMut) {
    #[cfg(target_arch = "x86_64")]
    {
        use std::arch::x86_64::{_mm_prefetch, _MM_HINT_T0};
        let (s, e) = walls.range(i);
        for k in s..e {
            let at = walls.shear.0.add(k) as *const i8;
            // Its first and last byte: the lines it spans (≤ 3 of 64 B).
            _mm_prefetch::<_MM_HINT_T0>(at);
            _mm_prefetch::<_MM_HINT_T0>(at.add(64));
            _mm_prefetch::<_MM_HINT_T0>(at.add(std::mem::size_of::<WallShear>() - 1));
            if walls.keep {
                _mm_prefetch::<_MM_HINT_T0>(walls.history.0.add(k) as *const i8);
            }
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = (i, walls);
}
