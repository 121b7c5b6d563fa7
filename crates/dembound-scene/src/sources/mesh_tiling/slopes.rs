//! The friction a covering's bumps add, from its geometry alone.
//!
//! **The surface a particle's centre follows.** A particle of radius ρ
//! resting on boundary spheres (radius R_b, centres c_i) above a point X
//! of a flat face (normal n toward the particles) has its centre at height
//! t(X) = max_i t_i(X), t_i(X) = (c_i − X)·n + √(a² − |ℓ_i|²), with
//! a = R_b + ρ and ℓ_i the in-plane part of c_i − X ([`super::measure`]).
//! Each t_i is a dome; t is their upper envelope.
//!
//! **A slope is a friction coefficient.** A frictionless particle pressed
//! on the face by a normal load N (its weight) and pushed along it by F_t
//! moves its centre on t. Where t rises at slope tan θ in the direction
//! of the push, the contact forces are normal to the domes, and the
//! balance along and across the face is that of an inclined plane: it
//! climbs only if F_t ≥ N tan θ. The bumps act as a Coulomb friction
//! μ = tan θ, which a flat wall does not have.
//!
//! **Where the slope is largest: the hollows.** A dome's slope
//! |∇t_i| = |ℓ_i|/√(a² − |ℓ_i|²) grows with the distance from its top, and
//! on a flat patch (all centres R_b behind the face) the dome on top is
//! that of the laterally nearest centre, so each dome reigns over its
//! Voronoi cell and is steepest at the cell's vertices: the hollows, where
//! three or more domes meet and the particle rests lowest. At a hollow P
//! the centre rises, in the in-plane direction d, at the rate
//! D(d) = max_i g_i·d over the domes meeting there, g_i = ℓ_i/√(a² − |ℓ_i|²)
//! (it climbs whichever dome it meets first). Two numbers, at the deepest
//! hollow:
//!
//! - the **exit friction** μ_exit = min_d D(d): a particle resting in the
//!   hollow needs F_t ≥ μ_exit N to leave it by the easiest way, toward
//!   the saddle between two spheres; on that way t rises ever less
//!   steeply (to slope 0 at the saddle), so μ_exit is also the steepest
//!   slope met on the easiest path. The least friction the bumps add to
//!   sliding from rest.
//! - the **steepest slope** μ_max = max_d D(d) = max_i |g_i|: a push toward
//!   a sphere's top; the steepest slope of t anywhere on the face.
//!
//! Closed forms on a flat lattice of spacing s (the hollow at distance w
//! from its spheres' axes, t₀ = √(a² − w²), a > w):
//!
//! - square: w = s/√2, μ_exit = (s/2)/t₀ (d along a row: the two spheres
//!   ahead are at ℓ·d = s/2), μ_max = w/t₀;
//! - hexagonal: w = s/√3, μ_exit = (s/(2√3))/t₀ (d toward the midpoint of
//!   two of the three spheres: ℓ·d = w cos 60°), μ_max = w/t₀.
//!
//! For touching spheres (s = 2 R_b) and ρ = R_b: square 1/√2 and 1,
//! hexagonal 1/√8 and 2/√8. Numerically: the deepest resting sample of
//! [`super::measure`] (neighbourhood on its patch), moved to the in-plane
//! point equidistant from its three laterally nearest centres (the
//! hollow, exactly, on a flat lattice), where the domes within 1e−9 a of
//! the top are the ones meeting; min and max of D over the directions
//! where two of them are equal and the directions −g_i (the extrema of an
//! upper envelope of cosines are among these).

use super::measure::resting_heights;
use super::{Covering, PointGrid};
use crate::walls::mesh::geometry::{add, dot, norm, scale, sub};

/// The bump slopes a particle meets at the deepest hollow (module doc).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BumpSlopes {
    /// μ_exit: tan of the slope out of the hollow the easiest way.
    pub exit: f64,
    /// μ_max: tan of the steepest slope (toward a sphere's top).
    pub steepest: f64,
    /// The hollow, m.
    pub at: [f64; 3],
    /// How many domes meet there.
    pub domes: usize,
}

/// In-plane gradients g_i of the domes within `reach` of the normal line
/// through `x`, with their heights t_i.
fn domes(
    c: &Covering,
    grid: &PointGrid,
    x: [f64; 3],
    n: [f64; 3],
    reach: f64,
) -> Vec<(f64, [f64; 3])> {
    let mut out = Vec::new();
    grid.around(x, 1, |id| {
        let w = sub(c.spheres[id as usize].position, x);
        let wn = dot(w, n);
        let lateral = sub(w, scale(n, wn));
        let l2 = dot(lateral, lateral);
        if l2 < reach * reach {
            let root = (reach * reach - l2).sqrt();
            out.push((wn + root, scale(lateral, 1.0 / root)));
        }
    });
    out
}

