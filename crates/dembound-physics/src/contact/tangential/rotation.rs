//! How the stored tangential spring follows a contact whose normal turns
//! (the scene key `contact.spring_rotation`): step 1 of the module's list
//! ([`super::FrictionPair::rotate_spring`]).
//!
//! - [`SpringRotation::Rescale`] (`"rescale"`, the default): the spring
//!   projected onto the new tangent plane and scaled back to its old
//!   length ([`super::FrictionPair::turn_spring`]): LAMMPS's `pair
//!   granular` (`GranSubModTangentialLinearHistory` and the Mindlin
//!   variants, `gran_sub_mod_tangential.cpp`: "rotate and rescale", above
//!   a threshold on the normal component; `rotate_rescale_vec` in 2021's
//!   `PairGranular::compute`).
//! - [`SpringRotation::Project`] (`"project"`): the spring projected onto
//!   the new tangent plane and left at the projection's length, δ ← δ −
//!   (δ·n) n ([`project_spring`]): LIGGGHTS 3.8's
//!   `TangentialModel<TANGENTIAL_HISTORY>::surfacesIntersect`
//!   (`tangential_model_history.h`: `rsht = shear·en; shear −= rsht en`,
//!   no rescale). A spring in the old tangent plane whose normal turns by
//!   θ in a step is shortened by a factor cos θ ≈ 1 − θ²/2 (when the turn
//!   is along the spring). LIGGGHTS projects after adding the step's slip
//!   v_t Δt, dembound before: the same in exact arithmetic, as v_t lies in
//!   the tangent plane (P(δ + v_t Δt) = P δ + v_t Δt), so the two differ
//!   by round-off.
//!
//! Neither is Yade's (`ScGeom::rotate`: a first-order turn of the stored
//! shear force, `F −= F × (n₀ × n)`, which lengthens it by θ²/2 a step,
//! then a twist about n; docs/export-yade.md). The rolling spring is
//! turned with its length kept under both ([`super::super::rolling`]).

use super::dot;

/// How the stored tangential spring follows a turning normal.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum SpringRotation {
    /// Projected and scaled back to its length (LAMMPS's).
    #[default]
    Rescale,
    /// Projected, its length not restored (LIGGGHTS 3.8's).
    Project,
}

/// The names `contact.spring_rotation` takes, in the order of
/// [`SpringRotation`].
pub const SPRING_ROTATION_NAMES: [&str; 2] = ["rescale", "project"];

impl SpringRotation {
    /// The rotation named `name` (one of [`SPRING_ROTATION_NAMES`]).
    pub fn from_name(name: &str) -> Option<Self> {
        match name {
            "rescale" => Some(Self::Rescale),
            "project" => Some(Self::Project),
            _ => None,
        }
    }

    /// The name of the rotation, as a scene writes it.
    pub fn name(self) -> &'static str {
        match self {
            Self::Rescale => SPRING_ROTATION_NAMES[0],
            Self::Project => SPRING_ROTATION_NAMES[1],
        }
    }
}

/// The stored spring `shear` (a displacement, m, or a force, N) projected
/// onto the tangent plane of the unit normal `normal`, δ ← δ − (δ·n) n,
/// its length not restored: LIGGGHTS 3.8's operations in its order
/// (`rsht = shear[0]·enx + shear[1]·eny + shear[2]·enz`, then `shear[k] −=
/// rsht·en_k`).
#[inline(always)]
pub fn project_spring(shear: &mut [f64; 3], normal: [f64; 3]) {
    let along = dot(*shear, normal);
    shear[0] -= along * normal[0];
    shear[1] -= along * normal[1];
    shear[2] -= along * normal[2];
}

#[cfg(test)]
mod tests {
    use super::super::FrictionPair;
    use super::*;

    /// δ = a x̂ and the normal turned by θ about y from ẑ, n = (sin θ, 0,
    /// cos θ): δ·n = a sin θ, so the projection is a (1 − sin²θ, 0,
    /// −sin θ cos θ) = a cos θ (cos θ, 0, −sin θ) (closed form), of length
    /// a cos θ: shorter than the rescaled spring, a (cos θ, 0, −sin θ), by
    /// the factor cos θ. Tolerance 1e-15 of a: a few roundings of values
    /// ≤ a (1.1e-16 each). θ = 1e-3 and 0.3: the shortening 1 − cos θ =
    /// 5e-7 and 4.5e-2 is far above it, so a projection that rescaled (or
    /// did nothing) fails.
    #[test]
    fn project_drops_the_normal_part_and_keeps_the_shorter_length() {
        let a = 3.0e-7;
        for th in [1.0e-3f64, 0.3] {
            let n = [th.sin(), 0.0, th.cos()];
            let mut shear = [a, 0.0, 0.0];
            project_spring(&mut shear, n);
            let expected = [a * th.cos() * th.cos(), 0.0, -a * th.cos() * th.sin()];
            for c in 0..3 {
                assert!(
                    (shear[c] - expected[c]).abs() < 1e-15 * a,
                    "θ = {th}: {shear:?} against {expected:?}"
                );
            }
            let length = dot(shear, shear).sqrt();
            assert!((length / (a * th.cos()) - 1.0).abs() < 1e-14, "{length}");
            // The rescale keeps a: the two differ by 1 − cos θ of a.
            let mut rescaled = [a, 0.0, 0.0];
            FrictionPair::turn_spring(&mut rescaled, n);
            let kept = dot(rescaled, rescaled).sqrt();
            assert!((kept / a - 1.0).abs() < 1e-14, "{kept}");
        }
        // A spring in the plane is kept bit for bit; one along the normal
        // becomes zero.
        let mut flat = [1.0e-7, -2.0e-7, 0.0];
        project_spring(&mut flat, [0.0, 0.0, 1.0]);
        assert_eq!(flat, [1.0e-7, -2.0e-7, 0.0]);
        let mut upright = [0.0, 0.0, 1.0e-7];
        project_spring(&mut upright, [0.0, 0.0, 1.0]);
        assert_eq!(upright, [0.0; 3]);
    }

    /// The names round-trip, and nothing else is a rotation.
    #[test]
    fn names_round_trip() {
        for name in SPRING_ROTATION_NAMES {
            let r = SpringRotation::from_name(name).expect("a rotation");
            assert_eq!(r.name(), name);
        }
        assert_eq!(SpringRotation::default(), SpringRotation::Rescale);
        assert_eq!(SpringRotation::from_name("Project"), None);
        assert_eq!(SpringRotation::from_name(""), None);
    }
}
