//! Spring storage: the tangential and rolling springs of the pairs
//! (aligned with the pair list) and of the wall contacts, and their
//! transfer across list rebuilds and checkpoints by input ids.

use std::collections::HashMap;
use std::hash::BuildHasher;

use serde::{Deserialize, Serialize};

use crate::bodies::Bodies;
use crate::dynamics::contacts::extended;
use crate::geometry::ghosts::Ghosts;
use crate::geometry::neighbour::PairList;

/// The springs of one contact as saved in checkpoints and carried across
/// rebuilds: the tangential displacement of body 1's contact point
/// relative to body 2's (m, components 0..3) and the rolling spring's
/// torque on body 1 (N m, components 3..6). Seen from body 2 both change
/// sign.
pub type Springs = [f64; 6];

fn negate(s: Springs) -> Springs {
    s.map(|x| -x)
}

pub(super) fn split(s: &mut Springs) -> (&mut [f64; 3], &mut [f64; 3]) {
    let (a, b) = s.split_at_mut(3);
    // Infallible: 6 = 3 + 3.
    (
        a.try_into().unwrap_or_else(|_| unreachable!()),
        b.try_into().unwrap_or_else(|_| unreachable!()),
    )
}

/// Contact springs aligned with a [`PairList`] (like [`PairHistories`]),
/// seen from the row body i: the tangential displacements (`main`,
/// `extra`) and, only when some surface rolls, the rolling spring torques
/// (`roll_main`, `roll_extra`; empty otherwise, so that a scene without
/// rolling friction stores and touches 3 doubles per listed pair, not 6).
#[derive(Debug, Clone, Default)]
pub struct PairShear {
    pub main: Vec<[f64; 3]>,
    pub extra: Vec<[f64; 3]>,
    pub roll_main: Vec<[f64; 3]>,
    pub roll_extra: Vec<[f64; 3]>,
    /// The rolling springs are kept.
    pub rolling: bool,
}

impl PairShear {
    /// Appends an extra pair with relaxed springs.
    pub fn push_extra(&mut self) {
        self.extra.push([0.0; 3]);
        if self.rolling {
            self.roll_extra.push([0.0; 3]);
        }
    }

    fn springs(shear: [f64; 3], roll: Option<&[f64; 3]>) -> Springs {
        let r = roll.copied().unwrap_or([0.0; 3]);
        [shear[0], shear[1], shear[2], r[0], r[1], r[2]]
    }
}

/// A sphere–plane contact's springs with the values they had before the
/// step `stamp` moved them: evaluating the same step's forces twice (the
/// per-body pass again after a list rebuild) starts again from `before`.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct WallShear {
    pub shear: Springs,
    pub before: Springs,
    pub stamp: u64,
}

/// The springs of the pairs in contact, by input ids (a < b), seen from a.
pub fn active_shear(
    bodies: &Bodies,
    ghosts: &Ghosts,
    list: &PairList,
    shear: &PairShear,
) -> Vec<(u32, u32, Springs)> {
    let mut out = Vec::new();
    for_each_active(bodies, ghosts, list, shear, |a, b, s| out.push((a, b, s)));
    out.sort_by_key(|x| (x.0, x.1));
    out
}

/// [`active_shear`] straight into a map by (a, b), without the sorted list
/// beside it (a rebuild's saved springs: one copy of them at a time, not
/// two). A pair met twice keeps its last springs, as [`active_shear`]'s
/// stable sort collected into a map does.
pub fn active_shear_map<S: BuildHasher + Default>(
    bodies: &Bodies,
    ghosts: &Ghosts,
    list: &PairList,
    shear: &PairShear,
) -> HashMap<(u32, u32), Springs, S> {
    let mut out = HashMap::default();
    for_each_active(bodies, ghosts, list, shear, |a, b, s| {
        out.insert((a, b), s);
    });
    out
}

/// Calls `f(a, b, springs)` for each listed pair whose springs are not all
/// zero, by input ids (a < b), seen from a, in list order; nothing when
/// `shear` is not aligned with `list`.
fn for_each_active(
    bodies: &Bodies,
    ghosts: &Ghosts,
    list: &PairList,
    shear: &PairShear,
    mut f: impl FnMut(u32, u32, Springs),
) {
    let n = bodies.len();
    if list.start.len() != n + 1
        || shear.main.len() != list.j.len()
        || shear.extra.len() != list.extra.len()
    {
        return;
    }
    let mut push = |i: usize, owner: usize, s: Springs| {
        if s != [0.0; 6] {
            let (a, b) = (bodies.id[i], bodies.id[owner]);
            if a < b {
                f(a, b, s);
            } else {
                f(b, a, negate(s));
            }
        }
    };
    for i in 0..n {
        for k in list.start[i] as usize..list.start[i + 1] as usize {
            let s = PairShear::springs(shear.main[k], shear.roll_main.get(k));
            push(i, list.j[k] as usize, s);
        }
    }
    for (k, &(i, j)) in list.extra.iter().enumerate() {
        let (_, _, owner) = extended(bodies, ghosts, j as usize);
        let s = PairShear::springs(shear.extra[k], shear.roll_extra.get(k));
        push(i as usize, owner, s);
    }
}

