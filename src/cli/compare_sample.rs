//! What one row of a scene comparison gives (`dembound compare DECK`):
//! energies, contacts, bed height, wall forces, and the state difference
//! by id; the formulas in compare_scene.rs's module doc.

use super::compare_rows::Spheres;
use dembound_scene::setup::{SceneSetup, WallSetup};

/// What one row's state gives.
#[derive(Debug, Clone, Default)]
pub struct Sample {
    pub kinetic: f64,
    pub rotational: f64,
    pub potential: f64,
    pub contacts: f64,
    pub bed_height: f64,
    pub walls: Vec<f64>,
}

/// The fixed geometry: what every sample needs of the scene.
pub struct Geometry {
    gravity: [f64; 3],
    /// Unit vector "up" (−g, or z).
    up: [f64; 3],
    /// Plane walls: (point, unit normal into the domain).
    planes: Vec<([f64; 3], [f64; 3])>,
    /// The box length along each periodic axis (None: not periodic).
    period: [Option<f64>; 3],
}

pub fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

impl Geometry {
    pub fn new(setup: &SceneSetup) -> Self {
        let d = &setup.domain;
        let period: [Option<f64>; 3] =
            std::array::from_fn(|k| d.periodic[k].then(|| d.upper[k] - d.lower[k]));
        // Along a periodic axis a position is known only up to the box
        // length, so gravity there has no potential (a chute's flow gains
        // energy without end) and heights are taken along the rest of −g.
        let g: [f64; 3] = std::array::from_fn(|k| {
            if period[k].is_some() {
                0.0
            } else {
                setup.gravity[k]
            }
        });
        let gn = dot(g, g).sqrt();
        let up = if gn > 0.0 {
            [-g[0] / gn, -g[1] / gn, -g[2] / gn]
        } else {
            [0.0, 0.0, 1.0]
        };
        let planes = setup
            .walls
            .iter()
            .filter_map(|w| match w {
                WallSetup::Plane(p) => {
                    let l = dot(p.normal, p.normal).sqrt();
                    Some((p.point, p.normal.map(|c| c / l)))
                }
                _ => None,
            })
            .collect();
        Geometry {
            gravity: g,
            up,
            planes,
            period,
        }
    }

    /// b − a, by the nearest image on the periodic axes.
    pub fn separation(&self, a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
        std::array::from_fn(|k| {
            let d = b[k] - a[k];
            match self.period[k] {
                Some(l) => d - l * (d / l).round(),
                None => d,
            }
        })
    }

    pub fn sample(&self, s: &Spheres, walls: Vec<f64>) -> Sample {
        let mut out = Sample {
            walls,
            ..Sample::default()
        };
        let mut heights = Vec::new();
        for i in (0..s.len()).filter(|&i| !s.fixed[i]) {
            let (m, r) = (s.mass[i], s.radius[i]);
            out.kinetic += 0.5 * m * dot(s.velocity[i], s.velocity[i]);
            out.rotational += 0.5 * 0.4 * m * r * r * dot(s.spin[i], s.spin[i]);
            out.potential -= m * dot(self.gravity, s.position[i]);
            heights.push(dot(self.up, s.position[i]) + r);
            out.contacts += self
                .planes
                .iter()
                .filter(|(p, n)| {
                    let x = s.position[i];
                    dot(*n, [x[0] - p[0], x[1] - p[1], x[2] - p[2]]) < r
                })
                .count() as f64;
        }
        heights.sort_by(|a, b| b.total_cmp(a));
        let top = heights.len().div_ceil(10).max(1).min(heights.len());
        if top > 0 {
            out.bed_height = heights[..top].iter().sum::<f64>() / top as f64;
        }
        out.contacts += self.sphere_pairs(s) as f64;
        out
    }

    /// Overlapping sphere pairs, not both fixed, across periodic faces too
    /// (nearest image; sweep along the first non-periodic axis, every pair
    /// when all three are periodic).
    pub fn sphere_pairs(&self, s: &Spheres) -> usize {
        let x = &s.position;
        let axis = (0..3).find(|&k| self.period[k].is_none());
        let mut order: Vec<usize> = (0..x.len()).collect();
        if let Some(a) = axis {
            order.sort_by(|&p, &q| x[p][a].total_cmp(&x[q][a]));
        }
        let rmax = s.radius.iter().cloned().fold(0.0, f64::max);
        let mut count = 0;
        for (k, &i) in order.iter().enumerate() {
            for &j in &order[k + 1..] {
                if axis.is_some_and(|a| x[j][a] - x[i][a] > s.radius[i] + rmax) {
                    break;
                }
                if s.fixed[i] && s.fixed[j] {
                    continue;
                }
                let d = self.separation(x[i], x[j]);
                let reach = s.radius[i] + s.radius[j];
                if dot(d, d) < reach * reach {
                    count += 1;
                }
            }
        }
        count
    }

