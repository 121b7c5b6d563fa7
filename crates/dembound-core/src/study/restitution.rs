//! The paper's boundary-particle study (section 5) extended to dissipative
//! contacts: how the *effective* coefficient of restitution, the contact
//! time and the maximum overlap of a particle dropped on a boundary sphere
//! depend on r = R_b/R_m and ζ = E_b/E_m, for each dissipative law, and the
//! reverse question (which e to enter to get a given rebound on a given
//! boundary particle).
//!
//! **Calibration.** Each law turns a target e into a raw damping
//! coefficient using the effective properties of a pair (its stiffness k,
//! the mass, for the viscoelastic law the impact speed):
//!
//! - [`CalibrationSite::Pair`]: the coefficient is computed for each
//!   particle–boundary pair itself. Then e does not depend on r and ζ for
//!   the linear dashpot, Tsuji and Walton–Braun laws (their e is a function
//!   of a dimensionless damping ratio that the calibration holds fixed) nor,
//!   at the calibration speed, for the viscoelastic law; what remains is
//!   the small effect of gravity during the contact (and, with the base
//!   scenario's `contact.calibration = "formula"`, that of the
//!   no-attraction clamp, which the default `"exact"` calibrates away).
//! - [`CalibrationSite::Wall`]: the coefficient is computed once on the rigid
//!   half-space r = ζ = ∞ and the *same raw number* is reused on the
//!   boundary particle, as happens when a DEM code's material table is
//!   calibrated against a wall and then applied to boundary particles. The
//!   softer pair then has a larger damping ratio (linear, Tsuji: e drops),
//!   a smaller δ (viscoelastic: e rises) or a relatively stiffer unloading
//!   branch (Walton–Braun, k₂ = k₁(∞)/e²: e = e √(k₁/k₁(∞)) drops).
//!
//! The raw coefficients are c (N s/m, viscous), γ (N s/m^(5/4), Tsuji),
//! A (s, viscoelastic) and the unloading stiffness k₂ (N/m, Walton–Braun).
//!
//! Every point is one contact of the base scenario (by default the paper's
//! validation drop: 5 mm under g, Gear5, η = 1/50, event stepping) against a
//! fixed boundary, simulated with the core's time loop.

use crate::bounce::{simulate_with, ContactRecord, Problem, Scenario};
use crate::calibration::{damping_coefficient, with_damped};
use crate::contact::{
    ContactLawKind, ContactModel, DampingKind, Dissipation, LawVisitor, NormalContactLaw,
    WaltonBraun,
};
use crate::integrate::{Gear5, Scheme, Verlet};
use crate::{Error, Result};
use rayon::prelude::*;
use roots::{find_root_brent, Convergency};
use serde::Serialize;
use std::fmt;

/// The dissipative laws of the study.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum DissipativeLaw {
    /// Linear spring–dashpot, `law = "linear"`, `damping = "viscous"`.
    Viscous,
    /// Hertz with Tsuji damping, `law = "hertz"`, `damping = "tsuji"`.
    Tsuji,
    /// Hertz with viscoelastic damping, `law = "hertz"`, `damping = "viscoelastic"`.
    Viscoelastic,
    /// Walton–Braun hysteretic linear law, `law = "walton-braun"`.
    WaltonBraun,
}

impl DissipativeLaw {
    pub const ALL: [DissipativeLaw; 4] = [
        DissipativeLaw::Viscous,
        DissipativeLaw::Tsuji,
        DissipativeLaw::Viscoelastic,
        DissipativeLaw::WaltonBraun,
    ];

