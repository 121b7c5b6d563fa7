//! The integrators, per body (so parallel and exact for any thread count).
//!
//! - Velocity Verlet (kick–drift–kick): v ← v + Δt/2 a; x ← x + Δt v; new
//!   forces; v ← v + Δt/2 a. Second order, symplectic.
//! - The paper's Gear5 predictor–corrector (eqs 18–19) in its many-body
//!   form: every body carries x, v and the scaled derivatives r₂..r₅
//!   (r_k = Δt^k x⁽ᵏ⁾/k!); predict all bodies (Pascal's triangle), evaluate
//!   forces at the predicted state, correct with Δ = Δt² a/2 − r₂ᵖ and
//!   c = (3/16 or 3/20, 251/360, 1, 11/18, 1/6, 1/60) (Allen & Tildesley
//!   1987, table E.2; the bounce's `integrate::gear5`). Hand-written: the
//!   schemes are what the paper studies.

use rayon::prelude::*;

use crate::bodies::Bodies;

/// Gear5 corrector coefficients for a force that does or does not depend
/// on the velocity (c₀ = 3/20 or 3/16).
pub fn gear5_corrector(depends_on_velocity: bool) -> [f64; 6] {
    let c0 = if depends_on_velocity {
        3.0 / 20.0
    } else {
        3.0 / 16.0
    };
    [c0, 251.0 / 360.0, 1.0, 11.0 / 18.0, 1.0 / 6.0, 1.0 / 60.0]
}

/// Largest squared displacement of a free body from `reference`, m².
fn max_displacement2(x: [f64; 3], r: [f64; 3]) -> f64 {
    let d = [x[0] - r[0], x[1] - r[1], x[2] - r[2]];
    d[0] * d[0] + d[1] * d[1] + d[2] * d[2]
}

/// Verlet's first half: half kick and drift of the free bodies. Returns the
/// largest squared displacement from `reference` (m²; the max is exact in
/// any order).
pub fn verlet_kick_drift(
    bodies: &mut Bodies,
    reference: &[[f64; 3]],
    dt: f64,
    pool: &rayon::ThreadPool,
) -> f64 {
    let half = 0.5 * dt;
    let Bodies {
        position,
        velocity,
        force,
        inverse_mass,
        ..
    } = bodies;
    pool.install(|| {
        position
            .par_iter_mut()
            .zip(velocity.par_iter_mut())
            .zip(force.par_iter())
            .zip(inverse_mass.par_iter())
            .zip(reference.par_iter())
            .map(|((((x, v), f), &w), r)| {
                if w == 0.0 {
                    return 0.0;
                }
                let hw = half * w;
                for a in 0..3 {
                    v[a] += hw * f[a];
                    x[a] += dt * v[a];
                }
                max_displacement2(*x, *r)
            })
            .reduce(|| 0.0, f64::max)
    })
}

/// Verlet's last half kick.
pub fn verlet_kick(bodies: &mut Bodies, dt: f64, pool: &rayon::ThreadPool) {
    let half = 0.5 * dt;
    let Bodies {
        velocity,
        force,
        inverse_mass,
        ..
    } = bodies;
    pool.install(|| {
        velocity
            .par_iter_mut()
            .zip(force.par_iter())
            .zip(inverse_mass.par_iter())
            .for_each(|((v, f), &w)| {
                let hw = half * w;
                for a in 0..3 {
                    v[a] += hw * f[a];
                }
            });
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
    pool: &rayon::ThreadPool,
) -> f64 {
    let inv_dt = 1.0 / dt;
    let Bodies {
        position,
        velocity,
        inverse_mass,
        higher,
        ..
    } = bodies;
    pool.install(|| {
        position
            .par_iter_mut()
            .zip(velocity.par_iter_mut())
            .zip(higher.par_iter_mut())
            .zip(inverse_mass.par_iter())
            .zip(reference.par_iter())
            .map(|((((x, v), r), &w), reference)| {
                if w == 0.0 {
                    return 0.0;
                }
                for a in 0..3 {
                    let (r2, r3, r4, r5) = (r[0][a], r[1][a], r[2][a], r[3][a]);
                    let r1 = v[a] * dt;
                    x[a] += (r1 + r2) + (r3 + r4) + r5;
                    v[a] = (r1 + 2.0 * r2 + 3.0 * r3 + 4.0 * r4 + 5.0 * r5) * inv_dt;
                    r[0][a] = r2 + 3.0 * r3 + 6.0 * r4 + 10.0 * r5;
                    r[1][a] = r3 + 4.0 * r4 + 10.0 * r5;
                    r[2][a] = r4 + 5.0 * r5;
                }
                max_displacement2(*x, *reference)
            })
            .reduce(|| 0.0, f64::max)
    })
}

/// Gear5 corrector with coefficients `c` ([`gear5_corrector`]).
pub fn gear5_correct(bodies: &mut Bodies, dt: f64, c: [f64; 6], pool: &rayon::ThreadPool) {
    let inv_dt = 1.0 / dt;
    let half_dt2 = 0.5 * dt * dt;
    let Bodies {
        position,
        velocity,
        force,
        inverse_mass,
        higher,
        ..
    } = bodies;
    pool.install(|| {
        position
            .par_iter_mut()
            .zip(velocity.par_iter_mut())
            .zip(higher.par_iter_mut())
            .zip(force.par_iter())
            .zip(inverse_mass.par_iter())
            .for_each(|((((x, v), r), f), &w)| {
                if w == 0.0 {
                    return;
                }
                for a in 0..3 {
                    let delta = half_dt2 * w * f[a] - r[0][a];
                    x[a] += c[0] * delta;
                    v[a] += c[1] * delta * inv_dt;
                    r[0][a] += c[2] * delta;
                    r[1][a] += c[3] * delta;
                    r[2][a] += c[4] * delta;
                    r[3][a] += c[5] * delta;
                }
            });
    });
}
