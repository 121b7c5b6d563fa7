#!/usr/bin/env python3
"""Independent check of the numbers quoted in docs/errata.md.

Standard library only, written apart from dembound's code: bisection for
h_max, a midpoint rule (after h = h_max (1 - u^2), which removes the
square-root singularity) for the contact time. Accurate to about 6 digits,
enough for every comparison in the errata.
"""
from math import atan, inf, pi, sqrt

G = 9.81          # m/s^2
C2 = 1e7          # c^2 = E_m/rho, m^2/s^2
R = 5e-4          # R_m, m
NU = 0.3
GAP = 0.005       # m (ERRATA 4)
V = sqrt(2 * G * GAP)


def bar(x):
    return 1.0 if x == inf else x / (x + 1)


def p2(alpha, r, z):
    """p^2 of eqs 11-14."""
    return bar(z) * bar(r) ** (2 - alpha) / (pi * (1 - NU**2)) * C2 * R ** (-1 - alpha)


def h_max(alpha, r, z):
    p = p2(alpha, r, z)
    if alpha == 1:
        return (G + sqrt(G * G + V * V * p)) / p       # ERRATA 6
    f = lambda h: p * h ** (alpha + 1) / (alpha + 1) - G * h - V * V / 2  # ERRATA 8
    lo, hi = 0.0, 1e-3
    for _ in range(200):
        mid = (lo + hi) / 2
        lo, hi = (lo, mid) if f(mid) > 0 else (mid, hi)
    return lo


def t_c(alpha, r, z, n=200_000):
    """Contact time: 2 * integral_0^h_max dh / sqrt(D(h)) (ERRATA 8)."""
    p, hm = p2(alpha, r, z), h_max(alpha, r, z)
    s = 0.0
    for i in range(n):
        u = (i + 0.5) / n
        h = hm * (1 - u * u)
        d = V * V + 2 * G * h - 2 * p * h ** (alpha + 1) / (alpha + 1)
        s += 2 * hm * u / sqrt(d) / n
    return 2 * s


def indicator(alpha, r, z):
    """Eq 32 on h_max against r_max = zeta_max = 1000, % (ERRATA 14)."""
    ref = h_max(alpha, 1000, 1000)
    return 100 * (h_max(alpha, r, z) - ref) / ref


print(f"ERRATA 4: v_c = {V:.4f} m/s for 5 mm, {sqrt(2 * G * 0.0025):.4f} m/s for 2.5 mm")
p = p2(1, 100, 100)
tcl = (pi + 2 * atan(G / (V * sqrt(p)))) / sqrt(p)
t_r2 = sqrt(2 * GAP / G) + 2 * tcl + 2 * V / G
print(f"ERRATA 4, 7: second rebound (linear) at {t_r2 * 1e3:.2f} ms; "
      f"2.5 mm would give {3 * sqrt(2 * 0.0025 / G) * 1e3:.1f} ms")
print(f"ERRATA 5: T_cL = {tcl * 1e9:.1f} ns, T_cL/50 = {tcl / 50 * 1e9:.2f} ns")
print(f"ERRATA 6: linear h_max = {h_max(1, 100, 100) * 1e9:.2f} nm, "
      f"a_max = {sqrt(G * G + V * V * p):.4g} m/s^2, "
      f"eq 26 as printed / exact - 1 = {2 * atan(V * sqrt(p) / G) / sqrt(p) / tcl - 1:.2e}")
ph = p2(1.5, 100, 100)
print(f"ERRATA 10: Hertz a_max = {ph * h_max(1.5, 100, 100) ** 1.5 - G:.6g} m/s^2")
print(f"ERRATA 11: (239 - 234)/234 = {100 * 5 / 234:.2f} %")
print(f"ERRATA 12: {100 * (0.319 - 0.313) / 0.313:.2f} %, {100 * (0.315 - 0.313) / 0.313:.2f} %")
print(f"ERRATA 13: r = zeta = inf: h = {h_max(1.5, inf, inf) * 1e6:.5f} um, "
      f"T_c = {t_c(1.5, inf, inf) * 1e6:.4f} us; r = zeta = 1000: "
      f"h = {h_max(1.5, 1000, 1000) * 1e6:.5f} um, T_c = {t_c(1.5, 1000, 1000) * 1e6:.4f} us")
for alpha, name in ((1, "linear"), (1.5, "hertz")):
    print(f"ERRATA 14: {name}: zeta = 10, 100: {indicator(alpha, 1000, 10):.4f} %, "
          f"{indicator(alpha, 1000, 100):.5f} %; r = 10, 100: "
          f"{indicator(alpha, 10, 1000):.4f} %, {indicator(alpha, 100, 1000):.5f} %")
