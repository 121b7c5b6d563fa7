//! How far two runs of the same scene agree over time (`dembound compare`
//! on a scene deck): up to when they are the same state to
//! [`IDENTICAL`], when they part and how fast the difference grows, and
//! whether their late-time statistics agree.
//!
//! Why this split: two codes that integrate the same model start from the
//! same state and differ at first only by round-off (another summation
//! order). A granular bed is chaotic: every collision amplifies a
//! difference in the contact geometry, so the round-off grows roughly
//! exponentially, |Δ(t)| ~ |Δ₀| e^(λ t), until the two runs are different
//! realisations of the same flow. Equal digits can only be asked of the
//! first phase; after it, only statistics (means over a window, with their
//! standard errors) can agree.

/// The relative difference below which two runs are the same state.
pub const IDENTICAL: f64 = 1e-9;

/// The relative difference from which the two runs are taken as
/// decorrelated: the exponential fit stops there (the growth saturates at
/// the size of the fluctuations, order 1).
pub const SATURATED: f64 = 1e-2;

/// When a difference series leaves [`IDENTICAL`] and how fast it grows.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Divergence {
    /// The last time (s) before the first row above the threshold, at
    /// which the runs still agreed to it (None: not even at the first row).
    pub identical_until: Option<f64>,
    /// The time (s) of the first row above the threshold (None: never).
    pub diverged_at: Option<f64>,
    /// λ (1/s) of the least-squares fit of ln|Δ| against t over the rows
    /// from `diverged_at` to the first row at or above [`SATURATED`]
    /// (both included), rows with Δ = 0 left out; None with fewer than two
    /// such rows.
    pub growth_rate: Option<f64>,
    /// The rows the fit used.
    pub fit_rows: usize,
}

/// The divergence of the relative differences `relative` (≥ 0) at times
/// `time` (s, ascending), against `threshold` (use [`IDENTICAL`]).
pub fn divergence(time: &[f64], relative: &[f64], threshold: f64) -> Divergence {
    let n = time.len().min(relative.len());
    let Some(first) = (0..n).find(|&k| relative[k] > threshold) else {
        return Divergence {
            identical_until: n.checked_sub(1).map(|k| time[k]),
            diverged_at: None,
            growth_rate: None,
            fit_rows: 0,
        };
    };
    let end = (first..n)
        .find(|&k| relative[k] >= SATURATED)
        .unwrap_or(n - 1);
    let points: Vec<(f64, f64)> = (first..=end)
        .filter(|&k| relative[k] > 0.0 && relative[k].is_finite())
        .map(|k| (time[k], relative[k].ln()))
        .collect();
    Divergence {
        identical_until: first.checked_sub(1).map(|k| time[k]),
        diverged_at: Some(time[first]),
        growth_rate: slope(&points),
        fit_rows: points.len(),
    }
}

/// The least-squares slope of y on x (None with fewer than two distinct x).
fn slope(points: &[(f64, f64)]) -> Option<f64> {
    let n = points.len() as f64;
    if points.len() < 2 {
        return None;
    }
    let mx = points.iter().map(|p| p.0).sum::<f64>() / n;
    let my = points.iter().map(|p| p.1).sum::<f64>() / n;
    let sxx: f64 = points.iter().map(|p| (p.0 - mx) * (p.0 - mx)).sum();
    let sxy: f64 = points.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    (sxx > 0.0).then(|| sxy / sxx)
}

/// The mean of a series over a window and its standard error.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct WindowMean {
    pub mean: f64,
    /// The standard error of the mean by batch means: the window cut into
    /// `blocks` consecutive blocks, the standard deviation of the block
    /// means over √blocks (successive rows of a run are correlated, so the
    /// rows' own standard deviation over √rows would understate it).
    pub standard_error: f64,
    /// The batch means' blocks (0 for [`window_mean_autocorrelated`]).
    pub blocks: usize,
    /// [`window_mean_autocorrelated`]: the integrated autocorrelation time
    /// the standard error used, in rows (absent for batch means).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub autocorrelation_rows: Option<f64>,
    /// [`window_mean_autocorrelated`]: whether τ could be estimated from
    /// the series ([`Autocorrelation::reliable`]); false: the window holds
    /// too few autocorrelation times, the error is uncertain and the
    /// verdict says so.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub autocorrelation_reliable: Option<bool>,
}

