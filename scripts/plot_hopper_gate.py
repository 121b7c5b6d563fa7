#!/usr/bin/env python3
"""Mass flow rate out of a hopper whose gate opens (issue 28), from a
`dembound scene --out DIR` run of examples/scenes/hopper_gate.toml.

    python3 scripts/plot_hopper_gate.py DIR/series.csv OUT.png [--gate 0.15]

Top: the outlet's mass flow rate (series.csv `outlet0_rate_kg_per_s`: the
mass removed since the previous row over the time between, kg/s) against
time, the gate's opening marked, and the steady rate (the mean over the
rows from 0.08 s after the opening to the end: the first spheres reach the outlet box 20 mm below the gate after √(2·0.02/g) = 64 ms) as a line with its standard
error. Bottom: the mass discharged (`outlet0_mass_kg`, g) and the gate
energy booked (`gate_energy_J`, µJ). Needs matplotlib.
"""

import argparse
import csv
import math
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("series", help="series.csv of the run")
    p.add_argument("out", help="the PNG to write")
    p.add_argument("--gate", type=float, default=0.15, help="the gate's opening time, s")
    p.add_argument("--settle", type=float, default=0.08,
                   help="the steady rate is taken from this long after the opening, s")
    a = p.parse_args()
    with open(a.series, newline="") as f:
        rows = list(csv.DictReader(f))
    if not rows or "outlet0_rate_kg_per_s" not in rows[0]:
        print(f"{a.series}: no outlet0 columns (a scene with an [[outlet]]?)", file=sys.stderr)
        return 2
    t = [float(r["time_s"]) for r in rows]
    rate = [float(r["outlet0_rate_kg_per_s"]) for r in rows]
    mass = [1e3 * float(r["outlet0_mass_kg"]) for r in rows]
    gate = [1e6 * float(r["gate_energy_J"]) for r in rows] if "gate_energy_J" in rows[0] else None
    steady = [q for s, q in zip(t, rate) if s >= a.gate + a.settle and q > 0.0]
    mean = sum(steady) / len(steady) if steady else float("nan")
    sd = (math.sqrt(sum((q - mean) ** 2 for q in steady) / (len(steady) - 1))
          if len(steady) > 1 else float("nan"))
    err = sd / math.sqrt(len(steady)) if steady else float("nan")
    # The steady window may end when the hopper runs empty: report where.
    print(f"steady rate {mean:.6g} kg/s ± {err:.2g} kg/s (standard error over {len(steady)} "
          f"rows from t = {a.gate + a.settle:g} s with a non-zero rate); discharged "
          f"{mass[-1]:.4g} g by t = {t[-1]:g} s")

    fig, (top, bottom) = plt.subplots(2, 1, figsize=(7.5, 6.5), sharex=True)
    top.plot(t, [1e3 * q for q in rate], lw=0.8, color="tab:blue", label="outlet 0")
    top.axvline(a.gate, color="k", ls="--", lw=0.8, label=f"gate opens (t = {a.gate:g} s)")
    if steady:
        top.axhline(1e3 * mean, color="tab:red", lw=1.0,
                    label=f"steady {1e3 * mean:.3g} ± {1e3 * err:.1g} g/s")
    top.set_ylabel("mass flow rate (g/s)")
    top.legend(loc="upper left", fontsize=8)
    top.set_title("Hopper discharge through an opening gate (dembound, hopper_gate.toml)", fontsize=10)
    bottom.plot(t, mass, color="tab:green", label="mass discharged (g)")
    bottom.set_ylabel("mass discharged (g)")
    bottom.set_xlabel("time (s)")
    bottom.axvline(a.gate, color="k", ls="--", lw=0.8)
    if gate is not None:
        right = bottom.twinx()
        right.plot(t, gate, color="tab:purple", lw=0.8, label="gate energy G (µJ)")
        right.set_ylabel("gate energy G (µJ)")
        right.legend(loc="lower right", fontsize=8)
    bottom.legend(loc="upper left", fontsize=8)
    fig.tight_layout()
    fig.savefig(a.out, dpi=120)
    return 0


if __name__ == "__main__":
    sys.exit(main())
