//! `[[wall]] motion` and `oscillation` through the CLI (issue 27): bad
//! values refused naming the key, value and range (exit 2, nothing
//! written); a moving floor's work in `--json`'s energy balance and in a
//! `work_by_walls_J` column of `series.csv`, which a scene of fixed walls
//! does not get.

mod common;

use common::{dembound, lattice_drop};
use serde_json::Value;

fn run(sets: &[&str], out: &std::path::Path) -> std::process::Output {
    let mut cmd = dembound();
    cmd.arg("scene").arg(lattice_drop());
    for s in ["integration.steps=3000", "output.series_every=500"] {
        cmd.args(["--set", s]);
    }
    for s in sets {
        cmd.args(["--set", s]);
    }
    cmd.args(["--json", "-q", "--out"])
        .arg(out)
        .output()
        .expect("the binary runs")
}

#[test]
fn bad_motion_values_are_refused_naming_the_key() {
    let tmp = tempfile::tempdir().unwrap();
    for (set, needles) in [
        (
            "wall.4.motion.end=-1",
            vec!["wall[4].motion.end", "-1", "allowed"],
        ),
        (
            "wall.4.motion.start=-0.5",
            vec!["wall[4].motion.start", "≥ 0"],
        ),
        (
            "wall.4.motion.angular_velocity=[0,0,1e7]",
            vec!["wall[4].motion.angular_velocity", "1e6"],
        ),
        (
            "wall.4.oscillation={amplitude=[0,0,1e-3],frequency=0}",
            vec!["wall[4].oscillation.frequency", "> 0"],
        ),
        (
            "wall.4.oscillation={amplitude=[0,0,1],frequency=1e5}",
            vec!["wall[4].oscillation", "peak speed"],
        ),
        ("wall.4.motion.spin=[0,0,1]", vec!["spin"]),
    ] {
        let out_dir = tmp.path().join("out");
        let o = run(&[set], &out_dir);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{set}: {err}");
        for n in needles {
            assert!(err.contains(n), "{set}: {err}");
        }
        assert!(!out_dir.exists(), "{set}: something was written");
    }
}

#[test]
fn a_moving_floor_reports_its_work_and_fixed_walls_do_not() {
    let tmp = tempfile::tempdir().unwrap();
    let read = |name: &str, sets: &[&str]| -> (Value, String) {
        let d = tmp.path().join(name);
        let o = run(sets, &d);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let j: Value = serde_json::from_slice(&o.stdout).unwrap();
        (j, std::fs::read_to_string(d.join("series.csv")).unwrap())
    };
    let (fixed, series) = read("fixed", &[]);
    assert!(fixed["energy_balance"].get("work_by_walls").is_none());
    assert!(!series.contains("work_by_walls"));
    let (moving, series) = read(
        "moving",
        &[
            "wall.4.motion.velocity=[0.05,0,0]",
            "wall.4.oscillation={amplitude=[0,0,2e-5],frequency=200}",
        ],
    );
    let b = &moving["energy_balance"];
    let work = b["work_by_walls"].as_f64().unwrap();
    assert!(work != 0.0, "{b}");
    // K + E + P + D − W = E₀ (D = E₀ + W − (K + E + P)): to rounding.
    let (total, initial) = (
        b["total"].as_f64().unwrap(),
        b["total_initial"].as_f64().unwrap(),
    );
    assert!((total - initial).abs() <= 1e-12 * initial.abs(), "{b}");
    let header = series.lines().next().unwrap();
    assert!(
        header.contains("dissipated_energy_J,work_by_walls_J,particle_contacts"),
        "{header}"
    );
    let last: Vec<&str> = series.lines().last().unwrap().split(',').collect();
    assert_eq!(last[6].parse::<f64>().unwrap(), work);
}
