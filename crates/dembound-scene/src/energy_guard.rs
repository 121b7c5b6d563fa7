//! The energy balance as a run-time guard (issue 24): a run that creates
//! energy stops with an error instead of reporting numbers.
//!
//! The balance: kinetic K + elastic E + potential P + dissipated D, with D
//! the initial K + E + P minus the current one ([`Observation`]); with
//! moving walls (issue 27) plus the work W they did on the spheres, so
//! that K + E + P + D − W is the initial energy and a drum or a piston
//! that feeds energy in does not read as a gain. W counts in the scale as
//! the work of gravity does. It closes
//! by construction, so what tells a sound run from one that creates energy
//! is the sign of D: contacts, damping and friction only ever take energy
//! out; a negative D is energy made by the integration error (a step too
//! large for the stiffness, a body too light or too stiff) or by a
//! geometry the contacts cannot resolve (a deep overlap).
//!
//! **The scale** the gain is measured against does not depend on where the
//! potential energy's zero is: the largest K + E + |P − P₀| + |D| seen so
//! far (P₀ the potential at the run's first check: |P − P₀| is the work of
//! gravity). **The allowed gain** is [`MAX_ENERGY_GAIN`] of the scale plus
//! the rounding of D, [`ROUNDING`] × (K + E + |P| + |initial|) (D is a
//! difference of sums whose terms may be large when P's zero is far away).
//!
//! Why 1e-3 ([`MAX_ENERGY_GAIN`]): the integration error of a sound run
//! makes D slightly negative on undamped scenes, and that error grows with
//! Δt/T_c. Measured (`dembound scene --json`, `energy_balance.drift_relative`
//! over the whole run, see the README): at most 1.1e-5 on the example
//! scenes (the validation drop, Gear5), 2.4e-5 on the undamped lattice
//! drop under Gear5, and 2.4e-4 on it under Verlet at 0.34 T_c (near the
//! step bound).
//! The energy-creating scenes of issue 24 gain 1e-2 to 1e13 of the scale.
//!
//! The guard checks each observation the run takes (the time series, the
//! end): no pass of its own. The CLI, MPI, Python's `step` and the wall
//! study's impacts, beds and chutes run under it (`Simulation::step_guarded`).
//!
//! **Not judged: gravity along a periodic axis** (a periodic chute). P is
//! computed from positions folded into the box, so a sphere that leaves
//! through one face and enters through the other changes P by m g_a L_a
//! although nothing happened, and D (hence the gain) jumps by as much. Such
//! a run's balance is reported with `checked = false` and the reason; the
//! finite-state check still applies. (The fix is the unfolded position
//! through image counts, carried over migrations and checkpoints.)

use serde::Serialize;

use crate::error::SceneError;
use crate::limits;
use crate::setup::{SceneSetup, Scheme};
use crate::simulation::Observation;
use crate::time_step;

/// The largest energy gain allowed, as a fraction of the scale (module doc).
pub const MAX_ENERGY_GAIN: f64 = 1e-3;
/// Rounding allowance of D per joule of the terms it is computed from.
pub const ROUNDING: f64 = 1e-10;

