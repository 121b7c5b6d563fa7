"""scripts/render_scene.py (issue 26): renders a `dembound scene --out`
run's snapshot with its mesh walls to a PNG; colours a wall by the
pressure of its per-triangle load file (`wall_K_NNNNNN.vtp`) when the .pvd
lists one; places meshes as the engine does; missing files exit 2 naming
them."""

from __future__ import annotations

import base64
import importlib.util
import math
import struct
import subprocess
import sys

import numpy as np
import pytest

from conftest import REPO

SCRIPT = REPO / "scripts" / "render_scene.py"
_spec = importlib.util.spec_from_file_location("render_scene", SCRIPT)
render_scene = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(render_scene)

PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"

# A floor [0, 0.02]² at z = 0 as two triangles (ASCII STL).
FLOOR = """solid floor
facet normal 0 0 1
outer loop
vertex 0 0 0
vertex 0.02 0 0
vertex 0.02 0.02 0
endloop
endfacet
facet normal 0 0 1
outer loop
vertex 0 0 0
vertex 0.02 0.02 0
vertex 0 0.02 0
endloop
endfacet
endsolid floor
"""
FLOOR_TRIANGLES = np.array(
    [[[0, 0, 0], [0.02, 0, 0], [0.02, 0.02, 0]], [[0, 0, 0], [0.02, 0.02, 0], [0, 0.02, 0]]], dtype=float
)

TINY_SCENE = """
[domain]
lower = [0.0, 0.0, -0.001]
upper = [0.02, 0.02, 0.02]

[[material]]
name = "grain"
density = 1000.0
youngs_modulus = 1.0e7
poisson_ratio = 0.3

[[particles]]
lattice = { counts = [3, 3, 2], spacing = [5.0e-3, 5.0e-3, 3.0e-3], origin = [5.0e-3, 5.0e-3, 2.0e-3], radius = 1.0e-3 }
material = "grain"

[[wall]]
mesh = { file = "floor.stl" }
material = "grain"

[integration]
dt = 5.0e-6
steps = 400

[output]
every = 200
"""


def run_script(*args):
    return subprocess.run(
        [sys.executable, str(SCRIPT), *map(str, args)], capture_output=True, text=True, timeout=300
    )


def assert_png(path):
    data = path.read_bytes()
    assert data[:8] == PNG_SIGNATURE, f"{path} is not a PNG"
    # IHDR: width and height, big-endian, right after the signature.
    width, height = struct.unpack(">II", data[16:24])
    assert width > 300 and height > 200, f"{path}: {width} × {height} px"


# ------------------------------------------------------------ VTK writer
# The engine's format (crates/dembound-scene/src/io/vtk.rs): XML PolyData,
# base64 binary arrays with a UInt64 byte count, little-endian.


def data_array(name, values, kind):
    raw = np.ascontiguousarray(values, dtype={"Float64": "<f8", "Int64": "<i8", "Int32": "<i4"}[kind]).tobytes()
    comps = values.shape[1] if np.ndim(values) == 2 else 1
    extra = f' NumberOfComponents="{comps}"' if comps > 1 else ""
    text = base64.b64encode(struct.pack("<Q", len(raw)) + raw).decode()
    return f'<DataArray type="{kind}" Name="{name}"{extra} format="binary">{text}</DataArray>'


def write_vtp(path, points, time, point_data=(), cells=None, cell_data=()):
    """PolyData: spheres as vertices (cells None) or triangles (cells)."""
    n = len(points)
    if cells is None:
        topology = "Verts"
        conn, offsets = np.arange(n), np.arange(1, n + 1)
        counts = f'NumberOfVerts="{n}" NumberOfPolys="0"'
    else:
        topology = "Polys"
        conn, offsets = np.asarray(cells).ravel(), 3 * np.arange(1, len(cells) + 1)
        counts = f'NumberOfVerts="0" NumberOfPolys="{len(cells)}"'
    path.write_text(
        '<?xml version="1.0"?>\n'
        '<VTKFile type="PolyData" version="1.0" byte_order="LittleEndian" header_type="UInt64">\n'
        f"<PolyData><FieldData>{data_array('TIME', np.array([time]), 'Float64')}</FieldData>\n"
        f'<Piece NumberOfPoints="{n}" {counts} NumberOfLines="0" NumberOfStrips="0">\n'
        f"<Points>{data_array('position', np.asarray(points, float), 'Float64')}</Points>\n"
        "<PointData>" + "".join(data_array(k, v, t) for k, v, t in point_data) + "</PointData>\n"
        "<CellData>" + "".join(data_array(k, v, t) for k, v, t in cell_data) + "</CellData>\n"
        f"<{topology}>{data_array('connectivity', conn, 'Int64')}{data_array('offsets', offsets, 'Int64')}"
        f"</{topology}>\n</Piece></PolyData></VTKFile>\n"
    )


