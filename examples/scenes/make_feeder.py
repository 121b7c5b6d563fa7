#!/usr/bin/env python3
"""Writes feeder.stl, the vibratory feeder of feeder.toml, next to this file.

feeder.stl: a straight, horizontal U-shaped trough (the cross-section of
chute.stl: inner width W = 46.9 mm, side walls 23.4 mm high, walls and
floor T = 7.8 mm thick) from x = XA to x = XB = XA + 125 mm, its inner
floor at z = ZF = 375 mm, open at its downstream end (the spheres leave
it there) and closed at its upstream end by a back block: two closed
surfaces, no open edge, normals out of the solid. It lies over the steep
run of chute.stl (whose floor is 63 mm lower at x = XA and 144 mm lower
at x = XB), inside the chute's side walls in y, so whatever leaves its
end falls into the chute.

The scene moves it by `oscillation` (a sinusoidal translation): a
vibratory feeder. Every length is a dyadic rational (a multiple of 2^-16
m), so the vertices are exact in binary STL's f32 and each face's
triangles join into one flat patch, as in make_chute.py.

    python3 examples/scenes/make_feeder.py [DIR]     # default: this file's folder

Standard library; the STL writer and the cross-section are make_chute.py's.
"""

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import make_chute  # noqa: E402
from make_chute import T, W, grid  # noqa: E402

XA = 1 / 64  # m, the trough's upstream end (the back block's inner face)
XB = XA + 1 / 8  # m, its open downstream end
ZF = 3 / 8  # m, its inner floor
HF = 3 / 128  # m, its side walls' height above the floor
N_ALONG = 8  # cells along the trough


def box(x0, x1, y0, y1, z0, z1, n):
    """A closed box, n × n cells a face, normals out of it."""
    return (
        grid((x0, y0, z0), (x0, y1, z0), (x1, y0, z0), n, n)  # −z
        + grid((x0, y0, z1), (x1, y0, z1), (x0, y1, z1), n, n)  # +z
        + grid((x0, y0, z0), (x0, y0, z1), (x0, y1, z0), n, n)  # −x
        + grid((x1, y0, z0), (x1, y1, z0), (x1, y0, z1), n, n)  # +x
        + grid((x0, y0, z0), (x1, y0, z0), (x0, y0, z1), n, n)  # −y
        + grid((x0, y1, z0), (x0, y1, z1), (x1, y1, z0), n, n)  # +y
    )


def trough():
    """The U trough: chute.stl's cross-section (walls HF high here) swept
    along x at the floor height ZF from XA − T/2 (inside the back block:
    the two solids cross, no face of one lies on a face of the other) to XB,
    closed by its two U-shaped end faces."""
    loop = [(y, o * HF / make_chute.H if o > 0 else o) for y, o in make_chute.profile()]
    x0 = XA - T / 2  # inside the back block, which hides this end
    stations = [(x0 + (XB - x0) * i / N_ALONG, ZF) for i in range(N_ALONG + 1)]
    tris = []
    for k in range(len(loop)):
        (ya, oa), (yb, ob) = loop[k], loop[(k + 1) % len(loop)]
        for (xs, zs), (xt, zt) in zip(stations, stations[1:]):
            a, b = (xs, ya, zs + oa), (xt, ya, zt + oa)
            c, d = (xt, yb, zt + ob), (xs, yb, zs + ob)
            tris += [(a, b, c), (a, c, d)]
    return tris + make_chute.end_cap(x0, ZF, -1, HF) + make_chute.end_cap(XB, ZF, +1, HF)


def feeder():
    """The trough and its back block (T thick in x, T/2 wider and
    higher than the trough on every side, its face x = XA closing the
    trough)."""
    return trough() + back_block()


def back_block():
    return box(XA - T, XA, -1.5 * T, W + 1.5 * T, ZF - 1.5 * T, ZF + HF + T / 2, 4)


def main():
    out = Path(sys.argv[1]) if len(sys.argv) > 1 else Path(__file__).resolve().parent
    trough_tris, back = trough(), back_block()
    for name, part in (("trough", trough_tris), ("back block", back)):
        assert make_chute.open_edges(part) == 0, f"the {name} is not closed"
        assert make_chute.signed_volume(part) > 0.0, f"the {name}'s normals point in"
    make_chute.write_binary_stl(out / "feeder.stl", feeder(), "vibratory feeder trough")
    print(f"wrote {out / 'feeder.stl'}: {len(feeder())} triangles")


if __name__ == "__main__":
    main()
