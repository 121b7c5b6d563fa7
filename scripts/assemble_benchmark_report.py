#!/usr/bin/env python3
"""Joins the reports of `dembound benchmarks NAME --out DIR` runs, one
directory per benchmark run in turn, into one report (docs/benchmarks/):
one summary table, every benchmark's section as its run wrote it, the PNG
figures (no SVG, HTML or CSV: the directory stays small).

    python3 scripts/assemble_benchmark_report.py --out docs/benchmarks \\
        --times times.txt --machine "…" RUN_DIR…

`--times`: lines `NAME WALL_S wall CPU_S user …` (GNU time's
`-f "NAME %e s wall %U s user"`), added to the summary as wall and CPU
time; the run time in each section is the run's own wall clock.
Standard library only.
"""
import argparse
import os
import re
import shutil
import sys


def sections(text):
    """(summary rows, the rest from the first `## NAME:` section on)."""
    lines = text.split("\n")
    rows = [l for l in lines if l.startswith("| ") and not l.startswith("| benchmark")
            and not l.startswith("| ---") and not l.startswith("| quantity")]
    start = next(i for i, l in enumerate(lines) if re.match(r"^## [a-z0-9-]+: ", l))
    body = "\n".join(lines[start:])
    # Only the summary table's rows (before the first section).
    summary = [l for l in lines[:start] if l in rows]
    return summary, body


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--out", required=True)
    ap.add_argument("--times", required=True)
    ap.add_argument("--machine", required=True)
    ap.add_argument("--preamble", help="Markdown file placed after the title")
    ap.add_argument("runs", nargs="+")
    a = ap.parse_args()

    times = {}
    with open(a.times) as f:
        for line in f:
            m = re.match(r"^(\S+) ([0-9.]+) s wall ([0-9.]+) s user", line)
            if m:
                times[m.group(1)] = (float(m.group(2)), float(m.group(3)))

    os.makedirs(a.out, exist_ok=True)
    rows, bodies, verdicts = [], [], []
    for run in a.runs:
        with open(os.path.join(run, "report.md")) as f:
            text = f.read()
        summary, body = sections(text)
        name = re.match(r"^## ([a-z0-9-]+): ", body).group(1)
        if name not in times:
            sys.exit(f"{name}: no line in {a.times}")
        rows += summary
        bodies.append(body.rstrip() + "\n")
        verdicts.append((name, "Verdict: **pass**" in body, times[name]))
        for png in sorted(os.listdir(run)):
            if png.endswith(".png"):
                shutil.copy(os.path.join(run, png), os.path.join(a.out, png))

    passed = sum(1 for _, ok, _ in verdicts if ok)
    wall = sum(t[0] for _, _, t in verdicts)
    cpu = sum(t[1] for _, _, t in verdicts)
    out = ["# dembound benchmarks: full runs\n"]
    out.append(
        f"{len(verdicts)} benchmarks run in full, one at a time "
        f"(`dembound benchmarks NAME --out DIR`, then "
        f"`scripts/assemble_benchmark_report.py`); {passed} passed every check. "
        f"Machine: {a.machine}. Total {wall:.0f} s wall clock, {cpu:.0f} s CPU.\n"
    )
    if a.preamble:
        with open(a.preamble) as f:
            out.append(f.read().rstrip() + "\n")
    out.append("## Run times\n")
    out.append("| benchmark | verdict | wall clock (s) | CPU (s) |")
    out.append("| --- | --- | ---: | ---: |")
    for name, ok, (w, c) in verdicts:
        out.append(f"| {name} | {'pass' if ok else 'FAIL'} | {w:.1f} | {c:.1f} |")
    out.append("")
    out.append("## Summary\n")
    out.append("| benchmark | quantity | ours | published | band | verdict | run time (s) |")
    out.append("| --- | --- | ---: | ---: | ---: | --- | ---: |")
    out += rows
    out.append("")
    out += bodies
    with open(os.path.join(a.out, "report.md"), "w") as f:
        f.write("\n".join(out))


if __name__ == "__main__":
    main()
