#!/usr/bin/env python3
"""Statistics over repeated seeds of `dembound compare DECK --json` reports.

One run of a chaotic scene is one realisation: its late-window standard
error measures the rattle of that packing, not the spread between
packings. This script takes the reports of N decks of one scene and one
peer code, each exported with another seed (or a perturbation that chaos
amplifies), and puts the two codes' late-window means side by side as a
mean over the seeds with its standard error (sample standard deviation
over sqrt(N)); the differences are paired by seed (the two runs of a
seed start from the same spheres), mean ± SE of the per-seed differences,
with a verdict against issue 32's bars (agree: within the bar, or within
two standard errors of the paired difference, as `compare`'s own verdict):

- bed height and the floor's force (wall[0] |F|): |peer/dembound - 1| <= 1 %;
  every other wall's |F| (side walls) against the same 1 %, and their sum
  (per seed, each code's sum of its side walls' means);
- packing-fraction profile: the largest |delta phi| over the z bins of the
  seed-averaged profiles <= 0.02;
- the flow-velocity profile (a chute): the largest |delta v| (m/s), no bar.

"resolved" says whether twice the combined standard error is below the
bar (else the seeds cannot tell a difference of the bar's size).
Speed: seconds per particle-step and core of each code (mean over the seeds),
by CPU time where the run reports it, else by the peer process's CPU time
where jittered_seeds.py wrote it (REPORT.cpu beside REPORT.json: LIGGGHTS),
else by the wall clock.

Wall forces: each report's `wall_forces` says whether its wall rows are
the force at the row's step ("at_row_step", walls.txt) or the mean over
every step since the previous row ("mean_over_row_interval",
walls_mean.txt); the text output names the kind (and flags a mix).

With --per-seed, each wall's (and the side walls' sum's) per-seed paired
differences are described: their SD, skewness, excess kurtosis, median,
the extreme seeds, the share of the squared deviations the 5 % largest
carry (heavy tails), the two codes' correlation over the seeds and each
code's own seed-to-seed spread, and whether |difference| + 2 SE is within
the bar (the stricter test than 2 SE alone), with the seeds that would
take at this spread; beside the mean, the mean of ln(peer/dembound) (the
ratio's mean is biased up by ~SD^2/2 when the codes are exchangeable) and
the median with its bootstrap SE (docs/export-lammps.md, "A's single side walls").

Usage: compare_seeds.py --label "B pour, Yade" REPORT.json [REPORT.json ...]
       (add --markdown for one table row per quantity, --bins for every
       z bin of the packing and flow-velocity profiles, --quantity NAME for
       another of compare's quantities, e.g. "free spheres in the domain"
       or "discharge rate" of a deck with inlets and outlets, against
       compare's own 1 % bar, --per-seed for the walls' per-seed
       differences)
"""

import argparse
import json
import math
import os
import random
import sys

BARS = {"bed height": 0.01, "wall[0] force |F|": 0.01}
PACKING_BAR = 0.02


def mean_se(values):
    n = len(values)
    m = sum(values) / n
    if n < 2:
        return m, float("nan")
    var = sum((v - m) ** 2 for v in values) / (n - 1)
    return m, math.sqrt(var / n)


