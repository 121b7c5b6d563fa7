#!/usr/bin/env python3
"""Translational and rotational kinetic energy (J) of a dembound VTK
snapshot, to set beside LAMMPS's `ke` (translational only) and
`compute erotate/sphere`; dembound's `kinetic_energy` is their sum.

Usage: snapshot_energy.py SNAPSHOT.vtp DENSITY_KG_M3
(one density for every sphere, as in the lattice-drop scene; fixed spheres
are skipped). Reads the uncompressed base64 arrays dembound writes
(header_type UInt64). Standard library only.
"""
import base64
import math
import re
import struct
import sys


def arrays(path):
    text = open(path).read()
    out = {}
    for m in re.finditer(r'<DataArray type="(\w+)" Name="(\w+)"[^>]*format="binary">([^<]*)</DataArray>', text):
        kind, name, data = m.groups()
        raw = base64.b64decode(data.strip())
        (size,) = struct.unpack_from("<Q", raw, 0)
        code = {"Float64": "d", "UInt8": "B", "Int32": "i", "Int64": "q", "UInt64": "Q"}[kind]
        n = size // struct.calcsize(code)
        out[name] = struct.unpack_from(f"<{n}{code}", raw, 8)
    return out


def main():
    path, density = sys.argv[1], float(sys.argv[2])
    a = arrays(path)
    r, v, w, fixed = a["radius"], a["velocity"], a["angular_velocity"], a["fixed"]
    trans = rot = 0.0
    for i, ri in enumerate(r):
        if fixed[i]:
            continue
        m = density * 4.0 / 3.0 * math.pi * ri**3
        inertia = 0.4 * m * ri * ri
        trans += 0.5 * m * sum(x * x for x in v[3 * i : 3 * i + 3])
        rot += 0.5 * inertia * sum(x * x for x in w[3 * i : 3 * i + 3])
    print(f"translational {trans:.10e} J  rotational {rot:.10e} J  total {trans + rot:.10e} J")


if __name__ == "__main__":
    main()
