#!/usr/bin/env python3
"""dembound against scipy's solve_ivp on the paper's validation case.

The case (Scenario::default(), paper section 4.2 with ERRATA item 4): an
elastic sphere (rho = 1000 kg/m3, E = 1e10 Pa, nu = 0.3, R = 0.5 mm) dropped
from rest through a 5 mm gap under g = 9.81 m/s2 onto a boundary sphere with
r = zeta = 100, Hertz law, two contacts. In contact the gap x < 0 obeys
x'' = -g + p2 (-x)^(3/2) (ERRATA 1, eq 9 corrected) with p2 from eqs 10-14;
out of contact x'' = -g.

scipy solves it with solve_ivp (RK45, DOP853, LSODA) phase by phase: a
terminal event at the contact onset (x = 0 falling) ends a flight, a
terminal event at the rebound (x = 0 rising) ends a contact, a non-terminal
event on v = 0 gives the maximum overlap, and each phase restarts the
solver from the event state with the other right-hand side.

Matched accuracy: dembound's relative errors in t_r(2), h_max(2), v_r(2) at
its default (Gear5, eta = 1/50, event stepping) are measured against the
exact reference; for each scipy method the loosest rtol on a grid
10^(-k/4) whose largest error of the three is no larger than dembound's is
used (atol = rtol times the phase's scale of x and v), and that run is
timed (best of N). dembound's time, results and the exact values come from
`examples/time_validation.rs` (built with cargo if needed) in the same run.

Usage: python3 bench/compare_scipy.py [--repeat N]
(creates bench/.venv with numpy and scipy from PyPI on first use).
"""

import json
import os
import subprocess
import sys
import time
import venv

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
VENV = os.path.join(HERE, ".venv")


def ensure_venv():
    """Re-runs this script inside bench/.venv, creating it if needed."""
    python = os.path.join(VENV, "bin", "python")
    if os.path.realpath(sys.prefix) == os.path.realpath(VENV):
        return
    if not os.path.exists(python):
        print(f"creating {VENV} (numpy, scipy from PyPI)...", file=sys.stderr)
        venv.EnvBuilder(with_pip=True).create(VENV)
        subprocess.run(
            [python, "-m", "pip", "install", "-q", "numpy", "scipy"], check=True
        )
    os.execv(python, [python, os.path.abspath(__file__)] + sys.argv[1:])


def dembound_run():
    """dembound's compute time, results and the exact reference (JSON)."""
    env = dict(os.environ)
    env.setdefault("CARGO_TARGET_DIR", os.path.join(ROOT, "target"))
    exe = os.path.join(env["CARGO_TARGET_DIR"], "release", "examples", "time_validation")
    subprocess.run(
        ["cargo", "build", "--release", "-q", "-p", "dembound-core",
         "--example", "time_validation"],
        cwd=ROOT, env=env, check=True,
    )
    out = subprocess.run([exe], check=True, capture_output=True, text=True).stdout
    return json.loads(out)


G = 9.81
GAP = 5e-3
CONTACTS = 2


def solve(method, rtol, p2):
    """t_r, h_max, v_r of the 2nd contact and the number of RHS calls."""
    import numpy as np
    from scipy.integrate import solve_ivp

    def flight(t, y):
        return [y[1], -G]

    def contact(t, y):
        h = max(-y[0], 0.0)
        return [y[1], -G + p2 * h * np.sqrt(h)]

    def onset(t, y):
        return y[0]

    onset.terminal, onset.direction = True, -1.0

    def rebound(t, y):
        return y[0]

    rebound.terminal, rebound.direction = True, 1.0

    def turn(t, y):
        return y[1]

    turn.direction = 1.0

    v_scale = np.sqrt(2 * G * GAP)
    h_scale = 5e-7
    t, y = 0.0, np.array([GAP, 0.0])
    nfev = 0
    result = None
    for _ in range(CONTACTS):
        # Flight: x'' = -g until x = 0 falling (terminal).
        s = solve_ivp(flight, (t, t + 1.0), y, method=method, rtol=rtol,
                      atol=[rtol * GAP, rtol * v_scale], events=onset)
        nfev += s.nfev
        t, y = s.t_events[0][0], s.y_events[0][0].copy()
        y[0] = 0.0
        # Contact: until x = 0 rising (terminal); v = 0 gives h_max.
        s = solve_ivp(contact, (t, t + 1e-3), y, method=method, rtol=rtol,
                      atol=[rtol * h_scale, rtol * v_scale],
                      events=[rebound, turn])
        nfev += s.nfev
        h_max = -s.y_events[1][0][0]
        t, y = s.t_events[0][0], s.y_events[0][0].copy()
        y[0] = 0.0
        result = (t, h_max, y[1])
    return result, nfev


def rel_errors(values, exact):
    return [abs(v / e - 1.0) for v, e in zip(values, exact)]


def best_time(f, repeat):
    best = float("inf")
    for _ in range(repeat):
        t0 = time.perf_counter()
        f()
        best = min(best, time.perf_counter() - t0)
    return best


def main():
    ensure_venv()
    import scipy

    repeat = 20
    if "--repeat" in sys.argv:
        repeat = int(sys.argv[sys.argv.index("--repeat") + 1])
    d = dembound_run()
    exact = [d["exact_t_rebound"], d["exact_max_overlap"], d["exact_rebound_velocity"]]
    ours = [d["t_rebound"], d["max_overlap"], d["rebound_velocity"]]
    target = max(rel_errors(ours, exact))
    p2 = d["p_squared"]
    print(f"scipy {scipy.__version__}, python {sys.version.split()[0]}")
    print("quantities of the 2nd contact: t_r, h_max, v_r; errors relative to the exact reference")
    print(f"exact: t_r = {exact[0]:.15e} s, h_max = {exact[1]:.15e} m, v_r = {exact[2]:.15e} m/s")
    e = rel_errors(ours, exact)
    print(f"dembound (Gear5, eta = 1/50, event stepping): {d['steps']} steps, "
          f"errors {e[0]:.2e} {e[1]:.2e} {e[2]:.2e}, {d['time_us']:.2f} us per run")
    print(f"{'method':8} {'rtol':>9} {'nfev':>6} {'err t_r':>9} {'err h_max':>9} "
          f"{'err v_r':>9} {'time (us)':>11} {'/ dembound':>10}")
    for method in ["RK45", "DOP853", "LSODA"]:
        chosen = None
        for k in range(8, 56):
            rtol = 10.0 ** (-k / 4)
            try:
                values, nfev = solve(method, rtol, p2)
            except Exception:  # a failed event search at a loose tolerance
                continue
            err = rel_errors(values, exact)
            if max(err) <= target:
                chosen = (rtol, nfev, err)
                break
        if chosen is None:
            print(f"{method:8} did not reach {target:.2e}")
            continue
        rtol, nfev, err = chosen
        t = best_time(lambda: solve(method, rtol, p2), repeat)
        print(f"{method:8} {rtol:9.1e} {nfev:6d} {err[0]:9.2e} {err[1]:9.2e} {err[2]:9.2e} "
              f"{t * 1e6:11.0f} {t * 1e6 / d['time_us']:10.0f}")


if __name__ == "__main__":
    main()
