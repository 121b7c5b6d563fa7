//! Where the frictionless pair loop ([`Rows`](super::Rows)) finds a
//! contact's law: the scene's [`LawTable`], looked up and dispatched on
//! per contact, or, when every row of the table has the variants of a
//! kernel ([`Variants`]), the table's one row when the scene has one body
//! class ([`OneLaw`]) or its rows ([`ClassLaws`]), with the sub-model
//! variants known to the compiler.
//!
//! Why (as the friction loop's `friction::row_laws`): the composer's
//! sub-models are enums (`NormalPair`, `DampingPair`, the clamp flag), so
//! a loop that reads the law per contact dispatches on them per contact,
//! besides the two class loads and the index of each lookup: the
//! frictionless 10k lattice drop (undamped Hertz, one class, 10,000
//! steps, one thread) ran 27.5·10⁹ instructions with them and 20.3·10⁹
//! without (BENCHMARKS.md, session 35). A kernel
//! instantiated for the one row's variants ([`Variants`]) runs the same
//! sub-model methods on the same values (the same bits) without the
//! dispatch: each read states the variants the row was checked to have
//! ([`std::hint::assert_unchecked`]) and the compiler folds the matches
//! on them. The physics crate's code is the only contact law; the kernel
//! only tells the compiler what was checked once per call.

use std::marker::PhantomData;

use dembound_physics::contact::{DampingPair, NormalPair, PairLaw};

use super::LawTable;
use crate::bodies::Bodies;

/// The law of the contact between bodies i and j of `bodies`.
pub(crate) trait PairLaws: Sync {
    fn law(&self, bodies: &Bodies, i: usize, j: usize) -> PairLaw;
}

impl PairLaws for LawTable {
    #[inline(always)]
    fn law(&self, bodies: &Bodies, i: usize, j: usize) -> PairLaw {
        self.pair(bodies, i, j)
    }
}

/// Which [`Variants`] every row of a class table has, if any: found once
/// when the table is made ([`LawTable::from_keys`], which alone writes the
/// rows), not at every step.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum RowVariants {
    HertzUndamped,
    HertzTsuji,
}

impl RowVariants {
    /// The variants every one of `rows` has (none for an empty table or
    /// one that keeps contact histories: no kernel has them).
    pub(super) fn of(rows: &[PairLaw], history: bool) -> Option<Self> {
        if history || rows.is_empty() {
            None
        } else if rows.iter().all(HertzUndamped::matches) {
            Some(Self::HertzUndamped)
        } else if rows.iter().all(HertzTsuji::matches) {
            Some(Self::HertzTsuji)
        } else {
            None
        }
    }
}

/// Sub-model variants a law may be checked to have, so that a kernel
/// instantiated for them has no per-contact dispatch.
pub(crate) trait Variants: Sync {
    /// The table-wide name of these variants.
    const ROWS: RowVariants;

    /// Whether `law` has these variants.
    fn matches(law: &PairLaw) -> bool;

    /// Tells the compiler that `law` has these variants, one fact per
    /// sub-model (a single condition joined by `&&` is a chain of branches
    /// the optimiser does not split back into facts).
    ///
    /// # Safety
    /// `Self::matches(law)`.
    unsafe fn assume(law: &PairLaw);
}

/// Hertz without damping, clamped (no attraction): the lattice-drop
/// benchmark's law (LAMMPS `hertz/material` undamped), and every scene
/// that sets only `law = "hertz"`.
pub(crate) struct HertzUndamped;

impl Variants for HertzUndamped {
    const ROWS: RowVariants = RowVariants::HertzUndamped;

    #[inline(always)]
    fn matches(law: &PairLaw) -> bool {
        matches!(law.normal(), NormalPair::Hertz(_))
            && matches!(law.damping(), DampingPair::None(_))
            && !law.attractive()
    }

    #[inline(always)]
    unsafe fn assume(law: &PairLaw) {
        use std::hint::assert_unchecked;
        // SAFETY: the caller's (`Self::matches`).
        unsafe {
            assert_unchecked(matches!(law.normal(), NormalPair::Hertz(_)));
            assert_unchecked(matches!(law.damping(), DampingPair::None(_)));
            assert_unchecked(!law.attractive());
        }
    }
}

