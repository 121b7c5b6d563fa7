//! Normal contact laws, one small unit per law behind [`NormalContactLaw`]
//! (after the LAMMPS granular refactor: each law knows its force, whether it
//! needs the overlap rate, and its contact-time estimate; the model that owns
//! it does the rest).
//!
//! A law sees one particle pair: overlap `h ≥ 0` and overlap rate `ḣ`
//! (positive while the spheres approach). It knows nothing of gravity, the
//! integrator or the number of bodies, so dissipative laws (spring–dashpot,
//! Tsuji, Kuwabara–Kono, hysteretic) plug in without touching either.
//!
//! The damped laws are the physics crate's normal and damping sub-models
//! combined by one model object, [`Damped`], which applies the
//! no-attraction clamp (a type parameter, so the elastic laws' inner loop
//! is unchanged); [`crate::calibration::with_model`] picks the types.

mod damped;
mod physics_laws;
pub(crate) mod registered;

pub use damped::{BounceDamping, Damped};
pub use dembound_physics::contact::damping::{
    none::NoDamping, tsuji::Tsuji, viscoelastic::Viscoelastic, viscous::Viscous,
};
pub use dembound_physics::contact::normal::{
    hertz::Hertz, hertz_kn::HertzKn, hooke::Hooke, linear::Linear as LinearSpring, power::PowerLaw,
    walton_braun::WaltonBraun,
};
/// The closed-form e(ξ) relations and their inverses, and LIGGGHTS' β,
/// from the physics crate (where they are documented).
pub use dembound_physics::contact::{
    damping_ratio_for, free_restitution, restitution_to_damping_ratio, tsuji_beta,
};
pub use registered::Registered;

/// What a Walton–Braun contact remembers: the physics crate's one
/// per-pair history (largest overlap, unloading flag).
pub type WaltonBraunHistory = dembound_physics::contact::ContactHistory;

use crate::material::ContactPair;
use dembound_physics::contact::peak::Linearization;
use dembound_physics::contact::registry;
use serde::{Deserialize, Serialize};

/// A normal contact law for one pair of spheres.
pub trait NormalContactLaw: Send + Sync + std::fmt::Debug {
    /// What the law remembers of the current contact (the largest overlap
    /// so far, for a hysteretic law); `()` for history-free laws. A fresh
    /// `Default` value starts each contact.
    type History: Copy + Default + std::fmt::Debug;

    /// Short name used in reports (`"linear"`, `"hertz"`, ...).
    fn name(&self) -> &'static str;

    /// Normal force on the particle, N, repulsive positive, for overlap
    /// `overlap` (m) and overlap rate `overlap_rate` (m/s).
    ///
    /// For `overlap < 0` a law returns the smooth continuation of its
    /// in-contact force (the odd extension, F(−h) = −F(h) for elastic power
    /// laws). It is used only inside the one step that straddles the
    /// rebound, so that the step's polynomial is smooth there and locates
    /// h = 0 to the scheme's order; the physical force after separation is 0.
    fn force(&self, overlap: f64, overlap_rate: f64, history: &Self::History) -> f64;

    /// Updates the history after an accepted step ending at (`overlap`,
    /// `overlap_rate`).
    #[inline(always)]
    fn update_history(&self, _overlap: f64, _overlap_rate: f64, _history: &mut Self::History) {}

    /// The same law with every force multiplied by `factor` (the integration
    /// loop uses `scaled(1/m)` so that it reads accelerations directly,
    /// one multiplication fewer on the latency chain of every step).
    fn scaled(&self, factor: f64) -> Self
    where
        Self: Sized;

    /// True when the force depends on the overlap rate; the Gear corrector
    /// then uses 3/20 instead of 3/16 for its first coefficient.
    fn depends_on_rate(&self) -> bool {
        false
    }

    /// Contact duration (s) of a gravity-free impact at `impact_speed` (m/s)
    /// of a body of `mass` (kg): the scale of the time step Δt = η T_c.
    fn contact_time_estimate(&self, mass: f64, impact_speed: f64) -> f64;

