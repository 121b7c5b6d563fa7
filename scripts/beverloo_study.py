#!/usr/bin/env python3
"""Beverloo's discharge law in dembound, with LIGGGHTS side by side (issues
28 and 30): a flat-bottomed silo (examples/scenes/make_silo.py) emptied
through four circular orifices; the steady mass flow rate W of each, and
the fit of Beverloo, Leniger & van de Velde (1961),

    W = C ρ_b √g (D − k d)^{5/2},

with ρ_b the bed's measured bulk density and d the mean sphere diameter.
W^{2/5} is linear in D: its least-squares line gives slope s and intercept
b, so C = s^{5/2}/(ρ_b √g) and k = −b/(s d).

    python3 scripts/beverloo_study.py [--orifices 10 12 14 16] [--work DIR]
        [--liggghts 10 14 | --liggghts none] [--figure beverloo.png] [--jobs 2]
        [--fill lattice|inlet]

Rate: the least-squares slope of the discharged mass (series.csv
outlet0_mass_kg; LIGGGHTS: the mass of the spheres whose centre is below
z = −20 mm, the outlet box's top) against time over the window
[--from, the run's end]; its error the standard deviation of the slopes of
four equal sub-windows over √4. Bulk density: the spheres whose centres lie
in the core r < 15 mm, 5 mm < z < 25 mm of the settled bed (the snapshot at
the gate's opening, 0.1 s), their mass over the core's volume.
LIGGGHTS runs the deck of `dembound export liggghts` of the same scene
without tube, gate and outlet (the export refuses them), completed here:
the tube a zcylinder primitive, the gate a zplane removed by `unfix` at the
opening, the fallen spheres left on the floor 40 mm below (counted, not
deleted). Runs already in --work are reused. Needs matplotlib for the
figure (rate against time, rate against D with the fit).

`--friction MU`: the same scenes with the sliding friction μ (grains and
walls: the scene's one `[contact] friction`) set to MU instead of 0.5, a
variant for the question whether the grains' friction sets C.

The bulk density of the flowing bed: the same core averaged over the
snapshots inside the window (every 0.1 s), and the cylinder r < D/2,
0 < z < D/2 just above the orifice; printed beside ρ_b (Beverloo's ρ_b
is the bed's bulk density; these show how much looser the flowing bed is).

`--fill inlet`: the silo of `make_silo.py --fill inlet`, filled by an
`[[inlet]]` until 0.124 s, the gate opening at 0.3 s, the run ending at
0.65 s (window from 0.4 s). The export refuses inlets, so the LIGGGHTS
deck is exported from the scene without the inlet and with one placeholder
sphere (r = 0.9 mm: the export's neighbour skin, 0.2 of the smallest
radius, is the inlet's), which is then taken out of particles.data; the
script adds the insertion: `fix particletemplate/sphere` per radius of a
discrete approximation of the uniform radii (LIGGGHTS has no uniform
radius distribution), `fix particledistribution/discrete/numberbased`
with equal fractions, `fix insert/rate/region` with the same cylinder,
number rate, interval, count and velocity (`all_in yes`: wholly inside,
as dembound places them).
"""

import argparse
import base64
import csv
import math
import random
import re
import statistics
import struct
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path
from typing import NamedTuple

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "examples/scenes"))
import make_silo as silo  # noqa: E402  (the scene's constants: one source)
G = 9.81  # m/s²
DENSITY = 2500.0  # kg/m³ (make_silo.py's glass)
MEAN_DIAMETER = 2.0e-3  # m: radii uniform in [0.9, 1.1] mm
DT = 2.0e-5  # s
CORE_RADIUS, CORE_Z = 15.0e-3, (5.0e-3, 25.0e-3)  # m
OUTLET_TOP = -0.02  # m
# Published ranges (see docs/beverloo.md for the sources).
C_RANGE = (0.55, 0.65)
K_RANGE = (1.0, 3.0)


class Fill(NamedTuple):
    """How the silo is filled (make_silo.py --fill) and the run's times."""

    name: str
    gate_step: int  # the gate's opening / Δt
    steps: int
    tag: str  # in file names: silo{tag}_D<mm>.toml

    @property
    def gate_open(self):
        return self.gate_step * DT

    @property
    def end(self):
        return self.steps * DT


