//! The force blocks on two workers, taken from both ends of the list
//! until the workers meet (`run_blocks_then` with two threads): no share
//! to balance, each worker does what the other has not reached. Which
//! worker runs a block never changes what the block computes: the bits
//! do not depend on it.

use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};

use crate::geometry::neighbour::PairList;
use crate::parallel::Workers;

/// Two workers take the blocks from both ends of the list, worker 0 from
/// block 0 up, worker 1 from the last block down, until they meet: no
/// share to balance, each does what the other has not. Unit k is even
/// block 2k and the odd block on the taker's side of it (2k − 1 going up,
/// 2k + 1 going down; its other even neighbour the taker's own last
/// unit). Worker 0's units below last step's meeting (less a margin,
/// at least one unit when there are two) are its own without a claim;
/// every other unit is claimed one at a time (an atomic pair of ends),
/// worker 1's included, so that worker 0, the caller, which always runs,
/// can take them all when worker 1 has not started (a busy machine: its
/// core taken), and the stage then ends without waiting for it to start
/// ([`Workers::broadcast_present`]). On its own core worker 1 claims its
/// units from the top, each a compare-and-swap on a line it alone
/// touches until the two meet.
/// The odd block where they meet is run by the first worker to find
/// nothing left to claim. `follow_block(c)` runs once for each block c
/// as soon as c and c − 1 are done, by the worker that ran the odd one
/// of the two (or block 0, for c = 0).
///
/// Why no follow-up can be missed, with no final pass waiting for the
/// rest: of the blocks c − 1 and c that follow-up c needs, one is odd,
/// b, and the worker that runs b has first waited until its even
/// neighbours b − 1 and b + 1 were done (an Acquire load that saw the
/// flag set; `run_blocks_then`'s `run`). Right after b, that worker tries
/// follow-ups b and b + 1 (`unit`, and the meeting's odd block below):
/// for each, one flag is its own store and the other one it has already
/// seen set, and a later load of a flag never set back cannot see it
/// clear (coherence of one location). So `complete` holds there for
/// both, and the swap of `followed` lets exactly one worker run it.
/// Follow-up 0 (block 0 alone) is tried by whoever runs block 0. There
/// is no store–load race in which both workers miss a completed pair:
/// that would need two blocks that neither waits for, and the two
/// blocks of a follow-up are an odd one and an even one it waits for.
pub(super) fn run(
    workers: &Workers,
    list: &PairList,
    run: &(dyn Fn(usize) + Sync),
    complete: &(dyn Fn(usize) -> bool + Sync),
    follow_block: &(dyn Fn(usize) -> f64 + Sync),
) -> f64 {
    let blocks = list.blocks.len() - 1;
    let units = blocks.div_ceil(2);
    let last = list.shares.meet.load(Ordering::Relaxed);
    let last = if last == usize::MAX {
        list.shares
            .blocks(1, 2)
            .map_or(units / 2, |(first, _)| first / 2)
    } else {
        last
    }
    .min(units);
    let margin = (units / 8).max(1);
    let mut lo0 = last.saturating_sub(margin);
    if units >= 2 {
        // Worker 0 keeps a unit at its end; worker 1's are all claimed
        // (none is left to a worker that may not come).
        lo0 = lo0.clamp(1, units - 1);
    }
    let hi0 = units.max(lo0);
    let pack = |lo: usize, hi: usize| (lo as u64) | ((hi as u64) << 32);
    let ends = AtomicU64::new(pack(lo0, hi0));
    let first_out = AtomicBool::new(false);
    let followed: Vec<AtomicBool> = (0..blocks).map(|_| AtomicBool::new(false)).collect();
    let try_follow = |c: usize, value: &mut f64| {
        if c < blocks && complete(c) && !followed[c].swap(true, Ordering::AcqRel) {
            *value = value.max(follow_block(c));
        }
    };
    // Each block's listed pairs, for the stages' trace.
    let traced = |b: usize| {
        if b < blocks && crate::parallel::trace::on() {
            let (lo, hi) = (list.blocks[b] as usize, list.blocks[b + 1] as usize);
            crate::parallel::trace::add_units(u64::from(list.start[hi] - list.start[lo]));
        }
    };
    let run = |b: usize| {
        run(b);
        traced(b);
    };
    workers
        .broadcast_present(|t| {
            let up = t == 0;
            let mut value = 0.0f64;
            let unit = |k: usize, value: &mut f64| {
                run(2 * k);
                if up {
                    if k > 0 {
                        run(2 * k - 1);
                        try_follow(2 * k - 1, value);
                    }
                    try_follow(2 * k, value);
                    try_follow(2 * k + 1, value);
                } else {
                    if 2 * k + 1 < blocks {
                        run(2 * k + 1);
                    }
                    try_follow(2 * k + 1, value);
                    try_follow(2 * k + 2, value);
                    try_follow(2 * k, value);
                }
            };
            if up {
                for k in 0..lo0 {
                    unit(k, &mut value);
                }
            }
            let mut now = ends.load(Ordering::Acquire);
            let meet = loop {
                let (lo, hi) = ((now & 0xffff_ffff) as usize, (now >> 32) as usize);
                if lo >= hi {
                    break lo;
                }
                let (k, next) = if up {
                    (lo, pack(lo + 1, hi))
                } else {
                    (hi - 1, pack(lo, hi - 1))
                };
                match ends.compare_exchange_weak(now, next, Ordering::AcqRel, Ordering::Acquire) {
                    Ok(_) => {
                        unit(k, &mut value);
                        now = ends.load(Ordering::Acquire);
                    }
                    Err(seen) => now = seen,
                }
            };
            if !first_out.swap(true, Ordering::AcqRel) {
                // The odd block where the two met (it waits for the
                // other's last even block).
                if meet >= 1 && 2 * meet - 1 < blocks {
                    run(2 * meet - 1);
                    try_follow(2 * meet - 1, &mut value);
                    try_follow(2 * meet, &mut value);
                }
                list.shares.meet.store(meet, Ordering::Relaxed);
            }
            // No follow-up is left for after the claims: each was tried by
            // a worker that had seen both its blocks done (see `run`'s
            // doc), so no final pass waits for any.
            value
        })
        .into_iter()
        .fold(0.0, f64::max)
}

