#!/usr/bin/env python3
"""Writes a flat-bottomed silo for Beverloo's discharge law (issues 28, 30):
silo_floor_D<mm>.stl (the floor: an annulus with a circular orifice of
diameter D), silo_spheres.csv (the fill) and silo_D<mm>.toml (the scene).

    python3 examples/scenes/make_silo.py [--orifice D_m] [--out DIR]

Geometry (metres; the axis is z, the floor at z = 0): a tube of radius
18 mm (the scene's cylinder wall) on a flat floor with a central orifice of
diameter D (default 12 mm); a gate plane at z = 0 closes the orifice until
t = 0.1 s (`active.to`). Spheres: d = 2 mm ± 10 % (radius uniform in
[0.9, 1.1] mm, against crystallisation), ~6,100 of them on a jittered
cubic lattice (spacing 2.3 mm) inside the tube; they settle onto the gate
and floor in the first 0.1 s (scripts/beverloo_study.py prints the bed's
top at the opening and at the end).

Standard library only. The floor's triangles are two-sided in dembound;
the order makes (b − a) × (c − a) point up (+z).
"""

import argparse
import math
import random
import struct
from pathlib import Path

SILO_RADIUS = 18.0e-3  # m
FLOOR_RADIUS = 20.0e-3  # m: the floor reaches past the tube
RADIUS_MIN, RADIUS_MAX = 0.9e-3, 1.1e-3  # m
SPACING = 2.3e-3  # m: the fill lattice
FILL_HEIGHT = 80.0e-3  # m: the top lattice layer's centre (loose; settles to ~44 mm)
GATE_OPEN = 0.1  # s
SEED = 1


def floor_triangles(orifice_radius, segments=64):
    """The annulus orifice_radius ≤ r ≤ FLOOR_RADIUS at z = 0."""
    out = []
    for i in range(segments):
        a0 = 2.0 * math.pi * i / segments
        a1 = 2.0 * math.pi * (i + 1) / segments
        p0 = (orifice_radius * math.cos(a0), orifice_radius * math.sin(a0), 0.0)
        p1 = (orifice_radius * math.cos(a1), orifice_radius * math.sin(a1), 0.0)
        q0 = (FLOOR_RADIUS * math.cos(a0), FLOOR_RADIUS * math.sin(a0), 0.0)
        q1 = (FLOOR_RADIUS * math.cos(a1), FLOOR_RADIUS * math.sin(a1), 0.0)
        out.append((p0, q0, q1))
        out.append((p0, q1, p1))
    return out


def write_stl(path, triangles):
    with open(path, "wb") as f:
        f.write(b"silo floor (make_silo.py)".ljust(80, b"\0"))
        f.write(struct.pack("<I", len(triangles)))
        for a, b, c in triangles:
            f.write(struct.pack("<3f", 0.0, 0.0, 1.0))
            for p in (a, b, c):
                f.write(struct.pack("<3f", *p))
            f.write(b"\0\0")


def fill(seed=SEED):
    """(x, y, z, r) on a jittered cubic lattice wholly inside the tube."""
    rng = random.Random(seed)
    spheres = []
    n = int(SILO_RADIUS / SPACING) + 1
    z = RADIUS_MAX + 0.2e-3
    while z <= FILL_HEIGHT:
        for i in range(-n, n + 1):
            for j in range(-n, n + 1):
                r = rng.uniform(RADIUS_MIN, RADIUS_MAX)
                jitter = 0.5 * (SPACING - 2.0 * RADIUS_MAX)
                x = i * SPACING + rng.uniform(-jitter, jitter)
                y = j * SPACING + rng.uniform(-jitter, jitter)
                if math.hypot(x, y) + RADIUS_MAX + 0.1e-3 < SILO_RADIUS:
                    spheres.append((x, y, z, r))
        z += SPACING
    return spheres


