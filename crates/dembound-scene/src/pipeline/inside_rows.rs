//! Series rows observed inside a stretch of fused Verlet steps, without
//! ending it (issue 31 item 2). Verlet fuses step n's pair pass with step
//! n + 1's body pass block by block; the state of step n (positions before
//! the drift, velocities after the closing half kick) exists only inside
//! that fused pass. A row of step n takes each part where the fused steps
//! have it:
//!
//! - the walls' loads and the walls' contact counts and energy, once the
//!   body pass that placed the bodies at step n has written them, before
//!   step n's fused pass overwrites them with step n + 1's;
//! - the pairs' tally in step n's pair loop (`contacts::PairTally`);
//! - each body's kinetic and potential energy terms in the fused follow-up,
//!   after the closing half kick and before the next kick and drift
//!   ([`RowTerms`]), stored per body and summed afterwards in the chunks and
//!   order of `observe::kick_then_energies`, so that the row has the bits of
//!   the row observed by ending the stretch;
//! - the state check (finite state, `domain.outside = "error"`) on the
//!   same per-body values.
//!
//! Frictionless scenes of one process only, with fixed plane walls and
//! nothing else that observes or changes the bodies between steps
//! ([`applies`]); elsewhere a row ends its stretch as before.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Mutex;

use crate::dynamics::contacts;
use crate::parallel::{SharedMut, Workers, BODY_CHUNK};
use crate::walls::WallLoad;
use crate::Observation;

use super::observe::{self, ObserveHooks};
use super::{Local, World};
use crate::dynamics::friction_observables::ContactObservables;

/// Which states the stretch observes: every step s with
/// (s − origin) mod every = 0, strictly inside the stretch.
#[derive(Debug, Clone)]
pub(crate) struct RowSchedule {
    pub(crate) every: u64,
    pub(crate) origin: u64,
    /// The mechanical energy at the start, J (the dissipated energy's
    /// reference).
    pub(crate) initial_energy: f64,
    /// The box of `domain.outside = "error"` (`Simulation::outside_box`).
    pub(crate) check_box: Option<([f64; 3], [f64; 3])>,
}

impl RowSchedule {
    /// Whether the state after `step` steps is a row.
    pub(crate) fn wants(&self, step: u64) -> bool {
        step >= self.origin && (step - self.origin) % self.every.max(1) == 0
    }
}

/// What a row inside the stretch found when its state was not sound.
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum RowFailure {
    /// A position or velocity not finite at this step.
    NotFinite { step: u64 },
    /// A free sphere lost for good at this step (`Simulation::check_inside`'s
    /// test): input id, index, axis, its centre (m) and radius (m).
    Lost {
        step: u64,
        id: u32,
        index: usize,
        axis: usize,
        centre: [f64; 3],
        radius: f64,
    },
}

/// The per-body part of a row, written by the fused follow-up
/// (`verlet::row_terms`).
pub(crate) struct RowTerms {
    /// Each body's kinetic and potential energy at the row's state (J), or
    /// NaN where a value the state check tests is not finite.
    pub(crate) terms: SharedMut<[f64; 2]>,
    /// The check's box, when `domain.outside = "error"`.
    pub(crate) check_box: Option<([f64; 3], [f64; 3])>,
    /// A free body's centre lies outside the box by more than its radius.
    pub(crate) outside: AtomicBool,
    /// Those bodies: index, centre (m) and velocity (m/s) at the row.
    pub(crate) outside_bodies: Mutex<Vec<(usize, [f64; 3], [f64; 3])>>,
}

/// Whether rows can be observed inside the stretch for this world (one
/// process, Verlet, frictionless, plane or cylinder walls that do not
/// move, no collision log, dissipation, removal, inlets, gates, moving
/// groups or boundary-particle walls). Cheap: no pass over the bodies.
pub(crate) fn applies(world: &World) -> bool {
    world.scheme == crate::setup::Scheme::Verlet
        && world.friction.is_none()
        && world.tracks.is_none()
        && world.dissipation.is_none()
        && world.moving.is_none()
        && world.removal.is_none()
        && world.gates.is_none()
        && world.inlets.is_none()
        && world
            .walls
            .iter()
            .all(|w| matches!(w, super::WallKind::Surface(_)))
        && !world.has_moving_groups()
}

