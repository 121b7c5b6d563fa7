#!/usr/bin/env python3
"""Writes the meshes and the spheres of chute.toml, next to this file:

- chute.stl: an open-topped box chute of inner width W = 46.9 mm with
  vertical side walls H = 46.9 mm high and a back wall at its top. Its
  floor runs 289 mm down a 30° slope, bends (a concave edge across the
  chute) onto a flatter run of 192 mm at 12°, and ends open, 108 mm above
  the catch box's floor: the spheres fall off its end.
- chute_bin.stl: the catch box under the chute's end, an open-topped box
  (floor and four walls 78 mm high) from 62.5 mm behind the end to 250 mm
  beyond it, 47 mm wider than the chute on each side.
- chute_spheres.csv: 2160 spheres of radius 1.8 to 2.2 mm (uniform,
  seeded) on a lattice block (30 along the slope, 9 across, 8 layers)
  lying on the steep run, 1 mm clear of its floor, back and side walls:
  the charge released at t = 0.

Coordinates in m: x along the flow in plan, y across the chute (its side
walls at y = 0 and y = W), z up (gravity −z). The floor's top edge (the
back wall's foot) is at x = 0, z = Z0. Each face is cut into cells of
about 12 to 18 mm, two triangles each (so the per-triangle wall loads show
where the flow presses; a flat face's triangles act as one plane whatever
their number), ordered so that (b − a) × (c − a) points into the chute
(into the catch box).

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


def chute():
    """The chute's triangles, normals into the chute."""
    (x0, z0), (x1, z1), (x2, z2) = floor_profile()
    tris = []
    n, m = N_ALONG, N_ACROSS
    for (xa, za), (xb, zb) in (((x0, z0), (x1, z1)), ((x1, z1), (x2, z2))):
        # Floor: u along the flow, v across (+y): u × v points up.
        tris += grid((xa, 0.0, za), (xb, 0.0, zb), (xa, W, za), n, m)
        # Side y = 0, normal +y: u up, v along the flow (up × along = +y).
        tris += grid((xa, 0.0, za), (xa, 0.0, za + H), (xb, 0.0, zb), m, n)
        # Side y = W, normal −y: u along the flow, v up.
        tris += grid((xa, W, za), (xb, W, zb), (xa, W, za + H), n, m)
    # Back wall x = 0, normal +x: u across (+y), v up.
    tris += grid((x0, 0.0, z0), (x0, W, z0), (x0, 0.0, z0 + H), m, m)
    return tris


def bin_extent():
    """The catch box's x and y ranges (m): x_lo, x_hi, y_lo, y_hi."""
    xe = floor_profile()[2][0]
    return xe - BIN_BEHIND, xe + BIN_BEYOND, -BIN_MARGIN, W + BIN_MARGIN


def catch_box():
    """The catch box's triangles (floor z = 0, walls BIN_HEIGHT high),
    normals into the box."""
    xa, xb, ya, yb = bin_extent()
    h, n = BIN_HEIGHT, N_BIN
    return (
        grid((xa, ya, 0.0), (xb, ya, 0.0), (xa, yb, 0.0), n, n)  # floor, +z
        + grid((xa, ya, 0.0), (xa, yb, 0.0), (xa, ya, h), n, n)  # x = xa, +x
        + grid((xb, ya, 0.0), (xb, ya, h), (xb, yb, 0.0), n, n)  # x = xb, −x
        + grid((xa, ya, 0.0), (xa, ya, h), (xb, ya, 0.0), n, n)  # y = ya, +y
        + grid((xa, yb, 0.0), (xb, yb, 0.0), (xa, yb, h), n, n)  # y = yb, −y
    )


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