SCENE = """\
# A flat-bottomed silo discharging through a circular orifice (Beverloo,
# Leniger & van de Velde 1961; issues 28 and 30), written by make_silo.py:
# a tube of radius 18 mm on a flat floor (silo_floor_D{mm}.stl, orifice
# diameter D = {mm} mm), {count} frictional spheres (d = 2 mm ± 10 %,
# silo_spheres.csv) settled onto a gate plane that vanishes at t = {gate} s;
# the spheres that fall through are removed by an outlet box 20–40 mm below.
# The mass flow rate: series.csv outlet0_mass_kg against time
# (scripts/beverloo_study.py fits it, and Beverloo's law over four D).
#
# Hertz with Tsuji damping (e = 0.5), μ = 0.5 everywhere, no tangential
# dashpot (so that `dembound export liggghts` is exact). Time step: Δt =
# 2e-5 s ≈ 0.18 of the Rayleigh time of the smallest sphere
# (π R √(ρ/G)/(0.1631 ν + 0.8766) = 1.1e-4 s for R = 0.9 mm, E = 5 MPa;
# LIGGGHTS's rule of thumb: below 0.2) and 1/15 of the Hertz contact time
# of two mean spheres at 0.5 m/s (3.1e-4 s; the orifice speed √(g D) is
# ~0.35 m/s). E = 5 MPa: the bed's ~0.5 kPa bottom stress overlaps the
# spheres by ~1 % of a radius.
#
#   python3 examples/scenes/make_silo.py --orifice {D} --out DIR
#   dembound scene DIR/silo_D{mm}.toml --out silo --json

[domain]
lower = [-0.03, -0.03, -0.04]
upper = [0.03, 0.03, 0.09]                      # m
periodic = [false, false, false]

[[material]]
name = "glass"
density = 2500.0                                # kg/m³
youngs_modulus = 5.0e6                          # Pa (soft: a larger time step)
poisson_ratio = 0.3

[[material]]
name = "steel"
density = 7800.0
youngs_modulus = 5.0e6
poisson_ratio = 0.3

[contact]
law = "hertz"
damping = "tsuji"
restitution = 0.5
friction = 0.5
tangential_damping = false

[[particles]]
csv = "silo_spheres.csv"                        # x,y,z,radius (m)
material = "glass"

[[wall]]
cylinder = {{ point = [0.0, 0.0, 0.0], axis = [0.0, 0.0, 1.0], radius = 0.018 }}
material = "steel"

[[wall]]
mesh = {{ file = "silo_floor_D{mm}.stl" }}
material = "steel"

# The gate: closed until t = {gate} s.
[[wall]]
plane = {{ point = [0.0, 0.0, 0.0], normal = [0.0, 0.0, 1.0] }}
material = "steel"
active = {{ to = {gate} }}                        # s

[[wall]]
plane = {{ point = [0.0, 0.0, -0.04], normal = [0.0, 0.0, 1.0] }}
material = "steel"

# Removes what fell through (centres 20–40 mm below the orifice).
[[outlet]]
region = {{ box = {{ lower = [-0.03, -0.03, -0.04], upper = [0.03, 0.03, -0.02] }} }}

[motion]
gravity = [0.0, 0.0, -9.81]                     # m/s²

[integration]
scheme = "verlet"
dt = 2.0e-5                                     # s
steps = 22500                                   # 0.45 s

[output]
every = 5000                                    # a snapshot at the opening (0.1 s)
series_every = 250                              # 5 ms
"""


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--orifice", type=float, default=12.0e-3, help="orifice diameter D, m")
    ap.add_argument("--out", type=Path, default=Path(__file__).resolve().parent)
    ap.add_argument("--seed", type=int, default=SEED, help="seed of the fill's radii and jitter")
    args = ap.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)
    mm = f"{args.orifice * 1e3:g}"
    write_stl(args.out / f"silo_floor_D{mm}.stl", floor_triangles(0.5 * args.orifice))
    spheres = fill(args.seed)
    with open(args.out / "silo_spheres.csv", "w") as f:
        f.write("x,y,z,radius\n")
        for s in spheres:
            f.write("{:.7g},{:.7g},{:.7g},{:.7g}\n".format(*s))
    (args.out / f"silo_D{mm}.toml").write_text(
        SCENE.format(mm=mm, D=args.orifice, count=len(spheres), gate=GATE_OPEN)
    )
    print(f"{len(spheres)} spheres; {args.out}/silo_D{mm}.toml")


if __name__ == "__main__":
    main()
