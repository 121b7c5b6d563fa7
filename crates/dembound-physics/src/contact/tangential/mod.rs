//! Tangential (friction) sub-models, after LAMMPS GRANULAR's
//! `gran_sub_mod_tangential.cpp`: each a small `Copy` type giving the
//! tangential stiffness k_t of a pair ([`TangentialSubModel`]), one
//! registry row each ([`TANGENTIAL_MODELS`]); the spring's history, its
//! rotation into the current tangent plane, the tangential damping and the
//! Coulomb limit are common to all and live in [`FrictionPair`], as in
//! `GranularModel::calculate_forces`.
//!
//! Per evaluation (LAMMPS `linear_history`/`mindlin`, LIGGGHTS
//! `tangential_model_history`):
//! 1. the stored displacement δ is projected onto the current tangent
//!    plane and rescaled to its old length (the contact frame rotates;
//!    LAMMPS's), or under `contact.spring_rotation = "project"` only
//!    projected (LIGGGHTS 3.8's; [`rotation`]);
//! 2. δ ← δ + v_t Δt (v_t the tangential relative velocity of the contact
//!    points);
//! 3. sliding if the spring alone exceeds the Coulomb limit, k_t |δ| >
//!    μ |F_n|: δ is cut back to length μ |F_n|/k_t and F_t = −k_t δ
//!    (magnitude exactly μ |F_n|, no damping; LIGGGHTS
//!    `tangential_model_history`);
//! 4. else sticking: F_t = −k_t δ − η_t v_t, capped at μ |F_n| in
//!    magnitude (the spring kept). LAMMPS instead caps the total and
//!    solves the spring back from it, δ = −(F_t + η_t v_t)/k_t, which can
//!    turn δ against the slip near onset (damping above the tiny limit)
//!    and make the next force push along the slip: with this order a
//!    sliding contact transmits exactly μ |F_n| at every step.
//!
//! Tangential damping from the same restitution as the normal: with η_n(h)
//! the normal damping coefficient (N s/m, the damping force per unit
//! overlap rate) and S_n(h) = dF/dh the normal law's tangent stiffness,
//! η_t = η_n √(k_t/S_n): the tangential spring gets the damping ratio of the
//! normal one. For Hertz with Tsuji damping this is LIGGGHTS's
//! γ_t = 2 √(5/6) β √(S_t m*) exactly (γ_n = 2 √(5/6) β √(S_n m*)); for the
//! linear spring–dashpot it is η_t = 2 ξ √(k_t m*). A scene may turn the
//! dashpot off (`contact.tangential_damping = false`,
//! [`FrictionPair::without_tangential_damping`]; LIGGGHTS's
//! `tangential_damping off`): a sticking contact's force is then the
//! spring's alone, which step 3 keeps within μ |F_n|, so the cap of step 4
//! never acts and the law is the same in both codes.
//!
//! `mindlin_force` ([`mindlin_force`], LAMMPS `mindlin/force`) stores the
//! spring's force instead and adds −k_t(h) v_t Δt to it in step 2 (an
//! incremental spring); steps 1, 3 and 4 act on that force as on −k_t δ.
//!
//! Rolling resistance is its own sub-model ([`super::rolling`]).
//!
//! Sign conventions: n is the unit normal from body 1 to body 2; v_t is the
//! velocity of body 1's contact point relative to body 2's, tangential part;
//! the returned force acts on body 1 (body 2 gets minus it).

use super::registry::Family;
use super::PairLaw;
use crate::error::PhysicsError;
use crate::material::{Material, PairProperties};

pub mod linear;
pub mod mindlin;
pub mod mindlin_force;
pub mod rotation;

pub use rotation::{project_spring, SpringRotation};

/// What a tangential sub-model is built from for one pair.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TangentialSetup {
    /// The pair's effective radius, modulus (4/3 included) and mass.
    pub pair: PairProperties,
    /// G* = 1/((2 − ν₁)/G₁ + (2 − ν₂)/G₂), Pa ([`effective_shear_modulus`]).
    pub shear_modulus: f64,
}

/// A tangential model resolved for one pair: its stiffness.
pub trait TangentialSubModel: Copy + std::fmt::Debug {
    /// The model for one pair.
    fn new(setup: &TangentialSetup) -> Self;

    /// k_t at overlap h > 0 (m), N/m.
    fn stiffness(&self, overlap: f64) -> f64;

    /// Whether the contact's tangential history is the spring's force F_s
    /// (N), incremented by −k_t(h) v_t Δt each step (LAMMPS
    /// `mindlin/force`), rather than its displacement δ (m), whose force is
    /// −k_t(h) δ.
    const STORES_FORCE: bool = false;
}

