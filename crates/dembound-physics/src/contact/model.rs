//! One contact, whole: the composer of the sub-models, in the spirit of
//! LAMMPS GRANULAR's `GranularModel::calculate_forces`
//! (`src/GRANULAR/granular_model.cpp`, 2022) and of LIGGGHTS's chain of
//! `surface_model_default`, `normal_model_*`, `tangential_model_history`
//! and `rolling_model_epsd2`. Every engine path that turns one
//! contact's geometry into forces (sphere pairs, boundary particles, walls;
//! the scalar loop and the batched one) calls the functions of this file,
//! so that this file alone says what a contact is.
//!
//! A contact between body 1 and body 2 (for a wall, body 2 is the wall):
//! - geometry ([`Geometry`]): overlap h (m, > 0 in contact), overlap rate ḣ
//!   (m/s, positive while approaching), unit normal n from body 1 to
//!   body 2;
//! - each side ([`Side`]): centre velocity v, spin ω, lever arm R (the
//!   undeformed radius: the contact point lies at R₁ n from body 1's
//!   centre and −R₂ n from body 2's) and inverse moment of inertia 1/I. A
//!   wall is side 2 with zero spin, zero lever arm, zero 1/I and its own
//!   surface velocity at the contact point ([`Side::wall`]);
//! - history ([`ContactState`]): the normal law's [`ContactHistory`], the
//!   tangential displacement δ (m) and, when some surface rolls, the
//!   rolling spring's torque M_r (N m), all seen from body 1.
//!
//! The stages, in the order of `calculate_forces`:
//! 1. normal ([`PairLaw::normal_stage`]): F_n = F_el(h, history) +
//!    F_damp(h, ḣ), clamped once to F_n ≥ 0 unless the model is attractive
//!    (LAMMPS `Fntot = Fne + Fdamp; if (limit_damping && Fntot < 0)
//!    Fntot = 0`), then the history advanced;
//! 2. slip ([`slip_velocity`]): v_c = v₁ − v₂ + (R₁ ω₁ + R₂ ω₂) × n, its
//!    tangential part v_t = v_c − (v_c·n) n (LAMMPS `vtr = vt − wr × nx`
//!    with LAMMPS's normal pointing the other way);
//! 3. tangential ([`ContactLaw::tangential_stage`]): the spring δ turned
//!    into the tangent plane, moved by v_t Δt, Coulomb-limited at μ |F_n|
//!    (`FrictionPair::tangential_force`); F_t acts on body 1;
//! 4. rolling ([`ContactLaw::rolling_stage`], only with a rolling spring):
//!    epsd2, M_r ← M_r − k_r ω_r Δt capped at μ_r R_eff |F_n|, ω_r the
//!    tangent-plane part of ω₁ − ω₂, I_eff = 1/(1/I₁ + 1/I₂)
//!    (`FrictionPair::rolling_torque`);
//! 5. sum ([`assemble`]): body 2 gets F_n n − F_t, body 1 the opposite;
//!    torques τ₁ = A₁ n × F_t + M_r and τ₂ = A₂ n × F_t − M_r, the arms
//!    A of [`ContactLaw::torque_arm`] ([`TorqueArm::arms`]): the radii R
//!    by default (the undeformed radius keeps the spin change of gross
//!    sliding at exactly (5/2) μ J_n/(m R)), or LAMMPS's R − h/2 for a
//!    sphere pair (`contact.torque_arm = "contact_point"`), or Yade's R −
//!    h/2 on every contact (`"overlap_middle"`, which also changes the
//!    slip of stage 2: [`TorqueArm::slip_sides`]).
//!
//! A frictionless contact is stage 1 alone ([`PairLaw::normal_stage`],
//! force F_n n on body 2): the same operations as the first stage of a
//! [`ContactLaw`]. Batched kernels run the stages over a batch of contacts
//! one stage at a time; they call these same inlined functions, so their
//! results are the scalar path's, bit for bit.

use super::tangential::FrictionPair;
pub use super::torque_arm::TorqueArm;
use super::{ContactHistory, PairLaw};

