//! `dembound export lammps|liggghts|yade`: a deck for another DEM code that
//! reproduces the scenario (the mapping and its pitfalls:
//! docs/export-lammps.md, docs/export-liggghts.md, docs/export-yade.md).

use super::{output_dir, warnings, CliError, CliResult};
use crate::output::report;
use crate::scenario_file::ScenarioArgs;
use anyhow::anyhow;
use clap::{Args, ValueEnum};
use dembound_export::{export, Code, Pitfall};
use std::io::Write;
use std::path::PathBuf;

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
