//! The spheres of one row of a scene comparison, by id, for both runs: a
//! dump row of the peer (its size varies when an inlet inserts or an
//! outlet deletes) and dembound's state at the same step, each sphere
//! with its radius, mass and whether it is fixed; and whether the two
//! rows hold the same spheres.
//!
//! Ids: the decks number the scene's spheres 1..n in input order and
//! delete with `compress no` (the others keep their ids); spheres an
//! inlet places take the next ids in both codes (LIGGGHTS:
//! `Atom::tag_extend`, from the largest id there; dembound: the next
//! input index). Index `i` here is id − 1 (dembound's input index).
//! Spheres of the scene file take their radius, mass and fixedness from
//! it, inserted ones their radius from the dump's `radius` column and
//! their mass from its `mass` column (LAMMPS, lammps_inlets.rs) or else
//! from the material of its `type` column (type = material + 1,
//! liggghts_inlets.rs), m = ρ 4/3 π R³.
//!
//! **An id given again.** LIGGGHTS numbers an inserted sphere from the
//! largest id present (`FixInsert` calls `Atom::tag_extend`,
//! src/atom.cpp), so when the sphere of the largest id was deleted before
//! an insertion its id comes back on another sphere. [`RowReader`] reads
//! the rows in order and takes an id that is in a row after a row without
//! it (having been in one before) as a new sphere: radius from the dump,
//! mass from its type, free, and an index of its own
//! ([`REUSED`] · generation + id − 1), which no dembound sphere has, so the
//! comparison by id stops there (the two codes' ids no longer name the
//! same spheres). An id deleted and given again between two dump rows is
//! not seen (the dump is all there is to go by).

use dembound_export::scene_dump::{DumpRow, DumpedSphere};
use dembound_scene::setup::SceneSetup;
use dembound_scene::Simulation;
use std::collections::{BTreeSet, HashMap};

/// The index stride of an id given again ([`RowReader`]): the k-th sphere
/// to carry id `i + 1` has index `k · REUSED + i` (k ≥ 1), above any
/// input index of either code.
pub const REUSED: usize = 1 << 40;

/// The spheres of one row, ascending index (id − 1).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Spheres {
    pub index: Vec<usize>,
    pub position: Vec<[f64; 3]>,
    pub velocity: Vec<[f64; 3]>,
    /// rad/s (0 where the run does not say).
    pub spin: Vec<[f64; 3]>,
    /// m.
    pub radius: Vec<f64>,
    /// kg.
    pub mass: Vec<f64>,
    pub fixed: Vec<bool>,
}

impl Spheres {
    pub fn len(&self) -> usize {
        self.index.len()
    }

    /// Every column in ascending index.
    fn sort_by_index(&mut self) {
        let mut order: Vec<usize> = (0..self.len()).collect();
        order.sort_by_key(|&k| self.index[k]);
        fn apply<T: Copy>(v: &mut Vec<T>, order: &[usize]) {
            *v = order.iter().map(|&k| v[k]).collect();
        }
        apply(&mut self.index, &order);
        apply(&mut self.position, &order);
        apply(&mut self.velocity, &order);
        apply(&mut self.spin, &order);
        apply(&mut self.radius, &order);
        apply(&mut self.mass, &order);
        apply(&mut self.fixed, &order);
    }

    /// The free spheres' count.
    pub fn free(&self) -> usize {
        self.fixed.iter().filter(|f| !**f).count()
    }
}

/// m = ρ 4/3 π R³ (kg), in the order of operations the comparison has
/// always used.
fn sphere_mass(density: f64, radius: f64) -> f64 {
    density * 4.0 / 3.0 * std::f64::consts::PI * radius.powi(3)
}

/// What the rows need of the scene: its spheres and material densities.
pub struct SceneSpheres {
    radius: Vec<f64>,
    mass: Vec<f64>,
    fixed: Vec<bool>,
    density: Vec<f64>,
    /// The scene has inlets: ids beyond its spheres may come.
    inserts: bool,
    /// The scene has outlets: ids may go.
    removes: bool,
}

