"""examples/scenes/plot_piston.py (issue 27): the oedometer example's
figure from a `dembound scene examples/scenes/piston.toml --out` run; a
missing run or column exits 2 naming it."""

from __future__ import annotations

import subprocess
import sys

from conftest import REPO

SCRIPT = REPO / "examples" / "scenes" / "plot_piston.py"
PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"


def plot(*args):
    return subprocess.run([sys.executable, str(SCRIPT), *map(str, args)], capture_output=True, text=True)


def test_a_short_piston_run_plots_to_a_png(cli, tmp_path):
    run = tmp_path / "run"
    done = cli(["scene", "examples/scenes/piston.toml", "--set", "integration.duration=0.002",
                "--set", "output.every=500", "--set", "output.series_every=50", "-q", "--out", str(run)])
    assert done.returncode == 0, done.stderr
    out = tmp_path / "piston.png"
    p = plot(run, out)
    assert p.returncode == 0, p.stderr
    assert out.read_bytes().startswith(PNG_SIGNATURE)
    # Wall 4 is a fixed side wall: it has no position column.
    p = plot(run, tmp_path / "x.png", "--lid", 4)
    assert p.returncode == 2 and "wall4_position_z_m" in p.stderr, p.stderr
    p = plot(tmp_path / "nothing", tmp_path / "y.png")
    assert p.returncode == 2 and "series.csv" in p.stderr, p.stderr
