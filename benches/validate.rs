//! Cost of `dembound validate`'s two computations: Tables 1–2 (32 runs) and
//! the convergence study (72 runs, η from 1/5 to 1/2000; the fixed-step
//! runs at small η dominate, ~2·10⁸ steps for the linear law at η = 1/2000).
//! Both run in parallel on rayon's pool.
//!
//! `cargo bench --bench validate`

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use dembound_core::study::validation::{convergence, validation_tables, CONVERGENCE_ETAS};
use std::time::Duration;

fn validate(c: &mut Criterion) {
    let mut group = c.benchmark_group("validate");
    group.sample_size(10);
    group.warm_up_time(Duration::from_secs(1));
    group.measurement_time(Duration::from_secs(10));
    group.bench_function("validation_tables", |b| {
        b.iter(|| black_box(validation_tables().expect("tables compute")))
    });
    // One iteration takes seconds: give the 10 samples the time they need.
    group.measurement_time(Duration::from_secs(60));
    group.bench_function("convergence", |b| {
        b.iter(|| black_box(convergence(&CONVERGENCE_ETAS).expect("convergence computes")))
    });
    group.finish();
}

criterion_group!(benches, validate);
criterion_main!(benches);
