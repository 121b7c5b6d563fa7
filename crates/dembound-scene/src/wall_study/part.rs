//! The wall study on the user's own part (issue 29, `dembound wall-study
//! --wall SURFACE`): single impacts at random (seeded) points of a
//! triangle mesh, the particle coming along the local face normal (normal
//! incidence) or at an angle from it, against the mesh wall itself (of a
//! reference material: the particles' own, steel, glass or any E, ν, ρ)
//! and against boundary-particle coverings of the same mesh
//! ([`crate::sources::mesh_tiling`]) of R_b = r R whose spheres have the
//! reference material with E scaled by ζ. The same points and directions
//! for every wall, so the deviations are paired.
//!
//! The bed settled in the part and its discharge: [`super::part_bed`],
//! run after the impacts on the same walls when [`PartConfig::bed`] is set.

use dembound_physics::material::Material;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::path::Path;

use super::part_bed::{self, BedWall, PartBed, PartBedConfig, PartRegion};
use super::{base_setup, StudyConfig};
use crate::setup::{BoundaryParticles, NamedMaterial, SphereInit, WallSetup};
use crate::sources::mesh_tiling::{cover_named, Covering, CoveringOptions, Names};
use crate::sources::tiling::Pattern;
use crate::walls::mesh::geometry::{cross, dot, norm, scale, sub};
use crate::walls::mesh::{Mesh, MeshGeometry, MeshOptions, Transform, Triangle};
use crate::{SceneError, Simulation};

/// One particle covering of the part: R_b = r R, E_b = ζ E_reference.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CoveringSpec {
    pub radius_ratio: f64,
    pub modulus_ratio: f64,
    pub pattern: Pattern,
}

impl CoveringSpec {
    /// `r=1 zeta=100 square`.
    pub fn label(&self) -> String {
        super::Floor::Particles {
            radius_ratio: self.radius_ratio,
            modulus_ratio: self.modulus_ratio,
            pattern: self.pattern,
        }
        .label()
    }
}

/// What the part study runs.
#[derive(Debug, Clone)]
pub struct PartConfig {
    /// The particles, contact law, impacts (per angle), speed, angles, η,
    /// seed and floor friction of the plane study; its `floors`, bed and
    /// chute are not used.
    pub study: StudyConfig,
    /// The part's triangles, m (the particles on the normals' side, or
    /// behind them with `flip`).
    pub triangles: Vec<Triangle>,
    /// The particles are behind the triangles' normals (a part whose
    /// normals point away from its inside, e.g. `hopper.stl`).
    pub flip: bool,
    /// Names the part in errors.
    pub name: String,
    /// The mesh wall's material (ζ is relative to its E).
    pub reference: Material,
    pub coverings: Vec<CoveringSpec>,
    /// The bed and the flow (`None`: impacts only).
    pub bed: Option<PartBedConfig>,
}

/// Where and how a particle is thrown at the part.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ImpactPoint {
    /// Incidence angle from the local normal, degrees.
    pub angle: f64,
    /// Point of the surface, m.
    pub point: [f64; 3],
    /// Unit face normal toward the particle.
    pub normal: [f64; 3],
    /// Unit tangent of the incidence plane (the velocity's tangential part).
    pub tangent: [f64; 3],
}

/// One impact, in the local frame (n, t, b = n × t) of its point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PartImpact {
    pub at: ImpactPoint,
    /// v'·n / v_n.
    pub normal_restitution: f64,
    /// v'·t / v_t (NaN at normal incidence).
    pub tangential_restitution: f64,
    /// |v'| / |v|.
    pub speed_ratio: f64,
    /// Angle of the rebound from the normal, degrees.
    pub rebound_angle: f64,
    /// v'·b / |v|: sideways deflection.
    pub deflection: f64,
    /// From the first contact's onset to the last one's end, s.
    pub contact_time: f64,
    pub contacts: usize,
    /// Rebound spin magnitude, rad/s.
    pub spin: f64,
}

