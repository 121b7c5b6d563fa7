//! Profiles along z for `dembound compare DECK` on a scene deck: the
//! packing fraction and, where gravity has a component across z (a chute),
//! the mean flow velocity, each averaged over the late window for the
//! peer's run and dembound's, with the largest difference between them.
//!
//! - Bins: slabs z ∈ [z₀ + k w, z₀ + (k + 1) w) from the domain's lower z,
//!   w = the mean free-sphere diameter of the scene file (stated in the
//!   report; the inlet's middle diameter when the scene starts empty), up
//!   to the domain's upper z. Each row's spheres are those there then
//!   (compare_rows.rs).
//! - Packing fraction of a bin: the free spheres' volume inside the slab
//!   (each sphere cut exactly: the volume of a sphere of radius R between
//!   heights a and b from its centre is π [R² t − t³/3] from a to b, t
//!   clipped to [−R, R]) over the slab's volume A w, A the domain's x–y
//!   area. Fixed spheres (a boundary-particle floor) are left out.
//! - Velocity of a bin: Σ m v·ê / Σ m over the free spheres whose centre is
//!   in it, ê the unit horizontal direction of gravity (m/s).
//! - Agreement: the packing profiles agree when the largest |Δφ| of the
//!   window means is ≤ 0.02 (issue 32's bar); the velocity profile is
//!   reported without a bar (the issue sets none).

use super::compare_rows::Spheres;
use dembound_export::agreement::{self, WindowMean};
use dembound_scene::setup::SceneSetup;
use serde::Serialize;

/// The packing profile's bar: the largest |Δφ| of two agreeing profiles.
pub const PACKING_BAR: f64 = 0.02;

/// One profile of both runs over the late window.
#[derive(Debug, Serialize)]
pub struct ProfileReport {
    pub name: String,
    pub unit: String,
    /// Bin width (m) and the bins' centres (m, along z).
    pub bin_width: f64,
    pub centres: Vec<f64>,
    pub code: Vec<Option<WindowMean>>,
    pub dembound: Vec<Option<WindowMean>>,
    /// The largest |code − dembound| of the bins' window means, and where.
    pub max_abs_difference: f64,
    pub at: f64,
    /// Combined standard error of the two means at that bin.
    pub standard_error_there: f64,
    pub bar: Option<f64>,
    pub agree: Option<bool>,
}

/// What the profiles need of the scene.
pub struct Profiles {
    lower: f64,
    width: f64,
    bins: usize,
    area: f64,
    /// The unit horizontal direction of gravity, when it has one.
    pub flow: Option<[f64; 3]>,
}

impl Profiles {
    /// Bins of `width` (m) over the domain's height.
    pub fn new(setup: &SceneSetup, width: f64) -> Self {
        let d = &setup.domain;
        let height = d.upper[2] - d.lower[2];
        let width = if width > 0.0 { width } else { height };
        let bins = ((height / width).ceil() as usize).clamp(1, 10_000);
        let g = setup.gravity;
        let h = (g[0] * g[0] + g[1] * g[1]).sqrt();
        Profiles {
            lower: d.lower[2],
            width,
            bins,
            area: (d.upper[0] - d.lower[0]) * (d.upper[1] - d.lower[1]),
            flow: (h > 1e-9 * g[2].abs()).then(|| [g[0] / h, g[1] / h, 0.0]),
        }
    }

    /// Packing fraction of each bin.
    pub fn packing(&self, s: &Spheres) -> Vec<f64> {
        let x = &s.position;
        let mut phi = vec![0.0; self.bins];
        // ∫ π (R² − t²) dt = π (R² t − t³/3).
        let cap = |r: f64, t: f64| {
            let t = t.clamp(-r, r);
            std::f64::consts::PI * (r * r * t - t * t * t / 3.0)
        };
        for i in (0..x.len()).filter(|&i| !s.fixed[i]) {
            let (z, r) = (x[i][2], s.radius[i]);
            let first = ((z - r - self.lower) / self.width).floor().max(0.0) as usize;
            let last = (((z + r - self.lower) / self.width).floor().max(0.0) as usize)
                .min(self.bins.saturating_sub(1));
            for (k, p) in phi.iter_mut().enumerate().take(last + 1).skip(first) {
                let a = self.lower + k as f64 * self.width - z;
                *p += cap(r, a + self.width) - cap(r, a);
            }
        }
        let volume = self.area * self.width;
        phi.iter().map(|v| v / volume).collect()
    }

