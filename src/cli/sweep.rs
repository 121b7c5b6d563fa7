//! `dembound sweep`: the grid of section 5 over r, ζ, laws and any other
//! scenario keys, integrator beside the exact reference, normalised by the
//! rigid half-space.

use super::lists;
use super::{CliError, CliResult};
use crate::output::files::AtomicDir;
use crate::output::format::{exact, sig};
use crate::output::progress;
use crate::plot::{Figure, Mark, Series};
use crate::scenario_file::ScenarioArgs;
use anyhow::{anyhow, Result};
use clap::Args;
use comfy_table::{presets, CellAlignment, Table};
use dembound_core::contact::ContactLawKind;
use dembound_core::study::sweep::{sweep, SweepError, SweepResult, SweepSpec, Values, Variant};
use dembound_core::study::Quantity;
use std::io::Write;
use std::path::{Path, PathBuf};

#[derive(Debug, Args)]
pub struct SweepArgs {
    #[command(flatten)]
    pub scenario: ScenarioArgs,

    /// Boundary radius ratios r = R_b/R_m: `1,10,100,inf`, `log:0.5:1000:13`, `lin:1:5:5` or a mix
    #[arg(
        long = "r",
        value_name = "LIST",
        required = true,
        allow_hyphen_values = true
    )]
    pub r: String,

    /// Boundary modulus ratios ζ = E_b/E_m (same syntax as --r)
    #[arg(
        long = "zeta",
        value_name = "LIST",
        required = true,
        allow_hyphen_values = true
    )]
    pub zeta: String,

    /// Contact laws: `linear,hertz` or `power=1.25` (default: the scenario's)
    #[arg(long, value_name = "LIST")]
    pub law: Option<String>,

    /// Also vary another scenario key over a list, e.g. `--vary motion.gap=0.001,0.005`
    /// (repeatable: every combination is run)
    #[arg(long, value_name = "SECTION.KEY=LIST")]
    pub vary: Vec<String>,

    /// Write sweep.csv and sweep.json (and the figures with --plot) into DIR
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,

    /// Figures of the normalised h_max, T_c and a_max against r and ζ (needs --out)
    #[arg(long)]
    pub plot: bool,

    /// Print the result as one JSON object to stdout instead of the table
    #[arg(long)]
    pub json: bool,

    /// No progress bar
    #[arg(long, short)]
    pub quiet: bool,
}

/// `--vary` arguments to scenario variants (every combination).
fn variants(args: &SweepArgs) -> Result<Vec<Variant>> {
    let mut combos: Vec<Vec<String>> = vec![Vec::new()];
    for v in &args.vary {
        let (key, list) = v.split_once('=').ok_or_else(|| {
            anyhow!("malformed --vary `{v}`: no `=` (expected SECTION.KEY=LIST, e.g. --vary motion.gap=0.001,0.005)")
        })?;
        let key = key.trim();
        let reserved = [
            ("boundary.radius_ratio", "--r"),
            ("boundary.modulus_ratio", "--zeta"),
            ("contact.law", "--law"),
        ];
        if let Some((_, flag)) = reserved.iter().find(|(k, _)| key.starts_with(k)) {
            return Err(anyhow!(
                "--vary `{v}`: `{key}` is swept with {flag}, not --vary"
            ));
        }
        let mut values = Vec::new();
        for item in list.split(',').map(str::trim) {
            let lower = item.to_ascii_lowercase();
            if lower.starts_with("log:") || lower.starts_with("lin:") {
                values.extend(
                    lists::numbers("--vary", item)?
                        .into_iter()
                        .map(|x| x.to_string()),
                );
            } else if item.is_empty() {
                return Err(anyhow!("malformed --vary `{v}`: an empty value"));
            } else {
                values.push(item.to_string());
            }
        }
        if combos.len() as u128 * values.len() as u128 > MAX_CASES {
            return Err(anyhow!(
                "--vary: {} combinations of the --vary values; at most {MAX_CASES} cases are \
                 allowed (every case is kept in memory): use fewer values",
                combos.len() as u128 * values.len() as u128
            ));
        }
        combos = combos
            .into_iter()
            .flat_map(|c| {
                values.iter().map(move |x| {
                    let mut c = c.clone();
                    c.push(format!("{key}={x}"));
                    c
                })
            })
            .collect();
    }
    combos
        .into_iter()
        .map(|sets| {
            let scenario = args.scenario.load_with(&sets)?.resolved();
            Ok(Variant {
                label: sets.join(", "),
                scenario,
            })
        })
        .collect()
}