#[inline(always)]
fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// One body of a contact as the contact law reads it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Side {
    /// Velocity of the centre, m/s (a wall: its surface velocity at the
    /// contact point).
    pub velocity: [f64; 3],
    /// Angular velocity, rad/s (a wall: 0).
    pub spin: [f64; 3],
    /// Lever arm from the centre to the contact point, m: the undeformed
    /// radius (a wall: 0). The spin's arm in the slip velocity; the
    /// tangential torque's too unless [`ContactLaw::torque_arm`] moves it
    /// ([`TorqueArm::arms`]).
    pub arm: f64,
    /// 1/I, 1/(kg m²) (a wall or a fixed body: 0).
    pub inverse_inertia: f64,
}

impl Side {
    /// A wall whose surface moves at `velocity` (m/s) at the contact point:
    /// no spin, no lever arm, infinite inertia.
    #[inline(always)]
    pub const fn wall(velocity: [f64; 3]) -> Self {
        Self {
            velocity,
            spin: [0.0; 3],
            arm: 0.0,
            inverse_inertia: 0.0,
        }
    }
}

/// The geometry of one contact.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Geometry {
    /// Overlap h, m (> 0 in contact).
    pub overlap: f64,
    /// Overlap rate ḣ = (v₁ − v₂)·n, m/s, positive while approaching.
    pub overlap_rate: f64,
    /// Unit normal n from body 1 to body 2.
    pub normal: [f64; 3],
}

/// The history of one contact, seen from body 1, which
/// [`ContactLaw::calculate_forces`] advances.
#[derive(Debug)]
pub struct ContactState<'a> {
    /// The normal law's history.
    pub history: &'a mut ContactHistory,
    /// Tangential displacement δ of body 1's contact point relative to
    /// body 2's, m.
    pub tangential: &'a mut [f64; 3],
    /// The rolling spring's torque on body 1, N m; `None` when no surface
    /// of the scene rolls (the rolling stage is then skipped: no torque).
    pub rolling: Option<&'a mut [f64; 3]>,
}

/// What one contact exerts.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactForces {
    /// F_n, N, repulsive positive: body 2 gets F_n n, body 1 −F_n n.
    pub normal: f64,
    /// F_t on body 1, N (body 2 gets −F_t); in the tangent plane.
    pub tangential: [f64; 3],
    /// The moment of F_t about body 1's centre, A₁ n × F_t, N m (A₁ the
    /// lever arm, [`TorqueArm::arms`]).
    pub tangential_torque1: [f64; 3],
    /// The moment of −F_t about body 2's centre, A₂ n × F_t, N m.
    pub tangential_torque2: [f64; 3],
    /// The rolling torque M_r on body 1 (body 2 gets −M_r), N m; `None`
    /// without a rolling stage.
    pub rolling: Option<[f64; 3]>,
}

impl ContactForces {
    /// The force on body 2, F_n n − F_t (N), for the contact's normal `n`.
    #[inline(always)]
    pub fn on_body2(&self, n: [f64; 3]) -> [f64; 3] {
        let (f, ft) = (self.normal, self.tangential);
        [f * n[0] - ft[0], f * n[1] - ft[1], f * n[2] - ft[2]]
    }

    /// The force on body 1, −F_n n + F_t (N), for the contact's normal
    /// `n`. Equal to minus [`Self::on_body2`] (up to the sign of an exact
    /// zero); for a wall, whose outward normal is −n, this is the
    /// F_n (−n) + F_t a wall loop adds, with the same bits.
    #[inline(always)]
    pub fn on_body1(&self, n: [f64; 3]) -> [f64; 3] {
        let (f, ft) = (-self.normal, self.tangential);
        [f * n[0] + ft[0], f * n[1] + ft[1], f * n[2] + ft[2]]
    }

    /// Torque on body 1, R₁ n × F_t + M_r (N m). A loop that adds the two
    /// parts to its sum one after the other (a wall's) reads
    /// [`Self::tangential_torque1`] and [`Self::rolling`] instead: the
    /// same terms, another rounding.
    #[inline(always)]
    pub fn torque1(&self) -> [f64; 3] {
        let t = self.tangential_torque1;
        match self.rolling {
            Some(m) => [t[0] + m[0], t[1] + m[1], t[2] + m[2]],
            None => t,
        }
    }

