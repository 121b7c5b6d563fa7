//! Where a contact's tangential force acts on each body: the lever arm of
//! its torque (the scene key `contact.torque_arm`).
//!
//! - [`TorqueArm::Radius`] (`"radius"`, the default): the undeformed
//!   radius R on both sides of a sphere pair and on the sphere of a wall
//!   contact. The slip velocity uses the same R, so the tangential force
//!   does work F_t·v_t exactly, and in gross sliding the spin changes by
//!   exactly (5/2) μ J_n/(m R).
//! - [`TorqueArm::ContactPoint`] (`"contact_point"`): LAMMPS's `pair
//!   granular` (29 Sep 2021, `PairGranular::compute`; 2023's
//!   `GranularModel::calculate_forces` alike): for a sphere pair the
//!   torque on each sphere is taken at `dist_to_contact = R − δ/2`, δ the
//!   overlap, i.e. at the midpoint of the overlap; against a wall
//!   (`fix wall/gran`, `fix wall/gran/region`) at R. LAMMPS keeps R in
//!   everything else: the slip velocity (`wr = radi ω_i + radj ω_j`),
//!   the rolling velocity and torque (R_eff), the twisting torque (no
//!   arm). So only the tangential torque of a sphere pair changes, by a
//!   factor 1 − δ/(2R).
//! - [`TorqueArm::OverlapMiddle`] (`"overlap_middle"`): Yade's (2023.02a,
//!   read in `pkg/common/Ig2_Box_Sphere_ScGeom.cpp`, `pkg/dem/ScGeom.cpp`
//!   `ScGeom::getIncidentVel` and the periodic branch of
//!   `Law2_ScGeom6D_CohFrictPhys_CohesionMoment::go`): every contact's
//!   force acts at the middle of the overlap, so the tangential torque
//!   has the arm R − δ/2 on a sphere of a pair and on a sphere against a
//!   wall. Against a wall (Yade's box face) the slip velocity takes the
//!   same arm R − δ/2 (`getIncidentVel` at the contact point). Between
//!   two spheres the slip keeps the radii and scales the centres'
//!   relative velocity by α = (R₁ + R₂)/(R₁ + R₂ − δ)
//!   (`avoidGranularRatcheting`, the default of
//!   `Ig2_Sphere_Sphere_ScGeom`).
//! - [`TorqueArm::HalfOverlap`] (`"half_overlap"`): LIGGGHTS's (3.8,
//!   read in `src/surface_model_default.h`,
//!   `SurfaceModel<SURFACE_DEFAULT>::surfacesIntersect`, and
//!   `src/tangential_model_history.h`,
//!   `TangentialModel<TANGENTIAL_HISTORY>::surfacesIntersect`): R − δ/2
//!   from each centre, `cri = radi − 0.5 deltan` and `crj = radj − 0.5
//!   deltan` in a sphere pair, `cr = radi − 0.5 deltan` against a wall,
//!   each used both in the slip velocity (`wr = (cri ω_i + crj ω_j)/r`,
//!   then `vtr = vt − wr × delta`) and as the tangential torque's arm
//!   (`delta_torque = −cri en × F_t`), with no scaling of the centres'
//!   velocities. Against a wall it is [`TorqueArm::OverlapMiddle`] bit
//!   for bit; in a sphere pair it has no α.
//!
//! The rolling spring (relative spin only) is the same under every arm.

use super::model::Side;

/// The lever arm of the tangential force's torque.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum TorqueArm {
    /// The undeformed radius R (dembound's model).
    #[default]
    Radius,
    /// R − δ/2 for sphere pairs, R against walls (LAMMPS's model).
    ContactPoint,
    /// R − δ/2 on every contact, in the slip against walls too, and the
    /// centres' relative velocity scaled by α in a pair's slip (Yade's
    /// model; [`TorqueArm::slip_sides`]).
    OverlapMiddle,
    /// R − δ/2 on every sphere of every contact, in the torque and in the
    /// slip, the centres' velocities as they are (LIGGGHTS's model).
    HalfOverlap,
}

