"""`Scene.add_cylinder` (issue 25): a sphere at rest in a horizontal tube
and on a horizontal post against the closed form of the curvature model
(LAMMPS `wall/gran` cylinders: the wall a sphere of radius ∓R_c, so
R_eff = R R_c/(R_c ∓ R)), and the refusals naming the argument."""

from __future__ import annotations

import math

import pytest

import dembound

E, NU, RHO, G = 1e7, 0.3, 1000.0, 9.81
R, RC = 1e-3, 4e-3
AXIS_Y, AXIS_Z = 0.01, 0.01


def scene(height: float) -> dembound.Scene:
    """One sphere of radius R at (0.01, AXIS_Y, height), damped Hertz
    (Tsuji, e = 0.3), no walls yet, 0.2 s."""
    return dembound.Scene.from_dict(
        {
            "domain": {"lower": [0.0, 0.0, 0.0], "upper": [0.02, 0.02, 0.02], "periodic": [False] * 3},
            "material": [{"name": "grain", "density": RHO, "youngs_modulus": E, "poisson_ratio": NU}],
            "contact": {"law": "hertz", "damping": "tsuji", "restitution": 0.3},
            "particles": [{"spheres": [{"position": [0.01, AXIS_Y, height], "radius": R}], "material": "grain"}],
            "motion": {"gravity": [0.0, 0.0, -G]},
            "integration": {"scheme": "verlet", "dt": 5e-6, "duration": 0.2},
        }
    )


def static_overlap(r_eff: float) -> float:
    """Hertz at rest: m g = 4/3 E* √R_eff δ^{3/2}, E* of the sphere against
    a wall of its own material: 1/E* = 2 (1 − ν²)/E."""
    weight = RHO * 4.0 / 3.0 * math.pi * R**3 * G
    e_star = E / (2.0 * (1.0 - NU**2))
    return (weight / (4.0 / 3.0 * e_star * math.sqrt(r_eff))) ** (2.0 / 3.0)


@pytest.mark.parametrize("inside", [True, False], ids=["tube", "post"])
def test_a_sphere_at_rest_on_a_cylinder_has_the_curvature_models_overlap(inside):
    # Inside the tube the sphere rests at its bottom, 0.1 mm clear of it at
    # the start; on the post at its top, 0.1 mm above.
    gap = 1e-4
    height = AXIS_Z - (RC - R) + gap if inside else AXIS_Z + RC + R + gap
    s = scene(height)
    s.add_cylinder([0.0, AXIS_Y, AXIS_Z], [1.0, 0.0, 0.0], RC, inside=inside)
    s.run()
    weight = RHO * 4.0 / 3.0 * math.pi * R**3 * G
    # Settled as in test_scene.py's floor test: the rebound and the
    # oscillation about rest decay by ~0.3 per half period (0.5 ms) over
    # 0.2 s, far below doubles; what is left is the rounding of the force
    # sums (1e-16 relative each). 1e-9 is far above that, far below a
    # missing factor.
    assert s.wall_forces[0, 2] == pytest.approx(-weight, rel=1e-9)
    # The sphere is exactly below (above) the axis: the normal is exactly
    # vertical, no sideways force.
    assert s.wall_forces[0, 0] == 0.0 and s.wall_forces[0, 1] == 0.0
    z = s.positions[0, 2]
    if inside:
        # Concave: the wall a sphere of radius −R_c, R_eff = R R_c/(R_c − R).
        overlap = (AXIS_Z - z) - (RC - R)
        expected = static_overlap(R * RC / (RC - R))
    else:
        # Convex: a sphere of radius R_c, R_eff = R R_c/(R_c + R).
        overlap = (RC + R) - (z - AXIS_Z)
        expected = static_overlap(R * RC / (RC + R))
    # δ ≈ 0.3 µm is the difference of lengths of ~10 mm: 4–5 digits of the
    # doubles' 16 go, leaving ~1e-12 relative; 1e-9 is well above that and
    # far below the flat-wall model's (R_eff = R) 10 % (tube) or 7 % (post)
    # difference, so it tells the curvature model apart.
    assert overlap == pytest.approx(expected, rel=1e-9)


@pytest.mark.parametrize(
    "arguments, names",
    [
        ({"axis": [0.0, 0.0, 0.0]}, ["axis"]),
        ({"axis": "x"}, ["axis"]),
        ({"radius": -1e-3}, ["radius"]),
        ({"radius": 5e-4}, ["radius", "largest free sphere"]),
        ({"length": -1.0}, ["length"]),
        ({"material": 3}, ["material"]),
        # The sphere's centre is 2.9 mm from the axis, outside a 2 mm tube
        # wider than the sphere.
        ({"radius": 2e-3}, ["outside"]),
        # ... and inside a 4 mm post.
        ({"inside": False}, ["inside the post"]),
    ],
)
def test_add_cylinder_refuses_naming_the_argument(arguments, names):
    s = scene(AXIS_Z - (RC - R) + 1e-4)
    given = {"point": [0.0, AXIS_Y, AXIS_Z], "axis": [1.0, 0.0, 0.0], "radius": RC, "inside": True}
    given.update(arguments)
    with pytest.raises(ValueError) as raised:
        s.add_cylinder(**given)
    for name in names:
        assert name in str(raised.value), str(raised.value)
    # A refused wall is not added: the scene still runs without it.
    assert s.wall_forces.shape == (0, 3)
