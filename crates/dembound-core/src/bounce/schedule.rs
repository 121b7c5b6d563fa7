//! Step sizes inside a contact in event stepping.
//!
//! A power law with non-integer α (Hertz: α = 3/2) makes the overlap near
//! h = 0 behave like h ≈ wτ + gτ²/2 − c τ^(α+2): the velocity then carries a
//! τ^(α+1) term whose higher derivatives are unbounded, which a degree-5
//! Nordsieck polynomial cannot follow. With a uniform Δt the local velocity
//! error of a step at τ is ~ Δt⁶ τ^(α−5); summed over the contact it makes
//! the scheme converge only at order α+1 = 2.5.
//!
//! The cure is a *graded mesh* over a fixed fraction of the contact at both
//! ends: over the first `T_g = T_c/4` the mesh points are τ_j = T_g (j/N)^q.
//! A step's velocity error is then ~ j^((α+1)q − 6) N^(−(α+1)q), which sums to
//! O(N⁻⁵) for q ≥ 6/(α+1) = 2.4 (here q = 3, N chosen so the last graded
//! step equals Δt): the full 5th order is back, for about T_g(q−1)/Δt extra
//! steps per end. (A ramp whose length shrinks with Δt only improves the
//! constant, not the order: the error of the uniform steps just after it
//! still sums to Δt^2.5.)
//!
//! - Onset: N steps of sizes T_g((j+1)^q − j^q)/N^q, then Δt.
//! - Rebound: once the maximum overlap is found at τ_mp, the rebound is
//!   expected at τ_r ≈ 2 τ_mp (exact for conservative laws, which are
//!   time-reversible; a guess for dissipative ones). The time up to
//!   τ_r − T_g is split into equal steps ≤ Δt and the onset mesh is mirrored
//!   after it. If the contact outlasts the plan, steps double (up to Δt)
//!   until the rebound is crossed.
//!
//! Laws whose onset is smooth (integer α) need none of this and get Δt throughout.
//!
//! Laws with a *singular* onset (damping ∝ h^(1/4) ḣ or h^(1/2) ḣ: the
//! velocity goes like τ^1.25) are different: their higher Nordsieck
//! components are huge near τ = 0, and the large early step ratios of the
//! power mesh (7×, 2.7×, …) amplify them by ratio⁵ on each rescaling. They
//! get a gentle geometric ramp instead: 16 steps growing by 1.4 from ~Δt/200.

/// Grading exponent q (≥ 2.4 for Hertz, see the module doc); an integer so
/// that the mesh costs two `powi`, not two `powf`, per step.
pub const GRADING_EXPONENT: i32 = 3;
/// Fraction of the contact-time estimate graded at each end.
pub const GRADED_FRACTION: f64 = 0.25;

/// How the steps of a contact are graded.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Grading {
    /// Δt throughout (smooth onset).
    Uniform,
    /// τ = T_g (j/N)^q at both ends (non-smooth but bounded force, Hertz).
    Power,
    /// Geometric ramp at the onset only (singular damping force).
    Geometric,
}

/// Growth ratio and length of the geometric onset ramp.
const GEOMETRIC_RATIO: f64 = 1.4;
const GEOMETRIC_STEPS: u64 = 16;

/// Step sizes of one contact.
#[derive(Debug, Clone, Copy)]
pub struct GradedSteps {
    pub(crate) dt: f64,
    pub(crate) grading: Grading,
    pub(crate) graded: bool,
    /// Length of the graded onset region and its number of steps.
    pub(crate) onset_region: f64,
    pub(crate) onset_steps: u64,
    /// Uniform steps left before the end region, and their size.
    pub(crate) uniform_left: u64,
    pub(crate) uniform_size: f64,
    /// End region: length, step count, steps left.
    pub(crate) end_region: f64,
    pub(crate) end_steps: u64,
    pub(crate) end_left: u64,
    pub(crate) planned: bool,
    pub(crate) last: f64,
}

/// Steps needed to grade a region of `length` so that its largest step is ≤ Δt.
pub(crate) fn graded_count(length: f64, dt: f64) -> u64 {
    ((f64::from(GRADING_EXPONENT) * length / dt).ceil().max(1.0)) as u64
}

