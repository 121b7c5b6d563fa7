//! Moving walls in a LIGGGHTS deck (issue 27): what of dembound's
//! `[[wall]] motion` LIGGGHTS 3.8 computes the same way, written as
//! `fix move/mesh`, and a refusal naming the key for the rest.
//!
//! Exported: a mesh turning at a constant ω from t = 0 for ever
//! (`motion = { angular_velocity = ω, center = c }`, no `velocity`,
//! `start` = 0, `end` = inf, no `oscillation`) as `fix move/mesh ...
//! rotate origin c axis ω̂ period 2π/|ω|`. The same motion in both codes:
//! - the pose: dembound turns the file's mesh by |ω| t about ω̂ through c
//!   (Rodrigues, from the reference placement: walls/motion.rs);
//!   LIGGGHTS's `MeshMoverRotate` turns the original nodes by the total
//!   angle 2π t/period about the same axis (right-handed about `axis`);
//! - the surface velocity at the contact point: dembound ω × (p − c);
//!   LIGGGHTS sets each node's velocity to ω × (x − c) and interpolates it
//!   at the contact point with the barycentric weights, which is exact for
//!   a field linear in the position (a rigid rotation is);
//! - both evaluate the wall at the step's time, after moving the spheres.
//!
//! Exported too: a mesh translating at a constant V from t = 0 for ever
//! (`motion = { velocity = V }`, no `angular_velocity`, no
//! `oscillation`) as `fix move/mesh ... linear Vx Vy Vz`:
//! - the pose: LIGGGHTS's `MeshMoverLinear` moves the nodes by the
//!   increment V Δt every step (`FixMesh::move(dx)`), so after n steps
//!   they are at X + Σ V Δt, dembound's X + V n Δt up to the rounding of
//!   the running sum (≤ n/2 ulp of the coordinates: 1e-14 m after 20 000
//!   steps of a 1 cm mesh, 1e-9 of a 1e-5 m overlap at worst);
//! - the node velocities are set to V every step (zeroed, then V added),
//!   so the surface velocity at the contact point is V, dembound's ḋ;
//! - the time: `FixMoveMesh::initial_integrate` moves the mesh at the
//!   start of each step, before the forces of the step, as for `rotate`.
//!
//! Refused, with the key: a motion that starts late or stops (`start`,
//! `end`; `fix move/mesh` runs from its creation for ever); a mesh that
//! turns and translates (two `fix move/mesh` on one mesh would each need
//! the other's reference point; not written); an `oscillation`: LIGGGHTS's
//! `wiggle` sets the node velocity a ω cos(ω t) at the step's end time and
//! moves the nodes by that velocity × Δt (an Euler sum, `MeshMoverWiggle`),
//! so its pose drifts from dembound's exact a sin(2π f t) by about
//! a ω Δt / 2 (relative 1.6e-4 of the amplitude at 50 Hz and Δt = 2 µs),
//! far more than round-off; and any moving plane or cylinder. A rotating cylinder would be LIGGGHTS's `zcylinder`
//! primitive with `shear`, whose wall velocity is ω × r at the sphere's
//! *centre* (`calcRadialDistance` of the centre), not at the contact
//! point as in dembound: a tangential speed off by the relative r/R of the
//! sphere in the drum. Give the drum as a mesh instead.

use crate::{num, Error, Result};
use dembound_scene::setup::WallSetup;
use dembound_scene::walls::motion::WallMotion;

/// How a moving mesh sweeps the box LIGGGHTS must hold it in.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Sweep {
    /// Turning about an axis through this centre, m ([`swept_bounds`]).
    Turn([f64; 3]),
    /// Translating at this velocity, m/s: the mesh's bounds shifted by
    /// V t for t in the run.
    Shift([f64; 3]),
}

