//! `[parallel] vtk_per_rank` (issue 31 item 5): each rank writes the
//! spheres it owns at a snapshot as its own piece
//! (`snapshot_NNNNNN_rank_R.vtp`, `io::vtk::write_piece`) and rank 0 the
//! `.pvtp` index listing every rank's piece (`io::vtk::write_parallel_index`);
//! no sphere crosses ranks for output. The pieces go into rank 0's staging
//! directory (`AtomicDir`: published with the rest of the set, all or
//! nothing), whose path rank 0 sends to the others: the ranks must share
//! a file system, as for LAMMPS's per-processor dump files. The end state
//! too: each rank's `state_rank_R.csv` instead of a gathered `state.csv`.
//!
//! The mesh walls' files likewise: each rank the slice of a wall's
//! triangles whose loads it summed (`wall_K_NNNNNN_rank_R.vtp`), rank 0
//! the index `wall_K_NNNNNN.pvtp`; no gather.
//!
//! `[parallel] checkpoint_per_rank`: each rank writes its part of the
//! checkpoint, `checkpoint_rank_R.cbor`, into the same staging directory,
//! and rank 0 the index `checkpoint.cbor` (`io::checkpoint_parts`).

use std::fs::File;
use std::io::{BufWriter, Write};
use std::os::unix::ffi::{OsStrExt, OsStringExt};
use std::path::{Path, PathBuf};

use anyhow::Context;
use dembound_scene::comm::mpi::MpiTransport;
use dembound_scene::comm::{DistributedSimulation, Transport};
use dembound_scene::io::checkpoint::{self, CheckpointFile};
use dembound_scene::io::checkpoint_parts::{self, PartEntry};
use dembound_scene::io::config::SceneFile;
use dembound_scene::io::{vtk, vtk_walls};

use crate::output::files::AtomicDir;

/// The staging directory of rank 0's `out` on every rank (collective).
pub(super) fn share_staging(t: &MpiTransport, out: Option<&AtomicDir>) -> PathBuf {
    let mine = out.map(|o| o.staging().to_path_buf());
    if t.rank() == 0 {
        let bytes = mine
            .as_deref()
            .map_or(&[][..], |p| p.as_os_str().as_bytes());
        let sends: Vec<(usize, Vec<u8>)> = (1..t.size()).map(|r| (r, bytes.to_vec())).collect();
        t.exchange(&sends, &[]);
        mine.unwrap_or_default()
    } else {
        let got = t.exchange(&[], &[0]);
        let bytes = got.into_iter().next().unwrap_or_default();
        PathBuf::from(std::ffi::OsString::from_vec(bytes))
    }
}

/// Writes this rank's piece of snapshot `k` into `dir` (every rank) and,
/// at rank 0, the `.pvtp` index of every rank's piece; returns the
/// index's name at rank 0. No communication.
pub(super) fn write_snapshot<T: Transport>(
    dir: &Path,
    sim: &DistributedSimulation<T>,
    k: usize,
    step: u64,
    time: f64,
) -> anyhow::Result<Option<String>> {
    let (rank, size) = (sim.rank(), sim.ranks());
    let (ids, s) = sim.owned_state();
    let ids: Vec<u64> = ids.into_iter().map(u64::from).collect();
    let materials: Vec<usize> = s.material.iter().map(|&m| m as usize).collect();
    write_file(&dir.join(vtk::piece_name(k, rank)), |w| {
        Ok(vtk::write_piece(
            w,
            &vtk::Snapshot {
                time,
                step,
                positions: &s.position,
                radii: &s.radius,
                velocities: &s.velocity,
                forces: &s.force,
                fixed: &s.fixed,
                materials: &materials,
                angular_velocities: &s.angular_velocity,
            },
            &ids,
        )?)
    })?;
    if rank != 0 {
        return Ok(None);
    }
    let name = vtk::parallel_snapshot_name(k);
    let pieces: Vec<String> = (0..size).map(|r| vtk::piece_name(k, r)).collect();
    write_file(&dir.join(&name), |w| {
        Ok(vtk::write_parallel_index(w, &pieces)?)
    })?;
    Ok(Some(name))
}

