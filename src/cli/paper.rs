//! `dembound paper`: the paper's section 5 reproduced (Figs 4–8, every
//! number it quotes, the convergence laws, the recommended limits) with
//! Tables 1–2, into a directory with figures, `report.md`, a self-contained
//! `report.html` and `paper.json`.
//!
//! Scaling constants are the Hertz rigid half-space values (ERRATA 13);
//! the indicators are eq 32 on h_max with ζ_max = r_max = 1000 and gravity
//! (ERRATA 14); theory is eq 33 as corrected (ERRATA 15), printed beside.

use super::lists::show;
use super::{CliError, CliResult};
use crate::output::format::sig;
use crate::output::restitution::{restitution_figures, restitution_markdown};
use crate::output::table::{Cell, Column, Format, Table, Unit};
use crate::output::validation;
use crate::plot::{Figure, Mark, Series};
use anyhow::{anyhow, Result};
use base64::engine::general_purpose::STANDARD as BASE64;
use base64::Engine as _;
use clap::Args;
use dembound_core::bounce::{simulate, Observer, Sample, Scenario};
use dembound_core::contact::ContactLawKind;
use dembound_core::exact;
use dembound_core::study::indicators::{
    convergence_exponents, eq33, paper_fit_values, section5_indicators, ExponentFit,
    QuotedIndicator, PAPER_MAX,
};
use dembound_core::study::recommend::{deviations, smallest, Deviations, Limit, Outcome};
use dembound_core::study::restitution::{restitution_sweep, RestitutionSpec, RestitutionStudy};
use dembound_core::study::sweep::{sweep, SweepResult, SweepSpec};
use dembound_core::study::validation::{
    convergence, validation_tables, ConvergencePoint, ValidationTable, CONVERGENCE_ETAS,
};
use dembound_core::study::{first_contact, gravity_free, Axis, Model, Quantity, StudyError};
use rayon::prelude::*;
use serde::Serialize;
use std::fmt::Write as _;
use std::io::Write;
use std::path::{Path, PathBuf};
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

const INF: f64 = f64::INFINITY;
const LAWS: [ContactLawKind; 2] = [ContactLawKind::Linear, ContactLawKind::Hertz];
/// Fig 4's radii and every figure's ζ curves (section 5).
const FIG4_R: [f64; 3] = [1.0, 10.0, 100.0];
const ZETAS: [f64; 4] = [1.0, 10.0, 100.0, 1000.0];
/// Fig 6's five radii (ERRATA 17).
const RADII: [f64; 5] = [0.5, 1.0, 10.0, 100.0, 1000.0];

fn study(e: StudyError) -> CliError {
    CliError::failed(anyhow!("{e}"))
}

/// The paper's scenario for section 5: the validation data (section 4.2,
/// ERRATA 4), Gear5, η = 1/50, one contact.
pub fn base_scenario() -> Scenario {
    let mut s = Scenario::default().resolved();
    s.motion.contacts = 1;
    s
}

/// The scaling constants (ERRATA 13) and the other single numbers.
#[derive(Debug, Clone, Serialize)]
pub struct Scaling {
    /// h_NL_max: Hertz, r = ζ = ∞, exact with gravity, m.
    pub h_nl: f64,
    /// T_c_NL, s.
    pub t_nl: f64,
    /// The same by the integrator.
    pub h_nl_integrator: f64,
    pub t_nl_integrator: f64,
    /// Hertz T_c at r = ζ = 1000, the study's stiffest case (ERRATA 13), s.
    pub t_r1000: f64,
    /// Hertz h_max at r = ζ = 1000, m.
    pub h_r1000: f64,
    /// Impact speed, m/s.
    pub impact_speed: f64,
}

fn scaling(base: &Scenario) -> Result<Scaling, StudyError> {
    let mut s = *base;
    s.contact.law = ContactLawKind::Hertz;
    s.boundary.radius_ratio = INF;
    s.boundary.modulus_ratio = INF;
    let e = first_contact(&s, Model::Exact)?;
    let n = first_contact(&s, Model::Simulated)?;
    s.boundary.radius_ratio = 1000.0;
    s.boundary.modulus_ratio = 1000.0;
    let e1000 = first_contact(&s, Model::Exact)?;
    Ok(Scaling {
        h_nl: e.max_overlap,
        t_nl: e.duration,
        h_nl_integrator: n.max_overlap,
        t_nl_integrator: n.duration,
        t_r1000: e1000.duration,
        h_r1000: e1000.max_overlap,
        impact_speed: s.impact_speed(),
    })
}

/// Records (t, h) of every sample of a run (event stepping with one
/// contact: the contact only).
struct Trace(Vec<(f64, f64)>);

impl Observer for Trace {
    fn sample(&mut self, s: &Sample) {
        self.0.push((s.t, s.overlap));
    }
}

/// One overlap history of Fig 4, normalised (t/T_c_NL, h/h_NL_max).
#[derive(Debug, Clone, Serialize)]
pub struct History {
    pub law: ContactLawKind,
    pub r: f64,
    pub zeta: f64,
    pub exact: Vec<(f64, f64)>,
    pub integrator: Vec<(f64, f64)>,
}

