//! The paper's section 5 as computed data (no I/O): the scaling constants,
//! Fig 4's overlap histories, the sweeps of Figs 5–8, every number the
//! paper quotes beside ours, the convergence laws, the recommended limits,
//! Tables 1–2 and the restitution study. `dembound paper` renders it.
//!
//! Scaling constants are the Hertz rigid half-space values (ERRATA 13);
//! the indicators are eq 32 on h_max with ζ_max = r_max = 1000 and gravity
//! (ERRATA 14); theory is eq 33 as corrected (ERRATA 15), printed beside.

use super::indicators::{
    convergence_exponents, paper_fit_values, section5_indicators, ExponentFit, QuotedIndicator,
};
use super::recommend::{deviation, deviations, smallest, Deviations, Limit};
use super::restitution::{
    restitution_sweep, CalibrationSite, DissipativeLaw, RestitutionSpec, RestitutionStudy,
};
use super::sweep::{sweep, SweepResult, SweepSpec};
use super::validation::{
    tables_and_convergence, ConvergencePoint, ValidationTable, CONVERGENCE_ETAS,
};
use super::{first_contact, gravity_free, show, sig, Axis, Model, Quantity};
use crate::bounce::{simulate, Observer, Sample, Scenario};
use crate::contact::ContactLawKind;
use crate::exact;
use crate::{Error, Result};
use rayon::prelude::*;
use serde::Serialize;

const INF: f64 = f64::INFINITY;
/// The two laws of section 5.
pub const LAWS: [ContactLawKind; 2] = [ContactLawKind::Linear, ContactLawKind::Hertz];
/// Fig 4's radii (section 5).
pub const FIG4_R: [f64; 3] = [1.0, 10.0, 100.0];
/// Every figure's ζ curves (section 5).
pub const ZETAS: [f64; 4] = [1.0, 10.0, 100.0, 1000.0];
/// Fig 6's five radii (ERRATA 17).
pub const RADII: [f64; 5] = [0.5, 1.0, 10.0, 100.0, 1000.0];

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

