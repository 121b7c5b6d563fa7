//! From a validated [`SceneFile`] to the engine's [`SceneSetup`]: the
//! particle sources are read or generated (paths relative to the scene
//! file), the boundary-particle walls tiled and appended, materials
//! indexed, the contact model and the time-step rule built.
//!
//! Input order of the bodies (every per-body output uses it): the
//! `[[particles]]` groups in file order, each in its source's order, then
//! the spheres of each `boundary_particles` wall in wall order.

use super::config::{
    LatticeSource, OutsideName, Particles, ParticlesSection, SceneFile, Scheme as SchemeName, RIGID,
};
use super::memory::SphereCount;
use crate::setup::{
    DomainSetup, FrictionSetup, IntegrationSetup, NamedMaterial, NeighbourSetup, Outside,
    RunLength, SceneSetup, Scheme, SphereInit, TimeStep,
};
use crate::sources::lammps_data::LammpsData;
use crate::sources::lattice::Lattice;
use crate::sources::random::RandomInsertion;
use crate::sources::tiling::Extent;
use crate::sources::{self, SourceSphere};
use crate::spheres::{LatticeRun, Spheres};
use crate::SceneError;
use dembound_physics::contact::tangential::SpringRotation;
use dembound_physics::contact::tangential::{FrictionModel, TangentialKind};
use dembound_physics::contact::TorqueArm;
use dembound_physics::material::Material;
use std::ops::Range;
use std::path::{Path, PathBuf};

/// A scene ready to run, with what the output needs to know of its make.
#[derive(Debug, Clone)]
pub struct ResolvedScene {
    pub setup: SceneSetup,
    /// Bodies of each `[[particles]]` group (input indices).
    pub groups: Vec<Range<usize>>,
    /// Bodies of each wall (empty for a plane).
    pub wall_bodies: Vec<Range<usize>>,
    /// The file as resolved: every default written out, source paths made
    /// absolute (so that it runs from anywhere).
    pub file: SceneFile,
    /// Plausibility warnings (large initial overlaps, issue 24), for stderr.
    pub warnings: Vec<String>,
    /// The largest hole of each mesh-form `boundary_particles` wall.
    pub covering_holes: Vec<CoveringHole>,
}

/// The largest hole of a mesh-form `boundary_particles` wall
/// (`sources::mesh_tiling::measure::holes`: sampled every s/8).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct CoveringHole {
    /// The wall (file order).
    pub wall: usize,
    /// Its boundary spheres.
    pub spheres: usize,
    /// Radius of the largest particle found to pass between them, m.
    pub largest_hole: f64,
    /// An upper bound on it (found + the sample spacing), m.
    pub largest_hole_bound: f64,
}

/// Density given to the reserved `"rigid"` material. It never matters: a
/// rigid plane has no mass, and a rigid particle must be fixed.
const RIGID_DENSITY: f64 = 1000.0;

/// What resolving a `[[wall]]` entry may add to (`walls::WallType::resolve`).
pub struct WallResolve<'a> {
    /// The materials so far (a surface's `"rigid"` is added once).
    pub materials: &'a mut Vec<NamedMaterial>,
    /// The spheres so far, in input order (a wall of boundary particles
    /// appends its own).
    pub spheres: &'a mut Spheres,
    /// The box a tiling fills.
    pub extent: Extent,
    /// The scene file's directory (paths in the file are relative to it).
    pub base_dir: &'a Path,
    /// Warnings for stderr (before the setup checks' own).
    pub warnings: &'a mut Vec<String>,
    /// (material of a wall's boundary spheres, the material it scales,
    /// wall): their friction is the wall's.
    pub boundary_materials: &'a mut Vec<(usize, usize, usize)>,
    /// Holes of mesh-form coverings (`wall` set by the caller).
    pub covering_holes: &'a mut Vec<CoveringHole>,
}

impl WallResolve<'_> {
    /// The index of material `name` (validated: a `[[material]]` or
    /// `"rigid"`).
    pub fn material_index(&mut self, name: &str) -> usize {
        material_index(name, self.materials)
    }
}

/// The index of material `name`, a `[[material]]` or `"rigid"` (added at
/// its first use).
fn material_index(name: &str, materials: &mut Vec<NamedMaterial>) -> usize {
    if let Some(k) = materials.iter().position(|m| m.name == name) {
        return k;
    }
    // Only "rigid" reaches here (validated).
    materials.push(NamedMaterial {
        name: RIGID.into(),
        material: Material::rigid(RIGID_DENSITY),
    });
    materials.len() - 1
}

