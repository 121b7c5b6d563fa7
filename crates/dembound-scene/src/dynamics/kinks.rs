//! Gear5 across the kinks of a contact: an onset or an end inside a step.
//!
//! The Gear predictor–corrector assumes that each body's acceleration is a
//! smooth function of time over a step. A contact breaks that twice: at
//! its onset the force starts from zero with a jump in one of its
//! derivatives (F = k h: dF/dt jumps from 0 to k v_c; Hertz h^{3/2}: the
//! second derivative is unbounded), and at its end it stops where the
//! predictor's polynomial would carry it on. With one fixed Δt through the
//! whole path the kink falls inside a step, and the corrector of that step
//! commits an error of order (pΔt)² that no later step removes (measured on
//! the paper's linear case at η = 1/50: 1.5e-4 in h_max and v_r; the bounce
//! crate avoids it by stepping to the event, which a many-body engine
//! cannot do).
//!
//! The cure is exact on the one part that is not smooth. The body's force
//! at the step's end is split into a smooth part, for the usual corrector,
//! and the kinked part of each contact that began or ended in the step,
//! whose effect over the step is integrated along the pair's straight
//! relative path (relative acceleration over one step changes the overlap
//! by O(a Δt²), a relative 1e-6 of the paper's case):
//!
//! - **Onset**, 0 < h < ḣΔt at the predicted state: the contact began
//!   τ = h/ḣ before the step's end. Its force along the path, f(s) =
//!   F(ḣ s, ḣ) for s ∈ [0, τ], gives the exact velocity and position
//!   increments ∫f ds / m and ∫(τ − s) f ds / m. Its value and first two
//!   derivatives give the body's r₂, r₃, r₄ contributions (r₅ gets none:
//!   the next steps rebuild it from smooth data), which the next
//!   predictor extrapolates over one step Δt: so they are those of the
//!   quadratic through f at τ, τ + Δt/2 and τ + Δt along the same path,
//!   not the derivatives at τ. For f ∝ s^α with α < 2 the second
//!   derivative at τ grows as τ^(α−2) (the first too, as τ^(α−1), for
//!   α < 1) when the onset falls just before the step's end (τ ≪ Δt),
//!   where their Taylor polynomial is no guide to the next step (it
//!   converges only within τ): Tsuji's damping, ∝ h^(1/4) ḣ, gave
//!   τ^(−3/4) and τ^(−7/4), and the validation drop with e = 0.3
//!   under Gear5 rebounded with e = 0.057 at η = 0.01875 (−81 %) and
//!   −11 % at 0.0125, exit 0 (session 37; over η = 0.004–0.031 now within
//!   0.27 %).
//! - **End**, for laws whose force vanishes at h = 0 (elastic, without
//!   history): the contact ended σ = h/ḣ ago (both negative). The predictor
//!   extrapolated the force past the end with its slope there, f_c(s) =
//!   −ḟ_e s; the corrector is given that continuation, as if it were still
//!   acting, and its response, ∫f_c and ∫(σ − s) f_c, is then taken away
//!   along with its derivatives. For Hertz ḟ_e = 0 and nothing changes;
//!   for the linear law this is the other half of the error. Damped and
//!   hysteretic laws end where the clamp sets F = 0 at h > 0, which is not
//!   located here: their end step keeps the plain corrector.
//!
//! Measured on the paper's validation case (crates/dembound-scene/tests/
//! validation.rs): see the tolerances there. Hand-written because it is
//! the integrator's own numerics; the integrals use the `quadrature`
//! crate's double-exponential rule (f(s) has an endpoint singularity in a
//! derivative, s^{3/2} or s^{1/4}).

use crate::bodies::Bodies;
use crate::dynamics::contacts::{extended, separation, LawTable};
use crate::geometry::ghosts::Ghosts;
use crate::geometry::neighbour::PairList;
use crate::walls::{Surface, WallContacts};
use dembound_physics::contact::{ContactHistory, PairLaw};

/// One body's corrections for the step (N for `removed`, m and m/s for
/// the increments).
#[derive(Debug, Clone, Copy, Default)]
struct Correction {
    /// Force (N) taken out of the acceleration the smooth corrector sees.
    removed: [f64; 3],
    /// Exact position increment of the kinked parts, m.
    dx: [f64; 3],
    /// Exact velocity increment of the kinked parts, m/s.
    dv: [f64; 3],
    /// Their contributions to r₂, r₃, r₄ (m).
    r: [[f64; 3]; 3],
}

