//! Granular column collapse in plane strain (Lube, Huppert, Sparks &
//! Freundt 2005, "Collapses of two-dimensional granular columns", Phys.
//! Rev. E 72, 041301; the axisymmetric case: Lube et al. 2004, J. Fluid
//! Mech. 508, 175–199; Lajeunesse, Monnier & Homsy 2005, Phys. Fluids 17,
//! 103302): a column of length L0 and height H0 against an end wall,
//! released by removing the gate, spreads to a deposit of run-out L∞ and
//! height H∞. The published laws, in the aspect ratio a = H0/L0:
//!
//! - run-out (L∞ − L0)/L0 = 1.2 a for a < 1.8 and 1.9 a^(2/3) for a > 2.8;
//! - final height H∞/L0 = a for a < 1.15 (the top of the column is left
//!   undisturbed) and a^(2/5) above (Lube et al. 2005's laws; Balmforth &
//!   Kerswell 2005, J. Fluid Mech. 538, 399–428, find H0/H∞ ∼ a^0.6 in
//!   wide channels, the same exponent, and note material-dependent
//!   prefactors).
//!
//! Here the channel is periodic across (plane strain, 3 mean diameters
//! wide: no side-wall friction), the base a flat frictional plane. The
//! column is settled behind the gate in one simulation and released into
//! a second one without the gate, from the settled positions and
//! velocities (the contacts' tangential springs restart from zero: the
//! settled column carries its weight on the normal forces; the collapse
//! then mobilises friction within a few contact times).

use super::granular::{advance, Grains, Rng};
use super::{Band, Check, Curve, Outcome, Plot, Style};
use crate::setup::{DomainSetup, Outside, Plane, SceneSetup, SphereInit, WallSetup};
use crate::{SceneError, Simulation};
use dembound_physics::material::Material;

pub(super) const SOURCE: &str = "Lube, Huppert, Sparks & Freundt (2005), Phys. Rev. E 72, 041301";
pub(super) const TITLE: &str =
    "Granular column collapse in plane strain: run-out and final height against aspect ratio";

/// The published run-out law (L∞ − L0)/L0 of Lube et al. (2005) at `a`,
/// with its regime; `None` between the regimes (1.8 ≤ a ≤ 2.8), where
/// the paper gives no law.
pub(super) fn published_runout(a: f64) -> Option<f64> {
    if a < 1.8 {
        Some(1.2 * a)
    } else if a > 2.8 {
        Some(1.9 * a.powf(2.0 / 3.0))
    } else {
        None
    }
}

/// The published final height H∞/L0 of Lube et al. (2005) at `a`.
pub(super) fn published_height(a: f64) -> f64 {
    if a < 1.15 {
        a
    } else {
        a.powf(0.4)
    }
}

fn grains() -> Grains {
    Grains {
        radius: 1.0e-3,
        spread: 0.1,
        material: Material {
            density: 2500.0,
            youngs_modulus: 5.0e6,
            poisson_ratio: 0.3,
        },
        friction: 0.5,
        rolling_friction: 0.1,
        restitution: 0.3,
    }
}

struct Setup {
    /// Column length L0 in mean diameters.
    length_diameters: f64,
    /// Channel width (periodic) in mean diameters.
    width_diameters: f64,
    /// Nominal aspect ratios (the measured settled ones are reported).
    ratios: Vec<f64>,
    /// One more run at (nominal a, L0 in mean diameters): the grain-size
    /// effect on the run-out.
    wider: Option<(f64, f64)>,
    settle: f64,
    /// Longest collapse simulated, s (the run stops earlier once at rest).
    collapse: f64,
}

fn setup(quick: bool) -> Setup {
    if quick {
        Setup {
            length_diameters: 6.0,
            width_diameters: 3.0,
            ratios: vec![1.0, 4.0],
            wider: None,
            settle: 0.2,
            collapse: 0.8,
        }
    } else {
        Setup {
            length_diameters: 8.0,
            width_diameters: 3.0,
            ratios: vec![0.5, 1.0, 1.5, 3.5, 5.0],
            wider: Some((1.0, 16.0)),
            settle: 0.3,
            collapse: 1.2,
        }
    }
}

