//! Spheres that leave the scene for good (issue 28): the test of a free
//! sphere lost outside the box (`domain.outside`), and, under
//! `domain.outside = "delete"`, their removal with the count, the mass and
//! the energy they carry out booked, so that the energy balance still
//! closes: K + E + P + D − W + C = E₀, C the energy carried out. The same
//! machinery removes the free spheres whose centres are inside an outlet
//! region, a box or a cylinder (`[[outlet]]`), counted by outlet. An outlet too removes a sphere
//! only once it touches nothing: then it carries out K + P only, exactly
//! (a contact's elastic energy would otherwise leave with it unbooked, or
//! booked with an error of the step's half kick by the contact force).
//!
//! When: at a neighbour-list rebuild of a step (the only place the engine
//! reorders and resizes its bodies already), just before the lists are
//! built; the decision depends on the sphere's own state only, and the
//! rebuild steps are the same on any number of threads, so a run removes
//! the same spheres at the same steps however it is split. Which: a free
//! sphere lost for good ([`lost_axis`]) that touches nothing (no sphere, no
//! wall element: a lost sphere still touching something waits, so that no
//! contact's elastic energy leaves with it). Ids stay: the others keep
//! their input index; per-sphere outputs list the spheres still there, in
//! input order.
//!
//! The energy carried out: ½ m v² (+ ½ I ω² with friction) − m g·x of the
//! sphere at the rebuild, which is mid-step: Verlet has x(t + Δt) and the
//! half-step velocity v(t + Δt/2), completed here by the free flight's last
//! half kick, v(t + Δt) = v(t + Δt/2) + g Δt/2 (a sphere that touches
//! nothing feels gravity only, and Verlet conserves K + P of a free flight
//! exactly, so this is the energy it had at every earlier complete step);
//! Gear5 has the predicted state, exact for a free flight (constant
//! acceleration: the derivatives beyond the second are zero).

use serde::{Deserialize, Serialize};

use crate::dynamics::contacts::{extended, touching};
use crate::pipeline::World;
use crate::setup::Scheme;

/// What a run has removed so far (`--json` `deleted_particles`,
/// `deleted_mass`, `carried_out_energy`; series.csv).
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct Removed {
    /// Spheres removed.
    pub particles: u64,
    /// Their mass, kg.
    pub mass: f64,
    /// The kinetic and potential energy they carried out, J.
    pub energy: f64,
}

/// What one outlet has removed so far.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct OutletRemoved {
    /// Spheres removed.
    pub count: u64,
    /// Their mass, kg.
    pub mass: f64,
}

/// The removal of lost spheres (`domain.outside = "delete"`) and of the
/// spheres that enter an outlet.
#[derive(Debug, Clone, PartialEq)]
pub struct Removal {
    /// Lost spheres are removed (`domain.outside = "delete"`).
    pub lost: bool,
    /// The box a free sphere is lost outside of, m: the domain grown to
    /// hold every fixed sphere.
    pub lower: [f64; 3],
    pub upper: [f64; 3],
    /// The outlets (file order): regions (`crate::region`, a unit
    /// cylinder axis) that remove the free spheres whose centres are inside
    /// them (surface included), once they touch nothing (module doc).
    pub outlets: Vec<crate::region::Region>,
    /// So far, by outlet (file order).
    pub by_outlet: Vec<OutletRemoved>,
    /// So far, in all (lost spheres and outlets).
    pub removed: Removed,
}

/// The axis along which a free sphere at `x` (m) of radius `r` (m) moving
/// at `v` (m/s) is lost for good outside the box `lower..upper` (m), or
/// `None`: wholly outside it (its centre more than its radius beyond a
/// face) along a non-periodic axis, moving away from the box or not
/// towards it, and gravity `g` (m/s²) not pulling it back. A sphere that
/// starts above an open box and falls in, or bounces out through an open
/// top and falls back, is not lost.
#[inline(always)]
pub(crate) fn lost_axis(
    x: &[f64; 3],
    r: f64,
    v: &[f64; 3],
    (lower, upper): (&[f64; 3], &[f64; 3]),
    periodic: &[bool; 3],
    g: &[f64; 3],
) -> Option<usize> {
    (0..3).find(|&a| {
        let side = if x[a] < lower[a] - r {
            -1.0
        } else if x[a] > upper[a] + r {
            1.0
        } else {
            return false;
        };
        !periodic[a] && side * v[a] >= 0.0 && side * g[a] >= 0.0
    })
}

