//! The collision log: one row per completed contact, its onset and end
//! located inside the step.
//!
//! Each tracked pair (or sphere–wall couple) keeps the overlap h and its
//! rate ḣ at the end of the previous step. Onset is extrapolated linearly
//! from the last contact-free state, the end back from the first
//! contact-free one (only contact-free forces act there; error O(a τ) in
//! the speed, a the contact-free relative acceleration, τ < Δt; an
//! interpolant across the step would straddle the kink of the force). The
//! largest overlap is the maximum of the cubic Hermite interpolant of
//! (h, ḣ) at both ends of the step where ḣ changes sign (error O(Δt⁴));
//! the discrete maximum alone would be off by ~(π η)²/8 (2·10⁻³ at
//! η = 1/50).

use serde::{Deserialize, Serialize};

/// The other side of a collision.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum Partner {
    /// A sphere, by input index.
    Body(usize),
    /// A plane wall, by wall index in file order.
    Wall(usize),
    /// One boundary particle of a boundary-particle wall: the wall's
    /// index in file order and the particle's input index.
    BoundaryParticle { wall: usize, body: usize },
}

impl Partner {
    /// The wall (file order) this partner belongs to, if any.
    pub fn wall(&self) -> Option<usize> {
        match *self {
            Partner::Body(_) => None,
            Partner::Wall(w) | Partner::BoundaryParticle { wall: w, .. } => Some(w),
        }
    }
}

/// One completed contact.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Collision {
    /// Sphere, input index (the smaller one of a sphere pair; the free
    /// sphere against a boundary particle).
    pub i: usize,
    pub j: Partner,
    /// Onset, s.
    pub t_start: f64,
    /// End (overlap back to 0), s.
    pub t_end: f64,
    /// t_end − t_start, s.
    pub duration: f64,
    /// Largest overlap, m.
    pub max_overlap: f64,
    /// Largest normal force, N.
    pub max_normal_force: f64,
    /// Normal approach speed at onset, m/s (positive).
    pub impact_normal_velocity: f64,
    /// Normal separation speed at the end, m/s (positive).
    pub rebound_normal_velocity: f64,
    /// Tangential speed of the centres (i relative to j, or to the wall)
    /// at the last state before contact, m/s (≥ 0; issue 13).
    #[serde(default)]
    pub impact_tangential_velocity: f64,
    /// Tangential velocity of the centres at the first state after the
    /// contact, along the impact's tangential direction, m/s (negative:
    /// reversed; the magnitude when the impact had none).
    #[serde(default)]
    pub rebound_tangential_velocity: f64,
    /// Angular velocity of sphere i before and after the contact, rad/s.
    #[serde(default)]
    pub impact_spin_i: [f64; 3],
    #[serde(default)]
    pub rebound_spin_i: [f64; 3],
    /// Angular velocity of sphere j (0 for a wall) before and after, rad/s.
    #[serde(default)]
    pub impact_spin_j: [f64; 3],
    #[serde(default)]
    pub rebound_spin_j: [f64; 3],
    /// Against a triangle-mesh wall: the triangle (cleaned-mesh id) the
    /// contact was on, named when the contact ended, from the sphere's
    /// first contact-free position, by the rule of the per-triangle loads
    /// (`walls::mesh::loads`: the triangle of the contact's patch under
    /// the centre, or holding the edge or vertex it touched). `None` for
    /// every other partner (and absent from a saved log then, so logs
    /// without mesh walls keep their bytes; issue 26).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub triangle: Option<u32>,
}

