//! `dembound scene`: a many-particle scene (issue 12). Thin: the scene
//! file is read and resolved by `dembound_scene::io`, run by its
//! `Simulation`, and its outputs written here through [`AtomicDir`].

use super::scene_collisions::{collision_report, summary_line, CollisionSummary};
use super::{CliError, CliResult};
use crate::output::files::AtomicDir;
use crate::output::format::{duration, sig};
use anyhow::anyhow;
use clap::Args;
use dembound_scene::io::checkpoint::{self, CheckpointFile};
use dembound_scene::io::resolve::{resolve, ResolvedScene};
use dembound_scene::io::series::{boundary_particle, partner_name};
use dembound_scene::io::{config, series, vtk, vtk_walls};
use dembound_scene::{Collision, EnergyBalance, Observation, SceneError, SceneSetup, Simulation};
use indicatif::{ProgressBar, ProgressStyle};
use serde::Serialize;
use std::io::{IsTerminal, Write};
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Without --threads, scenes of fewer free particles run on one thread.
pub const PARALLEL_MIN_PARTICLES: usize = 5000;

#[derive(Debug, Args)]
pub struct SceneArgs {
    /// Scene file (TOML, SI; see README "dembound scene")
    #[arg(value_name = "FILE.toml")]
    pub file: PathBuf,

    /// Override one key after the file, e.g. `--set integration.steps=500`,
    /// `--set wall.0.material=rigid` (lists indexed by number). VALUE is
    /// read as TOML, a bare word as a string. Setting integration.dt drops
    /// integration.eta and vice versa; steps and duration likewise.
    /// Repeatable.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,

    /// Write the VTK snapshots (snapshot_*.vtp, wall_K_*.vtp of mesh walls
    /// with their loads per triangle, snapshots.pvd),
    /// series.csv, collisions.csv (with output.collisions), the resolved
    /// scene.toml and checkpoint.cbor into DIR (all or nothing)
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,

    /// Print one JSON object (SI) to stdout instead of the summary
    #[arg(long)]
    pub json: bool,

    /// Worker threads (results do not depend on it); default: all cores,
    /// one for scenes of fewer than 5000 free particles
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u16).range(1..=1024))]
    pub threads: Option<u16>,

    /// Continue from a checkpoint written by --out (the scene file must
    /// describe the same bodies and Δt; raise integration.steps to go on)
    #[arg(long, value_name = "CHECKPOINT")]
    pub restart: Option<PathBuf>,

    /// No progress bar
    #[arg(long, short)]
    pub quiet: bool,

    /// Run even when more than 1e9 integration steps are asked for
    /// (integration.steps, or integration.duration / Δt)
    #[arg(long)]
    pub force: bool,
}

/// Bad input exits 2, anything else 1.
pub(super) fn scene_error(e: SceneError) -> CliError {
    if e.is_input() {
        CliError::input(e)
    } else {
        CliError::failed(e)
    }
}