impl SceneSpheres {
    pub fn new(setup: &SceneSetup) -> Self {
        let density: Vec<f64> = setup.materials.iter().map(|m| m.material.density).collect();
        SceneSpheres {
            radius: setup.spheres.iter().map(|s| s.radius).collect(),
            mass: setup
                .spheres
                .iter()
                .map(|s| sphere_mass(density[s.material], s.radius))
                .collect(),
            fixed: setup.spheres.iter().map(|s| s.fixed).collect(),
            density,
            inserts: !setup.inlets.is_empty(),
            removes: !setup.outlets.is_empty()
                || setup.outside == dembound_scene::setup::Outside::Delete,
        }
    }

    /// The spheres of the scene file.
    pub fn count(&self) -> usize {
        self.radius.len()
    }

    /// The free spheres of the scene file.
    pub fn free(&self) -> usize {
        self.fixed.iter().filter(|f| !**f).count()
    }

    /// A peer's dump row; an error (what is wrong, for "not this deck's
    /// run") when it holds an id the scene cannot have (0; beyond the
    /// scene's spheres without inlets, or without a `radius` and a known
    /// `type`), or lacks one of the scene's spheres it cannot have lost.
    /// One row alone, for the tests ([`RowReader`] reads a run's rows).
    #[cfg(test)]
    pub fn read_dump_row(&self, row: &DumpRow) -> Result<Spheres, String> {
        self.read_row(row, &HashMap::new())
    }

    /// The radius and mass of an inserted sphere, from its dump columns:
    /// the `mass` column when there is one (LAMMPS decks), else ρ 4/3 π R³
    /// of the material of its `type`.
    fn inserted(&self, step: u64, s: &DumpedSphere) -> Result<(f64, f64), String> {
        let r = s.radius.ok_or_else(|| {
            format!(
                "step {step}: sphere id {} (inserted) without a `radius` column",
                s.id
            )
        })?;
        if let Some(m) = s.mass {
            return Ok((r, m));
        }
        let rho = s
            .kind
            .and_then(|t| (t as usize).checked_sub(1))
            .and_then(|m| self.density.get(m))
            .ok_or_else(|| {
                format!(
                    "step {step}: sphere id {} (inserted) of type {:?}: not one of the {} \
                     materials",
                    s.id,
                    s.kind,
                    self.density.len()
                )
            })?;
        Ok((r, sphere_mass(*rho, r)))
    }

    /// A dump row (`read_dump_row`'s errors), `generation` the times each
    /// id (by index) has been given again so far ([`RowReader`]).
    fn read_row(
        &self,
        row: &DumpRow,
        generation: &HashMap<usize, usize>,
    ) -> Result<Spheres, String> {
        let n = self.count();
        let mut out = Spheres::default();
        for s in &row.spheres {
            let Some(i) = (s.id as usize).checked_sub(1) else {
                return Err(format!("step {}: sphere id 0 (ids start at 1)", row.step));
            };
            let again = generation.get(&i).copied().unwrap_or(0);
            let (radius, mass, fixed) = if again > 0 {
                let (r, m) = self.inserted(row.step, s)?;
                (r, m, false)
            } else if i < n {
                (self.radius[i], self.mass[i], self.fixed[i])
            } else if !self.inserts {
                return Err(format!(
                    "step {}: sphere id {} where scene.toml has {n} spheres and no inlet",
                    row.step, s.id
                ));
            } else {
                let (r, m) = self.inserted(row.step, s)?;
                (r, m, false)
            };
            out.index.push(again * REUSED + i);
            out.position.push(s.position);
            out.velocity.push(s.velocity);
            out.spin.push(s.spin.unwrap_or([0.0; 3]));
            out.radius.push(radius);
            out.mass.push(mass);
            out.fixed.push(fixed);
        }
        if !self.removes {
            let have = out.index.iter().filter(|&&i| i < n).count();
            if have < n {
                return Err(format!(
                    "step {}: {have} spheres of ids 1..{n} where scene.toml has {n} spheres and \
                     no outlet",
                    row.step
                ));
            }
        }
        if !generation.is_empty() {
            out.sort_by_index();
        }
        Ok(out)
    }

