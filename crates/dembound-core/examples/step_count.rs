//! Driver for instruction counts under callgrind (see BENCHMARKS.md):
//!
//! `step_count steps SCHEME LAW N` runs N in-contact steps (as
//! `benches/steps.rs` does); `step_count case STEPPING N` runs the
//! validation case N times; `step_count damped MODEL ETA` runs one damped
//! three-contact scenario at η = ETA through `simulate` (MODEL: `tsuji`,
//! `viscous`, `viscoelastic`, all clamped, or `viscous-attractive`) and
//! prints its step count. Instructions per step = difference of two
//! callgrind totals at different N (or η), divided by the difference in N
//! (or in steps).
use dembound_core::bounce::{simulate, Scenario, Stepping};
use dembound_core::contact::{ContactLawKind, DampingKind, Hertz, LinearSpring, NormalContactLaw};
use dembound_core::integrate::{Gear5, Integrator, Scheme, Verlet};
use dembound_core::material::{Boundary, ContactPair, Particle};
use std::hint::black_box;

fn run_steps<I: Integrator, L: NormalContactLaw<History = ()>>(
    it: I,
    law: &L,
    mass: f64,
    dt: f64,
    n: u64,
) -> f64 {
    // As the contact loop does: the law per unit mass, scaled once per step
    // size by the scheme's force gain (`Integrator::step_scaled`).
    let g = 9.81;
    let mut s = it.start([0.0, -0.3132, -g, 0.0, 0.0, 0.0], dt);
    let law = law.scaled(1.0 / mass).scaled(it.force_gain(&s));
    for _ in 0..n {
        it.step_scaled(&mut s, -g, |x, v| law.force(-x, -v, &()));
    }
    it.kinematics(&s).position
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let usage =
        "usage: step_count steps gear5|verlet hertz|linear N | step_count case event|event-verlet|fixed N \
         | step_count damped tsuji|viscous|viscoelastic|viscous-attractive ETA";
    if args.get(1).map(String::as_str) == Some("damped") {
        let eta: f64 = args.get(3).and_then(|a| a.parse().ok()).expect(usage);
        let mut s = Scenario::default();
        s.motion.contacts = 3;
        s.integration.eta = Some(eta);
        let c = &mut s.contact;
        (c.law, c.damping, c.restitution) = match args[2].as_str() {
            "tsuji" => (ContactLawKind::Hertz, DampingKind::Tsuji, Some(0.5)),
            "viscous" | "viscous-attractive" => {
                (ContactLawKind::Linear, DampingKind::Viscous, Some(0.5))
            }
            "viscoelastic" => (ContactLawKind::Hertz, DampingKind::Viscoelastic, None),
            _ => panic!("{usage}"),
        };
        if c.restitution.is_none() {
            c.damping_coefficient = Some(1e-6);
        }
        c.attractive = args[2] == "viscous-attractive";
        let steps = simulate(black_box(&s), &mut ()).map(|o| o.steps);
        println!("{steps:?} steps");
        return;
    }
    let n: u64 = args.last().and_then(|a| a.parse().ok()).expect(usage);
    let pair = ContactPair::new(Particle::PAPER, Boundary::PAPER);
    let mass = Particle::PAPER.mass();
    match args.get(1).map(String::as_str) {
        Some("steps") => {
            let hertz = pair.law::<Hertz>(&[]);
            let linear = pair.law::<LinearSpring>(&[]);
            let dt_h = hertz.contact_time_estimate(mass, 0.3132) / 50.0;
            let dt_l = linear.contact_time_estimate(mass, 0.3132) / 50.0;
            let x = match (args[2].as_str(), args[3].as_str()) {
                ("gear5", "hertz") => {
                    run_steps(Gear5::POSITION_DEPENDENT, black_box(&hertz), mass, dt_h, n)
                }
                ("gear5", "linear") => {
                    run_steps(Gear5::POSITION_DEPENDENT, black_box(&linear), mass, dt_l, n)
                }
                ("verlet", "hertz") => run_steps(Verlet, black_box(&hertz), mass, dt_h, n),
                ("verlet", "linear") => run_steps(Verlet, black_box(&linear), mass, dt_l, n),
                _ => panic!("{usage}"),
            };
            println!("{x}");
        }
        Some("case") => {
            let mut s = Scenario::default();
            s.integration.stepping = match args[2].as_str() {
                "event" | "event-verlet" => Stepping::Event,
                "fixed" => Stepping::Fixed,
                _ => panic!("{usage}"),
            };
            if args[2] == "event-verlet" {
                s.integration.scheme = Scheme::Verlet;
            }
            let mut steps = 0;
            for _ in 0..n {
                steps += simulate(black_box(&s), &mut ())
                    .map(|o| o.steps)
                    .unwrap_or(0);
            }
            println!("{steps} steps");
        }
        _ => panic!("{usage}"),
    }
}