/// The names `contact.torque_arm` takes, in the order of [`TorqueArm`].
pub const TORQUE_ARM_NAMES: [&str; 4] =
    ["radius", "contact_point", "overlap_middle", "half_overlap"];

impl TorqueArm {
    /// The arm named `name` (one of [`TORQUE_ARM_NAMES`]).
    pub fn from_name(name: &str) -> Option<Self> {
        match name {
            "radius" => Some(Self::Radius),
            "contact_point" => Some(Self::ContactPoint),
            "overlap_middle" => Some(Self::OverlapMiddle),
            "half_overlap" => Some(Self::HalfOverlap),
            _ => None,
        }
    }

    /// The name of the arm, as a scene writes it.
    pub fn name(self) -> &'static str {
        match self {
            Self::Radius => TORQUE_ARM_NAMES[0],
            Self::ContactPoint => TORQUE_ARM_NAMES[1],
            Self::OverlapMiddle => TORQUE_ARM_NAMES[2],
            Self::HalfOverlap => TORQUE_ARM_NAMES[3],
        }
    }

    /// The lever arms (m) of the tangential torque on body 1 and body 2
    /// of a contact of overlap `overlap` (m) between sides whose radii are
    /// `radius1` and `radius2` (m; a wall is side 2 with radius 0). Under
    /// [`Self::Radius`] the radii themselves (the same bits); under
    /// [`Self::ContactPoint`] R − δ/2 on both sides of a sphere pair
    /// (`radius2 > 0`), the radii unchanged against a wall; under
    /// [`Self::OverlapMiddle`] and [`Self::HalfOverlap`] R − δ/2 on every
    /// sphere (a wall keeps 0).
    #[inline(always)]
    pub fn arms(self, overlap: f64, radius1: f64, radius2: f64) -> (f64, f64) {
        match self {
            Self::ContactPoint | Self::OverlapMiddle | Self::HalfOverlap if radius2 > 0.0 => {
                (radius1 - 0.5 * overlap, radius2 - 0.5 * overlap)
            }
            Self::OverlapMiddle | Self::HalfOverlap => (radius1 - 0.5 * overlap, radius2),
            _ => (radius1, radius2),
        }
    }

    /// The sides as the slip velocity reads them (`model::slip_velocity`)
    /// for a contact of overlap `overlap` (m): unchanged (the same bits)
    /// under [`Self::Radius`] and [`Self::ContactPoint`]; under
    /// [`Self::OverlapMiddle`] Yade's: against a wall (side 2 of arm 0)
    /// body 1's arm R − δ/2, between two spheres both centre velocities
    /// times α = (R₁ + R₂)/(R₁ + R₂ − δ) (so their difference is α (v₁ −
    /// v₂); `ScGeom::getIncidentVel` with `avoidGranularRatcheting`);
    /// under [`Self::HalfOverlap`] LIGGGHTS's: every sphere's arm R − δ/2
    /// (a wall's stays 0), the velocities unchanged.
    #[inline(always)]
    pub fn slip_sides(self, overlap: f64, a: &Side, b: &Side) -> (Side, Side) {
        match self {
            Self::OverlapMiddle if b.arm > 0.0 => {
                let sum = a.arm + b.arm;
                let alpha = sum / (sum - overlap);
                let scale = |v: [f64; 3]| [alpha * v[0], alpha * v[1], alpha * v[2]];
                (
                    Side {
                        velocity: scale(a.velocity),
                        ..*a
                    },
                    Side {
                        velocity: scale(b.velocity),
                        ..*b
                    },
                )
            }
            Self::HalfOverlap if b.arm > 0.0 => (
                Side {
                    arm: a.arm - 0.5 * overlap,
                    ..*a
                },
                Side {
                    arm: b.arm - 0.5 * overlap,
                    ..*b
                },
            ),
            Self::OverlapMiddle | Self::HalfOverlap => (
                Side {
                    arm: a.arm - 0.5 * overlap,
                    ..*a
                },
                *b,
            ),
            _ => (*a, *b),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip_and_unknown_is_none() {
        assert_eq!(TORQUE_ARM_NAMES.len(), 4);
        for name in TORQUE_ARM_NAMES {
            assert_eq!(TorqueArm::from_name(name).map(TorqueArm::name), Some(name));
        }
        assert_eq!(TorqueArm::from_name("contact-point"), None);
        assert_eq!(TorqueArm::default(), TorqueArm::Radius);
    }

    /// R − δ/2 per sphere of a pair, the radius against a wall (radius 0).
    #[test]
    fn contact_point_arms_are_r_minus_half_the_overlap_for_pairs_only() {
        let (h, r1, r2) = (1e-5, 1e-3, 2e-3);
        assert_eq!(TorqueArm::Radius.arms(h, r1, r2), (r1, r2));
        assert_eq!(
            TorqueArm::ContactPoint.arms(h, r1, r2),
            (r1 - 0.5 * h, r2 - 0.5 * h)
        );
        assert_eq!(TorqueArm::ContactPoint.arms(h, r1, 0.0), (r1, 0.0));
        assert_eq!(
            TorqueArm::OverlapMiddle.arms(h, r1, r2),
            (r1 - 0.5 * h, r2 - 0.5 * h)
        );
        assert_eq!(
            TorqueArm::OverlapMiddle.arms(h, r1, 0.0),
            (r1 - 0.5 * h, 0.0)
        );
    }

    fn side(velocity: [f64; 3], spin: [f64; 3], arm: f64) -> Side {
        Side {
            velocity,
            spin,
            arm,
            inverse_inertia: 1.0,
        }
    }

    /// The slip under Yade's model against Yade's formulas
    /// (`ScGeom::getIncidentVel`), written out here: a pair's relative
    /// contact velocity α (v₁ − v₂) + (R₁ ω₁ + R₂ ω₂) × n with α = (R₁ +
    /// R₂)/(R₁ + R₂ − δ); a wall's v₁ − v_w + (R − δ/2) ω₁ × n. The other
    /// arms leave the sides as they are.
    #[test]
    fn overlap_middle_slip_is_yades_incident_velocity() {
        use crate::contact::model::slip_velocity;
        let (h, r1, r2) = (1e-4, 1e-3, 2e-3);
        let n = [0.0, 0.0, 1.0];
        let a = side([0.3, -0.1, 0.2], [10.0, 20.0, -5.0], r1);
        let b = side([-0.2, 0.4, 0.1], [-30.0, 5.0, 7.0], r2);
        let wall = side([0.05, 0.0, 0.0], [0.0; 3], 0.0);
        for arm in [TorqueArm::Radius, TorqueArm::ContactPoint] {
            assert_eq!(arm.slip_sides(h, &a, &b), (a, b));
            assert_eq!(arm.slip_sides(h, &a, &wall), (a, wall));
        }
        let alpha = (r1 + r2) / (r1 + r2 - h);
        // (R₁ ω₁ + R₂ ω₂) × n with n = z: (w_y, −w_x, 0) of w = R₁ ω₁ + R₂ ω₂.
        let w = [r1 * 10.0 + r2 * -30.0, r1 * 20.0 + r2 * 5.0];
        let pair = [alpha * 0.5 + w[1], alpha * -0.5 - w[0], 0.0];
        let (sa, sb) = TorqueArm::OverlapMiddle.slip_sides(h, &a, &b);
        let got = slip_velocity(&sa, &sb, n);
        for k in 0..3 {
            // a few ulps of the 0.5 m/s terms summed
            assert!((got[k] - pair[k]).abs() < 1e-15, "{got:?} {pair:?}");
        }
        let arm = r1 - 0.5 * h;
        let on_wall = [0.25 + arm * 20.0, -0.1 - arm * 10.0, 0.0];
        let (sa, sw) = TorqueArm::OverlapMiddle.slip_sides(h, &a, &wall);
        assert_eq!(sw, wall);
        let got = slip_velocity(&sa, &sw, n);
        for k in 0..3 {
            assert!((got[k] - on_wall[k]).abs() < 1e-15, "{got:?} {on_wall:?}");
        }
    }

    /// The slip under LIGGGHTS's model against LIGGGHTS's formulas
    /// (`surface_model_default.h`), written out here: a pair's relative
    /// contact velocity v₁ − v₂ + ((R₁ − δ/2) ω₁ + (R₂ − δ/2) ω₂) × n, no
    /// α (`vtr = vt − wr × delta` with `wr = (cri ω_i + crj ω_j)/r`: the
    /// normal of LIGGGHTS points from j to i, dembound's from 1 to 2, so
    /// both signs flip); against a wall exactly Yade's
    /// ([`TorqueArm::OverlapMiddle`]): the same sides and arms, bit for bit.
    #[test]
    fn half_overlap_slip_is_liggghts_relative_velocity() {
        use crate::contact::model::slip_velocity;
        let (h, r1, r2) = (1e-4, 1e-3, 2e-3);
        let n = [0.0, 0.0, 1.0];
        let a = side([0.3, -0.1, 0.2], [10.0, 20.0, -5.0], r1);
        let b = side([-0.2, 0.4, 0.1], [-30.0, 5.0, 7.0], r2);
        let wall = side([0.05, 0.0, 0.0], [0.0; 3], 0.0);
        let (c1, c2) = (r1 - 0.5 * h, r2 - 0.5 * h);
        // (c₁ ω₁ + c₂ ω₂) × n with n = z: (w_y, −w_x, 0).
        let w = [c1 * 10.0 + c2 * -30.0, c1 * 20.0 + c2 * 5.0];
        let pair = [0.5 + w[1], -0.5 - w[0], 0.0];
        let (sa, sb) = TorqueArm::HalfOverlap.slip_sides(h, &a, &b);
        assert_eq!((sa.velocity, sb.velocity), (a.velocity, b.velocity));
        let got = slip_velocity(&sa, &sb, n);
        for k in 0..3 {
            // a few ulps of the 0.5 m/s terms summed
            assert!((got[k] - pair[k]).abs() < 1e-15, "{got:?} {pair:?}");
        }
        // Yade's α = 3.0e-3/2.9e-3 would move the 0.5 m/s terms by 1.7e-2
        // m/s: the two pair slips are told apart far above the tolerance.
        let (ya, yb) = TorqueArm::OverlapMiddle.slip_sides(h, &a, &b);
        let yade = slip_velocity(&ya, &yb, n);
        assert!((yade[0] - got[0]).abs() > 1e-3, "{yade:?} {got:?}");
        assert_eq!(
            TorqueArm::HalfOverlap.arms(h, r1, r2),
            (r1 - 0.5 * h, r2 - 0.5 * h)
        );
        // At a wall: LIGGGHTS's cr = R − δ/2 in the slip and the torque,
        // the same bits as Yade's.
        assert_eq!(
            TorqueArm::HalfOverlap.slip_sides(h, &a, &wall),
            TorqueArm::OverlapMiddle.slip_sides(h, &a, &wall)
        );
        let (sa, _) = TorqueArm::HalfOverlap.slip_sides(h, &a, &wall);
        assert_eq!(sa.arm, r1 - 0.5 * h);
        assert_eq!(
            TorqueArm::HalfOverlap.arms(h, r1, 0.0).0.to_bits(),
            TorqueArm::OverlapMiddle.arms(h, r1, 0.0).0.to_bits()
        );
        assert_eq!(TorqueArm::HalfOverlap.arms(h, r1, 0.0), (r1 - 0.5 * h, 0.0));
    }
}
