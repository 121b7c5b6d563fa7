//! The body store: spheres, free and fixed, as a structure of arrays.
//!
//! Bodies are reordered by neighbour cell at every list rebuild
//! ([`Bodies::permute`]); `id` keeps each body's input index so that
//! outputs are always in input order.

use crate::parallel::{SharedMut, Workers, STEP_CHUNK};

/// Marker of "no group" in [`Bodies::group`].
pub const NO_GROUP: u32 = u32::MAX;

/// Marker of a removed sphere's input index in [`Bodies::index_of_ids`].
pub const REMOVED: u32 = u32::MAX;

/// Per-body arrays, all of the same length.
#[derive(Debug, Clone, Default)]
pub struct Bodies {
    /// Centre, m.
    pub position: Vec<[f64; 3]>,
    /// m/s (0 for fixed bodies).
    pub velocity: Vec<[f64; 3]>,
    /// Total force of the last force evaluation, N: contacts, walls and
    /// gravity (fixed bodies: contacts only).
    pub force: Vec<[f64; 3]>,
    /// m.
    pub radius: Vec<f64>,
    /// kg; `f64::INFINITY` for a fixed body.
    pub mass: Vec<f64>,
    /// 1/kg; 0 for a fixed body.
    pub inverse_mass: Vec<f64>,
    /// Material index.
    pub material: Vec<u32>,
    /// Fixed (boundary particle): infinite mass, never moves.
    pub fixed: Vec<bool>,
    /// Input index, stable across reordering.
    pub id: Vec<u32>,
    /// Wall index of a boundary particle, [`NO_GROUP`] otherwise.
    pub group: Vec<u32>,
    /// Pair-law class (see `dynamics::contacts::LawTable`).
    pub class: Vec<u16>,
    /// Gear5 only: the scaled derivatives r₂..r₅ (r_k = Δt^k x⁽ᵏ⁾/k!).
    pub higher: Vec<[[f64; 3]; 4]>,
    /// Angular velocity ω, rad/s (0 for fixed bodies; stays 0 without
    /// friction).
    pub angular_velocity: Vec<[f64; 3]>,
    /// Total torque of the last force evaluation, N m (friction only).
    pub torque: Vec<[f64; 3]>,
    /// 1/I with I = 2/5 m R² (a solid sphere), 1/(kg m²); 0 for a fixed body.
    pub inverse_inertia: Vec<f64>,
    /// Gear5 with friction only: the spin's scaled derivatives r₁..r₄
    /// (r_k = Δt^k ω⁽ᵏ⁾/k!, rad/s; `dynamics::gear5_rotation`).
    pub angular_higher: Vec<[[f64; 3]; 4]>,
}

impl Bodies {
    pub fn len(&self) -> usize {
        self.position.len()
    }

    pub fn is_empty(&self) -> bool {
        self.position.is_empty()
    }

    /// Room for exactly `n` bodies in the arrays every scene fills (pushing
    /// into a growing array leaves up to twice the room: 10⁷ spheres would
    /// hold 1.7× their per-body memory).
    pub fn reserve_exact(&mut self, n: usize) {
        self.position.reserve_exact(n);
        self.velocity.reserve_exact(n);
        self.force.reserve_exact(n);
        self.radius.reserve_exact(n);
        self.mass.reserve_exact(n);
        self.inverse_mass.reserve_exact(n);
        self.angular_velocity.reserve_exact(n);
        self.torque.reserve_exact(n);
        self.inverse_inertia.reserve_exact(n);
        self.material.reserve_exact(n);
        self.fixed.reserve_exact(n);
        self.id.reserve_exact(n);
        self.group.reserve_exact(n);
    }

    /// Reorders every array so that new body k is old body `order[k]`
    /// (a subset of the bodies keeps those only).
    pub fn permute(&mut self, order: &[u32]) {
        self.permute_on(order, &Workers::serial());
    }

    /// [`Self::permute`] with the gathers shared among `workers`, each
    /// chunk of the new order gathering every field (a copy: the same
    /// values whatever the threads). An empty field stays empty.
    pub fn permute_on(&mut self, order: &[u32], workers: &Workers) {
        let n = order.len();
        // One field at a time: the old array is freed before the next
        // one is gathered, so a rebuild holds the body arrays plus one
        // field (gathering them all at once held two copies of every
        // array: a 10⁷-sphere lattice's peak RSS was 96 B a sphere higher).
        macro_rules! gather_fields {
            ($($f:ident),*) => {
                $(if let Some(&first) = self.$f.first() {
                    let mut gathered = vec![first; n];
                    {
                        let (dst, src) = (SharedMut::new(&mut gathered), &self.$f[..]);
                        workers.run_bodies(n, STEP_CHUNK, |c| {
                            for k in c * STEP_CHUNK..((c + 1) * STEP_CHUNK).min(n) {
                                // SAFETY: chunk c writes entries k of its
                                // own range only; the gathered field holds
                                // n entries.
                                unsafe { *dst.at(k) = src[order[k] as usize] };
                            }
                        });
                    }
                    self.$f = gathered;
                })*
            };
        }
        gather_fields!(
            position,
            velocity,
            force,
            radius,
            mass,
            inverse_mass,
            material,
            fixed,
            id,
            group,
            class,
            higher,
            angular_velocity,
            torque,
            inverse_inertia,
            angular_higher
        );
    }

