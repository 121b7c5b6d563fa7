//! The observables of a scene with friction in one pass over the bodies
//! (issue 13): what `contacts::pair_observables`,
//! `walls::plane_observables` and `spring_energy::spring_energy` give,
//! with the same bits. (The walls' loads are the force pass's records,
//! `pipeline::wall_loads`.)
//!
//! Those four passes each test every listed pair or every (body, plane)
//! again and copy a pair law per contact; at `dembound scene`'s default
//! cadence (a series row every span/1000 steps: every 10 steps of the
//! lattice-drop benchmark) they cost 1.6 steps of forces per row. Here each
//! listed pair is tested once (positions only: the energies need no
//! velocity), the laws are read by reference from the class table, and the
//! planes are those the force pass looks at (a body's `near` and `touching`
//! masks; a body touches no other before the list is rebuilt, as the
//! force pass relies on).
//!
//! Every sum keeps its own accumulator, chunks and order, so each number
//! is bit for bit the one the separate passes give:
//! - pair counts, pair elastic energy and spring energy: per body, then
//!   per chunk of [`BODY_CHUNK`] in body order, then chunks in order
//!   (`Workers::sum`); a body's spring energy is its pairs' then its
//!   planes' (in plane order), as in `spring_energy`;
//! - wall contact count and wall elastic energy: into one accumulator
//!   per chunk in (body, entry) order, then chunks in order
//!   (`plane_observables`).
//!
//! The fast path needs the class table and a list without extra pairs;
//! otherwise [`observe`] returns `None` and the caller uses the separate
//! passes.

use super::contacts::{PairHistories, NO_HISTORY};

use super::friction::{FrictionLaw, FrictionTable, PairShear, PairTally};
use crate::bodies::{Bodies, NO_GROUP};
use crate::geometry::neighbour::PairList;
use crate::parallel::{Workers, BODY_CHUNK};
use crate::walls::{Surface, WallContacts};

/// The observables of the contacts, as the separate passes return them.
#[derive(Debug, Clone, PartialEq)]
pub struct ContactObservables {
    /// Pairs in contact, neither in a boundary-particle wall.
    pub particle_contacts: usize,
    /// Pairs in contact with a boundary particle.
    pub boundary_contacts: usize,
    /// Normal elastic energy of the touching pairs, J.
    pub pair_energy: f64,
    /// Sphere–wall contacts (planes, cylinders: every wall but the
    /// boundary particles).
    pub plane_contacts: usize,
    /// Normal elastic energy of the sphere–plane contacts, J.
    pub plane_energy: f64,
    /// Energy of the tangential and rolling springs, J.
    pub spring_energy: f64,
}

/// What one chunk of bodies adds.
struct Chunk {
    /// Σ over the chunk's bodies of (pair count, boundary count, pair
    /// energy, spring energy), each body's own sum first.
    pairs: [f64; 4],
    /// Wall contact count, then energy.
    planes: [f64; 2],
}

