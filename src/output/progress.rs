//! A progress bar on stderr, driven by [`Observer::progress`] (simulated
//! time against the expected end time).

use dembound_core::bounce::Observer;
use indicatif::{ProgressBar, ProgressStyle};
use std::io::IsTerminal;

/// Runs expected to take more steps than this get a progress bar.
pub const PROGRESS_MIN_STEPS: f64 = 5e6;

const TICKS: u64 = 1000;

/// Whether to show a progress bar: a long run, stderr a terminal, not quiet.
pub fn wanted(expected_steps: f64, quiet: bool) -> bool {
    !quiet && expected_steps > PROGRESS_MIN_STEPS && std::io::stderr().is_terminal()
}

/// The progress bar of one run.
pub struct Progress {
    bar: ProgressBar,
}

impl Progress {
    pub fn new() -> Self {
        let bar = ProgressBar::new(TICKS);
        let style = ProgressStyle::with_template(
            "{elapsed_precise} [{wide_bar}] {percent:>3}% of the simulated time, ETA {eta}",
        )
        .unwrap_or_else(|_| ProgressStyle::default_bar());
        bar.set_style(style.progress_chars("=> "));
        Progress { bar }
    }

    /// Removes the bar.
    pub fn finish(self) {
        self.bar.finish_and_clear();
    }
}

impl Default for Progress {
    fn default() -> Self {
        Self::new()
    }
}

impl Observer for Progress {
    const ACTIVE: bool = false;

    fn progress(&mut self, t: f64, t_end: f64) {
        if t_end > 0.0 {
            let fraction = (t / t_end).clamp(0.0, 1.0);
            self.bar.set_position((fraction * TICKS as f64) as u64);
        }
    }
}

/// A bar counting finished cases of a study, on stderr; `None` when quiet or
/// when stderr is not a terminal. Safe to tick from several threads.
pub fn counter(total: usize, quiet: bool, what: &str) -> Option<ProgressBar> {
    if quiet || !std::io::stderr().is_terminal() {
        return None;
    }
    let bar = ProgressBar::new(total as u64);
    let style = ProgressStyle::with_template(&format!(
        "{{elapsed_precise}} [{{wide_bar}}] {{pos}}/{{len}} {what}, ETA {{eta}}"
    ))
    .unwrap_or_else(|_| ProgressStyle::default_bar());
    bar.set_style(style.progress_chars("=> "));
    Some(bar)
}
