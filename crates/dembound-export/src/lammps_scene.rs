//! A many-particle scene (`dembound scene`'s TOML) as a LAMMPS deck: the
//! spheres as a data file (`atom_style sphere`), one atom type per
//! material of the free spheres and one per material of the fixed
//! (boundary) spheres, every type pair's coefficient written explicitly
//! with dembound's own mixing, plane walls as `fix wall/gran` with the
//! pre-mixed modulus, a thermo line of kinetic energy and contact counts
//! (docs/export-lammps.md, "Scenes").
//!
//! Why `hertz` with k_n = E_eff and not `hertz/material`: LAMMPS's
//! granular `hertz` is F = k_n a δ with a = √(R δ), R = R_i R_j/(R_i + R_j)
//! its own per-pair radius, so k_n = E_eff (dembound's eq 6 modulus, the
//! 4/3 included) gives dembound's F = E_eff √R_eff h^(3/2) for any radii:
//! exact for every pair, polydisperse or not. `hertz/material E ν`, given
//! explicitly for a pair i j, is read as two bodies of the same E and ν
//! (k_n = 4/3 E/(2(1 − ν²))), so it could be made to give E_eff too
//! (E = 3/2 E_eff (1 − ν²) for any ν), but then the number in the deck is
//! not a material's modulus and invites the reader to "correct" it; left to
//! LAMMPS's own mixing (only `i i` given) it mixes the cross pairs by its
//! own rule, which the single-contact pitfall `auto-mix` shows failing.
//! The absolute `hertz` form says what it is.
//!
//! Frozen spheres: dembound's fixed spheres have infinite mass and never
//! move. In the deck they are types of their own in group `frozen`: not
//! integrated, zero velocity, under `fix freeze` (which zeroes their force
//! and, read by `pair granular`, makes the pair's mass the free sphere's
//! alone, m_eff = m_i, dembound's limit for an infinite mass: it matters
//! for the Tsuji damping), and `neigh_modify exclude group frozen frozen`
//! (two fixed spheres never interact, as in dembound).

pub use crate::lammps_friction::torque_arm_note;
use crate::lammps_friction::{self, Surface};
use crate::{
    lammps::tsuji_input, lammps_gates, lammps_motion, lammps_output, num, Code, Deck, DeckFile,
    Error, Result,
};
use dembound_physics::contact::{DampingKind, DampingPair, Dissipation, NormalLaw};
use dembound_physics::material::{effective_modulus, Material, PairProperties};
use dembound_scene::io::resolve::ResolvedScene;
use dembound_scene::setup::{Scheme, SphereInit, WallSetup};
use dembound_scene::Simulation;
use std::fmt::Write;

/// The data file the deck reads.
pub const DATA_FILE: &str = "particles.data";

/// One LAMMPS atom type: a material, free or fixed.
#[derive(Debug, Clone, Copy, PartialEq)]
struct AtomType {
    material: usize,
    fixed: bool,
    /// A sphere of a boundary-particle wall (dembound counts its contacts
    /// as wall contacts; a fixed sphere of a `[[particles]]` group counts
    /// as a particle contact).
    wall: bool,
}

/// The contact model's arguments for one pair of the deck.
/// `tangential`: the `tangential … [rolling …]` arguments
/// ([`FRICTIONLESS`] without friction).
fn model_args(normal: &str, modulus: f64, damping: &Damping, tangential: &str) -> String {
    match damping {
        Damping::None => format!(
            "{normal} {} 0.0 {tangential} damping velocity",
            num(modulus)
        ),
        Damping::Tsuji { e_input, clamp } => format!(
            "{normal} {} {} {tangential} damping tsuji{}",
            num(modulus),
            num(*e_input),
            if *clamp { " limit_damping" } else { "" }
        ),
    }
}

/// The tangential arguments of a frictionless pair.
const FRICTIONLESS: &str = "tangential linear_nohistory 0.0 0.0";

/// The damping as the deck writes it (the same for every pair).
#[derive(Debug, Clone, Copy, PartialEq)]
enum Damping {
    None,
    /// `damping tsuji` given `e_input`, the e whose LAMMPS polynomial α is
    /// dembound's γ/(√(m_eff E_eff) R_eff^(1/4)), the same for every pair
    /// when γ comes from a restitution (γ = √5 ξ(e) √(k m)).
    Tsuji {
        e_input: f64,
        clamp: bool,
    },
}

/// The normal law's LAMMPS name and its coefficient for a pair of
/// effective modulus `modulus`.
fn normal_coefficient(law: &NormalLaw, modulus: f64) -> (&'static str, f64) {
    match law {
        NormalLaw::Hooke { stiffness } => ("hooke", *stiffness),
        _ => ("hertz", modulus),
    }
}

