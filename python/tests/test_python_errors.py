"""Bad input from Python is a ValueError naming the key or argument, for any
type (issue 24, point 5): None, bytes, complex, NumPy scalars and arrays of
any dtype (integers and float32 converted to float64, the rest refused by
dtype), negative, non-whole and huge integers; a dict nested 30,000 deep is
refused (a depth limit of 32), never a crash. A failure that is not the
user's is a RuntimeError. Each case asserts the exception's type itself
(`type(e) is ValueError`: a TypeError, OverflowError, RecursionError or
PyO3's PanicException would fail it) and that the message names the key.
Scene-level physical ranges, step bounds and data files are tested
elsewhere (test_scene_refusals.py, tests/*.rs)."""

from __future__ import annotations

import copy
import math
import subprocess
import sys
import textwrap

import numpy as np
import pytest

import dembound
from conftest import REPO

VALIDATION = REPO / "examples" / "scenes" / "validation.toml"

# A small valid scene as a dict: one sphere resting 0.1 mm above the
# domain's floor, Hertz contact.
BASE = {
    "domain": {"lower": [0.0, 0.0, 0.0], "upper": [0.01, 0.01, 0.01], "periodic": [False] * 3},
    "material": [{"name": "grain", "density": 1000.0, "youngs_modulus": 1e7, "poisson_ratio": 0.3}],
    "contact": {"law": "hertz"},
    "particles": [{"spheres": [{"position": [0.003, 0.005, 0.0011], "radius": 1e-3}], "material": "grain"}],
    "motion": {"gravity": [0.0, 0.0, -9.81]},
    "integration": {"scheme": "verlet", "dt": 5e-6, "steps": 10},
}


def refused(call, *names: str, error: type = ValueError) -> str:
    """Runs `call`, which must raise exactly `error` (not a subclass, not
    another type) with every one of `names` in its message; returns the
    message."""
    with pytest.raises(BaseException) as raised:
        call()
    assert type(raised.value) is error, f"{type(raised.value).__name__}: {raised.value}"
    message = str(raised.value)
    for name in names:
        assert name in message, f"the message does not name `{name}`: {message}"
    return message


def validation() -> dembound.Scene:
    return dembound.Scene.from_toml(VALIDATION)


def scene_with(path: list, value) -> dict:
    """BASE with the value at `path` (keys and list indices) replaced."""
    scene = copy.deepcopy(BASE)
    node = scene
    for k in path[:-1]:
        node = node[k]
    node[path[-1]] = value
    return scene


# ---- Scene.step, Scene.run ----------------------------------------------

BAD_COUNTS = [-1, 1.5, 2.0, 2**70, 10**16, None, "10", True, np.float64(3.0), 1j]


@pytest.mark.parametrize("n", BAD_COUNTS, ids=repr)
def test_step_refuses_what_is_not_a_step_count(n):
    scene = validation()
    refused(lambda: scene.step(n), "n: ", "allowed: a whole number from 0 to")
    assert scene.steps_done == 0


def test_step_takes_numpy_integers_and_zero():
    scene = validation()
    scene.step(np.int64(3))
    scene.step(np.uint8(2))
    scene.step(0)
    assert scene.steps_done == 5


@pytest.mark.parametrize("duration", ["x", b"1", True, math.nan, math.inf, -1.0, 1e300, 1j], ids=repr)
def test_run_refuses_durations(duration):
    refused(lambda: validation().run(duration), "duration")


def test_run_refuses_a_progress_that_cannot_be_called():
    scene = validation()
    refused(lambda: scene.run(1e-5, progress=3), "progress", "callable")
    assert scene.steps_done == 0


def test_run_takes_numpy_durations():
    # 1e-5 s as a float32 is 1.0000000e-05 to 7 digits: the same whole
    # number of steps (rounded) as the float64 1e-5.
    a, b = validation(), validation()
    assert a.run(np.float32(1e-5)) == b.run(1e-5) > 0


# ---- threads, paths, sets -----------------------------------------------

BAD_THREADS = [-1, 0, 1.5, 2**70, 1025, "2", True]


