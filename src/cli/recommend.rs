//! `dembound recommend`: the smallest boundary ζ (or r) that keeps h_max,
//! T_c or a_max within a tolerance of a reference (the rigid half-space, or
//! a flat wall of the boundary's own material), the trade-off between r and
//! ζ, or the deviations at given (r, ζ). Every answer in both forms: the
//! ratios r, ζ and the boundary's radius (m) and Young's modulus (Pa).

use super::lists;
use super::{CliError, CliResult};
use crate::output::boundary::{self, SiBoundary};
use crate::output::format::sig;
use crate::scenario_file::ScenarioArgs;
use anyhow::{anyhow, bail, Result};
use clap::{Args, ValueEnum};
use comfy_table::{presets, CellAlignment, Table};
use dembound_core::bounce::Scenario;
use dembound_core::contact::ContactLawKind;
use dembound_core::study::recommend::{
    check_tolerance, deviations_from, poisson_factor, smallest_against, tradeoff, Deviations,
    Limit, Outcome, Reference, Tradeoff, TradeoffPoint, MAX_TOLERANCE, MIN_TOLERANCE,
    SMALLEST_RATIO,
};
use dembound_core::study::{Axis, Quantity};
use dembound_core::Error;
use serde::Serialize;
use std::io::Write;

/// `--reference`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum ReferenceArg {
    /// The rigid half-space r = ζ = ∞ (the paper's normalisation)
    Rigid,
    /// A flat wall (r = ∞) of the boundary's own material (its E_b, ν_b): how
    /// large must a boundary sphere be to act like a flat plate of it; only r varies
    HalfSpace,
}

impl ReferenceArg {
    fn core(self) -> Reference {
        match self {
            ReferenceArg::Rigid => Reference::Rigid,
            ReferenceArg::HalfSpace => Reference::HalfSpace,
        }
    }
}

#[derive(Debug, Args)]
pub struct RecommendArgs {
    #[command(flatten)]
    pub scenario: ScenarioArgs,

    /// Largest allowed deviation |q/q_ref − 1|: a fraction (0.01) or a
    /// percentage (1%), 1e-8 ≤ T ≤ 100
    #[arg(long, value_name = "T", allow_hyphen_values = true)]
    pub tolerance: Option<String>,

    /// What q is compared with: `rigid` (the rigid half-space r = ζ = ∞) or
    /// `half-space` (a flat wall r = ∞ of the boundary's own material, ζ from
    /// --zeta or the scenario's boundary.youngs_modulus / modulus_ratio, ν_b
    /// from the scenario; only r is solved for)
    #[arg(
        long,
        value_enum,
        value_name = "REF",
        default_value = "rigid",
        hide_possible_values = true
    )]
    pub reference: ReferenceArg,

    /// Contact laws: `linear,hertz` or `power=1.25` [default: linear,hertz]
    #[arg(long, value_name = "LIST")]
    pub law: Option<String>,

    /// Quantities: max_overlap (h_max), duration (T_c), max_acceleration
    /// (a_max), comma-separated [default: all three]
    #[arg(long, value_name = "LIST")]
    pub quantity: Option<String>,

    /// Boundary radius ratios r = R_b/R_m: `100`, `1,10,inf`, `log:1:1000:7`.
    /// With --tolerance: the smallest ζ for each r
    #[arg(long = "r", value_name = "LIST", allow_hyphen_values = true)]
    pub r: Option<String>,

    /// Boundary modulus ratios ζ = E_b/E_m (same syntax as --r). With
    /// --tolerance: the smallest r for each ζ
    #[arg(long = "zeta", value_name = "LIST", allow_hyphen_values = true)]
    pub zeta: Option<String>,

    /// Print one JSON object to stdout instead of the tables
    #[arg(long)]
    pub json: bool,
}

/// `0.01` or `1%`, within the range the numerics resolve.
pub(crate) fn tolerance(text: &str) -> Result<f64> {
    let t = text.trim();
    let (num, scale) = match t.strip_suffix('%') {
        Some(n) => (n.trim(), 0.01),
        None => (t, 1.0),
    };
    let allowed = format!(
        "{MIN_TOLERANCE:e} ≤ T ≤ {MAX_TOLERANCE}, a fraction such as 0.01 or a percentage \
         such as 1%; below {MIN_TOLERANCE:e} the deviation q/q_ref − 1 is below what the \
         exact model and the integrator resolve"
    );
    let x = num.parse::<f64>().ok().map(|x| x * scale);
    match x {
        Some(x) if check_tolerance(x).is_ok() => {
            if scale == 1.0 && x > 0.1 {
                eprintln!(
                    "warning: --tolerance {t} is read as a fraction, {} %; write {t}% for {t} percent",
                    sig(x * 100.0, 4)
                );
            }
            Ok(x)
        }
        _ => bail!("invalid value for `--tolerance`: `{t}` (allowed: {allowed})"),
    }
}