/// The deck of a resolved scene: `in.lammps` and [`DATA_FILE`].
pub fn deck(scene: &ResolvedScene) -> Result<Deck> {
    let setup = &scene.setup;
    let model = &setup.contact;
    let refuse = |s: String| Err(Error::Export(s));
    if setup.integration.scheme != Scheme::Verlet {
        return refuse(
            "integration.scheme = \"gear5\" cannot be exported: LAMMPS integrates with velocity \
             Verlet (fix nve/sphere); set integration.scheme = \"verlet\" to get a deck that \
             runs the same scheme as dembound"
                .into(),
        );
    }
    // Moving walls and groups: `fix move` on groups of spheres, `fix
    // wall/gran … shear` on sliding planes, the rest refused
    // (lammps_motion.rs).
    lammps_motion::refuse_other_moving_walls(setup)?;
    let moves = lammps_motion::group_moves(setup)?;
    // Inlets: dembound's placements replayed (lammps_inlets.rs).
    crate::lammps_inlets::refuse(setup, !moves.is_empty())?;
    let inserts = !setup.inlets.is_empty();
    let outlets = crate::outlets::plan(setup, "LAMMPS", Some("free"), "state")?;
    crate::refuse_servo_walls(setup, "LAMMPS")?;
    // The deck writes planes and walls of boundary particles; every other
    // wall type says why LAMMPS cannot hold it (`WallType::export_note`).
    for (w, wall) in setup.walls.iter().enumerate() {
        let written = matches!(wall, WallSetup::Plane(_)) || wall.is_particles();
        let note = wall.export_note().or_else(|| {
            (!written).then(|| "the deck has no LAMMPS counterpart for it".to_string())
        });
        if let Some(note) = note {
            let kind = wall.key();
            return refuse(format!(
                "`wall[{w}].{kind}` cannot be exported yet: {note}; remove the {kind} (or \
                 replace it by planes) to export the scene"
            ));
        }
    }
    // Friction (lammps_friction.rs): None for a frictionless deck.
    let friction = lammps_friction::plan(setup)?;
    match model.normal {
        NormalLaw::Hertz | NormalLaw::Hooke { .. } => {}
        other => {
            return refuse(format!(
                "contact.law = \"{}\" is not exported for scenes (exported: hertz, hooke): LAMMPS \
                 `hooke` takes an absolute k_n, and dembound's linear k = E_eff R_eff changes \
                 from pair to pair",
                other.row().name
            ))
        }
    }
    // The engine validates the setup and fixes Δt and the run length.
    let sim = Simulation::new(setup.clone(), 1).map_err(|e| Error::Export(e.to_string()))?;
    let dt = sim.dt();
    let steps = sim.total_steps();
    let windows = lammps_gates::windows(setup, dt)?;
    let every = lammps_output::series_every(scene.file.output.series_every, steps);

    // Atom types: the free materials in material order (with the inlets'
    // materials), then the fixed ones.
    let mut types: Vec<AtomType> = Vec::new();
    let kind = |s: &SphereInit| AtomType {
        material: s.material,
        fixed: s.fixed,
        wall: s.group.is_some(),
    };
    for (fixed, wall) in [(false, false), (true, false), (true, true)] {
        for material in 0..setup.materials.len() {
            let t = AtomType {
                material,
                fixed,
                wall,
            };
            let inserted = !fixed && setup.inlets.iter().any(|i| i.material == material);
            if inserted || setup.spheres.iter().any(|s| kind(&s) == t) {
                types.push(t);
            }
        }
    }
    let type_of =
        |s: &SphereInit| -> usize { 1 + types.iter().position(|t| *t == kind(s)).unwrap_or(0) };
    let material = |k: usize| -> &Material { &setup.materials[k].material };
    let name = |k: usize| -> &str { &setup.materials[k].name };
    // Each type's one radius, if all its spheres share it (the linear
    // tangential spring's R_eff per type pair).
    let radius: Vec<Option<f64>> = types
        .iter()
        .map(|t| {
            // An inlet's smallest and largest radius: one radius if fixed.
            let inserted = setup
                .inlets
                .iter()
                .filter(|i| !t.fixed && i.material == t.material)
                .flat_map(|i| <[f64; 2]>::from(i.size.radius_range()));
            let mut radii = setup
                .spheres
                .iter()
                .filter(|s| kind(s) == *t)
                .map(|s| s.radius)
                .chain(inserted);
            let first = radii.next();
            first.filter(|r| radii.all(|q| q == *r))
        })
        .collect();
    let surface = |t: usize| Surface {
        material: material(types[t].material),
        coefficients: setup
            .friction
            .as_ref()
            .map_or((0.0, 0.0), |f| f.of_material(types[t].material)),
        radius: radius[t],
        plane: false,
    };

    // The damping, the same for every pair, or a refusal naming the key.
    let damping = match (model.damping.kind(), model.damping.dissipation()) {
        (DampingKind::None, _) => Damping::None,
        (DampingKind::Tsuji, Some(Dissipation::Restitution(_))) => {
            // α of one pair that occurs, then checked on every type pair.
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
            // A free sphere of the scene, else an inlet's largest.
            let free = setup
                .spheres
                .iter()
                .find(|s| !s.fixed)
                .map(|s| (s.radius, s.material))
                .or_else(|| {
                    setup
                        .inlets
                        .first()
                        .map(|i| (i.size.max_radius(), i.material))
                });
            let Some((radius, mat)) = free else {
                return Err(crate::no_free_sphere("LAMMPS"));
            };
            let m = material(mat);
            let reference = alpha(&PairProperties::spheres(
                radius,
                m.sphere_mass(radius),
                m,
                radius,
                m.sphere_mass(radius),
                m,
            ));
            let other = alpha(&PairProperties::sphere_plane(
                2.0 * radius,
                m.sphere_mass(radius),
                m,
                &Material::rigid(1.0),
            ));
            let same = (other / reference - 1.0).abs() < 1e-9;
            if !same {
                return refuse(format!(
                    "contact.damping = \"tsuji\": the damping is not the same multiple of \
                     sqrt(m_eff E_eff) R_eff^(1/4) for every pair (alpha {reference} and {other}); \
                     LAMMPS's damping tsuji needs one"
                ));
            }
            Damping::Tsuji {
                e_input: tsuji_input(reference)?,
                clamp: !model.attractive,
            }
        }
        (DampingKind::Tsuji, _) => return refuse(
            "contact.damping_coefficient cannot be exported for scenes: an absolute Tsuji gamma \
                 is a different multiple of sqrt(m_eff E_eff) R_eff^(1/4) for each pair, and \
                 LAMMPS's damping tsuji takes one; give contact.restitution instead"
                .into(),
        ),
        (kind, _) => {
            return refuse(format!(
                "contact.damping = \"{}\" is not exported to LAMMPS for scenes yet (exported: \"none\", and \
                 \"tsuji\" given by contact.restitution); the bounce scenario export maps it \
                 (`dembound export lammps SCENARIO.toml`)",
                kind.row().name
            ))
        }
    };

    // Every type pair that meets: E_eff finite.
    let pair_modulus = |a: &AtomType, b: &AtomType| -> Result<f64> {
        let e = effective_modulus(material(a.material), material(b.material));
        if e.is_finite() && e > 0.0 {
            Ok(e)
        } else {
            Err(Error::Export(format!(
                "`material[{}].youngs_modulus` and `material[{}].youngs_modulus` = inf \
                 (materials \"{}\" and \"{}\", both rigid) cannot be exported to LAMMPS: their \
                 contact has no finite stiffness for pair granular",
                a.material,
                b.material,
                name(a.material),
                name(b.material)
            )))
        }
    };

    // Plane walls: `fix wall/gran` for a normal along x, y or z, `fix
    // wall/gran/region` on a plane region otherwise (the same contact: the
    // distance to the plane; the steel-floor bed of tests/export_codes.rs
    // with its five walls rewritten by hand as regions ends in the same
    // kinetic energy to the last digit).
    struct Plane {
        index: usize,
        point: [f64; 3],
        /// Unit normal into the domain.
        normal: [f64; 3],
        /// The axis of an axis-aligned plane.
        axis: Option<usize>,
        material: usize,
    }
    let mut planes = Vec::new();
    for (index, w) in setup.walls.iter().enumerate() {
        if let WallSetup::Plane(dembound_scene::setup::Plane {
            point,
            normal,
            material,
        }) = *w
        {
            let length =
                (normal[0] * normal[0] + normal[1] * normal[1] + normal[2] * normal[2]).sqrt();
            let nonzero: Vec<usize> = (0..3).filter(|&k| normal[k] != 0.0).collect();
            planes.push(Plane {
                index,
                point,
                normal: normal.map(|c| c / length),
                axis: (nonzero.len() == 1).then(|| nonzero[0]),
                material,
            });
        }
    }

    let free_types: Vec<usize> = (0..types.len()).filter(|&t| !types[t].fixed).collect();
    let fixed_types: Vec<usize> = (0..types.len()).filter(|&t| types[t].fixed).collect();
    let wall_types: Vec<usize> = (0..types.len()).filter(|&t| types[t].wall).collect();
    let held_types: Vec<usize> = (0..types.len())
        .filter(|&t| types[t].fixed && !types[t].wall)
        .collect();
    if free_types.is_empty() {
        return Err(crate::no_free_sphere("LAMMPS"));
    }

    // The data file.
    let d = &setup.domain;
    let mut lo = d.lower;
    let mut hi = d.upper;
    for s in &setup.spheres {
        for k in 0..3 {
            if !d.periodic[k] {
                lo[k] = lo[k].min(s.position[k] - s.radius);
                hi[k] = hi[k].max(s.position[k] + s.radius);
            }
        }
    }
    // An inlet's sphere is created one step back along its flight
    // (lammps_inlets.rs): the box holds its region grown by that step.
    for i in &setup.inlets {
        let (a, b) = i.region.bounds();
        for k in 0..3 {
            let back = 2.0 * (i.velocity[k].abs() + setup.gravity[k].abs() * dt) * dt;
            if !d.periodic[k] {
                lo[k] = lo[k].min(a[k] - back);
                hi[k] = hi[k].max(b[k] + back);
            }
        }
    }
    // With inlets, a spare last type: the type a sphere is created with.
    let fresh = types.len() + 1;
    let mut data = String::new();
    writeln!(
        data,
        "LAMMPS data file (atom_style sphere) written by `dembound export lammps` from a scene\n\n\
         {} atoms\n{} atom types\n\n{} {} xlo xhi\n{} {} ylo yhi\n{} {} zlo zhi\n\n\
         Atoms # sphere\n",
        setup.spheres.len(),
        if inserts { fresh } else { types.len() },
        num(lo[0]),
        num(hi[0]),
        num(lo[1]),
        num(hi[1]),
        num(lo[2]),
        num(hi[2])
    )
    .ok();
    for (i, s) in setup.spheres.iter().enumerate() {
        let p = s.position;
        writeln!(
            data,
            "{} {} {} {} {} {} {}",
            i + 1,
            type_of(&s),
            num(2.0 * s.radius),
            num(material(s.material).density),
            num(p[0]),
            num(p[1]),
            num(p[2])
        )
        .ok();
    }
    writeln!(data, "\nVelocities\n").ok();
    for (i, s) in setup.spheres.iter().enumerate() {
        // A moving group's sphere starts at its rigid body's velocity and
        // spin at t = 0 (lammps_motion.rs), which the forces of step 0 see.
        let moving = moves.iter().find(|m| m.spheres.contains(&i));
        let (v, w) = match moving {
            Some(m) => lammps_motion::initial_velocity(&m.motion, s.position),
            None if s.fixed => ([0.0; 3], [0.0; 3]),
            None => (s.velocity, [0.0; 3]),
        };
        writeln!(
            data,
            "{} {} {} {} {} {} {}",
            i + 1,
            num(v[0]),
            num(v[1]),
            num(v[2]),
            num(w[0]),
            num(w[1]),
            num(w[2])
        )
        .ok();
    }

    // The deck.
    let mut x = String::new();
    let c = |x: &mut String, line: String| {
        writeln!(x, "# {line}").ok();
    };
    c(&mut x, "Exported by `dembound export lammps` from a dembound scene (SI units); scene.toml is the scene as resolved.".into());
    c(
        &mut x,
        "Run: lmp -in in.lammps -log log.lammps. Every number below comes from dembound.".into(),
    );
    c(&mut x, String::new());
    c(&mut x, format!("spheres: {} in {DATA_FILE} (ids in dembound's input order: the [[particles]] groups, then the boundary-particle walls)", setup.spheres.len()));
    c(
        &mut x,
        "atom types (one per material of the free spheres, one per material of the fixed spheres):"
            .into(),
    );
    for (t, ty) in types.iter().enumerate() {
        let m = material(ty.material);
        c(
            &mut x,
            format!(
                "  type {}: {} material \"{}\", rho = {} kg/m^3, E = {} Pa, nu = {}",
                t + 1,
                if ty.fixed { "fixed (frozen)" } else { "free" },
                name(ty.material),
                num(m.density),
                num(m.youngs_modulus),
                num(m.poisson_ratio)
            ),
        );
    }
    c(&mut x, "pair coefficients: every type pair explicitly, E_eff = 4/3 / ((1-nu_i^2)/E_i + (1-nu_j^2)/E_j) (paper eq 6, ERRATA 2),".into());
    c(&mut x, "  written as `hertz E_eff`: LAMMPS's F = k_n a delta, a = sqrt(R delta), R = R_i R_j/(R_i+R_j), is dembound's".into());
    c(&mut x, "  F = E_eff sqrt(R_eff) h^(3/2) for any radii. Not hertz/material: given for a pair i j it reads both bodies as".into());
    c(&mut x, "  the same E and nu, and left to its own mixing it does not give eq 6 (docs/export-lammps.md, pitfalls).".into());
    if let NormalLaw::Hooke { stiffness } = model.normal {
        c(
            &mut x,
            format!(
                "  law: hooke, F = k_n delta with k_n = {} N/m given (contact.law.stiffness), the same for every pair",
                num(stiffness)
            ),
        );
    }
    match damping {
        Damping::None => c(
            &mut x,
            "damping: none (contact.damping = \"none\"), `damping velocity` with coefficient 0"
                .into(),
        ),
        Damping::Tsuji { e_input, clamp } => {
            c(&mut x, format!(
                "damping: Tsuji, F_d = gamma h^(1/4) dh/dt with gamma = alpha sqrt(m_eff E_eff) R_eff^(1/4) from contact.restitution = {}",
                model.damping.dissipation().map_or(f64::NAN, |d| match d { Dissipation::Restitution(e) => e, Dissipation::Coefficient(c) => c })
            ));
            c(&mut x, format!(
                "  ({} calibration); LAMMPS's `damping tsuji` reads its coefficient as an e and makes alpha by its polynomial:",
                model.calibration.name()
            ));
            c(&mut x, format!(
                "  the deck gives e* = {} whose alpha is dembound's. m_eff: the free sphere's mass against a frozen one or a wall{}",
                num(e_input),
                if clamp { "; limit_damping = dembound's F = max(F, 0)" } else { "" }
            ));
        }
    }
    match &friction {
        None => c(
            &mut x,
            "friction: none (no friction keys, or every surface's mu = 0): the spheres do not spin"
                .into(),
        ),
        Some(_) => {
            c(&mut x, "friction: each pair's `tangential` (and `rolling`) arguments, written per type pair with dembound's mixing".into());
            c(&mut x, "  mu = sqrt(mu_a mu_b), mindlin k_t = 8 G* (LAMMPS multiplies by a = sqrt(R delta)), undamped (x_gamma,t = 0);".into());
            c(&mut x, "  one difference stays: LAMMPS applies the tangential torque at R - delta/2 from a sphere's centre in".into());
            c(&mut x, "  sphere-sphere pairs, dembound at R (relative size delta/(2R)); plane walls use R in both (docs/export-lammps.md)".into());
        }
    }
    c(&mut x, lammps_output::about(every, dt));
    if !setup.walls.is_empty() {
        c(&mut x, lammps_output::about_mean(every));
    }
    c(&mut x, format!("step: dt = {} s (integration.dt, or eta x the smallest contact-time estimate), {} steps, velocity Verlet (fix nve/sphere) as dembound's verlet", num(dt), steps));
    let g = setup.gravity;
    let g_norm = (g[0] * g[0] + g[1] * g[1] + g[2] * g[2]).sqrt();
    c(
        &mut x,
        format!(
            "gravity: {:?} m/s^2 (motion.gravity) on the free spheres",
            g
        ),
    );
    c(&mut x, "output: a thermo line at step 0 and at the last step: step, time (s), kinetic energy (J, translational, free spheres),".into());
    c(&mut x, "  v_pp = sphere-sphere contacts (free-free and free-fixed of [[particles]] groups), v_pw = contacts with planes and".into());
    c(&mut x, "  boundary-particle walls (the `particle_contacts` and `wall_contacts` of `dembound scene --json`).".into());

    let bnd: String = (0..3)
        .map(|k| if d.periodic[k] { "p" } else { "m" })
        .collect::<Vec<_>>()
        .join(" ");
    writeln!(
        x,
        "\nunits        si\natom_style   sphere\natom_modify  map array\nboundary     {bnd}\n\
         newton       off\ncomm_modify  vel yes\nread_data    {DATA_FILE}"
    )
    .ok();
    let list = |ts: &[usize]| -> String {
        ts.iter()
            .map(|t| (t + 1).to_string())
            .collect::<Vec<_>>()
            .join(" ")
    };
    writeln!(x, "group        free type {}", list(&free_types)).ok();
    if !fixed_types.is_empty() {
        writeln!(x, "group        frozen type {}", list(&fixed_types)).ok();
    }
    if !wall_types.is_empty() {
        writeln!(
            x,
            "group        frozen_wall type {}   # boundary-particle walls",
            list(&wall_types)
        )
        .ok();
    }
    if !held_types.is_empty() {
        writeln!(
            x,
            "group        frozen_held type {}   # fixed spheres of [[particles]] groups",
            list(&held_types)
        )
        .ok();
    }
    writeln!(x, "\npair_style   granular").ok();
    for a in 0..types.len() {
        for b in a..types.len() {
            let (ta, tb) = (&types[a], &types[b]);
            if ta.fixed && tb.fixed {
                // Never computed (neigh_modify exclude below); LAMMPS wants a coefficient.
                writeln!(
                    x,
                    "pair_coeff   {} {} {}   # frozen-frozen: excluded, never computed",
                    a + 1,
                    b + 1,
                    model_args("hertz", 1.0, &Damping::None, FRICTIONLESS)
                )
                .ok();
                continue;
            }
            let e = pair_modulus(ta, tb)?;
            let (law, k) = normal_coefficient(&model.normal, e);
            let (tangential, about) = match &friction {
                Some(f) => {
                    let (args, about) = f.pair_args(&surface(a), &surface(b))?;
                    (args, format!("; {about}"))
                }
                None => (FRICTIONLESS.to_string(), String::new()),
            };
            writeln!(
                x,
                "pair_coeff   {} {} {}   # \"{}\"{} - \"{}\"{}: E_eff = {} Pa{about}",
                a + 1,
                b + 1,
                model_args(law, k, &damping, &tangential),
                name(ta.material),
                if ta.fixed { " (fixed)" } else { "" },
                name(tb.material),
                if tb.fixed { " (fixed)" } else { "" },
                num(e)
            )
            .ok();
        }
    }
    if inserts {
        writeln!(
            x,
            "pair_coeff   * {fresh} {}   # type {fresh}: a sphere being created by an inlet, retyped before any run",
            model_args("hertz", 1.0, &Damping::None, FRICTIONLESS)
        )
        .ok();
    }
    // dembound's default skin: 0.2 × the smallest free radius, the
    // inlets' included.
    let skin = setup.neighbour.skin.unwrap_or_else(|| {
        0.2 * setup
            .spheres
            .iter()
            .filter(|s| !s.fixed)
            .map(|s| s.radius)
            .chain(setup.inlets.iter().map(|i| i.size.radius_range().0))
            .fold(f64::INFINITY, f64::min)
    });
    writeln!(
        x,
        "\nneighbor     {} bin\nneigh_modify delay 0 every 1 check yes",
        num(skin)
    )
    .ok();
    if !fixed_types.is_empty() {
        writeln!(x, "neigh_modify exclude group frozen frozen").ok();
    }
    if friction.is_some_and(|f| f.rolling) {
        // LAMMPS (fix_neigh_history.cpp, pre_exchange_*) hands a contact's
        // history to the other sphere of the pair negated, value by value,
        // when the pair is listed from that sphere at a rebuild; right for
        // the tangential displacement, wrong for `rolling sds`'s, which is
        // the same seen from either sphere (R_eff (ω_i − ω_j) × n_ij keeps
        // its sign when i and j swap). Sorting the atoms (every 1000 steps
        // by default) swaps many pairs' order; without it only a pair that
        // starts straddling a periodic face is handed over
        // (docs/export-lammps.md, "Rolling history in LAMMPS").
        writeln!(
            x,
            "atom_modify  sort 0 0.0   # no atom sorting: it would flip the sign of rolling springs"
        )
        .ok();
    }

    // Walls: one fix per plane and free type (the coefficient depends on both).
    let axis_name = ["xplane", "yplane", "zplane"];
    if !planes.is_empty() {
        for &t in &free_types {
            writeln!(x, "group        t{} type {}", t + 1, t + 1).ok();
        }
    }
    for p in planes.iter().filter(|p| p.axis.is_none()) {
        writeln!(
            x,
            "region       wall{} plane {} {} {} {} {} {} side in units box   # wall[{}], normal into the domain",
            p.index,
            num(p.point[0]),
            num(p.point[1]),
            num(p.point[2]),
            num(p.normal[0]),
            num(p.normal[1]),
            num(p.normal[2]),
            p.index
        )
        .ok();
    }
    let mut switches: Vec<lammps_gates::PlaneSwitch> = Vec::new();
    for p in &planes {
        // A sliding plane's `shear dim V` (lammps_motion.rs).
        let shear = match setup.wall_motions.get(p.index).copied().flatten() {
            Some(m) => lammps_motion::plane_shear(p.index, p.normal, p.axis, &m)?,
            None => String::new(),
        };
        let mut fixes_text = String::new();
        for &t in &free_types {
            let ty = &types[t];
            let e = pair_modulus(
                ty,
                &AtomType {
                    material: p.material,
                    fixed: true,
                    wall: true,
                },
            )?;
            let (law, k) = normal_coefficient(&model.normal, e);
            let (tangential, about) = match (&friction, &setup.friction) {
                (Some(f), Some(fs)) => {
                    let wall = Surface {
                        material: material(p.material),
                        coefficients: fs.of_wall(p.index, p.material),
                        radius: None,
                        plane: true,
                    };
                    let (args, about) = f.pair_args(&surface(t), &wall)?;
                    (args, format!("\n# wall[{}] friction: {about}", p.index))
                }
                _ => (FRICTIONLESS.to_string(), String::new()),
            };
            let geometry = match p.axis {
                Some(axis) if p.normal[axis] > 0.0 => {
                    format!("{} {} NULL", axis_name[axis], num(p.point[axis]))
                }
                Some(axis) => format!("{} NULL {}", axis_name[axis], num(p.point[axis])),
                None => format!("region wall{}", p.index),
            };
            writeln!(
                fixes_text,
                "# wall[{}]: plane of \"{}\" against \"{}\": the pre-mixed E_eff = {} Pa (R_eff = R); not\n\
                 # hertz/material, which would mix the wall as if it had the sphere's material{about}\n\
                 fix          wall{}_t{} t{} wall/gran{} granular {} {}{shear} contacts",
                p.index,
                name(p.material),
                name(ty.material),
                num(e),
                p.index,
                t + 1,
                t + 1,
                if p.axis.is_some() { "" } else { "/region" },
                model_args(law, k, &damping, &tangential),
                geometry
            )
            .ok();
        }
        if lammps_gates::on_at_start(windows[p.index]) {
            x.push_str(&fixes_text);
        }
        if setup.wall_active.get(p.index).is_some_and(Option::is_some) {
            switches.push(lammps_gates::PlaneSwitch {
                wall: p.index,
                fixes_text,
                fixes: free_types
                    .iter()
                    .map(|t| (format!("wall{}_t{}", p.index, t + 1), format!("t{}", t + 1)))
                    .collect(),
                in_wall: String::new(),
                force_lines: String::new(),
            });
        }
    }
    writeln!(x, "\nfix          integrate free nve/sphere").ok();
    for (k, m) in moves.iter().enumerate() {
        writeln!(
            x,
            "group        move{k} id {}:{}   # {}: a moving group of fixed spheres\n\
             fix          move{k} move{k} move {}",
            m.spheres.start + 1,
            m.spheres.end,
            m.key,
            m.args
        )
        .ok();
    }
    if !fixed_types.is_empty() {
        x.push_str(&lammps_output::before_freeze(setup));
        writeln!(
            x,
            "fix          freeze frozen freeze   # zero force on the frozen spheres; pair granular then uses m_eff = m_free"
        )
        .ok();
    }
    if g_norm > 0.0 {
        writeln!(
            x,
            "fix          gravity free gravity {} vector {} {} {}",
            num(g_norm),
            num(g[0] / g_norm),
            num(g[1] / g_norm),
            num(g[2] / g_norm)
        )
        .ok();
    }
    writeln!(x, "timestep     {}", num(dt)).ok();

    // Contact counts: compute contact/atom counts each touching pair on both
    // atoms; frozen-frozen pairs are excluded from the neighbour lists.
    // Summed over the free spheres it is 2 pp + ph + pw (ph: pairs with a
    // fixed sphere of a [[particles]] group, pw: with a boundary-particle
    // wall's sphere), over frozen_held ph, over frozen_wall pw. dembound
    // counts ph among the particle contacts, pw among the wall contacts.
    writeln!(
        x,
        "\ncompute      nc all contact/atom\ncompute      nc_free free reduce sum c_nc"
    )
    .ok();
    let mut pp = "c_nc_free".to_string();
    let mut wall_terms: Vec<String> = Vec::new();
    if !held_types.is_empty() {
        writeln!(x, "compute      nc_held frozen_held reduce sum c_nc").ok();
        pp.push_str("+c_nc_held");
    }
    if !wall_types.is_empty() {
        writeln!(x, "compute      nc_wall frozen_wall reduce sum c_nc").ok();
        pp.push_str("-c_nc_wall");
        wall_terms.push("c_nc_wall".into());
    }
    writeln!(x, "variable     pp equal ({pp})/2").ok();
    let coord = ["x", "y", "z"];
    if !planes.is_empty() {
        writeln!(x, "compute      radius all property/atom radius").ok();
    }
    for p in &planes {
        // n · (x − p), n the unit normal into the domain.
        let dist = (0..3)
            .filter(|&k| p.normal[k] != 0.0)
            .map(|k| {
                format!(
                    "({})*({}-({}))",
                    num(p.normal[k]),
                    coord[k],
                    num(p.point[k])
                )
            })
            .collect::<Vec<_>>()
            .join("+");
        let in_wall = format!("variable     in_wall{} atom ({dist})<c_radius\n", p.index);
        if lammps_gates::on_at_start(windows[p.index]) {
            x.push_str(&in_wall);
        } else {
            writeln!(x, "variable     in_wall{} atom 0", p.index).ok();
        }
        if let Some(sw) = switches.iter_mut().find(|sw| sw.wall == p.index) {
            sw.in_wall = in_wall;
        }
        writeln!(
            x,
            "compute      nw{} free reduce sum v_in_wall{}",
            p.index, p.index
        )
        .ok();
        wall_terms.push(format!("c_nw{}", p.index));
    }
    if wall_terms.is_empty() {
        wall_terms.push("0".into());
    }
    let plane_fixes: Vec<(usize, Vec<String>)> = planes
        .iter()
        .filter(|p| lammps_gates::on_at_start(windows[p.index]))
        .map(|p| {
            (
                p.index,
                free_types
                    .iter()
                    .map(|t| format!("wall{}_t{}", p.index, t + 1))
                    .collect(),
            )
        })
        .collect();
    x.push_str(&lammps_output::output(setup, every, &plane_fixes, inserts));
    // Moving frozen spheres carry velocities: the kinetic energy is the
    // free spheres' (dembound's), not `ke` of all atoms.
    let ke = if moves.is_empty() {
        "ke"
    } else {
        writeln!(x, "compute      ke_free free ke").ok();
        "c_ke_free"
    };
    // Inlets (lammps_inlets.rs): a created atom belongs to `all` only, so
    // after each event the groups of the free types are taken again.
    let mut regroup = format!("group        free type {}\n", list(&free_types));
    if !planes.is_empty() {
        for &t in &free_types {
            writeln!(regroup, "group        t{} type {}", t + 1, t + 1).ok();
        }
    }
    let free_type = |m: usize| -> usize {
        1 + types
            .iter()
            .position(|t| {
                *t == AtomType {
                    material: m,
                    fixed: false,
                    wall: false,
                }
            })
            .unwrap_or(0)
    };
    let inlets = crate::lammps_inlets::plan(
        setup,
        dt,
        steps,
        &windows,
        &crate::lammps_inlets::Naming {
            free_type: &free_type,
            fresh,
            regroup,
        },
    )?;
    if let Some(i) = &inlets {
        x.push_str(&i.setup);
    }
    if let Some(o) = &outlets {
        x.push_str(&o.setup);
    }
    writeln!(
        x,
        "variable     pw equal {}\n\
         thermo_style custom step time {ke} v_pp v_pw{}{}\n\
         thermo_modify norm no format float %.17g\n\
         thermo       {}",
        wall_terms.join("+"),
        inlets.as_ref().map_or("", |i| i.columns.as_str()),
        outlets.as_ref().map_or("", |o| o.columns.as_str()),
        // With inlets or outlets, the counts over time: at the series
        // cadence, so that a row between the outlets' checks reads the
        // counts of its own step (`compare` takes the thermo row of a dump
        // step, else the last before it: the last check's, short of the
        // spheres the dump already leaves out).
        if inlets.is_some() || outlets.is_some() {
            every
        } else {
            steps.max(1)
        },
    )
    .ok();
    for sw in &mut switches {
        let ids: Vec<String> = sw.fixes.iter().map(|(f, _)| f.clone()).collect();
        sw.force_lines = lammps_output::plane_force_lines(sw.wall, &ids);
    }
    x.push_str(&match &inlets {
        Some(i) => crate::lammps_inlets::runs(steps, dt, &windows, &switches, outlets.as_ref(), i),
        None => lammps_gates::runs(steps, dt, &windows, &switches, outlets.as_ref()),
    });

    Ok(Deck {
        code: Code::Lammps,
        files: vec![
            DeckFile {
                name: Code::Lammps.input_file().into(),
                text: x,
            },
            DeckFile {
                name: DATA_FILE.into(),
                text: data,
            },
        ],
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
[[particles]]
spheres = [ { position = [0.002, 0.005, 0.005], radius = 1.0e-3, velocity = [0.1, 0.0, 0.0] } ]
material = "a"
[[particles]]
spheres = [ { position = [0.004000000000000001, 0.005, 0.005], radius = 0.7e-3 } ]
material = "b"
fixed = true
[[wall]]
plane = { point = [0.0, 0.0, 0.0], normal = [0.0, 0.0, 1.0] }
material = "rigid"
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

    fn coefficient(deck: &str, pair: &str) -> f64 {
        let line = deck
            .lines()
            .find(|l| l.starts_with(&format!("pair_coeff   {pair} ")))
            .expect("the pair's line");
        line.split_whitespace()
            .nth(4)
            .expect("k_n")
            .parse()
            .expect("a number")
    }

    #[test]
    fn every_pair_gets_eq_6_and_the_data_round_trips() {
        let d = exported(&[]).expect("exports");
        let input = &d.files[0].text;
        let data = &d.files[1].text;
        // Written out here, not through the physics crate: eq 6.
        let e_ab = 4.0 / 3.0 / ((1.0 - 0.09) / 1.0e7 + (1.0 - 0.04) / 5.0e7);
        let e_aa = 4.0 / 3.0 / (2.0 * (1.0 - 0.09) / 1.0e7);
        // Type 1: free "a"; type 2: fixed "b".
        assert!((coefficient(input, "1 2") / e_ab - 1.0).abs() < 1e-15);
        assert!((coefficient(input, "1 1") / e_aa - 1.0).abs() < 1e-15);
        // The rigid floor: E_eff = 4/3 E_a/(1 − ν_a²), as a wall fix.
        let wall = input
            .lines()
            .find(|l| l.starts_with("fix          wall0_t1 t1 wall/gran granular hertz "))
            .expect("the floor");
        let k: f64 = wall
            .split_whitespace()
            .nth(6)
            .expect("k_n")
            .parse()
            .expect("a number");
        assert!((k / (4.0 / 3.0 * 1.0e7 / 0.91) - 1.0).abs() < 1e-15);
        assert!(wall.ends_with("zplane 0 NULL contacts"));
        assert!(input.contains("group        frozen type 2"));
        assert!(input.contains("fix          freeze frozen freeze"));
        assert!(input.contains("timestep     1e-6") && input.contains("run          10"));
        // The data file: positions read back to the same f64, the fixed
        // sphere's velocity 0.
        let atoms: Vec<Vec<f64>> = data
            .lines()
            .skip_while(|l| !l.starts_with("Atoms"))
            .skip(2)
            .take(2)
            .map(|l| {
                l.split_whitespace()
                    .map(|w| w.parse().expect("a number"))
                    .collect()
            })
            .collect();
        assert_eq!(
            atoms[0],
            vec![1.0, 1.0, 2.0e-3, 1000.0, 0.002, 0.005, 0.005]
        );
        assert_eq!(atoms[1][4], 0.004000000000000001);
        assert!(data.contains("\n1 1e-1 0 0 0 0 0\n") && data.contains("\n2 0 0 0 0 0 0\n"));
    }

    /// The wall forces: walls.txt samples the row's step (`ave/time N 1
    /// N`, as before), walls_mean.txt averages every step of each row
    /// interval (`ave/time 1 N N`: Nevery 1, Nrepeat N, Nfreq N), the
    /// same columns.
    #[test]
    fn wall_forces_are_written_at_the_row_and_averaged_over_every_step() {
        let d = exported(&["output.series_every=5"]).expect("exports");
        let input = &d.files[0].text;
        let columns = "v_w0x v_w0y v_w0z";
        assert!(input.contains(&format!(
            "fix          walls all ave/time 5 1 5 {columns} file walls.txt format \" %.17g\"\n"
        )));
        assert!(input.contains(&format!(
            "fix          walls_mean all ave/time 1 5 5 {columns} file walls_mean.txt format \" %.17g\"   #"
        )));
        assert!(input.contains("# walls_mean.txt: the same columns averaged over every step since the previous row (the row of step k: steps k-4 ... k; no row at step 0)"));
    }

    #[test]
    fn friction_coefficients_are_dembounds() {
        let d = exported(&[
            "contact.friction=0.4",
            "material.1.friction=0.9",
            "wall.0.friction=0.1",
        ])
        .expect("exports");
        let input = &d.files[0].text;
        let line = |start: &str| -> Vec<String> {
            input
                .lines()
                .find(|l| l.starts_with(start))
                .expect("the line")
                .split_whitespace()
                .map(String::from)
                .collect()
        };
        let after = |w: &[String], key: &str, k: usize| -> f64 {
            let i = w.iter().position(|x| x == key).expect("the keyword");
            w[i + k].parse().expect("a number")
        };
        // G = E/(2(1 + nu)); G* = 1/((2 - nu_a)/G_a + (2 - nu_b)/G_b).
        let g = |e: f64, nu: f64| e / (2.0 * (1.0 + nu));
        let (ga, gb) = (g(1.0e7, 0.3), g(5.0e7, 0.2));
        let ab = line("pair_coeff   1 2 ");
        assert!((after(&ab, "mindlin", 1) / (8.0 / (1.7 / ga + 1.8 / gb)) - 1.0).abs() < 1e-14);
        assert!((after(&ab, "mindlin", 3) - (0.4f64 * 0.9).sqrt()).abs() < 1e-15);
        // The rigid floor: G* = G_a/(2 - nu_a); mu = sqrt(0.4 x 0.1) = 0.2.
        let wall = line("fix          wall0_t1 ");
        assert!((after(&wall, "mindlin", 1) / (8.0 * ga / 1.7) - 1.0).abs() < 1e-14);
        assert!((after(&wall, "mindlin", 3) - 0.2).abs() < 1e-15);
        // mu = 0 everywhere: the frictionless deck.
        let none = exported(&["contact.friction=0"]).expect("exports");
        assert!(!none.files[0].text.contains("mindlin"));
    }

    /// Tsuji damping with friction under `contact.tangential_damping =
    /// false`: the normal damping as without friction, the tangential
    /// spring with x_gamma_t = 0 (no tangential dashpot, as dembound).
    #[test]
    fn damped_friction_without_the_tangential_dashpot_exports() {
        let damped = ["contact.damping=tsuji", "contact.restitution=0.5"];
        let frictionless = exported(&damped).expect("exports");
        let mut sets = damped.to_vec();
        sets.extend(["contact.friction=0.4", "contact.tangential_damping=false"]);
        let d = exported(&sets).expect("exports");
        let line = |deck: &Deck| -> String {
            deck.files[0]
                .text
                .lines()
                .find(|l| l.starts_with("pair_coeff   1 2 "))
                .expect("the pair's line")
                .to_string()
        };
        let (with, without) = (line(&d), line(&frictionless));
        // The same normal arguments (k_n, e*) before `tangential`.
        let normal = |l: &str| l.split(" tangential ").next().unwrap_or("").to_string();
        assert_eq!(normal(&with), normal(&without));
        assert!(
            with.contains(" tangential mindlin ") && with.contains(" damping tsuji limit_damping")
        );
        let w: Vec<&str> = with.split_whitespace().collect();
        let i = w.iter().position(|x| *x == "mindlin").expect("mindlin");
        assert_eq!(w[i + 2], "0.0", "x_gamma_t: {with}");
    }

    #[test]
    fn refusals_name_the_key() {
        for (sets, key) in [
            (vec!["integration.scheme=gear5"], "integration.scheme"),
            (
                vec!["contact.damping=tsuji", "contact.damping_coefficient=1e-3"],
                "contact.damping_coefficient",
            ),
            (vec!["contact.law=linear"], "contact.law"),
            (
                vec![
                    "contact.friction=0.5",
                    "contact.damping=tsuji",
                    "contact.restitution=0.5",
                ],
                "contact.damping",
            ),
            // Along the plane's normal (a plane sliding along itself is
            // exported as `shear`, lammps_motion.rs).
            (
                vec!["wall.0.motion.velocity=[0,0,0.1]"],
                "wall[0].motion.velocity",
            ),
            (
                vec!["wall.0.oscillation={amplitude=[0,1e-4,0],frequency=50}"],
                "wall[0].oscillation",
            ),
            (
                vec![
                    "contact.law={hooke=50.0}",
                    "contact.friction=0.5",
                    "contact.tangential_damping=false",
                    "contact.rolling_friction=0.1",
                    "contact.damping=viscous",
                    "contact.restitution=0.5",
                ],
                "rolling friction with contact.damping",
            ),
            (vec!["domain.outside=delete"], "domain.outside"),
            (
                vec!["wall.0.servo={force=1,axis=[1,0,0],max_velocity=0.1}"],
                "wall[0].servo",
            ),
        ] {
            let e = exported(&sets).expect_err("refused");
            assert!(e.to_string().contains(key), "{sets:?}: {e}");
        }
    }
}
