//! A rank's share of the inlets (`crate::inlets`, module doc of its
//! engine hooks: **Several ranks**): the spheres in an inlet's way
//! gathered from every rank, the placed spheres of this sub-domain kept.

use std::collections::BTreeMap;

use super::RankComm;
use crate::comm::pack::{Reader, Writer};
use crate::comm::Transport;
use crate::inlets::InsertHooks;
use crate::pipeline::{save_pairs, SavedPairs, World};

impl<T: Transport> InsertHooks for RankComm<T> {
    /// This rank's own bodies near the box (not the halo copies, not those
    /// removed at this rebuild, the spheres placed here earlier in the
    /// step included) sent to every other rank; every rank's, in input-id
    /// order (each body's images in [`crate::inlets`]'s order). The set is
    /// the one process's; the order does not change the exact overlap
    /// tests. Collective.
    fn spheres_near(
        &mut self,
        world: &World,
        bounds: ([f64; 3], [f64; 3]),
        reach: f64,
    ) -> Vec<(u32, [f64; 3], f64)> {
        let (halo, dropping) = (&self.halo, &self.dropping);
        let own = |k: usize| {
            !halo.get(k).copied().unwrap_or(false) && !dropping.get(k).copied().unwrap_or(false)
        };
        let mut all = crate::inlets::nearby(world, bounds, reach, &own);
        let mut out: BTreeMap<usize, Writer> = BTreeMap::new();
        if !all.is_empty() {
            for r in (0..self.transport.size()).filter(|&r| r != self.transport.rank()) {
                let w = out.entry(r).or_default();
                for &(id, x, radius) in &all {
                    w.u32(id);
                    w.vec3(x);
                    w.f64(radius);
                }
            }
        }
        for (_, bytes) in self.send_records(out) {
            let mut r = Reader::new(&bytes);
            while !r.done() {
                all.push((r.u32(), r.vec3(), r.f64()));
            }
        }
        // Stable: a body's images keep their order.
        all.sort_by_key(|s| s.0);
        all
    }

    /// The centre lies in this rank's sub-domain.
    fn keeps(&self, world: &World, x: [f64; 3]) -> bool {
        self.decomposition.owner(world.domain.wrap(x)) == self.transport.rank()
    }
}

impl<T: Transport> RankComm<T> {
    /// Inserts the spheres due at this rebuild (`crate::inlets`), this
    /// rank's kept; the per-id tables grow to the new ids (inserted
    /// spheres are free). Returns the pair state by input ids taken before
    /// (`None`: nothing due, the bodies unchanged). Collective.
    pub(super) fn insert_due(&mut self, world: &mut World) -> Option<SavedPairs> {
        let due = world
            .inlets
            .as_ref()
            .is_some_and(|i| i.due_at(world.steps_done + 1));
        if !due {
            return None;
        }
        let saved = save_pairs(world);
        crate::inlets::insert_due(world, self);
        let ids = world.inlets.as_ref().map_or(0, |i| i.next_id as usize);
        if ids > self.fixed_by_id.len() {
            self.fixed_by_id.resize(ids, false);
            self.owned_by_id.resize(ids, false);
        }
        Some(saved)
    }
}