    /// dembound's spheres now (positions as given: the caller wraps).
    pub fn read_simulation(&self, sim: &Simulation, position: Vec<[f64; 3]>) -> Spheres {
        let index: Vec<usize> = sim.ids().into_iter().map(|i| i as usize).collect();
        let radius = sim.radii();
        let material = sim.material_indices();
        let n = self.count();
        let mass = index
            .iter()
            .zip(&radius)
            .zip(&material)
            .map(|((&i, &r), &m)| {
                if i < n {
                    self.mass[i]
                } else {
                    sphere_mass(self.density[m], r)
                }
            })
            .collect();
        Spheres {
            position,
            velocity: sim.velocities(),
            spin: sim.angular_velocities(),
            mass,
            fixed: sim.fixed(),
            radius,
            index,
        }
    }
}

/// Reads a peer's dump rows in order, telling an id given again from the
/// sphere that had it (module doc).
pub struct RowReader<'a> {
    scene: &'a SceneSpheres,
    /// Times each index (id − 1) has been given again.
    generation: HashMap<usize, usize>,
    /// The indices of the last row read.
    present: BTreeSet<usize>,
    /// Indices that were in a row and missing from a later one.
    gone: BTreeSet<usize>,
}

impl<'a> RowReader<'a> {
    pub fn new(scene: &'a SceneSpheres) -> Self {
        RowReader {
            scene,
            generation: HashMap::new(),
            present: BTreeSet::new(),
            gone: BTreeSet::new(),
        }
    }

    /// The next row (SceneSpheres::read_dump_row's errors, and an id of
    /// the scene file given again in a scene without inlets).
    pub fn read(&mut self, row: &DumpRow) -> Result<Spheres, String> {
        let mut now = BTreeSet::new();
        for s in &row.spheres {
            let Some(i) = (s.id as usize).checked_sub(1) else {
                continue; // refused by read_row
            };
            if self.gone.remove(&i) {
                if !self.scene.inserts {
                    return Err(format!(
                        "step {}: sphere id {} is back after it was deleted, where scene.toml \
                         has no inlet",
                        row.step, s.id
                    ));
                }
                *self.generation.entry(i).or_insert(0) += 1;
            }
            now.insert(i);
        }
        self.gone.extend(self.present.difference(&now).copied());
        self.present = now;
        self.scene.read_row(row, &self.generation)
    }
}

/// The indices one row holds and the other does not: (only in `a`, only
/// in `b`), ascending.
pub fn set_difference(a: &Spheres, b: &Spheres) -> (Vec<usize>, Vec<usize>) {
    let (mut only_a, mut only_b) = (Vec::new(), Vec::new());
    let (mut i, mut j) = (0, 0);
    while i < a.len() || j < b.len() {
        match (a.index.get(i), b.index.get(j)) {
            (Some(x), Some(y)) if x == y => {
                i += 1;
                j += 1;
            }
            (Some(x), Some(y)) if x < y => {
                only_a.push(*x);
                i += 1;
            }
            (Some(x), None) => {
                only_a.push(*x);
                i += 1;
            }
            (_, Some(y)) => {
                only_b.push(*y);
                j += 1;
            }
            (None, None) => break,
        }
    }
    (only_a, only_b)
}

