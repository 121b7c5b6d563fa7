#!/usr/bin/env python3
"""Writes drum.stl: a closed drum (a regular N-gon prism with its two end
caps) about the y axis, radius R = 28 mm at the corners, length L = 18 mm,
centred on the origin, as outward triangles (ASCII STL, the coordinates
written to full double precision), for drum.toml.

    python3 examples/scenes/make_drum.py [OUT.stl] [--sides N]

Standard library only. N = 96 sides: a facet spans 3.75°, its middle is
R (1 − cos(π/N)) = 15 µm inside the corners (1.5 % of a sphere's radius,
1 mm in drum.toml). The mantle is 2N triangles, each cap a fan of N
triangles about its centre; every triangle is ordered so that
(b − a) × (c − a) points out of the drum.
"""

import math
import sys
from pathlib import Path

RADIUS = 0.028  # m, at the polygon's corners
LENGTH = 0.018  # m, along y
SIDES = 96


def drum(radius=RADIUS, length=LENGTH, sides=SIDES):
    """The outward triangles of the closed drum."""
    h = 0.5 * length
    ring = [
        (radius * math.cos(2 * math.pi * k / sides), radius * math.sin(2 * math.pi * k / sides))
        for k in range(sides)
    ]
    # A corner (x, z) at y: the angle runs from +x towards +z.
    def p(c, y):
        return (c[0], y, c[1])

    out = []
    for k in range(sides):
        a, b = ring[k], ring[(k + 1) % sides]
        # Mantle quad between corners a and b, y from −h to +h (outward:
        # checked by `outward` below).
        out += [(p(a, -h), p(a, h), p(b, h)), (p(a, -h), p(b, h), p(b, -h))]
        # Caps: fans about (0, ±h, 0).
        out += [((0.0, h, 0.0), p(b, h), p(a, h)), ((0.0, -h, 0.0), p(a, -h), p(b, -h))]
    return out


def normal(t):
    a, b, c = t
    e = [b[k] - a[k] for k in range(3)]
    f = [c[k] - a[k] for k in range(3)]
    n = (e[1] * f[2] - e[2] * f[1], e[2] * f[0] - e[0] * f[2], e[0] * f[1] - e[1] * f[0])
    length = sum(x * x for x in n) ** 0.5
    return tuple(x / length for x in n)


def outward(t):
    """Whether the triangle's normal points away from the drum's centre."""
    centroid = [sum(v[k] for v in t) / 3 for k in range(3)]
    return sum(n * c for n, c in zip(normal(t), centroid)) > 0


def write_ascii_stl(path, triangles):
    lines = ["solid drum"]
    for t in triangles:
        lines.append("facet normal {:.17g} {:.17g} {:.17g}".format(*normal(t)))
        lines.append("outer loop")
        for v in t:
            lines.append("vertex {:.17g} {:.17g} {:.17g}".format(*v))
        lines.append("endloop")
        lines.append("endfacet")
    lines.append("endsolid drum")
    Path(path).write_text("\n".join(lines) + "\n")


if __name__ == "__main__":
    args = sys.argv[1:]
    sides = SIDES
    if "--sides" in args:
        i = args.index("--sides")
        sides = int(args[i + 1])
        del args[i : i + 2]
    out = args[0] if args else Path(__file__).with_name("drum.stl")
    tris = drum(sides=sides)
    bad = [t for t in tris if not outward(t)]
    if bad:
        sys.exit(f"{len(bad)} triangles point inwards")
    write_ascii_stl(out, tris)
    print(f"wrote {out}: {len(tris)} triangles, R = {RADIUS} m, L = {LENGTH} m, {sides} sides")