pub(crate) fn quantities(text: Option<&str>) -> Result<Vec<Quantity>> {
    match text {
        None => Ok(Quantity::ALL.to_vec()),
        Some(t) => t
            .split(',')
            .map(|q| {
                Quantity::parse(q).ok_or_else(|| {
                    anyhow!(
                        "invalid value for `--quantity`: `{}` (allowed: max_overlap (h_max), duration (T_c), max_acceleration (a_max))",
                        q.trim()
                    )
                })
            })
            .collect(),
    }
}

/// A limit with the boundary of its answer in SI (none when not found).
#[derive(Debug, Serialize)]
struct LimitJson<'a> {
    #[serde(flatten)]
    limit: &'a Limit,
    #[serde(flatten)]
    si: Option<SiBoundary>,
}

/// A point of a trade-off curve with its SI boundary.
#[derive(Debug, Serialize)]
struct PointJson<'a> {
    #[serde(flatten)]
    point: &'a TradeoffPoint,
    #[serde(flatten)]
    si: SiBoundary,
}

#[derive(Debug, Serialize)]
struct TradeoffJson<'a> {
    law: ContactLawKind,
    quantity: Quantity,
    tolerance: f64,
    smallest_radius_ratio: f64,
    curve: Vec<PointJson<'a>>,
    pick: PointJson<'a>,
    share: f64,
    pick_rule: &'static str,
}

#[derive(Debug, Serialize)]
struct DeviationsJson<'a> {
    #[serde(flatten)]
    deviations: &'a Deviations,
    #[serde(flatten)]
    si: SiBoundary,
}

/// The rule by which the trade-off pick is chosen, for reports.
pub const PICK_RULE: &str = "balanced: r alone and ζ alone each cost the same share of the \
    tolerance, (1 + T_s)² = 1 + T (h_max, T_c) or (1 − T_s)² = 1 − T (a_max); to first order \
    in T the point of the curve with the smallest r·ζ";

pub(crate) fn core_error(e: Error) -> CliError {
    match e {
        Error::Input {
            field,
            value,
            allowed,
        } => {
            let flag = match field.as_str() {
                "zeta" => "--zeta".to_string(),
                other if other.contains('.') => other.to_string(),
                other => format!("--{other}"),
            };
            CliError::input(anyhow!(
                "invalid value for `{flag}`: {value} (allowed: {allowed})"
            ))
        }
        // A run or reference of the study refused the scenario at the
        // (r, ζ) asked (e.g. a contact gravity dominates on a tiny soft
        // boundary): bad input too, with the study's context.
        Error::Simulation(ref inner) | Error::Exact(ref inner)
            if matches!(**inner, Error::Input { .. }) =>
        {
            CliError::input(anyhow!("{e}"))
        }
        e => CliError::failed(e),
    }
}

/// What was asked.
enum Question {
    /// Smallest `solved` for each value of the other.
    Limits { solved: Axis, others: Vec<f64> },
    /// Both free (rigid reference): the axis limits and the trade-off.
    Tradeoff,
    /// Deviations at every (r, ζ).
    Deviations { rs: Vec<f64>, zetas: Vec<f64> },
}

fn question(args: &RecommendArgs, base: &Scenario, t: Option<f64>) -> Result<Question> {
    let rs = args
        .r
        .as_deref()
        .map(|t| lists::ratios("--r", t))
        .transpose()?;
    let zetas = args
        .zeta
        .as_deref()
        .map(|t| lists::ratios("--zeta", t))
        .transpose()?;
    let half = args.reference == ReferenceArg::HalfSpace;
    // Against a flat wall of the boundary's material, ζ is the boundary's.
    let zetas = match (half, zetas) {
        (true, None) => Some(vec![base.boundary.modulus_ratio]),
        (_, z) => z,
    };
    Ok(match (t, rs, zetas) {
        (Some(_), Some(_), Some(_)) if half => bail!(
            "--reference half-space solves for r (the flat wall has the boundary's own ζ): \
             give no --r with --tolerance"
        ),
        (Some(_), Some(_), Some(_)) => bail!(
            "with --tolerance give at most one of --r and --zeta (the other is solved for); \
             without --tolerance, --r and --zeta report the deviations"
        ),
        (Some(_), Some(rs), None) => Question::Limits {
            solved: Axis::Modulus,
            others: rs,
        },
        (Some(_), None, Some(zs)) => Question::Limits {
            solved: Axis::Radius,
            others: zs,
        },
        (Some(_), None, None) => Question::Tradeoff,
        (None, Some(rs), Some(zetas)) => Question::Deviations { rs, zetas },
        (None, _, _) => bail!(
            "give --tolerance T (with at most one of --r, --zeta) for limits, or both --r and \
             --zeta for deviations"
        ),
    })
}

