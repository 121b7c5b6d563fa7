//! A checkpoint written in parts, one a rank (`[parallel]
//! checkpoint_per_rank = true` under MPI, issue 31 item 5): each rank
//! writes the bodies it owns, their wall records and the pairs it lists as
//! `checkpoint_rank_R.cbor` (a checkpoint file, [`super::checkpoint`],
//! holding part of the bodies), and rank 0 writes `checkpoint.cbor` as the
//! index: the run's shared figures (step, Δt, energies, the walls' books,
//! the collision log, the scene's fingerprint settings) and each part's
//! file name, body count and SHA-256 ([`PartsIndex`]), format
//! [`FORMAT_PARTS`]. No rank gathers the bodies.
//!
//! `--restart DIR/checkpoint.cbor` reads either kind. Under MPI each rank
//! reads the parts [`parts_for_rank`] gives it (any rank count: the
//! records then go to the ranks holding their bodies,
//! `comm::distributed::checkpoint_parts`); on one process
//! [`read_whole`] reads every part and merges them into the whole
//! checkpoint, the one the run would have gathered. A part whose SHA-256
//! is not the index's (another run's, damaged, cut) is refused by name.

use std::ops::Range;
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};
use sha2::{Digest, Sha256};

use super::checkpoint::{self, CheckpointFile};
use crate::fingerprint::Fingerprint;
use crate::simulation::Checkpoint;
use crate::SceneError;

/// The index file's format (its parts are checkpoint files of
/// [`checkpoint::FORMAT`]).
pub const FORMAT_PARTS: &str = "dembound-scene checkpoint in parts";

/// The parts of a checkpoint written per rank.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PartsIndex {
    /// One a writing rank, in rank order.
    pub parts: Vec<PartEntry>,
}

/// One rank's part.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PartEntry {
    /// The file's name, beside the index.
    pub file: String,
    /// The bodies in it.
    pub bodies: u64,
    /// SHA-256 of the whole file, lowercase hex.
    pub sha256: String,
}

/// Rank `rank`'s part's file name.
pub fn part_name(rank: usize) -> String {
    format!("checkpoint_rank_{rank}.cbor")
}

/// `digest` as lowercase hex.
pub fn hex(digest: &[u8]) -> String {
    digest.iter().map(|b| format!("{b:02x}")).collect()
}

/// The parts (of `written`) that rank `rank` of `ranks` reads: each part
/// read by exactly one rank, in blocks (`written` = `ranks`: its own).
pub fn parts_for_rank(rank: usize, ranks: usize, written: usize) -> Range<usize> {
    let ranks = ranks.max(1);
    let at = |r: usize| (r * written).div_ceil(ranks);
    at(rank)..at(rank + 1).min(written)
}

/// The index's file for a run's shared figures `state` (no bodies) and
/// its `parts`.
pub fn index_file(
    scene: super::config::SceneFile,
    state: Checkpoint,
    parts: Vec<PartEntry>,
) -> CheckpointFile {
    CheckpointFile {
        format: FORMAT_PARTS.into(),
        version: checkpoint::VERSION,
        scene,
        state,
        parts: Some(PartsIndex { parts }),
    }
}

/// `c` (a rank's part, [`crate::comm::DistributedSimulation::checkpoint_part`])
/// without its bodies and records: the run's shared figures, for the index.
pub fn shared_figures(c: &Checkpoint) -> Checkpoint {
    Checkpoint {
        order: Vec::new(),
        position: Vec::new(),
        velocity: Vec::new(),
        force: Vec::new(),
        higher: Vec::new(),
        reference: Vec::new(),
        pair_histories: Vec::new(),
        plane_histories: Vec::new(),
        pair_tracks: Vec::new(),
        plane_tracks: Vec::new(),
        fingerprint: Fingerprint {
            settings: c.fingerprint.settings.clone(),
            ..Fingerprint::default()
        },
        angular_velocity: Vec::new(),
        torque: Vec::new(),
        pair_shear: Vec::new(),
        plane_shear: Vec::new(),
        element_records: Vec::new(),
        angular_higher: Vec::new(),
        ..c.clone()
    }
}

