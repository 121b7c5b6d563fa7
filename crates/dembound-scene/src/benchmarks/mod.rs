//! The engine's validation suite (`dembound benchmarks`, issue 30): each
//! benchmark a scene built here from published parameters, run, measured
//! and compared with its reference (a closed form derived in
//! [`closed_form`], or published points with their source). No files: the
//! CLI renders [`Outcome`] (tables, figures, report).
//!
//! Every parameter and every published number carries its source in the
//! benchmark's `parameters` and `notes`, which the report prints.

mod beverloo;
mod chung_ooi;
mod chung_ooi_oblique;
pub mod closed_form;
mod column_collapse;
mod digitised;
mod drum;
mod granular;
pub mod impact;
mod janssen;
mod peer;
mod repose;
mod repose_angle;
mod repose_zhou;

use crate::SceneError;
use std::time::Instant;

/// How far ours may be from the reference.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Band {
    /// |ours/published − 1| ≤ this.
    Relative(f64),
    /// |ours − published| ≤ this, in the quantity's unit.
    Absolute(f64),
    /// ours ≥ published: a one-sided bound (a sign resolved beyond its
    /// error, a lower limit).
    AtLeast,
}

/// One compared number.
#[derive(Debug, Clone, PartialEq)]
pub struct Check {
    pub quantity: String,
    /// SI unit, `1` for a ratio.
    pub unit: String,
    pub ours: f64,
    pub published: f64,
    pub band: Band,
    /// Where the published value comes from.
    pub reference: String,
}

impl Check {
    pub fn new(
        quantity: impl Into<String>,
        unit: &str,
        ours: f64,
        published: f64,
        band: Band,
        reference: impl Into<String>,
    ) -> Self {
        Self {
            quantity: quantity.into(),
            unit: unit.into(),
            ours,
            published,
            band,
            reference: reference.into(),
        }
    }

    /// Whether ours is within the band (a non-finite value never is).
    pub fn passes(&self) -> bool {
        if !(self.ours.is_finite() && self.published.is_finite()) {
            return false;
        }
        match self.band {
            Band::Relative(b) => (self.ours / self.published - 1.0).abs() <= b,
            Band::Absolute(b) => (self.ours - self.published).abs() <= b,
            Band::AtLeast => self.ours >= self.published,
        }
    }
}

/// How a curve is drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Style {
    /// The engine's points.
    Ours,
    /// The engine's points, not joined (positions of grains, regimes).
    OursPoints,
    /// A closed form (line).
    ClosedForm,
    /// Published points (digitised).
    Published,
    /// An edge of the pass band (dashed).
    Band,
    /// Another code's points for the same model (`peer.rs`), not joined,
    /// in the case's colour.
    Peer,
    /// An error bar: a segment of two points, in the case's colour.
    ErrorBar,
}

#[derive(Debug, Clone, PartialEq)]
pub struct Curve {
    pub label: String,
    pub points: Vec<(f64, f64)>,
    pub style: Style,
    /// Series sharing a colour share a material or case.
    pub group: usize,
}

impl Curve {
    pub fn new(
        label: impl Into<String>,
        points: Vec<(f64, f64)>,
        style: Style,
        group: usize,
    ) -> Self {
        Self {
            label: label.into(),
            points,
            style,
            group,
        }
    }
}

/// One figure: axis labels carry units.
#[derive(Debug, Clone, PartialEq)]
pub struct Plot {
    /// File stem.
    pub stem: String,
    pub title: String,
    pub x_label: String,
    pub y_label: String,
    pub curves: Vec<Curve>,
}

/// Everything one benchmark reports.
#[derive(Debug, Clone, PartialEq)]
pub struct Outcome {
    pub name: &'static str,
    pub title: &'static str,
    /// The publication the benchmark reproduces.
    pub source: &'static str,
    /// Inputs, each with its source.
    pub parameters: Vec<String>,
    /// The model used, differences from the publication, what is doubtful.
    pub notes: Vec<String>,
    pub checks: Vec<Check>,
    pub plots: Vec<Plot>,
    /// Wall-clock time of the runs, s.
    pub seconds: f64,
}

impl Outcome {
    pub fn passes(&self) -> bool {
        self.checks.iter().all(Check::passes)
    }
}

type Runner = fn(bool, &dyn Fn(&str)) -> Result<Outcome, SceneError>;