fn history(
    base: &Scenario,
    law: ContactLawKind,
    r: f64,
    zeta: f64,
    sc: &Scaling,
) -> Result<History> {
    let mut s = *base;
    s.contact.law = law;
    s.boundary.radius_ratio = r;
    s.boundary.modulus_ratio = zeta;
    let mut trace = Trace(Vec::new());
    let out = simulate(&s, &mut trace).map_err(|e| anyhow!("Fig 4 run failed: {e}"))?;
    let c = out.contacts[0];
    let integrator = trace
        .0
        .iter()
        .filter(|(t, _)| *t >= c.t_contact && *t <= c.t_rebound)
        .map(|(t, h)| ((t - c.t_contact) / sc.t_nl, h / sc.h_nl))
        .collect();
    let problem = exact::problem(&s);
    let v = s.impact_speed();
    let shape = exact::contact_shape(&problem, v).map_err(|e| anyhow!("{e}"))?;
    let n = 160;
    let exact = (0..=n)
        .map(|i| {
            let tau = shape.duration * i as f64 / n as f64;
            exact::overlap_at(&problem, v, tau)
                .map(|(h, _)| (tau / sc.t_nl, h / sc.h_nl))
                .map_err(|e| anyhow!("{e}"))
        })
        .collect::<Result<_>>()?;
    Ok(History {
        law,
        r,
        zeta,
        exact,
        integrator,
    })
}

/// 10^lo … 10^hi with `per` values per decade, decades exact.
fn decades(lo: i32, hi: i32, per: usize) -> Vec<f64> {
    let mut v = Vec::new();
    for k in lo..hi {
        for j in 0..per {
            v.push(10f64.powi(k) * 10f64.powf(j as f64 / per as f64));
        }
    }
    v.push(10f64.powi(hi));
    v
}

/// The r grid of Figs 5, 7b, 8b: 0.5 to 1000.
fn r_grid() -> Vec<f64> {
    let mut v = vec![0.5, 0.5 * 2f64.powf(1.0 / 3.0), 0.5 * 2f64.powf(2.0 / 3.0)];
    v.extend(decades(0, 3, 12));
    v
}

/// Whether a grid value gets a numerical point (4 per decade) or only the exact curve.
fn marked(x: f64) -> bool {
    let k = (x.log10() * 12.0).round() as i64;
    (x.log10() * 12.0 - k as f64).abs() > 1e-6 || k % 3 == 0
}

/// A quoted number of the paper beside ours.
#[derive(Debug, Clone, Serialize)]
pub struct Quoted {
    pub what: String,
    pub paper: String,
    /// Ours (exact model) in the paper's unit.
    pub ours: f64,
    /// Ours by the integrator, same unit.
    pub integrator: Option<f64>,
    pub unit: String,
    /// Digits after the point the paper printed.
    pub decimals: usize,
    pub note: String,
}

impl Quoted {
    fn paper_value(&self) -> f64 {
        self.paper.parse().unwrap_or(f64::NAN)
    }

    fn rounded(&self) -> String {
        format!("{:.*}", self.decimals, self.ours)
    }

    fn agrees(&self) -> bool {
        self.rounded() == format!("{:.*}", self.decimals, self.paper_value())
    }
}

/// Everything `paper` computes.
#[derive(Debug, Serialize)]
pub struct PaperData {
    pub scenario: Scenario,
    pub scaling: Scaling,
    pub quoted: Vec<Quoted>,
    pub indicators: Vec<QuotedIndicator>,
    pub exponents_exact: Vec<ExponentFit>,
    pub exponents_gravity_free: Vec<ExponentFit>,
    pub exponents_integrator: Vec<ExponentFit>,
    pub recommended: Vec<Deviations>,
    pub limits: Vec<Limit>,
    pub decay: Vec<(f64, f64, f64)>,
    #[serde(skip)]
    pub histories: Vec<History>,
    pub sweep_r: SweepResult,
    pub sweep_zeta: SweepResult,
    #[serde(skip)]
    pub tables: Vec<ValidationTable>,
    #[serde(skip)]
    pub convergence: Vec<ConvergencePoint>,
    /// Beyond the paper: dissipative laws on boundary particles.
    #[serde(skip)]
    pub restitution: RestitutionStudy,
    /// The closing table's points with LIGGGHTS' e → coefficient mapping
    /// (`contact.calibration = "formula"`; the study above uses the default).
    #[serde(skip)]
    pub restitution_formula: RestitutionStudy,
}

fn stage(quiet: bool, start: Instant, msg: &str) {
    if !quiet {
        eprintln!("paper: {:>6.2} s  {msg}", start.elapsed().as_secs_f64());
    }
}

