"""`Scene.set_wall_active` (issue 28): a sphere resting on a Hooke gate
plane that vanishes at 1 ms falls freely from rest; the gate energy booked
is the spring energy ½ k δ² at the resting overlap δ = m g / k; bad
windows are refused naming the key."""

from __future__ import annotations

import math

import pytest

import dembound

R, RHO, G, K, DT, T1 = 1e-3, 2500.0, 9.81, 1e3, 2.5e-7, 1e-3
MASS = RHO * 4.0 / 3.0 * math.pi * R**3
DELTA = MASS * G / K


def gate_scene() -> dembound.Scene:
    """One sphere at rest on the plane z = 0 at its resting overlap."""
    s = dembound.Scene.from_dict(
        {
            "domain": {"lower": [-0.01] * 3, "upper": [0.01] * 3, "periodic": [False] * 3},
            "material": [{"name": "grain", "density": RHO, "youngs_modulus": 1e7, "poisson_ratio": 0.3}],
            "contact": {"law": "hooke", "stiffness": K},
            "particles": [
                {"spheres": [{"position": [0.0, 0.0, R - DELTA], "velocity": [0.0, 0.0, 0.0], "radius": R}],
                 "material": "grain"}
            ],
            "motion": {"gravity": [0.0, 0.0, -G]},
            "integration": {"scheme": "verlet", "dt": DT, "duration": 0.005},
        }
    )
    s.add_plane([0.0, 0.0, 0.0], [0.0, 0.0, 1.0])
    return s


def test_an_opening_gate_books_the_spring_energy_and_lets_the_sphere_fall():
    """After the switch (the first step n with n Δt ≥ 1 ms), Verlet's free
    fall from rest: v = −g (τ + Δt/2) (the switch step's half kick sees no
    wall); G = ½ k δ² to the rounding of δ (1e-11), asserted to 1e-9."""
    s = gate_scene()
    s.set_wall_active(0, end=T1)
    off = next(n for n in range(10**6) if n * DT >= T1)
    s.step(off + 2000)
    o = s.observe()
    spring = 0.5 * K * DELTA**2
    assert abs(o["gate_energy_J"] - spring) <= 1e-9 * spring
    assert o["wall_contacts"] == 0
    tau = 2000 * DT
    vz = s.velocities[0][2]
    assert abs(vz + G * (tau + DT / 2)) <= 1e-12
    # A scene without a window has no gate column.
    assert "gate_energy_J" not in gate_scene().observe()


@pytest.mark.parametrize(
    "arguments, names",
    [
        ({"k": 1}, ["k"]),
        ({"k": 0, "start": -1.0}, ["wall[0].active.from"]),
        ({"k": 0, "start": 2.0, "end": 1.0}, ["wall[0].active.to"]),
        ({"k": 0, "end": math.nan}, ["wall[0].active.to"]),
    ],
)
def test_set_wall_active_refuses_naming_the_key(arguments, names):
    s = gate_scene()
    with pytest.raises(ValueError) as raised:
        s.set_wall_active(**arguments)
    for name in names:
        assert name in str(raised.value), str(raised.value)
    assert "gate_energy_J" not in s.observe()