/// The in-plane point (through `x`, normal `n`) equidistant from the
/// lateral positions of `p0..p2`, or `None` when they are collinear.
fn circumcentre(x: [f64; 3], n: [f64; 3], p: [[f64; 3]; 3]) -> Option<[f64; 3]> {
    let (u, v) = super::super::tiling::plane_axes(n);
    let q: Vec<[f64; 2]> = p
        .iter()
        .map(|&c| {
            let w = sub(c, x);
            [dot(w, u), dot(w, v)]
        })
        .collect();
    let (b, c) = (
        [q[1][0] - q[0][0], q[1][1] - q[0][1]],
        [q[2][0] - q[0][0], q[2][1] - q[0][1]],
    );
    let d = 2.0 * (b[0] * c[1] - b[1] * c[0]);
    let scale_sq = (b[0] * b[0] + b[1] * b[1]).max(c[0] * c[0] + c[1] * c[1]);
    if d.abs() <= 1e-9 * scale_sq {
        return None;
    }
    let (bb, cc) = (b[0] * b[0] + b[1] * b[1], c[0] * c[0] + c[1] * c[1]);
    let ox = (c[1] * bb - b[1] * cc) / d + q[0][0];
    let oy = (b[0] * cc - c[0] * bb) / d + q[0][1];
    Some(add(x, add(scale(u, ox), scale(v, oy))))
}

/// min and max over unit in-plane d of max_i g_i·d (module doc).
fn directional_extremes(g: &[[f64; 3]], n: [f64; 3]) -> (f64, f64) {
    let rate = |d: [f64; 3]| g.iter().map(|gi| dot(*gi, d)).fold(f64::MIN, f64::max);
    let mut candidates = Vec::new();
    for (i, gi) in g.iter().enumerate() {
        let l = norm(*gi);
        if l > 0.0 {
            candidates.push(scale(*gi, -1.0 / l));
        }
        for gj in &g[i + 1..] {
            // d ⊥ (g_i − g_j) in the plane: n × (g_i − g_j).
            let e = sub(*gi, *gj);
            let d = [
                n[1] * e[2] - n[2] * e[1],
                n[2] * e[0] - n[0] * e[2],
                n[0] * e[1] - n[1] * e[0],
            ];
            let l = norm(d);
            if l > 0.0 {
                candidates.push(scale(d, 1.0 / l));
                candidates.push(scale(d, -1.0 / l));
            }
        }
    }
    let lo = candidates
        .iter()
        .map(|&d| rate(d))
        .fold(f64::INFINITY, f64::min);
    let hi = g.iter().map(|gi| norm(*gi)).fold(0.0, f64::max);
    (lo.max(0.0), hi)
}