/// A registry row of a tangential model.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TangentialRow {
    /// Configuration name (`contact.tangential = "…"`).
    pub name: &'static str,
    /// The stiffness law, one line.
    pub formula: &'static str,
}

macro_rules! tangential_registry {
    ($( $(#[$doc:meta])* $V:ident => $T:ty = $row:expr; )+) => {
        /// Which tangential spring.
        #[derive(Debug, Clone, Copy, PartialEq, Eq)]
        pub enum TangentialKind {
            $( $(#[$doc])* $V, )+
        }

        /// A tangential spring resolved for one pair.
        #[derive(Debug, Clone, Copy, PartialEq)]
        pub enum TangentialPair {
            $( #[allow(missing_docs)] $V($T), )+
        }

        #[allow(non_upper_case_globals)]
        mod tangential_rows {
            use super::*;
            $( pub(super) const $V: TangentialRow = $row; )+
        }

        /// Every tangential model, one row each, in registry order.
        pub const TANGENTIAL_MODELS: &[TangentialRow] = &[ $( tangential_rows::$V ),+ ];

        impl TangentialKind {
            /// Its registry row.
            pub fn row(&self) -> &'static TangentialRow {
                match self { $( TangentialKind::$V => &tangential_rows::$V, )+ }
            }

            /// The model of registry name `name`.
            pub fn from_name(name: &str) -> Option<TangentialKind> {
                $( if name == tangential_rows::$V.name { return Some(TangentialKind::$V); } )+
                None
            }

            /// [`TangentialSubModel::STORES_FORCE`] of the model (the same
            /// for every pair of a scene: `contact.tangential` is one key).
            pub fn stores_force(&self) -> bool {
                match self { $( TangentialKind::$V => <$T as TangentialSubModel>::STORES_FORCE, )+ }
            }

            /// The model for one pair.
            pub fn resolve(&self, setup: &TangentialSetup) -> TangentialPair {
                match self { $( TangentialKind::$V => TangentialPair::$V(<$T as TangentialSubModel>::new(setup)), )+ }
            }
        }

        impl TangentialPair {
            /// [`TangentialSubModel::stiffness`].
            #[inline(always)]
            pub fn stiffness(&self, overlap: f64) -> f64 {
                match self { $( TangentialPair::$V(t) => t.stiffness(overlap), )+ }
            }

            /// Its registry row.
            pub fn row(&self) -> &'static TangentialRow {
                match self { $( TangentialPair::$V(_) => &tangential_rows::$V, )+ }
            }

            /// [`TangentialSubModel::STORES_FORCE`].
            #[inline(always)]
            pub fn stores_force(&self) -> bool {
                match self { $( TangentialPair::$V(_) => <$T as TangentialSubModel>::STORES_FORCE, )+ }
            }
        }
    };
}

tangential_registry! {
    /// Hertz–Mindlin no-slip: k_t = 8 G* √(R_eff h).
    Mindlin => mindlin::Mindlin = TangentialRow {
        name: "mindlin",
        formula: "k_t = 8 G* √(R_eff h), G* = 1/((2−ν₁)/G₁ + (2−ν₂)/G₂)",
    };
    /// Linear Cundall–Strack: k_t = (2/7) E_eff R_eff.
    Linear => linear::LinearTangential = TangentialRow {
        name: "linear",
        formula: "k_t = (2/7) E_eff R_eff (constant)",
    };
    /// Incremental Hertz–Mindlin: the stored force F_s += −8 G* √(R_eff h) v_t Δt.
    MindlinForce => mindlin_force::MindlinForce = TangentialRow {
        name: "mindlin_force",
        formula: "F_s += −k_t v_t Δt, k_t = 8 G* √(R_eff h) (LAMMPS mindlin/force)",
    };
}

/// Registry names of the tangential models, quoted, comma-separated.
pub fn tangential_names() -> String {
    TANGENTIAL_MODELS
        .iter()
        .map(|r| format!("\"{}\"", r.name))
        .collect::<Vec<_>>()
        .join(", ")
}

/// Effective shear modulus of a contact, G* = 1/((2 − ν₁)/G₁ + (2 − ν₂)/G₂)
/// with G = E/(2(1 + ν)) (Mindlin 1949; LAMMPS `mix_stiffnessG`), Pa; a
/// rigid material contributes 0 (written in reciprocal form, exact).
pub fn effective_shear_modulus(a: &Material, b: &Material) -> f64 {
    let term =
        |m: &Material| 2.0 * (2.0 - m.poisson_ratio) * (1.0 + m.poisson_ratio) / m.youngs_modulus;
    1.0 / (term(a) + term(b))
}

/// The friction coefficient of a pair of surfaces of coefficients `a` and
/// `b`: the geometric mean √(μ_a μ_b) (LAMMPS's default mixing of granular
/// coefficients; a frictionless surface makes the pair frictionless).
pub fn mix_friction(a: f64, b: f64) -> f64 {
    if a == b {
        a
    } else {
        (a * b).sqrt()
    }
}

/// The configured friction of a scene: tangential spring, sliding
/// friction μ and rolling friction μ_r (the defaults of every surface).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FrictionModel {
    /// `contact.tangential`.
    pub tangential: TangentialKind,
    /// `contact.friction`: Coulomb coefficient μ ≥ 0.
    pub friction: f64,
    /// `contact.rolling_friction`: rolling coefficient μ_r ≥ 0 (epsd2).
    pub rolling_friction: f64,
}

impl FrictionModel {
    /// Checks μ and μ_r: finite and ≥ 0.
    pub fn validate(&self) -> Result<(), PhysicsError> {
        check_coefficient("contact.friction", self.friction, "μ")?;
        check_coefficient("contact.rolling_friction", self.rolling_friction, "μ_r")
    }

    /// The friction of one pair whose normal law is `law` (its damping
    /// sets the tangential damping), of properties `pair` and effective
    /// shear modulus `shear_modulus` (Pa), with the pair's mixed
    /// coefficients `friction` and `rolling_friction`.
    pub fn pair(
        &self,
        law: &PairLaw,
        pair: &PairProperties,
        shear_modulus: f64,
        friction: f64,
        rolling_friction: f64,
    ) -> FrictionPair {
        let tangential = self.tangential.resolve(&TangentialSetup {
            pair: *pair,
            shear_modulus,
        });
        let family = law.normal().row().family;
        let normal_stiffness = law.normal().stiffness();
        let damping = law.damping();
        // η_n(h) = F_d(h, ḣ = 1): every damping model is linear in ḣ.
        let damped = damping.force(1.0, 1.0) != 0.0;
        FrictionPair {
            tangential,
            friction,
            rolling: super::rolling::Epsd2 {
                coefficient: rolling_friction,
                radius: pair.radius,
            },
            damping: if damped {
                TangentialDamping::SameRatio {
                    law: *law,
                    family,
                    normal_stiffness,
                }
            } else {
                TangentialDamping::None
            },
            rotation: SpringRotation::Rescale,
        }
    }
}

/// A friction coefficient's check: finite and ≥ 0.
pub fn check_coefficient(key: &str, value: f64, symbol: &str) -> Result<(), PhysicsError> {
    if value.is_finite() && value >= 0.0 {
        Ok(())
    } else {
        Err(PhysicsError::new(
            key,
            value,
            format!("finite and ≥ 0 ({symbol}, 1)"),
        ))
    }
}

/// How the tangential damping follows the normal one.
#[derive(Debug, Clone, Copy, PartialEq)]
enum TangentialDamping {
    None,
    /// η_t = η_n(h) √(k_t/S_n(h)).
    SameRatio {
        law: PairLaw,
        family: Family,
        normal_stiffness: f64,
    },
    /// No tangential dashpot (`contact.tangential_damping = false`, LIGGGHTS
    /// `tangential_damping off`); the rolling spring keeps the normal
    /// contact's damping ratio as under `SameRatio`.
    RollingOnly {
        law: PairLaw,
        family: Family,
        normal_stiffness: f64,
    },
}

/// The friction of one pair: tangential spring with damping and Coulomb
/// limit, and rolling resistance. `Copy`, small.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FrictionPair {
    tangential: TangentialPair,
    friction: f64,
    rolling: super::rolling::Epsd2,
    damping: TangentialDamping,
    /// How the spring follows a turning normal (step 1).
    rotation: SpringRotation,
}

/// A displacement spring moved by its contact's slip
/// ([`FrictionPair::move_spring`]): what the Coulomb test and cut of step
/// 3 read.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct MovedSpring {
    /// k_t at the contact's overlap, N/m.
    pub stiffness: f64,
    /// The Coulomb limit μ |F_n|, N.
    pub limit: f64,
    /// |δ|² of the moved spring, m².
    pub stretch: f64,
}

