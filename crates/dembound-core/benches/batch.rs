//! A 10,000-case Hertz sweep (the validation case with r, ζ and the drop
//! height varied; Gear5, η = 1/50, event stepping, 2 contacts each),
//! scalar (`simulate` per case, `par_iter`) against batched
//! (`simulate_batch_with`, every instruction set this CPU has), on 1 and 2
//! threads, all in one run.
//!
//! `scalar_*` drops each result as it comes (the reference of the
//! "batched ≥ 4× scalar" comparison); `scalar_collect_*` keeps them in a
//! `Vec` as `simulate_batch` must (the allocations of 10,000 outcomes cost
//! a few percent).
//!
//! `cargo bench -p dembound-core --bench batch`; throughput in cases/s
//! (criterion's elements/s).

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
mod common;

use common::sweep;
use dembound_core::bounce::batch::{simulate_batch_with, Isa};
use dembound_core::bounce::simulate;
use rayon::prelude::*;
use std::hint::black_box;

const CASES: usize = 10_000;

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
        group.bench_function(format!("scalar_collect_{threads}t"), |b| {
            b.iter(|| {
                pool.install(|| {
                    cases
                        .par_iter()
                        .map(|s| simulate(black_box(s), &mut ()))
                        .collect::<Vec<_>>()
                        .len()
                })
            })
        });
        for isa in [Isa::Avx512, Isa::Avx2, Isa::Baseline] {
            if !isa.available() {
                continue;
            }
            group.bench_function(format!("batched_{isa:?}_{threads}t"), |b| {
                b.iter(|| pool.install(|| simulate_batch_with(black_box(&cases), isa).len()))
            });
        }
    }
    group.finish();
}

criterion_group!(benches, sweep_bench);
criterion_main!(benches);