/// All of them in one pass; `None` when the fast path does not apply (no
/// class table, extra pairs, or a list or springs not aligned with the
/// bodies): then the separate passes give them.
#[allow(clippy::too_many_arguments)]
pub fn observe(
    bodies: &Bodies,
    list: &PairList,
    histories: &PairHistories,
    friction: &FrictionTable,
    shear: &PairShear,
    surfaces: &[Surface],
    walls: &WallContacts,
    workers: &Workers,
    tally: Option<&[PairTally]>,
) -> Option<ContactObservables> {
    let n = bodies.len();
    let np = surfaces.len();
    let classes = friction.classes;
    let aligned = list.start.len() == n + 1
        && list.extra.is_empty()
        && shear.main.len() == list.j.len()
        && (!shear.rolling || shear.roll_main.len() == list.j.len())
        && (np == 0 || (walls.bodies() == n && walls.shear.len() == walls.key.len()))
        && bodies.class.len() == n
        && bodies.group.len() == n
        && tally.is_none_or(|t| t.len() == n);
    if classes == 0 || !aligned {
        return None;
    }
    let pass = Pass {
        bodies,
        list,
        histories,
        shear,
        surfaces,
        walls,
        table: &friction.pairs,
        plane_table: &friction.planes,
        classes,
        tally,
    };
    #[cfg(target_arch = "x86_64")]
    let avx2 = std::is_x86_feature_detected!("avx2");
    let partial = workers.map_bodies(n, BODY_CHUNK, |c| {
        let (lo, hi) = (c * BODY_CHUNK, ((c + 1) * BODY_CHUNK).min(n));
        #[cfg(target_arch = "x86_64")]
        if avx2 {
            // SAFETY: the processor has AVX2 (checked above).
            return unsafe { pass.chunk_avx2(lo, hi) };
        }
        pass.chunk(lo, hi)
    });
    let mut pairs = [0.0; 4];
    let mut plane_sums = [0.0; 2];
    for chunk in partial {
        for (sum, x) in pairs.iter_mut().zip(chunk.pairs) {
            *sum += x;
        }
        for (sum, x) in plane_sums.iter_mut().zip(chunk.planes) {
            *sum += x;
        }
    }
    Some(ContactObservables {
        particle_contacts: pairs[0] as usize,
        boundary_contacts: pairs[1] as usize,
        pair_energy: pairs[2],
        plane_contacts: plane_sums[0] as usize,
        plane_energy: plane_sums[1],
        spring_energy: pairs[3],
    })
}

/// What the pass reads (lengths checked by [`observe`]).
#[derive(Clone, Copy)]
struct Pass<'a> {
    bodies: &'a Bodies,
    list: &'a PairList,
    histories: &'a PairHistories,
    shear: &'a PairShear,
    surfaces: &'a [Surface],
    walls: &'a WallContacts,
    table: &'a [FrictionLaw],
    plane_table: &'a [FrictionLaw],
    classes: usize,
    /// Each body's sums over its pairs, as the last pair pass tallied
    /// them at this state (`friction::PairTally`): the pairs are not
    /// visited again.
    tally: Option<&'a [PairTally]>,
}

