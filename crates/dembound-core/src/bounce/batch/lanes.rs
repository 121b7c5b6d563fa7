//! The lanes' state: one value per lane in memory ([`Lanes`], [`State`])
//! and in registers ([`Hot`], [`Geometry`]).

use super::simd::{self, Simd, V};
use crate::integrate::{Gear5, Gear5State};

/// Most lanes a kernel has.
pub(super) const MAX_LANES: usize = 16;
/// One value per lane, in memory.
///
/// Aligned to 64 bytes, as is everything the step loop holds: a register
/// load or store across two cache lines (as a 64-byte value at a 16-byte
/// aligned address is, three times in four) made the loop up to 25%
/// slower, depending on where the stack happened to be.
#[derive(Debug, Clone, Copy, PartialEq)]
#[repr(C, align(64))]
pub(super) struct Lanes(pub(super) [f64; MAX_LANES]);

impl Lanes {
    pub(super) const fn splat(x: f64) -> Self {
        Lanes([x; MAX_LANES])
    }
}

impl std::ops::Deref for Lanes {
    type Target = [f64];
    fn deref(&self) -> &[f64] {
        &self.0
    }
}

impl std::ops::DerefMut for Lanes {
    fn deref_mut(&mut self) -> &mut [f64] {
        &mut self.0
    }
}

/// The lanes' state that every step reads and writes, in memory (for the
/// events; the step loop keeps it in registers, [`Hot`]).
#[derive(Clone, Copy)]
pub(super) struct State {
    /// The corrected Nordsieck vector and the next prediction
    /// ([`Gear5State`]).
    pub(super) r: [Lanes; 6],
    pub(super) next: [Lanes; 6],
    /// The step size `r` is scaled for.
    pub(super) dt: Lanes,
    /// The current step, in τ = t − t_c.
    pub(super) tau_start: Lanes,
    pub(super) tau_end: Lanes,
    /// The smallest (most negative) position at a step end of this contact.
    pub(super) min_position: Lanes,
}

impl State {
    pub(super) fn new() -> Self {
        let z = Lanes::splat(0.0);
        State {
            r: [z; 6],
            next: [z; 6],
            dt: Lanes::splat(1.0),
            tau_start: z,
            tau_end: z,
            min_position: z,
        }
    }

    /// Lane `l` as the scalar path's state.
    pub(super) fn gear(&self, l: usize, gear: &Gear5) -> Gear5State {
        let dt = self.dt[l];
        let half_dt2 = 0.5 * dt * dt;
        let (mut r, mut next) = ([0.0; 6], [0.0; 6]);
        for k in 0..6 {
            r[k] = self.r[k][l];
            next[k] = self.next[k][l];
        }
        Gear5State {
            r,
            dt,
            half_dt2,
            inv_dt: 1.0 / dt,
            gain: gear.predicted_corrector[0] * half_dt2,
            next,
        }
    }

    /// Lane `l` idle: a state that stays put.
    pub(super) fn set_idle(&mut self, l: usize) {
        for k in 0..6 {
            self.r[k][l] = 0.0;
            self.next[k][l] = 0.0;
        }
        self.dt[l] = 1.0;
        self.tau_start[l] = 0.0;
        self.tau_end[l] = 0.0;
        self.min_position[l] = 0.0;
    }
}

/// The sizes of a step and the factors that depend on them alone.
#[derive(Clone, Copy)]
pub(super) struct Geometry<S: Simd, const G: usize> {
    pub(super) tau_end: V<S, G>,
    pub(super) len: V<S, G>,
    /// Where the size changes.
    pub(super) resize: simd::Mask<S, G>,
    /// The size's ratio to the last one, to the powers 1 to 5.
    pub(super) power: [V<S, G>; 5],
    pub(super) half_dt2: V<S, G>,
    /// The law's stiffness over m times the gain.
    pub(super) k_step: V<S, G>,
}

/// [`State`] in registers.
#[derive(Clone, Copy)]
pub(super) struct Hot<S: Simd, const G: usize> {
    pub(super) r: [V<S, G>; 6],
    pub(super) next: [V<S, G>; 6],
    pub(super) dt: V<S, G>,
    pub(super) tau_start: V<S, G>,
    pub(super) tau_end: V<S, G>,
    pub(super) min_position: V<S, G>,
}

impl<S: Simd, const G: usize> Hot<S, G> {
    #[inline(always)]
    pub(super) fn load(s: S, m: &State) -> Self {
        let v = |x: &Lanes| V::load(s, x);
        Hot {
            r: [
                v(&m.r[0]),
                v(&m.r[1]),
                v(&m.r[2]),
                v(&m.r[3]),
                v(&m.r[4]),
                v(&m.r[5]),
            ],
            next: [
                v(&m.next[0]),
                v(&m.next[1]),
                v(&m.next[2]),
                v(&m.next[3]),
                v(&m.next[4]),
                v(&m.next[5]),
            ],
            dt: v(&m.dt),
            tau_start: v(&m.tau_start),
            tau_end: v(&m.tau_end),
            min_position: v(&m.min_position),
        }
    }

    #[inline(always)]
    pub(super) fn store(&self, m: &mut State) {
        for k in 0..6 {
            self.r[k].store(&mut m.r[k]);
            self.next[k].store(&mut m.next[k]);
        }
        self.dt.store(&mut m.dt);
        self.tau_start.store(&mut m.tau_start);
        self.tau_end.store(&mut m.tau_end);
        self.min_position.store(&mut m.min_position);
    }
}
