//! Damping and friction of a scene as LIGGGHTS 3.8 `model hertz
//! tangential history` settings (docs/export-liggghts.md, "Damping and
//! friction"), or a refusal naming the key where LIGGGHTS would compute
//! another law.
//!
//! What is the same formula in both codes (LIGGGHTS `normal_model_hertz.h`,
//! `tangential_model_history.h`, `surface_model_default.h`,
//! `global_properties.cpp`; dembound `contact::damping::tsuji`,
//! `contact::tangential`):
//! - Damping. LIGGGHTS: F_d = −2 √(5/6) β √(S_n m*) v_n, S_n = 2 Y* √(R* δ),
//!   β = ln e/√(ln² e + π²) from `coefficientRestitution` e. dembound's
//!   Tsuji: F_d = γ h^(1/4) ḣ with γ = √5 ξ √(k m*), k = E_eff √R_eff =
//!   (4/3) Y* √R*: then γ h^(1/4) = 2 √(5/6) ξ √(S_n m*), the same force for
//!   ξ = −β. dembound's ξ is −β(e) itself with `calibration = "formula"` or
//!   with `attractive = true` (`Tsuji::new` takes the formula branch), so e
//!   is written as it is; with the default exact calibration of the
//!   clamped law ξ is the clamped oscillator's ratio
//!   ([`damping_ratio_for`]) and the deck gets the e′ whose β is −ξ,
//!   e′ = exp(−π ξ/√(1 − ξ²)) (the inverse of β(e)). The clamp
//!   F_n = max(F_n, 0) of a non-attractive model is LIGGGHTS's
//!   `limitForce on`.
//! - Tangential spring: k_t = 8 G* √(R* δ) in both (`St = 8 Geff sqrtval`),
//!   G* = 1/(2(2 − ν_i)(1 + ν_i)/Y_i + 2(2 − ν_j)(1 + ν_j)/Y_j) in both
//!   (`createGeff`), force −k_t δ on the stored displacement.
//! - Coulomb: sliding when k_t |δ| > μ |F_n| (F_n after the clamp); the
//!   spring cut back to μ |F_n|/k_t along itself, the force μ |F_n|, no
//!   dashpot: the same in both.
//! - Tangential dashpot while sticking: LIGGGHTS γ_t = −2 √(5/6) β
//!   √(S_t m*); dembound η_t = η_n √(k_t/S_n), the same number (but see
//!   the refusal below: the two cap it differently).
//! - μ per type pair: dembound's √(μ_a μ_b) written per pair.
//!
//! What differs, and is exported anyway (the deck's header says so):
//! 1. The lever arm, unless `contact.torque_arm = "half_overlap"`.
//!    LIGGGHTS takes R − δ/2 from each centre, in the slip velocity and in
//!    the torque of F_t, of sphere pairs and walls alike; dembound by
//!    default the undeformed R (`contact::model`), and its other arms
//!    R − δ/2 in part (`contact::torque_arm`). Relative size δ/(2R) of the
//!    spin terms. In gross sliding along a fixed direction F_t is μ |F_n|
//!    in both and the trajectory is the same; only the spin change
//!    differs, by ∫ (δ/2) μ F_n dt/I. Under `"half_overlap"` the arm is
//!    LIGGGHTS's (`TorqueArm::HalfOverlap`) and the header says so.
//! 2. The spring's rotation, unless `contact.spring_rotation = "project"`:
//!    LIGGGHTS projects δ onto the new tangent plane, dembound by default
//!    also restores its length (second order in the turn per step; none on
//!    a flat wall). Under `"project"` the rotation is LIGGGHTS's
//!    (`tangential::rotation`) and the header says so.
//!
//! Exported with `tangential_damping off`: damping together with friction
//! under `contact.tangential_damping = false`. Neither code then has a
//! tangential dashpot: a sticking contact's force is the spring's, −k_t δ,
//! within μ |F_n| by the sliding test, so the cap question below does not
//! arise and the law is the same (LIGGGHTS's `normal_model_hertz.h` sets
//! γ_t = 0 under the setting; the normal damping is untouched).
//!
//! Hooke (`contact.law = { hooke = k }`, undamped): `model hooke/stiffness`
//! with `kn` = k and zero `gamman_abs`/`gammat_abs`; with friction the
//! linear tangential spring's k_t = (2/7) E_eff R_eff as `kt` per type
//! pair (every wall on a type of its own), and rolling friction as
//! `rolling_friction epsd2` where LIGGGHTS's k_r = k_t R*² is dembound's
//! 2.25 k μ_r² R_eff² ([`hooke_springs`] checks it pair by pair). Kept:
//! the rolling history is not turned with the normal in LIGGGHTS, and a
//! wall's rolling spring is driven by ω (R − δ/2)/(R − δ) there
//! (`surface_model_default.h`).
//!
//! Refused: damping together with friction and the dashpot on (dembound's
//! default). dembound caps spring +
//! dashpot at μ |F_n| while sticking; LIGGGHTS does not cap its sticking
//! branch, and near a contact's onset the dashpot γ_t v_t (∝ δ^(1/4), like
//! the normal dashpot that sets μ |F_n| there) exceeds the limit by the
//! ratio of the slip to the approach speed over μ: measured on the test's
//! oblique impact (v_t/v_n = 3, μ = 0.3, e = 0.5) LIGGGHTS's sphere leaves
//! with 12 % more spin and 6 % of the throw speed apart. LIGGGHTS's
//! `tangential_damping off` removes its dashpot, dembound's
//! `contact.tangential_damping = false` its own (above); with the dashpots
//! on no setting of either code gives the other's law. Also refused: rolling friction (LIGGGHTS 3.8's `epsd2` takes k_r = k_t R*²,
//! no dashpot, no rotation of its history; dembound's epsd2 k_r = 2.25
//! (F_n/h) μ_r² R_eff² with a dashpot: a different law, and `cdt` is a
//! constant torque), the linear tangential spring (LIGGGHTS's `hertz`
//! gives k_t = 8 G* √(R* δ) only), damping models other than Tsuji and a
//! damping given as a raw coefficient (γ/√(5 k m*) then depends on the
//! pair's mass, LIGGGHTS takes one e per type pair).

