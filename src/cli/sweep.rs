//! `dembound sweep`: the grid of section 5 over r, ζ, laws and any other
//! scenario keys, integrator beside the exact reference, normalised by the
//! rigid half-space.

use super::lists;
use super::{CliError, CliResult};
use crate::output::boundary;
use crate::output::files::AtomicDir;
use crate::output::format::{exact, sig};
use crate::output::progress;
use crate::output::table::{Cell, Column, Format, Table, Unit};
use crate::plot::{infinity_position, Figure, Mark, Series, Shape, BLACK, SHAPES};
use crate::scenario_file::ScenarioArgs;
use anyhow::{anyhow, Result};
use clap::Args;
use dembound_core::contact::ContactLawKind;
use dembound_core::study::sweep::{sweep, SweepResult, SweepSpec, Values, Variant};
use dembound_core::study::Quantity;
use dembound_core::Error;
use std::io::Write;
use std::path::PathBuf;

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

    /// Contact laws: `linear,hertz` or `power=1.25` (the dissipative laws have
    /// no elastic reference to normalise by: see `restitution`) [default: the
    /// scenario's]
    #[arg(long, value_name = "LIST")]
    pub law: Option<String>,

    /// Also vary another scenario key over a list, e.g. `--vary motion.gap=0.001,0.005`
    /// (repeatable: every combination is run)
    #[arg(long, value_name = "SECTION.KEY=LIST")]
    pub vary: Vec<String>,

    /// Write sweep.csv and sweep.json (and the figures with --plot) into DIR
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,

    /// Figures of the deviation |q/q(r = ζ = ∞) − 1| of h_max, T_c and a_max
    /// against r and ζ, log scale, with the tolerance line (needs --out)
    #[arg(long)]
    pub plot: bool,

    /// The tolerance line drawn in the --plot figures: a fraction (0.01) or
    /// a percentage (1%); default 1%
    #[arg(long, value_name = "T", allow_hyphen_values = true)]
    pub tolerance: Option<String>,

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
            Some(l) => lists::laws_for("--law", l, "sweep")?,
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
    let tolerance = match &args.tolerance {
        Some(t) => super::recommend::tolerance(t).map_err(CliError::input)?,
        None => DEFAULT_TOLERANCE,
    };
    let spec = spec(args).map_err(CliError::input)?;
    check_size(&spec)?;
    let out = match &args.out {
        Some(dir) => Some(super::output_dir(dir, "sweep")?),
        None => None,
    };
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
        Error::CaseInput { .. } | Error::NothingToSweep(_) => CliError::input(e),
        e => CliError::failed(e),
    })?;

    let mut written = Vec::new();
    if let Some(mut out) = out {
        out.write("sweep.csv", |w| write_csv(&result, w))
            .map_err(CliError::failed)?;
        let json = sweep_json(&result).map_err(CliError::failed)?;
        out.write("sweep.json", |w| {
            serde_json::to_writer_pretty(&mut *w, &json)?;
            Ok(writeln!(w)?)
        })
        .map_err(CliError::failed)?;
        if args.plot {
            figures(&result, tolerance, &mut out).map_err(CliError::failed)?;
        }
        written = out.commit().map_err(CliError::failed)?;
    }

    let mut stdout = std::io::stdout().lock();
    if args.json {
        let json = sweep_json(&result).map_err(CliError::failed)?;
        write!(stdout, "{}", super::json_text(&json)?).map_err(CliError::failed)?;
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

/// The sweep as JSON: every case's key and every variant's scenario with
/// the boundary in SI (`boundary_radius`, m; `boundary_youngs_modulus`, Pa)
/// beside r and ζ.
fn sweep_json(result: &SweepResult) -> Result<serde_json::Value> {
    let mut v = serde_json::to_value(result)?;
    if let Some(cases) = v.get_mut("cases").and_then(|c| c.as_array_mut()) {
        for (json, case) in cases.iter_mut().zip(&result.cases) {
            let s = &result.variants[case.key.variant].scenario;
            let si = boundary::SiBoundary::new(s, case.key.radius_ratio, case.key.modulus_ratio);
            if let (Some(key), serde_json::Value::Object(si)) = (
                json.get_mut("key").and_then(|k| k.as_object_mut()),
                serde_json::to_value(si)?,
            ) {
                key.extend(si);
            }
        }
    }
    if let Some(variants) = v.get_mut("variants").and_then(|c| c.as_array_mut()) {
        for (json, variant) in variants.iter_mut().zip(&result.variants) {
            #[derive(serde::Serialize)]
            struct S<'a>(
                #[serde(serialize_with = "boundary::serialize_scenario")]
                &'a dembound_core::bounce::Scenario,
            );
            if let Some(slot) = json.get_mut("scenario") {
                *slot = serde_json::to_value(S(&variant.scenario))?;
            }
        }
    }
    Ok(v)
}