impl MovedSpring {
    /// Step 3's test and factor: whether the spring alone exceeds μ |F_n|
    /// (sliding), and the factor on the spring, limit/(k_t |δ|) when
    /// sliding, else exactly 1 (which changes no bit).
    #[inline(always)]
    pub fn cut(&self) -> (bool, f64) {
        let (k_t, limit, stretch) = (self.stiffness, self.limit, self.stretch);
        // 3. Coulomb on the spring (LIGGGHTS `tangential_model_history`):
        // sliding when the spring alone exceeds μ |F_n| (compared squared,
        // both sides ≥ 0); the spring is cut back to the limit and the
        // force is the limit, without damping.
        let sliding = k_t * k_t * stretch > limit * limit;
        // The cut's factor limit/(k_t |δ|) (the spring's magnitude > 0
        // when sliding: it exceeds limit² ≥ 0) is taken for every contact
        // and chosen without a jump; a sticking spring is scaled by exactly
        // 1. So the root and the division start as soon as the moved
        // spring is known, rather than after a test that contacts turning
        // between sticking and sliding make unpredictable (a sticking
        // contact discards them, an inf or NaN at |δ| = 0 included).
        // Undamped, sliding and sticking both return the spring's force
        // ([`FrictionPair::cut_spring_force`]).
        let spring = k_t * stretch.sqrt();
        (
            sliding,
            std::hint::select_unpredictable(sliding, limit / spring, 1.0),
        )
    }
}

