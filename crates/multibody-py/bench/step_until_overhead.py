"""What stepping a model from Python costs against one `simulate()` call of
the same run: the pendulum of examples/controlled_pendulum.dyad for 5 s,
every signal kept at saveat = 1 ms, (a) in 5000 calls of
`Simulator.step_until` of 1 ms each, (b) the same with the input set before
each step (to the value it holds, as a controller that holds its output
does), against one `Model.simulate()`. Both include making the model's
mechanism and handing every sample to Python. The issue asks (a) for at
most 1.5 times (c).

(d), for information: a PD law setting a new torque every step, which
makes the integrator start again every 1 ms (a different run).

    python crates/multibody-py/bench/step_until_overhead.py [seconds per side] [reltol]
"""

import statistics
import sys
import time
from pathlib import Path

import multibody

ROOT = Path(__file__).resolve().parents[3]
model = multibody.load(ROOT / "examples" / "controlled_pendulum.dyad")
budget = float(sys.argv[1]) if len(sys.argv) > 1 else 3.0
tol = float(sys.argv[2]) if len(sys.argv) > 2 else 1e-6
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


def median_seconds(call):
    call()  # warm up
    times = []
    deadline = time.perf_counter() + budget
    while time.perf_counter() < deadline or len(times) < 5:
        start = time.perf_counter()
        call()
        times.append(time.perf_counter() - start)
    return statistics.median(times), min(times)


a, b, c, d = [], [], [], []
for _ in range(3):  # alternate, so that drifts of the machine touch all alike
    c.append(median_seconds(simulate))
    a.append(median_seconds(stepped()))
    b.append(median_seconds(stepped(set_input=True)))
    d.append(median_seconds(stepped(controller=True)))
# The fastest run of each, as well: on a busy machine the medians wander.
(a, a_min), (b, b_min), (c, c_min), (d, d_min) = (
    (statistics.median(t for t, _ in x), min(m for _, m in x)) for x in (a, b, c, d)
)
one, many = simulate(), stepped()()
worst = max(abs(x - y) for n in one.names for x, y in zip(one[n], many[n]))
print(f"controlled_pendulum, 5 s at saveat 1 ms, reltol = abstol = {tol:g}: {len(one.names)} signals x {len(one)} samples")
print("                                            median        fastest    ratio to (c): median, fastest")
print(f"  (c) one simulate():                       {c * 1e3:8.3f} ms  {c_min * 1e3:8.3f} ms")
print(f"  (a) 5000 x step_until(t + 1 ms):          {a * 1e3:8.3f} ms  {a_min * 1e3:8.3f} ms  {a / c:.3f}  {a_min / c_min:.3f}")
print(f"  (b) the same with set_input (unchanged):  {b * 1e3:8.3f} ms  {b_min * 1e3:8.3f} ms  {b / c:.3f}  {b_min / c_min:.3f}")
print(f"  (d) a PD law setting a new torque:        {d * 1e3:8.3f} ms  {d_min * 1e3:8.3f} ms  {d / c:.3f}  {d_min / c_min:.3f}")
print(f"  largest difference of (a) from (c) over every signal: {worst:.2e}")
