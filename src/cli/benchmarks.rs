//! `dembound benchmarks [NAME…] [--quick] --out DIR` (issue 30): the
//! engine's validation suite. Thin: the runs and their references are
//! `dembound_scene::benchmarks`; here the names are checked, progress goes
//! to stderr, and one document model (the summary [`Table`], the figures)
//! is rendered to the terminal, `report.md`, `report.html` (through
//! `output::html`, as `paper` does) and `summary.csv`, all or nothing
//! through [`AtomicDir`](crate::output::files::AtomicDir).

use super::{CliError, CliResult};
use crate::output::format::sig;
use crate::output::table::{Cell, Column, Format, Table, Unit};
use crate::plot::{Figure, Mark, Series, Shape, BLACK};
use clap::Args;
use dembound_scene::benchmarks::{self, Band, Outcome, Style};
use std::fmt::Write as _;
use std::io::Write as _;
use std::path::PathBuf;
use std::time::Instant;

#[derive(Debug, Args)]
pub struct BenchmarksArgs {
    /// Benchmarks to run (default: all); `dembound benchmarks --list` names them
    pub names: Vec<String>,
    /// Output directory (report.md, report.html, summary.csv, figures);
    /// all files or none
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// The small versions (seconds each), as the test suite runs them
    #[arg(long)]
    pub quick: bool,
    /// Heaps per (μ_s, μ_r) pair, each with its own inlet seed (repose only;
    /// default 4 full, 1 quick; at most 16)
    #[arg(long, value_name = "N")]
    pub seeds: Option<usize>,
    /// Print the benchmark names and titles, run nothing
    #[arg(long)]
    pub list: bool,
    /// No progress lines on stderr
    #[arg(long, short)]
    pub quiet: bool,
}

fn band_text(b: Band, unit: &str) -> String {
    match b {
        Band::Relative(r) => format!("±{} %", sig(r * 100.0, 3)),
        Band::AtLeast => "≥ published".into(),
        Band::Absolute(a) => {
            if unit == "1" {
                format!("±{}", sig(a, 3))
            } else {
                format!("±{} {unit}", sig(a, 3))
            }
        }
    }
}

fn value_text(x: f64, unit: &str) -> String {
    if unit == "1" {
        sig(x, 7)
    } else {
        format!("{} {unit}", sig(x, 7))
    }
}

/// The summary: one row per check. The terminal and Markdown show the
/// values with their units; the CSV holds them exactly, the unit apart.
fn summary(outcomes: &[Outcome]) -> Table {
    let mut t = Table::new(vec![
        Column::text("benchmark").csv("benchmark"),
        Column::text("quantity").csv("quantity"),
        Column::text("ours").right(),
        Column::number("ours", Unit::NONE, Format::Text)
            .csv("ours")
            .csv_only(),
        Column::text("published").right(),
        Column::number("published", Unit::NONE, Format::Text)
            .csv("published")
            .csv_only(),
        Column::text("unit").csv("unit").csv_only(),
        Column::text("band").right().csv("band"),
        Column::text("verdict").csv("verdict"),
        Column::text("run time (s)").right(),
        Column::number("run time", Unit::SECOND, Format::Text)
            .csv("run_time")
            .csv_only(),
    ]);
    for o in outcomes {
        for (k, c) in o.checks.iter().enumerate() {
            let first = k == 0;
            t.push(vec![
                Cell::text(o.name),
                Cell::text(&c.quantity),
                Cell::text(value_text(c.ours, &c.unit)),
                Cell::Number(c.ours),
                Cell::text(value_text(c.published, &c.unit)),
                Cell::Number(c.published),
                Cell::text(&c.unit),
                Cell::text(band_text(c.band, &c.unit)),
                Cell::text(if c.passes() { "pass" } else { "FAIL" }),
                Cell::text(if first {
                    format!("{:.2}", o.seconds)
                } else {
                    String::new()
                }),
                if first {
                    Cell::Number(o.seconds)
                } else {
                    Cell::Empty
                },
            ]);
        }
    }
    t
}

