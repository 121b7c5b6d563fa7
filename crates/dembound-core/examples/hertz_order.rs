//! Error of the Hertz contact (g = 0 and with gravity) against η, event stepping.
use dembound_core::bounce::{simulate, Scenario};
use dembound_core::exact::scenario_contacts;
use dembound_core::integrate::Scheme;
fn main() {
    for g in [0.0, 9.81] {
        for scheme in [Scheme::Gear5, Scheme::Verlet] {
            for eta in [0.04, 0.02, 0.01, 0.005, 0.0025] {
                let mut s = Scenario::default();
                s.integration.scheme = scheme;
                s.motion.contacts = 1;
                s.motion.gravity = g;
                if g == 0.0 {
                    s.motion.velocity = -0.3132
                }
                s.integration.eta = Some(eta);
                let o = simulate(&s, &mut ()).unwrap();
                let e = scenario_contacts(&s).unwrap();
                let (c, e) = (o.contacts[0], e[0]);
                let r = |a: f64, b: f64| (a / b - 1.0).abs();
                println!(
                    "g={g} {:?} eta={eta} steps={} h {:.2e} T {:.2e} vr {:.2e} tmp {:.2e}",
                    scheme,
                    c.steps,
                    r(c.max_overlap, e.max_overlap),
                    r(c.duration, e.duration),
                    r(c.rebound_velocity, e.rebound_velocity),
                    r(c.t_max_overlap - c.t_contact, e.t_max_overlap - e.t_contact)
                );
            }
        }
    }
}
