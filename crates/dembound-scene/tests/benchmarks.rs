//! The validation suite's quick versions (`dembound benchmarks --quick`,
//! T_c/200 and a few points per curve): every check within its band, the
//! bands stated and justified where each check is made
//! (`src/benchmarks/`). Two comparisons fail in the full runs too, for
//! reasons the report states (the tangential model in the sticking regime
//! of Tests 5 and 6): for those the test holds the deviation to what the
//! full runs measured, so a change of the engine that moves them shows.

use dembound_scene::benchmarks::{names, run, Style};

/// Checks that fail against the paper's digitised curve, with the largest
/// deviation the full runs measured (`full` below, T_c/20,000, all
/// points), plus 5 %: the quick runs' points are a subset, so their
/// deviation cannot exceed it unless the engine changed.
const KNOWN_FAILURES: [(&str, &str, f64); 3] = [
    (
        "chung-ooi-5",
        "steel: largest |v_cp'/(μ v_n') − paper|",
        1.519 * 1.05,
    ),
    (
        "chung-ooi-5",
        "steel: largest |R ω'/(μ v_n) − paper|",
        1.087 * 1.05,
    ),
    (
        "chung-ooi-6",
        "aluminium alloy: largest |β = −v_cp'/v_cp − paper|",
        0.3011 * 1.05,
    ),
];

fn quick(name: &str) {
    let out = run(name, true, &|_| {}).unwrap_or_else(|e| panic!("{name}: {e}"));
    for c in &out.checks {
        let known = KNOWN_FAILURES
            .iter()
            .find(|(n, q, _)| *n == name && c.quantity.starts_with(q));
        match known {
            Some((_, _, bound)) => assert!(
                c.ours <= *bound,
                "{name}: {} = {} beyond the full runs' {bound}",
                c.quantity,
                c.ours
            ),
            None => assert!(
                c.passes(),
                "{name}: {} = {} vs {} ({:?})",
                c.quantity,
                c.ours,
                c.published,
                c.band
            ),
        }
    }
    assert!(out
        .plots
        .iter()
        .all(|p| p.curves.iter().any(|c| c.points.len() >= 2)));
}

#[test]
fn chung_ooi_1_to_3_normal_impacts() {
    for n in ["chung-ooi-1", "chung-ooi-2", "chung-ooi-3"] {
        quick(n);
    }
}

#[test]
fn chung_ooi_4_to_6_oblique_and_spinning_on_a_plane() {
    for n in ["chung-ooi-4", "chung-ooi-5", "chung-ooi-6"] {
        quick(n);
    }
}

#[test]
fn chung_ooi_7_and_8_sphere_pairs() {
    for n in ["chung-ooi-7", "chung-ooi-8"] {
        quick(n);
    }
}

/// Janssen's silo, quick (a tube 6 mean diameters wide, 800 spheres):
/// the bed sliding on the sinking floor follows Janssen's law (σ∞ =
/// ρ_b g λ, the K of the fit equal to the K measured at the wall, the
/// floor's stress on the law) within the bands the full run sets
/// (`janssen.rs`, `Bands`). The mobilised wall friction is below μ_w in
/// the full run too (the report says why): held between the full run's
/// share of μ_w less 10 % and μ_w itself, which Coulomb's law bounds
/// exactly (1e-9 for the sums' round-off).
#[test]
fn janssen_silo() {
    let out = run("janssen", true, &|_| {}).unwrap_or_else(|e| panic!("{e}"));
    for c in &out.checks {
        if c.quantity.starts_with("mobilised wall friction") {
            assert!(
                c.ours <= c.published * (1.0 + 1e-9)
                    && c.ours >= (FULL_JANSSEN_MOBILISED - 0.1) * c.published,
                "{} = {} (μ_w {})",
                c.quantity,
                c.ours,
                c.published
            );
        } else {
            assert!(
                c.passes(),
                "{} = {} vs {} ({:?})",
                c.quantity,
                c.ours,
                c.published,
                c.band
            );
        }
    }
    assert!(out
        .plots
        .iter()
        .all(|p| p.curves.iter().any(|c| c.points.len() >= 2)));
}

/// The full run's mobilised wall friction over μ_w (`full` below).
const FULL_JANSSEN_MOBILISED: f64 = 0.80;

/// The planar column collapse, quick (L0 = 6 mean diameters, a ≈ 1 and
/// 3.6): the run-outs within the published laws' band (±25 %, the full
/// run's band). The final heights (H∞ and H0 both the mean top of the
/// highest diameter band) are low against Lube et al.'s laws in the full
/// run too, and leave the band there at a = 4.73 (1.339 against 1.862,
/// −28.1 %; the report says why): each quick final height is held
/// between the law's band top (+25 %) and the full run's largest deficit
/// plus 5 % of it (the convention of KNOWN_FAILURES), 1 − 1.05 × 0.281 =
/// 0.705 of the law. Measured: 0.727 of the law at a = 0.99 (below the
/// band, where the full run's a = 0.98 at L0 = 8 diameters gives 0.776:
/// the quick column is 6 grains long) and 0.786 at a = 3.64. A column
/// that does not collapse (H∞ = H0 = a, 2.2 times the law at a = 3.64) or
/// a deposit spread flat fails.
#[test]
fn column_collapse() {
    let out = run("column-collapse", true, &|_| {}).unwrap_or_else(|e| panic!("{e}"));
    let floor = 1.0 - 1.05 * FULL_COLUMN_HEIGHT_DEFICIT;
    let mut heights = 0;
    for c in &out.checks {
        if c.quantity.contains("final height") {
            heights += 1;
            assert!(
                c.ours >= floor * c.published && c.ours <= 1.25 * c.published,
                "{} = {} (law {}, floor {floor} of it)",
                c.quantity,
                c.ours,
                c.published
            );
        } else {
            assert!(
                c.passes(),
                "{} = {} vs {} ({:?})",
                c.quantity,
                c.ours,
                c.published,
                c.band
            );
        }
    }
    assert_eq!(heights, 2, "one final height per column");
    assert!(out
        .plots
        .iter()
        .all(|p| p.curves.iter().any(|c| c.points.len() >= 2)));
}

