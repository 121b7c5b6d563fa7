//! `[[outlet]]` exported to LIGGGHTS 3.8 and LAMMPS (issue 28): the decks
//! delete the spheres whose centres are in an outlet region every 100
//! steps (crates/dembound-export/src/outlets.rs) and report the count and
//! mass removed per outlet as thermo columns. Five spheres fall freely
//! into two outlet boxes: each code removes them at the first multiple
//! of 100 steps at or after the step its centre entered (closed form),
//! by outlet, with their mass; the thermo rows (at the series cadence,
//! every step) count each and the dump's rows leave it out from the step
//! its centre entered; dembound removes the same spheres.
//! Outlets refused by Yade, `domain.outside = "delete"`, tilted
//! cylinders and `[[inlet]]` (LAMMPS and Yade) refused naming the key and
//! the code.
//!
//! Skips (saying so on stderr) when a code is not on PATH, except under
//! CI (tests/common/peer.rs).

mod common;

use common::dembound;
use common::peer::missing;
use std::path::Path;
use std::process::Command;

const G: f64 = 9.81;
const R: f64 = 1e-3;
const RHO: f64 = 2500.0;
const DT: f64 = 1e-5;
const STEPS: u64 = 8000;
/// The outlets' top face, m.
const TOP: f64 = 0.005;
/// Drop heights of the centres above TOP, m: column A over outlet 0 (x <
/// 5 mm), column B over outlet 1; 5 mm or more apart, starting at rest:
/// they never touch.
const DROPS_A: [f64; 3] = [0.005, 0.010, 0.015];
const DROPS_B: [f64; 2] = [0.007, 0.0125];
/// The decks' removal cadence, steps (outlets.rs `EVERY`).
const EVERY: u64 = 100;

fn scene(outlet1: &str, extra: &str) -> String {
    let sphere = |x: f64, d: f64| {
        format!(
            "{{ position = [{x:e}, 5e-3, {:e}], radius = {R:e} }}",
            TOP + d
        )
    };
    let spheres: Vec<String> = DROPS_A
        .iter()
        .map(|&d| sphere(0.0025, d))
        .chain(DROPS_B.iter().map(|&d| sphere(0.0075, d)))
        .collect();
    format!(
        r#"
[domain]
lower = [0.0, 0.0, 0.0]
upper = [0.01, 0.01, 0.03]
{extra}
[[material]]
name = "g"
density = {RHO:e}
youngs_modulus = 1e7
poisson_ratio = 0.3

[[particles]]
material = "g"
spheres = [{}]

[[outlet]]
region = {{ box = {{ lower = [0.0, 0.0, 0.0], upper = [0.005, 0.01, {TOP:e}] }} }}

[[outlet]]
region = {outlet1}

[motion]
gravity = [0.0, 0.0, -{G:e}]

[integration]
scheme = "verlet"
dt = {DT:e}
steps = {STEPS}
skin = 2e-4

[output]
series_every = 1
"#,
        spheres.join(", ")
    )
}

/// Outlet 1 as a box, and as a z cylinder holding the same falling
/// spheres (axis x = 7.5 mm, y = 5 mm, radius 2 mm, z from 0 to TOP).
const BOX1: &str = "{ box = { lower = [0.005, 0.0, 0.0], upper = [0.01, 0.01, 0.005] } }";
const CYL1: &str = "{ cylinder = { center = [0.0075, 0.005, 0.0025], axis = [0.0, 0.0, 1.0], \
                    radius = 0.002, length = 0.005 } }";

/// The step a sphere dropped from `d` above TOP is removed at by a deck:
/// Verlet is exact for a constant acceleration from rest, z_n = z₀ − ½ g
/// (n Δt)², so the centre is in at the first n with ½ g (n Δt)² ≥ d, and
/// the deck deletes it at the next multiple of EVERY.
fn removal_step(d: f64) -> u64 {
    let mut n = 0u64;
    while 0.5 * G * (n as f64 * DT).powi(2) < d {
        n += 1;
    }
    n.div_ceil(EVERY) * EVERY
}

/// Exports `scene` to `code` in `deck` and runs it; the thermo rows
/// (every field a number, `fields` of them).
fn run_deck(code: &str, scene: &Path, deck: &Path, fields: usize) -> Vec<Vec<f64>> {
    let o = dembound()
        .args(["export", code, "--out"])
        .arg(deck)
        .arg(scene)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let (bin, input, log) = match code {
        "lammps" => ("lmp", "in.lammps", "log.lammps"),
        _ => ("liggghts", "in.liggghts", "log.liggghts"),
    };
    let ran = Command::new(bin)
        .args(["-in", input, "-log", log])
        .current_dir(deck)
        .output()
        .unwrap();
    assert!(
        ran.status.success(),
        "{code}: {}",
        String::from_utf8_lossy(&ran.stdout)
    );
    std::fs::read_to_string(deck.join(log))
        .unwrap()
        .lines()
        .map(|l| l.split_whitespace().collect::<Vec<_>>())
        .filter(|w| w.len() == fields && w.iter().all(|x| x.parse::<f64>().is_ok()))
        .map(|w| w.iter().map(|x| x.parse().unwrap()).collect())
        .collect()
}