/// One collapse's result.
#[derive(Debug, Clone)]
struct Collapse {
    /// Settled aspect ratio H0/L0.
    a: f64,
    /// (L∞ − L0)/L0 and H∞/L0.
    runout: f64,
    height: f64,
    /// The deposit's highest sphere top over L0 (the former H∞).
    highest: f64,
    /// The farthest centre from the end wall among the spheres H∞
    /// averages, over L0: where the top band lies.
    band_reach: f64,
    spheres: usize,
    /// Time to rest, s (or the longest simulated).
    time: f64,
    /// Kinetic energy at the end over M g H0/2.
    rest: f64,
    /// The deposit's surface profile: (x/L0, h/L0).
    profile: Vec<(f64, f64)>,
}

/// A granular surface's height as Lube et al. (2005) read both H0 and H∞:
/// H∞/L0 = a below a = 1.15, where the top of the column is left
/// undisturbed, says that H∞ is the same surface's height as H0, measured
/// the same way. The top of a bed of grains is rough on the grain scale,
/// so the height is the mean top (z + R) of the spheres whose top lies
/// within `band` (one mean diameter) of the highest; the highest alone
/// would read a single grain's excursion. Applied to the settled column
/// (H0) and to the deposit (H∞), whose highest band lies at the end wall
/// (its reach is reported).
struct Top {
    /// The mean top of the band, m.
    height: f64,
    /// The highest sphere top, m.
    highest: f64,
    /// The largest x of the band's spheres' centres, m.
    reach: f64,
}

fn mean_top(x: &[[f64; 3]], radii: &[f64], band: f64) -> Top {
    let highest = x
        .iter()
        .zip(radii)
        .map(|(p, r)| p[2] + r)
        .fold(f64::NEG_INFINITY, f64::max);
    let (mut sum, mut count, mut reach) = (0.0, 0usize, f64::NEG_INFINITY);
    for (p, r) in x.iter().zip(radii) {
        let t = p[2] + r;
        if t > highest - band {
            sum += t;
            count += 1;
            reach = reach.max(p[0]);
        }
    }
    Top {
        height: sum / count.max(1) as f64,
        highest,
        reach,
    }
}

/// Largest top (z + R) of the spheres in each bin of width `bin` from
/// x = 0, up to the first empty bin (a grain beyond a gap is not part of
/// the deposit): (bin's right edge, top) per bin.
fn surface(x: &[[f64; 3]], radii: &[f64], bin: f64) -> Vec<(f64, f64)> {
    let far = x.iter().map(|p| p[0]).fold(0.0, f64::max);
    let bins = (far / bin).ceil() as usize + 2;
    let mut top = vec![f64::NAN; bins];
    let mut front = vec![0.0f64; bins];
    for (p, &r) in x.iter().zip(radii) {
        let k = (p[0] / bin).floor().max(0.0) as usize;
        if k < bins {
            let t = p[2] + r;
            top[k] = if top[k].is_nan() { t } else { top[k].max(t) };
            front[k] = front[k].max(p[0] + r);
        }
    }
    let mut out = Vec::new();
    for k in 0..bins {
        if top[k].is_nan() {
            break;
        }
        out.push((front[k].max(k as f64 * bin), top[k]));
    }
    out
}