    /// `viscous`, `tsuji`, `viscoelastic`, `walton-braun`: the registry
    /// name of its damping, or of its law when the law is dissipative on
    /// its own.
    pub fn name(&self) -> &'static str {
        match self.contact() {
            (law, DampingKind::None) => law.row().name,
            (_, damping) => damping.name(),
        }
    }

    /// Reads a name of [`Self::name`].
    pub fn parse(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|l| l.name() == name.trim())
    }

    /// A short description for reports.
    pub fn description(&self) -> &'static str {
        match self {
            DissipativeLaw::Viscous => "linear spring–dashpot",
            DissipativeLaw::Tsuji => "Hertz + Tsuji damping",
            DissipativeLaw::Viscoelastic => "Hertz + viscoelastic damping",
            DissipativeLaw::WaltonBraun => "Walton–Braun hysteretic",
        }
    }

    /// The scenario keys `contact.law` and `contact.damping` of the law.
    pub fn contact(&self) -> (ContactLawKind, DampingKind) {
        match self {
            DissipativeLaw::Viscous => (ContactLawKind::Linear, DampingKind::Viscous),
            DissipativeLaw::Tsuji => (ContactLawKind::Hertz, DampingKind::Tsuji),
            DissipativeLaw::Viscoelastic => (ContactLawKind::Hertz, DampingKind::Viscoelastic),
            DissipativeLaw::WaltonBraun => (ContactLawKind::WaltonBraun, DampingKind::None),
        }
    }

    /// Symbol of the raw coefficient.
    pub fn coefficient_symbol(&self) -> &'static str {
        match self.contact().1.row().coefficient {
            Some(coefficient) => coefficient.symbol,
            // Walton–Braun: its unloading stiffness.
            None => "k₂",
        }
    }

    /// Unit of the raw coefficient.
    pub fn coefficient_unit(&self) -> &'static str {
        match self {
            DissipativeLaw::Viscous => "N s/m",
            DissipativeLaw::Tsuji => "N s/m^(5/4)",
            DissipativeLaw::Viscoelastic => "s",
            DissipativeLaw::WaltonBraun => "N/m",
        }
    }
}

impl fmt::Display for DissipativeLaw {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// Where the raw damping coefficient is calibrated, on the rigid wall or on
/// the pair itself (see the module doc; not the mapping from e to the
/// coefficient, which is [`crate::contact::Calibration`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum CalibrationSite {
    /// On the rigid half-space r = ζ = ∞; the raw coefficient is reused on the pair.
    Wall,
    /// On each particle–boundary pair itself.
    Pair,
}

impl CalibrationSite {
    pub const ALL: [CalibrationSite; 2] = [CalibrationSite::Wall, CalibrationSite::Pair];

    pub fn name(&self) -> &'static str {
        match self {
            CalibrationSite::Wall => "wall",
            CalibrationSite::Pair => "pair",
        }
    }

    pub fn parse(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|c| c.name() == name.trim())
    }

    /// One line saying what the calibration means.
    pub fn description(&self) -> &'static str {
        match self {
            CalibrationSite::Wall => {
                "raw coefficient calibrated for e on the rigid wall (r = ζ = ∞), reused unchanged on the boundary particle"
            }
            CalibrationSite::Pair => {
                "raw coefficient calibrated for e on each particle–boundary pair's own effective properties"
            }
        }
    }
}

impl fmt::Display for CalibrationSite {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// The sweep's default ratios, for both r and ζ.
pub const DEFAULT_RATIOS: [f64; 8] = [1.0, 3.0, 10.0, 30.0, 100.0, 300.0, 1000.0, f64::INFINITY];

/// Target restitutions of the default sweep.
pub const DEFAULT_TARGETS: [f64; 2] = [0.5, 0.9];

/// What to sweep.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RestitutionSpec {
    pub laws: Vec<DissipativeLaw>,
    /// Target restitutions e (0 < e ≤ 1) set on the pair.
    pub targets: Vec<f64>,
    /// r values (> 0, or ∞).
    pub radius_ratios: Vec<f64>,
    /// ζ values (> 0, or ∞).
    pub modulus_ratios: Vec<f64>,
    pub calibrations: Vec<CalibrationSite>,
}

