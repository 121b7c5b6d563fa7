#!/usr/bin/env python3
"""Hopper discharge with particle walls against the mesh wall (issue 29).

    python3 scripts/hopper_particle_walls.py [--dembound BIN] [--work DIR]
        [--ratios 0.5,1,2] [--settle S] [--discharge S] [--skip S]
        [--seeds 1,2] [--jobs 2] [--same-outlet] [--friction MU]

The hopper is examples/scenes/hopper.stl (cone half-angle 30°, outlet
radius 6 mm at z = 0, bin radius 20 mm; make_hopper.py) with
examples/scenes/hopper.toml's 2000 glass spheres (R = 1 mm, E = 1e7 Pa,
ν = 0.3, Hertz, Tsuji e = 0.5, frictionless, Δt = 4 µs). For each wall —
the mesh wall itself (material "hopper", E = 5e7 Pa) and particle walls of
r = R_b/R = 0.5, 1, 2 (the mesh form `boundary_particles = { mesh =
"hopper.stl", flip = true }`, square tiling, touching, material "hopper",
ζ = inf: rigid spheres, the stiffest a particle wall can be; `dembound
recommend` finds no ζ within 3 % of the rigid wall at r ≤ 2, Hertz) — one
run per seed:
  1. fill: the spheres fall from a loose random packing onto a plug (a
     plane at z = 0, normal +z, closing the outlet) and settle for
     --settle s (a snapshot then);
  2. discharge: the plug drops to z = −39 mm within 10 ms (`motion`,
     3.9 m/s from the end of the settling: faster than the grains fall, so
     it leaves them at once) and the flow runs --discharge s; an [[outlet]]
     box below z = −10 mm removes the discharged spheres. The mass flow
     rate is the slope of series.csv's outlet0_mass_kg from --skip s after
     the opening to the end, its standard error from 5 batch means; the
     seeds' rates are averaged (standard error: the larger of the combined
     batch errors and the seeds' scatter).
(A restart from the settled checkpoint with the plug moved by --set is
refused: the checkpoint's fingerprint holds the walls.)
The packing fraction at the wall is measured in the settled bed (the
snapshot at the opening): the solid fraction of the free spheres in the
shell between the cone's surface and 2 mm (one diameter) inside it, for
6 mm ≤ z ≤ 16 mm, by 200,000 seeded random points (binomial standard
error).
--same-outlet also runs the mesh wall narrowed to each particle wall's
clear outlet radius (min over its spheres of distance from the axis − R_b;
the covering keeps sites up to one spacing beyond an open rim, so the
spheres extend the cone below z = 0): the cone continued down to that
radius, make_hopper.py's functions, the rest unchanged. It separates the
narrower outlet from the spheres' roughness.
--friction MU gives every surface Coulomb friction μ = MU (`contact.friction`:
grain–grain, grain–wall and the plug; Mindlin tangential spring with its
dashpot, the program's defaults), the rest unchanged: the bumps then add to
a wall friction already present.

Writes DIR/table.md, DIR/results.json and DIR/hopper_particle_walls.png.
numpy and matplotlib. Finished runs (same scene text) are reused.
"""

import argparse
import csv
import base64
import json
import math
import re
import struct
import subprocess
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
HOPPER = ROOT / "examples" / "scenes" / "hopper.stl"
DT = 4.0e-6
OUTLET_RADIUS = 6.0e-3
TOP_RADIUS = 20.0e-3
CONE_HEIGHT = (TOP_RADIUS - OUTLET_RADIUS) / math.tan(math.radians(30.0))


