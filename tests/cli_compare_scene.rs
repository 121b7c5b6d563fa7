//! `dembound compare DECK` on scene decks (issue 32): the divergence
//! analysis on a series of known exponential growth, LAMMPS's run of
//! exported decks against dembound's (an independent code integrating the
//! same model: the same state to 1e-9 until collisions amplify the
//! round-off), and the refusals of the compare and of the friction export.
//!
//! Without `lmp` on PATH the LAMMPS tests fail under CI and skip elsewhere.

mod common;

use common::peer::{export_lammps, lattice_bed, missing, run_lmp, STEEL_PLANE_FLOOR};
use common::{dembound, numbers};
use dembound_export::agreement::{divergence, IDENTICAL};
use serde_json::Value;
use std::path::Path;

fn have_lmp() -> bool {
    !missing("lmp", "lammps", "the scene compare")
}

/// Δ(t) = Δ₀ e^(λ t) sampled every `dt`, then a plateau at 0.1 (the runs
/// decorrelated): the first row above 1e-9 is the first k with
/// Δ₀ e^(λ k dt) > 1e-9, computed here in closed form, and the fit of
/// ln Δ over the rows from there to the first row ≥ 1e-2 is a straight
/// line of slope λ, so it returns λ to round-off (1e-9 relative allows
/// for the sums of the least-squares fit over ~40 rows).
#[test]
fn divergence_of_a_known_exponential_is_exact() {
    let (d0, lambda, dt) = (1e-12f64, 2345.0f64, 3e-5f64);
    let time: Vec<f64> = (0..400).map(|k| k as f64 * dt).collect();
    let delta: Vec<f64> = time
        .iter()
        .map(|t| (d0 * (lambda * t).exp()).min(0.1))
        .collect();
    let d = divergence(&time, &delta, IDENTICAL);
    // ln(1e-9/Δ₀)/λ = ln(1e3)/2345 = 2.9457e-3 s: between rows 98 and 99.
    let crossing = (IDENTICAL / d0).ln() / lambda / dt;
    let first = crossing.floor() as usize + 1;
    assert_eq!(first, 99);
    assert_eq!(d.diverged_at, Some(time[first]));
    assert_eq!(d.identical_until, Some(time[first - 1]));
    let rate = d.growth_rate.expect("a fit");
    assert!((rate / lambda - 1.0).abs() < 1e-9, "λ = {rate}");
    // The fit runs from row 99 to the first row ≥ 1e-2 (ln(1e10)/λ =
    // 9.819e-3 s: row 328, before the plateau starts at row 360).
    let saturated = (0..400).find(|&k| delta[k] >= 1e-2).expect("saturates");
    assert_eq!(saturated, 328);
    assert_eq!(d.fit_rows, saturated - first + 1);
    // Never above the threshold: identical to the last row.
    let flat = divergence(&time, &vec![1e-12; 400], IDENTICAL);
    assert_eq!(flat.diverged_at, None);
    assert_eq!(flat.identical_until, Some(time[399]));
}

/// Exports `text` (extra `--set`s `sets`), runs LAMMPS on it and `dembound
/// compare --json --figures`; the report.
fn lammps_compare(dir: &Path, text: &str, sets: &[&str]) -> Value {
    let scene = dir.join("bed.toml");
    std::fs::write(&scene, text).expect("written");
    let deck = dir.join("deck");
    export_lammps(&scene, sets, &deck, "bed");
    run_lmp(&deck, "bed");
    let out = dembound()
        .arg("compare")
        .arg(&deck)
        .arg("--json")
        .arg("--figures")
        .arg(dir.join("figures"))
        .output()
        .expect("dembound runs");
    assert!(
        out.status.success(),
        "compare failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).expect("one JSON object")
}

fn quantity<'a>(report: &'a Value, name: &str) -> &'a Value {
    report["quantities"]
        .as_array()
        .expect("quantities")
        .iter()
        .find(|q| q["name"].as_str().is_some_and(|n| n.starts_with(name)))
        .unwrap_or_else(|| panic!("no quantity {name}"))
}

