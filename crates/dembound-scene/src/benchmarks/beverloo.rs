//! Silo discharge: the steady mass flow rate through a circular orifice in
//! a flat floor against the orifice diameter D, fitted by Beverloo's law
//! (Beverloo, Leniger & van de Velde 1961, Chem. Eng. Sci. 15, 260–269):
//!
//! W = C ρ_b √g (D − k d)^{5/2},
//!
//! W the steady mass flow rate (kg/s), ρ_b the bulk density of the bed,
//! d the grain diameter, C and k empirical constants. W^{2/5} is linear in
//! D: the least-squares line's slope s and intercept b give
//! C = s^{5/2}/(ρ_b √g) and k = −b/(s d).
//!
//! The silo is the one of `examples/scenes/make_silo.py` (docs/beverloo.md):
//! a tube on a flat floor (a triangulated annulus) with a central orifice,
//! a gate plane under the orifice that vanishes at t = 0.1 s (the spheres
//! settle onto it first), an outlet box below that removes what fell
//! through. The rate is the least-squares slope of the removed mass against
//! time over the steady window, its standard error the scatter of four
//! sub-windows' slopes over √4. ρ_b is measured in the settled bed at the
//! opening (the spheres whose centres lie in a core cylinder above the
//! floor).

use super::granular::{advance, Grains, Rng, G};
use super::{Band, Check, Curve, Outcome, Plot, Style};
use crate::setup::{Cylinder, DomainSetup, NamedMaterial, Plane, TimeStep, WallSetup};
use crate::walls::gate::ActiveWindow;
use crate::walls::mesh::{Mesh, Transform, Triangle};
use crate::{SceneError, Simulation};
use dembound_physics::material::Material;
use std::f64::consts::PI;
use std::path::Path;

pub(super) const TITLE: &str = "Silo discharge through a circular orifice (Beverloo's law)";

pub(super) const SOURCE: &str = "Beverloo, Leniger & van de Velde (1961), Chem. Eng. Sci. 15, \
     260–269; ranges as summarised by Nedderman (1992), Statics and Kinematics of Granular \
     Materials, Cambridge University Press";

/// Published range of C (Nedderman 1992's summary of Beverloo's law).
const C_RANGE: (f64, f64) = (0.55, 0.65);
/// Published range of k (the same; it depends on grain shape).
const K_RANGE: (f64, f64) = (1.3, 2.9);

/// The fit of the study with the full silo (docs/beverloo.md, C = 0.479
/// ± 0.043, k = 1.24 ± 0.20): the quick test holds its rates to a band
/// about it. The full benchmark run (docs/benchmarks/) fits C = 0.528 ±
/// 0.030, k = 1.46 ± 0.11 to rates within 6 % of the study's: C and k
/// are strongly correlated over D/d = 5–8, and either pair gives the
/// rates (each full-run rate is within 4 % of this one's law).
pub const FULL_FIT_C: f64 = 0.479;
pub const FULL_FIT_K: f64 = 1.24;

/// One silo study.
struct Silo {
    grains: Grains,
    /// Tube radius, m.
    tube_radius: f64,
    /// Centre height of the top layer of the loose fill, m.
    fill_height: f64,
    /// Fill lattice spacing, m.
    spacing: f64,
    /// Orifice diameters, m.
    orifices: Vec<f64>,
    /// The gate vanishes at this time, s.
    gate: f64,
    /// The run ends at this time, s.
    end: f64,
    /// The steady window starts at this time, s.
    window: f64,
    /// The removed mass is sampled every this, s.
    sample: f64,
    /// ρ_b is measured in r < core_radius, core_z.0 < z < core_z.1, m.
    core_radius: f64,
    core_z: (f64, f64),
}