FILLS = {
    "lattice": Fill("lattice", round(silo.GATE_OPEN / DT), 22500, ""),
    "inlet": Fill("inlet", round(silo.INLET_GATE_OPEN / DT), silo.INLET_STEPS, "_inlet"),
}
RADIUS_MIN, RADIUS_MAX = silo.RADIUS_MIN, silo.RADIUS_MAX  # m
TEMPLATES = 11  # radii of the discrete approximation in LIGGGHTS


def vtp_arrays(path):
    """{name: list of numbers} of the binary DataArrays of a .vtp."""
    text = Path(path).read_text()
    out = {}
    for m in re.finditer(
        r'<DataArray type="(\w+)" Name="(\w+)"[^>]*format="binary">([^<]*)</DataArray>', text
    ):
        kind, name, data = m.groups()
        fmt = {"Float64": "d", "UInt64": "Q", "Int64": "q", "Int32": "i", "UInt32": "I"}.get(kind)
        if fmt is None:
            continue
        raw = base64.b64decode(data)
        (n,) = struct.unpack("<Q", raw[:8])
        out[name] = list(struct.unpack(f"<{n // struct.calcsize(fmt)}{fmt}", raw[8 : 8 + n]))
    return out


def run(cmd, cwd=None):
    done = subprocess.run(cmd, cwd=cwd, capture_output=True, text=True)
    if done.returncode != 0:
        sys.exit(f"failed: {' '.join(map(str, cmd))}\n{done.stderr}{done.stdout[-2000:]}")


def scene_dir(work, mm, fill, seed=1):
    run([sys.executable, ROOT / "examples/scenes/make_silo.py", "--orifice", f"{mm * 1e-3}", "--out", work,
         "--seed", str(seed), "--fill", fill.name])
    return work / f"silo{fill.tag}_D{mm:g}.toml"


def set_friction(toml, mu):
    """The scene at `toml` with its one `[contact] friction` set to mu."""
    text = toml.read_text()
    line = "friction = 0.5\n"
    if text.count(line) != 1:
        sys.exit(f"{toml}: expected one '{line.strip()}' line")
    toml.write_text(text.replace(line, f"friction = {mu!r}\n"))


def run_dembound(exe, work, mm, fill):
    out = work / f"dembound{fill.tag}_D{mm:g}"
    if not (out / "series.csv").exists():
        run([exe, "scene", work / f"silo{fill.tag}_D{mm:g}.toml", "--out", out, "--quiet", "--threads", "1"])
    return out


def primes_above(n, count):
    """The `count` primes above n (LIGGGHTS's seeds: primes > 10000)."""
    out, k = [], n + 1
    while len(out) < count:
        if all(k % q for q in range(2, math.isqrt(k) + 1)):
            out.append(k)
        k += 1
    return out


def template_radii(n=TEMPLATES):
    """The midpoints of n equal bins of [RADIUS_MIN, RADIUS_MAX]: equal
    fractions by number approximate the uniform distribution (mean exact,
    variance short by 1/n², E[R³] short by 3 σ²/n² / E[R³])."""
    w = (RADIUS_MAX - RADIUS_MIN) / n
    return [RADIUS_MIN + (i + 0.5) * w for i in range(n)]


def liggghts_insertion(seed):
    """The commands that pour make_silo.py's inlet in LIGGGHTS."""
    radii = template_radii()
    seeds = primes_above(10000 + 1000 * seed, len(radii) + 2)
    lines = ["# The inlet of make_silo.py --fill inlet: radii uniform in [0.9, 1.1] mm as "
             f"{len(radii)} equal-number bins' midpoints."]
    for k, r in enumerate(radii):
        lines.append(f"fix          pts{k} all particletemplate/sphere {seeds[k]} atom_type 1 "
                     f"density constant {DENSITY:g} radius constant {r:.9g}")
    fractions = [round(1.0 / len(radii), 12)] * (len(radii) - 1)
    fractions.append(1.0 - sum(fractions))  # the sum exactly 1
    pairs = " ".join(f"pts{k} {f:.12g}" for k, f in enumerate(fractions))
    lines.append(f"fix          pdd all particledistribution/discrete/numberbased {seeds[-2]} {len(radii)} {pairs}")
    z0, z1 = silo.INLET_Z
    lines.append(f"region       inlet cylinder z 0 0 {silo.INLET_RADIUS:g} {z0:g} {z1:g} units box")
    lines.append(f"fix          ins all insert/rate/region seed {seeds[-1]} distributiontemplate pdd "
                 f"nparticles {silo.INLET_COUNT} particlerate {silo.INLET_RATE:g} insert_every {silo.INLET_EVERY} "
                 f"overlapcheck yes all_in yes vel constant 0 0 {-silo.INLET_SPEED:g} region inlet ntry_mc 10000")
    return "\n".join(lines) + "\n"