#[inline(always)]
pub(crate) fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

impl FrictionPair {
    /// μ of the pair.
    pub fn friction(&self) -> f64 {
        self.friction
    }

    /// μ_r of the pair.
    pub fn rolling_friction(&self) -> f64 {
        self.rolling.coefficient
    }

    /// The tangential spring.
    pub fn tangential(&self) -> &TangentialPair {
        &self.tangential
    }

    /// The same friction without the tangential dashpot (η_t = 0; the
    /// rolling spring's damping kept): `contact.tangential_damping = false`,
    /// LIGGGHTS's `tangential_damping off`. A sticking contact's force is
    /// then the spring's alone, −k_t δ, within μ |F_n| by the sliding test.
    pub fn without_tangential_damping(self) -> Self {
        let damping = match self.damping {
            TangentialDamping::SameRatio {
                law,
                family,
                normal_stiffness,
            } => TangentialDamping::RollingOnly {
                law,
                family,
                normal_stiffness,
            },
            other => other,
        };
        Self { damping, ..self }
    }

    /// The same friction with the spring turned by `rotation` when the
    /// normal turns (`contact.spring_rotation`; [`Self::rotate_spring`]).
    pub fn with_spring_rotation(self, rotation: SpringRotation) -> Self {
        Self { rotation, ..self }
    }

    /// How the spring follows a turning normal.
    #[inline(always)]
    pub fn spring_rotation(&self) -> SpringRotation {
        self.rotation
    }

    /// Step 1 of [`Self::tangential_force`]: the stored spring `shear`
    /// back into the tangent plane of the unit normal `normal` as the
    /// pair's [`SpringRotation`] says: [`Self::turn_spring`] (its length
    /// kept, the default) or [`project_spring`] (LIGGGHTS's, its length
    /// not restored).
    #[inline(always)]
    pub fn rotate_spring(&self, shear: &mut [f64; 3], normal: [f64; 3]) {
        match self.rotation {
            SpringRotation::Rescale => Self::turn_spring(shear, normal),
            SpringRotation::Project => project_spring(shear, normal),
        }
    }

    /// Whether the tangential force has no dashpot: η_t = 0 at every
    /// overlap ([`Self::damping_coefficient`]), because the normal law is
    /// undamped or the dashpot was removed
    /// ([`Self::without_tangential_damping`]). A sticking contact's force
    /// is then the spring's alone. Lets a kernel specialised for such laws
    /// state it to the compiler once, rather than test the variant per
    /// contact.
    #[inline(always)]
    pub fn tangentially_undamped(&self) -> bool {
        !matches!(self.damping, TangentialDamping::SameRatio { .. })
    }

    /// Tangential damping coefficient η_t at overlap h (m) for stiffness
    /// `k_t` (N/m), N s/m.
    #[inline(always)]
    pub fn damping_coefficient(&self, overlap: f64, k_t: f64) -> f64 {
        match self.damping {
            TangentialDamping::None | TangentialDamping::RollingOnly { .. } => 0.0,
            TangentialDamping::SameRatio {
                law,
                family,
                normal_stiffness,
            } => {
                let s_n = match family {
                    Family::Hertzian => 1.5 * normal_stiffness * overlap.max(0.0).sqrt(),
                    _ => normal_stiffness,
                };
                if s_n > 0.0 {
                    law.damping().force(overlap, 1.0) * (k_t / s_n).sqrt()
                } else {
                    0.0
                }
            }
        }
    }

