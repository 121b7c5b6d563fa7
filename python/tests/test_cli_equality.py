"""The Python results are the CLI's `--json` documents bit for bit (issue
14, must-show 1): the paper's validation case and a sweep of 100 cases,
and every other study command once. The expected values are the output of
the separate `dembound` binary, parsed by Python's json."""

from __future__ import annotations

import math

import dembound
from conftest import assert_same


def test_comparison_is_strict():
    # The comparison itself must be able to fail: one ulp, a key, a type.
    import pytest

    x = 5.24190334774658e-07
    with pytest.raises(AssertionError):
        assert_same({"a": math.nextafter(x, 1.0)}, {"a": x})
    with pytest.raises(AssertionError):
        assert_same({"a": 1.0}, {"b": 1.0})
    with pytest.raises(AssertionError):
        assert_same({"a": 1}, {"a": 1.0})


def test_validation_case_run(cli_json):
    python = dembound.run()
    assert_same(python, cli_json(["run", "--json", "--quiet"]))
    # The paper's validation case, Hertz: h_max of contact 2 is 524.19 nm
    # (exact reference 524.1905 nm; the integrator agrees to ~1e-6).
    assert abs(python["contacts"][1]["max_overlap"] / 524.1905e-9 - 1) < 1e-5


def test_validation_case_run_compare_exact(cli_json):
    assert_same(
        dembound.run(compare_exact=True),
        cli_json(["run", "--json", "--quiet", "--compare-exact"]),
    )


def test_validation_case_linear_from_dict_and_keywords(cli_json):
    expected = cli_json(["run", "--json", "--quiet", "--set", "contact.law=linear"])
    assert_same(dembound.run(contact__law="linear"), expected)
    assert_same(dembound.run({"contact": {"law": "linear"}}), expected)
    assert_same(dembound.run({"contact.law": "linear"}), expected)


def test_validation_case_from_toml_file(cli_json):
    path = "examples/validation.toml"
    import os

    from conftest import REPO

    assert_same(dembound.run(os.path.join(REPO, path)), cli_json(["run", "--json", "--quiet", path]))


def test_validation_case_exact(cli_json):
    assert_same(dembound.exact(), cli_json(["exact", "--json"]))


def test_validate_tables(cli_json):
    assert_same(dembound.validate(), cli_json(["validate", "--json", "--quiet"]))


R = [0.5, 1.0, 2.0, 5.0, 10.0, 30.0, 100.0, 1000.0, 1e4, math.inf]
ZETA = [0.1, 0.5, 1.0, 3.0, 10.0, 30.0, 100.0, 1000.0, 1e4, math.inf]


def test_sweep_of_100_cases(cli_json):
    python = dembound.sweep(r=R, zeta=ZETA)
    expected = cli_json(
        [
            "sweep",
            "--json",
            "--quiet",
            "--r",
            "0.5,1,2,5,10,30,100,1000,1e4,inf",
            "--zeta",
            "0.1,0.5,1,3,10,30,100,1000,10000,inf",
        ]
    )
    assert len(expected["cases"]) == 100
    assert_same(python, expected)


def test_sweep_laws_and_vary(cli_json):
    python = dembound.sweep(
        r="1,100", zeta=[10, math.inf], law="linear,hertz", vary={"motion.gap": [1e-3, 5e-3]}
    )
    expected = cli_json(
        ["sweep", "--json", "--quiet", "--r", "1,100", "--zeta", "10,inf", "--law", "linear,hertz",
         "--vary", "motion.gap=0.001,0.005"]
    )
    assert_same(python, expected)


def test_recommend(cli_json):
    assert_same(
        dembound.recommend(tolerance="1%", law="hertz", quantity="duration", r="inf"),
        cli_json(["recommend", "--json", "--tolerance", "1%", "--law", "hertz", "--quantity", "duration",
                  "--r", "inf"]),
    )
    assert_same(
        dembound.recommend(r=[10, 100], zeta=100),
        cli_json(["recommend", "--json", "--r", "10,100", "--zeta", "100"]),
    )


def test_restitution_target(cli_json):
    assert_same(
        dembound.restitution(target=0.8, law="tsuji", r=10, zeta=10),
        cli_json(["restitution", "--json", "--target", "0.8", "--law", "tsuji", "--r", "10", "--zeta", "10"]),
    )


def test_keys(cli_json):
    assert_same(dembound.keys(), cli_json(["keys", "--json"]))


def test_cli_warnings_are_python_warnings(cli):
    # The CLI warns on stderr for a radius above 0.1 m; Python gets the same
    # text as a UserWarning, and the same document.
    import pytest

    stderr = cli(["run", "--json", "--quiet", "--set", "particle.radius=0.2"]).stderr
    line = next(s for s in stderr.splitlines() if s.startswith("warning: "))
    with pytest.warns(UserWarning) as caught:
        dembound.run(particle__radius=0.2)
    assert line[len("warning: "):] in [str(w.message) for w in caught]
