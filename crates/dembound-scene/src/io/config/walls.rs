//! `[[wall]]`: exactly one wall type's key (`walls::registry`: the
//! section, each type's entry and its checks are the types'), and the
//! material check the surface types share.

use super::checks::check;
use super::{SceneError, SceneFile, RIGID};
pub use crate::walls::boundary_particles::{BoundaryParticlesConfig, TilingName};
pub use crate::walls::cylinder::CylinderConfig;
pub use crate::walls::plane::PlaneConfig;
pub use crate::walls::registry::{listing, WallSection, KEYS};

impl SceneFile {
    pub(super) fn validate_wall(&self, i: usize, w: &WallSection) -> Result<(), SceneError> {
        let key = format!("wall[{i}]");
        let given = w.given();
        check(
            given.len() == 1,
            &key,
            if given.is_empty() {
                "neither".to_string()
            } else {
                given.join(" and ")
            },
            &format!("exactly one of {}", listing(KEYS.to_vec()).join(", ")),
        )?;
        w.validate_type(self, &key)?;
        if w.motion.is_some() || w.oscillation.is_some() {
            let kind = w.key().unwrap_or_default();
            let moved = if w.motion.is_some() {
                "motion"
            } else {
                "oscillation"
            };
            // A wall of boundary particles moves as one rigid body
            // (`pipeline::moving_groups`), not across periodic faces.
            if let Some(a) = self.domain.periodic.iter().position(|&p| p) {
                check(
                    !crate::walls::registry::is_particles_key(kind),
                    &format!("{key}.{moved}"),
                    format!("given for a `{kind}` wall in a domain periodic along axis {a}"),
                    "a moving wall of boundary particles in a domain with no periodic axis \
                     (its spheres are not carried across periodic faces)",
                )?;
            }
        }
        crate::walls::motion::validate(&key, w.motion.as_ref(), w.oscillation.as_ref())?;
        if let Some(servo) = &w.servo {
            let kind = w.key().unwrap_or_default();
            check(
                !crate::walls::registry::is_particles_key(kind),
                &format!("{key}.servo"),
                format!("given for a `{kind}` wall"),
                &format!(
                    "a {} (walls of boundary particles have no servo)",
                    crate::walls::registry::surface_kinds_or()
                ),
            )?;
            let moved = if w.motion.is_some() {
                Some("motion")
            } else if w.oscillation.is_some() {
                Some("oscillation")
            } else {
                None
            };
            if let Some(moved) = moved {
                return Err(super::checks::invalid(
                    &format!("{key}.servo"),
                    format!("given with `{key}.{moved}`"),
                    "a servo or a prescribed motion, not both: the servo sets the wall's velocity",
                ));
            }
            crate::walls::servo::validate(&key, servo)?;
        }
        if let Some(window) = &w.active {
            let kind = w.key().unwrap_or_default();
            crate::walls::gate::validate(&key, window, kind, w.servo.is_some())?;
        }
        Ok(())
    }
}

/// The material of a surface wall `key` (`wall[K]`): a `[[material]]`
/// name or `"rigid"`.
pub(crate) fn surface_material(
    file: &SceneFile,
    key: &str,
    material: &str,
) -> Result<(), SceneError> {
    check(
        file.material_known(material) || material == RIGID,
        &format!("{key}.material"),
        format!("{material:?}"),
        &format!(
            "a [[material]] name ({}) or \"rigid\"",
            file.material_names()
        ),
    )
}
