//! dembound's rolling spring (crates/dembound-physics/src/contact/rolling.rs)
//! as Yade's `CohFrictMat` moment law, for `contact.law = { hooke = k }`
//! with spheres of one radius R (docs/export-yade.md, "Rolling friction").
//!
//! dembound, per pair: k_r = 2.25 k μ_r² R_eff², the torque capped at
//! μ_r R_eff |F_n|, with R_eff = R/2 between two spheres and R against a
//! plane; μ_r of a pair is √(μ_a μ_b); the viscous term acts only when the
//! contact is damped, which Hooke scenes exported to Yade never are.
//!
//! Yade 2023.02a (`Ip2_CohFrictMat_CohFrictMat_CohFrictPhys`, measured on
//! the installed build: a pair's `CohFrictPhys` after one step):
//! k_r = α k_s D₁ D₂ with α = 2 α₁ α₂/(α₁ + α₂) (the materials' `alphaKr`)
//! and k_s the pair's shear stiffness; the cap `maxRollPl` |F_n| with
//! maxRollPl = min(η₁ D₁, η₂ D₂) (`etaRoll`); D = R for a sphere and, for
//! a box face (`Ig2_Box_Sphere_ScGeom6D`), the sphere's R again. So with
//! the free spheres' α_s, η_s:
//! - two free spheres: α_s k_s R² = 2.25 k μ_r² R²/4 and η_s R = μ_r R/2
//!   give α_s = 9 k μ_r²/(16 k_s) and η_s = μ_r/2, exactly;
//! - another body (a fixed-sphere material or a plane): its α follows from
//!   the harmonic mean (which cannot exceed 2 α_s), its η is the pair's cap
//!   over R, which min(η_o, η_s) reaches only while it is ≤ η_s = μ_r/2: a
//!   plane's cap μ_r,pair R therefore needs μ_r,pair ≤ μ_r/2 of the spheres.
//!   A plane of the spheres' own μ_r (the usual case) is refused.

/// `alphaKr` and `etaRoll` of one Yade material.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Rolling {
    pub alpha_kr: f64,
    pub eta_roll: f64,
}

/// dembound's (R_eff/R)² and R_eff/R against a plane (`wall`) or a sphere
/// of the same radius.
fn ratios(wall: bool) -> (f64, f64) {
    if wall {
        (1.0, 1.0)
    } else {
        (0.25, 0.5)
    }
}

/// The free spheres' material: `k` (N/m), their μ_r and Yade's k_s of a
/// pair of them (N/m).
pub fn free_spheres(k: f64, mu_r: f64, ks: f64) -> Rolling {
    let (r2, r1) = ratios(false);
    Rolling {
        alpha_kr: 2.25 * k * mu_r * mu_r * r2 / ks,
        eta_roll: mu_r * r1,
    }
}

/// Why a pair cannot be written: the text after "cannot be exported to Yade:".
pub type Refusal = String;

