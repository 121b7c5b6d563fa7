//! Gear5 for the spins (issue 13): the scene's rotation under the paper's
//! integrator.
//!
//! A sphere's orientation does not enter its contacts, so the rotational
//! state is the angular velocity alone and its equation is of first
//! order, dω/dt = τ/I with I = 2/5 m R². It gets Gear's predictor–corrector
//! for a first-order equation with five values, the Nordsieck vector
//! r₀ = ω, r_k = Δt^k ω⁽ᵏ⁾/k! (k = 1…4), in step with the centres'
//! Gear5 ([`super::integrate`]):
//!
//! 1. predict with the Pascal matrix (the physics crate's [`pascal`], the
//!    centres' predictor), so that the friction kernels see ω at t + Δt;
//! 2. the forces and torques are evaluated at the predicted state (the
//!    tangential springs move by v_t Δt, v_t the predicted slip velocity,
//!    as the Verlet path moves them by its half-step slip);
//! 3. correct with Δ = Δt τ(ωᵖ)/I − r₁ᵖ: r_k += c_k Δ, with Gear's
//!    coefficients for a first-order equation with five values,
//!    c = (251/720, 1, 11/12, 1/3, 1/24) (Gear 1971; Allen & Tildesley,
//!    *Computer Simulation of Liquids*, 1987, appendix E, table E.1;
//!    [`FIRST_ORDER_CORRECTOR`]).
//!
//! Five values, not six: these coefficients are exactly what Gear5's
//! second-order corrector does to a centre's velocity (its c₁…c₅ = 251/360,
//! 1, 11/18, 1/6, 1/60 in the velocity's scaling), so a spin is advanced as
//! the velocity of its centre is: the same order, and the same stability
//! (|λΔt| < 0.17 on the negative real axis, 0.23 on the imaginary axis).
//! The six-value set of the same table, (95/288, 1, 25/24, 35/72, 5/48,
//! 1/120), is of one order more (measured 6.0 on ω̇ = −kω) but stable only
//! to 0.09 and 0.12: the spins would limit Δt before the centres do.
//!
//! Known limit (not from the spins' coefficients): a dense, strongly
//! damped frictional bed can blow up under Gear5 where Verlet does not
//! (the settling bed with Tsuji e = 0.3 and μ = 0.5 at Δt = 2 µs; it runs
//! at 1 µs). Until session 37 the 8 × 8 × 6 drop of
//! `tests/friction_gear5.rs` (`gear5_strongly_damped_lattice_stays_finite`,
//! then ignored) blew up too, at 1 and 2 µs, with the spins on Gear's 3-,
//! 4-, 5- or 6-value sets alike: that was the damped onset's kink handing
//! the predictor unbounded derivatives (`dynamics::kinks`), not the spins;
//! it now settles at 1 µs (2 µs is refused by the closed-form bound on one
//! damped contact). What remains is likely Gear's small stability interval
//! for velocity-dependent forces (|λΔt| < 0.17, above) against the slip
//! modes of spheres with several sticking contacts, damped at
//! η_t (1/m + R²/I) per contact, 3.5 times the normal dashpot's rate for
//! one contact, summed over the contacts a spin couples; Verlet tolerates
//! ten times more.
//!
//! The start is as the centres': r₁ = Δt τ/I from the first torques,
//! r₂..r₄ = 0. Per body (parallel, the same bits for any thread count).
//! The contacts that begin or end inside a step are corrected for the
//! normal force only (`dynamics::kinks`); the tangential force's kink at
//! an onset is left to the corrector.

use dembound_physics::integrate::gear5::{pascal, FIRST_ORDER_CORRECTOR};
use dembound_physics::integrate::Vec3;

use crate::bodies::Bodies;
use crate::parallel::{SharedMut, Workers, BODY_CHUNK};

/// Starts the spins' Nordsieck vectors from the current torques:
/// r₁ = Δt τ/I, r₂..r₄ = 0 (fixed bodies: all 0).
pub fn start(bodies: &mut Bodies, dt: f64) {
    let n = bodies.len();
    bodies.angular_higher = vec![[[0.0; 3]; 4]; n];
    if bodies.torque.len() != n {
        return;
    }
    for i in 0..n {
        if bodies.fixed[i] {
            continue;
        }
        let w = dt * bodies.inverse_inertia[i];
        for a in 0..3 {
            bodies.angular_higher[i][0][a] = w * bodies.torque[i][a];
        }
    }
}