/// All the computation, in parallel where it pays.
fn compute(base: &Scenario, quiet: bool, start: Instant) -> CliResult<PaperData> {
    stage(quiet, start, "scaling constants, Fig 4 histories");
    let sc = scaling(base).map_err(study)?;
    let mut jobs = Vec::new();
    for r in FIG4_R {
        for z in ZETAS {
            for law in LAWS {
                jobs.push((law, r, z));
            }
        }
    }
    let histories = jobs
        .par_iter()
        .map(|&(law, r, z)| history(base, law, r, z, &sc))
        .collect::<Result<Vec<_>>>()
        .map_err(CliError::failed)?;

    stage(
        quiet,
        start,
        "sweeps over r and ζ (Figs 5–8), integrator and exact",
    );
    let swept =
        |spec: SweepSpec| sweep(&spec, &|_, _| {}).map_err(|e| CliError::failed(anyhow!("{e}")));
    let sweep_r = swept(SweepSpec::new(
        *base,
        r_grid(),
        ZETAS.to_vec(),
        LAWS.to_vec(),
    ))?;
    let sweep_zeta = swept(SweepSpec::new(
        *base,
        RADII.to_vec(),
        decades(0, 3, 12),
        LAWS.to_vec(),
    ))?;

    stage(
        quiet,
        start,
        "indicators, convergence laws, recommended limits",
    );
    let indicators = section5_indicators(base).map_err(study)?;
    let values = paper_fit_values();
    let exponents_exact = convergence_exponents(base, &values, Model::Exact).map_err(study)?;
    let exponents_gravity_free =
        convergence_exponents(&gravity_free(base), &values, Model::Exact).map_err(study)?;
    let exponents_integrator =
        convergence_exponents(base, &values, Model::Simulated).map_err(study)?;
    let mut recommended = Vec::new();
    for law in LAWS {
        for (r, z) in [(INF, 100.0), (100.0, INF), (100.0, 100.0)] {
            recommended
                .push(deviations(base, law, r, z).map_err(|e| CliError::failed(anyhow!("{e}")))?);
        }
    }
    let mut limit_jobs = Vec::new();
    for law in LAWS {
        for q in Quantity::ALL {
            for axis in [Axis::Modulus, Axis::Radius] {
                limit_jobs.push((law, q, axis));
            }
        }
    }
    let limits = limit_jobs
        .par_iter()
        .map(|&(law, q, axis)| smallest(base, law, q, 0.01, axis, INF))
        .collect::<Result<Vec<_>, _>>()
        .map_err(|e| CliError::failed(anyhow!("{e}")))?;
    // ERRATA 16: the departure from the rigid limit decays like 1/ζ.
    let decay = [10.0, 100.0, 1000.0, 10000.0]
        .iter()
        .map(|&z| {
            let d = |law| {
                dembound_core::study::recommend::deviation(
                    base,
                    law,
                    INF,
                    z,
                    Quantity::MaxOverlap,
                    Model::Exact,
                )
            };
            Ok((z, d(ContactLawKind::Linear)?, d(ContactLawKind::Hertz)?))
        })
        .collect::<Result<Vec<_>, StudyError>>()
        .map_err(study)?;

    stage(quiet, start, "Tables 1–2 and the convergence in Δt");
    let (tables, conv) = rayon::join(validation_tables, || convergence(&CONVERGENCE_ETAS));
    let tables = tables.map_err(|e| CliError::failed(anyhow!("{e}")))?;
    let convergence = conv.map_err(|e| CliError::failed(anyhow!("{e}")))?;

    stage(
        quiet,
        start,
        "beyond the paper: restitution of dissipative laws",
    );
    let restitution = restitution_sweep(&Scenario::default(), &RestitutionSpec::default())
        .map_err(|e| CliError::failed(anyhow!("{e}")))?;
    let mut formula_base = Scenario::default();
    formula_base.contact.calibration = Some(dembound_core::contact::Calibration::Formula);
    let restitution_formula =
        restitution_sweep(&formula_base, &crate::output::restitution::closing_spec())
            .map_err(|e| CliError::failed(anyhow!("{e}")))?;

    let quoted = quoted_numbers(&sc, &indicators);
    Ok(PaperData {
        restitution,
        restitution_formula,
        scenario: *base,
        scaling: sc,
        quoted,
        indicators,
        exponents_exact,
        exponents_gravity_free,
        exponents_integrator,
        recommended,
        limits,
        decay,
        histories,
        sweep_r,
        sweep_zeta,
        tables,
        convergence,
    })
}

fn quoted_numbers(sc: &Scaling, ind: &[QuotedIndicator]) -> Vec<Quoted> {
    let mut q = vec![
        Quoted {
            what: "h_NL_max, Hertz, r = ζ = ∞".into(),
            paper: "0.521".into(),
            ours: sc.h_nl * 1e6,
            integrator: Some(sc.h_nl_integrator * 1e6),
            unit: "µm".into(),
            decimals: 3,
            note: "scaling constant of Figs 4–7 (ERRATA 13)".into(),
        },
        Quoted {
            what: "T_c_NL, Hertz, r = ζ = ∞".into(),
            paper: "4.896".into(),
            ours: sc.t_nl * 1e6,
            integrator: Some(sc.t_nl_integrator * 1e6),
            unit: "µs".into(),
            decimals: 3,
            note: format!(
                "ERRATA 13: r = ζ = 1000 would give {} µs",
                sig(sc.t_r1000 * 1e6, 4)
            ),
        },
        Quoted {
            what: "h_NL_max / R_m".into(),
            paper: "0.104".into(),
            ours: sc.h_nl / base_scenario().particle.radius * 100.0,
            integrator: None,
            unit: "%".into(),
            decimals: 3,
            note: "overlap relative to the particle".into(),
        },
        Quoted {
            what: "h_max / R_b at r = ζ = 1000".into(),
            paper: "0.104".into(),
            ours: sc.h_r1000 / (1000.0 * base_scenario().particle.radius) * 100.0 * 1e3,
            integrator: None,
            unit: "10⁻³ %".into(),
            decimals: 3,
            note: "overlap relative to the boundary particle".into(),
        },
        Quoted {
            what: "impact velocity |v_c|".into(),
            paper: "0.313".into(),
            ours: sc.impact_speed,
            integrator: None,
            unit: "m/s".into(),
            decimals: 3,
            note: "5 mm drop (ERRATA 4)".into(),
        },
    ];
    for i in ind {
        q.push(Quoted {
            what: format!(
                "eq 32{} on h_max, {}, {} = {} ({} = {})",
                if i.axis == Axis::Modulus { "a" } else { "b" },
                i.law.name(),
                i.axis.symbol(),
                i.at,
                i.axis.other().symbol(),
                show(i.other)
            ),
            paper: format!("{:.*}", i.paper_decimals, i.paper),
            ours: i.exact,
            integrator: Some(i.simulated),
            unit: "%".into(),
            decimals: i.paper_decimals,
            note: if i.printed {
                "ERRATA 14: ζ_max = r_max = 1000, with gravity".into()
            } else {
                "not printed: \"the same as in the previous case\"".into()
            },
        });
    }
    q
}

// ----------------------------------------------------------------- figures