def export_scene(work, mm, fill):
    """The scene without tube, gate, outlet and inlet (the export refuses
    them); for the inlet fill with one placeholder sphere (module doc)."""
    scene = (work / f"silo{fill.tag}_D{mm:g}.toml").read_text()
    i, j = scene.index("[[wall]]\ncylinder"), scene.index("[[wall]]\nmesh")
    scene = scene[:i] + scene[j:]
    i, j = scene.index("# The gate:"), scene.index("[[wall]]\nplane = { point = [0.0, 0.0, -0.04]")
    scene = scene[:i] + scene[j:]
    scene = scene[: scene.index("# Removes what")] + scene[scene.index("[motion]") :]
    if fill.name == "inlet":
        i, j = scene.index("# The fill:"), scene.index("[[wall]]\nmesh")
        (work / "placeholder.csv").write_text(f"x,y,z,radius\n0,0,-0.03,{RADIUS_MIN}\n")
        scene = scene[:i] + '[[particles]]\ncsv = "placeholder.csv"\nmaterial = "glass"\n\n' + scene[j:]
    bare = work / f"silo{fill.tag}_D{mm:g}_export.toml"
    bare.write_text(scene)
    return bare


def drop_placeholder(data):
    """particles.data without its one atom (and its velocity)."""
    text = data.read_text()
    assert "\n1 atoms\n" in text, "the placeholder scene exports one atom"
    text = text.replace("\n1 atoms\n", "\n0 atoms\n")
    data.write_text(text[: text.index("\nAtoms\n")] + "\n")


def liggghts_deck(exe, work, mm, fill, seed):
    """The exported deck, completed with tube, gate, inlet and the discharged-mass print."""
    bare = export_scene(work, mm, fill)
    deck = work / f"liggghts{fill.tag}_D{mm:g}"
    run([exe, "export", "liggghts", bare, "--out", deck])
    if fill.name == "inlet":
        drop_placeholder(deck / "particles.data")
    text = (deck / "in.liggghts").read_text()
    # Drop the per-step trace and the full dumps (not needed, slow); end before the run.
    text = re.sub(r"\n# trajectory\.txt.*?screen no\n", "\n", text, flags=re.S)
    text = re.sub(r"\n# particles\.dump.*?%.17g\"\n", "\n", text, flags=re.S)
    text = text[: text.index("thermo_style")]
    if fill.name == "inlet":
        text += "\n" + liggghts_insertion(seed)
    text += f"""
# Completed by scripts/beverloo_study.py: the tube, the gate, the discharged mass.
fix          tube all wall/gran model hertz tangential history primitive type 2 zcylinder 0.018 0 0 tangential_damping off limitForce on
fix          gate all wall/gran model hertz tangential history primitive type 2 zplane 0 tangential_damping off limitForce on
region       below block INF INF INF INF INF {OUTLET_TOP} units box
variable     t equal step*dt
variable     mout equal mass(all,below)
fix          discharged all print 250 "${{t}} ${{mout}}" file discharged.txt title "# time_s discharged_mass_kg" screen no
thermo_style custom step time ke
thermo_modify norm no format float %.17g
thermo       2500
run          {fill.gate_step}
unfix        gate
run          {fill.steps - fill.gate_step}
"""
    (deck / "in.liggghts").write_text(text)
    return deck


def run_liggghts(exe, work, mm, fill, seed):
    deck = work / f"liggghts{fill.tag}_D{mm:g}"
    if not (deck / "done").exists():
        deck = liggghts_deck(exe, work, mm, fill, seed)
        run(["liggghts", "-in", "in.liggghts", "-log", "log.liggghts"], cwd=deck)
        (deck / "done").write_text("")
    return deck


def dembound_series(out):
    with open(out / "series.csv") as f:
        rows = list(csv.DictReader(f))
    return [float(r["time_s"]) for r in rows], [float(r["outlet0_mass_kg"]) for r in rows]


def liggghts_series(deck):
    t, m = [], []
    for line in (deck / "discharged.txt").read_text().splitlines():
        if line.startswith("#") or not line.strip():
            continue
        a, b = line.split()[:2]
        t.append(float(a))
        m.append(float(b))
    return t, m