def write_pvd(path, entries):
    rows = "".join(f'<DataSet timestep="{t:e}" group="" part="{p}" file="{f}"/>\n' for t, p, f in entries)
    path.write_text(
        '<?xml version="1.0"?>\n<VTKFile type="Collection" version="1.0" byte_order="LittleEndian">\n'
        f"<Collection>\n{rows}</Collection>\n</VTKFile>\n"
    )


def synthetic_run(tmp_path):
    """A run directory by hand: two snapshots of three spheres, a scene
    with two mesh walls (the floor, and the floor lifted by 0.01 m), and
    per-triangle loads of wall 0 at the second snapshot only: pressures
    50 and 200 Pa on its two triangles."""
    (tmp_path / "floor.stl").write_text(FLOOR)
    (tmp_path / "scene.toml").write_text(
        '[[wall]]\nmesh = { file = "floor.stl" }\nmaterial = "grain"\n'
        '[[wall]]\nplane = { point = [0.0, 0.0, 0.0], normal = [0.0, 0.0, 1.0] }\nmaterial = "grain"\n'
        '[[wall]]\nmesh = { file = "floor.stl", translate = [0.0, 0.0, 0.01] }\nmaterial = "grain"\n'
    )
    x = np.array([[0.005, 0.005, 0.002], [0.01, 0.012, 0.003], [0.015, 0.004, 0.002]])
    radius = np.full(3, 1e-3)
    for k, (t, v) in enumerate(((0.0, 0.0), (0.01, 0.5))):
        velocity = np.array([[0.0, 0.0, -v], [v, 0.0, 0.0], [0.0, 0.0, 0.0]])
        write_vtp(
            tmp_path / f"snapshot_{k:06d}.vtp",
            x,
            t,
            point_data=[("radius", radius, "Float64"), ("velocity", velocity, "Float64")],
        )
    points = FLOOR_TRIANGLES.reshape(-1, 3)
    write_vtp(
        tmp_path / "wall_0_000001.vtp",
        points,
        0.01,
        cells=np.arange(6).reshape(2, 3),
        cell_data=[
            ("force", np.array([[0.0, 0.0, -0.01], [0.0, 0.0, -0.04]]), "Float64"),
            ("pressure", np.array([50.0, 200.0]), "Float64"),
            ("shear", np.array([0.0, 1.0]), "Float64"),
            ("area", np.array([2e-4, 2e-4]), "Float64"),
            ("triangle_id", np.array([0, 1]), "Int32"),
        ],
    )
    write_pvd(
        tmp_path / "snapshots.pvd",
        [(0.0, 0, "snapshot_000000.vtp"), (0.01, 0, "snapshot_000001.vtp"), (0.01, 1, "wall_0_000001.vtp")],
    )
    return tmp_path


# ------------------------------------------------------------ tests


def test_a_tiny_mesh_scene_renders_to_a_png(cli, tmp_path):
    (tmp_path / "floor.stl").write_text(FLOOR)
    (tmp_path / "tiny.toml").write_text(TINY_SCENE)
    out = cli(["scene", str(tmp_path / "tiny.toml"), "--out", str(tmp_path / "run"), "-q"])
    assert out.returncode == 0, out.stderr
    png = tmp_path / "tiny.png"
    done = run_script(tmp_path / "run", png, "--index", "1", "--elev", "20", "--azim", "-50")
    assert done.returncode == 0, done.stderr
    assert_png(png)
    # The drawing of the same run, in process: the second snapshot (t =
    # 200 steps × 5 µs = 1 ms), its 18 spheres and the floor coloured by
    # the pressure of its load file (wall_0_*.vtp, written by the run).
    drawn = render_scene.render(tmp_path / "run", tmp_path / "again.png", index=1)
    # The snapshot's TIME: 200 steps of 5 µs, round-off of a few ulp.
    assert math.isclose(drawn["time"], 200 * 5e-6, rel_tol=1e-12)
    assert drawn["spheres"] == 18
    assert drawn["plain_walls"] == [] and list(drawn["pressure_walls"]) == [0]
    low, high = drawn["pressure_walls"][0]
    assert 0.0 <= low <= high
    assert drawn["colour_bars"] == ["wall pressure (Pa)", "speed |v| (m/s)"]
    # Without the load files (--no-walls aside, a scene file alone): grey.
    for p in (tmp_path / "run").glob("wall_*.vtp"):
        p.unlink()
    write_pvd(
        tmp_path / "run" / "snapshots.pvd",
        [(0.0, 0, "snapshot_000000.vtp"), (0.001, 0, "snapshot_000001.vtp")],
    )
    grey = render_scene.render(tmp_path / "run", tmp_path / "grey.png", index=1)
    assert grey["plain_walls"] == [0] and grey["pressure_walls"] == {}
    assert grey["colour_bars"] == ["speed |v| (m/s)"]


