//! `output.wall_force_mean` (issue 32): series.csv's `wallK_mean_force_*_N`
//! columns, each wall's force averaged over every step since the previous
//! row. Checked against the mean, computed here, of the per-step forces a
//! run with a row at every step writes; against a resting sphere's weight
//! m g (exact); and a scene that does not ask for them writes the same
//! series and snapshots as before, bit for bit (the key only appends).

mod common;

use common::dembound;
use common::peer::{lattice_bed, STEEL_PLANE_FLOOR};
use std::path::Path;

/// A frictional Hertz–Tsuji bed (e = 0.3, Mindlin μ = 0.5) of 384
/// spheres thrown at a steel floor and sideways (+x, +y), between four
/// plane side walls: the floor and the walls at x, y = 10.2 mm carry force
/// within the first rows.
const FRICTION: &str = "law = \"hertz\"\ndamping = \"tsuji\"\nrestitution = 0.3\nfriction = 0.5";
const THROW: &str = "[0.3, 0.2, -0.3]";
const STEPS: u64 = 600;

/// Runs `dembound scene` on `text` into `dir/out` (one thread); panics
/// unless it succeeds.
fn run(dir: &Path, text: &str) {
    let scene = dir.join("scene.toml");
    std::fs::write(&scene, text).expect("written");
    let out = dembound()
        .arg("scene")
        .arg(&scene)
        .args(["--threads", "1", "--quiet", "--json", "--out"])
        .arg(dir.join("out"))
        .output()
        .expect("dembound runs");
    assert!(
        out.status.success(),
        "scene failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// series.csv of a run: the header and the rows, as text.
fn series(dir: &Path) -> (Vec<String>, Vec<Vec<String>>) {
    let text = std::fs::read_to_string(dir.join("out/series.csv")).expect("series.csv");
    let mut lines = text.lines();
    let header = lines
        .next()
        .expect("a header")
        .split(',')
        .map(str::to_string)
        .collect();
    let rows = lines
        .map(|l| l.split(',').map(str::to_string).collect())
        .collect();
    (header, rows)
}

fn column(header: &[String], name: &str) -> usize {
    header
        .iter()
        .position(|h| h == name)
        .unwrap_or_else(|| panic!("no column {name} in {header:?}"))
}

/// Not asked, nothing changes: the series and every snapshot of a run
/// without the key are the same bytes as the same run's with it, less
/// the mean columns, which it appends after every other column (the
/// summing loop leaves Verlet's steps unfused; the same bits). Asked, the
/// columns are there, NaN at the row of step 0 (no step before it).
#[test]
fn a_scene_that_does_not_ask_keeps_its_series_and_snapshots() {
    let tmp = tempfile::tempdir().expect("temp dir");
    let (plain, mean) = (tmp.path().join("plain"), tmp.path().join("mean"));
    std::fs::create_dir_all(&plain).unwrap();
    std::fs::create_dir_all(&mean).unwrap();
    let text = |extra: &str| {
        lattice_bed(
            FRICTION,
            THROW,
            STEEL_PLANE_FLOOR,
            STEPS,
            &format!("[output]\nseries_every = 50\nevery = 200\n{extra}"),
        )
    };
    run(&plain, &text(""));
    run(&mean, &text("wall_force_mean = true"));
    let (h0, rows0) = series(&plain);
    let (h1, rows1) = series(&mean);
    assert!(!h0.iter().any(|h| h.contains("mean")), "{h0:?}");
    assert_eq!(h1.len(), h0.len() + 15, "5 walls × 3 components");
    assert_eq!(h1[..h0.len()], h0[..]);
    assert_eq!(h1[h0.len()], "wall0_mean_force_x_N");
    assert_eq!(h1[h1.len() - 1], "wall4_mean_force_z_N");
    assert_eq!(rows0.len(), rows1.len());
    assert_eq!(rows0.len() as u64, STEPS / 50 + 1);
    for (a, b) in rows0.iter().zip(&rows1) {
        assert_eq!(a[..], b[..a.len()], "row of step {}", a[0]);
    }
    assert!(rows1[0][h0.len()..].iter().all(|c| c == "NaN"));
    // Every snapshot the same bytes.
    let mut snapshots = 0;
    for entry in std::fs::read_dir(plain.join("out")).unwrap() {
        let name = entry.unwrap().file_name();
        if name.to_string_lossy().ends_with(".vtp") || name == "snapshots.pvd" {
            let a = std::fs::read(plain.join("out").join(&name)).unwrap();
            let b = std::fs::read(mean.join("out").join(&name)).unwrap();
            assert!(a == b, "{name:?} differs");
            snapshots += 1;
        }
    }
    assert!(snapshots >= 4, "{snapshots} snapshot files");
}

/// Each row's mean is the mean of the per-step forces since the previous
/// row: a run with a row at every step (no key: `wallK_force_*_N` at
/// each step, printed in shortest round-trip form, so read back exactly)
/// gives the forces of steps 50(k−1)+1 … 50k, averaged here, against the
/// same scene's run with rows every 50 steps and the key. The two runs
/// take the same steps to the bit (observing does not change the state),
/// so the only difference is the order of 50 additions and one division:
/// 1e-12 of the largest mean is far above that (~50 ε ≈ 1e-14) and far
/// below what sampling one step would give (checked: some row's force at
/// its step differs from its mean by more than 1e-3 of the scale).
#[test]
fn the_mean_columns_are_the_mean_of_every_steps_force() {
    let tmp = tempfile::tempdir().expect("temp dir");
    let (every, mean) = (tmp.path().join("every"), tmp.path().join("mean"));
    std::fs::create_dir_all(&every).unwrap();
    std::fs::create_dir_all(&mean).unwrap();
    let text = |extra: &str| lattice_bed(FRICTION, THROW, STEEL_PLANE_FLOOR, STEPS, extra);
    run(&every, &text("[output]\nseries_every = 1\nevery = 600\n"));
    run(
        &mean,
        &text("[output]\nseries_every = 50\nevery = 600\nwall_force_mean = true\n"),
    );
    let (h0, rows0) = series(&every);
    let (h1, rows1) = series(&mean);
    assert_eq!(rows0.len() as u64, STEPS + 1);
    let number = |s: &str| s.parse::<f64>().expect("a number");
    let walls = 5;
    let mut scale = 0.0f64;
    let mut expected = Vec::new();
    for k in 1..rows1.len() {
        assert_eq!(number(&rows1[k][0]), (50 * k) as f64);
        let mut m = vec![0.0f64; 3 * walls];
        for row in &rows0[50 * (k - 1) + 1..=50 * k] {
            for w in 0..walls {
                for (a, axis) in ["x", "y", "z"].iter().enumerate() {
                    m[3 * w + a] += number(&row[column(&h0, &format!("wall{w}_force_{axis}_N"))]);
                }
            }
        }
        let m: Vec<f64> = m.iter().map(|x| x / 50.0).collect();
        scale = m.iter().fold(scale, |s, x| s.max(x.abs()));
        expected.push(m);
    }
    let mut sampled_differs = false;
    let mut touched = [false; 5];
    for (k, m) in expected.iter().enumerate() {
        let row = &rows1[k + 1];
        for w in 0..walls {
            for (a, axis) in ["x", "y", "z"].iter().enumerate() {
                let got = number(&row[column(&h1, &format!("wall{w}_mean_force_{axis}_N"))]);
                let want = m[3 * w + a];
                assert!(
                    (got - want).abs() <= 1e-12 * scale,
                    "row {k}, wall {w} {axis}: {got} vs {want} N"
                );
                let at_step = number(&row[column(&h1, &format!("wall{w}_force_{axis}_N"))]);
                sampled_differs |= (at_step - want).abs() > 1e-3 * scale;
                touched[w] |= want != 0.0;
            }
        }
    }
    assert!(sampled_differs, "every mean is its row's force");
    assert!(
        touched[0] && touched[2] && touched[4],
        "a wall never touched: {touched:?}"
    );
}

/// One sphere (R = 0.5 mm, ρ = 1000 kg/m³) resting on a plane floor under
/// gravity, Tsuji-damped (e = 0.3) to rest: the mean force on the floor
/// over the last row's 1000 steps is its weight ρ 4/3 π R³ g (computed
/// here), pointing down, to 1e-6 (the residual oscillation after 40000
/// steps of a contact damped at e = 0.3 is orders of magnitude below),
/// with no sideways part (1e-12 of the weight: nothing acts sideways).
#[test]
fn a_resting_sphere_loads_the_floor_with_its_weight() {
    let (rho, r, g) = (1000.0f64, 0.5e-3f64, 9.81f64);
    let text = r#"
[domain]
lower = [0.0, 0.0, 0.0]
upper = [0.004, 0.004, 0.004]
[[material]]
name = "grain"
density = 1000.0
youngs_modulus = 1.0e7
poisson_ratio = 0.3
[contact]
law = "hertz"
damping = "tsuji"
restitution = 0.3
[[particles]]
spheres = [ { position = [0.002, 0.002, 0.0005], radius = 0.5e-3 } ]
material = "grain"
[[wall]]
plane = { point = [0.0, 0.0, 0.0], normal = [0.0, 0.0, 1.0] }
material = "grain"
[motion]
gravity = [0.0, 0.0, -9.81]
[integration]
scheme = "verlet"
dt = 2.0e-6
steps = 41000
[output]
series_every = 1000
every = 41000
wall_force_mean = true
"#;
    let tmp = tempfile::tempdir().expect("temp dir");
    run(tmp.path(), text);
    let (h, rows) = series(tmp.path());
    let last = rows.last().expect("rows");
    assert_eq!(last[0], "41000");
    let get = |name: &str| last[column(&h, name)].parse::<f64>().expect("a number");
    let weight = rho * 4.0 / 3.0 * std::f64::consts::PI * r.powi(3) * g;
    let fz = get("wall0_mean_force_z_N");
    assert!(
        (fz / -weight - 1.0).abs() < 1e-6,
        "{fz} N, weight {weight} N"
    );
    for axis in ["x", "y"] {
        let f = get(&format!("wall0_mean_force_{axis}_N"));
        assert!(f.abs() < 1e-12 * weight, "{axis}: {f} N");
    }
}

/// A value that is not a boolean is refused (exit 2) naming the key, and
/// nothing is written.
#[test]
fn a_non_boolean_is_refused_naming_the_key() {
    let tmp = tempfile::tempdir().expect("temp dir");
    let text = lattice_bed(
        FRICTION,
        THROW,
        STEEL_PLANE_FLOOR,
        10,
        "[output]\nwall_force_mean = 1\n",
    );
    let scene = tmp.path().join("scene.toml");
    std::fs::write(&scene, text).expect("written");
    let out_dir = tmp.path().join("out");
    let out = dembound()
        .arg("scene")
        .arg(&scene)
        .args(["--quiet", "--out"])
        .arg(&out_dir)
        .output()
        .expect("dembound runs");
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(err.contains("wall_force_mean"), "{err}");
    assert!(err.contains("boolean") || err.contains("bool"), "{err}");
    assert!(!out_dir.exists());
}