impl Default for RestitutionSpec {
    fn default() -> Self {
        RestitutionSpec {
            laws: DissipativeLaw::ALL.to_vec(),
            targets: DEFAULT_TARGETS.to_vec(),
            radius_ratios: DEFAULT_RATIOS.to_vec(),
            modulus_ratios: DEFAULT_RATIOS.to_vec(),
            calibrations: CalibrationSite::ALL.to_vec(),
        }
    }
}

/// One simulated point of the sweep.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct RestitutionPoint {
    pub law: DissipativeLaw,
    pub calibration: CalibrationSite,
    /// The target e the coefficient was calibrated for.
    pub target: f64,
    pub radius_ratio: f64,
    pub modulus_ratio: f64,
    /// The raw coefficient used (unit: [`DissipativeLaw::coefficient_unit`]).
    pub coefficient: f64,
    /// The simulated contact.
    pub contact: ContactRecord,
}

impl RestitutionPoint {
    /// Effective restitution v_r/|v_c|.
    pub fn restitution(&self) -> f64 {
        self.contact.restitution
    }
}

/// The result of a sweep.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RestitutionStudy {
    /// The base scenario (particle, motion, integration, `contact.attractive`).
    pub scenario: Scenario,
    pub spec: RestitutionSpec,
    /// Every (law, calibration, target, r, ζ), in that nesting order.
    pub points: Vec<RestitutionPoint>,
}

impl RestitutionStudy {
    /// The point of these parameters, if swept.
    pub fn point(
        &self,
        law: DissipativeLaw,
        calibration: CalibrationSite,
        target: f64,
        radius_ratio: f64,
        modulus_ratio: f64,
    ) -> Option<&RestitutionPoint> {
        self.points.iter().find(|p| {
            p.law == law
                && p.calibration == calibration
                && p.target == target
                && p.radius_ratio == radius_ratio
                && p.modulus_ratio == modulus_ratio
        })
    }
}

fn input(msg: impl Into<String>) -> Error {
    Error::Request(msg.into())
}

/// The base scenario with the pair (r, ζ) and one contact.
fn pair_scenario(base: &Scenario, radius_ratio: f64, modulus_ratio: f64) -> Scenario {
    let mut s = *base;
    s.boundary.radius_ratio = radius_ratio;
    s.boundary.modulus_ratio = modulus_ratio;
    s.motion.contacts = 1;
    s
}

/// Checks the base scenario: valid, fixed boundary.
fn check_base(base: &Scenario) -> Result<()> {
    base.validate()
        .map_err(|e| input(format!("base scenario: {e}")))?;
    if !base.boundary.fixed {
        return Err(input(
            "the restitution study needs a fixed boundary (boundary.fixed = true), as in the paper",
        ));
    }
    Ok(())
}

fn check_ratio(name: &str, x: f64) -> Result<()> {
    if x > 0.0 && !x.is_nan() {
        Ok(())
    } else {
        Err(input(format!("{name} = {x}: must be > 0, or inf")))
    }
}

/// The raw coefficient of `law` calibrated for restitution `e` on the pair
/// (r, ζ) of `base` ([`CalibrationSite::Pair`]) or on the rigid wall
/// ([`CalibrationSite::Wall`]).
pub fn raw_coefficient(
    base: &Scenario,
    law: DissipativeLaw,
    calibration: CalibrationSite,
    e: f64,
    radius_ratio: f64,
    modulus_ratio: f64,
) -> Result<f64> {
    let s = match calibration {
        CalibrationSite::Wall => pair_scenario(base, f64::INFINITY, f64::INFINITY),
        CalibrationSite::Pair => pair_scenario(base, radius_ratio, modulus_ratio),
    };
    let pair = s.pair();
    let mass = s.reduced_mass();
    let target = Dissipation::Restitution(e);
    // How e becomes the coefficient: the base scenario's contact.calibration.
    let (mapping, attractive) = (
        s.contact.calibration.unwrap_or_default(),
        s.contact.attractive,
    );
    let (law_kind, damping) = law.contact();
    let model = ContactModel {
        law: law_kind,
        damping,
        dissipation: Some(target),
        attractive,
        calibration: mapping,
        params: Default::default(),
    };
    Ok(match law {
        DissipativeLaw::Viscous | DissipativeLaw::Tsuji | DissipativeLaw::Viscoelastic => {
            damping_coefficient(&model, &pair, mass, s.impact_speed())
                // A target the law cannot reach is bad input, not a failed run.
                .map_err(|error| {
                    Error::OutOfReach(format!(
                        "{law}, {calibration}-calibrated for r = {}, ζ = {}: {error}",
                        s.boundary.radius_ratio, s.boundary.modulus_ratio
                    ))
                })?
        }
        DissipativeLaw::WaltonBraun => pair.power_law_stiffness(1.0) / (e * e),
    })
}

