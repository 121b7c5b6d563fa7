//! `[[wall]] servo` through the CLI (issue 27 item 2): bad values and bad
//! combinations refused naming the key, the value and the range (exit 2,
//! nothing written); a servo lid's motion in `series.csv` and `--json`
//! (its position, angle, velocity), which scenes of fixed walls do not
//! get; the lid's travel before it meets the spheres is v_max t exactly.

mod common;

use common::{dembound, lattice_drop};
use serde_json::Value;

fn run(scene: &std::path::Path, sets: &[&str], out: &std::path::Path) -> std::process::Output {
    let mut cmd = dembound();
    cmd.arg("scene").arg(scene).args(["--threads", "1"]);
    for s in ["integration.steps=1000", "output.series_every=250"] {
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

const LID: &str = "wall.5.servo={force=0.05,axis=[0,0,-1],max_velocity=0.5,gain=2}";

#[test]
fn bad_servo_values_are_refused_naming_the_key() {
    let tmp = tempfile::tempdir().unwrap();
    let particle_floor = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("examples/scenes/bed_particle_floor.toml");
    for (scene, sets, needles) in [
        (
            lattice_drop(),
            vec!["wall.5.servo={force=0,axis=[0,0,-1],max_velocity=0.5}"],
            vec!["wall[5].servo.force", "0 N", "> 0"],
        ),
        (
            lattice_drop(),
            vec!["wall.5.servo={force=-2,axis=[0,0,-1],max_velocity=0.5}"],
            vec!["wall[5].servo.force", "-2 N", "> 0"],
        ),
        (
            lattice_drop(),
            vec!["wall.5.servo={force=1,axis=[0,0,0],max_velocity=0.5}"],
            vec!["wall[5].servo.axis", "not all zero"],
        ),
        (
            lattice_drop(),
            vec!["wall.5.servo={force=1,axis=[0,0,-1],max_velocity=0}"],
            vec!["wall[5].servo.max_velocity", "> 0"],
        ),
        (
            lattice_drop(),
            vec!["wall.5.servo={force=1,axis=[0,0,-1],max_velocity=1,gain=-1}"],
            vec!["wall[5].servo.gain", "> 0"],
        ),
        (
            lattice_drop(),
            vec!["wall.5.servo={force=1,axis=[0,0,-1],max_velocity=1,kp=1}"],
            vec!["kp"],
        ),
        (
            lattice_drop(),
            vec![LID, "wall.5.motion.velocity=[0,0,-1]"],
            vec!["wall[5].servo", "wall[5].motion", "not both"],
        ),
        (
            particle_floor,
            vec!["wall.0.servo={force=1,axis=[0,0,1],max_velocity=1}"],
            vec![
                "wall[0].servo",
                "boundary_particles",
                "plane, cylinder or mesh",
            ],
        ),
    ] {
        let out_dir = tmp.path().join("out");
        let o = run(&scene, &sets, &out_dir);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{sets:?}: {err}");
        for n in needles {
            assert!(err.contains(n), "{sets:?}: {n}: {err}");
        }
        assert!(!out_dir.exists(), "{sets:?}: something was written");
    }
}

/// The lid of the lattice drop under a servo: nothing touches it in the
/// first 1000 steps (the lattice's top is 9 mm below and falls away), so
/// the controller asks k v_max = 1 m/s, clamped to v_max = 0.5 m/s, and
/// the lid is at −v_max t (the sum of n equal steps Δt v_max: n
/// roundings, 1e-12 allowed). Its row reports the speed, no angle.
#[test]
fn a_servo_lid_reports_its_motion_and_fixed_walls_do_not() {
    let tmp = tempfile::tempdir().unwrap();
    let read = |name: &str, sets: &[&str]| -> (Value, String) {
        let d = tmp.path().join(name);
        let o = run(&lattice_drop(), sets, &d);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let j: Value = serde_json::from_slice(&o.stdout).unwrap();
        (j, std::fs::read_to_string(d.join("series.csv")).unwrap())
    };
    let (fixed, series) = read("fixed", &[]);
    assert!(fixed.get("wall_motions").is_none());
    assert!(!series.contains("position"));
    let (servo, series) = read("servo", &[LID]);
    let m = &servo["wall_motions"][0];
    assert_eq!(m["wall"], 5);
    let t = servo["time"].as_f64().unwrap();
    let z = m["position"][2].as_f64().unwrap();
    assert!(
        (z + 0.5 * t).abs() <= 1e-12 * 0.5 * t,
        "{z} vs {}",
        -0.5 * t
    );
    assert_eq!(m["velocity"][2].as_f64(), Some(-0.5));
    assert_eq!(m["angle"].as_f64(), Some(0.0));
    let header: Vec<&str> = series.lines().next().unwrap().split(',').collect();
    let last: Vec<&str> = series.lines().last().unwrap().split(',').collect();
    let col = |name: &str| header.iter().position(|h| *h == name).expect(name);
    assert_eq!(
        last[col("wall5_position_z_m")].parse::<f64>().unwrap(),
        z,
        "the series' last row is the end state"
    );
    assert_eq!(
        last[col("wall5_velocity_z_m_s")].parse::<f64>().unwrap(),
        -0.5
    );
    assert_eq!(header.last(), Some(&"wall5_angular_velocity_z_rad_s"));
}