fn collapse_one(
    g: &Grains,
    s: &Setup,
    nominal_a: f64,
    length_diameters: f64,
    progress: &dyn Fn(&str),
) -> Result<Collapse, SceneError> {
    let d = 2.0 * g.radius;
    let l0 = length_diameters * d;
    let width = s.width_diameters * d;
    let h0_nominal = nominal_a * l0;
    let r_max = g.max_radius();
    let spacing = 2.05 * r_max;
    // The sites' packing fraction, (4π/3)/2.05³ (R/R_max)³ ≈ 0.37, settles
    // to ~0.6 and the layers settle into one another: the loose column
    // stands ~1.85× as tall as the settled one (measured in trial runs; the
    // settled a is measured and reported, not assumed).
    let loose = 1.85 * h0_nominal;
    let reach_z = loose + 0.5 * d;
    let mut rng = Rng(2005 + (nominal_a * 100.0) as u64);
    let lower = |x_hi: f64, z_hi: f64| DomainSetup {
        lower: [-d, 0.0, -d],
        upper: [x_hi, width, z_hi],
        periodic: [false, true, false],
    };
    let mut first = g.scene(lower(l0 + d, reach_z + 4.0 * d), 2.0, 25.0);
    let nx = ((l0 - 2.0 * r_max) / spacing).floor() as usize + 1;
    let ny = (width / spacing).floor() as usize;
    let dy = width / ny as f64;
    let mut z = r_max + 0.02 * g.radius;
    while z < loose {
        for i in 0..nx {
            for j in 0..ny {
                let x = r_max + 0.01 * g.radius + i as f64 * spacing;
                let y = (j as f64 + 0.5) * dy;
                let jit = 0.02 * g.radius;
                first.spheres.push(g.sphere(
                    [x + jit * rng.symmetric(), y + jit * rng.symmetric(), z],
                    &mut rng,
                ));
            }
        }
        z += spacing;
    }
    let floor = WallSetup::Plane(Plane {
        point: [0.0; 3],
        normal: [0.0, 0.0, 1.0],
        material: 0,
    });
    let back = WallSetup::Plane(Plane {
        point: [0.0; 3],
        normal: [1.0, 0.0, 0.0],
        material: 0,
    });
    let gate = WallSetup::Plane(Plane {
        point: [l0, 0.0, 0.0],
        normal: [-1.0, 0.0, 0.0],
        material: 0,
    });
    first.walls = vec![floor.clone(), back.clone(), gate];
    let n = first.spheres.len();
    let mut sim = Simulation::new(first.clone(), 1)?;
    advance(
        &mut sim,
        s.settle,
        &format!("column a = {nominal_a}: settling"),
        progress,
    )?;
    let (x, v, radii) = (sim.positions(), sim.velocities(), sim.radii());
    // The settled height, measured as the deposit's below.
    let h0 = mean_top(&x, &radii, d).height;
    let a = h0 / l0;
    // The run-out domain: the longest published run-out and a half more.
    let expected = published_runout(a).unwrap_or(1.9 * a.powf(2.0 / 3.0));
    let x_hi = l0 * (1.0 + 1.6 * expected) + 10.0 * d;
    let mut second: SceneSetup = first;
    second.domain = lower(x_hi, h0 + 10.0 * d);
    second.walls = vec![floor, back];
    second.outside = Outside::Keep;
    second.spheres = second
        .spheres
        .iter()
        .take(n)
        .enumerate()
        .map(|(i, s)| SphereInit {
            position: x[i],
            velocity: v[i],
            ..s
        })
        .collect();
    let mut sim = Simulation::new(second, 1)?;
    // Until at rest: kinetic energy below 1e-6 of the column's potential
    // energy (M g H0/2; about one grain in a hundred at 1 cm/s), checked
    // every 0.02 s.
    let mass: f64 = radii.iter().map(|&r| g.material.sphere_mass(r)).sum();
    let scale = mass * super::granular::G * h0 / 2.0;
    let mut t = 0.0;
    while t < s.collapse {
        advance(&mut sim, 0.02, "", &|_| {})?;
        t += 0.02;
        if sim.kinetic_energy() < 1e-6 * scale && t > 0.1 {
            break;
        }
    }
    let rest = sim.kinetic_energy() / scale;
    progress(&format!(
        "column a = {a:.2}, L0 = {length_diameters} d: {n} spheres, t = {t:.2} s, kinetic/potential energy {rest:.1e}"
    ));
    let x = sim.positions();
    let prof = surface(&x, &radii, d);
    let l_inf = prof.last().map(|p| p.0).unwrap_or(0.0);
    // H∞ as H0 (`mean_top`), over the deposit's spheres (those the
    // profile reaches).
    let reach = l_inf + d;
    let (xs, rs): (Vec<[f64; 3]>, Vec<f64>) = x
        .iter()
        .zip(&radii)
        .filter(|(p, _)| p[0] <= reach)
        .map(|(p, &r)| (*p, r))
        .unzip();
    let top = mean_top(&xs, &rs, d);
    Ok(Collapse {
        a,
        runout: (l_inf - l0) / l0,
        height: top.height / l0,
        highest: top.highest / l0,
        band_reach: top.reach / l0,
        spheres: n,
        time: t,
        rest,
        profile: prof.iter().map(|&(x, h)| (x / l0, h / l0)).collect(),
    })
}

