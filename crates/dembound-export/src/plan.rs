//! A scenario resolved into the numbers every exported deck needs, each
//! with where it comes from (the deck's comment block is written from
//! [`Plan::provenance`]).

use crate::{num, Error, Result};
use dembound_core::bounce::{plan as dembound_plan, ContactRecord, GravityOn, Scenario};
use dembound_core::calibration::damping_coefficient;
use dembound_core::contact::{ContactLawKind, DampingKind};
use dembound_core::exact;

/// The mobile sphere.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Particle {
    /// R_m, m.
    pub radius: f64,
    /// ρ, kg/m³.
    pub density: f64,
    /// m = 4/3 π ρ R_m³, kg.
    pub mass: f64,
    /// E_m, Pa.
    pub youngs_modulus: f64,
    /// ν_m.
    pub poisson_ratio: f64,
    /// Initial height of the centre, m (boundary centre or plane at z = 0).
    pub z: f64,
    /// Initial velocity, m/s, upward positive.
    pub velocity: f64,
}

/// The boundary as the codes see it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Boundary {
    /// A sphere of radius R_b centred at the origin: frozen (`fixed`) or a
    /// free sphere of its own mass (two-sphere collision).
    Sphere {
        radius: f64,
        youngs_modulus: f64,
        poisson_ratio: f64,
        fixed: bool,
        density: f64,
        mass: f64,
        velocity: f64,
    },
    /// r = ∞: the plane z = 0.
    Plane {
        youngs_modulus: f64,
        poisson_ratio: f64,
    },
}

/// The normal law with its coefficients, as dembound runs it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Law {
    /// F = k h^(3/2), k = E_eff √R_eff (N/m^(3/2)).
    Hertz { stiffness: f64 },
    /// F = k h, k = E_eff R_eff (N/m).
    Linear { stiffness: f64 },
    /// F = k h + c ḣ (N/m, N s/m); `clamp`: F = max(F, 0).
    Dashpot {
        stiffness: f64,
        damping: f64,
        clamp: bool,
    },
    /// F = k h^(3/2) + γ h^(1/4) ḣ (Tsuji; γ in N s/m^(5/4)).
    Tsuji {
        stiffness: f64,
        damping: f64,
        clamp: bool,
    },
    /// F = k (h^(3/2) + (3/2) A h^(1/2) ḣ) (Kuwabara–Kono; A in s).
    Viscoelastic { stiffness: f64, a: f64, clamp: bool },
}

/// A range of steps in which the deck writes the trace every step.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Window {
    pub start: u64,
    pub end: u64,
}

/// Everything a deck needs.
#[derive(Debug, Clone, PartialEq)]
pub struct Plan {
    /// The scenario, defaults written out.
    pub scenario: Scenario,
    pub particle: Particle,
    pub boundary: Boundary,
    /// E_eff = 4/3 / ((1 − ν_m²)/E_m + (1 − ν_b²)/E_b), Pa (eq 6, ERRATA 2).
    pub effective_modulus: f64,
    /// R_eff, m (eq 5; R_m for the plane).
    pub effective_radius: f64,
    /// The mass of the relative motion, kg.
    pub reduced_mass: f64,
    pub law: Law,
    /// Δt, s, and the contact-time estimate it came from.
    pub dt: f64,
    pub contact_time_estimate: f64,
    pub gravity: f64,
    pub gravity_on: GravityOn,
    /// The exact contacts (dembound exact), which place the windows.
    pub exact: Vec<ContactRecord>,
    pub windows: Vec<Window>,
}

/// Steps written before the onset and after the rebound of each contact
/// (the trace reader needs three free-flight steps on each side).
const MARGIN_STEPS: u64 = 12;
/// Extra margin for later contacts, as a share of the flight before them:
/// the other code's rebound differs from the exact one by its own error
/// (0.1 % in e moves the next onset by about 0.1 % of the flight).
const LATER_MARGIN: f64 = 0.02;

