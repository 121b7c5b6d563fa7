use super::measure::{bumpiness, holes};
use super::shapes;
use super::*;
use crate::walls::mesh::read::write_ascii_stl;

fn options(pattern: Pattern, radius: f64) -> CoveringOptions {
    CoveringOptions {
        radius,
        spacing: 2.0 * radius,
        pattern,
        flip: false,
    }
}

#[test]
fn flat_square_stl_is_the_plane_tiling() {
    // A flat square STL [0, 10]² at z = 0 (normal +z) against the plane
    // `boundary_particles` wall of point 0 and normal +z in a domain
    // whose x and y extent is the square: the same spheres, same order.
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("square.stl");
    write_ascii_stl(&path, &shapes::square(10.0)).unwrap();
    for pattern in [Pattern::Square, Pattern::Hexagonal] {
        let covered = cover_file(&path, &options(pattern, 1.0)).unwrap();
        let plane = Tiling {
            point: [0.0; 3],
            normal: [0.0, 0.0, 1.0],
            radius: 1.0,
            spacing: 2.0,
            pattern,
        }
        .spheres(
            &Extent {
                lower: [0.0; 3],
                upper: [10.0, 10.0, 5.0],
                periodic: [false; 3],
            },
            "wall[0]",
        )
        .unwrap();
        assert_eq!(covered.spheres, plane, "{pattern:?}");
        assert!(covered.origin.iter().all(|o| *o == Origin::Face));
    }
}

#[test]
fn flat_holes_are_the_classical_windows() {
    // Touching square tiling: the window's circumradius s/√2 = √2 R, hole
    // (√2 − 1) R; hexagonal: s/√3, hole (2/√3 − 1) R. The sampled value is
    // at most the true one and within the sample spacing h = s/8 of it.
    let r = 1.0;
    for (pattern, exact) in [
        (Pattern::Square, 2f64.sqrt() - 1.0),
        (Pattern::Hexagonal, 2.0 / 3f64.sqrt() - 1.0),
    ] {
        let c = cover(
            Path::new("square"),
            &shapes::square(10.0),
            &options(pattern, r),
        )
        .unwrap();
        let h = holes(&c);
        assert!(
            h.hole <= exact + 1e-12 && h.hole >= exact - h.spacing,
            "{pattern:?}: {h:?}"
        );
        assert!(h.hole_bound >= exact, "{h:?}");
    }
}

#[test]
fn a_surface_under_one_sphere_has_no_hole() {
    // A square 1e-6 R_b wide: every sample of the centres' surface lies
    // within R_b of a centre (the spheres overlap it all), so no particle
    // passes: a hole of radius 0 and a bound of 0 + h, never negative (it
    // printed −1 R_b; `flat_holes_are_the_classical_windows` keeps the
    // positive windows).
    let r = 1.0;
    let c = cover(
        Path::new("square"),
        &shapes::square(1e-6),
        &options(Pattern::Square, r),
    )
    .unwrap();
    let h = holes(&c);
    assert!(h.samples > 0, "{h:?}");
    assert_eq!(h.hole, 0.0, "{h:?}");
    assert!(h.hole_bound >= 0.0 && h.hole_bound <= h.spacing, "{h:?}");
}

#[test]
fn flat_bumpiness_is_the_hollow_depth() {
    // Square, touching, ρ = R: on top t = ρ; in the hollow (distance √2 R
    // from four centres at depth R) t = −R + √((2R)² − 2R²) = (√2 − 1) R:
    // bumpiness 2 − √2 = 0.586 R. The samples (spacing ≤ h = s/8) miss the
    // hollow's lowest point by at most h, and t rises from it with slope
    // 1 (d/dd of √((2R)² − d²) at d = √2 R), so the sampled value is
    // within h below the exact one, never above.
    let c = cover(
        Path::new("square"),
        &shapes::square(16.0),
        &options(Pattern::Square, 1.0),
    )
    .unwrap();
    let (b, used) = bumpiness(&c, 1.0).unwrap();
    assert!(used > 0);
    let exact = 2.0 - 2f64.sqrt();
    assert!(b <= exact + 1e-12 && b >= exact - 0.25, "{b}");
}

#[test]
fn cube_is_closed_and_no_sphere_crosses_the_surface() {
    let r = 0.05;
    let c = cover(
        Path::new("cube"),
        &shapes::cube([0.0; 3], [1.0; 3]),
        &options(Pattern::Square, r),
    )
    .unwrap();
    // Every centre inside the cube, at least R from every face.
    for s in &c.spheres {
        for k in 0..3 {
            let d = s.position[k].min(1.0 - s.position[k]);
            assert!(d >= r * (1.0 - 1e-9), "{s:?}");
        }
    }
    // Corners and edges got spheres tangent to their faces: the corner
    // sphere at (R, R, R).
    assert!(c
        .spheres
        .iter()
        .any(|s| norm(sub(s.position, [r, r, r])) < 1e-12));
    // Kept centres at least s/2 apart.
    for (i, a) in c.spheres.iter().enumerate() {
        for b in &c.spheres[i + 1..] {
            assert!(norm(sub(a.position, b.position)) >= r * (1.0 - 1e-12));
        }
    }
    let h = holes(&c);
    // Faces give (√2 − 1) R; the rounded edges of a cube must not be
    // worse than a face window by more than the sampling.
    assert!(h.hole < 0.5 * r, "{h:?}");
}

#[test]
fn covering_is_deterministic_and_bad_radius_is_named() {
    let soup = shapes::hopper(0.1, 0.5, 0.5, 0.3, 24);
    let o = options(Pattern::Hexagonal, 0.02);
    let a = cover(Path::new("h"), &soup, &o).unwrap();
    let b = cover(Path::new("h"), &soup, &o).unwrap();
    assert_eq!(a.spheres, b.spheres);
    let e = cover(Path::new("h"), &soup, &options(Pattern::Square, -1.0))
        .unwrap_err()
        .to_string();
    assert!(e.contains("--radius") && e.contains("> 0"), "{e}");
}