/// The first step at which a sphere dropped from `d` above TOP has its
/// centre in the outlet (the region's surface included), by the closed
/// form of `removal_step`.
fn entry_step(d: f64) -> u64 {
    let mut n = 0u64;
    while 0.5 * G * (n as f64 * DT).powi(2) < d {
        n += 1;
    }
    n
}

/// The first step at which column `col` reaches `c` in `rows`.
fn first_step_with(rows: &[Vec<f64>], col: usize, c: f64) -> Option<u64> {
    rows.iter().find(|r| r[col] >= c).map(|r| r[0] as u64)
}

fn check(code: &str, outlet1: &str, fields: usize, first: usize) {
    let root = tempfile::tempdir().unwrap();
    let path = root.path().join("outlet.toml");
    std::fs::write(&path, scene(outlet1, "")).unwrap();
    let rows = run_deck(code, &path, &root.path().join("deck"), fields);
    let m = RHO * 4.0 / 3.0 * std::f64::consts::PI * R * R * R;
    let last = rows.last().expect("thermo rows");
    assert_eq!(last[0] as u64, STEPS);
    for (k, drops) in [&DROPS_A[..], &DROPS_B[..]].iter().enumerate() {
        let (n, mass) = (first + 2 * k, first + 2 * k + 1);
        assert_eq!(last[n], drops.len() as f64, "{code} outlet {k}");
        // A sum of equal masses, each LAMMPS's 4/3 π r³ ρ in its own
        // order: a few roundings, 1e-14 relative.
        let want = drops.len() as f64 * m;
        assert!(
            (last[mass] - want).abs() <= 1e-14 * want,
            "{code} outlet {k}: {} kg, want {want} kg",
            last[mass]
        );
        // The thermo rows are written at the series cadence (every step
        // here) and count a sphere from the step its centre enters (the
        // state a deletion at that row would leave); the rows at the
        // checks, the multiples of EVERY, count it from its deletion.
        let checks: Vec<Vec<f64>> = rows
            .iter()
            .filter(|r| (r[0] as u64).is_multiple_of(EVERY))
            .cloned()
            .collect();
        let mut entries: Vec<u64> = drops.iter().map(|&d| entry_step(d)).collect();
        entries.sort_unstable();
        for (c, &s) in entries.iter().enumerate() {
            assert_eq!(
                first_step_with(&rows, n, (c + 1) as f64),
                Some(s),
                "{code} outlet {k}: sphere {} counted from the wrong row",
                c + 1
            );
        }
        let mut steps: Vec<u64> = drops.iter().map(|&d| removal_step(d)).collect();
        steps.sort_unstable();
        for (c, &s) in steps.iter().enumerate() {
            assert_eq!(
                first_step_with(&checks, n, (c + 1) as f64),
                Some(s),
                "{code} outlet {k}: sphere {} removed at the wrong step",
                c + 1
            );
        }
    }
    // The dump (a row every step) is the state after the deletion: a
    // sphere leaves the rows at the step its centre enters an outlet, not
    // at the removal that follows (outlets.rs, "The rows are the state
    // after the deletion"). Ids 1, 2, 3 the column over outlet 0, 4 and 5
    // the other, in the scene file's order.
    let dump = std::fs::read_to_string(root.path().join("deck/particles.dump")).unwrap();
    let dumped = dembound_export::scene_dump::parse_dump(&dump).expect("the dump reads");
    assert_eq!(dumped.len() as u64, STEPS + 1, "{code}: a row every step");
    for (i, &d) in DROPS_A.iter().chain(&DROPS_B).enumerate() {
        let id = i as u64 + 1;
        let listed =
            |r: &dembound_export::scene_dump::DumpRow| r.spheres.iter().any(|s| s.id == id);
        let first_gone = dumped.iter().find(|r| !listed(r)).map(|r| r.step);
        assert_eq!(
            first_gone,
            Some(entry_step(d)),
            "{code}: sphere {id} left the rows"
        );
        assert!(
            dumped
                .iter()
                .filter(|r| r.step >= entry_step(d))
                .all(|r| !listed(r)),
            "{code}: sphere {id} came back"
        );
    }
    // dembound removes the same spheres by outlet.
    let o = dembound()
        .arg("scene")
        .arg(&path)
        .args(["--json", "--quiet"])
        .output()
        .unwrap();
    let j: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let outlets = j["outlets"].as_array().expect("outlets");
    assert_eq!(outlets[0]["count"], 3);
    assert_eq!(outlets[1]["count"], 2);
}

