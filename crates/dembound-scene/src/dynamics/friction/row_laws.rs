//! Where the batched pair kernel ([`MainPairs::batch`]) finds a contact's
//! law: the class table, looked up per contact ([`ClassTable`]), or the
//! table's one row when the scene has one body class ([`OneLaw`]), with
//! its sub-model variants known to the compiler.
//!
//! Why: the composer's sub-models are enums (`NormalPair`, `DampingPair`,
//! `TangentialPair`, `TorqueArm`, the clamp flag), so a kernel that reads
//! the law per contact dispatches on them per contact: in the machine code
//! two jump tables (the normal law, the damping) and the variant tests of
//! the tangential spring, the clamp and the torque arm, ~40 instructions
//! of a touching pair's ~375 in the settled lattice drop, besides the two
//! class loads and the index of each lookup. A monodisperse scene has one
//! row; a kernel instantiated for that row's variants ([`Variants`]) runs
//! the same sub-model methods on the same values (the same bits) without
//! the dispatch: each lookup states the variants the row was checked to
//! have ([`std::hint::assert_unchecked`]), and the compiler folds the
//! matches on them. The physics crate's code is the only contact law; the
//! kernel only tells the compiler what it already checked once per call.
//!
//! [`MainPairs::batch`]: super::pairs::MainPairs

use std::marker::PhantomData;

use dembound_physics::contact::tangential::TangentialPair;
use dembound_physics::contact::{DampingPair, NormalPair, TorqueArm};

use super::FrictionLaw;

/// The law of the contact between bodies i and j (both bodies of the
/// scene, < the class array's length).
pub(super) trait RowLaws: Sync {
    /// Whether every law's tangential spring stores its force
    /// (`TangentialPair::stores_force`, the scene's `contact.tangential`):
    /// the kernel's instance for one kind of spring, chosen once a run, so
    /// that the displacement springs' kernels have no test per contact.
    const STORES_FORCE: bool;

    fn law(&self, i: usize, j: usize) -> &FrictionLaw;
}

/// The class table: row class(i) · classes + class(j). `STORES_FORCE`:
/// [`RowLaws::STORES_FORCE`], checked by the caller for every row.
pub(super) struct ClassTable<'a, const STORES_FORCE: bool> {
    pub(super) table: &'a [FrictionLaw],
    pub(super) class: &'a [u16],
    pub(super) classes: usize,
}

impl<const STORES_FORCE: bool> RowLaws for ClassTable<'_, STORES_FORCE> {
    const STORES_FORCE: bool = STORES_FORCE;

    #[inline(always)]
    fn law(&self, i: usize, j: usize) -> &FrictionLaw {
        // SAFETY: classes are < `classes` when the table exists
        // (`FrictionTable::new`), so the row is in the table of classes²
        // rows; i and j are bodies (the caller's).
        unsafe {
            self.table.get_unchecked(
                *self.class.get_unchecked(i) as usize * self.classes
                    + *self.class.get_unchecked(j) as usize,
            )
        }
    }
}

/// Sub-model variants a law may be checked to have, so that a kernel
/// instantiated for them has no per-contact dispatch.
pub(super) trait Variants: Sync {
    /// [`RowLaws::STORES_FORCE`] of a law with these variants.
    const STORES_FORCE: bool;

    /// Whether `law` has these variants.
    fn matches(law: &FrictionLaw) -> bool;

    /// Tells the compiler that `law` has these variants, one fact per
    /// sub-model (a single condition joined by `&&` is a chain of branches
    /// the optimiser does not split back into facts).
    ///
    /// # Safety
    /// `Self::matches(law)`.
    unsafe fn assume(law: &FrictionLaw);
}

/// Hertz without damping, clamped (no attraction), the Mindlin spring,
/// the torque at the radius: the lattice-drop benchmarks' law (LAMMPS
/// `hertz/material … tangential mindlin`), and every scene that sets only
/// `law = "hertz"` and `tangential = "mindlin"`. Without normal damping
/// the tangential spring has no dashpot either
/// (`FrictionPair::tangentially_undamped`), stated too: a sticking
/// contact's force is the spring's, with no test of the dashpot's variant.
pub(super) struct HertzMindlin;

impl Variants for HertzMindlin {
    /// The Mindlin spring stores its displacement.
    const STORES_FORCE: bool = false;

    #[inline(always)]
    fn matches(law: &FrictionLaw) -> bool {
        matches!(law.law.normal(), NormalPair::Hertz(_))
            && matches!(law.law.damping(), DampingPair::None(_))
            && !law.law.attractive()
            && matches!(law.friction.tangential(), TangentialPair::Mindlin(_))
            && law.friction.tangentially_undamped()
            && law.torque_arm == TorqueArm::Radius
    }

    #[inline(always)]
    unsafe fn assume(law: &FrictionLaw) {
        use std::hint::assert_unchecked;
        // SAFETY: the caller's (`Self::matches`).
        unsafe {
            assert_unchecked(matches!(law.law.normal(), NormalPair::Hertz(_)));
            assert_unchecked(matches!(law.law.damping(), DampingPair::None(_)));
            assert_unchecked(!law.law.attractive());
            assert_unchecked(matches!(
                law.friction.tangential(),
                TangentialPair::Mindlin(_)
            ));
            assert_unchecked(law.friction.tangentially_undamped());
            assert_unchecked(law.torque_arm == TorqueArm::Radius);
        }
    }
}

/// The one law of a scene with one body class, checked to have the
/// variants `V`.
pub(super) struct OneLaw<V> {
    law: FrictionLaw,
    variants: PhantomData<V>,
}

impl<V: Variants> OneLaw<V> {
    /// `law` if it has the variants `V`.
    pub(super) fn new(law: &FrictionLaw) -> Option<Self> {
        V::matches(law).then_some(Self {
            law: *law,
            variants: PhantomData,
        })
    }
}

impl<V: Variants> RowLaws for OneLaw<V> {
    const STORES_FORCE: bool = V::STORES_FORCE;

    #[inline(always)]
    fn law(&self, _i: usize, _j: usize) -> &FrictionLaw {
        // SAFETY: checked in `new`, and the law is not changed after.
        unsafe { V::assume(&self.law) };
        &self.law
    }
}
