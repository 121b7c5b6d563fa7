//! `mpirun -np N dembound scene FILE.toml …` (feature `mpi`, issue 16):
//! one scene on N ranks through `dembound_scene::comm`. Every rank reads
//! the scene file; rank 0 alone prints and writes files (gathered from
//! the others), all or nothing through [`AtomicDir`].
//!
//! `--out` writes `checkpoint.cbor` (gathered at rank 0, bodies in input
//! order, the one-process engine's format); `--restart` reads it on every
//! rank and continues on any number of ranks (or without mpirun).
//! `[parallel] checkpoint_per_rank`: every rank writes its own part of the
//! checkpoint and rank 0 the index (`io::checkpoint_parts`); `--restart`
//! of the index reads each part at one rank, on any number of ranks.
//! `[parallel] vtk_per_rank`: the sphere snapshots written by every rank,
//! its own piece, with a `.pvtp` index ([`super::scene_mpi_pieces`]); the
//! mesh walls' files too, each rank a slice of the triangles.
//!
//! Errors: a setup error on any rank ends every rank (the ranks agree on
//! it before the first exchange; the lowest failing rank prints it; exit 2
//! for bad input); an output error at rank 0 after the run ends the run
//! with MPI_Abort (exit 1).

use std::io::Write;
use std::path::Path;

use anyhow::anyhow;
use dembound_scene::comm::distributed::balance::{imbalance, DEFAULT_REBALANCE_THRESHOLD};
use dembound_scene::comm::distributed::{GatheredState, PEER_REFUSED};
use dembound_scene::comm::mpi::MpiTransport;
use dembound_scene::comm::{DistributedSimulation, Transport};
use dembound_scene::io::checkpoint::{self, CheckpointFile};
use dembound_scene::io::checkpoint_parts;
use dembound_scene::io::resolve::{resolve, resolve_parts, PartGroup, ResolvedScene};
use dembound_scene::io::{config, labels, series, vtk, vtk_walls};
use dembound_scene::{Checkpoint, Collision, Observation};
use serde::Serialize;

use super::scene::{progress_bar, scene_error, Report, SceneArgs, PARALLEL_MIN_PARTICLES};
use super::scene_collisions::collision_report;
use super::{scene_mpi_pieces, CliError, CliResult};
use crate::output::files::AtomicDir;

/// How a rank ends on error: with an error to print, or silently with
/// the run's exit code (the message printed already).
enum Fail {
    Print(CliError),
    Silent(u8),
}

type RankResult<T> = Result<T, Fail>;

pub fn run(args: &SceneArgs) -> CliResult {
    let Some(t) = MpiTransport::init() else {
        return Err(CliError::failed(anyhow!("MPI was initialised twice")));
    };
    let result = run_rank(args, &t);
    // MPI_Finalize on every rank, also after an error.
    drop(t);
    match result {
        Ok(()) => Ok(()),
        Err(Fail::Print(e)) => Err(e),
        Err(Fail::Silent(code)) => std::process::exit(i32::from(code)),
    }
}

/// Agreement on a per-rank result: Ok on every rank, or every rank fails
/// (the lowest rank with an error of its own prints it).
fn agree<T>(t: &MpiTransport, r: Result<T, CliError>) -> RankResult<T> {
    let own = match &r {
        Ok(_) => 0.0,
        Err(e) if e.error().to_string() == PEER_REFUSED => -1.0,
        Err(e) => f64::from(e.exit_code()),
    };
    let codes = t.all_gather(own);
    if codes.iter().all(|&c| c == 0.0) {
        return r.map_err(Fail::Print);
    }
    let code = codes.iter().copied().fold(1.0, f64::max) as u8;
    let printer = codes.iter().position(|&c| c >= 1.0);
    if let Err(e) = r {
        if printer == Some(t.rank()) {
            eprintln!("error: {:#}", e.error());
        }
    }
    // Nobody exits before the message is out: mpirun ends the remaining
    // ranks as soon as one exits with an error.
    t.all_gather(0.0);
    Err(Fail::Silent(code))
}