    /// Tangential force on body 1 (N) at overlap `overlap` > 0 (m) with
    /// normal force `normal_force` (N; its magnitude sets the Coulomb limit),
    /// unit normal `normal` (body 1 to body 2) and tangential relative
    /// velocity `tangential_velocity` of the contact points (m/s), after a
    /// time `dt` (s) since the last evaluation (0: evaluate without moving
    /// the spring, as LAMMPS's setup does). Updates the spring `shear`,
    /// kept in the tangent plane: the displacement δ (m), or the force F_s
    /// (N) for a model that stores it ([`TangentialSubModel::STORES_FORCE`]).
    ///
    /// The two parts in turn: [`Self::rotate_spring`] (step 1 of the
    /// module's list, a function of the stored spring and the normal alone,
    /// [`Self::turn_spring`] by default), then
    /// [`Self::tangential_force_turned`] (steps 2–4). A many-contact loop
    /// may turn a batch's springs first and call the second part per
    /// contact: the same operations on the same values, the same bits.
    #[inline(always)]
    pub fn tangential_force(
        &self,
        overlap: f64,
        normal_force: f64,
        normal: [f64; 3],
        tangential_velocity: [f64; 3],
        dt: f64,
        shear: &mut [f64; 3],
    ) -> [f64; 3] {
        self.rotate_spring(shear, normal);
        self.tangential_force_turned(overlap, normal_force, tangential_velocity, dt, shear)
    }

    /// [`Self::tangential_force`] with the kind of spring known to the
    /// caller (`stores_force`: the pair's [`TangentialPair::stores_force`],
    /// a constant in a kernel; see [`Self::tangential_force_turned_known`]).
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    pub fn tangential_force_known(
        &self,
        stores_force: bool,
        overlap: f64,
        normal_force: f64,
        normal: [f64; 3],
        tangential_velocity: [f64; 3],
        dt: f64,
        shear: &mut [f64; 3],
    ) -> [f64; 3] {
        self.rotate_spring(shear, normal);
        self.tangential_force_turned_known(
            stores_force,
            overlap,
            normal_force,
            tangential_velocity,
            dt,
            shear,
        )
    }

    /// Step 1 of [`Self::tangential_force`]: the contact frame turned, the
    /// stored displacement `shear` (m) back into the tangent plane of the
    /// unit normal `normal`, its length kept (the projection and rescale
    /// of LAMMPS `GranSubModTangentialMindlin::calculate_forces`,
    /// `gran_sub_mod_tangential.cpp`, there only above a threshold). Depends
    /// on the spring and the normal only, not on the law, the overlap or
    /// the velocities.
    #[inline(always)]
    pub fn turn_spring(shear: &mut [f64; 3], normal: [f64; 3]) {
        // p = δ − (δ·n) n scaled by |δ|/|p| = 1/√(1 − x), with x =
        // (δ·n)²/|δ|² the squared sine of the turn since the last step.
        let along = dot(*shear, normal);
        if along != 0.0 {
            let before = dot(*shear, *shear);
            let mut p = [
                shear[0] - along * normal[0],
                shear[1] - along * normal[1],
                shear[2] - along * normal[2],
            ];
            let along2 = along * along;
            // A spring so short that |δ|² is subnormal (|δ| < 1.5e-154:
            // round-off slips of spheres at rest, ~1e-123 m/s) takes the
            // root below: there 1/|δ|² overflows to ∞ and the small turn's
            // factor would be ∞, the spring ∞ and then NaN.
            let scale = if along2 < 1.0e-8 * before && before >= f64::MIN_POSITIVE {
                // A small turn (every step of a resolved contact):
                // 1/√(1 − x) = 1 + x/2 to rounding (the next term, 3x²/8,
                // is below 4e-17). No root.
                1.0 + 0.5 * (along2 * (1.0 / before))
            } else {
                let after = dot(p, p);
                if after > 0.0 {
                    (before / after).sqrt()
                } else {
                    0.0
                }
            };
            for x in &mut p {
                *x *= scale;
            }
            *shear = p;
        }
    }

    /// Steps 2–4 of [`Self::tangential_force`] on a spring `shear` (m)
    /// already turned into the tangent plane ([`Self::turn_spring`]): the
    /// spring moved by the slip `tangential_velocity` (m/s) over `dt` (s),
    /// then cut back to the Coulomb limit μ |F_n| (`normal_force`, N) when
    /// sliding; the tangential force on body 1 (N) at overlap `overlap`
    /// (m).
    #[inline(always)]
    pub fn tangential_force_turned(
        &self,
        overlap: f64,
        normal_force: f64,
        tangential_velocity: [f64; 3],
        dt: f64,
        shear: &mut [f64; 3],
    ) -> [f64; 3] {
        self.tangential_force_turned_known(
            self.tangential.stores_force(),
            overlap,
            normal_force,
            tangential_velocity,
            dt,
            shear,
        )
    }

