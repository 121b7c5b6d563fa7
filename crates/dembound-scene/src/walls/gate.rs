//! Walls that appear and vanish (issue 28): `[[wall]] active = { from =
//! t₀, to = t₁ }` (s), for planes, cylinders and meshes, fixed or moving:
//! a gate that opens at t₁, a plug pulled, a lid that closes at t₀.
//!
//! **The rule.** A wall acts in the force evaluation of state n, at
//! t_n = n Δt (the f64 product, the outputs' `time`), exactly when
//! t₀ ≤ t_n < t₁: with `on` the first n with n Δt ≥ t₀ and `off` the
//! first n with n Δt ≥ t₁ ([`first_step`]), on states `on..off`. A wall
//! without `active` acts always (t₀ = 0, t₁ = ∞). Outside its window a
//! wall exerts no force, has no contacts and takes no load.
//!
//! **The switch.** The engine switches when it advances to a state at
//! which a wall's status changes (at most twice per wall in a run), before
//! that state's forces: the neighbour lists are rebuilt then, and the
//! near-element search (`WallContacts::refresh`) skips the walls not
//! active and drops their entries with their histories, springs and
//! collision tracks (a contact cut by a wall that vanishes did not
//! complete: the collision log has no row for it). No test per contact
//! per step: the force loops meet only the active walls' entries; a
//! scene without `active` runs as before, to the bit.
//!
//! **The energy.** The elastic energy stored in a vanishing wall's
//! contacts (its normal law's, and with friction its tangential and
//! rolling springs') leaves the system; a wall that appears where spheres
//! overlap it puts the normal law's energy of those overlaps in (its
//! springs start relaxed). Both are booked at the switch, at the state of
//! the switch, as the gate energy G = Σ E_off − Σ E_on, so that
//! K + E + P + D − W + C + G = E₀ (`dissipated_energy` is
//! E₀ + W − C − G − (K + E + P)): a gate that lets go of a loaded bed is not
//! counted as dissipation nor one closing on an overlap as energy created,
//! and the energy guard still judges every other gain. Each process books
//! its own spheres' contacts (its share, summed by the observation like
//! the moving walls' work).
//!
//! **Restarts.** The status is a function of the step: a run restored at
//! step n takes the status of step n (nothing booked), and the checkpoint
//! carries G; so a run restarted before or after a switch continues with
//! the bits of the run in one go.

use serde::{Deserialize, Serialize};

use super::Surface;
use crate::dynamics::contacts::NO_HISTORY;
use crate::error::SceneError;
use crate::io::config::checks::check;
use crate::limits;
use crate::pipeline::World;

/// `active = { from, to }` of a `[[wall]]` entry, s (the window the wall
/// acts in: module doc).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ActiveWindow {
    /// t₀, s (default 0).
    #[serde(default)]
    pub from: f64,
    /// t₁, s (default ∞: never vanishes).
    #[serde(default = "infinite", skip_serializing_if = "is_infinite")]
    pub to: f64,
}

fn infinite() -> f64 {
    f64::INFINITY
}

fn is_infinite(x: &f64) -> bool {
    *x == f64::INFINITY
}

impl ActiveWindow {
    /// The states (`on`, `off`) the wall acts on, `on..off`, at step
    /// `dt` (s): module doc. `off` is `u64::MAX` when t₁ is never reached.
    pub fn steps(&self, dt: f64) -> (u64, u64) {
        (first_step(self.from, dt), first_step(self.to, dt))
    }
}

/// The first state n ≥ 0 with n Δt ≥ `t` (n Δt the f64 product, as the
/// outputs' time), `dt` = Δt (s); `u64::MAX` for t = ∞ or beyond 9e15
/// steps (no run is that long).
pub fn first_step(t: f64, dt: f64) -> u64 {
    if t.is_nan() || t <= 0.0 {
        return 0;
    }
    let guess = (t / dt).ceil();
    if guess.is_nan() || guess >= 9.0e15 {
        return u64::MAX;
    }
    // The quotient's rounding may miss by one either way: settle it on
    // the product the rule compares.
    let mut n = guess as u64;
    while n > 0 && ((n - 1) as f64) * dt >= t {
        n -= 1;
    }
    while (n as f64) * dt < t {
        n += 1;
    }
    n
}

