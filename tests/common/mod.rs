//! Helpers shared by the CLI tests, which run the real binary.
// Each test binary uses a different subset of these.
#![allow(dead_code)]

pub mod peer;
pub mod shaft;
pub mod silo;

use assert_cmd::Command;
use serde_json::Value;

/// The `dembound` binary built for these tests.
pub fn dembound() -> Command {
    Command::new(env!("CARGO_BIN_EXE_dembound"))
}

/// Writes `text` to `dir/scene.toml` and runs `dembound scene` on it with
/// one thread and `args`, from the system's temporary directory (so that
/// relative paths resolve against the scene file): (exit code, stdout,
/// stderr).
pub fn scene_text(
    text: &str,
    dir: &std::path::Path,
    args: &[&str],
) -> (Option<i32>, String, String) {
    let path = dir.join("scene.toml");
    std::fs::write(&path, text).unwrap();
    let out = dembound()
        .current_dir(std::env::temp_dir())
        .arg("scene")
        .arg(&path)
        .args(["--threads", "1"])
        .args(args)
        .output()
        .expect("the binary runs");
    (
        out.status.code(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// Runs `dembound ARGS`, expecting success; the parsed stdout.
pub fn json(args: &[&str]) -> Value {
    let out = dembound().args(args).output().expect("the binary runs");
    assert!(
        out.status.success(),
        "dembound {args:?} failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).expect("stdout is one JSON object")
}

/// The per-contact keys `run --json` and `exact --json` promise (issue 2).
pub const CONTACT_KEYS: [&str; 9] = [
    "t_contact",
    "t_max_overlap",
    "t_rebound",
    "duration",
    "max_overlap",
    "max_force",
    "max_acceleration",
    "impact_velocity",
    "rebound_velocity",
];

/// `examples/scenes/lattice_drop.toml`.
pub fn lattice_drop() -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/scenes/lattice_drop.toml")
}

/// Runs `dembound scene SCENE --set S… EXTRA… --json --out OUT`, expecting
/// success (`what` names the run in the failure message); the summary,
/// with `kinetic_energy_exact`: the bits of its kinetic energy read
/// exactly from the text.
pub fn scene_summary<S: AsRef<str>>(
    scene: &std::path::Path,
    sets: &[S],
    extra: &[&std::ffi::OsStr],
    out: &std::path::Path,
    what: &str,
) -> Value {
    let mut cmd = dembound();
    cmd.arg("scene").arg(scene);
    for s in sets {
        cmd.args(["--set", s.as_ref()]);
    }
    let o = cmd
        .args(extra)
        .args(["--json", "--out"])
        .arg(out)
        .output()
        .expect("the binary runs");
    assert!(
        o.status.success(),
        "{what}: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    let text = String::from_utf8(o.stdout).expect("UTF-8");
    let mut v: Value = serde_json::from_str(&text).expect("one JSON object");
    v["kinetic_energy_exact"] = exact_number(&text, "kinetic_energy").to_bits().into();
    v
}

/// The number `key` of a `--json` summary read exactly from its text
/// (serde_json's own float parsing may be off by an ulp).
pub fn exact_number(json: &str, key: &str) -> f64 {
    let field = format!("\"{key}\": ");
    let start = json.find(&field).expect("the key") + field.len();
    let text: String = json[start..]
        .chars()
        .take_while(|c| !matches!(c, ',' | '\n' | '}'))
        .collect();
    text.trim().parse().expect("a number")
}

/// Writes `dir/name`: a scene in a closed box from the origin to `upper`,
/// one material `grain` (`density`, E = 1e7 Pa, ν = 0.3), the `[contact]`
/// body `contact`, one `[[particles]]` group of grain with the body
/// `particles`, a plane floor of grain at z = 0, gravity, and the
/// `[integration]` body `integration`; the path.
pub fn grain_floor_scene(
    dir: &std::path::Path,
    name: &str,
    upper: &str,
    density: f64,
    contact: &str,
    particles: &str,
    integration: &str,
) -> std::path::PathBuf {
    let text = format!(
        r#"
[domain]
lower = [0.0, 0.0, 0.0]
upper = {upper}
periodic = [false, false, false]

[[material]]
name = "grain"
density = {density:?}
youngs_modulus = 1.0e7
poisson_ratio = 0.3

[contact]
{contact}

[[particles]]
{particles}
material = "grain"

[[wall]]
plane = {{ point = [0.0, 0.0, 0.0], normal = [0.0, 0.0, 1.0] }}
material = "grain"

[motion]
gravity = [0.0, 0.0, -9.81]

[integration]
{integration}
"#
    );
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

/// The quantity named `name` of a `dembound compare --json` report.
pub fn quantity<'a>(report: &'a Value, name: &str) -> &'a Value {
    report["quantities"]
        .as_array()
        .expect("quantities")
        .iter()
        .find(|q| q["name"] == name)
        .unwrap_or_else(|| panic!("no quantity `{name}` in the report"))
}

/// A JSON array of numbers.
pub fn numbers(v: &Value) -> Vec<f64> {
    v.as_array()
        .expect("an array")
        .iter()
        .map(|x| x.as_f64().expect("a number"))
        .collect()
}

/// The number that follows `marker` in `text` (a refusal's bound, "…
/// (allowed: ≤ X (" or "… out of range: η ≤ X ("); panics naming both when
/// there is none.
pub fn number_after(text: &str, marker: &str) -> f64 {
    let tail = text
        .split(marker)
        .nth(1)
        .unwrap_or_else(|| panic!("no `{marker}` in: {text}"));
    tail.split_whitespace()
        .next()
        .and_then(|x| x.parse().ok())
        .unwrap_or_else(|| panic!("no number after `{marker}` in: {text}"))
}
