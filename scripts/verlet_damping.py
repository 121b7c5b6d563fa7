"""Session 35: velocity Verlet's error in e against the exact reference,
for the damped laws, with and without attraction, over target e and eta.
One gravity-free contact at 0.313 m/s on the validation pair (r = zeta = 100).
Usage: python3 scripts/verlet_damping.py target/release/dembound > table.tsv
(the table in README.md, "Accuracy" of the dissipative laws). Since session
36 Gear5 refuses a step past its stability bound on the damped contact: those
rows print rc=2 and the start of the message (the key and the largest eta)."""
import json, subprocess, sys
B = sys.argv[1]
laws = [("linear", "viscous"), ("hertz", "tsuji"), ("hertz", "viscoelastic")]
targets = [0.9, 0.5, 0.3, 0.1, 0.05, 0.02, 0.01]
etas = [0.005, 0.01, 0.02, 0.05, 0.1]
print("law\tattractive\ttarget\teta\tscheme\te_run\te_exact\trel_err\tnote")
for law, damp in laws:
    for attractive in ["false", "true"]:
        for e in targets:
            base = ["--set", f"contact.law={law}", "--set", f"contact.damping={damp}",
                    "--set", f"contact.restitution={e}", "--set", f"contact.attractive={attractive}",
                    "--set", "motion.gravity=0", "--set", "motion.velocity=-0.313",
                    "--set", "motion.contacts=1"]
            x = subprocess.run([B, "exact", "--json"] + base, capture_output=True, text=True)
            if x.returncode != 0:
                print(f"{damp}\t{attractive}\t{e}\t-\t-\t-\t-\t-\texact rc={x.returncode}: {x.stderr.strip()[-120:]}")
                continue
            ex = json.loads(x.stdout)["contacts"][0]["restitution"]
            for eta in etas:
                for scheme in ["verlet", "gear5"]:
                    r = subprocess.run([B, "run", "--json"] + base + ["--set", f"integration.eta={eta}",
                                        "--set", f"integration.scheme={scheme}"], capture_output=True, text=True)
                    if r.returncode != 0:
                        print(f"{damp}\t{attractive}\t{e}\t{eta}\t{scheme}\t-\t{ex:.6g}\t-\trc={r.returncode}: {r.stderr.strip()[:110]}")
                        continue
                    er = json.loads(r.stdout)["contacts"][0]["restitution"]
                    print(f"{damp}\t{attractive}\t{e}\t{eta}\t{scheme}\t{er:.6g}\t{ex:.6g}\t{er/ex-1:+.4%}\t")
                    sys.stdout.flush()