/// The tolerance line of the figures when `--tolerance` is not given.
pub const DEFAULT_TOLERANCE: f64 = 0.01;

fn table(result: &SweepResult) -> Table {
    let many = result.variants.len() > 1;
    let mut columns = Vec::new();
    if many {
        columns.push(Column::text("variant"));
    }
    columns.extend([
        Column::text("law"),
        Column::text("r").right(),
        Column::text("ζ").right(),
        Column::text("R_b (m)").right(),
        Column::text("E_b (Pa)").right(),
        Column::quantity("h_max/h_max∞", Unit::ONE, 7),
        Column::quantity("T_c/T_c∞", Unit::ONE, 7),
        Column::quantity("a_max/a_max∞", Unit::ONE, 7),
        Column::quantity("h_max", Unit::METRE, 6),
        Column::quantity("T_c", Unit::SECOND, 6),
        Column::number("integrator error", Unit::NONE, Format::Sci(2)),
    ]);
    let mut t = Table::new(columns).with_keys(usize::from(many) + 3);
    for c in &result.cases {
        let f = c.first();
        let s = &result.variants[c.key.variant].scenario;
        let mut row = vec![];
        if many {
            row.push(Cell::text(&result.variants[c.key.variant].label));
        }
        row.extend([
            Cell::text(c.key.law.name()),
            Cell::text(lists::show(c.key.radius_ratio)),
            Cell::text(lists::show(c.key.modulus_ratio)),
            Cell::text(boundary::si_text(boundary::radius(s, c.key.radius_ratio))),
            Cell::text(boundary::si_text(boundary::youngs_modulus(
                s,
                c.key.modulus_ratio,
            ))),
            f.exact_normalised.max_overlap.into(),
            f.exact_normalised.duration.into(),
            f.exact_normalised.max_acceleration.into(),
            f.exact.max_overlap.into(),
            f.exact.duration.into(),
            f.relative_error.max_abs().into(),
        ]);
        t.push(row);
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
        "boundary_radius_m",
        "boundary_youngs_modulus_Pa",
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
        let s = &result.variants[c.key.variant].scenario;
        for k in &c.contacts {
            let mut row = vec![
                c.key.variant.to_string(),
                result.variants[c.key.variant].label.clone(),
                c.key.law.name(),
                ratio_text(c.key.radius_ratio),
                ratio_text(c.key.modulus_ratio),
                ratio_text(boundary::radius(s, c.key.radius_ratio)),
                ratio_text(boundary::youngs_modulus(s, c.key.modulus_ratio)),
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

/// The deviation's axis label.
pub fn deviation_label(q: Quantity) -> String {
    let s = q.symbol();
    format!("deviation |{s} / {s}(r = ζ = ∞) − 1|  (1), log scale")
}

fn law_file_name(law: ContactLawKind) -> String {
    match law {
        ContactLawKind::Power(a) => format!("power{a}"),
        other => other.name(),
    }
}

fn sorted(xs: impl Iterator<Item = f64>) -> Vec<f64> {
    let mut v: Vec<f64> = xs.collect();
    v.sort_by(f64::total_cmp);
    v.dedup();
    v
}

/// A percentage for labels: `1 %`, `0.5 %`.
fn percent_text(x: f64) -> String {
    let t = sig(x * 100.0, 3);
    let t = if t.contains('.') && !t.contains('e') {
        t.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        t
    };
    format!("{t} %")
}

/// Figures of the deviation |q/q(∞, ∞) − 1| of h_max, T_c and a_max
/// against r (one curve per ζ) and against ζ (one curve per r), per
/// variant and law, log scale, the tolerance as a dashed line, ∞ drawn
/// beyond the largest finite value; staged in `out` (SVG and PNG).
fn figures(result: &SweepResult, tolerance: f64, out: &mut AtomicDir) -> Result<()> {
    let many = result.variants.len() > 1;
    let mut combos: Vec<(usize, ContactLawKind)> = Vec::new();
    for c in &result.cases {
        if !combos.contains(&(c.key.variant, c.key.law)) {
            combos.push((c.key.variant, c.key.law));
        }
    }
    let all_r = sorted(result.cases.iter().map(|c| c.key.radius_ratio));
    let all_z = sorted(result.cases.iter().map(|c| c.key.modulus_ratio));
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
            for (xname, xs, others, along_r) in
                [("r", &all_r, &all_z, true), ("zeta", &all_z, &all_r, false)]
            {
                if xs.len() < 2 {
                    continue;
                }
                let finite: Vec<f64> = xs.iter().copied().filter(|x| x.is_finite()).collect();
                let x_log = finite.first().is_some_and(|&lo| {
                    lo > 0.0 && (finite.len() < 2 || finite[finite.len() - 1] / lo >= 20.0)
                });
                let has_inf = xs.iter().any(|x| x.is_infinite());
                let inf_at = infinity_position(&finite, x_log);
                let at = |x: f64| if x.is_infinite() { inf_at } else { x };
                let mut series = Vec::new();
                for (i, &o) in others.iter().enumerate() {
                    let pick = |x: f64| {
                        let (r, z) = if along_r { (x, o) } else { (o, x) };
                        result.find(variant, law, r, z).map(|c| *c.first())
                    };
                    let deviation = |v: &Values| (v.get(q) - 1.0).abs();
                    let exact: Vec<(f64, f64)> = xs
                        .iter()
                        .filter_map(|&x| pick(x).map(|c| (at(x), deviation(&c.exact_normalised))))
                        .collect();
                    let num: Vec<(f64, f64)> = xs
                        .iter()
                        .filter_map(|&x| {
                            pick(x).map(|c| (at(x), deviation(&c.numerical_normalised)))
                        })
                        .collect();
                    let label = format!("{} = {}", if along_r { "ζ" } else { "r" }, lists::show(o));
                    // Black is kept for the notes of the legend.
                    let color = if i >= BLACK { i + 1 } else { i };
                    let shape = SHAPES[i % SHAPES.len()];
                    series.push(Series::new(label, exact, Mark::LineShape(shape), color));
                    series.push(Series::new("", num, Mark::Shape(Shape::Cross), color));
                }
                let x_ends = (at(xs[0]), at(xs[xs.len() - 1]));
                series.push(Series::new(
                    format!("tolerance T = {}", percent_text(tolerance)),
                    vec![(x_ends.0, tolerance), (x_ends.1, tolerance)],
                    Mark::Dashed,
                    6,
                ));
                series.push(Series::new(
                    "lines, markers: exact",
                    vec![],
                    Mark::LineShape(Shape::Circle),
                    BLACK,
                ));
                series.push(Series::new(
                    "×: integrator",
                    vec![],
                    Mark::Shape(Shape::Cross),
                    BLACK,
                ));
                let fig = Figure {
                    title: format!(
                        "Deviation of {} from the rigid half-space against {}, {} law{}",
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
                    y_label: deviation_label(q),
                    x_log,
                    y_log: true,
                    series,
                    x_infinity: has_inf.then_some(inf_at),
                    legend_outside: true,
                };
                let stem = format!("{}_vs_{xname}_{}{suffix}", q.key(), law_file_name(law));
                fig.write_into(out, &stem)?;
            }
        }
    }
    Ok(())
}
