//! The collision log in `dembound scene`'s report: a summary always, the
//! rows themselves only where no `--out` directory holds them
//! (`collisions.csv`). A 10,000-sphere drop completes ~10⁶ contacts: as
//! JSON text they were hundreds of megabytes on standard output.

use super::scene::CollisionRow;
use crate::output::format::sig;
use dembound_scene::{Collision, Partner};
use serde::Serialize;

/// What the log holds, in SI: counts, extremes and durations, and the
/// contact of the largest overlap.
#[derive(Debug, Serialize)]
pub(super) struct CollisionSummary {
    /// Completed contacts logged.
    pub count: usize,
    /// Of them, between two spheres.
    pub sphere_contacts: usize,
    /// Of them, of a sphere with a wall (`"wall:K"`).
    pub wall_contacts: usize,
    /// Largest overlap of any contact, m (null without contacts).
    pub max_overlap: Option<f64>,
    /// Largest normal force of any contact, N.
    pub max_normal_force: Option<f64>,
    /// Largest normal approach speed at an onset, m/s.
    pub max_impact_normal_velocity: Option<f64>,
    /// Shortest, longest and mean contact duration, s.
    pub shortest_duration: Option<f64>,
    pub longest_duration: Option<f64>,
    pub mean_duration: Option<f64>,
    /// The contact of the largest overlap (the first such in the log).
    pub largest_overlap: Option<CollisionRow>,
    /// Where every row is: `"collisions.csv"` in the `--out` directory;
    /// null when the rows are in the report's `collisions` instead.
    pub file: Option<&'static str>,
}

/// The summary of `log` and, unless `to_file` (the rows go to
/// `collisions.csv`), its rows.
pub(super) fn collision_report(
    log: &[Collision],
    to_file: bool,
) -> (CollisionSummary, Option<Vec<CollisionRow>>) {
    let max = |f: fn(&Collision) -> f64| log.iter().map(f).reduce(f64::max);
    let largest = log
        .iter()
        .reduce(|a, b| if b.max_overlap > a.max_overlap { b } else { a });
    let sphere_contacts = log
        .iter()
        .filter(|c| matches!(c.j, Partner::Body(_)))
        .count();
    let summary = CollisionSummary {
        count: log.len(),
        sphere_contacts,
        wall_contacts: log.len() - sphere_contacts,
        max_overlap: max(|c| c.max_overlap),
        max_normal_force: max(|c| c.max_normal_force),
        max_impact_normal_velocity: max(|c| c.impact_normal_velocity),
        shortest_duration: log.iter().map(|c| c.duration).reduce(f64::min),
        longest_duration: max(|c| c.duration),
        mean_duration: (!log.is_empty())
            .then(|| log.iter().map(|c| c.duration).sum::<f64>() / log.len() as f64),
        largest_overlap: largest.map(CollisionRow::from),
        file: to_file.then_some("collisions.csv"),
    };
    let rows = (!to_file).then(|| log.iter().map(CollisionRow::from).collect());
    (summary, rows)
}

/// The summary's line of the text report.
pub(super) fn summary_line(s: &CollisionSummary) -> String {
    let mut line = format!(
        "{} completed collisions ({} between spheres, {} with walls)",
        s.count, s.sphere_contacts, s.wall_contacts
    );
    if let (Some(h), Some(f), Some(v), Some(t0), Some(t1)) = (
        s.max_overlap,
        s.max_normal_force,
        s.max_impact_normal_velocity,
        s.shortest_duration,
        s.longest_duration,
    ) {
        line += &format!(
            ": max overlap {} m, max normal force {} N, fastest impact {} m/s, \
             durations {}–{} s",
            sig(h, 6),
            sig(f, 6),
            sig(v, 6),
            sig(t0, 6),
            sig(t1, 6)
        );
    }
    if let Some(file) = s.file {
        line += &format!("; every contact in {file}");
    }
    line
}
