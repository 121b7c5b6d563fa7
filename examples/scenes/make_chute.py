#!/usr/bin/env python3
"""Writes the meshes and the spheres of chute.toml, next to this file:

- chute.stl: a box chute, a U-shaped trough of inner width W = 46.9 mm
  with vertical side walls H = 46.9 mm high, open at the top; walls and
  floor T = 7.8 mm thick, the part a CAD export gives: a closed surface, no
  open edge. Its floor runs 289 mm down a 30° slope, bends (a concave edge
  across the chute) onto a flatter run of 192 mm at 12°, and ends in a
  square lip 108 mm above the catch box's floor: the spheres fall off it.
  Its upper end is closed by the scene's plane x = 0 (the back wall).
- chute_bin.stl: the catch box under the chute's end, an open-topped box
  (inner floor at z = 0, walls 78 mm high, T thick, a closed surface)
  from 62.5 mm behind the end to 250 mm beyond it, 47 mm wider than the
  chute on each side.
- chute_spheres.csv: 2160 spheres of radius 1.8 to 2.2 mm (uniform,
  seeded) on a lattice block (30 along the slope, 9 across, 8 layers)
  lying on the steep run, 1 mm clear of its floor, back and side walls:
  the charge released at t = 0.

Coordinates in m: x along the flow in plan, y across the chute (its inner
walls at y = 0 and y = W), z up (gravity −z). The floor's top end is at
x = 0, z = Z0. Each face is cut into cells of about 12 to 18 mm, two
triangles each (so the per-triangle wall loads show where the flow
presses; a flat face's triangles act as one plane whatever their number),
ordered so that (b − a) × (c − a) points out of the solid (into the chute
and the box on their inner faces).

    python3 examples/scenes/make_chute.py [DIR]     # default: this file's folder

Standard library only; the constants below are the chute's definition
(python/tests/test_chute_example.py checks the flow against them).
"""

import math
import random
import struct
import sys
from pathlib import Path

# Every length is a dyadic rational with few bits (a multiple of 2^-16 m),
# and every face is cut into a power of two of cells: each vertex is then
# exact in binary STL's f32, every face's vertices lie exactly on its plane,
# and the engine joins each face's triangles into one flat patch (normals
# within 1e-6 rad; f32 rounding of a sloped face's vertices would tilt
# 12 mm triangles by ~1e-6 rad and split the face).
W = 3 / 64  # m, inner width (side walls at y = 0 and y = W): 46.9 mm
H = 3 / 64  # m, side and back walls' height above the floor, vertical
Z0 = 5 / 16  # m, floor height at the back wall (x = 0)
X1, DZ1 = 1 / 4, 591 / 4096  # m, steep run in plan and its drop: 29.99°
X2, DZ2 = 3 / 16, 163 / 4096  # m, the flatter run after the bend: 11.98°
T = 1 / 128  # m, thickness of the chute's and the catch box's walls and floors
N_ALONG, N_ACROSS = 16, 4  # cells along each run; across the floor and up the walls

BIN_BEHIND, BIN_BEYOND = 1 / 16, 1 / 4  # m, catch box from the chute's end, in x
BIN_MARGIN = 3 / 64  # m, catch box wider than the chute on each side
BIN_HEIGHT = 5 / 64  # m, catch box walls (floor at z = 0)
N_BIN = 8  # cells along each side of the catch box's faces

RADIUS = (1.8e-3, 2.2e-3)  # m, uniform radii
COUNTS = (30, 9, 8)  # spheres along the slope, across, layers
SEED = 26

SLOPE1 = math.degrees(math.atan2(DZ1, X1))  # 29.99°
SLOPE2 = math.degrees(math.atan2(DZ2, X2))  # 11.98°


def floor_profile():
    """(x, z) of the floor at the back wall, the bend and the end."""
    return (0.0, Z0), (X1, Z0 - DZ1), (X1 + X2, Z0 - DZ1 - DZ2)


def floor_z(x):
    """The floor's height (m) at x (m) in plan, for 0 ≤ x ≤ the end's x."""
    p0, p1, p2 = floor_profile()
    (xa, za), (xb, zb) = (p0, p1) if x <= p1[0] else (p1, p2)
    return za + (zb - za) * (x - xa) / (xb - xa)


def grid(a, b, d, n_a, n_b):
    """Triangles of the parallelogram a, a + u, a + u + v, a + v (u = b − a,
    v = d − a) cut into n_a × n_b cells, each cell two triangles turning
    a → b → d (normal along u × v)."""
    u = [b[k] - a[k] for k in range(3)]
    v = [d[k] - a[k] for k in range(3)]

    def at(i, j):
        return tuple(a[k] + u[k] * i / n_a + v[k] * j / n_b for k in range(3))

    out = []
    for i in range(n_a):
        for j in range(n_b):
            p, q, r, s = at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)
            out += [(p, q, r), (p, r, s)]
    return out


