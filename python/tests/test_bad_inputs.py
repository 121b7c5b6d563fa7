"""Bad input from Python raises ValueError naming the key (issue 14,
must-show 3): every refused case of tests/cli_bad_inputs.rs, table-driven,
each also through the binary: it must exit 2, and the Python message must
be the CLI's `error: …` message."""

from __future__ import annotations

import math

import pytest

import dembound

INF = math.inf

# (sets as the CLI's --set strings, the key the error must name); the rows of
# tests/cli_bad_inputs.rs: run_refuses_steps_that_do_not_resolve_the_contact,
# run_refuses_contacts_the_step_would_skip_or_gravity_dominates,
# run_refuses_physical_inputs_out_of_range.
RUN_CASES = [
    (["integration.eta=1"], "integration.eta"),
    (["integration.eta=0.5"], "integration.eta"),
    (["integration.eta=0.2"], "integration.eta"),
    (["integration.eta=0.11"], "integration.eta"),
    (["integration.eta=1e-12"], "integration.eta"),
    (["integration.dt=1e-4"], "integration.dt"),
    (["integration.dt=0.01"], "integration.dt"),
    (["integration.dt=1", "integration.stepping=fixed"], "integration.dt"),
    (["integration.dt=0.01", "integration.stepping=fixed"], "integration.dt"),
    (["integration.tolerance=5"], "integration.tolerance"),
    (["integration.tolerance=0.5"], "integration.tolerance"),
    (["motion.gap=1e-15"], "motion.gap"),
    (["motion.gap=1e-308"], "motion.gap"),
    (["motion.gap=0"], "motion.gap"),
    (["motion.gap=1e-12"], "motion.gap"),
    (["motion.gap=1e-15", "contact.law=linear"], "motion.gap"),
    (["motion.gap=1e-15", "integration.stepping=fixed"], "motion.gap"),
    (["contact.law=hertz", "contact.damping=tsuji", "contact.restitution=0.3", "motion.contacts=12"],
     "motion.contacts"),
    (["contact.law=hertz", "contact.damping=tsuji", "contact.restitution=0.3", "motion.contacts=8"],
     "motion.contacts"),
]

RANGE_CASES = [
    (["boundary.radius_ratio=1e-308"], "boundary.radius_ratio"),
    (["boundary.radius_ratio=1e-300", "integration.stepping=fixed"], "boundary.radius_ratio"),
    (["boundary.radius_ratio=1e300"], "boundary.radius_ratio"),
    (["boundary.modulus_ratio=1e-300"], "boundary.modulus_ratio"),
    (["particle.radius=1e3"], "particle.radius"),
    (["particle.radius=1e308"], "particle.radius"),
    (["particle.radius=1e-300"], "particle.radius"),
    (["particle.youngs_modulus=1"], "particle.youngs_modulus"),
    (["particle.youngs_modulus=1e300"], "particle.youngs_modulus"),
    (["particle.density=1e300"], "particle.density"),
    (["motion.gravity=1e-308"], "motion.gravity"),
    (["motion.gravity=1e300"], "motion.gravity"),
    (["motion.gap=1e308"], "motion.gap"),
    (["motion.velocity=1e300"], "motion.velocity"),
    (["motion.velocity=-1e300"], "motion.velocity"),
    (["boundary.fixed=false", "boundary.velocity=1e300", "motion.contacts=1"], "boundary.velocity"),
]


def python_value(text: str):
    """The --set VALUE as the Python value a user would pass."""
    if text in ("true", "false"):
        return text == "true"
    try:
        return int(text)
    except ValueError:
        pass
    try:
        return float(text)
    except ValueError:
        return text


def keywords(sets: list[str]) -> dict:
    out = {}
    for s in sets:
        key, value = s.split("=", 1)
        out[key.replace(".", "__")] = python_value(value)
    return out


def cli_message(cli, args: list[str], key: str) -> str:
    out = cli(args)
    assert out.returncode == 2, f"dembound {args}: exit {out.returncode}, expected 2: {out.stderr}"
    lines = [line for line in out.stderr.splitlines() if line.startswith("error: ")]
    assert lines, out.stderr
    message = out.stderr[out.stderr.index("error: ") + len("error: "):].strip()
    assert key in message
    return message


def check(cli, call, args: list[str], key: str) -> None:
    with pytest.raises(ValueError) as raised:
        call()
    message = str(raised.value)
    assert key in message, f"{args}: the ValueError does not name `{key}`: {message}"
    assert "NaN" not in message
    assert message == cli_message(cli, args, key)


def with_sets(command: str, sets: list[str]) -> list[str]:
    args = [command, "--json"]
    for s in sets:
        args += ["--set", s]
    return args


@pytest.mark.parametrize("sets,key", RUN_CASES + RANGE_CASES, ids=lambda x: str(x))
def test_run_refuses(cli, sets, key):
    check(cli, lambda: dembound.run(**keywords(sets)), with_sets("run", sets), key)