/// What every rank reads: the scene, the thread count, and at rank 0 the
/// output directory.
fn prepare(args: &SceneArgs, rank: usize, ranks: usize) -> Result<Prepared, CliError> {
    let file = config::read(&args.file, &args.set).map_err(scene_error)?;
    if file.output.wall_force_mean {
        // Each rank's per-step sum would hold only its share of the loads.
        return Err(CliError::input(anyhow!(
            "output.wall_force_mean = true is not available under mpirun: allowed here is \
             false (the default); run the scene on one process (`dembound scene`, threads \
             allowed) for the averaged wall-force columns"
        )));
    }
    let base = args.file.parent().unwrap_or(Path::new("."));
    // Every rank reads the checkpoint (as it reads the scene file) and
    // keeps its own bodies of it; of a checkpoint in parts, the index and
    // its share of the parts.
    let restart = match &args.restart {
        Some(path) => Some(read_restart(path, rank, ranks).map_err(scene_error)?),
        None => None,
    };
    // Lattices and data files: each rank makes its own part of the
    // spheres (`comm::distributed::input`), also to continue a checkpoint
    // in parts; else every rank all of them.
    let parts = match restart {
        None | Some(Restart::Parts(..)) => {
            resolve_parts(&file, base, ranks).map_err(scene_error)?
        }
        Some(Restart::Whole(_) | Restart::Index(_)) => None,
    };
    let (resolved, groups) = match parts {
        Some((r, g)) => (r, Some(g)),
        None => (resolve(&file, base).map_err(scene_error)?, None),
    };
    if rank == 0 {
        super::warnings::print(&resolved.warnings);
    }
    // One thread per rank unless asked: ranks already fill the cores.
    let threads = args.threads.map_or(1, usize::from);
    let _ = PARALLEL_MIN_PARTICLES;
    let out = match (&args.out, rank) {
        (Some(dir), 0) => Some(super::output_dir(dir, "scene")?),
        _ => None,
    };
    Ok((resolved, threads, out, restart, groups))
}

/// What `--restart` continues: a whole checkpoint, or the shared figures
/// of one in parts and the parts this rank read.
enum Restart {
    Whole(Checkpoint),
    Parts(Checkpoint, Vec<Checkpoint>),
    /// The index of a checkpoint in parts whose parts were spent.
    Index(Checkpoint),
}

/// Reads `--restart`'s checkpoint at rank `rank` of `ranks`.
fn read_restart(
    path: &Path,
    rank: usize,
    ranks: usize,
) -> Result<Restart, dembound_scene::SceneError> {
    let file = checkpoint::read_any(path)?;
    let Some(index) = file.parts else {
        return Ok(Restart::Whole(file.state));
    };
    let mine = checkpoint_parts::parts_for_rank(rank, ranks, index.parts.len());
    let parts = index.parts[mine]
        .iter()
        .map(|e| checkpoint_parts::read_part(path, e))
        .collect::<Result<Vec<_>, _>>()?;
    Ok(Restart::Parts(file.state, parts))
}

/// The parts of `--restart`'s checkpoint in parts that rank `rank` of
/// `ranks` reads (again).
fn read_restart_parts(
    args: &SceneArgs,
    rank: usize,
    ranks: usize,
) -> Result<Vec<Checkpoint>, dembound_scene::SceneError> {
    let path = args.restart.as_deref().unwrap_or(Path::new(""));
    match read_restart(path, rank, ranks)? {
        Restart::Parts(_, parts) => Ok(parts),
        _ => Err(dembound_scene::SceneError::input(format!(
            "`{}` changed while read: no longer a checkpoint in parts",
            path.display()
        ))),
    }
}

/// The scene, the threads per rank, the output directory (rank 0), the
/// checkpoint to continue, and the groups each rank makes its part of.
type Prepared = (
    ResolvedScene,
    usize,
    Option<AtomicDir>,
    Option<Restart>,
    Option<Vec<PartGroup>>,
);

/// The scene resolved whole (every rank makes every sphere).
fn resolve_whole(args: &SceneArgs) -> Result<ResolvedScene, CliError> {
    let file = config::read(&args.file, &args.set).map_err(scene_error)?;
    let base = args.file.parent().unwrap_or(Path::new("."));
    resolve(&file, base).map_err(scene_error)
}

