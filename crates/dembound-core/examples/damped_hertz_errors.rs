//! Relative errors of the damped Hertz laws (Tsuji, viscoelastic) against
//! the adaptive reference (`reference::dissipative::damped_hertz`), per
//! target e, impact, attraction setting, scheme and stepping, with the
//! steps spent in the contact; the default e → coefficient calibration.
//!
//! ```text
//! cargo run --release -p dembound-core --example damped_hertz_errors -- [ETA] [FILTER]...
//! ```
//!
//! ETA defaults to 1/50. Each FILTER word keeps only the rows with that
//! value in its group (`gear5`/`verlet`, `event`/`fixed`, `attr`/`noattr`,
//! `tsuji`/`viscoelastic`); the environment variable `TARGETS=0.1,0.2`
//! replaces the targets 0.3, 0.5, 0.9. The last line gives the largest error
//! in e, T_c and h_max per scheme and attraction setting.

use dembound_core::bounce::{simulate, Scenario, Stepping};
use dembound_core::calibration::damping_coefficient;
use dembound_core::contact::{Calibration, ContactLawKind, DampingKind, Dissipation};
use dembound_core::integrate::Scheme;
use dembound_core::reference::dissipative::{damped_hertz, DampedHertz};

fn rel(a: f64, b: f64) -> f64 {
    (a / b - 1.0).abs()
}

/// The filter groups: a row is kept when, in every group the user named a
/// word of, its own word was named.
const GROUPS: [[&str; 2]; 4] = [
    ["gear5", "verlet"],
    ["event", "fixed"],
    ["attr", "noattr"],
    ["tsuji", "viscoelastic"],
];

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let eta: f64 = args.first().and_then(|s| s.parse().ok()).unwrap_or(0.02);
    let filters: Vec<&str> = args.iter().skip(1).map(String::as_str).collect();
    let keep = |words: [&str; 4]| {
        GROUPS.iter().zip(words).all(|(group, word)| {
            !group.iter().any(|g| filters.contains(g)) || filters.contains(&word)
        })
    };
    let targets: Vec<f64> = std::env::var("TARGETS")
        .ok()
        .map(|s| s.split(',').filter_map(|x| x.parse().ok()).collect())
        .unwrap_or_else(|| vec![0.3, 0.5, 0.9]);
    println!(
        "law           e    v(m/s)  g     attr  scheme stepping |  e err     T_c err   h_max err  t_mp err  tF0 err  | steps"
    );
    // [scheme][attractive]
    let mut worst = [[0.0f64; 2]; 2];
    for damping in [DampingKind::Tsuji, DampingKind::Viscoelastic] {
        for &e in &targets {
            for (v, g) in [(0.01, 0.0), (0.313, 0.0), (3.0, 0.0), (0.0, 9.81)] {
                for attractive in [true, false] {
                    for scheme in [Scheme::Gear5, Scheme::Verlet] {
                        for stepping in [Stepping::Event, Stepping::Fixed] {
                            let words = [
                                scheme.name(),
                                if stepping == Stepping::Event {
                                    "event"
                                } else {
                                    "fixed"
                                },
                                if attractive { "attr" } else { "noattr" },
                                damping.name(),
                            ];
                            if !keep(words) {
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
                            let exact = Calibration::Exact;
                            let mut model = s.contact.model();
                            (model.dissipation, model.calibration) = (Some(target), exact);
                            let coefficient = damping_coefficient(&model, &s.pair(), m, speed)?;
                            let model = match damping {
                                DampingKind::Tsuji => DampedHertz::Tsuji {
                                    stiffness: k,
                                    damping: coefficient,
                                },
                                _ => DampedHertz::Viscoelastic {
                                    stiffness: k,
                                    a: coefficient,
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
                            let w = &mut worst[usize::from(scheme == Scheme::Verlet)]
                                [usize::from(attractive)];
                            *w = errs[..3].iter().fold(*w, |w, x| w.max(*x));
                            println!(
                                "{:<13} {e:<4} {speed:<7.3} {g:<5} {:<5} {:<6} {:<8} | {:.2e}  {:.2e}  {:.2e}  {:.2e}  {:.2e} | {}",
                                damping.name(),
                                attractive,
                                scheme.name(),
                                format!("{stepping:?}"),
                                errs[0],
                                errs[1],
                                errs[2],
                                errs[3],
                                errs[4],
                                c.steps
                            );
                        }
                    }
                }
            }
        }
    }
    println!(
        "worst over e, T_c, h_max: gear5 [forbidden, allowed] = {:.2e} {:.2e}; verlet = {:.2e} {:.2e}",
        worst[0][0], worst[0][1], worst[1][0], worst[1][1]
    );
    Ok(())
}