impl Pass<'_> {
    /// [`Self::chunk`] compiled for AVX2: no fused multiply–add (Rust does
    /// not contract a·b + c), so the same bits with fewer instructions, as
    /// the force kernels.
    ///
    /// # Safety
    /// The processor must have AVX2.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx,avx2")]
    unsafe fn chunk_avx2(&self, lo: usize, hi: usize) -> Chunk {
        match self.tally {
            Some(tally) => self.tallied_avx2(tally, lo, hi),
            None => self.chunk(lo, hi),
        }
    }

    /// [`Self::chunk`]'s tallied sums with AVX2: a body's four tallied
    /// sums are one 4-lane register added to the chunk's four running sums
    /// (lane d takes sum d with the scalar loop's additions in its order,
    /// IEEE per lane); a free body with near walls first has its planes'
    /// spring energy added to its springs' lane, as the scalar loop does.
    ///
    /// # Safety
    /// The processor must have AVX2.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx,avx2")]
    unsafe fn tallied_avx2(&self, tally: &[PairTally], lo: usize, hi: usize) -> Chunk {
        use std::arch::x86_64::*;
        let mut out = Chunk {
            pairs: [0.0; 4],
            planes: [0.0; 2],
        };
        let planes = !self.surfaces.is_empty();
        let (start, fixed) = (&self.walls.start[..], &self.bodies.fixed[..]);
        let mut sums = _mm256_setzero_pd();
        for (i, t) in (lo..hi).zip(&tally[lo..hi]) {
            // `walls.range(i)` not empty (`observe` checked the lengths
            // when there are planes).
            let row = if planes && start[i] != start[i + 1] && !fixed[i] {
                let mut t = *t;
                self.planes(i, &mut out.planes, &mut t[3]);
                _mm256_loadu_pd(t.as_ptr())
            } else {
                _mm256_loadu_pd(t.as_ptr())
            };
            sums = _mm256_add_pd(sums, row);
        }
        _mm256_storeu_pd(out.pairs.as_mut_ptr(), sums);
        out
    }

    /// Bodies lo..hi.
    #[inline(always)]
    fn chunk(&self, lo: usize, hi: usize) -> Chunk {
        let Pass {
            bodies,
            list,
            histories,
            shear,
            surfaces,
            walls,
            table,
            classes,
            tally,
            ..
        } = *self;
        let np = surfaces.len();
        let mut out = Chunk {
            pairs: [0.0; 4],
            planes: [0.0; 2],
        };
        let (position, radius, class, group) = (
            &bodies.position[..],
            &bodies.radius[..],
            &bodies.class[..],
            &bodies.group[..],
        );
        if let Some(tally) = tally {
            // The pairs' sums made by the force pass
            // (`friction::add_pair_forces_tallied`); a body's planes
            // only where it has near walls.
            for (i, &[count, walled, energy, mut springs]) in
                tally.iter().enumerate().take(hi).skip(lo)
            {
                if np > 0 && !bodies.fixed[i] && !walls.range(i).is_empty() {
                    self.planes(i, &mut out.planes, &mut springs);
                }
                for (sum, x) in out.pairs.iter_mut().zip([count, walled, energy, springs]) {
                    *sum += x;
                }
            }
            return out;
        }
        for i in lo..hi {
            let (xi, ri, ci) = (position[i], radius[i], class[i] as usize);
            let walled_i = group[i] != NO_GROUP;
            // `pair_observables`'s per-body sums.
            let (mut count, mut walled, mut energy) = (0.0, 0.0, 0.0);
            // `spring_energy`'s per-body sum.
            let mut springs = 0.0;
            let (s, e) = (list.start[i] as usize, list.start[i + 1] as usize);
            for (k, (&j, t)) in (s..e).zip(list.j[s..e].iter().zip(&shear.main[s..e])) {
                let j = j as usize;
                let xj = position[j];
                // `contacts::touching`, without the velocities.
                let d = [xj[0] - xi[0], xj[1] - xi[1], xj[2] - xi[2]];
                let r2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
                let sum = ri + radius[j];
                if r2 >= sum * sum || r2 == 0.0 {
                    continue;
                }
                let overlap = sum - r2.sqrt();
                let fl = &table[ci * classes + class[j] as usize];
                if walled_i || group[j] != NO_GROUP {
                    walled += 1.0;
                } else {
                    count += 1.0;
                }
                energy += fl.law.elastic_energy(overlap, histories.main(k));
                let r = if shear.rolling {
                    shear.roll_main[k]
                } else {
                    [0.0; 3]
                };
                if *t != [0.0; 3] || r != [0.0; 3] {
                    springs += fl.spring_energy(overlap, t, &r);
                }
            }
            if np > 0 && !bodies.fixed[i] {
                self.planes(i, &mut out.planes, &mut springs);
            }
            for (sum, x) in out.pairs.iter_mut().zip([count, walled, energy, springs]) {
                *sum += x;
            }
        }
        out
    }

    /// Body i's plane contacts: the count and elastic energy into
    /// `planes` (the chunk's running sums), their springs' energy into
    /// `springs` (the body's, after its pairs').
    #[inline(always)]
    fn planes(&self, i: usize, planes: &mut [f64; 2], springs: &mut f64) {
        let Pass {
            bodies,
            surfaces,
            walls,
            plane_table,
            classes,
            ..
        } = *self;
        let slots = plane_table.len() / classes.max(1);
        let (xi, ri, ci) = (
            bodies.position[i],
            bodies.radius[i],
            bodies.class[i] as usize,
        );
        for k in walls.range(i) {
            let key = walls.key[k];
            let surface = &surfaces[key.wall as usize];
            // Positions only: the count and energies need no velocity.
            let c = surface.contact(key.element, xi, [0.0; 3], ri);
            let h = c.overlap;
            if h <= 0.0 {
                continue;
            }
            let fl = &plane_table[ci * slots + surface.law_slot(key.element)];
            let hist = walls.history.get(k).unwrap_or(&NO_HISTORY);
            let stored = &walls.shear[k].shear;
            planes[0] += 1.0;
            planes[1] += fl.law.elastic_energy(h, hist);
            // `spring_energy`'s planes.
            if *stored != [0.0; 6] {
                let t = [stored[0], stored[1], stored[2]];
                let r = [stored[3], stored[4], stored[5]];
                *springs += fl.spring_energy(h, &t, &r);
            }
        }
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use dembound_physics::contact::tangential::{FrictionModel, TangentialKind};
    use dembound_physics::contact::{ContactModel, Damping, DampingKind, Dissipation, NormalLaw};
    use dembound_physics::material::Material;

    use crate::setup::{
        DomainSetup, FrictionSetup, NamedMaterial, Plane, RunLength, SphereInit, TimeStep,
        WallSetup,
    };
    use crate::{SceneSetup, Simulation};

    /// A dropping lattice of two sizes (two body classes) in a box of six
    /// planes, Hertz + Tsuji (e = 0.3), Mindlin μ = 0.5 and rolling
    /// friction 0.05 everywhere: impacts, sliding and sticking on pairs and
    /// planes, damping and rolling springs.
    pub(crate) fn scene() -> SceneSetup {
        let (side, layers, a, c) = (6, 5, 1.2e-3, 0.54e-3);
        let upper = [side as f64 * a + 0.5 * a, side as f64 * a + 0.5 * a, 0.02];
        let mut s = SceneSetup::new(
            DomainSetup {
                lower: [0.0; 3],
                upper,
                periodic: [false; 3],
            },
            ContactModel::damped(
                NormalLaw::Hertz,
                Damping::new(DampingKind::Tsuji, Dissipation::Restitution(0.3)),
            ),
            TimeStep::Fixed(2.0e-5),
            RunLength::Steps(0),
        );
        s.gravity = [0.0, 0.0, -9.81];
        s.neighbour.skin = Some(1.0e-4);
        s.materials.push(NamedMaterial {
            name: "grain".into(),
            material: Material {
                density: 1000.0,
                youngs_modulus: 1.0e7,
                poisson_ratio: 0.3,
            },
        });
        for k in 0..layers {
            let shift = 0.5 * a * (k % 2) as f64;
            for j in 0..side {
                for i in 0..side {
                    s.spheres.push(SphereInit {
                        position: [
                            0.5 * a + i as f64 * a + shift,
                            0.5 * a + j as f64 * a + shift,
                            0.505e-3 + k as f64 * c,
                        ],
                        velocity: [1.0e-2 * (i as f64 - 2.5), 0.0, 0.0],
                        radius: if (i + j + k) % 2 == 0 {
                            0.5e-3
                        } else {
                            0.45e-3
                        },
                        material: 0,
                        fixed: false,
                        group: None,
                    });
                }
            }
        }
        for axis in 0..3 {
            let mut n = [0.0; 3];
            n[axis] = 1.0;
            s.walls.push(WallSetup::Plane(Plane {
                point: [0.0; 3],
                normal: n,
                material: 0,
            }));
            n[axis] = -1.0;
            s.walls.push(WallSetup::Plane(Plane {
                point: upper,
                normal: n,
                material: 0,
            }));
        }
        s.friction = Some(FrictionSetup {
            model: FrictionModel {
                tangential: TangentialKind::Mindlin,
                friction: 0.5,
                rolling_friction: 0.05,
            },
            materials: Vec::new(),
            walls: vec![Some((0.5, 0.05)); 6],
            tangential_damping: true,
            torque_arm: Default::default(),
            spring_rotation: Default::default(),
        });
        s
    }

    /// The tallied sums four lanes at a time (`Pass::tallied_avx2`) against
    /// the scalar loop over the same tally (`Pass::chunk`, the reference:
    /// one sum at a time), bit for bit, over every range lo..hi of the
    /// bodies, at states along a run with pair and plane contacts and
    /// loaded springs (the planes' springs added to a body's before its
    /// four sums), and with a NaN and an infinite tally value.
    #[cfg(target_arch = "x86_64")]
    #[test]
    fn tallied_sums_four_lanes_equal_the_scalar_loop_bit_for_bit() {
        if !std::is_x86_feature_detected!("avx2") {
            return;
        }
        let mut sim = Simulation::new(scene(), 1).unwrap();
        let mut walled = 0;
        for round in 0..6 {
            sim.will_observe();
            sim.step(60);
            let w = &sim.world;
            let mut tally = sim
                .pipeline
                .pair_tally(w)
                .friction
                .expect("a tally of this state")
                .to_vec();
            let n = tally.len();
            if round == 4 {
                tally[n / 2][3] = f64::NAN;
            }
            if round == 5 {
                tally[n / 3][0] = f64::INFINITY;
            }
            let pass = super::Pass {
                bodies: &w.bodies,
                list: &w.list,
                histories: &w.histories,
                shear: &w.shear,
                surfaces: &w.surfaces,
                walls: &w.wall_contacts,
                table: &w.friction.as_ref().unwrap().pairs,
                plane_table: &w.friction.as_ref().unwrap().planes,
                classes: w.friction.as_ref().unwrap().classes,
                tally: Some(&tally),
            };
            walled += (0..n)
                .filter(|&i| !w.wall_contacts.range(i).is_empty())
                .count();
            for lo in 0..=n {
                for hi in lo..=n {
                    // SAFETY: AVX2 checked above.
                    let four = unsafe { pass.tallied_avx2(&tally, lo, hi) };
                    let one = pass.chunk(lo, hi);
                    assert_eq!(
                        (four.pairs.map(f64::to_bits), four.planes.map(f64::to_bits)),
                        (one.pairs.map(f64::to_bits), one.planes.map(f64::to_bits)),
                        "{round} {lo}..{hi}"
                    );
                }
            }
        }
        // Bodies with near walls were there.
        assert!(walled > 100, "{walled}");
    }

    /// The one pass gives the separate passes' numbers bit for bit, along a
    /// run and on 1 and 2 threads (the expected values are the separate
    /// passes', an independent computation of the same sums).
    #[test]
    fn one_pass_equals_the_separate_passes_bit_for_bit() {
        for threads in [1, 2] {
            let mut sim = Simulation::new(scene(), threads).unwrap();
            let mut checked = 0;
            for _ in 0..30 {
                sim.step(50);
                let w = &sim.world;
                let one = super::observe(
                    &w.bodies,
                    &w.list,
                    &w.histories,
                    w.friction.as_ref().unwrap(),
                    &w.shear,
                    &w.surfaces,
                    &w.wall_contacts,
                    &sim.workers,
                    None,
                )
                .expect("the fast path applies: class table, no extra pairs");
                let passes = sim.contact_observables();
                let (pc, plane_contacts, springs) = (
                    passes.particle_contacts,
                    passes.plane_contacts,
                    passes.spring_energy,
                );
                assert_eq!(
                    (one.particle_contacts, one.boundary_contacts),
                    (pc, passes.boundary_contacts)
                );
                assert_eq!(one.plane_contacts, plane_contacts);
                assert_eq!(one.pair_energy.to_bits(), passes.pair_energy.to_bits());
                assert_eq!(one.plane_energy.to_bits(), passes.plane_energy.to_bits());
                assert_eq!(one.spring_energy.to_bits(), springs.to_bits());
                if pc > 0 && plane_contacts > 0 && springs > 0.0 {
                    checked += 1;
                }
            }
            // Most checks see pair and plane contacts with loaded springs.
            assert!(checked > 20, "{checked}");
        }
    }
}
