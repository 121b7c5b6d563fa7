//! The many-body `recommend` (issue 13): which floors of boundary
//! particles keep each measured quantity within a named tolerance of the
//! plane of the particles' own material. Pure: takes the study's results,
//! returns one verdict per floor and quantity; the CLI renders them.
//!
//! Each quantity has its own kind of tolerance, because their scales
//! differ:
//! - restitution (mean e_n, e_t at each angle): absolute, |e − e_plane| ≤
//!   tol; their spread (standard deviation over the impact points):
//!   sd ≤ sd_plane + tol (the plane's is zero: every point is alike);
//! - median contact time at each angle: relative, |t/t_plane − 1| ≤ tol;
//! - packing fraction of the first layer (0–2R): absolute;
//! - floor pressure against the weight per area N m g/A: relative, and no
//!   particle fallen through the floor;
//! - floor pressure fluctuation (sd/mean over the last fifth of the
//!   settling): absolute;
//! - the chute's slip, as a fraction of the bed's mean velocity, from the
//!   first layer and extrapolated from the profile's lower part: absolute.

use super::{Floor, FloorResult};

/// The tolerances, each named by what it bounds.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Tolerances {
    /// Absolute, on mean e_n and e_t and on their spread beyond the plane's.
    pub restitution: f64,
    /// Relative, on the median contact time.
    pub contact_time: f64,
    /// Absolute, on the solid fraction 0–2R.
    pub packing: f64,
    /// Relative, on the floor pressure against N m g/A.
    pub pressure: f64,
    /// Absolute, on the relative floor-force fluctuation.
    pub fluctuation: f64,
    /// Absolute, on slip velocity / mean bed velocity.
    pub slip: f64,
}

impl Default for Tolerances {
    /// e ± 0.05 (a tenth of the default e = 0.5), contact time ± 10 %,
    /// packing ± 0.02 (a tenth of the gap between random loose and
    /// random close packing, 0.55–0.64, doubled), pressure ± 1 %,
    /// fluctuation ± 0.01, slip ± 0.1 of the mean velocity.
    fn default() -> Self {
        Tolerances {
            restitution: 0.05,
            contact_time: 0.10,
            packing: 0.02,
            pressure: 0.01,
            fluctuation: 0.01,
            slip: 0.10,
        }
    }
}

/// One quantity on one floor against the plane.
#[derive(Debug, Clone, PartialEq)]
pub struct Verdict {
    /// Name with unit, e.g. `median contact time at 0° (µs)`.
    pub quantity: String,
    /// The tolerance in words, e.g. `± 10 % of the plane`.
    pub tolerance: String,
    pub plane: f64,
    pub value: f64,
    /// `None`: not measured on this floor (or on the plane).
    pub within: Option<bool>,
}

/// Every compared quantity on one floor.
#[derive(Debug, Clone, PartialEq)]
pub struct FloorVerdict {
    pub floor: Floor,
    /// Why the floor is not a wall, if it is not one ([`Floor::not_a_wall`]).
    pub not_a_wall: Option<String>,
    pub verdicts: Vec<Verdict>,
}

impl FloorVerdict {
    /// Every measured quantity within its tolerance, on a wall.
    pub fn within_all_measured(&self) -> bool {
        self.not_a_wall.is_none() && self.verdicts.iter().all(|v| v.within != Some(false))
    }

    /// Quantities not measured on this floor.
    pub fn unmeasured(&self) -> Vec<&str> {
        self.verdicts
            .iter()
            .filter(|v| v.within.is_none())
            .map(|v| v.quantity.as_str())
            .collect()
    }
}

/// Mean of the finite values (NaN if none).
pub fn mean(v: &[f64]) -> f64 {
    let f: Vec<f64> = v.iter().copied().filter(|x| x.is_finite()).collect();
    if f.is_empty() {
        return f64::NAN;
    }
    f.iter().sum::<f64>() / f.len() as f64
}

/// Sample standard deviation of the finite values (0 for fewer than two).
pub fn std_dev(v: &[f64]) -> f64 {
    let m = mean(v);
    let f: Vec<f64> = v.iter().copied().filter(|x| x.is_finite()).collect();
    if f.len() < 2 {
        return 0.0;
    }
    (f.iter().map(|x| (x - m) * (x - m)).sum::<f64>() / (f.len() - 1) as f64).sqrt()
}

/// Median of the finite values (NaN if none).
pub fn median(v: &[f64]) -> f64 {
    let mut f: Vec<f64> = v.iter().copied().filter(|x| x.is_finite()).collect();
    if f.is_empty() {
        return f64::NAN;
    }
    f.sort_by(f64::total_cmp);
    let k = f.len() / 2;
    if f.len() % 2 == 1 {
        f[k]
    } else {
        0.5 * (f[k - 1] + f[k])
    }
}