/// Resolves `file`; relative source paths are taken from `base_dir` (the
/// scene file's directory).
pub fn resolve(file: &SceneFile, base_dir: &Path) -> Result<ResolvedScene, SceneError> {
    resolve_with(file, base_dir, Particles::Required)
}

/// [`resolve`], with `[[particles]]` optional under [`Particles::Later`]
/// (a scene built from code, whose spheres are added afterwards).
pub fn resolve_with(
    file: &SceneFile,
    base_dir: &Path,
    particles: Particles,
) -> Result<ResolvedScene, SceneError> {
    resolve_inner(file, base_dir, particles, None).map(|(r, _)| r)
}

/// [`resolve`] without making the spheres of the lattices and data files:
/// each group described instead ([`PartGroup`]: its input indices, its
/// source), so that each of `ranks` MPI ranks makes its own part
/// (`comm::distributed::input`); `setup.spheres` stays empty. `Ok(None)`
/// when the scene has a source or a feature that part-wise input does not
/// cover (random, CSV and inline spheres, walls other than planes,
/// inlets, moving groups, removal, a data file with velocities); those
/// resolve whole.
pub fn resolve_parts(
    file: &SceneFile,
    base_dir: &Path,
    ranks: usize,
) -> Result<Option<(ResolvedScene, Vec<PartGroup>)>, SceneError> {
    let covered = file.particles.iter().all(|g| {
        (g.lattice.is_some() || g.lammps_data.is_some())
            && g.motion.is_none()
            && g.oscillation.is_none()
    }) && !file.particles.is_empty()
        && file.inlets.is_empty()
        && file.outlets.is_empty()
        // Plane walls only: the other types' resolving and placement
        // checks look at all spheres (a boundary-particle wall's R_ref, a
        // cylinder's largest free sphere).
        && file.walls.iter().all(|w| w.key() == Some("plane"))
        && !matches!(file.domain.outside, Some(OutsideName::Delete));
    if !covered {
        return Ok(None);
    }
    let (r, parts) = resolve_inner(file, base_dir, Particles::Required, Some(ranks.max(1)))?;
    let plain = !r.setup.walls.iter().any(|w| w.is_particles())
        && r.setup.inlets.is_empty()
        && r.setup.group_motions.is_empty()
        && parts.iter().all(|p| match &p.source {
            PartSource::Data { header, .. } => !header.velocities_first,
            PartSource::Lattice { .. } => true,
        });
    Ok(plain.then_some((r, parts)))
}

