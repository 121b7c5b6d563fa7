#!/usr/bin/env python3
"""How well two workers can share the force stage, from its blocks alone
(issue 31 item 3: why two threads give less at 10k spheres than at 100k).

The frictionless force stage runs the pair list's blocks (contiguous
bodies, each block's pairs reaching at most into the next one) from both
ends, two workers claiming a unit (an even block and its odd neighbour)
at a time until they meet; the odd block where they meet goes to the
first one out, and each block's bodies are advanced by the worker that ran
the odd one of it and the block below (`dynamics/contacts/both_ends.rs`).
A block cannot be thinner than the pairs' reach (one cell layer: bodies
within a cut-off of the block above), so the stage's granularity is set
by the scene, not by a constant.

This replays that schedule with each block's cost modelled from the
one-thread profile of the 10k lattice drop (perf, session 36): 72 % of a
step in the pair rows (cost ∝ listed pairs), 19 % advancing the bodies
(∝ bodies), the remaining 9 % taken as perfectly shared. Hand-offs,
waits and cache traffic cost nothing here: the result is an upper bound
on the two-thread speed-up from the blocks' granularity alone.

Input: the lines `team trace: force blocks: bodies [...] pairs [...]`
that a run prints to standard error with DEMBOUND_TEAM_TRACE set and two
threads (one line per list build), e.g.

  DEMBOUND_TEAM_TRACE=1 target/release/dembound scene \\
      examples/scenes/lattice_drop_data.toml \\
      --set particles.0.lammps_data=lattice_10k.data \\
      --set integration.steps=10000 -q --json --threads 2 2> trace.txt
  python3 scripts/two_ends_bound.py trace.txt

Also prints the bound if every block were split in two (what a finer
decomposition would give).
"""

import re
import statistics
import sys

PAIRS, ADVANCE, REST = 0.72, 0.19, 0.09


def blocks_of(path):
    for line in open(path, encoding="utf-8"):
        if "force blocks:" in line:
            bodies, pairs = re.findall(r"\[([^\]]*)\]", line)
            yield ([float(x) for x in bodies.split(",")],
                   [float(x) for x in pairs.split(",")])


def both_ends(bodies, pairs):
    """Makespan of the two-ends schedule over the one-worker time."""
    n = len(bodies)
    per_pair = PAIRS / max(sum(pairs), 1.0)
    per_body = ADVANCE / max(sum(bodies), 1.0)

    def cost(b):
        c = per_pair * pairs[b]
        if b % 2 == 1:  # the odd block's worker advances b and b + 1
            c += per_body * (bodies[b] + (bodies[b + 1] if b + 1 < n else 0.0))
        if b == 0:
            c += per_body * bodies[0]
        return c

    t = [0.0, 0.0]
    lo, hi = 0, (n + 1) // 2
    while lo < hi:
        if t[0] <= t[1]:
            k, lo = lo, lo + 1
            t[0] += cost(2 * k) + (cost(2 * k - 1) if k > 0 else 0.0)
        else:
            k, hi = hi - 1, hi - 1
            t[1] += cost(2 * k) + (cost(2 * k + 1) if 2 * k + 1 < n else 0.0)
    if lo >= 1 and 2 * lo - 1 < n:
        t[0 if t[0] <= t[1] else 1] += cost(2 * lo - 1)
    stage = max(t) / (PAIRS + ADVANCE)
    return 1.0 / ((PAIRS + ADVANCE) * stage + REST / 2.0)


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    lists = list(blocks_of(sys.argv[1]))
    if not lists:
        sys.exit("no 'force blocks' lines: run with DEMBOUND_TEAM_TRACE set and --threads 2")
    now = [both_ends(b, p) for b, p in lists]
    halved = [both_ends([x / 2 for x in b for _ in (0, 1)], [x / 2 for x in p for _ in (0, 1)])
              for b, p in lists]
    counts = [len(b) for b, _ in lists]
    print(f"lists: {len(lists)}, force blocks per list: mean {statistics.mean(counts):.1f} "
          f"(min {min(counts)}, max {max(counts)})")
    print(f"two-thread speed-up bound from the blocks alone: mean {statistics.mean(now):.3f} "
          f"(min {min(now):.3f}, max {max(now):.3f})")
    print(f"with every block split in two: mean {statistics.mean(halved):.3f} "
          f"(min {min(halved):.3f}, max {max(halved):.3f})")


if __name__ == "__main__":
    main()
