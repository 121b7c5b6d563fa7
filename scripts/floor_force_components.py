#!/usr/bin/env python3
"""The floor's force split into components, late-window means paired by seed.

`dembound compare` reports the floor's |F|; in a chute that mixes the
normal load (the weight's normal part, m g_z per sphere, when the bed does
not accelerate along z) with the floor's friction. This script reads, per
seed, a scene deck's `walls.txt` (step, then Fx Fy Fz of each wall: the
force the spheres exert on it) and dembound's `series.csv` of the same
scene (`dembound scene DECK/scene.toml --out DIR`: wall0_force_x_N …), and
prints the mean over seeds of each code's late-window mean of wall 0's Fx
and Fz, and the per-seed differences code/dembound − 1 (mean ± SE).

Usage: floor_force_components.py --from T_S --dt DT DECK DIR [DECK DIR ...]
(T_S: the window's start in s, as `dembound compare` prints it in
`window_from`; DT: the scene's time step in s.)
"""

import argparse
import csv
import math


def mean_se(values):
    n = len(values)
    m = sum(values) / n
    if n < 2:
        return m, float("nan")
    return m, math.sqrt(sum((v - m) ** 2 for v in values) / (n - 1) / n)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--from", dest="start", type=float, required=True)
    ap.add_argument("--dt", type=float, required=True)
    ap.add_argument("pairs", nargs="+")
    args = ap.parse_args()
    if len(args.pairs) % 2:
        ap.error("give DECK DIR pairs")
    code = {"x": [], "z": []}
    dem = {"x": [], "z": []}
    for deck, out in zip(args.pairs[::2], args.pairs[1::2]):
        with open(f"{deck}/walls.txt") as f:
            rows = [list(map(float, line.split())) for line in f if not line.startswith("#")]
        rows = [r for r in rows if r[0] * args.dt >= args.start - 1e-12]
        with open(f"{out}/series.csv") as f:
            series = [r for r in csv.DictReader(f) if float(r["time_s"]) >= args.start - 1e-12]
        for axis, column in (("x", 1), ("z", 3)):
            code[axis].append(sum(r[column] for r in rows) / len(rows))
            dem[axis].append(sum(float(r[f"wall0_force_{axis}_N"]) for r in series) / len(series))
    n = len(code["x"])
    for axis in ("x", "z"):
        c, d = mean_se(code[axis]), mean_se(dem[axis])
        rel = mean_se([a / b - 1.0 for a, b in zip(code[axis], dem[axis])])
        print(f"F{axis} (N): code {c[0]:.5g} ± {c[1]:.2g}, dembound {d[0]:.5g} ± {d[1]:.2g}, "
              f"code/dembound - 1 = {100 * rel[0]:+.2f} % ± {100 * rel[1]:.2f} % over {n} seeds")


if __name__ == "__main__":
    main()
