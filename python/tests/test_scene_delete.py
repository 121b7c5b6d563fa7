"""`domain.outside = "delete"` from Python (issue 28): two spheres fall out
of an open box; `Scene.deleted` gives the count, the mass and the energy
they carried out, `observe()` the series.csv columns of the removal, and
the balance closes against the closed form."""

from __future__ import annotations

import math

import dembound

RHO, R, G = 2500.0, 1e-3, 9.81


def open_box(outside: str) -> dembound.Scene:
    """Two spheres (R = 1 mm) at rest at z = 8 mm and 2 mm in a 10 mm box
    with no walls, gravity −z, Verlet Δt = 10 µs."""
    return dembound.Scene.from_dict(
        {
            "domain": {"lower": [0.0] * 3, "upper": [0.01] * 3, "outside": outside},
            "material": [{"name": "g", "density": RHO, "youngs_modulus": 1e7, "poisson_ratio": 0.3}],
            "particles": [
                {
                    "material": "g",
                    "spheres": [
                        {"position": [0.005, 0.005, 0.008], "radius": R},
                        {"position": [0.002, 0.002, 0.002], "radius": R},
                    ],
                }
            ],
            "motion": {"gravity": [0.0, 0.0, -G]},
            "integration": {"scheme": "verlet", "dt": 1e-5, "duration": 0.1},
        }
    )


def test_deleted_counts_mass_and_energy_carried_out() -> None:
    scene = open_box("delete")
    assert scene.deleted == (0, 0.0, 0.0)
    scene.step(10_000)
    count, mass, carried = scene.deleted
    m = RHO * 4.0 / 3.0 * math.pi * R**3
    assert count == 2
    # Two equal masses summed: one rounding.
    assert math.isclose(mass, 2 * m, rel_tol=1e-15)
    # Both rested at t = 0: E₀ = m g (z₁ + z₂), all carried out (free
    # fall, nothing dissipated; Verlet conserves it up to rounding).
    e0 = m * G * (0.008 + 0.002)
    assert math.isclose(carried, e0, rel_tol=1e-9)
    row = scene.observe()
    assert row["deleted_particles"] == 2
    assert row["deleted_mass_kg"] == mass
    assert row["carried_out_energy_J"] == carried
    assert abs(row["dissipated_energy_J"]) <= 1e-9 * e0
    assert len(scene) == 0


def test_no_removal_no_columns() -> None:
    scene = open_box("keep")
    scene.step(10)
    assert scene.deleted is None
    assert "deleted_particles" not in scene.observe()