impl Plan {
    pub fn new(scenario: &Scenario) -> Result<Self> {
        let s = scenario.resolved();
        s.validate().map_err(|e| Error::Export(e.to_string()))?;
        let problem = dembound_plan(&s).map_err(|e| Error::Export(e.to_string()))?;
        let exact = exact::scenario_contacts(&s)
            .map_err(|e| Error::Export(format!("no exact reference for this scenario: {e}")))?;
        let pair = s.pair();
        let p = s.particle;
        let nu_b = pair.boundary_poisson_ratio();
        let e_b = pair.boundary_modulus();
        let r_b = pair.boundary_radius();
        let boundary = if r_b.is_finite() {
            let density = s.boundary.density.unwrap_or(p.density);
            Boundary::Sphere {
                radius: r_b,
                youngs_modulus: e_b,
                poisson_ratio: nu_b,
                fixed: s.boundary.fixed,
                density,
                mass: 4.0 / 3.0 * std::f64::consts::PI * density * r_b.powi(3),
                velocity: s.boundary.velocity.unwrap_or(0.0),
            }
        } else {
            Boundary::Plane {
                youngs_modulus: e_b,
                poisson_ratio: nu_b,
            }
        };
        let z_surface = if r_b.is_finite() { r_b } else { 0.0 };
        let particle = Particle {
            radius: p.radius,
            density: p.density,
            mass: p.mass(),
            youngs_modulus: p.youngs_modulus,
            poisson_ratio: p.poisson_ratio,
            z: z_surface + p.radius + s.motion.gap,
            velocity: s.motion.velocity,
        };
        let c = s.contact;
        // The damped laws' configuration (no dissipation given: 0), their
        // coefficient calibrated as the run calibrates it.
        let mut model = c.model();
        model.dissipation = model
            .dissipation
            .or(Some(dembound_core::contact::Dissipation::Coefficient(0.0)));
        let coefficient = || {
            damping_coefficient(&model, &pair, s.reduced_mass(), s.impact_speed())
                .map_err(|e| Error::Export(e.to_string()))
        };
        let clamp = !model.attractive;
        let law = match (c.law, c.damping) {
            (ContactLawKind::Hertz, DampingKind::None) => Law::Hertz {
                stiffness: pair.power_law_stiffness(1.5),
            },
            (ContactLawKind::Linear, DampingKind::None) => Law::Linear {
                stiffness: pair.power_law_stiffness(1.0),
            },
            (ContactLawKind::Linear, DampingKind::Viscous) => Law::Dashpot {
                stiffness: pair.power_law_stiffness(1.0),
                damping: coefficient()?,
                clamp,
            },
            (ContactLawKind::Hertz, DampingKind::Tsuji) => Law::Tsuji {
                stiffness: pair.power_law_stiffness(1.5),
                damping: coefficient()?,
                clamp,
            },
            (ContactLawKind::Hertz, DampingKind::Viscoelastic) => Law::Viscoelastic {
                stiffness: pair.power_law_stiffness(1.5),
                a: coefficient()?,
                clamp,
            },
            (law, damping) => {
                return Err(Error::Export(format!(
                    "contact.law = \"{}\" with contact.damping = \"{}\" is not exported yet \
                     (exported: hertz, linear, linear with viscous damping, hertz with tsuji or \
                     viscoelastic damping to LAMMPS)",
                    law.name(),
                    damping.name()
                )))
            }
        };
        let windows = windows(&exact, problem.dt);
        Ok(Plan {
            scenario: s,
            particle,
            boundary,
            effective_modulus: pair.effective_modulus(),
            effective_radius: pair.effective_radius(),
            reduced_mass: s.reduced_mass(),
            law,
            dt: problem.dt,
            contact_time_estimate: problem.contact_time_estimate,
            gravity: s.motion.gravity,
            gravity_on: s.motion.gravity_on,
            exact,
            windows,
        })
    }

    /// The step after the last window: the run's length.
    pub fn total_steps(&self) -> u64 {
        self.windows.last().map_or(0, |w| w.end)
    }

    /// Gravity on the particle, m/s² (0 unless `gravity_on` includes it).
    pub fn particle_gravity(&self) -> f64 {
        match self.gravity_on {
            GravityOn::Particle | GravityOn::Both => self.gravity,
            GravityOn::None => 0.0,
        }
    }

    /// Gravity on a free boundary sphere, m/s².
    pub fn boundary_gravity(&self) -> f64 {
        match self.gravity_on {
            GravityOn::Both => self.gravity,
            _ => 0.0,
        }
    }

