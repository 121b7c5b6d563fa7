//! Relative errors of the damped Hertz laws (Tsuji, viscoelastic) against
//! the adaptive reference, per e, impact speed, attraction setting, scheme
//! and stepping, at η = 1/50; with the steps spent in the contact.
//!
//! `cargo run --release -p dembound-core --example damped_hertz_errors`

use dembound_core::bounce::{simulate, Scenario, Stepping};
use dembound_core::contact::{
    Calibration, ContactLawKind, DampingKind, Dissipation, HertzTsuji, HertzViscoelastic,
};
use dembound_core::integrate::Scheme;
use dembound_core::reference::dissipative::{damped_hertz, DampedHertz};

fn rel(a: f64, b: f64) -> f64 {
    (a / b - 1.0).abs()
}

fn category(a: &str) -> u8 {
    match a {
        "gear5" | "verlet" => 0,
        "event" | "fixed" => 1,
        "attr" | "noattr" => 2,
        _ => 3,
    }
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let eta: f64 = args.first().and_then(|s| s.parse().ok()).unwrap_or(0.02);
    let only = |what: &str| args.len() < 2 || args[1..].iter().any(|a| a == what);
    println!("law           e    v(m/s)  g     attr  scheme stepping |  e err     T_c err   h_max err  t_mp err  tF0 err  | steps");
    let mut worst = [[0.0f64; 2]; 2];
    for damping in [DampingKind::Tsuji, DampingKind::Viscoelastic] {
        let targets: Vec<f64> = std::env::var("TARGETS")
            .ok()
            .map(|s| s.split(',').filter_map(|x| x.parse().ok()).collect())
            .unwrap_or_else(|| vec![0.3, 0.5, 0.9]);
        for &e in &targets {
            for (v, g) in [(0.01, 0.0), (0.313, 0.0), (3.0, 0.0), (0.0, 9.81)] {
                for attractive in [true, false] {
                    for scheme in [Scheme::Gear5, Scheme::Verlet] {
                        for stepping in [Stepping::Event, Stepping::Fixed] {
                            let names = [
                                scheme.name(),
                                if stepping == Stepping::Event {
                                    "event"
                                } else {
                                    "fixed"
                                },
                                if attractive { "attr" } else { "noattr" },
                                damping.name(),
                            ];
                            if !names.iter().all(|n| {
                                only(n)
                                    || !args[1..].iter().any(|a| {
                                        [
                                            "gear5",
                                            "verlet",
                                            "event",
                                            "fixed",
                                            "attr",
                                            "noattr",
                                            "tsuji",
                                            "viscoelastic",
                                        ]
                                        .contains(&a.as_str())
                                            && category(a) == category(n)
                                    })
                            }) {
                                continue;
                            }
                            let mut s = Scenario::default();
                            s.contact.law = ContactLawKind::Hertz;
                            s.contact.damping = damping;
                            s.contact.restitution = Some(e);
                            s.contact.attractive = attractive;
                            s.motion.contacts = 1;
                            s.motion.gravity = g;
                            if g == 0.0 {
                                s.motion.velocity = -v;
                            }
                            s.integration.scheme = scheme;
                            s.integration.stepping = stepping;
                            s.integration.eta = Some(eta);
                            let (k, m) = (s.pair().power_law_stiffness(1.5), s.particle.mass());
                            let speed = s.impact_speed();
                            let target = Dissipation::Restitution(e);
                            let model = match damping {
                                DampingKind::Tsuji => DampedHertz::Tsuji {
                                    stiffness: k,
                                    damping: HertzTsuji::calibrated(
                                        &s.pair(),
                                        m,
                                        target,
                                        Calibration::Exact,
                                        attractive,
                                    )
                                    .damping,
                                },
                                _ => DampedHertz::Viscoelastic {
                                    stiffness: k,
                                    a: HertzViscoelastic::calibrated(
                                        &s.pair(),
                                        m,
                                        target,
                                        speed,
                                        Calibration::Exact,
                                        attractive,
                                    )?
                                    .a,
                                },
                            };
                            let r = damped_hertz(model, m, speed, g, attractive)?;
                            let c = simulate(&s, &mut ())?.contacts[0];
                            let errs = [
                                rel(c.restitution, r.restitution),
                                rel(c.duration, r.duration),
                                rel(c.max_overlap, r.max_overlap),
                                rel(c.t_max_overlap - c.t_contact, r.t_max_overlap),
                                match (c.t_force_zero, r.t_force_zero) {
                                    (Some(a), Some(b)) => rel(a - c.t_contact, b),
                                    _ => 0.0,
                                },
                            ];
                            let wi = if scheme == Scheme::Gear5 { 0 } else { 1 };
                            let ai = attractive as usize;
                            let mx = errs[..3].iter().cloned().fold(0.0, f64::max);
                            worst[wi][ai] = worst[wi][ai].max(mx);
                            println!(
                                "{:<13} {e:<4} {speed:<7.3} {g:<5} {:<5} {:<6} {:<8} | {:.2e}  {:.2e}  {:.2e}  {:.2e}  {:.2e} | {}",
                                damping.name(), attractive, scheme.name(), format!("{stepping:?}"),
                                errs[0], errs[1], errs[2], errs[3], errs[4], c.steps
                            );
                        }
                    }
                }
            }
        }
    }
    println!("worst over e, T_c, h_max: gear5 [forbidden, allowed] = {:.2e} {:.2e}; verlet = {:.2e} {:.2e}",
        worst[0][0], worst[0][1], worst[1][0], worst[1][1]);
    Ok(())
}