pub fn run(args: &SceneArgs) -> CliResult {
    #[cfg(feature = "mpi")]
    if dembound_scene::comm::mpi::MpiTransport::launched() {
        return super::scene_mpi::run(args);
    }
    let file = config::read(&args.file, &args.set).map_err(scene_error)?;
    let base = args.file.parent().unwrap_or(Path::new("."));
    let mut resolved = resolve(&file, base).map_err(scene_error)?;
    super::warnings::print(&resolved.warnings);
    let free = resolved.setup.spheres.iter().filter(|s| !s.fixed).count();
    let threads = match args.threads {
        Some(n) => usize::from(n),
        // Small scenes run faster on one thread than they synchronise two.
        None if free < PARALLEL_MIN_PARTICLES => 1,
        None => std::thread::available_parallelism().map_or(1, |n| n.get()),
    };
    let fixed = resolved.setup.spheres.len() - free;
    // The sphere list moves into the engine, which drops it once its own
    // arrays are built: a copy would hold 88 B a sphere more at the peak
    // (10⁷ spheres: 0.9 GB; issue 31 item 4).
    let spheres = std::mem::take(&mut resolved.setup.spheres);
    let setup = SceneSetup {
        spheres,
        ..resolved.setup.clone()
    };
    let mut sim = match &args.restart {
        Some(path) => {
            // Whole, or merged from its parts (`[parallel] checkpoint_per_rank`).
            let scene = dembound_scene::fingerprint::Fingerprint::of(&setup);
            let saved = dembound_scene::io::checkpoint_parts::read_whole(path, &scene)
                .map_err(scene_error)?;
            drop(scene);
            Simulation::restore(setup, &saved.state, threads)
        }
        None => Simulation::new(setup, threads),
    }
    .map_err(scene_error)?;
    // What a restart into changed walls dropped and added, a line a wall.
    for note in sim.restart_notes() {
        eprintln!("{note}");
    }

    let total = sim.total_steps();
    let start = sim.steps_done();
    super::scene_limits::check_run(
        &resolved.setup,
        total,
        start,
        sim.dt(),
        args.restart.is_some(),
        args.force,
    )?;
    let span = total.saturating_sub(start);
    let every = resolved.file.output.every.unwrap_or((span / 20).max(1));
    let series_every = resolved
        .file
        .output
        .series_every
        .unwrap_or((span / 1000).max(1));

    let mut out = match &args.out {
        Some(dir) => Some(super::output_dir(dir, "scene")?),
        None => None,
    };
    let mut rows: Vec<Observation> = Vec::new();
    // The `.pvd` entries: (time, file, part): part 0 the spheres, K + 1
    // mesh wall K (its loads per triangle, `vtk_walls`).
    let mut snapshots: Vec<(f64, String, usize)> = Vec::new();
    let mut snapshot_count = 0;
    let mesh_walls = sim.mesh_walls();
    let bar = progress_bar(span, args.quiet);
    // Progress is updated at least every 1/200 of the run.
    let tick = (span / 200).max(1);

    // `output.wall_force_mean`: each row also gets the walls' forces
    // averaged over every step since the previous row.
    let wall_force_mean = resolved.file.output.wall_force_mean;
    let walls = resolved.setup.walls.len();
    let mut stepping = 0.0;
    loop {
        let step = sim.steps_done();
        if (step - start) % series_every == 0 || step == total {
            // The energy guard checks every observation (no pass of its own).
            let mut row = sim.observe_checked().map_err(scene_error)?;
            if wall_force_mean {
                // No step since the previous row (the first): no mean.
                let means = sim.take_wall_force_mean();
                row.wall_force_means = Some(means.unwrap_or_else(|| vec![[f64::NAN; 3]; walls]));
                sim.start_wall_force_mean();
            }
            rows.push(row);
        }
        if let Some(out) = &mut out {
            if (step - start) % every == 0 || step == total {
                let k = snapshot_count;
                write_snapshot(out, &sim, k).map_err(CliError::failed)?;
                snapshots.push((sim.time(), vtk::snapshot_name(k), 0));
                for &wall in &mesh_walls {
                    write_wall_snapshot(out, &sim, wall, k).map_err(CliError::failed)?;
                    snapshots.push((sim.time(), vtk_walls::wall_name(wall, k), wall + 1));
                }
                snapshot_count += 1;
            }
        }
        if step >= total {
            break;
        }
        let mut next = total.min(step + tick);
        for interval in [series_every, if out.is_some() { every } else { u64::MAX }] {
            let k = (step - start) / interval + 1;
            next = next.min(start.saturating_add(k.saturating_mul(interval)));
        }
        if (next - start) % series_every == 0 || next == total {
            // A row follows: the last pair pass tallies it.
            sim.will_observe();
        }
        let t0 = Instant::now();
        sim.step_checked(next - step).map_err(scene_error)?;
        stepping += t0.elapsed().as_secs_f64();
        if let Some(bar) = &bar {
            bar.set_position(next - start);
        }
    }
    if let Some(bar) = bar {
        bar.finish_and_clear();
    }
    let last = rows.last().cloned().unwrap_or_else(|| sim.observe());
    let particle_steps = sim.body_count() as f64 * span as f64;
    let mut report = Report {
        // The scene's spheres (those removed included: `deleted_particles`).
        particles: sim.body_count() + last.removed.map_or(0, |r| r.particles as usize),
        free_particles: free,
        fixed_particles: fixed,
        steps: sim.steps_done(),
        steps_this_run: span,
        time: sim.time(),
        dt: sim.dt(),
        contact_time_estimate: sim.time_step().contact_time,
        impact_speed: sim.time_step().impact_speed,
        rayleigh_time: sim.time_step().rayleigh_time,
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
        wall_triangle_counts: triangle_counts(sim.wall_triangle_counts()),
        boundary_particle_holes: resolved.covering_holes.clone(),
        wall_motions: last.wall_motions.clone(),
        group_motions: last.group_motions.clone(),
        wall_clock: stepping,
        wall_clock_total: super::process_seconds(),
        particle_steps_per_second: if stepping > 0.0 {
            particle_steps / stepping
        } else {
            0.0
        },
        threads: sim.threads(),
        neighbour_list_builds: sim.list_builds(),
        collision_summary: None,
        collisions: None,
    };
    if resolved.file.output.collisions {
        let (summary, rows) = collision_report(sim.collisions(), out.is_some());
        report.collision_summary = Some(summary);
        report.collisions = rows;
    }

    // Spheres an inlet could not place are reported, not silently lost.
    super::warnings::print(&not_placed_warnings(&report.inlets));
    let written = match out {
        Some(out) => Some(finish_outputs(out, &resolved, &sim, &rows, &snapshots)?),
        None => None,
    };
    // The whole process: reading, set-up, stepping and the outputs written.
    report.wall_clock_total = super::process_seconds();

    let mut stdout = std::io::stdout().lock();
    if args.json {
        write!(stdout, "{}", super::json_text(&report)?).map_err(CliError::failed)?;
    } else {
        write!(stdout, "{}", summary(&report, &resolved)).map_err(CliError::failed)?;
        for path in written.unwrap_or_default() {
            writeln!(stdout, "wrote {}", path.display()).map_err(CliError::failed)?;
        }
    }
    stdout.flush().map_err(CliError::failed)
}