/// The batch-means estimate over `values` (10 blocks, fewer for short
/// windows, at least 2 rows per block); None with fewer than 4 values.
pub fn window_mean(values: &[f64]) -> Option<WindowMean> {
    if values.len() < 4 {
        return None;
    }
    let blocks = (values.len() / 2).min(10);
    let size = values.len() / blocks;
    let means: Vec<f64> = (0..blocks)
        .map(|b| values[b * size..(b + 1) * size].iter().sum::<f64>() / size as f64)
        .collect();
    let mean = values.iter().sum::<f64>() / values.len() as f64;
    let mb = means.iter().sum::<f64>() / blocks as f64;
    let var = means.iter().map(|m| (m - mb) * (m - mb)).sum::<f64>() / (blocks - 1) as f64;
    Some(WindowMean {
        mean,
        standard_error: (var / blocks as f64).sqrt(),
        blocks,
        autocorrelation_rows: None,
        autocorrelation_reliable: None,
    })
}

/// Sokal's window factor c: the autocorrelations are summed up to the
/// first lag M with M ≥ c τ(M) (Sokal 1997, "Monte Carlo methods in
/// statistical mechanics", NATO ASI B 361, section 3; c = 5 as in
/// emcee's `integrated_time`, Foreman-Mackey et al. 2013).
pub const AUTOCORRELATION_WINDOW: f64 = 5.0;

/// The fewest autocorrelation times a series must span for its τ to be
/// trusted: emcee's documentation asks for a chain of at least ~50 τ
/// (Foreman-Mackey, "Autocorrelation analysis & convergence"); on shorter
/// series the windowed sum is biased low (a series of 100 rows with τ = 39
/// rows gives τ ≈ 3–12 in `tests`, a ramp of 50 rows τ = 6).
pub const RELIABLE_SPAN: f64 = 50.0;

/// The integrated autocorrelation time of a series, in rows.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Autocorrelation {
    /// τ = 1 + 2 Σ_{t=1}^{M} ρ(t), so that the variance of the mean of n
    /// rows is τ σ² / n (σ² the rows' variance).
    pub rows: f64,
    /// The window M.
    pub window: usize,
    /// Whether M ≥ c τ(M) was reached before the series' end (else the
    /// largest τ(M) is given) and the series spans [`RELIABLE_SPAN`] τ.
    pub reliable: bool,
}

/// τ of `values` by Sokal's automatic window ([`AUTOCORRELATION_WINDOW`]),
/// from the biased autocovariances C(t) = Σ_{i<n−t} (x_i − x̄)(x_{i+t} −
/// x̄) / n, ρ(t) = C(t)/C(0); None with fewer than 4 values. A constant
/// series has τ = 1.
pub fn integrated_autocorrelation(values: &[f64]) -> Option<Autocorrelation> {
    let n = values.len();
    if n < 4 {
        return None;
    }
    let mean = values.iter().sum::<f64>() / n as f64;
    let d: Vec<f64> = values.iter().map(|v| v - mean).collect();
    let c0 = d.iter().map(|x| x * x).sum::<f64>() / n as f64;
    if c0 <= 0.0 {
        return Some(Autocorrelation {
            rows: 1.0,
            window: 0,
            reliable: true,
        });
    }
    let mut tau = 1.0;
    let mut largest = (1.0, 0);
    for m in 1..n {
        let c = d[..n - m]
            .iter()
            .zip(&d[m..])
            .map(|(a, b)| a * b)
            .sum::<f64>()
            / n as f64;
        tau += 2.0 * c / c0;
        if tau > largest.0 {
            largest = (tau, m);
        }
        if m as f64 >= AUTOCORRELATION_WINDOW * tau {
            return Some(Autocorrelation {
                rows: tau,
                window: m,
                reliable: n as f64 >= RELIABLE_SPAN * tau,
            });
        }
    }
    Some(Autocorrelation {
        rows: largest.0,
        window: largest.1,
        reliable: false,
    })
}

/// The mean of `values` and its standard error from the integrated
/// autocorrelation time: SE = √(τ s² / n), s² the rows' sample variance,
/// τ from [`integrated_autocorrelation`] but never below 1 (rows taken as
/// no less correlated than independent ones: the estimate never falls
/// below the naive one). For a series whose correlation outlasts the
/// batch means' blocks (a hold-up that changes over a transit time longer
/// than a tenth of the window): the blocks' means are then correlated and
/// [`window_mean`] understates the error. None with fewer than 4 values.
pub fn window_mean_autocorrelated(values: &[f64]) -> Option<WindowMean> {
    let a = integrated_autocorrelation(values)?;
    let n = values.len() as f64;
    let mean = values.iter().sum::<f64>() / n;
    let var = values.iter().map(|v| (v - mean) * (v - mean)).sum::<f64>() / (n - 1.0);
    let tau = a.rows.max(1.0);
    Some(WindowMean {
        mean,
        standard_error: (tau * var / n).sqrt(),
        blocks: 0,
        autocorrelation_rows: Some(tau),
        autocorrelation_reliable: Some(a.reliable),
    })
}

