//! Export of a dembound bounce scenario to other DEM codes, and the way
//! back.
//!
//! [`plan::Plan`] resolves a [`Scenario`] into the numbers every code needs
//! (radii, masses, the pre-mixed effective modulus, the law's stiffness and
//! damping coefficient, Δt from dembound's rule, where the spheres start,
//! and the step windows around each exact contact in which the deck writes
//! a per-step trace). One writer per code turns a plan into files:
//! [`lammps`], [`liggghts`], [`yade`]. [`trace`] reads the trace back and
//! measures h_max, T_c, v_c, v_r and e from it.
//!
//! Every deck writes the same trace format (`trace.txt`): one line per
//! step, `time (s) overlap (m) relative velocity (m/s, upward positive)
//! contact force on the particle (N, upward positive)`, `#` comments.

pub mod agreement;
pub mod lammps;
mod lammps_friction;
mod lammps_gates;
mod lammps_inlets;
mod lammps_motion;
pub mod lammps_output;
pub mod lammps_scene;
pub mod liggghts;
mod liggghts_contact;
mod liggghts_gates;
pub mod liggghts_inlets;
mod liggghts_motion;
pub mod liggghts_scene;
mod outlets;
pub mod plan;
pub mod scene_dump;
pub mod trace;
pub mod yade;
pub mod yade_rolling;
pub mod yade_scene;

use dembound_core::bounce::Scenario;

/// The codes a scenario can be exported to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Code {
    Lammps,
    Liggghts,
    Yade,
}

impl Code {
    /// The code's own spelling, as refusals name it.
    pub fn title(&self) -> &'static str {
        match self {
            Code::Lammps => "LAMMPS",
            Code::Liggghts => "LIGGGHTS",
            Code::Yade => "Yade",
        }
    }

    pub fn name(&self) -> &'static str {
        match self {
            Code::Lammps => "lammps",
            Code::Liggghts => "liggghts",
            Code::Yade => "yade",
        }
    }

    /// The input file the deck starts from.
    pub fn input_file(&self) -> &'static str {
        match self {
            Code::Lammps => "in.lammps",
            Code::Liggghts => "in.liggghts",
            Code::Yade => "bounce.py",
        }
    }

    /// The command that runs the deck inside its directory.
    pub fn command(&self) -> &'static str {
        match self {
            Code::Lammps => "lmp -in in.lammps -log log.lammps",
            Code::Liggghts => "liggghts -in in.liggghts -log log.liggghts",
            Code::Yade => "yade -n -x bounce.py",
        }
    }
}

/// Known wrong settings a deck can be written with on purpose, to show by
/// number what they do (docs/export-lammps.md). Never the default.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Pitfall {
    /// LAMMPS: the boundary as `fix wall/gran … hertz/material E_b 0 ν_b`,
    /// a plane given the boundary's own modulus (LAMMPS then treats the
    /// particle as E_b too).
    WallMaterial,
    /// LAMMPS: per-type `pair_coeff i i hertz/material` for the particle and
    /// the frozen boundary sphere, the cross pair left to LAMMPS's mixing.
    AutoMix,
    /// Yade: the plane as `utils.wall` (the Mindlin functor then takes
    /// R* = R_m/2).
    YadeWall,
    /// Yade: `NewtonIntegrator` left at its default Cundall damping 0.2.
    CundallDamping,
}

impl Pitfall {
    pub fn name(&self) -> &'static str {
        match self {
            Pitfall::WallMaterial => "wall-material",
            Pitfall::AutoMix => "auto-mix",
            Pitfall::YadeWall => "yade-wall",
            Pitfall::CundallDamping => "cundall-damping",
        }
    }

    pub fn parse(s: &str) -> Option<Self> {
        match s {
            "wall-material" => Some(Pitfall::WallMaterial),
            "auto-mix" => Some(Pitfall::AutoMix),
            "yade-wall" => Some(Pitfall::YadeWall),
            "cundall-damping" => Some(Pitfall::CundallDamping),
            _ => None,
        }
    }
}

/// One file of a deck: its name inside the output directory and its text.
#[derive(Debug, Clone, PartialEq)]
pub struct DeckFile {
    pub name: String,
    pub text: String,
}

/// The files of an exported deck.
#[derive(Debug, Clone, PartialEq)]
pub struct Deck {
    pub code: Code,
    pub files: Vec<DeckFile>,
}

