//! What a decomposed run reports: per-rank figures, the end state and
//! the collision log gathered at rank 0.

use super::DistributedSimulation;
use crate::bodies::Bodies;
use crate::comm::pack::{self, Reader, Writer};
use crate::comm::Transport;
use crate::dynamics::collisions::Collision;
use crate::pipeline::partner_key;

/// Per-rank figures of a run.
#[derive(Debug, Clone, PartialEq)]
pub struct RankReport {
    /// Bodies owned, at the end.
    pub owned: usize,
    /// Halo copies held, at the end.
    pub halo: usize,
    /// Seconds per step spent stepping.
    pub seconds_per_step: f64,
    /// Bytes this rank sent per step: halo updates, migration and halo
    /// rebuilds (reductions not counted).
    pub bytes_per_step: f64,
    /// Of which at list rebuilds (migration and new halo), per step.
    pub rebuild_bytes_per_step: f64,
    /// Seconds per step in the per-step halo exchange beyond the pairs
    /// it overlapped: posting, waiting, unpacking.
    pub halo_wait_per_step: f64,
    /// Steps whose halo exchange ran during the pairs that need none of
    /// it (`dynamics::halo_split`).
    pub overlapped_steps: u64,
    /// Pairs of the last lists computed once the halo had arrived (with
    /// a free halo copy).
    pub deferred_pairs: usize,
}

/// The end state gathered at rank 0, input order.
#[derive(Debug, Clone, Default)]
pub struct GatheredState {
    pub position: Vec<[f64; 3]>,
    pub velocity: Vec<[f64; 3]>,
    pub force: Vec<[f64; 3]>,
    pub radius: Vec<f64>,
    pub fixed: Vec<bool>,
    pub material: Vec<u32>,
    /// rad/s (0 without friction).
    pub angular_velocity: Vec<[f64; 3]>,
    /// Rank owning each body.
    pub rank: Vec<u32>,
}

impl<T: Transport> DistributedSimulation<T> {
    /// Every rank's collision log, merged at rank 0 in the engine's order
    /// (by the step that completed each, then sphere i and partner);
    /// `None` elsewhere. Collective.
    pub fn collisions(&self) -> Option<Vec<Collision>> {
        let w = &self.sim.world;
        // The order: a restart's log first, as it was; then by step, sphere
        // and partner (steps count from 1).
        type Key = (u64, u64, (u8, usize));
        let mine: Vec<(Key, Collision)> = self
            .comm
            .collision_steps
            .iter()
            .zip(&w.collisions)
            .enumerate()
            .map(|(k, (&step, c))| {
                let key = if k < self.comm.restored_collisions {
                    (0, k as u64, (0, 0))
                } else {
                    (step, c.i as u64, partner_key(c.j))
                };
                (key, *c)
            })
            .collect();
        let parts = self.comm.transport.gather(pack::encode(&mine))?;
        let mut all: Vec<(Key, Collision)> = parts
            .iter()
            .filter_map(|b| pack::decode::<Vec<(Key, Collision)>>(b))
            .flatten()
            .collect();
        all.sort_by_key(|(key, _)| *key);
        Some(all.into_iter().map(|(_, c)| c).collect())
    }

    /// This rank's figures, gathered for every rank (rank order). Collective.
    pub fn rank_reports(&self) -> Vec<RankReport> {
        let steps = self.steps_run.max(1) as f64;
        let owned = self.comm.transport.all_gather(self.owned() as f64);
        let halo = self
            .comm
            .transport
            .all_gather(self.comm.halo.iter().filter(|&&h| h).count() as f64);
        let secs = self.comm.transport.all_gather(self.stepping / steps);
        let bytes = self
            .comm
            .transport
            .all_gather(self.comm.bytes_sent as f64 / steps);
        let rebuild = self
            .comm
            .transport
            .all_gather(self.comm.rebuild_bytes as f64 / steps);
        let wait = self.comm.transport.all_gather(self.comm.halo_wait / steps);
        let overlapped = self
            .comm
            .transport
            .all_gather(self.comm.overlapped_steps as f64);
        let deferred = self
            .comm
            .transport
            .all_gather(self.comm.deferred_pairs as f64);
        (0..self.comm.transport.size())
            .map(|r| RankReport {
                owned: owned[r] as usize,
                halo: halo[r] as usize,
                seconds_per_step: secs[r],
                bytes_per_step: bytes[r],
                rebuild_bytes_per_step: rebuild[r],
                halo_wait_per_step: wait[r],
                overlapped_steps: overlapped[r] as u64,
                deferred_pairs: deferred[r] as usize,
            })
            .collect()
    }

