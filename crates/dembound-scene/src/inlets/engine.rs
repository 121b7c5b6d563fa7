//! The inlets in the engine's step (module doc of `crate::inlets`: **The
//! engine**, **Energy**): at a list rebuild with an event, the spheres
//! placed and appended to the bodies with their state and law classes.

use std::collections::HashMap;
use std::f64::consts::PI;

use super::placement::{event_rng, nearby, place_event, Obstacles};
use crate::pipeline::World;
use crate::setup::Scheme;

/// At a list rebuild of a step with an insertion event (call after the
/// removal, before the lists are built): places every inlet's spheres due
/// at this step and appends them to the bodies (module doc).
pub(crate) fn insert_due(world: &mut World) {
    let Some(mut inlets) = world.inlets.take() else {
        return;
    };
    let step = world.steps_done + 1;
    let first_new = world.bodies.len();
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
        let mut obstacles = Obstacles::new(nearby(world, setup.region.bounds(), r_max), r_max);
        let surfaces = &world.surfaces;
        let walls_clear = |x: [f64; 3], r: f64| {
            surfaces.iter().all(|s| {
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
            let energy = push_sphere(world, x, r, m, setup.velocity, setup.material as u32, id);
            so_far.count += 1;
            so_far.mass += m;
            so_far.energy += energy;
        }
        inlets.inlets[k].so_far = so_far;
    }
    world.inlets = Some(inlets);
    if world.bodies.len() > first_new {
        assign_classes(world, first_new);
    }
}

/// Appends a free sphere at `x` (m) of radius `r` (m), mass `m` (kg),
/// velocity `v` (m/s) at the rebuild's time (module doc: Verlet's
/// half-step velocity, Gear5's predicted state); returns the energy it
/// brings in, ½ m v² − m g·x (J).
fn push_sphere(
    world: &mut World,
    x: [f64; 3],
    r: f64,
    m: f64,
    v: [f64; 3],
    material: u32,
    id: u32,
) -> f64 {
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
    if !b.higher.is_empty() {
        // r₂ = Δt² x''/2 with x'' = g (a free flight), the rest 0.
        let r2 = [0, 1, 2].map(|a| 0.5 * dt * dt * g[a]);
        b.higher.push([r2, [0.0; 3], [0.0; 3], [0.0; 3]]);
    }
    b.angular_velocity.push([0.0; 3]);
    b.torque.push([0.0; 3]);
    b.inverse_inertia.push(1.0 / (0.4 * m * r * r));
    if !b.angular_higher.is_empty() {
        b.angular_higher.push([[0.0; 3]; 4]);
    }
    world.wall_contacts.push_body(&[]);
    0.5 * m * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2])
        - m * (g[0] * x[0] + g[1] * x[1] + g[2] * x[2])
}

/// The law classes of the bodies `first_new..`: an existing class of the
/// same radius, mass and material, else the tables made again over every
/// body (the laws of a pair are computed from those three alone: the same
/// bits whichever table, or none, holds them).
fn assign_classes(world: &mut World, first_new: usize) {
    use crate::dynamics::contacts::{LawTable, NO_CLASS};
    let b = &mut world.bodies;
    let key = |k: usize| (b.radius[k].to_bits(), b.mass[k].to_bits(), b.material[k]);
    b.class.truncate(first_new);
    let tabulated = world.laws.classes() > 0;
    if !tabulated && b.class.contains(&NO_CLASS) {
        // Too many classes already: every law computed per contact.
        b.class.resize(b.len(), NO_CLASS);
        return;
    }
    let mut known: HashMap<(u64, u64, u32), u16> = HashMap::new();
    if tabulated {
        for k in 0..first_new {
            known.entry(key(k)).or_insert(b.class[k]);
        }
    }
    let found: Option<Vec<u16>> = (first_new..b.len())
        .map(|k| known.get(&key(k)).copied())
        .collect();
    if let Some(classes) = found {
        b.class.extend(classes);
        return;
    }
    let laws = LawTable::new(
        world.laws.model,
        world.laws.materials.clone(),
        &mut world.bodies,
        world.laws.slots.clone(),
    );
    world.laws = laws;
    if let Some(f) = world.friction.as_ref() {
        let table = crate::dynamics::friction::FrictionTable::new(
            f.setup.clone(),
            &world.laws,
            &world.bodies,
        );
        world.friction = Some(table);
    }
}
