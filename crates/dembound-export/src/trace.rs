//! Reading a trace back (`trace.txt`, written by every exported deck) and
//! measuring each contact in it the way dembound reports contacts.
//!
//! Method, the same for every code (hand-written: it is the measurement
//! whose accuracy the comparison rests on):
//! - A contact is a run of steps with overlap h > 0 inside one window of
//!   consecutive steps.
//! - Onset t_c and rebound t_r: outside the contact the relative motion is
//!   free flight under constant gravity, which velocity Verlet and
//!   leapfrog integrate exactly, so h(t) there is a parabola. t_c is the
//!   root of the parabola through the last three steps before the contact,
//!   t_r the root of the parabola through the first three after it; this
//!   also holds after a clamped force has returned to zero (free flight
//!   while the overlap closes).
//! - v_c and v_r: the velocity, linear in time in free flight, from the two
//!   nearest free-flight samples on each side (samples whose velocity no
//!   contact force has touched under velocity Verlet or leapfrog),
//!   evaluated at t_c and t_r. A header line `# velocity_time_offset_s = X`
//!   says the velocities are those at t + X (Yade's half step).
//! - h_max: the vertex of the parabola through the largest sample and its
//!   two neighbours.

use crate::{Error, Result};

/// One line of a trace.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sample {
    /// s.
    pub time: f64,
    /// m, positive in contact.
    pub overlap: f64,
    /// m/s, relative, upward positive.
    pub velocity: f64,
    /// N, contact force on the particle, upward positive.
    pub force: f64,
}

/// A parsed trace.
#[derive(Debug, Clone, PartialEq)]
pub struct Trace {
    pub samples: Vec<Sample>,
    /// The velocities are those at `time + velocity_time_offset`, s.
    pub velocity_time_offset: f64,
    /// The scenario fingerprint in the header (`scenario=…`), if any.
    pub scenario: Option<String>,
}

/// One contact measured in a trace, in dembound's terms (SI).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MeasuredContact {
    pub t_contact: f64,
    pub t_rebound: f64,
    pub duration: f64,
    pub max_overlap: f64,
    /// Largest sampled contact force, N (a step sample, not interpolated).
    pub max_force: f64,
    pub impact_velocity: f64,
    pub rebound_velocity: f64,
    pub restitution: f64,
}

impl Trace {
    /// Parses the text of a trace: `#` comments, then four numbers a line.
    pub fn parse(text: &str) -> Result<Self> {
        let mut samples = Vec::new();
        let mut offset = 0.0;
        let mut scenario = None;
        for (n, line) in text.lines().enumerate() {
            let line = line.trim();
            if line.is_empty() {
                continue;
            }
            if let Some(comment) = line.strip_prefix('#') {
                if let Some(at) = comment.find("scenario=") {
                    scenario = comment[at + 9..]
                        .split_whitespace()
                        .next()
                        .map(String::from);
                }
                if let Some((key, value)) = comment.split_once('=') {
                    if key.trim() == "velocity_time_offset_s" {
                        offset = value.trim().parse().map_err(|_| {
                            Error::Trace(format!("line {}: bad velocity_time_offset_s", n + 1))
                        })?;
                    }
                }
                continue;
            }
            let fields: Vec<f64> = line
                .split_whitespace()
                .map(str::parse)
                .collect::<Result<_, _>>()
                .map_err(|_| Error::Trace(format!("line {}: not four numbers: `{line}`", n + 1)))?;
            if fields.len() != 4 || fields.iter().any(|x| !x.is_finite()) {
                return Err(Error::Trace(format!(
                    "line {}: expected four finite numbers (time, overlap, velocity, force), got `{line}`",
                    n + 1
                )));
            }
            samples.push(Sample {
                time: fields[0],
                overlap: fields[1],
                velocity: fields[2],
                force: fields[3],
            });
        }
        if samples.len() < 8 {
            return Err(Error::Trace(format!(
                "{} samples: too few to hold a contact",
                samples.len()
            )));
        }
        Ok(Trace {
            samples,
            velocity_time_offset: offset,
            scenario,
        })
    }

    /// Every complete contact, in time order.
    pub fn contacts(&self) -> Result<Vec<MeasuredContact>> {
        let mut out = Vec::new();
        for window in self.windows() {
            let s = &self.samples[window.0..window.1];
            let mut i = 0;
            while i < s.len() {
                if s[i].overlap <= 0.0 {
                    i += 1;
                    continue;
                }
                let k = i;
                while i < s.len() && s[i].overlap > 0.0 {
                    i += 1;
                }
                let j = i;
                if k < 3 || j + 3 > s.len() {
                    return Err(Error::Trace(format!(
                        "the contact at t = {} s is cut by the end of its window (3 free steps are \
                         needed on each side)",
                        s[k].time
                    )));
                }
                out.push(self.measure(s, k, j));
            }
        }
        if out.is_empty() {
            return Err(Error::Trace("no contact (overlap > 0) in the trace".into()));
        }
        Ok(out)
    }

    /// Ranges of consecutive steps (a time jump larger than 1.5 steps
    /// separates windows).
    fn windows(&self) -> Vec<(usize, usize)> {
        let s = &self.samples;
        let mut steps: Vec<f64> = s.windows(2).map(|w| w[1].time - w[0].time).collect();
        steps.sort_by(f64::total_cmp);
        let dt = steps[steps.len() / 2];
        let mut out = Vec::new();
        let mut start = 0;
        for i in 1..s.len() {
            if s[i].time - s[i - 1].time > 1.5 * dt {
                out.push((start, i));
                start = i;
            }
        }
        out.push((start, s.len()));
        out
    }

