//! The scene engine as the Python class `dembound.Scene`: build from a
//! scene file or a dict, add spheres and plane walls from arrays, step,
//! read the state as NumPy arrays, write VTK snapshots and checkpoints.

use crate::args;
use crate::errors::{guarded, Failure};
use dembound_scene::fingerprint::Fingerprint;
use dembound_scene::io::checkpoint::{self, CheckpointFile};
use dembound_scene::io::checkpoint_parts;
use dembound_scene::io::config::Particles;
use dembound_scene::io::config::{self, SceneFile};
use dembound_scene::io::resolve::resolve_with;
use dembound_scene::io::{series, vtk};
use dembound_scene::setup::{Cylinder, Mesh, Plane, SceneSetup, SphereInit, WallSetup};
use dembound_scene::walls::mesh::Transform;
use dembound_scene::{Partner, SceneError, Simulation};
use numpy::{IntoPyArray, PyArray1, PyArray2, PyArrayMethods};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyType};
use std::path::{Path, PathBuf};

mod inout;

fn scene_failure(e: SceneError) -> Failure {
    if e.is_input() {
        Failure::Input(e.to_string())
    } else {
        Failure::Failed(e.to_string())
    }
}

/// Rows of 3 as an (n, 3) array.
fn rows3<'py>(py: Python<'py>, rows: Vec<[f64; 3]>) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let n = rows.len();
    let flat: Vec<f64> = rows.into_iter().flatten().collect();
    flat.into_pyarray(py).reshape([n, 3])
}

/// A many-particle scene (spheres, plane walls, walls of boundary
/// particles). SI throughout: m, m/s, N, J, s.
#[pyclass(module = "dembound._native")]
pub struct Scene {
    /// The running scene; None while it has no spheres (a scene built
    /// from a dict without `[[particles]]`, before `add_particles`).
    sim: Option<Simulation>,
    setup: SceneSetup,
    file: SceneFile,
    /// The spheres of each `[[particles]]` group (input indices), for
    /// `set_group_motion`.
    groups: Vec<std::ops::Range<usize>>,
    threads: usize,
    /// The row the last `observe()` returned (an outlet's rate is since
    /// it).
    observed: Option<dembound_scene::Observation>,
}

impl Scene {
    fn build(file: SceneFile, base: &Path, threads: usize) -> Result<Scene, Failure> {
        Scene::build_with(file, base, threads, Particles::Required)
    }

    fn build_with(
        file: SceneFile,
        base: &Path,
        threads: usize,
        particles: Particles,
    ) -> Result<Scene, Failure> {
        let resolved = resolve_with(&file, base, particles).map_err(scene_failure)?;
        let sim = Scene::start(&resolved.setup, threads)?;
        Ok(Scene {
            sim,
            setup: resolved.setup,
            file: resolved.file,
            groups: resolved.groups,
            threads,
            observed: None,
        })
    }

    /// The simulation of `setup`, or None when it has no spheres yet.
    fn start(setup: &SceneSetup, threads: usize) -> Result<Option<Simulation>, Failure> {
        if !inout::runnable(setup) {
            return Ok(None);
        }
        Ok(Some(
            Simulation::new(setup.clone(), threads).map_err(scene_failure)?,
        ))
    }

    /// The running simulation, or the error that the scene has no spheres.
    fn running(&self) -> Result<&Simulation, Failure> {
        self.sim.as_ref().ok_or_else(no_spheres)
    }

    /// Rows of the running simulation, none while it has no spheres.
    fn rows_or_none(&self, rows: fn(&Simulation) -> Vec<[f64; 3]>) -> Vec<[f64; 3]> {
        self.sim.as_ref().map_or_else(Vec::new, rows)
    }

    /// Advances `n` steps with the GIL released.
    fn advance(&mut self, py: Python<'_>, n: u64) -> PyResult<()> {
        let Some(sim) = self.sim.as_mut() else {
            return Err(no_spheres().into());
        };
        Ok(py.detach(|| guarded(|| sim.step_guarded(n).map_err(scene_failure)))?)
    }

    /// Rebuilds the simulation after the setup changed (only before the
    /// first step).
    fn rebuild(&mut self, what: &str) -> Result<(), Failure> {
        let steps_done = self.sim.as_ref().map_or(0, Simulation::steps_done);
        if steps_done > 0 {
            return Err(Failure::Input(format!(
                "{what}: the scene has run {steps_done} steps; bodies and walls can be added only before the first step"
            )));
        }
        self.sim = Scene::start(&self.setup, self.threads)?;
        Ok(())
    }
}

/// The error of a call that needs the spheres of a scene that has none yet.
fn no_spheres() -> Failure {
    Failure::Input(
        "the scene has no spheres yet: add them with add_particles() \
         (or [[particles]] in the scene) first"
            .into(),
    )
}

/// The most steps one `step()` or `run()` call takes (1e15 steps of the
/// smallest useful Δt are far beyond any run that ends).
const MAX_CALL_STEPS: u64 = 1_000_000_000_000_000;

/// The material index of a body or wall added from Python.
fn material_index(material: &Bound<'_, PyAny>, count: usize) -> Result<usize, Failure> {
    args::index(material, "material", 0, count.saturating_sub(1)).map_err(|e| match e {
        Failure::Input(m) => Failure::Input(format!("{m}: the scene's materials in file order")),
        other => other,
    })
}