pub fn run(args: &RecommendArgs) -> CliResult {
    let base = args.scenario.load().map_err(CliError::input)?.resolved();
    let laws = match &args.law {
        Some(l) => lists::laws_for("--law", l, "recommend").map_err(CliError::input)?,
        None => vec![ContactLawKind::Linear, ContactLawKind::Hertz],
    };
    let qs = quantities(args.quantity.as_deref()).map_err(CliError::input)?;
    let t = args
        .tolerance
        .as_deref()
        .map(tolerance)
        .transpose()
        .map_err(CliError::input)?;
    let question = question(args, &base, t).map_err(CliError::input)?;
    let reference = args.reference.core();

    let mut limits = Vec::new();
    let mut tradeoffs = Vec::new();
    let mut deviations = Vec::new();
    match (&question, t) {
        (Question::Limits { solved, others }, Some(t)) => {
            for &law in &laws {
                for &q in &qs {
                    for &other in others {
                        limits.push(
                            smallest_against(&base, law, q, t, *solved, other, reference)
                                .map_err(core_error)?,
                        );
                    }
                }
            }
        }
        (Question::Tradeoff, Some(t)) => {
            let inf = f64::INFINITY;
            for &law in &laws {
                for &q in &qs {
                    for axis in [Axis::Modulus, Axis::Radius] {
                        limits.push(
                            smallest_against(&base, law, q, t, axis, inf, reference)
                                .map_err(core_error)?,
                        );
                    }
                    if let Some(tr) = tradeoff(&base, law, q, t).map_err(core_error)? {
                        tradeoffs.push(tr);
                    }
                }
            }
        }
        (Question::Deviations { rs, zetas }, _) => {
            for &law in &laws {
                for &r in rs {
                    for &z in zetas {
                        let mut d =
                            deviations_from(&base, law, r, z, reference).map_err(core_error)?;
                        d.quantities.retain(|x| qs.contains(&x.quantity));
                        deviations.push(d);
                    }
                }
            }
        }
        _ => {}
    }

    let mut out = String::new();
    if args.json {
        let value = json(&base, reference, t, &limits, &tradeoffs, &deviations)
            .map_err(CliError::failed)?;
        out = super::json_text(&value)?;
    } else {
        out.push_str(&context(&base, reference, &question));
        if let Some(t) = t {
            out.push_str(&format!("{}\n", limits_table(&base, &limits)));
            out.push_str(&format!(
                "tolerance T = {} % on |q(r, ζ)/{} − 1|; limits from the exact model \
                 (Brent), checked by the integrator ({}, η = {}) at the limit; the closed \
                 forms are in the ratio solved for\n",
                sig(t * 100.0, 4),
                reference.symbol(),
                base.integration.scheme.name(),
                base.integration
                    .eta
                    .map(|e| e.to_string())
                    .unwrap_or_else(|| "given Δt".into())
            ));
            for l in &limits {
                if let Outcome::Unreachable { floor } = l.outcome {
                    out.push_str(&format!(
                        "{} {}: no {} satisfies T: {} = {} alone already gives {} %\n",
                        l.law.name(),
                        l.quantity.symbol(),
                        l.solved.symbol(),
                        l.solved.other().symbol(),
                        lists::show(l.other),
                        sig(floor * 100.0, 4)
                    ));
                }
            }
            for tr in &tradeoffs {
                out.push_str(&tradeoff_text(&base, tr));
            }
            for l in &limits {
                if let Some(line) =
                    answer(l).and_then(|(r, _)| super::recommend_holes::hole_line(r))
                {
                    out.push_str(&line);
                }
            }
        } else {
            out.push_str(&format!("{}\n", deviations_table(&base, &deviations)));
            out.push_str(&format!(
                "deviation = |q(r, ζ)/{} − 1|, exact and by the integrator against its own reference run\n",
                reference.symbol()
            ));
        }
    }
    let mut stdout = std::io::stdout().lock();
    stdout.write_all(out.as_bytes()).map_err(CliError::failed)?;
    stdout.flush().map_err(CliError::failed)?;
    Ok(())
}

