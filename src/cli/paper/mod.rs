//! `dembound paper`: the paper's section 5 reproduced (Figs 4–8, every
//! number it quotes, the convergence laws, the recommended limits) with
//! Tables 1–2, into a directory with figures, `report.md`, a self-contained
//! `report.html` and `paper.json`.
//!
//! What is computed is [`dembound_core::study::paper`]; here: the command,
//! the files and the rendering (`figures`, `markdown`; the HTML through
//! `output::html`).

mod figures;
mod markdown;

use super::{CliError, CliResult};
use crate::output::format::sig;
use crate::output::restitution::restitution_figures;
use crate::output::table::{Cell, Column, Table};
use crate::output::validation;
use anyhow::{anyhow, Result};
use clap::Args;
use dembound_core::study::paper::{base_scenario, compute};
use rayon::prelude::*;
use std::io::Write;
use std::path::PathBuf;
use std::time::Instant;

#[derive(Debug, Args)]
pub struct PaperArgs {
    /// Output directory (created if missing; checked before computing; all
    /// files or none)
    #[arg(long, value_name = "DIR", default_value = "paper-reproduction")]
    pub out: PathBuf,

    /// No progress messages on stderr
    #[arg(long, short)]
    pub quiet: bool,
}

fn stage(quiet: bool, start: Instant, msg: &str) {
    if !quiet {
        eprintln!("paper: {:>6.2} s  {msg}", start.elapsed().as_secs_f64());
    }
}

/// docs/errata.md: the ERRATA items the report cites, written beside it.
const ERRATA: &str = include_str!("../../../docs/errata.md");

/// Subfolder of the reproduction that holds the restitution study's figures.
const RESTITUTION_DIR: &str = "restitution";

pub fn run(args: &PaperArgs) -> CliResult {
    let start = Instant::now();
    let dir = &args.out;
    // Before computing: a bad --out fails at once.
    let mut out = super::output_dir(dir, "paper")?;
    let base = base_scenario();
    let data = compute(&base, &|msg| stage(args.quiet, start, msg))
        .map_err(|e| CliError::failed(anyhow!("{e}")))?;
    let compute_seconds = start.elapsed().as_secs_f64();

    stage(args.quiet, start, "figures and report");
    // Everything is drawn into the staging directory and published at once.
    let staging = out.staging().to_path_buf();
    let figs = figures::figures(&data);
    figs.par_iter()
        .map(|(stem, fig, _)| fig.write(&staging.join(stem)))
        .collect::<Result<Vec<_>>>()
        .map_err(CliError::failed)?;
    let conv_figs =
        validation::convergence_figures(&data.convergence, &staging).map_err(CliError::failed)?;
    let restitution_figs = restitution_figures(&data.restitution, &staging.join(RESTITUTION_DIR))
        .map_err(CliError::failed)?;
    let captions: Vec<(String, String)> = figs.into_iter().map(|(s, _, c)| (s, c)).collect();
    let md = markdown::report_markdown(
        &data,
        &captions,
        &conv_figs,
        &restitution_figs,
        compute_seconds,
    );
    let html = crate::output::html::report_html(
        &md,
        &staging,
        "dembound: reproduction of Jasevičius &amp; Kačianauskas (2007)",
    )
    .map_err(CliError::failed)?;
    out.write("report.md", |w| Ok(w.write_all(md.as_bytes())?))
        .map_err(CliError::failed)?;
    out.write("report.html", |w| Ok(w.write_all(html.as_bytes())?))
        .map_err(CliError::failed)?;
    out.write("paper.json", |w| {
        serde_json::to_writer_pretty(&mut *w, &data)?;
        Ok(writeln!(w)?)
    })
    .map_err(CliError::failed)?;
    out.write("errata.md", |w| Ok(w.write_all(ERRATA.as_bytes())?))
        .map_err(CliError::failed)?;
    let written = out.commit().map_err(CliError::failed)?;

    let mut stdout = std::io::stdout().lock();
    let mut t = Table::new(vec![
        Column::text("quoted in the paper"),
        Column::text("unit"),
        Column::text("paper").right(),
        Column::text("ours (exact)").right(),
        Column::text("ours (integrator)").right(),
        Column::text("same digits"),
    ]);
    for q in &data.quoted {
        t.push(vec![
            Cell::text(&q.what),
            Cell::text(&q.unit),
            Cell::text(&q.paper),
            Cell::text(sig(q.ours, 7)),
            Cell::text(
                q.integrator
                    .map(|x| sig(x, 7))
                    .unwrap_or_else(|| "–".into()),
            ),
            Cell::text(if q.agrees() { "yes" } else { "NO" }),
        ]);
    }
    let total = start.elapsed().as_secs_f64();
    writeln!(
        stdout,
        "{t}\nwrote {} files into {} (report.md, report.html, paper.json, errata.md, figures)\n\
         compute time {:.2} s, total time {:.2} s",
        written.len(),
        dir.display(),
        compute_seconds,
        total
    )
    .map_err(CliError::failed)?;
    stdout.flush().map_err(CliError::failed)?;
    Ok(())
}