/// Predicts the spins of the free bodies to t + Δt (Pascal's triangle).
pub fn predict(bodies: &mut Bodies, workers: &Workers) {
    let n = bodies.len();
    assert!(bodies.angular_velocity.len() == n && bodies.angular_higher.len() == n);
    let (w, r) = (
        SharedMut::new(&mut bodies.angular_velocity),
        SharedMut::new(&mut bodies.angular_higher),
    );
    let fixed = &bodies.fixed;
    workers.run_bodies(n, BODY_CHUNK, |c| {
        let lo = c * BODY_CHUNK;
        for (i, &is_fixed) in fixed
            .iter()
            .enumerate()
            .take(n.min(lo + BODY_CHUNK))
            .skip(lo)
        {
            if is_fixed {
                continue;
            }
            // SAFETY: one body per iteration, i < n (asserted lengths).
            let (w, r) = unsafe { (w.at(i), r.at(i)) };
            // Five values through the six-value Pascal sums (the sixth 0:
            // its terms add exact zeros).
            let p = pascal(&[
                Vec3(*w),
                Vec3(r[0]),
                Vec3(r[1]),
                Vec3(r[2]),
                Vec3(r[3]),
                Vec3([0.0; 3]),
            ]);
            *w = p[0].0;
            for k in 0..4 {
                r[k] = p[k + 1].0;
            }
        }
    });
}

/// Corrects the spins of the free bodies with the torques at the predicted
/// state: Δ = Δt τ/I − r₁ᵖ, ω += c₀ Δ, r_k += c_k Δ.
pub fn correct(bodies: &mut Bodies, dt: f64, workers: &Workers) {
    let c = FIRST_ORDER_CORRECTOR;
    let n = bodies.len();
    assert!(
        bodies.angular_velocity.len() == n
            && bodies.angular_higher.len() == n
            && bodies.torque.len() == n
    );
    let (w, r) = (
        SharedMut::new(&mut bodies.angular_velocity),
        SharedMut::new(&mut bodies.angular_higher),
    );
    let (torque, inverse_inertia, fixed) = (&bodies.torque, &bodies.inverse_inertia, &bodies.fixed);
    workers.run_bodies(n, BODY_CHUNK, |ch| {
        for i in ch * BODY_CHUNK..((ch + 1) * BODY_CHUNK).min(n) {
            if fixed[i] {
                continue;
            }
            // SAFETY: one body per iteration, i < n (asserted lengths).
            let (w, r) = unsafe { (w.at(i), r.at(i)) };
            let scale = dt * inverse_inertia[i];
            for a in 0..3 {
                let delta = scale * torque[i][a] - r[0][a];
                w[a] += c[0] * delta;
                for k in 0..4 {
                    r[k][a] += c[k + 1] * delta;
                }
            }
        }
    });
}

#[cfg(test)]
mod tests {
    use super::*;

    /// One body under a torque that depends on its spin, τ = −k ω (I = 1),
    /// started from the exact Nordsieck vector: ω(t) = ω₀ e^{−kt}.
    /// Measured at kΔt = 1/20, 1/40, 1/80: errors 4.0e-8, 1.25e-9,
    /// 3.9e-11, order 5.00 (the five-value corrector: 5th order, as Gear5's
    /// velocities). Asserted > 4.8: a wrong coefficient drops the order
    /// to 1–2; the smallest error is still 1e5 times ω's rounding over 80
    /// steps.
    #[test]
    fn spin_decay_converges_at_high_order() {
        let workers = Workers::new(1).unwrap();
        let (k, w0, t_end) = (1.0, 1.0, 1.0);
        let run = |steps: usize| {
            let dt = t_end / steps as f64;
            let mut b = Bodies {
                angular_velocity: vec![[w0, 0.0, 0.0]],
                torque: vec![[-k * w0, 0.0, 0.0]],
                inverse_inertia: vec![1.0],
                fixed: vec![false],
                position: vec![[0.0; 3]],
                ..Bodies::default()
            };
            // Exact derivatives at the start: r_k = (−kΔt)^k ω₀/k!.
            start(&mut b, dt);
            let mut term = w0;
            for j in 0..4 {
                term *= -k * dt / (j + 1) as f64;
                b.angular_higher[0][j][0] = term;
            }
            for _ in 0..steps {
                predict(&mut b, &workers);
                b.torque[0][0] = -k * b.angular_velocity[0][0];
                correct(&mut b, dt, &workers);
            }
            (b.angular_velocity[0][0] - w0 * (-k * t_end).exp()).abs()
        };
        let errors: Vec<f64> = [20, 40, 80].iter().map(|&s| run(s)).collect();
        let orders: Vec<f64> = errors.windows(2).map(|e| (e[0] / e[1]).log2()).collect();
        eprintln!("spin decay: errors {errors:?}, orders {orders:?}");
        for p in orders {
            assert!(p > 4.8, "order {p}");
        }
    }
}
