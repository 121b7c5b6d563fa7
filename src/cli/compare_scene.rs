//! `dembound compare DECK` on a scene deck (`dembound export lammps|liggghts
//! SCENE.toml`, run there): the peer's `particles.dump` (and LAMMPS's
//! `walls.txt`) beside dembound's run of the deck's `scene.toml`, row by
//! row, quantity by quantity; when the two are the same state (to 1e-9),
//! when they part and how fast, and whether their late-time means agree
//! (docs/export-lammps.md, "Comparing scenes"; the numerics in
//! `dembound_export::agreement`).
//!
//! Every quantity is computed from the dumped state by the same code for
//! both runs, so the comparison is of states, not of two codes' ways of
//! summing them:
//! - kinetic energy Σ ½ m v², rotational Σ ½ (2/5 m R²) ω², potential
//!   −Σ m g·x (free spheres, J; m = ρ 4/3 π R³; g without its components
//!   along periodic axes, where a position is defined only up to the box);
//! - contacts: pairs of spheres (not both fixed) with |x_i − x_j| < R_i + R_j
//!   (nearest image across periodic faces), and free spheres closer than R
//!   to a plane wall (other wall types are not counted), from the
//!   positions: the same rule for both runs;
//! - bed height: the mean of h + R over the highest tenth of the free
//!   spheres (at least one), h the height along −g without its periodic
//!   components (along z without gravity), m;
//! - each wall's force |F| (N), from walls.txt and the engine at the
//!   row's step; when the deck wrote walls_mean.txt (LAMMPS's and
//!   LIGGGHTS's `fix ave/time 1 N N`, Yade's runner every step), |mean F|
//!   over every step since the previous row from that file and from
//!   dembound's own per-step sum
//!   (`Simulation::step_wall_force_mean`), the same steps on both sides;
//! - the state: max over free spheres of |Δx| / R_min (R_min the smallest
//!   free radius; Δx by the nearest image, as a sphere at a periodic face
//!   is wrapped by one code and not yet by the other), only for the
//!   divergence.
//!
//! The relative difference of a quantity at a row is |a − b| over the
//! largest |a|, |b| of the whole run (so a quantity passing through 0 is not
//! divided by 0).
//!
//! With inlets or outlets the rows vary in size: each is read by sphere id
//! (compare_rows.rs), every quantity above is over the spheres there then,
//! the state is compared by id while both rows hold the same spheres and
//! the inserted ones stand at the same places ([`StateEnd`] says where and
//! why that ends), and the running counts and the discharge rate are added
//! (compare_flow.rs).

use super::compare::CompareArgs;
use super::compare_flow::{self, Flow};
use super::compare_profiles::{ProfileReport, Profiles, PACKING_BAR};
use super::compare_rows::{ids_text, set_difference, RowReader, SceneSpheres, Spheres};
use super::compare_sample::{dot, Geometry, Sample};
use super::compare_scene_report::{text_report, write_figures};
use super::{CliError, CliResult};
use crate::output::format::sig;
use anyhow::anyhow;
use dembound_export::agreement::{self, Divergence, Verdict, WindowMean};
use dembound_export::scene_dump::{self, DumpRow};
use dembound_scene::io::{config, resolve::resolve};
use dembound_scene::setup::SceneSetup;
use dembound_scene::Simulation;
use serde::Serialize;
use std::io::Write;
use std::path::{Path, PathBuf};

/// Whether `dir` holds a scene deck (its `scene.toml`, no bounce
/// `scenario.toml`).
pub fn is_scene_deck(dir: &Path) -> bool {
    dir.join("scene.toml").is_file() && !dir.join("scenario.toml").is_file()
}

