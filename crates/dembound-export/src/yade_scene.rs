//! A many-particle scene (`dembound scene`'s TOML) as a Yade script
//! (`scene.py`, checked with Yade 2023.02a): the spheres, fixed spheres
//! (boundary-particle walls and fixed `[[particles]]` groups) with materials
//! of their own, axis-aligned plane walls as `utils.wall`, and a recorder
//! that writes what `dembound compare` reads (docs/export-yade.md, "Scenes").
//!
//! Contact models (Yade's `Ip2_FrictMat_FrictMat_*`, pkg/dem/HertzMindlin.cpp
//! and FrictPhys.cpp):
//! - Hertz: `MindlinPhys`/`Law2_ScGeom_MindlinPhys_Mindlin`: k_n⁰ = 4/3 E R*
//!   ^(1/2), E = 1/((1 − ν_a²)/E_a + (1 − ν_b²)/E_b), R* = D_a D_b/(D_a + D_b);
//!   k_s⁰ = 8 G* √R*, G* = 1/((2 − ν_a)/G_a + (2 − ν_b)/G_b) (measured on the
//!   installed 2023.02a: `kso` of a sphere on a fixed sphere of another
//!   material; the older sources' 2 √(4R*) G/(2 − V) with the arithmetic
//!   means G and V is not what it computes). That is dembound's eq 6 and
//!   8 G* √(R h) for any two spheres, so a fixed sphere keeps its own
//!   material. A `utils.wall` gets a stand-in material ([`stand_in`]) whose
//!   E and ν make both Yade numbers dembound's: Yade takes D_a = D_b = R
//!   there (R* = R/2, dembound R).
//! - `contact.law = "hooke"`: `FrictPhys`/`Law2_ScGeom_FrictPhys_CundallStrack`:
//!   k_n = 2 E_a D_a E_b D_b/(E_a D_a + E_b D_b), k_s the same mean of
//!   E D ν: "young" = k/R and "poisson" = k_t/k for one sphere radius.
//! - Rolling friction under Hooke: `CohFrictMat`'s alphaKr and etaRoll with
//!   `Law2_ScGeom6D_CohFrictPhys_CohesionMoment` ([`yade_rolling`]), the
//!   planes as box faces (Yade has no ScGeom6D of `utils.wall`).
//! - Damping (Hertz, Tsuji given by a restitution): Yade's `betan`, c_n =
//!   2 β_n √(m̄ k_n) with k_n = 3/2 k_n⁰ √δ, is dembound's γ h^(1/4) ḣ with
//!   β_n = α/√6, α = γ/(√(m_eff E_eff) R_eff^(1/4)); `betas = 0` (no
//!   tangential dashpot). m̄ is the moving body's mass against a fixed one,
//!   as dembound's m_eff. Yade 2023 clamps the damped normal force at 0
//!   (dembound's `contact.attractive = false`; measured, not read in its
//!   source: a damped two-sphere bounce on a plane is identical to 1e-14).
//! - Friction: Yade takes the smaller friction angle of the two materials;
//!   each stand-in material gets atan(√(μ_a μ_b)), which is the smaller one
//!   when √(μ_a μ_b) ≤ μ of the spheres.
//!
//! The integrator: `NewtonIntegrator(damping=0)` (Yade's default Cundall
//! damping is 0.2) is leapfrog, positions identical to velocity Verlet; the
//! velocity it stores is half a step back, so the script starts from
//! v₀ − g Δt/2 and the recorder (before the integrator) writes
//! v + a Δt/2, dembound's velocity at the row's step.

use crate::lammps_output::{series_every, DUMP_FILE, WALLS_FILE, WALLS_MEAN_FILE};
use crate::{num, yade_rolling, Code, Deck, DeckFile, Error, Result};
use dembound_physics::contact::tangential::{
    effective_shear_modulus, mix_friction, SpringRotation, TangentialKind,
};
use dembound_physics::contact::{DampingKind, DampingPair, Dissipation, NormalLaw};
use dembound_physics::material::{effective_modulus, Material, PairProperties};
use dembound_scene::io::resolve::ResolvedScene;
use dembound_scene::setup::{Scheme, SphereInit, WallSetup};
use dembound_scene::Simulation;
use std::fmt::Write;

/// The script of a scene deck.
pub const SCRIPT: &str = "scene.py";
/// Its timing line, in LAMMPS's "Loop time of …" form.
pub const LOG: &str = "log.yade";
/// The command that runs the deck inside its directory (one thread).
pub const COMMAND: &str = "yade -n -j1 -x scene.py";

/// A Yade material: E, ν (Yade's "young", "poisson", which are stiffness
/// factors under `FrictPhys`), friction angle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct YadeMaterial {
    pub young: f64,
    pub poisson: f64,
    pub friction_angle: f64,
}

fn refuse<T>(s: String) -> Result<T> {
    Err(Error::Export(s))
}

/// The stand-in Hertz–Mindlin material of a body met by spheres of
/// material `free`: Yade 2023.02a's k_n⁰ = 4/3 E √(ρR) and k_s⁰ = 8 G_Y
/// √(ρR), E = 1/((1 − ν_f²)/E_f + (1 − ν'²)/E') and G_Y = 1/((2 −
/// ν_f)/G_f + (2 − ν')/G') (ρ = Yade's R*/dembound's R_eff: 1 against a
/// sphere, 1/2 against `utils.wall`), equal dembound's E_eff √R and 8 G* √R, where
/// E_eff and G* are dembound's for `free` and `other`. The normal condition
/// fixes c = (1 − ν'²)/E' = 4√ρ/(3 E_eff) − (1 − ν_f²)/E_f; the shear one,
/// d = (2 − ν')/G' = √ρ/G* − (2 − ν_f)/G_f with G' = (1 − ν')/(2c), gives
/// ν' = (d − 4c)/(d − 2c). At ρ = 1 that is `other` itself. None when no
/// E' > 0, ν' ∈ (−1, 1) exists.
pub fn stand_in(free: &Material, other: &Material, rho: f64) -> Option<(f64, f64)> {
    let e_eff = effective_modulus(free, other);
    let g_star = effective_shear_modulus(free, other);
    let nu_f = free.poisson_ratio;
    let c = 4.0 * rho.sqrt() / (3.0 * e_eff) - (1.0 - nu_f * nu_f) / free.youngs_modulus;
    if !(c > 0.0 && c.is_finite()) {
        return None;
    }
    let g_f = free.youngs_modulus / (2.0 * (1.0 + nu_f));
    let d = rho.sqrt() / g_star - (2.0 - nu_f) / g_f;
    let nu = (d - 4.0 * c) / (d - 2.0 * c);
    if !(nu > -1.0 && nu < 1.0) {
        return None;
    }
    Some(((1.0 - nu * nu) / c, nu))
}

/// One body kind of the deck besides the free spheres.
struct Other {
    /// What the comment and refusals call it.
    name: String,
    /// dembound's material of the body.
    material: Material,
    /// (μ, μ_r) of its surface.
    friction: (f64, f64),
    /// `utils.wall` (R* = R/2 in Yade).
    wall: bool,
    /// The key that sets its rolling friction.
    rolling_key: String,
}