fn spec(args: &SweepArgs) -> Result<SweepSpec> {
    Ok(SweepSpec {
        radius_ratios: lists::ratios("--r", &args.r)?,
        modulus_ratios: lists::ratios("--zeta", &args.zeta)?,
        laws: match &args.law {
            Some(l) => lists::laws("--law", l)?,
            None => Vec::new(),
        },
        variants: variants(args)?,
    })
}

/// The most cases a sweep may have: each keeps its runs and references in
/// memory (1000 × 1000 cases took 3.7 GB), so 1e5 stay below ~0.4 GB.
pub const MAX_CASES: u128 = 100_000;

/// Refuses (exit 2) a grid of more than [`MAX_CASES`] cases, before
/// anything is allocated for it.
fn check_size(spec: &SweepSpec) -> CliResult {
    let laws = if spec.laws.is_empty() {
        1
    } else {
        spec.laws.len() as u128
    };
    let variants = spec.variants.len() as u128;
    let cases =
        variants * laws * spec.radius_ratios.len() as u128 * spec.modulus_ratios.len() as u128;
    if cases <= MAX_CASES {
        return Ok(());
    }
    Err(CliError::input(anyhow!(
        "the sweep has {cases} cases ({} values of --r × {} of --zeta × {} law(s) × {} \
         --vary combination(s)); at most {MAX_CASES} are allowed (every case is kept in memory): \
         use fewer values, e.g. log:A:B:N with a smaller N",
        spec.radius_ratios.len(),
        spec.modulus_ratios.len(),
        laws,
        variants
    )))
}

pub fn run(args: &SweepArgs) -> CliResult {
    if args.plot && args.out.is_none() {
        return Err(CliError::input(anyhow!(
            "--plot writes figures into the output directory: give --out DIR"
        )));
    }
    let spec = spec(args).map_err(CliError::input)?;
    check_size(&spec)?;
    let total = spec.cases().len();
    let bar = progress::counter(total, args.quiet, "cases");
    let result = sweep(&spec, &|done, _| {
        if let Some(b) = &bar {
            b.set_position(done as u64);
        }
    });
    if let Some(b) = bar {
        b.finish_and_clear();
    }
    let result = result.map_err(|e| match e {
        SweepError::Input { .. } | SweepError::Empty(_) => CliError::input(e),
        e => CliError::failed(e),
    })?;

    let mut written = Vec::new();
    if let Some(dir) = &args.out {
        let mut out = AtomicDir::create(dir).map_err(CliError::failed)?;
        out.write("sweep.csv", |w| write_csv(&result, w))
            .map_err(CliError::failed)?;
        out.write("sweep.json", |w| {
            serde_json::to_writer_pretty(&mut *w, &result)?;
            Ok(writeln!(w)?)
        })
        .map_err(CliError::failed)?;
        written = out.commit().map_err(CliError::failed)?;
        if args.plot {
            written.extend(figures(&result, dir).map_err(CliError::failed)?);
        }
    }

    let mut stdout = std::io::stdout().lock();
    if args.json {
        let text = serde_json::to_string_pretty(&result).map_err(CliError::failed)?;
        writeln!(stdout, "{text}").map_err(CliError::failed)?;
    } else {
        writeln!(stdout, "{}", table(&result)).map_err(CliError::failed)?;
        writeln!(
            stdout,
            "exact values over the exact rigid half-space (r = ζ = ∞) of the same law; \
             integrator error = largest |integrator/exact − 1| of T_c, h_max, a_max, F_max, v_r (first contact)"
        )
        .map_err(CliError::failed)?;
        for path in written {
            writeln!(stdout, "wrote {}", path.display()).map_err(CliError::failed)?;
        }
    }
    stdout.flush().map_err(CliError::failed)?;
    Ok(())
}