/// One warning per inlet that left spheres unplaced (`--json`
/// `inlets[K].not_placed`): reported, never silently lost.
pub(super) fn not_placed_warnings(inlets: &[dembound_scene::inlets::InletReport]) -> Vec<String> {
    inlets
        .iter()
        .enumerate()
        .filter(|(_, i)| i.not_placed > 0)
        .map(|(k, i)| {
            format!(
                "inlet[{k}]: {} of the {} spheres due found no free place in the region \
                 (inlet[{k}].max_attempts centres each): the region is full or too small \
                 for the rate",
                i.not_placed,
                i.not_placed + i.inserted
            )
        })
        .collect()
}

pub(super) fn progress_bar(steps: u64, quiet: bool) -> Option<ProgressBar> {
    if quiet || !std::io::stderr().is_terminal() {
        return None;
    }
    let bar = ProgressBar::new(steps);
    let style = ProgressStyle::with_template(
        "{elapsed_precise} [{wide_bar}] {pos}/{len} steps ({per_sec}), ETA {eta}",
    )
    .unwrap_or_else(|_| ProgressStyle::default_bar());
    bar.set_style(style.progress_chars("=> "));
    Some(bar)
}

fn write_snapshot(out: &mut AtomicDir, sim: &Simulation, k: usize) -> anyhow::Result<()> {
    out.write(&vtk::snapshot_name(k), |w| {
        Ok(vtk::write_simulation(w, sim)?)
    })
}