fn figure(p: &dembound_scene::benchmarks::Plot) -> Figure {
    let shapes = [
        Shape::Circle,
        Shape::Square,
        Shape::Triangle,
        Shape::Diamond,
    ];
    Figure {
        title: p.title.clone(),
        x_label: p.x_label.clone(),
        y_label: p.y_label.clone(),
        series: p
            .curves
            .iter()
            .map(|c| {
                let (mark, color) = match c.style {
                    Style::Ours => (Mark::LineShape(shapes[c.group % shapes.len()]), c.group),
                    Style::OursPoints => (Mark::Shape(shapes[c.group % shapes.len()]), c.group),
                    // A closed form of one case in its case's colour, dashed;
                    // one for all cases (group 7) solid black.
                    Style::ClosedForm if c.group == BLACK => (Mark::Line, BLACK),
                    Style::ClosedForm => (Mark::Dashed, c.group),
                    Style::Published => (Mark::Shape(Shape::Cross), 6),
                    Style::Band => (Mark::Dashed, 6),
                    Style::Peer => (Mark::Shape(Shape::HollowCircle), c.group),
                    Style::ErrorBar => (Mark::Line, c.group),
                };
                Series::new(c.label.clone(), c.points.clone(), mark, color)
            })
            .collect(),
        legend_outside: true,
        ..Default::default()
    }
}

fn markdown(outcomes: &[Outcome], quick: bool, seeds: Option<usize>, total: f64) -> String {
    let mut m = String::new();
    let passed = outcomes.iter().filter(|o| o.passes()).count();
    let flags = format!(
        "{}{}",
        if quick { " --quick" } else { "" },
        seeds.map_or(String::new(), |n| format!(" --seeds {n}"))
    );
    let _ = writeln!(
        m,
        "# dembound benchmarks\n\nGenerated by `dembound benchmarks{}` (dembound {}): {} benchmark(s), \
         {passed} passed every check; total run time {:.1} s.\n\n\
         Each benchmark is built in code from published parameters (sources under each section), \
         run by the many-particle engine (`dembound_scene::Simulation`, one thread, velocity Verlet) \
         and compared with its reference: a closed form derived in \
         `crates/dembound-scene/src/benchmarks/closed_form.rs`, or the publication's curve as \
         digitised in a cited public repository, or a published law (Janssen's, Lube et al.'s). \
         A check passes when ours is within the band of \
         the published value.\n",
        flags,
        env!("CARGO_PKG_VERSION"),
        outcomes.len(),
        total
    );
    let _ = writeln!(m, "## Summary\n");
    m.push_str(&summary(outcomes).markdown());
    for o in outcomes {
        let _ = writeln!(
            m,
            "\n## {}: {}\n\nSource: {}. Verdict: **{}**. Run time {:.2} s.\n",
            o.name,
            o.title,
            o.source,
            if o.passes() { "pass" } else { "fail" },
            o.seconds
        );
        let _ = writeln!(m, "Parameters:\n");
        for p in &o.parameters {
            let _ = writeln!(m, "- {p}");
        }
        let _ = writeln!(m, "\nNotes:\n");
        for n in &o.notes {
            let _ = writeln!(m, "- {n}");
        }
        let _ = writeln!(m);
        let mut t = Table::new(vec![
            Column::text("quantity"),
            Column::text("ours").right(),
            Column::text("published").right(),
            Column::text("band").right(),
            Column::text("verdict"),
            Column::text("reference"),
        ]);
        for c in &o.checks {
            t.push(vec![
                Cell::text(&c.quantity),
                Cell::text(value_text(c.ours, &c.unit)),
                Cell::text(value_text(c.published, &c.unit)),
                Cell::text(band_text(c.band, &c.unit)),
                Cell::text(if c.passes() { "pass" } else { "FAIL" }),
                Cell::text(&c.reference),
            ]);
        }
        m.push_str(&t.markdown());
        for p in &o.plots {
            let _ = writeln!(m, "\n![{}]({}.png)\n", p.title, p.stem);
        }
    }
    m
}