fn resolve_inner(
    file: &SceneFile,
    base_dir: &Path,
    particles: Particles,
    defer: Option<usize>,
) -> Result<(ResolvedScene, Vec<PartGroup>), SceneError> {
    file.validate_with(particles)?;
    let mut file = file.clone();
    let mut materials: Vec<NamedMaterial> = file
        .materials
        .iter()
        .map(|m| NamedMaterial {
            name: m.name.clone(),
            material: Material {
                density: m.density,
                youngs_modulus: m.youngs_modulus,
                poisson_ratio: m.poisson_ratio,
            },
        })
        .collect();

    // The memory the generated spheres need, before any is made; the
    // files' and walls' spheres are counted once read (below).
    let heavy = file.integration.scheme == SchemeName::Gear5 || has_friction(&file);
    let available = super::memory::available();
    let (generated, largest) = generated_count(&file);
    // The listed ones (random, inline); a lattice is kept as its formula.
    let listed = listed_count(&file);
    let made = SphereCount {
        listed,
        lattice: generated.saturating_sub(listed),
    };
    // Made in parts: each rank holds about its share.
    let share = |n: SphereCount| defer.map_or(n, |ranks| n.share(ranks as u64));
    super::memory::check(share(made), heavy, &largest, available)?;
    let mut spheres = Spheres::new();
    let mut parts: Vec<PartGroup> = Vec::new();
    // The input indices given so far (the spheres made, or described).
    let mut next = 0usize;
    // Room for the listed ones.
    spheres
        .try_reserve(
            usize::try_from(if defer.is_some() { 0 } else { listed }).unwrap_or(usize::MAX),
        )
        .map_err(|e| {
            SceneError::input(format!(
                "[[particles]]: cannot allocate {generated} spheres: {e}"
            ))
        })?;
    let mut groups = Vec::with_capacity(file.particles.len());
    for (i, group) in file.particles.iter_mut().enumerate() {
        let key = format!("particles[{i}]");
        let material = material_index(&group.material, &mut materials);
        let first = next;
        if defer.is_some() {
            let (count, source) = if group.lammps_data.is_some() {
                let (header, path, by_type) = lammps_header(group, &key, base_dir, &mut materials)?;
                let count = header.atoms;
                (
                    count,
                    PartSource::Data {
                        path,
                        key: format!("{key}.lammps_data"),
                        by_type,
                        header,
                    },
                )
            } else if let Some(l) = &group.lattice {
                let lattice = lattice_of(l, &key)?;
                (
                    lattice.len(),
                    PartSource::Lattice {
                        lattice,
                        velocity: l.velocity,
                    },
                )
            } else {
                return Err(SceneError::input(format!("`{key}`: no source")));
            };
            next += count;
            parts.push(PartGroup {
                ids: first..next,
                material,
                fixed: group.fixed,
                source,
            });
            groups.push(first..next);
            continue;
        }
        if group.lammps_data.is_some() {
            let atoms = lammps_atoms(group, &key, base_dir, material, &mut materials)?;
            spheres.extend(atoms.into_iter().map(|(s, material)| SphereInit {
                position: s.position,
                velocity: s.velocity,
                radius: s.radius,
                material,
                fixed: group.fixed,
                group: None,
            }));
            next = spheres.len();
            groups.push(first..spheres.len());
            continue;
        }
        if let Some(l) = &group.lattice {
            spheres.push_lattice(LatticeRun {
                lattice: lattice_of(l, &key)?,
                velocity: l.velocity,
                material,
                fixed: group.fixed,
                group: None,
            });
            next = spheres.len();
            groups.push(first..spheres.len());
            continue;
        }
        let made = group_spheres(group, &key, base_dir, &spheres)?;
        spheres.extend(made.into_iter().map(|s| SphereInit {
            position: s.position,
            velocity: s.velocity,
            radius: s.radius,
            material,
            fixed: group.fixed,
            group: None,
        }));
        next = spheres.len();
        groups.push(first..spheres.len());
    }

    let d = &file.domain;
    let extent = Extent {
        lower: d.lower,
        upper: d.upper,
        periodic: d.periodic,
    };
    let mut walls = Vec::with_capacity(file.walls.len());
    // (material of the boundary spheres, the material it scales, wall).
    let mut boundary_materials: Vec<(usize, usize, usize)> = Vec::new();
    let mut wall_bodies = Vec::with_capacity(file.walls.len());
    let mut wall_motions = Vec::with_capacity(file.walls.len());
    let mut wall_servos = Vec::with_capacity(file.walls.len());
    let mut warnings = Vec::new();
    let mut covering_holes = Vec::new();
    for (w, wall) in file.walls.iter_mut().enumerate() {
        let before = covering_holes.len();
        let mut cx = WallResolve {
            materials: &mut materials,
            spheres: &mut spheres,
            extent,
            base_dir,
            warnings: &mut warnings,
            boundary_materials: &mut boundary_materials,
            covering_holes: &mut covering_holes,
        };
        let setup = wall.resolve(w, &mut cx)?;
        for h in &mut covering_holes[before..] {
            h.wall = w;
        }
        wall_motions.push(crate::walls::motion::WallMotion::from_config(
            wall.motion.as_ref(),
            wall.oscillation.as_ref(),
        ));
        wall_servos.push(
            wall.servo
                .as_ref()
                .map(crate::walls::servo::Servo::from_config),
        );
        let end = if defer.is_some() { next } else { spheres.len() };
        wall_bodies.push(setup.bodies().unwrap_or(end..end));
        walls.push(setup);
    }

    let total = if defer.is_some() { next } else { spheres.len() } as u64;
    // Every sphere but the lattices' is listed (data files, walls too).
    let all = SphereCount {
        listed: total.saturating_sub(made.lattice),
        lattice: made.lattice,
    };
    super::memory::check(share(all), heavy, "the scene", available)?;

    let n = &file.integration;
    // Parts: the data files hold no velocities (else read whole), a
    // lattice one velocity: one sphere of each group stands for them all.
    let standing: Vec<SphereInit> = parts
        .iter()
        .map(|p| SphereInit {
            position: [0.0; 3],
            velocity: match &p.source {
                PartSource::Lattice { velocity, .. } => *velocity,
                PartSource::Data { .. } => [0.0; 3],
            },
            radius: 1.0,
            material: p.material,
            fixed: p.fixed,
            group: None,
        })
        .collect();
    let impact_speed = match n.impact_speed {
        Some(v) => Ok(v),
        None if defer.is_some() => default_impact_speed(&file, standing),
        None => default_impact_speed(&file, &spheres),
    };
    let time_step = match (n.dt, n.eta) {
        (Some(dt), _) => TimeStep::Fixed(dt),
        (None, Some(eta)) => TimeStep::Eta {
            eta,
            impact_speed: impact_speed.clone()?,
        },
        (None, None) => {
            return Err(SceneError::input(
                "`integration.dt`: missing (give dt or eta)",
            ))
        }
    };
    let length = match (n.steps, n.duration) {
        (Some(s), _) => RunLength::Steps(s),
        (None, Some(t)) => RunLength::Duration(t),
        (None, None) => return Err(SceneError::input("`integration.steps`: missing")),
    };
    let setup = SceneSetup {
        domain: DomainSetup {
            lower: d.lower,
            upper: d.upper,
            periodic: d.periodic,
        },
        materials,
        contact: file.contact.model(impact_speed.ok())?,
        spheres,
        walls,
        gravity: file.motion.gravity,
        integration: IntegrationSetup {
            scheme: match n.scheme {
                SchemeName::Verlet => Scheme::Verlet,
                SchemeName::Gear5 => Scheme::Gear5,
            },
            time_step,
            length,
        },
        neighbour: NeighbourSetup { skin: n.skin },
        collisions: file.output.collisions,
        dissipation: file.output.dissipation,
        friction: friction_setup(&file, &boundary_materials),
        outside: match d.outside {
            None | Some(OutsideName::Error) => Outside::Error,
            Some(OutsideName::Keep) => Outside::Keep,
            Some(OutsideName::Delete) => Outside::Delete,
        },
        outlets: file.outlets.iter().map(|o| o.outlet_region()).collect(),
        // The file's materials come first, in file order.
        inlets: (0..file.inlets.len())
            .map(|i| {
                let name = &file.inlets[i].material;
                let m = file
                    .materials
                    .iter()
                    .position(|m| m.name == *name)
                    .unwrap_or(0);
                file.inlet_setup(i, m)
            })
            .collect(),
        wall_motions: if wall_motions.iter().any(Option::is_some) {
            wall_motions
        } else {
            Vec::new()
        },
        wall_servos: if wall_servos.iter().any(Option::is_some) {
            wall_servos
        } else {
            Vec::new()
        },
        // The gates (issue 28, `walls::gate`): empty when no wall has one.
        wall_active: if file.walls.iter().any(|w| w.active.is_some()) {
            file.walls.iter().map(|w| w.active).collect()
        } else {
            Vec::new()
        },
        group_motions: file
            .particles
            .iter()
            .zip(&groups)
            .enumerate()
            .filter_map(|(k, (p, spheres))| {
                let motion = crate::walls::motion::WallMotion::from_config(
                    p.motion.as_ref(),
                    p.oscillation.as_ref(),
                )?;
                Some(crate::setup::GroupMotion {
                    group: k,
                    spheres: spheres.clone(),
                    motion,
                })
            })
            .collect(),
    };
    if defer.is_none() {
        warnings.extend(super::labels::check(&setup, &file, &groups, &wall_bodies)?);
    }
    Ok((
        ResolvedScene {
            setup,
            groups,
            wall_bodies,
            file,
            warnings,
            covering_holes,
        },
        parts,
    ))
}

