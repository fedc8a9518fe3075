"""What calling `simulate` from Python costs over the Rust call it makes,
on Modelica's DoublePendulum (examples/msl/DoublePendulum.dyad), every
signal kept: the same simulation timed both ways in the same run.

    python crates/multibody-py/bench/simulate_overhead.py [seconds per side]
"""

import statistics
import sys
import time
from pathlib import Path

import multibody

ROOT = Path(__file__).resolve().parents[3]
model = multibody.load(ROOT / "examples" / "msl" / "DoublePendulum.dyad")
names = model.signals()
budget = float(sys.argv[1]) if len(sys.argv) > 1 else 3.0


def median_seconds(call):
    call()  # warm up
    times = []
    deadline = time.perf_counter() + budget
    while time.perf_counter() < deadline or len(times) < 11:
        start = time.perf_counter()
        call()
        times.append(time.perf_counter() - start)
    return statistics.median(times), len(times)


# Alternate the two, so that drifts of the machine touch both alike.
rust, python = [], []
for _ in range(3):
    rust.append(median_seconds(lambda: model._native._simulate_in_rust(names)))
    python.append(median_seconds(lambda: model.simulate(signals="all")))
r = statistics.median(t for t, _ in rust)
p = statistics.median(t for t, _ in python)
samples = len(model.simulate(signals="all"))
print(f"DoublePendulum, {len(names)} signals x {samples} samples")
print(f"  Rust call:          {r * 1e3:.3f} ms (median)")
print(f"  Python simulate():  {p * 1e3:.3f} ms (median)")
print(f"  Python / Rust:      {p / r:.3f}")
