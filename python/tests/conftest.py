"""Shared helpers: the `dembound` binary the Python results are compared
with, and a bit-for-bit comparison of JSON-like values."""

from __future__ import annotations

import json
import math
import os
import struct
import subprocess
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]


def binary() -> Path:
    """The CLI: $DEMBOUND_BIN, or the workspace's release build (built here
    if missing)."""
    given = os.environ.get("DEMBOUND_BIN")
    if given:
        return Path(given)
    path = REPO / "target" / "release" / "dembound"
    if not path.exists():
        subprocess.run(
            ["cargo", "build", "--release", "--bin", "dembound"], cwd=REPO, check=True
        )
    return path


@pytest.fixture(scope="session")
def cli():
    """cli(args) -> CompletedProcess of the `dembound` binary (text)."""
    exe = binary()

    def call(args: list[str]) -> subprocess.CompletedProcess:
        return subprocess.run(
            [str(exe), *args], cwd=REPO, capture_output=True, text=True, timeout=600
        )

    return call


@pytest.fixture(scope="session")
def cli_json(cli):
    """cli_json(args) -> the parsed stdout of `dembound ARGS` (which must
    exit 0). Python's json reads each number as the nearest double, and the
    CLI prints the shortest text that reads back as its double, so the
    parsed floats are the CLI's doubles exactly."""

    def call(args: list[str]):
        out = cli(args)
        assert out.returncode == 0, f"dembound {args} exited {out.returncode}: {out.stderr}"
        return json.loads(out.stdout)

    return call


def assert_same(python, cli, path: str = "$") -> None:
    """Equal structure, key names, types and values, floats bit for bit."""
    if isinstance(cli, float) or isinstance(python, float):
        assert isinstance(python, float) and isinstance(cli, float), (
            f"{path}: {python!r} ({type(python).__name__}) vs CLI {cli!r} ({type(cli).__name__})"
        )
        assert struct.pack("<d", python) == struct.pack("<d", cli), (
            f"{path}: {python!r} vs CLI {cli!r} (differ by {python - cli!r})"
            if not (math.isnan(python) or math.isnan(cli))
            else f"{path}: {python!r} vs CLI {cli!r}"
        )
    elif isinstance(cli, dict):
        assert isinstance(python, dict), f"{path}: {type(python).__name__} vs CLI object"
        assert sorted(python) == sorted(cli), f"{path}: keys {sorted(python)} vs CLI {sorted(cli)}"
        for k in cli:
            assert_same(python[k], cli[k], f"{path}.{k}")
    elif isinstance(cli, list):
        assert isinstance(python, list), f"{path}: {type(python).__name__} vs CLI array"
        assert len(python) == len(cli), f"{path}: {len(python)} items vs CLI {len(cli)}"
        for i, (p, c) in enumerate(zip(python, cli)):
            assert_same(p, c, f"{path}[{i}]")
    else:
        assert type(python) is type(cli) and python == cli, f"{path}: {python!r} vs CLI {cli!r}"