/// The impacts on one wall of the part.
#[derive(Debug, Clone)]
pub struct PartWallResult {
    /// `None`: the mesh wall (the reference).
    pub covering: Option<CoveringSpec>,
    pub label: String,
    /// Boundary spheres of the covering (0 for the mesh).
    pub spheres: usize,
    pub impacts: Vec<PartImpact>,
}

/// The part study's results: the mesh wall first.
#[derive(Debug, Clone)]
pub struct PartResults {
    pub walls: Vec<PartWallResult>,
    /// The coverings' spheres (for pictures), in `coverings` order.
    pub coverings: Vec<Covering>,
    /// Where the bed went, and the bed on each wall (`walls` order).
    pub region: Option<PartRegion>,
    pub beds: Vec<PartBed>,
    /// The mesh wall's bed scene as a `dembound scene` file (a part read
    /// from a file only).
    pub mesh_scene: Option<String>,
    /// s.
    pub dt: f64,
}

impl PartConfig {
    /// Checks the numbers (the plane study's, the reference material's
    /// and each covering's); an error names the option.
    pub fn validate(&self) -> Result<(), SceneError> {
        let mut study = self.study.clone();
        study.floors = self
            .coverings
            .iter()
            .map(|c| super::Floor::Particles {
                radius_ratio: c.radius_ratio,
                modulus_ratio: c.modulus_ratio,
                pattern: c.pattern,
            })
            .collect();
        study.chute = None;
        study.validate()?;
        if let Some(bed) = &self.bed {
            bed.validate()?;
        }
        let m = &self.reference;
        let ok = m.density.is_finite()
            && m.density > 0.0
            && m.youngs_modulus > 0.0
            && !m.youngs_modulus.is_nan()
            && m.poisson_ratio > -1.0
            && m.poisson_ratio < 0.5;
        if !ok {
            return Err(SceneError::invalid(
                "--reference-material",
                format!(
                    "E = {} Pa, ν = {}, ρ = {} kg/m³",
                    m.youngs_modulus, m.poisson_ratio, m.density
                ),
                "E > 0 Pa (or inf), -1 < ν < 0.5, ρ > 0 kg/m³",
            ));
        }
        Ok(())
    }

    /// Where the bed goes ([`part_bed::region`]), `None` without a bed:
    /// refuses a part with no pour column on its particles' side before
    /// anything runs.
    pub fn bed_region(&self) -> Result<Option<PartRegion>, SceneError> {
        let Some(bed) = &self.bed else {
            return Ok(None);
        };
        let g = geometry(self)?;
        part_bed::region(&g, self.flip, self.study.radius, bed.particles, &self.name).map(Some)
    }

    /// The boundary spheres' material of `spec`: the reference, E × ζ.
    pub fn boundary_material(&self, spec: &CoveringSpec) -> Material {
        Material {
            youngs_modulus: self.reference.youngs_modulus * spec.modulus_ratio,
            ..self.reference
        }
    }

    /// The shortest Hertz contact time of the particle against a flat wall
    /// of any of the walls' materials at the impact speed, s (the flat wall
    /// is the stiffest geometry: a boundary sphere's curvature lengthens
    /// the contact). t_c = 2.87 h_max / v, h_max = (5 m v² / (4 k))^(2/5),
    /// k = 4/3 E* √R, 1/E* = (1 − ν²)/E + (1 − ν_w²)/E_w (Johnson,
    /// Contact Mechanics, §11.4).
    pub fn contact_time(&self) -> f64 {
        let wall_compliance = self
            .coverings
            .iter()
            .map(|c| self.boundary_material(c).compliance())
            .fold(self.reference.compliance(), f64::min);
        let c = &self.study;
        // Written as the plane study's (`StudyConfig::contact_time`): a
        // wall of the particles' material gives its Δt to the bit.
        let e_eff = 4.0 / 3.0 / (c.material.compliance() + wall_compliance);
        let k = e_eff * c.radius.sqrt();
        let mass = c.material.sphere_mass(c.radius);
        let h_max = (1.25 * mass * c.speed * c.speed / k).powf(0.4);
        dembound_physics::contact::HERTZ_CONTACT_TIME_FACTOR * h_max / c.speed
    }