/// How a quantity is compared with the plane's.
#[derive(Clone, Copy)]
enum Rule {
    /// |x − plane| ≤ tol.
    Absolute(f64),
    /// x ≤ plane + tol.
    AtMostAbove(f64),
    /// |x/plane − 1| ≤ tol.
    Relative(f64),
    /// x = plane exactly (counts).
    Equal,
}

impl Rule {
    fn check(self, plane: f64, x: f64) -> Option<bool> {
        if !plane.is_finite() || !x.is_finite() {
            return None;
        }
        Some(match self {
            Rule::Absolute(t) => (x - plane).abs() <= t,
            Rule::AtMostAbove(t) => x <= plane + t,
            Rule::Relative(t) => (x / plane - 1.0).abs() <= t,
            Rule::Equal => x == plane,
        })
    }

    fn describe(self) -> String {
        match self {
            Rule::Absolute(t) => format!("± {t}"),
            Rule::AtMostAbove(t) => format!("≤ plane + {t}"),
            Rule::Relative(t) => format!("± {} %", 100.0 * t),
            Rule::Equal => "= plane".into(),
        }
    }
}

/// (quantity, rule, value) of one floor, in a fixed order.
fn quantities(r: &FloorResult, angles: &[f64], t: &Tolerances) -> Vec<(String, Rule, f64)> {
    let mut q = Vec::new();
    for &a in angles {
        let at: Vec<_> = r.impacts.iter().filter(|i| i.angle == a).collect();
        if at.is_empty() {
            continue;
        }
        let en: Vec<f64> = at.iter().map(|i| i.normal_restitution).collect();
        q.push((
            format!("e_n at {a}° (1)"),
            Rule::Absolute(t.restitution),
            mean(&en),
        ));
        q.push((
            format!("e_n spread (sd) at {a}° (1)"),
            Rule::AtMostAbove(t.restitution),
            std_dev(&en),
        ));
        if a > 0.0 {
            let et: Vec<f64> = at.iter().map(|i| i.tangential_restitution).collect();
            q.push((
                format!("e_t at {a}° (1)"),
                Rule::Absolute(t.restitution),
                mean(&et),
            ));
            q.push((
                format!("e_t spread (sd) at {a}° (1)"),
                Rule::AtMostAbove(t.restitution),
                std_dev(&et),
            ));
        }
        let tc: Vec<f64> = at.iter().map(|i| i.contact_time * 1e6).collect();
        q.push((
            format!("median contact time at {a}° (µs)"),
            Rule::Relative(t.contact_time),
            median(&tc),
        ));
    }
    if let Some(b) = &r.bed {
        q.push((
            "packing fraction 0–2R (1)".into(),
            Rule::Absolute(t.packing),
            b.wall_packing,
        ));
        q.push((
            "floor pressure / (N m g/A) (1)".into(),
            Rule::Relative(t.pressure),
            b.floor_pressure / b.weight_pressure,
        ));
        q.push((
            "floor pressure fluctuation (1)".into(),
            Rule::Absolute(t.fluctuation),
            b.pressure_fluctuation,
        ));
        q.push((
            "particles fallen through the floor (1)".into(),
            Rule::Equal,
            b.fell_through as f64,
        ));
    }
    if let Some(chute) = &r.chute {
        let (first, fitted) = match chute {
            Ok(ch) => (
                ch.slip_velocity / ch.mean_velocity,
                ch.slip_fit
                    .map_or(f64::NAN, |f| f.slip_velocity / ch.mean_velocity),
            ),
            Err(_) => (f64::NAN, f64::NAN),
        };
        q.push((
            "chute first-layer slip / mean velocity (1)".into(),
            Rule::Absolute(t.slip),
            first,
        ));
        q.push((
            "chute extrapolated slip / mean velocity (1)".into(),
            Rule::Absolute(t.slip),
            fitted,
        ));
    }
    q
}

