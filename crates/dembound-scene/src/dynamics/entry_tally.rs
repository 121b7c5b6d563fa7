//! Each main-list entry's own share of the series row, written by a force
//! pass that tallies (`contacts::add_pair_forces_tallied`,
//! `friction::add_pair_forces_tallied`) beside the rows' sums. A rank of a
//! decomposed scene needs the entries, not the rows' sums: it counts a
//! pair listed on two ranks on one of them and adds the pairs' energies
//! one by one in list order (`comm::distributed::observe`), so it reads
//! these instead of testing every listed pair and evaluating its law
//! again.

use crate::parallel::SharedMut;

/// The energy of an entry whose pair does not touch: a signalling NaN,
/// which no arithmetic gives (results are quiet NaNs), so no touching
/// pair's energy, not even a NaN one, is taken for it. Compared by bits
/// ([`apart`]).
pub const APART: f64 = f64::from_bits(0x7FF4_0000_0A9A_0001);

/// Whether an entry's [`EntryTally::energy`] says its pair does not touch.
#[inline(always)]
pub fn apart(energy: f64) -> bool {
    energy.to_bits() == APART.to_bits()
}

/// Each main-list entry's terms at the state of the force pass that wrote
/// them.
#[derive(Debug, Clone, Default)]
pub struct EntryTally {
    /// The pair's normal elastic energy (J) where it touches, as the rows'
    /// tally adds it; [`APART`] where it does not.
    pub energy: Vec<f64>,
    /// With friction, the pair's springs' energy (J) where it touches, as
    /// the rows' tally adds it, 0 where its springs are relaxed (adding 0
    /// to a sum that started at +0 and adds no −0 changes no bit); empty
    /// without.
    pub spring: Vec<f64>,
}

impl EntryTally {
    /// Every entry of a list of `entries` main entries marked apart (and
    /// its springs 0, with `friction`): the force pass then writes the
    /// touching ones through the returned pointers.
    pub(crate) fn prepare(&mut self, entries: usize, friction: bool) -> EntryTerms {
        self.energy.clear();
        self.energy.resize(entries, APART);
        self.spring.clear();
        if friction {
            self.spring.resize(entries, 0.0);
        }
        EntryTerms {
            energy: SharedMut(self.energy.as_mut_ptr()),
            spring: SharedMut(if friction {
                self.spring.as_mut_ptr()
            } else {
                std::ptr::null_mut()
            }),
        }
    }

    /// Whether it describes a list of `entries` main entries (with
    /// `friction`: the springs too).
    pub fn fits(&self, entries: usize, friction: bool) -> bool {
        self.energy.len() == entries && (!friction || self.spring.len() == entries)
    }
}

/// Where a tallying force pass writes each touching entry's terms
/// ([`EntryTally`]); null pointers: not asked.
#[derive(Clone, Copy)]
pub(crate) struct EntryTerms {
    energy: SharedMut<f64>,
    spring: SharedMut<f64>,
}

impl EntryTerms {
    /// Nothing asked.
    pub(crate) const NONE: EntryTerms = EntryTerms {
        energy: SharedMut(std::ptr::null_mut()),
        spring: SharedMut(std::ptr::null_mut()),
    };

    /// Whether a rank asked for the terms (the pointers are set).
    #[inline(always)]
    pub(crate) fn asked(&self) -> bool {
        !self.energy.0.is_null()
    }

    /// Entry k's elastic energy (J), when asked.
    ///
    /// # Safety
    /// k is a main entry of the list [`EntryTally::prepare`] was given,
    /// and no other thread writes entry k meanwhile (its row's block
    /// alone visits it).
    #[inline(always)]
    pub(crate) unsafe fn energy(&self, k: usize, energy: f64) {
        if !self.energy.0.is_null() {
            *self.energy.at(k) = energy;
        }
    }

    /// Entry k's elastic energy and springs' energy (J), when asked.
    ///
    /// # Safety
    /// As [`Self::energy`].
    #[inline(always)]
    pub(crate) unsafe fn energy_and_spring(&self, k: usize, energy: f64, spring: f64) {
        if !self.energy.0.is_null() {
            *self.energy.at(k) = energy;
        }
        if !self.spring.0.is_null() {
            *self.spring.at(k) = spring;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The mark is no result of arithmetic: NaNs from invalid operations
    /// and NaNs carried through operations are quiet, the mark is not.
    #[test]
    fn apart_is_no_computed_value() {
        let zero = std::hint::black_box(0.0f64);
        let made = [
            zero / zero,
            f64::INFINITY - f64::INFINITY,
            (-1.0f64).sqrt(),
            APART + 1.0,
            APART * 2.0,
            -APART,
            f64::NAN,
            0.0,
            -0.0,
        ];
        assert!(apart(APART));
        for x in made {
            assert!(!apart(x), "{:#x}", x.to_bits());
        }
    }
}
