//! A contact's stiffest point: its linearisation at the largest overlap it
//! can reach, the ω and β of the step bound of a damped contact under
//! Gear5 ([`crate::integrate::gear5_stability`]).
//!
//! Every normal law here stiffens with the overlap (∂F/∂h = α k h^(α−1),
//! α ≥ 1) and every damping's coefficient grows with it or is constant
//! (c, γ h^(1/4), (3/2) k A h^(1/2)), so both are largest at the largest
//! overlap. That overlap is bounded by the energy balance of the undamped
//! law, E_el(h) = ½ m v² + m g h (damping only removes energy; g the
//! relative gravity pressing the bodies together): a bound, reached by a
//! weakly damped contact and overestimated for a strongly damped one.
//! There the linearisation is
//!
//!   ω² = (∂F_n/∂h)/m (a central difference of the normal force, relative
//!   step 1e−4: error ~1e−8 relative for the power laws),
//!   β = F_d(h, ḣ = 1 m/s)/m (exact: each damping force is its
//!   coefficient at h times ḣ).
//!
//! The damping's h-derivative, (∂F_d/∂h) ḣ, adds to the stiffness where
//! ḣ ≠ 0; it vanishes at the largest overlap (ḣ = 0) and is left out.

use roots::find_root_brent;

use super::calibration::Ulps;
use super::{ContactHistory, PairLaw};

/// A contact linearised as ẍ = −ω² x − β ẋ at one overlap.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Linearization {
    /// The overlap it is taken at, m.
    pub overlap: f64,
    /// ω = √((∂F/∂h)/m), rad/s.
    pub omega: f64,
    /// β = (∂F/∂ḣ)/m, 1/s.
    pub rate: f64,
}

/// The largest overlap (m) of a contact whose undamped law stores
/// `energy(h)` (J) at overlap h, for a body of `mass` (kg) meeting it at
/// `impact_speed` (m/s) under relative gravity `gravity` (m/s², pressing
/// the bodies together): the root of E_el(h) = ½ m v² + m g h, bracketed
/// by doubling (E_el grows faster than linearly), then Brent's method. 0
/// when there is nothing to store.
pub fn largest_overlap(
    energy: impl Fn(f64) -> f64,
    mass: f64,
    impact_speed: f64,
    gravity: f64,
) -> f64 {
    let excess =
        |h: f64| energy(h) - mass * (0.5 * impact_speed * impact_speed + gravity.max(0.0) * h);
    if impact_speed == 0.0 && gravity <= 0.0 {
        return 0.0;
    }
    let mut hi = 1e-12;
    let mut doublings = 0;
    while excess(hi) < 0.0 {
        hi *= 2.0;
        doublings += 1;
        if doublings > 2100 || !hi.is_finite() {
            return f64::INFINITY;
        }
    }
    // A lower end with excess < 0 (excess(0) is 0 under gravity alone,
    // where Brent would take h = 0 for the root): hi/2 after a doubling,
    // halvings when the first guess already holds the root.
    let mut lo = hi;
    while lo > 0.0 && excess(lo) >= 0.0 {
        lo *= 0.5;
    }
    // Brent's method (`roots`), as the calibration's roots
    // ([`super::calibration::Ulps`]).
    find_root_brent(lo, hi, excess, &mut Ulps).unwrap_or(hi)
}

/// The linearisation at `overlap` (m) of a contact of `mass` (kg) whose
/// normal force is `normal_force(h)` (N) and damping force at unit overlap
/// rate `damping_per_rate(h)` (N per m/s).
pub fn linearize(
    normal_force: impl Fn(f64) -> f64,
    damping_per_rate: impl Fn(f64) -> f64,
    overlap: f64,
    mass: f64,
) -> Linearization {
    let step = 1e-4 * overlap;
    let stiffness = if step > 0.0 {
        (normal_force(overlap + step) - normal_force(overlap - step)) / (2.0 * step)
    } else {
        0.0
    };
    Linearization {
        overlap,
        omega: (stiffness.max(0.0) / mass).sqrt(),
        rate: damping_per_rate(overlap).max(0.0) / mass,
    }
}

impl PairLaw {
    /// This pair's linearisation at the largest overlap of an impact at
    /// `impact_speed` (m/s) under relative gravity `gravity` (m/s²)
    /// (module doc), from a fresh contact's history.
    pub fn peak_linearization(&self, impact_speed: f64, gravity: f64) -> Linearization {
        let history = ContactHistory::default();
        let overlap = largest_overlap(
            |h| self.elastic_energy(h, &history),
            self.mass(),
            impact_speed,
            gravity,
        );
        linearize(
            |h| self.normal().force(h, 0.0, &history),
            |h| self.damping().force(h, 1.0),
            overlap,
            self.mass(),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hertz_peak_is_the_closed_form() {
        // F = k h^(3/2): h_max = (5 m v²/(4 k))^(2/5) (paper eq 29),
        // ∂F/∂h = (3/2) k h^(1/2); Tsuji's γ h^(1/4) at h_max.
        let (k, m, v, gamma) = (2.0e9, 3.0e-6, 0.7, 0.05);
        let h = largest_overlap(|h: f64| 0.4 * k * h.powf(2.5), m, v, 0.0);
        let h_exact = (1.25 * m * v * v / k).powf(0.4);
        assert!((h / h_exact - 1.0).abs() < 1e-12, "{h} {h_exact}");
        let lin = linearize(
            |h: f64| k * h.powf(1.5),
            |h: f64| gamma * h.powf(0.25),
            h,
            m,
        );
        let omega = (1.5 * k * h_exact.sqrt() / m).sqrt();
        // The central difference's error: (α−2)(α−1)/6 · (1e−4)² /… ≈ 1e−10.
        assert!((lin.omega / omega - 1.0).abs() < 1e-8, "{lin:?} {omega}");
        assert!((lin.rate / (gamma * h_exact.powf(0.25) / m) - 1.0).abs() < 1e-12);
    }

    #[test]
    fn gravity_adds_its_work() {
        // Linear spring at rest on contact: ½ k h² = m g h, h = 2 m g/k
        // (the overshoot of a sudden load: twice the static overlap).
        let (k, m, g) = (1.0e5, 2.0e-3, 9.81);
        let h = largest_overlap(|h| 0.5 * k * h * h, m, 0.0, g);
        assert!((h / (2.0 * m * g / k) - 1.0).abs() < 1e-12, "{h}");
        assert_eq!(largest_overlap(|h| 0.5 * k * h * h, m, 0.0, 0.0), 0.0);
    }
}
