//! Cases per second of a 10,000-case Hertz sweep (the validation case with
//! r, ζ and the impact speed varied), scalar against batched, on 1 and 2
//! threads: `cargo run --release -p dembound-core --example batch_throughput [N]`;
//! `… batch_throughput N batch K`: `simulate_batch` alone, best of K.
#[path = "../benches/common/mod.rs"]
mod common;

use common::sweep;
use dembound_core::bounce::batch::{simulate_batch_with, Isa};
use dembound_core::bounce::simulate;
use rayon::prelude::*;
use std::time::Instant;

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
        // The path the Python package's `dembound.batch` runs
        // (`simulate_batch`: detected ISA, global pool), best of K:
        // bench/python_batch.py measures the same cases from Python.
        Some("batch") => {
            let k: usize = std::env::args()
                .nth(3)
                .and_then(|a| a.parse().ok())
                .unwrap_or(10);
            let best = (0..k)
                .map(|_| {
                    let t = Instant::now();
                    let ok = dembound_core::bounce::simulate_batch(&cases)
                        .iter()
                        .filter(|r| r.is_ok())
                        .count();
                    assert_eq!(ok, n);
                    t.elapsed().as_secs_f64()
                })
                .fold(f64::INFINITY, f64::min);
            println!("rust simulate_batch: {:.0} cases/s", n as f64 / best);
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
