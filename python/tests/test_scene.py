"""The scene engine from Python: the CLI's `scene --json` document, arrays,
collision log, VTK, checkpoint and restart, bodies and walls from arrays."""

from __future__ import annotations

import math

import numpy as np
import pytest

import dembound
from conftest import REPO, assert_same

VALIDATION = REPO / "examples" / "scenes" / "validation.toml"
# Wall-clock figures differ from run to run; everything else must not.
TIMINGS = ("wall_clock", "wall_clock_total", "particle_steps_per_second")


def test_scene_json_equals_cli(cli_json):
    python = dembound.scene(VALIDATION, threads=1)
    expected = cli_json(["scene", "--json", "--quiet", "--threads", "1", str(VALIDATION)])
    for k in TIMINGS:
        assert k in expected
        python.pop(k)
        expected.pop(k)
    assert_same(python, expected)


def test_scene_stepping_arrays_and_collision_log():
    scene = dembound.Scene.from_toml(VALIDATION)
    assert len(scene) == 2
    assert scene.positions.shape == (2, 3)
    assert scene.radii.tolist() == [0.5e-3, 0.05]
    assert scene.fixed.tolist() == [False, True]
    z0 = scene.positions[0, 2]
    scene.step(1000)
    assert scene.steps_done == 1000
    # Free fall from rest (no contact yet): z = z0 − g t²/2, v = −g t; the
    # integrator is exact for constant acceleration up to rounding.
    t = scene.time
    assert abs(t - 1000 * scene.dt) <= 1e-12 * t
    assert scene.positions[0, 2] == pytest.approx(z0 - 9.81 * t * t / 2, rel=1e-12)
    assert scene.velocities[0, 2] == pytest.approx(-9.81 * t, rel=1e-12)
    # No friction key: nothing spins (exactly zero, not small).
    assert scene.angular_velocities.shape == (2, 3)
    assert not scene.angular_velocities.any()
    calls = []
    steps = scene.run(progress=lambda done, total: calls.append((done, total)))
    assert steps == scene.total_steps - 1000
    assert calls[-1] == (steps, steps) and len(calls) >= 50
    assert scene.forces.shape == (2, 3) and scene.wall_forces.shape == (0, 3)
    log = scene.collisions
    assert len(log["i"]) == 1 and log["i"][0] == 0 and log["j"][0] == 1 and log["wall"][0] == -1
    # The exact reference of the validation case (Hertz, the paper's drop):
    # h_max = 524.1905 nm, T_c = 4.92579 µs; the scene's Gear5 at η = 1/50
    # is within 6e-5 (crates/dembound-scene tests), so 1e-4 here.
    assert log["max_overlap"][0] == pytest.approx(524.1905e-9, rel=1e-4)
    assert log["duration"][0] == pytest.approx(4.92579e-6, rel=1e-4)
    energies = scene.observe()
    assert energies["step"] == scene.steps_done and "kinetic_energy_J" in energies


def test_checkpoint_and_restart_are_bit_for_bit(tmp_path):
    straight = dembound.Scene.from_toml(VALIDATION)
    straight.step(200_000)
    first = dembound.Scene.from_toml(VALIDATION)
    first.step(120_000)
    first.checkpoint(tmp_path / "c.cbor")
    again = dembound.Scene.from_toml(VALIDATION)
    again.restore(tmp_path / "c.cbor")
    assert again.steps_done == 120_000
    again.step(80_000)
    assert np.array_equal(again.positions, straight.positions)
    assert np.array_equal(again.velocities, straight.velocities)
    loaded = dembound.Scene.from_checkpoint(tmp_path / "c.cbor")
    loaded.step(80_000)
    assert np.array_equal(loaded.positions, straight.positions)


LATTICE = REPO / "examples" / "scenes" / "lattice_drop.toml"
# lattice_drop.toml cut to 8 x 8 x 6 spheres in a 10.2 mm box, Mindlin
# friction 0.5 and rolling friction 0.05 on grains and walls, dt = 20 us:
# the lattice lands on the floor from step ~50 and bounces.
FRICTIONAL_LATTICE = [
    "particles.0.lattice.counts=[8,8,6]",
    "domain.upper=[0.0102,0.0102,0.03]",
    "wall.1.plane.point=[0.0102,0.0,0.0]",
    "wall.3.plane.point=[0.0,0.0102,0.0]",
    "contact.friction=0.5",
    "contact.rolling_friction=0.05",
    "integration.dt=2e-5",
    "output.collisions=true",
]