def slope(t, m):
    n = len(t)
    tm, mm = sum(t) / n, sum(m) / n
    return sum((a - tm) * (b - mm) for a, b in zip(t, m)) / sum((a - tm) ** 2 for a in t)


def steady_rate(t, m, start):
    """(rate kg/s, standard error kg/s) over t ≥ start."""
    pts = [(a, b) for a, b in zip(t, m) if a >= start - 1e-12]
    ts, ms = [p[0] for p in pts], [p[1] for p in pts]
    whole = slope(ts, ms)
    q = len(ts) // 4
    parts = [slope(ts[k * q : (k + 1) * q + 1], ms[k * q : (k + 1) * q + 1]) for k in range(4)]
    mean = sum(parts) / 4
    sd = math.sqrt(sum((p - mean) ** 2 for p in parts) / 3)
    return whole, sd / 2.0


def bulk_density(out, gate_step):
    """ρ_b (kg/m³) of the core of the bed at the gate's opening, and the bed's top (m)."""
    for vtp in sorted(out.glob("snapshot_*.vtp")):
        a = vtp_arrays(vtp)
        if a.get("STEP", [None])[0] == gate_step:
            break
    else:
        sys.exit(f"{out}: no snapshot at step {gate_step}")
    pos, radius = a["position"], a["radius"]
    mass, zs = 0.0, []
    for i, r in enumerate(radius):
        x, y, z = pos[3 * i : 3 * i + 3]
        zs.append(z)
        if math.hypot(x, y) < CORE_RADIUS and CORE_Z[0] < z < CORE_Z[1]:
            mass += DENSITY * 4.0 / 3.0 * math.pi * r**3
    zs.sort()
    top = zs[int(0.99 * len(zs))]
    return mass / (math.pi * CORE_RADIUS**2 * (CORE_Z[1] - CORE_Z[0])), top


def flowing_densities(out, from_step, orifice):
    """(core, above the orifice) densities (kg/m³) averaged over the
    snapshots at or after `from_step`: the core of `bulk_density`, and the
    cylinder r < D/2, 0 < z < D/2."""
    cores, holes = [], []
    for vtp in sorted(out.glob("snapshot_*.vtp")):
        a = vtp_arrays(vtp)
        if a.get("STEP", [-1])[0] < from_step:
            continue
        pos, radius = a["position"], a["radius"]
        core = hole = 0.0
        for i, r in enumerate(radius):
            x, y, z = pos[3 * i : 3 * i + 3]
            m = DENSITY * 4.0 / 3.0 * math.pi * r**3
            if math.hypot(x, y) < CORE_RADIUS and CORE_Z[0] < z < CORE_Z[1]:
                core += m
            if math.hypot(x, y) < orifice / 2 and 0.0 < z < orifice / 2:
                hole += m
        cores.append(core / (math.pi * CORE_RADIUS**2 * (CORE_Z[1] - CORE_Z[0])))
        holes.append(hole / (math.pi * (orifice / 2) ** 2 * orifice / 2))
    if not cores:
        sys.exit(f"{out}: no snapshot in the window")
    return sum(cores) / len(cores), sum(holes) / len(holes), len(cores)


def fit(ds, ws, rho_b, d=MEAN_DIAMETER):
    """(C, k) of W = C ρ_b √g (D − k d)^{5/2} by the line through (D, W^{2/5})."""
    ys = [w**0.4 for w in ws]
    s = slope(ds, ys)
    b = sum(ys) / len(ys) - s * sum(ds) / len(ds)
    return s**2.5 / (rho_b * math.sqrt(G)), -b / (s * d)