fn silo(quick: bool) -> Silo {
    let grains = Grains {
        radius: 1.0e-3,
        spread: 0.1,
        material: Material {
            density: 2500.0,
            youngs_modulus: 5.0e6,
            poisson_ratio: 0.3,
        },
        friction: 0.5,
        rolling_friction: 0.0,
        restitution: 0.5,
    };
    if quick {
        // 1,173 spheres in a 12 mm tube, two orifices, a short window:
        // seconds. The tube is only 2 D at the larger orifice.
        Silo {
            grains,
            tube_radius: 12.0e-3,
            fill_height: 40.0e-3,
            spacing: 2.3e-3,
            orifices: vec![10.0e-3, 12.0e-3],
            gate: 0.1,
            end: 0.25,
            window: 0.17,
            sample: 5.0e-3,
            core_radius: 9.0e-3,
            core_z: (5.0e-3, 20.0e-3),
        }
    } else {
        // The study's silo (docs/beverloo.md): 18 mm tube, ~6,200
        // spheres, D/d = 5–8.
        Silo {
            grains,
            tube_radius: 18.0e-3,
            fill_height: 80.0e-3,
            spacing: 2.3e-3,
            orifices: vec![10.0e-3, 12.0e-3, 14.0e-3, 16.0e-3],
            gate: 0.1,
            end: 0.45,
            window: 0.2,
            sample: 5.0e-3,
            core_radius: 15.0e-3,
            core_z: (5.0e-3, 25.0e-3),
        }
    }
}

/// The floor: the annulus D/2 ≤ r ≤ `outer` at z = 0, 2 × 64 triangles
/// (make_silo.py's), normal +z.
fn floor(orifice_radius: f64, outer: f64) -> Vec<Triangle> {
    let n = 64;
    let at = |r: f64, k: usize| {
        let a = 2.0 * PI * k as f64 / n as f64;
        [r * a.cos(), r * a.sin(), 0.0]
    };
    (0..n)
        .flat_map(|k| {
            let (p0, p1) = (at(orifice_radius, k), at(orifice_radius, k + 1));
            let (q0, q1) = (at(outer, k), at(outer, k + 1));
            [[p0, q0, q1], [p0, q1, p1]]
        })
        .collect()
}

/// One discharge: ρ_b at the opening (kg/m³), the removed mass against
/// time ((s, kg) from the opening on), the sphere count, and the bulk
/// densities of the flowing bed (means over the steady window's samples).
struct Discharge {
    bulk_density: f64,
    removed: Vec<(f64, f64)>,
    spheres: usize,
    /// The core of `bulk_density` while it flows (kg/m³).
    flowing_core_density: f64,
    /// The cylinder r < D/2, 0 < z < D/2 just above the orifice, where the
    /// grains accelerate towards it (kg/m³).
    orifice_density: f64,
}

/// The mass of the spheres whose centres lie in r < `radius`, `z.0` < z <
/// `z.1`, over that cylinder's volume (kg/m³): the mean density of a
/// homogeneous bed, whatever the spheres' size (a centre falls in the
/// cylinder with the probability of its volume share).
fn density_in_cylinder(
    positions: &[[f64; 3]],
    radii: &[f64],
    material: &Material,
    radius: f64,
    z: (f64, f64),
) -> f64 {
    let mass: f64 = radii
        .iter()
        .zip(positions)
        .filter(|(_, x)| x[0].hypot(x[1]) < radius && x[2] > z.0 && x[2] < z.1)
        .map(|(&r, _)| material.sphere_mass(r))
        .sum();
    mass / (PI * radius * radius * (z.1 - z.0))
}