/// The axis along which Yade's `InsertionSortCollider` makes its initial
/// sweep (`sortAxis`) when planes are written as boxes in a periodic cell:
/// the first non-periodic axis, or None when every axis is periodic.
///
/// Why (Yade's pkg/common/InsertionSortCollider.cpp, read at the 2022
/// sources; reproduced on the installed 2023.02a): in a periodic cell the
/// bounds are wrapped into the cell (`cellWrap`), so along a periodic axis a
/// box wider than the period has its min and max wrapped to two arbitrary
/// points (both to the cell's middle for a box centred there).
/// `findOverlaps`, the initial sweep along `sortAxis` (x by default), pairs
/// a sphere with the box only if its wrapped x-interval meets the box's
/// wrapped one; every sphere whose bounds already overlap the box on the
/// other axes at that sweep (the chute's lattice: 0.1 mm above the floor,
/// inside the collider's Verlet sweep of R/2) and whose x is elsewhere gets
/// no interaction, and no later inversion on z creates one, since its z
/// bounds never cross again. Measured: 20 of the chute's 100 bottom
/// spheres, those whose x-bounds (R plus the sweep R/2) cover the cell's
/// middle, met the floor; the other 80 fell through. Later inversions are handled right:
/// `spatialOverlapPeri` skips an axis on which `allowBiggerThanPeriod` finds
/// the box larger than half the period. Sweeping along a non-periodic axis,
/// on which every box is smaller than half the cell (the deck makes them
/// so), finds every pair (measured: 100 of 100).
fn periodic_box_sort_axis(periodic: [bool; 3]) -> Option<usize> {
    (0..3).find(|&k| !periodic[k])
}

