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
//! - each wall's force |F| (N), from walls.txt and the engine;
//! - the state: max over free spheres of |Δx| / R_min (R_min the smallest
//!   free radius; Δx by the nearest image, as a sphere at a periodic face
//!   is wrapped by one code and not yet by the other), only for the
//!   divergence.
//!
//! The relative difference of a quantity at a row is |a − b| over the
//! largest |a|, |b| of the whole run (so a quantity passing through 0 is not
//! divided by 0).

use super::compare::CompareArgs;
use super::compare_flow::{self, Flow};
use super::compare_profiles::{ProfileReport, Profiles, PACKING_BAR};
use super::compare_rows::{ids_text, set_difference, SceneSpheres, Spheres};
use super::{CliError, CliResult};
use crate::output::format::sig;
use crate::output::table::{Cell, Column, Table};
use crate::plot::{Figure, Mark, Series};
use anyhow::anyhow;
use dembound_export::agreement::{self, Divergence, Verdict, WindowMean};
use dembound_export::scene_dump::{self, DumpRow};
use dembound_scene::io::{config, resolve::resolve};
use dembound_scene::setup::{SceneSetup, WallSetup};
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
    /// What could not be compared, and why.
    pub notes: Vec<String>,
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

/// What one row's state gives.
#[derive(Debug, Clone, Default)]
struct Sample {
    kinetic: f64,
    rotational: f64,
    potential: f64,
    contacts: f64,
    bed_height: f64,
    walls: Vec<f64>,
}

/// The fixed geometry: what every sample needs of the scene.
struct Geometry {
    gravity: [f64; 3],
    /// Unit vector "up" (−g, or z).
    up: [f64; 3],
    /// Plane walls: (point, unit normal into the domain).
    planes: Vec<([f64; 3], [f64; 3])>,
    /// The box length along each periodic axis (None: not periodic).
    period: [Option<f64>; 3],
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

impl Geometry {
    fn new(setup: &SceneSetup) -> Self {
        let d = &setup.domain;
        let period: [Option<f64>; 3] =
            std::array::from_fn(|k| d.periodic[k].then(|| d.upper[k] - d.lower[k]));
        // Along a periodic axis a position is known only up to the box
        // length, so gravity there has no potential (a chute's flow gains
        // energy without end) and heights are taken along the rest of −g.
        let g: [f64; 3] = std::array::from_fn(|k| {
            if period[k].is_some() {
                0.0
            } else {
                setup.gravity[k]
            }
        });
        let gn = dot(g, g).sqrt();
        let up = if gn > 0.0 {
            [-g[0] / gn, -g[1] / gn, -g[2] / gn]
        } else {
            [0.0, 0.0, 1.0]
        };
        let planes = setup
            .walls
            .iter()
            .filter_map(|w| match w {
                WallSetup::Plane(p) => {
                    let l = dot(p.normal, p.normal).sqrt();
                    Some((p.point, p.normal.map(|c| c / l)))
                }
                _ => None,
            })
            .collect();
        Geometry {
            gravity: g,
            up,
            planes,
            period,
        }
    }

    /// b − a, by the nearest image on the periodic axes.
    fn separation(&self, a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
        std::array::from_fn(|k| {
            let d = b[k] - a[k];
            match self.period[k] {
                Some(l) => d - l * (d / l).round(),
                None => d,
            }
        })
    }

