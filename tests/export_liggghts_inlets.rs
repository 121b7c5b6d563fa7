//! `[[inlet]]` exported to LIGGGHTS 3.8 (issue 28): `fix
//! insert/rate/region` with one template per radius
//! (crates/dembound-export/src/liggghts_inlets.rs). Spheres poured into
//! free fall, each event one thin layer that has fallen clear of the
//! region before the next (no contact in either code: dembound's
//! `particle_contacts` stays 0):
//! - a fixed radius, 40 spheres per event: the inserted count at every
//!   thermo/series row equals the closed form in both codes, the mass
//!   to 1e-12, the kinetic energy of both codes equals the closed form of
//!   free fall, every LIGGGHTS sphere's velocity too and its start inside
//!   the region; the mean heights of the two codes within what random
//!   placement allows;
//! - a table of three radii at a mass rate, 16 spheres per event:
//!   LIGGGHTS inserts exactly 8, 4, 4 of them per event (its stratified
//!   split), so its mass per event is exact; dembound draws each radius,
//!   so its mass is within the spread of 16 draws per event;
//! - a cylinder not along an axis refused naming the key and LIGGGHTS.
//!
//! Skips (saying so on stderr) when `liggghts` is not on PATH, except
//! under CI (tests/common/peer.rs).

mod common;

use common::dembound;
use common::peer::missing;
use std::collections::HashMap;
use std::f64::consts::PI;
use std::path::Path;
use std::process::Command;

const RHO: f64 = 2500.0;
const G: f64 = 9.81;
const DT: f64 = 1e-5;
const EVERY: u64 = 500;
const STEPS: u64 = 5000;
/// The thermo and series cadence, steps.
const SERIES: u64 = 50;
/// Downward speed at insertion, m/s.
const V0: f64 = 1.0;
/// The region: x, y in [0, 50] mm, z from Z_LO to 0.5 m.
const SIDE: f64 = 0.05;
const Z_TOP: f64 = 0.5;

/// A scene of one inlet: `rate`, `size` (TOML), the region's bottom
/// `z_lo`, `end` (TOML line or empty). Each layer is ≥ V0 · EVERY · DT =
/// 5 mm below the next at its insertion, more than the layer's spread of
/// centres plus two radii (checked per test), and every earlier layer
/// falls faster: nothing ever touches.
fn scene(rate: &str, size: &str, z_lo: f64, end: &str) -> String {
    format!(
        r#"
[domain]
lower = [0.0, 0.0, 0.3]
upper = [{SIDE:e}, {SIDE:e}, {Z_TOP:e}]
[[material]]
name = "glass"
density = {RHO:e}
youngs_modulus = 1e7
poisson_ratio = 0.3
[contact]
law = "hertz"
[motion]
gravity = [0.0, 0.0, -{G:e}]
[integration]
scheme = "verlet"
dt = {DT:e}
steps = {STEPS}
skin = 2e-4
[output]
series_every = {SERIES}
[[inlet]]
region = {{ box = {{ lower = [0.0, 0.0, {z_lo:e}], upper = [{SIDE:e}, {SIDE:e}, {Z_TOP:e}] }} }}
rate = {rate}
size = {size}
material = "glass"
velocity = [0.0, 0.0, -{V0:e}]
every = {EVERY}
seed = 3
{end}
"#
    )
}

/// A LIGGGHTS sphere of the last dump frame: id, radius, position,
/// velocity (SI).
struct Sphere {
    id: u64,
    r: f64,
    x: [f64; 3],
    v: [f64; 3],
}

/// Exports `scene` to LIGGGHTS in `deck`, runs it; the thermo rows `step
/// time ke n m` and the last frame of particles.dump.
fn run_liggghts(scene: &Path, deck: &Path) -> (Vec<[f64; 5]>, Vec<Sphere>) {
    let o = dembound()
        .args(["export", "liggghts", "--out"])
        .arg(deck)
        .arg(scene)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let ran = Command::new("liggghts")
        .args(["-in", "in.liggghts", "-log", "log.liggghts"])
        .current_dir(deck)
        .output()
        .unwrap();
    let log = std::fs::read_to_string(deck.join("log.liggghts")).unwrap_or_default();
    assert!(ran.status.success(), "{log}");
    assert!(
        !log.contains("Less insertions than requested"),
        "LIGGGHTS could not place every sphere: {log}"
    );
    let rows = log
        .lines()
        .map(|l| l.split_whitespace().collect::<Vec<_>>())
        .filter(|w| w.len() == 5 && w.iter().all(|x| x.parse::<f64>().is_ok()))
        .map(|w| [0, 1, 2, 3, 4].map(|k| w[k].parse().unwrap()))
        .collect();
    let dump = std::fs::read_to_string(deck.join("particles.dump")).unwrap();
    let last = dump.rfind("ITEM: ATOMS").expect("a frame");
    let spheres = dump[last..]
        .lines()
        .skip(1)
        .map(|l| {
            let w: Vec<f64> = l.split_whitespace().map(|x| x.parse().unwrap()).collect();
            Sphere {
                id: w[0] as u64,
                r: w[2],
                x: [w[3], w[4], w[5]],
                v: [w[6], w[7], w[8]],
            }
        })
        .collect();
    (rows, spheres)
}