    /// [`Self::tangential_force_turned`] with the kind of spring known to
    /// the caller: `stores_force` must be the pair's
    /// [`TangentialPair::stores_force`]. A kernel passes a constant, chosen
    /// once a run from the scene's `contact.tangential` (the key is one per
    /// scene), so that its instance for displacement springs (`mindlin`,
    /// `linear`) compiles to their code alone, without a test per contact.
    #[inline(always)]
    pub fn tangential_force_turned_known(
        &self,
        stores_force: bool,
        overlap: f64,
        normal_force: f64,
        tangential_velocity: [f64; 3],
        dt: f64,
        shear: &mut [f64; 3],
    ) -> [f64; 3] {
        debug_assert_eq!(stores_force, self.tangential.stores_force());
        if stores_force {
            return self.incremental_force_turned(
                overlap,
                normal_force,
                tangential_velocity,
                dt,
                shear,
            );
        }
        let moved = self.move_spring(overlap, normal_force, tangential_velocity, dt, shear);
        let (sliding, s) = moved.cut();
        self.cut_spring_force(&moved, sliding, s, overlap, tangential_velocity, shear)
    }

    /// Step 2 of [`Self::tangential_force_turned_known`] for a
    /// displacement spring (not [`TangentialSubModel::STORES_FORCE`]): the
    /// spring `shear` (m), turned already, moved by the slip
    /// `tangential_velocity` (m/s) over `dt` (s); returns what step 3's
    /// Coulomb test and cut read ([`MovedSpring`]). Then
    /// [`MovedSpring::cut`] and [`Self::cut_spring_force`]: the three in
    /// turn are that function's operations in its order (the same bits),
    /// so that a many-contact loop may run each over a batch of contacts,
    /// the cut's root and division of several contacts overlapping
    /// instead of ending each contact's chain of dependent operations.
    #[inline(always)]
    pub fn move_spring(
        &self,
        overlap: f64,
        normal_force: f64,
        tangential_velocity: [f64; 3],
        dt: f64,
        shear: &mut [f64; 3],
    ) -> MovedSpring {
        debug_assert!(!self.tangential.stores_force());
        let k_t = self.tangential.stiffness(overlap);
        // 2. The spring moves with the contact points.
        let v = tangential_velocity;
        for a in 0..3 {
            shear[a] += v[a] * dt;
        }
        let limit = self.friction * normal_force.abs();
        let stretch = dot(*shear, *shear);
        MovedSpring {
            stiffness: k_t,
            limit,
            stretch,
        }
    }

    /// Steps 3–4 of [`Self::tangential_force_turned_known`] for a
    /// displacement spring after [`Self::move_spring`] gave `moved` and
    /// [`MovedSpring::cut`] gave `(sliding, s)`: the spring `shear` (m)
    /// scaled by `s`, and the tangential force on body 1 (N) at overlap
    /// `overlap` (m) with slip `tangential_velocity` (m/s, the one the
    /// spring moved by).
    #[inline(always)]
    pub fn cut_spring_force(
        &self,
        moved: &MovedSpring,
        sliding: bool,
        s: f64,
        overlap: f64,
        tangential_velocity: [f64; 3],
        shear: &mut [f64; 3],
    ) -> [f64; 3] {
        let (k_t, limit, v) = (moved.stiffness, moved.limit, tangential_velocity);
        for x in shear.iter_mut() {
            *x *= s;
        }
        if sliding {
            return [-k_t * shear[0], -k_t * shear[1], -k_t * shear[2]];
        }
        // 4. Sticking: spring and dashpot, the total still capped at μ |F_n|
        // (the spring kept). Undamped, the force is the spring's, within
        // the limit already.
        let eta = self.damping_coefficient(overlap, k_t);
        if eta == 0.0 {
            return [-k_t * shear[0], -k_t * shear[1], -k_t * shear[2]];
        }
        let mut f = [
            -k_t * shear[0] - eta * v[0],
            -k_t * shear[1] - eta * v[1],
            -k_t * shear[2] - eta * v[2],
        ];
        let magnitude2 = dot(f, f);
        if magnitude2 > limit * limit {
            let s = limit / magnitude2.sqrt();
            for x in &mut f {
                *x *= s;
            }
        }
        f
    }

