//! The closed-form references of the impact benchmarks, derived here from
//! the theory, independently of the engine and the physics crate.
//!
//! - Hertz (1882), as in Johnson, *Contact Mechanics* (1985) §11.1: two
//!   elastic spheres (or a sphere and a plane) approaching at v, with
//!   1/E* = (1 − ν₁²)/E₁ + (1 − ν₂²)/E₂, R* = R₁R₂/(R₁ + R₂) and
//!   m* = m₁m₂/(m₁ + m₂), F = (4/3) E* √R* h^(3/2). Energy:
//!   ½ m* v² = (8/15) E* √R* h_max^(5/2), so
//!   h_max = (15 m* v²/(16 E* √R*))^(2/5), F_max = (4/3) E* √R* h_max^(3/2),
//!   and the duration T_c = 2 (h_max/v) ∫₀¹ dx/√(1 − x^(5/2)) (time to
//!   the largest overlap from ½ m* ḣ² = ½ m* v² (1 − (h/h_max)^(5/2)),
//!   doubled by symmetry); the integral (≈ 1.4716) is computed below by
//!   quadrature, not taken from a table.
//! - Rigid-body impact with Coulomb friction throughout the contact
//!   (Maw, Barber & Fawcett 1976; Wu, Thornton & Li 2003, the "sliding"
//!   limit Chung & Ooi 2011 quote for Tests 4–8): the normal impulse is
//!   P_n = m*(1 + e) v_n; while the contact slides the tangential impulse
//!   is −μ P_n against the slip s (the tangential velocity of the contact
//!   point of body 1 relative to body 2). For solid spheres
//!   (I = (2/5) m R²) the slip changes by
//!   Δs = −μ P_n Σ (1/m_k + R_k²/I_k) = −(7/2) μ (1 + e) v_n (the sum over
//!   both bodies is (7/2)(1/m₁ + 1/m₂), and P_n (1/m₁ + 1/m₂) = (1 + e) v_n;
//!   a fixed plane adds nothing): the same for a sphere on a plane and for
//!   two spheres of any sizes. The contact slides throughout if and only
//!   if |s₀| ≥ (7/2) μ (1 + e) v_n; then a sphere's centre changes its
//!   tangential velocity by μ(1 + e) v_n m*/m and its spin by
//!   (5/2) μ (1 + e) v_n (m*/m)/R. Below the threshold the rigid theory
//!   has the slip stop (rolling: the centre keeps 5/7 of its tangential
//!   velocity on a plane); an elastic tangential spring makes it reverse,
//!   which only the integration of the contact describes.

/// ∫₀¹ dx/√(1 − x^(5/2)), by the substitution x = 1 − t² (which removes
/// the end-point singularity: the integrand 2t/√(1 − (1 − t²)^(5/2)) tends
/// to 2/√(5/2) at t = 0) and composite Simpson on 20,000 panels: the
/// integrand is smooth, so the error is far below 1e-12.
pub fn hertz_time_integral() -> f64 {
    let f = |t: f64| {
        if t == 0.0 {
            2.0 / 2.5f64.sqrt()
        } else {
            let x = 1.0 - t * t;
            2.0 * t / (1.0 - x * x * x.sqrt()).sqrt()
        }
    };
    let n = 20_000;
    let h = 1.0 / n as f64;
    let mut sum = f(0.0) + f(1.0);
    for k in 1..n {
        let w = if k % 2 == 1 { 4.0 } else { 2.0 };
        sum += w * f(k as f64 * h);
    }
    sum * h / 3.0
}

/// One elastic body in a Hertz contact: E (Pa; `f64::INFINITY` for a rigid
/// plane), ν, R (m; `f64::INFINITY` for a plane), m (kg; infinite for a
/// fixed body).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Body {
    pub youngs_modulus: f64,
    pub poisson_ratio: f64,
    pub radius: f64,
    pub mass: f64,
}

/// What Hertz's theory predicts for a normal impact at approach speed v.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HertzImpact {
    /// Largest overlap, m.
    pub max_overlap: f64,
    /// Largest normal force, N.
    pub max_force: f64,
    /// Contact duration, s.
    pub duration: f64,
}

