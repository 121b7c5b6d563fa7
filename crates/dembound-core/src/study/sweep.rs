//! The parametric study of section 5: a grid over the boundary's radius
//! ratio r and modulus ratio ζ (either may be ∞), the contact law and any
//! other scenario field (a list of scenario variants), each case run by the
//! integrator and by the exact reference, and each quantity normalised by
//! the rigid half-space value (r = ζ = ∞, same variant and law).
//!
//! Pure computation: cases run in parallel with rayon, progress is reported
//! through a callback, the result serialises with serde.

use crate::bounce::{simulate_batch, ContactRecord, RunOutcome, Scenario};
use crate::contact::ContactLawKind;
use crate::exact::scenario_contacts;
use crate::{Error, Result};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::fmt;
use std::sync::atomic::{AtomicUsize, Ordering};

/// One scenario the grid is laid over (its r, ζ and, when the sweep lists
/// laws, its law are replaced case by case).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Variant {
    /// What distinguishes it, e.g. `motion.gap=0.001` (empty for a single variant).
    pub label: String,
    pub scenario: Scenario,
}

/// What to sweep.
#[derive(Debug, Clone, PartialEq)]
pub struct SweepSpec {
    /// r values (`f64::INFINITY` allowed).
    pub radius_ratios: Vec<f64>,
    /// ζ values (`f64::INFINITY` allowed).
    pub modulus_ratios: Vec<f64>,
    /// Contact laws; empty means each variant's own law.
    pub laws: Vec<ContactLawKind>,
    /// Scenario variants (at least one).
    pub variants: Vec<Variant>,
}

impl SweepSpec {
    /// A sweep of one scenario over r, ζ and laws.
    pub fn new(
        scenario: Scenario,
        radius_ratios: Vec<f64>,
        modulus_ratios: Vec<f64>,
        laws: Vec<ContactLawKind>,
    ) -> Self {
        SweepSpec {
            radius_ratios,
            modulus_ratios,
            laws,
            variants: vec![Variant {
                label: String::new(),
                scenario,
            }],
        }
    }

    fn laws_of(&self, v: &Variant) -> Vec<ContactLawKind> {
        if self.laws.is_empty() {
            vec![v.scenario.contact.law]
        } else {
            self.laws.clone()
        }
    }

    /// Every (variant, law, r, ζ) of the grid, in that nesting order.
    pub fn cases(&self) -> Vec<CaseKey> {
        let mut out = Vec::new();
        for (i, v) in self.variants.iter().enumerate() {
            for law in self.laws_of(v) {
                for &r in &self.radius_ratios {
                    for &z in &self.modulus_ratios {
                        out.push(CaseKey {
                            variant: i,
                            law,
                            radius_ratio: r,
                            modulus_ratio: z,
                        });
                    }
                }
            }
        }
        out
    }

    /// The scenario of a case.
    pub fn scenario(&self, key: &CaseKey) -> Scenario {
        let mut s = self.variants[key.variant].scenario;
        s.contact.law = key.law;
        s.boundary.radius_ratio = key.radius_ratio;
        s.boundary.modulus_ratio = key.modulus_ratio;
        s
    }
}

/// Where a case sits in the grid.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct CaseKey {
    /// Index into [`SweepSpec::variants`].
    pub variant: usize,
    pub law: ContactLawKind,
    /// r.
    #[serde(with = "crate::serde_inf")]
    pub radius_ratio: f64,
    /// ζ.
    #[serde(with = "crate::serde_inf")]
    pub modulus_ratio: f64,
}

impl fmt::Display for CaseKey {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "variant {}, law {}, r = {}, ζ = {}",
            self.variant,
            self.law.name(),
            self.radius_ratio,
            self.modulus_ratio
        )
    }
}

/// The per-contact quantities a sweep reports (SI, or ratios once normalised).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Values {
    /// T_c.
    pub duration: f64,
    /// h_max.
    pub max_overlap: f64,
    /// a_max (gravity included).
    pub max_acceleration: f64,
    /// F_max.
    pub max_force: f64,
    /// v_r.
    pub rebound_velocity: f64,
}