/// One compared quantity over the run.
#[derive(Debug, Serialize)]
pub struct QuantityReport {
    pub name: String,
    pub unit: String,
    pub time: Vec<f64>,
    pub code: Vec<f64>,
    pub dembound: Vec<f64>,
    /// |code − dembound| / the largest |value| of the run.
    pub relative_difference: Vec<f64>,
    pub divergence: Divergence,
    /// Means over the late window (None for the state row or a short run).
    pub code_window: Option<WindowMean>,
    pub dembound_window: Option<WindowMean>,
    /// code/dembound − 1 of the window means.
    pub window_relative_difference: Option<f64>,
    pub verdict: Option<Verdict>,
    /// A running count (inserted, discharged): compared for equality at
    /// every row (its `divergence` from the first row, without a growth
    /// rate), no window means.
    pub running_count: bool,
}

/// Speed of a run: free-sphere steps per core-second, from the CPU time
/// where the run reports it (a per-core cost even on a loaded machine), else
/// from the wall clock × cores (`clock` says which: LIGGGHTS's log has only
/// its wall-clock "Loop time"; LAMMPS's adds "% CPU use"; Yade's timing
/// line is CPU time; dembound measures both).
#[derive(Debug, Serialize)]
pub struct Speed {
    /// Wall-clock seconds of the stepping, when known.
    pub wall_seconds: Option<f64>,
    /// CPU seconds of the stepping (all cores), when known.
    pub cpu_seconds: Option<f64>,
    pub cores: u64,
    /// "CPU" or "wall": what `particle_steps_per_core_second` divides by.
    pub clock: &'static str,
    pub particle_steps_per_core_second: f64,
}

impl Speed {
    /// `particle_steps` free-sphere steps in `wall` s (on `cores` cores)
    /// and/or `cpu` s.
    fn new(particle_steps: f64, wall: Option<f64>, cpu: Option<f64>, cores: u64) -> Option<Self> {
        let (clock, core_seconds) = match (cpu, wall) {
            (Some(c), _) if c > 0.0 => ("CPU", c),
            (_, Some(w)) if w > 0.0 => ("wall", w * cores.max(1) as f64),
            _ => return None,
        };
        Some(Speed {
            wall_seconds: wall,
            cpu_seconds: cpu,
            cores,
            clock,
            particle_steps_per_core_second: particle_steps / core_seconds,
        })
    }
}

/// CPU seconds this process has used so far (all its threads; user +
/// system), or None where the platform does not say.
fn process_cpu_seconds() -> Option<f64> {
    #[cfg(unix)]
    {
        // SAFETY: getrusage fills the struct it is given; a zeroed rusage
        // is a valid value of that plain C struct.
        let mut usage: libc::rusage = unsafe { std::mem::zeroed() };
        if unsafe { libc::getrusage(libc::RUSAGE_SELF, &mut usage) } != 0 {
            return None;
        }
        let seconds = |t: libc::timeval| t.tv_sec as f64 + t.tv_usec as f64 * 1e-6;
        Some(seconds(usage.ru_utime) + seconds(usage.ru_stime))
    }
    #[cfg(not(unix))]
    {
        None
    }
}

#[derive(Debug, Serialize)]
pub struct SceneCompareReport {
    pub code: String,
    pub deck: PathBuf,
    pub spheres: usize,
    pub free_spheres: usize,
    pub dt: f64,
    pub rows: usize,
    /// The late window: rows from this time (s) on.
    pub window_from: f64,
    pub identical_threshold: f64,
    /// Where the comparison by id stopped before the run's end, and why
    /// (None: every row held the same spheres in both runs, at the same
    /// places up to the divergence).
    pub state_end: Option<StateEnd>,
    pub quantities: Vec<QuantityReport>,
    /// From the peer's log ("Loop time"), when found.
    pub code_speed: Option<Speed>,
    pub dembound_speed: Option<Speed>,
    /// Packing fraction and flow velocity against z over the late window
    /// (compare_profiles.rs).
    pub profiles: Vec<ProfileReport>,
    /// What the `wall[k] force |F|` rows hold (None: no wall compared).
    pub wall_forces: Option<WallForces>,
    /// What could not be compared, and why.
    pub notes: Vec<String>,
}