/// Scratch: the corrections of the bodies touched by a kink this step.
#[derive(Debug, Clone, Default)]
pub struct Kinks {
    /// Per body: index into `entries`, or `u32::MAX`.
    slot: Vec<u32>,
    body: Vec<u32>,
    entries: Vec<Correction>,
}

/// The kinked part of one contact, per unit mass, along its normal: what
/// to remove from the smooth corrector's force and what to add instead.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Kink {
    /// Force at the step's end to take out of the smooth corrector, N.
    pub removed: f64,
    /// ∫(t_end − t) f dt over the step, N s².
    pub position: f64,
    /// ∫ f dt over the step, N s.
    pub velocity: f64,
    /// f, df/dt, d²f/dt² at the step's end (N, N/s, N/s²).
    pub derivatives: [f64; 3],
}

/// Force along the straight path of a contact that began `s` ago at
/// overlap rate `rate` (> 0).
fn path_force(law: &PairLaw, rate: f64, s: f64) -> f64 {
    law.force(rate * s, rate, &ContactHistory::default())
}

/// Relative tolerance of the ramp integrals: far below the corrections'
/// own size (they are O((pΔt)²) of the contact's quantities).
const QUADRATURE_TOLERANCE: f64 = 1e-12;

/// The kink of a contact whose onset was `tau` (s) before the end of a
/// step of `dt` (s), approaching at `rate` (m/s).
pub fn onset(law: &PairLaw, rate: f64, tau: f64, dt: f64) -> Kink {
    let f = |s: f64| path_force(law, rate, s);
    let scale = f(tau).abs().max(f64::MIN_POSITIVE) * tau;
    let velocity =
        quadrature::double_exponential::integrate(f, 0.0, tau, QUADRATURE_TOLERANCE * scale)
            .integral;
    let position = quadrature::double_exponential::integrate(
        |s| (tau - s) * f(s),
        0.0,
        tau,
        QUADRATURE_TOLERANCE * scale * tau,
    )
    .integral;
    // The quadratic through f(τ), f(τ + Δt/2), f(τ + Δt) (module doc):
    // what the next predictor extrapolates over its step, bounded however
    // close τ is to 0.
    let (f0, f1, f2) = (f(tau), f(tau + 0.5 * dt), f(tau + dt));
    Kink {
        removed: f0,
        position,
        velocity,
        derivatives: [
            f0,
            (-3.0 * f0 + 4.0 * f1 - f2) / dt,
            4.0 * (f0 - 2.0 * f1 + f2) / (dt * dt),
        ],
    }
}

/// The kink of an elastic contact that ended `sigma` (s) before the
/// step's end, separating at `rate` (m/s, < 0).
pub fn end(law: &PairLaw, rate: f64, sigma: f64) -> Kink {
    // Slope of the force just before the end, N/s (f falls to 0 there).
    let before = 1e-3 * sigma;
    let slope = path_force(law, -rate, before) / before;
    // The continuation the predictor assumed: f_c(s) = −slope·s. The
    // corrector is given it as if still acting (its force is the actual
    // one minus `removed`, so removed = −f_c(σ)); the kinked part, which
    // the step then adds exactly, is −f_c.
    Kink {
        removed: slope * sigma,
        position: slope * sigma.powi(3) / 6.0,
        velocity: slope * sigma * sigma / 2.0,
        derivatives: [slope * sigma, slope, 0.0],
    }
}

