#!/usr/bin/env python3
"""Chung & Ooi (2011) Test 6 integrated apart from dembound (standard
library only; the equations in scripts/chung_ooi_model.py): an
aluminium-alloy sphere (R = 0.1 m, E = 70 GPa, nu = 0.33,
rho = 2700 kg/m^3), centre at rest tangentially, spinning so that its
contact point moves at v_cp = v_n tan(theta), hits a plane at v_n = 0.2 m/s;
mu = 0.4, Hertz with Tsuji damping (alpha of a clamped impact rebounding
with e = 0.5), Mindlin spring with the dashpot at the normal damping ratio.

Two set-ups, to account for the benchmark's comparison with LAMMPS
(scripts/lammps_chung_ooi_6.py):
  ours   - rigid plane (E* = E/(1 - nu^2), G* = G/(2 - nu)), torque arm R,
           dembound's Coulomb order, dt = T_c/20,000;
  LAMMPS - a target of the same material (E*, G* halved: the same
           k_t/k_n), torque arm R - h/2, LAMMPS's Coulomb order, alpha
           from LAMMPS's polynomial at the e the deck gives, dt = 5e-8 s.
Prints per theta both set-ups' beta = -v_cp'/v_cp and v_cp'/v_n', and the
largest difference between them (beta absolute; the recoil tangent
relative beyond 1, |a - b|/max(|b|, 1)): the band of the benchmark's LAMMPS
check. Options:
  --halve      the ours set-up with k_t halved (the dashpot following,
               at the same damping ratio), beside the digitised curve;
  --undamped-t the ours set-up without the tangential dashpot.
"""
import math
import sys

from chung_ooi_lammps import tsuji_alpha, tsuji_input_for
from chung_ooi_model import contact_time, impact, moduli, tsuji_alpha_for

E, NU, RHO, R, VN, MU, E_REST = 7e10, 0.33, 2700.0, 0.1, 0.2, 0.4, 0.5
M = 4 / 3 * math.pi * R**3 * RHO
ANGLES = [5.0 * k for k in range(1, 18)]
# digitised.rs T6_BETA_ALLOY (x1 = 3.5 mu (1 + e) v_n/v_cp, beta).
PAPER_BETA = [
    (0.17621145374449387, -0.8200274348422496), (0.35242290748898686, -0.6334705075445815),
    (0.5506607929515415, -0.4447187928669407), (0.7709251101321586, -0.24279835390946491),
    (0.9691629955947132, -0.027709190672153494), (1.1894273127753303, 0.09739368998628262),
    (1.4537444933920707, 0.11934156378600824), (1.7400881057268727, 0.09958847736625531),
    (2.0925110132158586, 0.057887517146776424), (2.4889867841409696, 0.005212620027434944),
    (2.995594713656388, -0.04965706447187923), (3.6343612334801767, -0.10013717421124824),
    (4.515418502202644, -0.13964334705075443), (5.748898678414097, -0.17475994513031534),
    (7.819383259911897, -0.2076817558299039), (11.894273127753305, -0.2581618655692728),
    (24.00881057268723, -0.34156378600823023),
]


def interpolate(curve, x):
    pts = sorted(curve)
    for (x0, y0), (x1, y1) in zip(pts, pts[1:]):
        if x0 <= x <= x1:
            return y0 + (y1 - y0) * (x - x0) / (x1 - x0)
    return None


def run(deg, lammps, kt_factor=1.0, undamped_t=False):
    es, gs = moduli(E, NU, lammps)
    if lammps:
        alpha = tsuji_alpha(tsuji_input_for(tsuji_alpha_for(E_REST)))
        dt = 5e-8
    else:
        alpha = tsuji_alpha_for(E_REST)
        dt = contact_time(M, R, es, VN) / 20000
    vcp = VN * math.tan(math.radians(deg))
    vx, vz, w = impact(radius=R, mass=M, es=es, gs=gs, vn=VN, vx=0.0,
                       spin=-vcp / R, mu=MU, dt=dt, alpha=alpha,
                       order="lammps" if lammps else "ours", half_arm=lammps,
                       kt_factor=kt_factor, undamped_t=undamped_t)
    slip = vx - R * w
    return -slip / vcp, slip / vz, vz / VN


def main():
    x1 = lambda deg: 3.5 * MU * (1 + E_REST) / math.tan(math.radians(deg))
    if "--halve" in sys.argv or "--undamped-t" in sys.argv:
        halve = "--halve" in sys.argv
        for deg in ANGLES:
            b, y, _ = run(deg, False, 0.5 if halve else 1.0, not halve)
            p = interpolate(PAPER_BETA, x1(deg))
            paper = f"{p:+.4f}" if p is not None else "   -   "
            print(f"theta = {deg:4.1f}, x1 = {x1(deg):7.4f}: beta = {b:+.4f} (paper {paper}), v_cp'/v_n' = {y:+.4f}")
        return
    worst_b = worst_y = 0.0
    for deg in ANGLES:
        a = run(deg, False)
        b = run(deg, True)
        db = abs(a[0] - b[0])
        dy = abs(a[1] - b[1]) / max(abs(b[1]), 1.0)
        worst_b, worst_y = max(worst_b, db), max(worst_y, dy)
        print(f"theta = {deg:4.1f}: ours beta {a[0]:+.4f} tan {a[1]:+.4f} (e {a[2]:.5f})  "
              f"LAMMPS set-up beta {b[0]:+.4f} tan {b[1]:+.4f} (e {b[2]:.5f})  differ {db:.4f} {dy:.4f}")
    print(f"largest difference of the set-ups: beta {worst_b:.4f}, v_cp'/v_n' {worst_y:.4f} (relative beyond 1)")


if __name__ == "__main__":
    main()
