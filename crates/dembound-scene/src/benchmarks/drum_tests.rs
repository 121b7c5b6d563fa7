//! The drum benchmark's unit tests: Mellmann's bands, the classification
//! rules on synthetic frames, and a harness for the full run's points.

use super::*;

/// Mellmann's bands: the overlaps give two regimes, Fr ≥ 1
/// centrifuging alone (its lower edge included: the closed form).
#[test]
fn the_map_allows_the_overlapping_bands() {
    assert_eq!(allowed(3e-4), vec![0, 1]);
    assert_eq!(allowed(3e-3), vec![1, 2]);
    assert_eq!(allowed(3e-2), vec![2]);
    assert_eq!(allowed(0.3), vec![3]);
    assert_eq!(allowed(1.0), vec![4]);
    assert_eq!(allowed(2.0), vec![4]);
}

/// A bed turning rigidly with the drum, spread round the wall, is
/// centrifuging; the same bed at rest at the bottom, with one grain in
/// four flowing, rolls.
#[test]
fn rigid_rotation_is_centrifuging_and_a_flowing_flat_bed_rolls() {
    let (radius, omega) = (0.02, 10.0);
    let n = 40;
    let mut x = Vec::new();
    let mut v = Vec::new();
    for k in 0..n {
        let a = k as f64 * std::f64::consts::TAU / n as f64;
        let p = [0.019 * a.cos(), 0.0, 0.019 * a.sin()];
        v.push([omega * p[2], 0.0, -omega * p[0]]);
        x.push(p);
    }
    let r = vec![1e-3; n];
    let f = frame(&x, &v, &r, &[], &[], 0.005, radius, omega);
    assert_eq!(f.co_rotating, 1.0);
    assert!((f.upper - 0.5).abs() < 0.05);
    assert_eq!(classify(&[f; 10]), 4);
    // A flat bed of touching grains along z = −0.01 (no surface tilt),
    // a quarter of them sliding at 1 m/s.
    let x: Vec<[f64; 3]> = (0..16)
        .map(|k| [-0.015 + 2e-3 * k as f64, 0.0, -0.01])
        .collect();
    let v: Vec<[f64; 3]> = (0..16)
        .map(|k| {
            let p = x[k];
            let drum = [omega * p[2], 0.0, -omega * p[0]];
            if k % 4 == 0 {
                [drum[0] + 1.0, 0.0, drum[2]]
            } else {
                drum
            }
        })
        .collect();
    let f = frame(&x, &v, &[1e-3; 16], &[], &[], 0.005, radius, omega);
    assert!(f.angle.abs() < 1e-9, "{}", f.angle);
    assert_eq!(f.thrown, 0.0);
    assert_eq!(classify(&[f; 10]), 1);
}

/// The thrown rule: over a bed of touching grains above the axis, a
/// grain leaping half a diameter clear of it touches nothing but is
/// not thrown (the flowing layer's leaps); one three diameters clear
/// is. With 11 bed grains and the two free ones, thrown = 1/13
/// exactly (a count), where the first rule (touching nothing above
/// the axis) gave 2/13.
#[test]
fn only_grains_clear_of_the_bed_are_thrown() {
    let (r, d) = (1e-3, 2e-3);
    // Centres 1.99 mm apart: each bed grain overlaps its neighbours.
    let mut x: Vec<[f64; 3]> = (0..11)
        .map(|k| [-0.01 + 1.99e-3 * k as f64, 0.0, 0.002])
        .collect();
    let top = 0.002 + r;
    x.push([0.0, 0.0, top + 0.5 * d + r]);
    x.push([0.006, 0.0, top + 3.0 * d + r]);
    let v = vec![[0.0; 3]; x.len()];
    let f = frame(&x, &v, &vec![r; x.len()], &[], &[], 0.005, 0.02, 1.0);
    assert_eq!(f.thrown, 1.0 / 13.0);
    assert_eq!(f.upper, 1.0);
}

/// Not a check: runs the full benchmark's drum at the Froude numbers
/// of `DRUM_FROUDE` (comma separated; default 3e-2), prints each
/// run's measures and regime and, with `DRUM_DUMP=DIR`, writes every
/// frame's grains and lining to `DIR/drum_fr<Fr>.csv` (t, kind, x, y,
/// z, vx, vy, vz, r; SI) to study the classification rules offline.
/// `cargo test --release -p dembound-scene --lib full_drum_points -- --ignored --nocapture`
#[test]
#[ignore]
fn full_drum_points() {
    use std::io::Write;
    let list = std::env::var("DRUM_FROUDE").unwrap_or_else(|_| "3e-2".into());
    let dump = std::env::var("DRUM_DUMP").ok();
    let s = setup(false);
    for fr in list
        .split(',')
        .map(|t| t.trim().parse::<f64>().expect("a Froude number"))
    {
        let mut out = dump.as_ref().map(|dir| {
            std::io::BufWriter::new(
                std::fs::File::create(format!("{dir}/drum_fr{fr}.csv")).expect("dump file"),
            )
        });
        let mut write = |t: f64, smp: &Sample| {
            let Some(out) = out.as_mut() else { return };
            for (i, p) in smp.0.iter().enumerate() {
                let u = smp.1[i];
                writeln!(
                    out,
                    "{t},0,{},{},{},{},{},{},{}",
                    p[0], p[1], p[2], u[0], u[1], u[2], smp.2[i]
                )
                .expect("write");
            }
            for (p, r) in smp.3.iter().zip(&smp.4) {
                writeln!(out, "{t},1,{},{},{},0,0,0,{r}", p[0], p[1], p[2]).expect("write");
            }
        };
        let run = run_one(&grains(), &s, fr, &|m| eprintln!("{m}"), &mut write)
            .unwrap_or_else(|e| panic!("{e}"));
        println!(
            "Fr = {fr}: {} (thrown {:.4}, upper {:.3}, flowing {:.3}, upper/lower angle {:.1}/{:.1})",
            REGIMES[run.regime],
            mean_of(&run.frames, &|f| f.thrown),
            mean_of(&run.frames, &|f| f.upper),
            mean_of(&run.frames, &|f| f.flowing),
            mean_of(&run.frames, &|f| f.upper_angle),
            mean_of(&run.frames, &|f| f.lower_angle),
        );
    }
}