impl Collision {
    /// The log's row of contact `c` of sphere `i` with `j`, from the
    /// couple's motion before and after it; `spins` gives a motion's
    /// (sphere i's, partner j's) angular velocity as the row names them.
    pub fn completed(
        i: usize,
        j: Partner,
        c: &Completed,
        before: &Motion,
        after: &Motion,
        spins: impl Fn(&Motion) -> [[f64; 3]; 2],
        triangle: Option<u32>,
    ) -> Self {
        let (vt_in, vt_out) = Motion::tangential_pair(before, after);
        let ([impact_spin_i, impact_spin_j], [rebound_spin_i, rebound_spin_j]) =
            (spins(before), spins(after));
        Collision {
            i,
            j,
            t_start: c.t_start,
            t_end: c.t_end,
            duration: c.t_end - c.t_start,
            max_overlap: c.max_overlap,
            max_normal_force: c.max_force,
            impact_normal_velocity: c.impact,
            rebound_normal_velocity: c.rebound,
            impact_tangential_velocity: vt_in,
            rebound_tangential_velocity: vt_out,
            impact_spin_i,
            rebound_spin_i,
            impact_spin_j,
            rebound_spin_j,
            triangle,
        }
    }
}

/// The tangential motion of a couple at one instant (collision log).
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct Motion {
    /// Tangential part of v_i − v_j (centres), m/s.
    pub tangential: [f64; 3],
    /// ω_i, rad/s.
    pub spin_i: [f64; 3],
    /// ω_j, rad/s.
    pub spin_j: [f64; 3],
}

impl Motion {
    /// (impact tangential speed, rebound tangential velocity along the
    /// impact's direction) of a contact from `impact` to `rebound`, m/s.
    pub fn tangential_pair(impact: &Motion, rebound: &Motion) -> (f64, f64) {
        let a = impact.tangential;
        let b = rebound.tangential;
        let m = (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
        if m > 0.0 {
            (m, (a[0] * b[0] + a[1] * b[1] + a[2] * b[2]) / m)
        } else {
            (0.0, (b[0] * b[0] + b[1] * b[1] + b[2] * b[2]).sqrt())
        }
    }
}

/// What a tracked couple remembers between steps.
///
/// Laid out in declaration order on one cache line per couple's step: a
/// contact in progress reads and writes only the first eight fields (64
/// B: the flags, the overlap and rate, the onset, the maxima), the two
/// motions (144 B) only at an onset, an end or a step apart
/// ([`Self::advance_listed`]). A log of 27,000 contacts in progress thus
/// reads 1.7 MB a step rather than 5.4 MB (the stage's first loads of
/// each track were 44 % of its time).
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
#[repr(C, align(64))]
pub struct Track {
    known: bool,
    overlap: f64,
    rate: f64,
    in_contact: bool,
    t_start: f64,
    impact: f64,
    max_overlap: f64,
    max_force: f64,
    /// The couple's motion at the previous step (issue 13).
    #[serde(default)]
    last: Motion,
    /// Its motion at the last state before the current contact.
    #[serde(default)]
    impact_motion: Motion,
}

/// A completed contact, before it is named.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Completed {
    pub t_start: f64,
    pub t_end: f64,
    pub max_overlap: f64,
    pub max_force: f64,
    pub impact: f64,
    pub rebound: f64,
}

/// Cubic Hermite interpolant on s ∈ [0, 1] of a step of length dt.
struct Hermite {
    p0: f64,
    m0: f64,
    p1: f64,
    m1: f64,
}

impl Hermite {
    fn new(h0: f64, r0: f64, h1: f64, r1: f64, dt: f64) -> Self {
        Self {
            p0: h0,
            m0: r0 * dt,
            p1: h1,
            m1: r1 * dt,
        }
    }

    fn value(&self, s: f64) -> f64 {
        let s2 = s * s;
        let s3 = s2 * s;
        (2.0 * s3 - 3.0 * s2 + 1.0) * self.p0
            + (s3 - 2.0 * s2 + s) * self.m0
            + (-2.0 * s3 + 3.0 * s2) * self.p1
            + (s3 - s2) * self.m1
    }

    /// dH/ds.
    fn slope(&self, s: f64) -> f64 {
        let s2 = s * s;
        (6.0 * s2 - 6.0 * s) * self.p0
            + (3.0 * s2 - 4.0 * s + 1.0) * self.m0
            + (-6.0 * s2 + 6.0 * s) * self.p1
            + (3.0 * s2 - 2.0 * s) * self.m1
    }

