"""Inlets and outlets from Python (issue 28): `Scene.add_inlet` and
`Scene.add_outlet` take the scene file's keys; the count inserted is the
rate's closed form; bad values are ValueErrors naming the argument; and
`observe()` returns series.csv's row, outlet and inlet columns included,
with its names (units in them) and its numbers."""

from __future__ import annotations

import csv
import math

import pytest

import dembound

RHO, R, G = 2500.0, 1e-3, 9.81

INLET_AND_OUTLET = f"""
[domain]
lower = [0.0, 0.0, 0.0]
upper = [0.02, 0.02, 0.05]
[[material]]
name = "g"
density = {RHO!r}
youngs_modulus = 1e7
poisson_ratio = 0.3
[[inlet]]
region = {{ box = {{ lower = [0.0, 0.0, 0.045], upper = [0.02, 0.02, 0.05] }} }}
rate = {{ number = 1000.0 }}
size = {{ fixed = {R!r} }}
material = "g"
velocity = [0.0, 0.0, -2.0]
end = 0.02
every = 100
seed = 3
[[outlet]]
region = {{ box = {{ lower = [0.0, 0.0, 0.0], upper = [0.02, 0.02, 0.01] }} }}
[motion]
gravity = [0.0, 0.0, {-G!r}]
[integration]
scheme = "verlet"
dt = 1e-5
duration = 0.04
[output]
series_every = 500
"""