/// The energy balance of a run at one observation, J (`--json`
/// `energy_balance`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct EnergyBalance {
    /// K + E + P at t = 0, J (the reference of `dissipated_energy`).
    pub total_initial: f64,
    /// K + E + P + D − W now, J (equal to `total_initial` up to
    /// rounding; W the moving walls' work, 0 without).
    pub total: f64,
    /// W: the work done on the spheres by the moving walls, J (absent
    /// when every wall is fixed).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub work_by_walls: Option<f64>,
    /// C: the energy the removed spheres carried out, J (`crate::removal`;
    /// absent when the scene removes none); `total` is then
    /// K + E + P + D − W + C.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub carried_out_energy: Option<f64>,
    /// G: the elastic energy the walls that vanished took out of their
    /// contacts less what the walls that appeared put in, J
    /// (`walls::gate`; absent when every wall acts always); `total` is then
    /// K + E + P + D − W + C + G.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub gate_energy: Option<f64>,
    /// I: the energy the inserted spheres brought in, J (`crate::inlets`;
    /// absent without inlets); `total` is then K + E + P + D − W + C (+ G) − I.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub brought_in_energy: Option<f64>,
    /// The guard's scale: the largest K + E + |P − P₀| + |D| seen, J.
    pub scale: f64,
    /// The largest energy gained (−D) at any check, J (0: never).
    pub drift: f64,
    /// The largest gain over the scale at any check.
    pub drift_relative: f64,
    /// The gain over the scale that stops a run ([`MAX_ENERGY_GAIN`]).
    pub drift_allowed: f64,
    /// Whether the guard judges this run's gain (false: see `unchecked`).
    pub checked: bool,
    /// Why the gain is not judged (gravity along a periodic axis).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub unchecked: Option<&'static str>,
    /// D_c: the dissipated energy summed contact by contact, J
    /// (`output.dissipation`; absent when off).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub dissipated_by_contacts: Option<f64>,
    /// The balance error E₀ + W − C − G + I − (K + E + P + D_c) = D − D_c
    /// now, J: energy gone that no contact took out (negative: energy
    /// created); absent without `output.dissipation`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub balance_error: Option<f64>,
    /// The largest |balance error| over the scale at any check.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub balance_error_relative: Option<f64>,
    /// The |balance error| over the scale that stops a run
    /// ([`balance_allowance`]).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub balance_error_allowed: Option<f64>,
}

/// The balance error the guard allows, as a fraction of the scale, for a
/// step `dt` (s) and smallest contact time `contact_time` (s; `None`:
/// unknown): velocity Verlet keeps a shadow energy of a linear contact
/// of angular frequency ω = π/T_c, H̃ = H − (ωΔt)²/8 · ω² h² m*, so its
/// energy (the balance's K + E) is off by up to (ωΔt)²/4 of the contact's
/// energy while it lasts, and each collision that starts or ends between
/// steps keeps an error of that order. Summed over the collisions their
/// signs mix; [`BALANCE_FACTOR`] × (ωΔt)² of the scale (which holds
/// every joule that went in or out) bounds what the example scenes
/// measured (README, "Energy balance"). At least [`MAX_ENERGY_GAIN`]
/// when the contact time is unknown.
pub fn balance_allowance(dt: f64, contact_time: Option<f64>) -> f64 {
    match contact_time {
        Some(t) if t > 0.0 && t.is_finite() => {
            let w_dt = std::f64::consts::PI * dt / t;
            BALANCE_FACTOR * w_dt * w_dt
        }
        _ => MAX_ENERGY_GAIN,
    }
}

/// The multiple of (ωΔt)² of the scale the balance error may reach
/// ([`balance_allowance`]).
pub const BALANCE_FACTOR: f64 = 1.0;

/// The guard's state over a run.
#[derive(Debug, Clone)]
pub struct EnergyGuard {
    reference_potential: Option<f64>,
    initial_elastic: f64,
    scale: f64,
    drift: f64,
    drift_relative: f64,
    /// What to blame, worked out from the setup (extreme inputs, the step).
    suspects: Vec<String>,
    step: String,
    /// Why the gain is not judged, if it is not (module doc).
    unchecked: Option<&'static str>,
    /// The balance error allowed over the scale ([`balance_allowance`]).
    balance_allowed: f64,
    /// The largest |balance error| over the scale seen.
    balance_relative: f64,
}

/// The reason the gain of a periodic chute is not judged (module doc).
pub const PERIODIC_GRAVITY: &str = "gravity has a component along a periodic axis: the potential \
     energy of positions folded into the box jumps by m g L when a sphere crosses that axis's \
     faces, so the dissipated energy is not a balance there";

impl EnergyGuard {
    /// A guard for a run of `setup` at step `dt` (s).
    pub fn new(setup: &SceneSetup, dt: f64) -> Self {
        Self {
            reference_potential: None,
            initial_elastic: 0.0,
            scale: 0.0,
            drift: 0.0,
            drift_relative: 0.0,
            suspects: extreme_inputs(setup),
            step: step_share(setup, dt),
            balance_allowed: balance_allowance(
                dt,
                time_step::step_bound(setup).map(|b| b.contact_time),
            ),
            balance_relative: 0.0,
            unchecked: (0..3)
                .any(|a| setup.domain.periodic[a] && setup.gravity[a] != 0.0)
                .then_some(PERIODIC_GRAVITY),
        }
    }

