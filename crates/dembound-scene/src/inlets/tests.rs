use super::*;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

fn box_setup(size: SizeDistribution) -> InletSetup {
    InletSetup {
        region: Region::Box {
            lower: [0.0; 3],
            upper: [0.2, 0.2, 0.2],
        },
        rate: InletRate::Number(1.0),
        size,
        material: 0,
        velocity: [0.0; 3],
        start: 0.0,
        end: None,
        seed: 7,
        every: None,
        max_attempts: 100,
    }
}

/// 10⁵ insertions over 1000 events, each against 300 fresh obstacles
/// (radii 2 to 30 mm, some too large for the grid) and a plane z ≥ 0.03 m,
/// checked by an O(N²) loop: no placed sphere overlaps an obstacle, an
/// earlier sphere of its event or the plane, and each lies in the region.
#[test]
fn no_inserted_sphere_overlaps_anything_over_1e5_insertions() {
    let setup = box_setup(SizeDistribution::Uniform(0.002, 0.004));
    let plane_z = 0.03;
    let walls_clear = |x: [f64; 3], r: f64| x[2] - plane_z >= r;
    let mut obstacle_rng = ChaCha8Rng::seed_from_u64(99);
    let (mut placed_total, mut missed_total) = (0u64, 0u64);
    for e in 0..1000 {
        let obstacles: Vec<([f64; 3], f64)> = (0..300)
            .map(|_| {
                let x = [0, 1, 2].map(|_| -0.05 + 0.3 * obstacle_rng.gen::<f64>());
                let r = 0.002 + 0.028 * obstacle_rng.gen::<f64>().powi(4);
                (x, r)
            })
            .collect();
        let mut grid = Obstacles::new(obstacles.clone(), setup.size.max_radius());
        let mut rng = event_rng(setup.seed, 0, e);
        let (placed, missed) = place_event(&setup, 100, &mut rng, &mut grid, &walls_clear);
        placed_total += placed.len() as u64;
        missed_total += missed;
        assert_eq!(placed.len() as u64 + missed, 100);
        for (i, &(x, r)) in placed.iter().enumerate() {
            assert!((0.002..=0.004).contains(&r));
            for c in x {
                assert!(c - r >= 0.0 && c + r <= 0.2, "outside the region");
            }
            assert!(x[2] - plane_z >= r, "in the plane");
            let others = obstacles.iter().chain(&placed[..i]);
            for &(y, ry) in others {
                let d2 = (0..3).map(|a| (x[a] - y[a]).powi(2)).sum::<f64>();
                assert!(d2 >= (r + ry) * (r + ry), "overlap at event {e}");
            }
        }
    }
    // Nearly all fit (the obstacles leave most of the region free): the
    // test exercised 1e5 insertions, not 1e5 refusals.
    assert!(placed_total + missed_total == 100_000);
    assert!(placed_total > 90_000, "placed {placed_total}");
}

/// The same seed, inlet and event give the same spheres; another event
/// other ones.
#[test]
fn draws_depend_on_seed_inlet_and_event_only() {
    let setup = box_setup(SizeDistribution::Fixed(0.003));
    let run = |k: usize, e: u64| {
        let mut grid = Obstacles::new(Vec::new(), 0.003);
        place_event(&setup, 20, &mut event_rng(3, k, e), &mut grid, &|_, _| true).0
    };
    assert_eq!(run(0, 5), run(0, 5));
    assert_ne!(run(0, 5), run(0, 6));
    assert_ne!(run(0, 5), run(1, 5));
}

/// A region already full places nothing and counts every sphere missed.
#[test]
fn a_full_region_counts_the_spheres_not_placed() {
    let setup = box_setup(SizeDistribution::Fixed(0.01));
    // One sphere covering the whole region.
    let mut grid = Obstacles::new(vec![([0.1; 3], 1.0)], 0.01);
    let (placed, missed) = place_event(&setup, 7, &mut event_rng(0, 0, 0), &mut grid, &|_, _| true);
    assert!(placed.is_empty());
    assert_eq!(missed, 7);
}

