//! Walls of boundary particles: a plane tiled with fixed spheres, the
//! paper's boundary sphere (radius ratio r = R_b/R_m, modulus ratio
//! ζ = E_b/E_m, eq 8) in its many-particle form.
//!
//! **Where the spheres sit.** The wall is given like a plane wall, by a
//! point and an outward normal n (pointing into the domain). Each boundary
//! sphere's centre is placed at `site − R_b n`, so that the top of every
//! sphere touches the plane: the plane is the wall's contact surface, and a
//! particle resting on the wall sits where it would sit on the plane wall
//! of the same point and normal (exactly so on top of a sphere, lower in
//! the hollows between them). Replacing `plane` by `boundary_particles` in
//! a scene thus keeps the particles' initial gaps.
//!
//! **Tilings.** The sites form a square lattice (spacing s along both
//! in-plane axes) or a hexagonal one (rows s√3/2 apart, odd rows shifted
//! by s/2); s = 2 R_b (touching spheres) unless given. The in-plane axes
//! are u = the coordinate axis least aligned with n, made orthogonal to n,
//! and v = n × u: for a floor (n = +z) u = x and v = y. The lattice
//! contains the point itself and covers the domain's extent projected on
//! the plane, one site beyond each edge. Along a periodic axis the sites
//! tile [lower, upper) exactly, and the period must be a multiple of the
//! tiling's period along it (s, or s√3 for the rows of a hexagonal tiling).

use super::SourceSphere;
use crate::SceneError;

/// The pattern of sites in the plane.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Pattern {
    Square,
    Hexagonal,
}

/// One wall of boundary particles, in absolute units.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Tiling {
    /// A point of the wall's contact plane, m.
    pub point: [f64; 3],
    /// Normal pointing into the domain (need not be unit length).
    pub normal: [f64; 3],
    /// Boundary-sphere radius R_b, m.
    pub radius: f64,
    /// Centre distance of neighbouring sites, m (2 R_b: touching).
    pub spacing: f64,
    pub pattern: Pattern,
}

/// The box the wall must cover.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Extent {
    pub lower: [f64; 3],
    pub upper: [f64; 3],
    pub periodic: [bool; 3],
}

/// More boundary spheres than this in one wall is refused.
pub const MAX_WALL_SPHERES: usize = 20_000_000;

/// Tolerance of "a multiple of the period": 1e-9 relative, far above the
/// rounding of a product of two decimal inputs and far below any
/// mismatch a user would make on purpose.
const COMMENSURATE: f64 = 1e-9;

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// `v` scaled to unit length, or `None` for a zero or non-finite vector.
/// Where the plain square underflows or overflows (|v| ≤ 1e-150 or not
/// finite: [0, 0, 1e-160] squares to a subnormal that keeps 11 bits,
/// [0, 0, 1e-170] to 0, [0, 0, 1e200] to ∞), the length is the norm scaled
/// by the largest component, so that any finite non-zero vector gives a
/// unit one (every other vector keeps the plain root's bits).
pub fn unit(v: [f64; 3]) -> Option<[f64; 3]> {
    let mut n = dot(v, v).sqrt();
    if !(n.is_finite() && n > 1e-150) {
        n = crate::limits::norm(v);
    }
    (n > 0.0 && n.is_finite()).then(|| v.map(|x| x / n))
}

/// The in-plane axes (u, v) of a unit normal n (module doc).
pub fn plane_axes(n: [f64; 3]) -> ([f64; 3], [f64; 3]) {
    let mut k = 0;
    for j in 1..3 {
        if n[j].abs() < n[k].abs() {
            k = j;
        }
    }
    let mut e = [0.0; 3];
    e[k] = 1.0;
    let along = dot(e, n);
    let u = unit([
        e[0] - along * n[0],
        e[1] - along * n[1],
        e[2] - along * n[2],
    ])
    .unwrap_or(e);
    // An axis-aligned normal gives u exactly on a coordinate axis.
    let u = u.map(|x| if x.abs() < 1e-15 { 0.0 } else { x });
    (u, cross(n, u))
}

