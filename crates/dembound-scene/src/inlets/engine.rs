//! The inlets in the engine's step (module doc of `crate::inlets`: **The
//! engine**, **Energy**): at a list rebuild with an event, the spheres
//! placed and appended to the bodies with their state and law classes.
//!
//! **Several ranks** (`comm::distributed`). Every rank runs the same
//! placement against the same obstacles: the spheres near the region are
//! gathered from every rank's own bodies ([`InsertHooks::spheres_near`]),
//! so the draws, the spheres placed, their ids, counts, masses and energy
//! are those of one process; each rank then keeps the placed spheres whose
//! centres lie in its sub-domain ([`InsertHooks::keeps`]). The law
//! classes grow by the keys of every placed sphere, in placement order, on
//! every rank alike ([`assign_classes`]).

use std::f64::consts::PI;

use super::placement::{event_rng, nearby, place_event, Obstacles};
use crate::dynamics::contacts::{class_key, ClassKey, LawTable, NO_CLASS};
use crate::pipeline::World;
use crate::setup::Scheme;

/// Where the spheres in an inlet's way come from and which placed spheres
/// this process keeps: one process sees and keeps them all; a rank of a
/// decomposed run gathers them from every rank and keeps those of its
/// sub-domain.
pub(crate) trait InsertHooks {
    /// Every sphere of the whole scene near the box `bounds` grown by
    /// `reach` (m), with its periodic images ([`nearby`]): (input id,
    /// centre, radius; m). Collective on several ranks.
    fn spheres_near(
        &mut self,
        world: &World,
        bounds: ([f64; 3], [f64; 3]),
        reach: f64,
    ) -> Vec<(u32, [f64; 3], f64)>;
    /// This process holds a sphere placed at `x` (m).
    fn keeps(&self, world: &World, x: [f64; 3]) -> bool;
}

/// One process: every body is here.
pub(crate) struct OneProcess;

impl InsertHooks for OneProcess {
    fn spheres_near(
        &mut self,
        world: &World,
        bounds: ([f64; 3], [f64; 3]),
        reach: f64,
    ) -> Vec<(u32, [f64; 3], f64)> {
        nearby(world, bounds, reach, &|_| true)
    }
    fn keeps(&self, _world: &World, _x: [f64; 3]) -> bool {
        true
    }
}

/// At a list rebuild of a step with an insertion event (call after the
/// removal, before the lists are built): places every inlet's spheres due
/// at this step and appends those `hooks` keeps to the bodies (module
/// doc).
pub(crate) fn insert_due(world: &mut World, hooks: &mut dyn InsertHooks) {
    let Some(mut inlets) = world.inlets.take() else {
        return;
    };
    let step = world.steps_done + 1;
    let first_new = world.bodies.len();
    // The class key of every sphere placed (kept here or not), in order.
    let mut placed_keys: Vec<ClassKey> = Vec::new();
    for k in 0..inlets.inlets.len() {
        let Some(e) = inlets.event_at(k, step) else {
            continue;
        };
        let due = inlets.due_after(k, e);
        let n = due.saturating_sub(inlets.inlets[k].due);
        inlets.inlets[k].due = due.max(inlets.inlets[k].due);
        if n == 0 {
            continue;
        }
        let setup = inlets.inlets[k].setup.clone();
        let r_max = setup.size.max_radius();
        let near = hooks.spheres_near(world, setup.region.bounds(), r_max);
        let mut obstacles =
            Obstacles::new(near.into_iter().map(|(_, x, r)| (x, r)).collect(), r_max);
        let surfaces = &world.surfaces;
        // Only the walls acting at this state (`walls::gate`): a gate
        // open now (or not yet closed) is no obstacle.
        let acting = world.gates.as_deref().map(|g| g.status_at(step));
        let walls_clear = |x: [f64; 3], r: f64| {
            surfaces.iter().enumerate().all(|(w, s)| {
                if acting
                    .as_ref()
                    .is_some_and(|a| !a.get(w).copied().unwrap_or(true))
                {
                    return true;
                }
                let mut clear = true;
                s.wall().near_elements(x, r, 0.0, &mut |el| {
                    if clear && s.wall().contact(el, x, [0.0; 3], r).overlap > 0.0 {
                        clear = false;
                    }
                });
                clear
            })
        };
        let mut rng = event_rng(setup.seed, k, e);
        let (placed, missed) = place_event(&setup, n, &mut rng, &mut obstacles, &walls_clear);
        let density = inlets.inlets[k].density;
        let material = world.laws.materials.get(setup.material).copied();
        let mut so_far = inlets.inlets[k].so_far;
        so_far.not_placed += missed;
        for (x, r) in placed {
            let m = material.map_or(4.0 / 3.0 * PI * density * r * r * r, |mat| {
                mat.sphere_mass(r)
            });
            let id = inlets.next_id;
            inlets.next_id = inlets.next_id.saturating_add(1);
            let v = setup.velocity;
            if hooks.keeps(world, x) {
                push_sphere(world, x, r, m, v, setup.material as u32, id);
            }
            placed_keys.push((r.to_bits(), m.to_bits(), setup.material as u32));
            inlets.placed.push((r, m, setup.material as u32));
            so_far.count += 1;
            so_far.mass += m;
            so_far.energy += brought_in_energy(world.gravity, x, m, v);
        }
        inlets.inlets[k].so_far = so_far;
    }
    world.inlets = Some(inlets);
    if !placed_keys.is_empty() {
        assign_classes(world, first_new, &placed_keys);
    }
}