    fn measure(&self, s: &[Sample], k: usize, j: usize) -> MeasuredContact {
        let off = self.velocity_time_offset;
        let t_contact = parabola_root(&s[k - 3..k], s[k - 1].time, s[k].time);
        let t_rebound = parabola_root(&s[j..j + 3], s[j - 1].time, s[j].time);
        let line_at = |a: &Sample, b: &Sample, t: f64| {
            let (ta, tb) = (a.time + off, b.time + off);
            a.velocity + (b.velocity - a.velocity) * (t - ta) / (tb - ta)
        };
        let impact_velocity = line_at(&s[k - 2], &s[k - 1], t_contact);
        let rebound_velocity = line_at(&s[j + 1], &s[j + 2], t_rebound);
        let (imax, _) = s[k..j]
            .iter()
            .enumerate()
            .fold((0, f64::MIN), |(bi, bh), (i, x)| {
                if x.overlap > bh {
                    (i, x.overlap)
                } else {
                    (bi, bh)
                }
            });
        let m = k + imax;
        let (y0, y1, y2) = (s[m - 1].overlap, s[m].overlap, s[m + 1].overlap);
        let curvature = y0 - 2.0 * y1 + y2;
        let max_overlap = if curvature < 0.0 {
            let p = (y0 - y2) / (2.0 * curvature);
            y1 - (y0 - y2) * p / 4.0
        } else {
            y1
        };
        let max_force = s[k..j].iter().map(|x| x.force).fold(f64::MIN, f64::max);
        MeasuredContact {
            t_contact,
            t_rebound,
            duration: t_rebound - t_contact,
            max_overlap,
            max_force,
            impact_velocity,
            rebound_velocity,
            restitution: rebound_velocity / impact_velocity.abs(),
        }
    }
}

/// The root in [lo, hi] of the parabola through three samples' overlaps.
fn parabola_root(p: &[Sample], lo: f64, hi: f64) -> f64 {
    // Lagrange form in u = t − t0 (small numbers: no cancellation in t).
    let t0 = p[0].time;
    let (u0, u1, u2) = (0.0, p[1].time - t0, p[2].time - t0);
    let (h0, h1, h2) = (p[0].overlap, p[1].overlap, p[2].overlap);
    let f = |u: f64| {
        h0 * (u - u1) * (u - u2) / ((u0 - u1) * (u0 - u2))
            + h1 * (u - u0) * (u - u2) / ((u1 - u0) * (u1 - u2))
            + h2 * (u - u0) * (u - u1) / ((u2 - u0) * (u2 - u1))
    };
    // Bisection: the parabola changes sign on [lo, hi] (free flight crosses
    // h = 0 once there); 200 halvings reach the last bit.
    let (mut a, mut b) = (lo - t0, hi - t0);
    let fa = f(a);
    if fa * f(b) > 0.0 {
        // No sign change (e.g. a grazing contact): the secant of the samples.
        return lo;
    }
    for _ in 0..200 {
        let mid = 0.5 * (a + b);
        if mid == a || mid == b {
            break;
        }
        if (f(mid) > 0.0) == (fa > 0.0) {
            a = mid;
        } else {
            b = mid;
        }
    }
    t0 + 0.5 * (a + b)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A linear spring contact with free flight on each side, sampled at
    /// a fixed step, measured back: the closed form is known.
    #[test]
    fn measures_a_closed_form_contact() {
        // Gravity-free: h = v sin(ω (t − t_c))/ω in contact, v (t − t_c) before,
        // −v (t − t_r) after; v = 1 m/s, ω = 1e5 /s, t_c = 1.2345e-4 s.
        let (v, w, tc) = (1.0, 1.0e5, 1.2345e-4);
        let tr = tc + std::f64::consts::PI / w;
        let dt = 1.0e-7;
        let mut text = String::from("# t h v f\n");
        for n in 1000..1700 {
            let t = n as f64 * dt;
            let (h, vel) = if t < tc {
                (v * (t - tc), -v)
            } else if t < tr {
                ((v / w) * (w * (t - tc)).sin(), -v * (w * (t - tc)).cos())
            } else {
                (-v * (t - tr), v)
            };
            text.push_str(&format!("{t:e} {h:e} {vel:e} 0\n"));
        }
        let c = Trace::parse(&text).unwrap().contacts().unwrap();
        assert_eq!(c.len(), 1);
        // Linear free flight: roots exact to rounding.
        assert!((c[0].t_contact - tc).abs() < 1e-15, "{}", c[0].t_contact);
        assert!((c[0].t_rebound - tr).abs() < 1e-15);
        assert!((c[0].restitution - 1.0).abs() < 1e-12);
        // Vertex of a sampled sine: error ≤ (ω Δt)⁴/… ≈ 1e-6 at ω Δt = 0.01.
        assert!((c[0].max_overlap / (v / w) - 1.0).abs() < 1e-6);
    }

    #[test]
    fn bad_lines_are_named() {
        let e = Trace::parse("# x\n1 2 3\n").unwrap_err();
        assert!(matches!(&e, Error::Trace(m) if m.contains("line 2")), "{e}");
    }
}
