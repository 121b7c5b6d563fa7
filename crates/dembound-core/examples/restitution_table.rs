//! The closing note of the restitution study: the effective restitution at
//! r = ζ = 100 and on the rigid half-space r = ζ = ∞, for target e = 0.5 and
//! 0.9 under each dissipative law, with both e → coefficient mappings
//! (`contact.calibration`: "exact", the default, and LIGGGHTS' "formula").
//!
//! The validation drop (5 mm, g = 9.81, Gear5, η = 1/50, event stepping,
//! attraction forbidden). "pair" sets each pair's damping from the target
//! with that pair's own k (and, for the viscoelastic law, its own first
//! impact speed); "wall" keeps the raw coefficient calibrated on the
//! half-space and applies it to r = ζ = 100. The `dembound paper` report
//! prints the same numbers (its "beyond the paper" closing note).
//!
//! `cargo run --release -p dembound-core --example restitution_table`

use dembound_core::bounce::Scenario;
use dembound_core::contact::Calibration;
use dembound_core::study::restitution::{
    raw_coefficient, simulate_coefficient, CalibrationSite, DissipativeLaw,
};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    println!(
        "effective restitution v_r/|v_c|, validation drop (impact 0.313 m/s, g = 9.81), attraction forbidden"
    );
    println!(
        "{:<13} {:<4} | {:>10} {:>10} {:>10} | {:>10} {:>10} {:>10}",
        "law", "e", "∞ exact", "100 pair", "100 wall", "∞ formula", "100 pair", "100 wall"
    );
    for law in DissipativeLaw::ALL {
        for e in [0.5, 0.9] {
            let mut cells = Vec::new();
            for mapping in [Calibration::Exact, Calibration::Formula] {
                let mut base = Scenario::default();
                base.contact.calibration = Some(mapping);
                let inf = f64::INFINITY;
                for (cal, r) in [
                    (CalibrationSite::Pair, inf),
                    (CalibrationSite::Pair, 100.0),
                    (CalibrationSite::Wall, 100.0),
                ] {
                    let c = raw_coefficient(&base, law, cal, e, r, r)?;
                    cells.push(simulate_coefficient(&base, law, c, r, r)?.restitution);
                }
            }
            println!(
                "{:<13} {e:<4} | {:>10.6} {:>10.6} {:>10.6} | {:>10.6} {:>10.6} {:>10.6}",
                law.name(),
                cells[0],
                cells[1],
                cells[2],
                cells[3],
                cells[4],
                cells[5]
            );
        }
    }
    Ok(())
}