def scene(wall: str, steps: int, settle: int, seed: int, friction: float = 0.0) -> str:
    opened = settle * DT
    # μ of every surface (grain–grain, grain–wall, grain–plug); the
    # frictionless scene's text is unchanged (its finished runs are reused).
    coulomb = f"friction = {friction!r}\n" if friction > 0 else ""
    return f"""
[domain]
lower = [-0.06, -0.06, -0.04]
upper = [0.06, 0.06, 0.095]
periodic = [false, false, false]

[[material]]
name = "glass"
density = 2500.0
youngs_modulus = 1.0e7
poisson_ratio = 0.3

[[material]]
name = "hopper"
density = 7800.0
youngs_modulus = 5.0e7
poisson_ratio = 0.3

[contact]
law = "hertz"
damping = "tsuji"
restitution = 0.5
{coulomb}
[[particles]]
random = {{ count = 2000, radius = 1.0e-3, lower = [-0.013, -0.013, 0.026], upper = [0.013, 0.013, 0.093], seed = {seed} }}
material = "glass"

[[wall]]
{wall}
material = "hopper"

[[wall]]                                        # the plug: drops to z = −39 mm in 10 ms
plane = {{ point = [0.0, 0.0, 0.0], normal = [0.0, 0.0, 1.0] }}
material = "hopper"
motion = {{ velocity = [0.0, 0.0, -3.9], start = {opened!r}, end = {opened + 0.01!r} }}

[[outlet]]
region = {{ box = {{ lower = [-0.06, -0.06, -0.04], upper = [0.06, 0.06, -0.01] }} }}

[motion]
gravity = [0.0, 0.0, -9.81]

[integration]
scheme = "verlet"
dt = {DT!r}
steps = {steps}

[output]
every = {settle}                                 # a snapshot at the opening
series_every = 1250
"""


def wall_entry(r):
    if r is None:
        return f'mesh = {{ file = "{HOPPER}" }}'
    if isinstance(r, tuple):  # ("same outlet", r, STL of the narrowed hopper)
        return f'mesh = {{ file = "{r[2]}" }}'
    return (
        f'boundary_particles = {{ mesh = "{HOPPER}", flip = true, radius_ratio = {r!r}, '
        'modulus_ratio = inf, tiling = "square", reference_radius = 1.0e-3 }'
    )


def label(r):
    if r is None:
        return "mesh"
    if isinstance(r, tuple):
        return f"mesh-outlet-r{r[1]:g}"
    return f"r{r:g}"


def run(binary, scene_path, out, extra):
    cmd = [str(binary), "scene", str(scene_path), "--json", "-q", "--threads", "1",
           "--out", str(out)] + extra
    t0 = time.time()
    p = subprocess.run(cmd, capture_output=True, text=True)
    if p.returncode != 0:
        raise SystemExit(f"{' '.join(cmd)} failed:\n{p.stderr}")
    return json.loads(p.stdout), time.time() - t0


def clear_outlet_radius(vtp: Path):
    """The radius of the opening the fixed spheres leave at the outlet:
    min over them of (distance from the axis − R_b), m."""
    text = vtp.read_text()
    pts = _array(text, "position").reshape(-1, 3)
    rad = _array(text, "radius")
    fixed = _array(text, "fixed") != 0
    return float((np.hypot(pts[fixed, 0], pts[fixed, 1]) - rad[fixed]).min())


def narrowed_hopper(outlet: float, path: Path):
    """hopper.stl's cone continued below z = 0 down to the radius
    `outlet` (same half-angle, same bin), written by make_hopper.py's
    functions."""
    import importlib.util

    spec = importlib.util.spec_from_file_location("make_hopper", HOPPER.with_name("make_hopper.py"))
    mh = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mh)
    z_out = -(OUTLET_RADIUS - outlet) / math.tan(math.radians(30.0))

    def profile(rings_cone, rings_bin):
        out = []
        for k in range(rings_cone + 1):
            f = k / rings_cone
            out.append((outlet + f * (TOP_RADIUS - outlet), z_out + f * (CONE_HEIGHT - z_out)))
        for k in range(1, rings_bin + 1):
            out.append((TOP_RADIUS, CONE_HEIGHT + k / rings_bin * mh.BIN_HEIGHT))
        return out

    mh.profile = profile
    mh.write_binary_stl(path, mh.hopper(48), 48)


def read_positions(vtp: Path):
    """Centres and radii of the free spheres of a snapshot (dembound's
    snapshot_*.vtp: base64 arrays, each after a UInt64 byte count)."""
    text = vtp.read_text()
    pts = _array(text, "position").reshape(-1, 3)
    rad = _array(text, "radius")
    free = _array(text, "fixed") == 0
    return pts[free], rad[free]


