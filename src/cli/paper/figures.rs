//! The paper's figures (Figs 4–8) drawn from [`PaperData`], each with its
//! file stem and caption.

use crate::cli::lists::show;
use crate::plot::{Figure, Mark, Series};
use dembound_core::contact::ContactLawKind;
use dembound_core::study::indicators::{eq33, PAPER_MAX};
use dembound_core::study::paper::{PaperData, FIG4_R, LAWS, RADII, ZETAS};
use dembound_core::study::sweep::SweepResult;
use dembound_core::study::{Axis, Quantity};

/// Whether a grid value gets a numerical point (4 per decade) or only the exact curve.
pub(super) fn marked(x: f64) -> bool {
    let k = (x.log10() * 12.0).round() as i64;
    (x.log10() * 12.0 - k as f64).abs() > 1e-6 || k % 3 == 0
}

const R_LABEL: &str = "boundary radius ratio r = R_b/R_m  (1)";
const Z_LABEL: &str = "boundary modulus ratio ζ = E_b/E_m  (1)";

fn law_color(law: ContactLawKind) -> usize {
    match law {
        ContactLawKind::Linear => 0,
        _ => 1,
    }
}

fn fig4(d: &PaperData, r: f64, letter: char) -> Figure {
    let mut series = Vec::new();
    for (i, z) in ZETAS.iter().enumerate() {
        for law in LAWS {
            let Some(h) = d
                .histories
                .iter()
                .find(|h| h.law == law && h.r == r && h.zeta == *z)
            else {
                continue;
            };
            let (line, points) = match law {
                ContactLawKind::Linear => (Mark::Dashed, Mark::Triangles),
                _ => (Mark::Line, Mark::Points),
            };
            series.push(Series::new(
                format!("{}, ζ = {}", law.name(), show(*z)),
                h.exact.clone(),
                line,
                i,
            ));
            let every = if law == ContactLawKind::Linear { 4 } else { 2 };
            let pts = h.integrator.iter().step_by(every).copied().collect();
            series.push(Series::new("", pts, points, i));
        }
    }
    series.push(Series::new("integrator, Hertz", vec![], Mark::Points, 7));
    series.push(Series::new(
        "integrator, linear",
        vec![],
        Mark::Triangles,
        7,
    ));
    Figure {
        title: format!("Fig 4{letter}: overlap histories, r = {}", show(r)),
        x_label: "time since contact onset t* = t / T_c_NL  (1)".into(),
        y_label: "overlap h* = h / h_NL_max  (1)".into(),
        x_log: false,
        y_log: false,
        series,
        ..Default::default()
    }
}

/// h* (or T_c*) against the swept axis, one curve per value of the other.
fn curves(
    sw: &SweepResult,
    law: ContactLawKind,
    along_r: bool,
    others: &[f64],
    q: Quantity,
    scale: f64,
) -> Vec<Series> {
    let mut series = Vec::new();
    for (i, &o) in others.iter().enumerate() {
        let mut cases: Vec<_> = sw
            .cases
            .iter()
            .filter(|c| {
                c.key.law == law
                    && if along_r {
                        c.key.modulus_ratio == o
                    } else {
                        c.key.radius_ratio == o
                    }
            })
            .collect();
        let x = |c: &&dembound_core::study::sweep::SweepCase| {
            if along_r {
                c.key.radius_ratio
            } else {
                c.key.modulus_ratio
            }
        };
        cases.sort_by(|a, b| x(a).total_cmp(&x(b)));
        let exact = cases
            .iter()
            .map(|c| (x(c), c.first().exact.get(q) / scale))
            .collect();
        let num = cases
            .iter()
            .filter(|c| marked(x(c)))
            .map(|c| (x(c), c.first().numerical.get(q) / scale))
            .collect();
        let name = if along_r { "ζ" } else { "r" };
        series.push(Series::new(
            format!("{name} = {}", show(o)),
            exact,
            Mark::Line,
            i,
        ));
        series.push(Series::new("", num, Mark::Points, i));
    }
    series.push(Series::new("lines: exact reference", vec![], Mark::Line, 7));
    series.push(Series::new(
        "points: integrator (Gear5, η = 1/50)",
        vec![],
        Mark::Points,
        7,
    ));
    series
}

