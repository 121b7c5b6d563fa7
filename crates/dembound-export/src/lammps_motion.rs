//! Moving walls and moving groups of fixed spheres in a LAMMPS scene deck
//! (issue 27): what of dembound's `motion = { velocity, angular_velocity,
//! center, start, end }` and `oscillation = { amplitude, frequency }`
//! LAMMPS (checked against its `fix_move.cpp` and `fix_wall_gran.cpp`)
//! computes the same way, and a refusal naming the key for the rest.
//!
//! **Moving groups** (`[[particles]] fixed = true` with a motion, and
//! `boundary_particles` walls with one): the spheres stay frozen atoms
//! (`fix freeze`: no force integrated, m_eff = the free sphere's mass in
//! `pair granular`, as for a still group), and a `fix move` on the
//! group's atom ids sets their positions and velocities every step:
//! - `rotate P axis period` (a constant ω about the axis through c):
//!   LAMMPS puts atom k at P + C + A cos(ω t) + B sin(ω t) (A the part of
//!   X_k − P normal to the axis, C the part along it, B = ω̂ × A), which
//!   is Rodrigues' rotation of X_k − P by ω t about ω̂ — dembound's pose
//!   x_k = c + R(t)(X_k − c) with P = c; the velocity ω ω̂ × (A cos +
//!   B sin) = ω × (x_k − c), dembound's. LAMMPS also sets the atom's
//!   omega to ω ω̂ (its `omega_flag` branch, for atoms of non-zero
//!   radius), as dembound gives each group sphere the group's ω, so the
//!   surface velocity the contact sees at its contact point p is
//!   v_k + ω × (p − x_k) = ω × (p − c) in both codes. ω = 2π/period
//!   with period = 2π/|ω| written: |ω| to the last bit or one off.
//! - `linear V`: X_k + V t, velocity V, omega left as read (0); dembound
//!   c + (X_k − c) + V t, velocity V, spin 0.
//! - `wiggle a period` with period = 1/f: X_k + a sin(2π t/period),
//!   velocity a 2π/period cos(2π t/period); dembound's oscillation is
//!   X_k + a sin(2π f t), velocity 2π f a cos(2π f t).
//!
//! The time: LAMMPS's `fix move` sets the atoms in `initial_integrate`
//! at t = (step − step of the fix's creation) Δt, the step already
//! counted up, so the forces of step n + 1 see the pose at (n + 1) Δt;
//! dembound places the groups at the time of the force evaluation that
//! follows (`pipeline::moving_groups`). The fix is created before the
//! first `run`, at step 0. The pose at t = 0 is the data file's; the
//! velocities and spins at t = 0, which the setup forces of step 0 see,
//! are written into the data file's `Velocities` section.
//!
//! One `fix move` style per group: a group that turns and translates,
//! or translates and oscillates, is refused (two fixes would each set
//! the positions from the original ones, the last winning). A motion
//! with `start` ≠ 0 or a finite `end` is refused: `fix move` runs from
//! its creation for ever, and the switch at the first step n with
//! n Δt ≥ start would need the deck's run in segments with a `fix move`
//! created at that step, whose time origin (its step) is start only when
//! start is a multiple of Δt (not written).
//!
//! **Planes**: a plane moving along itself at a constant V (a conveyor:
//! V · n = 0, V along one axis, no ω, no oscillation, from t = 0 for
//! ever) as `fix wall/gran … shear dim V`. An infinite plane translated
//! along itself stays the same plane, so the pose is unchanged in both
//! codes; `fix wall/gran` with `shear` sets the wall's velocity to V
//! along `dim` in its contact (v_r = v − v_wall), and dembound's plane
//! contact takes the wall's surface velocity ḋ = V at the contact point.
//! Refused: a plane oscillating along its normal: LAMMPS's `wiggle` puts
//! it at lo + A − A cos(ω t) with velocity A ω sin(ω t) (its
//! `post_force`), where dembound's oscillation is a sin(2π f t): a
//! quarter period apart, with an offset A, not the same motion; a plane
//! moving along its normal at constant speed or turning (no `fix
//! wall/gran` motion for it); a plane given as a region (`fix
//! wall/gran/region`, not axis-aligned).