TYPES = {"Float64": "<f8", "Float32": "<f4", "UInt8": "u1", "Int32": "<i4",
         "UInt32": "<u4", "Int64": "<i8", "UInt64": "<u8"}


def _array(text, name):
    m = re.search(rf'<DataArray type="(\w+)" Name="{name}"[^>]*>(.*?)</DataArray>', text, re.S)
    if m is None:
        raise SystemExit(f"no {name} array in the snapshot")
    raw = base64.b64decode(m.group(2).strip())
    count = struct.unpack("<Q", raw[:8])[0]
    return np.frombuffer(raw[8:8 + count], dtype=TYPES[m.group(1)]).astype(float)


def steady_rate(series: Path, t0: float, t1: float):
    """Mean mass flow rate over [t0, t1], kg/s, from series.csv's
    outlet0_mass_kg, and its standard error from 5 batch means (the rate
    fluctuates on the time scale of a few rows, so the rows' own scatter
    would understate it)."""
    rows = list(csv.DictReader(series.open()))
    t = np.array([float(r["time_s"]) for r in rows])
    m = np.array([float(r["outlet0_mass_kg"]) for r in rows])
    keep = (t >= t0 - 1e-12) & (t <= t1 + 1e-12)
    t, m = t[keep], m[keep]
    if len(t) < 6:
        raise SystemExit(f"{series}: too few rows in [{t0}, {t1}] s")
    rate = (m[-1] - m[0]) / (t[-1] - t[0])
    edges = np.linspace(0, len(t) - 1, 6).round().astype(int)
    batches = [(m[b] - m[a]) / (t[b] - t[a]) for a, b in zip(edges[:-1], edges[1:])]
    return float(rate), float(np.std(batches, ddof=1) / math.sqrt(len(batches)))


