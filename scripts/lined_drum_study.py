#!/usr/bin/env python3
"""The paper's question on a moving wall (issue 27): is a drum lined with
fixed boundary spheres the same drum? examples/scenes/lined_drum.toml with
the lining of radius ratio r = R_b/R_m = 0.5, 1, 2 (ζ = E_b/E_m = 10),
against the same drum with a smooth (μ = 0) and a frictional (μ = 0.5)
STL mantle.

    lined_drum_study.py [--fr 1e-2] [--steps 120000] [--from 0.62]
                        [--series-every 1000] [--snapshot-every 10000]
                        [--keep DIR] [--png-dir DIR] [--threads 1]
                        [--cases stl-0.5 stl-0 r0.5 r1 r2]

Every case has the same 1,904 free spheres, the same end caps
(lined_drum_caps.stl, material "liner": E = 1e7 Pa, μ = 0.5) and the same
motion (ω = √(Fr g/R) about +y, R = 28 mm); only the mantle differs:
- stl-0.5: the 96-sided STL mantle (lined_drum_mantle.stl), "liner", μ = 0.5;
- stl-0: the same, frictionless (`friction = 0.0` on that wall);
- rX: no mantle wall; the lining lined_drum_rX.csv (make_lined_drum.py) as
  a `[[particles]]` group with `fixed = true` and the drum's `motion`,
  material "liner" (its μ = 0.5 from `contact.friction`).

Measured per case: the dynamic angle of repose (scripts/drum_angle.py:
the mid-length slab's free surface averaged over the snapshots at
t ≥ FROM, a line over |x| < R/2; fixed spheres left out) and the torque
the spheres put on the drum about its axis, mantle and caps together,
averaged over the series rows at t ≥ FROM (sign: −τ_y, the torque a motor
must supply against the bed, N m), with its check from the drum's work:
the power dW/dt over the window divided by ω. Printed: a markdown table.
"""

import argparse
import csv
import json
import math
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
SCENES = ROOT / "examples/scenes"
sys.path.insert(0, str(ROOT / "scripts"))
import drum_angle  # noqa: E402
import numpy as np  # noqa: E402

G = 9.81  # m/s²
RADIUS = 0.028  # m
CASES = ["stl-0.5", "stl-0", "r0.5", "r1", "r2"]


def scene_text(case, omega, steps, series_every, snapshot_every):
    """The scene of `case` (module doc) from lined_drum.toml, paths absolute."""
    text = (SCENES / "lined_drum.toml").read_text()
    start = text.index("# The lining: fixed spheres")
    end = text.index("[[wall]]", start)
    lining = text[start:end]
    if case.startswith("stl"):
        mu = "0.0" if case == "stl-0" else "0.5"
        text = text.replace(lining, "")
        text += (
            "\n[[wall]]\n"
            f'mesh = {{ file = "{SCENES / "lined_drum_mantle.stl"}" }}\n'
            'material = "liner"\n'
            f"friction = {mu}\n"
            f"motion = {{ angular_velocity = [0.0, {omega!r}, 0.0], center = [0.0, 0.0, 0.0] }}\n"
        )
    else:
        ratio = case[1:]
        text = text.replace(
            'csv = "lined_drum_r1.csv"', f'csv = "{SCENES / f"lined_drum_r{ratio}.csv"}"'
        )
    text = text.replace('file = "lined_drum_caps.stl"', f'file = "{SCENES / "lined_drum_caps.stl"}"')
    text = text.replace("[0.0, 1.8718, 0.0]", f"[0.0, {omega!r}, 0.0]")
    text = text.replace("steps = 120000", f"steps = {steps}")
    text = text.replace("series_every = 10000", f"series_every = {series_every}")
    text = text.replace("every = 10000 ", f"every = {snapshot_every} ")
    return text


def torque_and_power(series_path, t_from, omega):
    """(mean −τ_y of every wall and moving group, N m; dW/dt / ω, N m)."""
    with open(series_path) as f:
        rows = list(csv.DictReader(f))
    keys = [k for k in rows[0] if k.endswith("_torque_y_N_m")]
    used = [r for r in rows if float(r["time_s"]) >= t_from - 1e-12]
    torque = -sum(sum(float(r[k]) for k in keys) for r in used) / len(used)
    t0, t1 = float(used[0]["time_s"]), float(used[-1]["time_s"])
    w0, w1 = float(used[0]["work_by_walls_J"]), float(used[-1]["work_by_walls_J"])
    return torque, (w1 - w0) / (t1 - t0) / omega


