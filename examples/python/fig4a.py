"""Fig 4a of Jasevičius & Kačianauskas (2007) from Python: the overlap
history of the first contact on a boundary particle of the particle's own
size (r = R_b/R_m = 1) for ζ = E_b/E_m = 1, 10, 100, 1000, Hertz and linear,
in the paper's normalisation h* = h/h_NL_max against t* = (t − t_c)/T_c_NL,
where h_NL_max and T_c_NL are the exact Hertz values against the rigid
half-space (r = ζ = ∞) of the same drop (`dembound paper` draws the same
figure from Rust: paper-reproduction/fig4a.svg).

    pip install . matplotlib
    python examples/python/fig4a.py [fig4a.png]
"""

import math
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import dembound  # noqa: E402

R = 1.0
ZETAS = [1.0, 10.0, 100.0, 1000.0]
LAWS = {"hertz": ("-", "o"), "linear": ("--", "^")}
# Section 5 (`dembound paper`): the validation drop, one contact, Gear5, η = 1/50.
BASE = {"motion__contacts": 1}

# The normalisation: exact Hertz contact against the rigid half-space.
rigid = dembound.exact(
    contact__law="hertz", boundary__radius_ratio=math.inf, boundary__modulus_ratio=math.inf, **BASE
)["contacts"][0]
h_nl, t_nl = rigid["max_overlap"], rigid["duration"]  # m, s

fig, ax = plt.subplots(figsize=(7.5, 5))
colors = plt.rcParams["axes.prop_cycle"].by_key()["color"]
for i, zeta in enumerate(ZETAS):
    for law, (line, marker) in LAWS.items():
        run = dembound.run(
            contact__law=law,
            boundary__radius_ratio=R,
            boundary__modulus_ratio=zeta,
            history=100_000,  # every integration step of the contact
            **BASE,
        )
        c = run["contacts"][0]
        h = run["history"]
        inside = (h["t"] >= c["t_contact"]) & (h["t"] <= c["t_rebound"])
        t_star = (h["t"][inside] - c["t_contact"]) / t_nl
        h_star = h["overlap"][inside] / h_nl
        ax.plot(t_star, h_star, line, marker=marker, markevery=3, markersize=3.5,
                color=colors[i], label=f"{law}, ζ = {zeta:g}")

ax.set_title(f"Fig 4a: overlap histories, r = {R:g}")
ax.set_xlabel("time since contact onset t* = (t − t_c) / T_c_NL  (1)")
ax.set_ylabel("overlap h* = h / h_NL_max  (1)")
ax.set_xlim(left=0)
ax.set_ylim(bottom=0)
ax.grid(alpha=0.3)
ax.legend(fontsize=8, ncol=2)
fig.text(0.01, 0.01, f"h_NL_max = {h_nl * 1e9:.4f} nm, T_c_NL = {t_nl * 1e6:.5f} µs "
         "(Hertz, r = ζ = ∞, exact); lines and points: Gear5 steps, η = 1/50", fontsize=7)
fig.tight_layout(rect=(0, 0.03, 1, 1))
out = sys.argv[1] if len(sys.argv) > 1 else "fig4a.png"
fig.savefig(out, dpi=150)
print(f"wrote {out}")