    /// [`Self::tangential_force_turned`] for a spring that stores its force
    /// `spring` (N; [`TangentialSubModel::STORES_FORCE`]), already turned
    /// into the tangent plane: LAMMPS `GranSubModTangentialMindlin::
    /// calculate_forces` with `mindlin_force` (`gran_sub_mod_tangential.cpp`),
    /// 1. F_s ← F_s + (−k_t(h) Δt) v_t, the stiffness of this step's overlap;
    /// 2. sliding if the spring alone exceeds μ |F_n|: F_s scaled by
    ///    μ |F_n|/|F_s| and returned, without damping;
    /// 3. else F_s − η_t v_t, capped at μ |F_n| (the spring kept).
    ///
    /// Steps 2–3 are the Coulomb order of the displacement springs (the
    /// module's list). Without the tangential dashpot (η_t = 0: LAMMPS's
    /// x_γ,t = 0, the exported decks) they are LAMMPS's operations: its
    /// force |F_s| = √(F_s·F_s) tested against Fscrit = μ |F_n|, F_s scaled
    /// by Fscrit/|F_s|. With the dashpot LAMMPS caps spring plus dashpot
    /// and solves the spring back from the capped force (see the module's
    /// list): the two differ only while that sum exceeds the limit.
    #[inline(always)]
    fn incremental_force_turned(
        &self,
        overlap: f64,
        normal_force: f64,
        tangential_velocity: [f64; 3],
        dt: f64,
        spring: &mut [f64; 3],
    ) -> [f64; 3] {
        let k_t = self.tangential.stiffness(overlap);
        let v = tangential_velocity;
        let step = -k_t * dt;
        for a in 0..3 {
            spring[a] += step * v[a];
        }
        let limit = self.friction * normal_force.abs();
        let magnitude = dot(*spring, *spring).sqrt();
        if magnitude > limit {
            let s = limit / magnitude;
            for x in spring.iter_mut() {
                *x *= s;
            }
            return *spring;
        }
        let eta = self.damping_coefficient(overlap, k_t);
        if eta == 0.0 {
            return *spring;
        }
        let mut f = [
            spring[0] - eta * v[0],
            spring[1] - eta * v[1],
            spring[2] - eta * v[2],
        ];
        let magnitude = dot(f, f).sqrt();
        if magnitude > limit {
            let s = limit / magnitude;
            for x in &mut f {
                *x *= s;
            }
        }
        f
    }

    /// The tangential force on body 1 (N) that the last step applied,
    /// given the spring `shear` (m) it stored and the same overlap,
    /// normal force, normal and slip: [`Self::tangential_force`] through a
    /// step of zero length, except that a spring cut back to the Coulomb
    /// limit by the step (k_t |δ| = μ |F_n| to rounding) is taken as
    /// sliding, as the step took it (its force the spring's alone). A
    /// re-evaluation alone would see the cut spring at or a rounding below
    /// the limit, half the time, and add the dashpot: the force it gives
    /// then differs from the applied one wherever the slip turns, and the
    /// dissipation summed from it is biased (`dembound-scene`'s
    /// `pipeline::dissipation`).
    pub fn applied_tangential_force(
        &self,
        overlap: f64,
        normal_force: f64,
        normal: [f64; 3],
        tangential_velocity: [f64; 3],
        shear: [f64; 3],
    ) -> [f64; 3] {
        let limit = self.friction * normal_force.abs();
        if self.tangential.stores_force() {
            // The stored force itself: cut to the limit, as below.
            if dot(shear, shear).sqrt() >= limit * (1.0 - 1.0e-12) {
                return shear;
            }
        } else {
            let k_t = self.tangential.stiffness(overlap);
            // The cut scales δ by limit/(k_t |δ|): k_t |δ| lands within a few
            // ulp of the limit; 1e-12 is far above that and far below any
            // sticking spring's approach to the limit within a step.
            if k_t * dot(shear, shear).sqrt() >= limit * (1.0 - 1.0e-12) {
                return [-k_t * shear[0], -k_t * shear[1], -k_t * shear[2]];
            }
        }
        let mut s = shear;
        self.tangential_force(
            overlap,
            normal_force,
            normal,
            tangential_velocity,
            0.0,
            &mut s,
        )
    }

    /// The rolling torque on body 1 (N m) that the last step applied,
    /// given the rolling spring `history` (N m) it stored: as
    /// [`Self::applied_tangential_force`], a spring at the limit μ_r R_eff
    /// |F_n| (to rounding) is the applied torque, without the dashpot.
    #[allow(clippy::too_many_arguments)]
    pub fn applied_rolling_torque(
        &self,
        law: &PairLaw,
        overlap: f64,
        normal_force: f64,
        normal: [f64; 3],
        relative_spin: [f64; 3],
        inertia: f64,
        history: [f64; 3],
    ) -> [f64; 3] {
        if self.rolling.coefficient == 0.0 {
            return [0.0; 3];
        }
        let limit = self.rolling.coefficient * self.rolling.radius * normal_force.abs();
        if dot(history, history).sqrt() >= limit * (1.0 - 1.0e-12) {
            return history;
        }
        let mut m = history;
        self.rolling_torque(
            law,
            overlap,
            normal_force,
            normal,
            relative_spin,
            inertia,
            0.0,
            &mut m,
        )
    }

