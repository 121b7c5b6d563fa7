//! Argument parsing and the subcommands, one file each.
//!
//! Exit codes: 0 success, 1 a run that failed, 2 bad input (including
//! clap's usage errors). Errors go to stderr as `error: …`.

pub mod benchmarks;
pub mod compare;
mod compare_flow;
mod compare_profiles;
mod compare_rows;
mod compare_sample;
mod compare_scene;
mod compare_scene_report;
pub mod exact;
pub mod export;
pub mod keys;
pub mod keys_scene;
pub mod lists;
pub mod paper;
pub mod particle_wall;
pub mod particle_wall_choice;
mod particle_wall_report;
pub mod recommend;
mod recommend_holes;
pub mod restitution;
pub mod run;
pub mod scene;
mod scene_collisions;
mod scene_limits;
#[cfg(feature = "mpi")]
mod scene_mpi;
#[cfg(feature = "mpi")]
mod scene_mpi_pieces;
pub mod sweep;
pub mod validate;
pub mod wall_study;
pub mod warnings;

use crate::output::files::AtomicDir;
use crate::output::interrupt;
use clap::{Parser, Subcommand};
use std::cell::RefCell;
use std::path::Path;
use std::process::ExitCode;
use std::sync::OnceLock;
use std::time::Instant;

/// DEM studies of an elastic sphere bouncing on a boundary sphere
/// (Jasevičius & Kačianauskas 2007). All inputs and outputs are SI.
#[derive(Debug, Parser)]
#[command(name = "dembound", version, propagate_version = true)]
pub struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Run one scenario and report every contact (the paper's validation
    /// case when no file is given)
    Run(run::RunArgs),
    /// The exact per-contact values of a scenario (the paper's validation
    /// case when no file is given), with the paper's estimates (eqs 26–30)
    Exact(exact::ExactArgs),
    /// Reproduce the paper's Tables 1–2 against the exact reference, and a
    /// convergence study in the time step
    Validate(validate::ValidateArgs),
    /// Sweep r, ζ, laws and other keys; integrator beside the exact
    /// reference, normalised by the rigid half-space
    Sweep(sweep::SweepArgs),
    /// Smallest ζ or r within a tolerance of the rigid half-space or of a
    /// flat wall of the boundary's material, the r–ζ trade-off, or the
    /// deviations at given (r, ζ); answers as ratios and in SI
    Recommend(recommend::RecommendArgs),
    /// Reproduce the paper's section 5 (Figs 4–8, quoted numbers, Tables
    /// 1–2) into a directory with report.md and report.html
    Paper(paper::PaperArgs),
    /// Effective restitution of the dissipative laws on boundary particles
    /// (sweep over r and ζ, wall- or pair-calibrated damping), or with
    /// --target the e to enter for a wanted rebound
    Restitution(restitution::RestitutionArgs),
    /// Run a many-particle 3D scene (spheres, plane walls, walls of
    /// boundary particles) from a scene file
    Scene(scene::SceneArgs),
    /// Every scenario key with its unit, default and allowed range
    Keys(keys::KeysArgs),
    /// Boundary particles against a plane in a many-particle bed (issue 13)
    WallStudy(Box<wall_study::WallStudyArgs>),
    /// Write a LAMMPS or LIGGGHTS deck or a Yade script that reproduces
    /// the scenario (pre-mixed moduli, damping in the code's convention,
    /// dembound's Δt, a per-step trace); a scene file (LAMMPS, LIGGGHTS) as
    /// a data file and a deck
    Export(export::ExportArgs),
    /// The validation suite: classic benchmarks with published numbers
    /// (Chung & Ooi 2011 Tests 1–8), a report with verdicts and figures
    Benchmarks(benchmarks::BenchmarksArgs),
    /// Cover a part (STL/OBJ, or a square or cylinder) with boundary
    /// spheres, tops on its surface: CSV, LAMMPS data, VTK, a picture and
    /// a report of the count, the largest hole and the bumpiness
    ParticleWall(particle_wall::ParticleWallArgs),
    /// Read the trace an exported deck wrote and print its h_max, T_c,
    /// v_r, e beside dembound's and the exact reference
    Compare(compare::CompareArgs),
}

/// Why a command did not succeed, and so its exit code.
#[derive(Debug)]
pub enum CliError {
    /// Bad input: a scenario file, a flag, a value out of range (exit 2).
    Input(anyhow::Error),
    /// A run or an output that failed (exit 1).
    Failed(anyhow::Error),
}

impl CliError {
    pub fn input(e: impl Into<anyhow::Error>) -> Self {
        CliError::Input(e.into())
    }

    pub fn failed(e: impl Into<anyhow::Error>) -> Self {
        CliError::Failed(e.into())
    }

    pub fn exit_code(&self) -> u8 {
        match self {
            CliError::Input(_) => 2,
            CliError::Failed(_) => 1,
        }
    }

    /// The error, with its context.
    pub fn error(&self) -> &anyhow::Error {
        match self {
            CliError::Input(e) | CliError::Failed(e) => e,
        }
    }
}

pub type CliResult<T = ()> = Result<T, CliError>;

