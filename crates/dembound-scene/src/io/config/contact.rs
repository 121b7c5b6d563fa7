//! `[contact]`: the contact law, damping and friction keys, read through
//! the physics crate's registry, and their checks.

use super::checks::{check, invalid};
use super::{SceneError, SceneFile};
use crate::limits;
use dembound_physics::contact::tangential::{tangential_names, SpringRotation, TangentialKind};
use dembound_physics::contact::{ContactModel, ContactSpec, LawParams, TorqueArm};
use serde::{Deserialize, Serialize};

/// `[contact]`: the keys of `dembound run`'s `[contact]`, checked against
/// the physics crate's registry ([`ContactSection::model`]). Unknown keys
/// are refused by [`LawParams`], which takes the rest of the table (a
/// flattened field cannot be combined with `deny_unknown_fields`).
/// Written by hand ([`Serialize`] below) as the struct it was before the
/// parameters came from the registry, so that checkpoints keep their bytes.
#[derive(Debug, Clone, PartialEq, Deserialize)]
pub struct ContactSection {
    /// `"linear"`, `"hertz"`, `"walton-braun"`, … or `{ power = α }`
    /// (default `"hertz"`, also when `[contact]` gives other keys only).
    #[serde(default = "hertz")]
    pub law: Law,
    /// `"none"`, `"viscous"`, `"tsuji"`, `"viscoelastic"`.
    #[serde(default = "no_damping")]
    pub damping: String,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub restitution: Option<f64>,
    /// `"exact"` or `"formula"`.
    #[serde(default = "exact")]
    pub calibration: String,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub damping_coefficient: Option<f64>,
    #[serde(default)]
    pub attractive: bool,
    /// The normal laws' parameters by their registry keys
    /// (`contact.stiffness`: k_n of `"hooke"` in N/m, of `"hertz-kn"` in
    /// Pa; `contact.exponent`: α of `"power"`), as `dembound run`'s.
    #[serde(flatten)]
    pub params: LawParams,
    /// Coulomb friction coefficient μ ≥ 0 of every surface (issue 13):
    /// with friction (here, on a material or on a wall) the spheres rotate
    /// and each contact carries a tangential spring.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub friction: Option<f64>,
    /// The tangential spring: `"mindlin"` (default; Hertz–Mindlin no-slip,
    /// the force −k_t(h) δ of the stored displacement), `"mindlin_force"`
    /// (the same k_t on a stored force, F_s += −k_t(h) v_t Δt: LAMMPS
    /// `mindlin/force`, Yade's law) or `"linear"` (Cundall–Strack, k_t =
    /// 2/7 E_eff R_eff).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tangential: Option<String>,
    /// Rolling friction μ_r ≥ 0: an elastic–plastic rolling spring whose
    /// torque is limited to μ_r R_eff |F_n| (`contact::rolling`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rolling_friction: Option<f64>,
    /// Whether a sticking contact has a tangential dashpot (default true:
    /// η_t with the normal contact's damping ratio); false: the spring
    /// alone (LIGGGHTS `tangential_damping off`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tangential_damping: Option<bool>,
    /// The lever arm of the tangential force's torque: `"radius"` (default:
    /// R), `"contact_point"` (LAMMPS's R − δ/2 for sphere pairs, R
    /// against walls), `"overlap_middle"` (Yade's R − δ/2 on every
    /// contact) or `"half_overlap"` (LIGGGHTS's R − δ/2 in the torque and
    /// the slip of every contact; `dembound_physics::contact::TorqueArm`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub torque_arm: Option<String>,
    /// How the tangential spring follows a turning normal: `"rescale"`
    /// (default: projected onto the new tangent plane and scaled back to
    /// its length, LAMMPS's) or `"project"` (projected only, LIGGGHTS
    /// 3.8's; `dembound_physics::contact::tangential::SpringRotation`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub spring_rotation: Option<String>,
}