/// Displacements for a new list from `saved` (by input ids, as
/// [`active_shear`] gives them), under any hasher (the rebuild's Fx maps,
/// a checkpoint's standard one); `rolling`: keep the rolling springs
/// ([`FrictionTable::rolling`]).
pub fn restore_shear<S: BuildHasher>(
    bodies: &Bodies,
    ghosts: &Ghosts,
    list: &PairList,
    saved: &HashMap<(u32, u32), Springs, S>,
    rolling: bool,
) -> PairShear {
    let mut main = vec![[0.0; 3]; list.j.len()];
    let mut extra = vec![[0.0; 3]; list.extra.len()];
    let (mut roll_main, mut roll_extra) = if rolling {
        (
            vec![[0.0; 3]; list.j.len()],
            vec![[0.0; 3]; list.extra.len()],
        )
    } else {
        (Vec::new(), Vec::new())
    };
    if !saved.is_empty() {
        let get = |i: usize, j_ext: usize| -> Option<Springs> {
            let (_, _, owner) = extended(bodies, ghosts, j_ext);
            let (a, b) = (bodies.id[i], bodies.id[owner]);
            if a < b {
                saved.get(&(a, b)).copied()
            } else {
                saved.get(&(b, a)).map(|s| negate(*s))
            }
        };
        let put = |s: Springs, shear: &mut [f64; 3], roll: Option<&mut [f64; 3]>| {
            *shear = [s[0], s[1], s[2]];
            if let Some(r) = roll {
                *r = [s[3], s[4], s[5]];
            }
        };
        for (i, k) in list.entries() {
            if let Some(s) = get(i, list.j[k] as usize) {
                put(s, &mut main[k], roll_main.get_mut(k));
            }
        }
        for (k, &(i, j)) in list.extra.iter().enumerate() {
            if let Some(s) = get(i as usize, j as usize) {
                put(s, &mut extra[k], roll_extra.get_mut(k));
            }
        }
    }
    PairShear {
        main,
        extra,
        roll_main,
        roll_extra,
        rolling,
    }
}

#[cfg(test)]
mod tests {
    use super::{active_shear, active_shear_map};
    use crate::dynamics::friction_observables::tests::scene;
    use crate::Simulation;
    use std::collections::{HashMap, HashSet};

    /// A rebuild's saved springs (`active_shear_map`) are exactly the
    /// listed pairs whose tangential or rolling spring is not all zero,
    /// keyed by input ids (a < b) and seen from a (negated when the row's
    /// body has the larger id): the reference is written entry by entry
    /// from the list and the springs, and `active_shear` (the checkpoints'
    /// sorted list) holds the same, along the settling bed with Mindlin
    /// and rolling friction.
    #[test]
    fn saved_springs_are_the_listed_pairs_with_loaded_springs() {
        let mut sim = Simulation::new(scene(), 1).unwrap();
        let (mut loaded, mut relaxed, mut rolling_only) = (0, 0, 0);
        for round in 0..20 {
            sim.step(50);
            if round == 19 {
                // A contact whose tangential spring is zero and rolling
                // spring is not (rare in a run: made here) is saved too.
                let w = &mut sim.world;
                let k = (0..w.shear.main.len())
                    .find(|&k| w.shear.main[k] != [0.0; 3])
                    .expect("a loaded spring");
                w.shear.main[k] = [0.0; 3];
                w.shear.roll_main[k] = [1.0e-9, -2.0e-9, 0.0];
            }
            let w = &sim.world;
            let (b, list, shear) = (&w.bodies, &w.list, &w.shear);
            assert!(shear.rolling && list.extra.is_empty());
            let mut expected = HashMap::new();
            for i in 0..b.len() {
                for k in list.start[i] as usize..list.start[i + 1] as usize {
                    let j = list.j[k] as usize;
                    let (t, r) = (shear.main[k], shear.roll_main[k]);
                    let s = [t[0], t[1], t[2], r[0], r[1], r[2]];
                    if s.iter().all(|&x| x == 0.0) {
                        relaxed += 1;
                        continue;
                    }
                    if t == [0.0; 3] {
                        rolling_only += 1;
                    }
                    let (a, c) = (b.id[i], b.id[j]);
                    let key = (a.min(c), a.max(c));
                    let seen = if a < c { s } else { s.map(|x| -x) };
                    assert!(expected.insert(key, seen).is_none(), "{key:?} twice");
                    loaded += 1;
                }
            }
            let map: HashMap<(u32, u32), [f64; 6]> = active_shear_map(b, &w.ghosts, list, shear);
            let bits = |m: &HashMap<(u32, u32), [f64; 6]>| -> HashSet<((u32, u32), [u64; 6])> {
                m.iter().map(|(&k, s)| (k, s.map(f64::to_bits))).collect()
            };
            assert!(bits(&map) == bits(&expected));
            let sorted: HashMap<_, _> = active_shear(b, &w.ghosts, list, shear)
                .into_iter()
                .map(|(a, c, s)| ((a, c), s))
                .collect();
            assert!(bits(&sorted) == bits(&expected));
        }
        // Loaded springs and listed pairs apart (relaxed springs) both met.
        assert!(
            loaded > 1000 && relaxed > 1000,
            "{loaded} {relaxed} {rolling_only}"
        );
    }
}