/// dembound's series.csv rows of `scene` as columns by name.
fn run_dembound(scene: &Path, out: &Path) -> HashMap<String, Vec<f64>> {
    let o = dembound()
        .arg("scene")
        .arg(scene)
        .arg("--out")
        .arg(out)
        .args(["--quiet", "--threads", "1"])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = std::fs::read_to_string(out.join("series.csv")).unwrap();
    let mut lines = text.lines();
    let names: Vec<String> = lines.next().unwrap().split(',').map(String::from).collect();
    let mut cols: HashMap<String, Vec<f64>> = names.iter().map(|n| (n.clone(), vec![])).collect();
    for l in lines {
        for (n, x) in names.iter().zip(l.split(',')) {
            cols.get_mut(n).unwrap().push(x.parse().unwrap());
        }
    }
    cols
}

/// The step of event e: 1 + e · EVERY (start = 0: the first step).
fn event_step(e: u64) -> u64 {
    1 + e * EVERY
}

/// Events done by the end of step `s`.
fn events_by(s: u64) -> u64 {
    if s == 0 {
        0
    } else {
        (s - 1) / EVERY + 1
    }
}

/// The downward speed at the end of step `s` of a sphere inserted at step
/// `e_step` at V0: velocity Verlet is exact under a constant force, and
/// both codes give V0 at the end of the insertion step.
fn speed(s: u64, e_step: u64) -> f64 {
    V0 + G * (s - e_step) as f64 * DT
}