/// The moment the process began its work (set first thing in [`main`]).
static PROCESS_START: OnceLock<Instant> = OnceLock::new();

/// Seconds since the process began: the whole-process wall clock a scene
/// reports (reading, set-up, stepping and writing; issue 31 item 2).
pub(crate) fn process_seconds() -> f64 {
    PROCESS_START
        .get_or_init(Instant::now)
        .elapsed()
        .as_secs_f64()
}

/// Parses the command line, runs the subcommand and turns the outcome into
/// an exit code.
pub fn main() -> ExitCode {
    PROCESS_START.get_or_init(Instant::now);
    // Usage errors exit 2 and --help/--version exit 0, both printed by clap.
    let cli = Cli::parse();
    interrupt::install();
    match dispatch(&cli) {
        Ok(()) => ExitCode::SUCCESS,
        // The reader of stdout went away (e.g. `| head`): stop quietly.
        Err(e) if is_broken_pipe(e.error()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {:#}", e.error());
            ExitCode::from(e.exit_code())
        }
    }
}

/// Runs the subcommand of a parsed command line.
pub fn dispatch(cli: &Cli) -> CliResult {
    match &cli.command {
        Command::Run(args) => run::run(args),
        Command::Exact(args) => exact::run(args),
        Command::Validate(args) => validate::run(args),
        Command::Sweep(args) => sweep::run(args),
        Command::Recommend(args) => recommend::run(args),
        Command::Paper(args) => paper::run(args),
        Command::Restitution(args) => restitution::run(args),
        Command::Scene(args) => scene::run(args),
        Command::Keys(args) => keys::run(args),
        Command::WallStudy(args) => wall_study::run(args),
        Command::Export(args) => export::run(args),
        Command::Compare(args) => compare::run(args),
        Command::Benchmarks(args) => benchmarks::run(args),
        Command::ParticleWall(args) => particle_wall::run(args),
    }
}

thread_local! {
    /// Set inside [`capture_json`]: the `--json` document lands here (as
    /// compact JSON text) instead of on stdout.
    static JSON_CAPTURE: RefCell<Option<Option<String>>> = const { RefCell::new(None) };
}

/// The text a `--json` command prints: `doc` pretty-printed with a final
/// newline. Inside [`capture_json`] the document is kept as compact JSON
/// text instead (the same serialisation, so the same numbers bit for bit)
/// and the text returned is empty.
pub fn json_text(doc: &impl serde::Serialize) -> CliResult<String> {
    let captured = JSON_CAPTURE.with(|slot| {
        slot.borrow_mut()
            .as_mut()
            .map(|kept| serde_json::to_string(doc).map(|text| *kept = Some(text)))
    });
    match captured {
        Some(result) => result.map(|()| String::new()).map_err(CliError::failed),
        None => serde_json::to_string_pretty(doc)
            .map(|text| text + "\n")
            .map_err(CliError::failed),
    }
}

thread_local! {
    /// Set inside [`capture_warnings`]: warnings are kept, not printed.
    static WARNING_CAPTURE: RefCell<Option<Vec<String>>> = const { RefCell::new(None) };
}

/// Keeps a warning if [`capture_warnings`] is active (true), else leaves
/// it to be printed (false).
pub fn capture_warning(warning: &str) -> bool {
    WARNING_CAPTURE.with(|slot| match slot.borrow_mut().as_mut() {
        Some(kept) => {
            kept.push(warning.to_string());
            true
        }
        None => false,
    })
}

/// Runs `f` and returns the warnings it would have printed to stderr (the
/// Python bindings raise them as Python warnings).
pub fn capture_warnings<T>(f: impl FnOnce() -> T) -> (T, Vec<String>) {
    let previous = WARNING_CAPTURE.with(|slot| slot.replace(Some(Vec::new())));
    let result = f();
    let kept = WARNING_CAPTURE.with(|slot| slot.replace(previous));
    (result, kept.unwrap_or_default())
}

/// Runs `f` (a command with `--json`) and returns the JSON document it
/// would have printed, as compact JSON text: how the Python bindings get
/// exactly the CLI's `--json` documents. `None` if the command printed none.
pub fn capture_json(f: impl FnOnce() -> CliResult) -> CliResult<Option<String>> {
    let previous = JSON_CAPTURE.with(|slot| slot.replace(Some(None)));
    let result = f();
    let kept = JSON_CAPTURE.with(|slot| slot.replace(previous)).flatten();
    result.map(|()| kept)
}

/// The output directory of `--out`, opened (made if missing, a staging
/// directory in it) before anything is computed: a path that is not a
/// writable directory is bad input (exit 2). `set` names the subcommand
/// whose files it receives.
pub fn output_dir(dir: &Path, set: &str) -> CliResult<AtomicDir> {
    AtomicDir::create(dir, set).map_err(|e| {
        CliError::input(e.context(format!(
            "--out `{}`: cannot write the output there",
            dir.display()
        )))
    })
}

fn is_broken_pipe(e: &anyhow::Error) -> bool {
    e.chain().any(|cause| {
        cause
            .downcast_ref::<std::io::Error>()
            .is_some_and(|io| io.kind() == std::io::ErrorKind::BrokenPipe)
    })
}