#[pymethods]
impl Scene {
    /// A scene from a scene file (TOML, SI) with `--set`-style overrides
    /// (`["integration.steps=500"]`); relative source paths are taken from
    /// the file's directory. `threads`: worker threads (results do not
    /// depend on it), default 1.
    #[classmethod]
    #[pyo3(signature = (path, sets = None, threads = None))]
    fn from_toml(
        _cls: &Bound<'_, PyType>,
        py: Python<'_>,
        path: &Bound<'_, PyAny>,
        sets: Option<&Bound<'_, PyAny>>,
        threads: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Scene> {
        let path = args::path(path, "path")?;
        let sets = args::sets(sets)?;
        let threads = args::threads(threads)?;
        Ok(py.detach(|| {
            guarded(|| {
                let file = config::read(&path, &sets).map_err(scene_failure)?;
                let base = path.parent().unwrap_or(Path::new(".")).to_path_buf();
                Scene::build(file, &base, threads)
            })
        })?)
    }

    /// A scene from a dict with the scene file's structure; relative source
    /// paths are taken from `base_dir` (default: the current directory).
    /// Unlike a scene file, the dict may leave out `particles`: add the
    /// spheres with `add_particles()` before the first step.
    #[classmethod]
    #[pyo3(signature = (scene, base_dir = None, threads = None))]
    fn from_dict(
        _cls: &Bound<'_, PyType>,
        py: Python<'_>,
        scene: &Bound<'_, PyAny>,
        base_dir: Option<&Bound<'_, PyAny>>,
        threads: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Scene> {
        let table = crate::dict::table(scene)?;
        let base_dir = match base_dir.filter(|b| !b.is_none()) {
            Some(b) => Some(args::path(b, "base_dir")?),
            None => None,
        };
        let threads = args::threads(threads)?;
        Ok(py.detach(|| {
            guarded(|| {
                let file = config::from_table_with(table, "<dict>", Particles::Later)
                    .map_err(scene_failure)?;
                let base = base_dir.unwrap_or_else(|| PathBuf::from("."));
                Scene::build_with(file, &base, threads, Particles::Later)
            })
        })?)
    }

    /// A scene continued from a checkpoint written by `checkpoint()` or
    /// `dembound scene --out` (the scene recorded in it; bodies added from
    /// arrays are not recorded there: restore those with `restore()`), or
    /// from the index of one written in parts under MPI (`[parallel]
    /// checkpoint_per_rank`): its parts are read and merged, as the CLI
    /// does without mpirun.
    #[classmethod]
    #[pyo3(signature = (path, threads = None))]
    fn from_checkpoint(
        _cls: &Bound<'_, PyType>,
        py: Python<'_>,
        path: &Bound<'_, PyAny>,
        threads: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Scene> {
        let path = args::path(path, "path")?;
        let threads = args::threads(threads)?;
        Ok(py.detach(|| {
            guarded(|| {
                // Whole, or the index of one in parts (`[parallel]
                // checkpoint_per_rank`): its parts merged for this scene.
                let file = checkpoint::read_any(&path).map_err(scene_failure)?;
                let mut scene = Scene::build(file.scene.clone(), Path::new("."), threads)?;
                let fingerprint = Fingerprint::of(&scene.setup);
                let saved = checkpoint_parts::merge_file(&path, file, &fingerprint)
                    .map_err(scene_failure)?;
                drop(fingerprint);
                scene.sim = Some(
                    Simulation::restore(scene.setup.clone(), &saved.state, threads)
                        .map_err(scene_failure)?,
                );
                Ok(scene)
            })
        })?)
    }

    /// Adds spheres before the first step: `positions` (n, 3) m, `radii`
    /// (n,) m, optional `velocities` (n, 3) m/s, `fixed` (n,) bool and the
    /// material index (in the scene's `[[material]]` order).
    #[pyo3(signature = (positions, radii, velocities = None, fixed = None, material = None))]
    fn add_particles(
        &mut self,
        positions: &Bound<'_, PyAny>,
        radii: &Bound<'_, PyAny>,
        velocities: Option<&Bound<'_, PyAny>>,
        fixed: Option<&Bound<'_, PyAny>>,
        material: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<()> {
        let (r, _) = args::floats(radii, "radii", &[None])?;
        let n = r.len();
        let (p, _) = args::floats(positions, "positions", &[Some(n), Some(3)])?;
        let v = match velocities.filter(|v| !v.is_none()) {
            Some(v) => Some(args::floats(v, "velocities", &[Some(n), Some(3)])?.0),
            None => None,
        };
        let f = match fixed.filter(|f| !f.is_none()) {
            Some(f) => Some(args::flags(f, "fixed", n)?),
            None => None,
        };
        let material = match material {
            Some(m) => material_index(m, self.setup.materials.len())?,
            None => 0,
        };
        let before = self.setup.spheres.len();
        for i in 0..n {
            self.setup.spheres.push(SphereInit {
                position: [p[3 * i], p[3 * i + 1], p[3 * i + 2]],
                velocity: v
                    .as_ref()
                    .map_or([0.0; 3], |v| [v[3 * i], v[3 * i + 1], v[3 * i + 2]]),
                radius: r[i],
                material,
                fixed: f.as_ref().is_some_and(|f| f[i]),
                group: None,
            });
        }
        if let Err(e) = guarded(|| self.rebuild("add_particles")) {
            self.setup.spheres.truncate(before);
            return Err(e.into());
        }
        Ok(())
    }

    /// Adds an inlet before the first step, its arguments the keys of a
    /// scene file's `[[inlet]]` (README): `region` a dict `{"box":
    /// {"lower": [x, y, z], "upper": [x, y, z]}}` or `{"cylinder":
    /// {"center", "axis", "radius", "length"}}` (m); `rate` `{"number": N}`
    /// (spheres/s) or `{"mass": Q}` (kg/s); `size` (radii, m) `{"fixed":
    /// R}`, `{"uniform": [Rmin, Rmax]}`, `{"normal": {"mean", "std", "min",
    /// "max"}}` or `{"table": [[R, fraction], ...]}`; `material` a
    /// `[[material]]` name; `velocity` (m/s, default 0); `start`, `end`
    /// (s; default 0 and the run's end); `seed` (default 0); `every`
    /// (steps between insertion events; default from the rate);
    /// `max_attempts` (centres tried per sphere, default 100). A bad value
    /// is a ValueError naming the argument. A scene with an inlet runs
    /// without spheres of its own.
    #[pyo3(signature = (region, rate, size, material, velocity = None, start = None, end = None, seed = None, every = None, max_attempts = None))]
    #[allow(clippy::too_many_arguments)]
    fn add_inlet(
        &mut self,
        py: Python<'_>,
        region: &Bound<'_, PyAny>,
        rate: &Bound<'_, PyAny>,
        size: &Bound<'_, PyAny>,
        material: &Bound<'_, PyAny>,
        velocity: Option<&Bound<'_, PyAny>>,
        start: Option<&Bound<'_, PyAny>>,
        end: Option<&Bound<'_, PyAny>>,
        seed: Option<&Bound<'_, PyAny>>,
        every: Option<&Bound<'_, PyAny>>,
        max_attempts: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<()> {
        let given = [
            Some(region),
            Some(rate),
            Some(size),
            Some(material),
            velocity,
            start,
            end,
            seed,
            every,
            max_attempts,
        ];
        let named: Vec<_> = inout::INLET_ARGUMENTS.iter().copied().zip(given).collect();
        let table =
            crate::dict::table(inout::arguments(py, &named)?.as_any()).map_err(|e| match e {
                Failure::Input(m) => Failure::Input(format!("add_inlet: {m}")),
                other => other,
            })?;
        Ok(guarded(|| self.add_inlet_table(table))?)
    }

    /// Adds an outlet before the first step: `region` as a scene file's
    /// `[[outlet]] region` (README), a dict `{"box": {"lower": [x, y, z],
    /// "upper": [x, y, z]}}` or `{"cylinder": {"center", "axis", "radius",
    /// "length"}}` (m); the free spheres whose centres enter it are removed
    /// (counted in `observe()`'s `outletK_*` columns). A bad value is a
    /// ValueError naming the argument.
    fn add_outlet(&mut self, py: Python<'_>, region: &Bound<'_, PyAny>) -> PyResult<()> {
        let table = crate::dict::table(inout::arguments(py, &[("region", Some(region))])?.as_any())
            .map_err(|e| match e {
                Failure::Input(m) => Failure::Input(format!("add_outlet: {m}")),
                other => other,
            })?;
        Ok(guarded(|| self.add_outlet_table(table))?)
    }

    /// Adds a fixed plane wall before the first step: through `point` (m)
    /// with `normal` pointing into the domain, of material index `material`.
    #[pyo3(signature = (point, normal, material = None))]
    fn add_plane(
        &mut self,
        point: &Bound<'_, PyAny>,
        normal: &Bound<'_, PyAny>,
        material: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<()> {
        let three = |obj, name| -> Result<[f64; 3], Failure> {
            let (x, _) = args::floats(obj, name, &[Some(3)])?;
            Ok([x[0], x[1], x[2]])
        };
        let point = three(point, "point")?;
        let normal = three(normal, "normal")?;
        let material = match material {
            Some(m) => material_index(m, self.setup.materials.len())?,
            None => 0,
        };
        self.setup.walls.push(WallSetup::Plane(Plane {
            point,
            normal,
            material,
        }));
        if let Err(e) = guarded(|| self.rebuild("add_plane")) {
            self.setup.walls.pop();
            return Err(e.into());
        }
        Ok(())
    }

    /// Adds a fixed cylinder wall before the first step: a tube of
    /// `radius` (m) about the axis through `point` (m) along `axis`, the
    /// spheres `inside` it (else outside a post), closed by flat discs at
    /// point ± length/2 · axis when `length` (m) is given; of material index
    /// `material`.
    #[pyo3(signature = (point, axis, radius, inside = true, length = None, material = None))]
    #[allow(clippy::too_many_arguments)]
    fn add_cylinder(
        &mut self,
        point: &Bound<'_, PyAny>,
        axis: &Bound<'_, PyAny>,
        radius: &Bound<'_, PyAny>,
        inside: bool,
        length: Option<&Bound<'_, PyAny>>,
        material: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<()> {
        let three = |obj, name| -> Result<[f64; 3], Failure> {
            let (x, _) = args::floats(obj, name, &[Some(3)])?;
            Ok([x[0], x[1], x[2]])
        };
        let point = three(point, "point")?;
        let axis = three(axis, "axis")?;
        let radius = args::real(radius, "radius")?;
        let length = match length.filter(|l| !l.is_none()) {
            Some(l) => Some(args::real(l, "length")?),
            None => None,
        };
        let material = match material {
            Some(m) => material_index(m, self.setup.materials.len())?,
            None => 0,
        };
        self.setup.walls.push(WallSetup::Cylinder(Cylinder {
            point,
            axis,
            radius,
            inside,
            length,
            material,
        }));
        if let Err(e) = guarded(|| self.rebuild("add_cylinder")) {
            self.setup.walls.pop();
            return Err(e.into());
        }
        Ok(())
    }

    /// Adds a fixed triangle-mesh wall before the first step: the
    /// triangles of `path` (STL, binary or ASCII, or OBJ; relative to the
    /// working directory) placed by x' = R (scale x) + translate, R the
    /// rotation by `rotate_angle` degrees about `rotate_axis` through the
    /// origin; of material index `material`. The cleaning's counts
    /// (dropped triangles, open edges) are Python warnings.
    #[pyo3(signature = (path, scale = None, translate = None, rotate_axis = None, rotate_angle = None, material = None))]
    #[allow(clippy::too_many_arguments)]
    fn add_mesh(
        &mut self,
        py: Python<'_>,
        path: &Bound<'_, PyAny>,
        scale: Option<&Bound<'_, PyAny>>,
        translate: Option<&Bound<'_, PyAny>>,
        rotate_axis: Option<&Bound<'_, PyAny>>,
        rotate_angle: Option<&Bound<'_, PyAny>>,
        material: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<()> {
        let three = |obj, name| -> Result<[f64; 3], Failure> {
            let (x, _) = args::floats(obj, name, &[Some(3)])?;
            Ok([x[0], x[1], x[2]])
        };
        let path = args::path(path, "path")?;
        let mut transform = Transform::default();
        if let Some(s) = scale.filter(|x| !x.is_none()) {
            transform.scale = args::real(s, "scale")?;
        }
        if let Some(t) = translate.filter(|x| !x.is_none()) {
            transform.translate = three(t, "translate")?;
        }
        if let Some(a) = rotate_axis.filter(|x| !x.is_none()) {
            transform.axis = three(a, "rotate_axis")?;
        }
        if let Some(a) = rotate_angle.filter(|x| !x.is_none()) {
            transform.angle_degrees = args::real(a, "rotate_angle")?;
        }
        // The transform's ranges, named by this method's arguments.
        if let Err(e) = transform.validate() {
            let arg = match e {
                dembound_scene::walls::mesh::MeshError::Transform { key, .. } => {
                    key.replace("rotate.", "rotate_")
                }
                _ => "transform".into(),
            };
            return Err(Failure::Input(format!("{arg}: {e}")).into());
        }
        let material = match material {
            Some(m) if !m.is_none() => material_index(m, self.setup.materials.len())?,
            _ => 0,
        };
        let mesh = Mesh::load(&path, transform, material)
            .map_err(|e| Failure::Input(format!("path: {e}")))?;
        let d = &self.setup.domain;
        mesh.check_meets(d.lower, d.upper, "add_mesh")
            .map_err(scene_failure)?;
        for w in mesh.geometry.warnings() {
            let text = format!("add_mesh ({}): {w}", mesh.file_name());
            PyErr::warn(
                py,
                &py.get_type::<pyo3::exceptions::PyUserWarning>(),
                &std::ffi::CString::new(text).unwrap_or_default(),
                1,
            )?;
        }
        self.setup.walls.push(WallSetup::Mesh(mesh));
        if let Err(e) = guarded(|| self.rebuild("add_mesh")) {
            self.setup.walls.pop();
            return Err(e.into());
        }
        Ok(())
    }

    /// Gives wall `k` (file order, then walls added) a prescribed rigid
    /// motion before the first step (`[[wall]] motion` and `oscillation`
    /// of the scene file): translation at `velocity` (m/s) and rotation at
    /// `angular_velocity` (rad/s) about the axis through `center` (m),
    /// from `start` to `end` (s; default 0 and for ever), plus a
    /// sinusoidal translation `amplitude` sin(2π `frequency` t) (m, Hz)
    /// when both are given. A plane, cylinder or mesh, or a wall of
    /// boundary particles (its spheres move as one rigid body); the work
    /// the walls do shows in `observe()["work_by_walls_J"]`.
    #[pyo3(signature = (k, velocity = None, angular_velocity = None, center = None, start = None, end = None, amplitude = None, frequency = None))]
    #[allow(clippy::too_many_arguments)]
    fn set_wall_motion(
        &mut self,
        k: &Bound<'_, PyAny>,
        velocity: Option<&Bound<'_, PyAny>>,
        angular_velocity: Option<&Bound<'_, PyAny>>,
        center: Option<&Bound<'_, PyAny>>,
        start: Option<&Bound<'_, PyAny>>,
        end: Option<&Bound<'_, PyAny>>,
        amplitude: Option<&Bound<'_, PyAny>>,
        frequency: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<()> {
        use dembound_scene::walls::motion::{self, WallMotion};
        let walls = self.setup.walls.len();
        if walls == 0 {
            return Err(Failure::Input("k: the scene has no wall to move".into()).into());
        }
        let k = args::index(k, "k", 0, walls - 1)?;
        let (config, oscillation) = motion_args(
            velocity,
            angular_velocity,
            center,
            (start, end),
            (amplitude, frequency),
        )?;
        let key = format!("wall[{k}]");
        motion::validate(&key, Some(&config), oscillation.as_ref()).map_err(scene_failure)?;
        if self.setup.wall_servos.get(k).is_some_and(Option::is_some) {
            return Err(Failure::Input(format!(
                "invalid value for `{key}.motion`: given to a wall with a servo (allowed: a \
                 servo or a prescribed motion, not both: the servo sets the wall's velocity)"
            ))
            .into());
        }
        let before = self.setup.wall_motions.clone();
        self.setup.wall_motions.resize(walls, None);
        self.setup.wall_motions[k] = WallMotion::from_config(Some(&config), oscillation.as_ref());
        if let Err(e) = guarded(|| self.rebuild("set_wall_motion")) {
            self.setup.wall_motions = before;
            return Err(e.into());
        }
        Ok(())
    }

    /// Gives the `[[particles]]` group `group` (file order), all of whose
    /// spheres are fixed, a prescribed rigid motion before the first step
    /// (`[[particles]] motion` and `oscillation` of the scene file): each
    /// sphere, at X at t = 0, is at c(t) + R(t)(X − c₀), translating at
    /// `velocity` (m/s) and turning at `angular_velocity` (rad/s) about
    /// the axis through `center` (m), from `start` to `end` (s; default 0
    /// and for ever), plus `amplitude` sin(2π `frequency` t) (m, Hz) when
    /// both are given.
    #[pyo3(signature = (group, velocity = None, angular_velocity = None, center = None, start = None, end = None, amplitude = None, frequency = None))]
    #[allow(clippy::too_many_arguments)]
    fn set_group_motion(
        &mut self,
        group: &Bound<'_, PyAny>,
        velocity: Option<&Bound<'_, PyAny>>,
        angular_velocity: Option<&Bound<'_, PyAny>>,
        center: Option<&Bound<'_, PyAny>>,
        start: Option<&Bound<'_, PyAny>>,
        end: Option<&Bound<'_, PyAny>>,
        amplitude: Option<&Bound<'_, PyAny>>,
        frequency: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<()> {
        use dembound_scene::setup::GroupMotion;
        use dembound_scene::walls::motion::{self, WallMotion};
        if self.groups.is_empty() {
            return Err(Failure::Input(
                "group: the scene has no [[particles]] group to move".into(),
            )
            .into());
        }
        let k = args::index(group, "group", 0, self.groups.len() - 1)?;
        let (config, oscillation) = motion_args(
            velocity,
            angular_velocity,
            center,
            (start, end),
            (amplitude, frequency),
        )?;
        let key = format!("particles[{k}]");
        motion::validate(&key, Some(&config), oscillation.as_ref()).map_err(scene_failure)?;
        let spheres = self.groups[k].clone();
        if let Some(i) = spheres
            .clone()
            .find(|&i| self.setup.spheres.get(i).is_some_and(|s| !s.fixed))
        {
            return Err(Failure::Input(format!(
                "group: particles[{k}] has a free sphere (input index {i}); a group that moves \
                 is one of fixed spheres (fixed = true)"
            ))
            .into());
        }
        let before = self.setup.group_motions.clone();
        self.setup.group_motions.retain(|g| g.group != k);
        if let Some(m) = WallMotion::from_config(Some(&config), oscillation.as_ref()) {
            let at = self.setup.group_motions.partition_point(|g| g.group < k);
            self.setup.group_motions.insert(
                at,
                GroupMotion {
                    group: k,
                    spheres,
                    motion: m,
                },
            );
        }
        if let Err(e) = guarded(|| self.rebuild("set_group_motion")) {
            self.setup.group_motions = before;
            return Err(e.into());
        }
        Ok(())
    }

    /// Puts wall `k` (file order, then walls added) under force control
    /// before the first step (`[[wall]] servo` of the scene file): it
    /// moves along `axis` at v = `gain` `max_velocity` (F − N)/F, clamped
    /// to ±`max_velocity` (m/s), N the spheres' push against `axis` (N),
    /// F = `force` (N); LIGGGHTS's servo with `kp` = `gain` (default
    /// 0.01). A plane, cylinder or mesh without a prescribed motion; its
    /// position and velocity show in `observe()["wallK_position_z_m"]`
    /// and the like.
    #[pyo3(signature = (k, force, axis, max_velocity, gain = None))]
    fn set_wall_servo(
        &mut self,
        k: &Bound<'_, PyAny>,
        force: &Bound<'_, PyAny>,
        axis: &Bound<'_, PyAny>,
        max_velocity: &Bound<'_, PyAny>,
        gain: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<()> {
        use dembound_scene::walls::servo::{self, Servo, ServoConfig, DEFAULT_GAIN};
        let walls = self.setup.walls.len();
        if walls == 0 {
            return Err(Failure::Input("k: the scene has no wall to control".into()).into());
        }
        let k = args::index(k, "k", 0, walls - 1)?;
        let (a, _) = args::floats(axis, "axis", &[Some(3)])?;
        let config = ServoConfig {
            force: args::real(force, "force")?,
            axis: [a[0], a[1], a[2]],
            max_velocity: args::real(max_velocity, "max_velocity")?,
            gain: match gain.filter(|g| !g.is_none()) {
                None => DEFAULT_GAIN,
                Some(g) => args::real(g, "gain")?,
            },
        };
        let key = format!("wall[{k}]");
        if self.setup.walls[k].is_particles() {
            return Err(Failure::Input(format!(
                "invalid value for `{key}.servo`: a `{}` wall (allowed: a plane, cylinder or \
                 mesh; walls of boundary particles have no servo)",
                self.setup.walls[k].key()
            ))
            .into());
        }
        if self.setup.wall_motions.get(k).is_some_and(Option::is_some) {
            return Err(Failure::Input(format!(
                "invalid value for `{key}.servo`: given to a wall with a prescribed motion \
                 (allowed: a servo or a prescribed motion, not both)"
            ))
            .into());
        }
        if self.setup.wall_active.get(k).is_some_and(Option::is_some) {
            return Err(Failure::Input(format!(
                "invalid value for `{key}.servo`: given to a wall with an `active` window \
                 (allowed: a wall that acts always; a servo steers by a load the wall does \
                 not feel out of its window)"
            ))
            .into());
        }
        servo::validate(&key, &config).map_err(scene_failure)?;
        let before = self.setup.wall_servos.clone();
        self.setup.wall_servos.resize(walls, None);
        self.setup.wall_servos[k] = Some(Servo::from_config(&config));
        if let Err(e) = guarded(|| self.rebuild("set_wall_servo")) {
            self.setup.wall_servos = before;
            return Err(e.into());
        }
        Ok(())
    }

    /// Sets the window wall `k` (file order, then walls added) acts in,
    /// before the first step (`[[wall]] active = { from, to }` of the
    /// scene file): on the steps n with `start` ≤ n Δt < `end` (s; default
    /// 0 and inf); a plane, cylinder or mesh without a servo. Outside it
    /// the wall exerts no force; the elastic energy its contacts held when
    /// it vanishes (or its overlaps put in when it appears) shows in
    /// `observe()["gate_energy_J"]`.
    #[pyo3(signature = (k, start = None, end = None))]
    fn set_wall_active(
        &mut self,
        k: &Bound<'_, PyAny>,
        start: Option<&Bound<'_, PyAny>>,
        end: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<()> {
        use dembound_scene::walls::gate::{self, ActiveWindow};
        let walls = self.setup.walls.len();
        if walls == 0 {
            return Err(Failure::Input("k: the scene has no wall to switch".into()).into());
        }
        let k = args::index(k, "k", 0, walls - 1)?;
        let given = |x: Option<&Bound<'_, PyAny>>, name, default| -> Result<f64, Failure> {
            match x.filter(|x| !x.is_none()) {
                None => Ok(default),
                Some(x) => args::real(x, name),
            }
        };
        let window = ActiveWindow {
            from: given(start, "start", 0.0)?,
            to: given(end, "end", f64::INFINITY)?,
        };
        let servo = self.setup.wall_servos.get(k).is_some_and(Option::is_some);
        gate::validate(
            &format!("wall[{k}]"),
            &window,
            self.setup.walls[k].key(),
            servo,
        )
        .map_err(scene_failure)?;
        let before = self.setup.wall_active.clone();
        self.setup.wall_active.resize(walls, None);
        self.setup.wall_active[k] = Some(window);
        if let Err(e) = guarded(|| self.rebuild("set_wall_active")) {
            self.setup.wall_active = before;
            return Err(e.into());
        }
        Ok(())
    }

    /// Advances `n` steps (0 to 1e15; GIL released), then checks the state
    /// and the energy balance (`Simulation::step_guarded`).
    fn step(&mut self, py: Python<'_>, n: &Bound<'_, PyAny>) -> PyResult<()> {
        let n = args::whole(n, "n", 0, MAX_CALL_STEPS)?;
        self.advance(py, n)
    }

    /// Runs for `duration` s (rounded to whole steps), or to the scene's
    /// end (`integration.steps`/`duration`) when None. `progress(done,
    /// total)` (steps of this call) is called about 100 times; Ctrl-C stops
    /// between chunks. Returns the steps taken.
    #[pyo3(signature = (duration = None, progress = None))]
    fn run(
        &mut self,
        py: Python<'_>,
        duration: Option<&Bound<'_, PyAny>>,
        progress: Option<Bound<'_, PyAny>>,
    ) -> PyResult<u64> {
        let progress = progress.filter(|p| !p.is_none());
        if let Some(p) = &progress {
            if !p.is_callable() {
                return Err(Failure::Input(format!(
                    "progress: {} of type {} (allowed: a callable progress(done, total), or None)",
                    args::repr(p),
                    args::type_name(p)
                ))
                .into());
            }
        }
        let duration = match duration.filter(|d| !d.is_none()) {
            Some(d) => Some(args::real(d, "duration")?),
            None => None,
        };
        let total = match duration {
            None => self.running()?.remaining_steps(),
            Some(d) if d.is_finite() && d >= 0.0 => {
                let dt = self.running()?.dt();
                let steps = (d / dt).round();
                if steps > MAX_CALL_STEPS as f64 {
                    return Err(Failure::Input(format!(
                        "duration: {d} s is {steps:e} steps of Δt = {dt} s (allowed: up to 1e15 steps)"
                    ))
                    .into());
                }
                steps as u64
            }
            Some(d) => {
                return Err(Failure::Input(format!(
                    "duration: {d} s (allowed: a finite time ≥ 0 s)"
                ))
                .into())
            }
        };
        let chunk = (total / 100).max(1);
        let mut done = 0;
        while done < total {
            let n = chunk.min(total - done);
            self.advance(py, n)?;
            done += n;
            if let Some(callback) = &progress {
                callback.call1((done, total))?;
            }
            py.check_signals()?;
        }
        Ok(done)
    }

    /// Simulated time, s (0 while the scene has no spheres).
    #[getter]
    fn time(&self) -> f64 {
        self.sim.as_ref().map_or(0.0, Simulation::time)
    }

    /// Δt, s (an error while the scene has no spheres: the time step
    /// rule needs them).
    #[getter]
    fn dt(&self) -> PyResult<f64> {
        Ok(self.running()?.dt())
    }

    /// The spheres removed so far under `domain.outside = "delete"`, as
    /// `(count, mass in kg, energy carried out in J)`; `None` when the
    /// scene removes none.
    #[getter]
    fn deleted(&self) -> Option<(u64, f64, f64)> {
        let sim = self.sim.as_ref()?;
        sim.removed().map(|r| (r.particles, r.mass, r.energy))
    }

    /// Steps taken since the start (restarts included).
    #[getter]
    fn steps_done(&self) -> u64 {
        self.sim.as_ref().map_or(0, Simulation::steps_done)
    }

    /// The scene's run length in steps (an error while it has no spheres).
    #[getter]
    fn total_steps(&self) -> PyResult<u64> {
        Ok(self.running()?.total_steps())
    }

    /// Number of spheres (boundary particles included).
    fn __len__(&self) -> usize {
        self.sim.as_ref().map_or(0, Simulation::body_count)
    }

    /// Centres, (n, 3) m, input order.
    #[getter]
    fn positions<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        rows3(py, self.rows_or_none(Simulation::positions))
    }

    /// Velocities, (n, 3) m/s.
    #[getter]
    fn velocities<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        rows3(py, self.rows_or_none(Simulation::velocities))
    }

    /// Angular velocities, (n, 3) rad/s (zero without friction).
    #[getter]
    fn angular_velocities<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        rows3(py, self.rows_or_none(Simulation::angular_velocities))
    }

    /// Force on each sphere at the last force evaluation, (n, 3) N.
    #[getter]
    fn forces<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        rows3(py, self.rows_or_none(Simulation::forces))
    }

    /// Radii, (n,) m.
    #[getter]
    fn radii<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        self.sim
            .as_ref()
            .map_or_else(Vec::new, Simulation::radii)
            .into_pyarray(py)
    }

    /// Masses, (n,) kg: 4/3 π r³ ρ of each sphere's material (a fixed
    /// sphere's too, although the dynamics treats it as infinitely heavy).
    #[getter]
    fn masses<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        let masses: Vec<f64> = self.sim.as_ref().map_or_else(Vec::new, |sim| {
            sim.radii()
                .into_iter()
                .zip(sim.material_indices())
                .map(|(r, m)| self.setup.materials[m].material.sphere_mass(r))
                .collect()
        });
        masses.into_pyarray(py)
    }

    /// Whether each sphere is fixed, (n,) bool.
    #[getter]
    fn fixed<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<bool>> {
        self.sim
            .as_ref()
            .map_or_else(Vec::new, Simulation::fixed)
            .into_pyarray(py)
    }

    /// Force on each wall (file order, then walls added), (walls, 3) N.
    #[getter]
    fn wall_forces<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        // No spheres: nothing loads the walls.
        let none = vec![[0.0; 3]; self.setup.walls.len()];
        rows3(py, self.sim.as_ref().map_or(none, Simulation::wall_forces))
    }

    /// Torque on each wall (file order, then walls added), (walls, 3) N m,
    /// about its point in `wall_torque_points`.
    #[getter]
    fn wall_torques<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let none = vec![[0.0; 3]; self.setup.walls.len()];
        rows3(py, self.sim.as_ref().map_or(none, Simulation::wall_torques))
    }

    /// The point each wall's torque is taken about, (walls, 3) m: a
    /// plane's point, a cylinder's axis point, the centroid of a
    /// boundary-particle wall's spheres.
    #[getter]
    fn wall_torque_points<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        rows3(py, self.running()?.wall_torque_points())
    }

    /// The loads of mesh wall `k` (file order, then walls added) per
    /// triangle of its cleaned mesh (the file's triangles in file order,
    /// degenerate and duplicate ones dropped), from the forces the last
    /// force stage applied, each contact given to one triangle (the one
    /// under the sphere's centre; on a seam, edge or vertex the lowest id
    /// holding it): a dict of NumPy arrays `force` (n, 3) N (on the wall),
    /// `pressure` (n,) Pa (|F·n̂|/A), `shear` (n,) Pa (|F − (F·n̂)n̂|/A),
    /// `area` (n,) m², `centroid` (n, 3) m. ValueError when wall `k` does
    /// not exist or is not a mesh.
    fn wall_triangle_loads<'py>(&self, py: Python<'py>, k: i64) -> PyResult<Bound<'py, PyDict>> {
        let loads = guarded(|| {
            let wall = usize::try_from(k).map_err(|_| {
                Failure::Input(format!("k: wall {k} does not exist (k must be ≥ 0)"))
            })?;
            self.running()?
                .wall_triangle_loads(wall)
                .map_err(|e| Failure::Input(format!("k: {e}")))
        })?;
        let out = PyDict::new(py);
        out.set_item("force", rows3(py, loads.force)?)?;
        out.set_item("pressure", loads.pressure.into_pyarray(py))?;
        out.set_item("shear", loads.shear.into_pyarray(py))?;
        out.set_item("area", loads.area.into_pyarray(py))?;
        out.set_item("centroid", rows3(py, loads.centroid)?)?;
        Ok(out)
    }

