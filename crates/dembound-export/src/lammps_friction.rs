//! Friction of a scene as LAMMPS `pair granular` / `fix wall/gran
//! granular` arguments (docs/export-lammps.md, "Scenes with friction"):
//! the tangential spring, its Coulomb limit and the rolling spring of each
//! type pair, or a refusal naming the key when LAMMPS would not compute
//! what dembound computes.
//!
//! What maps exactly (dembound `contact::tangential`, LAMMPS 2021
//! `PairGranular::compute`):
//! - `contact.tangential = "mindlin"`: dembound's k_t = 8 G* √(R_eff h) on
//!   a stored displacement, the force −k_t(h) δ with the current stiffness,
//!   is LAMMPS's `tangential mindlin k_t` (k_tangential = k_t a,
//!   a = √(R_eff δ)) with k_t = 8 G* written per type pair, G* =
//!   1/((2 − ν₁)/G₁ + (2 − ν₂)/G₂). Not `mindlin/force` (which integrates
//!   the force, dF = −k_t(h) v_t Δt, and differs as soon as h changes under
//!   a loaded spring) nor `mindlin_rescale` (which shrinks δ on unloading).
//! - `contact.tangential = "mindlin_force"`: dembound's incremental spring
//!   (a stored force F_s += −k_t(h) v_t Δt) is LAMMPS's `tangential
//!   mindlin/force k_t` with the same k_t = 8 G* per type pair.
//! - `contact.tangential = "linear"`: k_t = (2/7) E_eff R_eff, LAMMPS's
//!   `linear_history k_t` with that number per type pair: exact when every
//!   pair of the two types has the same R_eff (each type of one radius).
//! - The Coulomb limit μ |F_n| with μ = √(μ_a μ_b) (dembound's mixing,
//!   written per pair, never left to LAMMPS's mixing), F_n the elastic
//!   normal force (damped and clamped when the normal contact is, below).
//! - Sliding, undamped: both cut the spring back to μ |F_n|/k_t along
//!   itself (LAMMPS's δ = −(F_crit f̂ + η_t v_t)/k_t with η_t = 0).
//! - Rolling (`rolling sds`) under `contact.law = "hooke"`: dembound's
//!   spring torque M_r −= k_r ω_r Δt, k_r = 2.25 k μ_r² R_eff², capped at
//!   μ_r R_eff |F_n|, is LAMMPS's rolling displacement ξ = R_eff ∫ ω × n
//!   with force −k_roll ξ and torque R_eff n × F: k_roll = k_r/R_eff² =
//!   2.25 k μ_r², mu_roll = μ_r, damp_roll = 0.
//!
//! - Damping (`damping tsuji`, lammps_scene.rs) with friction under
//!   `contact.tangential_damping = false`: the tangential argument
//!   x_γ,t = 0 gives LAMMPS no tangential dashpot, dembound has none
//!   either; the Coulomb limit is μ |F_n| of the total (damped, clamped by
//!   `limit_damping`) normal force in both (LAMMPS's F_ncrit = |F_ntot|).
//!
//! What is refused, with the key:
//! - `contact.spring_rotation = "project"` (LIGGGHTS's rotation of the
//!   tangential spring, its length not restored): `pair granular` always
//!   rotates and rescales its history (`gran_sub_mod_tangential.cpp`;
//!   2021's `rotate_rescale_vec`), dembound's default.
//! - damping with friction and dembound's tangential dashpot on
//!   (`contact.tangential_damping`, default true): on sliding
//!   LAMMPS caps spring + dashpot together and solves the spring back
//!   from the cap; dembound cuts the spring alone and drops the dashpot
//!   (tangential/mod.rs, step 3). Near onset the two springs point apart.
//! - rolling friction with damping: dembound damps the rolling spring
//!   with the normal contact's local damping ratio; `rolling sds` takes
//!   one constant damp_roll.
//! - rolling friction under Hertz: epsd2's k_r follows the secant stiffness
//!   F_n/h ∝ √h; `rolling sds` takes a constant k_roll.
//! - a linear tangential spring between types of several radii.
//!
//! One difference stays, of relative size h/(2R): LAMMPS applies the
//! tangential force's torque at R − δ/2 from each centre, dembound at R
//! (both use R in the slip velocity). The test
//! (tests/export_codes.rs, `lammps_friction`) measures what it does.

use crate::{num, Error, Result};
use dembound_physics::contact::tangential::{
    effective_shear_modulus, mix_friction, SpringRotation, TangentialKind,
};
use dembound_physics::contact::{DampingKind, NormalLaw};
use dembound_physics::material::{effective_modulus, effective_radius, Material};
use dembound_scene::setup::{SceneSetup, WallSetup};

