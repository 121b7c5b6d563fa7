#!/usr/bin/env python3
"""Chung & Ooi (2011) Test 6 in LAMMPS, the reference of the benchmark's
cross-check (`LAMMPS_T6_ALLOY` in
crates/dembound-scene/src/benchmarks/peer.rs).

An aluminium-alloy sphere (R = 0.1 m, E = 70 GPa, nu = 0.33,
rho = 2700 kg/m^3), centre at rest tangentially and spinning so that its
contact point moves at v_cp = v_n tan(theta), theta = 5-85 degrees, hits at
v_n = 0.2 m/s (mu = 0.4, e = 0.5) a sphere of the same material 1000 times
larger that LAMMPS does not integrate (scripts/chung_ooi_lammps.py's deck).
pair_style granular, hertz/material with `damping tsuji` and
`limit_damping` (the normal force clamped at 0, as dembound's), Tsuji's
alpha the one whose clamped impact rebounds with e = 0.5
(scripts/chung_ooi_model.py's tsuji_alpha_for; LAMMPS takes a restitution
coefficient and maps it through its polynomial, so the e given is the one
the polynomial maps to that alpha), `tangential mindlin` (k_t = 8 G* a)
with x_gammat = sqrt(4 G*/E*): the tangential dashpot at the normal
damping ratio, dembound's. Delta t = 5e-8 s, about T_c/19,000 of this
set-up.

Prints, per theta, beta = -v_cp'/v_cp and v_cp'/v_n' as rows of the
table. Needs `lmp` on PATH; about 1 s per angle.

    python3 scripts/lammps_chung_ooi_6.py
"""
import math
import tempfile

from chung_ooi_lammps import impact, tsuji_input_for
from chung_ooi_model import contact_time, moduli, tsuji_alpha_for

E, NU, RHO, R, VN, MU, E_REST = 7e10, 0.33, 2700.0, 0.1, 0.2, 0.4, 0.5
M = 4 / 3 * math.pi * R**3 * RHO
DT = 5e-8
ANGLES = [5.0 * k for k in range(1, 18)]


def coefficients():
    """The pair_coeff text: LAMMPS's e input for Tsuji's alpha of e = 0.5,
    and x_gammat = sqrt(4 G*/E*) (the same for any pair of one material)."""
    es, gs = moduli(E, NU, True)
    e_in = tsuji_input_for(tsuji_alpha_for(E_REST))
    xgt = math.sqrt(4 * gs / es)
    return (f"hertz/material {E!r} {e_in!r} {NU!r} tangential mindlin NULL "
            f"{xgt!r} {MU!r} damping tsuji limit_damping")


def steps():
    """Steps covering the contact with a margin (T_c of this set-up: the
    target's compliance halves E*)."""
    return math.ceil(1.3 * contact_time(M, R, moduli(E, NU, True)[0], VN) / DT)


def main():
    coeffs = coefficients()
    n = steps()
    with tempfile.TemporaryDirectory() as work:
        for deg in ANGLES:
            vcp = VN * math.tan(math.radians(deg))
            vx, vz, wy = impact(work, radius=R, density=RHO, vx=0.0, vz=-VN,
                                wy=-vcp / R, coeffs=coeffs, dt=DT, steps=n)
            slip = vx - R * wy
            print(f"    ({deg!r}, {-slip / vcp:.4f}, {slip / vz:.4f}),")


if __name__ == "__main__":
    main()
