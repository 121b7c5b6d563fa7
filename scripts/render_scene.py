#!/usr/bin/env python3
"""Render one snapshot of a `dembound scene --out DIR` run to a PNG, with
its triangle-mesh walls, without ParaView or a VTK library.

    render_scene.py DIR OUT.png [--index K | --time T] [--elev E] [--azim A]
                    [--scene SCENE.toml] [--no-walls] [--title TEXT]

DIR holds the run's `snapshots.pvd` (a .pvd file may be given instead of
DIR) and `scene.toml` (the resolved scene, whose mesh files are absolute;
`--scene` names another). The snapshot is the K-th of the .pvd (default
the last; negative counts from the end) or the one nearest to T seconds.

Drawn: every sphere of the snapshot as a marker sized by its radius and
coloured by its speed |v| (colour bar in m/s); every `[[wall]] mesh` as
its triangles, placed as the engine places them (scale, then the rotation
about `axis` by `angle` degrees through the origin, then `translate`).
When the .pvd lists per-triangle loads for that snapshot
(`wall_K_NNNNNN.vtp`: PolyData with the placed triangles and the cell
array `pressure` in Pa), wall K's triangles are coloured by their normal
pressure (colour bar "wall pressure (Pa)"), semi-transparent so that the
spheres behind show; otherwise they are drawn in translucent grey.
Planes, cylinders and boundary particles are not drawn. Axes in m.

The VTK files are read as the engine writes them (XML, `format="binary"`
base64 arrays with a UInt64 or UInt32 size header, uncompressed; or
`format="ascii"`); STL (binary or ASCII) and Wavefront OBJ by the small
readers below. Needs numpy and matplotlib. A missing or unreadable file
exits 2 naming it.
"""

import argparse
import base64
import math
import re
import struct
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib import cm, colors, ticker  # noqa: E402
from mpl_toolkits.mplot3d import proj3d  # noqa: E402
from mpl_toolkits.mplot3d.art3d import Poly3DCollection  # noqa: E402

TYPES = {
    "Float64": "<f8",
    "Float32": "<f4",
    "Int64": "<i8",
    "Int32": "<i4",
    "UInt64": "<u8",
    "UInt32": "<u4",
    "UInt8": "u1",
    "Int8": "i1",
}
SNAPSHOT = re.compile(r"snapshot_(\d+)\.vtp$")
WALL_LOADS = re.compile(r"wall_(\d+)_(\d+)\.vtp$")


class InputError(Exception):
    """A missing, unreadable or malformed input file (exit 2)."""


# ---------------------------------------------------------------- VTK XML


def read_vtk(path):
    """The arrays of a VTK XML PolyData file, by section: `field`, `points`,
    `point`, `cell` (dicts name → array) and `polys`, `verts` (dicts with
    `connectivity` and `offsets`). Vectors come as (n, components)."""
    path = Path(path)
    if not path.is_file():
        raise InputError(f"{path}: no such file")
    try:
        root = ET.parse(path).getroot()
    except (ET.ParseError, OSError) as e:
        raise InputError(f"{path}: not a readable VTK XML file ({e})") from e
    if root.get("compressor"):
        raise InputError(f"{path}: compressed arrays ({root.get('compressor')}) are not supported")
    header = {"UInt64": "<Q", "UInt32": "<I"}.get(root.get("header_type", "UInt32"))
    if header is None:
        raise InputError(f"{path}: header_type {root.get('header_type')} is not UInt64 or UInt32")
    sections = {"FieldData": "field", "Points": "points", "PointData": "point", "CellData": "cell",
                "Polys": "polys", "Verts": "verts"}
    out = {name: {} for name in sections.values()}
    for element in root.iter():
        section = sections.get(element.tag)
        if section is None:
            continue
        for a in element.findall("DataArray"):
            name = a.get("Name", "")
            try:
                out[section][name] = decode_array(a, header)
            except (ValueError, KeyError, struct.error) as e:
                raise InputError(f"{path}: array {name!r} cannot be decoded ({e})") from e
    points = out.pop("points")
    out["points"] = next(iter(points.values())) if points else np.zeros((0, 3))
    return out