/// The `--json` object: the one-process run's keys, plus the ranks'.
#[derive(Debug, Serialize)]
struct MpiReport {
    #[serde(flatten)]
    report: Report,
    ranks: usize,
    /// Sub-domains along x, y, z.
    grid: [usize; 3],
    /// Bodies owned by each rank at the end.
    rank_particles: Vec<usize>,
    /// Halo copies held by each rank at the end.
    rank_halo_particles: Vec<usize>,
    /// s per step, each rank's own stepping time.
    rank_seconds_per_step: Vec<f64>,
    /// Bytes each rank sent per step (halo updates, migration, halo
    /// rebuilds; reductions not counted).
    rank_bytes_per_step: Vec<f64>,
    /// Of which at neighbour-list rebuilds.
    rank_rebuild_bytes_per_step: Vec<f64>,
    /// s per step each rank spent in the per-step halo exchange beyond
    /// the pairs it overlapped (posting, waiting, unpacking).
    rank_halo_wait_seconds_per_step: Vec<f64>,
    /// Steps whose halo exchange ran during the pairs that need none of
    /// it (`parallel.halo_overlap`), per rank.
    rank_overlapped_steps: Vec<u64>,
    /// Pairs of each rank's last lists computed once the halo had
    /// arrived (with a free halo copy).
    rank_deferred_pairs: Vec<usize>,
    /// Free bodies owned by each rank at the end, at the first list build
    /// of this run, and just before the last re-partition (empty if none).
    rank_free_particles: Vec<usize>,
    rank_free_particles_start: Vec<usize>,
    rank_free_particles_before_rebalance: Vec<usize>,
    /// Largest over mean of `rank_free_particles`.
    imbalance: f64,
    /// `parallel.rebalance_threshold` (null: never).
    rebalance_threshold: Option<f64>,
    /// Re-partitions in this run.
    rebalances: u64,
    /// The sub-domain cuts along x, y and z at the end, m.
    cuts: [Vec<f64>; 3],
    /// Each rank made or read only its part of the spheres
    /// (`comm::distributed::input`); false: every rank read them all.
    input_in_parts: bool,
    /// s from the process start until every rank held its bodies (the
    /// scene read, the spheres made or read, the first forces), slowest
    /// rank.
    input_seconds: f64,
    /// Each rank's peak resident memory so far (VmHWM of
    /// /proc/self/status), bytes; empty where not available.
    rank_peak_memory: Vec<u64>,
}

/// This process's peak resident memory (VmHWM), bytes, where Linux
/// reports it.
fn peak_memory() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib * 1024)
}

