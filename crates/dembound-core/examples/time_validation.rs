//! Compute time of the paper's validation case (Hertz, Gear5, η = 1/50,
//! event stepping, 2 contacts), averaged over many runs, with its results
//! and the exact reference, as one JSON line (for `bench/compare_scipy.py`):
//!
//! `cargo run --release -p dembound-core --example time_validation [RUNS]`
use dembound_core::bounce::{simulate, Scenario};
use dembound_core::exact::scenario_contacts;
use std::hint::black_box;
use std::time::Instant;

fn main() {
    let runs: u32 = std::env::args()
        .nth(1)
        .and_then(|a| a.parse().ok())
        .unwrap_or(20_000);
    let s = Scenario::default();
    let out = simulate(&s, &mut ()).expect("the validation case runs");
    // Best of 5 batches of `runs`, mean per run within a batch.
    let mut best = f64::INFINITY;
    for _ in 0..5 {
        let t = Instant::now();
        for _ in 0..runs {
            black_box(simulate(black_box(&s), &mut ()).is_ok());
        }
        best = best.min(t.elapsed().as_secs_f64() / f64::from(runs));
    }
    let exact = scenario_contacts(&s).expect("the exact reference");
    let (c, e) = (out.contacts[1], exact[1]);
    println!(
        "{{\"time_us\": {:.4}, \"steps\": {}, \"t_rebound\": {:e}, \"max_overlap\": {:e}, \
         \"rebound_velocity\": {:e}, \"exact_t_rebound\": {:e}, \"exact_max_overlap\": {:e}, \
         \"exact_rebound_velocity\": {:e}, \"t_contact_1\": {:e}, \"p_squared\": {:e}}}",
        best * 1e6,
        out.steps,
        c.t_rebound,
        c.max_overlap,
        c.rebound_velocity,
        e.t_rebound,
        e.max_overlap,
        e.rebound_velocity,
        exact[0].t_contact,
        {
            let p = s.pair().p(1.5);
            p * p
        }
    );
}