/// Sites along one in-plane axis: the integer range of indices and, for a
/// periodic axis, nothing else to do (the range tiles the period).
#[derive(Debug, Clone, Copy)]
struct Span {
    first: i64,
    last: i64,
}

impl Tiling {
    /// The row spacing along v, m.
    fn row_spacing(&self) -> f64 {
        match self.pattern {
            Pattern::Square => self.spacing,
            Pattern::Hexagonal => self.spacing * 3f64.sqrt() / 2.0,
        }
    }

    /// The boundary spheres covering `extent`, at rest, row by row (v),
    /// each row along u. `key` names the wall in messages (e.g. `wall[1]`).
    pub fn spheres(&self, extent: &Extent, key: &str) -> Result<Vec<SourceSphere>, SceneError> {
        let bp = format!("{key}.boundary_particles");
        let n = unit(self.normal).ok_or_else(|| {
            SceneError::input(format!(
                "`{bp}.normal` = {:?}: must be a non-zero finite vector",
                self.normal
            ))
        })?;
        if !(self.radius > 0.0 && self.radius.is_finite()) {
            return Err(SceneError::input(format!(
                "`{bp}`: boundary-sphere radius {:e} m (radius_ratio × the reference radius) must be finite and > 0",
                self.radius
            )));
        }
        if !(self.spacing > 0.0 && self.spacing.is_finite()) {
            return Err(SceneError::input(format!(
                "`{bp}.spacing` = {}: must be a finite distance > 0 m",
                self.spacing
            )));
        }
        if self.point.iter().any(|x| !x.is_finite()) {
            return Err(SceneError::input(format!(
                "`{bp}.point` = {:?}: must be finite",
                self.point
            )));
        }
        let (u, v) = plane_axes(n);
        let (su, sv) = (self.spacing, self.row_spacing());
        // Row parity shifts u by s/2 in the hexagonal tiling: half a
        // period more to cover along u.
        let hexagonal = self.pattern == Pattern::Hexagonal;
        let span_u = self.span(extent, u, n, su, 1, hexagonal, &bp)?;
        let span_v = self.span(extent, v, n, sv, if hexagonal { 2 } else { 1 }, false, &bp)?;
        let count_u = (span_u.last - span_u.first + 1) as usize;
        let count_v = (span_v.last - span_v.first + 1) as usize;
        let total = count_u.saturating_mul(count_v);
        if total > MAX_WALL_SPHERES {
            return Err(SceneError::input(format!(
                "`{bp}`: {count_u} × {count_v} boundary spheres of radius {:e} m would tile the domain, more \
                 than {MAX_WALL_SPHERES}; raise `radius_ratio` or `spacing`",
                self.radius
            )));
        }
        let mut out = Vec::with_capacity(total);
        for j in span_v.first..=span_v.last {
            let shift = match self.pattern {
                Pattern::Hexagonal if j.rem_euclid(2) == 1 => 0.5 * su,
                _ => 0.0,
            };
            let b = j as f64 * sv;
            for i in span_u.first..=span_u.last {
                let a = i as f64 * su + shift;
                let mut c = [0.0; 3];
                for k in 0..3 {
                    c[k] = self.point[k] + a * u[k] + b * v[k] - self.radius * n[k];
                }
                out.push(SourceSphere::at_rest(c, self.radius));
            }
        }
        Ok(out)
    }