/// Hertz with Tsuji's damping, clamped: the damped law of most example
/// scenes (`law = "hertz"`, `damping = "tsuji"`; LIGGGHTS's and LAMMPS's
/// `tsuji` damping).
pub(crate) struct HertzTsuji;

impl Variants for HertzTsuji {
    const ROWS: RowVariants = RowVariants::HertzTsuji;

    #[inline(always)]
    fn matches(law: &PairLaw) -> bool {
        matches!(law.normal(), NormalPair::Hertz(_))
            && matches!(law.damping(), DampingPair::Tsuji(_))
            && !law.attractive()
    }

    #[inline(always)]
    unsafe fn assume(law: &PairLaw) {
        use std::hint::assert_unchecked;
        // SAFETY: the caller's (`Self::matches`).
        unsafe {
            assert_unchecked(matches!(law.normal(), NormalPair::Hertz(_)));
            assert_unchecked(matches!(law.damping(), DampingPair::Tsuji(_)));
            assert_unchecked(!law.attractive());
        }
    }
}

/// The laws of a scene's class table when every row has the variants of
/// a kernel the loop has: its one row ([`OneLaw`]) when it has one class
/// (no lookup: 1.0·10⁹ fewer instructions of the lattice drop's 21.3·10⁹
/// than [`ClassLaws`] on its one row), else the table ([`ClassLaws`]).
pub(crate) enum KnownLaw<'a> {
    OneHertzUndamped(OneLaw<HertzUndamped>),
    OneHertzTsuji(OneLaw<HertzTsuji>),
    HertzUndamped(ClassLaws<'a, HertzUndamped>),
    HertzTsuji(ClassLaws<'a, HertzTsuji>),
}

impl<'a> KnownLaw<'a> {
    /// The laws of `laws` for `bodies` if a kernel has their variants
    /// (the table's rows were checked when it was made: a few loads a
    /// step, whatever the number of classes).
    pub(crate) fn of(laws: &'a LawTable, bodies: &'a Bodies) -> Option<Self> {
        match (laws.row_variants?, laws.classes) {
            (RowVariants::HertzUndamped, 1) => OneLaw::of(laws).map(Self::OneHertzUndamped),
            (RowVariants::HertzTsuji, 1) => OneLaw::of(laws).map(Self::OneHertzTsuji),
            (RowVariants::HertzUndamped, _) => ClassLaws::of(laws, bodies).map(Self::HertzUndamped),
            (RowVariants::HertzTsuji, _) => ClassLaws::of(laws, bodies).map(Self::HertzTsuji),
        }
    }
}

/// The one law of a scene with one body class, checked to have the
/// variants `V`.
pub(crate) struct OneLaw<V> {
    law: PairLaw,
    variants: PhantomData<V>,
}

impl<V: Variants> OneLaw<V> {
    /// The one law of `laws` if the table has one body class and its row
    /// has the variants `V` (no histories: [`RowVariants::of`]).
    pub(crate) fn of(laws: &LawTable) -> Option<Self> {
        let fits = laws.classes == 1 && laws.row_variants == Some(V::ROWS);
        fits.then(|| Self {
            law: laws.pairs[0],
            variants: PhantomData,
        })
    }
}

impl<V: Variants> PairLaws for OneLaw<V> {
    #[inline(always)]
    fn law(&self, _bodies: &Bodies, _i: usize, _j: usize) -> PairLaw {
        // SAFETY: the table's one row, checked when the table was made
        // (`RowVariants::of` in `LawTable::from_keys`; `of` required `V`).
        unsafe { V::assume(&self.law) };
        self.law
    }
}

/// The class table of a scene, every row checked to have the variants
/// `V`: row class(i) · classes + class(j).
pub(crate) struct ClassLaws<'a, V> {
    table: &'a [PairLaw],
    class: &'a [u16],
    classes: usize,
    variants: PhantomData<V>,
}

impl<'a, V: Variants> ClassLaws<'a, V> {
    /// The table of `laws` if it has one (few enough classes), keeps no
    /// contact histories, its rows all have the variants `V` (checked
    /// when the table was made: [`RowVariants::of`]) and `bodies` carry
    /// its classes.
    pub(crate) fn of(laws: &'a LawTable, bodies: &'a Bodies) -> Option<Self> {
        let classes = laws.classes;
        let fits = classes > 0
            && laws.row_variants == Some(V::ROWS)
            && laws.pairs.len() == classes * classes
            && bodies.class.len() == bodies.len();
        fits.then_some(Self {
            table: &laws.pairs,
            class: &bodies.class,
            classes,
            variants: PhantomData,
        })
    }
}