/// One `[[particles]]` group made in parts ([`resolve_parts`]).
#[derive(Debug, Clone)]
pub struct PartGroup {
    /// Its input indices.
    pub ids: Range<usize>,
    /// Its material (data files: of the atoms whose type `types` leaves
    /// unnamed).
    pub material: usize,
    pub fixed: bool,
    pub source: PartSource,
}

/// Where a group's spheres come from.
#[derive(Debug, Clone)]
pub enum PartSource {
    Lattice {
        lattice: Lattice,
        /// Every sphere's initial velocity, m/s.
        velocity: [f64; 3],
    },
    Data {
        path: PathBuf,
        /// The scene key naming the file (`particles[0].lammps_data`).
        key: String,
        /// Atom type → material index (`types`).
        by_type: std::collections::HashMap<u32, usize>,
        header: crate::sources::lammps_part::DataHeader,
    },
}

/// The header of a `lammps_data` group's file and its type → material
/// map, as [`lammps_atoms`] makes them (the same materials added in the
/// same order); makes the path absolute.
#[allow(clippy::type_complexity)]
fn lammps_header(
    group: &mut ParticlesSection,
    key: &str,
    base_dir: &Path,
    materials: &mut Vec<NamedMaterial>,
) -> Result<
    (
        crate::sources::lammps_part::DataHeader,
        PathBuf,
        std::collections::HashMap<u32, usize>,
    ),
    SceneError,