const R_LABEL: &str = "boundary radius ratio r = R_b/R_m  (1)";
const Z_LABEL: &str = "boundary modulus ratio ζ = E_b/E_m  (1)";

fn law_color(law: ContactLawKind) -> usize {
    match law {
        ContactLawKind::Linear => 0,
        _ => 1,
    }
}

fn fig4(d: &PaperData, r: f64, letter: char) -> Figure {
    let mut series = Vec::new();
    for (i, z) in ZETAS.iter().enumerate() {
        for law in LAWS {
            let Some(h) = d
                .histories
                .iter()
                .find(|h| h.law == law && h.r == r && h.zeta == *z)
            else {
                continue;
            };
            let (line, points) = match law {
                ContactLawKind::Linear => (Mark::Dashed, Mark::Triangles),
                _ => (Mark::Line, Mark::Points),
            };
            series.push(Series::new(
                format!("{}, ζ = {}", law.name(), show(*z)),
                h.exact.clone(),
                line,
                i,
            ));
            let every = if law == ContactLawKind::Linear { 4 } else { 2 };
            let pts = h.integrator.iter().step_by(every).copied().collect();
            series.push(Series::new("", pts, points, i));
        }
    }
    series.push(Series::new("integrator, Hertz", vec![], Mark::Points, 7));
    series.push(Series::new(
        "integrator, linear",
        vec![],
        Mark::Triangles,
        7,
    ));
    Figure {
        title: format!("Fig 4{letter}: overlap histories, r = {}", show(r)),
        x_label: "time since contact onset t* = t / T_c_NL  (1)".into(),
        y_label: "overlap h* = h / h_NL_max  (1)".into(),
        x_log: false,
        y_log: false,
        series,
        ..Default::default()
    }
}

/// h* (or T_c*) against the swept axis, one curve per value of the other.
fn curves(
    sw: &SweepResult,
    law: ContactLawKind,
    along_r: bool,
    others: &[f64],
    q: Quantity,
    scale: f64,
) -> Vec<Series> {
    let mut series = Vec::new();
    for (i, &o) in others.iter().enumerate() {
        let mut cases: Vec<_> = sw
            .cases
            .iter()
            .filter(|c| {
                c.key.law == law
                    && if along_r {
                        c.key.modulus_ratio == o
                    } else {
                        c.key.radius_ratio == o
                    }
            })
            .collect();
        let x = |c: &&dembound_core::study::sweep::SweepCase| {
            if along_r {
                c.key.radius_ratio
            } else {
                c.key.modulus_ratio
            }
        };
        cases.sort_by(|a, b| x(a).total_cmp(&x(b)));
        let exact = cases
            .iter()
            .map(|c| (x(c), c.first().exact.get(q) / scale))
            .collect();
        let num = cases
            .iter()
            .filter(|c| marked(x(c)))
            .map(|c| (x(c), c.first().numerical.get(q) / scale))
            .collect();
        let name = if along_r { "ζ" } else { "r" };
        series.push(Series::new(
            format!("{name} = {}", show(o)),
            exact,
            Mark::Line,
            i,
        ));
        series.push(Series::new("", num, Mark::Points, i));
    }
    series.push(Series::new("lines: exact reference", vec![], Mark::Line, 7));
    series.push(Series::new(
        "points: integrator (Gear5, η = 1/50)",
        vec![],
        Mark::Points,
        7,
    ));
    series
}

fn fig8(d: &PaperData, axis: Axis) -> Figure {
    let along_r = axis == Axis::Radius;
    let sw = if along_r { &d.sweep_r } else { &d.sweep_zeta };
    let others: &[f64] = if along_r { &ZETAS } else { &RADII };
    let mut series = Vec::new();
    let xs: Vec<f64> = {
        let mut v: Vec<f64> = sw
            .cases
            .iter()
            .map(|c| {
                if along_r {
                    c.key.radius_ratio
                } else {
                    c.key.modulus_ratio
                }
            })
            .filter(|x| *x < PAPER_MAX)
            .collect();
        v.sort_by(f64::total_cmp);
        v.dedup();
        v
    };
    for law in LAWS {
        let c = law_color(law);
        let alpha = law.exponent();
        let theory = xs
            .iter()
            .map(|&x| (x, eq33(axis, x, PAPER_MAX, alpha, false)))
            .collect();
        series.push(Series::new(
            format!(
                "{}: eq 33{} corrected (theory)",
                law.name(),
                if along_r { "b" } else { "a" }
            ),
            theory,
            Mark::Line,
            c,
        ));
        // Numerical: eq 32 on the integrator's h_max, every curve of Fig 5 (6).
        let mark = if law == ContactLawKind::Linear {
            Mark::Triangles
        } else {
            Mark::Points
        };
        for (k, &o) in others.iter().enumerate() {
            let at = |x: f64| {
                let (r, z) = if along_r { (x, o) } else { (o, x) };
                sw.find(0, law, r, z)
                    .map(|c| c.first().numerical.max_overlap)
            };
            let Some(h_max) = at(PAPER_MAX) else { continue };
            let pts = xs
                .iter()
                .filter(|x| marked(**x))
                .filter_map(|&x| at(x).map(|h| (x, 100.0 * (h - h_max) / h_max)))
                .collect();
            let label = if k == 0 {
                format!(
                    "{}: eq 32{} integrator, {} = {} … {}",
                    law.name(),
                    if along_r { "b" } else { "a" },
                    if along_r { "ζ" } else { "r" },
                    show(others[0]),
                    show(others[others.len() - 1])
                )
            } else {
                String::new()
            };
            series.push(Series::new(label, pts, mark, c));
        }
    }
    // As printed: 33a is the same for both laws; 33b differs from the corrected form for Hertz.
    if along_r {
        let printed = xs
            .iter()
            .map(|&x| (x, eq33(axis, x, PAPER_MAX, 1.5, true)))
            .collect();
        series.push(Series::new(
            "Hertz: eq 33b as printed",
            printed,
            Mark::Dashed,
            1,
        ));
    } else {
        let printed = xs
            .iter()
            .map(|&x| (x, eq33(axis, x, PAPER_MAX, 1.5, true)))
            .collect();
        series.push(Series::new(
            "eq 33a as printed (both laws)",
            printed,
            Mark::Dashed,
            6,
        ));
    }
    Figure {
        title: format!(
            "Fig 8{}: indicator ΔΨ against {} ({}_max = 1000)",
            if along_r { 'b' } else { 'a' },
            axis.symbol(),
            axis.symbol()
        ),
        x_label: if along_r {
            R_LABEL.into()
        } else {
            Z_LABEL.into()
        },
        y_label: "indicator ΔΨ on h_max  (%)".into(),
        x_log: true,
        y_log: true,
        series,
        ..Default::default()
    }
}

