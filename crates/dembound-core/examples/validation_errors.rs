//! Prints the relative errors of the validation case (2nd contact) against
//! the exact reference, for both laws, schemes, stepping modes and η.
use dembound_core::bounce::{simulate, Scenario, Stepping};
use dembound_core::contact::ContactLawKind;
use dembound_core::exact::scenario_contacts;
use dembound_core::integrate::Scheme;

fn main() {
    println!("law     scheme  stepping eta    steps      d(t_r)     d(h_max)   d(a_max)   d(v_r)");
    for law in [ContactLawKind::Linear, ContactLawKind::Hertz] {
        for scheme in [Scheme::Gear5, Scheme::Verlet] {
            for stepping in [Stepping::Fixed, Stepping::Event] {
                for eta in [0.1, 0.02] {
                    let mut s = Scenario::default();
                    s.contact.law = law;
                    s.integration.scheme = scheme;
                    s.integration.stepping = stepping;
                    s.integration.eta = Some(eta);
                    let Ok(out) = simulate(&s, &mut ()) else {
                        continue;
                    };
                    let Ok(ex) = scenario_contacts(&s) else {
                        continue;
                    };
                    let (c, e) = (out.contacts[1], ex[1]);
                    let r = |a: f64, b: f64| (a / b - 1.0).abs();
                    println!(
                        "{:7} {:7} {:8} {:<6} {:<10} {:<10.3e} {:<10.3e} {:<10.3e} {:<10.3e}",
                        law.name(),
                        scheme.name(),
                        format!("{stepping:?}"),
                        eta,
                        out.steps,
                        r(c.t_rebound, e.t_rebound),
                        r(c.max_overlap, e.max_overlap),
                        r(c.max_acceleration, e.max_acceleration),
                        r(c.rebound_velocity, e.rebound_velocity)
                    );
                }
            }
        }
    }
}
