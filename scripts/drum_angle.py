#!/usr/bin/env python3
"""The dynamic angle of repose of a rotating-drum run (issue 27), from its
free surface, and a picture of it.

    drum_angle.py RUN [--liggghts] [--from T] [--radius R] [--length L]
                  [--png OUT.png] [--title TEXT] [--json]

RUN is a `dembound scene --out DIR` run (its VTK snapshots, `snapshots.pvd`)
or, with --liggghts, the directory of a deck written by `dembound export
liggghts` and run there (its `particles.dump`). The drum's axis is y through
the origin, gravity along −z (examples/scenes/drum.toml). Fixed spheres
(the lining of examples/scenes/lined_drum.toml) are left out.

Method (stated, as the issue asks):
1. the mid-length slab: the spheres whose centre has |y| < L/4 (the middle
   half of the drum, away from the end caps' friction);
2. the free surface: the slab's x range cut into bins one mean diameter
   wide; in each bin the top of the top-most sphere, max(z + r);
3. time average: the surface height per bin averaged over the snapshots
   at t ≥ T (the steady part; default: the last half of the run);
4. a straight line z = a + b x fitted by least squares to the averaged
   heights of the bins in the flat middle of the surface, |x| < R/2 (the
   surface's chord spans ~±0.95 R at the drum's 33 % fill; its ends bend
   where the bed meets the wall);
5. the angle = atan |b|, in degrees.

The picture: the last snapshot's slab (spheres as circles of their radius,
projected on the x–z plane), the drum's circle, the averaged surface bins
(the fitted ones marked) and the fitted line; axes in mm.

Needs numpy and matplotlib. Exits 2 naming a missing or unreadable file.
"""

import argparse
import base64
import json
import math
import re
import struct
import sys
from pathlib import Path

import numpy as np

DRUM_RADIUS = 0.028  # m, examples/scenes/drum.toml's drum (corners)
DRUM_LENGTH = 0.018  # m


def fail(msg):
    print(f"drum_angle.py: {msg}", file=sys.stderr)
    sys.exit(2)


def vtp_arrays(path):
    """{name: numpy array} of the binary DataArrays of an engine .vtp."""
    text = Path(path).read_text()
    out = {}
    for m in re.finditer(
        r'<DataArray type="(\w+)" Name="(\w+)"[^>]*format="binary">([^<]*)</DataArray>', text
    ):
        kind, name, data = m.groups()
        raw = base64.b64decode(data)
        (n,) = struct.unpack("<Q", raw[:8])
        fmt = {"Float64": "d", "UInt64": "Q", "Int64": "q", "Int32": "i", "UInt32": "I",
               "UInt8": "B"}.get(kind)
        if fmt is None:
            continue
        size = struct.calcsize(fmt)
        out[name] = np.array(struct.unpack(f"<{n // size}{fmt}", raw[8 : 8 + n]))
    return out


def dembound_frames(run):
    """[(t in s, positions (n, 3) m, radii (n,) m)] of a dembound run."""
    files = sorted(Path(run).glob("snapshot_*.vtp"))
    if not files:
        fail(f"no snapshot_*.vtp in {run}")
    frames = []
    for f in files:
        a = vtp_arrays(f)
        if "position" not in a or "radius" not in a or "TIME" not in a:
            fail(f"{f}: no position, radius or TIME array")
        pos, radius = a["position"].reshape(-1, 3), a["radius"]
        if "fixed" in a:
            # The free spheres only (a lined drum's lining is fixed).
            free = a["fixed"] == 0
            pos, radius = pos[free], radius[free]
        frames.append((float(a["TIME"][0]), pos, radius))
    return frames


def liggghts_frames(deck):
    """The same from a LIGGGHTS deck's particles.dump (id type radius x y z ...)."""
    path = Path(deck) / "particles.dump"
    try:
        text = path.read_text()
    except OSError as e:
        fail(f"{path}: {e}")
    dt = None
    for line in (Path(deck) / "in.liggghts").read_text().splitlines():
        if line.startswith("timestep"):
            dt = float(line.split()[1])
    if dt is None:
        fail(f"{deck}/in.liggghts: no timestep")
    frames = []
    for block in text.split("ITEM: TIMESTEP\n")[1:]:
        lines = block.splitlines()
        step = int(lines[0])
        start = next(i for i, l in enumerate(lines) if l.startswith("ITEM: ATOMS")) + 1
        rows = np.array([[float(w) for w in l.split()[:6]] for l in lines[start:] if l.strip()])
        frames.append((step * dt, rows[:, 3:6], rows[:, 2]))
    if not frames:
        fail(f"{path}: no dump")
    return frames


def surface(pos, radius, edges, length):
    """Top of the top-most sphere of the mid-length slab in each x bin (nan: empty)."""
    slab = np.abs(pos[:, 1]) < 0.25 * length
    x, top = pos[slab, 0], pos[slab, 2] + radius[slab]
    k = np.digitize(x, edges) - 1
    h = np.full(len(edges) - 1, np.nan)
    for b in range(len(h)):
        sel = k == b
        if sel.any():
            h[b] = top[sel].max()
    return h


