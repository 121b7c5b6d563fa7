//! A 10,000-case Hertz sweep (the validation case with r, ζ and the drop
//! height varied; Gear5, η = 1/50, event stepping, 2 contacts each),
//! scalar (`simulate` per case, `par_iter`) against batched
//! (`simulate_batch`), on 1 and 2 threads.
//!
//! `cargo bench -p dembound-core --bench batch`; throughput in cases/s
//! (criterion's elements/s).

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use dembound_core::bounce::batch::{simulate_batch_with, Isa};
use dembound_core::bounce::{simulate, Scenario};
use rayon::prelude::*;
use std::hint::black_box;

const CASES: usize = 10_000;

/// n cases spread over r ∈ [0.5, 10⁴], ζ ∈ [0.1, 10⁴], gap ∈ [0.1, 10] mm
/// (the same sweep as `examples/batch_throughput.rs`).
fn sweep(n: usize) -> Vec<Scenario> {
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

fn sweep_bench(c: &mut Criterion) {
    let cases = sweep(CASES);
    let mut group = c.benchmark_group("sweep_10000");
    group.sample_size(10);
    group.throughput(Throughput::Elements(CASES as u64));
    for threads in [1, 2] {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .expect("a thread pool");
        group.bench_function(format!("scalar_{threads}t"), |b| {
            b.iter(|| {
                pool.install(|| {
                    cases
                        .par_iter()
                        .map(|s| simulate(black_box(s), &mut ()).is_ok())
                        .filter(|&ok| ok)
                        .count()
                })
            })
        });
        for isa in [Isa::detect(), Isa::Baseline] {
            group.bench_function(format!("batched_{isa:?}_{threads}t"), |b| {
                b.iter(|| pool.install(|| simulate_batch_with(black_box(&cases), isa).len()))
            });
        }
    }
    group.finish();
}

criterion_group!(benches, sweep_bench);
criterion_main!(benches);