    /// Torque on body 2, R₂ n × F_t − M_r (N m).
    #[inline(always)]
    pub fn torque2(&self) -> [f64; 3] {
        let t = self.tangential_torque2;
        match self.rolling {
            Some(m) => [t[0] - m[0], t[1] - m[1], t[2] - m[2]],
            None => t,
        }
    }
}

/// The normal and tangential laws of one pair of bodies (or body and
/// wall), resolved: LAMMPS's `GranularModel` for one pair of types.
/// `Copy`, small: a many-body loop may tabulate it per pair of classes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactLaw {
    /// Normal law + damping + clamp.
    pub law: PairLaw,
    /// Tangential spring with its damping and Coulomb limit, and the
    /// rolling spring.
    pub friction: FrictionPair,
    /// The lever arm of the tangential force's torque (stage 5).
    pub torque_arm: TorqueArm,
}

impl PairLaw {
    /// Stage 1, the normal force: F_n (N, repulsive positive) at overlap
    /// `overlap` > 0 (m) and rate `overlap_rate` (m/s) given `history`
    /// ([`PairLaw::force`]: law + damping, clamped once), then the
    /// history advanced to this state ([`PairLaw::update`]). A frictionless
    /// contact is this stage alone: body 2 gets F_n n.
    #[inline(always)]
    pub fn normal_stage(
        &self,
        overlap: f64,
        overlap_rate: f64,
        history: &mut ContactHistory,
    ) -> f64 {
        let f = self.force(overlap, overlap_rate, history);
        self.update(overlap, overlap_rate, history);
        f
    }
}

/// The overlap rate ḣ = (v₁ − v₂)·n (m/s) of centres moving at `v1` and
/// `v2` for the unit normal `n` from body 1 to body 2.
#[inline(always)]
pub fn overlap_rate(v1: [f64; 3], v2: [f64; 3], n: [f64; 3]) -> f64 {
    (v1[0] - v2[0]) * n[0] + (v1[1] - v2[1]) * n[1] + (v1[2] - v2[2]) * n[2]
}

/// Stage 2, the slip: the tangential part v_t (m/s) of the velocity of
/// body 1's contact point relative to body 2's, v_c = v₁ − v₂ + (R₁ ω₁ +
/// R₂ ω₂) × n, for the unit normal `n` from body 1 to body 2.
#[inline(always)]
pub fn slip_velocity(a: &Side, b: &Side, n: [f64; 3]) -> [f64; 3] {
    let arm = [
        a.arm * a.spin[0] + b.arm * b.spin[0],
        a.arm * a.spin[1] + b.arm * b.spin[1],
        a.arm * a.spin[2] + b.arm * b.spin[2],
    ];
    let spin = cross(arm, n);
    let v = [
        a.velocity[0] - b.velocity[0] + spin[0],
        a.velocity[1] - b.velocity[1] + spin[1],
        a.velocity[2] - b.velocity[2] + spin[2],
    ];
    let along = v[0] * n[0] + v[1] * n[1] + v[2] * n[2];
    [
        v[0] - along * n[0],
        v[1] - along * n[1],
        v[2] - along * n[2],
    ]
}

/// Effective rolling inertia 1/(1/I₁ + 1/I₂) (kg m²) from the sum of the
/// inverse inertias (0 when both bodies are fixed or walls).
#[inline(always)]
pub fn effective_inertia(inverse_inertia: f64) -> f64 {
    if inverse_inertia > 0.0 {
        1.0 / inverse_inertia
    } else {
        0.0
    }
}

