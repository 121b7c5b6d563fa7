"""Session 36: Gear5's error in e on a damped contact against the exact
reference, over law (spring-dashpot, Tsuji, viscoelastic), attraction,
target e = 0.01-0.9, eta = 0.02-0.1, gravity off or 9.81 m/s^2, impact
speed 0.001, 0.313 and 3 m/s (gap 0), event and fixed stepping: one
contact, `run --json` against `exact --json`. Refused runs print their
exit code and the start of the message (the key and the largest eta
it accepts).
Usage: python3 scripts/gear5_damped_envelope.py target/release/dembound > grid.tsv
(about 5300 runs, 2-4 min; BENCHMARKS.md, session 36)."""
import json, subprocess, sys, itertools
B = sys.argv[1]
laws = [("linear", "viscous"), ("hertz", "tsuji"), ("hertz", "viscoelastic")]
targets = [0.9, 0.5, 0.3, 0.1, 0.05, 0.02, 0.01]
etas = [0.02, 0.025, 0.03, 0.035, 0.04, 0.05, 0.06, 0.07, 0.08, 0.1]
speeds = [0.001, 0.313, 3.0]
print("law\tattractive\ttarget\tgravity\tspeed\tstepping\teta\te_run\te_exact\trel_err\tnote")
def js(args):
    r = subprocess.run([B] + args, capture_output=True, text=True)
    if r.returncode != 0:
        return None, f"rc={r.returncode}: {r.stderr.strip()[:200]}"
    return json.loads(r.stdout)["contacts"][0]["restitution"], ""
for (law, damp), att, e, g, v in itertools.product(laws, ["false", "true"], targets, [0, 9.81], speeds):
    base = ["--set", f"contact.law={law}", "--set", f"contact.damping={damp}",
            "--set", f"contact.restitution={e}", "--set", f"contact.attractive={att}",
            "--set", f"motion.gravity={g}", "--set", f"motion.velocity={-v}", "--set", "motion.gap=0",
            "--set", "motion.contacts=1"]
    ex, note = js(["exact", "--json"] + base)
    if ex is None:
        print(f"{damp}\t{att}\t{e}\t{g}\t{v}\t-\t-\t-\t-\t-\texact {note}"); continue
    for st in ["event", "fixed"]:
        for eta in etas:
            er, note = js(["run", "--json"] + base + ["--set", f"integration.eta={eta}", "--set", f"integration.stepping={st}"])
            if er is None:
                print(f"{damp}\t{att}\t{e}\t{g}\t{v}\t{st}\t{eta}\t-\t{ex:.9g}\t-\t{note}")
            else:
                print(f"{damp}\t{att}\t{e}\t{g}\t{v}\t{st}\t{eta}\t{er:.9g}\t{ex:.9g}\t{er/ex-1:+.3e}\t")
            sys.stdout.flush()