/// The relative tolerance of the statistical verdict.
pub const RELATIVE_TOLERANCE: f64 = 0.01;

/// Whether two window means agree.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Verdict {
    /// |Δ mean| ≤ 1 % of the reference mean.
    WithinOnePercent,
    /// Not within 1 %, but within two combined standard errors (the window
    /// is too noisy to say more).
    WithinTwoStandardErrors,
    /// Neither, where a standard error from the autocorrelation time is
    /// not reliable ([`RELIABLE_SPAN`]): the window is too short for the
    /// series' correlation to say whether they differ.
    Undecided,
    /// Neither.
    Differ,
}

impl Verdict {
    pub fn text(&self) -> &'static str {
        match self {
            Verdict::WithinOnePercent => "agree (≤ 1 %)",
            Verdict::WithinTwoStandardErrors => "agree (≤ 2 SE)",
            Verdict::Undecided => "undecided (window < 50 τ)",
            Verdict::Differ => "DIFFER",
        }
    }
}

/// The verdict on `code` against `reference`.
pub fn verdict(code: &WindowMean, reference: &WindowMean) -> Verdict {
    let d = (code.mean - reference.mean).abs();
    let se = code.standard_error.hypot(reference.standard_error);
    if d <= RELATIVE_TOLERANCE * reference.mean.abs() {
        Verdict::WithinOnePercent
    } else if d <= 2.0 * se {
        Verdict::WithinTwoStandardErrors
    } else if [code, reference]
        .iter()
        .any(|w| w.autocorrelation_reliable == Some(false))
    {
        Verdict::Undecided
    } else {
        Verdict::Differ
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn identical_series_never_diverge() {
        let t = [0.0, 1.0, 2.0];
        let d = divergence(&t, &[0.0, 1e-12, 1e-10], IDENTICAL);
        assert_eq!(d.identical_until, Some(2.0));
        assert_eq!(d.diverged_at, None);
    }

    #[test]
    fn batch_means_of_a_constant_have_no_error() {
        let w = window_mean(&[3.0; 40]).expect("enough rows");
        assert_eq!((w.mean, w.standard_error, w.blocks), (3.0, 0.0, 10));
        assert_eq!(verdict(&w, &w), Verdict::WithinOnePercent);
        assert!(window_mean(&[1.0; 3]).is_none());
    }

    /// x_{k+1} = φ x_k + ε_k, ε i.i.d. uniform on [−1, 1) (variance 1/3)
    /// from a fixed 64-bit generator (splitmix64, Steele et al. 2014).
    fn ar1(phi: f64, n: usize, seed: u64) -> Vec<f64> {
        let mut state = seed;
        let mut next = || {
            state = state.wrapping_add(0x9e37_79b9_7f4a_7c15);
            let mut z = state;
            z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
            z ^= z >> 31;
            (z >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        };
        let mut x = 0.0;
        (0..n)
            .map(|_| {
                x = phi * x + next();
                x
            })
            .collect()
    }

    #[test]
    fn an_ar1_series_has_its_exact_autocorrelation_time() {
        // ρ(t) = φ^t, τ = 1 + 2 φ/(1 − φ) = (1 + φ)/(1 − φ) = 9 for φ =
        // 0.8. Sokal's error of τ is τ √(2(2M + 1)/n) (M ≈ 5τ = 45): 4 %
        // at n = 1e5; 15 % is ~4 of those.
        let phi = 0.8;
        let exact = (1.0 + phi) / (1.0 - phi);
        let v = ar1(phi, 100_000, 7);
        let a = integrated_autocorrelation(&v).expect("long enough");
        assert!(a.reliable);
        assert!((a.rows / exact - 1.0).abs() < 0.15, "τ = {}", a.rows);
        // The error of the mean: Var(x) = (1/3)/(1 − φ²), Var(x̄) ≈ τ
        // Var(x)/n; the estimate within the same 15 % (√τ: half of it).
        let w = window_mean_autocorrelated(&v).expect("long enough");
        let want = (exact * (1.0 / 3.0) / (1.0 - phi * phi) / v.len() as f64).sqrt();
        assert!(
            (w.standard_error / want - 1.0).abs() < 0.15,
            "SE {} against {want}",
            w.standard_error
        );
        // Batch means of 10 blocks see the same here (blocks of 1e4 rows ≫
        // τ): the two estimators agree when the blocks are long.
        let b = window_mean(&v).expect("long enough");
        assert!((b.standard_error / w.standard_error - 1.0).abs() < 0.5);
    }

    #[test]
    fn a_window_short_for_its_correlation_is_flagged() {
        // φ = 0.95: τ = 39 rows. Cut into 80 series of 100 rows (the fed
        // hopper's window: 100 rows of 2 ms, a hold-up correlated over a
        // transit time of ~0.1 s), the spread of the 80 means is the true
        // error of one. Both estimates from one series fall well short of
        // it on average (batch means: 10 blocks of 10 rows < τ; the
        // windowed τ: biased low on a series of 2.5 τ): no estimate from
        // such a window can be trusted, and nearly every one is flagged.
        let phi = 0.95;
        let v = ar1(phi, 8_000, 11);
        let series: Vec<&[f64]> = v.chunks(100).collect();
        let means: Vec<f64> = series
            .iter()
            .map(|s| s.iter().sum::<f64>() / s.len() as f64)
            .collect();
        let m = means.iter().sum::<f64>() / means.len() as f64;
        let spread = (means.iter().map(|x| (x - m) * (x - m)).sum::<f64>()
            / (means.len() - 1) as f64)
            .sqrt();
        let mean_se = |f: fn(&[f64]) -> Option<WindowMean>| {
            series
                .iter()
                .map(|s| f(s).expect("100 rows").standard_error)
                .sum::<f64>()
                / series.len() as f64
        };
        // Measured: 0.42 and 0.42 against a spread of 0.99; 78 of the 80
        // flagged (the other two drew τ < 2 rows by chance): 90 % asked.
        let batch = mean_se(window_mean);
        let auto = mean_se(window_mean_autocorrelated);
        assert!(batch < 0.7 * spread, "batch {batch}, spread {spread}");
        assert!(auto < 0.7 * spread, "τ-based {auto}, spread {spread}");
        let flagged = series
            .iter()
            .filter(|s| {
                window_mean_autocorrelated(s)
                    .expect("100 rows")
                    .autocorrelation_reliable
                    == Some(false)
            })
            .count();
        assert!(flagged >= 72, "flagged {flagged} of {}", series.len());
    }

    #[test]
    fn a_constant_or_short_series() {
        let w = window_mean_autocorrelated(&[2.0; 10]).expect("10 rows");
        assert_eq!((w.mean, w.standard_error), (2.0, 0.0));
        assert_eq!(w.autocorrelation_rows, Some(1.0));
        assert!(window_mean_autocorrelated(&[1.0, 2.0, 3.0]).is_none());
        // A ramp: correlated over its whole length; the windowed sum
        // settles on τ ≈ 6 rows (Python by hand: M = 37, τ = 6.44), which
        // 50 rows do not span 50 times: not reliable, and a difference
        // beyond 2 SE is undecided rather than a difference.
        let ramp: Vec<f64> = (0..50).map(f64::from).collect();
        let a = integrated_autocorrelation(&ramp).expect("50 rows");
        assert!(!a.reliable && (a.rows - 6.4385).abs() < 1e-3, "{a:?}");
        let w = window_mean_autocorrelated(&ramp).expect("50 rows");
        assert_eq!(w.autocorrelation_reliable, Some(false));
        let far = WindowMean {
            mean: w.mean * 2.0,
            ..w
        };
        assert_eq!(verdict(&far, &w), Verdict::Undecided);
        let sure = WindowMean {
            autocorrelation_reliable: Some(true),
            ..w
        };
        let far = WindowMean {
            mean: w.mean * 2.0,
            ..sure
        };
        assert_eq!(verdict(&far, &sure), Verdict::Differ);
    }

    #[test]
    fn alternating_blocks_give_the_textbook_error() {
        // 10 blocks of 2 rows, block means alternating 0 and 2: mean 1,
        // sample variance of the block means 10/9, SE = sqrt(10/9/10) = 1/3.
        let v: Vec<f64> = (0..20)
            .map(|k| if (k / 2) % 2 == 0 { 0.0 } else { 2.0 })
            .collect();
        let w = window_mean(&v).expect("enough rows");
        assert!((w.mean - 1.0).abs() < 1e-15);
        assert!((w.standard_error - 1.0 / 3.0).abs() < 1e-15);
        let other = WindowMean {
            mean: 1.5,
            standard_error: 1.0 / 3.0,
            blocks: 10,
            autocorrelation_rows: None,
            autocorrelation_reliable: None,
        };
        // |Δ| = 0.5 ≤ 2 √(2/9) = 0.943: within two standard errors.
        assert_eq!(verdict(&other, &w), Verdict::WithinTwoStandardErrors);
        let far = WindowMean { mean: 3.0, ..other };
        assert_eq!(verdict(&far, &w), Verdict::Differ);
    }
}
