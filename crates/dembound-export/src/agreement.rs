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
    pub blocks: usize,
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
    /// Neither.
    Differ,
}

impl Verdict {
    pub fn text(&self) -> &'static str {
        match self {
            Verdict::WithinOnePercent => "agree (≤ 1 %)",
            Verdict::WithinTwoStandardErrors => "agree (≤ 2 SE)",
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
        };
        // |Δ| = 0.5 ≤ 2 √(2/9) = 0.943: within two standard errors.
        assert_eq!(verdict(&other, &w), Verdict::WithinTwoStandardErrors);
        let far = WindowMean { mean: 3.0, ..other };
        assert_eq!(verdict(&far, &w), Verdict::Differ);
    }
}