/// A struct of the fields in declaration order, each optional one only
/// when given, the law parameters where `contact.stiffness` stood (after
/// `attractive`): what `#[derive(Serialize)]` wrote without the flattened
/// map (a flattened field makes it a map of unknown length, other bytes in
/// a checkpoint).
impl Serialize for ContactSection {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        use serde::ser::SerializeStruct;
        let given = |o: bool| o as usize;
        let len = 4
            + given(self.restitution.is_some())
            + given(self.damping_coefficient.is_some())
            + self.params.iter().count()
            + given(self.friction.is_some())
            + given(self.tangential.is_some())
            + given(self.rolling_friction.is_some())
            + given(self.tangential_damping.is_some())
            + given(self.torque_arm.is_some())
            + given(self.spring_rotation.is_some());
        let mut s = serializer.serialize_struct("ContactSection", len)?;
        s.serialize_field("law", &self.law)?;
        s.serialize_field("damping", &self.damping)?;
        if let Some(e) = &self.restitution {
            s.serialize_field("restitution", e)?;
        }
        s.serialize_field("calibration", &self.calibration)?;
        if let Some(c) = &self.damping_coefficient {
            s.serialize_field("damping_coefficient", c)?;
        }
        s.serialize_field("attractive", &self.attractive)?;
        for (key, value) in self.params.iter() {
            s.serialize_field(key, &value)?;
        }
        if let Some(mu) = &self.friction {
            s.serialize_field("friction", mu)?;
        }
        if let Some(t) = &self.tangential {
            s.serialize_field("tangential", t)?;
        }
        if let Some(mu_r) = &self.rolling_friction {
            s.serialize_field("rolling_friction", mu_r)?;
        }
        if let Some(on) = &self.tangential_damping {
            s.serialize_field("tangential_damping", on)?;
        }
        if let Some(arm) = &self.torque_arm {
            s.serialize_field("torque_arm", arm)?;
        }
        if let Some(rotation) = &self.spring_rotation {
            s.serialize_field("spring_rotation", rotation)?;
        }
        s.end()
    }
}

fn hertz() -> Law {
    Law::Name("hertz".into())
}

fn no_damping() -> String {
    "none".into()
}

fn exact() -> String {
    "exact".into()
}

impl Default for ContactSection {
    fn default() -> Self {
        Self {
            law: hertz(),
            damping: no_damping(),
            restitution: None,
            calibration: exact(),
            damping_coefficient: None,
            attractive: false,
            params: LawParams::default(),
            friction: None,
            tangential: None,
            rolling_friction: None,
            tangential_damping: None,
            torque_arm: None,
            spring_rotation: None,
        }
    }
}

/// `contact.law`: a registry name, or `{ name = value }` (the law's first
/// parameter: `{ power = 1.25 }`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum Law {
    Name(String),
    WithValue(std::collections::BTreeMap<String, f64>),
}

impl ContactSection {
    /// The contact model, through the physics crate's registry;
    /// `reference_speed` (m/s) is the impact speed of a speed-dependent
    /// calibration (the viscoelastic law's).
    pub fn model(&self, reference_speed: Option<f64>) -> Result<ContactModel, SceneError> {
        let mut spec = match &self.law {
            Law::Name(name) => ContactSpec::law(name),
            Law::WithValue(map) => {
                let mut entries = map.iter();
                match (entries.next(), entries.next()) {
                    (Some((name, value)), None) => ContactSpec::law_with_value(name, *value),
                    _ => {
                        return Err(invalid(
                            "contact.law",
                            format!("{map:?}"),
                            "a law name, or one `{ name = value }` such as { power = 1.25 }",
                        ))
                    }
                }
            }
        };
        spec.law_params
            .extend(self.params.iter().map(|(k, v)| (k.to_string(), v)));
        spec.damping = self.damping.clone();
        spec.restitution = self.restitution;
        spec.damping_coefficient = self.damping_coefficient;
        spec.calibration = self.calibration.clone();
        spec.attractive = self.attractive;
        spec.reference_speed = reference_speed;
        // The registry names a law's parameter by its own key (`contact.
        // exponent`), as a scene may write it; or the scene wrote it
        // `law = { power = α }`.
        let key = |k: &str| -> String {
            let given = k
                .strip_prefix("contact.")
                .is_some_and(|p| self.params.get(p).is_some());
            match &self.law {
                Law::WithValue(map) if !given && !SCENE_CONTACT_KEYS.contains(&k) => map
                    .keys()
                    .next()
                    .map_or(k.to_string(), |name| format!("contact.law.{name}")),
                _ => k.to_string(),
            }
        };
        let model = ContactModel::from_spec(&spec)
            .map_err(|e| invalid(&key(&e.key), e.value, &e.allowed))?;
        model
            .validate()
            .map_err(|e| invalid(&key(&e.key), e.value, &e.allowed))?;
        let walton_braun = matches!(&self.law, Law::Name(n) if n == "walton-braun");
        check(
            !(walton_braun && self.attractive),
            "contact.attractive",
            self.attractive,
            "false for law = \"walton-braun\" (the law has no tensile branch; `dembound run` \
             refuses it likewise)",
        )?;
        Ok(model)
    }
}

