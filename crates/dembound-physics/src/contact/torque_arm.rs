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

/// The lever arm of the tangential force's torque.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum TorqueArm {
    /// The undeformed radius R (dembound's model).
    #[default]
    Radius,
    /// R − δ/2 for sphere pairs, R against walls (LAMMPS's model).
    ContactPoint,
}

/// The names `contact.torque_arm` takes, in the order of [`TorqueArm`].
pub const TORQUE_ARM_NAMES: [&str; 2] = ["radius", "contact_point"];

impl TorqueArm {
    /// The arm named `name` (`"radius"` or `"contact_point"`).
    pub fn from_name(name: &str) -> Option<Self> {
        match name {
            "radius" => Some(Self::Radius),
            "contact_point" => Some(Self::ContactPoint),
            _ => None,
        }
    }

    /// The name of the arm, as a scene writes it.
    pub fn name(self) -> &'static str {
        match self {
            Self::Radius => TORQUE_ARM_NAMES[0],
            Self::ContactPoint => TORQUE_ARM_NAMES[1],
        }
    }

    /// The lever arms (m) of the tangential torque on body 1 and body 2
    /// of a contact of overlap `overlap` (m) between sides whose radii are
    /// `radius1` and `radius2` (m; a wall is side 2 with radius 0). Under
    /// [`Self::Radius`] the radii themselves (the same bits); under
    /// [`Self::ContactPoint`] R − δ/2 on both sides of a sphere pair
    /// (`radius2 > 0`), the radii unchanged against a wall.
    #[inline(always)]
    pub fn arms(self, overlap: f64, radius1: f64, radius2: f64) -> (f64, f64) {
        match self {
            Self::ContactPoint if radius2 > 0.0 => {
                (radius1 - 0.5 * overlap, radius2 - 0.5 * overlap)
            }
            _ => (radius1, radius2),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip_and_unknown_is_none() {
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
    }
}
