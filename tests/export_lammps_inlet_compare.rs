//! `dembound compare DECK` on a LAMMPS scene deck of a fed silo (issue 32:
//! inlets exported to LAMMPS, crates/dembound-export/src/lammps_inlets.rs).
//! The flat-bottomed silo of tests/export_lammps_flow_compare.rs (four
//! plane side walls 20 mm apart, a floor of 60 fixed spheres with the 21
//! sites within 5 mm of the axis left out as the orifice, an outlet box
//! below), holding 300 glass spheres (R = 1 mm, Hertz–Tsuji e = 0.5,
//! frictionless) at the start and fed from above by an inlet: a box 3 mm
//! tall at the top, 2500 spheres/s, events every 1000 steps (4 ms: 10
//! spheres per event, a whole number), thrown down at 1 m/s. Each event's
//! spheres have fallen ≥ 4 mm by the next (V0 · 4 ms), more than the
//! layer's 1 mm spread of centres plus the deck's guard 2R: nothing is in
//! the way of an insertion, so the deck creates exactly dembound's
//! spheres. Exported, run in LAMMPS, compared; the assertions read the
//! comparison's JSON and LAMMPS's log:
//! - inserted count and mass equal in both codes at every row, and equal
//!   to the closed form 10 × (events by then), 10 m each; LAMMPS skipped
//!   none;
//! - in each code at every row, spheres in the domain + discharged = 300
//!   + inserted, the discharged mass that count times m;
//! - the same state (1e-9) at least until the last row before the first
//!   contact (its time in closed form from the initial positions),
//!   inserted spheres included (they are created at dembound's places);
//! - over 0.1–0.3 s, the discharge rate and the hold-up (spheres in the
//!   domain) within 3 combined standard errors.
//!
//! Skips (saying so on stderr) when `lmp` is not on PATH, except under CI
//! (tests/common/peer.rs).

mod common;

use common::peer::{export_lammps, missing, run_lmp};
use common::silo::{assert_windows_agree, silo_scene, DT, G, R, RHO};
use common::{dembound, numbers, quantity};
use serde_json::Value;
use std::f64::consts::PI;

/// Spheres at the start.
const N0: f64 = 300.0;
/// Inlet: spheres/s, steps between events, spheres per event.
const RATE: f64 = 2500.0;
const EVERY: u64 = 1000;
const PER_EVENT: f64 = 10.0;
const STEPS: u64 = 75_000;
const SERIES: u64 = 500;
const WINDOW_FROM: f64 = 0.1;

fn scene() -> String {
    let inlet = format!(
        r#"[[inlet]]
region = {{ box = {{ lower = [-0.0095, -0.0095, 0.062], upper = [0.0095, 0.0095, 0.065] }} }}
rate = {{ number = {RATE:e} }}
size = {{ fixed = {R:e} }}
material = "glass"
velocity = [0.0, 0.0, -1.0]
every = {EVERY}
seed = 11
"#
    );
    silo_scene(N0, 0.025, &inlet, STEPS, SERIES)
}

