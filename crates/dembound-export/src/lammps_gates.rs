//! Walls that appear and vanish (`[[wall]] active = { from, to }`, issue
//! 28) in the LAMMPS scene deck: the run is written in segments, `run N₁`,
//! then the switch (`fix wall/gran` written or `unfix`ed, with the wall's
//! force columns and contact count), then `run N₂`, as LAMMPS users
//! script a gate. The steps are dembound's: a wall acts on states
//! `on..off`, `on` the first state n with n Δt ≥ t₀ and `off` the first
//! with n Δt ≥ t₁ (`ActiveWindow::steps`).
//!
//! **The half kick at a switch.** dembound switches before the forces of
//! the state of the switch, so both half kicks around state `off` use
//! forces without the wall. LAMMPS's `run` ending at `off` has already
//! given the spheres the second half kick of the wall's force at `off`
//! (velocity Verlet: v(n+1) = v(n+½) + Δt/2 F(n+1)/m). The deck takes it
//! back before the `unfix`: v −= Δt/2 F_wall/m per sphere, F_wall the
//! force the `fix wall/gran` stored at that step (its `contacts` array,
//! columns 2–4), so a sphere resting on a gate that opens falls as in
//! dembound. Not corrected: the angular half kick of a frictional
//! wall's torque at `off` (dt/2 τ/I on the spheres touching the gate as
//! it opens), and a wall that appears where a sphere already overlaps
//! it (that sphere lacks the half kick Δt/2 F/m of the new contact at
//! state `on`); a switch at the run's last state is not written (the
//! run ends before it acts).

use std::fmt::Write as _;

use dembound_scene::setup::WallSetup;
use dembound_scene::SceneSetup;

use crate::{Error, Result};

/// The states (`on`, `off`) each wall acts on (`on..off`; (0, u64::MAX)
/// for a wall without `active`), at step `dt` (s). Refuses `active` on a
/// wall the deck does not write as a `fix wall/gran` (walls of boundary
/// particles), naming the key.
pub(crate) fn windows(setup: &SceneSetup, dt: f64) -> Result<Vec<(u64, u64)>> {
    let mut out = Vec::with_capacity(setup.walls.len());
    for (w, wall) in setup.walls.iter().enumerate() {
        match setup.wall_active.get(w).copied().flatten() {
            None => out.push((0, u64::MAX)),
            Some(window) => {
                if !matches!(wall, WallSetup::Plane(_)) {
                    return Err(Error::Export(format!(
                        "`wall[{w}].active` cannot be exported: the LAMMPS deck switches plane \
                         walls only (a `fix wall/gran` unfixed between runs); wall[{w}] is a \
                         {}; remove `wall[{w}].active` to export the scene",
                        wall.key()
                    )));
                }
                out.push(window.steps(dt));
            }
        }
    }
    Ok(out)
}

/// Whether a wall with window `(on, off)` acts at state 0.
pub(crate) fn on_at_start((on, off): (u64, u64)) -> bool {
    on == 0 && off > 0
}

/// What the deck writes at a switch of one plane wall.
pub(crate) struct PlaneSwitch {
    /// The wall's index in `[[wall]]`.
    pub wall: usize,
    /// The `fix wall/gran` lines of the wall (one per free type).
    pub fixes_text: String,
    /// The fix ids with the group of free type each acts on.
    pub fixes: Vec<(String, String)>,
    /// The wall's contact-count formula (`variable in_wallW atom …`).
    pub in_wall: String,
    /// The wall's force columns (`lammps_output::plane_force_lines`).
    pub force_lines: String,
}

/// The switches within a run of `steps` steps of the walls `items` (the
/// wall of each by `wall`; `windows` per wall: its first step and the
/// first step without it): (step, arrives, item), in step order; at one
/// step walls leave before others arrive (both at the same state: the
/// order does not change the forces), then in wall order. Shared by the
/// LAMMPS and LIGGGHTS decks.
pub(crate) fn switch_events<'a, T>(
    steps: u64,
    windows: &[(u64, u64)],
    items: &'a [T],
    wall: impl Fn(&T) -> usize,
) -> Vec<(u64, bool, &'a T)> {
    let mut events = Vec::new();
    for item in items {
        let (on, off) = windows[wall(item)];
        if on >= off {
            continue;
        }
        if on > 0 && on < steps {
            events.push((on, true, item));
        }
        if off < steps {
            events.push((off, false, item));
        }
    }
    events.sort_by_key(|&(step, arrives, item)| (step, arrives, wall(item)));
    events
}

/// The `run` commands of a run of `steps` steps of `dt` (s), with the
/// switches of the gated plane walls (`windows` per wall) in between.
/// With `outlets`, the spheres in the outlets are removed at every
/// multiple of `outlets::EVERY` steps (`outlets::run_lines`).
pub(crate) fn runs(
    steps: u64,
    dt: f64,
    windows: &[(u64, u64)],
    planes: &[PlaneSwitch],
    outlets: Option<&crate::outlets::Outlets>,
) -> String {
    let events = switch_events(steps, windows, planes, |p| p.wall);
    let mut x = String::new();
    let mut done = 0;
    for (step, arrives, p) in events {
        if step > done {
            x.push_str(&crate::outlets::run_lines(done, step - done, outlets));
            done = step;
        }
        x.push_str(&switch_text(step, arrives, p, dt));
    }
    x.push_str(&crate::outlets::run_lines(done, steps - done, outlets));
    x
}

/// What the deck writes at the switch of plane `p` at state `step`
/// (`arrives`: the wall appears, else it vanishes), steps of `dt` (s),
/// between the run that ends at `step` and the next.
pub(crate) fn switch_text(step: u64, arrives: bool, p: &PlaneSwitch, dt: f64) -> String {
    let mut x = String::new();
    let w = p.wall;
    if arrives {
        writeln!(
            x,
            "# wall[{w}] appears at step {step} (t = {} s)",
            crate::num(step as f64 * dt)
        )
        .ok();
        x.push_str(&p.fixes_text);
        x.push_str(&p.in_wall);
        x.push_str(&p.force_lines);
    } else {
        writeln!(
            x,
            "# wall[{w}] vanishes at step {step} (t = {} s): take back the half kick of its force at this step\n\
             # (dembound's state {step} has no force of wall[{w}]), then remove it",
            crate::num(step as f64 * dt)
        )
        .ok();
        for (fix, group) in &p.fixes {
            for (k, c) in ["x", "y", "z"].iter().enumerate() {
                writeln!(
                    x,
                    "variable     gate_v atom v{c}-{}*f_{fix}[{}]/mass\n\
                     set          group {group} v{c} v_gate_v",
                    crate::num(0.5 * dt),
                    k + 2
                )
                .ok();
            }
        }
        writeln!(x, "variable     gate_v delete").ok();
        for (fix, _) in &p.fixes {
            for c in ["x", "y", "z"] {
                writeln!(x, "uncompute    {fix}_{c}").ok();
            }
            writeln!(x, "unfix        {fix}").ok();
        }
        writeln!(x, "variable     in_wall{w} atom 0").ok();
        for c in ["x", "y", "z"] {
            writeln!(x, "variable     w{w}{c} equal 0").ok();
        }
    }
    x
}