/// One side of a pair as the friction mapping needs it.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Surface<'a> {
    pub material: &'a Material,
    /// (μ, μ_r) of the surface.
    pub coefficients: (f64, f64),
    /// The radius every sphere of the type has (None: several, or a plane).
    pub radius: Option<f64>,
    /// A plane wall (infinite radius).
    pub plane: bool,
}

/// The friction of an exported scene: what every pair's arguments need.
#[derive(Debug, Clone, Copy)]
pub(crate) struct FrictionPlan {
    pub tangential: TangentialKind,
    /// Any surface rolls (μ_r > 0).
    pub rolling: bool,
    /// `contact.law = "hooke"`'s k (N/m), which the rolling stiffness uses.
    pub hooke: Option<f64>,
}

/// The friction plan of `setup`, None when the deck is frictionless: no
/// friction keys, or every surface's μ is 0 (then no tangential force ever
/// acts, no sphere spins, and rolling resistance, driven by spin, never
/// acts either: `--set contact.friction=0` on a frictional file).
pub(crate) fn plan(setup: &SceneSetup) -> Result<Option<FrictionPlan>> {
    let Some(f) = &setup.friction else {
        return Ok(None);
    };
    let materials = 0..setup.materials.len();
    let plane_walls: Vec<(usize, usize)> = setup
        .walls
        .iter()
        .enumerate()
        .filter_map(|(w, s)| match s {
            WallSetup::Plane(p) => Some((w, p.material)),
            _ => None,
        })
        .collect();
    let mut surfaces: Vec<(String, (f64, f64))> = materials
        .map(|m| {
            (
                format!("material \"{}\"", setup.materials[m].name),
                f.of_material(m),
            )
        })
        .collect();
    for &(w, m) in &plane_walls {
        surfaces.push((format!("wall[{w}]"), f.of_wall(w, m)));
    }
    if surfaces.iter().all(|(_, (mu, _))| *mu == 0.0) {
        return Ok(None);
    }
    let refuse = |s: String| Err(Error::Export(s));
    if f.spring_rotation == SpringRotation::Project {
        return refuse(
            "contact.spring_rotation = \"project\" with friction cannot be exported to LAMMPS: \
             its pair granular and fix wall/gran granular turn the tangential history into the \
             new tangent plane and rescale it to its old length (\"rotate and rescale\", \
             gran_sub_mod_tangential.cpp; rotate_rescale_vec in 2021's PairGranular), with no \
             setting to project only, so the decks would part wherever a contact's normal turns \
             under a loaded spring (allowed: contact.spring_rotation = \"rescale\", the default \
             and LAMMPS's rotation; or export without friction: --set contact.friction=0)"
                .to_string(),
        );
    }
    let damping = setup.contact.damping.kind();
    if damping != DampingKind::None && f.tangential_damping {
        return refuse(format!(
            "contact.damping = \"{}\" with friction (contact.friction = {}) and the tangential \
             dashpot on (contact.tangential_damping, default true) cannot be exported to \
             LAMMPS: when a contact starts to slide LAMMPS caps spring + dashpot together and \
             solves the spring back from the cap, dembound cuts the spring alone to the \
             Coulomb limit and drops the dashpot, so the decks would differ at every sliding \
             onset (allowed with friction: contact.tangential_damping = false, no tangential \
             dashpot in either code; or contact.damping = \"none\"; or export without \
             friction: --set contact.friction=0)",
            damping.row().name,
            f.model.friction
        ));
    }
    let rolling = surfaces.iter().any(|(_, (_, r))| *r > 0.0);
    if rolling && damping != DampingKind::None {
        return refuse(format!(
            "rolling friction with contact.damping = \"{}\" cannot be exported to LAMMPS: \
             dembound damps the rolling spring with the normal contact's local damping ratio \
             (eta_r = 2 xi sqrt(k_r I)), LAMMPS's rolling sds takes one constant damp_roll \
             (allowed: rolling friction 0 (contact.rolling_friction, and each material's and \
             wall's rolling_friction), or contact.damping = \"none\")",
            damping.row().name
        ));
    }
    let hooke = match setup.contact.normal {
        NormalLaw::Hooke { stiffness } => Some(stiffness),
        _ => None,
    };
    if rolling && hooke.is_none() {
        let key = if f.model.rolling_friction > 0.0 {
            format!("contact.rolling_friction = {}", f.model.rolling_friction)
        } else {
            let (name, (_, r)) = surfaces
                .iter()
                .find(|(_, (_, r))| *r > 0.0)
                .cloned()
                .unwrap_or_default();
            format!("rolling_friction = {r} of {name}")
        };
        return refuse(format!(
            "{key} under contact.law = \"{}\" cannot be exported to LAMMPS: dembound's rolling \
             spring (epsd2) has k_r = 2.25 (F_n/h) mu_r^2 R_eff^2, which follows the Hertz \
             secant stiffness, and LAMMPS's rolling sds takes a constant k_roll (allowed: \
             rolling friction 0, or contact.law = \"hooke\")",
            setup.contact.normal.row().name
        ));
    }
    Ok(Some(FrictionPlan {
        tangential: f.model.tangential,
        rolling,
        hooke,
    }))
}

