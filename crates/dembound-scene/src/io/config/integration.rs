//! How the scene runs: `[motion]`, `[integration]`, `[output]` and
//! `[parallel]`, and their checks.

use super::checks::{check, finite3, invalid, positive};
use super::{SceneError, SceneFile};
use crate::limits;
use serde::{Deserialize, Serialize};

/// `[motion]`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MotionSection {
    /// m/s².
    #[serde(default = "default_gravity")]
    pub gravity: [f64; 3],
}

fn default_gravity() -> [f64; 3] {
    [0.0, 0.0, -9.81]
}

impl Default for MotionSection {
    fn default() -> Self {
        Self {
            gravity: default_gravity(),
        }
    }
}

/// `[integration]`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct IntegrationSection {
    #[serde(default)]
    pub scheme: Scheme,
    /// Δt, s (or `eta`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub dt: Option<f64>,
    /// Δt = η × the smallest pair contact-time estimate (addition).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub eta: Option<f64>,
    /// Impact speed for the contact-time estimate, m/s (addition; default
    /// the fastest of √(2 |g| H), H the domain's extent along g, and the
    /// fastest initial particle speed).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub impact_speed: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub steps: Option<u64>,
    /// s (addition; or `steps`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub duration: Option<f64>,
    /// Verlet-list skin, m (addition; default the engine's).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub skin: Option<f64>,
}

/// `integration.scheme`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Scheme {
    #[default]
    Verlet,
    Gear5,
}

/// `[output]`.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OutputSection {
    /// One row per completed contact (JSON and `collisions.csv`).
    #[serde(default)]
    pub collisions: bool,
    /// Sum the dissipated energy contact by contact every step and report
    /// the energy balance's error (addition; costs a pass per step).
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub dissipation: bool,
    /// Steps between VTK snapshots (addition; default: 20 intervals).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub every: Option<u64>,
    /// Steps between time-series rows (addition; default: 1000 intervals).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub series_every: Option<u64>,
    /// Each series row also gives each wall's force averaged over every
    /// step since the previous row (addition: series.csv's
    /// `wallK_mean_force_*_N` after all other columns; what LAMMPS's `fix
    /// ave/time 1 N N` writes, docs/export-lammps.md, "Wall forces: one
    /// step or every step"). One process only.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub wall_force_mean: bool,
}

/// Most steps a scene may ask for (a typo guard, 10¹²).
pub const MAX_STEPS: u64 = 1_000_000_000_000;

/// `[parallel]` (addition, issue 16): how `mpirun -np N dembound scene`
/// (feature `mpi`) cuts the box. Ignored by runs on one process.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ParallelSection {
    /// Sub-domains along x, y, z; their product must be the number of
    /// ranks, and periodic axes are not split. Default: the grid of least
    /// sub-domain surface for the box.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub grid: Option<[usize; 3]>,
    /// Move the cuts between sub-domains (at a neighbour-list rebuild)
    /// when the largest rank's owned free particles exceed this many times
    /// the mean; > 1, `inf`: never. Default 1.2
    /// (`comm::distributed::balance`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rebalance_threshold: Option<f64>,
    /// With `--out`: each rank writes the spheres it owns at each snapshot
    /// as its own piece (`snapshot_NNNNNN_rank_R.vtp`), indexed by
    /// `snapshot_NNNNNN.pvtp`, instead of rank 0 gathering every sphere
    /// into `snapshot_NNNNNN.vtp` (default false).
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub vtk_per_rank: bool,
    /// With `--out`: each rank writes the bodies it owns and its pairs'
    /// histories as its own part of the checkpoint
    /// (`checkpoint_rank_R.cbor`), indexed by `checkpoint.cbor`, instead
    /// of rank 0 gathering the whole state (default false;
    /// `io::checkpoint_parts`).
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub checkpoint_per_rank: bool,
    /// Exchange the halo's per-step state while the pairs that need none
    /// of it are computed; false (default): before the force stage, then
    /// the engine's own loop (fewer instructions; on one node the
    /// blocking exchange is short: BENCHMARKS.md, "Two ranks at 10k:
    /// halo buffers"). The same bits either way (`dynamics::halo_split`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub halo_overlap: Option<bool>,
}

impl ParallelSection {
    pub fn is_default(&self) -> bool {
        self == &Self::default()
    }
}

impl SceneFile {
    /// `motion.gravity`: finite, zero or in [`limits::GRAVITY`].
    pub(super) fn validate_motion(&self) -> Result<(), SceneError> {
        finite3("motion.gravity", self.motion.gravity, "m/s²")?;
        let g = limits::norm(self.motion.gravity);
        check(
            g == 0.0 || limits::within(g, limits::GRAVITY),
            "motion.gravity",
            format!("{:?} (|g| = {} m/s²)", self.motion.gravity, limits::show(g)),
            &format!("|g| = 0 or {}", limits::describe(limits::GRAVITY, "m/s²")),
        )?;
        Ok(())
    }

    pub(super) fn validate_integration(&self) -> Result<(), SceneError> {
        let n = &self.integration;
        match (n.dt, n.eta) {
            (Some(dt), None) => positive("integration.dt", dt, "s")?,
            (None, Some(eta)) => {
                check(eta > 0.0 && eta <= 1.0, "integration.eta", eta, "0 < η ≤ 1")?
            }
            (Some(_), Some(_)) => {
                return Err(invalid(
                    "integration.dt",
                    "given with integration.eta",
                    "one of dt and eta",
                ))
            }
            (None, None) => return Err(invalid("integration.dt", "missing", "give dt (s) or eta")),
        }
        if let Some(v) = n.impact_speed {
            positive("integration.impact_speed", v, "m/s")?;
        }
        match (n.steps, n.duration) {
            (Some(s), None) => check(
                (1..=MAX_STEPS).contains(&s),
                "integration.steps",
                s,
                &format!("1 ≤ steps ≤ {MAX_STEPS}"),
            )?,
            (None, Some(t)) => positive("integration.duration", t, "s")?,
            (Some(_), Some(_)) => {
                return Err(invalid(
                    "integration.steps",
                    "given with integration.duration",
                    "one of steps and duration",
                ))
            }
            (None, None) => {
                return Err(invalid(
                    "integration.steps",
                    "missing",
                    "give steps or duration (s)",
                ))
            }
        }
        if let Some(s) = n.skin {
            positive("integration.skin", s, "m")?;
        }
        Ok(())
    }

    /// The output intervals, each ≥ 1 step.
    pub(super) fn validate_output(&self) -> Result<(), SceneError> {
        let o = &self.output;
        if let Some(every) = o.every {
            check(every >= 1, "output.every", every, "≥ 1 step")?;
        }
        if let Some(every) = o.series_every {
            check(every >= 1, "output.series_every", every, "≥ 1 step")?;
        }
        Ok(())
    }

    /// The MPI grid and the re-balance threshold.
    pub(super) fn validate_parallel(&self) -> Result<(), SceneError> {
        if let Some(g) = self.parallel.grid {
            check(
                g.iter().all(|&k| (1..=1 << 20).contains(&k)),
                "parallel.grid",
                format!("{g:?}"),
                "three sub-domain counts, each ≥ 1 (their product: the number of MPI ranks)",
            )?;
        }
        if let Some(t) = self.parallel.rebalance_threshold {
            check(
                t > 1.0,
                "parallel.rebalance_threshold",
                t,
                "> 1 (largest over mean of the ranks' free particles; inf: never re-balance)",
            )?;
        }
        Ok(())
    }
}