def along_path(x_a, z_a, x_b, z_b, n):
    """The n + 1 (x, floor z) stations of a run from (x_a, z_a) to (x_b, z_b)."""
    return [(x_a + (x_b - x_a) * i / n, z_a + (z_b - z_a) * i / n) for i in range(n + 1)]


def profile():
    """The chute's cross-section, a U, as a closed loop of (y, o) points
    (o: height above the floor), every face's cells included, in the order
    that makes the faces' normals point out of the solid: inner floor, inner
    wall y = W, its rim, outer wall, underside, outer wall, rim, inner wall
    y = 0. The walls and the floor are T thick."""
    m, t = N_ACROSS, T

    def line(a, b, n):  # n cells from a, b excluded
        return [(a[0] + (b[0] - a[0]) * i / n, a[1] + (b[1] - a[1]) * i / n) for i in range(n)]

    return (
        line((0.0, 0.0), (W, 0.0), m)
        + line((W, 0.0), (W, H), m)
        + line((W, H), (W + t, H), 1)
        + line((W + t, H), (W + t, 0.0), m)
        + line((W + t, 0.0), (W + t, -t), 1)
        + line((W + t, -t), (W, -t), 1)
        + line((W, -t), (0.0, -t), m)
        + line((0.0, -t), (-t, -t), 1)
        + line((-t, -t), (-t, 0.0), 1)
        + line((-t, 0.0), (-t, H), m)
        + line((-t, H), (0.0, H), 1)
        + line((0.0, H), (0.0, 0.0), m)
    )


def end_cap(x, z, outward, h=H):
    """The U-shaped end face of the chute at station (x, floor z), normal
    along +x (outward = +1) or −x: three rectangles (the two walls' ends
    and the floor's), cut to match the profile's cells; walls h high."""
    m, t = N_ACROSS, T
    tris = []
    # (y0, y1, o0, o1, cells along y, cells along o)
    for y0, y1, o0, o1, n_y, n_o in (
        (-t, 0.0, 0.0, h, 1, m),
        (W, W + t, 0.0, h, 1, m),
        (-t, 0.0, -t, 0.0, 1, 1),
        (0.0, W, -t, 0.0, m, 1),
        (W, W + t, -t, 0.0, 1, 1),
    ):
        a, b, d = (x, y0, z + o0), (x, y1, z + o0), (x, y0, z + o1)
        tris += grid(a, b, d, n_y, n_o) if outward > 0 else grid(a, d, b, n_o, n_y)
    return tris


def chute():
    """The chute: a U-shaped trough T thick, swept along the floor's two
    runs and closed by its two end faces, a closed surface (no open edge),
    normals out of the solid (into the trough on its inner faces). The back
    wall is a plane of the scene (x = 0)."""
    (x0, z0), (x1, z1), (x2, z2) = floor_profile()
    loop = profile()
    tris = []
    for stations in (along_path(x0, z0, x1, z1, N_ALONG), along_path(x1, z1, x2, z2, N_ALONG)):
        for k in range(len(loop)):
            (ya, oa), (yb, ob) = loop[k], loop[(k + 1) % len(loop)]
            for (xs, zs), (xt, zt) in zip(stations, stations[1:]):
                a, b = (xs, ya, zs + oa), (xt, ya, zt + oa)
                c, d = (xt, yb, zt + ob), (xs, yb, zs + ob)
                tris += [(a, b, c), (a, c, d)]
    return tris + end_cap(x0, z0, -1) + end_cap(x2, z2, +1)


def bin_extent():
    """The catch box's inner x and y ranges (m): x_lo, x_hi, y_lo, y_hi."""
    xe = floor_profile()[2][0]
    return xe - BIN_BEHIND, xe + BIN_BEYOND, -BIN_MARGIN, W + BIN_MARGIN


def rectangle_loop(x0, x1, y0, y1, z, n):
    """The rectangle's boundary at height z, n cells a side, anticlockwise
    seen from above, from (x0, y0)."""
    corners = [(x0, y0), (x1, y0), (x1, y1), (x0, y1)]
    out = []
    for (xa, ya), (xb, yb) in zip(corners, corners[1:] + corners[:1]):
        out += [(xa + (xb - xa) * i / n, ya + (yb - ya) * i / n, z) for i in range(n)]
    return out