def measure(frames, t_from, drum_radius, length):
    """(angle in degrees, slope b, intercept a (m), bin centres, mean heights, fitted mask, frames used)."""
    diameter = 2.0 * float(np.mean(frames[0][2]))
    n_bins = int(2 * drum_radius / diameter)
    edges = np.linspace(-drum_radius, drum_radius, n_bins + 1)
    centres = 0.5 * (edges[1:] + edges[:-1])
    used = [f for f in frames if f[0] >= t_from - 1e-12]
    if not used:
        fail(f"no snapshot at t >= {t_from} s (the last is at {frames[-1][0]} s)")
    heights = np.array([surface(p, r, edges, length) for _, p, r in used])
    # Bins empty in some frame are left out of that frame's mean.
    with np.errstate(all="ignore"):
        mean = np.nanmean(heights, axis=0)
    fit = (np.abs(centres) < 0.5 * drum_radius) & np.isfinite(mean)
    if fit.sum() < 3:
        fail("fewer than 3 surface bins in |x| < R/2: is the drum filled?")
    b, a = np.polyfit(centres[fit], mean[fit], 1)
    return math.degrees(math.atan(abs(b))), b, a, centres, mean, fit, used


def frame_angles(frames, drum_radius, length):
    """The angle (degrees) fitted to each snapshot alone: a steady rolling
    surface keeps it within a degree or two; slumping saws up and down."""
    out = []
    for f in frames:
        angle, *_ = measure([f], f[0], drum_radius, length)
        out.append(angle)
    return np.array(out)


def picture(path, frame, drum_radius, length, centres, mean, fit, a, b, angle, title):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.collections import PatchCollection
    from matplotlib.patches import Circle

    t, pos, radius = frame
    slab = np.abs(pos[:, 1]) < 0.25 * length
    fig, ax = plt.subplots(figsize=(6.4, 6.4))
    circles = [Circle((1e3 * x, 1e3 * z), 1e3 * r) for (x, _, z), r in zip(pos[slab], radius[slab])]
    ax.add_collection(PatchCollection(circles, facecolor="#9ecae1", edgecolor="#3182bd", lw=0.4))
    ax.add_patch(Circle((0, 0), 1e3 * drum_radius, fill=False, color="k", lw=1.2))
    ok = np.isfinite(mean)
    ax.plot(1e3 * centres[ok & ~fit], 1e3 * mean[ok & ~fit], "o", ms=3, color="0.5",
            label="mean surface (bins not fitted)")
    ax.plot(1e3 * centres[fit], 1e3 * mean[fit], "o", ms=4, color="C3",
            label="mean surface (fitted, |x| < R/2)")
    xs = np.array([-drum_radius, drum_radius])
    ax.plot(1e3 * xs, 1e3 * (a + b * xs), "-", color="C3", lw=1.5,
            label=f"fit: angle {angle:.1f}°")
    ax.set_xlim(-1.05e3 * drum_radius, 1.05e3 * drum_radius)
    ax.set_ylim(-1.05e3 * drum_radius, 1.05e3 * drum_radius)
    ax.set_aspect("equal")
    ax.set_xlabel("x (mm)")
    ax.set_ylabel("z (mm), gravity along −z")
    ax.set_title(title or f"drum, mid-length slab |y| < L/4 at t = {t:.2f} s")
    ax.legend(loc="upper left", fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("run")
    p.add_argument("--liggghts", action="store_true", help="RUN is a LIGGGHTS deck directory")
    p.add_argument("--from", dest="t_from", type=float, help="start of the steady part, s")
    p.add_argument("--radius", type=float, default=DRUM_RADIUS, help="drum radius, m")
    p.add_argument("--length", type=float, default=DRUM_LENGTH, help="drum length, m")
    p.add_argument("--png", help="write the picture here")
    p.add_argument("--title")
    p.add_argument("--json", action="store_true", help="print the result as JSON")
    args = p.parse_args()
    frames = (liggghts_frames if args.liggghts else dembound_frames)(args.run)
    t_end = frames[-1][0]
    t_from = args.t_from if args.t_from is not None else 0.5 * t_end
    angle, b, a, centres, mean, fit, used = measure(frames, t_from, args.radius, args.length)
    if args.png:
        picture(args.png, used[-1], args.radius, args.length, centres, mean, fit, a, b, angle,
                args.title)
    spread = frame_angles(used, args.radius, args.length)
    result = {
        "angle_deg": angle,
        "per_snapshot_std_deg": float(np.std(spread)),
        "slope": b,
        "intercept_m": a,
        "snapshots": len(used),
        "from_s": t_from,
        "to_s": t_end,
        "fitted_bins": int(fit.sum()),
    }
    if args.json:
        print(json.dumps(result))
    else:
        print(
            f"dynamic angle of repose {angle:.2f}° (slope {b:+.4f}, {int(fit.sum())} bins, "
            f"{len(used)} snapshots from t = {t_from:.3f} s to {t_end:.3f} s; each snapshot's "
            f"own fit {np.mean(spread):.2f}° ± {np.std(spread):.2f}°)"
        )


if __name__ == "__main__":
    main()
