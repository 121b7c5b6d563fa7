#!/usr/bin/env python3
"""Writes a mid-discharge state of the hopper as a scene, for the speed
comparison (BENCHMARKS.md, "Session 11 — mesh walls").

    python3 scripts/hopper_state.py RUN_DIR/snapshot_NNNNNN.vtp OUT_DIR [--stl STL]

Reads a VTK snapshot of `dembound scene examples/scenes/hopper.toml` (positions,
velocities, spins, radii, materials), writes OUT_DIR/hopper_state.data (a
LAMMPS data file of atom_style sphere with a Velocities section, which
dembound's `lammps_data` source reads) and OUT_DIR/hopper_state.toml:
hopper.toml with its spheres read from that file and its mesh replaced by
STL (default: hopper.stl; give the 20,000-triangle one of
`make_hopper.py --segments 200`). Both codes then start from the same
flowing state (`dembound export liggghts OUT_DIR/hopper_state.toml`).
Standard library only.
"""

import argparse
import re
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from hopper_discharge import vtp_arrays  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("snapshot")
    p.add_argument("out")
    p.add_argument("--stl", default=str(ROOT / "examples/scenes/hopper.stl"))
    p.add_argument("--scene", default=str(ROOT / "examples/scenes/hopper.toml"))
    args = p.parse_args()
    a = vtp_arrays(args.snapshot)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    scene = Path(args.scene).read_text()
    densities = [float(d) for d in re.findall(r"^density = ([0-9.eE+-]+)", scene, re.M)]
    n = len(a["radius"])
    x, v, w = a["position"], a["velocity"], a["angular_velocity"]
    lines = ["hopper state from " + Path(args.snapshot).name, "", f"{n} atoms", "1 atom types", ""]
    lo = [min(x[3 * i + k] - a["radius"][i] for i in range(n)) for k in range(3)]
    hi = [max(x[3 * i + k] + a["radius"][i] for i in range(n)) for k in range(3)]
    for k, name in enumerate("xyz"):
        lines.append(f"{lo[k]!r} {hi[k]!r} {name}lo {name}hi")
    lines += ["", "Atoms # sphere", ""]
    for i in range(n):
        rho = densities[int(a["material"][i])]
        lines.append(
            f"{i + 1} 1 {2.0 * a['radius'][i]!r} {rho!r} {x[3 * i]!r} {x[3 * i + 1]!r} {x[3 * i + 2]!r}"
        )
    lines += ["", "Velocities", ""]
    for i in range(n):
        lines.append(
            f"{i + 1} {v[3 * i]!r} {v[3 * i + 1]!r} {v[3 * i + 2]!r} "
            f"{w[3 * i]!r} {w[3 * i + 1]!r} {w[3 * i + 2]!r}"
        )
    (out / "hopper_state.data").write_text("\n".join(lines) + "\n")
    particles = re.compile(r"\[\[particles\]\].*?\nmaterial = \"glass\"\n", re.S)
    new = particles.sub(
        '[[particles]]\nlammps_data = "hopper_state.data"\nmaterial = "glass"\n', scene, count=1
    )
    new = new.replace('mesh = { file = "hopper.stl" }', f'mesh = {{ file = "{Path(args.stl).resolve()}" }}')
    (out / "hopper_state.toml").write_text(new)
    print(f"wrote {out}/hopper_state.data ({n} spheres) and {out}/hopper_state.toml")


if __name__ == "__main__":
    main()