/// The `wall_triangle_counts` key: `None` (absent) without a mesh wall.
pub(super) fn triangle_counts(counts: Vec<Option<usize>>) -> Option<Vec<Option<usize>>> {
    counts.iter().any(Option::is_some).then_some(counts)
}

/// Mesh wall `wall`'s loads per triangle at snapshot number `k`.
fn write_wall_snapshot(
    out: &mut AtomicDir,
    sim: &Simulation,
    wall: usize,
    k: usize,
) -> anyhow::Result<()> {
    let loads = sim.wall_triangle_loads(wall)?;
    out.write(&vtk_walls::wall_name(wall, k), |w| {
        Ok(vtk_walls::write_wall(
            w,
            wall,
            sim.time(),
            sim.steps_done(),
            &loads,
        )?)
    })
}

/// The series, the collision log, the resolved scene and the checkpoint,
/// then everything renamed into place.
fn finish_outputs(
    mut out: AtomicDir,
    resolved: &ResolvedScene,
    sim: &Simulation,
    rows: &[Observation],
    snapshots: &[(f64, String, usize)],
) -> CliResult<Vec<PathBuf>> {
    let failed = CliError::failed;
    out.write("snapshots.pvd", |w| {
        Ok(vtk::write_series_parts(w, snapshots)?)
    })
    .map_err(failed)?;
    let walls = resolved.setup.walls.len();
    out.write("series.csv", |w| Ok(series::write_series(w, rows, walls)?))
        .map_err(failed)?;
    if resolved.file.output.collisions {
        out.write("collisions.csv", |w| {
            Ok(series::write_collisions(
                w,
                sim.collisions(),
                !sim.mesh_walls().is_empty(),
            )?)
        })
        .map_err(failed)?;
    }
    let toml = toml::to_string(&resolved.file).map_err(CliError::failed)?;
    out.write("scene.toml", |w| {
        writeln!(
            w,
            "# The scene as run: every default written out, source paths absolute."
        )?;
        Ok(w.write_all(toml.as_bytes())?)
    })
    .map_err(failed)?;
    let saved = CheckpointFile::new(resolved.file.clone(), sim.checkpoint());
    out.write("checkpoint.cbor", |w| {
        checkpoint::write(w, &saved).map_err(|e| anyhow!(e))
    })
    .map_err(failed)?;
    out.commit().map_err(failed)
}