/// The deck of a resolved scene: [`SCRIPT`].
pub fn deck(scene: &ResolvedScene) -> Result<Deck> {
    let setup = &scene.setup;
    let model = &setup.contact;
    if setup.integration.scheme != Scheme::Verlet {
        return refuse(
            "integration.scheme = \"gear5\" cannot be exported to Yade: its NewtonIntegrator is \
             leapfrog (velocity Verlet's positions); set integration.scheme = \"verlet\""
                .into(),
        );
    }
    crate::refuse_moving_walls(setup, "Yade")?;
    crate::refuse_moving_groups(setup, "Yade")?;
    crate::refuse_removal(setup, "Yade")?;
    crate::refuse_inlets(
        setup,
        "Yade",
        "the Yade deck inserts no spheres during the run",
    )?;
    crate::refuse_servo_walls(setup, "Yade")?;
    crate::refuse_gates(setup, "Yade")?;
    let d = &setup.domain;
    for k in 0..3 {
        if d.periodic[k] && d.lower[k] != 0.0 {
            return refuse(format!(
                "domain.lower = {:?} with periodic axes cannot be exported to Yade: its periodic \
                 cell starts at 0 and shifting every position would change the numbers; put the \
                 lower corner at 0 on the periodic axes",
                d.lower
            ));
        }
    }
    // Walls: axis-aligned planes (utils.wall) and boundary particles.
    // (wall, axis, position, material, the spheres' side: +1 or −1)
    let mut planes: Vec<(usize, usize, f64, usize, f64)> = Vec::new();
    for (w, wall) in setup.walls.iter().enumerate() {
        match wall {
            WallSetup::Plane(p) => {
                let nonzero: Vec<usize> = (0..3).filter(|&k| p.normal[k] != 0.0).collect();
                if nonzero.len() != 1 {
                    return refuse(format!(
                        "`wall[{w}].plane` with normal {:?} cannot be exported to Yade: the deck \
                         writes planes as utils.wall, which is normal to x, y or z; give an \
                         axis-aligned normal",
                        p.normal
                    ));
                }
                let axis = nonzero[0];
                planes.push((w, axis, p.point[axis], p.material, p.normal[axis].signum()));
            }
            w_setup if w_setup.is_particles() => {}
            other => {
                let kind = other.key();
                return refuse(format!(
                    "`wall[{w}].{kind}` cannot be exported to Yade yet: the deck writes planes \
                     (utils.wall) and boundary-particle walls (fixed spheres); Yade's facets \
                     take R* = 2R/3 against a sphere and meet a sphere on each facet of an \
                     edge, which no stand-in material corrects for every facet; remove the \
                     {kind} (or replace it by planes) to export the scene"
                ));
            }
        }
    }
    // The free spheres with their input indices.
    let free: Vec<(usize, SphereInit)> = setup
        .spheres
        .iter()
        .enumerate()
        .filter(|(_, s)| !s.fixed)
        .collect();
    let Some(&(_, first)) = free.first() else {
        return Err(crate::no_free_sphere("Yade"));
    };
    let free_material = first.material;
    if let Some((_, other)) = free.iter().find(|(_, s)| s.material != free_material) {
        return refuse(format!(
            "free spheres of materials \"{}\" and \"{}\" cannot be exported to Yade: the deck \
             maps the walls and fixed spheres by a stand-in material against one free \
             material (Yade averages G and nu of a pair); give the free spheres one material",
            setup.materials[free_material].name, setup.materials[other.material].name
        ));
    }
    let fm = setup.materials[free_material].material;
    if !fm.youngs_modulus.is_finite() {
        return refuse(format!(
            "`material[{free_material}].youngs_modulus` = inf (material \"{}\", rigid) cannot be \
             exported to Yade: its FrictMat needs a finite Young's modulus",
            setup.materials[free_material].name
        ));
    }
    let surface = |m: usize| {
        setup
            .friction
            .as_ref()
            .map_or((0.0, 0.0), |f| f.of_material(m))
    };
    let (mu_f, _) = surface(free_material);
    // Friction: one tangential model; no rolling; no tangential dashpot with damping.
    let frictional = {
        let mut any = mu_f > 0.0;
        if let Some(f) = &setup.friction {
            for (w, wall) in setup.walls.iter().enumerate() {
                if let Some(m) = wall.material() {
                    any |= f.of_wall(w, m).0 > 0.0;
                }
            }
            for m in 0..setup.materials.len() {
                any |= f.of_material(m).0 > 0.0;
            }
        }
        any && setup.friction.is_some()
    };
    if let Some(f) = setup.friction.as_ref().filter(|_| frictional) {
        if f.spring_rotation == SpringRotation::Project {
            return refuse(
                "contact.spring_rotation = \"project\" with friction cannot be exported to Yade: \
                 Yade turns its stored shear force by a first-order rotation each step \
                 (ScGeom::rotate: F -= F x (n0 x n), then a twist about n), which lengthens it \
                 by theta^2/2 of itself where \"project\" shortens the spring by as much, twice \
                 the difference of the default, which keeps the length (allowed: \
                 contact.spring_rotation = \"rescale\", the default; or export without \
                 friction: --set contact.friction=0)"
                    .to_string(),
            );
        }
        let mut rolling: Vec<String> = Vec::new();
        if f.model.rolling_friction > 0.0 {
            rolling.push(format!(
                "contact.rolling_friction = {}",
                f.model.rolling_friction
            ));
        }
        for m in 0..setup.materials.len() {
            if f.of_material(m).1 > 0.0 && f.materials.get(m).copied().flatten().is_some() {
                rolling.push(format!("material[{m}].rolling_friction"));
            }
        }
        for (w, wall) in setup.walls.iter().enumerate() {
            if f.walls.get(w).copied().flatten().is_some_and(|c| c.1 > 0.0)
                && wall.material().is_some()
            {
                rolling.push(format!("wall[{w}].rolling_friction"));
            }
        }
        if let Some(key) = rolling
            .first()
            .filter(|_| !matches!(model.normal, NormalLaw::Hooke { .. }))
        {
            return refuse(format!(
                "{key} under contact.law = \"{}\" cannot be exported to Yade: dembound's \
                 rolling spring has k_r = 2.25 k_n mu_r^2 R_eff^2 with the normal law's secant \
                 stiffness k_n; Yade's moment laws take a constant k_r (Mindlin includeMoment) \
                 or k_r = alpha_kr k_s R_1 R_2 with CohFrictPhys's linear contact; only \
                 contact.law = {{ hooke = k }} exports rolling friction (or export with --set \
                 contact.rolling_friction=0)",
                model.normal.row().name
            ));
        }
        let law_tangential_ok = match model.normal {
            NormalLaw::Hertz => matches!(
                f.model.tangential,
                TangentialKind::Mindlin | TangentialKind::MindlinForce
            ),
            NormalLaw::Hooke { .. } => f.model.tangential == TangentialKind::Linear,
            _ => true,
        };
        if !law_tangential_ok {
            return refuse(format!(
                "contact.tangential = \"{}\" under contact.law = \"{}\" cannot be exported to \
                 Yade: its MindlinPhys pairs a Hertz normal force with the Mindlin spring and \
                 its FrictPhys a linear normal force with a linear spring, nothing else (set \
                 contact.tangential = \"{}\")",
                f.model.tangential.row().name,
                model.normal.row().name,
                if matches!(model.normal, NormalLaw::Hertz) {
                    "mindlin"
                } else {
                    "linear"
                }
            ));
        }
        if model.damping.kind() != DampingKind::None && f.tangential_damping {
            return refuse(format!(
                "contact.tangential_damping = true (the default) with contact.damping = \"{}\" \
                 and friction cannot be exported to Yade: its Mindlin law damps the shear with \
                 c_s = c_n (Tsuji form) or 2 beta_s sqrt(m k_s), neither dembound's tangential \
                 dashpot (set contact.tangential_damping = false: beta_s = 0, no tangential \
                 dashpot in either code)",
                model.damping.kind().row().name
            ));
        }
    }
    // The other bodies: fixed-sphere materials, then plane walls.
    let mut others: Vec<Other> = Vec::new();
    let mut other_of_sphere: Vec<Option<usize>> = vec![None; setup.spheres.len()];
    for (i, s) in setup.spheres.iter().enumerate() {
        if !s.fixed {
            continue;
        }
        let name = format!(
            "material \"{}\" (fixed spheres)",
            setup.materials[s.material].name
        );
        let k = match others.iter().position(|o| o.name == name) {
            Some(k) => k,
            None => {
                others.push(Other {
                    name,
                    material: setup.materials[s.material].material,
                    friction: surface(s.material),
                    wall: false,
                    rolling_key: format!("material[{}].rolling_friction", s.material),
                });
                others.len() - 1
            }
        };
        other_of_sphere[i] = Some(k);
    }
    let mut other_of_plane: Vec<usize> = Vec::new();
    for &(w, _, _, m, _) in &planes {
        let friction = setup
            .friction
            .as_ref()
            .map_or((0.0, 0.0), |f| f.of_wall(w, m));
        others.push(Other {
            name: format!("wall[{w}]"),
            material: setup.materials[m].material,
            friction,
            wall: true,
            rolling_key: format!("wall[{w}].rolling_friction"),
        });
        other_of_plane.push(others.len() - 1);
    }
    // Each other body's Yade material.
    let radius_f = first.radius;
    let mut comments: Vec<String> = Vec::new();
    // Rolling friction (Hooke only): CohFrictMat's alphaKr and etaRoll of the
    // free spheres and of each other body.
    let mut rolling: Option<(yade_rolling::Rolling, Vec<yade_rolling::Rolling>)> = None;
    let (physics, law, free_yade, other_yade) = match model.normal {
        NormalLaw::Hertz => {
            if let Some(f) = setup.friction.as_ref().filter(|_| frictional) {
                comments.push(
                    if f.model.tangential == TangentialKind::MindlinForce {
                        "tangential: Yade's Mindlin law increments the shear force by -k_s(h) du_s each step, dembound's contact.tangential = \"mindlin_force\": the same spring"
                    } else {
                        "tangential: Yade's Mindlin law increments the shear force by -k_s(h) du_s each step; dembound's contact.tangential = \"mindlin\" applies -k_s(h) to the whole displacement: the two differ when the overlap changes under a loaded spring (\"mindlin_force\" is Yade's)"
                    }
                    .to_string(),
                );
            }
            let free_yade = YadeMaterial {
                young: fm.youngs_modulus,
                poisson: fm.poisson_ratio,
                friction_angle: mu_f.atan(),
            };
            let mut other_yade = Vec::new();
            for o in &others {
                let rho = if o.wall { 0.5 } else { 1.0 };
                // Yade's Mindlin numbers between two spheres are dembound's
                // (module doc): a fixed sphere keeps its own material (a
                // rigid one has no stand-in either: refused below).
                let (e, nu) = if !o.wall && o.material.youngs_modulus.is_finite() {
                    (o.material.youngs_modulus, o.material.poisson_ratio)
                } else {
                    stand_in(&fm, &o.material, rho).ok_or_else(|| {
                        Error::Export(format!(
                            "{} cannot be exported to Yade against material \"{}\": no finite \
                             stand-in material gives Yade's Mindlin stiffnesses dembound's \
                             E_eff and 8 G* (a rigid or much stiffer body against utils.wall \
                             needs E_mix > sqrt(2) E_eff of the spheres' own)",
                            o.name, setup.materials[free_material].name
                        ))
                    })?
                };
                other_yade.push((e, nu));
            }
            let betan = match (model.damping.kind(), model.damping.dissipation()) {
                (DampingKind::None, _) => None,
                (DampingKind::Tsuji, Some(Dissipation::Restitution(_))) => {
                    let alpha = |props: &PairProperties| -> f64 {
                        match model.pair(props).damping() {
                            DampingPair::Tsuji(t) => {
                                t.coefficient
                                    / (props.mass * props.modulus).sqrt()
                                    / props.radius.powf(0.25)
                            }
                            _ => f64::NAN,
                        }
                    };
                    let m = fm.sphere_mass(radius_f);
                    let a = alpha(&PairProperties::spheres(radius_f, m, &fm, radius_f, m, &fm));
                    let b = alpha(&PairProperties::sphere_plane(
                        2.0 * radius_f,
                        m,
                        &fm,
                        &Material::rigid(1.0),
                    ));
                    if !((a / b - 1.0).abs() < 1e-9 && a.is_finite()) {
                        return refuse(format!(
                            "contact.damping = \"tsuji\": the damping is not the same multiple of \
                             sqrt(m_eff E_eff) R_eff^(1/4) for every pair (alpha {a} and {b}); \
                             Yade's betan takes one"
                        ));
                    }
                    if model.attractive {
                        return refuse(
                            "contact.attractive = true with contact.damping = \"tsuji\" cannot \
                             be exported to Yade: Yade 2023's Mindlin law clamps the damped \
                             normal force at F = max(F, 0) (measured: a damped bounce is \
                             identical to 1e-14 against dembound's clamped force and leaves \
                             5e-3 m/s faster than its attractive one); set contact.attractive \
                             = false (the default)"
                                .into(),
                        );
                    }
                    comments.push(format!(
                        "damping: Tsuji from contact.restitution, alpha = gamma/(sqrt(m_eff E_eff) R_eff^(1/4)) = {}; Yade's c_n = 2 betan sqrt(m k_n), k_n = 3/2 k_no sqrt(delta): betan = alpha/sqrt(6)",
                        num(a)
                    ));
                    Some(a / 6f64.sqrt())
                }
                (DampingKind::Tsuji, _) => {
                    return refuse(
                        "contact.damping_coefficient cannot be exported to Yade for scenes: an \
                         absolute Tsuji gamma is a different multiple of sqrt(m_eff E_eff) \
                         R_eff^(1/4) for each pair and Yade's betan takes one; give \
                         contact.restitution instead"
                            .into(),
                    )
                }
                (kind, _) => {
                    return refuse(format!(
                        "contact.damping = \"{}\" cannot be exported to Yade (exported: \"none\", \
                         and \"tsuji\" given by contact.restitution, as betan)",
                        kind.row().name
                    ))
                }
            };
            (
                match betan {
                    Some(b) => format!(
                        "Ip2_FrictMat_FrictMat_MindlinPhys(betan={}, betas=0.0)",
                        num(b)
                    ),
                    None => "Ip2_FrictMat_FrictMat_MindlinPhys()".to_string(),
                },
                "Law2_ScGeom_MindlinPhys_Mindlin()",
                free_yade,
                other_yade,
            )
        }
        NormalLaw::Hooke { stiffness: k } => {
            if model.damping.kind() != DampingKind::None {
                return refuse(format!(
                    "contact.damping = \"{}\" under contact.law = \"hooke\" cannot be exported to \
                     Yade: its linear law (FrictPhys, CundallStrack) has no normal dashpot",
                    model.damping.kind().row().name
                ));
            }
            if let Some(other) = setup.spheres.iter().find(|s| s.radius != radius_f) {
                return refuse(format!(
                    "contact.law = \"hooke\" with spheres of several radii ({} and {} m) cannot \
                     be exported to Yade: FrictPhys makes k_n = 2 E_a D_a E_b D_b/(E_a D_a + \
                     E_b D_b) from the radii, one k for one radius only",
                    num(radius_f),
                    num(other.radius)
                ));
            }
            // k_t of a sphere pair (R_eff = R/2) and against a plane (R_eff = R).
            let kt =
                |other: &Material, r_eff: f64| 2.0 / 7.0 * effective_modulus(&fm, other) * r_eff;
            let nu_f = if frictional {
                kt(&fm, radius_f / 2.0) / k
            } else {
                0.0
            };
            let free_yade = YadeMaterial {
                young: k / radius_f,
                poisson: nu_f,
                friction_angle: mu_f.atan(),
            };
            let mut other_yade = Vec::new();
            for o in &others {
                if !frictional {
                    other_yade.push((k / radius_f, 0.0));
                    continue;
                }
                let t = kt(&o.material, if o.wall { radius_f } else { radius_f / 2.0 }) / k;
                // k_s = 2 k ν_f ν'/(ν_f + ν') = k t.
                let nu = if (t / (2.0 * nu_f) - 1.0).abs() < 1e-12 {
                    // The limit ν' → ∞: ν' = 1e12 ν_f gives k t (1 − 1e-12).
                    1e12 * nu_f
                } else if t < 2.0 * nu_f {
                    t * nu_f / (2.0 * nu_f - t)
                } else {
                    return refuse(format!(
                        "{}: its k_t = {} N/m is more than twice the spheres' and Yade's \
                         FrictPhys mixes k_s as a harmonic mean, which cannot reach it",
                        o.name,
                        num(k * t)
                    ));
                };
                other_yade.push((k / radius_f, nu));
            }
            comments.push(format!(
                "law: hooke k = {} N/m: FrictPhys k_n = 2 E_a D_a E_b D_b/(E_a D_a + E_b D_b) with young = k/R; k_s the same mean of E D nu, nu = k_t/k (k_t = 2/7 E_eff R_eff)",
                num(k)
            ));
            let mu_r_f = surface(free_material).1;
            if frictional && mu_r_f > 0.0 {
                let free_rolling = yade_rolling::free_spheres(k, mu_r_f, kt(&fm, radius_f / 2.0));
                let mut other_rolling = Vec::new();
                for o in &others {
                    let mu_r = mix_friction(mu_r_f, o.friction.1);
                    let ks = kt(&o.material, if o.wall { radius_f } else { radius_f / 2.0 });
                    other_rolling.push(
                        yade_rolling::other(free_rolling, k, mu_r, ks, o.wall).or_else(|why| {
                            refuse(format!(
                                "{} (set by {}; pair mu_r = {}) cannot be exported to Yade: {why}; \
                                 {}",
                                o.name,
                                o.rolling_key,
                                num(mu_r),
                                if o.wall {
                                    format!(
                                        "a plane needs a pair mu_r <= mu_r/2 of the spheres, i.e. \
                                         {} <= {} (docs/export-yade.md, \"Rolling friction\")",
                                        o.rolling_key,
                                        num(mu_r_f / 4.0)
                                    )
                                } else {
                                    format!("give {} the spheres' own value", o.rolling_key)
                                }
                            ))
                        })?,
                    );
                }
                comments.push(format!(
                    "rolling friction mu_r = {} of the spheres: CohFrictMat alphaKr, etaRoll with Yade's k_r = alpha k_s R^2 (alpha the harmonic mean) = dembound's 2.25 k mu_r^2 R_eff^2 and cap min(eta_1, eta_2) R |F_n| = mu_r R_eff |F_n| (R_eff = R/2 between spheres, R on a plane)",
                    num(mu_r_f)
                ));
                rolling = Some((free_rolling, other_rolling));
            }
            (
                "Ip2_FrictMat_FrictMat_FrictPhys()".to_string(),
                "Law2_ScGeom_FrictPhys_CundallStrack()",
                free_yade,
                other_yade,
            )
        }
        other => {
            return refuse(format!(
                "contact.law = \"{}\" cannot be exported to Yade for scenes (exported: hertz, \
                 hooke)",
                other.row().name
            ))
        }
    };
    // Friction angles: Yade takes the smaller of the two.
    let mut other_angles = Vec::new();
    for o in &others {
        let mu = mix_friction(mu_f, o.friction.0);
        if mu > mu_f {
            return refuse(format!(
                "{} with friction {} against spheres of friction {} cannot be exported to Yade: \
                 the pair's mu = sqrt(mu_a mu_b) = {} is above the spheres' own, and Yade takes \
                 the smaller friction angle of the two materials",
                o.name, o.friction.0, mu_f, mu
            ));
        }
        other_angles.push(mu.atan());
    }

    let sim = Simulation::new(setup.clone(), 1).map_err(|e| Error::Export(e.to_string()))?;
    let dt = sim.dt();
    let steps = sim.total_steps();
    let every = series_every(scene.file.output.series_every, steps);
    let g = setup.gravity;

    let mut x = String::new();
    let c = |x: &mut String, line: &str| {
        writeln!(x, "# {line}").ok();
    };
    c(&mut x, "Exported by `dembound export yade` from a dembound scene (SI units); scene.toml is the scene as resolved.");
    c(
        &mut x,
        &format!("Run: {COMMAND}. Every number below comes from dembound."),
    );
    c(
        &mut x,
        &format!(
            "spheres: {} (body ids in dembound's input order), then the plane walls as utils.wall",
            setup.spheres.len()
        ),
    );
    c(&mut x, "materials: the free spheres' own; every fixed sphere its own (Yade 2023.02a's Mindlin numbers between two");
    c(&mut x, "  spheres are dembound's); every wall a stand-in whose Yade stiffnesses against the free spheres are");
    c(
        &mut x,
        "  dembound's E_eff sqrt(R_eff) and 8 G* sqrt(R_eff) (docs/export-yade.md)",
    );
    for line in &comments {
        c(&mut x, line);
    }
    c(
        &mut x,
        &format!(
            "step: dt = {} s, {} steps; NewtonIntegrator(damping=0): leapfrog, Verlet's positions",
            num(dt),
            steps
        ),
    );
    c(&mut x, &format!("rows every {every} steps: {DUMP_FILE} (id x y z vx vy vz omegax omegay omegaz at the row's step) and {WALLS_FILE} (step, Fx Fy Fz N per wall)"));
    c(&mut x, &format!("{LOG}: the CPU time of the run as LAMMPS's `Loop time of T on 1 procs for N steps with M atoms`"));
    writeln!(x, "import time\nfrom yade import utils\n").ok();
    let bnd = |p: bool| if p { "True" } else { "False" };
    let periodic = d.periodic.iter().any(|p| *p);
    // Planes as boxes in a periodic cell: Yade's initial sweep along a
    // non-periodic axis (`periodic_box_sort_axis`).
    let sort_axis = if rolling.is_some() && periodic && !planes.is_empty() {
        match periodic_box_sort_axis(d.periodic) {
            Some(k) => format!(", sortAxis={k}"),
            None => {
                return refuse(format!(
                    "contact.rolling_friction = {} with plane walls in a domain periodic on \
                     every axis cannot be exported to Yade: each plane becomes a box wider than \
                     the period on every axis, which Yade's collider cannot sweep",
                    num(surface(free_material).1)
                ))
            }
        }
    } else {
        String::new()
    };
    // Non-periodic axes of a periodic scene: a cell long enough that nothing wraps.
    let cell: Vec<f64> = (0..3)
        .map(|k| {
            if d.periodic[k] {
                d.upper[k]
            } else {
                100.0 * (d.upper[k].abs() + (d.upper[k] - d.lower[k]))
            }
        })
        .collect();
    if d.periodic.iter().any(|p| *p) {
        let size: Vec<String> = cell.iter().map(|&c| num(c)).collect();
        writeln!(
            x,
            "O.periodic = True   # periodic axes x, y, z: {}, {}, {}; the others as long as 100 domains\n\
             O.cell.setBox({}, {}, {})",
            bnd(d.periodic[0]),
            bnd(d.periodic[1]),
            bnd(d.periodic[2]),
            size[0],
            size[1],
            size[2]
        )
        .ok();
        if d.lower.iter().zip(d.periodic).any(|(l, p)| !p && *l < 0.0) {
            return refuse(format!(
                "domain.lower = {:?} below 0 on a non-periodic axis of a periodic scene cannot be \
                 exported to Yade: its cell starts at 0",
                d.lower
            ));
        }
    }
    // FrictMat, or CohFrictMat with the rolling spring (twist free: alphaKtw 0).
    let material = |rolling: Option<yade_rolling::Rolling>| {
        match rolling {
        None => ("FrictMat", String::new()),
        Some(r) => (
            "CohFrictMat",
            format!(
                ", alphaKr={}, etaRoll={}, alphaKtw=0.0, etaTwist=0.0, momentRotationLaw=True, isCohesive=False",
                num(r.alpha_kr),
                num(r.eta_roll)
            ),
        ),
    }
    };
    let (class, extra) = material(rolling.as_ref().map(|r| r.0));
    writeln!(
        x,
        "free = O.materials.append({class}(young={}, poisson={}, density={}, frictionAngle={}{extra}))   # \"{}\"",
        num(free_yade.young),
        num(free_yade.poisson),
        num(fm.density),
        num(free_yade.friction_angle),
        setup.materials[free_material].name
    )
    .ok();
    writeln!(x, "other = []").ok();
    for (k, o) in others.iter().enumerate() {
        let (e, nu) = other_yade[k];
        let (class, extra) = material(rolling.as_ref().map(|r| r.1[k]));
        writeln!(
            x,
            "other.append(O.materials.append({class}(young={}, poisson={}, density={}, frictionAngle={}{extra})))   # {}: E = {} Pa, nu = {}",
            num(e),
            num(nu),
            num(o.material.density.max(1.0)),
            num(other_angles[k]),
            o.name,
            num(o.material.youngs_modulus),
            num(o.material.poisson_ratio)
        )
        .ok();
    }
    writeln!(
        x,
        "\n# masks: free 3, fixed 9, walls 18, avoidSelfInteractionMask 24: as in dembound, fixed \
         spheres meet\n# neither each other nor the walls (their forces would enter the wall forces)"
    )
    .ok();
    writeln!(x, "\n# x y z radius fixed material (-1: free)\nspheres = [").ok();
    for (i, s) in setup.spheres.iter().enumerate() {
        let p = s.position;
        writeln!(
            x,
            "    ({}, {}, {}, {}, {}, {}),",
            num(p[0]),
            num(p[1]),
            num(p[2]),
            num(s.radius),
            bnd(s.fixed),
            other_of_sphere[i].map_or(-1, |k| k as i64)
        )
        .ok();
    }
    writeln!(x, "]\nvelocities = [").ok();
    for &(i, s) in &free {
        let v = s.velocity;
        writeln!(x, "    ({i}, {}, {}, {}),", num(v[0]), num(v[1]), num(v[2])).ok();
    }
    writeln!(x, "]").ok();
    // Contacts at t = 0: leapfrog's v(−Δt/2) also takes their half kick,
    // −F_c/m Δt/2 (and −T/I Δt/2 on the spin), F_c dembound's contact force
    // at t = 0 (its force minus m g). Empty when no sphere touches anything.
    let (f0, t0) = (sim.forces(), sim.torques());
    writeln!(
        x,
        "# contacts at t = 0: body, then F_c/m and T/I (dembound's at t = 0) times dt/2\nkicks = ["
    )
    .ok();
    for &(i, s) in &free {
        let m = setup.materials[s.material].material.sphere_mass(s.radius);
        let inertia = 0.4 * m * s.radius * s.radius;
        let dv: Vec<f64> = (0..3).map(|k| (f0[i][k] / m - g[k]) * dt / 2.0).collect();
        let dw: Vec<f64> = (0..3).map(|k| t0[i][k] / inertia * dt / 2.0).collect();
        // Rounding of F = F_c + m g: |F_c| below 1e-12 m |g| is no contact.
        let floor = 1e-12 * (g[0] * g[0] + g[1] * g[1] + g[2] * g[2]).sqrt() * dt / 2.0;
        if dv.iter().chain(&dw).any(|v| v.abs() > floor) {
            writeln!(
                x,
                "    ({i}, {}, {}, {}, {}, {}, {}),",
                num(dv[0]),
                num(dv[1]),
                num(dv[2]),
                num(dw[0]),
                num(dw[1]),
                num(dw[2])
            )
            .ok();
        }
    }
    writeln!(x, "]").ok();
    writeln!(
        x,
        "for (px, py, pz, r, fixed, m) in spheres:\n\
         \x20   O.bodies.append(sphere((px, py, pz), r, material=(free if m < 0 else other[m]), fixed=fixed, mask=(9 if fixed else 3)))\n\
         walls = []"
    )
    .ok();
    for (k, &(w, axis, pos, _, side)) in planes.iter().enumerate() {
        if rolling.is_some() {
            // A box behind the plane (Yade has no ScGeom6D of utils.wall): its
            // face at the plane, as thick as the domain, 100 domains wide
            // (10 along a non-periodic axis of a periodic cell: there it must
            // stay below half the cell, see `periodic_box_sort_axis`).
            let mut centre = [0.0; 3];
            let mut half = [0.0; 3];
            for j in 0..3 {
                let size = d.upper[j] - d.lower[j];
                if j == axis {
                    half[j] = size;
                    centre[j] = pos - side * size;
                } else {
                    let domains = if periodic && !d.periodic[j] {
                        10.0
                    } else {
                        100.0
                    };
                    half[j] = domains * (d.upper[j].abs() + size);
                    centre[j] = 0.5 * (d.lower[j] + d.upper[j]);
                }
            }
            writeln!(
                x,
                "walls.append(({w}, O.bodies.append(box(({}, {}, {}), ({}, {}, {}), material=other[{}], fixed=True, mask=18))))   # the plane {} = {} as a box face",
                num(centre[0]), num(centre[1]), num(centre[2]),
                num(half[0]), num(half[1]), num(half[2]),
                other_of_plane[k],
                ["x", "y", "z"][axis],
                num(pos)
            )
            .ok();
        } else {
            writeln!(
                x,
                "walls.append(({w}, O.bodies.append(utils.wall({}, axis={axis}, material=other[{}], mask=18))))",
                num(pos),
                other_of_plane[k]
            )
            .ok();
        }
    }
    let groups: Vec<(usize, Vec<usize>)> = setup
        .walls
        .iter()
        .enumerate()
        .filter(|(_, wall)| wall.is_particles())
        .map(|(w, _)| {
            (
                w,
                setup
                    .spheres
                    .iter()
                    .enumerate()
                    .filter(|(_, s)| s.group == Some(w))
                    .map(|(i, _)| i)
                    .collect(),
            )
        })
        .collect();
    writeln!(
        x,
        "# boundary-particle walls: wall index, first and last body id"
    )
    .ok();
    write!(x, "particle_walls = [").ok();
    for (w, ids) in &groups {
        if let (Some(a), Some(b)) = (ids.first(), ids.last()) {
            write!(x, "({w}, {a}, {b}), ").ok();
        }
    }
    writeln!(x, "]\nwall_count = {}", setup.walls.len()).ok();
    let g_vec = format!("({}, {}, {})", num(g[0]), num(g[1]), num(g[2]));
    let (bound, geometry, physics, law) = if rolling.is_some() {
        (
            "Bo1_Box_Aabb()",
            "Ig2_Sphere_Sphere_ScGeom6D(), Ig2_Box_Sphere_ScGeom6D()",
            "Ip2_CohFrictMat_CohFrictMat_CohFrictPhys()".to_string(),
            "Law2_ScGeom6D_CohFrictPhys_CohesionMoment(useIncrementalForm=True, always_use_moment_law=True)",
        )
    } else {
        (
            "Bo1_Wall_Aabb()",
            "Ig2_Sphere_Sphere_ScGeom(), Ig2_Wall_Sphere_ScGeom()",
            physics,
            law,
        )
    };
    writeln!(
        x,
        "\ng = Vector3{g_vec}\n\
         O.dt = {dt}\n\
         O.engines = [\n\
         \x20   ForceResetter(),\n\
         \x20   InsertionSortCollider([Bo1_Sphere_Aabb(), {bound}], allowBiggerThanPeriod=True, avoidSelfInteractionMask=24{sort_axis}),\n\
         \x20   InteractionLoop([{geometry}], [{physics}], [{law}]),\n\
         \x20   # before the integrator: positions, forces and torques of step O.iter\n\
         \x20   PyRunner(command='record()', iterPeriod={every}, initRun=True),\n\
         \x20   PyRunner(command='add_wall_forces()', iterPeriod=1),\n\
         \x20   NewtonIntegrator(damping=0.0, gravity=g),\n\
         ]\n\
         # leapfrog stores v(t - dt/2): start from v0 - g dt/2, minus the contacts' half kick at t = 0\n\
         for (i, vx, vy, vz) in velocities:\n\
         \x20   O.bodies[i].state.vel = Vector3(vx, vy, vz) - g * (O.dt / 2)\n\
         for (i, ax, ay, az, bx, by, bz) in kicks:\n\
         \x20   O.bodies[i].state.vel -= Vector3(ax, ay, az)\n\
         \x20   O.bodies[i].state.angVel -= Vector3(bx, by, bz)\n\
         \n\
         dump = open('{DUMP_FILE}', 'w')\n\
         wallfile = open('{WALLS_FILE}', 'w')\n\
         wallfile.write('# step then Fx Fy Fz (N) of each wall in file order: the force the spheres exert on it\\n')\n\
         meanfile = open('{WALLS_MEAN_FILE}', 'w')\n\
         meanfile.write('# step then Fx Fy Fz (N) of each wall in file order, each the mean over every step since the previous row (the row of step k: steps k-{last} ... k)\\n')\n\
         n = len(spheres)\n\
         \n\
         # a boundary-particle wall's force: each component summed over its spheres in id order\n\
         # by Yade (utils.sumForces: the same additions as a sum of the Vector3s, without Python per sphere)\n\
         particle_wall_ids = [(w, list(range(a, b + 1))) for (w, a, b) in particle_walls]\n\
         axes = (Vector3(1, 0, 0), Vector3(0, 1, 0), Vector3(0, 0, 1))\n\
         \n\
         def wall_forces():\n\
         \x20   f = [Vector3(0, 0, 0) for k in range(wall_count)]\n\
         \x20   for (w, body) in walls:\n\
         \x20       f[w] = O.forces.f(body)\n\
         \x20   for (w, ids) in particle_wall_ids:\n\
         \x20       f[w] = Vector3(*(utils.sumForces(ids, axis) for axis in axes))\n\
         \x20   return f\n\
         \n\
         # every step's wall forces summed from step 1; at each row their mean, then the sum restarts\n\
         force_sum = [Vector3(0, 0, 0) for k in range(wall_count)]\n\
         summed = 0\n\
         \n\
         def add_wall_forces():\n\
         \x20   global summed\n\
         \x20   if O.iter == 0:\n\
         \x20       return\n\
         \x20   for (w, F) in enumerate(wall_forces()):\n\
         \x20       force_sum[w] += F\n\
         \x20   summed += 1\n\
         \x20   if O.iter % {every} == 0:\n\
         \x20       meanfile.write('%d' % O.iter + ''.join(' %.17g %.17g %.17g' % (F[0] / summed, F[1] / summed, F[2] / summed) for F in force_sum) + '\\n')\n\
         \x20       for w in range(wall_count):\n\
         \x20           force_sum[w] = Vector3(0, 0, 0)\n\
         \x20       summed = 0\n\
         \n\
         def record():\n\
         \x20   dump.write('ITEM: TIMESTEP\\n%d\\nITEM: NUMBER OF ATOMS\\n%d\\nITEM: ATOMS id x y z vx vy vz omegax omegay omegaz\\n' % (O.iter, n))\n\
         \x20   h = O.dt / 2\n\
         \x20   for i in range(n):\n\
         \x20       b = O.bodies[i]\n\
         \x20       s = b.state\n\
         \x20       if b.dynamic:\n\
         \x20           v = s.vel + (O.forces.f(i) / s.mass + g) * h\n\
         \x20           w = s.angVel + O.forces.t(i) / s.inertia[0] * h\n\
         \x20       else:\n\
         \x20           v = w = Vector3(0, 0, 0)\n\
         \x20       p = s.pos\n\
         \x20       dump.write('%d %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g\\n' % (i + 1, p[0], p[1], p[2], v[0], v[1], v[2], w[0], w[1], w[2]))\n\
         \x20   wallfile.write('%d' % O.iter + ''.join(' %.17g %.17g %.17g' % (F[0], F[1], F[2]) for F in wall_forces()) + '\\n')\n\
         \n\
         # {steps} steps and one more, whose recorder (before the integrator) writes the state of step {steps}\n\
         clock = time.process_time()\n\
         O.run({run}, True)\n\
         seconds = time.process_time() - clock\n\
         dump.close()\n\
         wallfile.close()\n\
         meanfile.close()\n\
         with open('{LOG}', 'w') as log:\n\
         \x20   log.write('Yade, one thread: the CPU time of O.run\\n')\n\
         \x20   log.write('Loop time of %r on 1 procs for %d steps with %d atoms\\n' % (seconds, {run}, len(velocities)))",
        dt = num(dt),
        run = steps + 1,
        last = every - 1,
    )
    .ok();
    Ok(Deck {
        code: Code::Yade,
        files: vec![DeckFile {
            name: SCRIPT.into(),
            text: x,
        }],
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use dembound_scene::io::{config, resolve::resolve};

    const SCENE: &str = r#"
[domain]
lower = [0.0, 0.0, 0.0]
upper = [0.01, 0.01, 0.01]
[[material]]
name = "a"
density = 1000.0
youngs_modulus = 1.0e7
poisson_ratio = 0.3
[[material]]
name = "b"
density = 2500.0
youngs_modulus = 5.0e7
poisson_ratio = 0.2
[contact]
law = "hertz"
friction = 0.5
[[particles]]
spheres = [ { position = [0.002, 0.005, 0.005], radius = 1.0e-3, velocity = [0.1, 0.0, 0.0] } ]
material = "a"
[[particles]]
spheres = [ { position = [0.005, 0.005, 0.005], radius = 0.7e-3 } ]
material = "b"
fixed = true
[[wall]]
plane = { point = [0.0, 0.0, 0.0], normal = [0.0, 0.0, 1.0] }
material = "a"
[integration]
dt = 1.0e-6
steps = 10
"#;

    fn exported(sets: &[&str]) -> Result<Deck> {
        let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
        let file = config::load(SCENE, "test", &sets).expect("a valid scene");
        let scene = resolve(&file, std::path::Path::new(".")).expect("resolves");
        deck(&scene)
    }

    /// Yade 2023.02a's Mindlin numbers (HertzMindlin.cpp, written out here;
    /// the installed Yade's `kno` and `kso`, docs/export-yade.md "Stand-in
    /// materials, exactly") for a pair of FrictMats (E, ν) at R* = ρ R:
    /// (k_n⁰, k_s⁰)/√R.
    fn yade_mindlin(a: (f64, f64), b: (f64, f64), rho: f64) -> (f64, f64) {
        let e = a.0 * b.0 / ((1.0 - a.1 * a.1) * b.0 + (1.0 - b.1 * b.1) * a.0);
        let g = |m: (f64, f64)| m.0 / (2.0 * (1.0 + m.1));
        let g_y = 1.0 / ((2.0 - a.1) / g(a) + (2.0 - b.1) / g(b));
        (4.0 / 3.0 * e * rho.sqrt(), 8.0 * g_y * rho.sqrt())
    }

    /// dembound's eq 6 and 8 G* (written out, not through the physics crate).
    fn dembound_pair(a: (f64, f64), b: (f64, f64)) -> (f64, f64) {
        let e = 4.0 / 3.0 / ((1.0 - a.1 * a.1) / a.0 + (1.0 - b.1 * b.1) / b.0);
        let g = |m: (f64, f64)| m.0 / (2.0 * (1.0 + m.1));
        let g_star = 1.0 / ((2.0 - a.1) / g(a) + (2.0 - b.1) / g(b));
        (e, 8.0 * g_star)
    }

    /// The written-out Yade numbers are the installed Yade's: `kno` and
    /// `kso` that Yade 2023.02a computed (`O.interactions[i, j].phys` after
    /// one step, printed to 17 digits) for a free sphere (E 1e7 Pa, ν 0.3,
    /// R 0.5 mm) on a fixed sphere (R 2 mm) and on `utils.wall`, with the
    /// stand-ins the deck wrote before (solved for the older formula with
    /// averaged G and ν) and with those it writes now (scene A's floor, E
    /// 1e8 Pa, ν 0.3, ζ = 10; its walls of the spheres' material).
    #[test]
    fn yades_mindlin_numbers_are_the_installed_yades() {
        let free = (1.0e7, 0.3);
        let sphere: f64 = 0.5e-3 * 2.0e-3 / 2.5e-3;
        let wall: f64 = 0.5e-3;
        for (other, rho, r_eff, kno, kso) in [
            // The floor's earlier stand-in: k_s 17 % below dembound's.
            (
                (2.914985208583392e7, 8.571676300578035e-1),
                1.0,
                sphere,
                266400.26640026644,
                272283.83854648256,
            ),
            // The walls' earlier stand-in: k_s 7.5 % below dembound's.
            (
                (1.924981287470848e7, 5.238400953609688e-1),
                0.5,
                wall,
                163814.5038461384,
                187197.47849947645,
            ),
            // Now: the floor's own material, and the walls' stand-in.
            (
                (1.0e8, 0.3),
                1.0,
                sphere,
                266400.2664002664,
                329082.68202385854,
            ),
            (
                (24142135.62373094, 0.3),
                0.5,
                wall,
                163814.5038461384,
                202359.09298640623,
            ),
        ] {
            let (kn, ks) = yade_mindlin(free, other, rho);
            let (kn, ks) = (kn * r_eff.sqrt(), ks * r_eff.sqrt());
            // Round-off of a dozen operations in either code: 1e-13.
            assert!(
                (kn / kno - 1.0).abs() < 1e-13 && (ks / kso - 1.0).abs() < 1e-13,
                "{other:?}: ({kn}, {ks}) against Yade's ({kno}, {kso})"
            );
        }
        // The stand-in of the plane walls is the material Yade was given.
        let m = |e: f64, nu: f64| Material {
            density: 1000.0,
            youngs_modulus: e,
            poisson_ratio: nu,
        };
        let (e, nu) = stand_in(&m(1.0e7, 0.3), &m(1.0e7, 0.3), 0.5).expect("exists");
        assert!((e / 24142135.62373094 - 1.0).abs() < 1e-13 && (nu - 0.3).abs() < 1e-13);
    }

    #[test]
    fn stand_in_materials_give_yade_dembounds_stiffnesses() {
        let m = |e: f64, nu: f64| Material {
            density: 1000.0,
            youngs_modulus: e,
            poisson_ratio: nu,
        };
        for (other, rho) in [
            ((1.0e8, 0.3), 1.0),
            ((5.0e7, 0.2), 1.0),
            ((1.0e7, 0.3), 0.5),
            ((2.0e7, 0.25), 0.5),
        ] {
            let free = (1.0e7, 0.3);
            let s = stand_in(&m(free.0, free.1), &m(other.0, other.1), rho).expect("exists");
            let (kn, ks) = yade_mindlin(free, s, rho);
            let (e, kt) = dembound_pair(free, other);
            // Round-off of a dozen operations: 1e-13.
            assert!((kn / e - 1.0).abs() < 1e-13, "{other:?} {rho}: {kn} vs {e}");
            assert!(
                (ks / kt - 1.0).abs() < 1e-13,
                "{other:?} {rho}: {ks} vs {kt}"
            );
        }
        // A rigid wall against utils.wall (R* = R/2) needs E_mix = sqrt(2)
        // E_eff of the sphere alone: no finite material gives it.
        assert!(stand_in(&m(1.0e7, 0.3), &Material::rigid(1.0), 0.5).is_none());
    }

    #[test]
    fn the_script_holds_dembounds_numbers() {
        let d = exported(&[]).expect("exports");
        let s = &d.files[0].text;
        assert_eq!(d.files[0].name, SCRIPT);
        // The free material as given, mu = 0.5 as an angle.
        assert!(s.contains(&format!(
            "free = O.materials.append(FrictMat(young=1e7, poisson=3e-1, density=1e3, frictionAngle={}))",
            num(0.5f64.atan())
        )));
        // The fixed sphere of "b" and the plane of "a": stand-ins whose
        // Yade stiffnesses are dembound's.
        let materials: Vec<(f64, f64)> = s
            .lines()
            .filter(|l| l.starts_with("other.append("))
            .map(|l| {
                let get = |key: &str| -> f64 {
                    let at = l.find(key).expect("the key") + key.len();
                    l[at..]
                        .split([',', ')'])
                        .next()
                        .expect("a value")
                        .parse()
                        .expect("a number")
                };
                (get("young="), get("poisson="))
            })
            .collect();
        assert_eq!(materials.len(), 2);
        let free = (1.0e7, 0.3);
        for (k, (other, rho)) in [((5.0e7, 0.2), 1.0), ((1.0e7, 0.3), 0.5)]
            .into_iter()
            .enumerate()
        {
            let (kn, ks) = yade_mindlin(free, materials[k], rho);
            let (e, kt) = dembound_pair(free, other);
            assert!((kn / e - 1.0).abs() < 1e-13 && (ks / kt - 1.0).abs() < 1e-13);
        }
        assert!(s.contains("utils.wall(0, axis=2, material=other[1], mask=18)"));
        assert!(s.contains("O.dt = 1e-6") && s.contains("O.run(11, True)"));
        assert!(s.contains("NewtonIntegrator(damping=0.0, gravity=g)"));
        assert!(s.contains("(0, 1e-1, 0, 0),"));
    }

    /// walls_mean.txt: a runner every step before the integrator (the
    /// forces of step O.iter, as the recorder's) sums each wall's force
    /// from step 1 and writes the mean at every multiple of the cadence,
    /// then starts again; walls.txt keeps the row's own step.
    #[test]
    fn the_script_averages_the_wall_forces_over_every_step() {
        let d = exported(&["output.series_every=5"]).expect("exports");
        let s = &d.files[0].text;
        // Each line must be there (an absent one fails here, not as a
        // `None` that compares below every position).
        let at = |line: &str| s.find(line).unwrap_or_else(|| panic!("{line}\n{s}"));
        let record = at("PyRunner(command='record()', iterPeriod=5, initRun=True),\n");
        let add = at("PyRunner(command='add_wall_forces()', iterPeriod=1),\n");
        let newton = at("NewtonIntegrator(damping=0.0, gravity=g),");
        assert!(record < add && add < newton, "{s}");
        for line in [
            "meanfile = open('walls_mean.txt', 'w')\n",
            "(the row of step k: steps k-4 ... k)",
            "    if O.iter == 0:\n        return\n",
            "        force_sum[w] += F\n    summed += 1\n    if O.iter % 5 == 0:\n",
            "' %.17g %.17g %.17g' % (F[0] / summed, F[1] / summed, F[2] / summed) for F in force_sum",
            "            force_sum[w] = Vector3(0, 0, 0)\n        summed = 0\n",
            "for F in wall_forces()) + '\\n')\n",
            "meanfile.close()\n",
        ] {
            assert!(s.contains(line), "{line}\n{s}");
        }
    }

    #[test]
    fn tsuji_damping_is_betan_alpha_over_sqrt_6() {
        let d = exported(&[
            "contact.damping=tsuji",
            "contact.restitution=0.5",
            "contact.tangential_damping=false",
        ])
        .expect("exports");
        let s = &d.files[0].text;
        let at = s.find("betan=").expect("betan") + 6;
        let betan: f64 = s[at..]
            .split(',')
            .next()
            .expect("v")
            .parse()
            .expect("a number");
        let at = s
            .find("= gamma/(sqrt(m_eff E_eff) R_eff^(1/4)) = ")
            .expect("alpha")
            + 42;
        let alpha: f64 = s[at..]
            .split(';')
            .next()
            .expect("v")
            .parse()
            .expect("a number");
        assert!((betan - alpha / 6f64.sqrt()).abs() < 1e-15 * alpha);
        assert!(s.contains("betas=0.0"));
    }

    #[test]
    fn hooke_maps_to_frictphys() {
        let d = exported(&[
            "contact.law={hooke=50.0}",
            "contact.tangential=linear",
            "particles.1.spheres.0.radius=1.0e-3",
        ])
        .expect("exports");
        let s = &d.files[0].text;
        // young = k/R; poisson = k_t/k with k_t = 2/7 E_eff R/2.
        let e_eff = 4.0 / 3.0 / (2.0 * 0.91 / 1.0e7);
        assert!(s.contains(&format!(
            "young={}, poisson={}",
            num(50.0 / 1.0e-3),
            num(2.0 / 7.0 * e_eff * 0.5e-3 / 50.0)
        )));
        assert!(s.contains("Ip2_FrictMat_FrictMat_FrictPhys()"));
    }

    #[test]
    fn hooke_rolling_friction_maps_to_cohfrictmat() {
        let hooke = [
            "contact.law={hooke=50.0}",
            "contact.tangential=linear",
            "particles.1.spheres.0.radius=1.0e-3",
            "contact.rolling_friction=0.1",
        ];
        // The plane at the spheres' own mu_r: its cap mu_r R is twice what
        // min(eta_1, eta_2) R reaches.
        let mut sets = hooke.to_vec();
        let e = exported(&sets).expect_err("refused").to_string();
        assert!(
            e.contains("wall[0].rolling_friction") && e.contains("Yade"),
            "{e}"
        );
        sets.push("wall.0.rolling_friction=0.025");
        let d = exported(&sets).expect("exports");
        let s = &d.files[0].text;
        // alpha_s = 9 k mu_r^2/(16 k_s), k_s = 2/7 E_eff R/2; eta_s = mu_r/2.
        let ks = 2.0 / 7.0 * (4.0 / 3.0 / (2.0 * 0.91 / 1.0e7)) * 0.5e-3;
        assert!(s.contains(&format!(
            "alphaKr={}, etaRoll={}",
            num(9.0 * 50.0 * 0.01 / (16.0 * ks)),
            num(0.05)
        )));
        assert!(s.contains("Law2_ScGeom6D_CohFrictPhys_CohesionMoment(useIncrementalForm=True, always_use_moment_law=True)"));
        assert!(s.contains("Ig2_Box_Sphere_ScGeom6D()") && s.contains("box((5e-3, 5e-3, -1e-2)"));
        assert!(!s.contains("sortAxis"));
        // Periodic with a plane: the collider sweeps along z, the box is 100
        // periods wide on x and y (cell z: 100 (|upper| + size) = 2 m).
        sets.push("domain.periodic=[true,true,false]");
        let d = exported(&sets).expect("exports");
        let s = &d.files[0].text;
        assert!(s.contains("avoidSelfInteractionMask=24, sortAxis=2)"));
        assert!(s.contains("O.cell.setBox(1e-2, 1e-2, 2e0)"));
        assert!(s.contains("box((5e-3, 5e-3, -1e-2), (2e0, 2e0, 1e-2)"));
    }

    #[test]
    fn periodic_boxes_are_swept_along_a_non_periodic_axis() {
        assert_eq!(periodic_box_sort_axis([true, true, false]), Some(2));
        assert_eq!(periodic_box_sort_axis([true, false, false]), Some(1));
        assert_eq!(periodic_box_sort_axis([false, true, true]), Some(0));
        assert_eq!(periodic_box_sort_axis([true; 3]), None);
    }

    #[test]
    fn refusals_name_the_key_and_yade() {
        for (sets, key) in [
            (vec!["integration.scheme=gear5"], "integration.scheme"),
            (vec!["wall.0.motion.velocity=[0,0.1,0]"], "wall[0].motion"),
            (
                vec!["wall.0.servo={force=1,axis=[1,0,0],max_velocity=0.1}"],
                "wall[0].servo",
            ),
            (vec!["domain.outside=delete"], "domain.outside"),
            (vec!["wall.0.plane.normal=[0,1,1]"], "wall[0].plane"),
            (
                vec!["contact.rolling_friction=0.1"],
                "contact.rolling_friction",
            ),
            (vec!["contact.tangential=linear"], "contact.tangential"),
            (
                vec!["contact.law={hooke=50.0}", "contact.tangential=linear"],
                "contact.law = \"hooke\" with spheres of several radii",
            ),
            (
                vec!["contact.damping=tsuji", "contact.restitution=0.5"],
                "contact.tangential_damping",
            ),
            (
                vec![
                    "contact.damping=tsuji",
                    "contact.restitution=0.5",
                    "contact.tangential_damping=false",
                    "contact.attractive=true",
                ],
                "contact.attractive",
            ),
            (
                vec![
                    "contact.damping=tsuji",
                    "contact.damping_coefficient=1e-3",
                    "contact.tangential_damping=false",
                ],
                "contact.damping_coefficient",
            ),
            (vec!["contact.law=linear"], "contact.law"),
            (vec!["particles.1.fixed=false"], "free spheres of materials"),
            (vec!["material.1.friction=0.9"], "above the spheres' own"),
        ] {
            let e = exported(&sets).expect_err("refused");
            let text = e.to_string();
            assert!(
                text.contains(key) && text.contains("Yade"),
                "{sets:?}: {text}"
            );
        }
    }
}
