"""The batched path gives each case exactly what `run` gives it."""

from __future__ import annotations

import math
import struct

import numpy as np

import dembound


def bits(x: float) -> bytes:
    return struct.pack("<d", x)


def test_batch_equals_run_case_by_case():
    # Hertz (batched SIMD lanes) and linear, r and ζ on a grid including ∞,
    # and the drop height per case: every quantity of every contact, bit for bit.
    r = np.array([1.0, 10.0, math.inf])
    zeta = np.array([1.0, 1000.0])
    R, Z = np.meshgrid(r, zeta, indexing="ij")
    gaps = np.full(R.shape, 1e-3)
    gaps[0, 0] = 4e-3
    for law in ("hertz", "linear"):
        grid = dembound.batch(r=R, zeta=Z, motion__gap=gaps, contact__law=law)
        assert grid["max_overlap"].shape == (3, 2, 2)
        for i in range(3):
            for j in range(2):
                doc = dembound.run(
                    contact__law=law,
                    boundary__radius_ratio=float(R[i, j]),
                    boundary__modulus_ratio=float(Z[i, j]),
                    motion__gap=float(gaps[i, j]),
                )
                assert grid["steps"][i, j] == doc["steps"]
                assert bits(grid["dt"][i, j]) == bits(doc["dt"])
                for k, contact in enumerate(doc["contacts"]):
                    for name in ("t_contact", "t_max_overlap", "t_rebound", "duration", "max_overlap",
                                 "max_force", "max_acceleration", "impact_velocity", "rebound_velocity",
                                 "restitution", "energy_dissipated"):
                        assert bits(float(grid[name][i, j, k])) == bits(contact[name]), (law, i, j, k, name)


def test_batch_without_arrays_is_one_run():
    one = dembound.batch()
    doc = dembound.run()
    assert one["max_overlap"].shape == (2,)
    assert [bits(float(x)) for x in one["max_overlap"]] == [bits(c["max_overlap"]) for c in doc["contacts"]]
