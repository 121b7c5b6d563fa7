#!/usr/bin/env python3
"""Run a scene against a peer code over seeds with jittered initial velocities.

Per seed k (docs/export-lammps.md, "A's side walls over jittered seeds"):

1. once: `dembound export yade SCENE --set POSITIONS_SET... --out RUNS/positions`
   (only for the resolved spheres' positions and velocities, 17 digits;
   Yade is not run);
2. `jitter_velocities.py RUNS/positions AMPLITUDE k RUNS/Jk.toml`
   (with --mirror-x, then `mirror_scene.py RUNS/Jk.toml RUNS/Jk.toml`: the
   seed's mirror image in x);
3. `dembound export CODE RUNS/Jk.toml --set SET... --out RUNS/Jk`;
4. the peer run in RUNS/Jk under `nice -n 5` (LAMMPS: `lmp -in in.lammps
   -log log.lammps`; LIGGGHTS: `liggghts -in in.liggghts -log
   log.liggghts`; Yade: `yade -n -j1 -x scene.py`); its process CPU time
   (user + system, setup and output included) goes to RUNS/Jk.cpu, since
   LIGGGHTS's log has only the wall clock (`compare_seeds.py` reads it);
5. `dembound compare RUNS/Jk --json > RUNS/Jk.json`;
6. the deck's particles.dump and trajectory.txt are deleted (tens of MB
   a seed) unless --keep-dumps; walls.txt, the logs and the JSON report stay.

A scene whose spheres are drawn at random (`[particles.random]`) has
its own seed: with --seed-key KEY (e.g. particles.0.random.seed) steps 1
and 2 are left out and step 3 exports SCENE with `--set KEY=k`.

Seeds whose report exists are skipped, so an interrupted series resumes.
One seed at a time: the machine's cores are shared. Then
`compare_seeds.py RUNS/J*.json` puts the seeds together.

Usage: jittered_seeds.py --scene S.toml --code lammps --runs DIR --seeds 0:50
           [--positions-set KEY=VALUE ...] [--set KEY=VALUE ...]
           [--amplitude 1e-4] [--dembound BIN] [--keep-dumps]
           [--replace OLD NEW ...] [--compare-arg=ARG ...]
Example (scene A, LAMMPS, dembound under LAMMPS's arm):
    jittered_seeds.py --scene examples/compare/bed.toml --code lammps \\
        --set contact.torque_arm=contact_point --runs /tmp/A --seeds 0:50
"""

import argparse
import os
import resource
import shutil
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
DECK = {"lammps": "in.lammps", "liggghts": "in.liggghts", "yade": "scene.py"}
PEER = {
    "lammps": ["lmp", "-in", "in.lammps", "-log", "log.lammps"],
    "liggghts": ["liggghts", "-in", "in.liggghts", "-log", "log.liggghts"],
    "yade": ["yade", "-n", "-j1", "-x", "scene.py"],
}


def run(cmd, cwd=None, stdout=subprocess.DEVNULL):
    done = subprocess.run(cmd, cwd=cwd, stdout=stdout, stderr=subprocess.PIPE, text=True)
    if done.returncode != 0:
        sys.exit(f"`{' '.join(cmd)}` (in {cwd or '.'}) exited {done.returncode}:\n{done.stderr[-2000:]}")


def sets(pairs):
    return [a for p in pairs for a in ("--set", p)]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--scene", required=True)
    ap.add_argument("--code", choices=sorted(PEER), required=True)
    ap.add_argument("--runs", required=True, help="directory for the decks and reports")
    ap.add_argument("--seeds", default="0:12", help="FIRST:END (END excluded)")
    ap.add_argument("--amplitude", type=float, default=1e-4, help="m/s per component")
    ap.add_argument("--positions-set", action="append", default=[],
                    help="--set for the Yade export that gives the positions only")
    ap.add_argument("--set", action="append", default=[], help="--set for the peer's export")
    ap.add_argument("--dembound", default=os.environ.get("DEMBOUND_BIN", "dembound"))
    ap.add_argument("--keep-dumps", action="store_true")
    ap.add_argument("--seed-key", help="seed the scene's own random draw by this key instead of jittering")
    ap.add_argument("--replace", nargs=2, action="append", default=[], metavar=("OLD", "NEW"),
                    help="replace every OLD by NEW in the exported deck's input (in.lammps, "
                    "in.liggghts or scene.py) before the peer runs: a variant of the peer's "
                    "model that dembound's side (scene.toml) does not share; OLD must occur")
    ap.add_argument("--mirror-x", action="store_true",
                    help="run each seed's mirror image in x (mirror_scene.py on the jittered "
                    "scene): the chirality test of docs/export-yade.md")
    ap.add_argument("--compare-arg", action="append", default=[],
                    help="an argument for `dembound compare` (e.g. --compare-arg=--window-from=0.2)")
    args = ap.parse_args()
    if args.mirror_x and args.seed_key:
        sys.exit("--mirror-x mirrors the jittered scene; a scene with its own --seed-key has none")
    first, end = (int(x) for x in args.seeds.split(":"))
    os.makedirs(args.runs, exist_ok=True)
    positions = os.path.join(args.runs, "positions")
    if not args.seed_key and not os.path.isfile(os.path.join(positions, "scene.py")):
        run([args.dembound, "export", "yade", args.scene, *sets(args.positions_set),
             "--out", positions])
    for k in range(first, end):
        deck = os.path.join(args.runs, f"J{k}")
        report = deck + ".json"
        if os.path.isfile(report):
            continue
        start = time.time()
        if os.path.isdir(deck):
            shutil.rmtree(deck)  # an interrupted seed: start it again
        if args.seed_key:
            run([args.dembound, "export", args.code, args.scene, "--set", f"{args.seed_key}={k}",
                 *sets(args.set), "--out", deck])
        else:
            run([sys.executable, os.path.join(HERE, "jitter_velocities.py"), positions,
                 repr(args.amplitude), str(k), deck + ".toml"])
            if args.mirror_x:
                run([sys.executable, os.path.join(HERE, "mirror_scene.py"), deck + ".toml",
                     deck + ".toml"])
            run([args.dembound, "export", args.code, deck + ".toml", *sets(args.set),
                 "--out", deck])
        if args.replace:
            path = os.path.join(deck, DECK[args.code])
            text = open(path).read()
            for old, new in args.replace:
                if old not in text:
                    sys.exit(f"--replace: `{old}` does not occur in {path}")
                text = text.replace(old, new)
            with open(path, "w") as out:
                out.write(text)
        cpu = resource.getrusage(resource.RUSAGE_CHILDREN)
        run(["nice", "-n", "5", *PEER[args.code]], cwd=deck)
        after = resource.getrusage(resource.RUSAGE_CHILDREN)
        with open(deck + ".cpu", "w") as out:
            out.write(f"{after.ru_utime + after.ru_stime - cpu.ru_utime - cpu.ru_stime:.3f}\n")
        peer = time.time() - start
        with open(report + ".part", "w") as out:
            run(["nice", "-n", "5", args.dembound, "compare", deck, "--json", *args.compare_arg],
                stdout=out)
        os.replace(report + ".part", report)
        if not args.keep_dumps:
            # LIGGGHTS's and LAMMPS's decks also trace sphere 1 every step
            for name in ("particles.dump", "trajectory.txt"):
                dump = os.path.join(deck, name)
                if os.path.exists(dump):
                    os.remove(dump)
        print(f"seed {k}: {args.code} run {peer:.0f} s, compare {time.time() - start - peer:.0f} s "
              f"(wall clock) -> {report}", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
