"""A scene built from code as a new user builds it: a dict without
particles, spheres added from arrays, the series row with its units, the
masses, and a clean ``dir(dembound)`` (issue 28, item 7)."""

from __future__ import annotations

import csv
import math

import numpy as np
import pytest

import dembound
from conftest import REPO

VALIDATION = REPO / "examples" / "scenes" / "validation.toml"


def _scene(particles: bool) -> dict:
    scene = {
        "domain": {"lower": [0.0, 0.0, 0.0], "upper": [0.01, 0.01, 0.01]},
        "material": [
            {"name": "grain", "density": 2500.0, "youngs_modulus": 1e7, "poisson_ratio": 0.3},
            {"name": "steel", "density": 7800.0, "youngs_modulus": 2e11, "poisson_ratio": 0.3},
        ],
        "contact": {"law": "hertz"},
        "motion": {"gravity": [0.0, 0.0, -9.81]},
        "integration": {"scheme": "verlet", "eta": 0.02, "impact_speed": 0.1, "duration": 0.05},
        "wall": [{"plane": {"point": [0.0, 0.0, 0.0], "normal": [0.0, 0.0, 1.0]}, "material": "grain"}],
    }
    if particles:
        scene["particles"] = [
            {"spheres": [{"position": [0.005, 0.005, 0.004], "radius": 1e-3}], "material": "grain"}
        ]
    return scene


def test_a_dict_without_particles_takes_them_from_arrays():
    # The same sphere named in the dict or added from arrays is the same
    # scene: the same Δt and, after the fall and bounce, the same bits.
    named = dembound.Scene.from_dict(_scene(particles=True))
    later = dembound.Scene.from_dict(_scene(particles=False))
    assert len(later) == 0 and later.steps_done == 0 and later.time == 0.0
    assert later.positions.shape == (0, 3) and later.radii.shape == (0,)
    assert "no spheres yet" in repr(later)
    # Nothing to step and no time step rule without spheres: a clear error.
    for call in (lambda: later.step(1), lambda: later.observe(), lambda: later.dt):
        with pytest.raises(ValueError, match="no spheres yet: add them with add_particles"):
            call()
    later.add_particles(np.array([[0.005, 0.005, 0.004]]), np.array([1e-3]))
    assert later.dt == named.dt
    named.run()
    later.run()
    assert later.positions.tobytes() == named.positions.tobytes()
    assert later.velocities.tobytes() == named.velocities.tobytes()


def test_masses_are_the_materials_spheres():
    # m = 4/3 π r³ ρ, by hand: a grain sphere and a fixed steel one (whose
    # dynamics mass is infinite: `masses` reports its material's mass).
    scene = dembound.Scene.from_dict(_scene(particles=False))
    scene.add_particles(np.array([[0.003, 0.005, 0.004]]), np.array([1e-3]))
    scene.add_particles(
        np.array([[0.007, 0.005, 0.001]]), np.array([5e-4]), fixed=np.array([True]), material=1
    )
    expected = [4 / 3 * math.pi * 1e-3**3 * 2500.0, 4 / 3 * math.pi * 5e-4**3 * 7800.0]
    # Two roundings of the same product in another order: 1e-15.
    assert scene.masses == pytest.approx(expected, rel=1e-15)


def test_observe_is_the_series_row_with_its_units(cli, tmp_path):
    # The CLI's series.csv row at step 2000 and observe() after 2000
    # steps of the same scene: the same column names (units in them) and
    # the same numbers (the CSV prints the shortest text that reads back
    # as its double, so float() gives the same bits).
    out = tmp_path / "run"
    sets = ["integration.steps=2000", "output.series_every=1000"]
    args = ["scene", str(VALIDATION), "-q", "--out", str(out)]
    for s in sets:
        args += ["--set", s]
    done = cli(args)
    assert done.returncode == 0, done.stderr
    with open(out / "series.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    last = rows[-1]
    assert last["step"] == "2000"
    scene = dembound.Scene.from_toml(VALIDATION, sets)
    scene.step(2000)
    row = scene.observe()
    assert list(row) == list(last)
    for name, text in last.items():
        value = row[name]
        if isinstance(value, int):
            assert value == int(text), name
        else:
            assert value == float(text), name
    assert "time_s" in row and "kinetic_energy_J" in row


def test_dir_lists_only_the_public_names():
    names = dir(dembound)
    assert "Scene" in names and "scene" in names and "run" in names
    for private in ("np", "os", "json", "math", "Any", "Optional", "Union", "Callable"):
        assert private not in names