def surfaces(path, profiles, fr, t_from):
    """Every case's time-averaged free surface and fitted line in one picture."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    names = {"stl-0.5": "STL mantle, μ = 0.5", "stl-0": "STL mantle, μ = 0 (smooth)",
             "r0.5": "lining r = 0.5", "r1": "lining r = 1", "r2": "lining r = 2"}
    fig, ax = plt.subplots(figsize=(7.0, 5.0))
    for k, (case, centres, mean, icpt, b, angle) in enumerate(profiles):
        ok = np.isfinite(mean)
        style = "-" if case.startswith("stl") else "--"
        ax.plot(1e3 * centres[ok], 1e3 * mean[ok], "o", ms=3, color=f"C{k}")
        xs = np.array([-0.5 * RADIUS, 0.5 * RADIUS])
        ax.plot(1e3 * xs, 1e3 * (icpt + b * xs), style, color=f"C{k}",
                label=f"{names.get(case, case)}: {angle:.1f}°")
    t = np.linspace(math.pi, 2 * math.pi, 200)
    ax.plot(1e3 * RADIUS * np.cos(t), 1e3 * RADIUS * np.sin(t), "k-", lw=1, label="drum, R = 28 mm")
    ax.set_xlabel("x (mm)")
    ax.set_ylabel("mean free-surface height z (mm)")
    ax.set_title(f"lined drum, Fr = {fr:g}: surfaces averaged over t ≥ {t_from} s")
    ax.legend(fontsize=8)
    ax.set_aspect("equal")
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--fr", type=float, default=1e-2)
    p.add_argument("--steps", type=int, default=120000)
    p.add_argument("--from", dest="t_from", type=float, default=0.62)
    p.add_argument("--series-every", type=int, default=1000)
    p.add_argument("--snapshot-every", type=int, default=10000)
    p.add_argument("--dembound", default=str(ROOT / "target/release/dembound"))
    p.add_argument("--threads", type=int, default=1)
    p.add_argument("--keep")
    p.add_argument("--png-dir")
    p.add_argument("--cases", nargs="+", default=CASES, choices=CASES)
    p.add_argument("--reuse", action="store_true",
                   help="measure the runs already under --keep instead of running them")
    a = p.parse_args()
    subprocess.run([sys.executable, str(SCENES / "make_lined_drum.py")], check=True,
                   capture_output=True)
    omega = math.sqrt(a.fr * G / RADIUS)
    base = Path(a.keep) if a.keep else Path(tempfile.mkdtemp(prefix="lined-drum-"))
    base.mkdir(parents=True, exist_ok=True)
    results = []
    profiles = []
    for case in a.cases:
        d = base / case
        d.mkdir(exist_ok=True)
        t0 = time.monotonic()
        if a.reuse:
            kept = d / "summary.json"
            summary = json.loads(kept.read_text()) if kept.exists() else {}
        else:
            (d / "scene.toml").write_text(
                scene_text(case, omega, a.steps, a.series_every, a.snapshot_every))
            done = subprocess.run(
                [a.dembound, "scene", str(d / "scene.toml"), "--threads", str(a.threads),
                 "--json", "-q", "--out", str(d / "run")],
                capture_output=True, text=True)
            if done.returncode != 0:
                sys.exit(f"{case}: {done.stderr[-3000:]}")
            (d / "summary.json").write_text(done.stdout)
            summary = json.loads(done.stdout)
        seconds = time.monotonic() - t0
        frames = drum_angle.dembound_frames(d / "run")
        angle, b, icpt, centres, mean, fit, used = drum_angle.measure(
            frames, a.t_from, drum_angle.DRUM_RADIUS, drum_angle.DRUM_LENGTH)
        spread = drum_angle.frame_angles(used, drum_angle.DRUM_RADIUS, drum_angle.DRUM_LENGTH)
        torque, from_work = torque_and_power(d / "run" / "series.csv", a.t_from, omega)
        if a.png_dir:
            Path(a.png_dir).mkdir(parents=True, exist_ok=True)
            drum_angle.picture(Path(a.png_dir) / f"lined_drum_{case}.png", frames[-1],
                               drum_angle.DRUM_RADIUS, drum_angle.DRUM_LENGTH, centres, mean,
                               fit, icpt, b, angle, f"{case}, Fr = {a.fr:g}, t = {frames[-1][0]:.2f} s")
        profiles.append((case, centres, mean, icpt, b, angle))
        r = {"case": case, "angle_deg": angle, "frame_spread_deg": float(spread.std()),
             "torque_N_m": torque, "torque_from_work_N_m": from_work, "seconds": seconds,
             "drift_relative": summary.get("energy_balance", {}).get("drift_relative"),
             "snapshots": len(used)}
        results.append(r)
        print(json.dumps(r), flush=True)
    if a.png_dir:
        surfaces(Path(a.png_dir) / "lined_drum_surfaces.png", profiles, a.fr, a.t_from)
    ref = {r["case"]: r for r in results}
    wall = ref.get("stl-0.5")
    print(f"\nFr = {a.fr:g}, ω = {omega:.4f} rad/s, {a.steps} steps of 10 µs, window t ≥ {a.t_from} s\n")
    print("| mantle | angle (°) | − frictional STL | each snapshot's spread (°) | torque −τ_y (N m) | from dW/dt ÷ ω (N m) | within 1° of the wall |")
    print("|---|---|---|---|---|---|---|")
    for r in results:
        diff = r["angle_deg"] - wall["angle_deg"] if wall else float("nan")
        ok = "—" if r["case"].startswith("stl") else ("yes" if abs(diff) <= 1.0 else "no")
        print(f"| {r['case']} | {r['angle_deg']:.2f} | {diff:+.2f} | {r['frame_spread_deg']:.2f} | "
              f"{r['torque_N_m']:.4e} | {r['torque_from_work_N_m']:.4e} | {ok} |")


if __name__ == "__main__":
    main()