    /// The index range of sites along the in-plane `axis` (spacing `step`).
    /// `period_rows` is how many steps make one period of the pattern
    /// along it (2 for the rows of a hexagonal tiling); `shifted_rows`
    /// adds one site below for rows shifted by half a step.
    #[allow(clippy::too_many_arguments)]
    fn span(
        &self,
        extent: &Extent,
        axis: [f64; 3],
        n: [f64; 3],
        step: f64,
        period_rows: i64,
        shifted_rows: bool,
        bp: &str,
    ) -> Result<Span, SceneError> {
        let names = ["x", "y", "z"];
        // A periodic coordinate axis along this in-plane axis?
        for k in 0..3 {
            if !extent.periodic[k] {
                continue;
            }
            if n[k] != 0.0 {
                return Err(SceneError::input(format!(
                    "`{bp}.normal` = {:?}: a wall must be parallel to the periodic axis {}; \
                     its normal must have no {} component",
                    self.normal, names[k], names[k]
                )));
            }
            if axis[k].abs() != 1.0 {
                continue;
            }
            let length = extent.upper[k] - extent.lower[k];
            let period = step * period_rows as f64;
            let periods = (length / period).round();
            if periods < 1.0 || (periods * period - length).abs() > COMMENSURATE * length {
                return Err(SceneError::input(format!(
                    "`{bp}`: along the periodic axis {} (length {length:e} m) the tiling repeats every \
                     {period:e} m; the length must be a whole multiple of it: choose `spacing` to fit",
                    names[k],
                )));
            }
            // Sites at point + i·step·axis, their coordinate in [lower, upper).
            let first = if axis[k] > 0.0 {
                ((extent.lower[k] - self.point[k]) / step).ceil() as i64
            } else {
                ((self.point[k] - extent.upper[k]) / step).floor() as i64 + 1
            };
            let count = (periods as i64) * period_rows;
            return Ok(Span {
                first,
                last: first + count - 1,
            });
        }
        // Not periodic: the projection of the box's corners, one site more
        // on each side (half a cell more along u for shifted rows).
        let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
        for corner in 0..8 {
            let c: [f64; 3] = std::array::from_fn(|k| {
                let side = if corner >> k & 1 == 0 {
                    extent.lower[k]
                } else {
                    extent.upper[k]
                };
                side - self.point[k]
            });
            let t = dot(c, axis);
            lo = lo.min(t);
            hi = hi.max(t);
        }
        let margin = if shifted_rows { 1.0 } else { 0.0 };
        let first = (lo / step).floor() - margin;
        let last = (hi / step).ceil();
        if !(first.is_finite() && last.is_finite()) || last - first > MAX_WALL_SPHERES as f64 {
            return Err(SceneError::input(format!(
                "`{bp}`: more than {MAX_WALL_SPHERES} boundary spheres along one row; raise `radius_ratio` or `spacing`"
            )));
        }
        Ok(Span {
            first: first as i64,
            last: last as i64,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn floor(pattern: Pattern, radius: f64) -> Tiling {
        Tiling {
            point: [0.0; 3],
            normal: [0.0, 0.0, 1.0],
            radius,
            spacing: 2.0 * radius,
            pattern,
        }
    }

    fn box10(periodic: [bool; 3]) -> Extent {
        Extent {
            lower: [0.0; 3],
            upper: [10.0, 10.0, 5.0],
            periodic,
        }
    }

    #[test]
    fn square_floor_counts_and_touching_neighbours() {
        // R = 1, s = 2 on [0, 10]²: sites 0, 2, …, 10 along x and y, 6 × 6.
        let s = floor(Pattern::Square, 1.0)
            .spheres(&box10([false; 3]), "wall[0]")
            .unwrap();
        assert_eq!(s.len(), 36);
        for sphere in &s {
            // Tops on the plane z = 0: centre at −R.
            assert_eq!(sphere.position[2], -1.0);
            assert_eq!(sphere.radius, 1.0);
        }
        // Touching: every sphere's nearest neighbour is exactly 2R away.
        assert_eq!(s[0].position, [0.0, 0.0, -1.0]);
        assert_eq!(s[1].position, [2.0, 0.0, -1.0]);
        assert_eq!(s[6].position, [0.0, 2.0, -1.0]);
        assert_nearest_is(&s, 2.0);
    }

    fn assert_nearest_is(s: &[SourceSphere], d: f64) {
        for (i, a) in s.iter().enumerate() {
            let nearest = s
                .iter()
                .enumerate()
                .filter(|(j, _)| *j != i)
                .map(|(_, b)| super::super::distance_squared(a.position, b.position).sqrt())
                .fold(f64::INFINITY, f64::min);
            // Sites are sums of two products of decimals: a few ulps.
            assert!(
                (nearest - d).abs() < 1e-12 * d,
                "sphere {i}: nearest {nearest}"
            );
        }
    }

    #[test]
    fn hexagonal_floor_touches_six_neighbours() {
        let t = floor(Pattern::Hexagonal, 0.5);
        let s = t.spheres(&box10([false; 3]), "wall[0]").unwrap();
        // Rows 0..=ceil(10/(√3/2)) = 0..=12 (13 rows); along x one site
        // more before 0: −1..=10, 12 per row.
        assert_eq!(s.len(), 13 * 12);
        assert_nearest_is(&s, 1.0);
        // An interior sphere has exactly six neighbours at 2R.
        let centre = s
            .iter()
            .position(|p| (p.position[0] - 5.0).abs() < 1e-9 && p.position[1] > 4.0)
            .unwrap();
        let touching = s
            .iter()
            .filter(|b| {
                (super::super::distance_squared(s[centre].position, b.position).sqrt() - 1.0).abs()
                    < 1e-9
            })
            .count();
        assert_eq!(touching, 6);
    }

    #[test]
    fn spacing_and_other_normals() {
        let mut t = floor(Pattern::Square, 1.0);
        t.spacing = 2.5;
        // 0, 2.5, …, 10: 5 × 5.
        assert_eq!(t.spheres(&box10([false; 3]), "w").unwrap().len(), 25);
        // A wall at x = 10 facing −x: u = y, v = z, centres at x = 10 + R.
        let t = Tiling {
            point: [10.0, 0.0, 0.0],
            normal: [-2.0, 0.0, 0.0],
            ..floor(Pattern::Square, 1.0)
        };
        let s = t.spheres(&box10([false; 3]), "w").unwrap();
        assert!(s.iter().all(|p| p.position[0] == 11.0));
        // y ∈ {0, 2, …, 10}, z ∈ {0, 2, 4, 6}.
        assert_eq!(s.len(), 6 * 4);
    }

    #[test]
    fn periodic_axes_are_tiled_exactly_once() {
        let s = floor(Pattern::Square, 1.0)
            .spheres(&box10([true, true, false]), "w")
            .unwrap();
        // [0, 10) with s = 2: 0, 2, 4, 6, 8 each way.
        assert_eq!(s.len(), 25);
        assert!(s
            .iter()
            .all(|p| p.position[0] >= 0.0 && p.position[0] < 10.0));
        // 10 is not a multiple of 3.
        let mut t = floor(Pattern::Square, 1.0);
        t.spacing = 3.0;
        let e = t
            .spheres(&box10([true, false, false]), "wall[2]")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("wall[2].boundary_particles") && e.contains("periodic axis x"),
            "{e}"
        );
        // A floor cannot cross the periodic z axis.
        let e = floor(Pattern::Square, 1.0)
            .spheres(&box10([false, false, true]), "w")
            .unwrap_err()
            .to_string();
        assert!(e.contains("periodic axis z"), "{e}");
    }

    /// A floor normal of any finite non-zero length tiles alike: along z,
    /// 1e-160 (its square a subnormal keeping 11 bits: the unit normal was
    /// 1 + 5.7e-6 long, the rows 5.7e-6 too far apart, touching spheres
    /// overlapping), 1e-170 and 1e200 (squares 0 and ∞: refused as "not a
    /// non-zero finite vector", which the scene's key check had accepted)
    /// give the spheres of [0, 0, 1] to the bit.
    #[test]
    fn tiny_and_huge_normals_tile_as_unit_ones() {
        let unit_floor = floor(Pattern::Hexagonal, 1.0)
            .spheres(&box10([false; 3]), "w")
            .unwrap();
        for z in [1e-160, 1e-170, 1e200] {
            let t = Tiling {
                normal: [0.0, 0.0, z],
                ..floor(Pattern::Hexagonal, 1.0)
            };
            assert_eq!(
                t.spheres(&box10([false; 3]), "w"),
                Ok(unit_floor.clone()),
                "{z}"
            );
        }
    }

    #[test]
    fn too_many_spheres_or_bad_numbers_are_refused() {
        let e = floor(Pattern::Square, 1e-5)
            .spheres(&box10([false; 3]), "w")
            .unwrap_err()
            .to_string();
        assert!(e.contains("radius_ratio"), "{e}");
        let mut t = floor(Pattern::Square, 1.0);
        t.normal = [0.0; 3];
        assert!(t
            .spheres(&box10([false; 3]), "w")
            .unwrap_err()
            .to_string()
            .contains("normal"));
    }
}
