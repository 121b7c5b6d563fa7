"""Issue 24 from Python: the scene refusals of tests/cli_scene_refusals.rs
reach `Scene.from_dict` (the scene file's checks, through `resolve`) and
`add_particles` / `add_plane` (the engine's setup checks, through
`Simulation::prepare`). The exception type is another helper's concern
(issue 24, part 5): here any exception, with the key or the pair named."""

from __future__ import annotations

import copy

import numpy as np
import pytest

import dembound

BASE = {
    "domain": {"lower": [0.0, 0.0, 0.0], "upper": [0.01, 0.01, 0.01]},
    "material": [{"name": "g", "density": 1000.0, "youngs_modulus": 1e7, "poisson_ratio": 0.3}],
    "particles": [
        {"material": "g", "spheres": [{"position": [0.005, 0.005, 0.002], "radius": 0.0005}]}
    ],
    "wall": [{"plane": {"point": [0.0, 0.0, 0.0], "normal": [0.0, 0.0, 1.0]}, "material": "g"}],
    "integration": {"dt": 1e-6, "steps": 100},
}


def scene(**changes):
    d = copy.deepcopy(BASE)
    for path, value in changes.items():
        *parents, last = path.split("__")
        here = d
        for p in parents:
            here = here[int(p)] if p.isdigit() else here.setdefault(p, {})
        if last.isdigit():
            here[int(last)] = value
        else:
            here[last] = value
    return d


def refused(d, *needles):
    with pytest.raises(Exception) as info:
        dembound.Scene.from_dict(d)
    text = str(info.value)
    for n in needles:
        assert n in text, text
    return text


def test_the_base_scene_runs():
    s = dembound.Scene.from_dict(scene())
    s.step(10)
    assert s.steps_done == 10


def test_a_wall_across_a_periodic_axis():
    refused(scene(domain__periodic=[False, False, True]), "wall[0].plane.normal", "domain.periodic")


def test_a_sphere_behind_a_plane():
    d = scene(particles__0__spheres=[{"position": [0.005, 0.005, -0.002], "radius": 0.0005}])
    # The centre is 2 mm behind the floor.
    refused(d, "particles[0].spheres[0]", "wall[0].plane", "behind", "2.0000e-3 m")


def test_coincident_spheres():
    same = {"position": [0.005, 0.005, 0.002], "radius": 0.0005}
    refused(scene(particles__0__spheres=[same, same]),
            "particles[0].spheres[0]", "particles[0].spheres[1]", "coincident")


@pytest.mark.parametrize("path,value,key", [
    ("material__0__density", 5e-324, "material[0].density"),
    ("material__0__youngs_modulus", 1e20, "material[0].youngs_modulus"),
    ("motion__gravity", [0.0, 0.0, -1e300], "motion.gravity"),
    ("contact__friction", 11.0, "contact.friction"),
])
def test_physical_ranges(path, value, key):
    refused(scene(**{path: value}), key)


def test_velocity_and_radius_ranges():
    fast = {"position": [0.005, 0.005, 0.002], "radius": 0.0005, "velocity": [0.0, 0.0, 1e300]}
    refused(scene(particles__0__spheres=[fast]), "particles[0].spheres[0].velocity")
    tiny = {"position": [0.005, 0.005, 0.002], "radius": 1e-300}
    refused(scene(particles__0__spheres=[tiny]), "particles[0].spheres[0].radius")


def test_messages_name_keys_that_exist():
    text = refused(scene(contact={"law": {"power": 3.5}}), "contact.law.power")
    assert "contact.exponent" not in text
    refused(scene(contact={"law": "walton-braun", "restitution": 0.5, "attractive": True}),
            "contact.attractive")


def test_arrays_added_from_python_are_checked_by_the_engine():
    s = dembound.Scene.from_dict(scene())
    # On the existing sphere's centre: coincident, named by input index.
    with pytest.raises(Exception, match="coincident"):
        s.add_particles(np.array([[0.005, 0.005, 0.002]]), np.array([0.0005]))
    # Behind the floor.
    with pytest.raises(Exception, match="behind"):
        s.add_particles(np.array([[0.003, 0.003, -0.001]]), np.array([0.0005]))
    # A plane across a periodic axis.
    p = dembound.Scene.from_dict(scene(domain__periodic=[True, False, False], wall=[]))
    with pytest.raises(Exception, match="domain.periodic"):
        p.add_plane([0.0, 0.0, 0.0], [1.0, 0.0, 0.0])
    # The refused additions left the scene as it was: it still runs.
    s.step(10)
    assert len(s) == 1