fn fig8(d: &PaperData, axis: Axis) -> Figure {
    let along_r = axis == Axis::Radius;
    let sw = if along_r { &d.sweep_r } else { &d.sweep_zeta };
    let others: &[f64] = if along_r { &ZETAS } else { &RADII };
    let mut series = Vec::new();
    let xs: Vec<f64> = {
        let mut v: Vec<f64> = sw
            .cases
            .iter()
            .map(|c| {
                if along_r {
                    c.key.radius_ratio
                } else {
                    c.key.modulus_ratio
                }
            })
            .filter(|x| *x < PAPER_MAX)
            .collect();
        v.sort_by(f64::total_cmp);
        v.dedup();
        v
    };
    for law in LAWS {
        let c = law_color(law);
        let alpha = law.exponent();
        let theory = xs
            .iter()
            .map(|&x| (x, eq33(axis, x, PAPER_MAX, alpha, false)))
            .collect();
        series.push(Series::new(
            format!(
                "{}: eq 33{} corrected (theory)",
                law.name(),
                if along_r { "b" } else { "a" }
            ),
            theory,
            Mark::Line,
            c,
        ));
        // Numerical: eq 32 on the integrator's h_max, every curve of Fig 5 (6).
        let mark = if law == ContactLawKind::Linear {
            Mark::Triangles
        } else {
            Mark::Points
        };
        for (k, &o) in others.iter().enumerate() {
            let at = |x: f64| {
                let (r, z) = if along_r { (x, o) } else { (o, x) };
                sw.find(0, law, r, z)
                    .map(|c| c.first().numerical.max_overlap)
            };
            let Some(h_max) = at(PAPER_MAX) else { continue };
            let pts = xs
                .iter()
                .filter(|x| marked(**x))
                .filter_map(|&x| at(x).map(|h| (x, 100.0 * (h - h_max) / h_max)))
                .collect();
            let label = if k == 0 {
                format!(
                    "{}: eq 32{} integrator, {} = {} … {}",
                    law.name(),
                    if along_r { "b" } else { "a" },
                    if along_r { "ζ" } else { "r" },
                    show(others[0]),
                    show(others[others.len() - 1])
                )
            } else {
                String::new()
            };
            series.push(Series::new(label, pts, mark, c));
        }
    }
    // As printed: 33a is the same for both laws; 33b differs from the corrected form for Hertz.
    if along_r {
        let printed = xs
            .iter()
            .map(|&x| (x, eq33(axis, x, PAPER_MAX, 1.5, true)))
            .collect();
        series.push(Series::new(
            "Hertz: eq 33b as printed",
            printed,
            Mark::Dashed,
            1,
        ));
    } else {
        let printed = xs
            .iter()
            .map(|&x| (x, eq33(axis, x, PAPER_MAX, 1.5, true)))
            .collect();
        series.push(Series::new(
            "eq 33a as printed (both laws)",
            printed,
            Mark::Dashed,
            6,
        ));
    }
    Figure {
        title: format!(
            "Fig 8{}: indicator ΔΨ against {} ({}_max = 1000)",
            if along_r { 'b' } else { 'a' },
            axis.symbol(),
            axis.symbol()
        ),
        x_label: if along_r {
            R_LABEL.into()
        } else {
            Z_LABEL.into()
        },
        y_label: "indicator ΔΨ on h_max  (%)".into(),
        x_log: true,
        y_log: true,
        series,
        ..Default::default()
    }
}