fn run_rank(args: &SceneArgs, t: &MpiTransport) -> RankResult<()> {
    let rank = t.rank();
    let (mut resolved, threads, mut out, restart, groups) =
        agree(t, prepare(args, rank, t.size()))?;
    let grid = resolved.file.parallel.grid;
    // Spheres named in refusals as one process names them.
    let label = labels::label(&resolved.file, &resolved.groups, &resolved.wall_bodies);
    let (parted, restart) = match (&groups, restart) {
        (Some(g), None) => (
            DistributedSimulation::new_parts(&resolved.setup, g, &label, threads, grid, t),
            None,
        ),
        // The bodies from the parts, the scene's spheres each rank its part.
        (Some(g), Some(Restart::Parts(index, parts))) => (
            DistributedSimulation::restore_parts_in_parts(
                &resolved.setup,
                g,
                &label,
                &index,
                parts,
                threads,
                grid,
                t,
            ),
            Some(Restart::Index(index)),
        ),
        (_, restart) => (Ok(None), restart),
    };
    drop(label);
    let parted = agree(t, parted.map_err(scene_error))?;
    if parted.is_none() && groups.is_some() {
        // Not covered by the part-wise input: every rank reads all.
        resolved = agree(t, resolve_whole(args))?;
    }
    let built = match (parted, restart) {
        (Some((sim, warnings)), _) => {
            // The overlap warnings one process prints with the scene's.
            super::warnings::print(&warnings);
            Ok(sim)
        }
        (None, Some(Restart::Whole(c))) => {
            DistributedSimulation::restore(&resolved.setup, &c, threads, grid, t)
        }
        (None, Some(Restart::Parts(index, parts))) => {
            DistributedSimulation::restore_parts(&resolved.setup, &index, parts, threads, grid, t)
        }
        (None, Some(Restart::Index(index))) => {
            // The parts were spent on the part-wise attempt: read again.
            let parts = agree(
                t,
                read_restart_parts(args, rank, t.size()).map_err(scene_error),
            )?;
            DistributedSimulation::restore_parts(&resolved.setup, &index, parts, threads, grid, t)
        }
        (None, None) => DistributedSimulation::new(&resolved.setup, threads, grid, t),
    };
    let mut sim = agree(t, built.map_err(scene_error))?;
    let input_seconds = t.max(super::process_seconds());
    let input_in_parts = groups.is_some() && resolved.setup.spheres.is_empty();
    if rank == 0 {
        for note in sim.restart_notes() {
            eprintln!("{note}");
        }
    }
    let threshold = resolved.file.parallel.rebalance_threshold;
    sim.set_rebalance_threshold(threshold.unwrap_or(DEFAULT_REBALANCE_THRESHOLD));
    sim.set_halo_overlap(resolved.file.parallel.halo_overlap.unwrap_or(false));

    let total = sim.total_steps();
    let start = sim.steps_done();
    let limits = super::scene_limits::check_run(
        &resolved.setup,
        total,
        start,
        resolved_dt(&sim),
        args.restart.is_some(),
        args.force,
    );
    agree(t, limits)?;
    let span = total.saturating_sub(start);
    let every = resolved.file.output.every.unwrap_or((span / 20).max(1));
    let series_every = resolved
        .file
        .output
        .series_every
        .unwrap_or((span / 1000).max(1));
    let mut rows: Vec<Observation> = Vec::new();
    // The `.pvd` entries (time, file, part), as `scene.rs`.
    let mut snapshots: Vec<(f64, String, usize)> = Vec::new();
    let mut snapshot_count = 0;
    let mesh_walls = sim.mesh_walls();
    // `[parallel] vtk_per_rank`, `checkpoint_per_rank`: where every rank
    // writes its pieces (collective: every rank reads the same scene and
    // arguments).
    let parallel = &resolved.file.parallel;
    let staging = (args.out.is_some() && (parallel.vtk_per_rank || parallel.checkpoint_per_rank))
        .then(|| scene_mpi_pieces::share_staging(t, out.as_ref()));
    let pieces = staging.clone().filter(|_| parallel.vtk_per_rank);
    let bar = if rank == 0 {
        progress_bar(span, args.quiet)
    } else {
        None
    };
    let tick = (span / 200).max(1);
    let dt = resolved_dt(&sim);
    let write_failed = |e: anyhow::Error| -> ! {
        eprintln!("error: {e:#}");
        t.abort(1)
    };
    loop {
        let step = sim.steps_done();
        if (step - start) % series_every == 0 || step == total {
            // Collective; every rank takes the guard's same decision.
            rows.push(agree(t, sim.observe_checked().map_err(scene_error))?);
        }
        if args.out.is_some() && ((step - start) % every == 0 || step == total) {
            let k = snapshot_count;
            let time = step as f64 * dt;
            if let Some(dir) = &pieces {
                // Each rank its own spheres, rank 0 the index.
                match scene_mpi_pieces::write_snapshot(dir, &sim, k, step, time) {
                    Ok(Some(index)) => snapshots.push((time, index, 0)),
                    Ok(None) => {}
                    Err(e) => write_failed(e),
                }
            } else if let (Some(out), Some(state)) = (out.as_mut(), sim.gather_state()) {
                if let Err(e) = write_snapshot(out, &state, step, time, k) {
                    write_failed(e);
                }
                snapshots.push((time, vtk::snapshot_name(k), 0));
            }
            for &wall in &mesh_walls {
                if let Some(dir) = &pieces {
                    // Each rank its slice of the triangles, rank 0 the
                    // index (collective).
                    match scene_mpi_pieces::write_wall(dir, &sim, wall, k, step, time) {
                        Ok(Some(index)) => snapshots.push((time, index, wall + 1)),
                        Ok(None) => {}
                        Err(e) => write_failed(e),
                    }
                    continue;
                }
                // Collective: every rank sends its records, rank 0 writes.
                let loads = match sim.wall_triangle_loads(wall) {
                    Ok(loads) => loads,
                    Err(e) => write_failed(e.into()),
                };
                if let (Some(out), Some(loads)) = (out.as_mut(), loads) {
                    let name = vtk_walls::wall_name(wall, k);
                    let written = out.write(&name, |w| {
                        Ok(vtk_walls::write_wall(w, wall, time, step, &loads)?)
                    });
                    if let Err(e) = written {
                        write_failed(e);
                    }
                    snapshots.push((time, name, wall + 1));
                }
            }
            snapshot_count += 1;
        }
        if step >= total {
            break;
        }
        let mut next = total.min(step + tick);
        for interval in [
            series_every,
            if args.out.is_some() { every } else { u64::MAX },
        ] {
            let k = (step - start) / interval + 1;
            next = next.min(start.saturating_add(k.saturating_mul(interval)));
        }
        if (next - start) % series_every == 0 || next == total {
            // A row follows: the last pair pass and half kick tally it.
            sim.will_observe();
        }
        sim.step(next - step);
        // A blown-up run stops on every rank with one message (exit 2).
        agree(t, sim.check_finite().map_err(scene_error))?;
        if let Some(bar) = &bar {
            bar.set_position(next - start);
        }
    }
    // The whole process up to here, the slowest rank (rank 0 writes the
    // outputs after this).
    let wall_total = t.max(super::process_seconds());
    if let Some(bar) = bar {
        bar.finish_and_clear();
    }
    let stepping = t.max(sim.stepping_seconds());
    let reports = sim.rank_reports();
    let free = sim.free_counts();
    let balance = sim.balance_report();
    let last = rows.last().cloned().unwrap_or_else(|| sim.observe());
    // The end state for `state.csv`: gathered at rank 0 (collective), or
    // with `vtk_per_rank` each rank's own in its `state_rank_R.csv`;
    // nothing without `--out`.
    let final_state = match &pieces {
        _ if args.out.is_none() => None,
        None => sim.gather_state(),
        Some(dir) => {
            if let Err(e) = scene_mpi_pieces::write_state(dir, &sim) {
                write_failed(e);
            }
            None
        }
    };
    // The collision log, merged at rank 0 (collective).
    let log = if resolved.file.output.collisions {
        sim.collisions()
    } else {
        None
    };
    // The checkpoint, gathered at rank 0 in input order, or with
    // `checkpoint_per_rank` each rank's part in its own file and the index
    // at rank 0 (collective).
    let saved = match (&staging, args.out.is_some()) {
        (_, false) => None,
        (Some(dir), true) if resolved.file.parallel.checkpoint_per_rank => {
            match scene_mpi_pieces::write_checkpoint_part(dir, &sim, &resolved.file) {
                Ok(index) => index,
                Err(e) => write_failed(e),
            }
        }
        _ => match sim.checkpoint() {
            Ok(c) => c.map(|c| CheckpointFile::new(resolved.file.clone(), c)),
            Err(e) => write_failed(e.into()),
        },
    };
    // Collective: every rank's peak (−1 where unknown).
    let peaks = t.all_gather(peak_memory().map_or(-1.0, |b| b as f64));
    if rank != 0 {
        return Ok(());
    }
    // The scene's spheres and those the inlets inserted (`inlets`).
    let inserted: u64 = last.inlets.iter().map(|i| i.count).sum();
    let (inputs, fixed) = sim.input_counts();
    let n = inputs + inserted as usize;
    // The log's summary; its rows only where collisions.csv does not hold
    // them.
    let (collision_summary, collisions) = match &log {
        Some(l) => {
            let (summary, rows) = collision_report(l, args.out.is_some());
            (Some(summary), rows)
        }
        None => (None, None),
    };
    let report = Report {
        particles: n,
        free_particles: inputs - fixed,
        fixed_particles: fixed,
        steps: sim.steps_done(),
        steps_this_run: span,
        time: sim.steps_done() as f64 * dt,
        dt,
        contact_time_estimate: sim.local().time_step().contact_time,
        impact_speed: sim.local().time_step().impact_speed,
        rayleigh_time: sim.local().time_step().rayleigh_time,
        kinetic_energy: last.kinetic_energy,
        elastic_energy: last.elastic_energy,
        potential_energy: last.potential_energy,
        dissipated_energy: last.dissipated_energy,
        deleted_particles: last.removed.map(|r| r.particles),
        deleted_mass: last.removed.map(|r| r.mass),
        outlets: dembound_scene::outlets::outlet_reports(&rows),
        inlets: last.inlets.iter().map(|&i| i.into()).collect(),
        energy_balance: sim.energy_balance(&last),
        particle_contacts: last.particle_contacts,
        wall_contacts: last.wall_contacts,
        wall_forces: last.wall_forces.clone(),
        wall_torques: last.wall_torques.clone(),
        wall_torque_points: sim.wall_torque_points(),
        wall_triangle_counts: super::scene::triangle_counts(sim.wall_triangle_counts()),
        boundary_particle_holes: resolved.covering_holes.clone(),
        wall_motions: last.wall_motions.clone(),
        group_motions: last.group_motions.clone(),
        wall_clock: stepping,
        wall_clock_total: wall_total,
        particle_steps_per_second: if stepping > 0.0 {
            n as f64 * span as f64 / stepping
        } else {
            0.0
        },
        threads,
        neighbour_list_builds: sim.local().list_builds(),
        collision_summary,
        collisions,
    };
    super::warnings::print(&super::scene::not_placed_warnings(&report.inlets));
    let doc = MpiReport {
        report,
        ranks: t.size(),
        grid: sim.grid(),
        rank_particles: reports.iter().map(|r| r.owned).collect(),
        rank_halo_particles: reports.iter().map(|r| r.halo).collect(),
        rank_seconds_per_step: reports.iter().map(|r| r.seconds_per_step).collect(),
        rank_bytes_per_step: reports.iter().map(|r| r.bytes_per_step).collect(),
        rank_rebuild_bytes_per_step: reports.iter().map(|r| r.rebuild_bytes_per_step).collect(),
        rank_halo_wait_seconds_per_step: reports.iter().map(|r| r.halo_wait_per_step).collect(),
        rank_overlapped_steps: reports.iter().map(|r| r.overlapped_steps).collect(),
        rank_deferred_pairs: reports.iter().map(|r| r.deferred_pairs).collect(),
        imbalance: imbalance(&free),
        rank_free_particles: free,
        rank_free_particles_start: balance.free_at_start,
        rank_free_particles_before_rebalance: balance.free_before_last,
        rebalance_threshold: balance.threshold.is_finite().then_some(balance.threshold),
        rebalances: balance.rebalances,
        cuts: balance.cuts,
        input_in_parts,
        input_seconds,
        rank_peak_memory: if peaks.iter().all(|&p| p >= 0.0) {
            peaks.iter().map(|&p| p as u64).collect()
        } else {
            Vec::new()
        },
    };
    let written = match out {
        Some(out) => {
            match finish_outputs(
                out,
                &resolved,
                &rows,
                &snapshots,
                final_state.as_ref(),
                saved,
                log.as_deref().map(|l| (l, !mesh_walls.is_empty())),
            ) {
                Ok(w) => w,
                Err(e) => write_failed(e),
            }
        }
        None => Vec::new(),
    };
    let mut stdout = std::io::stdout().lock();
    let text = if args.json {
        super::json_text(&doc).map_err(Fail::Print)?
    } else {
        let mut s = format!(
            "{} spheres on {} MPI ranks (grid {:?}; per rank {:?} owned, {} re-partitions); ran {} \
             steps to t = {} s in {:.3} s ({:.3e} particle-steps/s)\n\
             energy: kinetic {:.6e} J, elastic {:.6e} J, potential {:.6e} J, dissipated {:.3e} J\n\
             contacts now: {} particle–particle, {} particle–wall\n",
            n,
            t.size(),
            doc.grid,
            doc.rank_particles,
            doc.rebalances,
            span,
            doc.report.time,
            stepping,
            doc.report.particle_steps_per_second,
            last.kinetic_energy,
            last.elastic_energy,
            last.potential_energy,
            last.dissipated_energy,
            last.particle_contacts,
            last.wall_contacts
        );
        s += &super::scene::balance_line(&doc.report.energy_balance);
        for (k, (f, t)) in last.wall_forces.iter().zip(&last.wall_torques).enumerate() {
            s += &format!(
                "wall {k}: force [{:.4e}, {:.4e}, {:.4e}] N, torque [{:.4e}, {:.4e}, {:.4e}] N m\n",
                f[0], f[1], f[2], t[0], t[1], t[2]
            );
        }
        for p in &written {
            s += &format!("wrote {}\n", p.display());
        }
        s
    };
    write!(stdout, "{text}")
        .and_then(|()| stdout.flush())
        .map_err(|e| Fail::Print(CliError::failed(e)))
}