@pytest.mark.parametrize("threads", BAD_THREADS, ids=repr)
def test_scene_constructors_refuse_thread_counts(threads, tmp_path):
    refused(lambda: dembound.Scene.from_toml(VALIDATION, threads=threads), "threads", "1 to 1024")
    refused(lambda: dembound.Scene.from_dict(BASE, threads=threads), "threads", "1 to 1024")
    scene = validation()
    scene.checkpoint(tmp_path / "c.cbor")
    refused(lambda: dembound.Scene.from_checkpoint(tmp_path / "c.cbor", threads=threads), "threads")


@pytest.mark.parametrize("threads", BAD_THREADS, ids=repr)
def test_scene_function_refuses_thread_counts(threads):
    refused(lambda: dembound.scene(VALIDATION, threads=threads), "threads")


def test_threads_take_numpy_integers():
    assert len(dembound.Scene.from_toml(VALIDATION, threads=np.int32(2))) == 2


@pytest.mark.parametrize("path", [None, 42, 1.5, ""], ids=repr)
def test_paths_are_checked(path, tmp_path):
    refused(lambda: dembound.Scene.from_toml(path), "path")
    refused(lambda: dembound.Scene.from_checkpoint(path), "path")
    scene = validation()
    refused(lambda: scene.checkpoint(path), "path")
    refused(lambda: scene.restore(path), "path")
    refused(lambda: scene.write_vtk(path), "directory")
    if path is not None:
        refused(lambda: dembound.Scene.from_dict(BASE, base_dir=path), "base_dir")


@pytest.mark.parametrize("sets", ["integration.steps=5", [1], [None], 5], ids=repr)
def test_sets_must_be_a_list_of_strings(sets):
    refused(lambda: dembound.Scene.from_toml(VALIDATION, sets), "sets")


# ---- Scene.add_particles, Scene.add_plane -------------------------------


@pytest.mark.parametrize(
    "dtype", [np.int64, np.int32, np.uint16, np.float32, np.float16, np.float64], ids=lambda d: d.__name__
)
def test_add_particles_converts_integer_and_float_arrays(dtype):
    # Small whole numbers, which every one of these dtypes holds exactly
    # (a 10 m box, spheres of 1 m at 3 m and 7 m): float64 gets the same
    # values.
    scene = dembound.Scene.from_dict(
        scene_with(["domain", "upper"], [10.0, 10.0, 10.0])
        | {"particles": [{"spheres": [{"position": [5.0, 5.0, 5.0], "radius": 1.0}], "material": "grain"}]}
    )
    positions = np.array([[3, 3, 2], [7, 7, 2]], dtype=dtype)
    radii = np.array([1, 1], dtype=dtype)
    velocities = np.array([[1, 0, 0], [0, 0, 2]], dtype=dtype)
    scene.add_particles(positions, radii, velocities=velocities)
    assert len(scene) == 3
    assert scene.positions[1:].tolist() == [[3.0, 3.0, 2.0], [7.0, 7.0, 2.0]]
    assert scene.radii[1:].tolist() == [1.0, 1.0]
    assert scene.velocities[1:].tolist() == [[1.0, 0.0, 0.0], [0.0, 0.0, 2.0]]


def test_add_particles_converts_float32_exactly():
    # float32 → float64 is exact: the stored values are the float32 values.
    scene = dembound.Scene.from_dict(BASE)
    p32 = np.array([[0.007, 0.005, 0.0011]], dtype=np.float32)
    r32 = np.array([1e-3], dtype=np.float32)
    scene.add_particles(p32, r32, velocities=[[0.0, 0.0, -0.5]], fixed=[False])
    assert scene.positions[1].tolist() == [float(x) for x in p32[0]]
    assert scene.radii[1] == float(r32[0]) != 1e-3