use crate::{num, Error, Result};
use dembound_physics::contact::calibration::damping_ratio_for;
use dembound_physics::contact::tangential::linear::LinearTangential;
use dembound_physics::contact::tangential::{
    mix_friction, SpringRotation, TangentialKind, TangentialSetup, TangentialSubModel,
};
use dembound_physics::contact::{Calibration, DampingKind, Dissipation, NormalLaw, TorqueArm};
use dembound_physics::material::{effective_modulus, effective_radius, PairProperties};
use dembound_scene::setup::{SceneSetup, WallSetup};

/// The contact settings of a LIGGGHTS scene deck.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct ContactPlan {
    /// `coefficientRestitution` of every type pair.
    pub restitution: f64,
    /// `limitForce on` (dembound's clamp F_n ≥ 0 with damping).
    pub limit_force: bool,
    /// With friction: μ of each atom type (0-based), `tangential history`.
    pub friction: Option<Vec<f64>>,
    /// `tangential_damping off`: damping with friction, exported only under
    /// dembound's `contact.tangential_damping = false` (no dashpot in either
    /// code).
    pub tangential_damping_off: bool,
    /// Atom type (0-based) of each wall in file order (None: not a plane
    /// or mesh); a wall whose μ differs from its material's gets a type of
    /// its own after the materials' (its material's E and ν).
    pub wall_types: Vec<Option<usize>>,
    /// The material of each type (materials first, then the walls' own).
    pub type_materials: Vec<usize>,
    /// Header lines of the deck saying what was mapped.
    pub notes: Vec<String>,
    /// `contact.law = { hooke = k }`: `model hooke/stiffness` with k_n = k
    /// for every type pair (None: `model hertz`).
    pub hooke: Option<f64>,
    /// Under Hooke with friction: k_t (N/m) of each type pair, row-major
    /// (dembound's linear k_t = (2/7) E_eff R_eff; 0 for pairs that never
    /// meet).
    pub tangential_stiffness: Option<Vec<f64>>,
    /// Rolling friction: μ_r of each atom type (`rolling_friction epsd2`).
    pub rolling: Option<Vec<f64>>,
}