    fn sample(&self, s: &Spheres, walls: Vec<f64>) -> Sample {
        let mut out = Sample {
            walls,
            ..Sample::default()
        };
        let mut heights = Vec::new();
        for i in (0..s.len()).filter(|&i| !s.fixed[i]) {
            let (m, r) = (s.mass[i], s.radius[i]);
            out.kinetic += 0.5 * m * dot(s.velocity[i], s.velocity[i]);
            out.rotational += 0.5 * 0.4 * m * r * r * dot(s.spin[i], s.spin[i]);
            out.potential -= m * dot(self.gravity, s.position[i]);
            heights.push(dot(self.up, s.position[i]) + r);
            out.contacts += self
                .planes
                .iter()
                .filter(|(p, n)| {
                    let x = s.position[i];
                    dot(*n, [x[0] - p[0], x[1] - p[1], x[2] - p[2]]) < r
                })
                .count() as f64;
        }
        heights.sort_by(|a, b| b.total_cmp(a));
        let top = heights.len().div_ceil(10).max(1).min(heights.len());
        if top > 0 {
            out.bed_height = heights[..top].iter().sum::<f64>() / top as f64;
        }
        out.contacts += self.sphere_pairs(s) as f64;
        out
    }

    /// Overlapping sphere pairs, not both fixed, across periodic faces too
    /// (nearest image; sweep along the first non-periodic axis, every pair
    /// when all three are periodic).
    fn sphere_pairs(&self, s: &Spheres) -> usize {
        let x = &s.position;
        let axis = (0..3).find(|&k| self.period[k].is_none());
        let mut order: Vec<usize> = (0..x.len()).collect();
        if let Some(a) = axis {
            order.sort_by(|&p, &q| x[p][a].total_cmp(&x[q][a]));
        }
        let rmax = s.radius.iter().cloned().fold(0.0, f64::max);
        let mut count = 0;
        for (k, &i) in order.iter().enumerate() {
            for &j in &order[k + 1..] {
                if axis.is_some_and(|a| x[j][a] - x[i][a] > s.radius[i] + rmax) {
                    break;
                }
                if s.fixed[i] && s.fixed[j] {
                    continue;
                }
                let d = self.separation(x[i], x[j]);
                let reach = s.radius[i] + s.radius[j];
                if dot(d, d) < reach * reach {
                    count += 1;
                }
            }
        }
        count
    }