/// The full run's largest final-height deficit against Lube et al.'s law,
/// 1 − H∞/law (a = 4.73: 1.339 against 1.862, `full` below).
const FULL_COLUMN_HEIGHT_DEFICIT: f64 = 0.281;

#[test]
fn names_are_unique_and_unknown_ones_refused() {
    let mut n = names();
    let all = n.len();
    n.sort();
    n.dedup();
    assert_eq!(n.len(), all);
    let e = run("chung-ooi-9", true, &|_| {}).unwrap_err().to_string();
    assert!(
        e.contains("chung-ooi-9") && e.contains("chung-ooi-1"),
        "{e}"
    );
}

/// The full runs, printed: `cargo test --release -p dembound-scene --test
/// benchmarks full -- --ignored --nocapture` (what KNOWN_FAILURES quotes).
#[test]
#[ignore]
fn full() {
    for name in names() {
        let out = run(name, false, &|_| {}).unwrap_or_else(|e| panic!("{name}: {e}"));
        for c in &out.checks {
            println!(
                "{name}: {} = {:e} (published {:e}, {:?}) {}",
                c.quantity,
                c.ours,
                c.published,
                c.band,
                if c.passes() { "pass" } else { "FAIL" }
            );
        }
        println!("{name}: {:.2} s", out.seconds);
    }
}

/// The rotating drum, quick (R = 12 mm, 181 grains, Fr = 3e-3 and 2):
/// each regime one of those Mellmann's (2001) map allows at its Fr (the
/// map's bands, not a tolerance: the check's band admits exactly the
/// allowed regimes), centrifuging above Fr = 1 as the closed form says.
#[test]
fn drum_regimes() {
    quick("drum");
}

/// The poured heap, quick (300 grains, μ_r = 0.2, μ_s = 0.2 and 0.8, one
/// heap a pair): its heaps are ~6 diameters tall, so the angle's error
/// (±3° a heap) does not resolve the sign the full run checks; the test
/// holds each heap's angle to the full runs' at the same (μ_s, μ_r)
/// within three standard errors (the quick heap's and the full value's
/// combined), and the difference to the right sign.
#[test]
fn repose_heaps() {
    let out = run("repose", true, &|_| {}).unwrap_or_else(|e| panic!("{e}"));
    let c = &out.checks[0];
    assert!(c.ours > 0.0, "{} = {}", c.quantity, c.ours);
    // The figure's curves: the angles, and the error bars (θ ± one
    // standard error, one segment a μ_s).
    let plot = &out.plots[0];
    let angles = &plot
        .curves
        .iter()
        .find(|c| c.label == "ours (one heap), μ_r = 0.2")
        .unwrap_or_else(|| panic!("no curve of the angles"))
        .points;
    let error_at = |ms: f64| {
        plot.curves
            .iter()
            .find(|c| c.style == Style::ErrorBar && c.points[0].0 == ms)
            .map(|c| 0.5 * (c.points[1].1 - c.points[0].1))
            .unwrap_or_else(|| panic!("no error bar at μ_s = {ms}"))
    };
    for (ms, full, full_error) in FULL_REPOSE_MU_R_02 {
        let k = angles
            .iter()
            .position(|p| p.0 == ms)
            .unwrap_or_else(|| panic!("μ_s = {ms}"));
        let (angle, error) = (angles[k].1, error_at(ms));
        assert!(
            (angle - full).abs() <= 3.0 * error.hypot(full_error),
            "μ_s = {ms}: {angle}° ± {error}° against the full runs' {full}° ± {full_error}°"
        );
    }
}

/// The full runs' angles at μ_r = 0.2: (μ_s, θ, its standard error), in
/// degrees. μ_s = 0.8: the mean of the seeded full run's 4 heaps
/// (docs/benchmarks/report.md); μ_s = 0.2, not in that run: the one heap
/// (seed 2001) of the earlier full run of all six pairs, ± its fit error.
const FULL_REPOSE_MU_R_02: [(f64, f64, f64); 2] = [(0.2, 27.0, 1.2), (0.8, 34.3, 0.7)];

/// The silo discharge, quick (1,173 spheres in a 12 mm tube, D = 10 and
/// 12 mm, a 80 ms window): the rate grows with D (Beverloo's law) and each
/// rate lies within ±40 % of the full silo's fit (C = 0.479, k = 1.24,
/// docs/beverloo.md, with the quick bed's own ρ_b; the full benchmark run
/// of docs/benchmarks/ fits C = 0.528, k = 1.46 to rates within 4 % of
/// that law: W = 10.16, 18.55, 30.15, 47.01 g/s against 10.57, 19.06,
/// 30.70, 45.81). The band: the quick window's standard error is ~10 % of
/// W (measured: 11.4 ± 1.1 and 19.2 ± 1.5 g/s, +11 % and +4 % from the
/// fit, +18 % and +6 % from the full run's); the full run's 5 ms rate
/// bins scatter by ±30 % at
/// D = 10 mm; 16 bins), and its tube is only 2–2.4 D against the full
/// run's 2.25–3.6 D, which Beverloo's law does not cover; a broken gate,
/// outlet or floor orifice gives W = 0 or the free-fall rate, far outside.
#[test]
fn beverloo_silo() {
    quick("beverloo");
}
