//! Helpers shared by the CLI tests, which run the real binary.
// Each test binary uses a different subset of these.
#![allow(dead_code)]

use assert_cmd::Command;
use serde_json::Value;

/// The `dembound` binary built for these tests.
pub fn dembound() -> Command {
    Command::new(env!("CARGO_BIN_EXE_dembound"))
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