    /// Energies (J), contact counts, wall forces (N) and torques (N m)
    /// now: the CLI's series.csv row as a dict, keyed by its column names
    /// (units in the names: `time_s`, `kinetic_energy_J`,
    /// `wall0_force_z_N`, `outlet0_mass_kg`, `inlet0_inserted`, …); counts
    /// are ints, the rest floats. An outlet's `outletK_rate_kg_per_s` is
    /// the mass flow rate since the previous `observe()` call (the first:
    /// since t = 0), as series.csv's since its previous row.
    fn observe<'py>(&mut self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let sim = self.running()?;
        let observation = guarded(|| Ok(sim.observe()))?;
        let (header, cells) = series::series_columns(&observation, self.observed.as_ref());
        let out = PyDict::new(py);
        for (name, cell) in header.into_iter().zip(cells) {
            match cell {
                series::Cell::Count(n) => out.set_item(name, n)?,
                series::Cell::Value(x) => out.set_item(name, x)?,
            }
        }
        self.observed = Some(observation);
        Ok(out)
    }

    /// The collision log (completed contacts; needs `output.collisions =
    /// true` in the scene): arrays `i` (sphere), `j` (sphere, or -1),
    /// `wall` (plane wall index, or -1), `triangle` (the mesh triangle a
    /// mesh wall contact was on, or -1), `t_start`, `t_end`, `duration`
    /// (s), `max_overlap` (m), `max_normal_force` (N),
    /// `impact_normal_velocity`, `rebound_normal_velocity` (m/s).
    #[getter]
    fn collisions<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let log = self.sim.as_ref().map_or(&[][..], Simulation::collisions);
        let out = PyDict::new(py);
        let ints =
            |f: fn(&dembound_scene::Collision) -> i64| -> Vec<i64> { log.iter().map(f).collect() };
        out.set_item("i", ints(|c| c.i as i64).into_pyarray(py))?;
        out.set_item(
            "j",
            ints(|c| match c.j {
                Partner::Body(b) => b as i64,
                _ => -1,
            })
            .into_pyarray(py),
        )?;
        out.set_item(
            "wall",
            ints(|c| match c.j {
                Partner::Wall(w) => w as i64,
                _ => -1,
            })
            .into_pyarray(py),
        )?;
        out.set_item(
            "triangle",
            ints(|c| c.triangle.map_or(-1, i64::from)).into_pyarray(py),
        )?;
        let floats =
            |f: fn(&dembound_scene::Collision) -> f64| -> Vec<f64> { log.iter().map(f).collect() };
        out.set_item("t_start", floats(|c| c.t_start).into_pyarray(py))?;
        out.set_item("t_end", floats(|c| c.t_end).into_pyarray(py))?;
        out.set_item("duration", floats(|c| c.duration).into_pyarray(py))?;
        out.set_item("max_overlap", floats(|c| c.max_overlap).into_pyarray(py))?;
        out.set_item(
            "max_normal_force",
            floats(|c| c.max_normal_force).into_pyarray(py),
        )?;
        out.set_item(
            "impact_normal_velocity",
            floats(|c| c.impact_normal_velocity).into_pyarray(py),
        )?;
        out.set_item(
            "rebound_normal_velocity",
            floats(|c| c.rebound_normal_velocity).into_pyarray(py),
        )?;
        Ok(out)
    }

    /// Writes a VTK PolyData snapshot (`snapshot_STEP.vtp`, ParaView) into
    /// `directory` (created if missing) and returns its path.
    fn write_vtk(&self, py: Python<'_>, directory: &Bound<'_, PyAny>) -> PyResult<PathBuf> {
        let directory = args::path(directory, "directory")?;
        let sim = self.running()?;
        let path = directory.join(format!("snapshot_{:09}.vtp", sim.steps_done()));
        Ok(py.detach(|| {
            guarded(|| {
                std::fs::create_dir_all(&directory)
                    .and_then(|()| {
                        let mut w = std::io::BufWriter::new(std::fs::File::create(&path)?);
                        vtk::write_simulation(&mut w, sim)?;
                        std::io::Write::flush(&mut w)
                    })
                    .map_err(|e| {
                        Failure::Failed(format!("cannot write `{}`: {e}", path.display()))
                    })?;
                Ok(path.clone())
            })
        })?)
    }

    /// Writes a checkpoint (CBOR, the CLI's format) to `path`: the run goes
    /// on bit for bit from it with `restore()` or `Scene.from_checkpoint()`.
    fn checkpoint(&self, py: Python<'_>, path: &Bound<'_, PyAny>) -> PyResult<()> {
        let path = args::path(path, "path")?;
        let saved = guarded(|| {
            Ok(CheckpointFile::new(
                self.file.clone(),
                self.running()?.checkpoint(),
            ))
        })?;
        Ok(py.detach(|| {
            guarded(|| {
                let mut w = std::io::BufWriter::new(std::fs::File::create(&path).map_err(|e| {
                    Failure::Failed(format!("cannot write `{}`: {e}", path.display()))
                })?);
                checkpoint::write(&mut w, &saved).map_err(Failure::Failed)?;
                std::io::Write::flush(&mut w)
                    .map_err(|e| Failure::Failed(format!("cannot write `{}`: {e}", path.display())))
            })
        })?)
    }

    /// Replaces the state with a checkpoint of this same scene (same
    /// bodies and Δt), whole or in parts (merged).
    fn restore(&mut self, py: Python<'_>, path: &Bound<'_, PyAny>) -> PyResult<()> {
        let path = args::path(path, "path")?;
        let setup = self.setup.clone();
        let threads = self.threads;
        let sim = py.detach(|| {
            guarded(|| {
                // Whole, or merged from its parts.
                let fingerprint = Fingerprint::of(&setup);
                let saved =
                    checkpoint_parts::read_whole(&path, &fingerprint).map_err(scene_failure)?;
                drop(fingerprint);
                Simulation::restore(setup, &saved.state, threads).map_err(scene_failure)
            })
        })?;
        self.sim = Some(sim);
        Ok(())
    }

    fn __repr__(&self) -> String {
        match &self.sim {
            Some(sim) => format!(
                "Scene({} spheres, {} walls, t = {} s, step {}/{}, dt = {} s)",
                sim.body_count(),
                self.setup.walls.len(),
                sim.time(),
                sim.steps_done(),
                sim.total_steps(),
                sim.dt()
            ),
            None => format!(
                "Scene(0 spheres, {} walls, no spheres yet: add_particles() first)",
                self.setup.walls.len()
            ),
        }
    }
}

