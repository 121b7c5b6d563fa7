//! Energy held by the friction springs (issue 13): the tangential spring
//! ½ k_t |δ|² and the rolling spring ½ |M_r|²/k_r of every touching pair
//! and sphere–plane contact, at the bodies' current state
//! ([`dembound_physics::contact::tangential::FrictionPair::spring_energy`]).
//! Part of the observables' elastic energy, so that an elastic contact
//! that sticks conserves kinetic + elastic + potential energy.

use super::contacts::{extended, touching, LawTable};
use super::friction::{FrictionTable, PairShear};
use crate::bodies::Bodies;
use crate::geometry::ghosts::Ghosts;
use crate::geometry::neighbour::PairList;
use crate::parallel::Workers;
use crate::walls::{Surface, WallContacts};

fn halves(s: &[f64; 6]) -> ([f64; 3], [f64; 3]) {
    ([s[0], s[1], s[2]], [s[3], s[4], s[5]])
}

/// The tangential and rolling springs of listed pair k (`extra`: of the
/// extra pairs), `None` when both are relaxed.
fn pair_springs(shear: &PairShear, k: usize, extra: bool) -> Option<([f64; 3], [f64; 3])> {
    let (t, r) = if extra {
        (&shear.extra, &shear.roll_extra)
    } else {
        (&shear.main, &shear.roll_main)
    };
    let t = t[k];
    let r = if shear.rolling { r[k] } else { [0.0; 3] };
    (t != [0.0; 3] || r != [0.0; 3]).then_some((t, r))
}

/// Σ over touching pairs and sphere–plane contacts, J. Sums per body in
/// fixed chunks ([`Workers::sum`]): the same bits on any thread count.
#[allow(clippy::too_many_arguments)]
pub fn spring_energy(
    bodies: &Bodies,
    ghosts: &Ghosts,
    list: &PairList,
    laws: &LawTable,
    friction: &FrictionTable,
    shear: &PairShear,
    surfaces: &[Surface],
    walls: &WallContacts,
    workers: &Workers,
) -> f64 {
    spring_energy_counted(
        bodies,
        ghosts,
        list,
        laws,
        friction,
        shear,
        surfaces,
        walls,
        workers,
        |_, _| true,
    )
}

/// [`spring_energy`] over the pairs (i, partner) that `counted` keeps (a
/// domain decomposition counts a pair held by two ranks once).
#[allow(clippy::too_many_arguments)]
pub fn spring_energy_counted(
    bodies: &Bodies,
    ghosts: &Ghosts,
    list: &PairList,
    laws: &LawTable,
    friction: &FrictionTable,
    shear: &PairShear,
    surfaces: &[Surface],
    walls: &WallContacts,
    workers: &Workers,
    counted: impl Fn(usize, usize) -> bool + Sync,
) -> f64 {
    let n = bodies.len();
    let np = surfaces.len();
    let pairs_ok = list.start.len() == n + 1
        && shear.main.len() == list.j.len()
        && shear.extra.len() == list.extra.len();
    let walls_ok = np > 0 && walls.bodies() == n && walls.shear.len() == walls.key.len();
    let [main] = workers.sum(n, |i| {
        let mut e = 0.0;
        if pairs_ok {
            for k in list.start[i] as usize..list.start[i + 1] as usize {
                let Some((t, r)) = pair_springs(shear, k, false) else {
                    continue;
                };
                let j = list.j[k] as usize;
                if !counted(i, j) {
                    continue;
                }
                if let Some(g) = touching(
                    bodies.position[i],
                    bodies.velocity[i],
                    bodies.radius[i],
                    bodies.position[j],
                    bodies.velocity[j],
                    bodies.radius[j],
                ) {
                    let mut scratch = None;
                    let fl = friction.pair(laws, bodies, i, j, &mut scratch);
                    e += fl.spring_energy(g.overlap, &t, &r);
                }
            }
        }
        if walls_ok && !bodies.fixed[i] {
            for k in walls.range(i) {
                let s = &walls.shear[k].shear;
                if *s == [0.0; 6] {
                    continue;
                }
                let key = walls.key[k];
                let surface = &surfaces[key.wall as usize];
                let h = surface
                    .contact(
                        key.element,
                        bodies.position[i],
                        bodies.velocity[i],
                        bodies.radius[i],
                    )
                    .overlap;
                if h > 0.0 {
                    let (t, r) = halves(s);
                    let mut scratch = None;
                    let slot = surface.law_slot(key.element);
                    let fl = friction.plane(laws, bodies, i, slot, &mut scratch);
                    e += fl.spring_energy(h, &t, &r);
                }
            }
        }
        [e]
    });
    let mut extra = 0.0;
    if pairs_ok {
        for (k, &(i, j)) in list.extra.iter().enumerate() {
            let Some((t, r)) = pair_springs(shear, k, true) else {
                continue;
            };
            let (i, j) = (i as usize, j as usize);
            let (xj, vj, owner) = extended(bodies, ghosts, j);
            if !counted(i, owner) {
                continue;
            }
            if let Some(g) = touching(
                bodies.position[i],
                bodies.velocity[i],
                bodies.radius[i],
                xj,
                vj,
                bodies.radius[owner],
            ) {
                let mut scratch = None;
                let fl = friction.pair(laws, bodies, i, owner, &mut scratch);
                extra += fl.spring_energy(g.overlap, &t, &r);
            }
        }
    }
    main + extra
}
