//! `[[inlet]]` (addition, issue 28): spheres inserted during the run in a
//! region (`crate::inlets`). Keys: `region` (`{ box = { lower, upper } }`
//! or `{ cylinder = { center, axis, radius, length } }`, m), `rate`
//! (`{ number = N }` spheres/s or `{ mass = Q }` kg/s), `size` (radii in
//! m: `{ fixed = R }`, `{ uniform = [Rmin, Rmax] }`, `{ normal = { mean,
//! std, min, max } }` or `{ table = [[R, fraction], …] }`, fractions by
//! number), `material` (a `[[material]]` name), `velocity` (m/s, default
//! 0), `start` and `end` (s; default 0 and the run's end), `seed`
//! (default 0), `every` (steps between insertion events; default from the
//! rate, `crate::inlets`), `max_attempts` (centres tried per sphere,
//! default 100).

use super::checks::{check, positive, speed};
use super::{SceneError, SceneFile};
use crate::inlets::{InletRate, InletSetup, SizeDistribution, MAX_TABLE_ROWS};
use crate::region::Region;
use serde::{Deserialize, Serialize};

/// One `[[inlet]]`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct InletSection {
    pub region: Region,
    pub rate: RateSection,
    pub size: SizeSection,
    pub material: String,
    /// m/s.
    #[serde(default)]
    pub velocity: [f64; 3],
    /// s.
    #[serde(default)]
    pub start: f64,
    /// s; absent: the run's end.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub end: Option<f64>,
    #[serde(default)]
    pub seed: u64,
    /// Steps between insertion events; absent: chosen from the rate.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub every: Option<u64>,
    #[serde(default = "default_attempts")]
    pub max_attempts: u64,
}

fn default_attempts() -> u64 {
    crate::inlets::DEFAULT_MAX_ATTEMPTS
}

/// `rate`: spheres per second or kilograms per second.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase", deny_unknown_fields)]
pub enum RateSection {
    /// Spheres/s.
    Number(f64),
    /// kg/s.
    Mass(f64),
}

/// `size`: the radius distribution, m.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase", deny_unknown_fields)]
pub enum SizeSection {
    Fixed(f64),
    Uniform([f64; 2]),
    Normal {
        mean: f64,
        std: f64,
        min: f64,
        max: f64,
    },
    /// Rows `[R, fraction]`, fractions by number (normalised to their sum).
    Table(Vec<[f64; 2]>),
}