/// The `--json` object.
#[derive(Debug, Serialize)]
pub(super) struct Report {
    pub(super) particles: usize,
    pub(super) free_particles: usize,
    pub(super) fixed_particles: usize,
    /// Steps since t = 0 (a restart continues the count).
    pub(super) steps: u64,
    pub(super) steps_this_run: u64,
    pub(super) time: f64,
    pub(super) dt: f64,
    pub(super) contact_time_estimate: Option<f64>,
    pub(super) impact_speed: Option<f64>,
    pub(super) rayleigh_time: Option<f64>,
    pub(super) kinetic_energy: f64,
    pub(super) elastic_energy: f64,
    pub(super) potential_energy: f64,
    pub(super) dissipated_energy: f64,
    /// Spheres removed so far (`domain.outside = "delete"`; absent
    /// otherwise).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(super) deleted_particles: Option<u64>,
    /// Their mass, kg.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(super) deleted_mass: Option<f64>,
    /// What each outlet removed and its steady mass flow rate (`[[outlet]]`;
    /// absent without outlets).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub(super) outlets: Vec<dembound_scene::outlets::OutletReport>,
    /// What each inlet inserted (`[[inlet]]`: `inserted`, `mass` in kg,
    /// `not_placed`); absent without inlets.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub(super) inlets: Vec<dembound_scene::inlets::InletReport>,
    /// The balance K + E + P + D against the start, and the largest energy
    /// gain the guard saw (`dembound_scene::energy_guard`).
    pub(super) energy_balance: EnergyBalance,
    pub(super) particle_contacts: usize,
    pub(super) wall_contacts: usize,
    /// Force on each wall (file order), N: what the last force stage
    /// applied to it.
    pub(super) wall_forces: Vec<[f64; 3]>,
    /// Torque on each wall (file order), N m, about its point in
    /// `wall_torque_points`.
    pub(super) wall_torques: Vec<[f64; 3]>,
    /// The point each wall's torque is taken about (file order), m.
    pub(super) wall_torque_points: Vec<[f64; 3]>,
    /// Triangles of each wall's cleaned mesh (null for a wall that is not
    /// a mesh); absent when the scene has no mesh wall. The per-triangle
    /// loads are in the `wall_K_*.vtp` files, not here.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(super) wall_triangle_counts: Option<Vec<Option<usize>>>,
    /// The largest hole of each mesh-form `boundary_particles` wall:
    /// `wall` (file order), `spheres`, `largest_hole` (the radius of the
    /// largest particle found to pass, m) and `largest_hole_bound` (an
    /// upper bound, m); absent without such walls.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub(super) boundary_particle_holes: Vec<dembound_scene::io::resolve::CoveringHole>,
    /// Each moving or force-controlled wall's motion at the end (issue
    /// 27): `wall` (file order), `position` (its reference point's
    /// displacement, m), `angle` (rad), `velocity` (m/s),
    /// `angular_velocity` (rad/s); absent when every wall is fixed.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub(super) wall_motions: Vec<dembound_scene::pipeline::wall_states::WallMotionState>,
    /// Each moving `[[particles]]` group at the end (issue 27): `group`
    /// (file order), its motion as `wall_motions`, and `force` (N),
    /// `torque` (N m) the spheres put on it about `torque_point` (the
    /// motion's centre now, m); absent when no group moves.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub(super) group_motions: Vec<dembound_scene::pipeline::moving_groups::GroupMotionState>,
    /// Seconds spent stepping (output excluded).
    pub(super) wall_clock: f64,
    /// Seconds of the whole process up to this report: reading the scene,
    /// set-up, stepping, sampling and the outputs written.
    pub(super) wall_clock_total: f64,
    pub(super) particle_steps_per_second: f64,
    pub(super) threads: usize,
    pub(super) neighbour_list_builds: u64,
    /// With `output.collisions`: the log's counts, extremes and durations
    /// ([`CollisionSummary`]).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(super) collision_summary: Option<CollisionSummary>,
    /// With `output.collisions` and no `--out`: every completed contact
    /// (with `--out` they are in `collisions.csv`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(super) collisions: Option<Vec<CollisionRow>>,
}

#[derive(Debug, Serialize)]
pub(super) struct CollisionRow {
    i: usize,
    /// A sphere's input index, or "wall:K".
    j: serde_json::Value,
    /// Input index of the boundary particle hit when `j` is a
    /// boundary-particle wall.
    #[serde(skip_serializing_if = "Option::is_none")]
    boundary_particle: Option<usize>,
    t_start: f64,
    t_end: f64,
    duration: f64,
    max_overlap: f64,
    max_normal_force: f64,
    impact_normal_velocity: f64,
    rebound_normal_velocity: f64,
    /// m/s (issue 13).
    impact_tangential_velocity: f64,
    rebound_tangential_velocity: f64,
    /// rad/s.
    impact_spin_i: [f64; 3],
    rebound_spin_i: [f64; 3],
    impact_spin_j: [f64; 3],
    rebound_spin_j: [f64; 3],
    /// The mesh triangle a wall contact was on (mesh walls only).
    #[serde(skip_serializing_if = "Option::is_none")]
    triangle: Option<u32>,
}