    /// Body index of each input index (the inverse of `id`); after
    /// spheres were removed (`crate::removal`), [`REMOVED`] at theirs.
    pub fn index_of_ids(&self) -> Vec<u32> {
        let bound = self.id.iter().max().map_or(0, |&m| m as usize + 1);
        let mut at = vec![REMOVED; bound.max(self.len())];
        for (k, &id) in self.id.iter().enumerate() {
            at[id as usize] = k as u32;
        }
        at
    }

    /// Whether every input index below the body count is here (no sphere
    /// was removed).
    fn dense(&self) -> bool {
        let n = self.len();
        self.id.iter().all(|&id| (id as usize) < n)
    }

    /// One per-body array in input order (after spheres were removed,
    /// those still here in input order).
    pub fn in_input_order<T: Copy>(&self, values: &[T]) -> Vec<T> {
        if !self.dense() {
            let mut by_id: Vec<usize> = (0..self.len()).collect();
            by_id.sort_unstable_by_key(|&k| self.id[k]);
            return by_id.into_iter().map(|k| values[k]).collect();
        }
        let mut out: Vec<T> = values.to_vec();
        for (k, &id) in self.id.iter().enumerate() {
            out[id as usize] = values[k];
        }
        out
    }

    /// The input indices of the bodies still here, ascending (all of
    /// 0..n unless spheres were removed).
    pub fn ids_in_input_order(&self) -> Vec<u32> {
        let mut ids = self.id.clone();
        ids.sort_unstable();
        ids
    }
}

#[cfg(test)]
mod permute_tests {
    use super::*;

    /// The gather moves every field to where the order says (the
    /// expected bodies pushed here one by one from `order`), for a
    /// reversal with strides and for a subset, on 1, 2 and 3 threads;
    /// empty fields stay empty.
    #[test]
    fn permute_moves_every_field_on_any_thread_count() {
        let n = 5000;
        let mut b = Bodies::default();
        for k in 0..n {
            let x = k as f64;
            b.position.push([x, 2.0 * x, 3.0 * x]);
            b.velocity.push([-x, 0.5, x]);
            b.force.push([x * x, 1.0, 0.0]);
            b.radius.push(1.0 + x);
            b.mass.push(2.0 + x);
            b.inverse_mass.push(1.0 / (2.0 + x));
            b.material.push((k % 3) as u32);
            b.fixed.push(k % 5 == 0);
            b.id.push(k as u32);
            b.group.push(NO_GROUP);
            b.class.push((k % 7) as u16);
            b.angular_velocity.push([x, -x, 0.25]);
            b.torque.push([0.0, x, 1.0]);
            b.inverse_inertia.push(3.0 + x);
        }
        let reversed: Vec<u32> = (0..n as u32).map(|k| (k * 7) % n as u32).rev().collect();
        let subset: Vec<u32> = (0..n as u32).step_by(3).collect();
        for order in [reversed, subset] {
            let mut expected = Bodies::default();
            for &o in &order {
                let o = o as usize;
                expected.position.push(b.position[o]);
                expected.velocity.push(b.velocity[o]);
                expected.force.push(b.force[o]);
                expected.radius.push(b.radius[o]);
                expected.mass.push(b.mass[o]);
                expected.inverse_mass.push(b.inverse_mass[o]);
                expected.material.push(b.material[o]);
                expected.fixed.push(b.fixed[o]);
                expected.id.push(b.id[o]);
                expected.group.push(b.group[o]);
                expected.class.push(b.class[o]);
                expected.angular_velocity.push(b.angular_velocity[o]);
                expected.torque.push(b.torque[o]);
                expected.inverse_inertia.push(b.inverse_inertia[o]);
            }
            let mut serial = b.clone();
            serial.permute(&order);
            assert_eq!(format!("{serial:?}"), format!("{expected:?}"));
            for threads in [2, 3] {
                let workers = Workers::new(threads).expect("threads start");
                let mut shared = b.clone();
                shared.permute_on(&order, &workers);
                assert_eq!(
                    format!("{shared:?}"),
                    format!("{expected:?}"),
                    "{threads} threads"
                );
                assert_eq!(shared.id.len(), order.len());
                assert!(shared.higher.is_empty());
            }
        }
    }
}