    /// The largest |Δx| / R_min over the free spheres both rows hold (by
    /// index; R_min the smallest of their radii; Δx by the nearest image),
    /// over those of index ≥ `from` only.
    pub fn state_difference(&self, a: &Spheres, b: &Spheres, from: usize) -> f64 {
        let mut r_min = f64::INFINITY;
        let mut worst: f64 = 0.0;
        let (mut i, mut j) = (0, 0);
        while i < a.len() && j < b.len() {
            match a.index[i].cmp(&b.index[j]) {
                std::cmp::Ordering::Less => i += 1,
                std::cmp::Ordering::Greater => j += 1,
                std::cmp::Ordering::Equal => {
                    if !a.fixed[i] && a.index[i] >= from {
                        let d = self.separation(a.position[i], b.position[j]);
                        worst = worst.max(dot(d, d).sqrt());
                        r_min = r_min.min(a.radius[i]);
                    }
                    i += 1;
                    j += 1;
                }
            }
        }
        if worst > 0.0 {
            worst / r_min
        } else {
            0.0
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use dembound_scene::io::{config, resolve::resolve};
    use std::path::Path;

    /// A box periodic in x and y, gravity tilted in x (a chute), two
    /// spheres of R = 0.5 mm.
    fn chute_geometry() -> Geometry {
        let text = r#"
[domain]
lower = [0.0, 0.0, 0.0]
upper = [0.012, 0.012, 0.02]
periodic = [true, true, false]
[[material]]
name = "grain"
density = 1000.0
youngs_modulus = 1.0e7
poisson_ratio = 0.3
[contact]
law = { hooke = 50.0 }
[[particles]]
spheres = [{ position = [0.0004, 0.006, 0.001], radius = 0.5e-3 }, { position = [0.0115, 0.006, 0.001], radius = 0.5e-3 }]
material = "grain"
[motion]
gravity = [4.0, 0.0, -9.0]
[integration]
dt = 1.0e-6
steps = 1
"#;
        let file = config::load(text, "chute", &[]).expect("the test's scene parses");
        let setup = resolve(&file, Path::new("."))
            .expect("the test's scene resolves")
            .setup;
        Geometry::new(&setup)
    }

    #[test]
    fn separation_takes_the_nearest_image_on_periodic_axes() {
        let g = chute_geometry();
        // x: 0.0117 → 0.0003 is +0.0006 through the face (12 mm box), not
        // −0.0114; z is not periodic and keeps its plain difference.
        let d = g.separation([0.0117, 0.0, 0.0], [0.0003, 0.0, 0.019]);
        assert!((d[0] - 0.0006).abs() < 1e-15, "{d:?}");
        assert!((d[2] - 0.019).abs() < 1e-15, "{d:?}");
        // One code's sphere at y = 1e-17, the other's wrapped to y = 0.012:
        // the same place (the row that made the state jump to 24 R).
        let d = g.separation([0.005, 0.012, 0.001], [0.005, 1e-17, 0.001]);
        assert!(d[1].abs() < 1e-15, "{d:?}");
    }

    #[test]
    fn pairs_across_a_periodic_face_are_contacts_and_gravity_along_it_has_no_potential() {
        let g = chute_geometry();
        // m = ρ 4/3 π R³ = 5.236e-7 kg.
        let m = 1000.0 * 4.0 / 3.0 * std::f64::consts::PI * 0.5e-3_f64.powi(3);
        let spheres = Spheres {
            index: vec![0, 1],
            position: vec![[0.0004, 0.006, 0.001], [0.0115, 0.006, 0.001]],
            velocity: vec![[0.0; 3]; 2],
            spin: vec![[0.0; 3]; 2],
            radius: vec![0.5e-3; 2],
            mass: vec![m; 2],
            fixed: vec![false; 2],
        };
        // 0.9 mm apart through the x face, R₁ + R₂ = 1 mm: one contact.
        assert_eq!(g.sphere_pairs(&spheres), 1);
        let s = g.sample(&spheres, Vec::new());
        // Potential: −Σ m g_z z only (g_x is along a periodic axis); the
        // height is along z.
        let expected = 2.0 * m * 9.0 * 0.001;
        assert!(
            (s.potential - expected).abs() < 1e-12 * expected,
            "{}",
            s.potential
        );
        assert!((s.bed_height - 0.0015).abs() < 1e-15, "{}", s.bed_height);
    }

    /// The state difference by id: only the spheres both rows hold, the
    /// fixed left out, over the smallest radius among them; from an index
    /// on (the inserted spheres).
    #[test]
    fn the_state_difference_reads_common_ids_only() {
        let g = chute_geometry();
        let row = |index: Vec<usize>, z: Vec<f64>, fixed: Vec<bool>| Spheres {
            position: z.iter().map(|&z| [0.005, 0.005, z]).collect(),
            velocity: vec![[0.0; 3]; z.len()],
            spin: vec![[0.0; 3]; z.len()],
            radius: index
                .iter()
                .map(|&i| if i == 3 { 0.25e-3 } else { 0.5e-3 })
                .collect(),
            mass: vec![1.0; z.len()],
            fixed,
            index,
        };
        // Common: 1 (Δz = 0.1 mm), 2 (fixed, Δz = 5 mm: left out), 3
        // (R = 0.25 mm, Δz = 0.05 mm); 0 and 4 in one row only.
        let a = row(
            vec![0, 1, 2, 3],
            vec![0.001, 0.002, 0.003, 0.004],
            vec![false, false, true, false],
        );
        let b = row(
            vec![1, 2, 3, 4],
            vec![0.0021, 0.008, 0.00405, 0.009],
            vec![false, true, false, false],
        );
        // max |Δz| = 0.1 mm over R_min = 0.25 mm: 0.4.
        assert!((g.state_difference(&a, &b, 0) - 0.4).abs() < 1e-12);
        // From index 3 on: 0.05 mm / 0.25 mm = 0.2.
        assert!((g.state_difference(&a, &b, 3) - 0.2).abs() < 1e-12);
        assert_eq!(g.state_difference(&a, &b, 5), 0.0);
    }
}