/// The crate's one error type. Each variant carries the message users see
/// (it names the key, the code's limitation or the trace's line).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum Error {
    /// A scenario or scene that cannot be exported: a value out of range
    /// or a feature the code lacks.
    #[error("{0}")]
    Export(String),
    /// A trace that cannot be read or measured ([`trace`]).
    #[error("{0}")]
    Trace(String),
}

/// `Result` with the crate's [`Error`].
pub type Result<T, E = Error> = std::result::Result<T, E>;

/// The refusal of a scene with a moving wall (issue 27) by the `code`
/// deck writer, naming the wall's key: the decks write fixed walls only
/// (LIGGGHTS's `fix move/mesh` and moving `wall/gran` are not written).
pub(crate) fn refuse_moving_walls(setup: &dembound_scene::SceneSetup, code: &str) -> Result<()> {
    for (w, m) in setup.wall_motions.iter().enumerate() {
        if let Some(m) = m {
            let key = if m.velocity != [0.0; 3] || m.angular_velocity != [0.0; 3] {
                "motion"
            } else {
                "oscillation"
            };
            return Err(Error::Export(format!(
                "`wall[{w}].{key}` cannot be exported: the {code} deck holds fixed walls only \
                 (moving walls are not written); remove `wall[{w}].motion` and \
                 `wall[{w}].oscillation` to export the scene"
            )));
        }
    }
    Ok(())
}

/// The refusal of a scene with a moving group of fixed spheres (a
/// `[[particles]]` group with `fixed = true` and `motion` or
/// `oscillation`, issue 27) by the `code` deck writer, naming the key:
/// written as still spheres it would be another scene (the LAMMPS deck
/// moves them, `lammps_motion`).
pub(crate) fn refuse_moving_groups(setup: &dembound_scene::SceneSetup, code: &str) -> Result<()> {
    if let Some(g) = setup.group_motions.first() {
        let k = g.group;
        return Err(Error::Export(format!(
            "`particles[{k}].motion` cannot be exported: the {code} deck holds fixed spheres that \
             stay where they are (a moving group is written to LAMMPS only, as fix move); remove \
             `particles[{k}].motion` and `particles[{k}].oscillation` to export the scene"
        )));
    }
    Ok(())
}

/// The refusal of a scene that removes spheres (`[[outlet]]` or
/// `domain.outside = "delete"`, issue 28) by the `code` deck writer (the
/// Yade deck: no removal written).
pub(crate) fn refuse_removal(setup: &dembound_scene::SceneSetup, code: &str) -> Result<()> {
    if !setup.outlets.is_empty() {
        return Err(Error::Export(format!(
            "`outlet[0]` cannot be exported: the {code} deck has no removal by dembound's rule \
             (a centre inside the region, touching nothing); remove the [[outlet]] sections to \
             export the scene (the LAMMPS and LIGGGHTS decks write outlets)"
        )));
    }
    refuse_lost_removal(setup, code)
}

/// The refusal of `domain.outside = "delete"` by the `code` deck writer:
/// LAMMPS's `thermo_modify lost ignore` drops an atom the moment it
/// crosses a face of a fixed boundary, where dembound removes a sphere
/// wholly outside the box grown to hold the fixed spheres, moving away
/// and touching nothing; the decks would not run the same scene.
pub(crate) fn refuse_lost_removal(setup: &dembound_scene::SceneSetup, code: &str) -> Result<()> {
    if setup.outside == dembound_scene::setup::Outside::Delete {
        return Err(Error::Export(format!(
            "`domain.outside = \"delete\"` cannot be exported: the {code} deck has no removal \
             of lost spheres by dembound's rule (wholly outside the box, moving away, touching \
             nothing); set domain.outside to \"error\" or \"keep\" to export the scene"
        )));
    }
    Ok(())
}

/// The refusal of a scene with inlets (`[[inlet]]`, issue 28) by the
/// `code` deck writer, `why` the code's reason.
pub(crate) fn refuse_inlets(
    setup: &dembound_scene::SceneSetup,
    code: &str,
    why: &str,
) -> Result<()> {
    if !setup.inlets.is_empty() {
        return Err(Error::Export(format!(
            "`inlet[0]` cannot be exported: {why}; remove the [[inlet]] sections to export the \
             scene to {code}"
        )));
    }
    Ok(())
}