/// The scaling constants of `base` (ERRATA 13).
pub fn scaling(base: &Scenario) -> Result<Scaling> {
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

/// Fig 4's history of `law` at r, ζ: the integrator's samples during the
/// first contact and the exact reference at 161 points.
pub fn history(
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
    let out = simulate(&s, &mut trace).map_err(Error::simulation)?;
    let c = out.contacts[0];
    let integrator = trace
        .0
        .iter()
        .filter(|(t, _)| *t >= c.t_contact && *t <= c.t_rebound)
        .map(|(t, h)| ((t - c.t_contact) / sc.t_nl, h / sc.h_nl))
        .collect();
    let problem = exact::problem(&s);
    let v = s.impact_speed();
    let shape = exact::contact_shape(&problem, v).map_err(Error::exact)?;
    let n = 160;
    let exact = (0..=n)
        .map(|i| {
            let tau = shape.duration * i as f64 / n as f64;
            exact::overlap_at(&problem, v, tau).map(|(h, _)| (tau / sc.t_nl, h / sc.h_nl))
        })
        .collect::<Result<_, _>>()
        .map_err(Error::exact)?;
    Ok(History {
        law,
        r,
        zeta,
        exact,
        integrator,
    })
}

/// 10^lo … 10^hi with `per` values per decade, decades exact.
pub fn decades(lo: i32, hi: i32, per: usize) -> Vec<f64> {
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
pub fn r_grid() -> Vec<f64> {
    let mut v = vec![0.5, 0.5 * 2f64.powf(1.0 / 3.0), 0.5 * 2f64.powf(2.0 / 3.0)];
    v.extend(decades(0, 3, 12));
    v
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
    /// The paper's number (NaN if it does not parse).
    pub fn paper_value(&self) -> f64 {
        self.paper.parse().unwrap_or(f64::NAN)
    }

    /// Ours, rounded to the digits the paper printed.
    pub fn rounded(&self) -> String {
        format!("{:.*}", self.decimals, self.ours)
    }

    /// Whether ours prints the same digits as the paper's.
    pub fn agrees(&self) -> bool {
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

/// The points of the closing table: every law, e = 0.5 and 0.9, r = ζ = 100
/// and the rigid wall, both calibrations.
pub fn closing_spec() -> RestitutionSpec {
    RestitutionSpec {
        laws: DissipativeLaw::ALL.to_vec(),
        targets: vec![0.5, 0.9],
        radius_ratios: vec![100.0, f64::INFINITY],
        modulus_ratios: vec![100.0, f64::INFINITY],
        calibrations: CalibrationSite::ALL.to_vec(),
    }
}

/// All the computation, in parallel where it pays. `stage` is told the
/// name of each stage as it starts (for progress messages).
///
/// Tables 1–2 and the convergence study (three quarters of the work, most
/// of it in a few fixed-step runs of 10⁸ steps) run alongside the other
/// stages, not after them: their longest-first queue
/// ([`tables_and_convergence`]) takes a thread at once, and the thread
/// that finishes the other stages joins it, so both threads stay busy to
/// the end. Every result is the same as computed one stage after another.
pub fn compute(base: &Scenario, stage: &(dyn Fn(&str) + Sync)) -> Result<PaperData> {
    stage("Tables 1–2 and the convergence in Δt, alongside the stages below");
    let (validation, rest) = rayon::join(
        || tables_and_convergence(&CONVERGENCE_ETAS),
        || section5_and_restitution(base, stage),
    );
    let (tables, convergence) = validation?;
    let rest = rest?;
    let quoted = quoted_numbers(&rest.scaling, &rest.indicators);
    Ok(PaperData {
        restitution: rest.restitution,
        restitution_formula: rest.restitution_formula,
        scenario: *base,
        scaling: rest.scaling,
        quoted,
        indicators: rest.indicators,
        exponents_exact: rest.exponents_exact,
        exponents_gravity_free: rest.exponents_gravity_free,
        exponents_integrator: rest.exponents_integrator,
        recommended: rest.recommended,
        limits: rest.limits,
        decay: rest.decay,
        histories: rest.histories,
        sweep_r: rest.sweep_r,
        sweep_zeta: rest.sweep_zeta,
        tables,
        convergence,
    })
}

/// Everything of [`PaperData`] but Tables 1–2, the convergence study and
/// the quoted numbers.
struct Section5 {
    scaling: Scaling,
    histories: Vec<History>,
    sweep_r: SweepResult,
    sweep_zeta: SweepResult,
    indicators: Vec<QuotedIndicator>,
    exponents_exact: Vec<ExponentFit>,
    exponents_gravity_free: Vec<ExponentFit>,
    exponents_integrator: Vec<ExponentFit>,
    recommended: Vec<Deviations>,
    limits: Vec<Limit>,
    decay: Vec<(f64, f64, f64)>,
    restitution: RestitutionStudy,
    restitution_formula: RestitutionStudy,
}

/// The stages of [`compute`] that run beside Tables 1–2 and the
/// convergence study, one after another.
fn section5_and_restitution(base: &Scenario, stage: &(dyn Fn(&str) + Sync)) -> Result<Section5> {
    stage("scaling constants, Fig 4 histories");
    let sc = scaling(base)?;
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
        .collect::<Result<Vec<_>, _>>()?;

    stage("sweeps over r and ζ (Figs 5–8), integrator and exact");
    let swept = |spec: SweepSpec| sweep(&spec, &|_, _| {});
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

    stage("indicators, convergence laws, recommended limits");
    let indicators = section5_indicators(base)?;
    let values = paper_fit_values();
    let exponents_exact = convergence_exponents(base, &values, Model::Exact)?;
    let exponents_gravity_free = convergence_exponents(&gravity_free(base), &values, Model::Exact)?;
    let exponents_integrator = convergence_exponents(base, &values, Model::Simulated)?;
    let mut recommended = Vec::new();
    for law in LAWS {
        for (r, z) in [(INF, 100.0), (100.0, INF), (100.0, 100.0)] {
            recommended.push(deviations(base, law, r, z)?);
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
        .collect::<Result<Vec<_>, _>>()?;
    // ERRATA 16: the departure from the rigid limit decays like 1/ζ.
    let decay = [10.0, 100.0, 1000.0, 10000.0]
        .iter()
        .map(|&z| {
            let d = |law| deviation(base, law, INF, z, Quantity::MaxOverlap, Model::Exact);
            Ok((z, d(ContactLawKind::Linear)?, d(ContactLawKind::Hertz)?))
        })
        .collect::<Result<Vec<_>>>()?;

    stage("beyond the paper: restitution of dissipative laws");
    let restitution = restitution_sweep(&Scenario::default(), &RestitutionSpec::default())?;
    let mut formula_base = Scenario::default();
    formula_base.contact.calibration = Some(crate::contact::Calibration::Formula);
    let restitution_formula = restitution_sweep(&formula_base, &closing_spec())?;
    Ok(Section5 {
        scaling: sc,
        histories,
        sweep_r,
        sweep_zeta,
        indicators,
        exponents_exact,
        exponents_gravity_free,
        exponents_integrator,
        recommended,
        limits,
        decay,
        restitution,
        restitution_formula,
    })
}

/// Every number the paper quotes in section 5 beside ours: the scaling
/// constants, the overlaps relative to the spheres, the impact speed and
/// the indicators of eq 32 (ERRATA 13–14).
pub fn quoted_numbers(sc: &Scaling, ind: &[QuotedIndicator]) -> Vec<Quoted> {
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grids_hold_the_decades_exactly() {
        let g = decades(0, 3, 12);
        assert_eq!(g.len(), 37);
        for d in [1.0, 10.0, 100.0, 1000.0] {
            assert!(g.contains(&d));
        }
        let r = r_grid();
        assert_eq!(r[0], 0.5);
        assert_eq!(r.len(), 40);
        assert_eq!(r[r.len() - 1], 1000.0);
    }
}