/// What a row's wall force is, on both sides alike.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum WallForces {
    /// |F| at the row's step (walls.txt, `fix ave/time N 1 N`).
    AtRowStep,
    /// |mean F| over every step since the previous row (walls_mean.txt,
    /// `fix ave/time 1 N N`; `Simulation::step_wall_force_mean`).
    MeanOverRowInterval,
}

/// The end of the state-by-state comparison, before the run's end.
#[derive(Debug, Serialize)]
pub struct StateEnd {
    /// The last row (s) compared (None: not even the first).
    pub compared_until: Option<f64>,
    /// The first row (s) not compared.
    pub at: f64,
    pub reason: String,
}

/// The profiles' bin width (m): the mean free-sphere diameter of the
/// scene file, or, with no free sphere before the inlets insert, the
/// middle of the first inlet's radius range, doubled.
fn profile_bin_width(setup: &SceneSetup) -> f64 {
    let free: Vec<f64> = setup
        .spheres
        .iter()
        .filter(|s| !s.fixed)
        .map(|s| s.radius)
        .collect();
    match setup.inlets.first() {
        Some(inlet) if free.is_empty() => {
            let (lo, hi) = inlet.size.radius_range();
            lo + hi
        }
        _ => 2.0 * free.iter().sum::<f64>() / free.len().max(1) as f64,
    }
}

fn input(e: impl std::fmt::Display) -> CliError {
    CliError::input(anyhow!("{e}"))
}

/// The peer code of a deck directory, and its log's name.
fn peer(dir: &Path) -> CliResult<(&'static str, &'static str)> {
    if dir.join("in.lammps").is_file() {
        Ok(("LAMMPS", "log.lammps"))
    } else if dir.join("in.liggghts").is_file() {
        Ok(("LIGGGHTS", "log.liggghts"))
    } else if dir.join(dembound_export::yade_scene::SCRIPT).is_file() {
        Ok(("Yade", dembound_export::yade_scene::LOG))
    } else {
        Err(input(format!(
            "`{}` holds scene.toml but none of in.lammps, in.liggghts, scene.py: not a scene \
             deck of `dembound export lammps|liggghts|yade`",
            dir.display()
        )))
    }
}