> {
    let Some(path) = &mut group.lammps_data else {
        return Err(SceneError::input(format!("`{key}`: no source")));
    };
    let full = base_dir.join(&*path);
    let full = std::path::absolute(&full).unwrap_or(full);
    *path = full.display().to_string();
    let header = crate::sources::lammps_part::read_header(&full, &format!("{key}.lammps_data"))?;
    let by_type = type_materials(group, materials);
    Ok((header, full, by_type))
}

/// Atom type → material index from a group's `types` (a name not among the
/// materials: the rigid material, added).
fn type_materials(
    group: &ParticlesSection,
    materials: &mut Vec<NamedMaterial>,
) -> std::collections::HashMap<u32, usize> {
    let mut by_type = std::collections::HashMap::new();
    for (t, name) in group.types.iter().flatten() {
        // Validated: whole numbers ≥ 1 and known names.
        let Ok(t) = t.parse::<u32>() else { continue };
        let k = match materials.iter().position(|m| m.name == *name) {
            Some(k) => k,
            None => {
                materials.push(NamedMaterial {
                    name: RIGID.into(),
                    material: Material::rigid(RIGID_DENSITY),
                });
                materials.len() - 1
            }
        };
        by_type.insert(t, k);
    }
    by_type
}

/// The material of an atom of type `atom_type` (`by_type`, else `default`),
/// or the message refusing its density ([`lammps_atoms`]'s check).
pub(crate) fn atom_material(
    atom: &crate::sources::lammps_data::DataAtom,
    by_type: &std::collections::HashMap<u32, usize>,
    default: usize,
    fixed: bool,
    materials: &[NamedMaterial],
    key: &str,
    path: &Path,
) -> Result<usize, SceneError> {
    let k = by_type.get(&atom.atom_type).copied().unwrap_or(default);
    let m = &materials[k];
    let fixed_rigid = fixed && m.name == RIGID;
    let expected = m.material.density;
    // Written so that a NaN density is refused too.
    let agrees = (atom.density - expected).abs() <= DENSITY_TOLERANCE * expected;
    if !fixed_rigid && !agrees {
        return Err(SceneError::input(format!(
            "`{key}`: atom {} (type {}) of `{}` has density {} kg/m³, but its \
             material \"{}\" has {} kg/m³ (allowed: equal to {DENSITY_TOLERANCE:e} relative; \
             give type {} a [[material]] of its density in `{key_types}`)",
            atom.id,
            atom.atom_type,
            path.display(),
            atom.density,
            m.name,
            expected,
            atom.atom_type,
            key_types = key.replace(".lammps_data", ".types"),
        )));
    }
    Ok(k)
}

