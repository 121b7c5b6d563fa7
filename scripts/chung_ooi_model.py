"""The Hertz-Mindlin impact of a sphere on a plane integrated apart from
dembound (standard library only), shared by scripts/chung_ooi_5_integrate.py
and scripts/chung_ooi_6_integrate.py (import it; not a program).

The equations (the model dembound and LAMMPS `pair_style granular` run):
  normal:  F_n = k h^(3/2) + alpha sqrt(m k) h^(1/4) dh/dt, clamped at 0
           (k = (4/3) E* sqrt(R); Tsuji et al. 1992's damping, alpha 0
           without damping; LAMMPS `damping tsuji` with `limit_damping`);
  spring:  k_t = 8 G* sqrt(R h) on the stored slip s, s += v_cp dt;
  dashpot: eta_t = eta_n sqrt(k_t/S_n), eta_n = alpha sqrt(m k) h^(1/4),
           S_n = dF/dh = 2 E* sqrt(R h): the normal damping ratio
           (LAMMPS: x_gammat = sqrt(4 G*/E*));
  Coulomb, two orders (they differ only with a dashpot):
    "ours":   sliding when the spring alone exceeds mu F_n (s cut back to
              mu F_n/k_t, F_t = -k_t s); else F_t = -k_t s - eta_t v_cp,
              capped at mu F_n with the spring kept (dembound's
              FrictionPair::tangential_force);
    "lammps": F_t = -k_t s - eta_t v_cp; beyond mu F_n the force is capped
              and the spring solved back from it, s = -(F_t + eta_t v_cp)/k_t
              (LAMMPS pair_granular.cpp, the tangential rescaling);
  torque arm R (ours) or R - h/2 (LAMMPS's dist_to_contact);
symplectic Euler (forces from the current state, velocities, then the
position).
"""
import functools
import math

# Hertz contact time T_c = 2.868 (m^2/(R E*^2 v))^(1/5) (paper eq 30 with
# the Beta function evaluated).
HERTZ_TIME = 2.868


def moduli(young, poisson, elastic_target):
    """(E*, G*) of a sphere on a rigid plane, or (elastic_target) on a
    body of its own material: E* = E/(1 - nu^2), G* = G/(2 - nu), halved."""
    es = young / (1 - poisson * poisson) / (2 if elastic_target else 1)
    gs = young / (2 * (1 + poisson)) / (2 - poisson) / (2 if elastic_target else 1)
    return es, gs


def contact_time(mass, radius, es, vn):
    """Hertz's elastic contact duration, s."""
    return HERTZ_TIME * (mass * mass / (radius * es * es * vn)) ** 0.2


def impact(*, radius, mass, es, gs, vn, vx, spin, mu, dt, alpha=0.0,
           order="ours", half_arm=False, kt_factor=1.0, undamped_t=False):
    """One impact at normal speed vn (m/s), centre tangential velocity vx
    (m/s, along x) and spin omega_y = spin (rad/s); the contact point moves
    at vx - R spin. `undamped_t`: no tangential dashpot. Returns (vx', vz', omega_y') after the contact."""
    R = radius
    inertia = 0.4 * mass * R * R
    k = 4 / 3 * es * math.sqrt(R)
    damp = alpha * math.sqrt(mass * k)
    z, vz, w, s = R, -vn, spin, 0.0
    while True:
        h = R - z
        if h <= 0 and vz > 0:
            break
        if h > 0:
            kt = kt_factor * 8 * gs * math.sqrt(R * h)
            slip = vx - R * w
            s_before = s
            s += slip * dt
            if damp == 0.0:
                fn = k * h**1.5
                if kt * abs(s) > mu * fn:
                    s = math.copysign(mu * fn / kt, s)
                ft = -kt * s
            else:
                eta_n = damp * h**0.25
                fn = max(k * h**1.5 - eta_n * vz, 0.0)
                eta_t = 0.0 if undamped_t else eta_n * math.sqrt(kt / (1.5 * k * math.sqrt(h)))
                limit = mu * fn
                if order == "ours":
                    if kt * abs(s) > limit:
                        s = math.copysign(limit / kt, s)
                        ft = -kt * s
                    else:
                        ft = -kt * s - eta_t * slip
                        if abs(ft) > limit:
                            ft = math.copysign(limit, ft)
                else:
                    ft = -kt * s - eta_t * slip
                    # LAMMPS tests the spring's length before this step's
                    # increment: a fresh spring over the limit gives no force.
                    if abs(ft) > limit:
                        if s_before != 0.0:
                            ft = math.copysign(limit, ft)
                            s = -(ft + eta_t * slip) / kt
                        else:
                            ft = 0.0
            arm = R - 0.5 * h if half_arm else R
        else:
            fn = ft = s = 0.0
            arm = R
        vz += fn / mass * dt
        vx += ft / mass * dt
        w += -arm * ft / inertia * dt
        z += vz * dt
    return vx, vz, w


@functools.lru_cache(maxsize=None)
def tsuji_alpha_for(e, steps=100000):
    """Tsuji's alpha whose clamped, gravity-free normal impact rebounds
    with restitution e (bisection on alpha; the impact integrated at
    T_c/steps; the result does not depend on E, R, m or v)."""
    es, radius, mass, vn = 1.0, 1.0, 1.0, 1.0
    k = 4 / 3 * es * math.sqrt(radius)
    dt = contact_time(mass, radius, es, vn) / steps

    def rebound(alpha):
        damp = alpha * math.sqrt(mass * k)
        h, v = 0.0, vn  # v = dh/dt
        while True:
            h += v * dt
            if h <= 0.0:
                return -v / vn
            f = max(k * h**1.5 + damp * h**0.25 * v, 0.0)
            v -= f / mass * dt

    lo, hi = 0.0, 3.0
    for _ in range(40):
        mid = 0.5 * (lo + hi)
        if rebound(mid) > e:
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)
