"""An r–ζ sweep into a pandas DataFrame, two ways.

1. `dembound.sweep`: the CLI's sweep document (integrator beside the exact
   reference, normalised by the rigid half-space), one row per case.
2. `dembound.batch`: a dense NumPy grid through the batched SIMD path (the
   integrator only), one row per grid point.

    pip install . pandas
    python examples/python/sweep_dataframe.py
"""

import math

import numpy as np
import pandas as pd

import dembound

# 1. The sweep document: 4 radius ratios × 5 modulus ratios, both laws.
doc = dembound.sweep(r=[1, 10, 100, math.inf], zeta=[1, 10, 100, 1000, math.inf], law="linear,hertz")
rows = []
for case in doc["cases"]:
    key, first = case["key"], case["contacts"][0]
    rows.append(
        {
            "law": key["law"],
            "r": key["radius_ratio"],
            "zeta": key["modulus_ratio"],
            "R_b (m)": key["boundary_radius"],
            "E_b (Pa)": key["boundary_youngs_modulus"],
            "h_max (m)": first["numerical"]["max_overlap"],
            "T_c (s)": first["numerical"]["duration"],
            "h_max/h_max∞": first["exact_normalised"]["max_overlap"],
            "T_c/T_c∞": first["exact_normalised"]["duration"],
            "integrator error h_max": first["relative_error"]["max_overlap"],
        }
    )
sweep = pd.DataFrame(rows)
# The sweep document writes r = ∞ as the string "inf"; make it a float.
sweep[["r", "zeta"]] = sweep[["r", "zeta"]].astype(float)
pd.set_option("display.width", 160)
print(sweep.to_string(index=False, float_format=lambda x: f"{x:.6g}"))

# 2. A 40 × 40 grid of Hertz runs in one call (GIL released, SIMD lanes).
r = np.logspace(0, 3, 40)
zeta = np.logspace(0, 3, 40)
R, Z = np.meshgrid(r, zeta, indexing="ij")
grid = dembound.batch(r=R, zeta=Z, contact__law="hertz")
frame = pd.DataFrame(
    {
        "r": R.ravel(),
        "zeta": Z.ravel(),
        "h_max (m)": grid["max_overlap"][..., 0].ravel(),
        "T_c (s)": grid["duration"][..., 0].ravel(),
        "v_r (m/s)": grid["rebound_velocity"][..., 0].ravel(),
        "steps": grid["steps"].ravel(),
    }
)
print(f"\n{len(frame)} batched runs; the stiffest and softest boundaries:")
print(frame.sort_values("h_max (m)").iloc[[0, -1]].to_string(index=False))
print("\nT_c (µs) by r (rows) and ζ (columns), every 13th value:")
table = frame.pivot(index="r", columns="zeta", values="T_c (s)") * 1e6
print(table.iloc[::13, ::13].round(4).to_string())