    /// A root of `f` in [0, 1] given f(0) and f(1) of opposite signs (or
    /// f(1) = 0): bisection to machine precision.
    fn bisect(f: impl Fn(f64) -> f64) -> f64 {
        let (mut a, mut b) = (0.0f64, 1.0f64);
        let fa_negative = f(0.0) < 0.0;
        for _ in 0..64 {
            let m = 0.5 * (a + b);
            if m <= a || m >= b {
                break;
            }
            if (f(m) < 0.0) == fa_negative {
                a = m;
            } else {
                b = m;
            }
        }
        0.5 * (a + b)
    }
}

impl Track {
    /// The names of [`Self::values`]' entries, in order (the checkpoint's
    /// columns).
    pub const VALUE_NAMES: [&'static str; 24] = [
        "overlap",
        "rate",
        "t_start",
        "impact",
        "max_overlap",
        "max_force",
        "last_tangential_x",
        "last_tangential_y",
        "last_tangential_z",
        "last_spin_i_x",
        "last_spin_i_y",
        "last_spin_i_z",
        "last_spin_j_x",
        "last_spin_j_y",
        "last_spin_j_z",
        "impact_tangential_x",
        "impact_tangential_y",
        "impact_tangential_z",
        "impact_spin_i_x",
        "impact_spin_i_y",
        "impact_spin_i_z",
        "impact_spin_j_x",
        "impact_spin_j_y",
        "impact_spin_j_z",
    ];
    /// [`Self::flags`]' bit: the track has a previous step.
    pub const KNOWN: u8 = 1;
    /// [`Self::flags`]' bit: the couple is in contact.
    pub const IN_CONTACT: u8 = 2;

    /// The two flags as bits ([`Self::KNOWN`], [`Self::IN_CONTACT`]).
    pub fn flags(&self) -> u8 {
        u8::from(self.known) * Self::KNOWN + u8::from(self.in_contact) * Self::IN_CONTACT
    }

    /// The track's f64 number `k` of [`Self::VALUE_NAMES`] (k < 24).
    pub fn value(&self, k: usize) -> f64 {
        let motion = |m: &Motion, k: usize| match k / 3 {
            0 => m.tangential[k % 3],
            1 => m.spin_i[k % 3],
            _ => m.spin_j[k % 3],
        };
        match k {
            0 => self.overlap,
            1 => self.rate,
            2 => self.t_start,
            3 => self.impact,
            4 => self.max_overlap,
            5 => self.max_force,
            6..=14 => motion(&self.last, k - 6),
            _ => motion(&self.impact_motion, k - 15),
        }
    }

    /// The track of [`Self::flags`] and the values of [`Self::value`]
    /// (other flag bits ignored).
    pub fn from_parts(flags: u8, v: &[f64; 24]) -> Self {
        let triple = |k: usize| [v[k], v[k + 1], v[k + 2]];
        let motion = |k: usize| Motion {
            tangential: triple(k),
            spin_i: triple(k + 3),
            spin_j: triple(k + 6),
        };
        Self {
            known: flags & Self::KNOWN != 0,
            overlap: v[0],
            rate: v[1],
            in_contact: flags & Self::IN_CONTACT != 0,
            t_start: v[2],
            impact: v[3],
            max_overlap: v[4],
            max_force: v[5],
            last: motion(6),
            impact_motion: motion(15),
        }
    }

    /// The couple has a previous step.
    pub fn is_known(&self) -> bool {
        self.known
    }

    /// A contact has started and not ended.
    pub fn in_contact(&self) -> bool {
        self.in_contact
    }

    /// The step ending at overlap `h` leaves this couple apart and out of
    /// contact (h ≤ 0 or not a number, no contact open): nothing can be
    /// logged, and [`Self::advance_apart`] does all that
    /// [`Self::advance_with_motion`] would.
    #[inline(always)]
    pub fn stays_apart(&self, h: f64) -> bool {
        Self::apart_after(self.in_contact, h)
    }

    /// [`Self::stays_apart`] for a track whose in-contact flag is
    /// `in_contact` (read from a dense copy without loading the track).
    #[inline(always)]
    pub fn apart_after(in_contact: bool, h: f64) -> bool {
        !in_contact && (h <= 0.0 || h.is_nan())
    }