def wall_packing(pts, rad, rng):
    """Solid fraction of the shell of thickness 2 mm inside the cone
    (distance to the cone's surface along its normal), 6 mm ≤ z ≤ 16 mm."""
    t = 2.0e-3
    z0, z1 = 6.0e-3, 16.0e-3
    tan30 = math.tan(math.radians(30.0))
    cos30 = math.cos(math.radians(30.0))
    n = 200_000
    z = rng.uniform(z0, z1, n)
    radial_wall = OUTLET_RADIUS + z * tan30
    # Horizontal depth inside the surface for a normal distance u: u / cos30.
    u = rng.uniform(0.0, t, n)
    rho = radial_wall - u / cos30
    phi = rng.uniform(0.0, 2 * math.pi, n)
    # Uniform in volume: weight ∝ rho (accept-reject).
    keep = rng.uniform(0.0, 1.0, n) < rho / radial_wall
    z, rho, phi = z[keep], rho[keep], phi[keep]
    q = np.stack([rho * np.cos(phi), rho * np.sin(phi), z], axis=1)
    order = np.argsort(q[:, 2])
    q = q[order]
    inside = np.zeros(len(q), dtype=bool)
    for c, r in zip(pts, rad):
        a, b = np.searchsorted(q[:, 2], [c[2] - r, c[2] + r])
        if a < b:
            d2 = ((q[a:b] - c) ** 2).sum(axis=1)
            inside[a:b] |= d2 <= r * r
    frac = inside.mean()
    return float(frac), float(math.sqrt(frac * (1 - frac) / len(q)))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--dembound", default=str(ROOT / "target" / "release" / "dembound"))
    ap.add_argument("--work", default="/tmp/hopper-particle-walls")
    ap.add_argument("--ratios", default="0.5,1,2")
    ap.add_argument("--settle", type=float, default=0.3, help="s")
    ap.add_argument("--discharge", type=float, default=0.3, help="s")
    ap.add_argument("--skip", type=float, default=0.05,
                    help="s after the opening left out of the rate (the flow's start)")
    ap.add_argument("--seeds", default="1,2")
    ap.add_argument("--same-outlet", action="store_true",
                    help="also run mesh walls narrowed to each particle wall's clear outlet")
    ap.add_argument("--jobs", type=int, default=2, help="runs at once")
    ap.add_argument("--friction", type=float, default=0.0,
                    help="Coulomb μ of every surface (contact.friction); 0: frictionless")
    a = ap.parse_args()
    if not 0.0 <= a.friction <= 10.0:
        ap.error(f"--friction {a.friction}: must be in [0, 10] (contact.friction's range)")
    work = Path(a.work)
    work.mkdir(parents=True, exist_ok=True)
    settle = round(a.settle / DT)
    total = settle + round(a.discharge / DT)
    walls = [None] + [float(r) for r in a.ratios.split(",")]
    seeds = [int(s) for s in a.seeds.split(",")]
    rng = np.random.default_rng(29)

    def one(task):
        r, seed = task
        name = label(r)
        d = work / f"{name}-s{seed}"
        d.mkdir(exist_ok=True)
        path = d / "scene.toml"
        text = scene(wall_entry(r), total, settle, seed, a.friction)
        kept = d / "summary.json"
        if kept.exists() and path.exists() and path.read_text() == text:
            j = json.loads(kept.read_text())  # this run is done (same scene)
            seconds = j["run_seconds"]
        else:
            path.write_text(text)
            j, seconds = run(a.dembound, path, d / "out", [])
            j["run_seconds"] = seconds
            kept.write_text(json.dumps(j))
        rate, error = steady_rate(d / "out" / "series.csv", settle * DT + a.skip, total * DT)
        print(f"{name} seed {seed}: {rate:.5g} ± {error:.2g} kg/s, "
              f"{j['fixed_particles']} wall spheres, {seconds:.0f} s", flush=True)
        return dict(spheres=j["fixed_particles"], rate=rate, error=error, seconds=seconds)

    tasks = [(r, seed) for r in walls for seed in seeds]
    with ThreadPoolExecutor(max_workers=a.jobs) as pool:
        done = dict(zip(tasks, pool.map(one, tasks)))
    if a.same_outlet:
        # Mesh walls whose outlet is the particle walls' clear opening: the
        # rate change the narrower outlet alone makes.
        more = []
        for r in walls[1:]:
            clear = clear_outlet_radius(work / f"r{r:g}-s{seeds[0]}" / "out" / "snapshot_000000.vtp")
            stl = work / f"hopper_outlet_r{r:g}.stl"
            narrowed_hopper(clear, stl)
            more.append(("same outlet", r, stl, clear))
        tasks = [(m[:3], seed) for m in more for seed in seeds]
        with ThreadPoolExecutor(max_workers=a.jobs) as pool:
            done.update(dict(zip(tasks, pool.map(one, tasks))))
        walls = walls + [m[:3] for m in more]
        clears = {m[1]: m[3] for m in more}
    results = []
    for r in walls:
        name = label(r)
        runs = [done[(r, seed)] for seed in seeds]
        # The packing at the wall in the settled bed (the snapshot at the
        # opening), each seed's.
        packs = [wall_packing(*read_positions(work / f"{name}-s{seed}" / "out" / f"snapshot_{1:06d}.vtp"), rng)
                 for seed in seeds]
        rates = [x["rate"] for x in runs]
        errors = [x["error"] for x in runs]
        rate = float(np.mean(rates))
        err = float(math.sqrt(sum(e * e for e in errors)) / len(errors))
        if len(rates) > 1:
            err = max(err, float(np.std(rates, ddof=1) / math.sqrt(len(rates))))
        pack = float(np.mean([p for p, _ in packs]))
        pack_err = float(math.sqrt(sum(e * e for _, e in packs)) / len(packs))
        if len(packs) > 1:
            pack_err = max(pack_err, float(np.std([p for p, _ in packs], ddof=1) / math.sqrt(len(packs))))
        kind = "mesh" if r is None else ("mesh, same outlet" if isinstance(r, tuple) else "particles")
        rnum = r[1] if isinstance(r, tuple) else r
        if r is None:
            outlet = OUTLET_RADIUS
        elif isinstance(r, tuple):
            outlet = clears[r[1]]
        else:
            outlet = clear_outlet_radius(work / f"{name}-s{seeds[0]}" / "out" / "snapshot_000000.vtp")
        results.append(dict(wall=name, kind=kind, outlet_radius=outlet, r=rnum, spheres=runs[0]["spheres"], rate=rate, rate_error=err,
                            packing=pack, packing_error=pack_err,
                            run_seconds=float(np.mean([x["seconds"] for x in runs])),
                            rates=rates, rate_errors=errors, packings=[p for p, _ in packs]))
    ref = results[0]
    lines = ["| wall | r | wall spheres | clear outlet radius (mm) | rate (kg/s) | vs mesh | "
             "packing at the wall | vs mesh | run time per seed (s) |",
             "|---|---|---|---|---|---|---|---|---|"]
    for x in results:
        dr = x["rate"] / ref["rate"] - 1
        dp = x["packing"] / ref["packing"] - 1
        rtext = "—" if x["r"] is None else f"{x['r']:g}"
        lines.append(
            f"| {x['kind']} | {rtext} | {x['spheres']} | {1e3 * x['outlet_radius']:.2f} | "
            f"{x['rate']:.4g} ± {x['rate_error']:.2g} | {100 * dr:+.1f} % | "
            f"{x['packing']:.3f} ± {x['packing_error']:.3f} | {100 * dp:+.1f} % | {x['run_seconds']:.0f} |")
    table = "\n".join(lines)
    print(table)
    (work / "table.md").write_text(table + "\n")
    (work / "results.json").write_text(json.dumps(results, indent=1))
    plot(results, work / "hopper_particle_walls.png", a.friction)