/// Checks `key.active` (`key` = `wall[K]`) of a wall of type `kind` with
/// a servo or not: the first bad value named with its range.
pub fn validate(
    key: &str,
    window: &ActiveWindow,
    kind: &str,
    servo: bool,
) -> Result<(), SceneError> {
    check(
        !crate::walls::registry::is_particles_key(kind),
        &format!("{key}.active"),
        format!("given for a `{kind}` wall"),
        &format!(
            "a {} (walls of boundary particles cannot be switched yet: their spheres \
             sit in the pair lists)",
            crate::walls::registry::surface_kinds_or()
        ),
    )?;
    check(
        !servo,
        &format!("{key}.active"),
        format!("given with `{key}.servo`"),
        "a wall without a servo (a servo steers by its load, which a wall out of its \
         window does not feel: it would run off)",
    )?;
    let w = window;
    check(
        w.from.is_finite() && w.from >= 0.0,
        &format!("{key}.active.from"),
        limits::show(w.from),
        "finite and ≥ 0, in s",
    )?;
    check(
        !w.to.is_nan() && w.to > w.from,
        &format!("{key}.active.to"),
        limits::show(w.to),
        &format!(
            "> active.from = {} s, or inf (never vanishes), in s",
            limits::show(w.from)
        ),
    )
}

/// The switched walls of a world: their windows in steps, which act now,
/// and the gate energy booked.
#[derive(Debug, Clone, PartialEq)]
pub struct Gates {
    /// (index into `World::surfaces`, on, off) of each wall with a window.
    windows: Vec<(usize, u64, u64)>,
    /// Whether each surface (`World::surfaces` order) acts now.
    pub active: Vec<bool>,
    /// G (module doc): this process's share, J.
    pub energy: f64,
}

impl Gates {
    /// The gates of `windows` (file order; missing or `None`: always
    /// active) for `surfaces`, at step `dt` (s), with the status of state
    /// 0; `None` when no wall has a window.
    pub fn new(
        windows: &[Option<ActiveWindow>],
        surfaces: &[Surface],
        dt: f64,
    ) -> Option<Box<Gates>> {
        let windows: Vec<(usize, u64, u64)> = surfaces
            .iter()
            .enumerate()
            .filter_map(|(s, surface)| {
                let w = windows.get(surface.file_index()).copied().flatten()?;
                let (on, off) = w.steps(dt);
                Some((s, on, off))
            })
            .collect();
        (!windows.is_empty()).then(|| {
            let mut g = Gates {
                windows,
                active: vec![true; surfaces.len()],
                energy: 0.0,
            };
            g.active = g.status_at(0);
            Box::new(g)
        })
    }

    /// No window, `surfaces` surfaces acting always, `energy` booked (J):
    /// a restart into a scene without gates keeps the gate energy of
    /// before (`crate::restart_walls`).
    pub fn carrying(surfaces: usize, energy: f64) -> Box<Gates> {
        Box::new(Gates {
            windows: Vec::new(),
            active: vec![true; surfaces],
            energy,
        })
    }

    /// Whether each surface acts at state `step`.
    pub fn status_at(&self, step: u64) -> Vec<bool> {
        let mut active = vec![true; self.active.len()];
        for &(s, on, off) in &self.windows {
            active[s] = on <= step && step < off;
        }
        active
    }

    /// Whether a wall's status changes at state `step` (> 0).
    #[inline]
    pub fn switches_at(&self, step: u64) -> bool {
        step > 0
            && self
                .windows
                .iter()
                .any(|&(_, on, off)| on == step || off == step)
    }
}

impl World {
    /// Before the forces of state `step`: when a wall's status changes
    /// there, books the elastic energy of the contacts of the walls that
    /// vanish (module doc) and takes the new status; the lists must then be
    /// rebuilt, and [`Self::gates_opened`] called with the returned flags
    /// (the surfaces that appear). `None`: nothing switches.
    pub(crate) fn switch_gates(&mut self, step: u64) -> Option<Vec<bool>> {
        let g = self.gates.as_deref()?;
        if !g.switches_at(step) {
            return None;
        }
        let now = g.status_at(step);
        let off: Vec<bool> = (0..now.len()).map(|s| g.active[s] && !now[s]).collect();
        let on: Vec<bool> = (0..now.len()).map(|s| !g.active[s] && now[s]).collect();
        let gone = self.wall_contact_energy(&off);
        if let Some(g) = self.gates.as_deref_mut() {
            g.energy += gone;
            g.active = now;
        }
        Some(on)
    }

    /// After the lists are rebuilt at a switch: books, negative, the
    /// elastic energy of the overlaps with the walls `on` (flags by
    /// surface) that appeared.
    pub(crate) fn gates_opened(&mut self, on: &[bool]) {
        if !on.iter().any(|&x| x) {
            return;
        }
        let came = self.wall_contact_energy(on);
        if let Some(g) = self.gates.as_deref_mut() {
            g.energy -= came;
        }
    }

    /// Sets the status of state `step` (a restore: nothing booked).
    pub(crate) fn set_gates_at(&mut self, step: u64) {
        if let Some(g) = self.gates.as_deref_mut() {
            g.active = g.status_at(step);
        }
    }