impl FrictionPlan {
    /// The `tangential … [rolling …]` arguments of a pair `a`–`b` (no
    /// damping: x_γ,t = 0 and damp_roll = 0), and a short comment.
    pub(crate) fn pair_args(&self, a: &Surface, b: &Surface) -> Result<(String, String)> {
        let mu = mix_friction(a.coefficients.0, b.coefficients.0);
        let mu_r = mix_friction(a.coefficients.1, b.coefficients.1);
        let (tangential, comment) = match self.tangential {
            TangentialKind::Mindlin => {
                let k = 8.0 * effective_shear_modulus(a.material, b.material);
                (
                    format!("mindlin {} 0.0 {}", num(k), num(mu)),
                    format!("8 G* = {} Pa, mu = {}", num(k), num(mu)),
                )
            }
            TangentialKind::MindlinForce => {
                let k = 8.0 * effective_shear_modulus(a.material, b.material);
                (
                    format!("mindlin/force {} 0.0 {}", num(k), num(mu)),
                    format!("8 G* = {} Pa, mu = {}, incremental", num(k), num(mu)),
                )
            }
            TangentialKind::Linear => {
                let radius = match (a.radius, b.radius) {
                    (Some(r), _) if b.plane => Some(r),
                    (_, Some(r)) if a.plane => Some(r),
                    (Some(ra), Some(rb)) => Some(effective_radius(ra, rb)),
                    _ => None,
                };
                let Some(r) = radius else {
                    return Err(Error::Export(
                        "contact.tangential = \"linear\" between spheres of several radii cannot \
                         be exported to LAMMPS: dembound's k_t = (2/7) E_eff R_eff changes from \
                         pair to pair and LAMMPS's linear_history takes one k_t per type pair \
                         (allowed: one radius per material, or contact.tangential = \"mindlin\")"
                            .into(),
                    ));
                };
                let k = 2.0 / 7.0 * effective_modulus(a.material, b.material) * r;
                (
                    format!("linear_history {} 0.0 {}", num(k), num(mu)),
                    format!("k_t = 2/7 E_eff R_eff = {} N/m, mu = {}", num(k), num(mu)),
                )
            }
        };
        let mut args = format!("tangential {tangential}");
        let mut comment = comment;
        if self.rolling {
            let k = self.hooke.unwrap_or(f64::NAN);
            let k_roll = 2.25 * k * mu_r * mu_r;
            args.push_str(&format!(" rolling sds {} 0.0 {}", num(k_roll), num(mu_r)));
            comment.push_str(&format!(
                ", k_roll = 2.25 k mu_r^2 = {} N/m, mu_r = {}",
                num(k_roll),
                num(mu_r)
            ));
        }
        Ok((args, comment))
    }
}

/// The note `dembound export lammps` prints for a scene with friction
/// (some μ > 0) that keeps `contact.torque_arm = "radius"`: LAMMPS's `pair
/// granular` takes the tangential torque of a sphere pair at R − δ/2, so
/// the two runs agree only until the first tangential sphere–sphere
/// contact; under `"overlap_middle"` (Yade's arms) it differs from the
/// first frictional contact. `None` without friction or under
/// `"contact_point"`.
pub fn torque_arm_note(setup: &SceneSetup) -> Option<String> {
    use dembound_physics::contact::TorqueArm;
    let f = setup.friction.as_ref()?;
    if f.torque_arm == TorqueArm::ContactPoint {
        return None;
    }
    plan(setup).ok().flatten()?;
    if f.torque_arm == TorqueArm::OverlapMiddle {
        return Some(
            "note: contact.torque_arm = \"overlap_middle\" is Yade's model (R − δ/2 in the \
             torque of every contact and in the slip against walls, the centres' velocity \
             scaled by (R₁ + R₂)/(R₁ + R₂ − δ) in a pair's slip); LAMMPS's pair granular and \
             fix wall/gran differ from it from the first frictional contact; set \
             contact.torque_arm = \"contact_point\" to run LAMMPS's arm in dembound"
                .to_string(),
        );
    }
    Some(
        "note: contact.torque_arm = \"radius\": dembound applies the tangential force's torque \
         at R, LAMMPS's pair granular at the contact point R − δ/2 (δ the overlap) for sphere \
         pairs, so the two runs agree only until the first tangential sphere–sphere contact \
         (then by up to δ/(2R) in the spins); set contact.torque_arm = \"contact_point\" to run \
         LAMMPS's arm in dembound"
            .to_string(),
    )
}