/// Reads part `entry` of the index at `index_path`, checked against the
/// index: its SHA-256, a checkpoint of the format with that many bodies.
pub fn read_part(index_path: &Path, entry: &PartEntry) -> Result<Checkpoint, SceneError> {
    let path = part_path(index_path, entry)?;
    let bytes = std::fs::read(&path).map_err(|e| {
        SceneError::input(format!(
            "`{}`: cannot read the checkpoint's part: {e}",
            path.display()
        ))
    })?;
    let digest = hex(&Sha256::digest(&bytes));
    if digest != entry.sha256 {
        return Err(SceneError::input(format!(
            "`{}`: the part's SHA-256 is {digest}, the index `{}` says {}: the part is \
             damaged or of another run",
            path.display(),
            index_path.display(),
            entry.sha256
        )));
    }
    let file = checkpoint::read_from(&bytes[..], &path.display().to_string())?;
    if file.parts.is_some() || file.state.order.len() as u64 != entry.bodies {
        return Err(SceneError::input(format!(
            "`{}`: not the part the index `{}` lists ({} bodies)",
            path.display(),
            index_path.display(),
            entry.bodies
        )));
    }
    Ok(file.state)
}

/// The part's path: its name beside the index (a bare file name only).
fn part_path(index_path: &Path, entry: &PartEntry) -> Result<PathBuf, SceneError> {
    let name = Path::new(&entry.file);
    if name.file_name() != Some(name.as_os_str()) {
        return Err(SceneError::input(format!(
            "`{}`: a part's name `{}` is not a file name",
            index_path.display(),
            entry.file
        )));
    }
    Ok(index_path.parent().unwrap_or(Path::new(".")).join(name))
}

/// Reads the checkpoint at `path`, whole or in parts; a checkpoint in
/// parts is merged ([`merge`]; `scene`: the fingerprint of the scene that
/// continues it).
pub fn read_whole(path: &Path, scene: &Fingerprint) -> Result<CheckpointFile, SceneError> {
    merge_file(path, checkpoint::read_any(path)?, scene)
}

/// The checkpoint `file` read from `path` ([`checkpoint::read_any`]) made
/// whole: as it is, or, the index of a checkpoint in parts, its parts
/// (beside `path`) read and merged as [`read_whole`] merges them.
pub fn merge_file(
    path: &Path,
    mut file: CheckpointFile,
    scene: &Fingerprint,
) -> Result<CheckpointFile, SceneError> {
    let Some(index) = file.parts.take() else {
        return Ok(file);
    };
    let parts = index
        .parts
        .iter()
        .map(|e| read_part(path, e))
        .collect::<Result<Vec<_>, _>>()?;
    file.state = merge(&file.state, parts, scene);
    file.format = checkpoint::FORMAT.into();
    Ok(file)
}