use crate::{num, Error, Result};
use dembound_scene::setup::{SceneSetup, WallSetup};
use dembound_scene::walls::motion::WallMotion;

/// One moving group of fixed spheres in the deck.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct GroupMove {
    /// The scene key (`particles[K]` or `wall[K]`).
    pub key: String,
    /// Its spheres: input indices (LAMMPS ids are these + 1).
    pub spheres: std::ops::Range<usize>,
    pub motion: WallMotion,
    /// The `fix move` arguments after `move`.
    pub args: String,
}

/// The moving groups of `setup` (`[[particles]]` groups, then the moving
/// boundary-particle walls, as `pipeline::moving_groups` orders them),
/// each with its `fix move` arguments, or a refusal naming the key.
pub(crate) fn group_moves(setup: &SceneSetup) -> Result<Vec<GroupMove>> {
    let mut out = Vec::new();
    for g in &setup.group_motions {
        let key = format!("particles[{}]", g.group);
        let args = move_args(&key, &g.motion)?;
        out.push(GroupMove {
            key,
            spheres: g.spheres.clone(),
            motion: g.motion,
            args,
        });
    }
    for (w, m) in setup.wall_motions.iter().enumerate() {
        let (Some(m), Some(wall)) = (m, setup.walls.get(w)) else {
            continue;
        };
        if !wall.is_particles() {
            continue;
        }
        let key = format!("wall[{w}]");
        let args = move_args(&key, m)?;
        let spheres = wall.bodies().unwrap_or(0..0);
        out.push(GroupMove {
            key,
            spheres,
            motion: *m,
            args,
        });
    }
    Ok(out)
}

/// The `fix move` style and arguments of a group's `motion` (`key`: its
/// scene key), or a refusal naming the key (module doc).
fn move_args(key: &str, motion: &WallMotion) -> Result<String> {
    let refuse = |s: String| Err(Error::Export(s));
    let turns = motion.angular_velocity != [0.0; 3];
    let slides = motion.velocity != [0.0; 3];
    if (turns || slides) && (motion.start != 0.0 || motion.end != f64::INFINITY) {
        return refuse(format!(
            "`{key}.motion` with start = {} s, end = {} s is not exported to LAMMPS: its fix \
             move runs from t = 0 for ever (start = 0, no end)",
            motion.start, motion.end
        ));
    }
    match (turns, slides, motion.oscillation) {
        (true, false, None) => {
            let w = motion.angular_velocity;
            let speed = (w[0] * w[0] + w[1] * w[1] + w[2] * w[2]).sqrt();
            let c = motion.center;
            Ok(format!(
                "rotate {} {} {} {} {} {} {} units box",
                num(c[0]),
                num(c[1]),
                num(c[2]),
                num(w[0] / speed),
                num(w[1] / speed),
                num(w[2] / speed),
                num(2.0 * std::f64::consts::PI / speed)
            ))
        }
        (false, true, None) => {
            let v = motion.velocity;
            Ok(format!(
                "linear {} {} {} units box",
                num(v[0]),
                num(v[1]),
                num(v[2])
            ))
        }
        (false, false, Some((a, f))) => Ok(format!(
            "wiggle {} {} {} {} units box",
            num(a[0]),
            num(a[1]),
            num(a[2]),
            num(1.0 / f)
        )),
        (false, false, None) => refuse(format!(
            "`{key}.motion` moves nothing (velocity and angular_velocity 0) and is not exported to \
             LAMMPS; remove it to export"
        )),
        _ => refuse(format!(
            "`{key}.motion` and `{key}.oscillation` combine several motions (velocity {:?} m/s, \
             angular_velocity {:?} rad/s, oscillation {}); the LAMMPS deck writes one fix move \
             style per group (rotate, linear or wiggle), so give one of them",
            motion.velocity,
            motion.angular_velocity,
            if motion.oscillation.is_some() {
                "given"
            } else {
                "none"
            }
        )),
    }
}