/// LIGGGHTS: thermo `step time ke` then n, m per outlet.
#[test]
fn liggghts_outlets_remove_at_the_closed_form_steps() {
    if missing("liggghts", "liggghts", "the LIGGGHTS outlets") {
        return;
    }
    check("liggghts", BOX1, 7, 3);
    check("liggghts", CYL1, 7, 3);
}

/// LAMMPS: thermo `step time ke pp pw` then n, m per outlet.
#[test]
fn lammps_outlets_remove_at_the_closed_form_steps() {
    if missing("lmp", "lammps", "the LAMMPS outlets") {
        return;
    }
    check("lammps", BOX1, 9, 5);
    check("lammps", CYL1, 9, 5);
}

/// What stays refused names the key and the code, exits 2 and writes
/// nothing: outlets in Yade, `domain.outside = "delete"` everywhere, a
/// tilted outlet cylinder in LAMMPS and LIGGGHTS.
#[test]
fn refusals_name_the_key_and_the_code() {
    let tilted = "{ cylinder = { center = [0.0075, 0.005, 0.0025], axis = [0.0, 0.6, 0.8], \
                  radius = 0.002, length = 0.005 } }";
    let cases = [
        ("yade", BOX1, "", "outlet", "Yade"),
        (
            "lammps",
            BOX1,
            "outside = \"delete\"",
            "domain.outside",
            "LAMMPS",
        ),
        (
            "liggghts",
            BOX1,
            "outside = \"delete\"",
            "domain.outside",
            "LIGGGHTS",
        ),
        (
            "lammps",
            tilted,
            "",
            "outlet[1].region.cylinder.axis",
            "LAMMPS",
        ),
        (
            "liggghts",
            tilted,
            "",
            "outlet[1].region.cylinder.axis",
            "LIGGGHTS",
        ),
    ];
    for (code, outlet1, extra, key, name) in cases {
        let root = tempfile::tempdir().unwrap();
        let path = root.path().join("s.toml");
        std::fs::write(&path, scene(outlet1, extra)).unwrap();
        let out = root.path().join("deck");
        let o = dembound()
            .args(["export", code, "--out"])
            .arg(&out)
            .arg(&path)
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{code} {key}: {stderr}");
        assert!(
            stderr.contains(key) && stderr.contains(name),
            "{code}: {stderr}"
        );
        assert!(!out.exists(), "{code} {key}: a deck was written");
    }
}

/// `[[inlet]]` is refused by the Yade deck, and by the LAMMPS deck beside
/// a moving group of fixed spheres (its placements are computed against
/// the fixed spheres where they start: lammps_inlets.rs), naming
/// `inlet[0]` and the code, exit 2, nothing written (an export that
/// dropped the inlet would run another scene; LIGGGHTS exports it:
/// tests/export_liggghts_inlets.rs, LAMMPS otherwise too:
/// tests/export_lammps_inlet_compare.rs).
#[test]
fn inlets_are_refused_naming_the_key_and_the_code() {
    let inlet = "[[inlet]]\n\
                 region = { box = { lower = [0.0, 0.0, 0.025], upper = [0.01, 0.01, 0.03] } }\n\
                 rate = { number = 100.0 }\n\
                 size = { fixed = 1e-3 }\n\
                 material = \"g\"\n";
    for (code, name) in [("lammps", "LAMMPS"), ("yade", "Yade")] {
        let root = tempfile::tempdir().unwrap();
        let path = root.path().join("s.toml");
        // The scene without its outlets, with the inlet.
        let full = scene(BOX1, "");
        let head = full.split("[[outlet]]").next().unwrap_or_default();
        // LAMMPS: beside a plate of fixed spheres moving up.
        let moving = if code == "lammps" {
            "[[particles]]\nmaterial = \"g\"\nfixed = true\n\
             spheres = [{ position = [5e-3, 5e-3, 1e-3], radius = 1e-3 }]\n\
             motion = { velocity = [0.0, 0.0, 0.01] }\n"
        } else {
            ""
        };
        let text = format!(
            "{head}{moving}{inlet}\n[motion]\ngravity = [0.0, 0.0, -9.81]\n\
             [integration]\nscheme = \"verlet\"\ndt = 1e-5\nsteps = 100\n"
        );
        std::fs::write(&path, &text).unwrap();
        let out = root.path().join("deck");
        let o = dembound()
            .args(["export", code, "--out"])
            .arg(&out)
            .arg(&path)
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{code}: {stderr}\n{text}");
        assert!(
            stderr.contains("inlet[0]") && stderr.contains(name),
            "{code}: {stderr}"
        );
        assert!(!out.exists(), "{code}: a deck was written");
    }
}