pub(super) fn run(quick: bool, progress: &dyn Fn(&str)) -> Result<Outcome, SceneError> {
    let g = grains();
    let s = setup(quick);
    let mut runs = Vec::new();
    for &a in &s.ratios {
        runs.push(collapse_one(&g, &s, a, s.length_diameters, progress)?);
    }
    let wider = match s.wider {
        Some((a, l)) => Some((l, collapse_one(&g, &s, a, l, progress)?)),
        None => None,
    };
    let band = Band::Relative(0.25);
    let mut checks = Vec::new();
    for c in &runs {
        if let Some(p) = published_runout(c.a) {
            checks.push(Check::new(
                format!("a = {:.2}: run-out (L∞ − L0)/L0", c.a),
                "1",
                c.runout,
                p,
                band,
                if c.a < 1.8 {
                    "Lube et al. 2005: 1.2 a (a < 1.8)"
                } else {
                    "Lube et al. 2005: 1.9 a^(2/3) (a > 2.8)"
                },
            ));
        }
        checks.push(Check::new(
            format!("a = {:.2}: final height H∞/L0", c.a),
            "1",
            c.height,
            published_height(c.a),
            band,
            if c.a < 1.15 {
                "Lube et al. 2005: a (a < 1.15)"
            } else {
                "Lube et al. 2005: a^(2/5) (a > 1.15)"
            },
        ));
    }
    if let Some((l, c)) = &wider {
        if let Some(p) = published_runout(c.a) {
            checks.push(Check::new(
                format!("a = {:.2}, L0 = {l} diameters: run-out (L∞ − L0)/L0", c.a),
                "1",
                c.runout,
                p,
                band,
                "Lube et al. 2005: 1.2 a (a < 1.8)",
            ));
        }
    }
    let a_max = runs.iter().map(|c| c.a).fold(6.0, f64::max);
    let law = |f: &dyn Fn(f64) -> Option<f64>, lo: f64, hi: f64| -> Vec<(f64, f64)> {
        (0..=40)
            .filter_map(|i| {
                let a = lo + (hi - lo) * i as f64 / 40.0;
                f(a).map(|y| (a, y))
            })
            .collect()
    };
    let plots = vec![
        Plot {
            stem: "column-runout".into(),
            title: "Column collapse: run-out against aspect ratio".into(),
            x_label: "aspect ratio a = H0/L0 (1)".into(),
            y_label: "run-out (L∞ − L0)/L0 (1)".into(),
            curves: vec![
                Curve::new(
                    format!("ours, L0 = {} diameters", s.length_diameters),
                    runs.iter().map(|c| (c.a, c.runout)).collect(),
                    Style::Ours,
                    0,
                ),
                Curve::new(
                    "ours, wider column",
                    wider.iter().map(|(_, c)| (c.a, c.runout)).collect(),
                    Style::Ours,
                    1,
                ),
                Curve::new(
                    "1.2 a (Lube et al. 2005, a < 1.8)",
                    law(&|a| Some(1.2 * a), 0.2, 1.8),
                    Style::ClosedForm,
                    7,
                ),
                Curve::new(
                    "1.9 a^(2/3) (a > 2.8)",
                    law(&|a| Some(1.9 * a.powf(2.0 / 3.0)), 2.8, a_max),
                    Style::ClosedForm,
                    7,
                ),
            ],
        },
        Plot {
            stem: "column-height".into(),
            title: "Column collapse: final height against aspect ratio".into(),
            x_label: "aspect ratio a = H0/L0 (1)".into(),
            y_label: "final height H∞/L0 (1)".into(),
            curves: vec![
                Curve::new(
                    "ours",
                    runs.iter().map(|c| (c.a, c.height)).collect(),
                    Style::Ours,
                    0,
                ),
                Curve::new(
                    "a, then a^(2/5) (Lube et al. 2005)",
                    law(&|a| Some(published_height(a)), 0.2, a_max),
                    Style::ClosedForm,
                    7,
                ),
            ],
        },
        Plot {
            stem: "column-deposits".into(),
            title: "Column collapse: final deposits".into(),
            x_label: "distance from the end wall x/L0 (1)".into(),
            y_label: "deposit surface h/L0 (1)".into(),
            curves: runs
                .iter()
                .enumerate()
                .map(|(k, c)| {
                    Curve::new(format!("a = {:.2}", c.a), c.profile.clone(), Style::Ours, k)
                })
                .collect(),
        },
    ];
    let mut notes = vec![
        format!(
            "Runs: {}.",
            runs.iter()
                .map(|c| format!(
                    "a = {:.2} ({} spheres, (L∞ − L0)/L0 = {:.2}, H∞/L0 = {:.3} (highest sphere \
                     top {:.3}, top band within x ≤ {:.2} L0 of the end wall), stopped at {:.2} s \
                     with kinetic energy {:.1e} of M g H0/2)",
                    c.a, c.spheres, c.runout, c.height, c.highest, c.band_reach, c.time, c.rest
                ))
                .collect::<Vec<_>>()
                .join("; ")
        ),
        "L∞: the farthest sphere edge of the deposit, counted from the end wall up to the first \
         empty one-diameter bin (grains beyond a gap are not the deposit). H0 and H∞ are one \
         definition, as Lube et al.'s H∞ = H0 for an undisturbed top (a < 1.15) requires: the \
         mean top of the spheres within one mean diameter of the highest sphere top, of the \
         settled column and of the deposit (whose top band lies at the end wall). The deposit's \
         highest sphere top (H∞'s definition before) is given with each run above."
            .into(),
        "No law is published between the regimes (1.8 ≤ a ≤ 2.8), so a run there is shown \
         without a run-out check. The band ±25 % is the spread of the laws' prefactors between \
         materials (Balmforth & Kerswell 2005 find them material dependent; Lube et al. report \
         them for their materials)."
            .into(),
    ];
    if let Some((l, c)) = &wider {
        // The run at the same nominal a with the shorter column.
        let short = runs.get(1);
        notes.push(format!(
            "Grain size: the same a ≈ {:.2} with L0 = {l} diameters ({} spheres) runs out to \
             (L∞ − L0)/L0 = {:.2}, H∞/L0 = {:.2}, against {:.2} and {:.2} at L0 = {} diameters. The \
             deposit ends in a tail one grain thick that adds one or two diameters to L∞ whatever \
             L0: 0.1–0.25 of the normalised run-out at L0 = 8 diameters. The run-out depends on \
             L0/d at small L0/d (Warnett et al. 2014, Granular Matter 16, 115–124; Man et al. 2021, \
             arXiv:2012.03287); Lube et al.'s columns were hundreds of grains long. If the \
             excess is a fixed length (∝ d/L0), the two lengths extrapolate to {:.2} at \
             L0/d → ∞ (2 × the wider run's − the shorter's), against 1.2 a = {:.2}.",
            c.a,
            c.spheres,
            c.runout,
            c.height,
            short.map_or(f64::NAN, |r| r.runout),
            short.map_or(f64::NAN, |r| r.height),
            s.length_diameters,
            short.map_or(f64::NAN, |r| (l * c.runout - s.length_diameters * r.runout)
                / (l - s.length_diameters)),
            1.2 * c.a
        ));
    }
    Ok(Outcome {
        name: "column-collapse",
        title: TITLE,
        source: SOURCE,
        parameters: vec![
            g.describe(),
            format!(
                "column L0 = {} mean diameters against a frictional end wall, on a flat frictional \
                 base (both of the grains' material and μ); the channel periodic across, {} diameters \
                 wide (plane strain)",
                s.length_diameters, s.width_diameters
            ),
            format!(
                "filled on a loose lattice, settled {} s behind the gate, released at rest (second \
                 simulation without the gate); Δt = 1/25 of the Hertz time at 2 m/s",
                s.settle
            ),
        ],
        notes,
        checks,
        plots,
        seconds: 0.0,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_mean_top_averages_the_band_below_the_highest_top() {
        // Tops (z + R) 1.00, 0.90, 0.80 within 0.25 of the highest, 0.70
        // and 0.50 below it: the mean of the first three, 0.9, exactly
        // (to round-off), the highest 1.0, the band's farthest centre the
        // 0.80 one at x = 3.
        let r = [0.1, 0.1, 0.2, 0.1, 0.1];
        let x = [
            [0.0, 0.0, 0.9],
            [1.0, 0.0, 0.8],
            [3.0, 0.0, 0.6],
            [2.0, 0.0, 0.6],
            [9.0, 0.0, 0.4],
        ];
        let t = mean_top(&x, &r, 0.25);
        assert!((t.height - 0.9).abs() < 1e-15, "{}", t.height);
        assert!((t.highest - 1.0).abs() < 1e-15, "{}", t.highest);
        assert_eq!(t.reach, 3.0);
    }
}