impl Kinks {
    /// Finds the contacts that began (and, for elastic laws, ended) inside
    /// the step just predicted, for the corrector. Serial and in list
    /// order: the same bits for any thread count.
    #[allow(clippy::too_many_arguments)]
    pub fn collect(
        &mut self,
        bodies: &Bodies,
        ghosts: &Ghosts,
        list: &PairList,
        surfaces: &[Surface],
        walls: &WallContacts,
        laws: &LawTable,
        dt: f64,
    ) {
        let n = bodies.len();
        self.slot.clear();
        self.slot.resize(n, u32::MAX);
        self.body.clear();
        self.entries.clear();
        let ends = !laws.model.depends_on_rate() && !laws.history;
        let kink = |law: &PairLaw, h: f64, rate: f64| -> Option<Kink> {
            if h > 0.0 && rate > 0.0 && h < rate * dt {
                Some(onset(law, rate, h / rate, dt))
            } else if ends && h <= 0.0 && rate < 0.0 && h > rate * dt {
                Some(end(law, rate, h / rate))
            } else {
                None
            }
        };
        let pair = |this: &mut Self, i: usize, j_ext: usize| {
            let (xj, vj, owner) = extended(bodies, ghosts, j_ext);
            let g = separation(
                bodies.position[i],
                bodies.velocity[i],
                bodies.radius[i],
                xj,
                vj,
                bodies.radius[owner],
            );
            if g.overlap < -g.overlap_rate.abs() * dt {
                return;
            }
            let law = laws.pair(bodies, i, owner);
            if let Some(k) = kink(&law, g.overlap, g.overlap_rate) {
                // The force on j is along the normal from i to j.
                this.add(bodies, owner, g.normal, &k);
                this.add(bodies, i, g.normal.map(|c| -c), &k);
            }
        };
        for i in 0..n {
            for k in list.start[i] as usize..list.start[i + 1] as usize {
                pair(self, i, list.j[k] as usize);
            }
        }
        for &(i, j) in &list.extra {
            pair(self, i as usize, j as usize);
        }
        for i in 0..n {
            if bodies.fixed[i] {
                continue;
            }
            if walls.bodies() != n {
                continue;
            }
            for e in walls.range(i) {
                let key = walls.key[e];
                let surface = &surfaces[key.wall as usize];
                let c = surface.contact(
                    key.element,
                    bodies.position[i],
                    bodies.velocity[i],
                    bodies.radius[i],
                );
                let (h, rate) = (c.overlap, c.rate);
                if h < -rate.abs() * dt {
                    continue;
                }
                let law = laws.wall(bodies, i, surface.law_slot(key.element));
                if let Some(k) = kink(&law, h, rate) {
                    self.add(bodies, i, c.normal, &k);
                }
            }
        }
    }

    fn add(&mut self, bodies: &Bodies, b: usize, normal: [f64; 3], k: &Kink) {
        if bodies.fixed[b] {
            return;
        }
        if self.slot[b] == u32::MAX {
            self.slot[b] = self.entries.len() as u32;
            self.body.push(b as u32);
            self.entries.push(Correction::default());
        }
        let c = &mut self.entries[self.slot[b] as usize];
        for (a, &n) in normal.iter().enumerate() {
            c.removed[a] += k.removed * n;
            c.dx[a] += k.position * n;
            c.dv[a] += k.velocity * n;
            for d in 0..3 {
                c.r[d][a] += k.derivatives[d] * n;
            }
        }
    }