/// One contact of `law` with raw coefficient `coefficient` on the pair
/// (r, ζ) of `base` (attraction as `base.contact.attractive`; Walton–Braun
/// never attracts).
pub fn simulate_coefficient(
    base: &Scenario,
    law: DissipativeLaw,
    coefficient: f64,
    radius_ratio: f64,
    modulus_ratio: f64,
) -> Result<ContactRecord> {
    let s = pair_scenario(base, radius_ratio, modulus_ratio);
    let fail = |error: Error| Error::StudyRun {
        law,
        radius_ratio,
        modulus_ratio,
        error: Box::new(error),
    };
    s.validate().map_err(fail)?;
    let pair = s.pair();
    let attractive = s.contact.attractive;
    let k1 = pair.power_law_stiffness(1.0);
    /// Runs the one contact with the law it is given.
    struct Visit<'a>(&'a Scenario);
    impl LawVisitor for Visit<'_> {
        type Output = Result<ContactRecord>;
        fn visit<L: NormalContactLaw>(self, law: L) -> Self::Output {
            run(self.0, law)
        }
    }
    match law {
        DissipativeLaw::Viscous | DissipativeLaw::Tsuji | DissipativeLaw::Viscoelastic => {
            let (law, damping) = law.contact();
            let model = ContactModel {
                law,
                damping,
                dissipation: Some(Dissipation::Coefficient(coefficient)),
                attractive,
                calibration: Default::default(),
                params: Default::default(),
            };
            with_damped(&model, &pair, s.reduced_mass(), coefficient, Visit(&s))
                .and_then(|outcome| outcome)
        }
        DissipativeLaw::WaltonBraun => run(
            &s,
            WaltonBraun {
                loading: k1,
                unloading: coefficient,
                residual_fraction: 1.0 - k1 / coefficient,
            },
        ),
    }
    .map_err(fail)
}

fn run<L: NormalContactLaw>(s: &Scenario, law: L) -> Result<ContactRecord> {
    let problem = Problem::new(s, &law)?;
    // Walton–Braun's unloading line must be resolved (e = 2e6 printed
    // for a target 1e-6 before).
    crate::bounce::check_unloading(s, &law, &problem)?;
    // A damped contact's Gear5 step must be stable (e = 0.59 printed for
    // a target 0.01 at η = 0.1 before).
    crate::bounce::check_damped_step(s, &law, &problem)?;
    let outcome = match s.integration.scheme {
        Scheme::Gear5 => {
            let gear = Gear5::for_force(law.depends_on_rate());
            simulate_with(&law, gear, &problem, &mut ())?
        }
        Scheme::Verlet => simulate_with(&law, Verlet, &problem, &mut ())?,
    };
    Ok(outcome.contacts[0])
}

