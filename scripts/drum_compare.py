#!/usr/bin/env python3
"""The rotating drum, dembound against LIGGGHTS, at several Froude numbers
(issue 27, "Drum against a peer and against the literature").

    drum_compare.py [--fr 1e-2 3e-3 1e-3 1e-4] [--keep DIR] [--threads 1]
                    [--dembound target/release/dembound] [--png-dir DIR]
                    [--quick] [--set KEY=VALUE ...] [--label NAME] [--window S]

For each Froude number Fr = ω² R/g (R = 28 mm, g = 9.81 m/s²) it runs
examples/scenes/drum.toml with the drum turning at ω = √(Fr g/R) about +y
(`--set wall.0.motion.angular_velocity=[0, ω, 0]`) with `dembound scene`
and, exported with `dembound export liggghts`, with LIGGGHTS 3.8 on one
process (`liggghts` on PATH; the deck's per-step `fix print` of sphere 1
is dropped so that both codes write the same snapshots only). The run
lasts until the drum has turned 0.6 rad (beyond the angle of repose, from
the settled lattice block) plus 0.3 s, then averages over 0.5 s more (6
snapshots; at Fr = 1e-3 the angle is steady from 0.5 s on, turned 0.3 rad); the dynamic angle of repose of each code is measured by
scripts/drum_angle.py over that window (its method: the top-most sphere
per x bin of the mid-length slab, time-averaged, a line fitted in the flat
middle |x| < R/2). Printed: a markdown table of Fr, ω, steps, both angles,
their difference, the regime against Mellmann's (2001) Froude map, and
both codes' wall time per step (s) on this machine.

--quick: 1 Froude number (1e-2) and a short window, for a smoke test.
--set KEY=VALUE (repeatable) is passed to both codes' scene (e.g. a shifted
lattice origin, a second start of the same drum, to separate the run-to-run
spread from the codes' difference); --label NAME names those runs'
directories and pictures (fr<Fr>_<NAME>) so they sit beside the first.
Needs numpy (and matplotlib for --png-dir).
"""

import argparse
import json
import math
import re
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "scripts"))
import drum_angle  # noqa: E402
import numpy as np  # noqa: E402

G = 9.81  # m/s²
DT = 1.0e-5  # s, drum.toml's


def mellmann(fr):
    """The regime of a drum at Froude number Fr by Mellmann's (2001) map
    (Powder Technol. 118, 251–270: slumping 1e-5 < Fr < 1e-3, rolling
    1e-4 < Fr < 1e-2, cascading 1e-3 < Fr < 1e-1, cataracting
    0.1 < Fr < 1, centrifuging Fr ≥ 1; the bands overlap, the overlaps
    named here by the band the issue quotes, rolling 1e-4 to 1e-2)."""
    if fr >= 1.0:
        return "centrifuging"
    if fr >= 0.1:
        return "cataracting"
    if 1e-4 <= fr <= 1e-2:
        return "rolling"
    if fr > 1e-2:
        return "cascading"
    return "slumping"