def test_observe_has_the_series_columns_of_outlets_and_inlets(cli, tmp_path):
    # Spheres poured in at the top (20 in all: 1000/s for 20 ms) fall at
    # ≥ 2 m/s into the outlet 35 mm below (≈ 15 ms later) and are removed.
    # observe() after each series row's steps, called at every row, is
    # that row: the same keys in the same order (units in the names) and
    # the same numbers (the CSV prints the shortest text that reads back as
    # its double), the outlet's rate since the previous call as the CSV's
    # since the previous row.
    path = tmp_path / "pour.toml"
    path.write_text(INLET_AND_OUTLET)
    out = tmp_path / "run"
    done = cli(["scene", str(path), "-q", "--out", str(out)])
    assert done.returncode == 0, done.stderr
    with open(out / "series.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    header = list(rows[0])
    for name in ["outlet0_removed", "outlet0_mass_kg", "outlet0_rate_kg_per_s",
                 "inlet0_inserted", "inlet0_mass_kg", "brought_in_energy_J"]:
        assert name in header
    scene = dembound.Scene.from_toml(path)
    done_steps = 0
    for last in rows:
        step = int(last["step"])
        if step > done_steps:
            scene.step(step - done_steps)
            done_steps = step
        row = scene.observe()
        assert list(row) == header
        for name, text in last.items():
            value = row[name]
            if isinstance(value, int):
                assert value == int(text), name
            else:
                assert value == float(text), (name, step)
    # Something went through: 20 spheres in, some removed.
    assert row["inlet0_inserted"] == 20
    assert row["outlet0_removed"] > 0


def empty_box() -> dembound.Scene:
    """A 20 mm × 20 mm × 50 mm box without spheres, gravity −z, Δt = 10 µs."""
    return dembound.Scene.from_dict(
        {
            "domain": {"lower": [0.0] * 3, "upper": [0.02, 0.02, 0.05]},
            "material": [{"name": "g", "density": RHO, "youngs_modulus": 1e7, "poisson_ratio": 0.3}],
            "wall": [{"plane": {"point": [0.0, 0.0, 0.0], "normal": [0.0, 0.0, 1.0]}, "material": "g"}],
            "motion": {"gravity": [0.0, 0.0, -G]},
            "integration": {"scheme": "verlet", "dt": 1e-5, "duration": 0.05},
        }
    )


def test_add_inlet_inserts_the_closed_form_count() -> None:
    # 2500 spheres/s from 1 ms to 11 ms: round(2500 · 0.01) = 25 spheres
    # (cumulative rounding: the module doc of `inlets`), of mass
    # 4/3 π ρ R³ each; the scene has no spheres of its own.
    scene = empty_box()
    scene.add_inlet(
        region={"box": {"lower": [0.0, 0.0, 0.04], "upper": [0.02, 0.02, 0.05]}},
        rate={"number": 2500.0},
        size={"fixed": R},
        material="g",
        start=0.001,
        end=0.011,
        every=100,
        seed=5,
    )
    scene.step(1500)
    m = RHO * 4.0 / 3.0 * math.pi * R**3
    row = scene.observe()
    assert row["inlet0_inserted"] == 25
    # 25 equal masses summed: rounding only.
    assert math.isclose(row["inlet0_mass_kg"], 25 * m, rel_tol=1e-14)
    assert len(scene) == 25


def test_add_outlet_cylinder_removes_a_falling_sphere() -> None:
    # One sphere dropped 10 mm above a vertical cylinder outlet (radius
    # 4 mm, z from 0 to 5 mm) on its axis: removed (enters at
    # √(2 · 0.01 / g) ≈ 45 ms, before it reaches the floor); a second
    # 4.95 mm off the axis, inside the cylinder's bounding box, is not.
    scene = empty_box()
    scene.add_particles([[0.01, 0.01, 0.015], [0.0135, 0.0135, 0.015]], [R, R])
    scene.add_outlet(
        {"cylinder": {"center": [0.01, 0.01, 0.0025], "axis": [0.0, 0.0, 3.0], "radius": 0.004, "length": 0.005}}
    )
    scene.step(5000)
    row = scene.observe()
    assert row["outlet0_removed"] == 1
    assert len(scene) == 1


def test_bad_arguments_are_value_errors_naming_them() -> None:
    box = {"box": {"lower": [0.0, 0.0, 0.04], "upper": [0.02, 0.02, 0.05]}}
    good = dict(region=box, rate={"number": 100.0}, size={"fixed": R}, material="g")
    for change, name, shown in [
        ({"rate": {"number": -1.0}}, "rate", "-1"),
        ({"rate": {"number": float("nan")}}, "rate", "NaN"),
        ({"rate": {"speed": 1.0}}, "rate", "speed"),
        ({"rate": "fast"}, "rate", "fast"),
        ({"size": {"fixed": 0.0}}, "size", "0"),
        ({"material": "steel"}, "material", "steel"),
        ({"region": {"box": {"lower": [0.0, 0.0, 0.04], "upper": [0.02, 0.02, 0.03]}}}, "region", "0.03"),
        ({"start": -1.0}, "start", "-1"),
        ({"every": 0}, "every", "0"),
    ]:
        scene = empty_box()
        with pytest.raises(ValueError) as e:
            scene.add_inlet(**{**good, **change})
        assert f"argument `{name}`" in str(e.value) or f"`{name}" in str(e.value), str(e.value)
        assert shown in str(e.value), str(e.value)
        # Nothing was added: the scene has no inlet column.
        with pytest.raises(ValueError):
            scene.observe()
    # A mass rate the region cannot hold is refused naming the rate.
    scene = empty_box()
    with pytest.raises(ValueError) as e:
        scene.add_inlet(**{**good, "rate": {"mass": 1e3}})
    assert "rate" in str(e.value), str(e.value)
    scene = empty_box()
    with pytest.raises(ValueError) as e:
        scene.add_outlet({"cylinder": {"center": [0.0] * 3, "axis": [0.0] * 3, "radius": 1.0, "length": 1.0}})
    assert "region.cylinder.axis" in str(e.value), str(e.value)
    # After the first step: refused, not a panic.
    scene = empty_box()
    scene.add_particles([[0.01, 0.01, 0.02]], [R])
    scene.step(1)
    with pytest.raises(ValueError) as e:
        scene.add_inlet(**good)
    assert "first step" in str(e.value)