/// The material of a body met by the free spheres (`free`): the pair's
/// mixed μ_r `mu_r_pair`, Yade's k_s of the pair `ks` (N/m), `wall` for a
/// plane (box face). Err: which of k_r and the cap Yade cannot reach.
pub fn other(
    free: Rolling,
    k: f64,
    mu_r_pair: f64,
    ks: f64,
    wall: bool,
) -> Result<Rolling, Refusal> {
    let (r2, r1) = ratios(wall);
    let alpha_pair = 2.25 * k * mu_r_pair * mu_r_pair * r2 / ks;
    let a = free.alpha_kr;
    // 2 a α/(a + α) = α_pair.
    let alpha_kr = if alpha_pair == 0.0 {
        0.0
    } else if (alpha_pair / (2.0 * a) - 1.0).abs() < 1e-12 {
        // The harmonic mean's limit: α = 1e12 a gives α_pair (1 − 1e-12).
        1e12 * a
    } else if alpha_pair < 2.0 * a {
        alpha_pair * a / (2.0 * a - alpha_pair)
    } else {
        return Err(format!(
            "its rolling stiffness alpha k_s R^2 needs alpha = {alpha_pair:e}, more than twice \
             the spheres' alphaKr = {a:e}, and Yade takes the harmonic mean of the two"
        ));
    };
    let cap = mu_r_pair * r1;
    if cap > free.eta_roll * (1.0 + 1e-12) {
        return Err(format!(
            "its rolling cap mu_r R_eff |F_n| = {cap:e} R |F_n| (mu_r = {mu_r_pair}, R_eff = {}) \
             is above the spheres' own etaRoll R |F_n| = {:e} R |F_n| (mu_r/2 of the spheres, \
             their pairs' cap at R_eff = R/2), and Yade caps a pair at min(eta_1 R, eta_2 R)",
            if wall { "R" } else { "R/2" },
            free.eta_roll
        ));
    }
    Ok(Rolling {
        alpha_kr,
        eta_roll: cap,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Yade's pair numbers (Ip2_CohFrictMat_CohFrictMat_CohFrictPhys as
    /// measured): k_r = 2 α₁α₂/(α₁ + α₂) k_s R², cap min(η₁, η₂) R.
    fn yade_pair(a: Rolling, b: Rolling, ks: f64, r: f64) -> (f64, f64) {
        let alpha = if a.alpha_kr == 0.0 || b.alpha_kr == 0.0 {
            0.0
        } else {
            2.0 * a.alpha_kr * b.alpha_kr / (a.alpha_kr + b.alpha_kr)
        };
        (alpha * ks * r * r, a.eta_roll.min(b.eta_roll) * r)
    }

    #[test]
    fn pairs_get_dembounds_spring_and_cap() {
        // The chute: k = 50 N/m, μ_r = 0.1, R = 0.5 mm; k_s of a sphere pair
        // 2/7 E_eff R/2 and twice that against a plane.
        let (k, mu_r, r) = (50.0, 0.1, 0.5e-3);
        let ks = 2.0 / 7.0 * (4.0 / 3.0 / (2.0 * 0.91 / 1.0e7)) * r / 2.0;
        let s = free_spheres(k, mu_r, ks);
        let (kr, cap) = yade_pair(s, s, ks, r);
        // dembound: 2.25 k μ_r² (R/2)², μ_r R/2 (written out).
        let want = 2.25 * k * mu_r * mu_r * (r / 2.0) * (r / 2.0);
        // Round-off of a few operations: 1e-15.
        assert!((kr / want - 1.0).abs() < 1e-15, "{kr} vs {want}");
        assert!((cap / (mu_r * r / 2.0) - 1.0).abs() < 1e-15);
        // A plane of pair μ_r = 0.05 (wall μ_r 0.025): exact.
        let mu_w = (mu_r * 0.025f64).sqrt();
        let w = other(s, k, mu_w, 2.0 * ks, true).expect("expressible");
        let (kr, cap) = yade_pair(s, w, 2.0 * ks, r);
        let want = 2.25 * k * mu_w * mu_w * r * r;
        assert!((kr / want - 1.0).abs() < 1e-14, "{kr} vs {want}");
        assert!((cap / (mu_w * r) - 1.0).abs() < 1e-15);
        // A plane of the spheres' own μ_r: the cap μ_r R is twice η_s R.
        let e = other(s, k, mu_r, 2.0 * ks, true).expect_err("refused");
        assert!(e.contains("rolling cap"), "{e}");
        // Fixed spheres of μ_r 0.05 (pair √0.005), same k_s: exact.
        let mu_p = (mu_r * 0.05f64).sqrt();
        let f = other(s, k, mu_p, ks, false).expect("expressible");
        let (kr, cap) = yade_pair(s, f, ks, r);
        let want = 2.25 * k * mu_p * mu_p * r * r / 4.0;
        assert!((kr / want - 1.0).abs() < 1e-14 && (cap / (mu_p * r / 2.0) - 1.0).abs() < 1e-15);
        // A stiffer rolling spring than the harmonic mean can reach.
        let e = other(s, k, mu_r, 0.4 * ks, false).expect_err("refused");
        assert!(e.contains("harmonic mean"), "{e}");
    }
}