/// Every figure with its file stem and caption.
fn figures(d: &PaperData) -> Vec<(String, Figure, String)> {
    let sc = &d.scaling;
    let mut out = Vec::new();
    for (r, letter) in FIG4_R.iter().zip(['a', 'b', 'c']) {
        out.push((
            format!("fig4{letter}"),
            fig4(d, *r, letter),
            format!(
                "Fig 4{letter}: overlap h* = h/h_NL_max against t* = t/T_c_NL during the first contact, r = {}, \
                 ζ = 1, 10, 100, 1000; Hertz solid lines and circles, linear dashed lines and triangles. \
                 Lines: exact reference (`exact::overlap_at`); points: integrator steps \
                 (every 2nd for Hertz, every 4th for linear).",
                show(*r)
            ),
        ));
    }
    let h = Quantity::MaxOverlap;
    let t = Quantity::Duration;
    for (law, letter) in LAWS.iter().zip(['a', 'b']) {
        out.push((
            format!("fig5{letter}"),
            Figure {
                title: format!(
                    "Fig 5{letter}: maximum overlap against r, {} law",
                    law.name()
                ),
                x_label: R_LABEL.into(),
                y_label: "h*_max = h_max / h_NL_max  (1)".into(),
                x_log: true,
                y_log: false,
                series: curves(&d.sweep_r, *law, true, &ZETAS, h, sc.h_nl),
                ..Default::default()
            },
            format!(
                "Fig 5{letter}: h*_max against r for ζ = 1, 10, 100, 1000, {} law.",
                law.name()
            ),
        ));
    }
    for (law, letter) in LAWS.iter().zip(['a', 'b']) {
        out.push((
            format!("fig6{letter}"),
            Figure {
                title: format!("Fig 6{letter}: maximum overlap against ζ, {} law", law.name()),
                x_label: Z_LABEL.into(),
                y_label: "h*_max = h_max / h_NL_max  (1)".into(),
                x_log: true,
                y_log: false,
                series: curves(&d.sweep_zeta, *law, false, &RADII, h, sc.h_nl),
                ..Default::default()
            },
            format!(
                "Fig 6{letter}: h*_max against ζ for r = 0.5, 1, 10, 100, 1000 (five curves, ERRATA 17), {} law.",
                law.name()
            ),
        ));
    }
    let hertz = ContactLawKind::Hertz;
    out.push((
        "fig7a".into(),
        Figure {
            title: "Fig 7a: contact duration against ζ, Hertz".into(),
            x_label: Z_LABEL.into(),
            y_label: "T*_c = T_c / T_c_NL  (1)".into(),
            x_log: true,
            y_log: false,
            series: curves(&d.sweep_zeta, hertz, false, &RADII, t, sc.t_nl),
            ..Default::default()
        },
        "Fig 7a: T*_c against ζ for r = 0.5, 1, 10, 100, 1000, Hertz.".into(),
    ));
    out.push((
        "fig7b".into(),
        Figure {
            title: "Fig 7b: contact duration against r, Hertz".into(),
            x_label: R_LABEL.into(),
            y_label: "T*_c = T_c / T_c_NL  (1)".into(),
            x_log: true,
            y_log: false,
            series: curves(&d.sweep_r, hertz, true, &ZETAS, t, sc.t_nl),
            ..Default::default()
        },
        "Fig 7b: T*_c against r for ζ = 1, 10, 100, 1000, Hertz.".into(),
    ));
    out.push((
        "fig8a".into(),
        fig8(d, Axis::Modulus),
        "Fig 8a: eq 32a on the integrator's h_max (ζ_max = 1000) for every r of Fig 6, against eq 33a \
         corrected (ERRATA 15) and as printed. Each law's points fall on one curve; the laws do not \
         share one (ERRATA 16)."
            .into(),
    ));
    out.push((
        "fig8b".into(),
        fig8(d, Axis::Radius),
        "Fig 8b: eq 32b on the integrator's h_max (r_max = 1000) for every ζ of Fig 5, against eq 33b \
         corrected and as printed (as printed, Hertz uses the exponent (2−α)/2 = 1/4 instead of 1/5; \
         for the linear law both forms agree)."
            .into(),
    ));
    out
}

// ------------------------------------------------------------------ report

fn pct(x: f64) -> String {
    format!("{} %", sig(x * 100.0, 4))
}