#[cfg(test)]
mod tests {
    use std::sync::atomic::{AtomicUsize, Ordering};

    use crate::balance::Shares;
    use crate::dynamics::contacts::run_blocks_then;
    use crate::geometry::neighbour::PairList;
    use crate::parallel::Workers;

    /// `count` blocks of 10 bodies, no pairs, shares for two workers.
    fn list(count: usize) -> PairList {
        let blocks: Vec<u32> = (0..=count as u32).map(|b| 10 * b).collect();
        let start = vec![0u32; 10 * count + 1];
        PairList {
            shares: Shares::new(2, &blocks, &start),
            start,
            blocks,
            ..PairList::default()
        }
    }

    /// Two workers from both ends, for 2 to 13 blocks and every place the
    /// last meeting may leave them: every block runs once, an odd block
    /// after both its even neighbours, each block's follow-up once, after
    /// the block and the one before it (all that write its bodies' forces
    /// or read their positions) and before the block after it starts
    /// nowhere (that one never reads them); the follow-ups' maximum is
    /// returned, the meeting kept. The order the engine relies on for its
    /// bits (`run_blocks_then`), checked by the blocks themselves.
    #[test]
    fn two_workers_run_every_block_once_in_the_blocks_order() {
        let workers = Workers::new(2).expect("threads start");
        for count in 2usize..=13 {
            let units = count.div_ceil(2);
            for last in (0..=units).chain([usize::MAX]) {
                let list = list(count);
                list.shares.meet.store(last, Ordering::Relaxed);
                let ran: Vec<AtomicUsize> = (0..count).map(|_| AtomicUsize::new(0)).collect();
                let followed: Vec<AtomicUsize> = (0..count).map(|_| AtomicUsize::new(0)).collect();
                let block = |b: usize| {
                    assert_eq!(ran[b].load(Ordering::SeqCst), 0, "block {b} twice");
                    if b % 2 == 1 {
                        assert_eq!(ran[b - 1].load(Ordering::SeqCst), 1, "{b} before {}", b - 1);
                        if b + 1 < count {
                            assert_eq!(
                                ran[b + 1].load(Ordering::SeqCst),
                                1,
                                "{b} before {}",
                                b + 1
                            );
                        }
                    }
                    // Block b reads and writes bodies of b and b + 1.
                    for c in [b, b + 1] {
                        if c < count {
                            assert_eq!(
                                followed[c].load(Ordering::SeqCst),
                                0,
                                "{c} followed before {b} ran"
                            );
                        }
                    }
                    ran[b].fetch_add(1, Ordering::SeqCst);
                };
                let follow = |lo: usize, hi: usize| -> f64 {
                    let c = lo / 10;
                    assert_eq!(hi, lo + 10);
                    assert_eq!(
                        ran[c].load(Ordering::SeqCst),
                        1,
                        "{c} followed before it ran"
                    );
                    if c > 0 {
                        assert_eq!(
                            ran[c - 1].load(Ordering::SeqCst),
                            1,
                            "{c} followed before {}",
                            c - 1
                        );
                    }
                    followed[c].fetch_add(1, Ordering::SeqCst);
                    c as f64
                };
                let value = run_blocks_then(&workers, &list, block, Some(&follow));
                for (b, (r, f)) in ran.iter().zip(&followed).enumerate() {
                    assert_eq!(r.load(Ordering::SeqCst), 1, "block {b} of {count}");
                    assert_eq!(f.load(Ordering::SeqCst), 1, "follow-up {b} of {count}");
                }
                assert_eq!(value, (count - 1) as f64);
                // Worker 0 keeps at least one unit (two or more units);
                // worker 1 may have run none (it came late).
                let meet = list.shares.meet.load(Ordering::Relaxed);
                assert!(meet <= units);
                if units >= 2 {
                    assert!(
                        (1..=units).contains(&meet),
                        "met at {meet} of {units} units"
                    );
                }
            }
        }
    }
}