def decode_array(a, header):
    dtype = np.dtype(TYPES[a.get("type")])
    comps = int(a.get("NumberOfComponents", "1"))
    text = (a.text or "").strip()
    fmt = a.get("format", "ascii")
    if fmt == "binary":
        raw = base64.b64decode(text)
        size = struct.calcsize(header)
        (n,) = struct.unpack(header, raw[:size])
        values = np.frombuffer(raw[size:size + n], dtype=dtype)
    elif fmt == "ascii":
        values = np.array(text.split(), dtype=dtype)
    else:
        raise ValueError(f"format {fmt!r} (appended data) is not supported")
    return values.reshape(-1, comps) if comps > 1 else values


def read_pvd(path):
    """The (time in s, file path) entries of a .pvd collection, in order."""
    path = Path(path)
    if not path.is_file():
        raise InputError(f"{path}: no such file (a `dembound scene --out DIR` run writes DIR/snapshots.pvd)")
    try:
        root = ET.parse(path).getroot()
    except (ET.ParseError, OSError) as e:
        raise InputError(f"{path}: not a readable .pvd file ({e})") from e
    entries = []
    for d in root.iter("DataSet"):
        try:
            entries.append((float(d.get("timestep")), path.parent / d.get("file")))
        except (TypeError, ValueError) as e:
            raise InputError(f"{path}: a DataSet without a valid timestep and file ({e})") from e
    return entries


def triangles_of(polydata, path):
    """(n, 3, 3) triangle vertices of a PolyData's Polys (m)."""
    polys = polydata["polys"]
    if "connectivity" not in polys or "offsets" not in polys:
        raise InputError(f"{path}: no Polys (triangles)")
    conn, offsets = polys["connectivity"].astype(np.int64), polys["offsets"].astype(np.int64)
    if len(offsets) and not np.array_equal(np.diff(np.concatenate(([0], offsets))), np.full(len(offsets), 3)):
        raise InputError(f"{path}: polygons other than triangles")
    if len(conn) and (conn.min() < 0 or conn.max() >= len(polydata["points"])):
        raise InputError(f"{path}: a triangle names a point out of range")
    return polydata["points"][conn].reshape(-1, 3, 3)


# ------------------------------------------------------------ mesh files


def read_mesh_file(path):
    """(n, 3, 3) triangle vertices of an STL (binary or ASCII) or OBJ file,
    in the file's units."""
    path = Path(path)
    if not path.is_file():
        raise InputError(f"{path}: no such mesh file")
    data = path.read_bytes()
    suffix = path.suffix.lower()
    if suffix == ".stl":
        # Binary when the length is exactly 84 + 50 n (n in the header),
        # as the engine decides: binary files may start with "solid" too.
        if len(data) >= 84 and len(data) == 84 + 50 * struct.unpack("<I", data[80:84])[0]:
            n = struct.unpack("<I", data[80:84])[0]
            records = np.frombuffer(data[84:], dtype=np.dtype([("n", "<f4", 3), ("v", "<f4", (3, 3)), ("a", "<u2")]),
                                    count=n)
            return records["v"].astype(np.float64)
        words = data.decode("ascii", errors="replace").split()
        try:
            values = [[float(w) for w in words[i + 1:i + 4]] for i, w in enumerate(words) if w == "vertex"]
        except ValueError as e:
            raise InputError(f"{path}: malformed ASCII STL ({e})") from e
        if not values or len(values) % 3:
            raise InputError(f"{path}: not a binary STL and no ASCII facets")
        return np.array(values).reshape(-1, 3, 3)
    if suffix == ".obj":
        vertices, faces = [], []
        for line in data.decode("utf-8", errors="replace").splitlines():
            parts = line.split()
            if not parts:
                continue
            try:
                if parts[0] == "v":
                    vertices.append([float(w) for w in parts[1:4]])
                elif parts[0] == "f":
                    idx = [int(w.split("/")[0]) for w in parts[1:]]
                    idx = [i - 1 if i > 0 else len(vertices) + i for i in idx]
                    faces += [(idx[0], idx[k], idx[k + 1]) for k in range(1, len(idx) - 1)]  # a fan
            except ValueError as e:
                raise InputError(f"{path}: malformed OBJ line {line!r}") from e
        v = np.array(vertices, dtype=np.float64).reshape(-1, 3)
        f = np.array(faces, dtype=np.int64).reshape(-1, 3)
        if len(f) == 0:
            raise InputError(f"{path}: no faces")
        if f.min() < 0 or f.max() >= len(v):
            raise InputError(f"{path}: a face names a vertex out of range")
        return v[f]
    raise InputError(f"{path}: unknown mesh format {suffix!r} (.stl or .obj)")


