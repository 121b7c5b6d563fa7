//! The radius distribution of an inlet's spheres (`[[inlet]] size`).

use rand::Rng;
use rand_chacha::ChaCha8Rng;
use std::f64::consts::PI;

/// The radius distribution of the inserted spheres, m.
#[derive(Debug, Clone, PartialEq)]
pub enum SizeDistribution {
    Fixed(f64),
    /// Uniform in [min, max].
    Uniform(f64, f64),
    /// Normal of `mean` and `std`, truncated to [min, max] (redrawn).
    Normal {
        mean: f64,
        std: f64,
        min: f64,
        max: f64,
    },
    /// (R, fraction by number); fractions normalised to their sum.
    Table(Vec<(f64, f64)>),
}

impl SizeDistribution {
    /// The smallest and largest radius the distribution draws, m (table
    /// rows of fraction 0 left out; an all-zero table gives (∞, 0)).
    pub fn radius_range(&self) -> (f64, f64) {
        match self {
            SizeDistribution::Fixed(r) => (*r, *r),
            SizeDistribution::Uniform(lo, hi) => (*lo, *hi),
            SizeDistribution::Normal { min, max, .. } => (*min, *max),
            SizeDistribution::Table(rows) => rows
                .iter()
                .filter(|r| r.1 > 0.0)
                .fold((f64::INFINITY, 0.0), |(lo, hi), r| {
                    (lo.min(r.0), hi.max(r.0))
                }),
        }
    }

    pub fn max_radius(&self) -> f64 {
        self.radius_range().1
    }

    /// E[R³], m³ (by number).
    pub fn mean_cube(&self) -> f64 {
        match self {
            SizeDistribution::Fixed(r) => r * r * r,
            SizeDistribution::Uniform(a, b) => {
                if b > a {
                    (b.powi(4) - a.powi(4)) / (4.0 * (b - a))
                } else {
                    a * a * a
                }
            }
            SizeDistribution::Normal {
                mean,
                std,
                min,
                max,
            } => {
                if *std == 0.0 || max <= min {
                    return mean.clamp(*min, *max).powi(3);
                }
                // Simpson's rule over the truncated density (its
                // normalisation cancels): smooth, 2000 intervals.
                let n = 2000;
                let h = (max - min) / n as f64;
                let (mut num, mut den) = (0.0, 0.0);
                for i in 0..=n {
                    let r = min + h * i as f64;
                    let w = if i == 0 || i == n {
                        1.0
                    } else if i % 2 == 1 {
                        4.0
                    } else {
                        2.0
                    };
                    let p = (-0.5 * ((r - mean) / std).powi(2)).exp();
                    num += w * p * r * r * r;
                    den += w * p;
                }
                num / den
            }
            SizeDistribution::Table(rows) => {
                let total: f64 = rows.iter().map(|r| r.1).sum();
                rows.iter().map(|r| r.1 * r.0.powi(3)).sum::<f64>() / total
            }
        }
    }

    /// One radius, m.
    pub(crate) fn sample(&self, rng: &mut ChaCha8Rng) -> f64 {
        match self {
            SizeDistribution::Fixed(r) => *r,
            SizeDistribution::Uniform(a, b) => a + (b - a) * rng.gen::<f64>(),
            SizeDistribution::Normal {
                mean,
                std,
                min,
                max,
            } => {
                if *std == 0.0 || max <= min {
                    return mean.clamp(*min, *max);
                }
                // Box–Muller, redrawn outside [min, max]; the mean lies
                // inside, so a draw is kept with probability ≥ that of one
                // half-width, and the bound below is never reached in
                // practice (then the mean).
                for _ in 0..10_000 {
                    let u1: f64 = 1.0 - rng.gen::<f64>();
                    let u2: f64 = rng.gen();
                    let z = (-2.0 * u1.ln()).sqrt() * (2.0 * PI * u2).cos();
                    let r = mean + std * z;
                    if r >= *min && r <= *max {
                        return r;
                    }
                }
                *mean
            }
            SizeDistribution::Table(rows) => {
                let total: f64 = rows.iter().map(|r| r.1).sum();
                let mut u = total * rng.gen::<f64>();
                for &(r, f) in rows {
                    if u < f {
                        return r;
                    }
                    u -= f;
                }
                // Rounding at the top end: the last row of weight.
                rows.iter().rev().find(|r| r.1 > 0.0).map_or(0.0, |r| r.0)
            }
        }
    }
}