/// E[R³] against closed forms: uniform (b⁴ − a⁴)/(4(b − a)), a table's
/// weighted mean; a normal of zero spread is its mean.
#[test]
fn mean_cubes_match_closed_forms() {
    let u = SizeDistribution::Uniform(1.0, 2.0).mean_cube();
    assert!((u - 15.0 / 4.0).abs() < 1e-15);
    let t = SizeDistribution::Table(vec![(1.0, 1.0), (2.0, 3.0)]).mean_cube();
    assert!((t - (1.0 + 3.0 * 8.0) / 4.0).abs() < 1e-15);
    let n = SizeDistribution::Normal {
        mean: 2.0,
        std: 0.0,
        min: 1.0,
        max: 3.0,
    };
    assert_eq!(n.mean_cube(), 8.0);
    // A symmetric truncation of a normal: E[R³] = μ³ + 3 μ σ_t², σ_t² the
    // truncated variance σ²(1 − 2 φ(1)/(Φ(1) − Φ(−1))) at ±1σ (φ(1) =
    // 0.24197072451914337, Φ(1) − Φ(−1) = 0.6826894921370859); Simpson
    // over 2000 intervals is far within 1e-9.
    let (mu, s) = (2.0, 0.1);
    let var = s * s * (1.0 - 2.0 * 0.24197072451914337 / 0.6826894921370859);
    let n = SizeDistribution::Normal {
        mean: mu,
        std: s,
        min: mu - s,
        max: mu + s,
    };
    assert!((n.mean_cube() - (mu * mu * mu + 3.0 * mu * var)).abs() < 1e-9);
}

/// Samples of a table follow its fractions (by number): 10⁵ draws of a
/// 1:3 table give 0.25 of the first radius within 5 standard errors
/// (√(0.25·0.75/10⁵) = 1.4e-3).
#[test]
fn table_samples_follow_the_fractions() {
    let d = SizeDistribution::Table(vec![(1.0, 1.0), (2.0, 3.0)]);
    let mut rng = event_rng(1, 0, 0);
    let n = 100_000;
    let small = (0..n).filter(|_| d.sample(&mut rng) == 1.0).count();
    assert!((small as f64 / n as f64 - 0.25).abs() < 5.0 * 1.4e-3);
}

/// Cylinder samples lie in the cylinder shrunk by the radius.
#[test]
fn cylinder_samples_lie_inside() {
    let axis = unit([1.0, 1.0, 0.0]);
    let c = [0.5, 0.5, 0.5];
    let region = Region::Cylinder {
        center: c,
        axis,
        radius: 0.1,
        length: 0.4,
    };
    let mut rng = event_rng(2, 0, 0);
    for _ in 0..10_000 {
        let x = region.sample(&mut rng, 0.02);
        let d = [0, 1, 2].map(|a| x[a] - c[a]);
        let along = d[0] * axis[0] + d[1] * axis[1] + d[2] * axis[2];
        let radial2 = d.iter().map(|v| v * v).sum::<f64>() - along * along;
        assert!(along.abs() <= 0.18 + 1e-12);
        assert!(radial2.sqrt() <= 0.08 + 1e-12);
    }
}

/// The schedule: cumulative rounding, events every `every` steps from the
/// first step at or after start, none at or after end.
#[test]
fn the_schedule_rounds_cumulatively() {
    let mut s = box_setup(SizeDistribution::Fixed(0.001));
    s.rate = InletRate::Number(2500.0);
    s.every = Some(10);
    s.end = Some(0.05);
    let inlets = Inlets::new(&[s], &[2500.0], 0, 1e-4, 1.0).unwrap();
    // Events at steps 1, 11, …, 491 (k · 10 · 1e-4 s < 0.05 s: k ≤ 49).
    assert_eq!(inlets.event_at(0, 1), Some(0));
    assert_eq!(inlets.event_at(0, 2), None);
    assert_eq!(inlets.event_at(0, 491), Some(49));
    assert_eq!(inlets.event_at(0, 501), None);
    // 2.5 spheres per event: round(2.5) = 3, round(5) = 5, …; all 125 by
    // the end.
    assert_eq!(inlets.due_after(0, 0), 3);
    assert_eq!(inlets.due_after(0, 1), 5);
    assert_eq!(inlets.due_after(0, 49), 125);
}

/// A rate that would fill more than a fifth of the region per event is
/// refused naming the key.
#[test]
fn a_rate_the_region_cannot_hold_is_refused() {
    let mut s = box_setup(SizeDistribution::Fixed(0.01));
    // 0.008 m³ region; one sphere 4.19e-6 m³; 1e6 spheres/s · 1 step of
    // 1e-3 s = 1000 spheres = 4.2e-3 m³ > 0.2 · 0.008.
    s.rate = InletRate::Number(1e6);
    s.every = Some(1);
    let e = Inlets::new(&[s], &[2500.0], 0, 1e-3, 1.0).unwrap_err();
    assert!(e.to_string().contains("inlet[0].rate.number"), "{e}");
}
