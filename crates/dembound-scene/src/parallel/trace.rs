//! The team's stages timed (a developer's diagnostic, off unless the
//! environment variable `DEMBOUND_TEAM_TRACE` is set when the team
//! starts): for each place a stage is started from, how many stages ran,
//! their length from the hand-off to the last worker's end, and per
//! worker its start latency, busy time, time waiting for another worker
//! inside the stage ([`add_wait`]) and at the stage's end, and the work
//! units it reported ([`add_units`], e.g. listed pairs), with how many
//! stages one worker was busy for nearly all of the workers' busy time
//! ([`ONE_SIDED`]; the other started late or found nothing left) and the
//! longest run of such stages in a row. Printed to
//! standard error when the team stops. Off, it costs one relaxed load a
//! stage and a wait. Each pair list built while it is on also prints its
//! force blocks ([`note_blocks`]): how finely the force stage can be
//! shared (the 10k lattice drop: 12 blocks of 400–1,200 bodies, each
//! about one cell layer, the pairs' reach).

use std::cell::Cell;
use std::collections::HashMap;
use std::panic::Location;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Mutex;
use std::time::Instant;

static ON: AtomicBool = AtomicBool::new(false);

/// A stage is one-sided when one worker's busy time is at least this
/// fraction of the workers' summed busy time (two workers from both ends:
/// the other was late or off its core for nearly the whole stage).
const ONE_SIDED: f64 = 0.9;

thread_local! {
    static WAITED: Cell<u64> = const { Cell::new(0) };
    static UNITS: Cell<u64> = const { Cell::new(0) };
}

/// Whether stages are timed.
#[inline]
pub fn on() -> bool {
    ON.load(Ordering::Relaxed)
}

/// Reads the environment (once per team).
pub(super) fn start() {
    if std::env::var_os("DEMBOUND_TEAM_TRACE").is_some() {
        ON.store(true, Ordering::Relaxed);
    }
}

/// Adds `ns` of waiting for another worker to this thread's stage.
pub fn add_wait(ns: u64) {
    WAITED.with(|w| w.set(w.get() + ns));
}

/// Adds `n` work units to this thread's stage.
pub fn add_units(n: u64) {
    UNITS.with(|u| u.set(u.get() + n));
}

/// Prints a new pair list's force blocks, one line: each block's bodies
/// and listed pairs (`blocks`: the boundaries, `start`: the rows' starts).
pub fn note_blocks(blocks: &[u32], start: &[u32]) {
    let span = |w: &[u32]| (w[0] as usize, w[1] as usize);
    let bodies: Vec<u32> = blocks.windows(2).map(|w| w[1] - w[0]).collect();
    let pairs: Vec<u32> = blocks
        .windows(2)
        .map(|w| {
            let (lo, hi) = span(w);
            match (start.get(lo), start.get(hi)) {
                (Some(a), Some(b)) => b - a,
                _ => 0,
            }
        })
        .collect();
    eprintln!("team trace: force blocks: bodies {bodies:?} pairs {pairs:?}");
}

/// One worker's part of one stage.
#[derive(Debug, Clone, Copy, Default)]
pub(super) struct Part {
    pub start: Option<Instant>,
    pub end: Option<Instant>,
    pub waited: u64,
    pub units: u64,
}

/// Runs `f` as this thread's part of a stage.
pub(super) fn part(f: impl FnOnce()) -> Part {
    WAITED.with(|w| w.set(0));
    UNITS.with(|u| u.set(0));
    let start = Instant::now();
    f();
    Part {
        start: Some(start),
        end: Some(Instant::now()),
        waited: WAITED.with(|w| w.get()),
        units: UNITS.with(|u| u.get()),
    }
}

#[derive(Debug, Default, Clone)]
struct Sum {
    stages: u64,
    span: f64,
    /// Per worker: start latency, busy, waits inside, wait at the end, units.
    latency: Vec<f64>,
    busy: Vec<f64>,
    inside: Vec<f64>,
    end: Vec<f64>,
    units: Vec<f64>,
    /// Σ over stages of (largest busy − smallest busy).
    spread: f64,
    /// Stages where one worker was ≥ [`ONE_SIDED`] of the busy time.
    one_sided: u64,
    /// One-sided stages in a row now, and the longest such run.
    streak: u64,
    longest: u64,
}