impl Values {
    pub fn of(c: &ContactRecord) -> Self {
        Values {
            duration: c.duration,
            max_overlap: c.max_overlap,
            max_acceleration: c.max_acceleration,
            max_force: c.max_force,
            rebound_velocity: c.rebound_velocity,
        }
    }

    fn map2(&self, other: &Values, f: impl Fn(f64, f64) -> f64) -> Values {
        Values {
            duration: f(self.duration, other.duration),
            max_overlap: f(self.max_overlap, other.max_overlap),
            max_acceleration: f(self.max_acceleration, other.max_acceleration),
            max_force: f(self.max_force, other.max_force),
            rebound_velocity: f(self.rebound_velocity, other.rebound_velocity),
        }
    }

    /// Each value divided by the reference's.
    pub fn ratio(&self, reference: &Values) -> Values {
        self.map2(reference, |a, b| a / b)
    }

    /// Relative differences `self/reference − 1`.
    pub fn relative_error(&self, reference: &Values) -> Values {
        self.map2(reference, |a, b| a / b - 1.0)
    }

    /// The value of a [`super::Quantity`].
    pub fn get(&self, q: super::Quantity) -> f64 {
        match q {
            super::Quantity::MaxOverlap => self.max_overlap,
            super::Quantity::Duration => self.duration,
            super::Quantity::MaxAcceleration => self.max_acceleration,
        }
    }

    /// Largest |component|.
    pub fn max_abs(&self) -> f64 {
        [
            self.duration,
            self.max_overlap,
            self.max_acceleration,
            self.max_force,
            self.rebound_velocity,
        ]
        .into_iter()
        .map(f64::abs)
        .fold(0.0, f64::max)
    }
}

/// One contact of one case.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ContactResult {
    /// 1-based contact number.
    pub contact: u32,
    /// From the integrator (SI).
    pub numerical: Values,
    /// From the exact reference (SI).
    pub exact: Values,
    /// Numerical values over the numerical rigid half-space values.
    pub numerical_normalised: Values,
    /// Exact values over the exact rigid half-space values.
    pub exact_normalised: Values,
    /// numerical/exact − 1.
    pub relative_error: Values,
}

/// One case of the grid.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SweepCase {
    pub key: CaseKey,
    /// Integration steps taken.
    pub steps: u64,
    pub contacts: Vec<ContactResult>,
}

impl SweepCase {
    /// The first contact.
    pub fn first(&self) -> &ContactResult {
        &self.contacts[0]
    }
}

/// The rigid half-space run of one (variant, law): the normalisation.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Reference {
    pub variant: usize,
    pub law: ContactLawKind,
    /// Per contact, from the integrator.
    pub numerical: Vec<Values>,
    /// Per contact, exact.
    pub exact: Vec<Values>,
}

/// Everything a sweep computed.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SweepResult {
    pub variants: Vec<Variant>,
    pub references: Vec<Reference>,
    pub cases: Vec<SweepCase>,
}

impl SweepResult {
    /// The case at (variant, law, r, ζ), if it was swept.
    pub fn find(
        &self,
        variant: usize,
        law: ContactLawKind,
        r: f64,
        zeta: f64,
    ) -> Option<&SweepCase> {
        self.cases.iter().find(|c| {
            c.key.variant == variant
                && c.key.law == law
                && c.key.radius_ratio == r
                && c.key.modulus_ratio == zeta
        })
    }

    /// The normalisation of a (variant, law).
    pub fn reference(&self, variant: usize, law: ContactLawKind) -> Option<&Reference> {
        self.references
            .iter()
            .find(|r| r.variant == variant && r.law == law)
    }
}

/// Per-contact values of one scenario: (integrator, exact, steps).
type Run = (Vec<Values>, Vec<Values>, u64);