    /// Records observation `o` of a run whose K + E + P at t = 0 was
    /// `initial` (J); an error when it has created more energy than allowed
    /// or its energies are no longer finite.
    pub fn check(&mut self, o: &Observation, initial: f64) -> Result<(), SceneError> {
        let (k, e, p, d) = (
            o.kinetic_energy,
            o.elastic_energy,
            o.potential_energy,
            o.dissipated_energy,
        );
        let p0 = *self.reference_potential.get_or_insert_with(|| {
            self.initial_elastic = e;
            p
        });
        let work = o.work_by_walls.unwrap_or(0.0);
        // The energy the removed spheres carried out (`crate::removal`).
        let carried = o.removed.map_or(0.0, |r| r.energy);
        // The gates' energy (`walls::gate`): booked like C.
        let carried = match o.gate_energy {
            None => carried,
            Some(g) => carried + g.abs(),
        };
        // The energy the inserted spheres brought in (`crate::inlets`).
        let brought = crate::inlets::brought_in(o);
        let finite = [k, e, p, d, initial, work, carried, brought.unwrap_or(0.0)]
            .iter()
            .all(|x| x.is_finite());
        if finite {
            // The walls' work is energy put in as gravity's is.
            let scale = match o.work_by_walls {
                None => k + e + (p - p0).abs() + d.abs(),
                Some(w) => k + e + (p - p0).abs() + d.abs() + w.abs(),
            };
            let scale = match o.removed {
                None => scale,
                Some(r) => scale + r.energy.abs(),
            };
            let scale = match o.gate_energy {
                None => scale,
                Some(g) => scale + g.abs(),
            };
            let scale = match brought {
                None => scale,
                Some(i) => scale + i.abs(),
            };
            self.scale = self.scale.max(scale);
        }
        let gain = -d;
        let allowed = MAX_ENERGY_GAIN * self.scale
            + ROUNDING
                * (k + e
                    + p.abs()
                    + initial.abs()
                    + work.abs()
                    + carried.abs()
                    + brought.map_or(0.0, f64::abs));
        if finite && gain > self.drift {
            self.drift = gain;
        }
        if finite && self.scale > 0.0 {
            self.drift_relative = self.drift_relative.max(gain / self.scale);
        }
        if !(finite && (gain <= allowed || self.unchecked.is_some())) {
            return Err(SceneError::Input(self.message(o, initial, allowed)));
        }
        // With D_c (`output.dissipation`): the balance error, both ways.
        let Some(dc) = o.dissipated_by_contacts else {
            return Ok(());
        };
        let error = d - dc;
        let rounding = allowed - MAX_ENERGY_GAIN * self.scale;
        let limit = self.balance_allowed * self.scale + rounding;
        if self.scale > 0.0 && error.is_finite() {
            self.balance_relative = self.balance_relative.max(error.abs() / self.scale);
        }
        if (error.abs() <= limit && error.is_finite()) || self.unchecked.is_some() {
            return Ok(());
        }
        Err(SceneError::Input(format!(
            "the energy balance does not close: by step {} (t = {:.6e} s) the contacts dissipated \
             {:.6e} J but the balance lost {:.6e} J, an error of {:.3e} J = {:.3e} of the energy \
             scale {:.4e} J where at most {:.3e} ((π Δt/T_c)², the integration error) is allowed; \
             likely cause: {}. Nothing was written",
            o.step,
            o.time,
            dc,
            d,
            error,
            error / self.scale.max(f64::MIN_POSITIVE),
            self.scale,
            self.balance_allowed,
            self.step
        )))
    }

