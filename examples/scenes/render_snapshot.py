#!/usr/bin/env python3
"""Render one `dembound scene` VTK snapshot (.vtp, or .pvtp of per-rank pieces) to a PNG, without ParaView.

Usage: render_snapshot.py SNAPSHOT.vtp|SNAPSHOT.pvtp OUT.png [--title TEXT] [--colour-by-piece]

A .pvtp (MPI, `[parallel] vtk_per_rank`) is read piece by piece, the pieces
its `<Piece Source>` entries name; --colour-by-piece colours each free sphere
by the piece (rank) that wrote it instead of by height.

Free spheres are drawn as shaded markers sized by their radius and coloured
by their height; fixed (boundary) spheres as their surfaces, clipped to the
box around the free spheres and drawn first (beneath the free spheres). Axes in mm. Needs numpy and
matplotlib (pip install matplotlib).
"""
import argparse
import base64
import struct
import xml.etree.ElementTree as ET

import numpy as np
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

TYPES = {"Float64": "<f8", "Float32": "<f4", "Int64": "<i8", "Int32": "<i4", "UInt8": "u1", "UInt64": "<u8"}


def read_vtp(path):
    """Every DataArray of the file by name (binary, UInt64 header, uncompressed)."""
    root = ET.parse(path).getroot()
    if root.get("header_type") != "UInt64" or root.get("compressor"):
        raise SystemExit(f"{path}: expected uncompressed binary arrays with a UInt64 header")
    arrays = {}
    for a in root.iter("DataArray"):
        raw = base64.b64decode(a.text.strip())
        (n,) = struct.unpack("<Q", raw[:8])
        values = np.frombuffer(raw[8 : 8 + n], dtype=TYPES[a.get("type")])
        comps = int(a.get("NumberOfComponents", "1"))
        arrays[a.get("Name")] = values.reshape(-1, comps) if comps > 1 else values
    return arrays


def read_pvtp(path):
    """The arrays of every piece a .pvtp lists, concatenated, and each point's piece number."""
    import os

    root = ET.parse(path).getroot()
    if root.get("type") != "PPolyData":
        raise SystemExit(f"{path}: expected a PPolyData index")
    sources = [p.get("Source") for p in root.iter("Piece")]
    pieces = [read_vtp(os.path.join(os.path.dirname(path), s)) for s in sources]
    local = {"connectivity", "offsets", "TIME", "STEP"}
    names = [n for n in pieces[0] if n not in local]
    arrays = {n: np.concatenate([p[n] for p in pieces]) for n in names}
    arrays["TIME"] = pieces[0]["TIME"]
    arrays["piece"] = np.concatenate([np.full(len(p["id"]), k) for k, p in enumerate(pieces)])
    return arrays


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("snapshot")
    p.add_argument("out")
    p.add_argument("--title", default=None)
    p.add_argument("--colour-by-piece", action="store_true")
    args = p.parse_args()
    d = read_pvtp(args.snapshot) if args.snapshot.endswith(".pvtp") else read_vtp(args.snapshot)
    by_piece = args.colour_by_piece and "piece" in d
    x, r, fixed = d["position"] * 1e3, d["radius"] * 1e3, d["fixed"].astype(bool)
    free = ~fixed
    lo, hi = x[free].min(axis=0) - r[free].max(), x[free].max(axis=0) + r[free].max()
    span = (hi - lo).max()
    fig = plt.figure(figsize=(8, 7), dpi=120)
    ax = fig.add_subplot(projection="3d", computed_zorder=False)
    # Boundary spheres: the part of each surface above the box's floor
    # and inside its x-y footprint.
    u = np.linspace(lo[0], hi[0], 60)
    v = np.linspace(lo[1], hi[1], 60)
    gx, gy = np.meshgrid(u, v)
    for c, rb in zip(x[fixed], r[fixed]):
        q = rb**2 - (gx - c[0]) ** 2 - (gy - c[1]) ** 2
        if (q <= 0).all():
            continue
        gz = np.where(q > 0, c[2] + np.sqrt(np.clip(q, 0, None)), np.nan)
        if np.nanmax(gz) < lo[2] - 0.5 * span:
            continue
        ax.plot_surface(gx, gy, gz, color="0.55", alpha=0.8, linewidth=0, antialiased=True, zorder=0)
    # Marker area in points²: the sphere's diameter as a fraction of the
    # axes' span, times the axes' width in points (approximate in 3D).
    width_pt = 0.42 * fig.get_size_inches()[0] * 72
    sizes = (2 * r[free] / span * width_pt) ** 2
    if by_piece:
        # One colour a piece, the colour bar's ticks the pieces.
        pieces = int(d["piece"].max()) + 1
        cmap = matplotlib.colors.ListedColormap(plt.get_cmap("tab10").colors[:pieces] if pieces <= 10
                                                else plt.get_cmap("viridis")(np.linspace(0, 1, pieces)))
        style = dict(c=d["piece"][free], cmap=cmap, vmin=-0.5, vmax=pieces - 0.5)
    else:
        style = dict(c=x[free][:, 2], cmap="viridis")
    sc = ax.scatter(*x[free].T, s=sizes, depthshade=True, edgecolors="k", linewidths=0.2, zorder=1,
                    **style)
    bar = fig.colorbar(sc, ax=ax, shrink=0.6, pad=0.1,
                       label="piece (MPI rank)" if by_piece else "height of the centre z (mm)")
    if by_piece:
        bar.set_ticks(range(pieces))
    centre = 0.5 * (lo + hi)
    for setter, k in ((ax.set_xlim, 0), (ax.set_ylim, 1), (ax.set_zlim, 2)):
        setter(centre[k] - 0.5 * span, centre[k] + 0.5 * span)
    ax.set_xlabel("x (mm)")
    ax.set_ylabel("y (mm)")
    ax.set_zlabel("z (mm)")
    ax.set_box_aspect((1, 1, 1))
    time = float(d["TIME"][0]) if "TIME" in d else float("nan")
    pieces_text = f" in {int(d['piece'].max()) + 1} pieces" if "piece" in d else ""
    ax.set_title(args.title or f"{free.sum()} free spheres, {fixed.sum()} boundary spheres{pieces_text}, "
                 f"t = {time * 1e3:.1f} ms")
    ax.view_init(elev=18, azim=-60)
    fig.savefig(args.out, bbox_inches="tight")
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