fn report_markdown(
    d: &PaperData,
    figs: &[(String, String)],
    conv_figs: &[PathBuf],
    restitution_figs: &[PathBuf],
    compute_seconds: f64,
) -> String {
    let mut m = String::new();
    let sc = &d.scaling;
    let _ = writeln!(
        m,
        "# Reproduction of Jasevičius & Kačianauskas (2007), section 5\n\n\
         Generated by `dembound paper` (dembound {}). Scenario: the paper's validation data \
         (c² = 10⁷ m²/s², ν = 0.3, R_m = 0.5 mm, a 5 mm drop under g = 9.81 m/s², ERRATA 4), \
         one contact, Gear5 with event stepping and Δt = T_c/50 (η = 1/50). \"Exact\" is the \
         exact reference of `dembound_core::exact` (closed forms for the linear law, quadrature \
         with gravity for Hertz, ERRATA 6 and 8); \"integrator\" is the Gear5 run. Compute time \
         {:.2} s.\n",
        env!("CARGO_PKG_VERSION"),
        compute_seconds
    );

    let _ = writeln!(m, "## Numbers quoted in the paper\n");
    // Each row in its own unit (the unit column): the values are text.
    let mut t = Table::new(vec![
        Column::text("quantity"),
        Column::text("unit"),
        Column::text("paper").right(),
        Column::text("ours (exact)").right(),
        Column::text("ours (integrator)").right(),
        Column::number("ours − paper", Unit::NONE, Format::SignedSci(3)),
        Column::text("same printed digits"),
        Column::text("note"),
    ]);
    for q in &d.quoted {
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
            (q.ours - q.paper_value()).into(),
            if q.agrees() {
                Cell::text("yes")
            } else {
                Cell::Markdown("**no**".into())
            },
            Cell::text(&q.note),
        ]);
    }
    m.push_str(&t.markdown());
    let _ = writeln!(
        m,
        "\nThe scaling constants are the Hertz values for the rigid half-space r = ζ = ∞ \
         (ERRATA 13): h_NL_max = {} µm, T_c_NL = {} µs. The percentages are indicator (32) on \
         h_max with ζ_max = r_max = 1000, evaluated at 10 and 100 with gravity (ERRATA 14), the \
         other parameter held at 1000 (any other value gives the same printed digits: gravity \
         couples r and ζ only at the 10⁻⁵ level). Without gravity ζ = 10 would give 4.828 % and \
         3.844 %: the paper's last digits of 4.829 % and 3.845 % come from gravity.\n",
        sig(sc.h_nl * 1e6, 6),
        sig(sc.t_nl * 1e6, 6)
    );

    let _ = writeln!(m, "## Theoretical indicators (eq 33)\n");
    let _ = writeln!(
        m,
        "ERRATA 15: eq 33a as printed has the prefactor's exponent sign flipped and both 33a and 33b use \
         the linear model's exponent for Hertz. Consistent forms: 100((ζ̄_max/ζ̄)^(1/(α+1)) − 1) and \
         100((r̄_max/r̄)^((2−α)/(α+1)) − 1).\n"
    );
    let percent = |label: &str| Column::number(label, Unit::PERCENT, Format::Fixed(5));
    let mut t = Table::new(vec![
        Column::text("law"),
        Column::text("indicator"),
        Column::text("at").right(),
        percent("eq 32, exact"),
        percent("eq 33 corrected"),
        percent("eq 33 as printed"),
    ]);
    for i in &d.indicators {
        let letter = if i.axis == Axis::Modulus { "a" } else { "b" };
        t.push(vec![
            Cell::text(i.law.name()),
            Cell::text(format!("32{letter}/33{letter}")),
            Cell::text(format!("{} = {}", i.axis.symbol(), i.at)),
            i.exact.into(),
            i.theory.into(),
            i.theory_printed.into(),
        ]);
    }
    m.push_str(&t.markdown());

    let _ = writeln!(m, "\n## Convergence laws (ERRATA 16)\n");
    let _ = writeln!(
        m,
        "Least-squares slope of ln(q/q(∞, ∞)) against ln ζ̄ (or ln r̄) over 13 values from 1 to 1000, the \
         other parameter at ∞. Theory (gravity-free): h_max and T_c ∝ ζ̄^(−1/(α+1)) r̄^(−(2−α)/(α+1)), \
         a_max inversely. The paper's conclusion states ((ζ+1)/ζ)^(1/2) and ((r+1)/r)^((2−α)/2): right \
         for the linear law, not for Hertz (2/5 and 1/5).\n"
    );
    let mut t = Table::new(vec![
        Column::text("law"),
        Column::text("axis"),
        Column::text("quantity"),
        Column::text("theory").right(),
        Column::text("exact, g = 9.81").right(),
        Column::text("exact, g = 0").right(),
        Column::text("integrator, g = 9.81").right(),
    ]);
    for ((e, f), n) in d
        .exponents_exact
        .iter()
        .zip(&d.exponents_gravity_free)
        .zip(&d.exponents_integrator)
    {
        t.push(vec![
            Cell::text(e.law.name()),
            Cell::text(format!("{}̄", e.axis.symbol())),
            Cell::text(e.quantity.symbol()),
            Cell::text(format!("{:+.4}", e.theory)),
            Cell::text(format!("{:+.6}", e.fitted)),
            Cell::text(format!("{:+.6}", f.fitted)),
            Cell::text(format!("{:+.6}", n.fitted)),
        ]);
    }
    m.push_str(&t.markdown());
    let _ = writeln!(
        m,
        "\nv_r does not depend on r or ζ at all (the model is conservative, v_r = |v_c|). The \
         *departure* from the rigid limit decays like 1/ζ, not ζ^(−1/2) as the paper's wording \
         suggests: \\|h_max(ζ)/h_max(∞) − 1\\| with r = ∞ (exact):\n"
    );
    let mut t = Table::new(vec![
        Column::text("ζ").right(),
        Column::number("linear", Unit::NONE, Format::Sci(5)),
        Column::number("Hertz", Unit::NONE, Format::Sci(5)),
    ]);
    for &(z, l, h) in &d.decay {
        t.push(vec![Cell::text(z.to_string()), l.into(), h.into()]);
    }
    m.push_str(&t.markdown());

    let _ = writeln!(m, "\n## Recommended limits ζ = r = 100\n");
    let _ = writeln!(
        m,
        "The paper recommends ζ = 100 and r = 100. Deviation \\|q(r, ζ)/q(∞, ∞) − 1\\| they leave:\n"
    );
    let mut t = Table::new(
        ["law", "r", "ζ"]
            .iter()
            .map(|n| Column::text(*n))
            .chain(
                [
                    "h_max exact",
                    "h_max integrator",
                    "T_c exact",
                    "T_c integrator",
                    "a_max exact",
                    "a_max integrator",
                ]
                .iter()
                .map(|n| Column::text(*n).right()),
            )
            .collect(),
    );
    for dv in &d.recommended {
        let g = |q: Quantity| {
            dv.quantities
                .iter()
                .find(|x| x.quantity == q)
                .map(|x| (x.exact, x.simulated))
                .unwrap_or((f64::NAN, f64::NAN))
        };
        let (h, tc, a) = (
            g(Quantity::MaxOverlap),
            g(Quantity::Duration),
            g(Quantity::MaxAcceleration),
        );
        t.push(
            [
                dv.law.name(),
                show(dv.radius_ratio),
                show(dv.modulus_ratio),
                pct(h.0),
                pct(h.1),
                pct(tc.0),
                pct(tc.1),
                pct(a.0),
                pct(a.1),
            ]
            .into_iter()
            .map(Cell::Text)
            .collect(),
        );
    }
    m.push_str(&t.markdown());
    let _ = writeln!(
        m,
        "\nFor comparison, the smallest ζ (r = ∞) and the smallest r (ζ = ∞) that keep each quantity \
         within T = 1 % (`dembound recommend --tolerance 0.01`; exact model, Brent):\n"
    );
    let mut t = Table::new(vec![
        Column::text("law"),
        Column::text("quantity"),
        Column::text("smallest ζ (r = ∞)").right(),
        Column::text("smallest r (ζ = ∞)").right(),
        Column::text("gravity-free closed forms"),
    ]);
    for law in LAWS {
        for q in Quantity::ALL {
            let find = |axis| {
                d.limits
                    .iter()
                    .find(|l| l.law == law && l.quantity == q && l.solved == axis)
            };
            let show_l = |l: Option<&Limit>| match l.map(|l| l.outcome) {
                Some(Outcome::Found { value }) => sig(value, 6),
                Some(Outcome::Unreachable { .. }) => "none".into(),
                Some(Outcome::AnyValue) => "any".into(),
                None => "–".into(),
            };
            let (z, r) = (find(Axis::Modulus), find(Axis::Radius));
            let free = format!(
                "ζ = {}, r = {}",
                z.and_then(|l| l.gravity_free)
                    .map(|x| sig(x, 6))
                    .unwrap_or_else(|| "–".into()),
                r.and_then(|l| l.gravity_free)
                    .map(|x| sig(x, 6))
                    .unwrap_or_else(|| "–".into())
            );
            t.push(
                [
                    law.name(),
                    q.symbol().to_string(),
                    show_l(z),
                    show_l(r),
                    free,
                ]
                .into_iter()
                .map(Cell::Text)
                .collect(),
            );
        }
    }
    m.push_str(&t.markdown());

    let _ = writeln!(m, "\n## Figures 4–8\n");
    for (stem, caption) in figs {
        let _ = writeln!(m, "![{stem}]({stem}.png)\n\n{caption}\n");
    }

    let _ = writeln!(m, "## Tables 1–2 (validation, section 4.2)\n");
    m.push_str(&validation::tables_markdown(&d.tables));
    let _ = writeln!(m, "\n### Convergence in the time step\n");
    m.push_str(&validation::convergence_markdown(&d.convergence));
    for p in conv_figs {
        if p.extension().is_some_and(|e| e == "png") {
            if let Some(name) = p.file_name() {
                let name = name.to_string_lossy();
                let _ = writeln!(m, "\n![{name}]({name})\n");
            }
        }
    }

    m.push('\n');
    m.push_str(&restitution_markdown(&d.restitution));
    m.push_str(&crate::output::restitution::closing_table(
        &d.restitution,
        &d.restitution_formula,
    ));
    let _ = writeln!(
        m,
        "\nEffective restitution against r (all figures, also against ζ and for T_c and \
         h_max, are in `{RESTITUTION_DIR}/`):\n"
    );
    for p in restitution_figs {
        if let Some(name) = p.file_name().map(|n| n.to_string_lossy()) {
            if name.ends_with("_restitution_vs_r.png") {
                let _ = writeln!(m, "![{name}]({RESTITUTION_DIR}/{name})\n");
            }
        }
    }

    let _ = writeln!(m, "\n## Where we depart from the printed text\n");
    let _ = writeln!(
        m,
        "Every item, with what the paper prints, what is right and how we know, is in \
         [errata.md](errata.md) (written beside this report; `docs/errata.md` in the dembound \
         sources).\n"
    );
    for item in ERRATA_USED {
        let _ = writeln!(m, "- {item}");
    }
    m
}