pub fn run(args: &BenchmarksArgs) -> CliResult {
    let all = benchmarks::names();
    if args.list {
        let mut out = std::io::stdout().lock();
        for n in &all {
            writeln!(out, "{n}  {}", benchmarks::title(n).unwrap_or(""))
                .map_err(CliError::failed)?;
        }
        return Ok(());
    }
    let Some(dir) = &args.out else {
        return Err(CliError::input(anyhow::anyhow!(
            "--out DIR is required (where report.md, report.html and the figures go)"
        )));
    };
    for n in &args.names {
        if !all.contains(&n.as_str()) {
            return Err(CliError::input(anyhow::anyhow!(
                "unknown benchmark `{n}`: the benchmarks are {}",
                all.join(", ")
            )));
        }
    }
    if let Some(n) = args.seeds {
        if n == 0 || n > benchmarks::MAX_SEEDS {
            return Err(CliError::input(anyhow::anyhow!(
                "--seeds {n}: allowed 1 to {} heaps per (μ_s, μ_r) pair",
                benchmarks::MAX_SEEDS
            )));
        }
        if args.names.is_empty()
            || args
                .names
                .iter()
                .any(|a| !benchmarks::SEEDED.contains(&a.as_str()))
        {
            return Err(CliError::input(anyhow::anyhow!(
                "--seeds {n}: applies only to {}; name it alone (e.g. `dembound benchmarks repose --seeds {n}`)",
                benchmarks::SEEDED.join(", ")
            )));
        }
    }
    let chosen: Vec<&str> = if args.names.is_empty() {
        all.clone()
    } else {
        all.iter()
            .copied()
            .filter(|n| args.names.iter().any(|a| a == n))
            .collect()
    };
    // Before computing: a bad --out fails at once.
    let mut out = super::output_dir(dir, "benchmarks")?;
    let start = Instant::now();
    let quiet = args.quiet;
    let progress = |msg: &str| {
        if !quiet {
            eprintln!(
                "benchmarks: {:>7.1} s  {msg}",
                start.elapsed().as_secs_f64()
            );
        }
    };
    let mut outcomes = Vec::new();
    for name in chosen {
        let o = benchmarks::run_seeded(name, args.quick, args.seeds, &progress)
            .map_err(|e| CliError::failed(anyhow::anyhow!("benchmark {name}: {e}")))?;
        progress(&format!(
            "{name}: {} in {:.2} s",
            if o.passes() { "pass" } else { "FAIL" },
            o.seconds
        ));
        outcomes.push(o);
    }
    let total = start.elapsed().as_secs_f64();
    progress("figures and report");
    for o in &outcomes {
        for p in &o.plots {
            figure(p)
                .write_into(&mut out, &p.stem)
                .map_err(CliError::failed)?;
        }
    }
    let md = markdown(&outcomes, args.quick, args.seeds, total);
    let html = crate::output::html::report_html(&md, out.staging(), "dembound benchmarks")
        .map_err(CliError::failed)?;
    let table = summary(&outcomes);
    out.write("report.md", |w| Ok(w.write_all(md.as_bytes())?))
        .map_err(CliError::failed)?;
    out.write("report.html", |w| Ok(w.write_all(html.as_bytes())?))
        .map_err(CliError::failed)?;
    out.write("summary.csv", |w| table.write_csv(w))
        .map_err(CliError::failed)?;
    let written = out.commit().map_err(CliError::failed)?;
    let passed = outcomes.iter().filter(|o| o.passes()).count();
    let mut stdout = std::io::stdout().lock();
    writeln!(
        stdout,
        "{table}\n{passed} of {} benchmarks passed every check; wrote {} files into {} in {:.1} s",
        outcomes.len(),
        written.len(),
        dir.display(),
        start.elapsed().as_secs_f64()
    )
    .map_err(CliError::failed)?;
    Ok(())
}
