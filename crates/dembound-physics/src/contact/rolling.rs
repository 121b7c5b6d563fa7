//! Rolling resistance: an elastic–plastic rolling spring (Iwashita & Oda
//! 1998; Ai, Chen, Rotter & Ooi, Powder Technol. 206, 269 (2011), model
//! C; Wensrich & Katterfeld, Powder Technol. 217, 409 (2012)) of stiffness
//! k_r = 2.25 k_n μ_r² R_eff² (k_n = F_n/h, the normal law's secant
//! stiffness) whose torque M_r is limited to μ_r R_eff |F_n|, driven by the
//! relative rolling velocity ω_r (the part of ω₁ − ω₂ in the tangent plane;
//! twisting is not resisted): M_r ← M_r − k_r ω_r Δt, then capped.
//!
//! A spring rather than a constant directional torque: a constant torque
//! reverses ω_r every step near rest and the chatter lets a sphere creep
//! down an incline it should hold; the spring holds it. While the spring
//! is below its limit a viscous torque −η_r ω_r damps it, η_r =
//! 2 ξ √(k_r I) with the local damping ratio ξ of the normal contact and
//! I = 1/(1/I₁ + 1/I₂) (Ai et al.'s model C damping; LIGGGHTS epsd2 drops
//! it, which leaves a resting sphere rocking forever).
//!
//! The history M_r (torque on body 1, N m) is kept in the tangent plane as
//! the tangential spring's is. LIGGGHTS's `rolling_friction epsd2` has the
//! same limit but the stiffness k_r = k_t R_eff² (rolling_model_epsd2.h):
//! the two are one law only where k_t = 2.25 k_n μ_r² (docs/export-liggghts.md).

/// The rolling spring of one pair.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Epsd2 {
    /// μ_r, dimensionless.
    pub coefficient: f64,
    /// R_eff, m.
    pub radius: f64,
}

impl Epsd2 {
    /// Torque on body 1 (N m) and the new spring torque in `history`, for
    /// normal force `normal_force` (N), secant normal stiffness
    /// `normal_stiffness` (N/m), damping ratio `damping_ratio`, effective
    /// rolling inertia `inertia` (kg m²), unit normal `normal`, relative
    /// spin ω₁ − ω₂ (rad/s) and time step `dt` (s; 0: the spring does not
    /// move).
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    pub fn torque(
        &self,
        normal_force: f64,
        normal_stiffness: f64,
        damping_ratio: f64,
        inertia: f64,
        normal: [f64; 3],
        relative_spin: [f64; 3],
        dt: f64,
        history: &mut [f64; 3],
    ) -> [f64; 3] {
        if self.coefficient == 0.0 {
            *history = [0.0; 3];
            return [0.0; 3];
        }
        let n = normal;
        let dot = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
        // Back into the tangent plane, length kept.
        let along = dot(*history, n);
        if along != 0.0 {
            let before = dot(*history, *history).sqrt();
            let mut p = [
                history[0] - along * n[0],
                history[1] - along * n[1],
                history[2] - along * n[2],
            ];
            let after = dot(p, p).sqrt();
            let s = if after > 0.0 { before / after } else { 0.0 };
            for x in &mut p {
                *x *= s;
            }
            *history = p;
        }
        let w = relative_spin;
        let a = dot(w, n);
        let wr = [w[0] - a * n[0], w[1] - a * n[1], w[2] - a * n[2]];
        let r2 = self.radius * self.radius;
        let k_r = 2.25 * normal_stiffness * self.coefficient * self.coefficient * r2;
        for d in 0..3 {
            history[d] -= k_r * wr[d] * dt;
        }
        let limit = self.coefficient * self.radius * normal_force.abs();
        let m = dot(*history, *history).sqrt();
        if m > limit {
            let s = if m > 0.0 { limit / m } else { 0.0 };
            for x in history.iter_mut() {
                *x *= s;
            }
            return *history;
        }
        let eta = 2.0 * damping_ratio * (k_r * inertia).max(0.0).sqrt();
        [
            history[0] - eta * wr[0],
            history[1] - eta * wr[1],
            history[2] - eta * wr[2],
        ]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spring_then_limit_against_rolling_only() {
        let r = Epsd2 {
            coefficient: 0.1,
            radius: 2.0e-3,
        };
        // k_r = 2.25 k_n μ_r² R² = 2.25 × 1e4 × 0.01 × 4e-6 = 9e-4 N m/rad.
        let (k_n, f_n, dt) = (1.0e4, 5.0, 1.0e-3);
        let k_r = 9.0e-4;
        let n = [0.0, 0.0, 1.0];
        let mut h = [0.0; 3];
        // Spin about y (rolling) plus twist about z: only rolling counts.
        let t = r.torque(f_n, k_n, 0.0, 1.0, n, [0.0, 3.0, 7.0], dt, &mut h);
        assert_eq!(t[2], 0.0);
        assert!((t[1] + k_r * 3.0 * dt).abs() < 1e-18, "{t:?}");
        // Keeps rolling: the spring reaches μ_r R F_n = 1e-3 N m and stays.
        for _ in 0..1000 {
            r.torque(f_n, k_n, 0.0, 1.0, n, [0.0, 3.0, 0.0], dt, &mut h);
        }
        assert!((h[1] + 1.0e-3).abs() < 1e-18, "{h:?}");
        // Damping below the limit: −2 ξ √(k_r I) ω_r on top of the spring.
        let mut h = [0.0; 3];
        let t = r.torque(f_n, k_n, 0.5, 4.0, n, [0.0, 1.0, 0.0], 0.0, &mut h);
        assert!((t[1] + 2.0 * 0.5 * (k_r * 4.0f64).sqrt()).abs() < 1e-15);
        // No coefficient: nothing, and the history is cleared.
        let z = Epsd2 {
            coefficient: 0.0,
            radius: 2.0e-3,
        };
        let mut h = [1.0; 3];
        assert_eq!(
            z.torque(f_n, k_n, 0.5, 1.0, n, [0.0, 1.0, 0.0], dt, &mut h),
            [0.0; 3]
        );
        assert_eq!(h, [0.0; 3]);
    }
}