@pytest.mark.parametrize("sets,key", RANGE_CASES, ids=lambda x: str(x))
def test_exact_refuses(cli, sets, key):
    check(cli, lambda: dembound.exact(**keywords(sets)), with_sets("exact", sets), key)


@pytest.mark.parametrize("sets,key", RANGE_CASES[:4], ids=lambda x: str(x))
def test_dict_scenario_refuses(cli, sets, key):
    # The same keys given as a nested dict.
    scenario: dict = {}
    for k, v in keywords(sets).items():
        section, name = k.split("__")
        scenario.setdefault(section, {})[name] = v
    check(cli, lambda: dembound.run(scenario), with_sets("run", sets), key)


# tests/cli_bad_inputs.rs other_subcommands_refuse_what_run_refuses: (the
# Python call, the CLI arguments, the key).
OTHER_CASES = [
    (lambda: dembound.recommend(r=1e-300, zeta=INF, integration__stepping="fixed"),
     ["recommend", "--json", "--r", "1e-300", "--zeta", "inf", "--set", "integration.stepping=fixed"],
     "radius_ratio"),
    (lambda: dembound.sweep(r="lin:1:2:100000", zeta="lin:1:2:100000"),
     ["sweep", "--json", "--r", "lin:1:2:100000", "--zeta", "lin:1:2:100000"], "--r"),
    (lambda: dembound.sweep(r="lin:1:2:1000", zeta="lin:1:2:1000"),
     ["sweep", "--json", "--r", "lin:1:2:1000", "--zeta", "lin:1:2:1000"], "--zeta"),
    (lambda: dembound.sweep(r=1, zeta=1, vary={"motion.gap": "lin:0.001:0.002:100000",
                                               "motion.velocity": "lin:-1:0:100000"}),
     ["sweep", "--json", "--r", "1", "--zeta", "1", "--vary", "motion.gap=lin:0.001:0.002:100000",
      "--vary", "motion.velocity=lin:-1:0:100000"], "--vary"),
    (lambda: dembound.sweep(r=[1, 10], zeta=INF, integration__eta=1),
     ["sweep", "--json", "--r", "1,10", "--zeta", "inf", "--set", "integration.eta=1"], "integration.eta"),
    (lambda: dembound.sweep(r=[1, 10], zeta=INF, integration__dt=1e-4),
     ["sweep", "--json", "--r", "1,10", "--zeta", "inf", "--set", "integration.dt=0.0001"], "integration.dt"),
    (lambda: dembound.sweep(r=[1, 10], zeta=INF, motion__gap=1e-15),
     ["sweep", "--json", "--r", "1,10", "--zeta", "inf", "--set", "motion.gap=1e-15"], "motion.gap"),
]


@pytest.mark.parametrize("call,args,key", OTHER_CASES, ids=lambda x: str(x) if isinstance(x, str) else None)
def test_other_commands_refuse(cli, call, args, key):
    check(cli, call, args, key)


def test_unknown_key_and_malformed_values():
    with pytest.raises(ValueError, match="particle.radiu"):
        dembound.run(particle__radiu=1e-3)
    with pytest.raises(ValueError, match="particle.radius"):
        dembound.run(particle__radius="big")
    with pytest.raises(ValueError, match="--r"):
        dembound.sweep(r="x", zeta=1)
    with pytest.raises(ValueError, match="scenario"):
        dembound.run(42)


def test_batch_refuses_naming_case_and_key():
    with pytest.raises(ValueError, match=r"case 1 \(boundary.radius_ratio=1e-300\).*boundary.radius_ratio"):
        dembound.batch(r=[1.0, 1e-300], zeta=100.0)
    with pytest.raises(ValueError, match="contact.law"):
        dembound.batch(contact__law=["linear"])
    with pytest.raises(ValueError, match="boundary.radius_ratio"):
        dembound.batch(r=[1.0, 2.0], zeta=[1.0, 2.0, 3.0])


def test_failures_follow_the_cli_exit_codes(cli, tmp_path):
    # A scenario file that cannot be read is bad input (exit 2): ValueError.
    assert cli(["run", "--json", "/nonexistent/scenario.toml"]).returncode == 2
    with pytest.raises(ValueError, match="/nonexistent/scenario.toml"):
        dembound.run("/nonexistent/scenario.toml")
    # A scene file that cannot be read exits 1 in the CLI: RuntimeError.
    assert cli(["scene", "--json", "/nonexistent/scene.toml"]).returncode == 1
    with pytest.raises(RuntimeError, match="/nonexistent/scene.toml"):
        dembound.Scene.from_toml("/nonexistent/scene.toml")
    # An output that cannot be written is a failed run: RuntimeError.
    from conftest import REPO

    scene = dembound.Scene.from_toml(REPO / "examples" / "scenes" / "validation.toml")
    with pytest.raises(RuntimeError, match="cannot write"):
        scene.checkpoint(tmp_path / "missing" / "dir" / "c.cbor")
