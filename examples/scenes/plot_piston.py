#!/usr/bin/env python3
"""The oedometer test of `piston.toml` in one figure: the force on the
servo lid and on the floor against time (with the target F), the lid's
height against time, and a side view of the compressed bed.

    plot_piston.py RUN_DIR OUT.png [--lid K] [--floor K] [--target F] [--height Z0]

RUN_DIR is a `dembound scene examples/scenes/piston.toml --out RUN_DIR`
directory: its `series.csv` (columns `wallK_force_z_N` and
`wallK_position_z_m`, the lid's displacement from its place in the
scene file) and its last `snapshot_*.vtp` (read with
scripts/render_scene.py's reader). SI in, mm and N on the axes. Needs
numpy and matplotlib. A missing file or column exits 2 naming it.
"""

import argparse
import csv
import sys
from pathlib import Path

import numpy as np

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.patches import Circle  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "scripts"))
import render_scene  # noqa: E402


def series(path):
    """The columns of series.csv as float arrays, by name."""
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    if not rows:
        raise render_scene.InputError(f"{path}: no rows")
    return {k: np.array([float(r[k]) for r in rows]) for k in rows[0]}


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("run", help="the `dembound scene --out` directory")
    p.add_argument("out", help="the PNG to write")
    p.add_argument("--lid", type=int, default=5, help="the servo wall's index (default 5)")
    p.add_argument("--floor", type=int, default=0, help="the floor's index (default 0)")
    p.add_argument("--target", type=float, default=0.05, help="the servo's force F, N (default 0.05)")
    p.add_argument("--height", type=float, default=0.011, help="the lid's height in the scene file, m (default 0.011)")
    a = p.parse_args(argv)
    run = Path(a.run)
    try:
        s = series(run / "series.csv")
        for name in (f"wall{a.lid}_force_z_N", f"wall{a.lid}_position_z_m", f"wall{a.floor}_force_z_N"):
            if name not in s:
                raise render_scene.InputError(f"{run / 'series.csv'}: no column {name}")
        snaps = sorted(run.glob("snapshot_*.vtp"))
        if not snaps:
            raise render_scene.InputError(f"{run}: no snapshot_*.vtp")
        last = render_scene.read_vtk(snaps[-1])
    except (render_scene.InputError, OSError, ValueError) as e:
        print(f"error: {e}", file=sys.stderr)
        return 2
    t = s["time_s"] * 1e3
    lid_force = s[f"wall{a.lid}_force_z_N"]
    floor_force = -s[f"wall{a.floor}_force_z_N"]
    lid_z = (a.height + s[f"wall{a.lid}_position_z_m"]) * 1e3

    fig = plt.figure(figsize=(11.0, 4.2))
    grid = fig.add_gridspec(1, 3, width_ratios=[1.2, 1.2, 0.8])
    ax = fig.add_subplot(grid[0])
    ax.plot(t, lid_force, label="on the lid (servo)")
    ax.plot(t, floor_force, label="on the floor", alpha=0.8)
    ax.axhline(a.target, color="k", ls=":", lw=1, label=f"target F = {a.target:g} N")
    ax.set_xlabel("time (ms)")
    ax.set_ylabel("wall force, z (N)")
    ax.legend(loc="upper left", fontsize=8)
    ax.set_title("force")

    ax = fig.add_subplot(grid[1])
    ax.plot(t, lid_z, color="C2")
    ax.set_xlabel("time (ms)")
    ax.set_ylabel("lid height z (mm)")
    ax.set_title("lid position")

    ax = fig.add_subplot(grid[2])
    x = last["points"]
    r = last["point"]["radius"]
    for (px, _, pz), rad in zip(x, r):
        ax.add_patch(Circle((px * 1e3, pz * 1e3), rad * 1e3, fc="C0", ec="k", lw=0.3, alpha=0.35))
    width = float(np.max(x[:, 0] + r)) * 1e3
    ax.axhline(lid_z[-1], color="C2", lw=2, label="lid")
    ax.axhline(0.0, color="k", lw=2)
    ax.set_xlim(0.0, max(width, 1e-9))
    ax.set_ylim(-0.3, a.height * 1e3)
    ax.set_aspect("equal")
    ax.set_xlabel("x (mm)")
    ax.set_ylabel("z (mm)")
    time = float(np.ravel(last["field"].get("TIME", [np.nan]))[0])
    ax.set_title(f"side view at {time * 1e3:.0f} ms")
    fig.suptitle(f"Servo lid on a settled bed ({len(r)} spheres): "
                 f"F = {lid_force[-1]:.4f} N, lid at z = {lid_z[-1]:.3f} mm")
    fig.tight_layout()
    fig.savefig(a.out, dpi=110)
    return 0


if __name__ == "__main__":
    sys.exit(main())