/// The walls' part of a row, taken before the fused pass of the row's step
/// overwrites it.
pub(crate) struct WallPart {
    pub(crate) loads: Vec<WallLoad>,
    /// Plane contacts and their elastic energy (J).
    pub(crate) planes: (usize, f64),
}

/// The walls' loads and contacts at the state the last body pass made
/// (`tallied`: each wall entry's energy from that pass, when it tallied).
pub(crate) fn wall_part(world: &World, workers: &Workers, tallied: Option<&[f64]>) -> WallPart {
    let w = world;
    let planes = tallied
        .and_then(|e| {
            crate::dynamics::walls::plane_observables_tallied(
                &w.bodies,
                &w.surfaces,
                &w.wall_contacts,
                workers,
                e,
            )
        })
        .unwrap_or_else(|| {
            crate::dynamics::walls::plane_observables(
                &w.bodies,
                &w.surfaces,
                &w.wall_contacts,
                &w.laws,
                workers,
            )
        });
    WallPart {
        loads: Local.wall_loads(world, workers),
        planes,
    }
}

/// The per-body terms summed as `observe::kick_then_energies` sums them:
/// each chunk of [`BODY_CHUNK`] bodies in order from +0, the chunks' sums
/// in order from +0.
pub(crate) fn summed_terms(terms: &[[f64; 2]], workers: &Workers) -> (f64, f64) {
    let n = terms.len();
    let partial = workers.map_bodies(n, BODY_CHUNK, |c| {
        let mut s = [0.0; 2];
        for t in &terms[c * BODY_CHUNK..((c + 1) * BODY_CHUNK).min(n)] {
            s[0] += t[0];
            s[1] += t[1];
        }
        s
    });
    let mut s = [0.0; 2];
    for p in partial {
        s[0] += p[0];
        s[1] += p[1];
    }
    (s[0], s[1])
}

/// What a row observed inside the stretch has in hand: the hooks of
/// `observe::observation` for one process.
pub(crate) struct InsideHooks<'a> {
    pub(crate) energies: (f64, f64),
    pub(crate) walls: &'a WallPart,
    pub(crate) tally: Option<&'a [contacts::PairTally]>,
}

impl ObserveHooks for InsideHooks<'_> {
    fn contacts(&self, world: &World, workers: &Workers) -> ContactObservables {
        let w = world;
        let (pc, wc, pe) = contacts::pair_observables(
            &w.bodies,
            &w.ghosts,
            &w.list,
            &w.histories,
            &w.laws,
            workers,
            self.tally,
        );
        ContactObservables {
            particle_contacts: pc,
            boundary_contacts: wc,
            pair_energy: pe,
            plane_contacts: self.walls.planes.0,
            plane_energy: self.walls.planes.1,
            spring_energy: 0.0,
        }
    }

    fn wall_loads(&self, _world: &World, _workers: &Workers) -> Vec<WallLoad> {
        self.walls.loads.clone()
    }

    fn sum(&self, values: Vec<f64>) -> Vec<f64> {
        values
    }

    fn body_energies(&self, _world: &World, _workers: &Workers) -> (f64, f64) {
        self.energies
    }
}

/// The row of the state whose parts are given, or what made it unsound.
/// `world.steps_done` is the row's step.
pub(crate) fn row(
    world: &World,
    workers: &Workers,
    schedule: &RowSchedule,
    terms: &[[f64; 2]],
    row_terms: &RowTerms,
    walls: &WallPart,
    tally: Option<&[contacts::PairTally]>,
) -> Result<Observation, RowFailure> {
    let step = world.steps_done;
    let energies = summed_terms(terms, workers);
    if !(energies.0.is_finite() && energies.1.is_finite()) {
        return Err(RowFailure::NotFinite { step });
    }
    if row_terms.outside.load(Ordering::Relaxed) {
        if let Some((lower, upper)) = schedule.check_box {
            let b = &world.bodies;
            let outside = row_terms
                .outside_bodies
                .lock()
                .map(|v| v.clone())
                .unwrap_or_default();
            let first = outside
                .iter()
                .filter_map(|&(i, x, v)| {
                    crate::removal::lost_axis(
                        &x,
                        b.radius[i],
                        &v,
                        (&lower, &upper),
                        &world.domain.periodic,
                        &world.gravity,
                    )
                    .map(|a| (b.id[i], i, a, x))
                })
                .min_by(|p, q| (p.0, p.1, p.2).cmp(&(q.0, q.1, q.2)));
            if let Some((id, index, axis, centre)) = first {
                return Err(RowFailure::Lost {
                    step,
                    id,
                    index,
                    axis,
                    centre,
                    radius: b.radius[index],
                });
            }
        }
    }
    let hooks = InsideHooks {
        energies,
        walls,
        tally,
    };
    Ok(observe::observation(
        world,
        workers,
        schedule.initial_energy,
        &hooks,
    ))
}