@pytest.mark.parametrize(
    "argument,value",
    [
        ("positions", np.array([[0.007, 0.005, 0.0011]], dtype=complex)),
        ("positions", np.array([["a", "b", "c"]])),
        ("positions", np.array([[True, False, True]])),
        ("positions", np.array([[0.007, 0.005, None]], dtype=object)),
        ("positions", [[0.007, 0.005], [0.0011]]),
        ("positions", None),
        ("positions", np.zeros((1, 2))),
        ("positions", np.zeros(3)),
        ("radii", np.array([1e-3 + 0j])),
        ("radii", b"x"),
        ("radii", np.array(["1e-3"])),
        ("velocities", np.array([[0, 0, 1j]])),
        ("velocities", np.zeros((2, 3))),
        ("fixed", np.array([0.5])),
        ("fixed", np.array([2])),
        ("fixed", np.array(["yes"])),
        ("fixed", np.array([True, False])),
        ("material", -1),
        ("material", 1),
        ("material", 1.0),
        ("material", 2**70),
        ("material", "grain"),
    ],
    ids=lambda x: x if isinstance(x, str) else None,
)
def test_add_particles_refuses_naming_the_argument(argument, value):
    arguments = {"positions": np.array([[0.007, 0.005, 0.0011]]), "radii": np.array([1e-3])}
    arguments[argument] = value
    scene = dembound.Scene.from_dict(BASE)
    refused(lambda: scene.add_particles(**arguments), f"{argument}:")
    assert len(scene) == 1


def test_add_particles_takes_integer_flags():
    scene = dembound.Scene.from_dict(BASE)
    scene.add_particles([[0.007, 0.005, 0.0011], [0.005, 0.008, 0.0011]], [1e-3, 1e-3], fixed=np.array([1, 0]))
    assert scene.fixed.tolist() == [False, True, False]


@pytest.mark.parametrize(
    "argument,value",
    [
        ("point", [0.0, 0.0]),
        ("point", None),
        ("point", np.array([0, 0, 1j])),
        ("normal", "up"),
        ("normal", np.array([0, 0, 1], dtype=object)),
        ("material", -1),
        ("material", 0.0),
    ],
    ids=lambda x: x if isinstance(x, str) else None,
)
def test_add_plane_refuses_naming_the_argument(argument, value):
    arguments = {"point": [0.0, 0.0, 0.0], "normal": [0.0, 0.0, 1.0]}
    arguments[argument] = value
    scene = dembound.Scene.from_dict(BASE)
    refused(lambda: scene.add_plane(**arguments), f"{argument}:")
    assert scene.wall_forces.shape == (0, 3)


def test_add_plane_takes_numpy_arrays():
    scene = dembound.Scene.from_dict(BASE)
    scene.add_plane(np.zeros(3, dtype=np.float32), np.array([0, 0, 1]), material=np.int64(0))
    assert scene.wall_forces.shape == (1, 3)


# ---- Scene.from_dict ----------------------------------------------------

DENSITY = ["material", 0, "density"]


@pytest.mark.parametrize(
    "value,what",
    [
        (None, "NoneType"),
        (b"1000", "bytes"),
        (1000j, "complex"),
        (np.complex128(1000), "complex128"),
        (object(), "object"),
        (np.array([1000.0 + 0j]), "complex128"),
        (np.array(["1000"]), "<U4"),
        (np.array([1000.0], dtype=object), "object"),
        (2**70, "64-bit integer"),
        (np.uint64(2**64 - 1), "64-bit integer"),
    ],
    ids=lambda x: x if isinstance(x, str) else None,
)
def test_from_dict_names_the_key_of_a_bad_value(value, what):
    message = refused(lambda: dembound.Scene.from_dict(scene_with(DENSITY, value)), "`material[0].density`")
    assert what in message
    assert "invalid type: unit value" not in message


def test_from_dict_names_keys_deep_in_lists():
    refused(
        lambda: dembound.Scene.from_dict(scene_with(["particles", 0, "spheres", 0, "position", 2], None)),
        "`particles[0].spheres[0].position[2]`",
    )
    refused(lambda: dembound.Scene.from_dict(scene_with(["domain", 3], 1.0)), "`domain`", "str keys")


@pytest.mark.parametrize("scene", [None, [1], "scene.toml", b"x"], ids=repr)
def test_from_dict_needs_a_dict(scene):
    refused(lambda: dembound.Scene.from_dict(scene), "scene: ")


