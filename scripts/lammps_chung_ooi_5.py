#!/usr/bin/env python3
"""Chung & Ooi (2011) Test 5 in LAMMPS, the reference of the benchmark's
cross-check (`LAMMPS_T5_STEEL` in
crates/dembound-scene/src/benchmarks/peer.rs).

A steel sphere (R = 1e-5 m, E = 200 GPa, nu = 0.3, rho = 7800 kg/m^3)
hits, at v_n = 5 m/s and v_t = psi1 mu v_n (mu = 0.3, no damping), a
sphere of the same material 1000 times larger that LAMMPS does not
integrate (infinite mass, no spin): a plane up to R/R2 = 1e-3 in the
contact geometry. pair_style granular, hertz/material with
`tangential mindlin` (k_t = 8 G* a, the force -k_t xi from the stored
displacement, the spring cut back to mu F_n): the model dembound runs.
Delta t = 2.5e-12 s, about T_c/20,000.

Prints, per psi1, psi2 = v_cp'/(mu v_n') and R omega'/(mu v_n) (negative
in the rolling sense). Needs `lmp` on PATH; about 1 s per point. The
deck is scripts/chung_ooi_lammps.py's.

    python3 scripts/lammps_chung_ooi_5.py [tangential model]
"""
import sys
import tempfile

from chung_ooi_lammps import impact

R, VN, MU = 1e-5, 5.0, 0.3
# The abscissae of the digitised steel curve (digitised.rs,
# T5_RECOIL_STEEL) up to psi1 = 6, the sticking range.
PSI1 = [
    0.0664652567975832, 0.3323262839879155, 0.6706948640483383,
    1.0090634441087611, 1.3353474320241694, 1.6616314199395772, 2.0,
    2.350453172205438, 2.990936555891238, 3.3413897280966762,
    4.006042296072506, 4.996978851963746, 6.0,
]


def run(psi1, tang, work):
    vx, vz, wy = impact(
        work,
        radius=R,
        density=7800.0,
        vx=psi1 * MU * VN,
        vz=-VN,
        wy=0.0,
        coeffs=f"hertz/material 2e11 0.0 0.3 tangential {tang} NULL 0.0 0.3",
        dt=2.5e-12,
        steps=40000,
    )
    return (vx - R * wy) / (MU * vz), -R * wy / (MU * VN)


def main():
    tang = sys.argv[1] if len(sys.argv) > 1 else "mindlin"
    with tempfile.TemporaryDirectory() as work:
        for psi1 in PSI1:
            psi2, spin = run(psi1, tang, work)
            print(f"    ({psi1!r}, {psi2:.4f}, {spin:.4f}),")


if __name__ == "__main__":
    main()