/// Size of step `j` (0-based, from the thin end) of a region of `length`
/// graded in `n` steps.
pub(crate) fn graded_step(length: f64, n: u64, j: u64) -> f64 {
    let q = GRADING_EXPONENT;
    // Through i64: the counts are far below 2⁶³, the values are the same,
    // and x86-64 converts i64 in one instruction (u64 takes a branchy
    // sequence; this runs every step of a graded region).
    let (j, n) = (j as i64, n as i64);
    let (a, b) = (j as f64 / n as f64, (j + 1) as f64 / n as f64);
    length * (b.powi(q) - a.powi(q))
}

impl GradedSteps {
    /// Δt, the contact-time estimate and the kind of grading.
    pub fn new(dt: f64, contact_time: f64, grading: Grading) -> Self {
        let onset_region = GRADED_FRACTION * contact_time;
        Self {
            dt,
            grading,
            graded: grading == Grading::Power,
            onset_region,
            onset_steps: graded_count(onset_region, dt),
            uniform_left: 0,
            uniform_size: dt,
            end_region: 0.0,
            end_steps: 0,
            end_left: 0,
            planned: false,
            last: dt,
        }
    }

    /// Plans the steps up to the expected rebound, from the end `tau` of the
    /// step in which the maximum overlap was found at `tau_max`.
    pub fn plan_end(&mut self, tau: f64, tau_max: f64) {
        if !self.graded || self.planned {
            return;
        }
        self.planned = true;
        let remaining = 2.0 * tau_max - tau;
        if remaining <= 0.0 {
            return;
        }
        let region = self.onset_region.min(remaining);
        let before = remaining - region;
        if before > 0.0 {
            let n = (before / self.dt).ceil().max(1.0);
            self.uniform_left = n as u64;
            self.uniform_size = before / n;
        }
        self.end_region = region;
        self.end_steps = graded_count(region, self.dt);
        self.end_left = self.end_steps;
    }

    /// Size of step number `j` (0-based) of the contact.
    pub fn next(&mut self, j: u64) -> f64 {
        let h = if self.grading == Grading::Geometric {
            if j < GEOMETRIC_STEPS {
                let from_end = (GEOMETRIC_STEPS - j) as i32;
                self.dt * GEOMETRIC_RATIO.powi(-from_end)
            } else {
                self.dt
            }
        } else if !self.graded {
            self.dt
        } else if self.planned {
            if self.uniform_left > 0 {
                self.uniform_left -= 1;
                self.uniform_size
            } else if self.end_left > 0 {
                self.end_left -= 1;
                graded_step(self.end_region, self.end_steps, self.end_left)
            } else {
                // Past the planned rebound: grow until it is crossed.
                (2.0 * self.last).min(self.dt)
            }
        } else if j < self.onset_steps {
            graded_step(self.onset_region, self.onset_steps, j)
        } else {
            self.dt
        };
        self.last = h;
        h
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn onset_region_is_covered_exactly_with_steps_up_to_dt() {
        let (dt, t) = (1.0, 50.0);
        let mut g = GradedSteps::new(dt, t, Grading::Power);
        let n = g.onset_steps;
        let steps: Vec<f64> = (0..n).map(|j| g.next(j)).collect();
        let covered: f64 = steps.iter().sum();
        assert!((covered - GRADED_FRACTION * t).abs() < 1e-12);
        assert!(steps.iter().all(|&h| h <= dt + 1e-12));
        assert_eq!(g.next(n), dt);
    }

    #[test]
    fn end_plan_lands_on_twice_the_time_of_maximum_overlap() {
        let (dt, t) = (1.0, 50.0);
        let mut g = GradedSteps::new(dt, t, Grading::Power);
        let mut tau = 0.0;
        let mut j = 0;
        while tau < 25.3 {
            tau += g.next(j);
            j += 1;
        }
        g.plan_end(tau, 25.1);
        while g.uniform_left > 0 || g.end_left > 0 {
            tau += g.next(j);
            j += 1;
        }
        assert!((tau - 50.2).abs() < 1e-12, "{tau}");
    }

    #[test]
    fn smooth_laws_get_uniform_steps() {
        let mut g = GradedSteps::new(0.5, 50.0, Grading::Uniform);
        g.plan_end(25.0, 24.9);
        assert!((0..10).all(|j| g.next(j) == 0.5));
    }
}