    /// R_m + R_b (sphere) or R_m (plane): the overlap is this minus the
    /// centre distance (or the height).
    pub fn contact_distance(&self) -> f64 {
        match self.boundary {
            Boundary::Sphere { radius, .. } => self.particle.radius + radius,
            Boundary::Plane { .. } => self.particle.radius,
        }
    }

    /// The comment block of every deck: what each number is and where it
    /// comes from, one line each (without the comment marker).
    pub fn provenance(&self) -> Vec<String> {
        let s = &self.scenario;
        let p = &self.particle;
        let mut l = vec![
            "Exported by `dembound export` from the scenario in scenario.toml (SI units).".into(),
            "Every number below comes from dembound; the names are the scenario's keys.".into(),
            String::new(),
            format!(
                "particle: R_m = {} m (particle.radius), rho = {} kg/m^3 (particle.density), \
                 m = 4/3 pi rho R_m^3 = {} kg",
                num(p.radius),
                num(p.density),
                num(p.mass)
            ),
            format!(
                "          E_m = {} Pa (particle.youngs_modulus), nu_m = {} (particle.poisson_ratio)",
                num(p.youngs_modulus),
                num(p.poisson_ratio)
            ),
        ];
        match self.boundary {
            Boundary::Sphere {
                radius,
                youngs_modulus,
                poisson_ratio,
                fixed,
                density,
                mass,
                velocity,
            } => {
                l.push(format!(
                    "boundary: sphere R_b = r R_m = {} x {} = {} m (boundary.radius_ratio), \
                     centre at the origin",
                    num(s.boundary.radius_ratio),
                    num(p.radius),
                    num(radius)
                ));
                l.push(format!(
                    "          E_b = zeta E_m = {} x {} = {} Pa (boundary.modulus_ratio), nu_b = {}",
                    num(s.boundary.modulus_ratio),
                    num(p.youngs_modulus),
                    num(youngs_modulus),
                    num(poisson_ratio)
                ));
                if fixed {
                    l.push(
                        "          fixed: frozen, never integrated (boundary.fixed = true)".into(),
                    );
                } else {
                    l.push(format!(
                        "          free sphere: rho_b = {} kg/m^3, m_b = {} kg, v_b = {} m/s; \
                         reduced mass m* = {} kg",
                        num(density),
                        num(mass),
                        num(velocity),
                        num(self.reduced_mass)
                    ));
                }
            }
            Boundary::Plane {
                youngs_modulus,
                poisson_ratio,
            } => {
                l.push("boundary: plane z = 0 (boundary.radius_ratio = inf)".into());
                l.push(format!(
                    "          E_b = zeta E_m = {} x {} = {} Pa (boundary.modulus_ratio), nu_b = {}",
                    num(s.boundary.modulus_ratio),
                    num(p.youngs_modulus),
                    num(youngs_modulus),
                    num(poisson_ratio)
                ));
            }
        }
        l.push(format!(
            "pair:     E_eff = 4/3 / ((1-nu_m^2)/E_m + (1-nu_b^2)/E_b) = {} Pa (paper eq 6, ERRATA 2)",
            num(self.effective_modulus)
        ));
        l.push(format!(
            "          R_eff = R_m R_b/(R_m + R_b) = {} m (eq 5; R_m for a plane)",
            num(self.effective_radius)
        ));
        l.push(match self.law {
            Law::Hertz { stiffness } => format!(
                "law:      Hertz F = k h^(3/2), k = E_eff sqrt(R_eff) = {} N/m^1.5 (eq 4, alpha = 3/2)",
                num(stiffness)
            ),
            Law::Linear { stiffness } => format!(
                "law:      linear F = k h, k = E_eff R_eff = {} N/m (eq 4, alpha = 1)",
                num(stiffness)
            ),
            Law::Dashpot {
                stiffness,
                damping,
                clamp,
            } => format!(
                "law:      spring-dashpot F = k h + c dh/dt{}, k = E_eff R_eff = {} N/m, c = {} N s/m \
                 (contact.restitution = {} by the {} calibration: damping ratio {})",
                if clamp { ", F = max(F, 0)" } else { "" },
                num(stiffness),
                num(damping),
                s.contact
                    .restitution
                    .map_or_else(|| "none (coefficient given)".into(), num),
                s.contact.calibration.unwrap_or_default().name(),
                num(damping / (2.0 * (stiffness * self.reduced_mass).sqrt()))
            ),
            Law::Tsuji {
                stiffness,
                damping,
                clamp,
            } => format!(
                "law:      Hertz-Tsuji F = k h^(3/2) + gamma h^(1/4) dh/dt{}, k = {} N/m^1.5, gamma = {} N s/m^1.25 \
                 (contact.restitution = {} by the {} calibration)",
                if clamp { ", F = max(F, 0)" } else { "" },
                num(stiffness),
                num(damping),
                s.contact
                    .restitution
                    .map_or_else(|| "none (coefficient given)".into(), num),
                s.contact.calibration.unwrap_or_default().name(),
            ),
            Law::Viscoelastic { stiffness, a, clamp } => format!(
                "law:      Hertz viscoelastic F = k (h^(3/2) + 3/2 A h^(1/2) dh/dt){}, k = {} N/m^1.5, A = {} s \
                 (contact.restitution = {} by the {} calibration at the first impact speed)",
                if clamp { ", F = max(F, 0)" } else { "" },
                num(stiffness),
                num(a),
                s.contact
                    .restitution
                    .map_or_else(|| "none (coefficient given)".into(), num),
                s.contact.calibration.unwrap_or_default().name(),
            ),
        });
        l.push(format!(
            "step:     dt = {} s = {} x the law's gravity-free contact time {} s at the first impact \
             speed (dembound's rule, integration.eta/dt/tolerance)",
            num(self.dt),
            num(self.dt / self.contact_time_estimate),
            num(self.contact_time_estimate)
        ));
        l.push(format!(
            "motion:   gap = {} m (motion.gap), v = {} m/s upward positive (motion.velocity), \
             g = {} m/s^2 on {} (motion.gravity, motion.gravity_on)",
            num(s.motion.gap),
            num(s.motion.velocity),
            num(s.motion.gravity),
            match self.gravity_on {
                GravityOn::Particle => "the particle only",
                GravityOn::Both => "both spheres",
                GravityOn::None => "neither sphere",
            }
        ));
        l.push(format!(
            "          particle centre starts at z = {} m",
            num(p.z)
        ));
        l.push("exact reference (dembound exact), per contact:".into());
        for (i, c) in self.exact.iter().enumerate() {
            l.push(format!(
                "  {}: t_c = {} s, h_max = {} m, T_c = {} s, v_c = {} m/s, v_r = {} m/s, e = {}",
                i + 1,
                num(c.t_contact),
                num(c.max_overlap),
                num(c.duration),
                num(c.impact_velocity),
                num(c.rebound_velocity),
                num(c.restitution)
            ));
        }
        l.push(String::new());
        l.push("output: trace.txt, every step inside windows around each exact contact:".into());
        l.push(
            "  time (s), overlap h (m), relative velocity v_m - v_b (m/s, upward positive),".into(),
        );
        l.push("  contact force on the particle (N, upward positive).".into());
        l.push("Read it back with `dembound compare DIR` (DIR holds this deck, scenario.toml, trace.txt).".into());
        l
    }
}

/// The windows around each contact [floor(t_c/Δt) − margin, ceil(t_r/Δt)
/// + margin], overlapping ones merged.
fn windows(contacts: &[ContactRecord], dt: f64) -> Vec<Window> {
    let mut out: Vec<Window> = Vec::new();
    let mut previous_end = 0.0;
    for (i, c) in contacts.iter().enumerate() {
        let extra = if i == 0 {
            0
        } else {
            (LATER_MARGIN * (c.t_contact - previous_end) / dt).ceil() as u64
        };
        let margin = MARGIN_STEPS + extra;
        let start = ((c.t_contact / dt).floor() as u64).saturating_sub(margin);
        let end = (c.t_rebound / dt).ceil() as u64 + margin;
        previous_end = c.t_rebound;
        match out.last_mut() {
            Some(last) if start <= last.end => last.end = end,
            _ => out.push(Window { start, end }),
        }
    }
    out
}
