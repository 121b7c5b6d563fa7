"""`Scene.set_wall_servo` (issue 27 item 2): a sphere between a fixed
floor and a servo piston (no gravity, damped Hertz) stops where two Hertz
contacts in series carry the target force; the piston's position and
speed in `observe()`; the refusals name the argument."""

from __future__ import annotations

import math

import pytest

import dembound

E, NU, RHO = 1e9, 0.3, 1000.0
R, GAP, DT = 1e-3, 5e-6, 5e-7


def piston_scene() -> dembound.Scene:
    """One sphere of radius R at rest on the floor z = 0, a plane facing
    down at z = 2R + GAP, no gravity, Tsuji damping e = 0.5."""
    s = dembound.Scene.from_dict(
        {
            "domain": {"lower": [-0.01] * 3, "upper": [0.01] * 3, "periodic": [False] * 3},
            "material": [{"name": "grain", "density": RHO, "youngs_modulus": E, "poisson_ratio": NU}],
            "contact": {"law": "hertz", "damping": "tsuji", "restitution": 0.5},
            "particles": [
                {"spheres": [{"position": [0.0, 0.0, R], "radius": R}], "material": "grain"}
            ],
            "motion": {"gravity": [0.0, 0.0, 0.0]},
            "integration": {"scheme": "verlet", "dt": DT, "duration": 0.01},
        }
    )
    s.add_plane([0.0, 0.0, 0.0], [0.0, 0.0, 1.0])
    s.add_plane([0.0, 0.0, 2 * R + GAP], [0.0, 0.0, -1.0])
    return s


def test_servo_piston_stops_at_two_hertz_contacts_in_series():
    """F = (4/3) E* √R (δ/2)^{3/2}, 1/E* = 2 (1 − ν²)/E: δ = 2 (F/k)^{2/3}.
    The loop's time constant is 0.16 ms, the run 6 ms (the Rust test's
    numbers, measured 1e-13): held to 1e-6."""
    s = piston_scene()
    force = 1.0
    s.set_wall_servo(1, force=force, axis=[0.0, 0.0, -2.0], max_velocity=0.02, gain=5.0)
    s.step(12_000)
    k = 4.0 / 3.0 * E / (2.0 * (1.0 - NU**2)) * math.sqrt(R)
    delta = 2 * (force / k) ** (2.0 / 3.0)
    o = s.observe()
    height = 2 * R + GAP + o["wall1_position_z_m"]
    assert abs((2 * R - height) - delta) <= 1e-6 * delta
    assert abs(o["wall1_force_z_N"] - force) <= 1e-6 * force
    assert abs(o["wall1_velocity_z_m_s"]) <= 1e-9
    assert o["wall1_angle_rad"] == 0.0
    # A scene without moving walls has no such columns.
    assert "wall1_position_z_m" not in piston_scene().observe()


@pytest.mark.parametrize(
    "arguments, names",
    [
        ({"k": 2, "force": 1.0, "axis": [0, 0, -1], "max_velocity": 0.1}, ["k"]),
        ({"k": 1, "force": 0.0, "axis": [0, 0, -1], "max_velocity": 0.1}, ["wall[1].servo.force"]),
        ({"k": 1, "force": 1.0, "axis": [0, 0, 0], "max_velocity": 0.1}, ["wall[1].servo.axis"]),
        ({"k": 1, "force": 1.0, "axis": [0, 0], "max_velocity": 0.1}, ["axis"]),
        ({"k": 1, "force": 1.0, "axis": [0, 0, -1], "max_velocity": -1.0}, ["wall[1].servo.max_velocity"]),
        ({"k": 1, "force": 1.0, "axis": [0, 0, -1], "max_velocity": 0.1, "gain": math.nan}, ["wall[1].servo.gain"]),
    ],
)
def test_set_wall_servo_refuses_naming_the_argument(arguments, names):
    s = piston_scene()
    with pytest.raises(ValueError) as raised:
        s.set_wall_servo(**arguments)
    for name in names:
        assert name in str(raised.value), str(raised.value)
    assert "wall1_position_z_m" not in s.observe()


def test_servo_and_motion_are_exclusive():
    s = piston_scene()
    s.set_wall_motion(1, velocity=[0.0, 0.0, -1e-3])
    with pytest.raises(ValueError, match="not both"):
        s.set_wall_servo(1, force=1.0, axis=[0, 0, -1], max_velocity=0.1)
    s = piston_scene()
    s.set_wall_servo(1, force=1.0, axis=[0, 0, -1], max_velocity=0.1)
    with pytest.raises(ValueError, match="not both"):
        s.set_wall_motion(1, velocity=[0.0, 0.0, -1e-3])
