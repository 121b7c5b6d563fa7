//! Rolling resistance, LIGGGHTS `rolling_friction epsd2` (Iwashita & Oda
//! 1998 in the constant-torque form of Ai, Chen, Rotter & Ooi, Powder
//! Technol. 206, 269 (2011), model A): a torque of constant magnitude
//! μ_r R_eff |F_n| against the relative rolling velocity, ω_r = the part of
//! ω₁ − ω₂ in the tangent plane (twisting is not resisted).

/// τ₁ = −μ_r R_eff |F_n| ω_r/|ω_r|.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Epsd2 {
    /// μ_r, dimensionless.
    pub coefficient: f64,
    /// R_eff, m.
    pub radius: f64,
}

/// Below this relative rolling speed (rad/s) the torque is zero: the
/// direction is undefined at rest.
pub const ROLLING_REST: f64 = 1.0e-12;

impl Epsd2 {
    /// Torque on body 1 (N m) for normal force `normal_force` (N), unit
    /// normal `normal` and relative spin ω₁ − ω₂ (rad/s).
    #[inline(always)]
    pub fn torque(&self, normal_force: f64, normal: [f64; 3], relative_spin: [f64; 3]) -> [f64; 3] {
        if self.coefficient == 0.0 {
            return [0.0; 3];
        }
        let w = relative_spin;
        let along = w[0] * normal[0] + w[1] * normal[1] + w[2] * normal[2];
        let r = [
            w[0] - along * normal[0],
            w[1] - along * normal[1],
            w[2] - along * normal[2],
        ];
        let m = (r[0] * r[0] + r[1] * r[1] + r[2] * r[2]).sqrt();
        if m <= ROLLING_REST {
            return [0.0; 3];
        }
        let s = -self.coefficient * self.radius * normal_force.abs() / m;
        [s * r[0], s * r[1], s * r[2]]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn constant_torque_against_rolling_only() {
        let r = Epsd2 {
            coefficient: 0.1,
            radius: 2.0e-3,
        };
        // Spin about y (rolling) plus twist about the normal z: only the
        // rolling part is resisted, with magnitude μ_r R F_n (exact up to
        // a rounding: 0.1 × 2e-3 × 5 = 1e-3 N m).
        let t = r.torque(5.0, [0.0, 0.0, 1.0], [0.0, 3.0, 7.0]);
        assert_eq!(t[2], 0.0);
        assert_eq!(t[0], 0.0);
        assert!((t[1] + 1.0e-3).abs() < 1e-18, "{t:?}");
        // The magnitude does not depend on the speed.
        let u = r.torque(5.0, [0.0, 0.0, 1.0], [0.0, 3.0e-6, 0.0]);
        assert!((u[1] - t[1]).abs() < 1e-18);
        // At rest, none.
        assert_eq!(r.torque(5.0, [0.0, 0.0, 1.0], [0.0, 0.0, 2.0]), [0.0; 3]);
    }
}
