//! `dembound compare DECK` on a LIGGGHTS scene deck whose spheres come and
//! go (issue 32): the conical hopper of examples/scenes/hopper.stl fed by
//! an inlet above it, 5 spheres (R = 1 mm) every 625 steps of 4 µs (2000
//! spheres/s, 20.9 g/s: below what the 12 mm orifice passes, so nothing
//! piles up), an outlet box below the orifice. Exported, run in LIGGGHTS,
//! compared; the assertions read the comparison's JSON:
//! - the inserted counts of both codes equal the closed form 5 ·
//!   (⌊(s − 1)/625⌋ + 1) at every row (events at steps 1, 626, …): the
//!   count per event is whole, so the export's nudged `particlerate`
//!   makes LIGGGHTS insert exactly 5 each time (liggghts_inlets.rs); the
//!   inserted mass that count times m = ρ 4/3 π R³;
//! - each code's dump row holds exactly its inserted less its discharged
//!   spheres, at every row (the dump read by id against the log's or the
//!   engine's counts: two outputs of each code);
//! - the comparison by id ends at the first insertion, saying that the
//!   codes draw the inserted positions each from its own generator;
//! - the discharge rate over 0.2–0.4 s: the two codes' means within 3
//!   combined standard errors of each other, and each within 3 of its
//!   standard errors of the inflow (bars below).
//!
//! Skips (saying so on stderr) when `liggghts` is not on PATH, except
//! under CI (tests/common/peer.rs).

mod common;

use common::peer::{missing, run_liggghts};
use common::{dembound, numbers, quantity};
use serde_json::Value;
use std::f64::consts::PI;
use std::path::Path;

const DT: f64 = 4e-6;
const EVERY: u64 = 625;
const PER_EVENT: f64 = 5.0;
const R: f64 = 1e-3;
const RHO: f64 = 2500.0;
/// The late window's start, s: the first spheres leave at ~0.08 s (the
/// fall from the inlet to the outlet), the flow is steady well before.
const WINDOW_FROM: f64 = 0.2;

fn scene(hopper: &Path) -> String {
    format!(
        r#"
[domain]
lower = [-0.06, -0.06, -0.04]
upper = [0.06, 0.06, 0.095]
[[material]]
name = "glass"
density = {RHO:e}
youngs_modulus = 1.0e7
poisson_ratio = 0.3
[[material]]
name = "hopper"
density = 7800.0
youngs_modulus = 5.0e7
poisson_ratio = 0.3
[contact]
law = "hertz"
damping = "tsuji"
restitution = 0.5
[[wall]]
mesh = {{ file = "{}" }}
material = "hopper"
[[wall]]
plane = {{ point = [0.0, 0.0, -0.04], normal = [0.0, 0.0, 1.0] }}
material = "hopper"
[[inlet]]
region = {{ box = {{ lower = [-0.01, -0.01, 0.085], upper = [0.01, 0.01, 0.089] }} }}
rate = {{ number = 2000.0 }}
size = {{ fixed = {R:e} }}
material = "glass"
velocity = [0.0, 0.0, -1.0]
every = {EVERY}
seed = 5
[[outlet]]
region = {{ box = {{ lower = [-0.06, -0.06, -0.04], upper = [0.06, 0.06, -0.02] }} }}
[motion]
gravity = [0.0, 0.0, -9.81]
[integration]
scheme = "verlet"
dt = {DT:e}
steps = 100000
[output]
series_every = 500
"#,
        hopper.display()
    )
}

#[test]
fn a_fed_hopper_compares_counts_exactly_and_its_discharge_statistically() {
    if missing("liggghts", "liggghts", "the LIGGGHTS flow comparison") {
        return;
    }
    let hopper = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/scenes/hopper.stl");
    let root = tempfile::tempdir().expect("a temporary directory");
    let path = root.path().join("fed_hopper.toml");
    std::fs::write(&path, scene(&hopper)).expect("written");
    let deck = root.path().join("deck");
    run_liggghts(&path, &deck);
    let input = std::fs::read_to_string(deck.join("in.liggghts")).expect("the deck");
    // A whole count per event: no note of LIGGGHTS's random rounding.
    assert!(!input.contains("is not a whole"), "{input}");
    let log = std::fs::read_to_string(deck.join("log.liggghts")).expect("the log");
    assert!(!log.contains("Less insertions than requested"), "{log}");
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

    let inserted = quantity(&report, "spheres inserted");
    let time = numbers(&inserted["time"]);
    let m = RHO * 4.0 / 3.0 * PI * R.powi(3);
    for (side, key) in [("LIGGGHTS", "code"), ("dembound", "dembound")] {
        let count = numbers(&inserted[key]);
        let mass = numbers(&quantity(&report, "mass inserted")[key]);
        let present = numbers(&quantity(&report, "free spheres in the domain")[key]);
        let gone = numbers(&quantity(&report, "spheres discharged")[key]);
        for (k, t) in time.iter().enumerate() {
            let step = (t / DT).round() as u64;
            let events = if step == 0 { 0 } else { (step - 1) / EVERY + 1 };
            let want = PER_EVENT * events as f64;
            assert_eq!(count[k], want, "{side}: inserted at step {step}");
            // A sum of `want` equal masses: that many roundings, 1e-12.
            assert!(
                (mass[k] - want * m).abs() <= 1e-12 * want * m,
                "{side}: mass inserted at step {step}: {} kg, want {} kg",
                mass[k],
                want * m
            );
            assert_eq!(
                present[k],
                count[k] - gone[k],
                "{side}: spheres in the row of step {step} against the counts"
            );
        }
    }

    // The first row with spheres (step 500) ends the comparison by id.
    let end = &report["state_end"];
    assert_eq!(end["at"].as_f64(), Some(500.0 * DT), "{end}");
    assert_eq!(end["compared_until"].as_f64(), Some(0.0), "{end}");
    assert!(
        end["reason"]
            .as_str()
            .is_some_and(|r| r.contains("own random draw")),
        "{end}"
    );

    // The discharge rate over the window. The runs are two realisations of
    // one flow: the difference of their means is about normal with the
    // combined standard error as its deviation, so 3 of those bound it
    // but for a 0.3 % chance. Against the inflow Q (exact: 80 events of 5
    // in the window's 0.2 s): a code's mean rate is Q less the change of
    // the spheres held up over the window, over its length, a fluctuation
    // its batch-means error covers (conservatively: the hold-up is
    // bounded, its changes from block to block anticorrelated); bound 3.
    let rate = quantity(&report, "discharge rate");
    let (c, d) = (&rate["code_window"], &rate["dembound_window"]);
    let mean = |w: &Value| w["mean"].as_f64().expect("a window mean");
    let se = |w: &Value| w["standard_error"].as_f64().expect("a standard error");
    let combined = se(c).hypot(se(d));
    assert!(
        (mean(c) - mean(d)).abs() <= 3.0 * combined,
        "discharge rate: LIGGGHTS {} ± {} kg/s, dembound {} ± {} kg/s",
        mean(c),
        se(c),
        mean(d),
        se(d)
    );
    let q = PER_EVENT / (EVERY as f64 * DT) * m;
    for (side, w) in [("LIGGGHTS", c), ("dembound", d)] {
        assert!(
            (mean(w) - q).abs() <= 3.0 * se(w),
            "{side}: discharge rate {} ± {} kg/s, inflow {q} kg/s",
            mean(w),
            se(w)
        );
        // A standard error that is there at all (a rate that varies).
        assert!(se(w) > 0.0 && se(w) < 0.1 * q, "{side}: SE {}", se(w));
    }
}