/// Stage 5, the sum: the forces and torques of a contact of normal force
/// `normal` (N), tangential force `tangential` on body 1 (N) and rolling
/// torque `rolling` on body 1 (N m; `None`: no rolling stage), unit normal
/// `n`, lever arms `arm1` and `arm2` (m).
#[inline(always)]
pub fn assemble(
    normal: f64,
    tangential: [f64; 3],
    rolling: Option<[f64; 3]>,
    n: [f64; 3],
    arm1: f64,
    arm2: f64,
) -> ContactForces {
    let nxf = cross(n, tangential);
    ContactForces {
        normal,
        tangential,
        tangential_torque1: [arm1 * nxf[0], arm1 * nxf[1], arm1 * nxf[2]],
        tangential_torque2: [arm2 * nxf[0], arm2 * nxf[1], arm2 * nxf[2]],
        rolling,
    }
}

impl ContactLaw {
    /// The whole contact (LAMMPS `GranularModel::calculate_forces`): the
    /// normal, slip, tangential, rolling and sum stages in turn, after a
    /// time `dt` (s) since the last evaluation (0: evaluate without moving
    /// the springs). Advances `springs`. Callers evaluate it only in
    /// contact (h > 0); a contact that ends relaxes its springs to their
    /// defaults.
    #[inline(always)]
    pub fn calculate_forces(
        &self,
        g: &Geometry,
        a: &Side,
        b: &Side,
        state: ContactState,
        dt: f64,
    ) -> ContactForces {
        let stores_force = self.friction.tangential().stores_force();
        self.calculate_forces_known(stores_force, g, a, b, state, dt)
    }

    /// [`Self::calculate_forces`] with the kind of tangential spring known
    /// to the caller (`stores_force`: the law's
    /// [`TangentialPair::stores_force`](crate::contact::tangential::TangentialPair::stores_force),
    /// a constant in a kernel chosen once a run: see
    /// `FrictionPair::tangential_force_turned_known`).
    #[inline(always)]
    pub fn calculate_forces_known(
        &self,
        stores_force: bool,
        g: &Geometry,
        a: &Side,
        b: &Side,
        state: ContactState,
        dt: f64,
    ) -> ContactForces {
        let n = g.normal;
        let f = self
            .law
            .normal_stage(g.overlap, g.overlap_rate, state.history);
        let (slip_a, slip_b) = self.torque_arm.slip_sides(g.overlap, a, b);
        let vt = slip_velocity(&slip_a, &slip_b, n);
        let ft = self.friction.tangential_force_known(
            stores_force,
            g.overlap,
            f,
            n,
            vt,
            dt,
            state.tangential,
        );
        let rolling = state
            .rolling
            .map(|m| self.rolling_stage(g.overlap, f, n, a, b, dt, m));
        let (arm1, arm2) = self.torque_arm.arms(g.overlap, a.arm, b.arm);
        assemble(f, ft, rolling, n, arm1, arm2)
    }

    /// The contact's forces at its present state, nothing advanced (an
    /// observation between steps): the stages of [`Self::calculate_forces`]
    /// with the normal force read from `history` without updating it
    /// ([`PairLaw::force`]) and the springs, copied, taken through a step
    /// of zero length (turned into the present tangent plane and capped at
    /// the present μ |F_n|, their dashpots at the present slip). `rolling`:
    /// the rolling spring, `None` to skip the rolling stage.
    #[inline]
    pub fn observe(
        &self,
        g: &Geometry,
        a: &Side,
        b: &Side,
        history: &ContactHistory,
        tangential: [f64; 3],
        rolling: Option<[f64; 3]>,
    ) -> ContactForces {
        let n = g.normal;
        let f = self.law.force(g.overlap, g.overlap_rate, history);
        let (slip_a, slip_b) = self.torque_arm.slip_sides(g.overlap, a, b);
        let vt = slip_velocity(&slip_a, &slip_b, n);
        let mut shear = tangential;
        let ft = self.tangential_stage(g.overlap, f, n, vt, 0.0, &mut shear);
        let rolling = rolling.map(|mut m| self.rolling_stage(g.overlap, f, n, a, b, 0.0, &mut m));
        let (arm1, arm2) = self.torque_arm.arms(g.overlap, a.arm, b.arm);
        assemble(f, ft, rolling, n, arm1, arm2)
    }