/// A case's values from its run (`outcome`, from [`simulate_batch`]) and
/// its exact reference.
fn run_case(s: &Scenario, outcome: Result<RunOutcome>, label: &str) -> Result<Run> {
    let out = outcome.map_err(|error| Error::CaseRun {
        case: label.to_string(),
        error: Box::new(error),
    })?;
    let exact = scenario_contacts(s).map_err(|error| Error::CaseExact {
        case: label.to_string(),
        error: Box::new(error),
    })?;
    Ok((
        out.contacts.iter().map(Values::of).collect(),
        exact.iter().map(Values::of).collect(),
        out.steps,
    ))
}

/// Runs the sweep. `progress(done, total)` is called after every run (from
/// any thread), the rigid half-space references included in `total`.
pub fn sweep(spec: &SweepSpec, progress: &(dyn Fn(usize, usize) + Sync)) -> Result<SweepResult> {
    if spec.variants.is_empty() {
        return Err(Error::NothingToSweep("scenario variants"));
    }
    if spec.radius_ratios.is_empty() {
        return Err(Error::NothingToSweep("radius ratios r"));
    }
    if spec.modulus_ratios.is_empty() {
        return Err(Error::NothingToSweep("modulus ratios ζ"));
    }
    let keys = spec.cases();
    // References: one rigid half-space run per (variant, law).
    let mut ref_keys: Vec<CaseKey> = Vec::new();
    for k in &keys {
        if !ref_keys
            .iter()
            .any(|r| r.variant == k.variant && r.law == k.law)
        {
            ref_keys.push(CaseKey {
                variant: k.variant,
                law: k.law,
                radius_ratio: f64::INFINITY,
                modulus_ratio: f64::INFINITY,
            });
        }
    }
    // Validate every case first, so that a bad value fails before any work.
    for k in keys.iter().chain(&ref_keys) {
        // The range of every key, and a step that resolves the contact.
        match crate::bounce::check_resolution(&spec.scenario(k)) {
            Ok(()) => {}
            Err(error @ Error::Input { .. }) => {
                return Err(Error::CaseInput {
                    case: k.to_string(),
                    error: Box::new(error),
                })
            }
            Err(error) => {
                return Err(Error::CaseRun {
                    case: k.to_string(),
                    error: Box::new(error),
                })
            }
        }
    }
    let total = keys.len() + ref_keys.len();
    let done = AtomicUsize::new(0);
    let tick = || {
        let n = done.fetch_add(1, Ordering::Relaxed) + 1;
        progress(n, total);
    };
    // Every run at once, in SIMD lanes where it can be ([`simulate_batch`]:
    // the same results as `simulate` case by case), references first.
    let all: Vec<CaseKey> = ref_keys.iter().chain(&keys).copied().collect();
    let scenarios: Vec<Scenario> = all.iter().map(|k| spec.scenario(k)).collect();
    let outcomes = simulate_batch(&scenarios);
    let mut runs = all
        .par_iter()
        .zip(&scenarios)
        .zip(outcomes)
        .map(|((k, s), outcome)| {
            let run = run_case(s, outcome, &k.to_string());
            tick();
            run
        })
        .collect::<Vec<_>>()
        .into_iter();
    let references: Vec<Reference> = ref_keys
        .iter()
        .zip(runs.by_ref())
        .map(|(k, run)| {
            let (numerical, exact, _) = run?;
            Ok(Reference {
                variant: k.variant,
                law: k.law,
                numerical,
                exact,
            })
        })
        .collect::<Result<_>>()?;
    let cases = keys
        .iter()
        .zip(runs)
        .map(|(k, run)| {
            let (numerical, exact, steps) = run?;
            let reference = references
                .iter()
                .find(|r| r.variant == k.variant && r.law == k.law)
                .expect("a reference for every (variant, law)");
            let contacts = numerical
                .iter()
                .zip(&exact)
                .enumerate()
                .map(|(i, (n, e))| {
                    let (rn, re) = (&reference.numerical[i], &reference.exact[i]);
                    ContactResult {
                        contact: i as u32 + 1,
                        numerical: *n,
                        exact: *e,
                        numerical_normalised: n.ratio(rn),
                        exact_normalised: e.ratio(re),
                        relative_error: n.relative_error(e),
                    }
                })
                .collect();
            Ok(SweepCase {
                key: *k,
                steps,
                contacts,
            })
        })
        .collect::<Result<_>>()?;
    Ok(SweepResult {
        variants: spec.variants.clone(),
        references,
        cases,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bounce::Stepping;
    use crate::integrate::Scheme;

    const INF: f64 = f64::INFINITY;

    #[test]
    fn integrator_matches_the_exact_reference_case_by_case() {
        // Gear5, event stepping, η = 1/50 (the defaults): the same bounds as
        // the core's closed-form tests, 1e−6 linear and 2e−4 Hertz, over the
        // paper's whole range of r and ζ, infinity included.
        let mut s = Scenario::default();
        s.integration.scheme = Scheme::Gear5;
        s.integration.stepping = Stepping::Event;
        s.integration.eta = Some(0.02);
        let rs = vec![0.5, 1.0, 10.0, 100.0, 1000.0, INF];
        let zs = vec![1.0, 10.0, 100.0, 1000.0, INF];
        let spec = SweepSpec::new(
            s,
            rs.clone(),
            zs.clone(),
            vec![ContactLawKind::Linear, ContactLawKind::Hertz],
        );
        let calls = AtomicUsize::new(0);
        let result = sweep(&spec, &|_, total| {
            assert_eq!(total, 2 * rs.len() * zs.len() + 2);
            calls.fetch_add(1, Ordering::Relaxed);
        })
        .unwrap();
        assert_eq!(calls.load(Ordering::Relaxed), 2 * rs.len() * zs.len() + 2);
        assert_eq!(result.cases.len(), 2 * rs.len() * zs.len());
        for case in &result.cases {
            let bound = match case.key.law {
                ContactLawKind::Linear => 1e-6,
                _ => 2e-4,
            };
            assert_eq!(case.contacts.len(), 2);
            for c in &case.contacts {
                let e = c.relative_error;
                for (name, err) in [
                    ("T_c", e.duration),
                    ("h_max", e.max_overlap),
                    ("a_max", e.max_acceleration),
                    ("v_r", e.rebound_velocity),
                ] {
                    assert!(err.abs() < bound, "{}: {name} {err:e}", case.key);
                }
            }
        }
        // The rigid half-space case normalises to exactly 1.
        let c = result
            .find(0, ContactLawKind::Hertz, INF, INF)
            .unwrap()
            .first();
        assert_eq!(c.exact_normalised.max_overlap, 1.0);
        assert_eq!(c.numerical_normalised.duration, 1.0);
        // Softer boundaries give more overlap and longer contacts.
        let soft = result
            .find(0, ContactLawKind::Hertz, 1.0, 1.0)
            .unwrap()
            .first();
        assert!(soft.exact_normalised.max_overlap > 1.3);
        assert!(soft.exact_normalised.max_acceleration < 0.8);
    }

    #[test]
    fn variants_and_bad_values() {
        let base = Scenario::default();
        let mut other = base;
        other.motion.gap = 1e-3;
        let spec = SweepSpec {
            radius_ratios: vec![10.0],
            modulus_ratios: vec![10.0],
            laws: vec![],
            variants: vec![
                Variant {
                    label: "gap 5 mm".into(),
                    scenario: base,
                },
                Variant {
                    label: "gap 1 mm".into(),
                    scenario: other,
                },
            ],
        };
        let r = sweep(&spec, &|_, _| {}).unwrap();
        assert_eq!(r.cases.len(), 2);
        assert_eq!(r.references.len(), 2);
        // Slower impact, smaller overlap.
        let h = |v| {
            r.find(v, ContactLawKind::Hertz, 10.0, 10.0)
                .unwrap()
                .first()
                .exact
                .max_overlap
        };
        assert!(h(1) < h(0));

        let mut bad = spec.clone();
        bad.radius_ratios = vec![-1.0];
        match sweep(&bad, &|_, _| {}) {
            Err(Error::CaseInput { error, .. }) => match *error {
                Error::Input { field, .. } => assert_eq!(field, "boundary.radius_ratio"),
                other => panic!("{other:?}"),
            },
            other => panic!("{other:?}"),
        }
    }
}