/// The friction of the scene (issue 13): `None` when no friction key is
/// given. Boundary spheres take their wall's coefficients, else those of
/// the material they scale.
fn friction_setup(
    file: &SceneFile,
    boundary_materials: &[(usize, usize, usize)],
) -> Option<FrictionSetup> {
    if !file.has_friction() {
        return None;
    }
    let c = &file.contact;
    let model = FrictionModel {
        tangential: c
            .tangential
            .as_deref()
            .and_then(TangentialKind::from_name)
            .unwrap_or(TangentialKind::Mindlin),
        friction: c.friction.unwrap_or(0.0),
        rolling_friction: c.rolling_friction.unwrap_or(0.0),
    };
    let of = |mu: Option<f64>, roll: Option<f64>, base: (f64, f64)| -> Option<(f64, f64)> {
        (mu.is_some() || roll.is_some()).then(|| (mu.unwrap_or(base.0), roll.unwrap_or(base.1)))
    };
    let defaults = (model.friction, model.rolling_friction);
    let mut materials: Vec<Option<(f64, f64)>> = file
        .materials
        .iter()
        .map(|m| of(m.friction, m.rolling_friction, defaults))
        .collect();
    let walls: Vec<Option<(f64, f64)>> = file
        .walls
        .iter()
        .map(|w| {
            let base = materials_of(&file.materials, &w.material, defaults).unwrap_or(defaults);
            of(w.friction, w.rolling_friction, base)
        })
        .collect();
    for &(material, base, wall) in boundary_materials {
        if materials.len() <= material {
            materials.resize(material + 1, None);
        }
        materials[material] = walls
            .get(wall)
            .copied()
            .flatten()
            .or_else(|| materials.get(base).copied().flatten());
    }
    Some(FrictionSetup {
        model,
        materials,
        walls,
        tangential_damping: c.tangential_damping.unwrap_or(true),
        torque_arm: c
            .torque_arm
            .as_deref()
            .and_then(TorqueArm::from_name)
            .unwrap_or_default(),
        spring_rotation: c
            .spring_rotation
            .as_deref()
            .and_then(SpringRotation::from_name)
            .unwrap_or_default(),
    })
}

/// (μ, μ_r) of the `[[material]]` named `name`, when it gives either.
fn materials_of(
    materials: &[super::config::MaterialSection],
    name: &str,
    defaults: (f64, f64),
) -> Option<(f64, f64)> {
    let m = materials.iter().find(|m| m.name == name)?;
    if m.friction.is_none() && m.rolling_friction.is_none() {
        return None;
    }
    Some((
        m.friction.unwrap_or(defaults.0),
        m.rolling_friction.unwrap_or(defaults.1),
    ))
}

/// Relative difference allowed between an atom's density and its
/// material's: the data file's printed digits (make_lattice.py writes
/// `1000`; a `%.17g` writer is exact).
const DENSITY_TOLERANCE: f64 = 1e-9;

/// The atoms of a `lammps_data` group with the material index of each (by
/// atom type, `types`, else `default`); makes the path absolute. An atom
/// whose density is not its material's is refused: the engine's masses
/// come from the materials, and a silently different mass would not be the
/// state LAMMPS runs.
fn lammps_atoms(
    group: &mut ParticlesSection,
    key: &str,
    base_dir: &Path,
    default: usize,
    materials: &mut Vec<NamedMaterial>,
) -> Result<Vec<(SourceSphere, usize)>, SceneError> {
    let Some(path) = &mut group.lammps_data else {
        return Ok(Vec::new());
    };
    let full = base_dir.join(&*path);
    let full = std::path::absolute(&full).unwrap_or(full);
    *path = full.display().to_string();
    let data = LammpsData::read_for(&full, &format!("{key}.lammps_data"))?;
    let by_type = type_materials(group, materials);
    let mut out = Vec::with_capacity(data.atoms.len());
    for atom in &data.atoms {
        let k = atom_material(
            atom,
            &by_type,
            default,
            group.fixed,
            materials,
            &format!("{key}.lammps_data"),
            &full,
        )?;
        out.push((atom.sphere, k));
    }
    Ok(out)
}

/// The spheres of one group; makes the group's file paths absolute.
fn group_spheres(
    group: &mut ParticlesSection,
    key: &str,
    base_dir: &Path,
    earlier: &Spheres,
) -> Result<Vec<SourceSphere>, SceneError> {
    let absolute = |p: &str| -> PathBuf {
        let p = base_dir.join(p);
        std::path::absolute(&p).unwrap_or(p)
    };
    if let Some(path) = &mut group.csv {
        let full = absolute(path);
        *path = full.display().to_string();
        return sources::csv::read_for(&full, &format!("{key}.csv"));
    }
    if let Some(r) = &group.random {
        let insertion = RandomInsertion {
            count: r.count,
            radius: r.radius.range(),
            lower: r.lower,
            upper: r.upper,
            velocity: r.velocity,
            seed: r.seed,
            max_attempts: r.max_attempts,
        };
        let existing: Vec<SourceSphere> = earlier
            .iter()
            .map(|s| SourceSphere {
                position: s.position,
                velocity: s.velocity,
                radius: s.radius,
            })
            .collect();
        return insertion.spheres(&format!("{key}.random"), &existing);
    }
    if let Some(list) = &group.spheres {
        return Ok(list
            .iter()
            .map(|s| SourceSphere {
                position: s.position,
                velocity: s.velocity,
                radius: s.radius,
            })
            .collect());
    }
    Err(SceneError::input(format!("`{key}`: no source")))
}