/// The frictionless elastic bed of 384 spheres thrown at a steel plane
/// floor (Hertz, the same model in both codes) over 400 steps, rows every
/// 20: LAMMPS's dump and dembound's run are the same state to 1e-9 at every
/// row (round-off, ~1e-16 per step in another summation order, stays
/// orders of magnitude below in 400 steps: the README measured 3e-13 in the
/// kinetic energy after 1000), in every quantity the compare reports; and
/// the test is not vacuous: the bed hits the floor (overlaps > 0, the
/// floor's force > 0) and the kinetic energy changes by more than 1e-3.
#[test]
fn lammps_run_of_a_small_bed_is_the_same_state_to_1e_9() {
    if !have_lmp() {
        return;
    }
    let dir = tempfile::tempdir().expect("a temporary directory");
    let text = lattice_bed(
        "law = \"hertz\"",
        "[0.0, 0.0, -0.1]",
        STEEL_PLANE_FLOOR,
        400,
        "[output]\nseries_every = 20\n",
    );
    let report = lammps_compare(dir.path(), &text, &[]);
    assert_eq!(report["code"], "LAMMPS");
    assert_eq!(report["rows"], 21);
    for q in report["quantities"].as_array().expect("quantities") {
        let rel = numbers(&q["relative_difference"]);
        let worst = rel.iter().cloned().fold(0.0, f64::max);
        assert!(worst <= IDENTICAL, "{}: {worst:e}", q["name"]);
        assert!(q["divergence"]["diverged_at"].is_null(), "{}", q["name"]);
    }
    let contacts = numbers(&quantity(&report, "contacts")["code"]);
    assert!(
        contacts.iter().any(|c| *c > 0.0),
        "no contact: {contacts:?}"
    );
    let floor = numbers(&quantity(&report, "wall[0]")["dembound"]);
    assert!(floor.iter().any(|f| *f > 0.0));
    let ke = numbers(&quantity(&report, "kinetic energy")["dembound"]);
    assert!((ke[ke.len() - 1] / ke[0] - 1.0).abs() > 1e-3, "{ke:?}");
    // Both speeds by CPU time: LAMMPS's log has its "% CPU use" line, and
    // dembound measures its own; the CPU time of a run cannot exceed its
    // wall time on its cores by more than the clocks' granularity (1e-2 s
    // covers getrusage's and LAMMPS's rounding of a run this short).
    for key in ["code_speed", "dembound_speed"] {
        let speed = &report[key];
        assert_eq!(speed["clock"], "CPU", "{key}: {speed}");
        let cpu = speed["cpu_seconds"].as_f64().expect("cpu_seconds");
        let wall = speed["wall_seconds"].as_f64().expect("wall_seconds");
        assert!(cpu > 0.0 && cpu <= wall + 1e-2, "{key}: {speed}");
    }
    // A figure per quantity and the differences, as SVG and PNG.
    for stem in ["kinetic_energy", "bed_height", "relative_differences"] {
        assert!(dir
            .path()
            .join("figures")
            .join(format!("{stem}.png"))
            .is_file());
        assert!(dir
            .path()
            .join("figures")
            .join(format!("{stem}.svg"))
            .is_file());
    }
}

/// The walls' rows of a `fix ave/time` file: step → the columns.
fn wall_rows(path: &Path) -> Vec<(u64, Vec<f64>)> {
    std::fs::read_to_string(path)
        .expect("the wall file")
        .lines()
        .filter(|l| !l.starts_with('#') && !l.trim().is_empty())
        .map(|l| {
            let w: Vec<f64> = l
                .split_whitespace()
                .map(|x| x.parse().expect("a number"))
                .collect();
            (w[0] as u64, w[1..].to_vec())
        })
        .collect()
}