fn resolved_dt<T: Transport>(sim: &DistributedSimulation<T>) -> f64 {
    sim.local().dt()
}

fn write_snapshot(
    out: &mut AtomicDir,
    s: &GatheredState,
    step: u64,
    time: f64,
    k: usize,
) -> anyhow::Result<()> {
    let materials: Vec<usize> = s.material.iter().map(|&m| m as usize).collect();
    out.write(&vtk::snapshot_name(k), |w| {
        Ok(vtk::write_snapshot(
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
        )?)
    })
}

/// `state.csv`'s columns and the `rows` of `s`: (input index, index into
/// `s`, rank) each.
pub(super) fn write_state(
    w: &mut dyn Write,
    s: &GatheredState,
    rows: impl Iterator<Item = (usize, usize, u32)>,
) -> anyhow::Result<()> {
    let mut c = csv::Writer::from_writer(w);
    c.write_record([
        "id", "x", "y", "z", "vx", "vy", "vz", "fx", "fy", "fz", "radius", "fixed", "rank",
    ])?;
    for (id, k, rank) in rows {
        let (x, v, f) = (s.position[k], s.velocity[k], s.force[k]);
        let mut row = vec![id.to_string()];
        row.extend(x.iter().chain(&v).chain(&f).map(|a| format!("{a:e}")));
        row.push(format!("{:e}", s.radius[k]));
        row.push(u8::from(s.fixed[k]).to_string());
        row.push(rank.to_string());
        c.write_record(&row)?;
    }
    c.flush()?;
    Ok(())
}