    /// Bodies this rank has handed to other ranks so far.
    pub fn migrated(&self) -> u64 {
        self.comm.migrated
    }

    /// Whether each step's largest displacement travels with the halo
    /// messages (every rank trades halo state with every other) rather
    /// than in a collective of its own.
    pub fn displacement_in_halo(&self) -> bool {
        self.comm.max_in_halo
    }

    /// Seconds this rank spent stepping.
    pub fn stepping_seconds(&self) -> f64 {
        self.stepping
    }

    /// This rank's owned bodies by input index, with those indices (no
    /// communication): a per-rank snapshot's spheres. `rank` is empty.
    pub fn owned_state(&self) -> (Vec<u32>, GatheredState) {
        let b: &Bodies = &self.sim.world.bodies;
        let mut own: Vec<usize> = (0..b.len()).filter(|&k| !self.comm.halo[k]).collect();
        own.sort_by_key(|&k| b.id[k]);
        let s = GatheredState {
            position: own.iter().map(|&k| b.position[k]).collect(),
            velocity: own.iter().map(|&k| b.velocity[k]).collect(),
            force: own.iter().map(|&k| b.force[k]).collect(),
            radius: own.iter().map(|&k| b.radius[k]).collect(),
            fixed: own.iter().map(|&k| b.fixed[k]).collect(),
            material: own.iter().map(|&k| b.material[k]).collect(),
            angular_velocity: own
                .iter()
                .map(|&k| b.angular_velocity.get(k).copied().unwrap_or_default())
                .collect(),
            rank: Vec::new(),
        };
        (own.iter().map(|&k| b.id[k]).collect(), s)
    }

    /// The owned bodies of every rank at rank 0, input order (`None`
    /// elsewhere). Collective.
    pub fn gather_state(&self) -> Option<GatheredState> {
        let (ids, own) = self.owned_state();
        let mut w = Writer::default();
        for (k, &id) in ids.iter().enumerate() {
            w.u32(id);
            w.vec3(own.position[k]);
            w.vec3(own.velocity[k]);
            w.vec3(own.force[k]);
            w.f64(own.radius[k]);
            w.u8(u8::from(own.fixed[k]));
            w.u32(own.material[k]);
            w.vec3(own.angular_velocity[k]);
        }
        drop(own);
        let parts = self.comm.transport.gather(w.0)?;
        let n = self.comm.fixed_by_id.len();
        let mut s = GatheredState {
            position: vec![[0.0; 3]; n],
            velocity: vec![[0.0; 3]; n],
            force: vec![[0.0; 3]; n],
            radius: vec![0.0; n],
            fixed: vec![false; n],
            material: vec![0; n],
            angular_velocity: vec![[0.0; 3]; n],
            rank: vec![u32::MAX; n],
        };
        for (rank, bytes) in parts.iter().enumerate() {
            let mut r = Reader::new(bytes);
            while !r.done() {
                let id = r.u32() as usize;
                let (x, v, f, rad, fixed, mat) =
                    (r.vec3(), r.vec3(), r.vec3(), r.f64(), r.u8() != 0, r.u32());
                let spin = r.vec3();
                if id < n {
                    s.angular_velocity[id] = spin;
                    s.position[id] = x;
                    s.velocity[id] = v;
                    s.force[id] = f;
                    s.radius[id] = rad;
                    s.fixed[id] = fixed;
                    s.material[id] = mat;
                    s.rank[id] = rank as u32;
                }
            }
        }
        Some(s)
    }
}