    /// The loading and unloading stiffnesses [k₁, k₂] (N/m) of a law whose
    /// linear unloading branch may be much stiffer than the loading the
    /// contact-time estimate describes (Walton–Braun's k₂ = k₁/e²), which
    /// the step must resolve on its own; `None` for the other laws.
    fn loading_unloading(&self) -> Option<[f64; 2]> {
        None
    }

    /// For a damped law (a force that depends on the overlap rate): the
    /// contact linearised at the largest overlap of an impact at
    /// `impact_speed` (m/s) under relative gravity `gravity` (m/s²) of a
    /// body of `mass` (kg), ω² = (∂F/∂h)/m and β = (∂F/∂ḣ)/m
    /// ([`dembound_physics::contact::peak`]): what bounds Gear5's step
    /// ([`crate::bounce::check_damped_step`]). `None` for the other laws.
    fn damped_peak(&self, _mass: f64, _impact_speed: f64, _gravity: f64) -> Option<Linearization> {
        None
    }

    /// How smooth the overlap is in time at the contact onset; it decides
    /// how event stepping grades its steps there ([`crate::bounce::schedule`]).
    /// The default, [`Onset::NonSmooth`], is right for Hertz-like laws.
    fn onset(&self) -> Onset {
        Onset::NonSmooth
    }

    /// One-sided time derivatives (h''', h'''', h''''') of the overlap at the
    /// contact onset h = 0⁺, given ḣ and ḧ there and the mass. They seed the
    /// Gear Nordsieck vector so that no stale (free-flight) derivatives cross
    /// the force discontinuity. A law returns 0 for a derivative that is
    /// infinite or unknown at h = 0 (Hertz: h'''' ∝ h^(-1/2)).
    fn onset_derivatives(&self, _mass: f64, _overlap_rate: f64, _overlap_accel: f64) -> [f64; 3] {
        [0.0; 3]
    }

    /// True when the law forbids an attractive normal force, F = max(F, 0)
    /// (LAMMPS `limit_damping`, LIGGGHTS `limitForce`). The contact loop then
    /// locates where the force first returns to zero after the maximum
    /// overlap (the physical end of the contact, `t_force_zero`), using
    /// [`unclamped_force`](Self::unclamped_force) inside that one step, and
    /// restarts the integrator there with the clamped force. A compile-time
    /// constant, so that laws without the clamp pay nothing for it.
    const NON_ATTRACTIVE: bool = false;

    /// The force without the clamp at zero: the smooth continuation used
    /// inside the step that straddles the return of the force to zero (the
    /// same idea as the continuation to negative overlap in [`force`](Self::force)).
    #[inline(always)]
    fn unclamped_force(&self, overlap: f64, overlap_rate: f64, history: &Self::History) -> f64 {
        self.force(overlap, overlap_rate, history)
    }

    /// Called once per contact at the located maximum overlap `overlap`. A
    /// law whose force changes branch there (hysteresis: loading to
    /// unloading) records it in `history` and returns true; the contact loop
    /// then restarts the integrator at that point, seeded with
    /// [`branch_derivatives`](Self::branch_derivatives), so that no step
    /// straddles the kink in the force.
    fn at_max_overlap(&self, _overlap: f64, _history: &mut Self::History) -> bool {
        false
    }

    /// (h''', h'''', h''''') on the current branch of the law at `overlap`,
    /// given ḣ, ḧ and the mass; seeds the restart after
    /// [`at_max_overlap`](Self::at_max_overlap). 0 where unknown.
    fn branch_derivatives(
        &self,
        _mass: f64,
        _overlap: f64,
        _overlap_rate: f64,
        _overlap_accel: f64,
        _history: &Self::History,
    ) -> [f64; 3] {
        [0.0; 3]
    }
}

/// How smooth a law makes the overlap at the contact onset h = 0⁺.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Onset {
    /// Analytic in (h, ḣ) (integer exponents, linear dashpot, Walton–Braun's
    /// linear branches): a uniform step keeps the integrator's full order.
    Smooth,
    /// Bounded force but non-analytic (h^(3/2)): event stepping grades the
    /// mesh at both ends of the contact, τ ∝ j³.
    NonSmooth,
    /// A fractional power of h multiplies ḣ (Tsuji h^(1/4) ḣ, viscoelastic
    /// h^(1/2) ḣ): the force's time derivatives are infinite at h = 0⁺ and a
    /// uniform first step loses ~1e−3 at η = 1/50. Both stepping modes grade
    /// the steps toward the onset and toward the end of the contact
    /// ([`crate::bounce::schedule::SingularMesh`]).
    Singular,
}

