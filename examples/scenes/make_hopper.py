#!/usr/bin/env python3
"""Writes hopper.stl: a conical hopper with a cylindrical bin above it, for
hopper.toml, as a binary STL (f32 coordinates, as CAD exports it).

    python3 examples/scenes/make_hopper.py [--segments N] [OUT.stl]

Geometry (metres; the axis is z, the outlet at z = 0):
- cone: half-angle 30° from the axis, outlet radius 6 mm (outlet diameter
  12 mm = 6 particle diameters of hopper.toml's 2 mm spheres), top radius
  20 mm, so its height is (20 − 6) mm / tan 30° = 24.25 mm;
- bin: a cylinder of radius 20 mm from the cone's top up 70 mm;
- open at the outlet and at the top.

Resolution: N segments around (default 48), and N/8 rings along the cone
and along the bin each, so 2 N (N/8 + N/8) = N²/2 triangles:
N = 48 → 1,152 triangles (hopper.stl), N = 200 → 20,000 (the speed test,
BENCHMARKS.md: `--segments 200 hopper_20k.stl`). The cone is ruled: each
strip between two segment angles is one flat trapezoid (its triangles
coplanar to f32 rounding), the bin's strips flat rectangles; the rings only
add triangles, not shape.

Standard library only. Triangles ordered so that (b − a) × (c − a) points
out of the hopper (away from the axis); dembound's mesh walls are
two-sided, the order only keeps the normals consistent.
"""

import argparse
import math
import struct
from pathlib import Path

OUTLET_RADIUS = 6.0e-3
TOP_RADIUS = 20.0e-3
HALF_ANGLE_DEG = 30.0
CONE_HEIGHT = (TOP_RADIUS - OUTLET_RADIUS) / math.tan(math.radians(HALF_ANGLE_DEG))
BIN_HEIGHT = 70.0e-3


def profile(rings_cone, rings_bin):
    """(radius, z) of every ring from the outlet up."""
    out = []
    for k in range(rings_cone + 1):
        s = k / rings_cone
        out.append((OUTLET_RADIUS + s * (TOP_RADIUS - OUTLET_RADIUS), s * CONE_HEIGHT))
    for k in range(1, rings_bin + 1):
        out.append((TOP_RADIUS, CONE_HEIGHT + k / rings_bin * BIN_HEIGHT))
    return out


def hopper(segments):
    """The triangles of the hopper with `segments` around."""
    rings = max(1, segments // 8)
    rim = profile(rings, rings)
    triangles = []
    for j in range(len(rim) - 1):
        (r0, z0), (r1, z1) = rim[j], rim[j + 1]
        for i in range(segments):
            a0 = 2.0 * math.pi * i / segments
            a1 = 2.0 * math.pi * (i + 1) / segments
            p = (r0 * math.cos(a0), r0 * math.sin(a0), z0)
            q = (r0 * math.cos(a1), r0 * math.sin(a1), z0)
            s = (r1 * math.cos(a1), r1 * math.sin(a1), z1)
            t = (r1 * math.cos(a0), r1 * math.sin(a0), z1)
            # p → q turns about +z; with the upward edge (q → s) the
            # normal (q − p) × (s − p) points outwards.
            triangles += [(p, q, s), (p, s, t)]
    return triangles


def normal(t):
    a, b, c = t
    e = [b[k] - a[k] for k in range(3)]
    f = [c[k] - a[k] for k in range(3)]
    n = (e[1] * f[2] - e[2] * f[1], e[2] * f[0] - e[0] * f[2], e[0] * f[1] - e[1] * f[0])
    length = sum(x * x for x in n) ** 0.5
    return tuple(x / length for x in n)


def write_binary_stl(path, triangles, segments):
    header = f"hopper: cone 30 deg, outlet 12 mm, bin r 20 mm; {segments} segments".encode()
    data = bytearray(header.ljust(80, b" ")[:80] + struct.pack("<I", len(triangles)))
    for t in triangles:
        data += struct.pack("<3f", *normal(t))
        for v in t:
            data += struct.pack("<3f", *v)
        data += struct.pack("<H", 0)
    Path(path).write_bytes(bytes(data))


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("out", nargs="?", default=str(Path(__file__).with_name("hopper.stl")))
    parser.add_argument("--segments", type=int, default=48, help="segments around (>= 8)")
    args = parser.parse_args()
    if args.segments < 8:
        parser.error(f"--segments {args.segments}: at least 8")
    triangles = hopper(args.segments)
    write_binary_stl(args.out, triangles, args.segments)
    print(f"wrote {args.out}: {len(triangles)} triangles")


if __name__ == "__main__":
    main()