/// The series, the gathered end state (`None`: written per rank, or
/// not at all), the resolved scene; then everything renamed into place.
fn finish_outputs(
    mut out: AtomicDir,
    resolved: &ResolvedScene,
    rows: &[Observation],
    snapshots: &[(f64, String, usize)],
    state: Option<&GatheredState>,
    saved: Option<CheckpointFile>,
    // The collision log, and whether it has a triangle column (a scene
    // with a mesh wall).
    log: Option<(&[Collision], bool)>,
) -> anyhow::Result<Vec<std::path::PathBuf>> {
    out.write("snapshots.pvd", |w| {
        Ok(vtk::write_series_parts(w, snapshots)?)
    })?;
    if let Some((log, mesh_walls)) = log {
        out.write("collisions.csv", |w| {
            Ok(series::write_collisions(w, log, mesh_walls)?)
        })?;
    }
    let walls = resolved.setup.walls.len();
    out.write("series.csv", |w| Ok(series::write_series(w, rows, walls)?))?;
    if let Some(state) = state {
        out.write("state.csv", |w| {
            write_state(
                w,
                state,
                (0..state.position.len())
                    // Removed (`domain.outside = "delete"`): held by no rank.
                    .filter(|&k| state.rank[k] != u32::MAX)
                    .map(|k| (k, k, state.rank[k])),
            )
        })?;
    }
    let toml = toml::to_string(&resolved.file)?;
    out.write("scene.toml", |w| {
        writeln!(
            w,
            "# The scene as run: every default written out, source paths absolute."
        )?;
        Ok(w.write_all(toml.as_bytes())?)
    })?;
    // The engine's checkpoint format (or the index of its parts):
    // `--restart` continues it on any number of ranks, or without mpirun.
    if let Some(file) = saved {
        out.write("checkpoint.cbor", |w| {
            checkpoint::write(w, &file).map_err(|e| anyhow!(e))
        })?;
    }
    out.commit()
}
