//! What `recommend`'s boundary-sphere size means as a wall (issue 29 item
//! 5): touching boundary spheres of radius R_b = r R tiling a plane leave
//! windows through which a sphere of radius (√2 − 1) R_b (square) or
//! (2/√3 − 1) R_b (hexagonal) passes (the window's circumradius, s/√2 or
//! s/√3 with s = 2 R_b, minus R_b). A particle of radius R passes unless
//! r ≤ 1/(√2 − 1) = 2.414 (square) or 1/(2/√3 − 1) = 6.464 (hexagonal).

use crate::output::format::sig;

/// Hole radius of a touching square tiling, in units of R_b.
pub const SQUARE_HOLE: f64 = std::f64::consts::SQRT_2 - 1.0;

/// Hole radius of a touching hexagonal tiling, in units of R_b.
pub fn hexagonal_hole() -> f64 {
    2.0 / 3f64.sqrt() - 1.0
}

/// One line about radius ratio `r` as a tiled wall (none for r = ∞: a
/// flat wall).
pub fn hole_line(r: f64) -> Option<String> {
    if !r.is_finite() || r <= 0.0 {
        return None;
    }
    let (square, hex) = (SQUARE_HOLE * r, hexagonal_hole() * r);
    let verdict = |hole: f64| {
        if hole < 1.0 {
            "leak-free for the particle"
        } else {
            "NOT a wall: the particle falls through"
        }
    };
    Some(format!(
        "r = {} as a wall of touching spheres: holes of radius {} R square ({}), {} R hexagonal ({}); \
         leak-free needs r ≤ 2.414 (square) or 6.464 (hexagonal); `dembound particle-wall` gives the \
         hole of a covered part\n",
        sig(r, 5),
        sig(square, 4),
        verdict(square),
        sig(hex, 4),
        verdict(hex)
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn thresholds_and_glass_on_steel() {
        // r = 1/(√2 − 1) = 1 + √2 is the square tiling's threshold.
        assert!((1.0 / SQUARE_HOLE - (1.0 + 2f64.sqrt())).abs() < 1e-12);
        assert!((1.0 / hexagonal_hole() - 6.464).abs() < 1e-3);
        // The README's glass-on-steel answer r = 39.6: holes of 16.4 R
        // (square) — a sieve.
        let line = hole_line(39.602).unwrap();
        assert!(
            line.contains("16.4") && line.contains("NOT a wall"),
            "{line}"
        );
        assert!(hole_line(f64::INFINITY).is_none());
        assert!(hole_line(2.0)
            .unwrap()
            .contains("0.8284 R square (leak-free"));
    }
}