    /// The elastic energy, J, of the listed contacts of this process's
    /// free spheres with the surfaces flagged in `walls`: each contact's
    /// normal law at its overlap and history, and with friction its
    /// tangential and rolling springs (as the observables count them).
    /// Bodies in the engine's order, a body's entries ascending.
    pub(crate) fn wall_contact_energy(&self, walls: &[bool]) -> f64 {
        let (b, wc) = (&self.bodies, &self.wall_contacts);
        if !walls.iter().any(|&x| x) || wc.bodies() != b.len() {
            return 0.0;
        }
        let mut e = 0.0;
        for i in (0..b.len()).filter(|&i| !b.fixed[i]) {
            for k in wc.range(i) {
                let key = wc.key[k];
                if !walls.get(key.wall as usize).copied().unwrap_or(false) {
                    continue;
                }
                let surface = &self.surfaces[key.wall as usize];
                let c = surface.contact(key.element, b.position[i], b.velocity[i], b.radius[i]);
                if c.overlap <= 0.0 {
                    continue;
                }
                let slot = surface.law_slot(key.element);
                let law = self.laws.wall(b, i, slot);
                let history = wc.history.get(k).unwrap_or(&NO_HISTORY);
                e += self.laws.elastic_energy(&law, c.overlap, history);
                if let (Some(table), Some(sh)) = (self.friction.as_ref(), wc.shear.get(k)) {
                    let s = &sh.shear;
                    if *s != [0.0; 6] {
                        let mut scratch = None;
                        let fl = table.plane(&self.laws, b, i, slot, &mut scratch);
                        e += fl.spring_energy(c.overlap, &[s[0], s[1], s[2]], &[s[3], s[4], s[5]]);
                    }
                }
            }
        }
        e
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The rule on the f64 product: Δt = 0.1 s is not exact in binary
    /// (3 × 0.1 = 0.30000000000000004 > 0.3), so a window from 0.3 s
    /// starts at state 3, and one from the next f64 above 3 × 0.1 at state
    /// 4 (3 Δt is below it); t = 0 and negatives give state 0, ∞ never.
    #[test]
    fn first_step_compares_the_product() {
        assert_eq!(first_step(0.3, 0.1), 3);
        let dt = std::hint::black_box(0.1f64);
        assert!(3.0 * dt >= 0.3 && 2.0 * dt < 0.3);
        let above = f64::from_bits((3.0 * dt).to_bits() + 1);
        assert!(3.0 * dt < above && 4.0 * dt >= above);
        assert_eq!(first_step(above, 0.1), 4);
        // 7 × 0.1 = 0.7000000000000001 ≥ 0.7, 6 × 0.1 = 0.6000000000000001 < 0.7.
        assert_eq!(first_step(0.7, 0.1), 7);
        assert_eq!(first_step(0.0, 0.1), 0);
        assert_eq!(first_step(-1.0, 0.1), 0);
        assert_eq!(first_step(f64::INFINITY, 0.1), u64::MAX);
        assert_eq!(first_step(1e-6, 1e-6), 1);
        // 2.5e-6/1e-6 = 2.5000000000000004: 3 × 1e-6 ≥ 2.5e-6 > 2 × 1e-6.
        assert_eq!(first_step(2.5e-6, 1e-6), 3);
    }

    /// Each bad value named with its key and range; a good window passes.
    #[test]
    fn bad_windows_are_named() {
        let w = |from, to| ActiveWindow { from, to };
        assert!(validate("wall[0]", &w(0.0, 1.0), "plane", false).is_ok());
        assert!(validate("wall[0]", &w(0.5, f64::INFINITY), "mesh", false).is_ok());
        let msg = |r: Result<(), SceneError>| r.unwrap_err().to_string();
        let m = msg(validate("wall[2]", &w(-1.0, 1.0), "plane", false));
        assert!(m.contains("wall[2].active.from") && m.contains("-1") && m.contains("≥ 0"));
        let m = msg(validate("wall[2]", &w(f64::NAN, 1.0), "plane", false));
        assert!(
            m.contains("wall[2].active.from") && m.contains("NaN"),
            "{m}"
        );
        let m = msg(validate("wall[1]", &w(2.0, 1.0), "cylinder", false));
        assert!(m.contains("wall[1].active.to") && m.contains("> active.from = 2 s"));
        let m = msg(validate("wall[1]", &w(0.0, f64::NAN), "cylinder", false));
        assert!(m.contains("wall[1].active.to"), "{m}");
        let m = msg(validate(
            "wall[3]",
            &w(0.0, 1.0),
            "boundary_particles",
            false,
        ));
        assert!(m.contains("wall[3].active") && m.contains("boundary_particles"));
        let m = msg(validate("wall[3]", &w(0.0, 1.0), "plane", true));
        assert!(m.contains("wall[3].active") && m.contains("servo"));
    }
}