    /// Energy held by the contact's springs at overlap `overlap` (m), J:
    /// ½ k_t(h) |δ|² for the tangential displacement `shear` (m) and
    /// ½ |M_r|²/k_r for the rolling spring's torque `rolling` (N m),
    /// k_r = 2.25 k_n μ_r² R_eff² with k_n the normal law's secant
    /// stiffness ([`super::rolling::Epsd2`]). The tangential term is the
    /// spring's potential while k_t is constant (linear; Mindlin at a fixed
    /// overlap): a Mindlin spring whose overlap changes does work
    /// −½ (dk_t/dh) |δ|² dh that no potential holds (LIGGGHTS and LAMMPS
    /// report the same ½ F_t²/k_t).
    #[inline]
    pub fn spring_energy(
        &self,
        law: &PairLaw,
        overlap: f64,
        shear: &[f64; 3],
        rolling: &[f64; 3],
    ) -> f64 {
        self.spring_energy_known(self.tangential.stores_force(), law, overlap, shear, rolling)
    }

    /// [`Self::spring_energy`] with the kind of spring known to the caller
    /// (`stores_force`: the pair's [`TangentialPair::stores_force`], a
    /// constant in a kernel; see [`Self::tangential_force_turned_known`]).
    #[inline(always)]
    pub fn spring_energy_known(
        &self,
        stores_force: bool,
        law: &PairLaw,
        overlap: f64,
        shear: &[f64; 3],
        rolling: &[f64; 3],
    ) -> f64 {
        debug_assert_eq!(stores_force, self.tangential.stores_force());
        if overlap <= 0.0 {
            return 0.0;
        }
        let k_t = self.tangential.stiffness(overlap);
        let mut e = if stores_force {
            // ½ |F_s|²/k_t (LAMMPS and Yade report the same).
            if k_t > 0.0 {
                0.5 * dot(*shear, *shear) / k_t
            } else {
                0.0
            }
        } else {
            0.5 * k_t * dot(*shear, *shear)
        };
        let m2 = dot(*rolling, *rolling);
        if m2 > 0.0 && self.rolling.coefficient > 0.0 {
            let secant = law
                .normal()
                .force(overlap, 0.0, &super::ContactHistory::default())
                / overlap;
            let r = self.rolling.radius * self.rolling.coefficient;
            let k_r = 2.25 * secant * r * r;
            if k_r > 0.0 {
                e += 0.5 * m2 / k_r;
            }
        }
        e
    }

    /// Rolling-resistance torque on body 1 (N m) at overlap `overlap` (m)
    /// with normal force `normal_force` (N), for the relative angular
    /// velocity ω₁ − ω₂ (rad/s) of bodies of effective rolling inertia
    /// `inertia` = 1/(1/I₁ + 1/I₂) (kg m²), after `dt` s
    /// ([`super::rolling::Epsd2`]); updates the spring torque `history`.
    /// Body 2 gets minus it. The damping ratio is the normal contact's
    /// local one, η_n/(2 √(S_n m*)).
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    pub fn rolling_torque(
        &self,
        law: &PairLaw,
        overlap: f64,
        normal_force: f64,
        normal: [f64; 3],
        relative_spin: [f64; 3],
        inertia: f64,
        dt: f64,
        history: &mut [f64; 3],
    ) -> [f64; 3] {
        if self.rolling.coefficient == 0.0 {
            *history = [0.0; 3];
            return [0.0; 3];
        }
        let h = overlap.max(f64::MIN_POSITIVE);
        let secant = law
            .normal()
            .force(h, 0.0, &super::ContactHistory::default())
            / h;
        let ratio = match self.damping {
            TangentialDamping::None => 0.0,
            TangentialDamping::SameRatio {
                family,
                normal_stiffness,
                ..
            }
            | TangentialDamping::RollingOnly {
                family,
                normal_stiffness,
                ..
            } => {
                let s_n = match family {
                    Family::Hertzian => 1.5 * normal_stiffness * h.sqrt(),
                    _ => normal_stiffness,
                };
                let eta_n = law.damping().force(h, 1.0);
                if s_n > 0.0 {
                    eta_n / (2.0 * (s_n * law.mass()).sqrt())
                } else {
                    0.0
                }
            }
        };
        self.rolling.torque(
            normal_force,
            secant,
            ratio,
            inertia,
            normal,
            relative_spin,
            dt,
            history,
        )
    }
}

#[cfg(test)]
mod tests;
