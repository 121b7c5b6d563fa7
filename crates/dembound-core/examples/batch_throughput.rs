//! Cases per second of a 10,000-case Hertz sweep (the validation case with
//! r, ζ and the impact speed varied), scalar against batched, on 1 and 2
//! threads: `cargo run --release -p dembound-core --example batch_throughput [N]`.
use dembound_core::bounce::batch::{simulate_batch_with, Isa};
use dembound_core::bounce::{simulate, Scenario};
use rayon::prelude::*;
use std::time::Instant;

/// The sweep of `benches/batch.rs`: n cases on a log grid.
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

fn main() {
    let n: usize = std::env::args()
        .nth(1)
        .and_then(|a| a.parse().ok())
        .unwrap_or(10_000);
    let cases = sweep(n);
    match std::env::args().nth(2).as_deref() {
        // For callgrind (which has no AVX-512): one pass of one path.
        Some("scalar") => {
            let ok = cases
                .iter()
                .filter(|s| simulate(s, &mut ()).is_ok())
                .count();
            println!("{ok}");
            return;
        }
        Some("batch-avx2") => {
            println!("{}", simulate_batch_with(&cases, Isa::Avx2).len());
            return;
        }
        _ => {}
    }
    let best = |f: &dyn Fn() -> usize| {
        (0..5)
            .map(|_| {
                let t = Instant::now();
                assert_eq!(f(), n);
                t.elapsed().as_secs_f64()
            })
            .fold(f64::INFINITY, f64::min)
    };
    println!("{n} cases, best of 5; ISA {:?}", Isa::detect());
    for threads in [1, 2] {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            let scalar = best(&|| {
                cases
                    .par_iter()
                    .map(|s| simulate(s, &mut ()))
                    .filter(|r| r.is_ok())
                    .count()
            });
            println!(
                "{threads} thread(s) scalar   : {:>10.0} cases/s",
                n as f64 / scalar
            );
            for isa in [Isa::Avx512, Isa::Avx2, Isa::Baseline] {
                if isa.available() {
                    let t = best(&|| {
                        simulate_batch_with(&cases, isa)
                            .iter()
                            .filter(|r| r.is_ok())
                            .count()
                    });
                    println!(
                        "{threads} thread(s) {:9}: {:>10.0} cases/s  ({:.2}x scalar)",
                        format!("{isa:?}"),
                        n as f64 / t,
                        scalar / t
                    );
                }
            }
        });
    }
}
