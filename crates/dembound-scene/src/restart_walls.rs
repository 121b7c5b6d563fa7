//! A restart with walls added or removed (issue 28): a checkpoint
//! continues in a scene whose `[[wall]]` list differs from the one that
//! wrote it (a plug plane taken out, a lid put in), instead of being
//! refused.
//!
//! **Matching.** A wall of the checkpoint and a wall of the scene are the
//! same wall when their identities are equal: the wall's type, geometry
//! and material (its setup as the checkpoint's fingerprint prints it,
//! `crate::fingerprint`), its prescribed motion or servo, and its own
//! friction coefficients. Walls are matched in file order: each wall of
//! the checkpoint takes the first wall of the scene with its identity not
//! yet taken (identical walls pair in order). A wall moved (`--set
//! wall.K.plane.point=…`) is another wall: the old one dropped, the new one
//! added. The window (`active`) is not part of the identity: a restart may
//! change when a gate opens (the status is that of the restart's step).
//!
//! **Dropped walls.** The checkpoint's walls with no match: the histories,
//! springs and collision tracks of their contacts are dropped, and one
//! line per wall names it and says how many spheres' contacts went
//! ([`WallChange::notes`]). The elastic energy those contacts held is not
//! known to the new scene (the wall's geometry is in the checkpoint only
//! as text): it counts as dissipated from the restart on.
//!
//! **Added walls.** The scene's walls with no match start with no contact
//! state; where one overlaps spheres at the restart, the elastic energy of
//! those overlaps enters the balance as gate energy (booked negative, as
//! a gate closing on them: `walls::gate`), so the energy guard does not
//! take it for energy created.
//!
//! **Refused.** A moving or force-controlled wall dropped or added, or the
//! moving walls reordered (the checkpoint keeps their state by order); a
//! wall of boundary particles added or removed changes the spheres, which
//! the body count refuses.

use std::collections::BTreeSet;

use crate::error::SceneError;
use crate::fingerprint::{Fingerprint, WallPrint};
use crate::simulation::Checkpoint;

/// How the checkpoint's walls map to the scene's.
#[derive(Debug, Clone, PartialEq, Default)]
pub(crate) struct WallChange {
    /// By the checkpoint's surface index (its walls in file order, less
    /// the boundary-particle walls): the scene's surface index, `None`:
    /// dropped.
    pub surfaces: Vec<Option<u32>>,
    /// By the scene's surface index: not in the checkpoint.
    pub added: Vec<bool>,
    /// One line per wall dropped or added (empty: the same walls).
    pub notes: Vec<String>,
}

impl WallChange {
    /// The walls are the checkpoint's, in the same order.
    pub fn unchanged(&self) -> bool {
        self.notes.is_empty()
            && self
                .surfaces
                .iter()
                .enumerate()
                .all(|(k, s)| *s == Some(k as u32))
    }
}

/// The surface index of each wall (file order; `None`: boundary
/// particles).
fn surface_indices(walls: &[WallPrint]) -> Vec<Option<u32>> {
    let mut next = 0u32;
    walls
        .iter()
        .map(|w| {
            (!w.particles).then(|| {
                next += 1;
                next - 1
            })
        })
        .collect()
}

/// Matches the walls of checkpoint `c` (its fingerprint) with those of the
/// scene (`scene`: its fingerprint), module doc.
pub(crate) fn match_walls(c: &Checkpoint, scene: &Fingerprint) -> Result<WallChange, SceneError> {
    match_walls_counted(c, scene, &|s| spheres_touching(c, s))
}

