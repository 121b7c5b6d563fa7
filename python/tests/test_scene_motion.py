"""`Scene.set_wall_motion` (issue 27): a sphere between a fixed floor and
a piston moving down at 1 mm/s (no gravity, elastic Hertz) against the
closed form of two Hertz contacts in series, the piston's work equal to
the energy stored, and the refusals naming the argument."""

from __future__ import annotations

import math

import pytest

import dembound

E, NU, RHO = 1e9, 0.3, 1000.0
R, V, DT = 1e-3, 1e-3, 2e-7


def piston_scene() -> dembound.Scene:
    """One sphere of radius R centred at z = R between the floor z = 0 and
    a plane at z = 2R facing down, no gravity; the sphere moving at −V/2
    (the centre's speed between the two contacts, so they load alike),
    10 ms."""
    s = dembound.Scene.from_dict(
        {
            "domain": {"lower": [-0.01] * 3, "upper": [0.01] * 3, "periodic": [False] * 3},
            "material": [{"name": "grain", "density": RHO, "youngs_modulus": E, "poisson_ratio": NU}],
            "contact": {"law": "hertz"},
            "particles": [
                {"spheres": [{"position": [0.0, 0.0, R], "velocity": [0.0, 0.0, -V / 2], "radius": R}],
                 "material": "grain"}
            ],
            "motion": {"gravity": [0.0, 0.0, 0.0]},
            "integration": {"scheme": "verlet", "dt": DT, "duration": 0.01},
        }
    )
    s.add_plane([0.0, 0.0, 0.0], [0.0, 0.0, 1.0])
    s.add_plane([0.0, 0.0, 2 * R], [0.0, 0.0, -1.0])
    return s


def test_piston_force_and_work_follow_two_hertz_contacts_in_series():
    """F = (4/3) E* √R (δ/2)^{3/2}, 1/E* = 2 (1 − ν²)/E (sphere and walls
    of one material), δ = V t the total compression; the work 2 × (2/5)
    (4/3) E* √R (δ/2)^{5/2}. The contacts load alike from the start, so
    both hold to the integration's error (measured 1e-10 in the Rust test):
    1e-6."""
    s = piston_scene()
    s.set_wall_motion(1, velocity=[0.0, 0.0, -V])
    s.step(50_000)
    delta = V * 50_000 * DT
    k = 4.0 / 3.0 * E / (2.0 * (1.0 - NU**2)) * math.sqrt(R)
    force = k * (delta / 2) ** 1.5
    o = s.observe()
    assert abs(o["wall1_force_z_N"] - force) <= 1e-6 * force
    assert abs(-o["wall0_force_z_N"] - force) <= 1e-6 * force
    stored = 2 * 0.4 * k * (delta / 2) ** 2.5
    assert abs(o["work_by_walls_J"] - stored) <= 1e-6 * stored
    # A scene without moving walls reports no work.
    assert "work_by_walls_J" not in piston_scene().observe()


@pytest.mark.parametrize(
    "arguments, names",
    [
        ({"k": 2}, ["k"]),
        ({"k": 1, "velocity": [0.0, 1.0]}, ["velocity"]),
        ({"k": 1, "end": -1.0}, ["wall[1].motion.end"]),
        ({"k": 1, "amplitude": [0.0, 0.0, 1e-4]}, ["amplitude", "frequency"]),
        ({"k": 1, "amplitude": [0.0, 0.0, 1e-4], "frequency": -5.0}, ["wall[1].oscillation.frequency"]),
        ({"k": 0, "angular_velocity": [math.nan, 0.0, 0.0]}, ["wall[0].motion.angular_velocity"]),
    ],
)
def test_set_wall_motion_refuses_naming_the_argument(arguments, names):
    s = piston_scene()
    with pytest.raises(ValueError) as raised:
        s.set_wall_motion(**arguments)
    for name in names:
        assert name in str(raised.value), str(raised.value)
    # Refused: nothing moves.
    assert "work_by_walls_J" not in s.observe()