    /// The contact's forces as the last step applied them, from the
    /// springs it stored (`tangential`, `rolling`: `None` skips the
    /// rolling stage): [`Self::observe`], except that a spring the step cut
    /// back to its limit is taken as sliding, as the step took it
    /// (`FrictionPair::applied_tangential_force`). For the dissipation
    /// summed contact by contact, whose tangential work must be the work
    /// of the applied forces.
    #[inline]
    pub fn observe_applied(
        &self,
        g: &Geometry,
        a: &Side,
        b: &Side,
        history: &ContactHistory,
        tangential: [f64; 3],
        rolling: Option<[f64; 3]>,
    ) -> ContactForces {
        let n = g.normal;
        let f = self.law.force(g.overlap, g.overlap_rate, history);
        let (slip_a, slip_b) = self.torque_arm.slip_sides(g.overlap, a, b);
        let vt = slip_velocity(&slip_a, &slip_b, n);
        let ft = self
            .friction
            .applied_tangential_force(g.overlap, f, n, vt, tangential);
        let rolling = rolling.map(|m| {
            let (w1, w2) = (a.spin, b.spin);
            self.friction.applied_rolling_torque(
                &self.law,
                g.overlap,
                f,
                n,
                [w1[0] - w2[0], w1[1] - w2[1], w1[2] - w2[2]],
                effective_inertia(a.inverse_inertia + b.inverse_inertia),
                m,
            )
        });
        let (arm1, arm2) = self.torque_arm.arms(g.overlap, a.arm, b.arm);
        assemble(f, ft, rolling, n, arm1, arm2)
    }

    /// Stage 3, the tangential force on body 1 (N) at overlap `overlap`
    /// (m) with normal force `normal_force` (N), unit normal `n` and slip
    /// `slip` ([`slip_velocity`], m/s), after `dt` s; moves the
    /// displacement `shear` (m). See `FrictionPair::tangential_force`.
    #[inline(always)]
    pub fn tangential_stage(
        &self,
        overlap: f64,
        normal_force: f64,
        n: [f64; 3],
        slip: [f64; 3],
        dt: f64,
        shear: &mut [f64; 3],
    ) -> [f64; 3] {
        self.friction
            .tangential_force(overlap, normal_force, n, slip, dt, shear)
    }

    /// Stage 4, the rolling torque on body 1 (N m) at overlap `overlap`
    /// (m) with normal force `normal_force` (N) and unit normal `n`, for
    /// the sides' relative spin ω₁ − ω₂ and effective inertia, after `dt`
    /// s; moves the rolling spring `spring` (N m). See
    /// `FrictionPair::rolling_torque`.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    pub fn rolling_stage(
        &self,
        overlap: f64,
        normal_force: f64,
        n: [f64; 3],
        a: &Side,
        b: &Side,
        dt: f64,
        spring: &mut [f64; 3],
    ) -> [f64; 3] {
        let (w1, w2) = (a.spin, b.spin);
        self.friction.rolling_torque(
            &self.law,
            overlap,
            normal_force,
            n,
            [w1[0] - w2[0], w1[1] - w2[1], w1[2] - w2[2]],
            effective_inertia(a.inverse_inertia + b.inverse_inertia),
            dt,
            spring,
        )
    }

    /// Energy held by the contact's tangential and rolling springs at
    /// overlap `overlap` (m), J (`FrictionPair::spring_energy`).
    #[inline]
    pub fn spring_energy(&self, overlap: f64, shear: &[f64; 3], rolling: &[f64; 3]) -> f64 {
        self.friction
            .spring_energy(&self.law, overlap, shear, rolling)
    }

    /// [`Self::spring_energy`] with the kind of tangential spring known to
    /// the caller (`stores_force`, as in [`Self::calculate_forces_known`]).
    #[inline]
    pub fn spring_energy_known(
        &self,
        stores_force: bool,
        overlap: f64,
        shear: &[f64; 3],
        rolling: &[f64; 3],
    ) -> f64 {
        self.friction
            .spring_energy_known(stores_force, &self.law, overlap, shear, rolling)
    }
}

#[cfg(test)]
#[path = "model_tests.rs"]
mod tests;