def catch_box():
    """The catch box: an open-topped box (inner floor z = 0, walls
    BIN_HEIGHT high) with walls and floor T thick, a closed surface,
    normals out of the solid (into the box on its inner faces)."""
    xa, xb, ya, yb = bin_extent()
    h, n, t = BIN_HEIGHT, N_BIN, T
    xo, xp, yo, yp = xa - t, xb + t, ya - t, yb + t
    inner = rectangle_loop(xa, xb, ya, yb, h, n)
    outer = rectangle_loop(xo, xp, yo, yp, h, n)
    rim = []
    for k in range(len(inner)):
        i0, i1, o0, o1 = inner[k], inner[(k + 1) % len(inner)], outer[k], outer[(k + 1) % len(outer)]
        rim += [(i0, o0, o1), (i0, o1, i1)]  # normal +z
    return (
        grid((xa, ya, 0.0), (xb, ya, 0.0), (xa, yb, 0.0), n, n)  # inner floor, +z
        + grid((xa, ya, 0.0), (xa, yb, 0.0), (xa, ya, h), n, n)  # x = xa, +x
        + grid((xb, ya, 0.0), (xb, ya, h), (xb, yb, 0.0), n, n)  # x = xb, −x
        + grid((xa, ya, 0.0), (xa, ya, h), (xb, ya, 0.0), n, n)  # y = ya, +y
        + grid((xa, yb, 0.0), (xb, yb, 0.0), (xa, yb, h), n, n)  # y = yb, −y
        + rim
        + grid((xo, yo, -t), (xo, yo, h), (xo, yp, -t), n, n)  # x = xo, −x
        + grid((xp, yo, -t), (xp, yp, -t), (xp, yo, h), n, n)  # x = xp, +x
        + grid((xo, yo, -t), (xp, yo, -t), (xo, yo, h), n, n)  # y = yo, −y
        + grid((xo, yp, -t), (xo, yp, h), (xp, yp, -t), n, n)  # y = yp, +y
        + grid((xo, yo, -t), (xo, yp, -t), (xp, yo, -t), n, n)  # underside, −z
    )


def open_edges(tris):
    """The number of edges not shared by exactly two triangles in
    opposite directions (0: a closed, consistently oriented surface)."""
    directed = {}
    for t in tris:
        for a, b in ((t[0], t[1]), (t[1], t[2]), (t[2], t[0])):
            directed[(a, b)] = directed.get((a, b), 0) + 1
    return sum(1 for (a, b), k in directed.items() if k != 1 or directed.get((b, a)) != 1)


def signed_volume(tris):
    """The enclosed volume (m³), positive when the normals point out."""
    total = 0.0
    for a, b, c in tris:
        total += (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
                  + a[2] * (b[0] * c[1] - b[1] * c[0])) / 6.0
    return total


def spheres():
    """(x, y, z, radius) of the released charge: a lattice block on the
    steep run, rows along the slope, 1 mm clear of the floor, the back
    wall and the side walls."""
    rng = random.Random(SEED)
    a = math.atan2(DZ1, X1)
    along = (math.cos(a), 0.0, -math.sin(a))
    normal = (math.sin(a), 0.0, math.cos(a))
    gap = 1.0e-3
    pitch = 2.0 * RADIUS[1] + 0.2e-3
    n_s, n_y, n_l = COUNTS
    across0 = 0.5 * (W - (n_y - 1) * pitch)
    assert across0 >= RADIUS[1] + gap, "the rows do not fit across the chute"
    out = []
    for layer in range(n_l):
        for j in range(n_y):
            for i in range(n_s):
                s = RADIUS[1] + gap + i * pitch
                h = RADIUS[1] + gap + layer * pitch
                r = rng.uniform(*RADIUS)
                x = s * along[0] + h * normal[0]
                z = Z0 + s * along[2] + h * normal[2]
                out.append((x, across0 + j * pitch, z, r))
    return out


def normal_of(t):
    a, b, c = t
    e = [b[k] - a[k] for k in range(3)]
    f = [c[k] - a[k] for k in range(3)]
    n = (e[1] * f[2] - e[2] * f[1], e[2] * f[0] - e[0] * f[2], e[0] * f[1] - e[1] * f[0])
    length = math.sqrt(sum(x * x for x in n))
    return tuple(x / length for x in n)


def write_binary_stl(path, triangles, title):
    data = bytearray(title.encode().ljust(80, b" ")[:80] + struct.pack("<I", len(triangles)))
    for t in triangles:
        data += struct.pack("<3f", *normal_of(t))
        for vertex in t:
            data += struct.pack("<3f", *vertex)
        data += b"\0\0"
    Path(path).write_bytes(bytes(data))


def write_spheres(path, rows):
    # 7 significant digits: 1e-9 m at these sizes, far below the 0.2 mm
    # clearance between neighbours.
    lines = ["x,y,z,radius"] + [",".join(f"{v:.7g}" for v in row) for row in rows]
    Path(path).write_text("\n".join(lines) + "\n")


if __name__ == "__main__":
    folder = Path(sys.argv[1]) if len(sys.argv) > 1 else Path(__file__).parent
    folder.mkdir(parents=True, exist_ok=True)
    outputs = (
        (folder / "chute.stl", lambda p: write_binary_stl(p, chute(), "chute: 30 deg run, bend, 12 deg run")),
        (folder / "chute_bin.stl", lambda p: write_binary_stl(p, catch_box(), "chute catch box, open top")),
        (folder / "chute_spheres.csv", lambda p: write_spheres(p, spheres())),
    )
    for path, write in outputs:
        write(path)
        print(f"wrote {path}")
