//! `particle-wall --tolerance`: the boundary spheres' size from the
//! single-contact study (issue 29 item 2), and the deviations of a size
//! given by `--radius`.
//!
//! The reference is the real wall: a flat wall (r = ∞) of the part's
//! material (E_b, ν_b of the scenario's boundary, as `recommend
//! --reference half-space`), hit by the scenario's particle at its impact
//! speed. The spheres are of the part's material too (ζ = E_b/E_m, the
//! scenario's), so only r is solved: for every law and quantity asked, the
//! smallest r that keeps |q(r, ζ)/q(∞, ζ) − 1| ≤ T, by `recommend`'s own
//! search ([`smallest_against`]); the choice is the largest of these (all
//! quantities within T). The geometric limits (leaks, bumps) are checked on
//! the covering by the caller.

use super::lists;
use super::recommend::{core_error, quantities, tolerance};
use super::{CliError, CliResult};
use crate::scenario_file::ScenarioArgs;
use anyhow::anyhow;
use clap::Args;
use dembound_core::bounce::Scenario;
use dembound_core::contact::ContactLawKind;
use dembound_core::study::recommend::{
    deviations_from, smallest_against, Deviations, Limit, Outcome, Reference,
};
use dembound_core::study::{Axis, Quantity};

/// The particle, the part's material and the question, as `recommend`
/// takes them.
#[derive(Debug, Args)]
pub struct ChoiceArgs {
    /// The particle and the part's material: the scenario's `particle.*`
    /// (R_m, E_m, ν_m, ρ) and `boundary.youngs_modulus` (or
    /// `modulus_ratio`) and `boundary.poisson_ratio` (the part's material),
    /// e.g. `--set boundary.youngs_modulus=200e9`; the drop (`motion.*`)
    /// gives the impact speed unless --speed does
    #[command(flatten)]
    pub scenario: ScenarioArgs,

    /// Choose R_b: the smallest spheres (of the part's material) that keep
    /// each --quantity within T of the flat wall of the part's material,
    /// as `recommend --reference half-space` (a fraction 0.03 or a
    /// percentage 3%); instead of --radius
    #[arg(long, value_name = "T", allow_hyphen_values = true)]
    pub tolerance: Option<String>,

    /// Quantities kept within T: max_overlap (h_max), duration (T_c),
    /// max_acceleration (a_max), comma-separated [default: all three]
    #[arg(long, value_name = "LIST")]
    pub quantity: Option<String>,

    /// Contact laws: `linear,hertz` or `power=1.25` [default: the
    /// scenario's contact.law]
    #[arg(long, value_name = "LIST")]
    pub law: Option<String>,

    /// Impact speed, m/s: the particle meets the wall at V (sets
    /// motion.gap = 0 and motion.velocity = −V)
    #[arg(long, value_name = "V", allow_hyphen_values = true)]
    pub speed: Option<f64>,
}

/// The question read from the arguments.
pub struct Question {
    /// The particle, the part's material (boundary ζ, ν_b) and the drop.
    pub base: Scenario,
    pub laws: Vec<ContactLawKind>,
    pub quantities: Vec<Quantity>,
    /// T, a fraction; `None` with --radius.
    pub tolerance: Option<f64>,
}

impl Question {
    /// ζ of the part's material (and of the spheres).
    pub fn modulus_ratio(&self) -> f64 {
        self.base.boundary.modulus_ratio
    }
}

pub fn question(args: &ChoiceArgs) -> CliResult<Question> {
    let extra = match args.speed {
        None => Vec::new(),
        Some(v) if v > 0.0 && v.is_finite() => {
            vec![
                "motion.gap=0".to_string(),
                format!("motion.velocity={:?}", -v),
            ]
        }
        Some(v) => {
            return Err(CliError::input(anyhow!(
                "invalid value for `--speed`: {v} (allowed: a finite impact speed > 0 m/s)"
            )))
        }
    };
    let base = args
        .scenario
        .load_with(&extra)
        .map_err(|e| {
            if args.speed.is_some() {
                CliError::input(e.context("with --speed"))
            } else {
                CliError::input(e)
            }
        })?
        .resolved();
    let laws = match &args.law {
        Some(l) => lists::laws_for("--law", l, "recommend").map_err(CliError::input)?,
        None => vec![base.contact.law],
    };
    let quantities = quantities(args.quantity.as_deref()).map_err(CliError::input)?;
    let tolerance = args
        .tolerance
        .as_deref()
        .map(tolerance)
        .transpose()
        .map_err(CliError::input)?;
    Ok(Question {
        base,
        laws,
        quantities,
        tolerance,
    })
}

/// The smallest r of every (law, quantity) and the choice: the largest of
/// them. `Err` naming --tolerance when no r or every r satisfies it.
pub fn choose(q: &Question, t: f64) -> CliResult<(f64, Vec<Limit>)> {
    let mut limits = Vec::new();
    for &law in &q.laws {
        for &quantity in &q.quantities {
            limits.push(
                smallest_against(
                    &q.base,
                    law,
                    quantity,
                    t,
                    Axis::Radius,
                    q.modulus_ratio(),
                    Reference::HalfSpace,
                )
                .map_err(core_error)?,
            );
        }
    }
    if let Some(l) = limits
        .iter()
        .find(|l| matches!(l.outcome, Outcome::Unreachable { .. }))
    {
        return Err(CliError::input(anyhow!(
            "invalid value for `--tolerance`: {} % (no sphere size keeps {} of the {} law within it)",
            t * 100.0,
            l.quantity.symbol(),
            l.law.name()
        )));
    }
    let r = limits
        .iter()
        .filter_map(Limit::value)
        .fold(f64::NEG_INFINITY, f64::max);
    if !r.is_finite() {
        return Err(CliError::input(anyhow!(
            "invalid value for `--tolerance`: {} % (every sphere size keeps the quantities within \
             it: nothing to choose; give --radius)",
            t * 100.0
        )));
    }
    Ok((r, limits))
}

/// The deviations at r from the flat wall of the part's material, per law,
/// the asked quantities only.
pub fn deviations(q: &Question, r: f64) -> CliResult<Vec<Deviations>> {
    q.laws
        .iter()
        .map(|&law| {
            let mut d = deviations_from(&q.base, law, r, q.modulus_ratio(), Reference::HalfSpace)
                .map_err(core_error)?;
            d.quantities.retain(|x| q.quantities.contains(&x.quantity));
            Ok(d)
        })
        .collect()
}

/// The largest deviation (exact model) of a set, a fraction.
pub fn largest(ds: &[Deviations]) -> f64 {
    ds.iter()
        .flat_map(|d| d.quantities.iter().map(|x| x.exact))
        .fold(0.0, f64::max)
}