@pytest.mark.parametrize(
    "convert",
    [
        lambda x: np.float64(x),
        lambda x: np.float32(x) if float(np.float32(x)) == x else np.float64(x),
        lambda x: np.int64(x) if x == int(x) else x,
        lambda x: np.array(x),
    ],
    ids=["float64", "float32 where exact", "int64 where whole", "0-d array"],
)
def test_from_dict_takes_numpy_scalars_as_their_values(convert):
    # Every float of BASE through a NumPy type: the same scene, bit for bit.
    def numpyfied(node):
        if isinstance(node, dict):
            return {k: numpyfied(v) for k, v in node.items()}
        if isinstance(node, list):
            return [numpyfied(v) for v in node]
        if isinstance(node, float):
            return convert(node)
        return node

    plain = dembound.Scene.from_dict(BASE)
    other = dembound.Scene.from_dict(numpyfied(BASE))
    plain.step(10)
    other.step(10)
    assert other.dt == plain.dt
    assert np.array_equal(other.positions, plain.positions)
    assert np.array_equal(other.radii, plain.radii)


def test_from_dict_takes_numpy_arrays_and_bools():
    scene = copy.deepcopy(BASE)
    scene["domain"]["upper"] = np.array([0.01, 0.01, 0.01])
    scene["domain"]["periodic"] = np.array([False, False, False])
    scene["particles"][0]["spheres"][0]["position"] = np.array([0.003, 0.005, 0.0011], dtype=np.float64)
    scene["particles"][0]["fixed"] = np.bool_(False)
    built = dembound.Scene.from_dict(scene)
    assert built.positions.tolist() == [[0.003, 0.005, 0.0011]]


DEEP = textwrap.dedent(
    """
    import dembound
    deep = {}
    node = deep
    for _ in range(30_000):
        node["a"] = {}
        node = node["a"]
    try:
        dembound.Scene.from_dict(%s)
    except ValueError as e:
        print("ValueError:", e)
    """
)


@pytest.mark.parametrize("scene", ["deep", "{'domain': deep}", "dict(BASE_DOMAIN=[deep])"])
def test_from_dict_refuses_deep_nesting_without_crashing(scene):
    # In a child process: a stack overflow (the crash this replaced) kills
    # the child with SIGSEGV, a failed test instead of a dead pytest.
    out = subprocess.run(
        [sys.executable, "-c", DEEP % scene], capture_output=True, text=True, timeout=300, cwd=REPO
    )
    assert out.returncode == 0, f"exit {out.returncode}: {out.stderr[-2000:]}"
    assert out.stdout.startswith("ValueError: scene dict: `"), out.stdout + out.stderr
    assert "nested deeper than 32 levels" in out.stdout


def test_from_dict_refuses_a_list_that_contains_itself():
    loop: list = []
    loop.append(loop)
    refused(lambda: dembound.Scene.from_dict(scene_with(["domain", "upper"], loop)), "`domain.upper[0]", "32 levels")


# ---- failures are RuntimeError ------------------------------------------


def test_a_missing_data_file_follows_the_cli_exit_code(cli, tmp_path):
    # ValueError where the CLI exits 2 (bad input), RuntimeError where it
    # exits 1: whichever the scene crate decides, Python says the same.
    missing = tmp_path / "missing.data"
    file = tmp_path / "scene.toml"
    file.write_text(
        textwrap.dedent(
            f"""
            [domain]
            lower = [0.0, 0.0, 0.0]
            upper = [0.01, 0.01, 0.01]
            [[material]]
            name = "grain"
            density = 1000.0
            youngs_modulus = 1e7
            poisson_ratio = 0.3
            [contact]
            law = "hertz"
            [[particles]]
            lammps_data = "{missing}"
            material = "grain"
            [integration]
            dt = 5e-6
            steps = 10
            """
        )
    )
    code = cli(["scene", "--json", "--quiet", str(file)]).returncode
    assert code in (1, 2)
    error = ValueError if code == 2 else RuntimeError
    refused(lambda: dembound.Scene.from_toml(file), str(missing), error=error)
    dict_scene = scene_with(["particles"], [{"lammps_data": str(missing), "material": "grain"}])
    refused(lambda: dembound.Scene.from_dict(dict_scene), str(missing), error=error)


def test_an_unwritable_output_is_runtime_error(tmp_path):
    blocker = tmp_path / "file"
    blocker.write_text("")
    scene = validation()
    refused(lambda: scene.write_vtk(blocker / "vtk"), "cannot write", error=RuntimeError)
    refused(lambda: scene.checkpoint(blocker / "c.cbor"), "cannot write", error=RuntimeError)