fn discharge(p: &Silo, orifice: f64, progress: &dyn Fn(&str)) -> Result<Discharge, SceneError> {
    let g = &p.grains;
    let half = p.tube_radius + 12.0e-3;
    let domain = DomainSetup {
        lower: [-half, -half, -0.04],
        upper: [half, half, p.fill_height + 10.0e-3],
        periodic: [false; 3],
    };
    let mut s = g.scene(domain, 0.5, 15.0);
    // Δt = 2e-5 s, as the study's scene (0.18 of the smallest sphere's
    // Rayleigh time, 1/15 of the Hertz contact time at 0.5 m/s).
    s.integration.time_step = TimeStep::Fixed(2.0e-5);
    s.materials.push(NamedMaterial {
        name: "steel".into(),
        material: Material {
            density: 7800.0,
            ..g.material
        },
    });
    if let Some(f) = s.friction.as_mut() {
        // No tangential dashpot: the study's scene, exported to LIGGGHTS
        // exactly.
        f.tangential_damping = false;
    }
    // The fill: a jittered cubic lattice wholly inside the tube (the
    // study's; a SplitMix64 stream instead of Python's generator, so
    // another packing of the same statistics).
    let mut rng = Rng(1);
    let rmax = g.max_radius();
    let n = (p.tube_radius / p.spacing) as i64 + 1;
    let jitter = 0.5 * (p.spacing - 2.0 * rmax);
    let mut z = rmax + 0.2e-3;
    while z <= p.fill_height {
        for i in -n..=n {
            for j in -n..=n {
                let sphere = g.sphere([0.0; 3], &mut rng);
                let x = i as f64 * p.spacing + jitter * rng.symmetric();
                let y = j as f64 * p.spacing + jitter * rng.symmetric();
                if x.hypot(y) + rmax + 0.1e-3 < p.tube_radius {
                    s.spheres.push(crate::setup::SphereInit {
                        position: [x, y, z],
                        ..sphere
                    });
                }
            }
        }
        z += p.spacing;
    }
    let spheres = s.spheres.len();
    // Walls: the tube, the floor with its orifice, the gate (until
    // p.gate), a catch plane at the domain's bottom.
    s.walls.push(WallSetup::Cylinder(Cylinder {
        point: [0.0; 3],
        axis: [0.0, 0.0, 1.0],
        radius: p.tube_radius,
        inside: true,
        length: None,
        material: 1,
    }));
    s.walls.push(WallSetup::Mesh(Mesh::from_triangles(
        Path::new("silo_floor.stl"),
        &floor(0.5 * orifice, p.tube_radius + 2.0e-3),
        Transform::default(),
        1,
    )?));
    s.walls.push(WallSetup::Plane(Plane {
        point: [0.0; 3],
        normal: [0.0, 0.0, 1.0],
        material: 1,
    }));
    s.walls.push(WallSetup::Plane(Plane {
        point: [0.0, 0.0, -0.04],
        normal: [0.0, 0.0, 1.0],
        material: 1,
    }));
    s.wall_active = vec![
        None,
        None,
        Some(ActiveWindow {
            from: 0.0,
            to: p.gate,
        }),
        None,
    ];
    // The outlet: centres 20–40 mm below the floor.
    s.outlets.push(crate::region::Region::Box {
        lower: [-half, -half, -0.04],
        upper: [half, half, -0.02],
    });
    let mut sim = Simulation::new(s, 1)?;
    let mm = orifice * 1e3;
    advance(
        &mut sim,
        p.gate,
        &format!("D = {mm} mm: settling"),
        progress,
    )?;
    let bulk_density = density_in_cylinder(
        &sim.positions(),
        &sim.radii(),
        &g.material,
        p.core_radius,
        p.core_z,
    );
    let per = (p.sample / sim.dt()).round().max(1.0) as u64;
    let samples = ((p.end - p.gate) / p.sample).round() as usize;
    let mut removed = Vec::with_capacity(samples + 1);
    removed.push((sim.time(), 0.0));
    let (mut core, mut at_orifice, mut in_window) = (0.0, 0.0, 0usize);
    for k in 0..samples {
        sim.step_checked(per)?;
        removed.push((sim.time(), sim.removed().map_or(0.0, |r| r.mass)));
        if sim.time() >= p.window - 1e-12 {
            let (x, r) = (sim.positions(), sim.radii());
            core += density_in_cylinder(&x, &r, &g.material, p.core_radius, p.core_z);
            at_orifice +=
                density_in_cylinder(&x, &r, &g.material, 0.5 * orifice, (0.0, 0.5 * orifice));
            in_window += 1;
        }
        if (k + 1) % (samples / 4).max(1) == 0 && k + 1 < samples {
            progress(&format!(
                "D = {mm} mm: discharging, t = {:.3} s",
                sim.time()
            ));
        }
    }
    let in_window = in_window.max(1) as f64;
    Ok(Discharge {
        bulk_density,
        removed,
        spheres,
        flowing_core_density: core / in_window,
        orifice_density: at_orifice / in_window,
    })
}