#[cfg(test)]
mod tests {
    use crate::dynamics::friction_observables::tests::scene;
    use crate::{Observation, Simulation};

    /// Every position, velocity, spin and force, as bits.
    fn state_bits(s: &Simulation) -> Vec<u64> {
        let b = &s.world.bodies;
        [&b.position, &b.velocity, &b.angular_velocity, &b.force]
            .iter()
            .flat_map(|v| v.iter().flatten().map(|x| x.to_bits()))
            .collect()
    }

    /// The reference: the same steps in stretches that end at each row,
    /// each row observed after its stretch (the path before this module).
    fn rows_by_ending(sim: &mut Simulation, n: u64, every: u64, origin: u64) -> Vec<Observation> {
        let target = sim.world.steps_done + n;
        let mut rows = Vec::new();
        loop {
            let now = sim.world.steps_done;
            let next = (origin + ((now - origin) / every + 1) * every).min(target);
            sim.will_observe();
            sim.step_checked(next - now).unwrap();
            if next == target {
                return rows;
            }
            rows.push(sim.observe_checked().unwrap());
        }
    }

    /// Rows observed inside a stretch of fused steps (frictionless, the
    /// scene's six plane walls loaded: the floor carries the bed) equal
    /// the rows observed by ending the stretch at each, bit for bit (every
    /// number of each row, by its exact decimal from `Debug`, and the
    /// energies' bits), over several rows and stretches of several
    /// lengths, with list rebuilds among them, on 1, 2 and 3 threads; the
    /// state after the stretch is the same bits too. The rows were taken
    /// inside (counted where the pipeline keeps them) and are not trivial
    /// (contacts with the walls and between spheres in most of them).
    /// With friction the rows still end their stretches (`applies`): the
    /// same rows, checked too.
    #[test]
    fn rows_inside_the_stretch_equal_the_rows_that_end_it() {
        for (threads, friction) in [(1, false), (2, false), (3, false), (1, true), (2, true)] {
            let mut setup = scene();
            if !friction {
                setup.friction = None;
            }
            let mut inside = Simulation::new(setup.clone(), threads).unwrap();
            let mut ending = Simulation::new(setup, threads).unwrap();
            assert_eq!(super::applies(&inside.world), !friction);
            let (every, origin) = (7, 0);
            let (mut compared, mut walled, mut paired, mut taken) = (0, 0, 0, 0);
            let builds = inside.list_builds();
            for (k, n) in [30u64, 45, 8, 70, 1, 120, 64].into_iter().enumerate() {
                // Rows strictly inside the stretch; the end's row the
                // caller's, asked for in every other stretch.
                if k % 2 == 0 {
                    inside.will_observe();
                }
                let got = inside.step_rows(n, every, origin).unwrap();
                let want = rows_by_ending(&mut ending, n, every, origin);
                assert_eq!(got.len(), want.len(), "stretch {k}");
                for (g, w) in got.iter().zip(&want) {
                    assert_eq!(format!("{g:?}"), format!("{w:?}"), "stretch {k}");
                    assert_eq!(g.kinetic_energy.to_bits(), w.kinetic_energy.to_bits());
                    assert_eq!(g.potential_energy.to_bits(), w.potential_energy.to_bits());
                    assert_eq!(g.elastic_energy.to_bits(), w.elastic_energy.to_bits());
                    compared += 1;
                    walled += usize::from(g.wall_contacts > 0);
                    paired += usize::from(g.particle_contacts > 0);
                }
                taken += got.len();
                assert!(state_bits(&inside) == state_bits(&ending), "stretch {k}");
                // The end's rows, observed as the caller does.
                let a = inside.observe();
                let b = ending.observe();
                assert_eq!(format!("{a:?}"), format!("{b:?}"));
            }
            assert!(compared >= 40, "{compared}");
            assert!(2 * walled > compared && 2 * paired > compared, "{walled} {paired}");
            assert!(taken == compared);
            assert!(inside.list_builds() > builds + 1, "no rebuild among the rows");
            assert_eq!(inside.list_builds(), ending.list_builds());
        }
    }

