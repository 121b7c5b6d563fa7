//! Step sizes inside a contact in event stepping (and, for laws with a
//! singular onset, between the grid points of fixed stepping).
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
//! Laws with a *singular* onset (damping ∝ h^β ḣ, β = 1/4 for Tsuji, 1/2
//! for the viscoelastic law) get [`SingularMesh`] instead, at *both* ends
//! whenever the end is h = 0. Near such an end, at a distance s in time,
//! the overlap is h = v s + g s²/2 − a s^(2+β) + … (v ≠ 0 at both ends when
//! attraction is allowed), so the velocity carries s^p with p = 1 + β
//! (5/4, 3/2) and its sixth derivative grows like s^(p−6) — much worse than
//! Hertz's s^(α+1−6). The error analysis is that of the Hertz mesh above:
//!
//! - A Gear5 step of size H at distance s ≥ H from the singular point makes
//!   a velocity error ~ H⁶ s^(p−6); on the mesh s = s_g (j/N)^q that is
//!   ~ j^(qp−6) N^(−qp), which sums to O(N⁻⁵) = O(Δt⁵) for qp ≥ 6
//!   ([`SINGULAR_EXPONENT`] q = 5: qp = 6.25 and 7.5), over
//!   s_g = [`SINGULAR_FRACTION`] T_c at each end, for (q−1) s_g/Δt extra
//!   steps per end. With uniform steps the same sum is dominated by the
//!   step nearest the singular point: O(Δt^p), the measured ~1e−4 … 1e−3
//!   in e at η = 1/50 before this mesh was used at the end.
//! - **Onset** (τ from the contact's start, known exactly): the step is
//!   min(Δt, ρτ, Δt (τ/s_g)^(1−1/q)), the derivative of the power mesh,
//!   capped to a growth of 1 + ρ = 1.4 per step. The cap matters: the
//!   higher Nordsieck components are poorly determined on a solution whose
//!   derivatives are infinite at τ = 0 (they are seeded with 0), and each
//!   growth by a ratio multiplies their error by ratio⁵; measured at
//!   η = 1/50, ρ = 0.6 and 1 gave 1e−5 and 7e−5 where ρ = 0.4 gives 1e−6,
//!   and ratios of 2 from a first step of 1e−6 Δt destroyed the run (25 %).
//!   The first step H₀ contains the singular point; its error is
//!   ~ (H₀/T_c)^p, so H₀ = [`SINGULAR_FIRST`] Δt (η/η₀)³ (η₀ = 1/50) makes it
//!   fall like η^(4p), faster than the η⁵ of the rest.
//! - **End** (its time only estimated): after the maximum overlap, each
//!   step asks for the time s left until x + v s + a s²/2 = 0 from the
//!   current gap, velocity and acceleration, and steps to the next point of
//!   the same power mesh counted from that estimate. The estimate only
//!   places the mesh: its relative error vanishes like s^β as s → 0, and a
//!   mesh placed with a wrong s is still a smooth graded mesh. From the
//!   mesh index j ≤ 2 on (s ≤ s_g (2/N)^q ∝ Δt⁵), one step of twice the
//!   time left crosses h = 0, where the rebound is located on the step's
//!   polynomial; its own error ~ (H/T_c)^p ∝ Δt^(qp) is negligible.
//!   A clamped (non-attractive) contact ends at the force zero before
//!   h = 0; the mesh is used there too (the force zero of a weakly damped
//!   contact lies within a step or two of the singular point), and the
//!   flight after it is exact.
//!
//! Measured (`examples/damped_hertz_errors`, Gear5, e ∈ {0.3, 0.5, 0.9},
//! four impact speeds, with and without attraction, event and fixed
//! stepping, exact calibration): the largest relative error in e, T_c and
//! h_max is 2.7e−4, 2.1e−6, 5.8e−8, 1.9e−9 at η = 1/25, 1/50, 1/100, 1/200
//! (5th order), for 86–95 steps per contact without attraction and 111–121
//! with it at η = 1/50 (elastic Hertz: 103; before this mesh 64–78, with
//! errors up to 1.8e−3 in e).

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
}