def plot(results, path, friction=0.0):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import matplotlib.ticker

    ref = results[0]
    parts = [x for x in results if x["kind"] == "particles"]
    same = [x for x in results if x["kind"] == "mesh, same outlet"]
    fig, ax = plt.subplots(1, 2, figsize=(9.5, 3.8))
    ax[0].errorbar([x["r"] for x in parts], [1e3 * x["rate"] for x in parts],
                   yerr=[1e3 * x["rate_error"] for x in parts], fmt="o", label="particle wall")
    if same:
        ax[0].errorbar([x["r"] for x in same], [1e3 * x["rate"] for x in same],
                       yerr=[1e3 * x["rate_error"] for x in same], fmt="s", mfc="none",
                       label="mesh wall, the particle wall's clear outlet")
    ax[0].axhline(1e3 * ref["rate"], color="k", label="mesh wall")
    ax[0].axhspan(1e3 * ref["rate"] * 0.97, 1e3 * ref["rate"] * 1.03, color="0.85",
                  label="mesh wall ± 3 %")
    ax[0].set_xscale("log")
    ax[0].set_xlabel("r = R_b / R (–)")
    ax[0].set_ylabel("discharge rate (g/s)")
    ax[0].legend(fontsize=8)
    ax[1].errorbar([x["r"] for x in parts], [x["packing"] for x in parts],
                   yerr=[x["packing_error"] for x in parts], fmt="o", label="particle wall")
    if same:
        ax[1].errorbar([x["r"] for x in same], [x["packing"] for x in same],
                       yerr=[x["packing_error"] for x in same], fmt="s", mfc="none",
                       label="mesh wall, the particle wall's clear outlet")
    ax[1].axhline(ref["packing"], color="k", label="mesh wall")
    ax[1].axhspan(ref["packing"] * 0.97, ref["packing"] * 1.03, color="0.85",
                  label="mesh wall ± 3 %")
    ax[1].set_xscale("log")
    ax[1].set_xlabel("r = R_b / R (–)")
    ax[1].set_ylabel("solid fraction within 2 mm of the cone (–)")
    ax[1].legend(fontsize=8)
    for axis in ax:
        axis.set_xticks([x["r"] for x in parts])
        axis.xaxis.set_major_formatter(matplotlib.ticker.ScalarFormatter())
        axis.xaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
    grains = f"μ = {friction:g} on every surface" if friction > 0 else "frictionless grains"
    fig.suptitle(f"Hopper discharge: particle walls (ζ = ∞) against the mesh wall, {grains}")
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    print(f"wrote {path}")


if __name__ == "__main__":
    main()