impl From<&Collision> for CollisionRow {
    fn from(c: &Collision) -> Self {
        let j = match c.j {
            dembound_scene::Partner::Body(b) => serde_json::Value::from(b),
            ref wall => serde_json::Value::from(partner_name(wall)),
        };
        Self {
            i: c.i,
            j,
            boundary_particle: boundary_particle(&c.j),
            t_start: c.t_start,
            t_end: c.t_end,
            duration: c.duration,
            max_overlap: c.max_overlap,
            max_normal_force: c.max_normal_force,
            impact_normal_velocity: c.impact_normal_velocity,
            rebound_normal_velocity: c.rebound_normal_velocity,
            impact_tangential_velocity: c.impact_tangential_velocity,
            rebound_tangential_velocity: c.rebound_tangential_velocity,
            impact_spin_i: c.impact_spin_i,
            rebound_spin_i: c.rebound_spin_i,
            impact_spin_j: c.impact_spin_j,
            rebound_spin_j: c.rebound_spin_j,
            triangle: c.triangle,
        }
    }
}

/// The energy balance line of the summaries (J).
pub(super) fn balance_line(b: &EnergyBalance) -> String {
    if let Some(why) = b.unchecked {
        return format!("energy balance: not checked ({why}); the finite-state check applies\n");
    }
    // The terms the scene's total holds beyond K + E + P + D (the JSON's
    // `energy_balance`): the walls' work, what removed spheres carried
    // out, the gates' energy, what inlets brought in.
    let terms = [
        (b.work_by_walls.is_some(), " − work by walls"),
        (b.carried_out_energy.is_some(), " + carried out"),
        (b.gate_energy.is_some(), " + gate energy"),
        (b.brought_in_energy.is_some(), " − brought in"),
    ];
    let carried: String = terms
        .iter()
        .filter(|(present, _)| *present)
        .map(|(_, term)| *term)
        .collect();
    let line = format!(
        "energy balance: kinetic + elastic + potential + dissipated{carried} = {} J (at t = 0: {} J); \
         largest gain {} J = {} of the scale {} J (allowed {})\n",
        sig(b.total, 9),
        sig(b.total_initial, 9),
        sig(b.drift, 3),
        sig(b.drift_relative, 3),
        sig(b.scale, 4),
        sig(b.drift_allowed, 2)
    );
    // With `output.dissipation`: D summed contact by contact and the error.
    match (b.dissipated_by_contacts, b.balance_error) {
        (Some(dc), Some(error)) => format!(
            "{line}energy balance by contacts: dissipated by contacts {} J, balance error {} J \
             (largest {} of the scale, allowed {})\n",
            sig(dc, 9),
            sig(error, 3),
            sig(b.balance_error_relative.unwrap_or(0.0), 3),
            sig(b.balance_error_allowed.unwrap_or(0.0), 2)
        ),
        _ => line,
    }
}

fn vector(v: [f64; 3], unit: &str) -> String {
    format!(
        "[{}, {}, {}] {unit}",
        sig(v[0], 4),
        sig(v[1], 4),
        sig(v[2], 4)
    )
}