/// The lattice of group `key`'s `lattice` table (`key`: `particles[i]`),
/// validated ([`Lattice::validate`], its messages naming `key.lattice`).
fn lattice_of(l: &LatticeSource, key: &str) -> Result<Lattice, SceneError> {
    let lattice = Lattice {
        counts: l.counts,
        spacing: l.spacing,
        origin: l.origin,
        radius: l.radius,
        stagger: l.stagger,
    };
    lattice.validate(&format!("{key}.lattice"))?;
    Ok(lattice)
}

/// The spheres the lattices, random insertions and inline lists of `file`
/// make (known before any is made), and the largest group named with its
/// count. A lattice over its own maximum is left to its validation.
fn generated_count(file: &SceneFile) -> (u64, String) {
    let mut count: u64 = 0;
    let mut largest = (0u64, String::from("[[particles]]"));
    for (i, group) in file.particles.iter().enumerate() {
        let (made, key) = if let Some(l) = &group.lattice {
            let n = l
                .counts
                .iter()
                .fold(1u64, |n, &c| n.saturating_mul(c as u64));
            let n = if n > crate::sources::lattice::MAX_SPHERES as u64 {
                0
            } else {
                n
            };
            (n, format!("particles[{i}].lattice.counts = {:?}", l.counts))
        } else if let Some(r) = &group.random {
            (
                r.count as u64,
                format!("particles[{i}].random.count = {}", r.count),
            )
        } else {
            let n = group.spheres.as_ref().map_or(0, |s| s.len() as u64);
            (n, format!("particles[{i}].spheres"))
        };
        if made > largest.0 {
            largest = (made, key);
        }
        count = count.saturating_add(made);
    }
    let what = if count == largest.0 {
        largest.1
    } else {
        format!("[[particles]] (the largest group: {})", largest.1)
    };
    (count, what)
}

/// The spheres the random insertions and inline lists of `file` make:
/// the generated ones held listed (a lattice is held as its formula).
fn listed_count(file: &SceneFile) -> u64 {
    file.particles
        .iter()
        .map(|g| match (&g.random, &g.spheres) {
            (Some(r), _) => r.count as u64,
            (None, Some(list)) => list.len() as u64,
            (None, None) => 0,
        })
        .fold(0u64, u64::saturating_add)
}

/// Whether `file` asks for friction anywhere (the spheres then carry
/// spins and springs: more memory each).
fn has_friction(file: &SceneFile) -> bool {
    let c = &file.contact;
    c.friction.is_some()
        || c.rolling_friction.is_some()
        || file
            .materials
            .iter()
            .any(|m| m.friction.is_some() || m.rolling_friction.is_some())
        || file
            .walls
            .iter()
            .any(|w| w.friction.is_some() || w.rolling_friction.is_some())
}

/// The impact speed of the contact-time estimate when the file gives none:
/// the larger of a free fall across the whole domain along g, √(2 |g| H)
/// (H the box's extent along g), and the fastest initial speed.
fn default_impact_speed(
    file: &SceneFile,
    spheres: impl IntoIterator<Item = SphereInit>,
) -> Result<f64, SceneError> {
    let g = file.motion.gravity;
    let g_norm = (g[0] * g[0] + g[1] * g[1] + g[2] * g[2]).sqrt();
    let d = &file.domain;
    let height: f64 = if g_norm > 0.0 {
        (0..3)
            .map(|k| g[k].abs() / g_norm * (d.upper[k] - d.lower[k]))
            .sum()
    } else {
        0.0
    };
    let fall = (2.0 * g_norm * height).sqrt();
    let fastest = spheres
        .into_iter()
        .filter(|s| !s.fixed)
        .map(|s| (s.velocity[0].powi(2) + s.velocity[1].powi(2) + s.velocity[2].powi(2)).sqrt())
        .fold(0.0, f64::max);
    let v = fall.max(fastest);
    if v > 0.0 {
        Ok(v)
    } else {
        Err(SceneError::input(
            "`integration.impact_speed` is needed with `eta`: no gravity and no initial velocity to \
             estimate it from (give a speed in m/s, > 0)",
        ))
    }
}
