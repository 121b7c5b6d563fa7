//! Small vector helpers and closest points on segments and triangles.

#[inline(always)]
pub fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

#[inline(always)]
pub fn add(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

#[inline(always)]
pub fn scale(a: [f64; 3], s: f64) -> [f64; 3] {
    [a[0] * s, a[1] * s, a[2] * s]
}

#[inline(always)]
pub fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

#[inline(always)]
pub fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

#[inline(always)]
pub fn norm(a: [f64; 3]) -> f64 {
    dot(a, a).sqrt()
}

/// The point of segment a–b closest to x, and its parameter t ∈ [0, 1]
/// (0 at a).
#[inline]
pub fn closest_on_segment(x: [f64; 3], a: [f64; 3], b: [f64; 3]) -> ([f64; 3], f64) {
    let e = sub(b, a);
    let ee = dot(e, e);
    let t = if ee > 0.0 {
        (dot(sub(x, a), e) / ee).clamp(0.0, 1.0)
    } else {
        0.0
    };
    if t == 0.0 {
        (a, 0.0)
    } else if t == 1.0 {
        (b, 1.0)
    } else {
        (add(a, scale(e, t)), t)
    }
}

/// The point of triangle (a, b, c) closest to x (by regions of the
/// triangle's Voronoi diagram: vertices, edges, face).
pub fn closest_on_triangle(x: [f64; 3], a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> [f64; 3] {
    let ab = sub(b, a);
    let ac = sub(c, a);
    let ap = sub(x, a);
    let d1 = dot(ab, ap);
    let d2 = dot(ac, ap);
    if d1 <= 0.0 && d2 <= 0.0 {
        return a;
    }
    let bp = sub(x, b);
    let d3 = dot(ab, bp);
    let d4 = dot(ac, bp);
    if d3 >= 0.0 && d4 <= d3 {
        return b;
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        return closest_on_segment(x, a, b).0;
    }
    let cp = sub(x, c);
    let d5 = dot(ab, cp);
    let d6 = dot(ac, cp);
    if d6 >= 0.0 && d5 <= d6 {
        return c;
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        return closest_on_segment(x, a, c).0;
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        return closest_on_segment(x, b, c).0;
    }
    let denom = va + vb + vc;
    if denom.abs() > 0.0 && denom.is_finite() {
        let v = vb / denom;
        let w = vc / denom;
        add(a, add(scale(ab, v), scale(ac, w)))
    } else {
        // A degenerate triangle (none reaches here after cleaning): its
        // closest edge point.
        let p = [
            closest_on_segment(x, a, b).0,
            closest_on_segment(x, b, c).0,
            closest_on_segment(x, c, a).0,
        ];
        let mut best = p[0];
        for q in &p[1..] {
            if norm(sub(*q, x)) < norm(sub(best, x)) {
                best = *q;
            }
        }
        best
    }
}

/// Where the segment from `p` to `q` meets triangle (a, b, c), if it does
/// (Möller–Trumbore; barycentric coordinates within 1e-12 of the
/// triangle's so that a segment through a seam meets one of its two
/// triangles; a segment parallel to the triangle's plane meets nothing).
pub fn segment_meets_triangle(
    p: [f64; 3],
    q: [f64; 3],
    a: [f64; 3],
    b: [f64; 3],
    c: [f64; 3],
) -> Option<[f64; 3]> {
    const EPS: f64 = 1e-12;
    let d = sub(q, p);
    let e1 = sub(b, a);
    let e2 = sub(c, a);
    let pv = cross(d, e2);
    let det = dot(e1, pv);
    // Parallel (or not a number): no crossing.
    let crossing = det.abs() > 1e-14 * norm(e1) * norm(e2) * norm(d);
    if !crossing {
        return None;
    }
    let inv = 1.0 / det;
    let s = sub(p, a);
    let u = dot(s, pv) * inv;
    if !(-EPS..=1.0 + EPS).contains(&u) {
        return None;
    }
    let qv = cross(s, e1);
    let v = dot(d, qv) * inv;
    if v < -EPS || u + v > 1.0 + EPS {
        return None;
    }
    let t = dot(e2, qv) * inv;
    if !(0.0..=1.0).contains(&t) {
        return None;
    }
    Some(add(p, scale(d, t)))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Closest points by region against hand values on the unit right
    /// triangle in z = 0.
    #[test]
    fn closest_points_by_region() {
        let (a, b, c) = ([0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]);
        // The face region: a + v ab + w ac with v, w from ratios of dot
        // products, exact to an ulp or two.
        let p = closest_on_triangle([0.2, 0.3, 5.0], a, b, c);
        assert!((p[0] - 0.2).abs() < 1e-16 && (p[1] - 0.3).abs() < 1e-16 && p[2] == 0.0);
        assert_eq!(closest_on_triangle([-1.0, -2.0, 1.0], a, b, c), a);
        assert_eq!(closest_on_triangle([3.0, -1.0, 0.0], a, b, c), b);
        assert_eq!(
            closest_on_triangle([0.5, -1.0, 2.0], a, b, c),
            [0.5, 0.0, 0.0]
        );
        // Beyond the hypotenuse x + y = 1 at (1, 1): its midpoint.
        let p = closest_on_triangle([1.0, 1.0, 0.0], a, b, c);
        assert!((p[0] - 0.5).abs() < 1e-15 && (p[1] - 0.5).abs() < 1e-15);
        let (q, t) = closest_on_segment([0.25, 7.0, 0.0], a, b);
        assert_eq!((q, t), ([0.25, 0.0, 0.0], 0.25));
        // A vertical segment through (0.25, 0.25) meets the triangle
        // there; one stopping short, or beside it, or in its plane, not.
        let hit = segment_meets_triangle([0.25, 0.25, 1.0], [0.25, 0.25, -1.0], a, b, c);
        assert!(hit.is_some_and(|h| h[2].abs() < 1e-16 && (h[0] - 0.25).abs() < 1e-16));
        assert!(segment_meets_triangle([0.25, 0.25, 1.0], [0.25, 0.25, 0.1], a, b, c).is_none());
        assert!(segment_meets_triangle([0.9, 0.9, 1.0], [0.9, 0.9, -1.0], a, b, c).is_none());
        assert!(segment_meets_triangle([-1.0, 0.2, 0.0], [2.0, 0.2, 0.0], a, b, c).is_none());
    }
}