def run(cmd, cwd=None):
    t0 = time.monotonic()
    done = subprocess.run(cmd, cwd=cwd, capture_output=True, text=True)
    if done.returncode != 0:
        sys.exit(f"failed: {' '.join(map(str, cmd))}\n{done.stderr[-2000:]}{done.stdout[-2000:]}")
    return done, time.monotonic() - t0


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--fr", type=float, nargs="+", default=[1e-2, 3e-3, 1e-3, 1e-4])
    p.add_argument("--scene", default=str(ROOT / "examples/scenes/drum.toml"))
    p.add_argument("--dembound", default=str(ROOT / "target/release/dembound"))
    p.add_argument("--threads", type=int, default=1)
    p.add_argument("--keep", help="write the runs under this directory and keep them")
    p.add_argument("--png-dir", help="write each run's picture here")
    p.add_argument("--quick", action="store_true")
    p.add_argument("--set", dest="extra_sets", action="append", default=[], metavar="KEY=VALUE",
                   help="a scene override for both codes (repeatable)")
    p.add_argument("--label", help="suffix of the runs' names (with --set)")
    p.add_argument("--window", type=float, default=0.5,
                   help="averaging window after the start-up, s (default 0.5; a slumping bed "
                   "needs several avalanche cycles)")
    p.add_argument("--only", choices=["dembound", "liggghts"],
                   help="run this code only (another call with --keep DIR runs the other and "
                   "measures both)")
    args = p.parse_args()
    if args.quick:
        args.fr = [1e-2]
    work = Path(args.keep) if args.keep else Path(tempfile.mkdtemp(prefix="drum_"))
    rows = []
    for fr in args.fr:
        omega = math.sqrt(fr * G / drum_angle.DRUM_RADIUS)
        t_from = 0.6 / omega + 0.3
        window = 0.1 if args.quick else args.window
        steps = int(math.ceil((t_from + window) / DT / 10000.0)) * 10000
        sets = [
            "--set", f"wall.0.motion.angular_velocity=[0.0, {omega!r}, 0.0]",
            "--set", f"integration.steps={steps}",
        ]
        for extra in args.extra_sets:
            sets += ["--set", extra]
        tag = f"fr{fr:g}" + (f"_{args.label}" if args.label else "")
        run_dir, deck = work / f"dembound_{tag}", work / f"liggghts_{tag}"
        if args.only != "liggghts" and not (run_dir / "snapshots.pvd").exists():
            done, _ = run([args.dembound, "scene", args.scene, *sets, "--threads",
                           str(args.threads), "--json", "--quiet", "--out", run_dir])
            (work / f"dembound_{tag}.json").write_text(done.stdout)
        done_l = (deck / "log.liggghts").exists() and "Loop time" in (deck / "log.liggghts").read_text()
        if args.only != "dembound" and not done_l:
            run([args.dembound, "export", "liggghts", args.scene, *sets, "--out", deck])
            deck_in = deck / "in.liggghts"
            deck_in.write_text("".join(
                l for l in deck_in.read_text().splitlines(keepends=True)
                if not l.startswith(("fix          trajectory", "variable     "))
            ))
            run(["liggghts", "-in", "in.liggghts", "-log", "log.liggghts"], cwd=deck)
        if args.only:
            continue
        d_json = json.loads((work / f"dembound_{tag}.json").read_text())
        d_step = d_json["wall_clock"] / d_json["steps_this_run"]
        loop = re.search(r"Loop time of ([0-9.eE+-]+) on (\d+) procs for (\d+) steps",
                         (deck / "log.liggghts").read_text())
        l_step = float(loop.group(1)) / int(loop.group(3))
        res = {}
        for code, frames in (("dembound", drum_angle.dembound_frames(run_dir)),
                             ("LIGGGHTS", drum_angle.liggghts_frames(deck))):
            angle, b, a, centres, mean, fit, used = drum_angle.measure(
                frames, t_from, drum_angle.DRUM_RADIUS, drum_angle.DRUM_LENGTH)
            per_frame = drum_angle.frame_angles(used, drum_angle.DRUM_RADIUS,
                                                drum_angle.DRUM_LENGTH)
            res[code] = angle
            res[code + " std"] = float(np.std(per_frame))
            if args.png_dir:
                Path(args.png_dir).mkdir(parents=True, exist_ok=True)
                drum_angle.picture(
                    Path(args.png_dir) / f"drum_{tag}_{code.lower()}.png", used[-1],
                    drum_angle.DRUM_RADIUS, drum_angle.DRUM_LENGTH, centres, mean, fit, a, b,
                    angle, f"{code}, Fr = {fr:g} (ω = {omega:.3f} rad/s), t = {used[-1][0]:.2f} s")
        rows.append((fr, omega, steps, t_from, res, d_step, l_step))
        print(f"Fr = {fr:g}: dembound {res['dembound']:.2f}° (per-snapshot spread "
              f"{res['dembound std']:.2f}°), LIGGGHTS {res['LIGGGHTS']:.2f}° "
              f"({res['LIGGGHTS std']:.2f}°)", flush=True)
    print("\n| Fr | ω (rad/s) | steps | window (s) | dembound (°) | LIGGGHTS (°) | difference (°) "
          "| per-snapshot spread d/L (°) | Mellmann 2001 | dembound s/step | LIGGGHTS s/step |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for fr, omega, steps, t_from, res, d_step, l_step in rows:
        a_d, a_l = res["dembound"], res["LIGGGHTS"]
        print(f"| {fr:g} | {omega:.4f} | {steps} | {t_from:.2f}–{steps * DT:.2f} | {a_d:.2f} | "
              f"{a_l:.2f} | {a_d - a_l:+.2f} | {res['dembound std']:.2f}/{res['LIGGGHTS std']:.2f} "
              f"| {mellmann(fr)} | {d_step:.3e} | {l_step:.3e} |")
    if not args.keep:
        print(f"(runs in {work})")


if __name__ == "__main__":
    main()