fn table(result: &SweepResult) -> Table {
    let many = result.variants.len() > 1;
    let mut t = Table::new();
    t.load_preset(presets::UTF8_FULL_CONDENSED);
    let mut header = vec![];
    if many {
        header.push("variant");
    }
    header.extend([
        "law",
        "r",
        "ζ",
        "h_max/h_max∞",
        "T_c/T_c∞",
        "a_max/a_max∞",
        "h_max (nm)",
        "T_c (µs)",
        "integrator error",
    ]);
    t.set_header(header);
    for c in &result.cases {
        let f = c.first();
        let mut row = vec![];
        if many {
            row.push(result.variants[c.key.variant].label.clone());
        }
        row.extend([
            c.key.law.name(),
            lists::show(c.key.radius_ratio),
            lists::show(c.key.modulus_ratio),
            sig(f.exact_normalised.max_overlap, 7),
            sig(f.exact_normalised.duration, 7),
            sig(f.exact_normalised.max_acceleration, 7),
            sig(f.exact.max_overlap * 1e9, 6),
            sig(f.exact.duration * 1e6, 6),
            format!("{:.1e}", f.relative_error.max_abs()),
        ]);
        t.add_row(row);
    }
    let first = usize::from(many) + 1;
    for i in first..first + 8 {
        if let Some(col) = t.column_mut(i) {
            col.set_cell_alignment(CellAlignment::Right);
        }
    }
    t
}

type Getter = fn(&Values) -> f64;

/// (name, unit, value) of the CSV columns.
const FIELDS: [(&str, &str, Getter); 5] = [
    ("duration", "s", |v| v.duration),
    ("max_overlap", "m", |v| v.max_overlap),
    ("max_acceleration", "m_s2", |v| v.max_acceleration),
    ("max_force", "N", |v| v.max_force),
    ("rebound_velocity", "m_s", |v| v.rebound_velocity),
];

fn ratio_text(x: f64) -> String {
    if x.is_infinite() {
        "inf".into()
    } else {
        exact(x)
    }
}

/// sweep.csv: one row per case and contact; SI values, the normalised ones
/// are ratios (1).
fn write_csv(result: &SweepResult, w: &mut dyn Write) -> Result<()> {
    let mut csv = csv::Writer::from_writer(w);
    let mut header: Vec<String> = [
        "variant",
        "variant_label",
        "law",
        "r",
        "zeta",
        "contact",
        "steps",
    ]
    .iter()
    .map(|s| s.to_string())
    .collect();
    for (name, unit, _) in FIELDS {
        header.push(format!("{name}_{unit}_integrator"));
        header.push(format!("{name}_{unit}_exact"));
        header.push(format!("{name}_normalised_integrator"));
        header.push(format!("{name}_normalised_exact"));
        header.push(format!("{name}_relative_error"));
    }
    csv.write_record(&header)?;
    for c in &result.cases {
        for k in &c.contacts {
            let mut row = vec![
                c.key.variant.to_string(),
                result.variants[c.key.variant].label.clone(),
                c.key.law.name(),
                ratio_text(c.key.radius_ratio),
                ratio_text(c.key.modulus_ratio),
                k.contact.to_string(),
                c.steps.to_string(),
            ];
            for (_, _, get) in FIELDS {
                row.push(exact(get(&k.numerical)));
                row.push(exact(get(&k.exact)));
                row.push(exact(get(&k.numerical_normalised)));
                row.push(exact(get(&k.exact_normalised)));
                row.push(exact(get(&k.relative_error)));
            }
            csv.write_record(&row)?;
        }
    }
    csv.flush()?;
    Ok(())
}

/// The normalised quantity's axis label.
pub fn normalised_label(q: Quantity) -> &'static str {
    match q {
        Quantity::MaxOverlap => "h_max / h_max(r = ζ = ∞)  (1)",
        Quantity::Duration => "T_c / T_c(r = ζ = ∞)  (1)",
        Quantity::MaxAcceleration => "a_max / a_max(r = ζ = ∞)  (1)",
    }
}

fn law_file_name(law: ContactLawKind) -> String {
    match law {
        ContactLawKind::Power(a) => format!("power{a}"),
        other => other.name(),
    }
}