/// The bump slopes of a covering for particles of radius `rho` (module
/// doc); `None` when no face sample holds such a particle away from edges.
pub fn bump_slopes(c: &Covering, rho: f64) -> Option<BumpSlopes> {
    let mut deepest: Option<([f64; 3], [f64; 3], f64)> = None;
    resting_heights(c, rho, |x, n, t| {
        if deepest.is_none_or(|(_, _, best)| t < best) {
            deepest = Some((x, n, t));
        }
    });
    let (x, n, t_sample) = deepest?;
    let reach = c.options.radius + rho;
    let mut grid = PointGrid::new(reach);
    for (i, s) in c.spheres.iter().enumerate() {
        grid.insert(s.position, i as u32);
    }
    // The three laterally nearest centres: their equidistant point is the
    // hollow next to the sample.
    let mut near: Vec<(f64, [f64; 3])> = Vec::new();
    grid.around(x, 1, |id| {
        let p = c.spheres[id as usize].position;
        let w = sub(p, x);
        let lateral = sub(w, scale(n, dot(w, n)));
        near.push((norm(lateral), p));
    });
    near.sort_by(|a, b| a.0.total_cmp(&b.0));
    let hollow = (near.len() >= 3)
        .then(|| circumcentre(x, n, [near[0].1, near[1].1, near[2].1]))
        .flatten()
        .filter(|p| norm(sub(*p, x)) <= c.options.spacing);
    let at = |p: [f64; 3]| {
        let d = domes(c, &grid, p, n, reach);
        let top = d.iter().map(|x| x.0).fold(f64::NEG_INFINITY, f64::max);
        (d, top)
    };
    // The refined point when it is a hollow at least as deep as the sample.
    let (point, meeting) = match hollow.map(|p| (p, at(p))) {
        Some((p, (d, top))) if top.is_finite() && top <= t_sample + 1e-9 * reach => (p, (d, top)),
        _ => (x, at(x)),
    };
    let (d, top) = meeting;
    let g: Vec<[f64; 3]> = d
        .iter()
        .filter(|(t, _)| *t >= top - 1e-9 * reach)
        .map(|(_, g)| *g)
        .collect();
    let (exit, steepest) = directional_extremes(&g, n);
    Some(BumpSlopes {
        exit,
        steepest,
        at: point,
        domes: g.len(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sources::mesh_tiling::{cover, shapes, CoveringOptions};
    use crate::sources::tiling::Pattern;
    use std::path::Path;

    fn flat(pattern: Pattern, radius: f64, spacing: f64) -> Covering {
        cover(
            Path::new("square"),
            &shapes::square(10.0),
            &CoveringOptions {
                radius,
                spacing,
                pattern,
                flip: false,
            },
        )
        .unwrap()
    }

    /// The closed forms of the module doc: (μ_exit, μ_max).
    fn closed_form(pattern: Pattern, radius: f64, spacing: f64, rho: f64) -> (f64, f64) {
        let a = radius + rho;
        let (w, along) = match pattern {
            Pattern::Square => (spacing / 2f64.sqrt(), spacing / 2.0),
            Pattern::Hexagonal => (spacing / 3f64.sqrt(), spacing / (2.0 * 3f64.sqrt())),
        };
        let t0 = (a * a - w * w).sqrt();
        (along / t0, w / t0)
    }

    #[test]
    fn flat_lattices_give_the_closed_forms() {
        // Touching spheres and ρ = R_b: square 1/√2 and 1, hexagonal 1/√8
        // and 2/√8; then overlapping spheres (s = 1.5 R_b) and a small
        // particle (ρ = 0.5 R_b), and a sparse lattice with a large one.
        // The hollow is found exactly (equidistant point of three
        // centres), so only rounding separates the two: 1e-9.
        let (tc, ts) = closed_form(Pattern::Square, 1.0, 2.0, 1.0);
        assert!((tc - 0.5f64.sqrt()).abs() < 1e-15 && (ts - 1.0).abs() < 1e-15);
        for pattern in [Pattern::Square, Pattern::Hexagonal] {
            for (radius, spacing, rho) in [(1.0, 2.0, 1.0), (1.0, 1.5, 0.5), (0.5, 1.3, 0.8)] {
                let got = bump_slopes(&flat(pattern, radius, spacing), rho).unwrap();
                let (exit, steepest) = closed_form(pattern, radius, spacing, rho);
                assert!(
                    (got.exit - exit).abs() < 1e-9 && (got.steepest - steepest).abs() < 1e-9,
                    "{pattern:?} R_b {radius} s {spacing} ρ {rho}: {got:?} against {exit}, {steepest}"
                );
                let domes = if pattern == Pattern::Square { 4 } else { 3 };
                assert_eq!(got.domes, domes, "{pattern:?}");
            }
        }
    }

    #[test]
    fn a_tilted_square_gives_the_same_slopes() {
        // The square turned 30° about x then 50° about z (normal no
        // longer an axis): its lattice is the same up to a shift, so the
        // same closed forms hold.
        let (a, b) = (30f64.to_radians(), 50f64.to_radians());
        let turn = |p: [f64; 3]| {
            let q = [
                p[0],
                p[1] * a.cos() - p[2] * a.sin(),
                p[1] * a.sin() + p[2] * a.cos(),
            ];
            [
                q[0] * b.cos() - q[1] * b.sin(),
                q[0] * b.sin() + q[1] * b.cos(),
                q[2],
            ]
        };
        let soup: Vec<_> = shapes::square(10.0)
            .into_iter()
            .map(|t| t.map(turn))
            .collect();
        for pattern in [Pattern::Square, Pattern::Hexagonal] {
            let options = CoveringOptions {
                radius: 1.0,
                spacing: 2.0,
                pattern,
                flip: false,
            };
            let c = cover(Path::new("tilted"), &soup, &options).unwrap();
            let got = bump_slopes(&c, 1.0).unwrap();
            let (exit, steepest) = closed_form(pattern, 1.0, 2.0, 1.0);
            // The f32-free soup still carries the rotation's rounding:
            // centres within ~1e-15 of the lattice, slopes to 1e-9.
            assert!(
                (got.exit - exit).abs() < 1e-9 && (got.steepest - steepest).abs() < 1e-9,
                "{pattern:?}: {got:?} against {exit}, {steepest}"
            );
        }
    }
}
