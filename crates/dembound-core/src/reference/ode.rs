//! Adaptive Dormand–Prince 5(4) for the two-dimensional autonomous system
//! y = (h, ḣ), with exact event location.
//!
//! Hand-written rather than taken from `ode_solvers` because (a) the
//! reference needs events (maximum overlap, force zero, rebound) located to
//! the tolerance, which that crate does not offer, and (b) it would pull
//! `nalgebra` into the physics core for a 2-state system. Coefficients:
//! Dormand & Prince, J. Comput. Appl. Math. 6, 19 (1980); step control as
//! in Hairer, Nørsett & Wanner, *Solving ODEs I*, II.4. An event is located
//! by bisection on the length of a single step taken from the start of the
//! step that contains it, so its error is that of one step (≤ tolerance).

use crate::{Error, Result};

/// (h, ḣ).
pub type State = [f64; 2];

/// Error control: a component passes when |err| ≤ atol + rtol |y|.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Tolerance {
    pub rtol: f64,
    pub atol: State,
}

/// The first event reached: its time, state and index in the event list.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Event {
    pub t: f64,
    pub y: State,
    pub index: usize,
}

const A21: f64 = 1.0 / 5.0;
const A31: f64 = 3.0 / 40.0;
const A32: f64 = 9.0 / 40.0;
const A41: f64 = 44.0 / 45.0;
const A42: f64 = -56.0 / 15.0;
const A43: f64 = 32.0 / 9.0;
const A51: f64 = 19372.0 / 6561.0;
const A52: f64 = -25360.0 / 2187.0;
const A53: f64 = 64448.0 / 6561.0;
const A54: f64 = -212.0 / 729.0;
const A61: f64 = 9017.0 / 3168.0;
const A62: f64 = -355.0 / 33.0;
const A63: f64 = 46732.0 / 5247.0;
const A64: f64 = 49.0 / 176.0;
const A65: f64 = -5103.0 / 18656.0;
const B1: f64 = 35.0 / 384.0;
const B3: f64 = 500.0 / 1113.0;
const B4: f64 = 125.0 / 192.0;
const B5: f64 = -2187.0 / 6784.0;
const B6: f64 = 11.0 / 84.0;
const E1: f64 = 71.0 / 57600.0;
const E3: f64 = -71.0 / 16695.0;
const E4: f64 = 71.0 / 1920.0;
const E5: f64 = -17253.0 / 339200.0;
const E6: f64 = 22.0 / 525.0;
const E7: f64 = -1.0 / 40.0;

fn lin(y: &State, terms: &[(f64, &State)], h: f64) -> State {
    let mut out = *y;
    for (c, k) in terms {
        out[0] += h * c * k[0];
        out[1] += h * c * k[1];
    }
    out
}

/// One Dormand–Prince step of size `h` from `y` (with k₁ = f(y)): the
/// 5th-order solution and the error estimate.
fn step(f: &impl Fn(&State) -> State, y: &State, k1: &State, h: f64) -> (State, State) {
    let k2 = f(&lin(y, &[(A21, k1)], h));
    let k3 = f(&lin(y, &[(A31, k1), (A32, &k2)], h));
    let k4 = f(&lin(y, &[(A41, k1), (A42, &k2), (A43, &k3)], h));
    let k5 = f(&lin(y, &[(A51, k1), (A52, &k2), (A53, &k3), (A54, &k4)], h));
    let k6 = f(&lin(
        y,
        &[(A61, k1), (A62, &k2), (A63, &k3), (A64, &k4), (A65, &k5)],
        h,
    ));
    let y5 = lin(
        y,
        &[(B1, k1), (B3, &k3), (B4, &k4), (B5, &k5), (B6, &k6)],
        h,
    );
    let k7 = f(&y5);
    let mut err = [0.0; 2];
    for i in 0..2 {
        err[i] = h * (E1 * k1[i] + E3 * k3[i] + E4 * k4[i] + E5 * k5[i] + E6 * k6[i] + E7 * k7[i]);
    }
    (y5, err)
}