pub fn run(args: &CompareArgs, dir: &Path) -> CliResult {
    let (code, log_name) = peer(dir)?;
    let scene_path = dir.join("scene.toml");
    let file = config::read(&scene_path, &[]).map_err(input)?;
    let setup = resolve(&file, dir).map_err(input)?.setup;
    let dump_path = dir.join(dembound_export::lammps_output::DUMP_FILE);
    let text = std::fs::read_to_string(&dump_path).map_err(|e| {
        input(format!(
            "cannot read `{}`: {e} (run the {code} deck first: cd {} && {})",
            dump_path.display(),
            dir.display(),
            match code {
                "LAMMPS" => "lmp -in in.lammps -log log.lammps",
                "Yade" => dembound_export::yade_scene::COMMAND,
                _ => "liggghts -in in.liggghts -log log.liggghts",
            }
        ))
    })?;
    let rows = scene_dump::parse_dump(&text)
        .map_err(|e| input(format!("`{}` of the {code} deck: {e}", dump_path.display())))?;
    let read_walls = |name: &str| match std::fs::read_to_string(dir.join(name)) {
        Ok(t) => scene_dump::parse_walls(&t)
            .map(Some)
            .map_err(|e| input(format!("`{name}` of the {code} deck: {e}"))),
        Err(_) => Ok(None),
    };
    // Both sides' means over every step of each row interval when the
    // deck wrote them, else the force at the row's step.
    let walls_mean = read_walls(dembound_export::lammps_output::WALLS_MEAN_FILE)?;
    let averaged = walls_mean.is_some();
    let walls = match walls_mean {
        Some(w) => Some(w),
        None => read_walls(dembound_export::lammps_output::WALLS_FILE)?,
    };
    let scene = SceneSpheres::new(&setup);
    let n = scene.count();
    // Every row read by id before the run: a dump of another scene stops
    // here.
    let mut reader = RowReader::new(&scene);
    let peer_rows: Vec<Spheres> = rows
        .iter()
        .map(|r| {
            reader.read(r).map_err(|e| {
                input(format!(
                    "`{}` {e}: the dump is not this deck's run ({code}; export and run again)",
                    dump_path.display()
                ))
            })
        })
        .collect::<CliResult<_>>()?;
    let log = std::fs::read_to_string(dir.join(log_name)).ok();
    let flows = !setup.inlets.is_empty() || !setup.outlets.is_empty();
    let thermo = log
        .as_deref()
        .map(scene_dump::thermo_rows)
        .unwrap_or_default();
    let geometry = Geometry::new(&setup);
    let threads = 1;
    let mut sim = Simulation::new(setup.clone(), threads).map_err(input)?;
    let dt = sim.dt();
    let total = sim.total_steps();
    if let Some(from) = args.window_from {
        let end = total as f64 * dt;
        if !(from >= 0.0 && from < end) {
            return Err(input(format!(
                "--window-from = {from} s is outside the run: give a time in [0, {end}) s \
                 (the scene runs {total} steps of {dt} s)"
            )));
        }
    }
    let mut time = Vec::new();
    let mut ours: Vec<Sample> = Vec::new();
    let mut theirs: Vec<Sample> = Vec::new();
    let mut state_diff = Vec::new();
    // The rows compared by id: until the sets part or inserted spheres
    // stand in different places (then `state_end` says why).
    let mut state_end: Option<StateEnd> = None;
    let (mut free_ours, mut free_theirs) = (Vec::new(), Vec::new());
    let (mut flow_code, mut flow_dem) = (Vec::new(), Vec::new());
    let wall_count = setup.walls.len();
    // A row of forces for every dump row; LIGGGHTS's `fix print` starts at
    // the first multiple of the cadence, so the row of step 0 may be missing
    // (the wall series then starts at the next row).
    let has_forces = |r: &DumpRow| {
        walls
            .as_ref()
            .and_then(|w| w.get(&r.step))
            .is_some_and(|f| f.len() >= 3 * wall_count)
    };
    let with_walls = wall_count > 0
        && rows.iter().any(|r| r.step > 0 && has_forces(r))
        && rows.iter().all(|r| r.step == 0 || has_forces(r));
    let mut wall_rows: Vec<bool> = Vec::new();
    let profiles = Profiles::new(&setup, profile_bin_width(&setup));
    let (mut packing_ours, mut packing_theirs) = (Vec::new(), Vec::new());
    let (mut flow_ours, mut flow_theirs) = (Vec::new(), Vec::new());
    let mut stepping = 0.0;
    let cpu_before = process_cpu_seconds();
    for (row, peer_row) in rows.iter().zip(peer_rows) {
        if row.step < sim.steps_done() {
            continue;
        }
        if row.step > total {
            return Err(input(format!(
                "`{}` has step {} beyond the scene's {total} steps: not this deck's run \
                 ({code}; export and run again)",
                dump_path.display(),
                row.step
            )));
        }
        let clock = std::time::Instant::now();
        let steps = row.step - sim.steps_done();
        let mean = if averaged && with_walls {
            sim.step_wall_force_mean(steps)
        } else {
            sim.step(steps);
            None
        };
        stepping += clock.elapsed().as_secs_f64();
        let t = row.step as f64 * dt;
        let mut x = sim.positions();
        // Both sides into the box: LAMMPS and dembound wrap a sphere only at
        // a list rebuild, Yade never, so a row may hold one outside it.
        wrap_periodic(&setup, &mut x);
        let mine = scene.read_simulation(&sim, x);
        let mut theirs_row = peer_row;
        wrap_periodic(&setup, &mut theirs_row.position);
        let wf = match (with_walls, averaged, mean) {
            (false, _, _) => Vec::new(),
            (true, false, _) => sim
                .wall_forces()
                .iter()
                .map(|f| dot(*f, *f).sqrt())
                .collect(),
            (true, true, Some(m)) => m.iter().map(|f| dot(*f, *f).sqrt()).collect(),
            // The row of step 0: no interval, no mean (nor in the file).
            (true, true, None) => vec![f64::NAN; wall_count],
        };
        ours.push(geometry.sample(&mine, wf));
        packing_ours.push(profiles.packing(&mine));
        packing_theirs.push(profiles.packing(&theirs_row));
        flow_ours.push(profiles.velocity(&mine));
        flow_theirs.push(profiles.velocity(&theirs_row));
        wall_rows.push(with_walls && has_forces(row));
        let cwf = match (&walls, with_walls && has_forces(row)) {
            (Some(wl), true) => {
                let f = &wl[&row.step];
                (0..wall_count)
                    .map(|k| {
                        dot(
                            [f[3 * k], f[3 * k + 1], f[3 * k + 2]],
                            [f[3 * k], f[3 * k + 1], f[3 * k + 2]],
                        )
                        .sqrt()
                    })
                    .collect()
            }
            _ if with_walls => vec![f64::NAN; wall_count],
            _ => Vec::new(),
        };
        theirs.push(geometry.sample(&theirs_row, cwf));
        free_ours.push(mine.free() as f64);
        free_theirs.push(theirs_row.free() as f64);
        if flows {
            flow_dem.push(compare_flow::dembound_flow(&sim.observe()));
            flow_code.push(compare_flow::peer_flow(
                &thermo,
                row.step,
                setup.inlets.len(),
                setup.outlets.len(),
            ));
        }
        if state_end.is_none() {
            let (only_code, only_dem) = set_difference(&theirs_row, &mine);
            if !only_code.is_empty() || !only_dem.is_empty() {
                state_end = Some(StateEnd {
                    compared_until: time.last().copied(),
                    at: t,
                    reason: format!(
                        "the runs hold different spheres (ids only in {code}: {}; only in \
                         dembound: {}): an outlet removes a sphere at another step in each code \
                         (the deck every 100 steps, dembound at a neighbour-list rebuild once it \
                         touches nothing), an inlet that could not place one, or chaos moving a \
                         sphere into an outlet earlier in one run",
                        if only_code.is_empty() {
                            "none".into()
                        } else {
                            ids_text(&only_code)
                        },
                        if only_dem.is_empty() {
                            "none".into()
                        } else {
                            ids_text(&only_dem)
                        },
                    ),
                });
            } else {
                // Spheres an inlet placed (none before the first insertion).
                let inserted = geometry.state_difference(&theirs_row, &mine, n);
                if inserted > agreement::IDENTICAL {
                    // The LAMMPS deck creates dembound's own placements
                    // (lammps_inlets.rs); LIGGGHTS draws its own.
                    let reason = if code == "LAMMPS" {
                        format!(
                            "the spheres the inlets placed (ids from {}) stand apart (max |Δx| \
                             / R_min = {} among them): the LAMMPS deck creates them at \
                             dembound's places, so they part as the runs part (collisions \
                             amplifying round-off) or where the deck skipped one (a free sphere \
                             in the way; its log says how many)",
                            n + 1,
                            sig(inserted, 3)
                        )
                    } else {
                        format!(
                            "the spheres the inlets placed (ids from {}) are where each code's \
                             own random draw put them (max |Δx| / R_min = {} among them): the \
                             codes' generators differ, so the states part at the first \
                             insertion; only statistics can agree after it",
                            n + 1,
                            sig(inserted, 3)
                        )
                    };
                    state_end = Some(StateEnd {
                        compared_until: time.last().copied(),
                        at: t,
                        reason,
                    });
                }
            }
        }
        if state_end.is_none() {
            state_diff.push(geometry.state_difference(&theirs_row, &mine, 0));
        }
        time.push(t);
    }
    let compared = state_diff.len();
    let window_start = match args.window_from {
        Some(from) => time.iter().position(|&t| t >= from).unwrap_or(time.len()),
        None => (2 * time.len()) / 3,
    };
    let window_from = time.get(window_start).copied().unwrap_or(0.0);
    let mut quantities = Vec::new();
    quantities.push(QuantityReport {
        name: "state: max |Δx| / R_min".into(),
        unit: "1".into(),
        relative_difference: state_diff.clone(),
        divergence: agreement::divergence(&time[..compared], &state_diff, agreement::IDENTICAL),
        code: vec![0.0; compared],
        dembound: vec![0.0; compared],
        time: time[..compared].to_vec(),
        code_window: None,
        dembound_window: None,
        window_relative_difference: None,
        verdict: None,
        running_count: false,
    });
    type Get = fn(&Sample) -> f64;
    let scalars: [(&str, &str, Get); 5] = [
        ("kinetic energy", "J", |s| s.kinetic),
        ("rotational energy", "J", |s| s.rotational),
        ("potential energy", "J", |s| s.potential),
        ("contacts (overlaps)", "1", |s| s.contacts),
        ("bed height", "m", |s| s.bed_height),
    ];
    let series: Vec<(String, String, Vec<f64>, Vec<f64>)> = scalars
        .iter()
        .map(|(name, unit, get)| {
            (
                name.to_string(),
                unit.to_string(),
                theirs.iter().map(get).collect(),
                ours.iter().map(get).collect(),
            )
        })
        .collect();
    let level = Window {
        start: window_start,
        compared,
        cumulative: false,
        autocorrelated: false,
    };
    for (name, unit, a, b) in series {
        quantities.push(quantity(name, unit, &time, a, b, level));
    }
    if flows {
        quantities.push(quantity(
            "free spheres in the domain".into(),
            "1".into(),
            &time,
            free_theirs.clone(),
            free_ours.clone(),
            Window {
                autocorrelated: true,
                ..level
            },
        ));
    }
    if with_walls {
        // The rows where the peer wrote forces (all, or all but step 0).
        let keep: Vec<usize> = (0..time.len()).filter(|&i| wall_rows[i]).collect();
        let wall_time: Vec<f64> = keep.iter().map(|&i| time[i]).collect();
        let wall_window = Window {
            start: keep.iter().filter(|&&i| i < window_start).count(),
            compared: keep.iter().filter(|&&i| i < compared).count(),
            cumulative: false,
            autocorrelated: false,
        };
        for k in 0..wall_count {
            quantities.push(quantity(
                format!("wall[{k}] force |F|"),
                "N".into(),
                &wall_time,
                keep.iter().map(|&i| theirs[i].walls[k]).collect(),
                keep.iter().map(|&i| ours[i].walls[k]).collect(),
                wall_window,
            ));
        }
    }
    let mut notes = Vec::new();
    let wall_forces = if !with_walls {
        None
    } else if averaged {
        Some(WallForces::MeanOverRowInterval)
    } else {
        Some(WallForces::AtRowStep)
    };
    if with_walls {
        notes.push(if averaged {
            format!(
                "wall forces: |mean F| over every step since the previous row, both codes ({} \
                 and dembound's per-step sum)",
                dembound_export::lammps_output::WALLS_MEAN_FILE
            )
        } else {
            format!(
                "wall forces: |F| at the row's step only, both codes ({}; one step sampled per \
                 row: a deck exported now also writes {}, averaged over every step)",
                dembound_export::lammps_output::WALLS_FILE,
                dembound_export::lammps_output::WALLS_MEAN_FILE
            )
        });
    }
    if flows {
        flow_quantities(
            code,
            &time,
            &flow_code,
            &flow_dem,
            (&setup, level),
            &mut quantities,
            &mut notes,
        );
    }
    let w = window_start.min(time.len());
    let mut profile_reports = vec![profiles.report(
        "packing fraction",
        "1",
        &packing_theirs[w..],
        &packing_ours[w..],
        Some(PACKING_BAR),
    )];
    if profiles.flow.is_some() {
        profile_reports.push(profiles.report(
            "flow velocity",
            "m/s",
            &flow_theirs[w..],
            &flow_ours[w..],
            None,
        ));
    }
    let cpu_stepping = match (cpu_before, process_cpu_seconds()) {
        (Some(a), Some(b)) => Some(b - a),
        _ => None,
    };
    // Free-sphere steps: the mean free count of the rows times the steps
    // (the count varies with inlets and outlets).
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len().max(1) as f64;
    let free = scene.free();
    let code_speed = log.as_deref().and_then(|log| {
        let (seconds, procs, steps) = scene_dump::total_loop_time(log)?;
        let particle_steps = if flows {
            mean(&free_theirs) * steps as f64
        } else {
            free as f64 * steps as f64
        };
        match code {
            // The Yade script times itself with time.process_time().
            "Yade" => Speed::new(particle_steps, None, Some(seconds), procs),
            // LAMMPS's "Loop time" is wall clock; its "X% CPU use" line is
            // rank 0's CPU over that time, taken for every rank.
            _ => {
                let cpu = scene_dump::cpu_use_percent(log)
                    .map(|percent| seconds * percent / 100.0 * procs as f64);
                Speed::new(particle_steps, Some(seconds), cpu, procs)
            }
        }
    });
    let dembound_particle_steps = if flows {
        mean(&free_ours) * sim.steps_done() as f64
    } else {
        free as f64 * sim.steps_done() as f64
    };
    let report = SceneCompareReport {
        code: code.into(),
        deck: dir.to_path_buf(),
        spheres: n,
        free_spheres: free,
        dt,
        rows: time.len(),
        window_from,
        identical_threshold: agreement::IDENTICAL,
        state_end,
        quantities,
        code_speed,
        dembound_speed: Speed::new(
            dembound_particle_steps,
            Some(stepping),
            cpu_stepping,
            threads as u64,
        ),
        profiles: profile_reports,
        wall_forces,
        notes,
    };
    if let Some(figures) = &args.figures {
        write_figures(&report, figures).map_err(CliError::failed)?;
    }
    let mut stdout = std::io::stdout().lock();
    if args.json {
        let text = serde_json::to_string_pretty(&report).map_err(CliError::failed)?;
        writeln!(stdout, "{text}").map_err(CliError::failed)?;
    } else {
        write!(stdout, "{}", text_report(&report)).map_err(CliError::failed)?;
    }
    stdout.flush().map_err(CliError::failed)?;
    Ok(())
}