def describe(values):
    """Mean, SE, SD, median, skewness and excess kurtosis of `values`."""
    n = len(values)
    m, se = mean_se(values)
    sd = se * math.sqrt(n)
    ordered = sorted(values)
    median = (ordered[(n - 1) // 2] + ordered[n // 2]) / 2
    skew = sum(((v - m) / sd) ** 3 for v in values) / n if sd > 0 else float("nan")
    kurt = sum(((v - m) / sd) ** 4 for v in values) / n - 3 if sd > 0 else float("nan")
    return m, se, sd, median, skew, kurt


def correlation(a, b):
    ma, mb = sum(a) / len(a), sum(b) / len(b)
    cov = sum((x - ma) * (y - mb) for x, y in zip(a, b))
    va = sum((x - ma) ** 2 for x in a)
    vb = sum((y - mb) ** 2 for y in b)
    return cov / math.sqrt(va * vb) if va > 0 and vb > 0 else float("nan")


def per_seed(names, pairs, bar):
    """Prints each wall's per-seed paired differences (`pairs`: name ->
    [(seed label, code mean, dembound mean)])."""
    for name in names:
        got = pairs.get(name)
        if not got or len(got) < 3:
            continue
        labels = [g[0] for g in got]
        c = [g[1] for g in got]
        d = [g[2] for g in got]
        rel = [a / b - 1.0 for a, b in zip(c, d)]
        n = len(rel)
        m, se, sd, median, skew, kurt = describe(rel)
        dev = sorted(((v - m) ** 2, lab, v) for lab, v in zip(labels, rel))
        top = max(1, round(0.05 * n))
        share = sum(x for x, _, _ in dev[-top:]) / sum(x for x, _, _ in dev)
        lo = min(zip(rel, labels))
        hi = max(zip(rel, labels))
        cv = [describe(v)[2] / abs(describe(v)[0]) for v in (c, d)]
        strict = abs(m) + 2 * se
        # Seeds for 2 SE <= bar at this SD, and for |m| + 2 SE <= bar if the
        # mean stays where it is.
        need_se = math.ceil((2 * sd / bar) ** 2)
        need_strict = (math.ceil((2 * sd / (bar - abs(m))) ** 2) if abs(m) < bar
                       else float("inf"))
        # The median's standard error by bootstrap over the seeds (2000
        # resamples, a fixed generator: the same numbers every time).
        draw = random.Random(1)
        medians = sorted(describe([draw.choice(rel) for _ in rel])[3] for _ in range(2000))
        median_se = describe(medians)[2]
        # peer/dembound - 1 is convex in the ratio: two codes whose values
        # are exchangeable give a mean of ~SD^2/2 above 0 (0.1-0.25 % at
        # 5-7 % a seed); ln(peer/dembound) has no such bias.
        log_m, log_se = mean_se([math.log(a / b) for a, b in zip(c, d)])
        print(f"{name}: n = {n}, difference {100 * m:+.2f} % ± {100 * se:.2f} % "
              f"(ln ratio {100 * log_m:+.2f} % ± {100 * log_se:.2f} %, "
              f"median {100 * median:+.2f} % ± {100 * median_se:.2f} %), SD {100 * sd:.2f} %, "
              f"skewness {skew:+.2f}, "
              f"excess kurtosis {kurt:+.2f}; the {top} largest of {n} carry {100 * share:.0f} % "
              f"of the squared deviations (a normal sample: ~{100 * normal_top_share(top, n):.0f} %); "
              f"extremes {100 * lo[0]:+.1f} % ({os.path.basename(lo[1])}), "
              f"{100 * hi[0]:+.1f} % ({os.path.basename(hi[1])}); codes' correlation over seeds "
              f"{correlation(c, d):.2f}, each code's seed-to-seed SD {100 * cv[0]:.1f} % / "
              f"{100 * cv[1]:.1f} %; |difference| + 2 SE = {100 * strict:.2f} % "
              f"({'within' if strict <= bar else 'above'} {100 * bar:g} %); seeds for 2 SE <= "
              f"{100 * bar:g} %: {need_se}, for |difference| + 2 SE <= {100 * bar:g} %: {need_strict}")


def normal_top_share(top, n):
    """The expected share of the squared deviations the `top` largest of n
    normal draws carry (chi-square with one degree of freedom: the tail
    above the (1 - top/n) quantile of |z|, whose E[z^2; |z| > q] is
    2 (q phi(q) + 1 - Phi(q)))."""
    p = top / n
    # |z| quantile by bisection on the normal tail 2 (1 - Phi(q)) = p.
    lo, hi = 0.0, 10.0
    for _ in range(100):
        q = (lo + hi) / 2
        if math.erfc(q / math.sqrt(2)) > p:
            lo = q
        else:
            hi = q
    phi = math.exp(-q * q / 2) / math.sqrt(2 * math.pi)
    return 2 * (q * phi) + math.erfc(q / math.sqrt(2))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("reports", nargs="+")
    ap.add_argument("--label", default="")
    ap.add_argument("--markdown", action="store_true")
    ap.add_argument("--quantity", action="append", default=[],
                    help="also put this quantity of compare's report side by side (its name "
                    "there, e.g. \"free spheres in the domain\"), against compare's own 1 %% bar")
    ap.add_argument("--bins", action="store_true",
                    help="also print every z bin of the profiles (both codes' means, paired Δ ± SE)")
    ap.add_argument("--versus-dir", metavar="DIR",
                    help="a second series of the same seeds (DIR/<each report's file name>), "
                    "e.g. another model of the peer: prints this series' peer against that "
                    "one's, paired by seed (both against one dembound run per seed), and stops")
    ap.add_argument("--versus-side", choices=["code", "dembound"], default="code",
                    help="with --versus-dir: pair the peer's means (default; the dembound runs "
                    "must be the same) or dembound's (the peer's runs must be the same, e.g. "
                    "dembound under another contact.torque_arm against one deck)")
    ap.add_argument("--per-seed", action="store_true",
                    help="also describe each wall's per-seed paired differences (spread, tails)")
    args = ap.parse_args()
    if args.versus_dir:
        return versus(args)
    reports = [json.load(open(p)) for p in args.reports]
    code = reports[0]["code"]
    n = len(reports)
    rows = []
    # Every other wall's force (side walls), with the floor's bar: walls
    # named in every report, in compare's order.
    walls = [q["name"] for q in reports[0]["quantities"]
             if q["name"].startswith("wall[") and q["name"] not in BARS]
    walls = [w for w in walls
             if all(any(q["name"] == w for q in r["quantities"]) for r in reports)]
    bars = dict(BARS, **{w: BARS["wall[0] force |F|"] for w in walls})
    for name in args.quantity:
        if not all(any(q["name"] == name for q in r["quantities"]) for r in reports):
            sys.exit(f"--quantity: no \"{name}\" in every report")
        bars[name] = 0.01
    def window_means(r, name):
        q = next((q for q in r["quantities"] if q["name"] == name), None)
        if q and q["code_window"] and q["dembound_window"]:
            return q["code_window"]["mean"], q["dembound_window"]["mean"]
        return None

    # The side walls' |F| summed per seed (each code's sum of its walls'
    # late-window means), with the same bar: what the walls hold together.
    summed = "side walls summed |F|"
    if len(walls) > 1:
        bars[summed] = BARS["wall[0] force |F|"]
    pairs = {}
    for name, bar in bars.items():
        c, d = [], []
        for path, r in zip(args.reports, reports):
            parts = [window_means(r, w) for w in (walls if name == summed else [name])]
            if all(parts):
                c.append(sum(p[0] for p in parts))
                d.append(sum(p[1] for p in parts))
                pairs.setdefault(name, []).append((path, c[-1], d[-1]))
        if len(c) < n or not all(d):
            pairs.pop(name, None)
            continue  # a wall that nothing touches (e.g. below an outlet) has no ratio
        (cm, cse), (dm, dse) = mean_se(c), mean_se(d)
        # Paired by seed: both codes start from the same spheres, so the
        # difference of each seed's pair has no seed-to-seed spread.
        rel, rel_se = mean_se([a / b - 1.0 for a, b in zip(c, d)])
        rows.append((name, f"{cm:.6g} ± {cse:.2g}", f"{dm:.6g} ± {dse:.2g}",
                     f"{100 * rel:+.2f} % ± {100 * rel_se:.2f} %",
                     "agree" if abs(rel) <= bar
                     else ("agree (≤ 2 SE)" if abs(rel) <= 2 * rel_se else "DIFFER"),
                     f"{100 * bar:g} %", "yes" if 2 * rel_se <= bar else "no"))
    for pname, bar, unit in [("packing fraction", PACKING_BAR, ""), ("flow velocity", None, " m/s")]:
        profiles = [next((p for p in r.get("profiles", []) if p["name"] == pname), None) for r in reports]
        if any(p is None for p in profiles):
            continue
        # Bins are one mean diameter of each deck's spheres: seeds of a
        # polydisperse scene differ slightly; bins are matched by index
        # (the widths' spread is printed).
        bins = min(len(p["centres"]) for p in profiles)
        widths = [p["bin_width"] for p in profiles]
        spread = (max(widths) - min(widths)) / min(widths)
        worst = (0.0, 0.0, 0.0, 0.0, 0.0)
        for k in range(bins):
            c = [p["code"][k]["mean"] for p in profiles if p["code"][k]]
            d = [p["dembound"][k]["mean"] for p in profiles if p["dembound"][k]]
            if len(c) < n or len(d) < n:
                continue
            (cm, _), (dm, _) = mean_se(c), mean_se(d)
            delta, delta_se = mean_se([a - b for a, b in zip(c, d)])
            if abs(delta) > worst[0]:
                worst = (abs(delta), profiles[0]["centres"][k], delta_se, cm, dm)
            if args.bins and (cm or dm):
                print(f"{pname}, z = {profiles[0]['centres'][k] * 1e3:.3g} mm: {code} {cm:.4g}, "
                      f"dembound {dm:.4g}, Δ = {delta:+.3g}{unit} ± {delta_se:.2g}"
                      + (f" ({100 * delta / dm:+.1f} % ± {100 * delta_se / abs(dm):.1f} %)" if dm else ""))
        diff, z, se, cm, dm = worst
        rows.append((f"{pname} (max over z bins of {profiles[0]['bin_width'] * 1e3:.4g} mm"
                     + (f", widths within {100 * spread:.2g} %" if spread > 0 else "") + ")",
                     f"{cm:.4g} at z = {z * 1e3:.3g} mm", f"{dm:.4g}",
                     f"|Δ| = {diff:.3g}{unit} ± {se:.2g}",
                     "—" if bar is None else ("agree" if diff <= bar else "DIFFER"),
                     "—" if bar is None else f"{bar:g}",
                     "—" if bar is None else ("yes" if 2 * se <= bar else "no")))
    # compare's speeds say which clock they divide by: CPU time where the
    # run reports it (dembound, LAMMPS's "% CPU use", Yade), else the wall
    # clock × cores (LIGGGHTS): a wall-clock rate on a loaded machine
    # understates that code's per-core speed.
    # A wall-clock peer rate (LIGGGHTS) is replaced by the peer process's
    # CPU time where jittered_seeds.py left it beside the report (REPORT
    # without .json, plus .cpu: user + system s, setup and output included).
    def peer_cpu(path, speed):
        cpu = path[:-5] + ".cpu" if path.endswith(".json") else None
        if speed.get("clock") != "wall" or not cpu or not os.path.isfile(cpu):
            return None
        steps = speed["particle_steps_per_core_second"] * speed["wall_seconds"] * speed["cores"]
        return float(open(cpu).read()) / steps, "process CPU"

    def seconds_per_step(key):
        got = [(key == "code_speed" and peer_cpu(p, r[key]))
               or (1.0 / r[key]["particle_steps_per_core_second"], r[key].get("clock", "wall"))
               for p, r in zip(args.reports, reports) if r.get(key)]
        if not got:
            return "—"
        clocks = sorted({c for _, c in got})
        return f"{sum(s for s, _ in got) / len(got):.3g} ({'/'.join(clocks)})"
    speed = (f"s per particle-step per core (by CPU time where known, else wall clock): {code} "
             + seconds_per_step("code_speed")
             + f", dembound {seconds_per_step('dembound_speed')} (means over {n} seeds)")
    if args.markdown:
        for row in rows:
            print(f"| {args.label} | " + " | ".join(row) + " |")
        print(f"| {args.label} | {speed} | | | | | | |")
    else:
        print(f"{args.label}: {code} against dembound over {n} seeds (mean of the late-window means ± SE over seeds)")
        # What the wall rows hold (compare's `wall_forces`; reports made
        # before it had the field sampled the row's step).
        modes = sorted({r.get("wall_forces") or "at_row_step" for r in reports})
        print("wall forces: " + ", ".join(modes)
              + ("  (MIXED: the seeds' wall rows are not the same quantity)" if len(modes) > 1 else ""))
        head = ("quantity", code, "dembound", "difference", "verdict", "bar", "resolved")
        widths = [max(len(str(r[i])) for r in rows + [head]) for i in range(len(head))]
        for r in [head] + rows:
            print("  ".join(str(r[i]).ljust(widths[i]) for i in range(len(head))))
        print(speed)
    if args.per_seed:
        per_seed([w for w in bars if w.startswith("wall[") or w == summed], pairs,
                 BARS["wall[0] force |F|"])
    return 0


def versus(args):
    """Two series of one scene's seeds whose dembound side is the same run
    (the same start and scene.toml; checked: equal dembound window means),
    or with --versus-side dembound whose peer side is (dembound's compared):
    each quantity's peer window mean of this series over the other's, − 1,
    mean ± SE over the seeds, and the same through dembound (the product of
    the two series' paired differences), so two variants of a peer, or two
    peers, are paired by seed."""
    pairs = []
    for path in args.reports:
        other = os.path.join(args.versus_dir, os.path.basename(path))
        if not os.path.isfile(other):
            sys.exit(f"--versus-dir: no {other} for {path}")
        pairs.append((json.load(open(path)), json.load(open(other))))
    side, fixed = (("code_window", "dembound_window") if args.versus_side == "code"
                   else ("dembound_window", "code_window"))
    a_code, b_code = ((pairs[0][0]["code"], pairs[0][1]["code"]) if args.versus_side == "code"
                      else ("dembound", "dembound"))
    print(f"{args.label}: {a_code} ({len(pairs)} seeds) against {b_code} of {args.versus_dir}, "
          "paired by seed (late-window means)")
    names = [q["name"] for q in pairs[0][0]["quantities"]
             if q.get("code_window") and q.get("dembound_window")]
    # The side walls (every wall but the floor, wall[0]) and their sum per
    # seed, as in the main table.
    walls = [n for n in names if n.startswith("wall[") and n != "wall[0] force |F|"]
    summed = "side walls summed |F|"
    for name in ["bed height", "wall[0] force |F|", *args.quantity,
                 *([summed] if len(walls) > 1 else [])]:
        if name not in names and name != summed:
            continue
        parts = walls if name == summed else [name]
        ratios, same = [], True
        for a, b in pairs:
            qa = [next((q for q in a["quantities"] if q["name"] == w), None) for w in parts]
            qb = [next((q for q in b["quantities"] if q["name"] == w), None) for w in parts]
            if not all(q and q.get(side) and q.get(fixed) for q in qa + qb):
                break
            same &= all(x[fixed]["mean"] == y[fixed]["mean"] for x, y in zip(qa, qb))
            ratios.append(sum(q[side]["mean"] for q in qa) / sum(q[side]["mean"] for q in qb)
                          - 1.0)
        if len(ratios) < len(pairs):
            continue
        m, se = mean_se(ratios)
        print(f"  {name}: {100 * m:+.2f} % ± {100 * se:.2f} %"
              + ("" if same else f"  (the {fixed.split('_')[0]} sides differ: not one run per seed)"))
    return 0


if __name__ == "__main__":
    sys.exit(main())