    fn message(&self, o: &Observation, initial: f64, allowed: f64) -> String {
        let what = if o.dissipated_energy.is_finite() {
            format!(
                "the run created energy: by step {} (t = {:.6e} s) the dissipated energy is {:.4e} J \
                 (kinetic {:.4e} J + elastic {:.4e} J + potential {:.4e} J now against {:.4e} J at \
                 t = 0), a gain of {:.3e} of the energy scale {:.4e} J where at most {MAX_ENERGY_GAIN:e} \
                 ({:.4e} J) is integration error",
                o.step,
                o.time,
                o.dissipated_energy,
                o.kinetic_energy,
                o.elastic_energy,
                o.potential_energy,
                initial,
                -o.dissipated_energy / self.scale.max(f64::MIN_POSITIVE),
                self.scale,
                allowed
            )
        } else {
            format!(
                "the energy is no longer finite by step {} (t = {:.6e} s): kinetic {:e} J, elastic \
                 {:e} J, potential {:e} J",
                o.step, o.time, o.kinetic_energy, o.elastic_energy, o.potential_energy
            )
        };
        let cause = if !self.suspects.is_empty() {
            format!(
                "likely cause: an extreme input ({}), not the step",
                self.suspects.join("; ")
            )
        } else if self.initial_elastic > 0.01 * self.scale {
            format!(
                "likely cause: initial overlaps (the contacts held {:.4e} J at the start, {:.1} % \
                 of the energy scale): separate the spheres",
                self.initial_elastic,
                100.0 * self.initial_elastic / self.scale
            )
        } else {
            format!("likely cause: {}", self.step)
        };
        format!("{what}; {cause}. Nothing was written")
    }

    /// The inputs far out of range found in the setup (empty: none).
    pub fn extreme_inputs(&self) -> &[String] {
        &self.suspects
    }

    /// The balance at observation `o` of a run whose K + E + P at t = 0
    /// was `initial` (J), with the largest gain seen.
    pub fn balance(&self, o: &Observation, initial: f64) -> EnergyBalance {
        EnergyBalance {
            total_initial: initial,
            total: match (o.work_by_walls, o.removed) {
                (None, None) => {
                    o.kinetic_energy + o.elastic_energy + o.potential_energy + o.dissipated_energy
                }
                (Some(w), None) => {
                    o.kinetic_energy + o.elastic_energy + o.potential_energy + o.dissipated_energy
                        - w
                }
                (w, Some(r)) => {
                    o.kinetic_energy + o.elastic_energy + o.potential_energy + o.dissipated_energy
                        - w.unwrap_or(0.0)
                        + r.energy
                } // (−0.0 adds nothing to any sum, −0.0 included.)
            } + o.gate_energy.unwrap_or(-0.0)
                - crate::inlets::brought_in(o).unwrap_or(0.0),
            work_by_walls: o.work_by_walls,
            carried_out_energy: o.removed.map(|r| r.energy),
            gate_energy: o.gate_energy,
            brought_in_energy: crate::inlets::brought_in(o),
            scale: self.scale,
            drift: self.drift,
            drift_relative: self.drift_relative,
            drift_allowed: MAX_ENERGY_GAIN,
            checked: self.unchecked.is_none(),
            unchecked: self.unchecked,
            dissipated_by_contacts: o.dissipated_by_contacts,
            balance_error: o.dissipated_by_contacts.map(|dc| o.dissipated_energy - dc),
            balance_error_relative: o.dissipated_by_contacts.map(|_| self.balance_relative),
            balance_error_allowed: o.dissipated_by_contacts.map(|_| self.balance_allowed),
        }
    }
}