/// Checks the motion of wall `w` (`Some`: it moves) for a LIGGGHTS deck:
/// the `fix move/mesh` line of a turning or translating mesh (mesh fix
/// `mesh{w}`) with how it sweeps the box, or a refusal naming the key.
pub(crate) fn move_mesh_line(
    w: usize,
    wall: &WallSetup,
    motion: &WallMotion,
) -> Result<(String, Sweep)> {
    let refuse = |s: String| Err(Error::Export(s));
    let WallSetup::Mesh(_) = wall else {
        let why = match wall {
            WallSetup::Cylinder(_) => {
                "LIGGGHTS's turning cylinder (`zcylinder` primitive with `shear`) moves the wall at \
                 omega x r of the sphere's centre, dembound at the contact point; give the drum as \
                 a `mesh` (fix move/mesh rotate is exact)"
            }
            _ => "only turning meshes are exported (fix move/mesh rotate); give the wall as a `mesh`",
        };
        let key = if motion.velocity == [0.0; 3] && motion.angular_velocity == [0.0; 3] {
            "oscillation"
        } else {
            "motion"
        };
        return refuse(format!(
            "`wall[{w}].{key}` of a `{}` wall is not exported to LIGGGHTS: {why}",
            wall.key()
        ));
    };
    if motion.velocity != [0.0; 3]
        && motion.angular_velocity == [0.0; 3]
        && motion.oscillation.is_none()
    {
        return linear_line(w, motion).map(|l| (l, Sweep::Shift(motion.velocity)));
    }
    rotate_line(w, motion).map(|l| (l, Sweep::Turn(motion.center)))
}

/// The `fix move/mesh ... linear` line of mesh `mesh{w}` translating at
/// `motion.velocity`, or a refusal naming the key when it starts late or
/// stops.
fn linear_line(w: usize, motion: &WallMotion) -> Result<String> {
    if motion.start != 0.0 || motion.end != f64::INFINITY {
        return Err(Error::Export(format!(
            "`wall[{w}].motion` with start = {} s, end = {} s is not exported to LIGGGHTS: its \
             fix move/mesh moves from t = 0 for ever (start = 0, no end)",
            motion.start, motion.end
        )));
    }
    let v = motion.velocity;
    Ok(format!(
        "# wall[{w}] translates at ({}, {}, {}) m/s (dembound's motion.velocity)\n\
         fix          move{w} all move/mesh mesh mesh{w} linear {} {} {}",
        num(v[0]),
        num(v[1]),
        num(v[2]),
        num(v[0]),
        num(v[1]),
        num(v[2])
    ))
}

/// The `fix move/mesh ... rotate` line of mesh `mesh{w}` for `motion`, or a
/// refusal naming the key when it is not a constant turn from t = 0.
fn rotate_line(w: usize, motion: &WallMotion) -> Result<String> {
    let refuse = |s: String| Err(Error::Export(s));
    if let Some((a, f)) = motion.oscillation {
        return refuse(format!(
            "`wall[{w}].oscillation` = {{ amplitude = {a:?}, frequency = {f} }} is not exported to \
             LIGGGHTS: its move/mesh wiggle sums the velocity times the step (an Euler sum), so \
             its pose drifts from dembound's a sin(2 pi f t) by about a 2 pi f dt/2 (exported: a \
             mesh turning at a constant motion.angular_velocity or translating at a constant \
             motion.velocity)"
        ));
    }
    if motion.velocity != [0.0; 3] {
        return refuse(format!(
            "`wall[{w}].motion.velocity` = {:?} m/s with an angular_velocity is not exported to \
             LIGGGHTS (exported: a mesh turning at a constant motion.angular_velocity about a \
             fixed centre, or translating at a constant motion.velocity)",
            motion.velocity
        ));
    }
    if motion.start != 0.0 || motion.end != f64::INFINITY {
        return refuse(format!(
            "`wall[{w}].motion` with start = {} s, end = {} s is not exported to LIGGGHTS: its \
             fix move/mesh turns from t = 0 for ever (start = 0, no end)",
            motion.start, motion.end
        ));
    }
    let omega = motion.angular_velocity;
    let speed = (omega[0] * omega[0] + omega[1] * omega[1] + omega[2] * omega[2]).sqrt();
    if speed == 0.0 {
        return refuse(format!(
            "`wall[{w}].motion` moves nothing (velocity and angular_velocity 0) and is not exported \
             to LIGGGHTS; remove it to export"
        ));
    }
    let c = motion.center;
    Ok(format!(
        "# wall[{w}] turns at |omega| = {} rad/s about the axis through ({}, {}, {}) m along omega\n\
         # (dembound's motion.angular_velocity; period 2 pi/|omega| s)\n\
         fix          move{w} all move/mesh mesh mesh{w} rotate origin {} {} {} axis {} {} {} period {}",
        num(speed),
        num(c[0]),
        num(c[1]),
        num(c[2]),
        num(c[0]),
        num(c[1]),
        num(c[2]),
        num(omega[0] / speed),
        num(omega[1] / speed),
        num(omega[2] / speed),
        num(2.0 * std::f64::consts::PI / speed)
    ))
}