/// Which contact law a scenario uses (TOML: `law = "linear"`, `"hertz"`,
/// `"walton-braun"`, `{ power = 1.25 }`, or the name of any other law of
/// the physics registry, `"hooke"`, `"hertz-kn"`, with its parameters as
/// `contact.` keys named by its row: `contact.stiffness`).
///
/// The paper's laws are variants of their own (the studies match on them);
/// every other registry law is [`ContactLawKind::Registry`], its row: a new
/// law of the registry is usable here with no edit to this crate.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ContactLawKind {
    /// α = 1: F = E_eff R_eff h (eq 4).
    Linear,
    /// α = 3/2: F = E_eff R_eff^(1/2) h^(3/2) (eq 4).
    Hertz,
    /// General exponent α ≥ 1: F = E_eff R_eff^(2−α) h^α (eq 4).
    Power(f64),
    /// Walton & Braun (1986) hysteretic linear law: loading k₁ h with
    /// k₁ = E_eff R_eff, unloading k₂ (h − h₀), k₂ = k₁/e² ([`WaltonBraun`]).
    WaltonBraun,
    /// Any other normal law of the physics registry (`hooke`, `hertz-kn`,
    /// …), by its row; its parameters are `contact.` keys of the row's
    /// parameter names ([`ContactModel::normal`]).
    Registry(&'static registry::NormalRow),
}

impl ContactLawKind {
    /// The law of registry name `name` (`"power"` with exponent `value`,
    /// the one law written `{ power = α }`); `None` for an unknown name.
    pub fn from_name(name: &str, value: Option<f64>) -> Option<Self> {
        let row = registry::normal_row(name)?;
        Some(match (row.name, value) {
            ("linear", None) => ContactLawKind::Linear,
            ("hertz", None) => ContactLawKind::Hertz,
            ("power", Some(alpha)) => ContactLawKind::Power(alpha),
            ("walton-braun", None) => ContactLawKind::WaltonBraun,
            (_, Some(_)) => return None,
            ("power", None) => return None,
            _ => ContactLawKind::Registry(row),
        })
    }

    /// The exponent α of F ∝ h^α on loading (eq 4): 1 for the linear
    /// family (Walton–Braun, `hooke`), 3/2 for the Hertzian one.
    pub fn exponent(&self) -> f64 {
        match *self {
            ContactLawKind::Linear | ContactLawKind::WaltonBraun => 1.0,
            ContactLawKind::Hertz => 1.5,
            ContactLawKind::Power(alpha) => alpha,
            ContactLawKind::Registry(row) => match row.family {
                registry::Family::Hertzian => 1.5,
                _ => 1.0,
            },
        }
    }

    /// The registry name (`"hertz"`), with the exponent for a power law
    /// (`"power 1.25"`).
    pub fn name(&self) -> String {
        match *self {
            ContactLawKind::Power(alpha) => format!("{} {alpha}", self.row().name),
            _ => self.row().name.into(),
        }
    }

    /// The law as the physics crate's registry configures it, each
    /// parameter other than the power law's exponent from `param(key)` (a
    /// `contact.` key of that name); Walton–Braun's restitution defaults
    /// to 1 (k₂ = k₁). `None` when a parameter is missing.
    pub fn to_physics(&self, param: impl Fn(&str) -> Option<f64>) -> Option<registry::NormalLaw> {
        Some(match *self {
            ContactLawKind::Linear => registry::NormalLaw::Linear,
            ContactLawKind::Hertz => registry::NormalLaw::Hertz,
            ContactLawKind::Power(exponent) => registry::NormalLaw::Power { exponent },
            ContactLawKind::WaltonBraun => registry::NormalLaw::WaltonBraun {
                restitution: param(registry::RESTITUTION.key).unwrap_or(1.0),
            },
            ContactLawKind::Registry(row) => {
                let values: Option<Vec<f64>> = row.params.iter().map(|p| param(p.key)).collect();
                return registry::NormalLaw::from_params(row.name, &values?);
            }
        })
    }