/// Step sizes of one contact.
#[derive(Debug, Clone, Copy)]
pub struct GradedSteps {
    pub(crate) dt: f64,
    /// Recorded for the batched path's lanes; `graded` is what `next` reads.
    #[allow(dead_code)]
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
    #[inline]
    pub fn next(&mut self, j: u64) -> f64 {
        self.next_with(j, |region, _, n, k| graded_step(region, n, k))
    }

    /// [`Self::next`] with the graded step sizes from `graded(region
    /// length, is the end region, steps, index)` (the batched path reads
    /// them from tables holding `graded_step`'s values).
    #[inline(always)]
    pub(crate) fn next_with(&mut self, j: u64, graded: impl Fn(f64, bool, u64, u64) -> f64) -> f64 {
        let h = if !self.graded {
            self.dt
        } else if self.planned {
            if self.uniform_left > 0 {
                self.uniform_left -= 1;
                self.uniform_size
            } else if self.end_left > 0 {
                self.end_left -= 1;
                graded(self.end_region, true, self.end_steps, self.end_left)
            } else {
                // Past the planned rebound: grow until it is crossed.
                (2.0 * self.last).min(self.dt)
            }
        } else if j < self.onset_steps {
            graded(self.onset_region, false, self.onset_steps, j)
        } else {
            self.dt
        };
        self.last = h;
        h
    }
}

/// Step sizes of a contact under a law with a singular onset
/// ([`crate::contact::Onset::Singular`]), graded toward both ends (see the
/// module doc for the error analysis behind the constants).
#[derive(Debug, Clone, Copy)]
pub struct SingularMesh {
    dt: f64,
    /// First step at the onset, s.
    first: f64,
    /// Length s_g of the graded region at each end, s.
    region: f64,
    /// Its number of steps N = q s_g/Δt (continuous: the mesh index is
    /// recomputed from the estimated time left at the end).
    steps: f64,
    /// No step is shorter than this, s (far above the rounding of τ).
    floor: f64,
}

/// Exponent q of the power mesh s = s_g (j/N)^q at a singular end (q p ≥ 6
/// for the velocity exponent p = 5/4 of Tsuji and 3/2 of the viscoelastic law).
pub const SINGULAR_EXPONENT: i32 = 5;
/// Fraction of the contact-time estimate graded at each singular end.
pub const SINGULAR_FRACTION: f64 = 0.15;
/// Largest growth of one step over the previous at the onset, minus one.
pub const SINGULAR_GROWTH: f64 = 0.4;
/// First step at the onset as a fraction of Δt at η = 1/50; it scales as
/// Δt η³ (so its error, ∝ (H₀/T_c)^p, falls like η^(4p) ≥ η⁵).
pub const SINGULAR_FIRST: f64 = 1e-3;
/// Shortest step, as a fraction of the contact-time estimate.
const SINGULAR_FLOOR: f64 = 1e-9;

impl SingularMesh {
    /// Δt and the contact-time estimate T_c, s.
    pub fn new(dt: f64, contact_time: f64) -> Self {
        let eta = dt / contact_time;
        let floor = SINGULAR_FLOOR * contact_time;
        let region = SINGULAR_FRACTION * contact_time;
        Self {
            dt,
            first: (SINGULAR_FIRST * dt * (eta / 0.02).powi(3)).max(floor),
            region,
            steps: f64::from(SINGULAR_EXPONENT) * region / dt,
            floor,
        }
    }

    /// Size of the step that starts `tau` (s) after the onset:
    /// min(Δt, ρτ, Δt (τ/s_g)^(1 − 1/q)), the first one [`SINGULAR_FIRST`].
    #[inline]
    pub fn onset_step(&self, tau: f64) -> f64 {
        if tau <= 0.0 {
            return self.first;
        }
        if tau >= self.region {
            return self.dt;
        }
        let q = f64::from(SINGULAR_EXPONENT);
        let power = self.dt * (tau / self.region).powf(1.0 - 1.0 / q);
        power.min(SINGULAR_GROWTH * tau)
    }

