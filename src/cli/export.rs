//! `dembound export lammps|liggghts|yade`: a deck for another DEM code that
//! reproduces the scenario (the mapping and its pitfalls:
//! docs/export-lammps.md, docs/export-liggghts.md, docs/export-yade.md).

use super::{output_dir, warnings, CliError, CliResult};
use crate::output::report;
use crate::scenario_file::ScenarioArgs;
use anyhow::anyhow;
use clap::{Args, ValueEnum};
use dembound_export::{export, Code, Pitfall};
use dembound_scene::io::{config, resolve::resolve};
use std::io::Write;
use std::path::{Path, PathBuf};

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum CodeArg {
    Lammps,
    Liggghts,
    Yade,
}

impl From<CodeArg> for Code {
    fn from(c: CodeArg) -> Self {
        match c {
            CodeArg::Lammps => Code::Lammps,
            CodeArg::Liggghts => Code::Liggghts,
            CodeArg::Yade => Code::Yade,
        }
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum PitfallArg {
    /// LAMMPS: the boundary as `fix wall/gran … hertz/material E_b`
    WallMaterial,
    /// LAMMPS: per-type `hertz/material` for particle and frozen boundary
    /// sphere, the cross pair left to LAMMPS's mixing
    AutoMix,
    /// Yade: the plane as `utils.wall` (Mindlin then takes R* = R_m/2)
    YadeWall,
    /// Yade: `NewtonIntegrator` at its default Cundall damping 0.2
    CundallDamping,
}

#[derive(Debug, Args)]
pub struct ExportArgs {
    /// The code to write a deck for
    #[arg(value_enum)]
    pub code: CodeArg,

    #[command(flatten)]
    pub scenario: ScenarioArgs,

    /// Directory for the deck, scenario.toml (and, after the run, the
    /// code's trace.txt); created if missing, checked before anything is
    /// written, all files or none
    #[arg(long, value_name = "DIR")]
    pub out: PathBuf,

    /// Write a known-wrong deck on purpose, to see by number what a common
    /// setting does (docs/export-lammps.md, docs/export-yade.md)
    #[arg(long, value_enum)]
    pub pitfall: Option<PitfallArg>,
}

pub fn run(args: &ExportArgs) -> CliResult {
    if let Some(path) = &args.scenario.scenario {
        if is_scene_file(path) {
            return run_scene(args, path);
        }
    }
    let scenario = args.scenario.load().map_err(CliError::input)?.resolved();
    warnings::print(&warnings::inputs(&scenario));
    let code = Code::from(args.code);
    let pitfall = args.pitfall.map(|p| match p {
        PitfallArg::WallMaterial => Pitfall::WallMaterial,
        PitfallArg::AutoMix => Pitfall::AutoMix,
        PitfallArg::YadeWall => Pitfall::YadeWall,
        PitfallArg::CundallDamping => Pitfall::CundallDamping,
    });
    let mut out = output_dir(&args.out, "export")?;
    let deck = export(code, &scenario, pitfall).map_err(|e| CliError::input(anyhow!("{e}")))?;
    for file in &deck.files {
        out.write(&file.name, |w| Ok(w.write_all(file.text.as_bytes())?))
            .map_err(CliError::failed)?;
    }
    let toml = report::scenario_toml(&scenario).map_err(CliError::failed)?;
    out.write("scenario.toml", |w| Ok(w.write_all(toml.as_bytes())?))
        .map_err(CliError::failed)?;
    let written = out.commit().map_err(CliError::failed)?;
    let mut stdout = std::io::stdout().lock();
    for path in written {
        writeln!(stdout, "wrote {}", path.display()).map_err(CliError::failed)?;
    }
    writeln!(
        stdout,
        "run it:      cd {} && {}\nthen compare: dembound compare {}",
        args.out.display(),
        code.command(),
        args.out.display()
    )
    .map_err(CliError::failed)?;
    Ok(())
}

/// A scene file (`dembound scene`'s TOML) rather than a bounce scenario:
/// it has a `[domain]` or `[[particles]]` section, which a scenario never
/// has. An unreadable file is left to the scenario loader's message.
fn is_scene_file(path: &Path) -> bool {
    std::fs::read_to_string(path)
        .ok()
        .and_then(|text| text.parse::<toml::Table>().ok())
        .is_some_and(|t| t.contains_key("domain") || t.contains_key("particles"))
}

/// `dembound export lammps|liggghts SCENE.toml`: the spheres as a data
/// file, the deck (and a LIGGGHTS deck's mesh STLs), the resolved scene
/// (docs/export-lammps.md and docs/export-liggghts.md, "Scenes").
fn run_scene(args: &ExportArgs, path: &Path) -> CliResult {
    let code = Code::from(args.code);
    if args.pitfall.is_some() {
        return Err(CliError::input(anyhow!(
            "--pitfall is for bounce scenarios, not scene files (the {} scene deck has no \
             pitfall variant)",
            code.title()
        )));
    }
    let scene_error = super::scene::scene_error;
    let file = config::read(path, &args.scenario.set).map_err(scene_error)?;
    let base = path.parent().unwrap_or(Path::new("."));
    let resolved = resolve(&file, base).map_err(scene_error)?;
    let mut out = output_dir(&args.out, "export")?;
    let deck = match code {
        Code::Liggghts => dembound_export::liggghts_scene::deck(&resolved),
        Code::Yade => dembound_export::yade_scene::deck(&resolved),
        Code::Lammps => dembound_export::lammps_scene::deck(&resolved),
    }
    .map_err(|e| CliError::input(anyhow!("{e}")))?;
    for f in &deck.files {
        out.write(&f.name, |w| Ok(w.write_all(f.text.as_bytes())?))
            .map_err(CliError::failed)?;
    }
    let toml = toml::to_string(&resolved.file).map_err(CliError::failed)?;
    out.write("scene.toml", |w| Ok(w.write_all(toml.as_bytes())?))
        .map_err(CliError::failed)?;
    let written = out.commit().map_err(CliError::failed)?;
    let mut stdout = std::io::stdout().lock();
    for p in written {
        writeln!(stdout, "wrote {}", p.display()).map_err(CliError::failed)?;
    }
    let what = match code {
        Code::Liggghts if resolved.setup.spheres.is_empty() => {
            "particles.dump holds every sphere at the series cadence, the thermo lines (step \
             time ke, then per inlet the spheres and mass inserted) the kinetic energy"
        }
        Code::Liggghts => {
            "trajectory.txt holds sphere 1 at every step, particles.dump every sphere at the \
             series cadence, the last thermo line (step time ke) the kinetic energy"
        }
        Code::Yade => {
            "particles.dump and walls.txt hold every sphere's state and each wall's force at the \
             series cadence, log.yade the CPU time of the run"
        }
        Code::Lammps => {
            "the last thermo line (step time ke pp pw) is the state `dembound scene --json` \
             ends in; particles.dump and walls.txt hold every sphere's state and each wall's \
             force at the series cadence"
        }
    };
    writeln!(
        stdout,
        "run it:  cd {} && {}\n{what}",
        args.out.display(),
        if code == Code::Yade {
            dembound_export::yade_scene::COMMAND
        } else {
            code.command()
        },
    )
    .map_err(CliError::failed)?;
    if code == Code::Liggghts {
        for note in dembound_export::liggghts_inlets::notes(&resolved.setup) {
            eprintln!("note: {note}");
        }
        if let Some(note) = dembound_export::liggghts_scene::torque_arm_note(&resolved.setup) {
            eprintln!("{note}");
        }
        if let Some(note) = dembound_export::liggghts_scene::spring_rotation_note(&resolved.setup) {
            eprintln!("{note}");
        }
    }
    if code == Code::Lammps {
        if let Some(note) = dembound_export::lammps_scene::torque_arm_note(&resolved.setup) {
            eprintln!("{note}");
        }
    }
    Ok(())
}
