#!/usr/bin/env python3
"""Hopper discharge, dembound against LIGGGHTS (issue 26, "against a peer").

Runs examples/scenes/hopper.toml (or SCENE) with `dembound scene` and,
exported with `dembound export liggghts`, with LIGGGHTS (`liggghts` on PATH),
once per seed of the random packing (`--set particles.0.random.seed=S`),
and prints the discharged mass — the mass of the spheres whose centre is
below the outlet plane z = 0 — at every snapshot of both runs, per seed and
as the mean over the seeds, with the relative difference.

    python3 scripts/hopper_discharge.py [--seeds 1 2 3] [--steps N]
        [--dembound target/release/dembound] [--scene SCENE] [--keep DIR]

dembound's positions come from its VTK snapshots (`output.every`),
LIGGGHTS's from the deck's particles.dump (the same cadence). Both runs
start from the same spheres; the flow is chaotic, so single runs part
within a few collisions and only the statistics over seeds compare.
Standard library only (Python ≥ 3.11 for tomllib).
"""

import argparse
import base64
import math
import re
import struct
import subprocess
import sys
import tempfile
import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
OUTLET_Z = 0.0  # m: the outlet plane of make_hopper.py's hopper


def vtp_arrays(path):
    """{name: list of floats/ints} of the binary DataArrays of a .vtp."""
    text = Path(path).read_text()
    out = {}
    for m in re.finditer(
        r'<DataArray type="(\w+)" Name="(\w+)"[^>]*format="binary">([^<]*)</DataArray>', text
    ):
        kind, name, data = m.groups()
        raw = base64.b64decode(data)
        (n,) = struct.unpack("<Q", raw[:8])
        fmt = {"Float64": "d", "UInt64": "Q", "Int64": "q", "Int32": "i", "UInt32": "I"}.get(kind)
        if fmt is None:
            continue
        size = struct.calcsize(fmt)
        out[name] = list(struct.unpack(f"<{n // size}{fmt}", raw[8 : 8 + n]))
    return out


def sphere_mass(radius, density):
    return density * 4.0 / 3.0 * math.pi * radius**3


def dembound_discharge(run_dir, densities):
    """{step: discharged mass (kg)} from dembound's snapshots."""
    out = {}
    for vtp in sorted(Path(run_dir).glob("snapshot_*.vtp")):
        a = vtp_arrays(vtp)
        step = a["STEP"][0]
        pos, radius = a["position"], a["radius"]
        material = a.get("material", [0] * len(radius))
        out[step] = sum(
            sphere_mass(radius[i], densities[int(material[i])])
            for i in range(len(radius))
            if pos[3 * i + 2] < OUTLET_Z
        )
    return out


def liggghts_discharge(deck_dir, densities):
    """{step: discharged mass (kg)} from the deck's particles.dump (atom type k = material k)."""
    out = {}
    text = (Path(deck_dir) / "particles.dump").read_text()
    for block in text.split("ITEM: TIMESTEP\n")[1:]:
        lines = block.splitlines()
        step = int(lines[0])
        start = next(i for i, l in enumerate(lines) if l.startswith("ITEM: ATOMS")) + 1
        mass = 0.0
        for line in lines[start:]:
            f = line.split()
            if float(f[5]) < OUTLET_Z:
                mass += sphere_mass(float(f[2]), densities[int(f[1]) - 1])
        out[step] = mass
    return out


def run(cmd, cwd=None):
    done = subprocess.run(cmd, cwd=cwd, capture_output=True, text=True)
    if done.returncode != 0:
        sys.exit(f"failed: {' '.join(map(str, cmd))}\n{done.stderr}{done.stdout[-2000:]}")


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--scene", default=str(ROOT / "examples/scenes/hopper.toml"))
    p.add_argument("--dembound", default=str(ROOT / "target/release/dembound"))
    p.add_argument("--seeds", type=int, nargs="+", default=[1, 2, 3])
    p.add_argument("--steps", type=int, help="integration.steps (default: the scene's)")
    p.add_argument("--keep", help="write the runs under this directory and keep them")
    args = p.parse_args()
    scene = tomllib.loads(Path(args.scene).read_text())
    densities = [m["density"] for m in scene["material"]]
    dt = scene["integration"]["dt"]
    work = Path(args.keep) if args.keep else Path(tempfile.mkdtemp(prefix="hopper_"))
    rows = {}
    for seed in args.seeds:
        sets = ["--set", f"particles.0.random.seed={seed}"]
        if args.steps:
            sets += ["--set", f"integration.steps={args.steps}"]
        run_dir, deck = work / f"dembound_{seed}", work / f"liggghts_{seed}"
        run([args.dembound, "scene", args.scene, *sets, "--quiet", "--out", run_dir])
        run([args.dembound, "export", "liggghts", args.scene, *sets, "--out", deck])
        run(["liggghts", "-in", "in.liggghts", "-log", "log.liggghts"], cwd=deck)
        d, l = dembound_discharge(run_dir, densities), liggghts_discharge(deck, densities)
        for step in sorted(set(d) & set(l)):
            rows.setdefault(step, []).append((d[step], l[step]))
            print(
                f"seed {seed}  t = {step * dt:.3f} s: discharged dembound {1e3 * d[step]:.3f} g, "
                f"LIGGGHTS {1e3 * l[step]:.3f} g",
                flush=True,
            )
    print(f"\nmean over seeds {args.seeds} (mass of spheres with centre below z = {OUTLET_Z} m):")
    print("| t (s) | dembound (g) | LIGGGHTS (g) | LIGGGHTS/dembound − 1 |")
    print("|---|---|---|---|")
    for step, pairs in sorted(rows.items()):
        md = sum(a for a, _ in pairs) / len(pairs)
        ml = sum(b for _, b in pairs) / len(pairs)
        rel = f"{ml / md - 1:+.2%}" if md > 0 else "—"
        print(f"| {step * dt:.3f} | {1e3 * md:.3f} | {1e3 * ml:.3f} | {rel} |")
    if not args.keep:
        print(f"(runs in {work})")


if __name__ == "__main__":
    main()
