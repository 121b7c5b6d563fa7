#!/usr/bin/env python3
"""A scene whose spheres start where an exported deck's do, each with its own
random initial velocity: seeds that break an ordered lattice's symmetry.

A uniform perturbation of a periodic lattice (every sphere's vx + k*1e-6 m/s)
breaks no symmetry: the lattice turns into a disordered flow only when each
code's round-off has grown to order one, at a time that is the code's own,
not a random draw over k (docs/export-yade.md, "The bed height of C*").
This script reads the free spheres' positions and initial velocities from
DECK/scene.py (written by `dembound export yade`, 17 digits, dembound's
resolved lattice) and the scene from DECK/scene.toml, and writes OUT.toml
with the lattice replaced by `spheres = [ ... ]`, each sphere's velocity
the lattice's plus a draw uniform in +-AMPLITUDE m/s per component from
random.Random(SEED). (A lattice at rest, as C*'s, gets the draw alone; a
thrown one, as scene A's at (0.03, 0.02, -0.1) m/s, keeps its throw.)
Fixed spheres (a boundary-particle wall's) are not listed: the scene's
wall makes them again.

Usage: jitter_velocities.py DECK AMPLITUDE SEED OUT.toml
Example (C*, the chute in Yade): jitter_velocities.py Y0 1e-4 3 J3.toml
"""

import random
import re
import sys

NUMBER = r"([-+0-9.eE]+|inf|nan)"


def main():
    if len(sys.argv) != 5:
        sys.exit(__doc__)
    deck, amplitude, seed, out = sys.argv[1], float(sys.argv[2]), int(sys.argv[3]), sys.argv[4]
    script = open(f"{deck}/scene.py").read()
    # spheres = [ (x, y, z, r, fixed, material), ... ] in dembound's order;
    # velocities = [ (index, vx, vy, vz), ... ] for the free ones
    block = re.search(r"^spheres = \[\n(.*?)^\]", script, re.M | re.S)
    if not block:
        sys.exit(f"{deck}/scene.py lists no spheres")
    spheres = re.findall(r"^    \(([^,]+), ([^,]+), ([^,]+), ([^,]+), (True|False), (-?\d+)\),$",
                         block.group(1), re.M)
    block = re.search(r"^velocities = \[\n(.*?)^\]", script, re.M | re.S)
    velocities = {}
    if block:
        for i, vx, vy, vz in re.findall(r"^    \((\d+), ([^,]+), ([^,]+), ([^,]+)\),$",
                                        block.group(1), re.M):
            velocities[int(i)] = [float(vx), float(vy), float(vz)]
    # free spheres: (x, y, z, r, False, -1)
    free = [(i, s) for i, s in enumerate(spheres) if s[4] == "False" and s[5] == "-1"]
    if not free:
        sys.exit(f"{deck}/scene.py lists no free spheres")
    text = open(f"{deck}/scene.toml").read()
    if text.count("[particles.lattice]") != 1:
        sys.exit(f"{deck}/scene.toml: expected one [particles.lattice] group")
    rng = random.Random(seed)
    lines = []
    for i, (x, y, z, r, _, _) in free:
        base = velocities.get(i, [0.0, 0.0, 0.0])
        v = [b + rng.uniform(-amplitude, amplitude) for b in base]
        lines.append("{ position = [%s, %s, %s], radius = %s, velocity = [%r, %r, %r] }"
                     % (x, y, z, r, *v))
    a = text.index("[particles.lattice]")
    # the next table header (a line starting with "["), or the end
    after = re.compile(r"^\[", re.M).search(text, a + 1)
    b = after.start() if after else len(text)
    text = text[:a] + "spheres = [\n  " + ",\n  ".join(lines) + "\n]\n\n" + text[b:]
    open(out, "w").write(text)
    moving = sum(1 for i, _ in free if any(velocities.get(i, [0.0] * 3)))
    print(f"wrote {out}: {len(lines)} spheres ({moving} with the lattice's own velocity), "
          f"plus velocities uniform in ±{amplitude} m/s (seed {seed})")


if __name__ == "__main__":
    main()
