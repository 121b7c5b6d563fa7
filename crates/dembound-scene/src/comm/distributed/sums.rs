//! The order of a rank's pair sums when some rank lists extra pairs
//! (periodic images, bodies too large for the cells): every pair's force
//! stored, each owned free body's sum gathered in the order of its
//! partners' input ids; and the boundary-particle walls' forces from this
//! rank's pairs.

use dembound_physics::contact::ContactHistory;

use super::RankComm;
use crate::bodies::NO_GROUP;
use crate::comm::Transport;
use crate::dynamics::contacts::{extended, touching, touching_lazy, NO_HISTORY};
use crate::parallel::{SharedMut, Workers, STEP_CHUNK};
use crate::pipeline::wall_loads::{add_particle_load, torque_points};
use crate::pipeline::{Pipeline, World};
use crate::walls::WallLoad;

/// Bit of an incidence: the body is the pair's i.
const NEGATIVE: u32 = 1 << 31;

/// One incident pair of a body: where its force is and with which sign.
#[derive(Debug, Clone, Copy)]
struct Incident {
    /// Input id of the partner (the summation order).
    partner: u32,
    /// Index into the pair forces (main entries, then extra).
    entry: u32,
    /// The body is the pair's i (it gets minus the stored force on j).
    negative: bool,
    /// The partner's boundary-particle wall, or [`NO_GROUP`].
    group: u32,
    /// The partner's local index.
    other: u32,
}

impl<T: Transport> RankComm<T> {
    /// Each owned free body's pairs, by partner id; and each copy of a
    /// moving group's sphere's (`pipeline::moving_groups`: its power and
    /// load are this rank's pairs' share).
    pub(super) fn build_incidence(&mut self, world: &World) {
        let b = &world.bodies;
        let n = b.len();
        let list = &world.list;
        let groups = world.has_moving_groups();
        let wanted = |k: usize| {
            (!self.halo[k] && !b.fixed[k])
                || (groups && b.fixed[k] && world.in_moving_group(b.id[k]))
        };
        let m = list.j.len();
        let mut count = vec![0u32; n + 1];
        let pairs = list
            .entries()
            .map(|(i, k)| (i, list.j[k] as usize, k))
            .chain(list.extra.iter().enumerate().map(|(q, &(i, j))| {
                let (_, _, owner) = extended(b, &world.ghosts, j as usize);
                (i as usize, owner, m + q)
            }));
        let pairs: Vec<(usize, usize, usize)> = pairs.collect();
        for &(i, j, _) in &pairs {
            if wanted(i) {
                count[i + 1] += 1;
            }
            if wanted(j) {
                count[j + 1] += 1;
            }
        }
        for k in 0..n {
            count[k + 1] += count[k];
        }
        let mut fill = count.clone();
        let blank = Incident {
            partner: 0,
            entry: 0,
            negative: false,
            group: NO_GROUP,
            other: 0,
        };
        let mut inc = vec![blank; count[n] as usize];
        for &(i, j, e) in &pairs {
            for (me, other, negative) in [(i, j, true), (j, i, false)] {
                if wanted(me) {
                    inc[fill[me] as usize] = Incident {
                        partner: b.id[other],
                        entry: e as u32,
                        negative,
                        group: b.group[other],
                        other: other as u32,
                    };
                    fill[me] += 1;
                }
            }
        }
        for k in 0..n {
            inc[count[k] as usize..count[k + 1] as usize].sort_by_key(|x| x.partner);
        }
        self.incidence_start = count;
        let code = |x: &Incident| x.entry | if x.negative { NEGATIVE } else { 0 };
        self.walled = inc
            .iter()
            .filter(|x| x.group != NO_GROUP)
            .map(|x| (code(x), x.group, x.other))
            .collect();
        self.incidence = inc.iter().map(code).collect();
    }