/// The velocity (m/s) and spin (rad/s) at t = 0 of a sphere at `x` of a
/// group moving by `motion`: the data file's `Velocities` row.
pub(crate) fn initial_velocity(motion: &WallMotion, x: [f64; 3]) -> ([f64; 3], [f64; 3]) {
    let s = motion.state(0.0);
    (s.velocity_at(x), s.spin)
}

/// The `shear dim V` keywords of plane `wall[w]` (unit normal `normal`,
/// axis-aligned along `axis`, or `None` for a region plane) moving by
/// `motion`, or a refusal naming the key (module doc).
pub(crate) fn plane_shear(
    w: usize,
    normal: [f64; 3],
    axis: Option<usize>,
    motion: &WallMotion,
) -> Result<String> {
    let refuse = |s: String| Err(Error::Export(s));
    if let Some((a, f)) = motion.oscillation {
        return refuse(format!(
            "`wall[{w}].oscillation` = {{ amplitude = {a:?}, frequency = {f} }} of a plane is not \
             exported to LAMMPS: its fix wall/gran wiggle moves the plane as A (1 - cos(omega t)), \
             dembound's oscillation is a sin(2 pi f t) (a quarter period apart)"
        ));
    }
    if motion.angular_velocity != [0.0; 3] {
        return refuse(format!(
            "`wall[{w}].motion.angular_velocity` of a plane is not exported to LAMMPS (fix \
             wall/gran has no turning plane)"
        ));
    }
    if motion.start != 0.0 || motion.end != f64::INFINITY {
        return refuse(format!(
            "`wall[{w}].motion` with start = {} s, end = {} s is not exported to LAMMPS: fix \
             wall/gran's shear acts from t = 0 for ever (start = 0, no end)",
            motion.start, motion.end
        ));
    }
    let v = motion.velocity;
    let Some(axis) = axis else {
        return refuse(format!(
            "`wall[{w}].motion` of a plane whose normal is not along x, y or z is not exported to \
             LAMMPS (fix wall/gran/region has no shear); give the plane an axis-aligned normal"
        ));
    };
    let along: Vec<usize> = (0..3).filter(|&k| v[k] != 0.0).collect();
    match along.as_slice() {
        [k] if *k != axis && normal[*k] == 0.0 => {
            Ok(format!(" shear {} {}", ["x", "y", "z"][*k], num(v[*k])))
        }
        _ => refuse(format!(
            "`wall[{w}].motion.velocity` = {v:?} m/s of a plane is not exported to LAMMPS: \
             exported is a plane sliding along itself (a conveyor) along one axis, written as fix \
             wall/gran shear; a plane moving along its normal has no fix wall/gran counterpart"
        )),
    }
}