/// docs/errata.md: the ERRATA items the report cites, written beside it.
const ERRATA: &str = include_str!("../../docs/errata.md");

const ERRATA_USED: [&str; 11] = [
    "ERRATA 1 — eqs 3 and 9: the contact force pushes the particle out, h'' = g − p² h^α; as printed eq 9 is undefined for Hertz.",
    "ERRATA 4 — the drop is a 5 mm gap (10 R_m), not 5 R_m: only this gives the paper's v_c = −0.313 m/s, which all of section 5 uses.",
    "ERRATA 6 and 8 — the exact references: the corrected linear closed forms (eq 26's arctan branch, eq 28's sign) and the Hertz quadrature with gravity.",
    "ERRATA 9–12 — Tables 1–2: units, the mislabelled reference row and the δ values (see the tables above).",
    "ERRATA 13 — h_NL_max and T_c_NL are the Hertz values for r = ζ = ∞ (r = ζ = 1000, the study's stiffest case, gives the same h_max to three digits but T_c = 4.899 µs, not 4.896 µs).",
    "ERRATA 14 — the quoted percentages are indicator (32) on h_max with ζ_max = r_max = 1000, at 10 and 100, with gravity.",
    "ERRATA 15 — eq 33a's prefactor exponent and both eqs' Hertz exponents are corrected; the printed forms are shown beside (Fig 8, tables).",
    "ERRATA 16 — the convergence laws: exponents 1/(α+1) in ζ̄ and (2−α)/(α+1) in r̄ (1/2, 1/2 linear; 2/5, 1/5 Hertz), a_max inversely, v_r constant; Fig 8a's \"single curve\" holds per law only.",
    "ERRATA 17 — Fig 6 has five curves (r = 0.5, 1, 10, 100, 1000), not four.",
    "Section 5 says the linear model was solved analytically and Hertz with Gear5; here both are run with Gear5 and both are compared with exact references.",
    "The paper's figures show both laws normalised by the Hertz constants; so do ours (linear h* ≈ 0.16).",
];

