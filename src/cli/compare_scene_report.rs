//! The text report and the figures of `dembound compare DECK` on a scene
//! deck (compare_scene.rs).

use super::compare_scene::{SceneCompareReport, Speed};
use crate::output::format::sig;
use crate::output::table::{Cell, Column, Table};
use crate::plot::{Figure, Mark, Series};
use anyhow::anyhow;
use dembound_export::agreement::{self, WindowMean};
use std::path::Path;

fn opt_s(t: Option<f64>) -> String {
    t.map_or("—".into(), |t| format!("{} s", sig(t, 4)))
}

pub fn text_report(r: &SceneCompareReport) -> String {
    let mut out = format!(
        "{} (deck {}, {} spheres, {} free) against dembound's run of scene.toml, {} rows, Δt = {} s\n\
         Relative difference: |{} − dembound| / the largest |value| of the run. Identical: ≤ {:e}.\n\
         Growth rate λ: fit of ln|Δ| against t from the divergence to the first row ≥ {:e}\n\
         (chaos: collisions amplify round-off about e^(λt) until the runs are different realisations).\n\n",
        r.code,
        r.deck.display(),
        r.spheres,
        r.free_spheres,
        r.rows,
        sig(r.dt, 6),
        r.code,
        r.identical_threshold,
        agreement::SATURATED
    );
    let mut t = Table::new(vec![
        Column::text("quantity"),
        Column::text("identical until").right(),
        Column::text("diverged at").right(),
        Column::text("λ (1/s)").right(),
        Column::text("decades/ms").right(),
    ]);
    for q in &r.quantities {
        let d = &q.divergence;
        t.push(vec![
            Cell::text(format!("{} ({})", q.name, q.unit)),
            Cell::text(opt_s(d.identical_until)),
            Cell::text(opt_s(d.diverged_at)),
            Cell::text(d.growth_rate.map_or("—".into(), |l| sig(l, 3))),
            Cell::text(
                d.growth_rate
                    .map_or("—".into(), |l| sig(l / std::f64::consts::LN_10 * 1e-3, 3)),
            ),
        ]);
    }
    out.push_str(&format!("Identical-state agreement:\n{t}\n"));
    if let Some(e) = &r.state_end {
        out.push_str(&format!(
            "The comparison by id ends at t = {} s ({}): {}. The identical-state columns cover \
             the rows before it.\n",
            sig(e.at, 4),
            e.compared_until
                .map_or("no row compared".into(), |t| format!(
                    "compared up to t = {} s",
                    sig(t, 4)
                )),
            e.reason
        ));
    }
    if r.quantities.iter().any(|q| q.running_count) {
        out.push_str(&format!(
            "Running counts (inserted, discharged) are compared at every row: \"identical until\" \
             is the last row before the first at which they differ by more than {:e} (relative).\n",
            r.identical_threshold
        ));
        for q in r.quantities.iter().filter(|q| q.running_count) {
            let (Some(a), Some(b)) = (q.code.last(), q.dembound.last()) else {
                continue;
            };
            let unequal = q
                .relative_difference
                .iter()
                .filter(|d| **d > r.identical_threshold)
                .count();
            out.push_str(&format!(
                "  {} at the last row: {} {} {}, dembound {} {} (rows that differ: {} of {})\n",
                q.name,
                r.code,
                sig(*a, 6),
                q.unit,
                sig(*b, 6),
                q.unit,
                unequal,
                q.code.len()
            ));
        }
    }
    let mut s = Table::new(vec![
        Column::text("quantity"),
        Column::text(format!("{} mean ± SE", r.code)).right(),
        Column::text("dembound mean ± SE").right(),
        Column::text("ratio − 1").right(),
        Column::text("verdict"),
    ]);
    for q in r.quantities.iter().filter(|q| q.verdict.is_some()) {
        let show = |w: &Option<WindowMean>| {
            w.map_or("—".into(), |w| {
                format!(
                    "{} ± {} {}",
                    sig(w.mean, 6),
                    sig(w.standard_error, 2),
                    q.unit
                )
            })
        };
        s.push(vec![
            Cell::text(q.name.clone()),
            Cell::text(show(&q.code_window)),
            Cell::text(show(&q.dembound_window)),
            Cell::text(
                q.window_relative_difference
                    .map_or("—".into(), |d| format!("{:+.2e}", d)),
            ),
            Cell::text(q.verdict.map_or("—", |v| v.text())),
        ]);
    }
    out.push_str(&format!(
        "\nStatistical agreement over the late window (t ≥ {} s, batch means; agree: within 1 % or 2 SE):\n{s}\n",
        sig(r.window_from, 4)
    ));
    out.push_str(&autocorrelation_notes(r));
    let speed = |s: &Speed| {
        let mut times = Vec::new();
        if let Some(c) = s.cpu_seconds {
            times.push(format!("{} s CPU", sig(c, 3)));
        }
        if let Some(w) = s.wall_seconds {
            times.push(format!(
                "{} s wall on {} core{}",
                sig(w, 3),
                s.cores,
                if s.cores == 1 { "" } else { "s" }
            ));
        }
        format!(
            "{:.2e} free-sphere steps per core-second by {} time ({})",
            s.particle_steps_per_core_second,
            s.clock,
            times.join(", ")
        )
    };
    for p in &r.profiles {
        out.push_str(&format!(
            "Profile of {} ({}) against z, bins of {} m (the mean free diameter), late window: \
             largest |{} − dembound| = {} at z = {} m (± {} combined SE){}\n",
            p.name,
            p.unit,
            sig(p.bin_width, 4),
            r.code,
            sig(p.max_abs_difference, 3),
            sig(p.at, 4),
            sig(p.standard_error_there, 2),
            match (p.bar, p.agree) {
                (Some(b), Some(true)) => format!(": agree (≤ {b})"),
                (Some(b), _) => format!(": DIFFER (> {b})"),
                _ => String::new(),
            }
        ));
    }
    out.push_str(&format!(
        "\nSpeed: {} {}; dembound {} (stepping only){}\n",
        r.code,
        r.code_speed
            .as_ref()
            .map_or("— (no Loop time in its log)".into(), speed),
        r.dembound_speed
            .as_ref()
            .map_or("— (no time measured)".into(), speed),
        match (
            r.code_speed.as_ref().map(|s| s.clock),
            r.dembound_speed.as_ref().map(|s| s.clock)
        ) {
            (Some(a), Some(b)) if a != b => {
                " — one by wall clock, one by CPU time: on a loaded machine the wall-clock rate understates that code's per-core speed"
            }
            _ => "",
        }
    ));
    for n in &r.notes {
        out.push_str(&format!("Note: {n}\n"));
    }
    out
}