/// A short list of 1-based ids ("1, 2, 3 and 4 more").
pub fn ids_text(indices: &[usize]) -> String {
    let shown: Vec<String> = indices
        .iter()
        .take(5)
        .map(|i| match i / REUSED {
            0 => (i + 1).to_string(),
            _ => format!("{} (given again)", i % REUSED + 1),
        })
        .collect();
    if indices.len() > 5 {
        format!("{} and {} more", shown.join(", "), indices.len() - 5)
    } else {
        shown.join(", ")
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use dembound_export::scene_dump::parse_dump;
    use dembound_scene::io::{config, resolve::resolve};
    use std::path::Path;

    /// Two spheres of glass (ρ = 2500), the second fixed; one inlet of a
    /// second material (ρ = 1000) and one outlet when `flows`.
    fn scene(flows: bool) -> SceneSpheres {
        let extra = if flows {
            "[[inlet]]\nregion = { box = { lower = [0.0, 0.0, 0.006], upper = [0.01, 0.01, 0.01] } }\n\
             rate = { number = 100.0 }\nsize = { fixed = 1.5e-3 }\nmaterial = \"light\"\n\
             [[outlet]]\nregion = { box = { lower = [0.0, 0.0, 0.0], upper = [0.01, 0.01, 0.001] } }\n"
        } else {
            ""
        };
        let text = format!(
            r#"
[domain]
lower = [0.0, 0.0, 0.0]
upper = [0.01, 0.01, 0.01]
[[material]]
name = "glass"
density = 2500.0
youngs_modulus = 1.0e7
poisson_ratio = 0.3
[[material]]
name = "light"
density = 1000.0
youngs_modulus = 1.0e7
poisson_ratio = 0.3
[contact]
law = "hertz"
[[particles]]
spheres = [{{ position = [0.005, 0.005, 0.005], radius = 1.0e-3 }}]
material = "glass"
[[particles]]
spheres = [{{ position = [0.002, 0.002, 0.002], radius = 1.0e-3 }}]
material = "glass"
fixed = true
[motion]
gravity = [0.0, 0.0, -9.81]
[integration]
dt = 1.0e-6
steps = 10
{extra}"#
        );
        let file = config::load(&text, "rows", &[]).expect("the test's scene parses");
        let setup = resolve(&file, Path::new("."))
            .expect("the test's scene resolves")
            .setup;
        SceneSpheres::new(&setup)
    }

    fn row(lines: &[&str]) -> DumpRow {
        let text = format!(
            "ITEM: TIMESTEP\n5\nITEM: NUMBER OF ATOMS\n{}\nITEM: BOX BOUNDS mm mm mm\n0 1\n0 1\n0 1\n\
             ITEM: ATOMS id type radius x y z vx vy vz\n{}\n",
            lines.len(),
            lines.join("\n")
        );
        parse_dump(&text).expect("a hand-written row").remove(0)
    }

    #[test]
    fn inserted_spheres_take_the_dumps_radius_and_their_types_density() {
        let s = scene(true);
        // Sphere 1 deleted, 2 (fixed) there, 3 inserted of type 2.
        let r = s
            .read_dump_row(&row(&[
                "3 2 0.0015 0.005 0.005 0.009 0 0 -1",
                "2 1 0.001 0.002 0.002 0.002 0 0 0",
            ]))
            .expect("a row of this scene");
        assert_eq!(r.index, [1, 2]);
        assert_eq!(r.fixed, [true, false]);
        assert_eq!(r.radius, [1e-3, 1.5e-3]);
        // ρ 4/3 π R³ by hand: 1000 × 4.18879 × 3.375e-9.
        let m = 1000.0 * 4.0 / 3.0 * std::f64::consts::PI * 3.375e-9;
        assert_eq!(r.mass[1], m);
        assert!((r.mass[1] - 1.4137167e-5).abs() < 1e-12);
        assert_eq!(r.free(), 1);
        // A type that is no material, or no radius column, is refused.
        let e = s
            .read_dump_row(&row(&["3 3 0.0015 0.005 0.005 0.009 0 0 -1"]))
            .expect_err("type 3 of 2 materials");
        assert!(e.contains("type Some(3)"), "{e}");
    }

    #[test]
    fn a_scene_without_flows_wants_its_spheres_and_no_others() {
        let s = scene(false);
        let full = [
            "1 1 0.001 0.005 0.005 0.005 0 0 0",
            "2 1 0.001 0.002 0.002 0.002 0 0 0",
        ];
        assert_eq!(s.read_dump_row(&row(&full)).expect("both").len(), 2);
        let e = s.read_dump_row(&row(&full[..1])).expect_err("one missing");
        assert!(e.contains("1 spheres of ids 1..2"), "{e}");
        let e = s
            .read_dump_row(&row(&[full[0], full[1], "3 1 0.001 0 0 0 0 0 0"]))
            .expect_err("an id too many");
        assert!(e.contains("sphere id 3") && e.contains("no inlet"), "{e}");
    }

    /// LIGGGHTS gives the id of a deleted top sphere again: in the rows
    /// 1 2 3 | 1 2 | 1 2 3 (radius 1.5 mm, then 1.2 mm) the last 3 is a new
    /// sphere: read with its own radius and mass, of an index no dembound
    /// sphere has, so that it does not match dembound's sphere 3. A
    /// scene-file id given again (1, radius 1 mm in the file) takes the
    /// dump's radius (0.8 mm) and its type's density, not the file's.
    #[test]
    fn an_id_given_again_after_its_deletion_is_a_new_sphere() {
        let s = scene(true);
        let mut reader = RowReader::new(&s);
        let first = reader
            .read(&row(&[
                "1 1 0.001 0.005 0.005 0.005 0 0 0",
                "2 1 0.001 0.002 0.002 0.002 0 0 0",
                "3 2 0.0015 0.005 0.005 0.009 0 0 -1",
            ]))
            .expect("a row");
        assert_eq!(first.index, [0, 1, 2]);
        let second = reader
            .read(&row(&["2 1 0.001 0.002 0.002 0.002 0 0 0"]))
            .expect("spheres 1 and 3 deleted");
        assert_eq!(second.index, [1]);
        let third = reader
            .read(&row(&[
                "3 1 0.0012 0.005 0.005 0.009 0 0 -1",
                "2 1 0.001 0.002 0.002 0.002 0 0 0",
                "1 2 0.0008 0.004 0.004 0.009 0 0 -1",
            ]))
            .expect("ids 1 and 3 given again");
        // Ascending index: the fixed sphere 2, then 1 and 3 given again.
        assert_eq!(third.index, [1, REUSED, REUSED + 2]);
        assert_eq!(third.radius, [1e-3, 0.8e-3, 1.2e-3]);
        assert_eq!(third.fixed, [true, false, false]);
        // ρ 4/3 π R³: the light material (type 2) for id 1, glass for 3.
        // By hand: 1000 × 4.18879 × 5.12e-10 = 2.14466e-6 kg and 2500 ×
        // 4.18879 × 1.728e-9 = 1.80956e-5 kg (6 digits of the hand values).
        assert!(
            (third.mass[1] / 2.14466e-6 - 1.0).abs() < 5e-6,
            "{}",
            third.mass[1]
        );
        assert!(
            (third.mass[2] / 1.80956e-5 - 1.0).abs() < 5e-6,
            "{}",
            third.mass[2]
        );
        // Against dembound's spheres 2 and 3 (indices 1, 2): the new ones
        // are only in the peer, dembound's 3 only in dembound.
        let ours = Spheres {
            index: vec![1, 2],
            ..Spheres::default()
        };
        let (only_peer, only_ours) = set_difference(&third, &ours);
        assert_eq!(only_peer, [REUSED, REUSED + 2]);
        assert_eq!(only_ours, [2]);
        assert_eq!(ids_text(&only_peer), "1 (given again), 3 (given again)");
        // Still there in the next row: the same new sphere, not another.
        let fourth = reader
            .read(&row(&["3 1 0.0012 0.005 0.005 0.008 0 0 -1"]))
            .expect("id 3 stays");
        assert_eq!(fourth.index, [REUSED + 2]);
        // With an outlet but no inlet an id cannot come back.
        let outlet_only = SceneSpheres {
            inserts: false,
            ..scene(true)
        };
        let mut reader = RowReader::new(&outlet_only);
        let both = [
            "1 1 0.001 0.005 0.005 0.005 0 0 0",
            "2 1 0.001 0.002 0.002 0.002 0 0 0",
        ];
        reader.read(&row(&both)).expect("both");
        reader.read(&row(&both[1..])).expect("1 deleted");
        let e = reader.read(&row(&both)).expect_err("1 back");
        assert!(
            e.contains("sphere id 1 is back") && e.contains("no inlet"),
            "{e}"
        );
    }

    #[test]
    fn set_difference_by_index() {
        let with = |index: Vec<usize>| Spheres {
            index,
            ..Spheres::default()
        };
        let (a, b) = set_difference(&with(vec![0, 2, 3, 7]), &with(vec![1, 2, 7, 8, 9]));
        assert_eq!((a, b), (vec![0, 3], vec![1, 8, 9]));
        let (a, b) = set_difference(&with(vec![0, 1]), &with(vec![0, 1]));
        assert!(a.is_empty() && b.is_empty());
        assert_eq!(ids_text(&[0, 1, 2, 3, 4, 5, 6]), "1, 2, 3, 4, 5 and 2 more");
    }
}