/// The inputs outside the ranges the numerics are known to handle
/// ([`crate::limits`], which `setup_checks` refuses before a run: so this
/// list is empty for any accepted scene and only guards a setup that
/// bypasses those checks).
fn extreme_inputs(setup: &SceneSetup) -> Vec<String> {
    let mut out = Vec::new();
    let outside = |x: f64, (lo, hi): (f64, f64)| !(x >= lo && x <= hi);
    for (k, m) in setup.materials.iter().enumerate() {
        let m_ = &m.material;
        if outside(m_.density, limits::DENSITY) {
            out.push(format!(
                "materials[{k}].density = {:e} kg/m³, usual {}",
                m_.density,
                limits::describe(limits::DENSITY, "")
            ));
        }
        if m_.youngs_modulus.is_finite() && outside(m_.youngs_modulus, limits::YOUNGS_MODULUS) {
            out.push(format!(
                "materials[{k}].youngs_modulus = {:e} Pa, usual {}",
                m_.youngs_modulus,
                limits::describe(limits::YOUNGS_MODULUS, "")
            ));
        }
    }
    if let Some((i, s)) = setup
        .spheres
        .iter()
        .enumerate()
        .find(|(_, s)| outside(s.radius, limits::RADIUS) && !s.fixed)
    {
        out.push(format!(
            "the radius of sphere {i} = {:e} m, usual {}",
            s.radius,
            limits::describe(limits::RADIUS, "")
        ));
    }
    let g = setup.gravity;
    let g_norm = (g[0] * g[0] + g[1] * g[1] + g[2] * g[2]).sqrt();
    if g_norm > limits::GRAVITY.1 {
        out.push(format!(
            "|gravity| = {g_norm:e} m/s², usual up to {}",
            limits::show(limits::GRAVITY.1)
        ));
    }
    if let Some((i, s)) = setup.spheres.iter().enumerate().find(|(_, s)| {
        s.velocity.iter().map(|v| v * v).sum::<f64>().sqrt() > limits::MAX_SPEED && !s.fixed
    }) {
        out.push(format!(
            "the speed of sphere {i} = {:e} m/s, usual up to {}",
            s.velocity.iter().map(|v| v * v).sum::<f64>().sqrt(),
            limits::show(limits::MAX_SPEED)
        ));
    }
    out
}

/// The step against its bound, for the message: "the step Δt = … s is
/// r × T_b …".
fn step_share(setup: &SceneSetup, dt: f64) -> String {
    let scheme = setup.integration.scheme;
    let advice = match scheme {
        Scheme::Verlet => "a smaller integration.dt or integration.eta".to_string(),
        Scheme::Gear5 => "a smaller integration.dt or integration.eta, or scheme = \"verlet\" \
            (Gear5 with friction is unstable at far shorter steps than Verlet on dense damped \
            beds)"
            .to_string(),
    };
    let step = match time_step::step_bound(setup) {
        Some(b) => format!(
            "the step or the contact stiffness: Δt = {dt:e} s is {:.3} × the smallest \
             contact-time estimate {:.4e} s ({}), within the bound of {} but too large for this \
             scene; try {advice}",
            dt / b.contact_time,
            b.contact_time,
            b.pair,
            b.ratio
        ),
        None => format!("the step or the contact stiffness (Δt = {dt:e} s); try {advice}"),
    };
    match spring_work(setup) {
        Some(note) => format!("{step}; {note}"),
        None => step,
    }
}

/// The other cause a frictional scene may have: a tangential spring whose
/// stiffness grows with the overlap (the Mindlin springs, k_t ∝ √h). A
/// loaded spring whose overlap changes gains or loses ½ |δ|² Δk_t
/// (stored displacement) that no potential holds
/// (`FrictionPair::spring_energy` of dembound-physics): the model's own work, which a
/// smaller step does not remove. Damping hides it; without, the guard can
/// see it: `dembound wall-study --quick --particles 0 --chute-time 0
/// --restitution 1` (elastic Hertz, Mindlin μ = 0.5) gained 1.9 % of its
/// energy scale at η = 0.05 and 1.6 % at η = 0.01, none with
/// `--tangential linear` (session 37). `None` without friction or with a
/// constant k_t.
fn spring_work(setup: &SceneSetup) -> Option<String> {
    use dembound_physics::contact::tangential::TangentialKind;
    let f = setup.friction.as_ref()?;
    let mu_given = f.model.friction > 0.0
        || f.materials.iter().flatten().any(|m| m.0 > 0.0)
        || f.walls.iter().flatten().any(|w| w.0 > 0.0);
    let kind = f.model.tangential;
    if !mu_given || kind == TangentialKind::Linear {
        return None;
    }
    Some(format!(
        "or, if a smaller step does not help, the tangential spring itself: under \
         contact.tangential = \"{}\" its stiffness grows with the overlap, and a loaded \
         spring whose overlap changes gains or loses ½ |δ|² Δk_t that no potential holds \
         (the model's work, percents of an undamped impact's energy); damp the contacts \
         (contact.restitution < 1) or use contact.tangential = \"linear\"",
        kind.row().name
    ))
}