/// Puts positions into the box [lower, upper) on the periodic axes (for
/// both runs: when a code wraps differs from code to code).
fn wrap_periodic(setup: &SceneSetup, x: &mut [[f64; 3]]) {
    let d = &setup.domain;
    for p in x.iter_mut() {
        for k in (0..3).filter(|&k| d.periodic[k]) {
            let length = d.upper[k] - d.lower[k];
            while p[k] >= d.upper[k] {
                p[k] -= length;
            }
            while p[k] < d.lower[k] {
                p[k] += length;
            }
        }
    }
}

/// Which rows of a series each part of the comparison reads.
#[derive(Debug, Clone, Copy)]
struct Window {
    /// The late window's first row.
    start: usize,
    /// The rows compared state by state (the identical-state columns).
    compared: usize,
    /// A running count (inserted, discharged): compared at every row for
    /// equality, without a growth rate or window means.
    cumulative: bool,
    /// The window's standard error from the series' integrated
    /// autocorrelation time (`agreement::window_mean_autocorrelated`), not
    /// from batch means: for the spheres in the domain, whose changes last
    /// a transit time, longer than the batch means' blocks.
    autocorrelated: bool,
}

fn quantity(
    name: String,
    unit: String,
    time: &[f64],
    code: Vec<f64>,
    dembound: Vec<f64>,
    window: Window,
) -> QuantityReport {
    let scale = code
        .iter()
        .chain(&dembound)
        .map(|v| v.abs())
        .fold(0.0, f64::max);
    let relative: Vec<f64> = code
        .iter()
        .zip(&dembound)
        .map(|(a, b)| {
            if scale > 0.0 {
                (a - b).abs() / scale
            } else {
                0.0
            }
        })
        .collect();
    let (cw, dw) = if window.cumulative {
        (None, None)
    } else {
        let start = window.start.min(code.len());
        let mean = if window.autocorrelated {
            agreement::window_mean_autocorrelated
        } else {
            agreement::window_mean
        };
        (mean(&code[start..]), mean(&dembound[start..]))
    };
    let (rel, verdict) = match (&cw, &dw) {
        (Some(c), Some(d)) => (
            (d.mean != 0.0).then(|| c.mean / d.mean - 1.0),
            Some(agreement::verdict(c, d)),
        ),
        _ => (None, None),
    };
    let divergence = if window.cumulative {
        Divergence {
            growth_rate: None,
            fit_rows: 0,
            ..agreement::divergence(time, &relative, agreement::IDENTICAL)
        }
    } else {
        let m = window.compared.min(time.len());
        agreement::divergence(&time[..m], &relative[..m], agreement::IDENTICAL)
    };
    QuantityReport {
        divergence,
        name,
        unit,
        time: time.to_vec(),
        code,
        dembound,
        relative_difference: relative,
        code_window: cw,
        dembound_window: dw,
        window_relative_difference: rel,
        verdict,
        running_count: window.cumulative,
    }
}

