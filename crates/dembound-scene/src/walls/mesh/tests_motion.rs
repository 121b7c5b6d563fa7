//! A moving mesh (issue 27) answers as the same surface moved: its
//! triangles stay in the reference placement and the sphere is taken
//! there by the inverse pose.

use super::fixtures::{mesh, square};
use super::*;
use crate::walls::motion::WallMotion;
use crate::walls::{PlaneWall, Surface};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// A unit square (2 triangles) and the plane z = 0 under one motion
/// (translation, rotation about a tilted axis through a point off the
/// square, oscillation), at several times: over the square's inside the
/// mesh's contact (overlap, normal, overlap rate) and its surface
/// velocity equal the moved plane's to rounding (1e-12: the mesh goes
/// through the inverse pose and back, the plane is placed directly, a
/// few roundings of numbers of order 1 apart); and `near_elements` finds
/// the patch exactly when the overlap exceeds −range.
#[test]
fn a_moving_square_is_the_moving_plane() {
    let motion = WallMotion {
        velocity: [0.2, -0.1, 0.3],
        angular_velocity: [0.5, 1.5, -0.7],
        center: [0.3, -0.2, 0.1],
        start: 0.05,
        end: 1.0,
        oscillation: Some(([0.01, 0.0, 0.02], 3.0)),
    };
    let reference_mesh = MeshWall {
        wall: 0,
        slot: 0,
        mesh: std::sync::Arc::new(mesh(&square(0.0))),
        moving: None,
    };
    let reference_plane = Surface::Plane(PlaneWall {
        wall: 0,
        point: [0.0; 3],
        normal: [0.0, 0.0, 1.0],
        slot: 0,
        moving: None,
    });
    let mut rng = ChaCha8Rng::seed_from_u64(27);
    let r = 0.05;
    for t in [0.0, 0.1, 0.6, 1.4] {
        let state = motion.state(t);
        let moved = Surface::Mesh(reference_mesh.clone()).posed(&state);
        let plane = reference_plane.posed(&state);
        for _ in 0..500 {
            // A point over the square's inside, at a height about r.
            let local = [
                rng.gen_range(0.1..0.9),
                rng.gen_range(0.1..0.9),
                rng.gen_range(0.5 * r..1.5 * r),
            ];
            let x = state.place(local);
            let v = [0, 1, 2].map(|_| rng.gen_range(-1.0..1.0));
            let (a, b) = (moved.contact(0, x, v, r), plane.contact(0, x, v, r));
            assert!((a.overlap - b.overlap).abs() < 1e-12, "{a:?} {b:?}");
            assert!((a.rate - b.rate).abs() < 1e-12, "{a:?} {b:?}");
            for k in 0..3 {
                assert!((a.normal[k] - b.normal[k]).abs() < 1e-12);
            }
            let at = [0, 1, 2].map(|k| x[k] - r * a.normal[k]);
            let (wa, wb) = (moved.surface_velocity(0, at), plane.surface_velocity(0, at));
            for k in 0..3 {
                assert!((wa[k] - wb[k]).abs() < 1e-12);
            }
            let mut near = false;
            moved.wall().near_elements(x, r, 0.01, &mut |_| near = true);
            if (a.overlap + 0.01).abs() > 1e-9 {
                assert_eq!(near, a.overlap > -0.01, "{a:?}");
            }
        }
        // The torque point moves with the mesh.
        let c = moved.torque_point();
        let want = state.place(reference_mesh.mesh.centroid);
        assert_eq!(c, want);
    }
}