/// The restitution study: every law × calibration × target × r × ζ of
/// `spec`, on the base scenario `base` (its particle, motion, integration
/// and `contact.attractive`; its contact law and boundary ratios are
/// replaced). Points run in parallel (rayon).
pub fn restitution_sweep(base: &Scenario, spec: &RestitutionSpec) -> Result<RestitutionStudy> {
    check_base(base)?;
    let lists = [
        ("--law", spec.laws.is_empty()),
        ("--e", spec.targets.is_empty()),
        ("--r", spec.radius_ratios.is_empty()),
        ("--zeta", spec.modulus_ratios.is_empty()),
        ("--calibrate", spec.calibrations.is_empty()),
    ];
    if let Some((name, _)) = lists.iter().find(|(_, empty)| *empty) {
        return Err(input(format!("{name}: at least one value is needed")));
    }
    for &e in &spec.targets {
        if !(e > 0.0 && e <= 1.0) {
            return Err(input(format!(
                "target restitution e = {e}: must be 0 < e ≤ 1"
            )));
        }
    }
    for &r in &spec.radius_ratios {
        check_ratio("r", r)?;
    }
    for &z in &spec.modulus_ratios {
        check_ratio("ζ", z)?;
    }
    let mut jobs = Vec::new();
    for &law in &spec.laws {
        for &calibration in &spec.calibrations {
            for &target in &spec.targets {
                for &r in &spec.radius_ratios {
                    for &z in &spec.modulus_ratios {
                        jobs.push((law, calibration, target, r, z));
                    }
                }
            }
        }
    }
    // Wall coefficients once per (law, target): the viscoelastic one is a root search.
    let mut walls: Vec<((DissipativeLaw, u64), f64)> = Vec::new();
    if spec.calibrations.contains(&CalibrationSite::Wall) {
        let keys: Vec<(DissipativeLaw, f64)> = spec
            .laws
            .iter()
            .flat_map(|&l| spec.targets.iter().map(move |&e| (l, e)))
            .collect();
        walls = keys
            .into_par_iter()
            .map(|(law, e)| {
                raw_coefficient(
                    base,
                    law,
                    CalibrationSite::Wall,
                    e,
                    f64::INFINITY,
                    f64::INFINITY,
                )
                .map(|c| ((law, e.to_bits()), c))
            })
            .collect::<Result<_, _>>()?;
    }
    let points = jobs
        .into_par_iter()
        .map(|(law, calibration, target, r, z)| {
            let coefficient = match calibration {
                CalibrationSite::Wall => walls
                    .iter()
                    .find(|(k, _)| *k == (law, target.to_bits()))
                    .map(|(_, c)| *c)
                    .ok_or_else(|| input("internal error: wall coefficient missing"))?,
                CalibrationSite::Pair => raw_coefficient(base, law, calibration, target, r, z)?,
            };
            let contact = simulate_coefficient(base, law, coefficient, r, z)?;
            Ok(RestitutionPoint {
                law,
                calibration,
                target,
                radius_ratio: r,
                modulus_ratio: z,
                coefficient,
                contact,
            })
        })
        .collect::<Result<Vec<_>>>()?;
    Ok(RestitutionStudy {
        scenario: *base,
        spec: spec.clone(),
        points,
    })
}

/// The answer to the reverse question.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct RequiredRestitution {
    pub law: DissipativeLaw,
    pub calibration: CalibrationSite,
    /// The rebound wanted on the boundary particle, E.
    pub target: f64,
    pub radius_ratio: f64,
    pub modulus_ratio: f64,
    /// The e to enter (calibrated by `calibration`).
    pub enter: f64,
    /// The raw coefficient it gives (unit: [`DissipativeLaw::coefficient_unit`]).
    pub coefficient: f64,
    /// The simulated rebound on the pair with that coefficient.
    pub achieved: f64,
    /// The simulated rebound on the pair when E itself is entered; `None`
    /// when E itself is refused (the law cannot be calibrated for it, or
    /// the step does not resolve Walton–Braun's unloading line at it).
    pub naive: Option<f64>,
}

/// Root-search convergence: x to 1e−13 or the function exactly zero.
struct Tight;

impl Convergency<f64> for Tight {
    fn is_root_found(&mut self, y: f64) -> bool {
        y == 0.0
    }
    fn is_converged(&mut self, x1: f64, x2: f64) -> bool {
        (x1 - x2).abs() <= 1e-13
    }
    fn is_iteration_limit_reached(&mut self, iter: usize) -> bool {
        iter >= 200
    }
}