    /// Its row of the physics registry (name, parameters, family: the
    /// law–damping compatibility table).
    pub fn row(&self) -> &'static registry::NormalRow {
        match *self {
            ContactLawKind::Linear => registry::NormalLaw::Linear.row(),
            ContactLawKind::Hertz => registry::NormalLaw::Hertz.row(),
            ContactLawKind::Power(exponent) => registry::NormalLaw::Power { exponent }.row(),
            ContactLawKind::WaltonBraun => {
                registry::NormalLaw::WaltonBraun { restitution: 1.0 }.row()
            }
            ContactLawKind::Registry(row) => row,
        }
    }
}

/// Written as the registry name, or `{ power = α }`.
impl Serialize for ContactLawKind {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        use serde::ser::SerializeMap;
        match *self {
            ContactLawKind::Power(alpha) => {
                let mut map = serializer.serialize_map(Some(1))?;
                map.serialize_entry(self.row().name, &alpha)?;
                map.end()
            }
            _ => serializer.serialize_str(self.row().name),
        }
    }
}

/// Read as a registry name, or `{ power = α }`; an unknown name is refused
/// with the registry's list.
impl<'de> Deserialize<'de> for ContactLawKind {
    fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        #[derive(Deserialize)]
        #[serde(untagged)]
        enum Raw {
            Name(String),
            WithValue(std::collections::BTreeMap<String, f64>),
        }
        let unknown = |name: &str| {
            serde::de::Error::custom(format!(
                "\"{name}\" is not a law of the registry (allowed: one of {}; the power law as {{ power = α }})",
                registry::normal_names()
            ))
        };
        match Raw::deserialize(deserializer)? {
            Raw::Name(name) => ContactLawKind::from_name(&name, None).ok_or_else(|| unknown(&name)),
            Raw::WithValue(map) => {
                let mut entries = map.into_iter();
                match (entries.next(), entries.next()) {
                    (Some((name, value)), None) => ContactLawKind::from_name(&name, Some(value))
                        .ok_or_else(|| unknown(&format!("{{ {name} = {value} }}"))),
                    _ => Err(serde::de::Error::custom(
                        "contact.law: a law name, or one { power = α }",
                    )),
                }
            }
        }
    }
}

/// Calls `f` with the concrete elastic law `law` (the physics registry's,
/// with its parameters) for `pair`, so that the integration loop is
/// monomorphised for each law (no dynamic dispatch in the inner loop). The
/// laws with the bounce's own extras (`physics_laws`) run as themselves;
/// any other registry law through [`Registered`], the physics crate's
/// enum-dispatched per-pair model with the generic extras.
pub fn with_law<R>(
    law: &registry::NormalLaw,
    pair: &ContactPair,
    mass: f64,
    f: impl LawVisitor<Output = R>,
) -> R {
    use registry::NormalLaw as N;
    match *law {
        N::Linear => f.visit(pair.law::<LinearSpring>(&[])),
        N::Hertz => f.visit(pair.law::<Hertz>(&[])),
        N::Power { exponent } => f.visit(pair.law::<PowerLaw>(&[exponent])),
        N::WaltonBraun { restitution } => f.visit(pair.law::<WaltonBraun>(&[restitution])),
        N::Hooke { stiffness } => f.visit(pair.law::<Hooke>(&[stiffness])),
        _ => f.visit(Registered::<false>::elastic(law, pair, mass)),
    }
}

/// Which dissipation is added to the elastic law (TOML `contact.damping`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum DampingKind {
    /// Elastic (or the law's own hysteresis: Walton–Braun).
    #[default]
    None,
    /// Linear spring–dashpot, with `law = "linear"` ([`Damped`] with [`Viscous`]).
    Viscous,
    /// Hertz with Tsuji-type damping (LIGGGHTS/EDEM), with `law = "hertz"` ([`Damped`] with [`Tsuji`]).
    Tsuji,
    /// Hertz with Kuwabara–Kono/Brilliantov viscoelastic damping, with
    /// `law = "hertz"` ([`Damped`] with [`Viscoelastic`]).
    Viscoelastic,
}

