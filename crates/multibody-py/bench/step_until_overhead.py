"""What stepping a model from Python costs against one `simulate()` call of
the same run: the pendulum of examples/controlled_pendulum.dyad for 5 s,
every signal kept at saveat = 1 ms,

  (a) 5000 calls of `Simulator.step_until`, 1 ms each,
  (b) the same with the input set before each step (to the value it holds,
      as a controller that holds its output does),
  (c) one `Model.simulate()`.

Each includes making the model's mechanism and handing every sample to
Python. The issue asks (a) for at most 1.5 times (c), with the same
outputs: the script checks that (a) records exactly what (c) records.

(d), for information: a PD law reading the outputs and setting a new
torque every step, which makes the integrator start again every 1 ms (a
different run, so a different result).

The ratio is measured in rounds (3 by default) that alternate the cases,
so that drifts of a busy machine touch all alike; each round prints the
ratio of the medians and of the fastest runs. Timing only: no assertion
on time (timing is not a test).

    python crates/multibody-py/bench/step_until_overhead.py [seconds per case] [rounds] [reltol]
"""

import os

# numpy's BLAS threads spin between calls and steal the cores being timed.
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import statistics  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import multibody  # noqa: E402

ROOT = Path(__file__).resolve().parents[3]
model = multibody.load(ROOT / "examples" / "controlled_pendulum.dyad")
budget = float(sys.argv[1]) if len(sys.argv) > 1 else 2.0
rounds = int(sys.argv[2]) if len(sys.argv) > 2 else 3
tol = float(sys.argv[3]) if len(sys.argv) > 3 else 1e-6
options = dict(stop=5.0, saveat=1e-3, reltol=tol, abstol=tol)
STEPS = 5000


def simulate():
    return model.simulate(signals="all", **options)


def stepped(set_input=False, controller=False):
    def run():
        sim = model.simulator(**options)
        for k in range(STEPS):
            if controller:
                out = sim.outputs
                sim.set_input("tau", 20.0 * (1.0 - out["angle"]) - 2.0 * out["speed"])
            elif set_input:
                sim.set_input("tau", 0.0)
            sim.step_until((k + 1) * 1e-3)
        return sim.result("all")

    return run


def timed(call):
    """The median and the fastest of as many runs as fit in the budget (at least 5)."""
    call()  # warm up
    times = []
    deadline = time.perf_counter() + budget
    while time.perf_counter() < deadline or len(times) < 5:
        start = time.perf_counter()
        call()
        times.append(time.perf_counter() - start)
    return statistics.median(times), min(times)


one, many = simulate(), stepped()()
worst = max(abs(x - y) for n in one.names for x, y in zip(one[n], many[n]))
print(f"controlled_pendulum, 5 s at saveat 1 ms, reltol = abstol = {tol:g}: {len(one.names)} signals x {len(one)} samples")
print(f"largest difference of (a) from (c) over every signal and sample: {worst:.2e}")
print(f"load average before: {os.getloadavg()[0]:.2f} (on {os.cpu_count()} cores)")
print()
print("round   (c) simulate   (a) step_until   (b) + set_input   (d) PD law     a/c median  a/c fastest  b/c median")
ratios = []
for r in range(rounds):
    c = timed(simulate)
    a = timed(stepped())
    b = timed(stepped(set_input=True))
    d = timed(stepped(controller=True))
    ratios.append(a[0] / c[0])
    print(
        f"{r + 1:5d}   {c[0] * 1e3:9.3f} ms   {a[0] * 1e3:11.3f} ms   {b[0] * 1e3:12.3f} ms   {d[0] * 1e3:8.3f} ms"
        f"   {a[0] / c[0]:10.3f}  {a[1] / c[1]:11.3f}  {b[0] / c[0]:10.3f}"
    )
print()
print(f"(a)/(c), the ratio the issue bounds by 1.5 (medians, per round): {', '.join(f'{x:.3f}' for x in ratios)}")
print(f"load average after: {os.getloadavg()[0]:.2f}")