def beverloo(D, C, k, rho_b, d=MEAN_DIAMETER):
    return C * rho_b * math.sqrt(G) * max(D - k * d, 0.0) ** 2.5


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--orifices", type=float, nargs="+", default=[10, 12, 14, 16], help="D, mm")
    p.add_argument("--liggghts", nargs="+", default=["10", "14"], help="orifices (mm) run in LIGGGHTS, or none")
    p.add_argument("--work", type=Path, default=Path("/tmp/beverloo-study"))
    p.add_argument("--dembound", default=str(ROOT / "target/release/dembound"))
    p.add_argument("--from", dest="start", type=float,
                   help="start of the measured window, s (default: 0.1 s after the gate's opening)")
    p.add_argument("--jobs", type=int, default=2)
    p.add_argument("--seed", type=int, default=1, help="seed of the fill (make_silo.py --seed)")
    p.add_argument("--figure", type=Path)
    p.add_argument("--fill", choices=sorted(FILLS), default="lattice",
                   help="the silo's fill (make_silo.py --fill): a lattice at the start or an inlet")
    p.add_argument("--friction", type=float,
                   help="sliding friction μ of grains and walls instead of the scene's 0.5 (a variant)")
    a = p.parse_args()
    if a.friction is not None and (not math.isfinite(a.friction) or a.friction < 0.0):
        sys.exit(f"--friction: {a.friction} is not a friction coefficient (finite, ≥ 0)")
    fill = FILLS[a.fill]
    if a.start is None:
        a.start = fill.gate_open + 0.1
    a.work.mkdir(parents=True, exist_ok=True)
    lig = [] if a.liggghts == ["none"] else [float(x) for x in a.liggghts]
    for mm in sorted(set(a.orifices) | set(lig)):  # all files first: the runs share silo_spheres.csv
        toml = scene_dir(a.work, mm, fill, a.seed)
        if a.friction is not None:
            set_friction(toml, a.friction)
    with ThreadPoolExecutor(a.jobs) as pool:
        dem = {mm: pool.submit(run_dembound, a.dembound, a.work, mm, fill) for mm in a.orifices}
        ligj = {mm: pool.submit(run_liggghts, a.dembound, a.work, mm, fill, a.seed) for mm in lig}
        dem = {mm: f.result() for mm, f in dem.items()}
        ligj = {mm: f.result() for mm, f in ligj.items()}

    print(f"fill: {fill.name}; window {a.start:.2f}–{fill.end:.2f} s; gate opened at {fill.gate_open:g} s; "
          f"d = 2 mm ± 10 %, μ = {0.5 if a.friction is None else a.friction:g}")
    print("| D (mm) | D/d | ρ_b (kg/m³) | bed top at opening (mm) | W dembound (g/s) | W LIGGGHTS (g/s) | LIGGGHTS/dembound − 1 |")
    print("|---|---|---|---|---|---|---|")
    ws, es, rhos, series, flows = [], [], [], {}, []
    for mm in a.orifices:
        rho_b, top = bulk_density(dem[mm], fill.gate_step)
        t, m = dembound_series(dem[mm])
        w, e = steady_rate(t, m, a.start)
        ws.append(w)
        es.append(e)
        rhos.append(rho_b)
        flows.append((mm, *flowing_densities(dem[mm], round(a.start / DT), mm * 1e-3)))
        series[mm] = (t, m, None)
        lcell, rel = "—", "—"
        if mm in ligj:
            tl, ml = liggghts_series(ligj[mm])
            wl, el = steady_rate(tl, ml, a.start)
            series[mm] = (t, m, (tl, ml))
            lcell, rel = f"{1e3 * wl:.2f} ± {1e3 * el:.2f}", f"{wl / w - 1:+.1%}"
        print(f"| {mm:g} | {mm / 2:.1f} | {rho_b:.0f} | {1e3 * top:.1f} | {1e3 * w:.2f} ± {1e3 * e:.2f} | {lcell} | {rel} |")
    rho_b = sum(rhos) / len(rhos)
    for mm, core, hole, n in flows:
        print(f"D = {mm:g} mm, flowing ({n} snapshots from {a.start:g} s): core {core:.0f} kg/m³, "
              f"r < D/2, 0 < z < D/2: {hole:.0f} kg/m³")
    flow_core = sum(f[1] for f in flows) / len(flows)
    print(f"flowing core: {flow_core:.0f} kg/m³, {flow_core / rho_b - 1:+.1%} against ρ_b")
    ds = [mm * 1e-3 for mm in a.orifices]
    if len(set(ds)) < 2:
        # One orifice (a seed comparison with LIGGGHTS): no line to fit.
        print(f"\nρ_b = {rho_b:.0f} kg/m³; one orifice: no Beverloo fit (give two or more)")
        return
    C, k = fit(ds, ws, rho_b)
    # Spread of (C, k) from the rates' standard errors: refits of 2000 draws.
    rng = random.Random(1)
    draws = [fit(ds, [max(w + rng.gauss(0.0, e), 1e-9) for w, e in zip(ws, es)], rho_b) for _ in range(2000)]
    sd_c = statistics.stdev(c for c, _ in draws)
    sd_k = statistics.stdev(q for _, q in draws)
    print(f"\nρ_b = {rho_b:.0f} kg/m³ (mean of the runs; solid fraction {rho_b / DENSITY:.3f})")
    print(f"Beverloo fit: C = {C:.3f} ± {sd_c:.3f} (published {C_RANGE[0]}–{C_RANGE[1]}), "
          f"k = {k:.2f} ± {sd_k:.2f} (published {K_RANGE[0]:g}–{K_RANGE[1]:g}); ± from the rates' errors")
    # With k fixed at the commonly quoted 1.5, C alone (least squares in W).
    fk = [beverloo(D, 1.0, 1.5, rho_b) for D in ds]
    c15 = sum(w * f for w, f in zip(ws, fk)) / sum(f * f for f in fk)
    print(f"with k = 1.5 fixed: C = {c15:.3f}")
    fk = [beverloo(D, 1.0, 1.4, rho_b) for D in ds]
    print(f"with k = 1.4 fixed: C = {sum(w * f for w, f in zip(ws, fk)) / sum(f * f for f in fk):.3f}")
    print(f"with the flowing core's density for ρ_b: C = {C * rho_b / flow_core:.3f}")
    for D, w in zip(ds, ws):
        print(f"  D = {1e3 * D:g} mm: W = {1e3 * w:.2f} g/s, fit {1e3 * beverloo(D, C, k, rho_b):.2f} g/s, "
              f"C = 0.58, k = 1.5: {1e3 * beverloo(D, 0.58, 1.5, rho_b):.2f} g/s")
    if a.figure:
        figure(a.figure, series, ds, ws, C, k, rho_b, a.start, fill)