    /// After the smooth corrector with coefficients `c` has used the full
    /// force: takes the kinked parts out of its correction and adds their
    /// exact increments and derivatives instead.
    pub fn apply(&self, bodies: &mut Bodies, dt: f64, c: [f64; 6]) {
        let half_dt2 = 0.5 * dt * dt;
        // r_k = Δt^k f⁽ᵏ⁻²⁾/(k! m) for k = 2, 3, 4.
        let scale = [half_dt2, dt * dt * dt / 6.0, dt * dt * dt * dt / 24.0];
        for (&b, e) in self.body.iter().zip(&self.entries) {
            let b = b as usize;
            let w = bodies.inverse_mass[b];
            let (x, v, r) = (
                &mut bodies.position[b],
                &mut bodies.velocity[b],
                &mut bodies.higher[b],
            );
            for a in 0..3 {
                let delta = half_dt2 * w * e.removed[a];
                x[a] += w * e.dx[a] - c[0] * delta;
                v[a] += w * e.dv[a] - c[1] * delta / dt;
                r[0][a] += scale[0] * w * e.r[0][a] - c[2] * delta;
                r[1][a] += scale[1] * w * e.r[1][a] - c[3] * delta;
                r[2][a] += scale[2] * w * e.r[2][a] - c[4] * delta;
                r[3][a] -= c[5] * delta;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use dembound_physics::contact::{ContactModel, NormalLaw};
    use dembound_physics::material::{Material, PairProperties};

    /// A steel sphere of R = 1 mm on a steel plane under `model`.
    fn pair(model: ContactModel) -> PairLaw {
        let m = Material {
            density: 7800.0,
            youngs_modulus: 2e11,
            poisson_ratio: 0.3,
        };
        let mass = 4.0 / 3.0 * std::f64::consts::PI * 1e-9 * 7800.0;
        let props = PairProperties::sphere_plane(1e-3, mass, &m, &m);
        model.pair(&props)
    }

    fn law(normal: NormalLaw) -> PairLaw {
        pair(ContactModel::elastic(normal))
    }

    /// The onset kink of F = K h^α along h = v s has closed-form moments:
    /// ∫₀^τ K (v s)^α ds = K v^α τ^{α+1}/(α+1) and ∫(τ−s)… =
    /// K v^α τ^{α+2}/((α+1)(α+2)); its derivatives are the quadratic's
    /// through the ramp at τ, τ + Δt/2, τ + Δt (written out here), so the
    /// Taylor polynomial they give passes through the ramp at those three
    /// times.
    #[test]
    fn onset_moments_match_the_power_ramp() {
        for (normal, alpha) in [(NormalLaw::Hertz, 1.5), (NormalLaw::Linear, 1.0)] {
            let law = law(normal);
            let (v, tau, dt) = (0.3, 2e-8, 1e-7);
            // K from one evaluation of the law itself is not independent;
            // it is only the prefactor, the τ-dependence is what is checked.
            let k = path_force(&law, v, tau) / (v * tau).powf(alpha);
            let kv = k * v.powf(alpha);
            let kink = onset(&law, v, tau, dt);
            let rel = |a: f64, b: f64| ((a - b) / b).abs();
            // Quadrature to 1e-12 relative; the prefactor shares rounding.
            assert!(rel(kink.velocity, kv * tau.powf(alpha + 1.0) / (alpha + 1.0)) < 1e-10);
            assert!(
                rel(
                    kink.position,
                    kv * tau.powf(alpha + 2.0) / ((alpha + 1.0) * (alpha + 2.0))
                ) < 1e-10
            );
            let ramp = |s: f64| kv * s.powf(alpha);
            let [f0, d1, d2] = kink.derivatives;
            for s in [0.0, 0.5 * dt, dt] {
                let taylor = f0 + d1 * s + 0.5 * d2 * s * s;
                // Rounding of three force evaluations and two differences.
                assert!(rel(taylor, ramp(tau + s)) < 1e-9, "{alpha} at {s}");
            }
            if alpha == 1.0 {
                // The linear ramp: its slope exactly, no curvature.
                assert!(rel(d1, kv) < 1e-9);
                assert!(d2.abs() < 1e-6 * kv / dt);
            }
        }
    }

    /// Tsuji's damped onset, f ∝ s^(1/4) near s = 0: the derivatives at τ
    /// grow as τ^(−3/4), τ^(−7/4) when τ ≪ Δt; the quadratic's stay of the
    /// size of the force over the step (|f′| Δt, |f″| Δt² ≤ a few f(τ + Δt)),
    /// for every τ down to 1e-6 Δt.
    #[test]
    fn a_damped_onset_near_the_step_end_keeps_bounded_derivatives() {
        use dembound_physics::contact::{Damping, DampingKind, Dissipation};
        let law = pair(ContactModel::damped(
            NormalLaw::Hertz,
            Damping::new(DampingKind::Tsuji, Dissipation::Restitution(0.3)),
        ));
        let (v, dt) = (0.3, 1e-7);
        let end = path_force(&law, v, dt);
        for tau in [1e-6 * dt, 1e-3 * dt, 0.1 * dt, 0.9 * dt] {
            let [_, d1, d2] = onset(&law, v, tau, dt).derivatives;
            assert!(d1.abs() * dt < 4.0 * end, "τ = {tau}: f′ Δt = {}", d1 * dt);
            assert!(
                d2.abs() * dt * dt < 8.0 * end,
                "τ = {tau}: f″ Δt² = {}",
                d2 * dt * dt
            );
        }
    }

    /// The end of a linear contact: the predictor's continuation −k v s
    /// removed over σ gives k v σ²/2 and k v σ³/6; Hertz has no slope there.
    #[test]
    fn end_of_a_linear_contact_removes_the_continuation() {
        let law = law(NormalLaw::Linear);
        let (v, sigma) = (0.3, 3e-8);
        let k = path_force(&law, v, 1e-8) / (v * 1e-8);
        let kink = end(&law, -v, sigma);
        let rel = |a: f64, b: f64| ((a - b) / b).abs();
        assert!(rel(kink.velocity, k * v * sigma * sigma / 2.0) < 1e-12);
        assert!(rel(kink.position, k * v * sigma.powi(3) / 6.0) < 1e-12);
    }
}