fn finite_sorted(xs: impl Iterator<Item = f64>) -> Vec<f64> {
    let mut v: Vec<f64> = xs.filter(|x| x.is_finite()).collect();
    v.sort_by(f64::total_cmp);
    v.dedup();
    v
}

/// Legend entries that explain the marks once: lines exact, points integrator.
pub fn style_legend(series: &mut Vec<Series>, numerical: &str) {
    series.push(Series::new("lines: exact reference", vec![], Mark::Line, 7));
    series.push(Series::new(numerical, vec![], Mark::Points, 7));
}

/// Figures of h_max, T_c, a_max (normalised) against r (one curve per ζ)
/// and against ζ (one curve per r), per variant and law.
fn figures(result: &SweepResult, dir: &Path) -> Result<Vec<PathBuf>> {
    let mut written = Vec::new();
    let rs = finite_sorted(result.cases.iter().map(|c| c.key.radius_ratio));
    let zs = finite_sorted(result.cases.iter().map(|c| c.key.modulus_ratio));
    let many = result.variants.len() > 1;
    let mut combos: Vec<(usize, ContactLawKind)> = Vec::new();
    for c in &result.cases {
        if !combos.contains(&(c.key.variant, c.key.law)) {
            combos.push((c.key.variant, c.key.law));
        }
    }
    let all_r: Vec<f64> = {
        let mut v: Vec<f64> = result.cases.iter().map(|c| c.key.radius_ratio).collect();
        v.sort_by(f64::total_cmp);
        v.dedup();
        v
    };
    let all_z: Vec<f64> = {
        let mut v: Vec<f64> = result.cases.iter().map(|c| c.key.modulus_ratio).collect();
        v.sort_by(f64::total_cmp);
        v.dedup();
        v
    };
    for (variant, law) in combos {
        let suffix = if many {
            format!("_v{variant}")
        } else {
            String::new()
        };
        let title_variant = if many {
            format!(" ({})", result.variants[variant].label)
        } else {
            String::new()
        };
        for q in Quantity::ALL {
            // (x axis name, x values, curve parameter values, is_r_axis)
            for (xname, xs, others, along_r) in
                [("r", &rs, &all_z, true), ("zeta", &zs, &all_r, false)]
            {
                if xs.len() < 2 {
                    continue;
                }
                let mut series = Vec::new();
                for (i, &o) in others.iter().enumerate() {
                    let pick = |x: f64| {
                        let (r, z) = if along_r { (x, o) } else { (o, x) };
                        result.find(variant, law, r, z).map(|c| *c.first())
                    };
                    let exact: Vec<(f64, f64)> = xs
                        .iter()
                        .filter_map(|&x| pick(x).map(|c| (x, c.exact_normalised.get(q))))
                        .collect();
                    let num: Vec<(f64, f64)> = xs
                        .iter()
                        .filter_map(|&x| pick(x).map(|c| (x, c.numerical_normalised.get(q))))
                        .collect();
                    let label = format!("{} = {}", if along_r { "ζ" } else { "r" }, lists::show(o));
                    series.push(Series::new(label, exact, Mark::Line, i));
                    series.push(Series::new("", num, Mark::Points, i));
                }
                style_legend(&mut series, "points: integrator");
                let x_log = xs[0] > 0.0 && xs[xs.len() - 1] / xs[0] >= 20.0;
                let fig = Figure {
                    title: format!(
                        "{} against {}, {} law{}",
                        q.symbol(),
                        if along_r { "r" } else { "ζ" },
                        law.name(),
                        title_variant
                    ),
                    x_label: if along_r {
                        "boundary radius ratio r = R_b/R_m  (1)".into()
                    } else {
                        "boundary modulus ratio ζ = E_b/E_m  (1)".into()
                    },
                    y_label: normalised_label(q).into(),
                    x_log,
                    y_log: false,
                    series,
                };
                let stem = dir.join(format!(
                    "{}_vs_{xname}_{}{suffix}",
                    q.key(),
                    law_file_name(law)
                ));
                written.extend(fig.write(&stem)?);
            }
        }
    }
    Ok(written)
}