    /// Mass-weighted mean velocity along the flow of each bin (0 if empty).
    pub fn velocity(&self, s: &Spheres) -> Vec<f64> {
        let (x, v) = (&s.position, &s.velocity);
        let Some(e) = self.flow else {
            return Vec::new();
        };
        let mut momentum = vec![0.0; self.bins];
        let mut mass = vec![0.0; self.bins];
        for i in (0..x.len()).filter(|&i| !s.fixed[i]) {
            let k = ((x[i][2] - self.lower) / self.width).floor();
            if k < 0.0 || k as usize >= self.bins {
                continue;
            }
            let k = k as usize;
            momentum[k] += s.mass[i] * (v[i][0] * e[0] + v[i][1] * e[1]);
            mass[k] += s.mass[i];
        }
        momentum
            .iter()
            .zip(&mass)
            .map(|(p, m)| if *m > 0.0 { p / m } else { 0.0 })
            .collect()
    }

    /// The report of one profile from its rows (one Vec per row of the
    /// window) of both runs.
    pub fn report(
        &self,
        name: &str,
        unit: &str,
        code: &[Vec<f64>],
        dembound: &[Vec<f64>],
        bar: Option<f64>,
    ) -> ProfileReport {
        let column = |rows: &[Vec<f64>], k: usize| -> Option<WindowMean> {
            let v: Vec<f64> = rows.iter().filter_map(|r| r.get(k).copied()).collect();
            agreement::window_mean(&v)
        };
        let c: Vec<Option<WindowMean>> = (0..self.bins).map(|k| column(code, k)).collect();
        let d: Vec<Option<WindowMean>> = (0..self.bins).map(|k| column(dembound, k)).collect();
        let mut worst = (0.0, 0.0, 0.0);
        for k in 0..self.bins {
            if let (Some(a), Some(b)) = (&c[k], &d[k]) {
                let diff = (a.mean - b.mean).abs();
                if diff > worst.0 {
                    worst = (
                        diff,
                        self.lower + (k as f64 + 0.5) * self.width,
                        a.standard_error.hypot(b.standard_error),
                    );
                }
            }
        }
        ProfileReport {
            name: name.into(),
            unit: unit.into(),
            bin_width: self.width,
            centres: (0..self.bins)
                .map(|k| self.lower + (k as f64 + 0.5) * self.width)
                .collect(),
            code: c,
            dembound: d,
            max_abs_difference: worst.0,
            at: worst.1,
            standard_error_there: worst.2,
            bar,
            agree: bar.map(|b| worst.0 <= b),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn profiles(bins: usize, width: f64) -> Profiles {
        Profiles {
            lower: 0.0,
            width,
            bins,
            area: 4.0,
            flow: Some([1.0, 0.0, 0.0]),
        }
    }

    /// Spheres of radius 0.5, 0.5, 1 (the last fixed), masses 1, 3, 1.
    fn spheres(x: [[f64; 3]; 3], v: [[f64; 3]; 3]) -> Spheres {
        Spheres {
            index: vec![0, 1, 2],
            position: x.to_vec(),
            velocity: v.to_vec(),
            spin: vec![[0.0; 3]; 3],
            radius: vec![0.5, 0.5, 1.0],
            mass: vec![1.0, 3.0, 1.0],
            fixed: vec![false, false, true],
        }
    }

    #[test]
    fn slices_add_up_to_the_spheres_volume() {
        // Two spheres of R = 0.5 cut by bins of width 0.3 anywhere: the bins
        // hold (4/3) π R³ each in all (the fixed one is left out).
        let p = profiles(20, 0.3);
        let phi = p.packing(&spheres(
            [[0.0, 0.0, 1.234], [0.0, 0.0, 2.0], [0.0, 0.0, 0.0]],
            [[0.0; 3]; 3],
        ));
        let total: f64 = phi.iter().map(|f| f * 4.0 * 0.3).sum();
        let exact = 2.0 * 4.0 / 3.0 * std::f64::consts::PI * 0.125;
        assert!((total / exact - 1.0).abs() < 1e-14, "{total} vs {exact}");
        // A bin of width 2R holding a whole sphere: φ = (4/3 π R³)/(A 2R).
        let p = profiles(4, 1.0);
        let phi = p.packing(&spheres(
            [[0.0, 0.0, 1.5], [0.0, 0.0, 3.5], [0.0, 0.0, 0.5]],
            [[0.0; 3]; 3],
        ));
        let one = 4.0 / 3.0 * std::f64::consts::PI * 0.125 / 4.0;
        assert!((phi[1] - one).abs() < 1e-15 && (phi[3] - one).abs() < 1e-15);
        assert_eq!(phi[0], 0.0);
    }

    #[test]
    fn velocity_is_mass_weighted_along_the_flow() {
        let p = profiles(4, 1.0);
        let v = p.velocity(&spheres(
            [[0.0, 0.0, 1.2], [0.0, 0.0, 1.7], [0.0, 0.0, 1.5]],
            [[1.0, 5.0, 0.0], [3.0, 0.0, 0.0], [9.0, 0.0, 0.0]],
        ));
        // (1 × 1 + 3 × 3)/4 = 2.5; the fixed sphere left out.
        assert_eq!(v, vec![0.0, 2.5, 0.0, 0.0]);
    }
}