/// The reverse question: which e to enter (with `calibration`: on the wall,
/// the coefficient then reused; or on the pair) so that a particle of
/// `base` rebounds from the boundary particle (r, ζ) with restitution
/// `target`. Brent's method (`roots`) on the simulated restitution as a
/// function of the entered e (it grows with e).
pub fn required_restitution(
    base: &Scenario,
    law: DissipativeLaw,
    calibration: CalibrationSite,
    target: f64,
    radius_ratio: f64,
    modulus_ratio: f64,
) -> Result<RequiredRestitution> {
    check_base(base)?;
    if !(target > 0.0 && target < 1.0) {
        return Err(input(format!(
            "--target {target}: the wanted restitution must be 0 < E < 1"
        )));
    }
    check_ratio("r", radius_ratio)?;
    check_ratio("ζ", modulus_ratio)?;
    let rebound = |e: f64| -> Result<(f64, f64)> {
        let c = raw_coefficient(base, law, calibration, e, radius_ratio, modulus_ratio)?;
        match simulate_coefficient(base, law, c, radius_ratio, modulus_ratio) {
            Ok(contact) => Ok((contact.restitution, c)),
            // Damped so hard the particle never leaves: no rebound at all.
            Err(Error::StudyRun { error, .. }) if matches!(*error, Error::NoRebound { .. }) => {
                Ok((0.0, c))
            }
            Err(e) => Err(e),
        }
    };
    let (top, _) = rebound(1.0)?;
    if top <= target {
        return Err(Error::OutOfReach(format!(
            "a rebound of E = {target} on r = {radius_ratio}, ζ = {modulus_ratio} is out of reach of \
             {law} with {calibration} calibration: even e = 1 gives {top:.6}"
        )));
    }
    // Bracket [lo, hi] with rebound(lo) < E < rebound(hi), halving e from E.
    let unreachable = |why: String| {
        Error::OutOfReach(format!(
            "a rebound of E = {target} on r = {radius_ratio}, ζ = {modulus_ratio} is out of reach of \
             {law} with {calibration} calibration: {why}"
        ))
    };
    // An entered e the law cannot be calibrated for (viscoelastic δ out of
    // range) or whose Walton–Braun unloading line the step does not resolve
    // is refused; the rebound grows with e, so the smallest accepted e
    // gives the smallest reachable E, and a smaller --target is refused
    // naming it (not the internal e that failed).
    let refused = |err: &Error| match err {
        Error::OutOfReach(_) => Some(format!(
            "{law} cannot be calibrated for a smaller e at this impact speed"
        )),
        Error::StudyRun { error, .. } => match &**error {
            Error::Input { field, .. } if field == "contact.restitution" => Some(
                "Walton–Braun's unloading line k₂ = k₁/e² would not be resolved by the step \
                 (a smaller integration.eta or integration.dt reaches lower)"
                    .to_string(),
            ),
            _ => None,
        },
        _ => None,
    };
    // The smallest accepted e in (bad, good] (bisection in log e to 1e−6
    // relative) and its rebound: Ok(e, rebound) if that rebound is below
    // the target (a bracket), else the refusal naming --target.
    let floor = |mut bad: f64, mut good: f64, why: String| -> Result<(f64, f64)> {
        while good / bad - 1.0 > 1e-6 {
            let mid = (bad * good).sqrt();
            match rebound(mid) {
                Ok(_) => good = mid,
                Err(err) if refused(&err).is_some() => bad = mid,
                Err(err) => return Err(err),
            }
        }
        let (lowest, _) = rebound(good)?;
        if lowest < target {
            return Ok((good, lowest));
        }
        Err(Error::Input {
            field: "--target".into(),
            value: target.to_string(),
            allowed: format!(
                "{lowest:.6} ≤ E < {top:.6} for {law} with {calibration} calibration on \
                 r = {radius_ratio}, ζ = {modulus_ratio} at this step: a smaller rebound needs \
                 an entered e below {good:.4e}, and {why}"
            ),
        })
    };
    let (mut lo, mut hi) = (target, 1.0);
    let naive = match rebound(target) {
        Ok((e, _)) => Some(e),
        Err(err) => match refused(&err) {
            // E itself is refused: the bracket starts at the smallest accepted e.
            Some(why) => {
                lo = floor(target, 1.0, why)?.0;
                None
            }
            None => return Err(err),
        },
    };
    if naive.is_some_and(|e| e >= target) {
        hi = target;
        loop {
            lo *= 0.5;
            if lo < 1e-6 {
                let slowest = rebound(2.0 * lo)?.0;
                return Err(unreachable(format!(
                    "even e = {:.1e} rebounds with {slowest:.6} (with attraction forbidden the \
                     rebound of the damped laws does not vanish with e)",
                    2.0 * lo
                )));
            }
            let e_lo = match rebound(lo) {
                Ok((e, _)) => e,
                Err(err) => match refused(&err) {
                    Some(why) => {
                        lo = floor(lo, hi, why)?.0;
                        break;
                    }
                    None => return Err(err),
                },
            };
            if e_lo < target {
                break;
            }
            hi = lo;
        }
    }
    let mut failure = None;
    let f = |e: f64| match rebound(e) {
        Ok((r, _)) => r - target,
        Err(err) => {
            failure.get_or_insert(err);
            f64::NAN
        }
    };
    let root = find_root_brent(lo, hi, f, &mut Tight);
    if let Some(err) = failure {
        return Err(err);
    }
    let enter = root.map_err(|e| {
        Error::OutOfReach(format!(
            "the root search for E = {target} ({law}, {calibration}) failed: {e}"
        ))
    })?;
    let (achieved, coefficient) = rebound(enter)?;
    Ok(RequiredRestitution {
        law,
        calibration,
        target,
        radius_ratio,
        modulus_ratio,
        enter,
        coefficient,
        achieved,
        naive,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bounce::simulate;

    #[test]
    fn the_study_path_matches_a_scenario_with_the_raw_coefficient() {
        for law in [
            DissipativeLaw::Viscous,
            DissipativeLaw::Tsuji,
            DissipativeLaw::Viscoelastic,
        ] {
            let base = Scenario::default();
            let c = raw_coefficient(&base, law, CalibrationSite::Wall, 0.6, 30.0, 10.0).unwrap();
            let study = simulate_coefficient(&base, law, c, 30.0, 10.0).unwrap();
            let mut s = pair_scenario(&base, 30.0, 10.0);
            (s.contact.law, s.contact.damping) = law.contact();
            s.contact.damping_coefficient = Some(c);
            let direct = simulate(&s, &mut ()).unwrap().contacts[0];
            assert_eq!(study, direct, "{law}");
        }
    }

    #[test]
    fn pair_calibration_does_not_depend_on_the_pair_and_walton_braun_is_exact() {
        // Gravity-free, attraction forbidden: e is a function of the
        // dimensionless damping the pair calibration holds fixed.
        let mut base = Scenario::default();
        base.motion.gravity = 0.0;
        base.motion.velocity = -0.313;
        let e_of = |law, r, z| {
            let c = raw_coefficient(&base, law, CalibrationSite::Pair, 0.7, r, z).unwrap();
            simulate_coefficient(&base, law, c, r, z)
                .unwrap()
                .restitution
        };
        for law in DissipativeLaw::ALL {
            let (soft, wall) = (
                e_of(law, 3.0, 10.0),
                e_of(law, f64::INFINITY, f64::INFINITY),
            );
            assert!((soft - wall).abs() < 1e-5, "{law}: {soft} {wall}");
            if law == DissipativeLaw::WaltonBraun {
                assert!((soft - 0.7).abs() < 1e-7, "{soft}");
            }
        }
        // Wall calibration: Walton–Braun e = e_wall √(k1/k1(∞)).
        let c = raw_coefficient(
            &base,
            DissipativeLaw::WaltonBraun,
            CalibrationSite::Wall,
            0.7,
            3.0,
            10.0,
        )
        .unwrap();
        let e = simulate_coefficient(&base, DissipativeLaw::WaltonBraun, c, 3.0, 10.0)
            .unwrap()
            .restitution;
        let ratio = (3.0 / 4.0) * (10.0 / 11.0);
        assert!((e - 0.7 * f64::sqrt(ratio)).abs() < 1e-7, "{e}");
    }

    #[test]
    fn a_target_below_what_the_step_resolves_is_refused_naming_target() {
        // Walton–Braun, wall calibration, on r = ζ = 1 gravity-free: the
        // rebound is the entered e times √(k₁/k₁(∞)) = √(1/2 · 1/2) = 1/2
        // (the test above), and the pair's own e = √(k₁/k₂) must be at
        // least a/(0.9 − a), a = η π/2 (η = 1/50, Gear5's ω₂Δt ≤ 0.9; see
        // `check_unloading`) = 0.036169. So E = 0.01 is out of reach (its
        // entered e, 0.02, and any e below 0.072338 are refused), reported
        // against --target with the reachable floor, the rebound at
        // e = 0.036169; session 34 saw the internal e = 0.005
        // named as `contact.restitution` instead. E = 0.05 is reachable
        // although E itself (entered e 0.05 → pair e 0.025) is refused:
        // enter e = 2E = 0.1, within Gear5's error in e at the pair's
        // ω₂Δt ≈ 0.9 · 0.036/0.05 = 0.65, 0.14 % (`limits`): 0.3 %.
        let mut base = Scenario::default();
        base.motion.gravity = 0.0;
        base.motion.velocity = -0.313;
        base.motion.contacts = 1;
        let (wb, wall) = (DissipativeLaw::WaltonBraun, CalibrationSite::Wall);
        let a = 0.02 * std::f64::consts::FRAC_PI_2;
        let e_min = a / (0.9 - a);
        match required_restitution(&base, wb, wall, 0.01, 1.0, 1.0) {
            Err(Error::Input {
                field,
                value,
                allowed,
            }) => {
                assert_eq!((field.as_str(), value.as_str()), ("--target", "0.01"));
                // The smallest entered e, 2 e_min (printed to 5 digits:
                // 1e−4 relative); its rebound e_min within Gear5's error at
                // ω₂Δt = 0.9, 0.64–0.76 % (`limits`): 1 %.
                let number = |after: &str| -> f64 {
                    let tail = &allowed[allowed.find(after).unwrap() + after.len()..];
                    tail.split([' ', ',']).next().unwrap().parse().unwrap()
                };
                let entered = number("an entered e below ");
                assert!((entered / (2.0 * e_min) - 1.0).abs() < 1e-4, "{allowed}");
                let floor: f64 = allowed.split(' ').next().unwrap().parse().unwrap();
                assert!((floor / e_min - 1.0).abs() < 0.01, "{allowed}");
                assert!(allowed.contains("integration.eta"), "{allowed}");
            }
            other => panic!("{other:?}"),
        }
        let ok = required_restitution(&base, wb, wall, 0.05, 1.0, 1.0).unwrap();
        assert_eq!(ok.naive, None);
        assert!((ok.enter / 0.1 - 1.0).abs() < 3e-3, "{ok:?}");
        assert!((ok.achieved - 0.05).abs() < 1e-7, "{ok:?}");
        // The viscoelastic law's own floor (δ ≤ 30) is named the same way.
        let e = required_restitution(&base, DissipativeLaw::Viscoelastic, wall, 1e-5, 1.0, 1.0)
            .unwrap_err();
        assert!(
            matches!(e, Error::Input { ref field, .. } if field == "--target"),
            "{e:?}"
        );
    }
}