/// Every floor but the plane against the plane (the first result whose
/// floor is [`Floor::Plane`]); empty if there is no plane.
pub fn recommend(results: &[FloorResult], angles: &[f64], t: &Tolerances) -> Vec<FloorVerdict> {
    let Some(plane) = results.iter().find(|r| r.floor == Floor::Plane) else {
        return Vec::new();
    };
    let reference = quantities(plane, angles, t);
    results
        .iter()
        .filter(|r| r.floor != Floor::Plane)
        .map(|r| {
            let mine = quantities(r, angles, t);
            let verdicts = reference
                .iter()
                .map(|(name, rule, p)| {
                    let x = mine
                        .iter()
                        .find(|(n, _, _)| n == name)
                        .map_or(f64::NAN, |q| q.2);
                    Verdict {
                        quantity: name.clone(),
                        tolerance: rule.describe(),
                        plane: *p,
                        value: x,
                        within: rule.check(*p, x),
                    }
                })
                .collect();
            FloorVerdict {
                floor: r.floor,
                not_a_wall: r.floor.not_a_wall(),
                verdicts,
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sources::tiling::Pattern;
    use crate::wall_study::Impact;

    fn impact(angle: f64, e_n: f64, e_t: f64, t: f64) -> Impact {
        Impact {
            angle,
            point: [0.0; 2],
            normal_restitution: e_n,
            tangential_restitution: e_t,
            rebound_angle: 0.0,
            deflection: 0.0,
            contact_time: t,
            contacts: 1,
            spin: 0.0,
        }
    }

    fn result(floor: Floor, impacts: Vec<Impact>) -> FloorResult {
        FloorResult {
            floor,
            impacts,
            bed: None,
            chute: None,
            dt: 1e-6,
        }
    }

    #[test]
    fn each_quantity_is_judged_by_its_own_tolerance() {
        let t = Tolerances::default();
        let plane = result(Floor::Plane, vec![impact(0.0, 0.5, f64::NAN, 100e-6); 3]);
        let floor = |r: f64| Floor::Particles {
            radius_ratio: r,
            modulus_ratio: 10.0,
            pattern: Pattern::Square,
        };
        // Mean e_n 0.5 − 0.04 (within 0.05), sd 0.04 (≤ 0 + 0.05),
        // median contact time 109 µs (within 10 %).
        let close = result(
            floor(1.0),
            vec![
                impact(0.0, 0.42, f64::NAN, 100e-6),
                impact(0.0, 0.46, f64::NAN, 109e-6),
                impact(0.0, 0.50, f64::NAN, 120e-6),
            ],
        );
        // Mean e_n 0.5 (equal) but sd 0.1 (> 0.05); median 111 µs.
        let rough = result(
            floor(2.0),
            vec![
                impact(0.0, 0.4, f64::NAN, 90e-6),
                impact(0.0, 0.5, f64::NAN, 111e-6),
                impact(0.0, 0.6, f64::NAN, 120e-6),
            ],
        );
        // r = 3 square is not a wall, whatever it measures.
        let holes = result(floor(3.0), vec![impact(0.0, 0.5, f64::NAN, 100e-6); 3]);
        let v = recommend(&[plane, close, rough, holes], &[0.0], &t);
        assert_eq!(v.len(), 3);
        let within =
            |k: usize| -> Vec<Option<bool>> { v[k].verdicts.iter().map(|x| x.within).collect() };
        // Order: e_n, its spread, the median contact time.
        assert_eq!(within(0), [Some(true), Some(true), Some(true)]);
        assert!(v[0].within_all_measured());
        assert_eq!(within(1), [Some(true), Some(false), Some(false)]);
        assert!(!v[1].within_all_measured());
        assert_eq!(within(2), [Some(true), Some(true), Some(true)]);
        assert!(v[2].not_a_wall.is_some());
        assert!(!v[2].within_all_measured());
        assert!((v[1].verdicts[1].value - 0.1).abs() < 1e-15);
    }

    #[test]
    fn wall_limits_are_where_the_gap_fits_a_particle() {
        // The hole between four touching spheres of radius r on a square
        // grid: centre-to-hole distance √2 r, so a sphere of (√2 − 1) r
        // fits; between three on a triangular grid: 2r/√3, (2/√3 − 1) r.
        assert!((Floor::wall_limit(Pattern::Square) - (1.0 + 2f64.sqrt())).abs() < 1e-12);
        let hex = 1.0 / (2.0 / 3f64.sqrt() - 1.0);
        assert!((Floor::wall_limit(Pattern::Hexagonal) - hex).abs() < 1e-12);
        assert!((hex - 6.4641).abs() < 1e-4);
        let f = |r, pattern| Floor::Particles {
            radius_ratio: r,
            modulus_ratio: 100.0,
            pattern,
        };
        assert!(f(2.4, Pattern::Square).not_a_wall().is_none());
        assert!(f(2.42, Pattern::Square).not_a_wall().is_some());
        assert!(f(6.4, Pattern::Hexagonal).not_a_wall().is_none());
        assert!(f(6.5, Pattern::Hexagonal).not_a_wall().is_some());
        // The paper's r = 100: holes of 41.4 R and 15.5 R.
        assert!((f(100.0, Pattern::Square).gap_radius().unwrap() - 41.42).abs() < 0.01);
        assert!((f(100.0, Pattern::Hexagonal).gap_radius().unwrap() - 15.47).abs() < 0.01);
        assert!(Floor::Plane.not_a_wall().is_none());
    }
}