/// Integrates y' = f(y) from `y0` at t = 0 until the first event, where an
/// event `i` is `events[i](y)` rising from < 0 to ≥ 0. `h0` is the first
/// trial step.
pub fn integrate_to_event(
    f: impl Fn(&State) -> State,
    y0: State,
    events: &[&dyn Fn(&State) -> f64],
    tol: Tolerance,
    h0: f64,
    max_steps: usize,
) -> Result<Event> {
    let (mut t, mut y, mut h) = (0.0_f64, y0, h0);
    let mut g: Vec<f64> = events.iter().map(|e| e(&y)).collect();
    for _ in 0..max_steps {
        let tiny = h.is_nan() || h <= 1e-300 * t.abs().max(1.0);
        if tiny || !y.iter().all(|x| x.is_finite()) {
            return Err(Error::StepUnderflow(t));
        }
        let k1 = f(&y);
        let (y_new, err) = step(&f, &y, &k1, h);
        let mut norm = 0.0;
        for i in 0..2 {
            let sc = tol.atol[i] + tol.rtol * y[i].abs().max(y_new[i].abs());
            norm += (err[i] / sc).powi(2);
        }
        let norm = (0.5 * norm).sqrt();
        if !norm.is_finite() || norm > 1.0 {
            let fac = if norm.is_finite() {
                (0.9 * norm.powf(-0.2)).max(0.1)
            } else {
                0.1
            };
            h *= fac;
            continue;
        }
        // Accepted: look for events inside the step.
        let g_new: Vec<f64> = events.iter().map(|e| e(&y_new)).collect();
        let mut first: Option<(f64, State, usize)> = None;
        for (i, event) in events.iter().enumerate() {
            if g[i] < 0.0 && g_new[i] >= 0.0 {
                let (mut lo, mut hi) = (0.0, h);
                let mut y_hi = y_new;
                for _ in 0..200 {
                    let mid = 0.5 * (lo + hi);
                    if mid <= lo || mid >= hi {
                        break;
                    }
                    let (ym, _) = step(&f, &y, &k1, mid);
                    if event(&ym) >= 0.0 {
                        hi = mid;
                        y_hi = ym;
                    } else {
                        lo = mid;
                    }
                }
                let earlier = match first {
                    Some((tau, _, _)) => hi < tau,
                    None => true,
                };
                if earlier {
                    first = Some((hi, y_hi, i));
                }
            }
        }
        if let Some((tau, y_event, index)) = first {
            return Ok(Event {
                t: t + tau,
                y: y_event,
                index,
            });
        }
        t += h;
        y = y_new;
        g = g_new;
        h *= (0.9 * norm.max(1e-10).powf(-0.2)).min(5.0);
    }
    Err(Error::TooManySteps(max_steps))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn harmonic_oscillator_zero_crossing_to_1e_12() {
        // h'' = −h from (0, 1): ḣ = 0 at π/2 with h = 1; h = 0 again at π.
        let tol = Tolerance {
            rtol: 1e-13,
            atol: [1e-14, 1e-14],
        };
        let f = |y: &State| [y[1], -y[0]];
        let top =
            integrate_to_event(f, [0.0, 1.0], &[&|y: &State| -y[1]], tol, 1e-3, 100_000).unwrap();
        assert!(
            (top.t - std::f64::consts::FRAC_PI_2).abs() < 1e-12,
            "{top:?}"
        );
        assert!((top.y[0] - 1.0).abs() < 1e-12);
        let back = integrate_to_event(f, top.y, &[&|y: &State| -y[0]], tol, 1e-3, 100_000).unwrap();
        assert!(
            (top.t + back.t - std::f64::consts::PI).abs() < 1e-12,
            "{back:?}"
        );
        assert!((back.y[1] + 1.0).abs() < 1e-12);
    }
}