def figure(path, series, ds, ws, C, k, rho_b, start, fill):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 4.2))
    for mm, (t, m, lig) in series.items():
        rate = [1e3 * (m[i] - m[i - 1]) / (t[i] - t[i - 1]) for i in range(1, len(t))]
        line = ax1.plot(t[1:], rate, label=f"D = {mm:g} mm")[0]
        if lig:
            tl, ml = lig
            rl = [1e3 * (ml[i] - ml[i - 1]) / (tl[i] - tl[i - 1]) for i in range(1, len(tl))]
            ax1.plot(tl[1:], rl, "--", color=line.get_color(), label=f"D = {mm:g} mm, LIGGGHTS")
    ax1.axvline(fill.gate_open, color="grey", lw=0.8)
    ax1.axvspan(start, fill.end, color="grey", alpha=0.12, label="measured window")
    if fill.name == "inlet":  # nothing flows out while the bed is poured and settles
        ax1.set_xlim(fill.gate_open - 0.05, fill.end)
    ax1.set_xlabel("time t (s)")
    ax1.set_ylabel("mass flow rate W (g/s), 5 ms bins")
    ax1.set_title(f"rate against time ({fill.name} fill; gate opens at {fill.gate_open:g} s)")
    ax1.legend(fontsize=7)
    Dline = [ds[0] * 0.8 + i * (ds[-1] * 1.1 - ds[0] * 0.8) / 100 for i in range(101)]
    ax2.plot([1e3 * D for D in ds], [1e3 * w for w in ws], "o", label="dembound")
    for mm, (t, m, lig) in series.items():
        if lig:
            wl, _ = steady_rate(lig[0], lig[1], start)
            ax2.plot(mm, 1e3 * wl, "x", color="k", label="LIGGGHTS" if mm == min(x for x in series if series[x][2]) else None)
    ax2.plot([1e3 * D for D in Dline], [1e3 * beverloo(D, C, k, rho_b) for D in Dline], "-",
             label=f"fit: C = {C:.3f}, k = {k:.2f}")
    ax2.plot([1e3 * D for D in Dline], [1e3 * beverloo(D, 0.58, 1.5, rho_b) for D in Dline], ":",
             label="C = 0.58, k = 1.5")
    ax2.set_xlabel("orifice diameter D (mm)")
    ax2.set_ylabel("steady mass flow rate W (g/s)")
    ax2.set_title(f"Beverloo: W = C ρ_b √g (D − k d)^5/2, ρ_b = {rho_b:.0f} kg/m³")
    ax2.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    print(f"wrote {path}")


if __name__ == "__main__":
    main()