/// [`match_walls`] with the spheres having a record on each of the
/// checkpoint's surfaces given by `touching` (a checkpoint in parts counts
/// them over its parts, `comm::distributed::checkpoint_parts`).
pub(crate) fn match_walls_counted(
    c: &Checkpoint,
    scene: &Fingerprint,
    touching: &dyn Fn(u32) -> usize,
) -> Result<WallChange, SceneError> {
    let (old, new) = (c.fingerprint.walls(), scene.walls());
    let mut taken = vec![false; new.len()];
    let map: Vec<Option<usize>> = old
        .iter()
        .map(|w| {
            let j = (0..new.len()).find(|&j| !taken[j] && new[j].identity == w.identity)?;
            taken[j] = true;
            Some(j)
        })
        .collect();
    let moves = |w: &WallPrint| !w.identity.contains("| motion none | servo none |");
    // The moving walls: all kept, in the same order.
    let mut last = None;
    for (k, w) in old.iter().enumerate() {
        if !moves(w) {
            continue;
        }
        let Some(j) = map[k] else {
            return Err(SceneError::Checkpoint(format!(
                "its wall[{k}] ({}) moves (motion or servo) and is not in the scene: a restart \
                 may add or remove fixed walls only",
                w.text
            )));
        };
        if last.is_some_and(|l| j < l) {
            return Err(SceneError::Checkpoint(format!(
                "the scene has its moving walls in another order (the checkpoint's wall[{k}] is \
                 the scene's wall[{j}]): keep the moving walls' order"
            )));
        }
        last = Some(j);
    }
    if let Some(j) = (0..new.len()).find(|&j| !taken[j] && moves(&new[j])) {
        return Err(SceneError::Checkpoint(format!(
            "the scene's wall[{j}] ({}) moves (motion or servo) and is not in the checkpoint: a \
             restart may add or remove fixed walls only",
            new[j].text
        )));
    }
    let (old_s, new_s) = (surface_indices(&old), surface_indices(&new));
    let surfaces_old = old_s.iter().flatten().count();
    let surfaces_new = new_s.iter().flatten().count();
    let mut change = WallChange {
        surfaces: vec![None; surfaces_old],
        added: vec![false; surfaces_new],
        notes: Vec::new(),
    };
    for (k, j) in map.iter().enumerate() {
        if let (Some(s), Some(j)) = (old_s[k], j) {
            change.surfaces[s as usize] = new_s[*j];
        }
    }
    for (k, w) in old.iter().enumerate() {
        if map[k].is_some() {
            continue;
        }
        let spheres = old_s[k].map_or(0, touching);
        change.notes.push(format!(
            "restart: the checkpoint's wall[{k}] ({}) is not in the scene: dropped, with the \
             contact state (histories, springs, collision tracks) of {spheres} spheres on it; \
             the elastic energy of its contacts counts as dissipated",
            w.text
        ));
    }
    for (j, w) in new.iter().enumerate() {
        if taken[j] {
            continue;
        }
        if let Some(s) = new_s[j] {
            change.added[s as usize] = true;
        }
        change.notes.push(format!(
            "restart: the scene's wall[{j}] ({}) is not in the checkpoint: it starts with no \
             contact histories",
            w.text
        ));
    }
    Ok(change)
}

/// The spheres with a record (history, springs, track) on surface `s` of
/// checkpoint `c`.
pub(crate) fn spheres_touching(c: &Checkpoint, s: u32) -> usize {
    let mut ids = BTreeSet::new();
    ids.extend(c.plane_histories.iter().filter(|r| r.1 == s).map(|r| r.0));
    ids.extend(c.plane_shear.iter().filter(|r| r.1 == s).map(|r| r.0));
    ids.extend(c.plane_tracks.iter().filter(|r| r.1 == s).map(|r| r.0));
    ids.extend(
        c.element_records
            .iter()
            .filter(|r| r.key.wall == s)
            .map(|r| r.id),
    );
    ids.len()
}

/// The checkpoint's surfaces (its walls less the boundary-particle ones).
pub(crate) fn surface_count(c: &Checkpoint) -> usize {
    surface_indices(&c.fingerprint.walls())
        .iter()
        .flatten()
        .count()
}

/// Checkpoint `c` with its wall records on the scene's surfaces
/// (`change`): each record's wall index mapped, those of dropped walls
/// left out; a record whose wall is out of range stays (the restore
/// refuses it by name).
pub(crate) fn remap(c: &Checkpoint, change: &WallChange) -> Checkpoint {
    let to = |p: u32| -> Option<u32> {
        match change.surfaces.get(p as usize) {
            Some(s) => *s,
            None => Some(p),
        }
    };
    let mut out = c.clone();
    out.plane_histories = c
        .plane_histories
        .iter()
        .filter_map(|&(id, p, h)| Some((id, to(p)?, h)))
        .collect();
    out.plane_shear = c
        .plane_shear
        .iter()
        .filter_map(|&(id, p, s)| Some((id, to(p)?, s)))
        .collect();
    out.plane_tracks = c
        .plane_tracks
        .iter()
        .filter_map(|&(id, p, t)| Some((id, to(p)?, t)))
        .collect();
    out.element_records = c
        .element_records
        .iter()
        .filter_map(|r| {
            let mut r = *r;
            r.key.wall = to(r.key.wall)?;
            Some(r)
        })
        .collect();
    out
}

/// After a restore into the scene's walls (`change`): the elastic energy
/// of the overlaps with the added walls at the restored state, booked as
/// gate energy (module doc), and the gate energy of the checkpoint
/// (`carried`, at one process of a decomposed run: `first`) kept when the
/// scene has no gate; nothing when no wall is added and the checkpoint
/// booked none.
pub(crate) fn book_added(
    world: &mut crate::pipeline::World,
    change: &WallChange,
    carried: Option<f64>,
    first: bool,
) {
    let e = if change.added.iter().any(|&a| a) {
        world.wall_contact_energy(&change.added)
    } else {
        0.0
    };
    // On every process alike (a decomposed run sums the shares).
    let added = change.added.iter().any(|&a| a);
    if world.gates.is_none() && (carried.is_some() || added) {
        let kept = if first { carried.unwrap_or(0.0) } else { 0.0 };
        world.gates = Some(crate::walls::gate::Gates::carrying(
            world.surfaces.len(),
            kept,
        ));
    }
    if e != 0.0 {
        if let Some(g) = world.gates.as_deref_mut() {
            g.energy -= e;
        }
    }
}