#[test]
fn a_fed_silo_inserts_the_same_spheres_and_discharges_alike() {
    if missing("lmp", "lammps", "the LAMMPS inlet comparison") {
        return;
    }
    let root = tempfile::tempdir().expect("a temporary directory");
    let path = root.path().join("fed.toml");
    std::fs::write(&path, scene()).expect("written");
    let deck = root.path().join("deck");
    export_lammps(&path, &[] as &[&str], &deck, "the fed silo");
    run_lmp(&deck, "the fed silo");
    let log = std::fs::read_to_string(deck.join("log.lammps")).expect("the log");
    assert!(
        log.contains(" 0 skipped"),
        "LAMMPS skipped spheres: {}",
        log.lines()
            .filter(|l| l.contains("skipped"))
            .collect::<Vec<_>>()
            .join("\n")
    );
    let out = dembound()
        .arg("compare")
        .arg(&deck)
        .args(["--json", "--window-from", &WINDOW_FROM.to_string()])
        .output()
        .expect("dembound runs");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let report: Value = serde_json::from_slice(&out.stdout).expect("JSON");
    assert_eq!(report["code"], "LAMMPS");
    let m = RHO * 4.0 / 3.0 * PI * R.powi(3);

    // Inserted: the closed form in both codes at every row. Events at
    // steps 1, 1 + EVERY, …; rows at multiples of SERIES (never an event
    // step), so a row at step s has had ⌈s / EVERY⌉ events.
    let inserted = quantity(&report, "spheres inserted");
    let inserted_mass = quantity(&report, "mass inserted");
    let time = numbers(&inserted["time"]);
    assert_eq!(time.len() as u64, STEPS / SERIES + 1, "rows");
    for (side, key) in [("LAMMPS", "code"), ("dembound", "dembound")] {
        let (n, mass) = (numbers(&inserted[key]), numbers(&inserted_mass[key]));
        for k in 0..time.len() {
            let step = (time[k] / DT).round() as u64;
            let want = PER_EVENT * step.div_ceil(EVERY) as f64;
            assert_eq!(n[k], want, "{side}: inserted at step {step}");
            // A sum of that many equal masses (each ρ 4/3 π R³ in its
            // code's order of operations): 1e-12 relative bounds their
            // roundings (≤ 750 terms).
            assert!(
                (mass[k] - want * m).abs() <= 1e-12 * want * m,
                "{side}: {} kg inserted at step {step}, want {} kg",
                mass[k],
                want * m
            );
        }
    }

    // Conservation in each code at every row: the spheres in the domain
    // (a dump) plus those discharged (a thermo column) are the scene's
    // plus those inserted (a thermo column).
    let present = quantity(&report, "free spheres in the domain");
    let gone = quantity(&report, "spheres discharged");
    let gone_mass = quantity(&report, "mass discharged");
    for (side, key) in [("LAMMPS", "code"), ("dembound", "dembound")] {
        let (p, n, i, mass) = (
            numbers(&present[key]),
            numbers(&gone[key]),
            numbers(&inserted[key]),
            numbers(&gone_mass[key]),
        );
        for k in 0..p.len() {
            assert_eq!(p[k] + n[k], N0 + i[k], "{side}: row {k}");
            assert!(
                (mass[k] - n[k] * m).abs() <= 1e-12 * n[k] * m,
                "{side}: row {k}: {} kg discharged for {} spheres",
                mass[k],
                n[k]
            );
        }
        // Not vacuous: the silo discharges.
        assert!(n[n.len() - 1] > 200.0, "{side}: {} out", n[n.len() - 1]);
    }

    // The same state while nothing touches: inserted spheres stand where
    // dembound put them (the deck replays its draws) and fly the same.
    // The first contact, in closed form: the spheres at rest fall
    // together (no contact among them), the inserted ones are ≥ 35 mm
    // above them (≥ 30 ms at ≥ 1 m/s closing), so the first is a sphere
    // at rest meeting a floor sphere it lies over (horizontal distance
    // d < 2R): after falling z − √(4R² − d²), in √(2 · that / g).
    let data = std::fs::read_to_string(deck.join("particles.data")).expect("the data file");
    let atoms: Vec<Vec<f64>> = data
        .lines()
        .skip_while(|l| !l.starts_with("Atoms"))
        .skip(2)
        .take_while(|l| !l.trim().is_empty())
        .map(|l| {
            l.split_whitespace()
                .map(|w| w.parse().expect("a number"))
                .collect()
        })
        .collect();
    let (free, floor): (Vec<&Vec<f64>>, Vec<&Vec<f64>>) = atoms.iter().partition(|a| a[1] == 1.0);
    assert_eq!((free.len(), floor.len()), (300, 60));
    let mut t_first = f64::INFINITY;
    for a in &free {
        for b in &floor {
            let d = (a[4] - b[4]).hypot(a[5] - b[5]);
            if d < 2.0 * R {
                let fall = a[6] - b[6] - (4.0 * R * R - d * d).sqrt();
                t_first = t_first.min((2.0 * fall / G).sqrt());
            }
        }
    }
    let ctime = numbers(&quantity(&report, "contacts (overlaps)")["time"]);
    let t_free = ctime
        .iter()
        .copied()
        .filter(|&t| t < t_first)
        .fold(0.0, f64::max);
    eprintln!("first contact at {t_first} s; the last row before it at {t_free} s");
    assert!(t_free >= 0.01, "the first contact at {t_first} s");
    for name in [
        "state: max |Δx| / R_min",
        "kinetic energy",
        "potential energy",
    ] {
        let d = &quantity(&report, name)["divergence"];
        let until = d["identical_until"].as_f64().unwrap_or(-1.0);
        assert!(
            until >= t_free,
            "{name}: identical until {until} s, the first contact at {t_first} s"
        );
    }

    // Window means: two realisations of one flow (they parted at the
    // first collisions), so the difference of their means is about normal
    // with the combined standard error as its deviation; 3 of those bound
    // it but for a 0.3 % chance. The standard errors are compare's
    // (agreement.rs: batch means for the rate, the autocorrelation time
    // for the hold-up). Each side's error below a fifth of its mean.
    for name in ["discharge rate", "free spheres in the domain"] {
        assert_windows_agree(&report, name, 0.2);
    }
}