impl ContactPlan {
    /// `tangential history` with friction, else `no_history`.
    pub fn tangential(&self) -> &'static str {
        if self.friction.is_some() {
            "history"
        } else {
            "no_history"
        }
    }

    /// The model words of `pair_style gran` and `fix wall/gran`.
    pub fn model_words(&self) -> String {
        let normal = if self.hooke.is_some() {
            "hooke/stiffness"
        } else {
            "hertz"
        };
        let rolling = if self.rolling.is_some() {
            " rolling_friction epsd2"
        } else {
            ""
        };
        format!("model {normal} tangential {}{rolling}", self.tangential())
    }

    /// The model settings, after the models in `pair_style gran` and at the
    /// end of `fix wall/gran` (which reads its own keywords first): empty or
    /// ` limitForce on`, and ` tangential_damping off` when damping and
    /// friction are exported together.
    pub fn settings(&self) -> String {
        let mut s = String::new();
        if self.hooke.is_some() {
            // γ_n and γ_t given absolutely as 0 (`gamman_abs`, `gammat_abs`):
            // undamped, as the Hooke scenes exported.
            s.push_str(" absolute_damping on");
        }
        if self.tangential_damping_off {
            s.push_str(" tangential_damping off");
        }
        if self.limit_force {
            s.push_str(" limitForce on");
        }
        s
    }

    /// Number of atom types.
    pub fn n_types(&self) -> usize {
        self.type_materials.len()
    }

    /// `coefficientRollingFriction peratomtypepair` values, row-major
    /// (μ_r mixed as μ, √(μ_a μ_b)).
    pub fn rolling_pairs(&self) -> Vec<String> {
        let n = self.n_types();
        let mu = self.rolling.clone().unwrap_or_else(|| vec![0.0; n]);
        let mut v = Vec::with_capacity(n * n);
        for i in 0..n {
            for j in 0..n {
                v.push(num(mix_friction(mu[i], mu[j])));
            }
        }
        v
    }

    /// `coefficientFriction peratomtypepair` values, row-major.
    pub fn friction_pairs(&self) -> Vec<String> {
        let n = self.n_types();
        let mut v = Vec::with_capacity(n * n);
        for i in 0..n {
            for j in 0..n {
                v.push(num(match &self.friction {
                    Some(mu) => mix_friction(mu[i], mu[j]),
                    None => 0.0,
                }));
            }
        }
        v
    }
}

/// The note `dembound export liggghts` prints for a frictional scene
/// (its deck has `tangential history`) under an arm other than
/// `contact.torque_arm = "half_overlap"`: LIGGGHTS 3.8 takes R − δ/2 in
/// the slip and the torque of every contact (`surface_model_default.h`,
/// `tangential_model_history.h`), so the two runs part at the first
/// frictional contact. `None` without friction, under `"half_overlap"` or
/// for a scene the export refuses.
pub fn torque_arm_note(setup: &SceneSetup) -> Option<String> {
    let f = setup.friction.as_ref()?;
    if f.torque_arm == TorqueArm::HalfOverlap {
        return None;
    }
    plan(setup).ok()?.friction?;
    Some(format!(
        "note: contact.torque_arm = \"{}\": LIGGGHTS takes the lever arm R − δ/2 (δ the overlap) \
         in the slip velocity and the tangential torque of every contact, so the two runs part at \
         the first frictional contact; set contact.torque_arm = \"half_overlap\"{} to run \
         LIGGGHTS's {} in dembound",
        f.torque_arm.name(),
        if f.spring_rotation == SpringRotation::Project {
            ""
        } else {
            " and contact.spring_rotation = \"project\""
        },
        if f.spring_rotation == SpringRotation::Project {
            "arm"
        } else {
            "arm and spring rotation"
        }
    ))
}

