//! `dembound paper` end to end: the release binary as a user runs it
//! (every study, 90-odd figures, the reports), into a temporary directory.
//!
//! `cargo bench --bench paper`
//!
//! One iteration takes ~6 s on 2 cores, so the group runs 10 samples.

use criterion::{criterion_group, criterion_main, Criterion};
use std::process::Command;
use std::time::Duration;

fn paper(c: &mut Criterion) {
    let exe = env!("CARGO_BIN_EXE_dembound");
    let mut group = c.benchmark_group("command");
    group.sample_size(10);
    group.warm_up_time(Duration::from_secs(1));
    group.measurement_time(Duration::from_secs(70));
    group.bench_function("paper", |b| {
        b.iter(|| {
            let dir = tempfile::tempdir().expect("a temporary directory");
            let status = Command::new(exe)
                .args(["paper", "--quiet", "--out"])
                .arg(dir.path().join("out"))
                .status()
                .expect("dembound runs");
            assert!(status.success(), "dembound paper failed: {status}");
        })
    });
    group.finish();
}

criterion_group!(benches, paper);
criterion_main!(benches);