/// A prescribed motion's arguments (`set_wall_motion`,
/// `set_group_motion`), each checked by name: three floats for a vector,
/// a real for a time or frequency; an oscillation needs both its
/// amplitude and frequency.
#[allow(clippy::type_complexity)]
fn motion_args(
    velocity: Option<&Bound<'_, PyAny>>,
    angular_velocity: Option<&Bound<'_, PyAny>>,
    center: Option<&Bound<'_, PyAny>>,
    (start, end): (Option<&Bound<'_, PyAny>>, Option<&Bound<'_, PyAny>>),
    (amplitude, frequency): (Option<&Bound<'_, PyAny>>, Option<&Bound<'_, PyAny>>),
) -> Result<
    (
        dembound_scene::walls::motion::MotionConfig,
        Option<dembound_scene::walls::motion::OscillationConfig>,
    ),
    Failure,
> {
    use dembound_scene::walls::motion::{MotionConfig, OscillationConfig};
    fn given<'a, 'py>(o: Option<&'a Bound<'py, PyAny>>) -> Option<&'a Bound<'py, PyAny>> {
        o.filter(|x| !x.is_none())
    }
    let three = |obj: Option<&Bound<'_, PyAny>>, name| -> Result<[f64; 3], Failure> {
        match given(obj) {
            None => Ok([0.0; 3]),
            Some(obj) => {
                let (x, _) = args::floats(obj, name, &[Some(3)])?;
                Ok([x[0], x[1], x[2]])
            }
        }
    };
    let real = |obj: Option<&Bound<'_, PyAny>>, name, default| -> Result<f64, Failure> {
        given(obj).map_or(Ok(default), |x| args::real(x, name))
    };
    let config = MotionConfig {
        velocity: three(velocity, "velocity")?,
        angular_velocity: three(angular_velocity, "angular_velocity")?,
        center: three(center, "center")?,
        start: real(start, "start", 0.0)?,
        end: real(end, "end", f64::INFINITY)?,
    };
    let oscillation = match (given(amplitude), given(frequency)) {
        (None, None) => None,
        (Some(_), Some(_)) => Some(OscillationConfig {
            amplitude: three(amplitude, "amplitude")?,
            frequency: real(frequency, "frequency", 0.0)?,
        }),
        _ => {
            return Err(Failure::Input(
                "amplitude and frequency: give both (an oscillation) or neither".into(),
            ))
        }
    };
    Ok((config, oscillation))
}
