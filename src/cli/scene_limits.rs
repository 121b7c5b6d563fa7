//! Limits of `dembound scene` checked before anything is computed or
//! written: the run length (a step count or duration far beyond what
//! could finish needs `--force`, like `dembound run`) and, on a restart,
//! a run length that ends before the checkpoint's steps.

use super::scene::scene_error;
use super::{CliError, CliResult};
use crate::output::format::{duration, sig};
use anyhow::anyhow;
use dembound_scene::io::checkpoint;
use dembound_scene::setup::{RunLength, SceneSetup};

/// Scene runs of more integration steps than this need `--force` (the
/// limit of `dembound run`: at ~1 µs a step for the smallest scene, some
/// 20 minutes; more for every sphere added).
pub const MAX_SCENE_STEPS_WITHOUT_FORCE: u64 = 1_000_000_000;

/// The cost of one step of the smallest scene assumed for the estimate
/// in the message, s (measured: ~1 µs for a few spheres on one thread).
const ASSUMED_SECONDS_PER_STEP: f64 = 1e-6;

/// Refuses a restart whose run length ends before the checkpoint's
/// `done` steps, and, without `force`, a run of more than
/// [`MAX_SCENE_STEPS_WITHOUT_FORCE`] steps in all (`total`, Δt `dt`).
pub(super) fn check_run(
    setup: &SceneSetup,
    total: u64,
    done: u64,
    dt: f64,
    restart: bool,
    force: bool,
) -> CliResult {
    if restart {
        checkpoint::check_run_length(setup, total, done).map_err(scene_error)?;
    }
    if force || total <= MAX_SCENE_STEPS_WITHOUT_FORCE {
        return Ok(());
    }
    let (key, value) = match setup.integration.length {
        RunLength::Steps(s) => ("integration.steps", s.to_string()),
        RunLength::Duration(t) => (
            "integration.duration",
            format!("{} s ({} steps of Δt = {} s)", sig(t, 6), total, sig(dt, 4)),
        ),
    };
    Err(CliError::input(anyhow!(
        "{key} = {value} is out of range: at most {MAX_SCENE_STEPS_WITHOUT_FORCE} steps without \
         --force (this run would take at least {} at ~1 µs a step); pass --force to run it \
         anyway, or shorten the run",
        duration(total as f64 * ASSUMED_SECONDS_PER_STEP)
    )))
}