/// The energy a sphere of mass `m` (kg) at `x` (m) moving at `v` (m/s)
/// brings in under gravity `g` (m/s²): ½ m v² − m g·x (J).
fn brought_in_energy(g: [f64; 3], x: [f64; 3], m: f64, v: [f64; 3]) -> f64 {
    0.5 * m * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2])
        - m * (g[0] * x[0] + g[1] * x[1] + g[2] * x[2])
}

/// Appends a free sphere at `x` (m) of radius `r` (m), mass `m` (kg),
/// velocity `v` (m/s) at the rebuild's time (module doc: Verlet's
/// half-step velocity, Gear5's predicted state); its law class is set
/// by [`assign_classes`].
pub(super) fn push_sphere(
    world: &mut World,
    x: [f64; 3],
    r: f64,
    m: f64,
    v: [f64; 3],
    material: u32,
    id: u32,
) {
    let g = world.gravity;
    let dt = world.dt;
    let b = &mut world.bodies;
    let stored = match world.scheme {
        Scheme::Verlet => [0, 1, 2].map(|a| v[a] - 0.5 * dt * g[a]),
        Scheme::Gear5 => v,
    };
    b.position.push(x);
    b.velocity.push(stored);
    b.force.push([0.0; 3]);
    b.radius.push(r);
    b.mass.push(m);
    b.inverse_mass.push(1.0 / m);
    b.material.push(material);
    b.fixed.push(false);
    b.id.push(id);
    b.group.push(crate::bodies::NO_GROUP);
    // Gear5's vectors, whether or not the scene had bodies before (a scene
    // that starts empty has none yet: `Pipeline::start` made them for its
    // zero bodies; the predictor would read past them otherwise).
    let gear5 = world.scheme == Scheme::Gear5;
    if gear5 {
        debug_assert!(b.higher.len() + 1 == b.position.len());
        // r₂ = Δt² x''/2 with x'' = g (a free flight), the rest 0.
        let r2 = [0, 1, 2].map(|a| 0.5 * dt * dt * g[a]);
        b.higher.push([r2, [0.0; 3], [0.0; 3], [0.0; 3]]);
    }
    b.angular_velocity.push([0.0; 3]);
    b.torque.push([0.0; 3]);
    b.inverse_inertia.push(1.0 / (0.4 * m * r * r));
    if gear5 && world.friction.is_some() {
        debug_assert!(b.angular_higher.len() + 1 == b.position.len());
        b.angular_higher.push([[0.0; 3]; 4]);
    }
    world.wall_contacts.push_body(&[]);
}

/// The law classes of the bodies `first_new..`: the law table's classes
/// grown by the keys of `placed` (every sphere placed at this step, kept
/// here or not, in placement order: the same classes on every rank), the
/// tables remade when a key is new, per contact for all once there are
/// too many. The laws of a pair are computed from its two keys alone: the
/// same bits whichever table, or none, holds them.
pub(super) fn assign_classes(world: &mut World, first_new: usize, placed: &[ClassKey]) {
    world.bodies.class.truncate(first_new);
    let Some(known) = world.laws.class_keys() else {
        // Too many classes already: every law computed per contact.
        let n = world.bodies.len();
        world.bodies.class.resize(n, NO_CLASS);
        return;
    };
    let mut keys = known.to_vec();
    for key in placed {
        if !keys.contains(key) {
            keys.push(*key);
        }
    }
    if keys.len() > known.len() {
        world.laws = LawTable::from_keys(
            world.laws.model,
            world.laws.materials.clone(),
            keys,
            world.laws.slots.clone(),
        );
        if world.laws.class_keys().is_none() {
            // Now too many: every body's laws per contact.
            let n = world.bodies.len();
            world.bodies.class = vec![NO_CLASS; first_new];
            world.bodies.class.resize(n, NO_CLASS);
        }
        if let Some(f) = world.friction.as_ref() {
            let table = crate::dynamics::friction::FrictionTable::new(f.setup.clone(), &world.laws);
            world.friction = Some(table);
        }
    }
    let b = &world.bodies;
    let classes: Vec<u16> = (first_new..b.len())
        .map(|k| {
            world
                .laws
                .class_keys()
                .and_then(|keys| keys.iter().position(|&q| q == class_key(b, k)))
                .map_or(NO_CLASS, |c| c as u16)
        })
        .collect();
    world.bodies.class.extend(classes);
}
