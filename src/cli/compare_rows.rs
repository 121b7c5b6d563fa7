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
//! their material from its `type` column (type = material + 1,
//! liggghts_inlets.rs), m = ρ 4/3 π R³.

use dembound_export::scene_dump::DumpRow;
use dembound_scene::setup::SceneSetup;
use dembound_scene::Simulation;

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
    pub fn read_dump_row(&self, row: &DumpRow) -> Result<Spheres, String> {
        let n = self.count();
        let mut out = Spheres::default();
        for s in &row.spheres {
            let Some(i) = (s.id as usize).checked_sub(1) else {
                return Err(format!("step {}: sphere id 0 (ids start at 1)", row.step));
            };
            let (radius, mass, fixed) = if i < n {
                (self.radius[i], self.mass[i], self.fixed[i])
            } else if !self.inserts {
                return Err(format!(
                    "step {}: sphere id {} where scene.toml has {n} spheres and no inlet",
                    row.step, s.id
                ));
            } else {
                let r = s.radius.ok_or_else(|| {
                    format!(
                        "step {}: sphere id {} (inserted) without a `radius` column",
                        row.step, s.id
                    )
                })?;
                let rho = s
                    .kind
                    .and_then(|t| (t as usize).checked_sub(1))
                    .and_then(|m| self.density.get(m))
                    .ok_or_else(|| {
                        format!(
                            "step {}: sphere id {} (inserted) of type {:?}: not one of the {} \
                             materials",
                            row.step,
                            s.id,
                            s.kind,
                            self.density.len()
                        )
                    })?;
                (r, sphere_mass(*rho, r), false)
            };
            out.index.push(i);
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
        .map(|i| (i + 1).to_string())
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
