//! The validation suite's quick versions (`dembound benchmarks --quick`):
//! every check of every benchmark within its band. The bands are stated
//! and justified where each check is made (`src/benchmarks/`); the full
//! runs the report quotes pass the same bands at 20 times finer steps.

use dembound_scene::benchmarks::{names, run};

fn quick(name: &str) {
    let out = run(name, true, &|_| {}).unwrap_or_else(|e| panic!("{name}: {e}"));
    for c in &out.checks {
        println!("{name}: {} = {:e} (published {:e}, {:?}) {}", c.quantity, c.ours, c.published, c.band, if c.passes() { "pass" } else { "FAIL" });
    }
    for c in &out.checks {
        assert!(c.passes(), "{name}: {} = {} vs {} ({:?})", c.quantity, c.ours, c.published, c.band);
    }
    assert!(!out.plots.is_empty() && out.plots.iter().all(|p| p.curves.iter().any(|c| !c.points.is_empty())));
}

#[test]
fn chung_ooi_1_to_3_normal_impacts() {
    for n in ["chung-ooi-1", "chung-ooi-2", "chung-ooi-3"] {
        quick(n);
    }
}

#[test]
fn chung_ooi_4_to_8_oblique_and_spinning_impacts() {
    for n in ["chung-ooi-4", "chung-ooi-5", "chung-ooi-6", "chung-ooi-7", "chung-ooi-8"] {
        quick(n);
    }
}

#[test]
fn every_benchmark_is_named_once() {
    let mut n = names();
    let all = n.len();
    n.dedup();
    assert_eq!(n.len(), all);
}

/// The full runs, printed (the report's numbers): `cargo test --release
/// -p dembound-scene --test benchmarks full -- --ignored --nocapture`.
#[test]
#[ignore]
fn full() {
    for name in names() {
        let out = run(name, false, &|_| {}).unwrap_or_else(|e| panic!("{name}: {e}"));
        for c in &out.checks {
            println!("{name}: {} = {:e} (published {:e}, {:?}) {}", c.quantity, c.ours, c.published, c.band, if c.passes() { "pass" } else { "FAIL" });
        }
        println!("{name}: {:.2} s", out.seconds);
    }
}