/// The lines that say what is compared with what, in SI.
fn context(base: &Scenario, reference: Reference, question: &Question) -> String {
    let p = &base.particle;
    let nu_b = base.boundary.poisson_ratio.unwrap_or(p.poisson_ratio);
    let mut s = format!(
        "particle: R_m = {} m, E_m = {} Pa, ν_m = {}, ρ = {} kg/m³; impact speed {} m/s; \
         boundary ν_b = {nu_b}\n",
        boundary::si_text(p.radius),
        boundary::si_text(p.youngs_modulus),
        p.poisson_ratio,
        boundary::si_text(p.density),
        sig(base.impact_speed(), 6),
    );
    match reference {
        Reference::Rigid => s.push_str("reference: the rigid half-space (r = ζ = ∞)\n"),
        Reference::HalfSpace => {
            let zetas: Vec<String> = match question {
                Question::Limits { others, .. } => others
                    .iter()
                    .map(|&z| {
                        format!(
                            "ζ = {} ({})",
                            lists::show(z),
                            boundary::modulus_text(boundary::youngs_modulus(base, z))
                        )
                    })
                    .collect(),
                _ => vec!["ζ of each row".into()],
            };
            s.push_str(&format!(
                "reference: a flat wall (r = ∞) of the boundary's own material, {}, ν_b = {nu_b}\n",
                zetas.join("; ")
            ));
        }
    }
    if (poisson_factor(base) - 1.0).abs() > 0.0 {
        s.push_str(&format!(
            "ν_b ≠ ν_m: the closed forms use ζ′ = ζ/c_ν with c_ν = (1 − ν_b²)/(1 − ν_m²) = {} (eq 6)\n",
            sig(poisson_factor(base), 6)
        ));
    }
    s
}

/// (r, ζ) of a limit's answer, when found.
fn answer(l: &Limit) -> Option<(f64, f64)> {
    l.value().map(|v| match l.solved {
        Axis::Modulus => (l.other, v),
        Axis::Radius => (v, l.other),
    })
}

fn point_json<'a>(base: &Scenario, p: &'a TradeoffPoint) -> PointJson<'a> {
    PointJson {
        si: SiBoundary::new(base, p.radius_ratio, p.modulus_ratio),
        point: p,
    }
}

fn json(
    base: &Scenario,
    reference: Reference,
    t: Option<f64>,
    limits: &[Limit],
    tradeoffs: &[Tradeoff],
    deviations: &[Deviations],
) -> Result<serde_json::Value> {
    let mut v = serde_json::json!({ "reference": reference });
    match t {
        Some(t) => {
            v["tolerance"] = serde_json::json!(t);
            let ls: Vec<LimitJson> = limits
                .iter()
                .map(|l| LimitJson {
                    limit: l,
                    si: answer(l).map(|(r, z)| SiBoundary::new(base, r, z)),
                })
                .collect();
            v["limits"] = serde_json::to_value(ls)?;
            if !tradeoffs.is_empty() {
                let trs: Vec<TradeoffJson> = tradeoffs
                    .iter()
                    .map(|tr| TradeoffJson {
                        law: tr.law,
                        quantity: tr.quantity,
                        tolerance: tr.tolerance,
                        smallest_radius_ratio: tr.smallest_radius_ratio,
                        curve: tr.curve.iter().map(|p| point_json(base, p)).collect(),
                        pick: point_json(base, &tr.pick),
                        share: tr.share,
                        pick_rule: PICK_RULE,
                    })
                    .collect();
                v["tradeoffs"] = serde_json::to_value(trs)?;
            }
        }
        None => {
            let ds: Vec<DeviationsJson> = deviations
                .iter()
                .map(|d| DeviationsJson {
                    deviations: d,
                    si: SiBoundary::new(base, d.radius_ratio, d.modulus_ratio),
                })
                .collect();
            v["deviations"] = serde_json::to_value(ds)?;
        }
    }
    Ok(v)
}

fn pct(x: Option<f64>) -> String {
    x.map(|x| format!("{} %", sig(x * 100.0, 6)))
        .unwrap_or_else(|| "–".into())
}

fn value(x: Option<f64>) -> String {
    x.map(|x| sig(x, 8)).unwrap_or_else(|| "–".into())
}

fn right_align(t: &mut Table, columns: std::ops::Range<usize>) {
    for i in columns {
        if let Some(c) = t.column_mut(i) {
            c.set_cell_alignment(CellAlignment::Right);
        }
    }
}