    /// A row inside the stretch is taken inside the fused step (not by
    /// ending the stretch): `Pipeline::steps` asked for rows every 5 steps
    /// over 23 steps keeps 4 of them (steps 5, 10, 15, 20; not 0, the
    /// start, nor 23, the end) and makes all 23 steps.
    #[test]
    fn rows_are_taken_inside_the_fused_steps() {
        let mut setup = scene();
        setup.friction = None;
        let mut sim = Simulation::new(setup, 1).unwrap();
        sim.pipeline.rows_inside = Some(super::RowSchedule {
            every: 5,
            origin: 0,
            initial_energy: sim.initial_energy,
            check_box: sim.outside_box,
        });
        sim.step(23);
        assert_eq!(sim.world.steps_done, 23);
        let steps: Vec<u64> = sim
            .pipeline
            .rows_taken
            .iter()
            .map(|r| r.as_ref().map(|o| o.step).unwrap())
            .collect();
        assert_eq!(steps, [5, 10, 15, 20]);
    }

    /// A state that is not sound at a row inside the stretch gives the
    /// error the stretch ending at that row gives (the same step, the
    /// same message): a velocity made NaN, and a sphere moving out of the
    /// box of `domain.outside = "error"` (the box's upper x face moved
    /// below it).
    #[test]
    fn an_unsound_row_inside_gives_the_error_of_the_row_that_ends_the_stretch() {
        for case in 0..2 {
            let mut setup = scene();
            setup.friction = None;
            let mut inside = Simulation::new(setup.clone(), 1).unwrap();
            let mut ending = Simulation::new(setup, 1).unwrap();
            for sim in [&mut inside, &mut ending] {
                sim.step(10);
                let b = &sim.world.bodies;
                if case == 0 {
                    let top = (0..b.len())
                        .max_by(|&p, &q| b.position[p][2].total_cmp(&b.position[q][2]))
                        .unwrap();
                    sim.world.bodies.velocity[top] = [f64::NAN, 0.0, 0.0];
                } else {
                    // The box's upper x face 1.5 radii below the centre of
                    // the sphere of largest x among those moving +x (no
                    // gravity along x: it is lost).
                    let k = (0..b.len())
                        .filter(|&k| b.velocity[k][0] > 1.0e-3)
                        .max_by(|&p, &q| b.position[p][0].total_cmp(&b.position[q][0]))
                        .unwrap();
                    let (lower, mut upper) = sim.outside_box.unwrap();
                    upper[0] = b.position[k][0] - 1.5 * b.radius[k];
                    sim.outside_box = Some((lower, upper));
                }
                sim.pipeline.forget_tally();
            }
            let got = inside.step_rows(100, 3, 0).map(|_| ()).unwrap_err();
            let want = (|| -> Result<(), crate::error::SceneError> {
                for _ in 0..40 {
                    ending.will_observe();
                    ending.step_checked(3 - ending.world.steps_done % 3)?;
                    ending.observe_checked()?;
                }
                Ok(())
            })()
            .unwrap_err();
            assert_eq!(format!("{got:?}"), format!("{want:?}"), "case {case}");
            // The case's own error: not finite, or the sphere lost.
            let text = format!("{got:?}");
            assert_eq!(text.contains("left the domain"), case == 1, "{text}");
            assert_eq!(text.contains("Unstable"), case == 0, "{text}");
        }
    }
}