/// The text summary, units on every number.
fn summary(r: &Report, resolved: &ResolvedScene) -> String {
    let mut s = String::new();
    let scheme = format!("{:?}", resolved.file.integration.scheme).to_lowercase();
    let inserted: u64 = r.inlets.iter().map(|i| i.inserted).sum();
    s += &if r.inlets.is_empty() {
        format!(
            "{} spheres ({} free, {} fixed), {} walls; {scheme}, Δt = {} s",
            r.particles,
            r.free_particles,
            r.fixed_particles,
            resolved.setup.walls.len(),
            sig(r.dt, 4)
        )
    } else {
        format!(
            "{} spheres ({} free at the start, {} fixed, {inserted} inserted by inlets), {} walls; \
             {scheme}, Δt = {} s",
            r.particles,
            r.free_particles,
            r.fixed_particles,
            resolved.setup.walls.len(),
            sig(r.dt, 4)
        )
    };
    if let (Some(tc), Some(v)) = (r.contact_time_estimate, r.impact_speed) {
        s += &format!(
            " (η × the smallest contact-time estimate {} s at {} m/s)",
            sig(tc, 4),
            sig(v, 3)
        );
    }
    if let Some(tr) = r.rayleigh_time {
        s += &format!("; Rayleigh time {} s", sig(tr, 4));
    }
    s += "\n";
    s += &format!(
        "ran {} steps to t = {} s in {} of stepping ({} particle-steps/s on {} thread{}); \
         whole process {}\n",
        r.steps_this_run,
        sig(r.time, 6),
        duration(r.wall_clock),
        sig(r.particle_steps_per_second, 3),
        r.threads,
        if r.threads == 1 { "" } else { "s" },
        duration(r.wall_clock_total)
    );
    s += &format!(
        "energy: kinetic {} J, elastic {} J, potential {} J, dissipated {} J\n",
        sig(r.kinetic_energy, 6),
        sig(r.elastic_energy, 6),
        sig(r.potential_energy, 6),
        sig(r.dissipated_energy, 3)
    );
    s += &balance_line(&r.energy_balance);
    if let (Some(n), Some(m)) = (r.deleted_particles, r.deleted_mass) {
        s += &format!(
            "deleted: {n} spheres (lost outside the box or through outlets), {} kg, carrying out {} J\n",
            sig(m, 6),
            sig(r.energy_balance.carried_out_energy.unwrap_or(0.0), 6)
        );
    }
    for (k, o) in r.outlets.iter().enumerate() {
        s += &format!(
            "outlet {k}: {} spheres removed, {} kg",
            o.count,
            sig(o.mass, 6)
        );
        if let (Some(q), Some(e)) = (o.steady_rate, o.steady_rate_error) {
            s += &format!(
                ", steady rate {} ± {} kg/s (second half)",
                sig(q, 4),
                sig(e, 2)
            );
        }
        s += "\n";
    }
    for (k, i) in r.inlets.iter().enumerate() {
        s += &format!(
            "inlet {k}: {} spheres inserted, {} kg, {} due but not placed (no free room in the region)\n",
            i.inserted,
            sig(i.mass, 6),
            i.not_placed
        );
    }
    s += &format!(
        "contacts now: {} particle–particle, {} particle–wall\n",
        r.particle_contacts, r.wall_contacts
    );
    for (k, ((f, t), wall)) in r
        .wall_forces
        .iter()
        .zip(&r.wall_torques)
        .zip(&resolved.setup.walls)
        .enumerate()
    {
        let kind = wall.summary();
        let about = r.wall_torque_points.get(k).copied().unwrap_or_default();
        s += &format!(
            "wall {k} ({kind}): force {}, torque {} about {}\n",
            vector(*f, "N"),
            vector(*t, "N m"),
            vector(about, "m")
        );
    }
    for m in &r.wall_motions {
        s += &format!(
            "wall {} moved: position {}, angle {} rad, velocity {}\n",
            m.wall,
            vector(m.position, "m"),
            sig(m.angle, 6),
            vector(m.velocity, "m/s")
        );
    }
    for g in &r.group_motions {
        s += &format!(
            "particles {} moved: position {}, angle {} rad; force {}, torque {} about {}\n",
            g.group,
            vector(g.position, "m"),
            sig(g.angle, 6),
            vector(g.force, "N"),
            vector(g.torque, "N m"),
            vector(g.torque_point, "m")
        );
    }
    if let Some(summary) = &r.collision_summary {
        s += &summary_line(summary);
        s += "\n";
    }
    if let Some(rows) = &r.collisions {
        if let Some(c) = rows.first() {
            s += &format!(
                "the first collision: {}–{} from {} s for {} s, max overlap {} m, max force {} N, \
                 impact {} m/s, rebound {} m/s\n",
                c.i,
                c.j,
                sig(c.t_start, 6),
                sig(c.duration, 6),
                sig(c.max_overlap, 6),
                sig(c.max_normal_force, 6),
                sig(c.impact_normal_velocity, 6),
                sig(c.rebound_normal_velocity, 6)
            );
        }
    }
    s
}