/// The note `dembound export liggghts` prints for a frictional scene
/// under `contact.torque_arm = "half_overlap"` that keeps the default
/// `contact.spring_rotation = "rescale"`: LIGGGHTS 3.8 projects the
/// tangential spring onto a contact's new tangent plane without restoring
/// its length (`tangential_model_history.h`), so sphere pairs whose normal
/// turns part by the spring's lost length (2e-8 of the state in
/// tests/export_liggghts_torque_arm.rs), then by chaos. Under the other
/// arms [`torque_arm_note`] names both keys. `None` without friction,
/// under `"project"`, under another arm or for a scene the export
/// refuses.
pub fn spring_rotation_note(setup: &SceneSetup) -> Option<String> {
    let f = setup.friction.as_ref()?;
    if f.spring_rotation == SpringRotation::Project || f.torque_arm != TorqueArm::HalfOverlap {
        return None;
    }
    plan(setup).ok()?.friction?;
    Some(
        "note: contact.spring_rotation = \"rescale\": dembound turns the tangential spring into a \
         contact's new tangent plane keeping its length, LIGGGHTS projects it (shorter by θ²/2 a \
         step, θ the turn of the normal), so the two runs part where a sphere pair's normal turns \
         under a loaded spring; set contact.spring_rotation = \"project\" to run LIGGGHTS's \
         rotation in dembound"
            .to_string(),
    )
}

/// e whose β = ln e/√(ln² e + π²) is −ξ (0 ≤ ξ < 1).
pub(crate) fn restitution_of_ratio(xi: f64) -> f64 {
    (-std::f64::consts::PI * xi / (1.0 - xi * xi).sqrt()).exp()
}