/// A fixed radius at 8000 spheres/s: 40 per event (whole), events every
/// 5 ms until end = 0.04 s, 8 events, 320 spheres. Region 2.2 mm tall:
/// centres within 0.2 mm in height, a layer 5 mm below the next when it
/// comes (≥ 2R + 0.2 mm).
#[test]
fn a_fixed_radius_inserts_the_same_counts_mass_and_velocities() {
    if missing("liggghts", "liggghts", "the LIGGGHTS inlets") {
        return;
    }
    const R: f64 = 1e-3;
    const PER: u64 = 40;
    const EVENTS: u64 = 8;
    let z_lo = Z_TOP - 2.2e-3;
    let root = tempfile::tempdir().unwrap();
    let path = root.path().join("inlet.toml");
    std::fs::write(
        &path,
        scene(
            "{ number = 8000.0 }",
            &format!("{{ fixed = {R:e} }}"),
            z_lo,
            "end = 0.04",
        ),
    )
    .unwrap();
    let (rows, spheres) = run_liggghts(&path, &root.path().join("deck"));
    let dem = run_dembound(&path, &root.path().join("dem"));
    let m = RHO * 4.0 / 3.0 * PI * R.powi(3);
    let count = |s: u64| PER * events_by(s).min(EVENTS);
    // The closed-form kinetic energy at the end of step s.
    let ke = |s: u64| {
        (0..events_by(s).min(EVENTS))
            .map(|e| PER as f64 * 0.5 * m * speed(s, event_step(e)).powi(2))
            .sum::<f64>()
    };
    assert_eq!(rows.len() as u64, STEPS / SERIES + 1, "thermo rows");
    assert_eq!(dem["step"].len(), rows.len(), "series rows");
    for (i, row) in rows.iter().enumerate() {
        let s = row[0] as u64;
        assert_eq!(dem["step"][i] as u64, s);
        let n = count(s);
        assert_eq!(row[3] as u64, n, "LIGGGHTS count at step {s}");
        assert_eq!(
            dem["inlet0_inserted"][i] as u64, n,
            "dembound count at step {s}"
        );
        // A sum of n equal masses (each 4/3 π ρ R³ in its code's order):
        // n roundings, 1e-12 relative at most.
        let want = n as f64 * m;
        for (code, got) in [("LIGGGHTS", row[4]), ("dembound", dem["inlet0_mass_kg"][i])] {
            assert!(
                (got - want).abs() <= 1e-12 * want,
                "{code} mass at step {s}: {got} kg, want {want} kg"
            );
        }
        // Free fall from the same velocity: both codes' K equals the
        // closed form to the rounding of ≤ 5000 Verlet steps: two half
        // kicks a step, each rounding v by ≤ ε/2 relative, so |Δv|/v ≤
        // STEPS ε = 1.1e-12 and |ΔK|/K ≤ 2.2e-12; bound 1e-11.
        let k = ke(s);
        for (code, got) in [
            ("LIGGGHTS", row[2]),
            ("dembound", dem["kinetic_energy_J"][i]),
        ] {
            assert!(
                (got - k).abs() <= 1e-11 * k.max(1e-30),
                "{code} K at step {s}: {got} J, want {k} J"
            );
        }
        assert_eq!(dem["particle_contacts"][i], 0.0, "a contact at step {s}");
    }
    // Every LIGGGHTS sphere: ids in insertion order (40 per event); its
    // velocity the closed form, its start (z run back by the exact
    // Verlet free fall) inside the region shrunk by R.
    assert_eq!(spheres.len() as u64, PER * EVENTS);
    for sp in &spheres {
        let e_step = event_step((sp.id - 1) / PER);
        let t = (STEPS - e_step) as f64 * DT;
        let v = speed(STEPS, e_step);
        // STEPS ε relative (above), bound 1e-11.
        assert!(
            (sp.v[2] + v).abs() <= 1e-11 * v,
            "sphere {}: vz {}",
            sp.id,
            sp.v[2]
        );
        assert!(sp.v[0] == 0.0 && sp.v[1] == 0.0 && sp.r == R);
        let z0 = sp.x[2] + V0 * t + 0.5 * G * t * t;
        // 1e-12 m: the rounding of positions near 0.5 m over the steps.
        assert!(
            z0 >= z_lo + R - 1e-12 && z0 <= Z_TOP - R + 1e-12,
            "sphere {}: z0 {z0}",
            sp.id
        );
        assert!(sp.x[0] >= R && sp.x[0] <= SIDE - R && sp.x[1] >= R && sp.x[1] <= SIDE - R);
    }
    // Mean heights at the end: the same falls, so they differ by the
    // difference of the two codes' mean starting heights, each the mean
    // of N = 320 centres uniform over w = 0.2 mm (the region's height
    // less 2R): standard deviation w/√(12 N) per code. Bound: 5 standard
    // deviations of the difference, 5 √2 w/√(12 N) = 14 µm. dembound's
    // from its potential energy −Σ m g·x = m g Σ z.
    let n = (PER * EVENTS) as f64;
    let w = Z_TOP - z_lo - 2.0 * R;
    let bound = 5.0 * 2f64.sqrt() * w / (12.0 * n).sqrt();
    let lig = spheres.iter().map(|s| s.x[2]).sum::<f64>() / n;
    let pe = *dem["potential_energy_J"].last().unwrap();
    let dem_mean = pe / (n * m * G);
    assert!(
        (lig - dem_mean).abs() <= bound,
        "mean z: LIGGGHTS {lig} m, dembound {dem_mean} m, bound {bound} m"
    );
    // LIGGGHTS's mean x and y: the region's centre within 5 standard
    // deviations of a mean of N uniform over the 48 mm the centres span.
    let bound_xy = 5.0 * (SIDE - 2.0 * R) / (12.0 * n).sqrt();
    for a in 0..2 {
        let mean = spheres.iter().map(|s| s.x[a]).sum::<f64>() / n;
        assert!(
            (mean - 0.5 * SIDE).abs() <= bound_xy,
            "mean along axis {a}: {mean} m"
        );
    }
}