/// One removed sphere: its input id, its mass (kg), the energy it
/// carries out (J, module doc) and where it went: 0 lost, K + 1 outlet K.
pub(crate) type Gone = (u32, f64, f64, u32);

/// The lost free spheres that touch nothing (module doc): a flag per body
/// and their records; nothing without a removal. Reads the lists of the
/// last build (call before they are rebuilt).
pub(crate) fn lost_spheres(world: &World) -> (Vec<bool>, Vec<Gone>) {
    let Some(removal) = world.removal.as_deref() else {
        return (Vec::new(), Vec::new());
    };
    let b = &world.bodies;
    let bounds = (&removal.lower, &removal.upper);
    let (periodic, g) = (world.domain.periodic, world.gravity);
    // Where each body goes: 0 lost, K + 1 outlet K (the first that holds
    // its centre), u32::MAX staying.
    let stay = u32::MAX;
    let place: Vec<u32> = (0..b.len())
        .map(|k| {
            if b.fixed[k] {
                return stay;
            }
            if let Some(o) = removal.outlets.iter().position(|o| o.holds(&b.position[k])) {
                return o as u32 + 1;
            }
            let lost = removal.lost
                && lost_axis(
                    &b.position[k],
                    b.radius[k],
                    &b.velocity[k],
                    bounds,
                    &periodic,
                    &g,
                )
                .is_some();
            if lost {
                0
            } else {
                stay
            }
        })
        .collect();
    let mut gone: Vec<bool> = place.iter().map(|&p| p != stay).collect();
    if !gone.iter().any(|&x| x) {
        return (Vec::new(), Vec::new());
    }
    for k in touching_any(world, &gone) {
        gone[k] = false;
    }
    let half = match world.scheme {
        Scheme::Verlet => 0.5 * world.dt,
        Scheme::Gear5 => 0.0,
    };
    let spin = world.friction.is_some();
    let records = (0..b.len())
        .filter(|&k| gone[k])
        .map(|k| {
            let m = b.mass[k];
            let v = b.velocity[k];
            let v = [v[0] + half * g[0], v[1] + half * g[1], v[2] + half * g[2]];
            let x = b.position[k];
            let mut e = 0.5 * m * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2])
                - m * (g[0] * x[0] + g[1] * x[1] + g[2] * x[2]);
            if spin {
                let w = b.angular_velocity[k];
                e += 0.5 * (w[0] * w[0] + w[1] * w[1] + w[2] * w[2]) / b.inverse_inertia[k];
            }
            (b.id[k], m, e, place[k])
        })
        .collect();
    (gone, records)
}

/// Books the spheres removed at one list build (of every process) in
/// input-id order: the sums do not depend on the engine's order nor on
/// which process held them.
pub(crate) fn book(world: &mut World, mut gone: Vec<Gone>) {
    let Some(r) = world.removal.as_deref_mut() else {
        return;
    };
    gone.sort_by_key(|&(id, ..)| id);
    for (_, m, e, place) in gone {
        r.removed.particles += 1;
        r.removed.mass += m;
        r.removed.energy += e;
        if let Some(o) = (place as usize)
            .checked_sub(1)
            .and_then(|k| r.by_outlet.get_mut(k))
        {
            o.count += 1;
            o.mass += m;
        }
    }
}