/// The refusal of a scene with no free sphere (every `[[particles]]`
/// group `fixed = true`, no `[[inlet]]`) by the `code` deck writer: the
/// decks integrate the free spheres and would run nothing.
pub(crate) fn no_free_sphere(code: &str) -> Error {
    Error::Export(format!(
        "the scene has no free sphere to export to {code}: every `particles[K].fixed` is true \
         and there is no [[inlet]]; give a group `fixed = false` (or an inlet) to export the scene"
    ))
}

/// The refusal of a scene with a force-controlled wall (issue 27,
/// `[[wall]] servo`) by the `code` deck writer, naming the wall's key:
/// the decks do not write LIGGGHTS's `servo` mesh module (nor has LAMMPS
/// one).
pub(crate) fn refuse_servo_walls(setup: &dembound_scene::SceneSetup, code: &str) -> Result<()> {
    if let Some(w) = setup.wall_servos.iter().position(Option::is_some) {
        return Err(Error::Export(format!(
            "`wall[{w}].servo` cannot be exported: the {code} deck holds no force-controlled \
             wall (the servo is not written); remove `wall[{w}].servo` to export the scene"
        )));
    }
    Ok(())
}

/// The refusal of a scene with a wall that appears or vanishes (`[[wall]]
/// active`, issue 28) by the `code` deck writer, naming the wall's key:
/// dembound switches a wall at the first step n with n Δt ≥ t (its
/// contacts' springs dropped, their energy booked); a deck would need
/// `run N₁`, `unfix`, `run N₂` with the same step counts, which is not
/// written yet.
pub(crate) fn refuse_gates(setup: &dembound_scene::SceneSetup, code: &str) -> Result<()> {
    if let Some(w) = setup.wall_active.iter().position(Option::is_some) {
        return Err(Error::Export(format!(
            "`wall[{w}].active` cannot be exported: the {code} deck holds walls that act for \
             the whole run (a wall switched on or off is not written); remove \
             `wall[{w}].active` to export the scene"
        )));
    }
    Ok(())
}

/// The deck of `scenario` for `code` (`pitfall`: a known-wrong variant,
/// for the code it belongs to).
pub fn export(code: Code, scenario: &Scenario, pitfall: Option<Pitfall>) -> Result<Deck> {
    // The plan is the same for every code: its refusals (a law or a value
    // no deck takes) get the code named here.
    let plan = plan::Plan::new(scenario).map_err(|e| {
        Error::Export(format!(
            "the scenario cannot be exported to {}: {e}",
            code.title()
        ))
    })?;
    let for_code = match pitfall {
        None => code,
        Some(Pitfall::WallMaterial | Pitfall::AutoMix) => Code::Lammps,
        Some(Pitfall::YadeWall | Pitfall::CundallDamping) => Code::Yade,
    };
    if for_code != code {
        return Err(Error::Export(format!(
            "--pitfall {} is a {} pitfall, not one of {} (see docs/export-{}.md)",
            pitfall.map_or("", |p| p.name()),
            for_code.name(),
            code.name(),
            code.name()
        )));
    }
    let input = match code {
        Code::Lammps => lammps::deck(&plan, pitfall)?,
        Code::Liggghts => liggghts::deck(&plan)?,
        Code::Yade => yade::deck(&plan, pitfall)?,
    };
    Ok(Deck {
        code,
        files: vec![DeckFile {
            name: code.input_file().into(),
            text: input,
        }],
    })
}

/// A short fingerprint of a scenario (FNV-1a over its resolved values),
/// written into the trace's header by every deck so that `dembound
/// compare` can refuse a trace left by a deck of another scenario.
pub fn fingerprint(scenario: &Scenario) -> String {
    // FNV-1a, 64 bit: a few lines, stable across Rust versions (unlike
    // std's DefaultHasher); not a security hash.
    let text = format!("{:?}", scenario.resolved());
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for b in text.bytes() {
        h ^= u64::from(b);
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    format!("{h:016x}")
}

/// The first header line of every trace.
pub fn trace_title(scenario: &Scenario) -> String {
    format!(
        "# time_s overlap_m velocity_m_s force_N scenario={}",
        fingerprint(scenario)
    )
}

/// A number as the decks write it: the shortest text that reads back to
/// the same f64 (Rust's `{:e}`), which LAMMPS, LIGGGHTS and Python parse.
pub fn num(x: f64) -> String {
    if x == 0.0 {
        "0".into()
    } else {
        format!("{x:e}")
    }
}