def place(triangles, mesh):
    """The engine's placement: x' = R (scale x) + translate, R the
    right-handed rotation by `angle` degrees about `axis` (Rodrigues)."""
    x = triangles * float(mesh.get("scale", 1.0))
    rotate = mesh.get("rotate")
    if rotate:
        k = np.asarray(rotate["axis"], dtype=np.float64)
        k = k / np.linalg.norm(k)
        theta = math.radians(float(rotate["angle"]))
        c, s = math.cos(theta), math.sin(theta)
        x = x * c + np.cross(k, x) * s + np.outer(x.reshape(-1, 3) @ k, k).reshape(x.shape) * (1 - c)
    return x + np.asarray(mesh.get("translate", [0.0, 0.0, 0.0]), dtype=np.float64)


def scene_meshes(scene_path):
    """{wall index: placed (n, 3, 3) triangles} of the scene's mesh walls."""
    try:
        import tomllib
    except ImportError:  # Python < 3.11: the same parser as the package tomli
        try:
            import tomli as tomllib
        except ImportError as e:
            raise InputError("reading scene.toml needs Python ≥ 3.11 or the package tomli (pip install tomli)") from e
    scene_path = Path(scene_path)
    if not scene_path.is_file():
        raise InputError(f"{scene_path}: no such scene file (name one with --scene, or pass --no-walls)")
    try:
        scene = tomllib.loads(scene_path.read_text())
    except (tomllib.TOMLDecodeError, OSError, UnicodeDecodeError) as e:
        raise InputError(f"{scene_path}: not a readable TOML scene ({e})") from e
    out = {}
    for k, wall in enumerate(scene.get("wall", [])):
        mesh = wall.get("mesh")
        if mesh is None:
            continue
        if "file" not in mesh:
            raise InputError(f"{scene_path}: wall[{k}].mesh has no file")
        file = Path(mesh["file"])
        if not file.is_absolute():
            file = scene_path.parent / file
        out[k] = place(read_mesh_file(file), mesh)
    return out


# ------------------------------------------------------------ selection


def choose_snapshot(entries, index=None, time=None):
    """(time, path, number) of the chosen particle snapshot."""
    snaps = []
    for t, p in entries:
        m = SNAPSHOT.search(p.name)
        if m:
            snaps.append((t, p, int(m.group(1))))
    if not snaps:
        raise InputError("the .pvd lists no snapshot_NNNNNN.vtp file")
    if time is not None:
        return min(snaps, key=lambda s: abs(s[0] - time))
    k = -1 if index is None else index
    if not -len(snaps) <= k < len(snaps):
        raise InputError(f"--index {k}: the .pvd has {len(snaps)} snapshots (0 to {len(snaps) - 1}, or −1 for the last)")
    return snaps[k]


def wall_load_files(entries, time, number):
    """{wall index: path} of the per-triangle load files of the snapshot:
    those the .pvd lists at the snapshot's time, or else (none there)
    those numbered as the snapshot (wall_K_NNNNNN.vtp)."""
    loads = [(t, int(m.group(1)), int(m.group(2)), p) for t, p in entries for m in [WALL_LOADS.search(p.name)] if m]
    at_time = {k: p for t, k, _, p in loads if math.isclose(t, time, rel_tol=1e-12, abs_tol=1e-300)}
    return at_time or {k: p for _, k, n, p in loads if n == number}


# ------------------------------------------------------------ drawing