/// One figure per quantity (both runs against time) and one of every
/// relative difference's log10 (a straight rise: exponential growth).
pub fn write_figures(r: &SceneCompareReport, dir: &Path) -> anyhow::Result<()> {
    std::fs::create_dir_all(dir)
        .map_err(|e| anyhow!("--figures `{}`: cannot create it: {e}", dir.display()))?;
    let stem = |name: &str| -> String {
        name.chars()
            .map(|c| {
                if c.is_ascii_alphanumeric() {
                    c.to_ascii_lowercase()
                } else {
                    '_'
                }
            })
            .collect::<String>()
            .split('_')
            .filter(|w| !w.is_empty())
            .collect::<Vec<_>>()
            .join("_")
    };
    for q in r.quantities.iter().filter(|q| !q.name.starts_with("state")) {
        let pts = |v: &[f64]| {
            q.time
                .iter()
                .zip(v)
                .map(|(t, y)| (*t, *y))
                .collect::<Vec<_>>()
        };
        let fig = Figure {
            title: format!("{}: {} and dembound", q.name, r.code),
            x_label: "t (s)".into(),
            y_label: format!("{} ({})", q.name, q.unit),
            series: vec![
                Series::new(r.code.clone(), pts(&q.code), Mark::Line, 0),
                Series::new("dembound", pts(&q.dembound), Mark::Dashed, 1),
            ],
            ..Figure::default()
        };
        fig.write(&dir.join(stem(&q.name)))?;
    }
    let mut fig = Figure {
        title: format!(
            "{} against dembound: relative differences (1e-9: identical)",
            r.code
        ),
        x_label: "t (s)".into(),
        // log10 on a linear axis: the figure module's log axes print
        // ticks far below the top of the range as "0".
        y_label: "log10 of the relative difference (1)".into(),
        legend_outside: true,
        ..Figure::default()
    };
    for (k, q) in r.quantities.iter().enumerate() {
        let pts: Vec<(f64, f64)> = q
            .time
            .iter()
            .zip(&q.relative_difference)
            .filter(|(_, d)| **d > 0.0)
            .map(|(t, d)| (*t, d.log10()))
            .collect();
        fig.series
            .push(Series::new(q.name.clone(), pts, Mark::Line, k));
    }
    fig.write(&dir.join("relative_differences"))?;
    for p in &r.profiles {
        let pts = |m: &[Option<WindowMean>]| -> Vec<(f64, f64)> {
            m.iter()
                .zip(&p.centres)
                .filter_map(|(w, z)| w.map(|w| (w.mean, *z)))
                .collect()
        };
        let fig = Figure {
            title: format!(
                "{} against z, late-window mean: {} and dembound (bins {} m)",
                p.name,
                r.code,
                sig(p.bin_width, 3)
            ),
            x_label: format!("{} ({})", p.name, p.unit),
            y_label: "z (m)".into(),
            series: vec![
                Series::new(r.code.clone(), pts(&p.code), Mark::Line, 0),
                Series::new("dembound", pts(&p.dembound), Mark::Dashed, 1),
            ],
            ..Figure::default()
        };
        fig.write(&dir.join(format!("profile_{}", stem(&p.name))))?;
    }
    Ok(())
}

/// The lines saying which window means took their standard error from the
/// integrated autocorrelation time τ (`agreement::window_mean_autocorrelated`),
/// with τ in seconds (rows × the row interval), and whether the window
/// spans enough of them to trust it.
fn autocorrelation_notes(r: &SceneCompareReport) -> String {
    let mut out = String::new();
    for q in &r.quantities {
        let (Some(c), Some(d)) = (q.code_window, q.dembound_window) else {
            continue;
        };
        let (Some(tc), Some(td)) = (c.autocorrelation_rows, d.autocorrelation_rows) else {
            continue;
        };
        let row = match q.time.as_slice() {
            [a, b, ..] => b - a,
            _ => continue,
        };
        let unreliable = [c, d]
            .iter()
            .any(|w| w.autocorrelation_reliable == Some(false));
        out.push_str(&format!(
            "  {}: SE from the integrated autocorrelation time (not batch means): τ = {} s ({}), \
             {} s (dembound){}\n",
            q.name,
            sig(tc * row, 3),
            r.code,
            sig(td * row, 3),
            if unreliable {
                "; the window spans fewer than 50 τ, so τ and the SE are uncertain (likely \
                 too small) and a difference beyond 2 SE is left undecided"
            } else {
                ""
            }
        ));
    }
    out
}
