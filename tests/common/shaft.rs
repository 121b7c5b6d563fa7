//! The colliding shaft of the removal tests (tests/cli_scene_delete.rs,
//! tests/cli_scene_outlet.rs) and the runs they compare.

use super::dembound;
use serde_json::Value;
use std::path::Path;

/// 360 spheres (R = 0.5 mm, ρ = 2500 kg/m³, Hertz, no damping) on a
/// 6 × 6 × 10 grid in a 10 mm shaft of four plane walls with no floor,
/// thrown in random directions (a fixed linear congruential sequence):
/// they collide while falling and leave through the bottom
/// (`domain.outside = "delete"`). `extra` is TOML added to the scene (e.g.
/// an `[[outlet]]`). Writes `dir/shaft.csv`; returns the scene's text.
pub fn shaft_scene(dir: &Path, extra: &str) -> String {
    let mut rows = Vec::new();
    let mut state: u64 = 12345;
    let mut next = || {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    };
    for k in 0..10 {
        for j in 0..6 {
            for i in 0..6 {
                let x = [
                    1.25e-3 + 1.5e-3 * i as f64,
                    1.25e-3 + 1.5e-3 * j as f64,
                    4e-3 + 1.5e-3 * k as f64,
                ];
                let v = [0.6 * next(), 0.6 * next(), 0.6 * next()];
                rows.push(format!(
                    "{:e},{:e},{:e},5e-4,{:e},{:e},{:e}",
                    x[0], x[1], x[2], v[0], v[1], v[2]
                ));
            }
        }
    }
    let csv = dir.join("shaft.csv");
    std::fs::write(
        &csv,
        "x,y,z,radius,vx,vy,vz\n".to_string() + &rows.join("\n") + "\n",
    )
    .unwrap();
    let mut text = format!(
        r#"
[domain]
lower = [0.0, 0.0, 0.0]
upper = [0.01, 0.01, 0.025]
outside = "delete"

[[material]]
name = "g"
density = 2500.0
youngs_modulus = 1e7
poisson_ratio = 0.3

[contact]
law = "hertz"

[[particles]]
material = "g"
csv = "{}"
{extra}
[motion]
gravity = [0.0, 0.0, -9.81]

[integration]
scheme = "verlet"
dt = 2e-6
steps = 30000

[output]
series_every = 100
every = 10000
"#,
        csv.display()
    );
    for (point, normal) in [
        ("[0.0, 0.0, 0.0]", "[1.0, 0.0, 0.0]"),
        ("[0.01, 0.0, 0.0]", "[-1.0, 0.0, 0.0]"),
        ("[0.0, 0.0, 0.0]", "[0.0, 1.0, 0.0]"),
        ("[0.0, 0.01, 0.0]", "[0.0, -1.0, 0.0]"),
    ] {
        text += &format!(
            "[[wall]]\nplane = {{ point = {point}, normal = {normal} }}\nmaterial = \"g\"\n"
        );
    }
    text
}

/// The one JSON object a `--json` run prints.
pub fn parse_json(stdout: &str) -> Value {
    serde_json::from_str(stdout).expect("one JSON object")
}

/// The number at `key` of the JSON object `j` (panics naming the key).
pub fn number(j: &Value, key: &str) -> f64 {
    j[key]
        .as_f64()
        .unwrap_or_else(|| panic!("{key} missing: {j}"))
}

/// `dembound scene DIR/scene.toml --threads T ARGS --json -q --out DIR/NAME`:
/// the JSON without its timing keys.
pub fn run_json(dir: &Path, threads: &str, name: &str, args: &[&str]) -> Value {
    let out = dembound()
        .arg("scene")
        .arg(dir.join("scene.toml"))
        .args(["--threads", threads, "--json", "-q", "--out"])
        .arg(dir.join(name))
        .args(args)
        .output()
        .expect("the binary runs");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let mut j = parse_json(&String::from_utf8_lossy(&out.stdout));
    for key in [
        "wall_clock",
        "wall_clock_total",
        "particle_steps_per_second",
        "threads",
        "steps_this_run",
    ] {
        j.as_object_mut().unwrap().remove(key);
    }
    j
}

/// The bytes of DIR/NAME/FILE.
pub fn read_output(dir: &Path, name: &str, file: &str) -> Vec<u8> {
    std::fs::read(dir.join(name).join(file)).unwrap_or_else(|e| panic!("{name}/{file}: {e}"))
}

/// `mpirun -np RANKS dembound scene DIR/scene.toml --json -q --out
/// DIR/NAME ARGS` (allowed as root): the JSON.
pub fn mpirun_json(dir: &Path, ranks: usize, name: &str, args: &[&str]) -> Value {
    let o = std::process::Command::new("mpirun")
        .env("OMPI_ALLOW_RUN_AS_ROOT", "1")
        .env("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1")
        .args(["--oversubscribe", "-np", &ranks.to_string()])
        .arg(env!("CARGO_BIN_EXE_dembound"))
        .arg("scene")
        .arg(dir.join("scene.toml"))
        .args(["--json", "-q", "--out"])
        .arg(dir.join(name))
        .args(args)
        .output()
        .expect("mpirun runs (Debian: openmpi-bin)");
    assert!(
        o.status.success(),
        "{ranks} ranks: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    parse_json(&String::from_utf8_lossy(&o.stdout))
}