/// Three radii by number (0.8 mm: 1/2, 1.0 mm: 1/4, 1.2 mm: 1/4) at the
/// mass rate of 16 spheres per event (Q = 16 m̄ / (EVERY Δt)), to the
/// run's end: events at steps 1, 501, …, 4501, 160 spheres. The region
/// 2.6 mm tall: centres within 1.0 mm (small) to 0.2 mm (large) in
/// height; a layer 5 mm below the next (≥ 1.0 mm + 2 · 1.2 mm).
#[test]
fn a_size_table_inserts_the_mass_rate() {
    if missing("liggghts", "liggghts", "the LIGGGHTS inlets") {
        return;
    }
    const PER: u64 = 16;
    let table = [(0.8e-3, 0.5), (1.0e-3, 0.25), (1.2e-3, 0.25)];
    let mass = |r: f64| RHO * 4.0 / 3.0 * PI * r.powi(3);
    let mean_m: f64 = table.iter().map(|&(r, f)| f * mass(r)).sum();
    let var_m: f64 = table
        .iter()
        .map(|&(r, f)| f * (mass(r) - mean_m).powi(2))
        .sum();
    let q = PER as f64 * mean_m / (EVERY as f64 * DT);
    let root = tempfile::tempdir().unwrap();
    let path = root.path().join("table.toml");
    std::fs::write(
        &path,
        scene(
            &format!("{{ mass = {q:e} }}"),
            "{ table = [[0.8e-3, 0.5], [1.0e-3, 0.25], [1.2e-3, 0.25]] }",
            Z_TOP - 2.6e-3,
            "",
        ),
    )
    .unwrap();
    let (rows, spheres) = run_liggghts(&path, &root.path().join("deck"));
    let dem = run_dembound(&path, &root.path().join("dem"));
    // LIGGGHTS: an event of 16 takes floor(16 w_i) = 8, 4, 4 of the
    // templates and hands out nothing at random (randomize_list with
    // exact_number = 1), so each event's mass is 8 m(0.8) + 4 m(1.0) +
    // 4 m(1.2) = 16 m̄: a sum of 16 masses, 1e-12 relative per event.
    let per_event = 8.0 * mass(0.8e-3) + 4.0 * mass(1.0e-3) + 4.0 * mass(1.2e-3);
    for (i, row) in rows.iter().enumerate() {
        let s = row[0] as u64;
        let e = events_by(s) as f64;
        assert_eq!(row[3], PER as f64 * e, "LIGGGHTS count at step {s}");
        assert_eq!(
            dem["inlet0_inserted"][i],
            PER as f64 * e,
            "dembound count at step {s}"
        );
        assert!(
            (row[4] - e * per_event).abs() <= 1e-12 * e * per_event,
            "LIGGGHTS mass at step {s}: {} kg, want {} kg",
            row[4],
            e * per_event
        );
        assert_eq!(dem["particle_contacts"][i], 0.0, "a contact at step {s}");
    }
    let radii = |r: f64| spheres.iter().filter(|s| s.r == r).count();
    assert_eq!([radii(0.8e-3), radii(1.0e-3), radii(1.2e-3)], [80, 40, 40]);
    // dembound draws each radius by number: after E events (16 E draws)
    // its mass is 16 E m̄ give or take √(16 E Var m); bound 5 of those
    // (the run is seeded: a fixed draw, within it).
    let events = events_by(STEPS) as f64;
    let got = *dem["inlet0_mass_kg"].last().unwrap();
    let want = PER as f64 * events * mean_m;
    let sigma = (PER as f64 * events * var_m).sqrt();
    assert!(
        (got - want).abs() <= 5.0 * sigma,
        "dembound mass {got} kg, want {want} ± 5 × {sigma} kg"
    );
    // And the mass rate both codes meant: Q over the 10 intervals.
    assert!((rows.last().unwrap()[4] - q * events * EVERY as f64 * DT).abs() <= 1e-12 * want);
}

/// What LIGGGHTS cannot express is refused naming the key and the code,
/// exit 2, nothing written: an inlet cylinder whose axis is not along x,
/// y or z (`region cylinder` is axis-aligned).
#[test]
fn a_tilted_cylinder_is_refused_naming_the_key() {
    let text = scene("{ number = 8000.0 }", "{ fixed = 1e-3 }", 0.45, "");
    let text = text.replace(
        "region = { box = { lower = [0.0, 0.0, 4.5e-1], upper = [5e-2, 5e-2, 5e-1] } }",
        "region = { cylinder = { center = [0.025, 0.025, 0.47], axis = [0.0, 0.6, 0.8], \
         radius = 0.01, length = 0.02 } }",
    );
    assert!(text.contains("cylinder"), "{text}");
    let root = tempfile::tempdir().unwrap();
    let path = root.path().join("s.toml");
    std::fs::write(&path, &text).unwrap();
    let out = root.path().join("deck");
    let o = dembound()
        .args(["export", "liggghts", "--out"])
        .arg(&out)
        .arg(&path)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{stderr}");
    assert!(
        stderr.contains("inlet[0].region.cylinder.axis") && stderr.contains("LIGGGHTS"),
        "{stderr}"
    );
    assert!(!out.exists(), "a deck was written");
}
