"""A sweep of 200 pendulum runs on every core against the same runs one
after another, in the same process and the same run.

    python crates/multibody-py/bench/sweep_parallel.py [threads]
"""

import statistics
import sys
import time
from pathlib import Path

import multibody

ROOT = Path(__file__).resolve().parents[3]
model = multibody.load(ROOT / "examples" / "pendulum.dyad")
threads = int(sys.argv[1]) if len(sys.argv) > 1 else 2
sets = [{"body.m": 0.5 + 0.01 * k} for k in range(200)]


def one_after_another():
    return [model.simulate(params=p) for p in sets]


def in_parallel():
    return model.sweep(sets, threads=threads)


def median_seconds(call, repeats=7):
    call()
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        call()
        times.append(time.perf_counter() - start)
    return statistics.median(times)


serial, parallel = [], []
for _ in range(3):  # alternate, so that drifts touch both alike
    serial.append(median_seconds(one_after_another))
    parallel.append(median_seconds(in_parallel))
s, p = statistics.median(serial), statistics.median(parallel)
same = all((a.values == b.values).all() for a, b in zip(one_after_another(), in_parallel()))
print(f"200 pendulum runs: one after another {s * 1e3:.1f} ms, sweep on {threads} threads {p * 1e3:.1f} ms")
print(f"  sweep / one after another: {p / s:.3f}; the same numbers: {same}")
