#!/usr/bin/env python3
"""Writes the lined drum of lined_drum.toml (issue 27, "the paper's
question on a moving wall"): drum.toml's drum with its cylindrical mantle
replaced by fixed boundary spheres that turn with it.

    python3 examples/scenes/make_lined_drum.py [--dir DIR]

Writes, next to this file (or in DIR):
- lined_drum_caps.stl: the two end caps of make_drum.py's drum alone (its
  triangles whose normal is along ±y), R = 28 mm, L = 18 mm, axis y;
- lined_drum_mantle.stl: its 96-sided mantle alone (the smooth and the
  frictional reference drums of scripts/lined_drum_study.py: the same caps,
  only the mantle differs);
- lined_drum_r0.5.csv, lined_drum_r1.csv, lined_drum_r2.csv: the lining
  for radius ratios r = R_b/R_m = 0.5, 1 and 2 (R_m = 1 mm, the mean of
  the drum's free spheres, 1.1 and 0.9 mm), `x,y,z,radius` in m.

The lining is a square tiling of the mantle: rings of boundary spheres
of radius R_b whose centres lie on the circle of radius R + R_b about the
axis (their inner tops on the drum's radius R, so that the spheres' tangent
envelope is the wall they stand for, as a boundary-particle floor's tops
are on its plane), N = ceil(2π (R + R_b)/(2 R_b)) spheres per ring spaced
evenly (touching or slightly overlapping: no hole wider than the tiling's
own), and n = ceil(L/(2 R_b)) rings spread evenly along y from
−L/2 + R_b to L/2 − R_b (the end rings touch the caps). Fixed spheres
never meet each other, so the overlaps are harmless. Standard library only.
"""

import argparse
import math
from pathlib import Path

import make_drum

MEAN_RADIUS = 1.0e-3  # m, R_m: the mean of drum.toml's 1.1 and 0.9 mm spheres
RATIOS = {"0.5": 0.5, "1": 1.0, "2": 2.0}


def lining(ratio, radius=make_drum.RADIUS, length=make_drum.LENGTH):
    """[(x, y, z, R_b)] of the lining of radius ratio `ratio`."""
    rb = ratio * MEAN_RADIUS
    ring = radius + rb
    per_ring = math.ceil(2 * math.pi * ring / (2 * rb))
    rings = math.ceil(length / (2 * rb))
    if rings == 1:
        ys = [0.0]
    else:
        first, last = -0.5 * length + rb, 0.5 * length - rb
        ys = [first + (last - first) * k / (rings - 1) for k in range(rings)]
    out = []
    for y in ys:
        for k in range(per_ring):
            a = 2 * math.pi * k / per_ring
            out.append((ring * math.cos(a), y, ring * math.sin(a), rb))
    return out


def caps(sides=make_drum.SIDES):
    """The end caps' triangles of make_drum's drum."""
    return [t for t in make_drum.drum(sides=sides) if abs(make_drum.normal(t)[1]) > 0.5]


def mantle(sides=make_drum.SIDES):
    """The mantle's triangles of make_drum's drum."""
    return [t for t in make_drum.drum(sides=sides) if abs(make_drum.normal(t)[1]) <= 0.5]


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--dir", default=str(Path(__file__).resolve().parent))
    a = p.parse_args()
    out = Path(a.dir)
    tris = caps()
    make_drum.write_ascii_stl(out / "lined_drum_caps.stl", tris)
    print(f"wrote {out / 'lined_drum_caps.stl'}: {len(tris)} triangles")
    tris = mantle()
    make_drum.write_ascii_stl(out / "lined_drum_mantle.stl", tris)
    print(f"wrote {out / 'lined_drum_mantle.stl'}: {len(tris)} triangles")
    for name, ratio in RATIOS.items():
        spheres = lining(ratio)
        path = out / f"lined_drum_r{name}.csv"
        lines = ["x,y,z,radius"] + ["{:.17g},{:.17g},{:.17g},{:.17g}".format(*s) for s in spheres]
        path.write_text("\n".join(lines) + "\n")
        print(f"wrote {path}: {len(spheres)} spheres of R_b = {ratio * MEAN_RADIUS:g} m")


if __name__ == "__main__":
    main()