/// The whole checkpoint of the shared figures `index` and the `parts`:
/// the bodies in input order, each wall and pair record once in key order,
/// as the run would have gathered it. The spheres the run removed are in
/// no part: their entries of the fingerprint's per-body lists are the
/// scene's (`scene`), not checked.
pub fn merge(index: &Checkpoint, parts: Vec<Checkpoint>, scene: &Fingerprint) -> Checkpoint {
    let mut c = index.clone();
    // (id, part, entry) of every body, in input order.
    let mut at: Vec<(u32, usize, usize)> = parts
        .iter()
        .enumerate()
        .flat_map(|(p, part)| {
            part.order
                .iter()
                .enumerate()
                .map(move |(k, &id)| (id, p, k))
        })
        .collect();
    at.sort_unstable();
    at.dedup_by_key(|e| e.0);
    fn take<T: Copy>(
        parts: &[Checkpoint],
        at: &[(u32, usize, usize)],
        f: fn(&Checkpoint) -> &Vec<T>,
    ) -> Vec<T> {
        if parts.iter().all(|p| f(p).is_empty()) {
            return Vec::new();
        }
        at.iter()
            .filter_map(|&(_, p, k)| f(&parts[p]).get(k).copied())
            .collect()
    }
    c.order = at.iter().map(|e| e.0).collect();
    c.position = take(&parts, &at, |p| &p.position);
    c.velocity = take(&parts, &at, |p| &p.velocity);
    c.force = take(&parts, &at, |p| &p.force);
    c.higher = take(&parts, &at, |p| &p.higher);
    c.reference = take(&parts, &at, |p| &p.reference);
    c.angular_velocity = take(&parts, &at, |p| &p.angular_velocity);
    c.torque = take(&parts, &at, |p| &p.torque);
    c.angular_higher = take(&parts, &at, |p| &p.angular_higher);
    // The fingerprint's per-body lists: every input sphere.
    let mut f = Fingerprint {
        settings: index.fingerprint.settings.clone(),
        ..scene.clone()
    };
    for &(id, p, k) in &at {
        let (part, id) = (&parts[p].fingerprint, id as usize);
        if let (Some(r), Some(m), Some(x)) = (
            f.radius.get_mut(id),
            f.material.get_mut(id),
            f.fixed.get_mut(id),
        ) {
            (*r, *m, *x) = (part.radius[k], part.material[k], part.fixed[k]);
        }
    }
    c.fingerprint = f;
    // Records keyed by ids: once each (a pair across a cut is in two
    // parts with the same bits), in key order.
    fn records<K: Ord + Copy, T: Copy>(
        parts: &[Checkpoint],
        f: fn(&Checkpoint) -> Vec<(K, T)>,
    ) -> Vec<(K, T)> {
        let map: std::collections::BTreeMap<K, T> = parts.iter().flat_map(f).collect();
        map.into_iter().collect()
    }
    // The pair and plane records: (index, index, value), keyed by the two.
    fn triples<A: Ord + Copy, B: Ord + Copy, T: Copy>(
        parts: &[Checkpoint],
        f: fn(&Checkpoint) -> &Vec<(A, B, T)>,
    ) -> Vec<(A, B, T)> {
        let map: std::collections::BTreeMap<(A, B), T> = parts
            .iter()
            .flat_map(|p| f(p).iter().map(|&(a, b, t)| ((a, b), t)))
            .collect();
        map.into_iter().map(|((a, b), t)| (a, b, t)).collect()
    }
    c.pair_histories = triples(&parts, |p| &p.pair_histories);
    c.plane_histories = triples(&parts, |p| &p.plane_histories);
    c.pair_tracks = triples(&parts, |p| &p.pair_tracks);
    c.plane_tracks = triples(&parts, |p| &p.plane_tracks);
    c.pair_shear = triples(&parts, |p| &p.pair_shear);
    c.plane_shear = triples(&parts, |p| &p.plane_shear);
    c.element_records = records(&parts, |p| {
        p.element_records
            .iter()
            .map(|&e| ((e.id, e.key), e))
            .collect()
    })
    .into_iter()
    .map(|(_, e)| e)
    .collect();
    c
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_part_is_read_by_exactly_one_rank() {
        for written in 1..7 {
            for ranks in 1..7 {
                let mut seen = vec![0; written];
                for r in 0..ranks {
                    for p in parts_for_rank(r, ranks, written) {
                        seen[p] += 1;
                    }
                }
                assert!(
                    seen.iter().all(|&s| s == 1),
                    "{written} parts on {ranks} ranks: {seen:?}"
                );
            }
        }
        // The same count: each rank its own part.
        assert_eq!(parts_for_rank(2, 3, 3), 2..3);
    }
}