# ---- the bounce studies: dembound.run, exact, sweep, batch… -------------


@pytest.mark.parametrize(
    "value,what",
    [
        (None, "NoneType"),
        (b"1e-3", "bytes"),
        (1e-3j, "complex"),
        (np.complex128(1e-3), "complex128"),
        (np.array([1e-3 + 0j]), "complex128"),
        (np.array(["1e-3"]), "<U4"),
        (np.array([1e-3], dtype=object), "object"),
        (object(), "object"),
    ],
    ids=lambda x: x if isinstance(x, str) else None,
)
def test_study_values_name_the_key(value, what):
    for call in (dembound.run, dembound.exact):
        message = refused(lambda: call(particle__radius=value), "`particle.radius`")
        assert what in message
    message = refused(lambda: dembound.run({"particle": {"radius": value}}), "`particle.radius`")
    assert what in message
    refused(lambda: dembound.scene(VALIDATION, integration__dt=value), "`integration.dt`")


@pytest.mark.parametrize(
    "numpy_value,python_value",
    [
        (np.float64(1.5e-3), 1.5e-3),
        (np.float32(1.5e-3), float(np.float32(1.5e-3))),
        (np.int64(2), 2),
    ],
    ids=["float64", "float32", "int64"],
)
def test_study_values_take_numpy_scalars(numpy_value, python_value):
    key = "motion__contacts" if isinstance(python_value, int) else "particle__radius"
    assert dembound.run(**{key: numpy_value}) == dembound.run(**{key: python_value})


def test_study_values_take_numpy_bools():
    assert dembound.run(boundary__fixed=np.bool_(True)) == dembound.run(boundary__fixed=True)


def test_deep_scenario_values_are_refused():
    deep: dict = {}
    node = deep
    for _ in range(30_000):
        node["a"] = {}
        node = node["a"]
    refused(lambda: dembound.run(contact__law=deep), "`contact.law", "32 levels")


@pytest.mark.parametrize("rows", [0, -1, 1.5, 2**70, True, None, "10"], ids=repr)
def test_history_rows_are_whole_numbers(rows):
    if rows is not None:
        refused(lambda: dembound.run(history=rows), "history: ")
    refused(lambda: dembound.history(points=rows), "points: ")


@pytest.mark.parametrize("target", [None, "0.5", b"0.5", 0.5j, True], ids=repr)
def test_restitution_target_is_a_real_number(target):
    refused(lambda: dembound.restitution(target=target, law="hertz-tsuji", r="inf", zeta="inf"), "target: ")


@pytest.mark.parametrize("target", [-math.inf, -0.5, math.inf, math.nan], ids=repr)
def test_restitution_target_out_of_range_names_target(target):
    # A negative value was passed as a separate argument, so "-inf" was
    # read as the flags -i -n -f ("unexpected argument '-i' found").
    refused(lambda: dembound.restitution(target=target, law="tsuji", r=10, zeta=10), "--target")


@pytest.mark.parametrize("tolerance", [-1.0, "-1%", -math.inf], ids=repr)
def test_recommend_negative_tolerance_names_tolerance(tolerance):
    refused(lambda: dembound.recommend(tolerance=tolerance), "--tolerance")


@pytest.mark.parametrize("tolerance", [b"1%", 0.01j, False, [0.01]], ids=repr)
def test_recommend_tolerance_is_a_number_or_text(tolerance):
    refused(lambda: dembound.recommend(tolerance=tolerance), "tolerance: ")


@pytest.mark.parametrize(
    "value", [b"1,10", [1, None], np.array([1 + 1j]), np.array([True]), {"a": 1}, True, 3j], ids=repr
)
def test_sweep_lists_name_the_option(value):
    refused(lambda: dembound.sweep(r=value, zeta=1), "`r`")
    refused(lambda: dembound.sweep(r=1, zeta=value), "`zeta`")


def test_sweep_lists_take_numpy_arrays():
    a = dembound.sweep(r=np.array([1, 10], dtype=np.int32), zeta=np.float64(1))
    b = dembound.sweep(r=[1.0, 10.0], zeta=1.0)
    assert a["cases"] == b["cases"]


