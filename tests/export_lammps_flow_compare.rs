//! `dembound compare DECK` on a LAMMPS scene deck whose spheres leave
//! through an outlet (issue 32). LAMMPS has no mesh wall in `fix
//! wall/gran`, so the conical hopper of the LIGGGHTS comparison
//! (tests/export_liggghts_flow_compare.rs) cannot be exported (the fed
//! version of this silo is tests/export_lammps_inlet_compare.rs): the scene here is a
//! flat-bottomed silo that LAMMPS can hold: four plane side walls (`fix
//! wall/gran … xplane|yplane`), a floor of 60 fixed spheres (R = 1 mm,
//! 2.05 mm apart; frozen in the deck) with an orifice of the 21 sites
//! within 5 mm of the axis left out, 1000 glass spheres (R = 1 mm, Hertz
//! with Tsuji damping, e = 0.5, frictionless) falling from a loose random
//! packing above it, and an outlet box below the orifice. Exported, run
//! in LAMMPS, compared; the assertions read the comparison's JSON:
//! - the same state until collisions amplify the round-off: every
//!   compared row up to the last row with no contact at all is identical
//!   to 1e-9 (state, kinetic and potential energy); before any contact
//!   the spheres fall freely and both codes' kinetic energy is free
//!   fall's closed form N m (g t)² / 2; the runs do part later (a
//!   divergence with a positive growth rate: chaos, not a bug);
//! - each code's rows hold exactly its 1000 spheres less those it
//!   discharged, at every row (a dump and a thermo column of each code),
//!   the discharged mass that count times m = ρ 4/3 π R³ to 1e-12;
//! - the discharge rate over 0.1–0.3 s: the two codes' means within 3
//!   combined standard errors of each other.
//!
//! Skips (saying so on stderr) when `lmp` is not on PATH, except under CI
//! (tests/common/peer.rs). Measured: 19 s of LAMMPS wall clock and 6 s
//! of compare on a shared 2-core machine.

mod common;

use common::peer::{export_lammps, missing, run_lmp};
use common::silo::{assert_windows_agree, silo_scene, G, R, RHO};
use common::{dembound, numbers, quantity};
use serde_json::Value;
use std::f64::consts::PI;

const N: f64 = 1000.0;
/// The late window's start, s: the first spheres reach the outlet at
/// ~0.05 s, the discharge is under way before 0.1 s.
const WINDOW_FROM: f64 = 0.1;

fn scene() -> String {
    silo_scene(N, 0.068, "", 75_000, 500)
}

#[test]
fn a_draining_silo_is_the_same_state_until_contacts_and_discharges_alike() {
    if missing("lmp", "lammps", "the LAMMPS flow comparison") {
        return;
    }
    let root = tempfile::tempdir().expect("a temporary directory");
    let path = root.path().join("silo.toml");
    std::fs::write(&path, scene()).expect("written");
    let deck = root.path().join("deck");
    export_lammps(&path, &[] as &[&str], &deck, "the silo");
    run_lmp(&deck, "the silo");
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
    assert_eq!(report["free_spheres"].as_f64(), Some(N));

    // Identical until contacts: the last row at which neither code has a
    // contact (the floor is 1 mm below the lowest free sphere's surface,
    // so the first rows are free flight).
    let contacts = quantity(&report, "contacts (overlaps)");
    let time = numbers(&contacts["time"]);
    let (cc, cd) = (numbers(&contacts["code"]), numbers(&contacts["dembound"]));
    let free_rows = (0..time.len())
        .take_while(|&k| cc[k] == 0.0 && cd[k] == 0.0)
        .count();
    assert!(
        free_rows >= 3,
        "the rows before the first contact: {free_rows}"
    );
    let t_free = time[free_rows - 1];
    // Free fall: velocity Verlet's v = n g Δt is exact but for the
    // rounding of n additions (n ≤ 3500 here: a relative 1e-12), squared
    // in the energy: 1e-11 bounds it.
    let m = RHO * 4.0 / 3.0 * PI * R.powi(3);
    let ke = quantity(&report, "kinetic energy");
    for (side, key) in [("LAMMPS", "code"), ("dembound", "dembound")] {
        let e = numbers(&ke[key]);
        for k in 0..free_rows {
            let want = N * 0.5 * m * (G * time[k]).powi(2);
            assert!(
                (e[k] - want).abs() <= 1e-11 * want.max(f64::MIN_POSITIVE),
                "{side}: kinetic energy {} J at t = {} s, free fall {want} J",
                e[k],
                time[k]
            );
        }
    }
    // The same state to 1e-9 (agreement.rs IDENTICAL) at least as long as
    // nothing touches: without a contact both codes integrate the same
    // free fall, the round-off ~1e-16 per step stays far below it. The
    // runs part later (collisions amplify the round-off): a divergence,
    // growing.
    for name in [
        "state: max |Δx| / R_min",
        "kinetic energy",
        "potential energy",
    ] {
        let d = &quantity(&report, name)["divergence"];
        let until = d["identical_until"].as_f64().unwrap_or(-1.0);
        assert!(
            until >= t_free,
            "{name}: identical until {until} s, no contact until {t_free} s"
        );
    }
    let state = &quantity(&report, "state: max |Δx| / R_min")["divergence"];
    assert!(state["diverged_at"].as_f64().is_some(), "{state}");
    assert!(
        state["growth_rate"].as_f64().is_some_and(|l| l > 0.0),
        "{state}"
    );

    // Counts at every row, each code against itself (a dump and a thermo
    // column): no sphere is lost or made; the mass is the count's, a sum
    // of equal masses (that many roundings: 1e-12).
    let present = quantity(&report, "free spheres in the domain");
    let gone = quantity(&report, "spheres discharged");
    let gone_mass = quantity(&report, "mass discharged");
    for (side, key) in [("LAMMPS", "code"), ("dembound", "dembound")] {
        let (p, n, mass) = (
            numbers(&present[key]),
            numbers(&gone[key]),
            numbers(&gone_mass[key]),
        );
        for k in 0..p.len() {
            assert_eq!(p[k] + n[k], N, "{side}: row {k}");
            assert!(
                (mass[k] - n[k] * m).abs() <= 1e-12 * n[k] * m,
                "{side}: row {k}: {} kg discharged for {} spheres",
                mass[k],
                n[k]
            );
        }
        // Not vacuous: the silo discharges.
        assert!(
            n[n.len() - 1] > 300.0,
            "{side}: {} discharged",
            n[n.len() - 1]
        );
    }

    // The discharge rate over the window. The runs are two realisations
    // of one flow (they parted at the first collisions): the difference
    // of their means is about normal with the combined standard error as
    // its deviation, so 3 of those bound it but for a 0.3 % chance. The
    // per-row rates (2 ms rows, ~45 spheres each) are nearly independent
    // and the batch means' error covers what is not. Each side's error
    // below a tenth of its rate: the window holds 100 rows.
    assert_windows_agree(&report, "discharge rate", 0.1);
}
