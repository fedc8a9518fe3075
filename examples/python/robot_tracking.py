"""Run the six-axis industrial robot of examples/robot (FullRobot: motors
driven by op-amp current loops, gears with bearing friction, P-PI
controllers, a synchronized point-to-point path) from Python, and plot the
six tracking errors, reference angle minus joint angle.

    pip install ./crates/multibody-py matplotlib
    python examples/python/robot_tracking.py [plot.png]
"""

import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")  # write a file; no window needed
import matplotlib.pyplot as plt

import multibody

robot = Path(__file__).resolve().parent.parent / "robot"
model = multibody.load(robot, analysis="FullRobotRun")  # every .dyad file of the folder
signals = [f"path.q[{i}]" for i in range(1, 7)] + [f"mechanics.r{i}.phi" for i in range(1, 7)]
result = model.simulate(signals=signals)

figure, axes = plt.subplots(figsize=(8, 4))
for i in range(1, 7):
    error = result[f"path.q[{i}]"] - result[f"mechanics.r{i}.phi"]
    axes.plot(result.time, 1e3 * error, label=f"axis {i} (max {1e3 * abs(error).max():.1f} mrad)")
axes.set_xlabel("time [s]")
axes.set_ylabel("angle_ref - angle [mrad]")
axes.set_title(f"{model.name}: tracking errors")
axes.legend(fontsize="small")
out = sys.argv[1] if len(sys.argv) > 1 else "robot_tracking_python.png"
figure.savefig(out, dpi=100)
print(f"{len(result)} samples, largest error {max(abs(result[f'path.q[{i}]'] - result[f'mechanics.r{i}.phi']).max() for i in range(1, 7)):.4f} rad -> {out}")