/// Every figure with its file stem and caption.
pub(super) fn figures(d: &PaperData) -> Vec<(String, Figure, String)> {
    let sc = &d.scaling;
    let mut out = Vec::new();
    for (r, letter) in FIG4_R.iter().zip(['a', 'b', 'c']) {
        out.push((
            format!("fig4{letter}"),
            fig4(d, *r, letter),
            format!(
                "Fig 4{letter}: overlap h* = h/h_NL_max against t* = t/T_c_NL during the first contact, r = {}, \
                 ζ = 1, 10, 100, 1000; Hertz solid lines and circles, linear dashed lines and triangles. \
                 Lines: exact reference (`exact::overlap_at`); points: integrator steps \
                 (every 2nd for Hertz, every 4th for linear).",
                show(*r)
            ),
        ));
    }
    let h = Quantity::MaxOverlap;
    let t = Quantity::Duration;
    for (law, letter) in LAWS.iter().zip(['a', 'b']) {
        out.push((
            format!("fig5{letter}"),
            Figure {
                title: format!(
                    "Fig 5{letter}: maximum overlap against r, {} law",
                    law.name()
                ),
                x_label: R_LABEL.into(),
                y_label: "h*_max = h_max / h_NL_max  (1)".into(),
                x_log: true,
                y_log: false,
                series: curves(&d.sweep_r, *law, true, &ZETAS, h, sc.h_nl),
                ..Default::default()
            },
            format!(
                "Fig 5{letter}: h*_max against r for ζ = 1, 10, 100, 1000, {} law.",
                law.name()
            ),
        ));
    }
    for (law, letter) in LAWS.iter().zip(['a', 'b']) {
        out.push((
            format!("fig6{letter}"),
            Figure {
                title: format!("Fig 6{letter}: maximum overlap against ζ, {} law", law.name()),
                x_label: Z_LABEL.into(),
                y_label: "h*_max = h_max / h_NL_max  (1)".into(),
                x_log: true,
                y_log: false,
                series: curves(&d.sweep_zeta, *law, false, &RADII, h, sc.h_nl),
                ..Default::default()
            },
            format!(
                "Fig 6{letter}: h*_max against ζ for r = 0.5, 1, 10, 100, 1000 (five curves, ERRATA 17), {} law.",
                law.name()
            ),
        ));
    }
    let hertz = ContactLawKind::Hertz;
    out.push((
        "fig7a".into(),
        Figure {
            title: "Fig 7a: contact duration against ζ, Hertz".into(),
            x_label: Z_LABEL.into(),
            y_label: "T*_c = T_c / T_c_NL  (1)".into(),
            x_log: true,
            y_log: false,
            series: curves(&d.sweep_zeta, hertz, false, &RADII, t, sc.t_nl),
            ..Default::default()
        },
        "Fig 7a: T*_c against ζ for r = 0.5, 1, 10, 100, 1000, Hertz.".into(),
    ));
    out.push((
        "fig7b".into(),
        Figure {
            title: "Fig 7b: contact duration against r, Hertz".into(),
            x_label: R_LABEL.into(),
            y_label: "T*_c = T_c / T_c_NL  (1)".into(),
            x_log: true,
            y_log: false,
            series: curves(&d.sweep_r, hertz, true, &ZETAS, t, sc.t_nl),
            ..Default::default()
        },
        "Fig 7b: T*_c against r for ζ = 1, 10, 100, 1000, Hertz.".into(),
    ));
    out.push((
        "fig8a".into(),
        fig8(d, Axis::Modulus),
        "Fig 8a: eq 32a on the integrator's h_max (ζ_max = 1000) for every r of Fig 6, against eq 33a \
         corrected (ERRATA 15) and as printed. Each law's points fall on one curve; the laws do not \
         share one (ERRATA 16)."
            .into(),
    ));
    out.push((
        "fig8b".into(),
        fig8(d, Axis::Radius),
        "Fig 8b: eq 32b on the integrator's h_max (r_max = 1000) for every ζ of Fig 5, against eq 33b \
         corrected and as printed (as printed, Hertz uses the exponent (2−α)/2 = 1/4 instead of 1/5; \
         for the linear law both forms agree)."
            .into(),
    ));
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use dembound_core::study::paper::decades;

    #[test]
    fn four_points_per_decade_are_marked() {
        let g = decades(0, 3, 12);
        for d in [1.0, 10.0, 100.0, 1000.0] {
            assert!(marked(d));
        }
        assert_eq!(g.iter().filter(|x| marked(**x)).count(), 13);
    }
}
