"""LAMMPS runs of one Chung & Ooi (2011) impact on a quasi-plane, shared by
scripts/lammps_chung_ooi_5.py and scripts/lammps_chung_ooi_6.py (import
it; not a program).

A sphere of radius R hits, along -z, a sphere of the same material 1000
times larger that LAMMPS does not integrate (infinite mass for the ball's
purposes, no spin): a plane up to R/R2 = 1e-3 in the contact geometry.
`pair_style granular`, the pair coefficients given by the caller (normal
model, damping, `tangential mindlin`). The ball starts 1e-7 R above the
target with the given velocity and spin about y, and is dumped once at the
end of the run (after the contact).

Needs `lmp` on PATH (written against LAMMPS 29 Sep 2021 - Update 2).
Standard library only.
"""
import os
import subprocess

TARGET_SCALE = 1000.0

DECK = """units si
atom_style sphere
atom_modify map array
boundary f f f
region box block {box_lo!r} {box_hi!r} {box_lo!r} {box_hi!r} {z_lo!r} {z_hi!r}
create_box 1 box
create_atoms 1 single 0 0 {z0!r}
create_atoms 1 single 0 0 {z_target!r}
set atom 1 diameter {d!r} density {rho!r}
set atom 2 diameter {d_target!r} density {rho!r}
set atom 1 omega 0.0 {wy!r} 0.0
group ball id 1
velocity ball set {vx!r} 0 {vz!r}
comm_modify vel yes
pair_style granular
pair_coeff * * {coeffs}
neighbor {skin!r} bin
neigh_modify one 10 page 1000
fix 1 ball nve/sphere
timestep {dt!r}
thermo {steps}
dump d ball custom {steps} {dump} id vx vz omegay
run {steps}
"""


def impact(work, *, radius, density, vx, vz, wy, coeffs, dt, steps):
    """Runs one impact in directory `work`; returns the ball's (v_x, v_z,
    omega_y) after `steps` steps of `dt` (SI units)."""
    r = radius
    big = TARGET_SCALE * r
    deck = os.path.join(work, "in.impact")
    dump = os.path.join(work, "out.impact")
    with open(deck, "w") as f:
        f.write(
            DECK.format(
                box_lo=-2.0 * big,
                box_hi=2.0 * big,
                z_lo=-2.1 * big,
                z_hi=0.1 * big,
                z0=r + 1e-7 * r,
                z_target=-big,
                d=2.0 * r,
                d_target=2.0 * big,
                rho=density,
                wy=wy,
                vx=vx,
                vz=vz,
                coeffs=coeffs,
                skin=0.2 * r,
                dt=dt,
                steps=steps,
                dump=dump,
            )
        )
    subprocess.run(
        ["lmp", "-in", deck, "-log", "none", "-screen", "none"],
        check=True,
        stdout=subprocess.DEVNULL,
    )
    with open(dump) as f:
        last = [line for line in f if line.strip()][-1].split()
    vx_out, vz_out, wy_out = map(float, last[1:])
    return vx_out, vz_out, wy_out


def tsuji_alpha(e):
    """LAMMPS `damping tsuji`'s conversion of the restitution coefficient
    given in pair_coeff to Tsuji's alpha (pair_granular.cpp, `coeff`: the
    polynomial fit of Tsuji et al. 1992's chart)."""
    return (1.2728 - 4.2783 * e + 11.087 * e**2 - 22.348 * e**3
            + 27.467 * e**4 - 18.022 * e**5 + 4.8218 * e**6)


def tsuji_input_for(alpha):
    """The e to give LAMMPS's `damping tsuji` so that it runs Tsuji's alpha
    `alpha` (the polynomial inverted by bisection on 0 < e < 1, where it
    decreases)."""
    lo, hi = 1e-9, 1.0
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if tsuji_alpha(mid) > alpha:
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)