fn limits_table(base: &Scenario, limits: &[Limit]) -> Table {
    let mut t = Table::new();
    t.load_preset(presets::UTF8_FULL_CONDENSED);
    t.set_header(vec![
        "law",
        "quantity",
        "given",
        "smallest",
        "R_b (m)",
        "E_b (Pa)",
        "exact deviation",
        "integrator deviation",
        "closed form, g = 0",
        "closed form with g",
    ]);
    for l in limits {
        let found = match l.outcome {
            Outcome::Found { value } => format!("{} = {}", l.solved.symbol(), sig(value, 8)),
            Outcome::Unreachable { floor } => format!("none ({} % already)", sig(floor * 100.0, 4)),
            // Every value a scenario accepts (r, ζ ≥ 1e-6).
            Outcome::AnyValue => format!("any value ≥ {SMALLEST_RATIO:e}"),
        };
        let (rb, eb) = match answer(l) {
            Some((r, z)) => (
                boundary::si_text(boundary::radius(base, r)),
                boundary::si_text(boundary::youngs_modulus(base, z)),
            ),
            None => ("–".into(), "–".into()),
        };
        t.add_row(vec![
            l.law.name(),
            l.quantity.symbol().to_string(),
            format!("{} = {}", l.solved.other().symbol(), lists::show(l.other)),
            found,
            rb,
            eb,
            pct(l.exact_deviation),
            pct(l.simulated_deviation),
            value(l.gravity_free),
            value(l.closed_form),
        ]);
    }
    right_align(&mut t, 3..10);
    t
}

/// One trade-off curve as a table, and its pick.
fn tradeoff_text(base: &Scenario, tr: &Tradeoff) -> String {
    let mut t = Table::new();
    t.load_preset(presets::UTF8_FULL_CONDENSED);
    t.set_header(vec![
        "",
        "r",
        "smallest ζ",
        "R_b (m)",
        "E_b (Pa)",
        "exact deviation",
        "integrator deviation",
    ]);
    let mut rows: Vec<(bool, &TradeoffPoint)> = tr.curve.iter().map(|p| (false, p)).collect();
    rows.push((true, &tr.pick));
    rows.sort_by(|a, b| a.1.radius_ratio.total_cmp(&b.1.radius_ratio));
    for (pick, p) in rows {
        t.add_row(vec![
            if pick { "pick" } else { "" }.to_string(),
            lists::show(p.radius_ratio),
            sig(p.modulus_ratio, 6),
            boundary::si_text(boundary::radius(base, p.radius_ratio)),
            boundary::si_text(boundary::youngs_modulus(base, p.modulus_ratio)),
            pct(Some(p.exact_deviation)),
            pct(Some(p.simulated_deviation)),
        ]);
    }
    right_align(&mut t, 1..7);
    let p = &tr.pick;
    format!(
        "\n{} {}, T = {} %: the smallest ζ for each r (below r = {} no ζ is enough)\n{t}\n\
         pick: r = {}, ζ = {} ({}, {}): r alone and ζ alone each cost {} % (balanced \
         shares of T; to first order the point of the curve with the smallest r·ζ)\n",
        tr.law.name(),
        tr.quantity.symbol(),
        sig(tr.tolerance * 100.0, 4),
        sig(tr.smallest_radius_ratio, 6),
        sig(p.radius_ratio, 6),
        sig(p.modulus_ratio, 6),
        boundary::radius_text(boundary::radius(base, p.radius_ratio)),
        boundary::modulus_text(boundary::youngs_modulus(base, p.modulus_ratio)),
        sig(tr.share * 100.0, 4),
    )
}

fn deviations_table(base: &Scenario, ds: &[Deviations]) -> Table {
    let mut t = Table::new();
    t.load_preset(presets::UTF8_FULL_CONDENSED);
    t.set_header(vec![
        "law",
        "r",
        "ζ",
        "R_b (m)",
        "E_b (Pa)",
        "quantity",
        "exact deviation",
        "integrator deviation",
    ]);
    for d in ds {
        for q in &d.quantities {
            t.add_row(vec![
                d.law.name(),
                lists::show(d.radius_ratio),
                lists::show(d.modulus_ratio),
                boundary::si_text(boundary::radius(base, d.radius_ratio)),
                boundary::si_text(boundary::youngs_modulus(base, d.modulus_ratio)),
                q.quantity.symbol().to_string(),
                pct(Some(q.exact)),
                pct(Some(q.simulated)),
            ]);
        }
    }
    right_align(&mut t, 6..8);
    t
}