fn harmonic(a: f64, b: f64) -> f64 {
    // 1/(1/a + 1/b) with an infinite partner contributing nothing.
    match (a.is_finite(), b.is_finite()) {
        (true, true) => a * b / (a + b),
        (true, false) => a,
        (false, true) => b,
        (false, false) => f64::INFINITY,
    }
}

/// Hertz's normal impact of `a` on `b` at relative approach speed `v`, m/s.
pub fn hertz_impact(a: Body, b: Body, v: f64) -> HertzImpact {
    let compliance = |k: Body| {
        if k.youngs_modulus.is_finite() {
            (1.0 - k.poisson_ratio * k.poisson_ratio) / k.youngs_modulus
        } else {
            0.0
        }
    };
    let e_star = 1.0 / (compliance(a) + compliance(b));
    let r_star = harmonic(a.radius, b.radius);
    let m_star = harmonic(a.mass, b.mass);
    let k = 4.0 / 3.0 * e_star * r_star.sqrt();
    // ½ m* v² = (2/5) k h_max^(5/2).
    let max_overlap = (1.25 * m_star * v * v / k).powf(0.4);
    HertzImpact {
        max_overlap,
        max_force: k * max_overlap.powf(1.5),
        duration: 2.0 * max_overlap / v * hertz_time_integral(),
    }
}

/// The slip at which a rigid-body impact slides throughout:
/// (7/2) μ (1 + e) v_n, m/s (module doc).
pub fn sliding_threshold(friction: f64, restitution: f64, normal_speed: f64) -> f64 {
    3.5 * friction * (1.0 + restitution) * normal_speed
}

/// The contact-point slip after an impact that slides throughout, from
/// s₀ (same sign convention), m/s.
pub fn sliding_final_slip(s0: f64, friction: f64, restitution: f64, normal_speed: f64) -> f64 {
    s0 - s0.signum() * sliding_threshold(friction, restitution, normal_speed)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_hertz_integral_is_the_beta_function_value() {
        // ∫₀¹ (1 − x^(5/2))^(−1/2) dx = (2/5) B(2/5, 1/2)
        // = (2/5) Γ(2/5) Γ(1/2)/Γ(9/10); Γ(0.4) = 2.218159543757688,
        // Γ(0.9) = 1.068628702119319 (Abramowitz & Stegun table 6.1):
        // 0.4 × 2.218159543757688 × √π/1.068628702119319.
        let exact =
            0.4 * 2.218_159_543_757_688 * std::f64::consts::PI.sqrt() / 1.068_628_702_119_319;
        assert!(
            (hertz_time_integral() - exact).abs() < 1e-12,
            "{}",
            hertz_time_integral()
        );
    }

    #[test]
    fn the_hertz_impact_matches_the_textbook_contact_time() {
        // Johnson (1985) eq 11.24: T_c = 2.868 (m*²/(R* E*² v))^(1/5) with
        // E* the plain effective modulus; three printed digits.
        let glass = Body {
            youngs_modulus: 4.8e10,
            poisson_ratio: 0.2,
            radius: 0.01,
            mass: 4.0 / 3.0 * std::f64::consts::PI * 2800.0 * 1e-6,
        };
        let h = hertz_impact(glass, glass, 20.0);
        let e_star: f64 = 4.8e10 / (2.0 * (1.0 - 0.04));
        let (m, r) = (0.5 * glass.mass, 0.005);
        let johnson = 2.868 * (m * m / (r * e_star * e_star * 20.0)).powf(0.2);
        assert!(
            (h.duration / johnson - 1.0).abs() < 1e-3,
            "{} vs {johnson}",
            h.duration
        );
        // Energy: the work of the Hertz force to h_max is ½ m* v².
        let work = 0.4 * h.max_force * h.max_overlap;
        assert!((work / (0.5 * m * 400.0) - 1.0).abs() < 1e-12);
    }

    #[test]
    fn sliding_slip_drops_by_the_threshold() {
        assert_eq!(sliding_threshold(0.4, 0.5, 0.2), 3.5 * 0.4 * 1.5 * 0.2);
        let s = sliding_final_slip(-1.0, 0.4, 0.5, 0.2);
        assert!((s - (-1.0 + 0.42)).abs() < 1e-15);
    }
}
