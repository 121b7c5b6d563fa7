#!/usr/bin/env python3
"""Writes mesh_box.stl: the closed box [0, 0.0246]² × [0, 0.03] m (the
lattice drop's box, lattice_drop.toml) as 12 outward triangles, a binary
STL (f32 coordinates, as CAD exports it), for mesh_box.toml.

    python3 examples/scenes/make_mesh_box.py [OUT.stl]

Standard library only. Faces in the order −x, +x, −y, +y, −z, +z, two
triangles each, ordered so that (b − a) × (c − a) points out of the box.
"""

import struct
import sys
from pathlib import Path

LO = (0.0, 0.0, 0.0)
HI = (0.0246, 0.0246, 0.03)


def box(lo, hi):
    """The 12 outward triangles of the box [lo, hi]."""
    out = []
    for axis in range(3):
        u, v = (axis + 1) % 3, (axis + 2) % 3
        for upper in (False, True):
            def corner(su, sv):
                p = [0.0, 0.0, 0.0]
                p[axis] = hi[axis] if upper else lo[axis]
                p[u] = hi[u] if su else lo[u]
                p[v] = hi[v] if sv else lo[v]
                return tuple(p)

            a, b, c, d = corner(0, 0), corner(1, 0), corner(1, 1), corner(0, 1)
            # (u, v, axis) is right-handed: a → b → c turns about +axis.
            out += [(a, b, c), (a, c, d)] if upper else [(a, c, b), (a, d, c)]
    return out


def normal(t):
    a, b, c = t
    e = [b[k] - a[k] for k in range(3)]
    f = [c[k] - a[k] for k in range(3)]
    n = (e[1] * f[2] - e[2] * f[1], e[2] * f[0] - e[0] * f[2], e[0] * f[1] - e[1] * f[0])
    length = sum(x * x for x in n) ** 0.5
    return tuple(x / length for x in n)


def write_binary_stl(path, triangles):
    header = b"mesh_box: the lattice drop's box, 12 triangles".ljust(80, b" ")
    data = bytearray(header + struct.pack("<I", len(triangles)))
    for t in triangles:
        data += struct.pack("<3f", *normal(t))
        for vertex in t:
            data += struct.pack("<3f", *vertex)
        data += b"\0\0"
    Path(path).write_bytes(bytes(data))


if __name__ == "__main__":
    out = sys.argv[1] if len(sys.argv) > 1 else Path(__file__).with_name("mesh_box.stl")
    write_binary_stl(out, box(LO, HI))
    print(f"wrote {out}")