impl<V: Variants> PairLaws for ClassLaws<'_, V> {
    #[inline(always)]
    fn law(&self, _bodies: &Bodies, i: usize, j: usize) -> PairLaw {
        // Checked indexing, as the table's own lookup (`LawTable::pair`):
        // a class the table does not hold (`NO_CLASS`, which no set-up
        // leaves beside a table) panics instead of reading past it.
        let law = &self.table[self.class[i] as usize * self.classes + self.class[j] as usize];
        // SAFETY: every row checked when the table was made
        // (`RowVariants::of` in `LawTable::from_keys`, the only writer of
        // the rows; `of` required its answer to be `V`).
        unsafe { V::assume(law) };
        *law
    }
}

#[cfg(test)]
mod tests {
    use super::{HertzTsuji, HertzUndamped, RowVariants, Variants};
    use dembound_physics::contact::{ContactModel, Damping, DampingKind, Dissipation, NormalLaw};
    use dembound_physics::material::{Material, PairProperties};

    /// The lattice drop's grain material.
    fn grain() -> Material {
        Material {
            density: 1000.0,
            youngs_modulus: 1.0e7,
            poisson_ratio: 0.3,
        }
    }

    /// Each variants' test accepts exactly its law (clamped Hertz,
    /// undamped or with Tsuji's damping): another damping, the attractive
    /// and another normal law are refused (each would be miscompiled under
    /// the kernel's stated facts).
    #[test]
    fn each_variants_test_matches_only_its_law() {
        let m = grain();
        let props = PairProperties::spheres(1.0e-3, 1.0e-6, &m, 1.0e-3, 1.0e-6, &m);
        let undamped = |model: ContactModel| HertzUndamped::matches(&model.pair(&props));
        let tsuji = |model: ContactModel| HertzTsuji::matches(&model.pair(&props));
        let hertz = ContactModel::elastic(NormalLaw::Hertz);
        let damping = |kind| Damping::new(kind, Dissipation::Restitution(0.5));
        let hertz_tsuji = ContactModel::damped(NormalLaw::Hertz, damping(DampingKind::Tsuji));
        assert!(undamped(hertz) && !tsuji(hertz));
        assert!(tsuji(hertz_tsuji) && !undamped(hertz_tsuji));
        for other in [
            ContactModel::elastic(NormalLaw::Linear),
            ContactModel::damped(NormalLaw::Linear, damping(DampingKind::Tsuji)),
            ContactModel::damped(NormalLaw::Hertz, damping(DampingKind::Viscoelastic)),
            ContactModel {
                attractive: true,
                ..hertz
            },
            ContactModel {
                attractive: true,
                ..hertz_tsuji
            },
        ] {
            assert!(!undamped(other) && !tsuji(other), "{other:?}");
        }
    }

    /// A table's variants are those of every row: a table mixing undamped
    /// and Tsuji rows (two materials, one damped) has none (a kernel would
    /// state a fact one row breaks), nor has an empty table or one keeping
    /// histories. Reference: the rows' own variants, built here.
    #[test]
    fn a_table_has_the_variants_of_every_row_or_none() {
        let m = grain();
        let props = PairProperties::spheres(1.0e-3, 1.0e-6, &m, 2.0e-3, 8.0e-6, &m);
        let undamped = ContactModel::elastic(NormalLaw::Hertz).pair(&props);
        let damping = Damping::new(DampingKind::Tsuji, Dissipation::Restitution(0.5));
        let tsuji = ContactModel::damped(NormalLaw::Hertz, damping).pair(&props);
        let of = |rows: &[_], history| RowVariants::of(rows, history);
        assert_eq!(of(&[undamped; 4], false), Some(RowVariants::HertzUndamped));
        assert_eq!(of(&[tsuji; 4], false), Some(RowVariants::HertzTsuji));
        assert_eq!(of(&[undamped, tsuji, tsuji, undamped], false), None);
        assert_eq!(of(&[tsuji, tsuji, tsuji, undamped], false), None);
        assert_eq!(of(&[undamped; 4], true), None);
        assert_eq!(of(&[], false), None);
    }
}