/// The `[contact]` keys a registry error may name as they are.
const SCENE_CONTACT_KEYS: [&str; 6] = [
    "contact.law",
    "contact.damping",
    "contact.restitution",
    "contact.calibration",
    "contact.damping_coefficient",
    "contact.attractive",
];

impl SceneFile {
    pub(super) fn validate_contact(&self) -> Result<(), SceneError> {
        // The impact speed matters only to the viscoelastic calibration,
        // solved again at resolution with the scene's own speed.
        self.contact.model(Some(1.0))?;
        self.validate_friction()
    }

    /// The friction keys (issue 13): each coefficient finite and ≥ 0, the
    /// tangential model a registry name (with Verlet or Gear5).
    fn validate_friction(&self) -> Result<(), SceneError> {
        let coefficient = |key: &str, v: Option<f64>, symbol: &str| -> Result<(), SceneError> {
            let range = if symbol == "μ" {
                limits::FRICTION
            } else {
                limits::ROLLING_FRICTION
            };
            match v {
                Some(x) => check(
                    limits::within(x, range),
                    key,
                    x,
                    &format!("{} ({symbol}, dimensionless)", limits::describe(range, "")),
                ),
                None => Ok(()),
            }
        };
        let c = &self.contact;
        coefficient("contact.friction", c.friction, "μ")?;
        coefficient("contact.rolling_friction", c.rolling_friction, "μ_r")?;
        if let Some(name) = &c.tangential {
            check(
                TangentialKind::from_name(name).is_some(),
                "contact.tangential",
                format!("{name:?}"),
                &format!("one of {}", tangential_names()),
            )?;
        }
        if let Some(on) = c.tangential_damping {
            check(
                self.has_friction(),
                "contact.tangential_damping",
                on,
                "given only with friction (contact.friction or a surface's friction): the \
                 dashpot acts on the tangential spring",
            )?;
        }
        if let Some(name) = &c.torque_arm {
            check(
                TorqueArm::from_name(name).is_some(),
                "contact.torque_arm",
                format!("{name:?}"),
                "\"radius\" (the default: the tangential torque at R), \"contact_point\" \
                 (LAMMPS's R − δ/2 for sphere pairs, R against walls), \"overlap_middle\" \
                 (Yade's R − δ/2 on every contact, in the slip against walls too) or \
                 \"half_overlap\" (LIGGGHTS's R − δ/2 on every contact, in the torque and the slip)",
            )?;
            check(
                self.has_friction(),
                "contact.torque_arm",
                format!("{name:?}"),
                "given only with friction (contact.friction or a surface's friction): the arm \
                 is the tangential force's",
            )?;
        }
        if let Some(name) = &c.spring_rotation {
            check(
                SpringRotation::from_name(name).is_some(),
                "contact.spring_rotation",
                format!("{name:?}"),
                "\"rescale\" (the default: the tangential spring projected onto the new tangent \
                 plane and scaled back to its length, LAMMPS's) or \"project\" (projected only, \
                 LIGGGHTS 3.8's)",
            )?;
            check(
                self.has_friction(),
                "contact.spring_rotation",
                format!("{name:?}"),
                "given only with friction (contact.friction or a surface's friction): the \
                 rotation is the tangential spring's",
            )?;
        }
        for (i, m) in self.materials.iter().enumerate() {
            coefficient(&format!("material[{i}].friction"), m.friction, "μ")?;
            coefficient(
                &format!("material[{i}].rolling_friction"),
                m.rolling_friction,
                "μ_r",
            )?;
        }
        for (i, w) in self.walls.iter().enumerate() {
            coefficient(&format!("wall[{i}].friction"), w.friction, "μ")?;
            coefficient(
                &format!("wall[{i}].rolling_friction"),
                w.rolling_friction,
                "μ_r",
            )?;
        }
        Ok(())
    }

    /// Whether any friction key is given (the scene then rotates its
    /// spheres and carries tangential springs).
    pub fn has_friction(&self) -> bool {
        let c = &self.contact;
        c.friction.is_some()
            || c.tangential.is_some()
            || c.rolling_friction.is_some()
            || self
                .materials
                .iter()
                .any(|m| m.friction.is_some() || m.rolling_friction.is_some())
            || self
                .walls
                .iter()
                .any(|w| w.friction.is_some() || w.rolling_friction.is_some())
    }
}
