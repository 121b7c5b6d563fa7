#!/usr/bin/env python3
"""Writes a flat-bottomed silo for Beverloo's discharge law (issues 28, 30):
silo_floor_D<mm>.stl (the floor: an annulus with a circular orifice of
diameter D), silo_spheres.csv (the fill) and silo_D<mm>.toml (the scene).

    python3 examples/scenes/make_silo.py [--orifice D_m] [--out DIR] [--fill lattice|inlet]

Geometry (metres; the axis is z, the floor at z = 0): a tube of radius
18 mm (the scene's cylinder wall) on a flat floor with a central orifice of
diameter D (default 12 mm); a gate plane at z = 0 closes the orifice until
t = 0.1 s (`active.to`). Spheres: d = 2 mm ± 10 % (radius uniform in
[0.9, 1.1] mm, against crystallisation), ~6,100 of them on a jittered
cubic lattice (spacing 2.3 mm) inside the tube; they settle onto the gate
and floor in the first 0.1 s (scripts/beverloo_study.py prints the bed's
top at the opening and at the end).

`--fill inlet` writes silo_inlet_D<mm>.toml instead (no CSV): the same
silo filled during the run by an `[[inlet]]`, a cylinder of radius 17 mm
from z = 55 to 85 mm pouring 6,200 spheres (radius uniform in [0.9, 1.1]
mm, the lattice's 6,194 to within 0.1 %) at 50,000 spheres/s over
0.124 s, 250 per event every 250 steps (5 ms), starting at 1 m/s
downwards; the gate opens at t = 0.3 s, once the bed has settled (in a
run of D = 10 mm the kinetic energy per sphere fell from ~8e-6 J while
pouring to 8e-10 J at 0.2 s and 2e-11 J at 0.3 s: docs/beverloo.md), and
the run lasts 0.35 s more (0.65 s, 32,500 steps).

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
# --fill inlet (module doc).
INLET_COUNT = 6200
INLET_RATE = 50000.0  # spheres/s
INLET_EVERY = 250  # steps (5 ms)
INLET_RADIUS = 0.017  # m: the region's, 1 mm inside the tube
INLET_Z = (0.055, 0.085)  # m: the region's bottom and top
INLET_SPEED = 1.0  # m/s, downwards
INLET_GATE_OPEN = 0.3  # s
INLET_STEPS = 32500  # 0.65 s


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


LATTICE_HEAD = """\
# A flat-bottomed silo discharging through a circular orifice (Beverloo,
# Leniger & van de Velde 1961; issues 28 and 30), written by make_silo.py:
# a tube of radius 18 mm on a flat floor (silo_floor_D{mm}.stl, orifice
# diameter D = {mm} mm), {count} frictional spheres (d = 2 mm ± 10 %,
# silo_spheres.csv) settled onto a gate plane that vanishes at t = {gate} s;
"""

INLET_HEAD = """\
# A flat-bottomed silo filled by an inlet and discharging through a circular
# orifice (Beverloo, Leniger & van de Velde 1961; issues 28 and 30), written
# by make_silo.py --fill inlet: a tube of radius 18 mm on a flat floor
# (silo_floor_D{mm}.stl, orifice diameter D = {mm} mm), {count} frictional
# spheres (d = 2 mm ± 10 %) poured by the [[inlet]] below over the first
# {pour:g} s onto a gate plane that vanishes at t = {gate} s, once settled;
"""

SCENE = """\
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
#   python3 examples/scenes/make_silo.py --orifice {D} --out DIR{fill_arg}
#   dembound scene DIR/{name} --out silo --json

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

{fill}
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
steps = {steps}                                   # {duration:g} s