/// One process: removes the lost free spheres that touch nothing (module
/// doc), booked in `world.removal`. Call before the lists are rebuilt;
/// the pair state to carry over must be saved before (it is keyed by input
/// ids: a removed sphere's simply finds no partner).
pub(crate) fn remove_lost(world: &mut World) {
    let (gone, records) = lost_spheres(world);
    if records.is_empty() {
        return;
    }
    book(world, records);
    let keep: Vec<u32> = (0..gone.len() as u32)
        .filter(|&k| !gone[k as usize])
        .collect();
    world.bodies.permute(&keep);
    world.wall_contacts.permute(&keep);
}

/// The bodies among `candidates` (flags by body) that touch a sphere or a
/// wall element now, by the lists of the last build.
fn touching_any(world: &World, candidates: &[bool]) -> Vec<usize> {
    let b = &world.bodies;
    let list = &world.list;
    let mut hit = vec![false; b.len()];
    let mut pair = |i: usize, owner: usize, xj: [f64; 3], vj: [f64; 3]| {
        if (candidates[i] || candidates[owner])
            && touching(
                b.position[i],
                b.velocity[i],
                b.radius[i],
                xj,
                vj,
                b.radius[owner],
            )
            .is_some()
        {
            hit[i] = true;
            hit[owner] = true;
        }
    };
    if list.start.len() == b.len() + 1 {
        for (i, k) in list.entries() {
            let (xj, vj, owner) = extended(b, &world.ghosts, list.j[k] as usize);
            pair(i, owner, xj, vj);
        }
    }
    for &(i, j) in &list.extra {
        let (xj, vj, owner) = extended(b, &world.ghosts, j as usize);
        pair(i as usize, owner, xj, vj);
    }
    let wc = &world.wall_contacts;
    if wc.bodies() == b.len() {
        for i in (0..b.len()).filter(|&i| candidates[i]) {
            for k in wc.range(i) {
                let key = wc.key[k];
                let c = world.surfaces[key.wall as usize].contact(
                    key.element,
                    b.position[i],
                    b.velocity[i],
                    b.radius[i],
                );
                if c.overlap > 0.0 {
                    hit[i] = true;
                }
            }
        }
    }
    (0..b.len()).filter(|&k| hit[k] && candidates[k]).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    const BOX: ([f64; 3], [f64; 3]) = ([0.0; 3], [1.0; 3]);
    const G: [f64; 3] = [0.0, 0.0, -9.81];

    #[test]
    fn below_an_open_floor_falling_is_lost_along_z() {
        // Centre 0.2 m below the floor, radius 0.1 m: wholly outside.
        let a = lost_axis(
            &[0.5, 0.5, -0.2],
            0.1,
            &[0.0, 0.0, -1.0],
            (&BOX.0, &BOX.1),
            &[false; 3],
            &G,
        );
        assert_eq!(a, Some(2));
    }

    #[test]
    fn partly_inside_or_coming_back_is_not_lost() {
        // Centre 0.05 m below the floor, radius 0.1 m: still overlaps it.
        assert_eq!(
            lost_axis(
                &[0.5, 0.5, -0.05],
                0.1,
                &[0.0, 0.0, -1.0],
                (&BOX.0, &BOX.1),
                &[false; 3],
                &G
            ),
            None
        );
        // Above the top moving up: gravity brings it back.
        assert_eq!(
            lost_axis(
                &[0.5, 0.5, 1.5],
                0.1,
                &[0.0, 0.0, 1.0],
                (&BOX.0, &BOX.1),
                &[false; 3],
                &G
            ),
            None
        );
        // Beside the box moving back towards it.
        assert_eq!(
            lost_axis(
                &[1.5, 0.5, 0.5],
                0.1,
                &[-1.0, 0.0, 0.0],
                (&BOX.0, &BOX.1),
                &[false; 3],
                &G
            ),
            None
        );
        // Along a periodic axis nothing is ever lost.
        assert_eq!(
            lost_axis(
                &[1.5, 0.5, 0.5],
                0.1,
                &[1.0, 0.0, 0.0],
                (&BOX.0, &BOX.1),
                &[true, false, false],
                &G
            ),
            None
        );
    }
}