@pytest.mark.parametrize(
    "scheme",
    [
        ["integration.scheme=verlet"],
        # Gear5 at 2 us (its stable step with friction on this bed), Tsuji
        # e = 0.6, E = 1e8 Pa: the lattice lands from step ~500.
        [
            "integration.scheme=gear5",
            "integration.dt=2e-6",
            "material.0.youngs_modulus=1e8",
            "contact.damping=tsuji",
            "contact.restitution=0.6",
        ],
    ],
    ids=["verlet", "gear5"],
)
def test_restart_in_the_middle_of_contacts_is_bit_for_bit(tmp_path, scheme):
    sets = FRICTIONAL_LATTICE + scheme
    n = 1000 if scheme[0].endswith("verlet") else 4000
    straight = dembound.Scene.from_toml(LATTICE, sets)
    straight.step(n)
    first = dembound.Scene.from_toml(LATTICE, sets)
    first.step(n // 2)
    # Not vacuous: contacts on pairs and on the floor are live at the
    # checkpoint, and friction is loaded there: the floor (wall 4, a plane
    # with friction) carries a tangential force, which without its
    # tangential springs it could not (elastic contacts: no damping), and
    # spheres spin.
    at = first.observe()
    assert at["particle_contacts"] > 0 and at["wall_contacts"] > 0, at
    assert np.any(first.wall_forces[4, :2] != 0.0), first.wall_forces[4]
    assert np.any(first.angular_velocities != 0.0)
    first.checkpoint(tmp_path / "c.cbor")
    for restarted in (
        dembound.Scene.from_toml(LATTICE, sets, threads=2),
        dembound.Scene.from_checkpoint(tmp_path / "c.cbor"),
    ):
        if restarted.steps_done == 0:
            restarted.restore(tmp_path / "c.cbor")
        assert restarted.steps_done == n // 2
        restarted.step(n - n // 2)
        for name in ("positions", "velocities", "angular_velocities", "forces", "wall_forces"):
            assert np.array_equal(getattr(restarted, name), getattr(straight, name)), name
        assert_same(restarted.observe(), straight.observe())
        for key, column in straight.collisions.items():
            assert np.array_equal(restarted.collisions[key], column), key
    assert np.all(np.isfinite(straight.positions))


def test_write_vtk(tmp_path):
    scene = dembound.Scene.from_toml(VALIDATION)
    path = scene.write_vtk(tmp_path / "vtk")
    text = path.read_text()
    assert path.name.endswith(".vtp") and "<VTKFile" in text and 'NumberOfPoints="2"' in text


def test_scene_from_dict_with_bodies_and_walls_from_arrays():
    # A box of two spheres falling onto a plane added from Python: each
    # rests on the floor at the end (damped), so the floor carries their
    # weight N m g.
    scene = dembound.Scene.from_dict(
        {
            "domain": {"lower": [0.0, 0.0, 0.0], "upper": [0.01, 0.01, 0.01], "periodic": [False] * 3},
            "material": [{"name": "grain", "density": 1000.0, "youngs_modulus": 1e7, "poisson_ratio": 0.3}],
            "contact": {"law": "hertz", "damping": "tsuji", "restitution": 0.3},
            "particles": [{"spheres": [{"position": [0.003, 0.005, 0.0011], "radius": 1e-3}], "material": "grain"}],
            "motion": {"gravity": [0.0, 0.0, -9.81]},
            "integration": {"scheme": "verlet", "dt": 5e-6, "duration": 0.2},
            "output": {"collisions": True},
        }
    )
    assert len(scene) == 1
    scene.add_particles(np.array([[0.007, 0.005, 0.0011]]), np.array([1e-3]))
    scene.add_plane([0.0, 0.0, 0.0], [0.0, 0.0, 1.0])
    assert len(scene) == 2 and scene.wall_forces.shape == (1, 3)
    scene.run()
    # The force on the floor is the bed's weight N m g pointing down (−z,
    # along gravity): the spheres push the floor down as it holds them up.
    weight = 2 * 1000.0 * 4 / 3 * math.pi * 1e-3**3 * 9.81
    # Settled: the rebounds from the 0.1 mm drop (0.044 m/s, e = 0.3)
    # end within 2v/(g(1 − e)) ≈ 13 ms; then each sphere oscillates about
    # its static overlap δ = (m g / (4/3 E* √R))^(2/3) = 0.32 µm at
    # ω = √(3 g / (2 δ)) = 6.8e3 rad/s, its amplitude shrinking by a
    # factor of order e every half period π/ω = 0.46 ms: over the 0.18 s
    # left, 390 half periods, about 0.3^390 ≈ 1e-204, nothing in doubles.
    # What is left is the rounding of a few force sums (1e-16 relative
    # each); 1e-9 is far above that and far below a missing sphere (½), a
    # mass or g off in any digit that matters, or a damping force still
    # acting.
    assert scene.wall_forces[0, 2] == pytest.approx(-weight, rel=1e-9)
    # A flat floor and spheres with no sideways motion: no sideways force.
    assert scene.wall_forces[0, 0] == 0.0 and scene.wall_forces[0, 1] == 0.0
    # The torque on the floor about its point (the origin): each sphere's
    # weight m g = N m g / 2 pressing at its contact point, below its centre
    # at d = (3, 5) mm and (7, 5) mm: Σ d × (0, 0, −m g) =
    # (−m g Σ d_y, m g Σ d_x, 0) = (−0.005, 0.005, 0) m × N m g; the z
    # part exactly 0 (vertical forces). Tolerance as the force's.
    assert scene.wall_torque_points.tolist() == [[0.0, 0.0, 0.0]]
    torque = scene.wall_torques
    assert torque.shape == (1, 3)
    assert torque[0, 0] == pytest.approx(-0.005 * weight, rel=1e-9)
    assert torque[0, 1] == pytest.approx(0.005 * weight, rel=1e-9)
    assert torque[0, 2] == 0.0
    row = scene.observe()
    assert [row[f"wall0_torque_{a}_N_m"] for a in "xyz"] == torque[0].tolist()
    assert [row[f"wall0_force_{a}_N"] for a in "xyz"] == scene.wall_forces[0].tolist()
    with pytest.raises(ValueError, match="before the first step"):
        scene.add_plane([0.0, 0.0, 0.01], [0.0, 0.0, -1.0])
    with pytest.raises(ValueError, match="missing field `material`"):
        dembound.Scene.from_dict({"domain": {"lower": [0, 0, 0], "upper": [1, 1, 1]}})


def test_scene_bad_input_is_value_error():
    with pytest.raises(ValueError, match="integration"):
        dembound.Scene.from_toml(VALIDATION, ["integration.eta=5"])


def test_a_step_beyond_the_bound_is_refused_and_energy_creation_stopped():
    # Δt = 1 ms, 500x the bed's 2 µs and 17x its contact time, is refused
    # when the scene is built (issue 24; it used to blow up).
    bed = REPO / "examples" / "scenes" / "bed_particle_floor.toml"
    with pytest.raises(ValueError, match=r"integration.dt = 1e-3 s is out of range"):
        dembound.Scene.from_toml(bed, ["integration.dt=1e-3"])
    # Inside the bounds, Gear5 with friction on the strongly damped settling
    # bed creates energy (by step 3,250; frictionless it runs since session
    # 37's fix of the damped onset): the energy guard stops it.
    settling = REPO / "examples" / "scenes" / "settling_bed.toml"
    scene = dembound.Scene.from_toml(
        settling, ['integration.scheme="gear5"', "contact.friction=0.5"]
    )
    with pytest.raises(ValueError, match=r"the run created energy"):
        for _ in range(100):
            scene.step(100)
    assert scene.steps_done < 8200


def test_a_damped_gear5_scene_past_its_stability_bound_is_refused():
    # Tsuji e = 0.01 with attraction on the validation drop at eta = 0.05: a
    # parasitic root of Gear5 passes -1 at (w dt/0.840)^2 + beta dt/0.163 = 1;
    # the scene rebounded with e = 0.081 (exact 0.0098) before (session 36),
    # creating no energy, so the energy guard could not stop it.
    keys = ["contact.damping=tsuji", "contact.restitution=0.01", "contact.attractive=true"]
    with pytest.raises(ValueError, match=r"integration.eta = 0.05 is out of range: .*gear5"):
        dembound.Scene.from_toml(VALIDATION, keys + ["integration.eta=0.05"])
    with pytest.raises(ValueError, match=r"integration.eta = 0.05 is out of range"):
        dembound.scene(
            VALIDATION,
            contact__damping="tsuji", contact__restitution=0.01, contact__attractive=True,
            integration__eta=0.05,
        )
    # The validation file's own eta = 0.02 is inside the bound (0.0225).
    dembound.Scene.from_toml(VALIDATION, keys)