/// The damping and friction of `setup` as LIGGGHTS settings, or a refusal
/// naming the key.
pub(crate) fn plan(setup: &SceneSetup) -> Result<ContactPlan> {
    let refuse = |s: String| Err(Error::Export(s));
    let model = &setup.contact;
    let mut notes = Vec::new();
    let hooke = match model.normal {
        NormalLaw::Hertz => None,
        NormalLaw::Hooke { stiffness } => Some(stiffness),
        other => {
            return refuse(format!(
                "contact.law = \"{}\" is not exported to LIGGGHTS for scenes (exported: hertz, as \
                 LIGGGHTS's `model hertz`, and {{ hooke = k }}, as `model hooke/stiffness`)",
                other.row().name
            ))
        }
    };
    if hooke.is_some() && model.damping.kind() != DampingKind::None {
        return refuse(format!(
            "contact.damping = \"{}\" with contact.law = {{ hooke = k }} is not exported to \
             LIGGGHTS: the scene export writes Hooke undamped only (LIGGGHTS's hooke/stiffness \
             takes one gamma_n per type pair, dembound's viscous c = 2 xi sqrt(k m*) changes \
             with the pair's mass); set contact.damping = \"none\"",
            model.damping.kind().row().name
        ));
    }
    let (restitution, limit_force) = match (model.damping.kind(), model.damping.dissipation()) {
        (DampingKind::None, _) | (_, None) => (1.0, false),
        (DampingKind::Tsuji, Some(Dissipation::Restitution(e))) => {
            let exact_clamped = model.calibration == Calibration::Exact && !model.attractive;
            let written = if exact_clamped {
                let xi = damping_ratio_for(e, false);
                if !(xi.is_finite() && (0.0..1.0).contains(&xi)) {
                    return refuse(format!(
                        "contact.restitution = {e} with calibration = \"exact\" needs the \
                         damping ratio xi = {xi} of the clamped law, which LIGGGHTS's \
                         beta = ln e/sqrt(ln^2 e + pi^2) (|beta| < 1) cannot give; use \
                         contact.calibration = \"formula\" or a larger restitution"
                    ));
                }
                notes.push(format!(
                    "# Damping: dembound's Tsuji gamma = xi sqrt(5 k m*), xi = {} (exact calibration of the clamped law for e = {}),\n\
                     # is LIGGGHTS's hertz damping for beta = -xi, i.e. coefficientRestitution e' = exp(-pi xi/sqrt(1 - xi^2)) = {}.",
                    num(xi),
                    num(e),
                    num(restitution_of_ratio(xi))
                ));
                restitution_of_ratio(xi)
            } else {
                notes.push(format!(
                    "# Damping: dembound's Tsuji with the published mapping (xi = -beta(e)) is LIGGGHTS's hertz damping for the same e = {}.",
                    num(e)
                ));
                e
            };
            if !model.attractive {
                notes.push(
                    "# limitForce on: dembound's clamp F_n = max(F_n, 0) (contact.attractive = false)."
                        .into(),
                );
            }
            (written, !model.attractive)
        }
        (DampingKind::Tsuji, Some(Dissipation::Coefficient(g))) => {
            return refuse(format!(
                "contact.damping_coefficient = {g} is not exported to LIGGGHTS: its hertz \
                 damping takes one coefficientRestitution per type pair, and a fixed gamma \
                 corresponds to a different e for every pair mass; give contact.restitution"
            ))
        }
        (kind, _) => {
            return refuse(format!(
                "contact.damping = \"{}\" is not exported to LIGGGHTS: its `model hertz` damping \
                 is the Tsuji form gamma h^(1/4) dh/dt (dembound's \"tsuji\"), which this model is \
                 not; exported: \"none\" and \"tsuji\" with contact.restitution",
                kind.row().name
            ))
        }
    };
    let n_materials = setup.materials.len();
    let mut type_materials: Vec<usize> = (0..n_materials).collect();
    let mut wall_types: Vec<Option<usize>> = setup
        .walls
        .iter()
        .map(|w| match w {
            WallSetup::Plane(p) => Some(p.material),
            WallSetup::Mesh(m) => Some(m.material),
            _ => None,
        })
        .collect();
    let mut tangential_damping_off = false;
    let friction = match &setup.friction {
        None => None,
        Some(f) => {
            let mut surfaces: Vec<(String, (f64, f64))> = (0..n_materials)
                .map(|m| {
                    (
                        format!("material \"{}\"", setup.materials[m].name),
                        f.of_material(m),
                    )
                })
                .collect();
            for (w, t) in wall_types.iter().enumerate() {
                if let Some(m) = *t {
                    surfaces.push((format!("wall[{w}]"), f.of_wall(w, m)));
                }
            }
            let rolls = surfaces.iter().find(|(_, (_, r))| *r != 0.0);
            if let (Some((who, (_, mu_r))), None) = (rolls, hooke) {
                let key = if f.model.rolling_friction != 0.0 {
                    "contact.rolling_friction".to_string()
                } else {
                    format!("rolling_friction of {who}")
                };
                return refuse(format!(
                    "{key} = {mu_r} under contact.law = \"hertz\" is not exported to LIGGGHTS: \
                     its rolling models are other laws (3.8's epsd2 takes k_r = k_t R*^2 with \
                     Hertz's k_t = 8 G* sqrt(R* d), dembound's epsd2 k_r = 2.25 (F_n/h) mu_r^2 \
                     R_eff^2; cdt is a constant torque); set every rolling friction to 0, or \
                     use contact.law = {{ hooke = k }}, or export to LAMMPS"
                ));
            }
            if surfaces.iter().all(|(_, (mu, _))| *mu == 0.0) {
                None
            } else {
                if hooke.is_some() && f.model.tangential != TangentialKind::Linear {
                    return refuse(format!(
                        "contact.tangential = \"{}\" with contact.law = {{ hooke = k }} is not \
                         exported to LIGGGHTS: its `model hooke/stiffness` takes one constant k_t \
                         per type pair, dembound's Mindlin k_t = 8 G* sqrt(R_eff h) follows the \
                         overlap; use contact.tangential = \"linear\" (k_t = (2/7) E_eff R_eff)",
                        f.model.tangential.row().name
                    ));
                }
                if hooke.is_none() && f.model.tangential == TangentialKind::MindlinForce {
                    return refuse(
                        "contact.tangential = \"mindlin_force\" is not exported to LIGGGHTS: \
                         its `tangential history` (tangential_model_history.h) stores the \
                         displacement and applies -k_t(h) times it with the current k_t, \
                         dembound's \"mindlin\" spring, not the incremental one (a stored \
                         force F_s += -k_t(h) v_t dt), and the two differ whenever the overlap \
                         changes under a loaded spring; use contact.tangential = \"mindlin\", \
                         or export to LAMMPS (tangential mindlin/force) or Yade (its Mindlin \
                         law is incremental)"
                            .to_string(),
                    );
                }
                if hooke.is_none() && f.model.tangential != TangentialKind::Mindlin {
                    return refuse(format!(
                        "contact.tangential = \"{}\" is not exported to LIGGGHTS: its `model \
                         hertz tangential history` has the Mindlin spring k_t = 8 G* sqrt(R* d) \
                         only; use contact.tangential = \"mindlin\"",
                        f.model.tangential.row().name
                    ));
                }
                let damped = limit_force || restitution != 1.0;
                if damped && f.tangential_damping {
                    return refuse(format!(
                        "contact.damping = \"{}\" with friction (contact.friction = {}) is not \
                         exported to LIGGGHTS: while a contact sticks LIGGGHTS adds the tangential \
                         dashpot to the spring without the Coulomb cap that dembound applies, so \
                         near every contact's onset LIGGGHTS's tangential force exceeds mu |F_n| \
                         (measured: an oblique impact leaves with 12 % more spin); set \
                         contact.tangential_damping = false (no tangential dashpot in dembound, \
                         LIGGGHTS's `tangential_damping off`: the same law in both), or export \
                         damping without friction (--set contact.friction=0) or friction without \
                         damping (--set contact.damping=none)",
                        model.damping.kind().row().name,
                        f.model.friction
                    ));
                }
                let mut mu: Vec<f64> = (0..n_materials).map(|m| f.of_material(m).0).collect();
                for (w, t) in wall_types.iter_mut().enumerate() {
                    if let Some(m) = *t {
                        let own = f.of_wall(w, m).0;
                        // Under Hooke every wall gets a type of its own: its
                        // k_t uses the sphere's R, a sphere pair's R_eff.
                        if own != mu[m] || hooke.is_some() {
                            *t = Some(type_materials.len());
                            type_materials.push(m);
                            mu.push(own);
                        }
                    }
                }
                if damped {
                    tangential_damping_off = true;
                    notes.push(
                        "# tangential_damping off: dembound's contact.tangential_damping = false, no tangential dashpot in either code\n\
                         # (a sticking contact's force is the spring's, -k_t d, within mu |F_n| by the sliding test in both)."
                            .into(),
                    );
                }
                let spring = if hooke.is_some() {
                    "dembound's linear spring, kt = (2/7) E_eff R_eff per type pair,"
                } else {
                    "dembound's Mindlin spring k_t = 8 G* sqrt(R* d)"
                };
                // The header as before for every other arm and the default
                // rotation (the same deck bytes); under LIGGGHTS's own arm
                // the arm is not a difference, under its own rotation the
                // spring's length is not.
                let project = f.spring_rotation == SpringRotation::Project;
                let kept = match (f.torque_arm == TorqueArm::HalfOverlap, project) {
                    (true, false) => " The lever arm is LIGGGHTS's\n\
                     # (contact.torque_arm = \"half_overlap\": R - d/2 in the slip and the torque of every contact). Difference kept: the spring's length on a turning normal.",
                    (true, true) => " The lever arm is LIGGGHTS's\n\
                     # (contact.torque_arm = \"half_overlap\": R - d/2 in the slip and the torque of every contact), and so is the spring's rotation\n\
                     # (contact.spring_rotation = \"project\": projected onto the new tangent plane, its length not restored).",
                    (false, false) => " Differences kept: the lever arm\n\
                     # (LIGGGHTS R - d/2 in the slip and the torque; relative d/2R in the spin terms), the spring's length on a turning normal.",
                    (false, true) => " Difference kept: the lever arm\n\
                     # (LIGGGHTS R - d/2 in the slip and the torque; relative d/2R in the spin terms). The spring's rotation is LIGGGHTS's\n\
                     # (contact.spring_rotation = \"project\": projected onto the new tangent plane, its length not restored).",
                };
                notes.push(format!(
                    "# Friction: tangential history = {spring} with the Coulomb cut,\n\
                     # no damping; mu per type pair = sqrt(mu_a mu_b) as dembound mixes.{kept}"
                ));
                Some(mu)
            }
        }
    };
    let (tangential_stiffness, rolling) = match (hooke, &friction, &setup.friction) {
        (Some(k), Some(_), Some(f)) => {
            let (kt, rolling) = hooke_springs(setup, k, f, &type_materials, &wall_types)?;
            if rolling.is_some() {
                notes.push(
                    "# Rolling: epsd2, LIGGGHTS k_r = k_t R*^2 = dembound's 2.25 k mu_r^2 R_eff^2 (checked per type pair), no dashpot (undamped).\n\
                     # Differences kept: the rolling history is not turned with the normal in LIGGGHTS; against a wall LIGGGHTS\n\
                     # drives it with omega (R - d/2)/(R - d) (surface_model_default.h), dembound with omega."
                        .into(),
                );
            }
            (Some(kt), rolling)
        }
        _ => (None, None),
    };
    if let Some(k) = hooke {
        notes.push(format!(
            "# Hooke: model hooke/stiffness, kn = {} N/m for every type pair (dembound's law = {{ hooke = k }}), undamped:\n\
             # gamman_abs = gammat_abs = 0 (absolute_damping on); with friction kt = dembound's linear (2/7) E_eff R_eff per type pair.",
            num(k)
        ));
    }
    if let Some(mu) = &friction {
        for (t, m) in type_materials.iter().enumerate().skip(n_materials) {
            notes.push(format!(
                "# type {}: material \"{}\" of a wall with its own friction {}",
                t + 1,
                setup.materials[*m].name,
                num(mu[t])
            ));
        }
    }
    Ok(ContactPlan {
        restitution,
        limit_force,
        friction,
        tangential_damping_off,
        wall_types,
        type_materials,
        notes,
        hooke,
        tangential_stiffness,
        rolling,
    })
}