/// `compare` reads the walls' forces averaged over every step when the
/// deck wrote walls_mean.txt, and the force at the row's step when only
/// walls.txt is there. The small frictionless bed of the test above (the
/// same state to 1e-9 in both codes over its 400 steps, rows every 20)
/// hits the floor during the run: per row, the peer's series is |mean F|
/// of walls_mean.txt's columns (computed here from the file), dembound's
/// (its own per-step sum) agrees with it to 1e-9, and it is not the
/// row-step force of walls.txt (the floor's force changes by more than
/// 1e-3 within a row interval while the bed lands). Without
/// walls_mean.txt the same compare reads walls.txt's |F| at the row.
#[test]
fn compare_reads_the_walls_averaged_over_every_step_when_the_deck_has_them() {
    if !have_lmp() {
        return;
    }
    let dir = tempfile::tempdir().expect("a temporary directory");
    let text = lattice_bed(
        "law = \"hertz\"",
        "[0.0, 0.0, -0.1]",
        STEEL_PLANE_FLOOR,
        400,
        "[output]\nseries_every = 20\n",
    );
    let report = lammps_compare(dir.path(), &text, &[]);
    let deck = dir.path().join("deck");
    assert_eq!(report["wall_forces"], "mean_over_row_interval");
    let norm = |c: &[f64]| (c[0] * c[0] + c[1] * c[1] + c[2] * c[2]).sqrt();
    let mean = wall_rows(&deck.join("walls_mean.txt"));
    let at_step = wall_rows(&deck.join("walls.txt"));
    // LAMMPS's fix ave/time 1 20 20: rows 20, 40, … 400, none at step 0.
    assert_eq!(mean.len(), 20);
    assert_eq!(mean[0].0, 20);
    let floor = quantity(&report, "wall[0]");
    let (code, ours) = (numbers(&floor["code"]), numbers(&floor["dembound"]));
    assert_eq!(code.len(), 20);
    let mut differs = false;
    for (k, (step, columns)) in mean.iter().enumerate() {
        let expected = norm(&columns[0..3]);
        // The report's number is the file's, through JSON (17 digits).
        assert!((code[k] - expected).abs() <= 1e-15 * expected, "row {step}");
        let scale = code.iter().cloned().fold(0.0, f64::max);
        assert!((ours[k] - code[k]).abs() <= 1e-9 * scale, "row {step}");
        let (s, c) = at_step.iter().find(|(s, _)| s == step).expect("same rows");
        assert_eq!(s, step);
        differs |= (norm(&c[0..3]) - expected).abs() > 1e-3 * scale;
    }
    assert!(differs, "the means are the row-step forces: {code:?}");
    // `dembound scene` on the deck's scene with `output.wall_force_mean`:
    // series.csv's mean columns are the numbers compare reported for
    // dembound (the same sums: 1e-14 allows the norm's rounding only), and
    // LAMMPS's walls_mean.txt component by component (1e-9 of the largest
    // mean: the same state to 1e-9, as above).
    let out = dir.path().join("scene_out");
    let run = dembound()
        .arg("scene")
        .arg(deck.join("scene.toml"))
        .args(["--set", "output.wall_force_mean=true", "--threads", "1"])
        .args(["--quiet", "--out"])
        .arg(&out)
        .output()
        .expect("dembound runs");
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let text = std::fs::read_to_string(out.join("series.csv")).expect("series.csv");
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().expect("a header").split(',').collect();
    let first = header
        .iter()
        .position(|h| *h == "wall0_mean_force_x_N")
        .expect("the mean columns");
    let walls = (header.len() - first) / 3;
    let rows: Vec<Vec<f64>> = lines
        .map(|l| l.split(',').map(|x| x.parse().expect("a number")).collect())
        .collect();
    // Rows at 0, 20, … 400; the row of step 0 has no mean.
    assert_eq!(rows.len(), 21);
    assert!(rows[0][first..].iter().all(|x| x.is_nan()));
    let scale = mean
        .iter()
        .flat_map(|(_, c)| c.iter())
        .fold(0.0f64, |s, x| s.max(x.abs()));
    for (k, (step, columns)) in mean.iter().enumerate() {
        let row = &rows[k + 1];
        assert_eq!(row[0] as u64, *step);
        for w in 0..walls {
            let cells = &row[first + 3 * w..first + 3 * w + 3];
            for (a, b) in cells.iter().zip(&columns[3 * w..3 * w + 3]) {
                assert!(
                    (a - b).abs() <= 1e-9 * scale,
                    "row {step} wall {w}: {a} vs {b}"
                );
            }
        }
        let reported = ours[k];
        let series = norm(&row[first..first + 3]);
        assert!(
            (series - reported).abs() <= 1e-14 * reported.max(1e-300),
            "row {step}: series {series} vs compare {reported}"
        );
    }
    // Without the averaged file: the row-step forces of walls.txt.
    std::fs::remove_file(deck.join("walls_mean.txt")).expect("removed");
    let out = dembound()
        .arg("compare")
        .arg(&deck)
        .arg("--json")
        .output()
        .expect("dembound runs");
    assert!(out.status.success());
    let report: Value = serde_json::from_slice(&out.stdout).expect("one JSON object");
    assert_eq!(report["wall_forces"], "at_row_step");
    let code = numbers(&quantity(&report, "wall[0]")["code"]);
    let rows: Vec<f64> = at_step.iter().map(|(_, c)| norm(&c[0..3])).collect();
    assert_eq!(code.len(), rows.len());
    for (a, b) in code.iter().zip(&rows) {
        assert!((a - b).abs() <= 1e-15 * b.max(1e-300), "{a} vs {b}");
    }
}