def points_per_metre(fig, ax, lo, hi):
    """Points per metre of the drawn view: each axis's half-extent about
    the box's centre, projected to the display, over its length in 3D (the
    largest: the axis least foreshortened; orthographic view)."""
    fig.canvas.draw()
    m = ax.get_proj()
    c = 0.5 * (lo + hi)
    best = 0.0
    for k in range(3):
        d = np.zeros(3)
        d[k] = 0.5 * (hi[k] - lo[k])
        a = ax.transData.transform(proj3d.proj_transform(*(c - d), m)[:2])
        b = ax.transData.transform(proj3d.proj_transform(*(c + d), m)[:2])
        best = max(best, float(np.hypot(*(b - a))) / (2 * d[k]))
    return best * 72.0 / fig.dpi


def render(run, out, index=None, time=None, scene=None, walls=True, elev=30.0, azim=-70.0, title=None,
           size=(9.0, 6.0), dpi=110, zoom=1.0, spheres=True):
    """Draws the chosen snapshot of `run` (a directory or a .pvd) into
    `out` (without the spheres when `spheres` is false: the walls'
    pressure seen unhidden); returns what it drew: {"time": s, "snapshot": path, "spheres":
    count, "plain_walls": [wall indices], "pressure_walls": {wall index:
    (min, max) Pa}, "colour_bars": [labels]}."""
    run = Path(run)
    pvd = run if run.suffix == ".pvd" else run / "snapshots.pvd"
    entries = read_pvd(pvd)
    t_pvd, snap_path, number = choose_snapshot(entries, index, time)
    d = read_vtk(snap_path)
    for name in ("radius", "velocity"):
        if name not in d["point"]:
            raise InputError(f"{snap_path}: no point array {name!r}")
    x, r = d["points"], d["point"]["radius"]
    speed = np.linalg.norm(d["point"]["velocity"], axis=1)
    count = len(x)
    if not spheres:
        x, r, speed = x[:0], r[:0], speed[:0]
    t = float(d["field"]["TIME"][0]) if "TIME" in d["field"] else t_pvd

    plain, loaded, labels = {}, {}, []
    if walls:
        loads = wall_load_files(entries, t_pvd, number)
        for k, p in loads.items():
            v = read_vtk(p)
            if "pressure" not in v["cell"]:
                raise InputError(f"{p}: no cell array 'pressure'")
            loaded[k] = (triangles_of(v, p), v["cell"]["pressure"])
        scene_path = Path(scene) if scene else pvd.parent / "scene.toml"
        if scene or len(loads) == 0 or scene_path.is_file():
            for k, tris in scene_meshes(scene_path).items():
                if k not in loaded:
                    plain[k] = tris

    # The 3-D axes and the colour bars in fixed places: speed on the
    # right, wall pressure (if drawn) on the left, outside the 3-D box.
    fig = plt.figure(figsize=size, dpi=dpi)
    left = 0.1 if loaded else 0.0
    ax = fig.add_axes((left, 0.0, 0.86 - left, 0.94), projection="3d", computed_zorder=False)
    boxes = [x - r[:, None], x + r[:, None]] if len(x) else []
    for tris in list(plain.values()) + [tr for tr, _ in loaded.values()]:
        if len(tris):
            boxes += [tris.reshape(-1, 3)]
    everything = np.concatenate([b.reshape(-1, 3) for b in boxes]) if boxes else np.zeros((1, 3))
    lo, hi = everything.min(axis=0), everything.max(axis=0)
    extent = np.maximum(hi - lo, 1e-3 * (hi - lo).max() + 1e-12)

    # Walls first (beneath the spheres: matplotlib does not depth-sort
    # between collections), translucent.
    for tris in plain.values():
        ax.add_collection3d(Poly3DCollection(tris, facecolors=(0.55, 0.58, 0.65, 0.12),
                                             edgecolors=(0.2, 0.2, 0.25, 0.14), linewidths=0.25, zorder=0))
    if loaded:
        p_max = max((float(np.max(p)) for _, p in loaded.values() if len(p)), default=0.0)
        norm = colors.Normalize(vmin=0.0, vmax=p_max if p_max > 0 else 1.0)
        cmap = plt.get_cmap("YlOrRd")
        for tris, p in loaded.values():
            face = cmap(norm(p))
            face[:, 3] = 0.55 if spheres else 0.95
            ax.add_collection3d(Poly3DCollection(tris, facecolors=face, edgecolors=(0.2, 0.2, 0.25, 0.25),
                                                 linewidths=0.3, zorder=0))
        bar = fig.colorbar(cm.ScalarMappable(norm=norm, cmap=cmap), cax=fig.add_axes((0.05, 0.22, 0.017, 0.5)))
        bar.ax.yaxis.set_ticks_position("left")
        bar.ax.yaxis.set_label_position("left")
        bar.set_label("wall pressure (Pa)")
        labels.append(bar.ax.get_ylabel())

    ax.set_xlim(lo[0], lo[0] + extent[0])
    ax.set_ylim(lo[1], lo[1] + extent[1])
    ax.set_zlim(lo[2], lo[2] + extent[2])
    ax.set_box_aspect(extent, zoom=zoom)
    ax.set_proj_type("ortho")
    ax.view_init(elev=elev, azim=azim)
    # About 5 ticks on the longest axis, proportionally fewer (at least 2)
    # on shorter ones, so that a short axis keeps its labels apart.
    for axis, e in zip((ax.xaxis, ax.yaxis, ax.zaxis), extent):
        axis.set_major_locator(ticker.MaxNLocator(nbins=max(2, min(5, int(round(5 * e / extent.max()))))))

    if spheres:
        speed_norm = colors.Normalize(vmin=0.0, vmax=float(speed.max()) if len(x) and speed.max() > 0 else 1.0)
        bar = fig.colorbar(cm.ScalarMappable(norm=speed_norm, cmap="viridis"),
                           cax=fig.add_axes((0.9, 0.22, 0.017, 0.5)))
        bar.set_label("speed |v| (m/s)")
        labels.append(bar.ax.get_ylabel())
        # Markers of the spheres' true size: area in points² = (2 r ×
        # points per metre)².
        sizes = (2 * r * points_per_metre(fig, ax, lo, lo + extent)) ** 2
        ax.scatter(*x.T, s=sizes, c=speed, cmap="viridis", norm=speed_norm, depthshade=True, edgecolors="none",
                   zorder=1)

    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.set_zlabel("z (m)")
    ax.set_title(title or (f"t = {t:.3f} s: {count} spheres" + ("" if spheres else " (not drawn)")))
    fig.savefig(out, bbox_inches="tight")
    plt.close(fig)
    return {
        "time": t,
        "snapshot": snap_path,
        "spheres": count,
        "plain_walls": sorted(plain),
        "pressure_walls": {k: (float(np.min(p)), float(np.max(p))) for k, (_, p) in loaded.items() if len(p)},
        "colour_bars": labels,
    }


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("run", help="a `dembound scene --out` directory, or its .pvd file")
    p.add_argument("out", help="the PNG to write")
    which = p.add_mutually_exclusive_group()
    which.add_argument("--index", type=int, help="the snapshot's position in the .pvd (default −1: the last)")
    which.add_argument("--time", type=float, help="the snapshot nearest to this time (s)")
    p.add_argument("--scene", help="the scene file naming the mesh walls (default DIR/scene.toml)")
    p.add_argument("--no-walls", action="store_true", help="draw the spheres only")
    p.add_argument("--no-spheres", action="store_true", help="draw the walls only (their pressure unhidden)")
    p.add_argument("--elev", type=float, default=30.0, help="view elevation (degrees, default 30)")
    p.add_argument("--azim", type=float, default=-70.0, help="view azimuth (degrees, default −70)")
    p.add_argument("--title", help="the figure's title (default: the time and the sphere count)")
    p.add_argument("--size", type=float, nargs=2, default=(9.0, 6.0), metavar=("WIDTH", "HEIGHT"),
                   help="figure size (inches, default 9 6)")
    p.add_argument("--dpi", type=float, default=110.0, help="pixels per inch (default 110)")
    p.add_argument("--zoom", type=float, default=1.0, help="enlarge the 3-D box in its axes (default 1)")
    args = p.parse_args(argv)
    try:
        render(args.run, args.out, args.index, args.time, args.scene, not args.no_walls, args.elev, args.azim,
               args.title, tuple(args.size), args.dpi, args.zoom, not args.no_spheres)
    except InputError as e:
        print(f"render_scene.py: {e}", file=sys.stderr)
        return 2
    print(f"wrote {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