def test_a_wall_with_a_load_file_is_coloured_by_its_pressure(tmp_path):
    run = synthetic_run(tmp_path)
    png = tmp_path / "loads.png"
    done = run_script(run, png)  # the last snapshot: wall 0's loads listed
    assert done.returncode == 0, done.stderr
    assert_png(png)
    drawn = render_scene.render(run, tmp_path / "again.png", time=0.011)
    assert drawn["snapshot"].name == "snapshot_000001.vtp"
    # Wall 0 from its load file (50 and 200 Pa as written), wall 2 (no
    # load file) from the STL, the plane (wall 1) not drawn.
    assert drawn["pressure_walls"] == {0: (50.0, 200.0)}
    assert drawn["plain_walls"] == [2]
    assert drawn["colour_bars"] == ["wall pressure (Pa)", "speed |v| (m/s)"]
    # The first snapshot has no load file: both meshes in grey.
    first = render_scene.render(run, tmp_path / "first.png", index=0)
    assert first["pressure_walls"] == {} and first["plain_walls"] == [0, 2]
    # Listed at another time, the load file is found by its number.
    write_pvd(
        run / "snapshots.pvd",
        [(0.0, 0, "snapshot_000000.vtp"), (0.01, 0, "snapshot_000001.vtp"), (0.0125, 1, "wall_0_000001.vtp")],
    )
    assert render_scene.render(run, tmp_path / "by_number.png")["pressure_walls"] == {0: (50.0, 200.0)}
    assert render_scene.render(run, tmp_path / "first_again.png", index=0)["pressure_walls"] == {}
    # Without the spheres: the same walls and pressures, no speed bar, the
    # sphere count still reported.
    bare = render_scene.render(run, tmp_path / "bare.png", time=0.011, spheres=False)
    assert bare["pressure_walls"] == {0: (50.0, 200.0)} and bare["plain_walls"] == [2]
    assert bare["colour_bars"] == ["wall pressure (Pa)"]
    assert bare["spheres"] == drawn["spheres"]
    assert_png(tmp_path / "bare.png")


def test_a_load_file_is_read_back_as_written(tmp_path):
    run = synthetic_run(tmp_path)
    loads = render_scene.read_vtk(run / "wall_0_000001.vtp")
    np.testing.assert_array_equal(render_scene.triangles_of(loads, "wall_0"), FLOOR_TRIANGLES)
    np.testing.assert_array_equal(loads["cell"]["pressure"], [50.0, 200.0])
    np.testing.assert_array_equal(loads["cell"]["triangle_id"], [0, 1])
    assert loads["cell"]["force"].shape == (2, 3)


def test_meshes_are_placed_as_the_engine_places_them(tmp_path):
    # Scale 2, then 90° about +z (x → y, y → −x), then translate (1, 2, 3):
    # (0.02, 0, 0) → (0.04, 0, 0) → (0, 0.04, 0) → (1, 2.04, 3).
    placed = render_scene.place(FLOOR_TRIANGLES, {"scale": 2.0, "rotate": {"axis": [0, 0, 5], "angle": 90.0},
                                                  "translate": [1.0, 2.0, 3.0]})
    np.testing.assert_allclose(placed[0, 1], [1.0, 2.04, 3.0], rtol=0, atol=1e-15)  # cos 90° = 6e-17
    np.testing.assert_allclose(placed[1, 2], [1.0 - 0.04, 2.0, 3.0], rtol=0, atol=1e-15)


def test_binary_and_ascii_stl_and_obj_read_the_same_triangles(tmp_path):
    (tmp_path / "a.stl").write_text(FLOOR)
    binary = bytearray(b"solid but binary".ljust(80) + struct.pack("<I", 2))
    for t in FLOOR_TRIANGLES:
        binary += struct.pack("<3f", 0, 0, 1) + struct.pack("<9f", *t.ravel()) + b"\0\0"
    (tmp_path / "b.stl").write_bytes(bytes(binary))
    # The same square as one quad, fanned from its first vertex.
    (tmp_path / "c.obj").write_text("v 0 0 0\nv 0.02 0 0\nv 0.02 0.02 0\nv 0 0.02 0\nf 1 2 3 4\n")
    for name in ("a.stl", "b.stl", "c.obj"):
        # 0.02 in f32 (binary STL) is 4.5e-10 from 0.02.
        np.testing.assert_allclose(render_scene.read_mesh_file(tmp_path / name), FLOOR_TRIANGLES, atol=1e-9)


@pytest.mark.parametrize(
    "remove, named",
    [
        ("snapshots.pvd", "snapshots.pvd"),
        ("snapshot_000001.vtp", "snapshot_000001.vtp"),
        ("wall_0_000001.vtp", "wall_0_000001.vtp"),
        ("floor.stl", "floor.stl"),
    ],
)
def test_a_missing_file_exits_2_naming_it(tmp_path, remove, named):
    run = synthetic_run(tmp_path)
    (run / remove).unlink()
    done = run_script(run, tmp_path / "x.png")
    assert done.returncode == 2, done.stderr
    assert named in done.stderr and "no such" in done.stderr, done.stderr
    assert not (tmp_path / "x.png").exists()


def test_an_index_out_of_range_exits_2(tmp_path):
    done = run_script(synthetic_run(tmp_path), tmp_path / "x.png", "--index", "2")
    assert done.returncode == 2 and "--index 2" in done.stderr and "2 snapshots" in done.stderr, done.stderr