/// The running counts and the discharge rate (compare_flow.rs), when the
/// peer's log has every count at every row (else a note).
fn flow_quantities(
    code: &str,
    time: &[f64],
    peer: &[Option<Flow>],
    dembound: &[Flow],
    (setup, window): (&SceneSetup, Window),
    quantities: &mut Vec<QuantityReport>,
    notes: &mut Vec<String>,
) {
    let Some(peer) = peer.iter().copied().collect::<Option<Vec<Flow>>>() else {
        notes.push(format!(
            "no inserted or discharged counts: the {code} log (its thermo columns insK[1], \
             insK[2], outK_n, outK_m) is missing or lacks a row at or before a dump row; run \
             the deck with -log as the export says"
        ));
        return;
    };
    type Get = fn(&Flow) -> f64;
    let mut counts: Vec<(&str, &str, Get)> = Vec::new();
    if !setup.inlets.is_empty() {
        counts.push(("spheres inserted", "1", |f| f.inserted));
        counts.push(("mass inserted", "kg", |f| f.inserted_mass));
    }
    if !setup.outlets.is_empty() {
        counts.push(("spheres discharged", "1", |f| f.discharged));
        counts.push(("mass discharged", "kg", |f| f.discharged_mass));
    }
    let running = Window {
        cumulative: true,
        ..window
    };
    for (name, unit, get) in counts {
        quantities.push(quantity(
            name.into(),
            unit.into(),
            time,
            peer.iter().map(get).collect(),
            dembound.iter().map(get).collect(),
            running,
        ));
    }
    if setup.outlets.is_empty() {
        return;
    }
    let mass = |f: &[Flow]| f.iter().map(|f| f.discharged_mass).collect::<Vec<f64>>();
    let (rate_time, code_rate) = compare_flow::rate(time, &mass(&peer));
    let (_, dem_rate) = compare_flow::rate(time, &mass(dembound));
    // The rate at row k is over (t_{k−1}, t_k]: the window's rates are
    // those of the intervals after its first row.
    let from = time.get(window.start).copied().unwrap_or(f64::INFINITY);
    quantities.push(quantity(
        "discharge rate".into(),
        "kg/s".into(),
        &rate_time,
        code_rate,
        dem_rate,
        Window {
            start: rate_time
                .iter()
                .position(|&t| t > from)
                .unwrap_or(rate_time.len()),
            compared: 0,
            cumulative: false,
            autocorrelated: false,
        },
    ));
}