/// The refusal of a moving wall the LAMMPS deck holds no motion for (not
/// a plane, not boundary particles).
pub(crate) fn refuse_other_moving_walls(setup: &SceneSetup) -> Result<()> {
    for (w, m) in setup.wall_motions.iter().enumerate() {
        let (Some(m), Some(wall)) = (m, setup.walls.get(w)) else {
            continue;
        };
        if wall.is_particles() || matches!(wall, WallSetup::Plane(_)) {
            continue;
        }
        let key = if m.velocity != [0.0; 3] || m.angular_velocity != [0.0; 3] {
            "motion"
        } else {
            "oscillation"
        };
        return Err(Error::Export(format!(
            "`wall[{w}].{key}` of a `{}` wall cannot be exported to LAMMPS: the deck moves \
             planes (fix wall/gran shear) and groups of spheres (fix move) only",
            wall.key()
        )));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn still() -> WallMotion {
        WallMotion {
            velocity: [0.0; 3],
            angular_velocity: [0.0; 3],
            center: [0.1, 0.2, 0.0],
            start: 0.0,
            end: f64::INFINITY,
            oscillation: None,
        }
    }

    /// rotate: the axis ω̂ through c and the period 2π/|ω|; linear: V;
    /// wiggle: a and the period 1/f.
    #[test]
    fn each_motion_gets_its_fix_move_style() {
        let turn = WallMotion {
            angular_velocity: [0.0, 0.0, -2.0],
            ..still()
        };
        assert_eq!(
            move_args("particles[1]", &turn).unwrap(),
            format!(
                "rotate {} {} 0 0 0 {} {} units box",
                num(0.1),
                num(0.2),
                num(-1.0),
                num(std::f64::consts::PI)
            )
        );
        let slide = WallMotion {
            velocity: [0.5, 0.0, 0.0],
            ..still()
        };
        assert_eq!(
            move_args("wall[0]", &slide).unwrap(),
            format!("linear {} 0 0 units box", num(0.5))
        );
        let shake = WallMotion {
            oscillation: Some(([0.0, 0.0, 1e-3], 40.0)),
            ..still()
        };
        assert_eq!(
            move_args("wall[0]", &shake).unwrap(),
            format!("wiggle 0 0 {} {} units box", num(1e-3), num(0.025))
        );
        // The data file's velocity of a sphere at (0.1, 0.3, 0) turning
        // at -2 rad/s about z through (0.1, 0.2, 0): ω × (x − c) = (0.2, 0, 0).
        let (v, w) = initial_velocity(&turn, [0.1, 0.3, 0.0]);
        assert!(
            (v[0] - 0.2).abs() < 1e-15 && v[1] == 0.0 && v[2] == 0.0,
            "{v:?}"
        );
        assert_eq!(w, [0.0, 0.0, -2.0]);
    }

    /// Combined motions, a late start or an early end, and a group that
    /// does not move are refused with their keys.
    #[test]
    fn other_group_motions_are_refused_with_their_keys() {
        let both = WallMotion {
            velocity: [0.1, 0.0, 0.0],
            angular_velocity: [0.0, 0.0, 1.0],
            ..still()
        };
        let e = move_args("particles[2]", &both).unwrap_err().to_string();
        assert!(
            e.contains("particles[2].motion") && e.contains("one fix move"),
            "{e}"
        );
        let late = WallMotion {
            start: 0.25,
            angular_velocity: [0.0, 0.0, 1.0],
            ..still()
        };
        let e = move_args("wall[3]", &late).unwrap_err().to_string();
        assert!(
            e.contains("wall[3].motion") && e.contains("start = 0.25"),
            "{e}"
        );
        let stops = WallMotion {
            end: 1.0,
            velocity: [0.0, 1.0, 0.0],
            ..still()
        };
        let e = move_args("wall[3]", &stops).unwrap_err().to_string();
        assert!(e.contains("end = 1"), "{e}");
        let e = move_args("wall[1]", &still()).unwrap_err().to_string();
        assert!(e.contains("moves nothing"), "{e}");
    }

    /// A conveyor along x on a floor (normal z) is `shear x V`; a plane
    /// moving along its normal, oscillating, turning or tilted is refused.
    #[test]
    fn planes_slide_as_shear_or_are_refused() {
        let conveyor = WallMotion {
            velocity: [0.05, 0.0, 0.0],
            ..still()
        };
        let z = [0.0, 0.0, 1.0];
        assert_eq!(
            plane_shear(0, z, Some(2), &conveyor).unwrap(),
            format!(" shear x {}", num(0.05))
        );
        let lift = WallMotion {
            velocity: [0.0, 0.0, 0.05],
            ..still()
        };
        let e = plane_shear(1, z, Some(2), &lift).unwrap_err().to_string();
        assert!(e.contains("wall[1].motion.velocity"), "{e}");
        let diagonal = WallMotion {
            velocity: [0.05, 0.05, 0.0],
            ..still()
        };
        assert!(plane_shear(1, z, Some(2), &diagonal).is_err());
        let shake = WallMotion {
            oscillation: Some(([0.0, 0.0, 1e-3], 40.0)),
            ..still()
        };
        let e = plane_shear(2, z, Some(2), &shake).unwrap_err().to_string();
        assert!(
            e.contains("wall[2].oscillation") && e.contains("cos"),
            "{e}"
        );
        let e = plane_shear(3, [0.6, 0.0, 0.8], None, &conveyor)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("wall[3].motion") && e.contains("axis-aligned"),
            "{e}"
        );
    }
}