    /// Δt = η × [`Self::contact_time`], s.
    pub fn dt(&self) -> f64 {
        self.study.eta * self.contact_time()
    }
}

fn geometry(c: &PartConfig) -> Result<MeshGeometry, SceneError> {
    MeshGeometry::from_triangles(
        Path::new(&c.name),
        &c.triangles,
        &Transform::default(),
        &MeshOptions::default(),
    )
    .map_err(|e| SceneError::input(e.to_string()))
}

/// The impact points: per angle, `impacts` points uniform over the
/// part's area (a triangle chosen with probability ∝ its area, a point
/// uniform on it), each with a uniformly random tangent direction; one
/// seeded stream, the same for every wall.
pub fn impact_points(
    mesh: &MeshGeometry,
    flip: bool,
    angles: &[f64],
    impacts: usize,
    seed: u64,
) -> Vec<ImpactPoint> {
    let tri: Vec<[[f64; 3]; 3]> = mesh
        .triangles
        .iter()
        .map(|t| t.map(|v| mesh.vertices[v as usize]))
        .collect();
    let mut cumulative = Vec::with_capacity(tri.len());
    let mut total = 0.0;
    for t in &tri {
        total += 0.5 * norm(cross(sub(t[1], t[0]), sub(t[2], t[0])));
        cumulative.push(total);
    }
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut out = Vec::with_capacity(angles.len() * impacts);
    for &angle in angles {
        for _ in 0..impacts {
            let pick = rng.gen::<f64>() * total;
            let k = cumulative.partition_point(|&c| c < pick).min(tri.len() - 1);
            let [a, b, c] = tri[k];
            // Uniform on the triangle: (1 − √u) a + √u (1 − w) b + √u w c.
            let (u, w) = (rng.gen::<f64>().sqrt(), rng.gen::<f64>());
            let point: [f64; 3] =
                std::array::from_fn(|i| (1.0 - u) * a[i] + u * (1.0 - w) * b[i] + u * w * c[i]);
            let n = cross(sub(b, a), sub(c, a));
            let normal = scale(n, if flip { -1.0 } else { 1.0 } / norm(n));
            let e1 = sub(b, a);
            let e1 = scale(e1, 1.0 / norm(e1));
            let e2 = cross(normal, e1);
            let phi = rng.gen::<f64>() * std::f64::consts::TAU;
            let tangent: [f64; 3] = std::array::from_fn(|i| phi.cos() * e1[i] + phi.sin() * e2[i]);
            out.push(ImpactPoint {
                angle,
                point,
                normal,
                tangent,
            });
        }
    }
    out
}

