#!/usr/bin/env python3
"""Run dembound's side of stored scene-deck seeds again under other settings.

`jittered_seeds.py` leaves, per seed k, RUNS/Jk.toml (the jittered scene),
the deck RUNS/Jk (the peer's log, walls.txt, walls_mean.txt; the dump is
deleted) and the report RUNS/Jk.json of `dembound compare`. This script
puts dembound's side of each seed under `--set KEY=VALUE` (e.g.
contact.torque_arm=overlap_middle) beside the same peer run, without
running the peer again:

1. `dembound export CODE RUNS/Jk.toml --set SET... --out OUT/Jk`; the new
   deck's input (in.liggghts, in.lammps) must be the stored deck's byte for
   byte but for its comment lines (the header's notes, which name e.g. the
   lever arm dembound's side runs; the peer's run is then this deck's),
   else the seed stops here;
2. the stored peer outputs are copied in (log, walls.txt, walls_mean.txt),
   and a stand-in particles.dump is written: every sphere of the deck's
   data file at its initial place, at the steps of the stored report's
   rows. `compare` needs a dump to run, but dembound's side (its run, its
   wall forces, its profiles) does not depend on it, nor do the peer's
   wall forces (walls_mean.txt / walls.txt);
3. `dembound compare OUT/Jk --json`, then the stand-in dump is deleted;
4. OUT/Jk.json is the stored report with dembound's side replaced by the
   new run's (each quantity's `dembound` series and `dembound_window`, the
   profiles' `dembound` bins, `dembound_speed`); the peer's side stays the
   stored one (from the real dump). Every field that mixes the two sides
   (relative differences, divergence, verdicts, the profile's largest
   difference) is set to null, and a note says what was done. Where the
   stored deck still holds the peer's particles.dump (jittered_seeds.py
   --keep-dumps), compare reads it instead of a stand-in and OUT/Jk.json
   is compare's own report, both sides from this run.
   The peer's wall series of the new run must equal the stored report's
   (the same file read the same way), else the seed stops.

Check first that the route reproduces the stored reports: with --set
giving the stored scene.toml's own values (or none), OUT/Jk.json's
dembound side must equal RUNS/Jk.json's exactly (--check prints, per
seed, whether it does, and exits 1 if not). `compare_seeds.py
OUT/J*.json` then reads the new reports as any others, and
`compare_seeds.py --versus-dir RUNS --versus-side dembound` pairs the two
dembound runs of each seed.

Usage: rerun_dembound_side.py --runs RUNS --out OUT --code liggghts
           [--set KEY=VALUE ...] [--seeds 0:90] [--dembound BIN] [--check]
"""

import argparse
import copy
import glob
import json
import os
import re
import shutil
import subprocess
import sys

DECK = {"lammps": ("in.lammps", "log.lammps", "particles.data"),
        "liggghts": ("in.liggghts", "log.liggghts", "particles.data")}
PEER_FILES = ("walls.txt", "walls_mean.txt")
MIXED = ("relative_difference", "divergence", "window_relative_difference", "verdict")


def fail(message, code=2):
    print(f"rerun_dembound_side.py: {message}", file=sys.stderr)
    sys.exit(code)


def run(cmd, stdout=subprocess.DEVNULL):
    done = subprocess.run(cmd, stdout=stdout, stderr=subprocess.PIPE, text=True)
    if done.returncode != 0:
        fail(f"`{' '.join(cmd)}` exited {done.returncode}:\n{done.stderr[-2000:]}", 1)


def data_atoms(path):
    """(id, type, radius, x, y, z) of every atom of a LAMMPS/LIGGGHTS data
    file of atom_style granular (`id type diameter density x y z`)."""
    atoms, inside = [], False
    for line in open(path):
        words = line.split()
        if not words:
            continue
        if words[0] in ("Atoms", "Velocities"):
            inside = words[0] == "Atoms"
            continue
        if inside and len(words) >= 7 and re.fullmatch(r"\d+", words[0]):
            atoms.append((int(words[0]), int(words[1]), float(words[2]) / 2, *words[4:7]))
    if not atoms:
        fail(f"{path}: no `Atoms` section of atom_style granular (id type diameter density x y z)")
    return atoms


def commands(path):
    """The deck's input without its comment lines (those starting with #,
    which the header's notes are: they say which of dembound's settings
    the deck was written under, e.g. the lever arm, and do not change the
    peer's run), byte for byte otherwise."""
    return [line for line in open(path, "rb").read().split(b"\n")
            if not line.lstrip().startswith(b"#")]


def stand_in_dump(path, atoms, steps):
    with open(path, "w") as out:
        body = "".join(f"{a[0]} {a[1]} {a[2]!r} {a[3]} {a[4]} {a[5]} 0 0 0 0 0 0\n" for a in atoms)
        for step in steps:
            out.write(f"ITEM: TIMESTEP\n{step}\nITEM: NUMBER OF ATOMS\n{len(atoms)}\n"
                      "ITEM: BOX BOUNDS mm mm mm\n0 1\n0 1\n0 1\n"
                      "ITEM: ATOMS id type radius x y z vx vy vz omegax omegay omegaz\n")
            out.write(body)


def row_steps(report):
    """The steps of the stored report's rows (its first quantity's times
    over dt; the state quantity stops at the divergence, so the longest)."""
    times = max((q["time"] for q in report["quantities"]), key=len)
    return [round(t / report["dt"]) for t in times]


