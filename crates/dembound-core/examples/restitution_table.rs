//! Effective restitution of the dissipative laws at r = ζ = 100 against the
//! rigid half-space r = ζ = ∞, for target e = 0.5 and 0.9.
//!
//! The validation drop (5 mm, g = 9.81, Gear5, η = 1/50, event stepping,
//! attraction forbidden). "own" sets each pair's damping from the target
//! with that pair's own k (and, for the viscoelastic law, its own first
//! impact speed); "fixed" keeps the raw coefficient calibrated on the
//! half-space and applies it to r = ζ = 100.
//!
//! `cargo run --release -p dembound-core --example restitution_table`

use dembound_core::bounce::{simulate, Scenario};
use dembound_core::contact::{
    ContactLawKind, DampingKind, Dissipation, HertzTsuji, HertzViscoelastic, LinearDashpot,
};
use dembound_core::material::{Boundary, ContactPair};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let models = [
        (ContactLawKind::Linear, DampingKind::Viscous),
        (ContactLawKind::Hertz, DampingKind::Tsuji),
        (ContactLawKind::Hertz, DampingKind::Viscoelastic),
        (ContactLawKind::WaltonBraun, DampingKind::None),
    ];
    println!("law           e_target  e(∞,own)   e(100,own)  e(100,fixed)  contact 2 (100,own)");
    for (law, damping) in models {
        for e in [0.5, 0.9] {
            let base = |r: f64| {
                let mut s = Scenario::default();
                s.contact.law = law;
                s.contact.damping = damping;
                s.contact.restitution = Some(e);
                s.boundary.radius_ratio = r;
                s.boundary.modulus_ratio = r;
                s
            };
            let inf = base(f64::INFINITY);
            let hundred = base(100.0);
            let run_inf = simulate(&inf, &mut ())?;
            let run_100 = simulate(&hundred, &mut ())?;
            // The half-space's raw coefficient applied at r = ζ = 100.
            let m = inf.particle.mass();
            let pair_inf = ContactPair::new(inf.particle, Boundary::RIGID_HALF_SPACE);
            let target = Dissipation::Restitution(e);
            let raw = match damping {
                DampingKind::Viscous => Some(LinearDashpot::for_pair(&pair_inf, m, target).damping),
                DampingKind::Tsuji => Some(HertzTsuji::for_pair(&pair_inf, m, target).damping),
                DampingKind::Viscoelastic => Some(
                    HertzViscoelastic::for_pair(&pair_inf, m, target, inf.impact_speed(), false)?.a,
                ),
                DampingKind::None => None,
            };
            let fixed = match raw {
                Some(c) => {
                    let mut s = hundred;
                    s.contact.restitution = None;
                    s.contact.damping_coefficient = Some(c);
                    simulate(&s, &mut ())?.contacts[0].restitution
                }
                None => {
                    // Walton–Braun: k2 = k1(∞)/e² kept, k1 of r = ζ = 100 (g = 0 exact).
                    let k1_100 = hundred.pair().power_law_stiffness(1.0);
                    let k2 = pair_inf.power_law_stiffness(1.0) / (e * e);
                    (k1_100 / k2).sqrt()
                }
            };
            println!(
                "{:<13} {e:<8}  {:.6}   {:.6}    {:.6}      {:.6}",
                format!("{}/{}", law.name(), damping.name()),
                run_inf.contacts[0].restitution,
                run_100.contacts[0].restitution,
                fixed,
                run_100.contacts[1].restitution,
            );
        }
    }
    Ok(())
}