@pytest.mark.parametrize(
    "values,dtype",
    [
        (np.array([1.0 + 1j, 2.0]), "complex128"),
        (np.array(["1", "2"]), "<U1"),
        (np.array([1.0, 2.0], dtype=object), "object"),
        (np.array([True, False]), "bool"),
    ],
    ids=lambda x: x if isinstance(x, str) else None,
)
def test_batch_refuses_arrays_that_are_not_real_numbers(values, dtype):
    message = refused(lambda: dembound.batch(r=values, zeta=100.0), "`boundary.radius_ratio`")
    assert dtype in message


def test_batch_converts_integer_and_float32_arrays():
    # 1, 2 and 4 are exact in every dtype: the same cases as float64.
    expected = dembound.batch(r=np.array([1.0, 2.0, 4.0]), zeta=100.0)
    for dtype in (np.int64, np.int8, np.uint32, np.float32):
        got = dembound.batch(r=np.array([1, 2, 4], dtype=dtype), zeta=100.0)
        for key, value in expected.items():
            assert np.array_equal(got[key], value, equal_nan=True), (dtype, key)


@pytest.mark.parametrize("value", [None, 1, "yes", 1.0], ids=repr)
def test_flags_are_bools(value):
    refused(lambda: dembound.run(compare_exact=value), "compare_exact: ")
    refused(lambda: dembound.run(force=value), "force: ")


@pytest.mark.parametrize("value", [1, b"rigid", 0.5], ids=repr)
def test_text_options_are_strings(value):
    refused(lambda: dembound.recommend(reference=value), "reference: ")
    refused(lambda: dembound.restitution(target=0.5, calibrate=value), "calibrate: ")


@pytest.mark.parametrize("path", [None, 42, b"scene.toml", ""], ids=repr)
def test_scene_and_scenario_paths_are_checked(path):
    refused(lambda: dembound.scene(path), "path: ")
    if path not in (None, 42):  # None is the default scenario; 42 is "not a scenario"
        refused(lambda: dembound.run(path), "scenario")


def test_a_damped_gear5_step_past_its_stability_bound_is_refused():
    # Spring-dashpot, e = 0.01 with attraction, eta = 0.1: a parasitic root
    # of Gear5 passes -1 at (w dt/0.840)^2 + beta dt/0.163 = 1; the run
    # printed e = 0.245 with exit 0 before (session 36). The largest eta it
    # accepts, 0.0256 (the message), runs.
    keys = dict(
        contact__law="linear", contact__damping="viscous", contact__restitution=0.01,
        contact__attractive=True, motion__gravity=0.0, motion__velocity=-0.313,
        motion__contacts=1,
    )
    message = refused(lambda: dembound.run(integration__eta=0.1, **keys), "integration.eta")
    assert "contact.restitution" in message, message
    refused(lambda: dembound.history(integration__eta=0.1, **keys), "integration.eta")
    e = dembound.run(integration__eta=0.025, **keys)["contacts"][0]["restitution"]
    # The closed form of the attractive spring-dashpot gives exactly 0.01;
    # Gear5 at the bound is within 1e-4 of it (the CLI test's grid).
    assert abs(e / 0.01 - 1.0) < 1e-3, e


def test_walton_braun_unloading_the_step_cannot_resolve_is_refused():
    # e = 0.001 at the default step: k2 = k1/e^2 oscillates ~1000 times
    # faster than the loading; the run printed e = 2.09 (energy created)
    # before the step's bound (omega2 dt <= 0.9 with Gear5).
    keys = dict(contact__law="walton-braun", contact__damping="none", contact__restitution=0.001)
    refused(lambda: dembound.run(**keys), "contact.restitution")
    refused(lambda: dembound.history(**keys), "contact.restitution")
    # A step that resolves it: the rebound is dissipative, 0 < e <= 1.
    ok = dembound.run(
        contact__law="walton-braun", contact__damping="none", contact__restitution=0.03,
        motion__contacts=1, integration__eta=0.01,
    )
    e = ok["contacts"][0]["restitution"]
    assert 0.0 < e <= 1.0, e