/// The box corners that hold every pose of a mesh of `vertices` turning
/// about an axis through `center`: the cube around `center` of half side
/// the farthest node's distance (LIGGGHTS refuses mesh nodes outside its
/// box).
pub(crate) fn swept_bounds(vertices: &[[f64; 3]], center: [f64; 3]) -> ([f64; 3], [f64; 3]) {
    let reach = vertices
        .iter()
        .map(|v| {
            let d = [v[0] - center[0], v[1] - center[1], v[2] - center[2]];
            (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt()
        })
        .fold(0.0, f64::max);
    (
        [center[0] - reach, center[1] - reach, center[2] - reach],
        [center[0] + reach, center[1] + reach, center[2] + reach],
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn turn(omega: [f64; 3]) -> WallMotion {
        WallMotion {
            velocity: [0.0; 3],
            angular_velocity: omega,
            center: [0.1, 0.2, 0.0],
            start: 0.0,
            end: f64::INFINITY,
            oscillation: None,
        }
    }

    /// The period is 2π/|ω| and the axis ω̂: a turn of 2 rad/s about −z.
    #[test]
    fn rotate_line_of_a_turning_mesh() {
        let line = rotate_line(3, &turn([0.0, 0.0, -2.0])).expect("exported");
        let expected = format!(
            "fix          move3 all move/mesh mesh mesh3 rotate origin {} {} 0 axis 0 0 {} period {}",
            num(0.1),
            num(0.2),
            num(-1.0),
            num(std::f64::consts::PI)
        );
        assert!(line.ends_with(&expected), "{line}");
    }

    /// A late start, a translation, an oscillation and a plane are refused
    /// with their keys.
    #[test]
    fn other_motions_are_refused_with_their_keys() {
        let late = WallMotion {
            start: 0.5,
            ..turn([0.0, 0.0, 1.0])
        };
        assert!(rotate_line(0, &late)
            .unwrap_err()
            .to_string()
            .contains("start = 0.5"));
        let sliding = WallMotion {
            velocity: [1.0, 0.0, 0.0],
            ..turn([0.0, 0.0, 1.0])
        };
        let e = rotate_line(1, &sliding).unwrap_err().to_string();
        assert!(e.contains("wall[1].motion.velocity"), "{e}");
        let late_slide = WallMotion {
            velocity: [1.0, 0.0, 0.0],
            end: 2.0,
            ..turn([0.0; 3])
        };
        let e = linear_line(1, &late_slide).unwrap_err().to_string();
        assert!(e.contains("wall[1].motion") && e.contains("end = 2"), "{e}");
        let line = linear_line(
            4,
            &WallMotion {
                velocity: [0.0, -0.5, 0.0],
                ..turn([0.0; 3])
            },
        )
        .expect("exported");
        assert!(
            line.ends_with(&format!("move/mesh mesh mesh4 linear 0 {} 0", num(-0.5))),
            "{line}"
        );
        let shaking = WallMotion {
            oscillation: Some(([0.0, 0.0, 1e-3], 50.0)),
            ..turn([0.0; 3])
        };
        let e = rotate_line(2, &shaking).unwrap_err().to_string();
        assert!(e.contains("wall[2].oscillation"), "{e}");
        let plane = WallSetup::Plane(dembound_scene::setup::Plane {
            point: [0.0; 3],
            normal: [0.0, 0.0, 1.0],
            material: 0,
        });
        let e = move_mesh_line(3, &plane, &turn([0.0, 0.0, 1.0]))
            .unwrap_err()
            .to_string();
        assert!(e.contains("wall[3].motion") && e.contains("mesh"), "{e}");
        let swept = swept_bounds(&[[0.1, 0.5, 0.0], [0.5, 0.2, 0.0]], [0.1, 0.2, 0.0]);
        assert!((swept.1[0] - 0.5).abs() < 1e-15 && (swept.0[1] + 0.2).abs() < 1e-15);
    }
}
