#!/usr/bin/env python3
"""A scene whose spheres start where an exported deck's do, each with its own
random initial velocity: seeds that break an ordered lattice's symmetry.

A uniform perturbation of a periodic lattice (every sphere's vx + k*1e-6 m/s)
breaks no symmetry: the lattice turns into a disordered flow only when each
code's round-off has grown to order one, at a time that is the code's own,
not a random draw over k (docs/export-yade.md, "The bed height of C*").
This script reads the free spheres' positions from DECK/scene.py (written by
`dembound export yade`, 17 digits, dembound's resolved lattice) and the scene
from DECK/scene.toml, and writes OUT.toml with the lattice replaced by
`spheres = [ ... ]`, each sphere's velocity uniform in +-AMPLITUDE m/s per
component from random.Random(SEED).

Usage: jitter_velocities.py DECK AMPLITUDE SEED OUT.toml
Example (C*, the chute in Yade): jitter_velocities.py Y0 1e-4 3 J3.toml
"""

import random
import re
import sys


def main():
    if len(sys.argv) != 5:
        sys.exit(__doc__)
    deck, amplitude, seed, out = sys.argv[1], float(sys.argv[2]), int(sys.argv[3]), sys.argv[4]
    script = open(f"{deck}/scene.py").read()
    # free spheres: (x, y, z, r, False, -1)
    free = re.findall(r"^    \(([^,]+), ([^,]+), ([^,]+), ([^,]+), False, -1\),$", script, re.M)
    if not free:
        sys.exit(f"{deck}/scene.py lists no free spheres")
    text = open(f"{deck}/scene.toml").read()
    if text.count("[particles.lattice]") != 1:
        sys.exit(f"{deck}/scene.toml: expected one [particles.lattice] group")
    rng = random.Random(seed)
    spheres = []
    for x, y, z, r in free:
        v = [rng.uniform(-amplitude, amplitude) for _ in range(3)]
        spheres.append("{ position = [%s, %s, %s], radius = %s, velocity = [%r, %r, %r] }"
                       % (x, y, z, r, *v))
    a = text.index("[particles.lattice]")
    # the next table header (a line starting with "["), or the end
    after = re.compile(r"^\[", re.M).search(text, a + 1)
    b = after.start() if after else len(text)
    text = text[:a] + "spheres = [\n  " + ",\n  ".join(spheres) + "\n]\n\n" + text[b:]
    open(out, "w").write(text)
    print(f"wrote {out}: {len(spheres)} spheres, velocities uniform in ±{amplitude} m/s (seed {seed})")


if __name__ == "__main__":
    main()