/// The wall a particle meets in one impact scene.
enum Target<'a> {
    Mesh(&'a Mesh),
    Particles(&'a Covering, Material),
}

fn impact(
    c: &PartConfig,
    target: &Target,
    at: &ImpactPoint,
    dt: f64,
) -> Result<PartImpact, SceneError> {
    let st = &c.study;
    let r = st.radius;
    let th = at.angle.to_radians();
    let (vn, vt) = (st.speed * th.cos(), st.speed * th.sin());
    let gap = 0.05 * r;
    let start: [f64; 3] = std::array::from_fn(|i| at.point[i] + (r + gap) * at.normal[i]);
    let velocity: [f64; 3] = std::array::from_fn(|i| vt * at.tangent[i] - vn * at.normal[i]);
    // The boundary spheres within reach of the particle in the impact.
    let reach = match target {
        Target::Mesh(_) => 0.0,
        Target::Particles(cov, _) => cov.options.radius,
    };
    let near = 12.0 * r + 2.0 * reach;
    let (mut lo, mut hi) = (start, start);
    let mut bodies = Vec::new();
    match target {
        Target::Mesh(m) => {
            for i in 0..3 {
                lo[i] = lo[i].min(m.geometry.lo[i]);
                hi[i] = hi[i].max(m.geometry.hi[i]);
            }
        }
        Target::Particles(cov, _) => {
            for s in &cov.spheres {
                if norm(sub(s.position, at.point)) <= near {
                    bodies.push(s.position);
                    for i in 0..3 {
                        lo[i] = lo[i].min(s.position[i]);
                        hi[i] = hi[i].max(s.position[i]);
                    }
                }
            }
        }
    }
    let margin = 3.0 * r + 2.5 * reach;
    let lo = lo.map(|x| x - margin);
    let hi = hi.map(|x| x + margin);
    let mut s = base_setup(st, lo, hi, dt);
    s.materials.push(NamedMaterial {
        name: "reference".into(),
        material: c.reference,
    });
    s.spheres.push(SphereInit {
        position: start,
        velocity,
        radius: r,
        material: 0,
        fixed: false,
        group: None,
    });
    match target {
        Target::Mesh(m) => {
            let mut m = (*m).clone();
            m.material = 1;
            s.walls.push(WallSetup::Mesh(m));
        }
        Target::Particles(cov, material) => {
            s.materials.push(NamedMaterial {
                name: "boundary".into(),
                material: *material,
            });
            for &p in &bodies {
                s.spheres.push(SphereInit {
                    position: p,
                    velocity: [0.0; 3],
                    radius: cov.options.radius,
                    material: 2,
                    fixed: true,
                    group: Some(0),
                });
            }
            s.walls
                .push(WallSetup::BoundaryParticles(BoundaryParticles {
                    first_body: 1,
                    count: bodies.len(),
                }));
        }
    }
    s.friction = st.friction_setup(&s, 0, &[]);
    s.collisions = true;
    let mut sim = Simulation::new(s, 1)?;
    let fall = (2.0 * reach + 2.0 * r) / vn.max(1e-3 * st.speed);
    let max_steps = ((20.0 * c.contact_time() + fall) / dt) as u64 + 100;
    let mut done = 0;
    while done < max_steps {
        sim.step_guarded(50)?;
        done += 50;
        let v = sim.velocities()[0];
        if dot(v, at.normal) > 0.0 && sim.wall_contacts() == 0 && !sim.collisions().is_empty() {
            break;
        }
    }
    let v = sim.velocities()[0];
    let w = sim.angular_velocities()[0];
    let log = sim.collisions();
    let t0 = log.iter().map(|k| k.t_start).fold(f64::INFINITY, f64::min);
    let t1 = log
        .iter()
        .map(|k| k.t_end)
        .fold(f64::NEG_INFINITY, f64::max);
    let b = cross(at.normal, at.tangent);
    let (v_n, v_t, v_b) = (dot(v, at.normal), dot(v, at.tangent), dot(v, b));
    Ok(PartImpact {
        at: *at,
        normal_restitution: v_n / vn,
        tangential_restitution: if vt > 0.0 { v_t / vt } else { f64::NAN },
        speed_ratio: norm(v) / st.speed,
        rebound_angle: (v_t * v_t + v_b * v_b).sqrt().atan2(v_n).to_degrees(),
        deflection: v_b / st.speed,
        contact_time: t1 - t0,
        contacts: log.len(),
        spin: norm(w),
    })
}

/// Runs the impacts on the mesh wall, then on each covering; `progress`
/// gets each wall's label as it starts.
pub fn run(c: &PartConfig, mut progress: impl FnMut(&str)) -> Result<PartResults, SceneError> {
    c.validate()?;
    let geometry = geometry(c)?;
    let points = impact_points(
        &geometry,
        c.flip,
        &c.study.angles,
        c.study.impacts,
        c.study.seed,
    );
    let mesh = Mesh::from_triangles(Path::new(&c.name), &c.triangles, Transform::default(), 1)?;
    let dt = c.dt();
    let mut walls = Vec::new();
    progress("mesh wall");
    let impacts = points
        .iter()
        .map(|p| impact(c, &Target::Mesh(&mesh), p, dt))
        .collect::<Result<Vec<_>, _>>()?;
    walls.push(PartWallResult {
        covering: None,
        label: "mesh wall".into(),
        spheres: 0,
        impacts,
    });
    let mut coverings: Vec<Covering> = Vec::new();
    for spec in &c.coverings {
        progress(&spec.label());
        let rb = spec.radius_ratio * c.study.radius;
        let options = CoveringOptions {
            radius: rb,
            spacing: 2.0 * rb,
            pattern: spec.pattern,
            flip: c.flip,
        };
        // ζ does not change the geometry: one covering per (r, tiling).
        let covering = match coverings.iter().find(|k| k.options == options) {
            Some(k) => k.clone(),
            // R_b = r R and s = 2 R_b: `wall-study --radius-ratios` sets both.
            None => cover_named(
                Path::new(&c.name),
                &c.triangles,
                &options,
                Names {
                    radius: "--radius-ratios",
                    spacing: "--radius-ratios",
                },
            )?,
        };
        let target = Target::Particles(&covering, c.boundary_material(spec));
        let impacts = points
            .iter()
            .map(|p| impact(c, &target, p, dt))
            .collect::<Result<Vec<_>, _>>()?;
        walls.push(PartWallResult {
            covering: Some(*spec),
            label: spec.label(),
            spheres: covering.spheres.len(),
            impacts,
        });
        coverings.push(covering);
    }
    let (region, beds, mesh_scene) = match &c.bed {
        Some(bed) => beds(c, bed, &geometry, &mesh, &coverings, dt, &mut progress)?,
        None => (None, Vec::new(), None),
    };
    Ok(PartResults {
        walls,
        coverings,
        region,
        beds,
        mesh_scene,
        dt,
    })
}

type Beds = (Option<PartRegion>, Vec<PartBed>, Option<String>);

/// The bed on the mesh wall, then on each covering (`coverings` holds
/// one per (r, tiling), in the order of the first spec that made it).
fn beds(
    c: &PartConfig,
    bed: &PartBedConfig,
    geometry: &MeshGeometry,
    mesh: &Mesh,
    coverings: &[Covering],
    dt: f64,
    progress: &mut impl FnMut(&str),
) -> Result<Beds, SceneError> {
    let region = part_bed::region(geometry, c.flip, c.study.radius, bed.particles, &c.name)?;
    progress("bed on the mesh wall");
    let mut out = vec![part_bed::run(
        c,
        bed,
        &region,
        geometry,
        &BedWall::Mesh(mesh),
        dt,
    )?];
    for spec in &c.coverings {
        progress(&format!("bed on {}", spec.label()));
        let rb = spec.radius_ratio * c.study.radius;
        let Some(cov) = coverings
            .iter()
            .find(|k| k.options.radius == rb && k.options.pattern == spec.pattern)
        else {
            return Err(SceneError::input(format!(
                "no covering of r = {} for the bed",
                spec.radius_ratio
            )));
        };
        out.push(part_bed::run(
            c,
            bed,
            &region,
            geometry,
            &BedWall::Covering(cov, spec),
            dt,
        )?);
    }
    let file = Path::new(&c.name);
    let mesh_scene = if file.is_file() {
        let file = file
            .canonicalize()
            .map_err(|e| SceneError::input(format!("--wall `{}`: {e}", c.name)))?;
        let (_, steps) = part_bed::scene(c, bed, &region, &BedWall::Mesh(mesh), dt)?;
        Some(part_bed::mesh_scene_toml(c, &region, &file, dt, steps))
    } else {
        None
    };
    Ok((Some(region), out, mesh_scene))
}