    /// [`Self::advance_with_motion`] for a step after which the couple
    /// [`Self::stays_apart`]: keeps what a later onset reads (the overlap,
    /// its rate and the motion at this step), without the normal force or
    /// the interpolant, which only a contact uses.
    #[inline(always)]
    pub fn advance_apart(&mut self, h: f64, rate: f64, motion: Motion) {
        debug_assert!(self.stays_apart(h));
        self.known = true;
        self.overlap = h;
        self.rate = rate;
        self.last = motion;
    }

    /// The couple's motion at its last step (a contact in progress stepped
    /// by [`Self::advance_listed`] leaves it to the caller: the log's copy
    /// of that step gives it when the track is read).
    pub fn set_last(&mut self, motion: Motion) {
        self.last = motion;
    }

    /// [`Self::advance_with_motion`] with the motion evaluated only where it
    /// is used (an onset not preceded by a known step, an end, a step that
    /// leaves the couple out of contact), and not stored while the contact
    /// goes on: then `last` is stale, and whoever reads the track must set
    /// it ([`Self::set_last`]) to the motion at the step (what
    /// [`Self::advance_with_motion`] would have stored). The same values
    /// otherwise, bit for bit.
    #[inline(always)]
    pub fn advance_listed(
        &mut self,
        t: f64,
        dt: f64,
        h: f64,
        rate: f64,
        motion: impl FnOnce() -> Motion,
        force: impl Fn(f64, f64) -> f64,
    ) -> Option<(Completed, Motion, Motion)> {
        let (was_known, was_in) = (self.known, self.in_contact);
        let done = self.advance(t, dt, h, rate, force);
        if self.in_contact {
            // A contact in progress completes nothing (see `advance`).
            if !was_in {
                self.impact_motion = if was_known { self.last } else { motion() };
            }
            return None;
        }
        let motion = motion();
        self.last = motion;
        done.map(|c| (c, self.impact_motion, motion))
    }

    /// [`Self::advance`] that also keeps the tangential motion: returns
    /// the completed contact with the motion before and after it
    /// ([`Self::advance_listed`] with the motion stored every step).
    pub fn advance_with_motion(
        &mut self,
        t: f64,
        dt: f64,
        h: f64,
        rate: f64,
        motion: Motion,
        force: impl Fn(f64, f64) -> f64,
    ) -> Option<(Completed, Motion, Motion)> {
        let done = self.advance_listed(t, dt, h, rate, || motion, force);
        self.last = motion;
        done
    }

