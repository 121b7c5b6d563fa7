"""`Scene.add_mesh` (issue 26): a sphere dropped onto a 2-triangle STL
floor moves exactly as on the plane through the same points (a flat patch
computes the plane's contact with the plane's arithmetic), the cleaning's
counts are warnings, and the refusals name the argument."""

from __future__ import annotations

import math

import numpy as np
import pytest

import dembound

E, NU, RHO, G, R = 1e7, 0.3, 1000.0, 9.81, 1e-3

# The square [0, 0.02]² at z = 0 as 2 triangles, normal +z (ASCII STL;
# every coordinate is exact in the f32 the format stores except 0.02, the
# same for both corners it appears in, so the floor is the plane z = 0).
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


def scene() -> dembound.Scene:
    """One sphere of radius R at (0.013, 0.007, 2 mm), damped Hertz
    (Tsuji, e = 0.3), no walls yet, 0.1 s."""
    return dembound.Scene.from_dict(
        {
            "domain": {"lower": [0.0, 0.0, 0.0], "upper": [0.02, 0.02, 0.02], "periodic": [False] * 3},
            "material": [{"name": "grain", "density": RHO, "youngs_modulus": E, "poisson_ratio": NU}],
            "contact": {"law": "hertz", "damping": "tsuji", "restitution": 0.3},
            "particles": [{"spheres": [{"position": [0.013, 0.007, 0.002], "radius": R}], "material": "grain"}],
            "motion": {"gravity": [0.0, 0.0, -G]},
            "integration": {"scheme": "verlet", "dt": 5e-6, "duration": 0.1},
        }
    )


@pytest.fixture
def floor(tmp_path):
    path = tmp_path / "floor.stl"
    path.write_text(FLOOR)
    return path


def test_a_sphere_on_a_mesh_floor_moves_as_on_the_plane(floor):
    on_mesh = scene()
    with pytest.warns(UserWarning, match="4 open edges"):
        on_mesh.add_mesh(floor)
    on_plane = scene()
    on_plane.add_plane([0.0, 0.0, 0.0], [0.0, 0.0, 1.0])
    for _ in range(20):
        on_mesh.step(1000)
        on_plane.step(1000)
        # Bit for bit: the patch's overlap, rate and normal are the plane's
        # numbers (the Rust tests show it at every step).
        assert (on_mesh.positions == on_plane.positions).all()
        assert (on_mesh.velocities == on_plane.velocities).all()
    # At rest after 0.1 s: the floor carries the weight (as the cylinder
    # test: the rebound decays far below doubles; 1e-9 is far above the
    # rounding, far below any missing factor).
    weight = RHO * 4.0 / 3.0 * math.pi * R**3 * G
    assert on_mesh.wall_forces[0, 2] == pytest.approx(-weight, rel=1e-9)
    assert (on_mesh.wall_forces == on_plane.wall_forces).all()


def test_a_placed_mesh_is_moved_scaled_and_turned(floor):
    # The floor in mm scaled to m, turned 90° about z (about the origin:
    # x' = −y) and moved back by +0.02 m along x: the same square.
    mm = floor.parent / "floor_mm.stl"
    mm.write_text(FLOOR.replace("0.02", "20"))
    s = scene()
    with pytest.warns(UserWarning):
        s.add_mesh(mm, scale=1e-3, rotate_axis=[0.0, 0.0, 1.0], rotate_angle=90.0, translate=[0.02, 0.0, 0.0])
    s.run()
    weight = RHO * 4.0 / 3.0 * math.pi * R**3 * G
    assert s.wall_forces[0, 2] == pytest.approx(-weight, rel=1e-9)


@pytest.mark.parametrize(
    "arguments, names",
    [
        ({"path": "missing.stl"}, ["path", "missing.stl", "cannot be read"]),
        ({"scale": 0.0}, ["scale"]),
        ({"scale": -1.0}, ["scale"]),
        ({"rotate_axis": [0.0, 0.0, 0.0]}, ["rotate_axis"]),
        ({"translate": [1.0, 0.0, 0.0]}, ["does not meet the domain"]),
        ({"material": 3}, ["material"]),
    ],
)
def test_add_mesh_refuses_naming_the_argument(floor, arguments, names):
    s = scene()
    given = {"path": floor}
    given.update(arguments)
    if given["path"] == "missing.stl":
        given["path"] = floor.parent / "missing.stl"
    with pytest.raises(ValueError) as raised:
        s.add_mesh(**given)
    for name in names:
        assert name in str(raised.value), str(raised.value)
    assert s.wall_forces.shape == (0, 3)


def test_triangle_loads_of_a_sphere_at_rest(floor):
    """`Scene.wall_triangle_loads` (issue 26): the sphere at rest at
    (13, 7) mm is over triangle 0 (below the diagonal y = x), which carries
    its weight m g (force −m g along z on the wall) and the pressure
    m g / A; triangle 1 carries nothing. A = ½ (0.02 as f32)² m² (the STL
    stores f32). Tolerance 1e-9 as above (at rest; the rounding is far
    below, a wrong triangle or factor far above); triangle 1, the shear and
    the in-plane components are exactly 0 (no contact there; the floor is
    exactly z = 0 and the force vertical)."""
    s = scene()
    with pytest.warns(UserWarning, match="4 open edges"):
        s.add_mesh(floor)
    s.add_plane([0.0, 0.0, 0.02], [0.0, 0.0, -1.0])
    s.step(20000)
    loads = s.wall_triangle_loads(0)
    assert set(loads) == {"force", "pressure", "shear", "area", "centroid"}
    assert loads["force"].shape == (2, 3) and loads["centroid"].shape == (2, 3)
    assert loads["pressure"].shape == loads["shear"].shape == loads["area"].shape == (2,)
    weight = RHO * 4.0 / 3.0 * math.pi * R**3 * G
    side = float(np.float32(0.02))
    area = 0.5 * side * side
    assert loads["area"] == pytest.approx([area, area], rel=1e-15)
    assert loads["force"][0, 2] == pytest.approx(-weight, rel=1e-9)
    assert (loads["force"][0, :2] == 0.0).all() and (loads["force"][1] == 0.0).all()
    assert loads["pressure"][0] == pytest.approx(weight / area, rel=1e-9)
    assert loads["pressure"][1] == 0.0 and (loads["shear"] == 0.0).all()
    assert loads["centroid"][0] == pytest.approx([2 * side / 3, side / 3, 0.0], rel=1e-15)
    # The triangles' forces sum to the wall's (one contact: the same bits).
    assert (loads["force"].sum(axis=0) == s.wall_forces[0]).all()
    # Refusals: a plane, a wall that does not exist, a negative index.
    with pytest.raises(ValueError, match="wall 1 is not a triangle mesh"):
        s.wall_triangle_loads(1)
    with pytest.raises(ValueError, match="wall 2 does not exist"):
        s.wall_triangle_loads(2)
    with pytest.raises(ValueError, match="wall -1 does not exist"):
        s.wall_triangle_loads(-1)
