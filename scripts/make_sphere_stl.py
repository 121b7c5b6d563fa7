#!/usr/bin/env python3
"""Writes a UV sphere as a binary STL: a curved part with no two triangles
coplanar (every triangle its own flat patch), for timing `particle-wall` on
large meshes (BENCHMARKS.md, "Covering a 100,000-triangle mesh").

    python3 scripts/make_sphere_stl.py [--radius M] [--segments N] [--rings M] OUT.stl

N segments around and M rings from pole to pole give 2 N (M - 1)
triangles: N = 320, M = 160 -> 101,760. Centre at the origin, normals
outward ((b - a) x (c - a) points away from the centre). Standard library
only.
"""

import argparse
import math
import struct


def triangles(radius, segments, rings):
    def point(i, j):
        theta = math.pi * j / rings
        phi = 2.0 * math.pi * i / segments
        return (
            radius * math.sin(theta) * math.cos(phi),
            radius * math.sin(theta) * math.sin(phi),
            radius * math.cos(theta),
        )

    for j in range(rings):
        for i in range(segments):
            a, b = point(i, j), point(i + 1, j)
            c, d = point(i + 1, j + 1), point(i, j + 1)
            if j > 0:
                yield (a, d, b)
            if j < rings - 1:
                yield (b, d, c)


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("out")
    p.add_argument("--radius", type=float, default=0.02, help="m (default 0.02)")
    p.add_argument("--segments", type=int, default=320)
    p.add_argument("--rings", type=int, default=160)
    a = p.parse_args()
    tris = list(triangles(a.radius, a.segments, a.rings))
    with open(a.out, "wb") as f:
        f.write(b"UV sphere, make_sphere_stl.py".ljust(80, b" "))
        f.write(struct.pack("<I", len(tris)))
        for t in tris:
            f.write(struct.pack("<3f", 0.0, 0.0, 0.0))
            for v in t:
                f.write(struct.pack("<3f", *v))
            f.write(b"\0\0")
    print(f"wrote {a.out}: {len(tris)} triangles")


if __name__ == "__main__":
    main()