def splice(stored, new, settings, binary):
    """The stored report with dembound's side from `new`."""
    out = copy.deepcopy(stored)
    by_name = {q["name"]: q for q in new["quantities"]}
    for q in out["quantities"]:
        n = by_name.get(q["name"])
        if n is None:
            fail(f"the new report has no quantity `{q['name']}`", 1)
        if not q["name"].startswith("state"):  # the state's series are only its rows' times
            q["dembound"] = n["dembound"]
            q["dembound_window"] = n["dembound_window"]
        for key in MIXED:
            q[key] = None
    profiles = {p["name"]: p for p in new.get("profiles", [])}
    for p in out.get("profiles", []):
        p["dembound"] = profiles[p["name"]]["dembound"]
        for key in ("max_abs_difference", "at", "standard_error_there", "agree"):
            p[key] = None
    out["dembound_speed"] = new["dembound_speed"]
    out["state_end"] = None
    out["notes"] = list(stored.get("notes", [])) + [
        f"dembound's side run again ({os.path.basename(binary)}, --set {' --set '.join(settings) or '(none)'}) "
        f"by scripts/rerun_dembound_side.py against the stored {stored['code']} run: the "
        f"{stored['code']} side (from its dump, since deleted) is the stored report's; fields "
        f"mixing the two sides are null"]
    return out


def dembound_side(report):
    """Everything of dembound's side of a report, for the exact check."""
    return ([(q["name"], q["dembound"], q["dembound_window"]) for q in report["quantities"]],
            [(p["name"], p["dembound"]) for p in report.get("profiles", [])])


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--runs", required=True, help="the stored seeds (Jk.toml, Jk/, Jk.json)")
    ap.add_argument("--out", required=True, help="directory for the new decks and reports")
    ap.add_argument("--code", choices=sorted(DECK), required=True)
    ap.add_argument("--set", action="append", default=[], help="--set for dembound's export")
    ap.add_argument("--seeds", help="FIRST:END (END excluded; default every RUNS/Jk.json)")
    ap.add_argument("--dembound", default=os.environ.get("DEMBOUND_BIN", "dembound"))
    ap.add_argument("--check", action="store_true",
                    help="compare the new dembound side with the stored one; exit 1 if it differs")
    args = ap.parse_args()
    if not os.path.isdir(args.runs):
        fail(f"--runs = {args.runs}: not a directory")
    if args.seeds:
        m = re.fullmatch(r"(\d+):(\d+)", args.seeds)
        if not m or int(m[1]) >= int(m[2]):
            fail(f"--seeds = {args.seeds}: expected FIRST:END with FIRST < END, e.g. 0:90")
        seeds = [k for k in range(int(m[1]), int(m[2]))
                 if os.path.isfile(os.path.join(args.runs, f"J{k}.json"))]
    else:
        seeds = sorted(int(re.search(r"J(\d+)\.json$", p)[1])
                       for p in glob.glob(os.path.join(args.runs, "J*.json")))
    if not seeds:
        fail(f"--runs = {args.runs}: no Jk.json" + (f" for --seeds {args.seeds}" if args.seeds else ""))
    os.makedirs(args.out, exist_ok=True)
    deck_file, log_file, data_file = DECK[args.code]
    differ = 0
    for k in seeds:
        stored_deck = os.path.join(args.runs, f"J{k}")
        report = os.path.join(args.out, f"J{k}.json")
        if os.path.isfile(report) and not args.check:
            continue
        deck = os.path.join(args.out, f"J{k}")
        if os.path.isdir(deck):
            shutil.rmtree(deck)
        sets = [a for s in args.set for a in ("--set", s)]
        run([args.dembound, "export", args.code, os.path.join(args.runs, f"J{k}.toml"), *sets,
             "--out", deck])
        if commands(os.path.join(deck, deck_file)) != \
                commands(os.path.join(stored_deck, deck_file)):
            fail(f"seed {k}: the commands of the new {deck_file} differ from "
                 f"{stored_deck}/{deck_file}: the stored {args.code} run is not this deck's", 1)
        for name in (log_file, *PEER_FILES):
            if os.path.isfile(os.path.join(stored_deck, name)):
                shutil.copy2(os.path.join(stored_deck, name), deck)
        cpu = os.path.join(args.runs, f"J{k}.cpu")
        if os.path.isfile(cpu):
            shutil.copy2(cpu, os.path.join(args.out, f"J{k}.cpu"))
        stored = json.load(open(os.path.join(args.runs, f"J{k}.json")))
        dump = os.path.join(deck, "particles.dump")
        # The peer's own dump when the stored deck kept it (--keep-dumps):
        # then the new report is compare's own, both sides from this run.
        real = os.path.join(stored_deck, "particles.dump")
        if os.path.isfile(real):
            os.symlink(os.path.abspath(real), dump)
        else:
            stand_in_dump(dump, data_atoms(os.path.join(deck, data_file)), row_steps(stored))
        with open(report + ".compare", "w") as out:
            run(["nice", "-n", "19", args.dembound, "compare", deck, "--json"], stdout=out)
        os.remove(dump)
        new = json.load(open(report + ".compare"))
        os.remove(report + ".compare")
        for q in stored["quantities"]:
            if q["name"].startswith("wall["):
                n = next(x for x in new["quantities"] if x["name"] == q["name"])
                if n["code"] != q["code"] or n["code_window"] != q["code_window"]:
                    fail(f"seed {k}: {q['name']}: the {args.code} series read now differs from "
                         f"the stored report's", 1)
        spliced = new if os.path.isfile(real) else splice(stored, new, args.set, args.dembound)
        with open(report + ".part", "w") as out:
            json.dump(spliced, out)
        os.replace(report + ".part", report)
        same = dembound_side(spliced) == dembound_side(stored)
        if args.check:
            differ += not same
            print(f"seed {k}: dembound's side {'equals' if same else 'DIFFERS from'} the stored "
                  f"report's", flush=True)
        else:
            print(f"seed {k}: -> {report}", flush=True)
    return 1 if differ else 0


if __name__ == "__main__":
    sys.exit(main())
