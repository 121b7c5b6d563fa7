//! The sweep shared by `benches/batch.rs` and `examples/batch_throughput.rs`
//! (the example includes this file by path), so both measure the same cases.

use dembound_core::bounce::Scenario;

/// n Hertz cases spread over r ∈ [0.5, 10⁴], ζ ∈ [0.1, 10⁴] and
/// gap ∈ [0.1, 10] mm: the validation case otherwise.
pub fn sweep(n: usize) -> Vec<Scenario> {
    (0..n)
        .map(|i| {
            let u = |k: usize| ((i * k) % 1000) as f64 / 1000.0;
            let mut s = Scenario::default();
            s.boundary.radius_ratio = 10f64.powf(-0.3 + 4.3 * u(7));
            s.boundary.modulus_ratio = 10f64.powf(-1.0 + 5.0 * u(13));
            s.motion.gap = 10f64.powf(-4.0 + 2.0 * u(31));
            s
        })
        .collect()
}
