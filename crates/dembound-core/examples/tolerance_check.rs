//! Measured errors (against the exact reference) of `integration.tolerance`
//! runs: `cargo run --release -p dembound-core --example tolerance_check`.
use dembound_core::bounce::{simulate, Scenario};
use dembound_core::contact::ContactLawKind;
use dembound_core::exact::scenario_contacts;
use dembound_core::integrate::Scheme;
fn main() {
    println!(
        "law     scheme  tol     eta       estimate  h_max     T_c       v_r       steps/contact"
    );
    for (law, scheme) in [
        (ContactLawKind::Hertz, Scheme::Gear5),
        (ContactLawKind::Linear, Scheme::Gear5),
        (ContactLawKind::Hertz, Scheme::Verlet),
        (ContactLawKind::Linear, Scheme::Verlet),
    ] {
        for tol in [1e-4, 1e-6, 1e-8, 1e-10] {
            let mut s = Scenario::default();
            s.contact.law = law;
            s.integration.scheme = scheme;
            s.integration.tolerance = Some(tol);
            let o = simulate(&s, &mut ()).unwrap();
            let e = scenario_contacts(&s).unwrap();
            let r = |a: f64, b: f64| (a / b - 1.0).abs();
            let mut worst = [0.0f64; 3];
            for (c, x) in o.contacts.iter().zip(&e) {
                worst[0] = worst[0].max(r(c.max_overlap, x.max_overlap));
                worst[1] = worst[1].max(r(c.duration, x.duration));
                worst[2] = worst[2].max(r(c.rebound_velocity, x.rebound_velocity));
            }
            println!(
                "{:7} {:7} {:7.0e} {:.3e} {:.2e}  {:.2e}  {:.2e}  {:.2e}  {}",
                law.name(),
                scheme.name(),
                tol,
                o.dt / o.contact_time_estimate,
                o.error_estimate.unwrap_or(f64::NAN),
                worst[0],
                worst[1],
                worst[2],
                o.contacts[0].steps
            );
        }
    }
}
