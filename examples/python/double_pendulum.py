"""Simulate the double pendulum of examples/double_pendulum.dyad from Python,
for three lengths of its first link at once, and plot the angle of the second.

    pip install ./crates/multibody-py matplotlib
    python examples/python/double_pendulum.py [plot.png]
"""

import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")  # write a file; no window needed
import matplotlib.pyplot as plt

import multibody

here = Path(__file__).resolve().parent
model = multibody.load(here.parent / "double_pendulum.dyad")
lengths = [0.5, 0.75, 1.0]
results = model.sweep([{"link1.length": length} for length in lengths], stop=3)

figure, axes = plt.subplots(figsize=(8, 4))
for length, result in zip(lengths, results):
    axes.plot(result.time, result["link2.joint.phi"], label=f"link1.length = {length} m")
axes.set_xlabel("time [s]")
axes.set_ylabel("link2.joint.phi [rad]")
axes.set_title(f"{model.name}: the second joint's angle")
axes.legend()
out = sys.argv[1] if len(sys.argv) > 1 else "double_pendulum_python.png"
figure.savefig(out, dpi=100)
print(f"{len(results)} runs of {len(results[0])} samples -> {out}")