/// The least-squares slope of y against x.
fn slope(pts: &[(f64, f64)]) -> f64 {
    let n = pts.len() as f64;
    let (mx, my) = pts
        .iter()
        .fold((0.0, 0.0), |(a, b), (x, y)| (a + x / n, b + y / n));
    let sxy: f64 = pts.iter().map(|(x, y)| (x - mx) * (y - my)).sum();
    let sxx: f64 = pts.iter().map(|(x, _)| (x - mx) * (x - mx)).sum();
    sxy / sxx
}

/// The steady rate (kg/s) over t ≥ `from` and its standard error (the
/// scatter of four sub-windows' slopes over √4), as the study's script.
fn steady_rate(series: &[(f64, f64)], from: f64) -> (f64, f64) {
    let pts: Vec<(f64, f64)> = series
        .iter()
        .copied()
        .filter(|(t, _)| *t >= from - 1e-12)
        .collect();
    let whole = slope(&pts);
    let q = pts.len() / 4;
    let parts: Vec<f64> = (0..4)
        .map(|k| slope(&pts[k * q..((k + 1) * q + 1).min(pts.len())]))
        .collect();
    let mean = parts.iter().sum::<f64>() / 4.0;
    let var = parts.iter().map(|p| (p - mean).powi(2)).sum::<f64>() / 3.0;
    (whole, var.sqrt() / 2.0)
}

/// (C, k) of Beverloo's law through the points (D m, W kg/s): the line
/// through (D, W^{2/5}).
fn fit(ds: &[f64], ws: &[f64], rho_b: f64, d: f64) -> (f64, f64) {
    let pts: Vec<(f64, f64)> = ds.iter().zip(ws).map(|(&x, &w)| (x, w.powf(0.4))).collect();
    let s = slope(&pts);
    let n = pts.len() as f64;
    let b = pts.iter().map(|p| p.1).sum::<f64>() / n - s * pts.iter().map(|p| p.0).sum::<f64>() / n;
    (s.powf(2.5) / (rho_b * G.sqrt()), -b / (s * d))
}

/// C of Beverloo's law with k fixed: the least-squares fit of W (not of
/// W^{2/5}) by C × (the law at C = 1), as scripts/beverloo_study.py.
fn fit_c_at_k(ds: &[f64], ws: &[f64], k: f64, rho_b: f64, d: f64) -> f64 {
    let unit: Vec<f64> = ds.iter().map(|&x| beverloo(x, 1.0, k, rho_b, d)).collect();
    let wf: f64 = ws.iter().zip(&unit).map(|(w, f)| w * f).sum();
    let ff: f64 = unit.iter().map(|f| f * f).sum();
    wf / ff
}

/// Beverloo's W (kg/s).
pub fn beverloo(d_orifice: f64, c: f64, k: f64, rho_b: f64, d: f64) -> f64 {
    c * rho_b * G.sqrt() * (d_orifice - k * d).max(0.0).powf(2.5)
}

/// The spread (standard deviations) of (C, k) over refits of the rates
/// drawn within their standard errors (2000 Gaussian draws, Box–Muller).
fn fit_spread(ds: &[f64], ws: &[f64], es: &[f64], rho_b: f64, d: f64) -> (f64, f64) {
    let mut rng = Rng(7);
    let mut gauss = || {
        let u = rng.next_f64().max(1e-300);
        let v = rng.next_f64();
        (-2.0 * u.ln()).sqrt() * (2.0 * PI * v).cos()
    };
    let draws: Vec<(f64, f64)> = (0..2000)
        .map(|_| {
            let w: Vec<f64> = ws
                .iter()
                .zip(es)
                .map(|(w, e)| (w + e * gauss()).max(1e-9))
                .collect();
            fit(ds, &w, rho_b, d)
        })
        .collect();
    let sd = |f: &dyn Fn(&(f64, f64)) -> f64| {
        let m = draws.iter().map(f).sum::<f64>() / draws.len() as f64;
        (draws.iter().map(|x| (f(x) - m).powi(2)).sum::<f64>() / (draws.len() - 1) as f64).sqrt()
    };
    (sd(&|x| x.0), sd(&|x| x.1))
}