    /// The largest |Δx| / R_min over the free spheres both rows hold (by
    /// index; R_min the smallest of their radii; Δx by the nearest image),
    /// over those of index ≥ `from` only.
    fn state_difference(&self, a: &Spheres, b: &Spheres, from: usize) -> f64 {
        let mut r_min = f64::INFINITY;
        let mut worst: f64 = 0.0;
        let (mut i, mut j) = (0, 0);
        while i < a.len() && j < b.len() {
            match a.index[i].cmp(&b.index[j]) {
                std::cmp::Ordering::Less => i += 1,
                std::cmp::Ordering::Greater => j += 1,
                std::cmp::Ordering::Equal => {
                    if !a.fixed[i] && a.index[i] >= from {
                        let d = self.separation(a.position[i], b.position[j]);
                        worst = worst.max(dot(d, d).sqrt());
                        r_min = r_min.min(a.radius[i]);
                    }
                    i += 1;
                    j += 1;
                }
            }
        }
        if worst > 0.0 {
            worst / r_min
        } else {
            0.0
        }
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
            "cannot read `{}`: {e} (run the deck first: cd {} && {})",
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
        .map_err(|e| input(format!("`{}`: {e}", dump_path.display())))?;
    let walls = match std::fs::read_to_string(dir.join(dembound_export::lammps_output::WALLS_FILE))
    {
        Ok(t) => Some(scene_dump::parse_walls(&t).map_err(input)?),
        Err(_) => None,
    };
    let scene = SceneSpheres::new(&setup);
    let n = scene.count();
    // Every row read by id before the run: a dump of another scene stops
    // here.
    let peer_rows: Vec<Spheres> = rows
        .iter()
        .map(|r| {
            scene.from_dump(r).map_err(|e| {
                input(format!(
                    "`{}` {e}: the dump is not this deck's run (export and run again)",
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
                "`{}` has step {} beyond the scene's {total} steps: not this deck's run",
                dump_path.display(),
                row.step
            )));
        }
        let clock = std::time::Instant::now();
        sim.step(row.step - sim.steps_done());
        stepping += clock.elapsed().as_secs_f64();
        let t = row.step as f64 * dt;
        let mut x = sim.positions();
        // Both sides into the box: LAMMPS and dembound wrap a sphere only at
        // a list rebuild, Yade never, so a row may hold one outside it.
        wrap_periodic(&setup, &mut x);
        let mine = scene.from_simulation(&sim, x);
        let mut theirs_row = peer_row;
        wrap_periodic(&setup, &mut theirs_row.position);
        let wf = if with_walls {
            sim.wall_forces()
                .iter()
                .map(|f| dot(*f, *f).sqrt())
                .collect()
        } else {
            Vec::new()
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
                    state_end = Some(StateEnd {
                        compared_until: time.last().copied(),
                        at: t,
                        reason: format!(
                            "the spheres the inlets placed (ids from {}) are where each code's \
                             own random draw put them (max |Δx| / R_min = {} among them): the \
                             codes' generators differ, so the states part at the first \
                             insertion; only statistics can agree after it",
                            n + 1,
                            sig(inserted, 3)
                        ),
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
            level,
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
        (
            agreement::window_mean(&code[start..]),
            agreement::window_mean(&dembound[start..]),
        )
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
        },
    ));
}

fn opt_s(t: Option<f64>) -> String {
    t.map_or("—".into(), |t| format!("{} s", sig(t, 4)))
}

fn text_report(r: &SceneCompareReport) -> String {
    let mut out = format!(
        "{} (deck {}, {} spheres, {} free) against dembound's run of scene.toml, {} rows, Δt = {} s\n\
         Relative difference: |{} − dembound| / the largest |value| of the run. Identical: ≤ {:e}.\n\
         Growth rate λ: fit of ln|Δ| against t from the divergence to the first row ≥ {:e}\n\
         (chaos: collisions amplify round-off about e^(λt) until the runs are different realisations).\n\n",
        r.code,
        r.deck.display(),
        r.spheres,
        r.free_spheres,
        r.rows,
        sig(r.dt, 6),
        r.code,
        r.identical_threshold,
        agreement::SATURATED
    );
    let mut t = Table::new(vec![
        Column::text("quantity"),
        Column::text("identical until").right(),
        Column::text("diverged at").right(),
        Column::text("λ (1/s)").right(),
        Column::text("decades/ms").right(),
    ]);
    for q in &r.quantities {
        let d = &q.divergence;
        t.push(vec![
            Cell::text(format!("{} ({})", q.name, q.unit)),
            Cell::text(opt_s(d.identical_until)),
            Cell::text(opt_s(d.diverged_at)),
            Cell::text(d.growth_rate.map_or("—".into(), |l| sig(l, 3))),
            Cell::text(
                d.growth_rate
                    .map_or("—".into(), |l| sig(l / std::f64::consts::LN_10 * 1e-3, 3)),
            ),
        ]);
    }
    out.push_str(&format!("Identical-state agreement:\n{t}\n"));
    if let Some(e) = &r.state_end {
        out.push_str(&format!(
            "The comparison by id ends at t = {} s ({}): {}. The identical-state columns cover \
             the rows before it.\n",
            sig(e.at, 4),
            e.compared_until
                .map_or("no row compared".into(), |t| format!(
                    "compared up to t = {} s",
                    sig(t, 4)
                )),
            e.reason
        ));
    }
    if r.quantities.iter().any(|q| q.running_count) {
        out.push_str(&format!(
            "Running counts (inserted, discharged) are compared at every row: \"identical until\" \
             is the last row before the first at which they differ by more than {:e} (relative).\n",
            r.identical_threshold
        ));
        for q in r.quantities.iter().filter(|q| q.running_count) {
            let (Some(a), Some(b)) = (q.code.last(), q.dembound.last()) else {
                continue;
            };
            let unequal = q
                .relative_difference
                .iter()
                .filter(|d| **d > r.identical_threshold)
                .count();
            out.push_str(&format!(
                "  {} at the last row: {} {} {}, dembound {} {} (rows that differ: {} of {})\n",
                q.name,
                r.code,
                sig(*a, 6),
                q.unit,
                sig(*b, 6),
                q.unit,
                unequal,
                q.code.len()
            ));
        }
    }
    let mut s = Table::new(vec![
        Column::text("quantity"),
        Column::text(format!("{} mean ± SE", r.code)).right(),
        Column::text("dembound mean ± SE").right(),
        Column::text("ratio − 1").right(),
        Column::text("verdict"),
    ]);
    for q in r.quantities.iter().filter(|q| q.verdict.is_some()) {
        let show = |w: &Option<WindowMean>| {
            w.map_or("—".into(), |w| {
                format!(
                    "{} ± {} {}",
                    sig(w.mean, 6),
                    sig(w.standard_error, 2),
                    q.unit
                )
            })
        };
        s.push(vec![
            Cell::text(q.name.clone()),
            Cell::text(show(&q.code_window)),
            Cell::text(show(&q.dembound_window)),
            Cell::text(
                q.window_relative_difference
                    .map_or("—".into(), |d| format!("{:+.2e}", d)),
            ),
            Cell::text(q.verdict.map_or("—", |v| v.text())),
        ]);
    }
    out.push_str(&format!(
        "\nStatistical agreement over the late window (t ≥ {} s, batch means; agree: within 1 % or 2 SE):\n{s}\n",
        sig(r.window_from, 4)
    ));
    let speed = |s: &Speed| {
        let mut times = Vec::new();
        if let Some(c) = s.cpu_seconds {
            times.push(format!("{} s CPU", sig(c, 3)));
        }
        if let Some(w) = s.wall_seconds {
            times.push(format!(
                "{} s wall on {} core{}",
                sig(w, 3),
                s.cores,
                if s.cores == 1 { "" } else { "s" }
            ));
        }
        format!(
            "{:.2e} free-sphere steps per core-second by {} time ({})",
            s.particle_steps_per_core_second,
            s.clock,
            times.join(", ")
        )
    };
    for p in &r.profiles {
        out.push_str(&format!(
            "Profile of {} ({}) against z, bins of {} m (the mean free diameter), late window: \
             largest |{} − dembound| = {} at z = {} m (± {} combined SE){}\n",
            p.name,
            p.unit,
            sig(p.bin_width, 4),
            r.code,
            sig(p.max_abs_difference, 3),
            sig(p.at, 4),
            sig(p.standard_error_there, 2),
            match (p.bar, p.agree) {
                (Some(b), Some(true)) => format!(": agree (≤ {b})"),
                (Some(b), _) => format!(": DIFFER (> {b})"),
                _ => String::new(),
            }
        ));
    }
    out.push_str(&format!(
        "\nSpeed: {} {}; dembound {} (stepping only){}\n",
        r.code,
        r.code_speed
            .as_ref()
            .map_or("— (no Loop time in its log)".into(), speed),
        r.dembound_speed
            .as_ref()
            .map_or("— (no time measured)".into(), speed),
        match (
            r.code_speed.as_ref().map(|s| s.clock),
            r.dembound_speed.as_ref().map(|s| s.clock)
        ) {
            (Some(a), Some(b)) if a != b => {
                " — one by wall clock, one by CPU time: on a loaded machine the wall-clock rate understates that code's per-core speed"
            }
            _ => "",
        }
    ));
    for n in &r.notes {
        out.push_str(&format!("Note: {n}\n"));
    }
    out
}

/// One figure per quantity (both runs against time) and one of every
/// relative difference's log10 (a straight rise: exponential growth).
fn write_figures(r: &SceneCompareReport, dir: &Path) -> anyhow::Result<()> {
    std::fs::create_dir_all(dir)
        .map_err(|e| anyhow!("--figures `{}`: cannot create it: {e}", dir.display()))?;
    let stem = |name: &str| -> String {
        name.chars()
            .map(|c| {
                if c.is_ascii_alphanumeric() {
                    c.to_ascii_lowercase()
                } else {
                    '_'
                }
            })
            .collect::<String>()
            .split('_')
            .filter(|w| !w.is_empty())
            .collect::<Vec<_>>()
            .join("_")
    };
    for q in r.quantities.iter().filter(|q| !q.name.starts_with("state")) {
        let pts = |v: &[f64]| {
            q.time
                .iter()
                .zip(v)
                .map(|(t, y)| (*t, *y))
                .collect::<Vec<_>>()
        };
        let fig = Figure {
            title: format!("{}: {} and dembound", q.name, r.code),
            x_label: "t (s)".into(),
            y_label: format!("{} ({})", q.name, q.unit),
            series: vec![
                Series::new(r.code.clone(), pts(&q.code), Mark::Line, 0),
                Series::new("dembound", pts(&q.dembound), Mark::Dashed, 1),
            ],
            ..Figure::default()
        };
        fig.write(&dir.join(stem(&q.name)))?;
    }
    let mut fig = Figure {
        title: format!(
            "{} against dembound: relative differences (1e-9: identical)",
            r.code
        ),
        x_label: "t (s)".into(),
        // log10 on a linear axis: the figure module's log axes print
        // ticks far below the top of the range as "0".
        y_label: "log10 of the relative difference (1)".into(),
        legend_outside: true,
        ..Figure::default()
    };
    for (k, q) in r.quantities.iter().enumerate() {
        let pts: Vec<(f64, f64)> = q
            .time
            .iter()
            .zip(&q.relative_difference)
            .filter(|(_, d)| **d > 0.0)
            .map(|(t, d)| (*t, d.log10()))
            .collect();
        fig.series
            .push(Series::new(q.name.clone(), pts, Mark::Line, k));
    }
    fig.write(&dir.join("relative_differences"))?;
    for p in &r.profiles {
        let pts = |m: &[Option<WindowMean>]| -> Vec<(f64, f64)> {
            m.iter()
                .zip(&p.centres)
                .filter_map(|(w, z)| w.map(|w| (w.mean, *z)))
                .collect()
        };
        let fig = Figure {
            title: format!(
                "{} against z, late-window mean: {} and dembound (bins {} m)",
                p.name,
                r.code,
                sig(p.bin_width, 3)
            ),
            x_label: format!("{} ({})", p.name, p.unit),
            y_label: "z (m)".into(),
            series: vec![
                Series::new(r.code.clone(), pts(&p.code), Mark::Line, 0),
                Series::new("dembound", pts(&p.dembound), Mark::Dashed, 1),
            ],
            ..Figure::default()
        };
        fig.write(&dir.join(format!("profile_{}", stem(&p.name))))?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A box periodic in x and y, gravity tilted in x (a chute), two
    /// spheres of R = 0.5 mm.
    fn chute_geometry() -> Geometry {
        let text = r#"
[domain]
lower = [0.0, 0.0, 0.0]
upper = [0.012, 0.012, 0.02]
periodic = [true, true, false]
[[material]]
name = "grain"
density = 1000.0
youngs_modulus = 1.0e7
poisson_ratio = 0.3
[contact]
law = { hooke = 50.0 }
[[particles]]
spheres = [{ position = [0.0004, 0.006, 0.001], radius = 0.5e-3 }, { position = [0.0115, 0.006, 0.001], radius = 0.5e-3 }]
material = "grain"
[motion]
gravity = [4.0, 0.0, -9.0]
[integration]
dt = 1.0e-6
steps = 1
"#;
        let file = config::load(text, "chute", &[]).expect("the test's scene parses");
        let setup = resolve(&file, Path::new("."))
            .expect("the test's scene resolves")
            .setup;
        Geometry::new(&setup)
    }

    #[test]
    fn separation_takes_the_nearest_image_on_periodic_axes() {
        let g = chute_geometry();
        // x: 0.0117 → 0.0003 is +0.0006 through the face (12 mm box), not
        // −0.0114; z is not periodic and keeps its plain difference.
        let d = g.separation([0.0117, 0.0, 0.0], [0.0003, 0.0, 0.019]);
        assert!((d[0] - 0.0006).abs() < 1e-15, "{d:?}");
        assert!((d[2] - 0.019).abs() < 1e-15, "{d:?}");
        // One code's sphere at y = 1e-17, the other's wrapped to y = 0.012:
        // the same place (the row that made the state jump to 24 R).
        let d = g.separation([0.005, 0.012, 0.001], [0.005, 1e-17, 0.001]);
        assert!(d[1].abs() < 1e-15, "{d:?}");
    }

    #[test]
    fn pairs_across_a_periodic_face_are_contacts_and_gravity_along_it_has_no_potential() {
        let g = chute_geometry();
        // m = ρ 4/3 π R³ = 5.236e-7 kg.
        let m = 1000.0 * 4.0 / 3.0 * std::f64::consts::PI * 0.5e-3_f64.powi(3);
        let spheres = Spheres {
            index: vec![0, 1],
            position: vec![[0.0004, 0.006, 0.001], [0.0115, 0.006, 0.001]],
            velocity: vec![[0.0; 3]; 2],
            spin: vec![[0.0; 3]; 2],
            radius: vec![0.5e-3; 2],
            mass: vec![m; 2],
            fixed: vec![false; 2],
        };
        // 0.9 mm apart through the x face, R₁ + R₂ = 1 mm: one contact.
        assert_eq!(g.sphere_pairs(&spheres), 1);
        let s = g.sample(&spheres, Vec::new());
        // Potential: −Σ m g_z z only (g_x is along a periodic axis); the
        // height is along z.
        let expected = 2.0 * m * 9.0 * 0.001;
        assert!(
            (s.potential - expected).abs() < 1e-12 * expected,
            "{}",
            s.potential
        );
        assert!((s.bed_height - 0.0015).abs() < 1e-15, "{}", s.bed_height);
    }

    /// The state difference by id: only the spheres both rows hold, the
    /// fixed left out, over the smallest radius among them; from an index
    /// on (the inserted spheres).
    #[test]
    fn the_state_difference_reads_common_ids_only() {
        let g = chute_geometry();
        let row = |index: Vec<usize>, z: Vec<f64>, fixed: Vec<bool>| Spheres {
            position: z.iter().map(|&z| [0.005, 0.005, z]).collect(),
            velocity: vec![[0.0; 3]; z.len()],
            spin: vec![[0.0; 3]; z.len()],
            radius: index
                .iter()
                .map(|&i| if i == 3 { 0.25e-3 } else { 0.5e-3 })
                .collect(),
            mass: vec![1.0; z.len()],
            fixed,
            index,
        };
        // Common: 1 (Δz = 0.1 mm), 2 (fixed, Δz = 5 mm: left out), 3
        // (R = 0.25 mm, Δz = 0.05 mm); 0 and 4 in one row only.
        let a = row(
            vec![0, 1, 2, 3],
            vec![0.001, 0.002, 0.003, 0.004],
            vec![false, false, true, false],
        );
        let b = row(
            vec![1, 2, 3, 4],
            vec![0.0021, 0.008, 0.00405, 0.009],
            vec![false, true, false, false],
        );
        // max |Δz| = 0.1 mm over R_min = 0.25 mm: 0.4.
        assert!((g.state_difference(&a, &b, 0) - 0.4).abs() < 1e-12);
        // From index 3 on: 0.05 mm / 0.25 mm = 0.2.
        assert!((g.state_difference(&a, &b, 3) - 0.2).abs() < 1e-12);
        assert_eq!(g.state_difference(&a, &b, 5), 0.0);
    }
}
