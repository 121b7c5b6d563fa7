//! The integrators, per body (so parallel and exact for any thread count),
//! over the physics crate's generic ones (`dembound_physics::integrate`,
//! on a body's [`Vec3`]):
//!
//! - Velocity Verlet (kick–drift–kick): v ← v + Δt/2 a; x ← x + Δt v; new
//!   forces; v ← v + Δt/2 a. Second order, symplectic. The kick and drift
//!   are [`verlet::half_kick`] and [`verlet::drift`].
//! - The paper's Gear5 predictor–corrector (eqs 18–19) in its many-body
//!   form: every body carries x, v and the scaled derivatives r₂..r₅
//!   (r_k = Δt^k x⁽ᵏ⁾/k!); predict all bodies ([`pascal`], Pascal's
//!   triangle), evaluate forces at the predicted state, correct with
//!   Δ = Δt² a/2 − r₂ᵖ and c = (3/16 or 3/20, 251/360, 1, 11/18, 1/6,
//!   1/60) ([`Gear5::for_force`]; Allen & Tildesley 1987, table E.2). The
//!   corrector is written here: the engine keeps v, not r₁ = Δt v, and
//!   the contacts that begin or end inside a step correct it
//!   (`dynamics::kinks`).

use dembound_physics::integrate::gear5::{pascal, Gear5};
use dembound_physics::integrate::{verlet, Vec3};

use crate::bodies::Bodies;
use crate::parallel::{SharedMut, Workers, BODY_CHUNK};

/// Gear5 corrector coefficients for a force that does or does not depend
/// on the velocity (c₀ = 3/20 or 3/16): the physics crate's.
pub fn gear5_corrector(depends_on_velocity: bool) -> [f64; 6] {
    Gear5::for_force(depends_on_velocity).corrector
}

/// Squared distance, m².
#[inline(always)]
pub fn displacement2(x: [f64; 3], r: [f64; 3]) -> f64 {
    let d = [x[0] - r[0], x[1] - r[1], x[2] - r[2]];
    d[0] * d[0] + d[1] * d[1] + d[2] * d[2]
}

/// Verlet half kick of one free body: v ← v + `dtfm` F with dtfm =
/// (Δt/2)/m (the LAMMPS `nve` rounding).
#[inline(always)]
pub fn half_kick(v: &mut [f64; 3], f: [f64; 3], dtfm: f64) {
    *v = verlet::half_kick(Vec3(*v), Vec3(f), dtfm).0;
}

/// Verlet drift of one body.
#[inline(always)]
pub fn drift(x: &mut [f64; 3], v: [f64; 3], dt: f64) {
    *x = verlet::drift(Vec3(*x), Vec3(v), dt).0;
}

/// Per-body loop over chunks of bodies.
fn for_bodies(workers: &Workers, n: usize, f: impl Fn(usize) + Sync + Send) {
    workers.run_bodies(n, BODY_CHUNK, |c| {
        for i in c * BODY_CHUNK..((c + 1) * BODY_CHUNK).min(n) {
            f(i);
        }
    });
}

/// Largest of `f(i)` over bodies (the max is exact in any order).
fn max_over_bodies(workers: &Workers, n: usize, f: impl Fn(usize) -> f64 + Sync + Send) -> f64 {
    workers
        .map(n.div_ceil(BODY_CHUNK), |c| {
            let mut m = 0.0f64;
            for i in c * BODY_CHUNK..((c + 1) * BODY_CHUNK).min(n) {
                m = m.max(f(i));
            }
            m
        })
        .into_iter()
        .fold(0.0, f64::max)
}

/// Verlet's last half kick.
pub fn verlet_kick(bodies: &mut Bodies, dt: f64, workers: &Workers) {
    let n = bodies.len();
    let v = SharedMut::new(&mut bodies.velocity);
    let (force, mass, fixed) = (&bodies.force, &bodies.mass, &bodies.fixed);
    for_bodies(workers, n, |i| {
        if !fixed[i] {
            // SAFETY: one body per iteration.
            half_kick(unsafe { v.at(i) }, force[i], 0.5 * dt / mass[i]);
        }
    });
}

/// Gear5 initial derivatives: r₂ = Δt² a/2 from the current forces, r₃..r₅ = 0.
pub fn gear5_start(bodies: &mut Bodies, dt: f64) {
    let n = bodies.len();
    bodies.higher = vec![[[0.0; 3]; 4]; n];
    for i in 0..n {
        let w = bodies.inverse_mass[i] * 0.5 * dt * dt;
        for a in 0..3 {
            bodies.higher[i][0][a] = w * bodies.force[i][a];
        }
    }
}

/// Gear5 predictor (Pascal's triangle) of the free bodies. Returns the
/// largest squared displacement from `reference`, m².
pub fn gear5_predict(
    bodies: &mut Bodies,
    reference: &[[f64; 3]],
    dt: f64,
    workers: &Workers,
) -> f64 {
    let inv_dt = 1.0 / dt;
    let n = bodies.len();
    // The vectors are written through raw pointers below: one per body.
    assert!(bodies.higher.len() == n && bodies.velocity.len() == n && reference.len() == n);
    let (x, v, r) = (
        SharedMut::new(&mut bodies.position),
        SharedMut::new(&mut bodies.velocity),
        SharedMut::new(&mut bodies.higher),
    );
    let fixed = &bodies.fixed;
    max_over_bodies(workers, n, |i| {
        if fixed[i] {
            return 0.0;
        }
        // SAFETY: one body per iteration.
        let (x, v, r) = unsafe { (x.at(i), v.at(i), r.at(i)) };
        // The Nordsieck vector of the body (r₁ = Δt v) through the
        // physics crate's Pascal predictor.
        let p = pascal(&[
            Vec3(*x),
            Vec3(*v) * dt,
            Vec3(r[0]),
            Vec3(r[1]),
            Vec3(r[2]),
            Vec3(r[3]),
        ]);
        *x = p[0].0;
        *v = (p[1] * inv_dt).0;
        r[0] = p[2].0;
        r[1] = p[3].0;
        r[2] = p[4].0;
        displacement2(*x, reference[i])
    })
}

/// Gear5 corrector with coefficients `c` ([`gear5_corrector`]).
pub fn gear5_correct(bodies: &mut Bodies, dt: f64, c: [f64; 6], workers: &Workers) {
    let inv_dt = 1.0 / dt;
    let half_dt2 = 0.5 * dt * dt;
    let n = bodies.len();
    // The vectors are written through raw pointers below: one per body.
    assert!(
        bodies.higher.len() == n
            && bodies.velocity.len() == n
            && bodies.force.len() == n
            && bodies.inverse_mass.len() == n
    );
    let (x, v, r) = (
        SharedMut::new(&mut bodies.position),
        SharedMut::new(&mut bodies.velocity),
        SharedMut::new(&mut bodies.higher),
    );
    let (force, w, fixed) = (&bodies.force, &bodies.inverse_mass, &bodies.fixed);
    for_bodies(workers, n, |i| {
        if fixed[i] {
            return;
        }
        // SAFETY: one body per iteration.
        let (x, v, r) = unsafe { (x.at(i), v.at(i), r.at(i)) };
        for a in 0..3 {
            let delta = half_dt2 * w[i] * force[i][a] - r[0][a];
            x[a] += c[0] * delta;
            v[a] += c[1] * delta * inv_dt;
            r[0][a] += c[2] * delta;
            r[1][a] += c[3] * delta;
            r[2][a] += c[4] * delta;
            r[3][a] += c[5] * delta;
        }
    });
}