pub(super) fn run(quick: bool, progress: &dyn Fn(&str)) -> Result<Outcome, SceneError> {
    let p = silo(quick);
    let d = 2.0 * p.grains.radius;
    let mut runs = Vec::new();
    for &orifice in &p.orifices {
        runs.push(discharge(&p, orifice, progress)?);
    }
    let rates: Vec<(f64, f64)> = runs
        .iter()
        .map(|r| steady_rate(&r.removed, p.window))
        .collect();
    let ws: Vec<f64> = rates.iter().map(|r| r.0).collect();
    let es: Vec<f64> = rates.iter().map(|r| r.1).collect();
    let rho_b = runs.iter().map(|r| r.bulk_density).sum::<f64>() / runs.len() as f64;
    let (c, k) = fit(&p.orifices, &ws, rho_b, d);
    let (sd_c, sd_k) = fit_spread(&p.orifices, &ws, &es, rho_b, d);
    // The candidates for a low C that the same runs measure (notes only;
    // the checks keep Beverloo's ρ_b, the bed's, and the whole window).
    let c_fixed_k = |k_fixed: f64| fit_c_at_k(&p.orifices, &ws, k_fixed, rho_b, d);
    let flowing = runs.iter().map(|r| r.flowing_core_density).sum::<f64>() / runs.len() as f64;
    let late_from = 0.5 * (p.window + p.end);
    let late: Vec<f64> = runs
        .iter()
        .map(|r| steady_rate(&r.removed, late_from).0)
        .collect();
    let (c_late, k_late) = fit(&p.orifices, &late, rho_b, d);

    let mut checks = Vec::new();
    let nedderman = "Nedderman (1992), summary of Beverloo's law";
    for (i, (&orifice, &(w, e))) in p.orifices.iter().zip(&rates).enumerate() {
        // Each rate against the full run's fit (the quick test's bound);
        // informative in the full run, where it is the fit itself.
        let reference = beverloo(orifice, FULL_FIT_C, FULL_FIT_K, rho_b, d);
        checks.push(Check::new(
            format!("W at D = {} mm (± {:.2} g/s)", orifice * 1e3, e * 1e3),
            "kg/s",
            w,
            reference,
            // The quick silo's tube is 2 D at the larger orifice, its
            // window 80 ms: ±40 % holds its rate near the law without
            // asking it to reproduce the full run (see tests/benchmarks.rs).
            Band::Relative(0.4),
            format!(
                "the full run's fit C = {FULL_FIT_C}, k = {FULL_FIT_K} (docs/beverloo.md), ρ_b measured"
            ),
        ));
        if i > 0 {
            checks.push(Check::new(
                format!(
                    "W({} mm) − W({} mm)",
                    orifice * 1e3,
                    p.orifices[i - 1] * 1e3
                ),
                "kg/s",
                w - ws[i - 1],
                0.0,
                Band::AtLeast,
                "Beverloo's law: W grows with D",
            ));
        }
    }
    if !quick {
        let mid = |r: (f64, f64)| 0.5 * (r.0 + r.1);
        checks.push(Check::new(
            format!("Beverloo C (± {sd_c:.3})"),
            "1",
            c,
            mid(C_RANGE),
            Band::Absolute(0.5 * (C_RANGE.1 - C_RANGE.0)),
            nedderman,
        ));
        checks.push(Check::new(
            format!("Beverloo k (± {sd_k:.2})"),
            "1",
            k,
            mid(K_RANGE),
            Band::Absolute(0.5 * (K_RANGE.1 - K_RANGE.0)),
            nedderman,
        ));
    }

    let mm = |x: f64| x * 1e3;
    let w25 = |w: f64| w.max(0.0).powf(0.4);
    let lo = p.orifices[0] * 0.8;
    let hi = p.orifices[p.orifices.len() - 1] * 1.1;
    let line = |c: f64, k: f64| -> Vec<(f64, f64)> {
        (0..=50)
            .map(|i| {
                let x = lo + (hi - lo) * i as f64 / 50.0;
                (mm(x), w25(beverloo(x, c, k, rho_b, d)))
            })
            .collect()
    };
    let fit_plot = Plot {
        stem: "beverloo_fit".into(),
        title: format!(
            "W^(2/5) against D: ρ_b = {rho_b:.0} kg/m³, d = {} mm",
            d * 1e3
        ),
        x_label: "orifice diameter D (mm)".into(),
        y_label: "W^(2/5) ((kg/s)^(2/5))".into(),
        curves: vec![
            Curve::new(
                "dembound",
                p.orifices
                    .iter()
                    .zip(&ws)
                    .map(|(&x, &w)| (mm(x), w25(w)))
                    .collect(),
                Style::OursPoints,
                0,
            ),
            Curve::new(
                format!("fit: C = {c:.3}, k = {k:.2}"),
                line(c, k),
                Style::ClosedForm,
                0,
            ),
            Curve::new(
                format!("published band edge: C = {}, k = {}", C_RANGE.0, K_RANGE.1),
                line(C_RANGE.0, K_RANGE.1),
                Style::Band,
                1,
            ),
            Curve::new(
                format!("published band edge: C = {}, k = {}", C_RANGE.1, K_RANGE.0),
                line(C_RANGE.1, K_RANGE.0),
                Style::Band,
                1,
            ),
        ],
    };
    let rate_plot = Plot {
        stem: "beverloo_rate".into(),
        title: format!(
            "discharged mass against time (gate opens at {} s; steady window from {} s)",
            p.gate, p.window
        ),
        x_label: "time t (s)".into(),
        y_label: "discharged mass (g)".into(),
        curves: runs
            .iter()
            .zip(&p.orifices)
            .enumerate()
            .map(|(i, (r, &o))| {
                Curve::new(
                    format!("D = {} mm", mm(o)),
                    r.removed.iter().map(|&(t, m)| (t, m * 1e3)).collect(),
                    Style::Ours,
                    i,
                )
            })
            .collect(),
    };

    let mut parameters = vec![
        p.grains.describe(),
        format!(
            "silo: a tube of radius {} mm on a flat floor (a 128-triangle annulus) with a central \
             orifice D; a gate plane under it until t = {} s; an outlet box 20–40 mm below the \
             floor; walls μ = {}, tangential dashpot off; Δt = 2e-5 s",
            p.tube_radius * 1e3,
            p.gate,
            p.grains.friction
        ),
        format!(
            "fill: {} spheres on a jittered cubic lattice (spacing {} mm) up to {} mm, settled onto \
             the gate",
            runs.first().map_or(0, |r| r.spheres),
            p.spacing * 1e3,
            p.fill_height * 1e3
        ),
        format!(
            "orifices D = {} mm (D/d = {}); steady rate: slope of the discharged mass over {}–{} s",
            p.orifices.iter().map(|&o| format!("{}", mm(o))).collect::<Vec<_>>().join(", "),
            p.orifices.iter().map(|&o| format!("{}", o / d)).collect::<Vec<_>>().join(", "),
            p.window,
            p.end
        ),
        format!(
            "ρ_b = {rho_b:.0} kg/m³ (solid fraction {:.3}): the settled bed at the opening, \
             r < {} mm, {}–{} mm above the floor",
            rho_b / p.grains.material.density,
            p.core_radius * 1e3,
            p.core_z.0 * 1e3,
            p.core_z.1 * 1e3
        ),
    ];
    for (&o, &(w, e)) in p.orifices.iter().zip(&rates) {
        parameters.push(format!(
            "D = {} mm: W = {:.2} ± {:.2} g/s (Beverloo with C = 0.58, k = 1.5: {:.2} g/s)",
            mm(o),
            w * 1e3,
            e * 1e3,
            beverloo(o, 0.58, 1.5, rho_b, d) * 1e3
        ));
    }
    let mut notes = vec![
        format!(
            "fit: C = {c:.3} ± {sd_c:.3}, k = {k:.2} ± {sd_k:.2} (± the spread of refits of the \
             rates drawn within their standard errors); C and k are strongly correlated over \
             D/d = 5–8 (a lower k goes with a lower C)"
        ),
        "published: Beverloo et al. (1961) fitted C ≈ 0.58 and k ≈ 1.5 as commonly quoted; \
         Nedderman (1992) summarises C ≈ 0.55–0.65 and k ≈ 1.3–2.9 depending on grain shape. \
         Neither text could be re-read for this benchmark: the numbers are as secondary sources \
         quote them"
            .into(),
        format!(
            "the fit with k fixed (Beverloo et al.'s k ≈ 1.4–1.5 as commonly quoted): C = {:.3} \
             at k = 1.4, {:.3} at k = 1.5 (least squares in W)",
            c_fixed_k(1.4),
            c_fixed_k(1.5)
        ),
        format!(
            "the window: the later half alone ({late_from:.3}–{} s) gives W = {} g/s, C = \
             {c_late:.3}, k = {k_late:.2} (the whole window: C = {c:.3}, k = {k:.2})",
            p.end,
            late.iter()
                .map(|w| format!("{:.2}", w * 1e3))
                .collect::<Vec<_>>()
                .join(", ")
        ),
        format!(
            "the bulk density: the same core while it flows (the window's samples every {} ms) \
             holds {flowing:.0} kg/m³ ({:+.1} % against the settled bed's {rho_b:.0}), which \
             would make C = {:.3}; just above the orifice (r < D/2, 0 < z < D/2) the flowing \
             grains hold {} kg/m³ (D = {} mm). Beverloo's ρ_b is the bed's bulk density, not the \
             flowing one: the checks keep the settled bed's",
            p.sample * 1e3,
            100.0 * (flowing / rho_b - 1.0),
            c * rho_b / flowing,
            runs.iter()
                .map(|r| format!("{:.0}", r.orifice_density))
                .collect::<Vec<_>>()
                .join(", "),
            p.orifices
                .iter()
                .map(|&o| format!("{}", mm(o)))
                .collect::<Vec<_>>()
                .join(", ")
        ),
    ];
    if !quick {
        // The full silo's measured cause (the quick silo's bed is too
        // shallow for its flowing core to stand for the bed's density).
        notes.push(
            "why C falls below 0.55, measured (docs/beverloo.md, \"Why C is below 0.55–0.65\"): \
             the grains' friction. The study's silo (another fill) with μ = 0.3 instead of 0.5 on \
             grains and walls, one run per orifice: W = 10.59, 20.33, 33.70, 50.18 g/s against \
             10.82, 18.75, 29.99, 46.48 (+8 to +12 % from D = 12 mm on), the bed 2.4 % denser \
             (ρ_b = 1465 against 1431 kg/m³), and C = 0.574 ± 0.042, k = 1.51 ± 0.16 (C = 0.571 \
             at k = 1.5 fixed, against 0.537 at μ = 0.5): Beverloo's C ≈ 0.58, k ≈ 1.5. Not a bug: \
             LIGGGHTS with the same contact law gives the same rates (D = 10 mm, 17 fills: \
             −0.3 % ± 1.7 %). The window, k fixed at 1.4–1.5 and the flowing bed's density (notes \
             above) move C by less than the gap; the published range is for the materials \
             Beverloo et al. measured, whose friction is not these spheres'"
                .into(),
        );
    }
    Ok(Outcome {
        name: "beverloo",
        title: TITLE,
        source: SOURCE,
        parameters,
        notes,
        checks,
        plots: vec![fit_plot, rate_plot],
        seconds: 0.0,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_fit_recovers_c_and_k_of_exact_rates() {
        // Rates from the law itself: the fit must return its C and k to
        // round-off (the line through W^{2/5} is exact).
        let (rho, d) = (1430.0, 2.0e-3);
        let ds = [10.0e-3, 12.0e-3, 14.0e-3, 16.0e-3];
        let ws: Vec<f64> = ds.iter().map(|&x| beverloo(x, 0.58, 1.5, rho, d)).collect();
        let (c, k) = fit(&ds, &ws, rho, d);
        assert!(
            (c - 0.58).abs() < 1e-12 && (k - 1.5).abs() < 1e-10,
            "{c} {k}"
        );
    }

    #[test]
    fn the_fit_at_fixed_k_recovers_c_of_exact_rates() {
        // Rates from the law at C = 0.58, k = 1.4: the fit with k = 1.4
        // must return 0.58 to round-off; at k = 1.5 it must return a
        // larger C (the same rates through a smaller effective orifice).
        let (rho, d) = (1437.0, 2.0e-3);
        let ds = [10.0e-3, 12.0e-3, 14.0e-3, 16.0e-3];
        let ws: Vec<f64> = ds.iter().map(|&x| beverloo(x, 0.58, 1.4, rho, d)).collect();
        let c = fit_c_at_k(&ds, &ws, 1.4, rho, d);
        assert!((c - 0.58).abs() < 1e-13, "{c}");
        assert!(fit_c_at_k(&ds, &ws, 1.5, rho, d) > 0.58);
    }

    #[test]
    fn the_density_in_a_cylinder_is_the_mass_of_the_centres_inside_over_its_volume() {
        // Two spheres with centres inside r < 2 mm, 0 < z < 3 mm, one
        // beyond its radius, one above it: (m(0.5 mm) + m(1 mm))/(π r² h).
        let m = Material {
            density: 2500.0,
            youngs_modulus: 5.0e6,
            poisson_ratio: 0.3,
        };
        let x = [
            [0.0, 0.0, 1.0e-3],
            [1.0e-3, 1.0e-3, 2.0e-3],
            [1.5e-3, 1.5e-3, 1.0e-3],
            [0.0, 0.0, 3.5e-3],
        ];
        let r = [0.5e-3, 1.0e-3, 1.0e-3, 1.0e-3];
        let rho = density_in_cylinder(&x, &r, &m, 2.0e-3, (0.0, 3.0e-3));
        let mass = |r: f64| 2500.0 * 4.0 / 3.0 * PI * r.powi(3);
        let expected = (mass(0.5e-3) + mass(1.0e-3)) / (PI * 4.0e-6 * 3.0e-3);
        assert!((rho / expected - 1.0).abs() < 1e-14, "{rho} {expected}");
    }

    #[test]
    fn the_steady_rate_of_a_line_is_its_slope_with_no_error() {
        let s: Vec<(f64, f64)> = (0..=40)
            .map(|i| (0.1 + 0.005 * i as f64, 0.02 * (0.005 * i as f64)))
            .collect();
        let (w, e) = steady_rate(&s, 0.15);
        assert!((w - 0.02).abs() < 1e-14 && e < 1e-14, "{w} {e}");
    }

    #[test]
    fn the_floor_is_an_annulus_of_the_orifice() {
        let t = floor(5.0e-3, 20.0e-3);
        assert_eq!(t.len(), 128);
        let rs: Vec<f64> = t.iter().flatten().map(|v| v[0].hypot(v[1])).collect();
        let min = rs.iter().cloned().fold(f64::INFINITY, f64::min);
        let max = rs.iter().cloned().fold(0.0, f64::max);
        assert!((min - 5.0e-3).abs() < 1e-15 && (max - 20.0e-3).abs() < 1e-15);
    }
}
