//! How the angle of a heap is measured: [`ridge_angle`], a line fitted
//! to each flank of the surface of a ridge (the method is stated there
//! and checked on synthetic ridges of known angle in the unit tests).

/// The measured angle of a heap.
#[derive(Debug, Clone)]
pub struct HeapAngle {
    /// Mean of the two flanks, degrees.
    pub angle: f64,
    /// Its error, degrees: the larger of the fits' combined standard
    /// error and half the flanks' difference.
    pub error: f64,
    /// The flanks' angles (−x side, +x side), degrees.
    pub flanks: [f64; 2],
    /// Heap height above the base, m.
    pub height: f64,
    /// The surface: (x, height above the base) of each bin's highest
    /// sphere, m.
    pub profile: Vec<(f64, f64)>,
}

/// Least-squares line through `pts`: (slope, its standard error); `None`
/// with fewer than 3 points.
fn line_fit(pts: &[(f64, f64)]) -> Option<(f64, f64)> {
    if pts.len() < 3 {
        return None;
    }
    let n = pts.len() as f64;
    let mx = pts.iter().map(|p| p.0).sum::<f64>() / n;
    let my = pts.iter().map(|p| p.1).sum::<f64>() / n;
    let sxy: f64 = pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    let sxx: f64 = pts.iter().map(|p| (p.0 - mx).powi(2)).sum();
    if sxx <= 0.0 {
        return None;
    }
    let b = sxy / sxx;
    let res: f64 = pts
        .iter()
        .map(|p| (p.1 - my - b * (p.0 - mx)).powi(2))
        .sum();
    Some((b, (res / (n - 2.0) / sxx).sqrt()))
}

/// The angle of the ridge of spheres at `x` (centres) with `radii`, its
/// crest along y near x = `crest`, on a base whose top is at `base`,
/// with bins of width `bin` (a mean diameter) along x.
///
/// Method: the x axis is cut into bins of width `bin`; the surface of a
/// bin is its highest sphere (the outermost sphere of the heap there,
/// over the periodic width): its x and its top (z + r). With H the heap's
/// height (the highest top above `base`), the bins whose surface lies
/// between 0.25 H and 0.75 H above the base are kept (the rounded crest
/// and the foot, where single grains roll out, are excluded), and a line
/// is fitted by least squares to their spheres' (x, top) on each flank.
/// (The sphere's own x, not the bin's centre: the highest sphere sits
/// nearer a bin's uphill edge by a distance that depends on how many
/// spheres the bin holds.) The angle is the mean of the flanks'. `None`
/// if a flank has fewer than 3 such bins.
pub fn ridge_angle(
    x: &[[f64; 3]],
    radii: &[f64],
    crest: f64,
    base: f64,
    bin: f64,
) -> Option<HeapAngle> {
    let (mut lo, mut hi, mut top) = (f64::INFINITY, f64::NEG_INFINITY, base);
    for (p, r) in x.iter().zip(radii) {
        lo = lo.min(p[0]);
        hi = hi.max(p[0]);
        top = top.max(p[2] + r);
    }
    let height = top - base;
    if height.is_nan() || height <= 0.0 {
        return None;
    }
    let bins = ((hi - lo) / bin).floor() as usize + 1;
    let mut surface = vec![(f64::NAN, f64::NAN); bins];
    for (p, r) in x.iter().zip(radii) {
        let k = (((p[0] - lo) / bin) as usize).min(bins - 1);
        let h = p[2] + r - base;
        if surface[k].1.is_nan() || h > surface[k].1 {
            surface[k] = (p[0], h);
        }
    }
    let flank = |side: f64| {
        let pts: Vec<(f64, f64)> = surface
            .iter()
            .copied()
            .filter(|&(px, h)| {
                (px - crest) * side > 0.0 && h >= 0.25 * height && h <= 0.75 * height
            })
            .collect();
        line_fit(&pts).map(|(b, e)| {
            // θ = atan(∓b), its error e/(1 + b²) (d atan b/db), degrees.
            (
                (-side * b).atan().to_degrees(),
                (e / (1.0 + b * b)).to_degrees(),
            )
        })
    };
    let (left, right) = (flank(-1.0)?, flank(1.0)?);
    let angle = 0.5 * (left.0 + right.0);
    let error = (0.5 * left.1.hypot(right.1)).max(0.5 * (left.0 - right.0).abs());
    Some(HeapAngle {
        angle,
        error,
        flanks: [left.0, right.0],
        height,
        profile: surface.into_iter().filter(|p| p.1.is_finite()).collect(),
    })
}

#[cfg(test)]
mod tests {
    use super::super::granular::Rng;
    use super::*;

    /// A synthetic ridge: spheres of radius 1 mm ± 10 % under a ridge of
    /// half-width `half` and slope `angle` (degrees), crest at x = 0, on
    /// a base at z = 0, 8 mm across: `n` at random places whose tops lie
    /// up to 0.2 mm under the surface (a rough surface layer, as a settled
    /// heap has: every bin's highest sphere touches the surface), and as
    /// many at random depths below it.
    fn ridge(angle: f64, half: f64, n: usize) -> (Vec<[f64; 3]>, Vec<f64>) {
        let t = angle.to_radians().tan();
        let mut rng = Rng(7);
        let (mut x, mut r) = (Vec::new(), Vec::new());
        while x.len() < 2 * n {
            let rad = 1e-3 * (1.0 + 0.1 * rng.symmetric());
            let (px, py) = (half * rng.symmetric(), 8e-3 * rng.next_f64());
            let surface = (half - px.abs()) * t;
            let z = if x.len() < n {
                surface - rad - 0.2e-3 * rng.next_f64()
            } else {
                rad + (surface - 2.0 * rad) * rng.next_f64()
            };
            if z >= rad {
                x.push([px, py, z]);
                r.push(rad);
            }
        }
        (x, r)
    }

    /// The method recovers the ridge's angle: each bin's highest sphere
    /// tops the surface within 0.2 mm at its own x. 1°: the resolution
    /// the friction checks need (the full run's angles differ by several
    /// degrees).
    #[test]
    fn the_angle_of_a_synthetic_ridge_is_recovered() {
        for angle in [20.0, 30.0, 40.0] {
            let (x, r) = ridge(angle, 0.04, 1_000);
            let m = ridge_angle(&x, &r, 0.0, 0.0, 2e-3).unwrap();
            assert!(
                (m.angle - angle).abs() < 1.0,
                "{angle}°: measured {}° ± {}°",
                m.angle,
                m.error
            );
            assert!(
                m.flanks.iter().all(|f| (f - angle).abs() < 1.5),
                "{:?}",
                m.flanks
            );
        }
    }

    /// A crest off x = 0 is taken where given; no spheres, no angle.
    #[test]
    fn the_crest_is_the_given_one_and_nothing_has_no_angle() {
        let (mut x, r) = ridge(30.0, 0.04, 1_000);
        for p in &mut x {
            p[0] += 0.01;
        }
        let m = ridge_angle(&x, &r, 0.01, 0.0, 2e-3).unwrap();
        assert!((m.angle - 30.0).abs() < 1.0, "{}", m.angle);
        assert!(ridge_angle(&[], &[], 0.0, 0.0, 2e-3).is_none());
    }
}
