"""`Scene.set_group_motion` and `Scene.set_wall_motion` on a wall of
boundary particles (issue 27 item 5): fixed spheres moving as one rigid
body, against the exact rigid motion and the closed-form rebound of an
elastic head-on hit, and the refusals naming the argument."""

from __future__ import annotations

import math

import numpy as np
import pytest

import dembound

E, NU, RHO = 1e7, 0.3, 1000.0
R, V, DT = 1e-3, 0.05, 1e-6


def scene(ring: bool = True) -> dembound.Scene:
    """Group 0: a free sphere at rest at the origin. Group 1: four fixed
    spheres on a ring of radius 5R about the z axis (ring = True), or one
    fixed sphere at x = −2.1R (ring = False, a gap of R/10 to the free
    sphere). No gravity, elastic Hertz (no damping, no friction)."""
    fixed = (
        [[5 * R * math.cos(a), 5 * R * math.sin(a), 0.0] for a in (0.0, 0.5 * math.pi, math.pi, 1.5 * math.pi)]
        if ring
        else [[-2.1 * R, 0.0, 0.0]]
    )
    return dembound.Scene.from_dict(
        {
            "domain": {"lower": [-0.01] * 3, "upper": [0.01] * 3, "periodic": [False] * 3},
            "material": [{"name": "g", "density": RHO, "youngs_modulus": E, "poisson_ratio": NU}],
            "contact": {"law": "hertz"},
            "particles": [
                {"spheres": [{"position": [0.0, 0.0, 0.0], "radius": R}], "material": "g"},
                {"spheres": [{"position": p, "radius": R} for p in fixed], "material": "g", "fixed": True},
            ],
            "motion": {"gravity": [0.0, 0.0, 0.0]},
            "integration": {"scheme": "verlet", "dt": DT, "duration": 0.01},
        }
    )


def test_a_turning_ring_is_exactly_rotated():
    """Sphere k at X_k is at R(ω t) X_k with velocity ω × x_k: the pose is
    computed from X_k at every step (no accumulated drift), so only the
    rounding of cos, sin and the products remains: 1e-15 m on 5 mm."""
    s = scene()
    omega = 3.0
    s.set_group_motion(1, angular_velocity=[0.0, 0.0, omega])
    x0 = s.positions[1:].copy()
    n = 1000
    s.step(n)
    a = omega * n * s.dt
    c, si = math.cos(a), math.sin(a)
    expected = np.column_stack([c * x0[:, 0] - si * x0[:, 1], si * x0[:, 0] + c * x0[:, 1], x0[:, 2]])
    assert np.max(np.abs(s.positions[1:] - expected)) <= 1e-15
    v = s.velocities[1:]
    assert np.max(np.abs(v - np.column_stack([-omega * expected[:, 1], omega * expected[:, 0], 0 * expected[:, 2]]))) <= 1e-15 * omega * 1e3
    # The free sphere at the centre, 3R clear of the ring, stays at rest.
    assert np.all(s.velocities[0] == 0.0)


def test_a_fixed_sphere_moving_at_v_sends_a_resting_one_off_at_2v():
    """In the frame of the fixed sphere (infinite mass) the free one comes
    in at −V and, the Hertz contact being elastic, leaves at +V: 2V in the
    lab. Verlet's energy error after a contact of t_c ≈ 0.34 ms (Hertz,
    2.87 (m²/(R* E*² V))^{1/5}) is O((Δt/t_c)²) ≈ 1e-5 of the energy at
    Δt = 1 µs: 1e-5 of the speed."""
    s = scene(ring=False)
    s.set_group_motion(1, velocity=[V, 0.0, 0.0])
    s.step(5_000)  # 5 ms: the gap R/10 closes at 2 ms, the contact lasts ~0.34 ms
    v = s.velocities
    assert abs(v[0, 0] - 2 * V) <= 1e-5 * V
    assert abs(v[1, 0] - V) == 0.0
    assert abs(s.positions[1, 0] - (-2.1 * R + V * s.steps_done * s.dt)) <= 1e-15


def test_set_wall_motion_moves_a_wall_of_boundary_particles():
    """A boundary-particle floor translating at V along x: each of its
    spheres at X + V t (exact up to rounding, 1e-15 m)."""
    s = dembound.Scene.from_dict(
        {
            "domain": {"lower": [-0.004] * 3, "upper": [0.004] * 3, "periodic": [False] * 3},
            "material": [{"name": "g", "density": RHO, "youngs_modulus": E, "poisson_ratio": NU}],
            "contact": {"law": "hertz"},
            "particles": [{"spheres": [{"position": [0.0, 0.0, 0.0], "radius": R}], "material": "g"}],
            "wall": [
                {
                    "boundary_particles": {"point": [0.0, 0.0, -0.003], "normal": [0.0, 0.0, 1.0], "radius_ratio": 1.0, "modulus_ratio": 1.0},
                    "material": "g",
                }
            ],
            "motion": {"gravity": [0.0, 0.0, 0.0]},
            "integration": {"scheme": "verlet", "dt": DT, "duration": 0.01},
        }
    )
    s.set_wall_motion(0, velocity=[V, 0.0, 0.0])
    fixed = s.fixed
    assert fixed.sum() > 4
    x0 = s.positions[fixed].copy()
    s.step(100)
    shift = V * 100 * s.dt
    assert np.max(np.abs(s.positions[fixed] - (x0 + [shift, 0.0, 0.0]))) <= 1e-15
    assert np.all(s.velocities[fixed][:, 0] == V)


@pytest.mark.parametrize(
    "arguments, names",
    [
        ({"group": 2}, ["group"]),
        ({"group": 0, "velocity": [V, 0.0, 0.0]}, ["group", "free sphere"]),
        ({"group": 1, "velocity": [0.0, 1.0]}, ["velocity"]),
        ({"group": 1, "end": -1.0}, ["particles[1].motion.end"]),
        ({"group": 1, "amplitude": [0.0, 0.0, 1e-4]}, ["amplitude", "frequency"]),
        ({"group": 1, "angular_velocity": [math.nan, 0.0, 0.0]}, ["particles[1].motion.angular_velocity"]),
    ],
)
def test_set_group_motion_refuses_naming_the_argument(arguments, names):
    s = scene()
    x0 = s.positions.copy()
    with pytest.raises(ValueError) as raised:
        s.set_group_motion(**arguments)
    for name in names:
        assert name in str(raised.value), str(raised.value)
    # Refused: nothing moves.
    s.step(10)
    assert np.array_equal(s.positions, x0)