/// Under `contact.law = { hooke = k }` with friction: k_t of each type
/// pair (dembound's linear (2/7) E_eff R_eff, row-major; 0 where no
/// sphere meets) and, with rolling friction, μ_r of each type, or a
/// refusal naming the key. LIGGGHTS 3.8's epsd2 (`rolling_model_epsd2.h`)
/// takes k_r = k_t R*² from the tangential model's k_t; dembound's
/// (`contact/rolling.rs`) k_r = 2.25 k μ_r² R_eff²: the same spring only
/// where k_t = 2.25 k μ_r², which is checked for every pair that rolls.
fn hooke_springs(
    setup: &SceneSetup,
    k: f64,
    f: &dembound_scene::setup::FrictionSetup,
    type_materials: &[usize],
    wall_types: &[Option<usize>],
) -> Result<(Vec<f64>, Option<Vec<f64>>)> {
    let n = type_materials.len();
    // The one radius of each sphere type (a sphere's type is its material).
    let mut radius: Vec<Option<f64>> = vec![None; n];
    for s in &setup.spheres {
        match radius[s.material] {
            None => radius[s.material] = Some(s.radius),
            Some(r) if r == s.radius => {}
            Some(_) => {
                return Err(Error::Export(format!(
                    "contact.tangential = \"linear\" between spheres of several radii (material \
                     \"{}\") is not exported to LIGGGHTS: dembound's k_t = (2/7) E_eff R_eff \
                     changes from pair to pair and LIGGGHTS's hooke/stiffness takes one kt per \
                     type pair (allowed: one radius per material)",
                    setup.materials[s.material].name
                )))
            }
        }
    }
    let wall = |t: usize| wall_types.contains(&Some(t));
    let mut mu_r: Vec<f64> = (0..n).map(|t| f.of_material(type_materials[t]).1).collect();
    for (w, t) in wall_types.iter().enumerate() {
        if let Some(t) = *t {
            mu_r[t] = f.of_wall(w, type_materials[t]).1;
        }
    }
    let rolls = mu_r.iter().any(|&r| r != 0.0);
    let mut kt = vec![0.0; n * n];
    for i in 0..n {
        for j in 0..n {
            let r_eff = match (radius[i], radius[j]) {
                (Some(a), Some(b)) => Some(effective_radius(a, b)),
                (Some(a), None) if wall(j) => Some(a),
                (None, Some(b)) if wall(i) => Some(b),
                _ => None,
            };
            let Some(r_eff) = r_eff else { continue };
            let (a, b) = (type_materials[i], type_materials[j]);
            let e = effective_modulus(&setup.materials[a].material, &setup.materials[b].material);
            // dembound's own linear spring (contact::tangential::linear).
            let k_t = LinearTangential::new(&TangentialSetup {
                pair: PairProperties {
                    radius: r_eff,
                    modulus: e,
                    mass: 0.0,
                },
                shear_modulus: 0.0,
            })
            .stiffness;
            if !(k_t.is_finite() && k_t > 0.0) {
                return Err(Error::Export(format!(
                    "contact.tangential = \"linear\" between materials \"{}\" and \"{}\": k_t = \
                     (2/7) E_eff R_eff = {k_t} N/m, which LIGGGHTS's hooke/stiffness cannot take \
                     (give both a finite modulus)",
                    setup.materials[a].name, setup.materials[b].name
                )));
            }
            kt[i * n + j] = k_t;
            let m = mix_friction(mu_r[i], mu_r[j]);
            let k_r = 2.25 * k * m * m;
            if m != 0.0 && (k_t / k_r - 1.0).abs() > 1e-9 {
                return Err(Error::Export(format!(
                    "contact.rolling_friction (mu_r = {} between \"{}\" and \"{}\") is not \
                     exported to LIGGGHTS: its epsd2 rolling spring is k_r = k_t R*^2 with the \
                     tangential k_t = {} N/m, dembound's is k_r = 2.25 k mu_r^2 R_eff^2 = {} \
                     R_eff^2 N/m: the same law only where k_t = 2.25 k mu_r^2 (choose the moduli \
                     so that (2/7) E_eff R_eff = 2.25 k mu_r^2 for every pair, or set every \
                     rolling friction to 0, or export to LAMMPS)",
                    num(m),
                    setup.materials[a].name,
                    setup.materials[b].name,
                    num(k_t),
                    num(k_r)
                )));
            }
        }
    }
    Ok((kt, rolls.then_some(mu_r)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use dembound_physics::contact::calibration::tsuji_beta;

    /// e′ inverts β(e): β(e′) = −ξ to round-off over the range of ξ.
    #[test]
    fn restitution_of_ratio_inverts_the_liggghts_beta() {
        for xi in [0.0, 1e-6, 0.05, 0.2, 0.5, 0.9, 0.99] {
            let e = restitution_of_ratio(xi);
            let beta = e.ln() / (e.ln().powi(2) + std::f64::consts::PI.powi(2)).sqrt();
            assert!((beta + xi).abs() < 1e-15, "xi {xi}: beta {beta}");
            assert!((tsuji_beta(e) + xi).abs() < 1e-15, "xi {xi}");
        }
        assert_eq!(restitution_of_ratio(0.0), 1.0);
    }
}