impl SceneFile {
    pub(super) fn validate_inlets(&self) -> Result<(), SceneError> {
        for (i, s) in self.inlets.iter().enumerate() {
            let key = |k: &str| format!("inlet[{i}].{k}");
            s.region.validate(&key("region"))?;
            match s.rate {
                RateSection::Number(n) => positive(&key("rate.number"), n, "spheres/s")?,
                RateSection::Mass(m) => positive(&key("rate.mass"), m, "kg/s")?,
            }
            match &s.size {
                SizeSection::Fixed(r) => positive(&key("size.fixed"), *r, "m")?,
                SizeSection::Uniform([lo, hi]) => {
                    positive(&key("size.uniform"), *lo, "m")?;
                    check(
                        hi.is_finite() && hi >= lo,
                        &key("size.uniform"),
                        format!("[{lo}, {hi}]"),
                        "[Rmin, Rmax] with 0 < Rmin ≤ Rmax, m",
                    )?;
                }
                SizeSection::Normal {
                    mean,
                    std,
                    min,
                    max,
                } => {
                    positive(&key("size.normal.mean"), *mean, "m")?;
                    check(
                        std.is_finite() && *std >= 0.0,
                        &key("size.normal.std"),
                        std,
                        "finite and ≥ 0, in m",
                    )?;
                    positive(&key("size.normal.min"), *min, "m")?;
                    check(
                        max.is_finite() && max >= min && mean >= min && mean <= max,
                        &key("size.normal.max"),
                        max,
                        &format!("finite, ≥ size.normal.min ({min}) and ≥ size.normal.mean ({mean}) (mean within [min, max]), m"),
                    )?;
                }
                SizeSection::Table(rows) => {
                    check(
                        !rows.is_empty() && rows.len() <= MAX_TABLE_ROWS,
                        &key("size.table"),
                        format!("{} rows", rows.len()),
                        &format!("1 to {MAX_TABLE_ROWS} rows [R (m), fraction by number]"),
                    )?;
                    for (r, row) in rows.iter().enumerate() {
                        positive(&key(&format!("size.table[{r}][0]")), row[0], "m")?;
                        check(
                            row[1].is_finite() && row[1] >= 0.0,
                            &key(&format!("size.table[{r}][1]")),
                            row[1],
                            "a fraction by number, finite and ≥ 0",
                        )?;
                    }
                    check(
                        rows.iter().any(|r| r[1] > 0.0),
                        &key("size.table"),
                        "all fractions 0",
                        "at least one fraction > 0",
                    )?;
                }
            }
            check(
                self.material_known(&s.material),
                &key("material"),
                format!("{:?}", s.material),
                &format!("one of the [[material]] names: {}", self.material_names()),
            )?;
            if let Some(m) = self.materials.iter().find(|m| m.name == s.material) {
                check(
                    m.density.is_finite(),
                    &key("material"),
                    format!("{:?}", s.material),
                    "a material of finite density (inserted spheres are free)",
                )?;
            }
            speed(&key("velocity"), s.velocity)?;
            check(
                s.start.is_finite() && s.start >= 0.0,
                &key("start"),
                s.start,
                "finite and ≥ 0, in s",
            )?;
            if let Some(end) = s.end {
                check(
                    end.is_finite() && end > s.start,
                    &key("end"),
                    end,
                    &format!("finite and > inlet[{i}].start ({} s), in s", s.start),
                )?;
            }
            if let Some(every) = s.every {
                check(
                    (1..=1_000_000_000).contains(&every),
                    &key("every"),
                    every,
                    "1 to 1e9 steps",
                )?;
            }
            check(
                (1..=1_000_000).contains(&s.max_attempts),
                &key("max_attempts"),
                s.max_attempts,
                "1 to 1e6 centres tried per sphere",
            )?;
            let d = &self.domain;
            let (lo, hi) = self.inlet_setup(i, 0).region.bounds();
            check(
                (0..3).all(|a| lo[a] >= d.lower[a] && hi[a] <= d.upper[a]),
                &key("region"),
                format!("spanning {lo:?} to {hi:?} m"),
                &format!(
                    "a region inside the domain ({:?} to {:?} m)",
                    d.lower, d.upper
                ),
            )?;
            let setup = self.inlet_setup(i, 0);
            let r_max = setup.size.max_radius();
            check(
                setup.region.fits(r_max),
                &key("region"),
                format!("spanning {lo:?} to {hi:?} m"),
                &format!(
                    "a region that holds a sphere of the largest radius {r_max} m (at least one \
                     diameter across each way)"
                ),
            )?;
        }
        Ok(())
    }

    /// The engine's form of inlet `i` (validated), `material` its index in
    /// the setup's materials (the file's `[[material]]` order).
    pub fn inlet_setup(&self, i: usize, material: usize) -> InletSetup {
        let s = &self.inlets[i];
        InletSetup {
            region: s.region.normalized(),
            rate: match s.rate {
                RateSection::Number(n) => InletRate::Number(n),
                RateSection::Mass(m) => InletRate::Mass(m),
            },
            size: match &s.size {
                SizeSection::Fixed(r) => SizeDistribution::Fixed(*r),
                SizeSection::Uniform([lo, hi]) => SizeDistribution::Uniform(*lo, *hi),
                SizeSection::Normal {
                    mean,
                    std,
                    min,
                    max,
                } => SizeDistribution::Normal {
                    mean: *mean,
                    std: *std,
                    min: *min,
                    max: *max,
                },
                SizeSection::Table(rows) => {
                    SizeDistribution::Table(rows.iter().map(|r| (r[0], r[1])).collect())
                }
            },
            material,
            velocity: s.velocity,
            start: s.start,
            end: s.end,
            seed: s.seed,
            every: s.every,
            max_attempts: s.max_attempts,
        }
    }
}