    /// Advances over the step that ends at time `t` (length `dt`) with
    /// overlap `h` (m, negative apart) and rate `rate` (m/s, approach
    /// positive); `force(h, rate)` is the normal force. Returns the
    /// contact if it ended in this step.
    pub fn advance(
        &mut self,
        t: f64,
        dt: f64,
        h: f64,
        rate: f64,
        force: impl Fn(f64, f64) -> f64,
    ) -> Option<Completed> {
        let mut done = None;
        let herm = Hermite::new(self.overlap, self.rate, h, rate, dt);
        let t0 = t - dt;
        if !self.in_contact && h > 0.0 {
            // Onset: extrapolated from the last state before contact,
            // where only the contact-free forces act (a kink in the force
            // at onset would spoil an interpolant across the step): error
            // O(a τ) in the speed, a the contact-free relative
            // acceleration, τ < Δt.
            if self.known && self.overlap <= 0.0 && self.rate > 0.0 {
                let ahead = (-self.overlap / self.rate).min(dt);
                self.t_start = t0 + ahead;
                self.impact = self.rate;
            } else {
                // Newly listed and already touching: from the current state.
                let back = if rate > 0.0 { (h / rate).min(dt) } else { 0.0 };
                self.t_start = t - back;
                self.impact = rate;
            }
            self.in_contact = true;
            self.max_overlap = h;
            self.max_force = force(h, rate).max(0.0);
            self.known = true;
            self.overlap = h;
            self.rate = rate;
            return None;
        }
        if self.in_contact {
            // A maximum of h inside the step.
            if self.known && self.rate > 0.0 && rate <= 0.0 {
                let s = Hermite::bisect(|s| herm.slope(s));
                let hm = herm.value(s);
                if hm > self.max_overlap {
                    self.max_overlap = hm;
                }
                self.max_force = self.max_force.max(force(hm, 0.0));
            }
            if h > 0.0 {
                self.max_overlap = self.max_overlap.max(h);
                self.max_force = self.max_force.max(force(h, rate));
            } else {
                // End: extrapolated back from the first state after it,
                // contact-free for the same reason.
                let (t_end, rebound) = if rate < 0.0 {
                    (t - (h / rate).min(dt), -rate)
                } else {
                    (t, -rate)
                };
                done = Some(Completed {
                    t_start: self.t_start,
                    t_end,
                    max_overlap: self.max_overlap,
                    max_force: self.max_force,
                    impact: self.impact,
                    rebound,
                });
                self.in_contact = false;
            }
        }
        self.known = true;
        self.overlap = h;
        self.rate = rate;
        done
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// What the log stage does with one couple at one step: the apart
    /// path when [`Track::stays_apart`], else the full one.
    fn observe_fast(
        track: &mut Track,
        t: f64,
        dt: f64,
        h: f64,
        rate: f64,
        motion: Motion,
        force: impl Fn(f64, f64) -> f64,
    ) -> Option<(Completed, Motion, Motion)> {
        if track.stays_apart(h) {
            track.advance_apart(h, rate, motion);
            return None;
        }
        track.advance_with_motion(t, dt, h, rate, motion, force)
    }

    /// 200 couples of 400 steps each that approach, touch for a few steps
    /// and part again, many times (xorshift from `seed`): one in ten listed
    /// while already touching, overlaps of exactly ±0 and a NaN now and
    /// then. `visit(couple, step, t, h, rate, motion)` at every step.
    fn swinging_couples(seed: u64, mut visit: impl FnMut(usize, usize, f64, f64, f64, Motion)) {
        let mut seed = seed;
        let mut next = move || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        let dt = DT;
        for couple in 0..200 {
            let mut h = if couple % 10 == 0 {
                2.0e-6
            } else {
                -3.0e-6 * next()
            };
            let mut t = 0.0;
            for step in 0..400 {
                t += dt;
                // A slow swing across contact with a jitter.
                let rate =
                    0.02 * (step as f64 * 0.05 + couple as f64).sin() + 2.0e-3 * (next() - 0.5);
                h += rate * dt;
                let mut h_seen = h;
                match (step * 7 + couple) % 97 {
                    0 => h_seen = 0.0,
                    1 => h_seen = -0.0,
                    2 => h_seen = f64::NAN,
                    _ => {}
                }
                let motion = Motion {
                    tangential: [next() - 0.5, next() - 0.5, next() - 0.5],
                    spin_i: [next(), 0.0, -next()],
                    spin_j: [0.0, next(), 1.0],
                };
                visit(couple, step, t, h_seen, rate, motion);
            }
        }
    }

    /// The step of [`swinging_couples`], s.
    const DT: f64 = 1.0e-6;

    /// The normal force of [`swinging_couples`]' tests, N.
    fn force(h: f64, r: f64) -> f64 {
        3.0e5 * h.max(0.0).powf(1.5) + 20.0 * r
    }

    #[test]
    fn apart_path_keeps_the_full_paths_state_and_log() {
        // The reference is the path every couple took before the apart
        // one existed: `advance_with_motion` at every step. On
        // `swinging_couples`, after every step the whole track (what a
        // later onset or a checkpoint reads) and what was logged must be
        // the same to the bit (compared as their Debug text, so that NaN
        // equals NaN). No tolerance: the two paths must do the same
        // arithmetic.
        let (mut contacts, mut onsets_known) = (0, 0);
        let (mut fast, mut reference) = (Track::default(), Track::default());
        swinging_couples(0x2545_f491_4f6c_dd1d, |couple, step, t, h, rate, motion| {
            if step == 0 {
                (fast, reference) = (Track::default(), Track::default());
            }
            let was_known = reference.is_known();
            let a = observe_fast(&mut fast, t, DT, h, rate, motion, force);
            let b = reference.advance_with_motion(t, DT, h, rate, motion, force);
            assert_eq!(
                format!("{a:?}"),
                format!("{b:?}"),
                "couple {couple} step {step}"
            );
            assert_eq!(
                format!("{fast:?}"),
                format!("{reference:?}"),
                "couple {couple} step {step}"
            );
            contacts += b.is_some() as usize;
            if reference.in_contact() && reference.t_start > t - DT && was_known {
                onsets_known += 1;
            }
        });
        // The sequences did exercise both paths: many completed contacts
        // and many onsets that read the state the apart path stored.
        assert!(
            contacts > 200 && onsets_known > 200,
            "{contacts} {onsets_known}"
        );
    }

    #[test]
    fn listed_path_logs_what_the_full_path_logs() {
        // The reference is `advance_with_motion` (the motion stored at
        // every step); `advance_listed` evaluates the motion only where it
        // is used and leaves `last` stale while a contact goes on, for the
        // reader to set from the step's state (`set_last`). On
        // `swinging_couples` the rows must be the same to the bit and so
        // must the whole track once `last` is set as a reader sets it. No
        // tolerance: the same arithmetic.
        let (mut rows, mut stale_steps, mut evaluated) = (0, 0, 0usize);
        let (mut listed, mut reference) = (Track::default(), Track::default());
        swinging_couples(0x1234_5678_9abc_def1, |couple, step, t, h, rate, motion| {
            if step == 0 {
                (listed, reference) = (Track::default(), Track::default());
            }
            let b = reference.advance_with_motion(t, DT, h, rate, motion, force);
            let once = || {
                evaluated += 1;
                motion
            };
            let a = listed.advance_listed(t, DT, h, rate, once, force);
            assert_eq!(
                format!("{a:?}"),
                format!("{b:?}"),
                "couple {couple} step {step}"
            );
            let mut read = listed;
            if listed.in_contact() {
                stale_steps += 1;
                read.set_last(motion);
            }
            assert_eq!(
                format!("{read:?}"),
                format!("{reference:?}"),
                "{couple} {step}"
            );
            rows += b.is_some() as usize;
        });
        // Many rows and many steps in contact (where the motion is not
        // evaluated: fewer evaluations than steps).
        assert!(rows > 200 && stale_steps > 5000, "{rows} {stale_steps}");
        assert!(evaluated + stale_steps / 2 < 200 * 400, "{evaluated}");
    }

    #[test]
    fn hermite_locates_a_parabola_exactly() {
        // In contact h(t) = v t − ½ a t² (a cubic interpolant is exact on
        // it), free flight at speed v outside: onset at 0, maximum
        // v²/(2a) at v/a, end at 2v/a with speed v; all exact.
        let (v, a, dt) = (0.3, 1.0e5, 1.0e-7);
        let end = 2.0 * v / a;
        let h = |t: f64| {
            if t < 0.0 {
                v * t
            } else if t > end {
                -v * (t - end)
            } else {
                v * t - 0.5 * a * t * t
            }
        };
        let r = |t: f64| {
            if t < 0.0 {
                v
            } else if t > end {
                -v
            } else {
                v - a * t
            }
        };
        let start = -0.37 * dt;
        let mut track = Track::default();
        let mut t = start;
        let mut out = None;
        while out.is_none() {
            out = track.advance(t, dt, h(t), r(t), |h, _| h);
            t += dt;
        }
        let c = out.unwrap();
        assert!(c.t_start.abs() < 1e-18, "{}", c.t_start);
        assert!((c.t_end / (2.0 * v / a) - 1.0).abs() < 1e-12);
        assert!((c.max_overlap / (v * v / (2.0 * a)) - 1.0).abs() < 1e-12);
        assert!((c.impact / v - 1.0).abs() < 1e-12);
        assert!((c.rebound / v - 1.0).abs() < 1e-12);
    }
}