impl DampingKind {
    /// The registry name.
    pub fn name(&self) -> &'static str {
        self.row().name
    }

    /// The damping as the physics crate's registry names it.
    pub fn to_physics(&self) -> registry::DampingKind {
        match self {
            DampingKind::None => registry::DampingKind::None,
            DampingKind::Viscous => registry::DampingKind::Viscous,
            DampingKind::Tsuji => registry::DampingKind::Tsuji,
            DampingKind::Viscoelastic => registry::DampingKind::Viscoelastic,
        }
    }

    /// Its row of the physics registry.
    pub fn row(&self) -> &'static registry::DampingRow {
        self.to_physics().row()
    }

    /// Whether it combines with `law`: the registry's one compatibility
    /// table ([`registry::DampingRow::combines`]).
    pub fn combines_with(&self, law: ContactLawKind) -> bool {
        self.row().combines(law.row())
    }
}

/// How a target restitution becomes a damping coefficient (TOML
/// `contact.calibration`, `"exact"` or `"formula"`; the physics crate's
/// type). In the bounce study, `Exact` inverts the closed form of
/// [`free_restitution`] by root finding for the spring–dashpot and Tsuji
/// and runs the adaptive reference integration for the viscoelastic law,
/// at the scenario's first impact speed; `Formula` is ξ = −β =
/// −ln e/√(ln² e + π²) for the spring–dashpot and Tsuji (a clamped contact
/// then rebounds faster, 0.550 for a target of 0.5) and, for the
/// viscoelastic law, which has no closed form, A solved for the unclamped
/// law.
pub use dembound_physics::contact::Calibration;

/// How strong the dissipation is: a target restitution or the damping's
/// raw coefficient (the physics crate's type).
pub use dembound_physics::contact::Dissipation;

/// The registry laws' parameters given by key (the physics crate's type).
pub use dembound_physics::contact::LawParams;

/// A complete choice of normal contact model.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactModel {
    pub law: ContactLawKind,
    pub damping: DampingKind,
    /// Required by the dissipative models (and Walton–Braun); ignored otherwise.
    pub dissipation: Option<Dissipation>,
    /// Allow an attractive (negative) normal force; false: F = max(F, 0).
    pub attractive: bool,
    /// How a [`Dissipation::Restitution`] becomes the law's coefficient.
    pub calibration: Calibration,
    /// The registry laws' parameters given by key (`contact.stiffness`:
    /// k_n of `hooke` in N/m, of `hertz-kn` in Pa).
    pub params: LawParams,
}

impl ContactModel {
    /// The elastic model of `law`.
    pub fn elastic(law: ContactLawKind) -> Self {
        ContactModel {
            law,
            damping: DampingKind::None,
            dissipation: None,
            attractive: false,
            calibration: Calibration::Exact,
            params: LawParams::default(),
        }
    }

    /// The value of the law parameter `key` of the registry (the
    /// restitution from the dissipation, any other from [`Self::params`]),
    /// if given.
    pub fn param(&self, key: &str) -> Option<f64> {
        if key == registry::RESTITUTION.key {
            match self.dissipation {
                Some(Dissipation::Restitution(e)) => Some(e),
                _ => None,
            }
        } else {
            self.params.get(key)
        }
    }

    /// The normal law as the physics registry configures it, with its
    /// parameters ([`ContactLawKind::to_physics`]); `None` when one is missing.
    pub fn normal(&self) -> Option<registry::NormalLaw> {
        self.law.to_physics(|key| self.param(key))
    }
}

/// A generic computation over a concrete law type (see [`with_law`]).
pub trait LawVisitor {
    type Output;
    fn visit<L: NormalContactLaw>(self, law: L) -> Self::Output;
}

/// Factor on the elastic contact time of a damped Hertz law with damping
/// ratio ξ, from the physics crate (where it is documented).
pub use dembound_physics::contact::heavy_damping_scale;
