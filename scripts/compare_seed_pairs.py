#!/usr/bin/env python3
"""Session 37: B's side walls per seed as pairs (x = 0 with x = L, y = 0 with y = L).

For each report (dembound compare --json) take the late-window means of the four side walls
(wall[1..4]: x = 0, x = L, y = 0, y = L) for both codes; print, paired by seed, peer/dembound - 1
(mean ± SE, SD, seeds for 2 SE <= 1 %) of each wall, the x pair's mean |F|, the y pair's, and the
sum; the within-run noise (each code's window SE from compare's 10 blocks, relative) against the
seed-to-seed SD of the difference; each code's own seed-to-seed SD and the codes' correlation.
Usage: scripts/compare_seed_pairs.py LABEL REPORT.json ...  (PAIRS_MD=1 adds Markdown rows)
"""
import json, math, sys

def ms(v):
    n = len(v); m = sum(v) / n
    sd = math.sqrt(sum((x - m) ** 2 for x in v) / (n - 1)) if n > 1 else float("nan")
    return m, sd / math.sqrt(n), sd

def corr(a, b):
    ma, mb = sum(a) / len(a), sum(b) / len(b)
    c = sum((x - ma) * (y - mb) for x, y in zip(a, b))
    return c / math.sqrt(sum((x - ma) ** 2 for x in a) * sum((y - mb) ** 2 for y in b))

label, paths = sys.argv[1], sys.argv[2:]
rows = {}
for p in paths:
    r = json.load(open(p))
    q = {x["name"]: x for x in r["quantities"]}
    w = [q[f"wall[{k}] force |F|"] for k in range(1, 5)]
    c = [x["code_window"]["mean"] for x in w]; d = [x["dembound_window"]["mean"] for x in w]
    cse = [x["code_window"]["standard_error"] for x in w]; dse = [x["dembound_window"]["standard_error"] for x in w]
    rows[p] = (c, d, cse, dse)
n = len(rows)
stats = {
    "x = 0": lambda v: v[0], "x = L": lambda v: v[1], "y = 0": lambda v: v[2], "y = L": lambda v: v[3],
    "x pair (mean of x = 0, x = L)": lambda v: (v[0] + v[1]) / 2,
    "y pair (mean of y = 0, y = L)": lambda v: (v[2] + v[3]) / 2,
    "four side walls summed": lambda v: sum(v),
}
print(f"{label}: {n} seeds; peer/dembound - 1 paired by seed (late window, walls averaged over every step)")
for name, f in stats.items():
    c = [f(rows[p][0]) for p in paths]; d = [f(rows[p][1]) for p in paths]
    rel = [a / b - 1 for a, b in zip(c, d)]
    m, se, sd = ms(rel)
    lnm, lnse, _ = ms([math.log(a / b) for a, b in zip(c, d)])
    # within-run noise of the window mean (compare's block SE), relative, per code; for a pair or a
    # sum, the blocks' SEs combined as if independent (an upper bound where the walls co-vary negatively)
    def noise(k):
        if name.startswith("x pair"): idx = [0, 1]; scale = 0.5
        elif name.startswith("y pair"): idx = [2, 3]; scale = 0.5
        elif name.startswith("four"): idx = [0, 1, 2, 3]; scale = 1
        else: idx = [list(stats).index(name)]; scale = 1
        return [scale * math.sqrt(sum(rows[p][k][i] ** 2 for i in idx)) / f(rows[p][k - 2]) for p in paths]
    nc = math.sqrt(sum(x * x for x in noise(2)) / n); nd = math.sqrt(sum(x * x for x in noise(3)) / n)
    need = math.ceil((2 * sd / 0.01) ** 2)
    print(f"  {name}: {ms(c)[0]*1e3:.4f} ± {ms(c)[1]*1e3:.4f} vs {ms(d)[0]*1e3:.4f} ± {ms(d)[1]*1e3:.4f} mN; "
          f"difference {100*m:+.2f} ± {100*se:.2f} % ({abs(m)/se:.1f} SE; ln {100*lnm:+.2f} ± {100*lnse:.2f} %), "
          f"SD {100*sd:.1f} %, seeds for 2 SE <= 1 %: {need}; codes' SD {100*ms(c)[2]/ms(c)[0]:.1f} / {100*ms(d)[2]/ms(d)[0]:.1f} %, "
          f"correlation {corr(c, d):+.2f}; window noise (rms block SE) {100*nc:.1f} / {100*nd:.1f} %")

# Markdown rows (PAIRS_MD=1): quantity | peer | dembound | difference | SD | seeds for 2 SE <= 1 % | verdict
import os
if os.environ.get("PAIRS_MD"):
    for name, f in stats.items():
        c = [f(rows[p][0]) for p in paths]; d = [f(rows[p][1]) for p in paths]
        rel = [a / b - 1 for a, b in zip(c, d)]
        m, se, sd = ms(rel)
        lnm, lnse, _ = ms([math.log(a / b) for a, b in zip(c, d)])
        verdict = ("agree, within 1 %" if abs(m) + 2 * se <= 0.01 else
                   "agree (≤ 2 SE)" if abs(m) <= 2 * se or abs(m) <= 0.01 else "DIFFER (> 2 SE)")
        print(f"| {name} | {ms(c)[0]*1e3:.3f} ± {ms(c)[1]*1e3:.3f} mN | {ms(d)[0]*1e3:.3f} ± {ms(d)[1]*1e3:.3f} mN | "
              f"{100*m:+.1f} ± {100*se:.1f} % (ln {100*lnm:+.1f} %) | {100*sd:.1f} % | {math.ceil((2*sd/0.01)**2)} | {verdict} |")