/// Writes this rank's piece of mesh wall `wall`'s file of snapshot `k`
/// (its slice of the triangles with their loads,
/// `DistributedSimulation::wall_triangle_loads_piece`) into `dir` and, at
/// rank 0, the `.pvtp` index of every rank's piece; returns the index's
/// name at rank 0. Collective (each triangle's records go to the rank of
/// its slice).
pub(super) fn write_wall<T: Transport>(
    dir: &Path,
    sim: &DistributedSimulation<T>,
    wall: usize,
    k: usize,
    step: u64,
    time: f64,
) -> anyhow::Result<Option<String>> {
    let (rank, size) = (sim.rank(), sim.ranks());
    let (first, loads) = sim.wall_triangle_loads_piece(wall)?;
    write_file(&dir.join(vtk_walls::wall_piece_name(wall, k, rank)), |w| {
        Ok(vtk_walls::write_wall_piece(
            w, wall, time, step, &loads, first,
        )?)
    })?;
    if rank != 0 {
        return Ok(None);
    }
    let name = vtk_walls::wall_index_name(wall, k);
    let pieces: Vec<String> = (0..size)
        .map(|r| vtk_walls::wall_piece_name(wall, k, r))
        .collect();
    write_file(&dir.join(&name), |w| {
        Ok(vtk_walls::write_wall_index(w, wall, &pieces)?)
    })?;
    Ok(Some(name))
}

/// Writes this rank's end state, the spheres it owns by input index, as
/// `state_rank_R.csv` (`state.csv`'s columns) into `dir`. No
/// communication.
pub(super) fn write_state<T: Transport>(
    dir: &Path,
    sim: &DistributedSimulation<T>,
) -> anyhow::Result<()> {
    let rank = sim.rank();
    let (ids, s) = sim.owned_state();
    write_file(&dir.join(format!("state_rank_{rank}.csv")), |w| {
        let rows = ids
            .iter()
            .enumerate()
            .map(|(k, &id)| (id as usize, k, rank as u32));
        super::scene_mpi::write_state(w, &s, rows)
    })
}

/// Writes this rank's part of the checkpoint into `dir` (every rank) and
/// returns at rank 0 the index's file: the run's shared figures and each
/// part's body count and SHA-256, gathered (32 + 8 bytes a rank).
/// Collective.
pub(super) fn write_checkpoint_part<T: Transport>(
    dir: &Path,
    sim: &DistributedSimulation<T>,
    scene: &SceneFile,
) -> anyhow::Result<Option<CheckpointFile>> {
    let part = sim.checkpoint_part();
    let bodies = part.order.len() as u64;
    let shared = (sim.rank() == 0).then(|| checkpoint_parts::shared_figures(&part));
    let file = CheckpointFile::new(scene.clone(), part);
    let mut digest = [0u8; 32];
    write_file(&dir.join(checkpoint_parts::part_name(sim.rank())), |w| {
        digest = checkpoint::write_hashed(w, &file).map_err(|e| anyhow::anyhow!(e))?;
        Ok(())
    })?;
    drop(file);
    let mut mine = bodies.to_le_bytes().to_vec();
    mine.extend_from_slice(&digest);
    // Every rank's part is on disk before rank 0 writes the index.
    let Some(all) = sim.transport().gather(mine) else {
        return Ok(None);
    };
    let parts = all
        .iter()
        .enumerate()
        .map(|(rank, b)| {
            let (count, sha) = b.split_at(8.min(b.len()));
            PartEntry {
                file: checkpoint_parts::part_name(rank),
                bodies: u64::from_le_bytes(count.try_into().unwrap_or([0; 8])),
                sha256: checkpoint_parts::hex(sha),
            }
        })
        .collect();
    Ok(shared.map(|s| checkpoint_parts::index_file(scene.clone(), s, parts)))
}

/// Writes `path` (in the staging directory, which must exist: it is never
/// made here) and syncs it.
fn write_file(
    path: &Path,
    write: impl FnOnce(&mut dyn Write) -> anyhow::Result<()>,
) -> anyhow::Result<()> {
    let context = || format!("cannot write `{}`", path.display());
    let file = File::create(path).with_context(context)?;
    let mut w = BufWriter::new(file);
    write(&mut w).with_context(context)?;
    w.flush().with_context(context)?;
    let file = w
        .into_inner()
        .map_err(|e| e.into_error())
        .with_context(context)?;
    file.sync_all().with_context(context)
}