    /// Size of the next step when the end is estimated `remaining` (s)
    /// away: to the next point s_g ((j − 1)/N)^q of the power mesh, j the
    /// continuous index of `remaining`; from j ≤ 2 on, one step of twice
    /// the time left, which crosses the end (located on its polynomial).
    #[inline]
    pub fn end_step(&self, remaining: f64) -> f64 {
        if remaining.is_nan() || remaining >= self.region {
            return self.dt;
        }
        let q = f64::from(SINGULAR_EXPONENT);
        let j = self.steps * (remaining.max(0.0) / self.region).powf(1.0 / q);
        if j <= 2.0 {
            return (2.0 * remaining).max(self.floor);
        }
        let next = self.region * ((j - 1.0) / self.steps).powi(SINGULAR_EXPONENT);
        (remaining - next).min(self.dt).max(self.floor)
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
    fn singular_onset_grows_by_at_most_1_4_and_reaches_dt_at_the_graded_fraction() {
        let (dt, t) = (1.0, 50.0);
        let mesh = SingularMesh::new(dt, t);
        let mut tau = 0.0;
        let mut last = mesh.onset_step(0.0);
        assert!((last - SINGULAR_FIRST * dt).abs() < 1e-18, "{last}");
        let mut n = 0;
        while last < dt {
            tau += last;
            let h = mesh.onset_step(tau);
            assert!(
                h <= (1.0 + SINGULAR_GROWTH) * last * (1.0 + 1e-12),
                "{tau}: {last} -> {h}"
            );
            last = h;
            n += 1;
        }
        // Δt once past s_g = 0.15 T_c = 7.5 Δt. The capped growth from
        // 1e−3 Δt meets the power mesh H = Δt (τ/s_g)^(4/5) at
        // τ = Δt (Δt/s_g)⁴/ρ⁵ = 0.031 Δt (10 steps of 1.4); from there the
        // power mesh has N (1 − (0.031/7.5)^(1/5)) = 25 of its N = 37.5 steps.
        assert!(tau >= SINGULAR_FRACTION * t - dt && tau < SINGULAR_FRACTION * t + dt);
        assert!((35..=40).contains(&n), "{n}");
        // The first step shrinks like Δt η³ (η = Δt/T_c).
        let finer = SingularMesh::new(0.5, t);
        assert!((finer.onset_step(0.0) / (0.5 * SINGULAR_FIRST / 8.0) - 1.0).abs() < 1e-12);
    }

    #[test]
    fn singular_end_follows_the_power_mesh_and_crosses_the_end() {
        // Exact time left: the steps walk the mesh s_g (j/N)^q down to
        // j = 2 and the last one crosses the end.
        let (dt, t) = (1.0, 50.0);
        let mesh = SingularMesh::new(dt, t);
        let end = 20.0;
        let (mut tau, mut n, mut last) = (0.0, 0, dt);
        while tau < end {
            let h = mesh.end_step(end - tau);
            assert!(h <= dt && h > 0.0);
            if tau + h < end {
                assert!(h <= last * (1.0 + 1e-12), "steps shrink toward the end");
            }
            last = h;
            tau += h;
            n += 1;
        }
        let region = SINGULAR_FRACTION * t;
        let big_n = f64::from(SINGULAR_EXPONENT) * region / dt;
        // The last step: twice the time left at j ≤ 2, s ≤ s_g (2/N)^q.
        assert!(last <= 2.0 * region * (2.0 / big_n).powi(SINGULAR_EXPONENT) * (1.0 + 1e-9));
        assert!(tau - end < last);
        // (end − s_g)/Δt uniform steps, then N − 1 graded ones and the last.
        let expected = (end - region) / dt + big_n - 1.0;
        assert!((n as f64 - expected).abs() <= 2.0, "{n} vs {expected}");
    }

    #[test]
    fn smooth_laws_get_uniform_steps() {
        let mut g = GradedSteps::new(0.5, 50.0, Grading::Uniform);
        g.plan_end(25.0, 24.9);
        assert!((0..10).all(|j| g.next(j) == 0.5));
    }
}