/// The report as one HTML file, every PNG embedded.
fn report_html(markdown: &str, dir: &Path) -> Result<String> {
    use pulldown_cmark::{html, Event, Options, Parser, Tag};
    let parser = Parser::new_ext(markdown, Options::ENABLE_TABLES);
    let mut failed = None;
    let events: Vec<Event> = parser
        .map(|e| match e {
            Event::Start(Tag::Image {
                link_type,
                dest_url,
                title,
                id,
            }) if !dest_url.starts_with("data:") => {
                let path = dir.join(dest_url.as_ref());
                match std::fs::read(&path) {
                    Ok(bytes) => Event::Start(Tag::Image {
                        link_type,
                        dest_url: format!("data:image/png;base64,{}", BASE64.encode(&bytes)).into(),
                        title,
                        id,
                    }),
                    Err(err) => {
                        failed.get_or_insert(anyhow!("cannot embed {}: {err}", path.display()));
                        Event::Start(Tag::Image {
                            link_type,
                            dest_url,
                            title,
                            id,
                        })
                    }
                }
            }
            e => e,
        })
        .collect();
    if let Some(e) = failed {
        return Err(e);
    }
    let mut body = String::new();
    html::push_html(&mut body, events.into_iter());
    Ok(format!(
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n\
         <title>dembound: reproduction of Jasevičius &amp; Kačianauskas (2007)</title>\n<style>\n\
         body {{ font-family: sans-serif; max-width: 1100px; margin: 2em auto; padding: 0 1em; line-height: 1.45; }}\n\
         table {{ border-collapse: collapse; margin: 1em 0; font-size: 0.9em; }}\n\
         th, td {{ border: 1px solid #bbb; padding: 0.25em 0.5em; }}\n\
         th {{ background: #f0f0f0; }}\n img {{ max-width: 100%; border: 1px solid #ddd; }}\n\
         code {{ background: #f4f4f4; padding: 0 0.2em; }}\n</style>\n</head>\n<body>\n{body}</body>\n</html>\n"
    ))
}

// --------------------------------------------------------------------- run

/// Subfolder of the reproduction that holds the restitution study's figures.
const RESTITUTION_DIR: &str = "restitution";

pub fn run(args: &PaperArgs) -> CliResult {
    let start = Instant::now();
    let dir = &args.out;
    // Before computing: a bad --out fails at once.
    let mut out = super::output_dir(dir, "paper")?;
    let base = base_scenario();
    let data = compute(&base, args.quiet, start)?;
    let compute_seconds = start.elapsed().as_secs_f64();

    stage(args.quiet, start, "figures and report");
    // Everything is drawn into the staging directory and published at once.
    let staging = out.staging().to_path_buf();
    let figs = figures(&data);
    figs.par_iter()
        .map(|(stem, fig, _)| fig.write(&staging.join(stem)))
        .collect::<Result<Vec<_>>>()
        .map_err(CliError::failed)?;
    let conv_figs =
        validation::convergence_figures(&data.convergence, &staging).map_err(CliError::failed)?;
    let restitution_figs = restitution_figures(&data.restitution, &staging.join(RESTITUTION_DIR))
        .map_err(CliError::failed)?;
    let captions: Vec<(String, String)> = figs.into_iter().map(|(s, _, c)| (s, c)).collect();
    let md = report_markdown(
        &data,
        &captions,
        &conv_figs,
        &restitution_figs,
        compute_seconds,
    );
    let html = report_html(&md, &staging).map_err(CliError::failed)?;
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grids_hold_the_decades_exactly() {
        let g = decades(0, 3, 12);
        assert_eq!(g.len(), 37);
        for d in [1.0, 10.0, 100.0, 1000.0] {
            assert!(g.contains(&d));
            assert!(marked(d));
        }
        assert_eq!(g.iter().filter(|x| marked(**x)).count(), 13);
        assert_eq!(r_grid()[0], 0.5);
    }
}