/// The sums of one team.
#[derive(Debug, Default)]
pub(super) struct Trace {
    sums: Mutex<HashMap<&'static Location<'static>, Sum>>,
    first: Mutex<Option<Instant>>,
    last: Mutex<Option<Instant>>,
}

fn ns(a: Instant, b: Instant) -> f64 {
    b.saturating_duration_since(a).as_nanos() as f64
}

impl Trace {
    pub fn record(
        &self,
        at: &'static Location<'static>,
        raised: Instant,
        done: Instant,
        parts: &[Part],
    ) {
        if let Ok(mut f) = self.first.lock() {
            f.get_or_insert(raised);
        }
        if let Ok(mut l) = self.last.lock() {
            *l = Some(done);
        }
        let Ok(mut sums) = self.sums.lock() else {
            return;
        };
        let s = sums.entry(at).or_default();
        let w = parts.len();
        if s.busy.len() != w {
            *s = Sum {
                latency: vec![0.0; w],
                busy: vec![0.0; w],
                inside: vec![0.0; w],
                end: vec![0.0; w],
                units: vec![0.0; w],
                ..Sum::default()
            };
        }
        s.stages += 1;
        s.span += ns(raised, done);
        let (mut lo, mut hi) = (f64::INFINITY, 0.0f64);
        let (mut total, mut timed) = (0.0, 0usize);
        for (t, p) in parts.iter().enumerate() {
            let (Some(a), Some(b)) = (p.start, p.end) else {
                continue;
            };
            let busy = ns(a, b) - p.waited as f64;
            s.latency[t] += ns(raised, a);
            s.busy[t] += busy;
            s.inside[t] += p.waited as f64;
            s.end[t] += ns(b, done);
            s.units[t] += p.units as f64;
            lo = lo.min(busy);
            hi = hi.max(busy);
            total += busy;
            timed += 1;
        }
        if hi >= lo {
            s.spread += hi - lo;
        }
        // One-sided: the busiest worker (`hi`) did nearly all of it.
        if total > 0.0 && timed > 1 {
            if hi >= ONE_SIDED * total {
                s.one_sided += 1;
                s.streak += 1;
                s.longest = s.longest.max(s.streak);
            } else {
                s.streak = 0;
            }
        }
    }

    /// The table, to standard error.
    pub fn print(&self) {
        let Ok(sums) = self.sums.lock() else { return };
        let whole = match (
            self.first.lock().ok().and_then(|f| *f),
            self.last.lock().ok().and_then(|l| *l),
        ) {
            (Some(a), Some(b)) => ns(a, b),
            _ => 0.0,
        };
        let mut rows: Vec<_> = sums.iter().collect();
        rows.sort_by(|a, b| b.1.span.total_cmp(&a.1.span));
        let staged: f64 = rows.iter().map(|r| r.1.span).sum();
        eprintln!(
            "team trace: first hand-off to last stage's end {:.4} s, in stages {:.4} s, between stages {:.4} s",
            whole * 1e-9,
            staged * 1e-9,
            (whole - staged) * 1e-9
        );
        eprintln!("stage | count | span µs/stage | per worker: latency / busy / waits inside / wait at end µs/stage, units/stage | spread µs/stage | one-sided stages (longest run)");
        for (at, s) in rows {
            let n = s.stages as f64;
            let per: Vec<String> = (0..s.busy.len())
                .map(|t| {
                    format!(
                        "w{t} {:.2}/{:.2}/{:.2}/{:.2} u{:.0}",
                        s.latency[t] / n * 1e-3,
                        s.busy[t] / n * 1e-3,
                        s.inside[t] / n * 1e-3,
                        s.end[t] / n * 1e-3,
                        s.units[t] / n
                    )
                })
                .collect();
            eprintln!(
                "{}:{} | {} | {:.2} | {} | {:.2} | {} ({})",
                at.file(),
                at.line(),
                s.stages,
                s.span / n * 1e-3,
                per.join("  "),
                s.spread / n * 1e-3,
                s.one_sided,
                s.longest
            );
        }
    }
}