/// The benchmarks: name, one-line title, runner.
const BENCHMARKS: [(&str, &str, Runner); 13] = [
    (
        "chung-ooi-1",
        "Elastic normal impact of two identical spheres",
        chung_ooi::test1,
    ),
    (
        "chung-ooi-2",
        "Elastic normal impact of a sphere with a rigid plane",
        chung_ooi::test2,
    ),
    (
        "chung-ooi-3",
        "Normal impact with different restitution coefficients",
        chung_ooi::test3,
    ),
    (
        "chung-ooi-4",
        "Oblique impact on a rigid plane: constant speed, varying incident angle",
        chung_ooi_oblique::test4,
    ),
    (
        "chung-ooi-5",
        "Oblique impact on a rigid plane: constant normal, varying tangential velocity",
        chung_ooi_oblique::test5,
    ),
    (
        "chung-ooi-6",
        "Impact of a spinning sphere on a rigid plane",
        chung_ooi_oblique::test6,
    ),
    (
        "chung-ooi-7",
        "Impact of two identical spinning spheres",
        chung_ooi_oblique::test7,
    ),
    (
        "chung-ooi-8",
        "Impact of a spinning sphere on a different sphere",
        chung_ooi_oblique::test8,
    ),
    ("janssen", janssen::TITLE, janssen::run),
    (
        "column-collapse",
        column_collapse::TITLE,
        column_collapse::run,
    ),
    ("repose", repose::TITLE, repose::run),
    ("drum", drum::TITLE, drum::run),
    ("beverloo", beverloo::TITLE, beverloo::run),
];

/// Every benchmark's name, in the report's order.
pub fn names() -> Vec<&'static str> {
    BENCHMARKS.iter().map(|b| b.0).collect()
}

/// The one-line title of `name`, if it is a benchmark.
pub fn title(name: &str) -> Option<&'static str> {
    BENCHMARKS.iter().find(|b| b.0 == name).map(|b| b.1)
}

/// Runs benchmark `name` (full, or the small `quick` version); `progress`
/// receives a line per stage.
pub fn run(name: &str, quick: bool, progress: &dyn Fn(&str)) -> Result<Outcome, SceneError> {
    let Some(&(_, _, runner)) = BENCHMARKS.iter().find(|b| b.0 == name) else {
        return Err(SceneError::invalid(
            "benchmark",
            name,
            format!("one of {}", names().join(", ")),
        ));
    };
    let start = Instant::now();
    let mut out = runner(quick, progress)?;
    out.seconds = start.elapsed().as_secs_f64();
    Ok(out)
}

/// The benchmarks a number of seeds applies to (`--seeds`): those that
/// repeat a random scene and report the mean over the repeats.
pub const SEEDED: [&str; 1] = ["repose"];

/// The most seeds `run_seeded` takes.
pub const MAX_SEEDS: usize = repose::MAX_SEEDS;

/// As [`run`], with `seeds` repeats of each random scene (`None`: the
/// benchmark's default); a number of seeds is refused by a benchmark not
/// in [`SEEDED`].
pub fn run_seeded(
    name: &str,
    quick: bool,
    seeds: Option<usize>,
    progress: &dyn Fn(&str),
) -> Result<Outcome, SceneError> {
    let Some(n) = seeds else {
        return run(name, quick, progress);
    };
    if name != "repose" {
        return Err(SceneError::invalid(
            "seeds",
            format!("{n} for benchmark {name}"),
            format!("only for {}", SEEDED.join(", ")),
        ));
    }
    let start = Instant::now();
    let mut out = repose::run_seeded(quick, Some(n), progress)?;
    out.seconds = start.elapsed().as_secs_f64();
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bands_decide_the_verdict() {
        let c = Check::new("x", "1", 1.01, 1.0, Band::Relative(0.02), "");
        assert!(c.passes());
        let c = Check::new("x", "1", 1.03, 1.0, Band::Relative(0.02), "");
        assert!(!c.passes());
        let c = Check::new("x", "1", f64::NAN, 1.0, Band::Absolute(1.0), "");
        assert!(!c.passes());
        assert!(Check::new("x", "1", -0.5, 0.0, Band::Absolute(0.5), "").passes());
        assert!(Check::new("x", "1", 0.5, 0.5, Band::AtLeast, "").passes());
        assert!(!Check::new("x", "1", 0.4, 0.5, Band::AtLeast, "").passes());
    }

    #[test]
    fn an_unknown_name_is_refused_with_the_list() {
        let e = run("nope", true, &|_| {}).unwrap_err().to_string();
        assert!(
            e.contains("nope") && e.contains("chung-ooi-1") && e.contains("chung-ooi-8"),
            "{e}"
        );
    }
}