    /// Every listed pair's force (history updated), then each owned free
    /// body's sum in partner-id order, added to its gravity and wall force
    /// (and each copy of a moving group's sphere's, from zero).
    pub(super) fn sum_pair_forces(
        &mut self,
        pipeline: &mut Pipeline,
        world: &mut World,
        workers: &Workers,
        dt: f64,
    ) {
        if self.plain_sums {
            pipeline.pair_forces(world, workers, dt);
            return;
        }
        if self.in_cell_order {
            pipeline.pair_forces(world, workers, dt);
            self.particle_wall_load = self.boundary_particle_loads(world);
            return;
        }
        let n = world.bodies.len();
        let list = &world.list;
        let m = list.j.len();
        let laws = &world.laws;
        let keep = laws.history;
        self.pair_force.resize(m + list.extra.len(), [0.0; 3]);
        self.hit.resize(m + list.extra.len(), false);
        let mut force = std::mem::take(&mut world.bodies.force);
        let b = &world.bodies;
        assert!(list.start.len() == n + 1 && (!keep || world.histories.main.len() == m));
        let pf = SharedMut::new(&mut self.pair_force);
        let hist = SharedMut::new(&mut world.histories.main);
        let pair = |xi,
                    vi,
                    ri,
                    xj,
                    vj,
                    rj,
                    law: &dembound_physics::contact::PairLaw,
                    h: &mut ContactHistory| {
            match touching(xi, vi, ri, xj, vj, rj) {
                Some(g) => {
                    let f = law.force(g.overlap, g.overlap_rate, h);
                    law.update(g.overlap, g.overlap_rate, h);
                    [f * g.normal[0], f * g.normal[1], f * g.normal[2]]
                }
                None => {
                    if *h != ContactHistory::default() {
                        *h = ContactHistory::default();
                    }
                    [0.0; 3]
                }
            }
        };
        let hit = SharedMut::new(&mut self.hit);
        let (position, velocity, radius) = (&b.position[..], &b.velocity[..], &b.radius[..]);
        workers.run(n.div_ceil(STEP_CHUNK), |c| {
            for i in c * STEP_CHUNK..((c + 1) * STEP_CHUNK).min(n) {
                let (xi, vi, ri) = (position[i], velocity[i], radius[i]);
                for k in list.start[i] as usize..list.start[i + 1] as usize {
                    let j = list.j[k] as usize;
                    // The partner's velocity and the law only in contact
                    // (as the engine's loop).
                    let g = touching_lazy(xi, vi, ri, position[j], || velocity[j], radius[j]);
                    // SAFETY: entry k belongs to row i, in this chunk only.
                    unsafe {
                        match g {
                            Some(g) => {
                                let mut scratch = NO_HISTORY;
                                let h = if keep { hist.at(k) } else { &mut scratch };
                                let law = laws.pair(b, i, j);
                                let f = law.force(g.overlap, g.overlap_rate, h);
                                law.update(g.overlap, g.overlap_rate, h);
                                *pf.at(k) = [f * g.normal[0], f * g.normal[1], f * g.normal[2]];
                                *hit.at(k) = true;
                            }
                            None => {
                                *hit.at(k) = false;
                                if keep && *hist.at(k) != ContactHistory::default() {
                                    *hist.at(k) = ContactHistory::default();
                                }
                            }
                        }
                    }
                }
            }
        });
        for (q, &(i, j)) in list.extra.iter().enumerate() {
            let (i, j) = (i as usize, j as usize);
            let (xj, vj, owner) = extended(b, &world.ghosts, j);
            let mut scratch = NO_HISTORY;
            let h = if keep {
                &mut world.histories.extra[q]
            } else {
                &mut scratch
            };
            let law = laws.pair(b, i, owner);
            self.hit[m + q] = true;
            self.pair_force[m + q] = pair(
                b.position[i],
                b.velocity[i],
                b.radius[i],
                xj,
                vj,
                b.radius[owner],
                &law,
                h,
            );
        }
        let (start, inc, pf, hit) = (
            &self.incidence_start,
            &self.incidence,
            &self.pair_force,
            &self.hit,
        );
        let f_ptr = SharedMut::new(&mut force);
        workers.run(n.div_ceil(STEP_CHUNK), |c| {
            for i in c * STEP_CHUNK..((c + 1) * STEP_CHUNK).min(n) {
                let (s, e) = (start[i] as usize, start[i + 1] as usize);
                if s == e {
                    continue;
                }
                // SAFETY: one body per iteration, chunks disjoint.
                let f = unsafe { f_ptr.at(i) };
                for &x in &inc[s..e] {
                    let entry = (x & !NEGATIVE) as usize;
                    // Pairs apart add nothing (f + 0 = f: skipping them
                    // changes no bit).
                    if !hit[entry] {
                        continue;
                    }
                    let p = pf[entry];
                    if x & NEGATIVE != 0 {
                        f[0] -= p[0];
                        f[1] -= p[1];
                        f[2] -= p[2];
                    } else {
                        f[0] += p[0];
                        f[1] += p[1];
                        f[2] += p[2];
                    }
                }
            }
        });
        // The boundary particles' reaction, from the free side (no
        // friction here: no torque on the particle itself).
        let points = torque_points(world);
        let mut wf = vec![WallLoad::default(); world.walls.len()];
        for &(x, group, other) in &self.walled {
            let entry = (x & !NEGATIVE) as usize;
            if hit[entry] {
                let p = pf[entry];
                // The free body got ∓p; the boundary particle gets ±p.
                let s = if x & NEGATIVE != 0 { 1.0 } else { -1.0 };
                let g = group as usize;
                add_particle_load(
                    &mut wf[g],
                    world.bodies.position[other as usize],
                    points[g],
                    p.map(|c| s * c),
                    [0.0; 3],
                );
            }
        }
        self.particle_wall_load = wf;
        world.bodies.force = force;
    }

    /// The load on each boundary-particle wall from this rank's pairs:
    /// the forces and torques its boundary particles (owned ones and halo
    /// copies) got in the last force stage (`pipeline::wall_loads`). A
    /// pair of a free body with a boundary particle is listed only on the
    /// rank owning the free body (two bodies flagged fixed, a halo copy
    /// being one, are never paired), so the sum over the ranks counts
    /// each pair once.
    pub(super) fn boundary_particle_loads(&self, world: &World) -> Vec<WallLoad> {
        let b = &world.bodies;
        let points = torque_points(world);
        let mut wf = vec![WallLoad::default(); world.walls.len()];
        for k in 0..b.len() {
            let g = b.group[k];
            if g != NO_GROUP && b.fixed[k] {
                if let Some(w) = wf.get_mut(g as usize) {
                    let tau = b.torque.get(k).copied().unwrap_or([0.0; 3]);
                    add_particle_load(w, b.position[k], points[g as usize], b.force[k], tau);
                }
            }
        }
        wf
    }
}