/// Damped friction exports under `contact.tangential_damping = false`
/// (Hertz–Tsuji e = 0.5, Mindlin μ = 0.5): thrown sideways at a steel
/// plane, the bottom layer slides on the floor with its springs loaded
/// for the first 50 steps (0.1 ms) before any two spheres touch; only
/// sphere–plane contacts act, which both codes compute with the same
/// formulas (torque arm R), so the states agree to 1e-9 (round-off over
/// 50 steps is ~1e-14) while the spins are not zero (the rotational
/// energy grows: the friction acts).
#[test]
fn damped_friction_without_the_tangential_dashpot_agrees_with_lammps() {
    if !have_lmp() {
        return;
    }
    let dir = tempfile::tempdir().expect("a temporary directory");
    let text = lattice_bed(
        "law = \"hertz\"\ndamping = \"tsuji\"\nrestitution = 0.5\nfriction = 0.5\ntangential_damping = false",
        "[0.03, 0.02, -0.1]",
        STEEL_PLANE_FLOOR,
        50,
        "[output]\nseries_every = 5\n",
    );
    let report = lammps_compare(dir.path(), &text, &[]);
    let state = quantity(&report, "state");
    let worst = numbers(&state["relative_difference"])
        .into_iter()
        .fold(0.0, f64::max);
    assert!(worst <= IDENTICAL, "positions differ by {worst:e} R");
    let spin = numbers(&quantity(&report, "rotational energy")["dembound"]);
    assert!(spin[spin.len() - 1] > 0.0, "no spin: {spin:?}");
    let rel = numbers(&quantity(&report, "rotational energy")["relative_difference"]);
    assert!(rel.iter().all(|d| *d <= IDENTICAL), "{rel:?}");
}

fn fails_with(args: &[&std::ffi::OsStr], words: &[&str]) {
    let out = dembound().args(args).output().expect("dembound runs");
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{args:?}: {err}");
    for w in words {
        assert!(err.contains(w), "{args:?}: `{w}` not in {err}");
    }
}

/// A scene deck not run yet, a dump of another scene, a deck with neither
/// input file: exit 2, saying what is wrong and what to do.
#[test]
fn compare_refusals_say_what_is_missing() {
    let dir = tempfile::tempdir().expect("a temporary directory");
    let scene = dir.path().join("bed.toml");
    std::fs::write(
        &scene,
        lattice_bed(
            "law = \"hertz\"",
            "[0.0, 0.0, -0.1]",
            STEEL_PLANE_FLOOR,
            10,
            "",
        ),
    )
    .expect("written");
    let deck = dir.path().join("deck");
    export_lammps(&scene, &[] as &[&str], &deck, "bed");
    let compare = |d: &Path| {
        vec![
            std::ffi::OsString::from("compare"),
            d.as_os_str().to_owned(),
        ]
    };
    let args = compare(&deck);
    let refs: Vec<&std::ffi::OsStr> = args.iter().map(|a| a.as_os_str()).collect();
    fails_with(&refs, &["particles.dump", "lmp -in in.lammps"]);
    // A dump of one sphere: not this deck's run.
    std::fs::write(
        deck.join("particles.dump"),
        "ITEM: TIMESTEP\n0\nITEM: NUMBER OF ATOMS\n1\nITEM: BOX BOUNDS mm mm mm\n0 1\n0 1\n0 1\n\
         ITEM: ATOMS id x y z vx vy vz\n1 0 0 0 0 0 0\n",
    )
    .expect("written");
    fails_with(&refs, &["1 spheres", "384", "not this deck's run"]);
    // scene.toml alone.
    std::fs::remove_file(deck.join("in.lammps")).expect("removed");
    fails_with(&refs, &["none of in.lammps, in.liggghts, scene.py"]);
}

/// The friction export's refusals touched by issue 32 name the key and
/// LAMMPS, exit 2, and leave no deck: damping with friction and the
/// tangential dashpot on (the way out, `contact.tangential_damping =
/// false`, named too), and rolling friction with damping.
#[test]
fn friction_export_refusals_name_the_key_and_lammps() {
    let dir = tempfile::tempdir().expect("a temporary directory");
    let scene = dir.path().join("bed.toml");
    std::fs::write(
        &scene,
        lattice_bed(
            "law = \"hertz\"\nfriction = 0.5",
            "[0.0, 0.0, -0.1]",
            STEEL_PLANE_FLOOR,
            10,
            "",
        ),
    )
    .expect("written");
    let out = dir.path().join("deck");
    let cases: [(&[&str], &[&str]); 2] = [
        (
            &["contact.damping=tsuji", "contact.restitution=0.5"],
            &[
                "contact.damping",
                "LAMMPS",
                "contact.tangential_damping = false",
            ],
        ),
        (
            &[
                "contact.law={hooke=50.0}",
                "contact.damping=viscous",
                "contact.restitution=0.5",
                "contact.tangential_damping=false",
                "contact.rolling_friction=0.1",
            ],
            &["rolling friction", "contact.damping", "LAMMPS"],
        ),
    ];
    for (sets, words) in cases {
        let mut args: Vec<std::ffi::OsString> =
            vec!["export".into(), "lammps".into(), scene.clone().into()];
        for s in sets {
            args.push("--set".into());
            args.push((*s).into());
        }
        args.push("--out".into());
        args.push(out.clone().into());
        let refs: Vec<&std::ffi::OsStr> = args.iter().map(|a| a.as_os_str()).collect();
        fails_with(&refs, words);
        assert!(!out.join("in.lammps").exists());
    }
}
