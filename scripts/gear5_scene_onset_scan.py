#!/usr/bin/env python3
"""The validation drop (examples/scenes/validation.toml, Gear5) with damped
laws over a grid of steps η, its collision log's e against `dembound exact`
(an adaptive Dormand–Prince integration of the same drop): the largest and
median relative error per law, and the steps beyond 0.5 %.

    python3 scripts/gear5_scene_onset_scan.py target/release/dembound [POINTS]

Session 37: before the fix of the damped onset (`dynamics/kinks.rs`) Tsuji
e = 0.3 was −81 % off at η = 0.01875 and −11 % at 0.0125 (exit 0).
Steps refused by the closed-form bound are counted, not run.
"""
import json
import pathlib
import subprocess
import sys

import numpy as np

BIN = sys.argv[1] if len(sys.argv) > 1 else "target/release/dembound"
POINTS = int(sys.argv[2]) if len(sys.argv) > 2 else 109
SCENE = pathlib.Path(__file__).resolve().parent.parent / "examples" / "scenes" / "validation.toml"
CASES = [
    ("Hertz, elastic", []),
    ("Tsuji e = 0.9", ["contact.damping=tsuji", "contact.restitution=0.9"]),
    ("Tsuji e = 0.5", ["contact.damping=tsuji", "contact.restitution=0.5"]),
    ("Tsuji e = 0.3", ["contact.damping=tsuji", "contact.restitution=0.3"]),
    ("Tsuji e = 0.1", ["contact.damping=tsuji", "contact.restitution=0.1"]),
    ("Tsuji e = 0.3, attractive", ["contact.damping=tsuji", "contact.restitution=0.3", "contact.attractive=true"]),
    ("Tsuji e = 0.01, attractive", ["contact.damping=tsuji", "contact.restitution=0.01", "contact.attractive=true"]),
    ("viscoelastic e = 0.85", ["contact.damping=viscoelastic", "contact.restitution=0.85", "contact.calibration=formula"]),
]


def sets(args):
    out = []
    for s in args:
        out += ["--set", s]
    return out


def exact(args):
    cmd = [BIN, "exact", "--json", "--set", "contact.law=hertz", "--set", "motion.contacts=1"] + sets(args)
    return json.loads(subprocess.run(cmd, check=True, capture_output=True, text=True).stdout)["contacts"][0]["restitution"]


def scene(args, eta):
    cmd = [BIN, "scene", str(SCENE), "--json", "-q"] + sets(args + [f"integration.eta={eta}"])
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode == 2:
        return None
    r.check_returncode()
    c = json.loads(r.stdout)["collisions"][0]
    return c["rebound_normal_velocity"] / c["impact_normal_velocity"]


print(f"| law | e exact | steps run (refused) | largest error | median | η beyond 0.5 % |")
print("| --- | ---: | ---: | ---: | ---: | --- |")
for name, args in CASES:
    e_exact = exact([a for a in args if not a.startswith("contact.calibration")] if "viscoelastic" not in name else args)
    errors, refused, beyond = [], 0, []
    for eta in np.linspace(0.004, 0.031, POINTS):
        e = scene(args, eta)
        if e is None:
            refused += 1
            continue
        err = e / e_exact - 1.0
        errors.append(abs(err))
        if abs(err) > 5e-3:
            beyond.append(f"{eta:.5f}: {100 * err:+.1f} %")
    print(f"| {name} | {e_exact:.5f} | {len(errors)} ({refused}) | {100 * max(errors):.3f} % | "
          f"{100 * float(np.median(errors)):.3f} % | {', '.join(beyond) or '—'} |", flush=True)