[output]
every = 5000                                    # a snapshot at the opening ({gate} s)
series_every = 250                              # 5 ms
"""


LATTICE_FILL = """\
[[particles]]
csv = "silo_spheres.csv"                        # x,y,z,radius (m)
material = "glass"
"""

INLET_FILL = """\
# The fill: {count} spheres poured from a cylinder 1 mm inside the tube,
# z = {z0:g}–{z1:g} m, at {rate:g} spheres/s from t = 0 to {end:g} s, {per} every
# {every} steps ({every_s:g} s), each starting at {speed:g} m/s downwards.
[[inlet]]
region = {{ cylinder = {{ center = [0.0, 0.0, {zc:g}], axis = [0.0, 0.0, 1.0], radius = {radius:g}, length = {length:g} }} }}
rate = {{ number = {rate:.1f} }}                 # spheres/s
size = {{ uniform = [{rmin:g}, {rmax:g}] }}           # radius, m
material = "glass"
velocity = [0.0, 0.0, {vz:.1f}]                 # m/s
start = 0.0                                     # s
end = {end:g}                                     # s
every = {every}                                       # steps
seed = {seed}
"""


def inlet_fill(seed):
    """The [[inlet]] section of --fill inlet (module doc) and its pour's end, s."""
    end = INLET_COUNT / INLET_RATE
    z0, z1 = INLET_Z
    text = INLET_FILL.format(
        count=INLET_COUNT, z0=z0, z1=z1, rate=INLET_RATE, end=end,
        per=round(INLET_RATE * INLET_EVERY * 2.0e-5), every=INLET_EVERY,
        every_s=INLET_EVERY * 2.0e-5, speed=INLET_SPEED, zc=0.5 * (z0 + z1),
        radius=INLET_RADIUS, length=z1 - z0, rmin=RADIUS_MIN, rmax=RADIUS_MAX,
        vz=-INLET_SPEED, seed=seed,
    )
    return "\n".join(align_comment(line) for line in text.split("\n")), end


def align_comment(line, column=48):
    """`key = value  # note` with the note at `column`, as in SCENE."""
    if line.startswith("#") or "  # " not in line:
        return line
    code, note = line.split("  # ", 1)
    return f"{code.rstrip():<{column - 1}} # {note}"


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--orifice", type=float, default=12.0e-3, help="orifice diameter D, m")
    ap.add_argument("--out", type=Path, default=Path(__file__).resolve().parent)
    ap.add_argument("--seed", type=int, default=SEED, help="seed of the fill's radii and jitter (or the inlet's)")
    ap.add_argument("--fill", choices=["lattice", "inlet"], default="lattice",
                    help="spheres on a jittered lattice at the start (silo_D<mm>.toml, silo_spheres.csv) "
                    "or poured by an [[inlet]] (silo_inlet_D<mm>.toml)")
    args = ap.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)
    mm = f"{args.orifice * 1e3:g}"
    write_stl(args.out / f"silo_floor_D{mm}.stl", floor_triangles(0.5 * args.orifice))
    if args.fill == "lattice":
        spheres = fill(args.seed)
        with open(args.out / "silo_spheres.csv", "w") as f:
            f.write("x,y,z,radius\n")
            for s in spheres:
                f.write("{:.7g},{:.7g},{:.7g},{:.7g}\n".format(*s))
        count, gate, steps, name, fill_arg = len(spheres), GATE_OPEN, 22500, f"silo_D{mm}.toml", ""
        head = LATTICE_HEAD.format(mm=mm, count=count, gate=gate)
        section = LATTICE_FILL
    else:
        section, pour = inlet_fill(args.seed)
        count, gate, steps, name = INLET_COUNT, INLET_GATE_OPEN, INLET_STEPS, f"silo_inlet_D{mm}.toml"
        fill_arg = " --fill inlet"
        head = INLET_HEAD.format(mm=mm, count=count, pour=pour, gate=gate)
    (args.out / name).write_text(head + SCENE.format(
        mm=mm, D=args.orifice, gate=gate, fill=section, steps=steps, duration=steps * 2.0e-5,
        name=name, fill_arg=fill_arg,
    ))
    print(f"{count} spheres; {args.out}/{name}")


if __name__ == "__main__":
    main()
