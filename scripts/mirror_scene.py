#!/usr/bin/env python3
"""A scene's mirror image in x: every listed sphere's x taken to lower + upper - x
(the domain's mid-plane) and its vx negated.

For the chirality test of docs/export-yade.md ("A's side walls: which
wall leans"): a code whose laws have no handedness gives the mirror
scene's results mirrored (the wall x = 0's force in the mirror is the
wall x = L's in the original, statistically over seeds); a term with a
handedness (a turn of one sign) does not. The input is a resolved scene
with its free spheres listed one a line as `jitter_velocities.py` writes
them (`{ position = [x, y, z], radius = r, velocity = [vx, vy, vz] }`);
the walls are kept as they are and must be the mirror image of
themselves (plane walls in pairs x = a and x = lower + upper - a, or
normal to x's plane; a boundary-particle wall's point on the mid-plane,
so that its tiling, symmetric about its point, maps onto itself), else
the script stops: the mirror scene would not be the original's mirror.
A scene with spins or another sphere form stops too.

Usage: mirror_scene.py IN.toml OUT.toml
"""

import re
import sys
import tomllib

NUMBER = r"([-+0-9.eE]+)"
SPHERE = re.compile(
    r"^(  \{ position = \[)" + NUMBER + r"(, [^\]]*\], radius = [^,]+, velocity = \[)" + NUMBER
    + r"(, [^\]]*\] \},?)$"
)


def mirrored_walls_ok(scene, mid2):
    """Whether the scene's walls map onto themselves under x -> mid2 - x."""
    planes = []
    for wall in scene.get("wall", []):
        if "plane" in wall:
            p, n = wall["plane"]["point"], wall["plane"]["normal"]
            planes.append((tuple(n), sum(a * b for a, b in zip(n, p))))
        elif "boundary_particles" in wall:
            bp = wall["boundary_particles"]
            if abs(2 * bp["point"][0] - mid2) > 1e-12 or abs(bp["normal"][0]) > 0:
                return False
        else:
            return False
    for n, d in planes:
        # the mirror of {y : n.y = d} is {y : n'.y = d'} with n' = (-nx, ny, nz), d' = d - nx*mid2
        image = ((-n[0], n[1], n[2]), d - n[0] * mid2)
        if not any(m == image[0] and abs(e - image[1]) <= 1e-12 for m, e in planes):
            return False
    return True


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    src, out = sys.argv[1], sys.argv[2]
    text = open(src).read()
    scene = tomllib.loads(text)
    mid2 = scene["domain"]["lower"][0] + scene["domain"]["upper"][0]
    if not mirrored_walls_ok(scene, mid2):
        sys.exit(f"{src}: its walls are not their own mirror image in x; the mirror scene would differ")
    lines, count = [], 0
    for line in text.split("\n"):
        if line.startswith("  { "):
            m = SPHERE.match(line)
            if not m:
                sys.exit(f"{src}: a sphere line of another form (spins?): {line}")
            x, vx = float(m.group(2)), float(m.group(4))
            line = f"{m.group(1)}{mid2 - x!r}{m.group(3)}{-vx!r}{m.group(5)}"
            count += 1
        lines.append(line)
    if count == 0:
        sys.exit(f"{src}: no spheres listed one a line")
    with open(out, "w") as f:
        f.write("\n".join(lines))
    print(f"{out}: {count} spheres mirrored in x about x = {mid2 / 2!r}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
