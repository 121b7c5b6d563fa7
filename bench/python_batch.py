"""Cases per second of the 10,000-case sweep of benches/batch.rs from
Python (`dembound.batch`: the batched SIMD path, GIL released, results as
NumPy arrays), best of K calls. The Rust figure of the same cases and path:
`target/release/examples/batch_throughput 10000 batch K`. BENCHMARKS.md runs
the two interleaved.

    python bench/python_batch.py [N] [K]
"""

import math
import sys
import time

import numpy as np

import dembound

n = int(sys.argv[1]) if len(sys.argv) > 1 else 10_000
k = int(sys.argv[2]) if len(sys.argv) > 2 else 10


def u(i: int, m: int) -> float:
    return ((i * m) % 1000) / 1000.0


# crates/dembound-core/benches/common/mod.rs: the validation case with r,
# ζ and the gap varied (Hertz, Gear5, η = 1/50, event stepping, 2 contacts).
r = np.array([math.pow(10.0, -0.3 + 4.3 * u(i, 7)) for i in range(n)])
zeta = np.array([math.pow(10.0, -1.0 + 5.0 * u(i, 13)) for i in range(n)])
gap = np.array([math.pow(10.0, -4.0 + 2.0 * u(i, 31)) for i in range(n)])

best = math.inf
for _ in range(k):
    t = time.perf_counter()
    out = dembound.batch(r=r, zeta=zeta, motion__gap=gap)
    best = min(best, time.perf_counter() - t)
    assert out["max_overlap"].shape == (n, 2) and np.all(out["max_overlap"] > 0)
print(f"python dembound.batch: {n / best:.0f} cases/s")
