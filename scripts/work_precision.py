#!/usr/bin/env python3
"""Work-precision: our adaptive integrator against MuJoCo's RK4.

For the Pendulum and DoublePendulum references, sets the wall time our
adaptive Dormand-Prince 5(4) needs to reach a given error of the final state
against the wall time MuJoCo's fixed-step RK4 needs for the same error.

Input: the JSON of `cargo run --release -p multibody --example
work_precision` (--ours FILE; without it the example is run here). It holds
the converged final states ("truth") that both sides are measured against,
our errors and times for reltol = abstol = 1e-3 ... 1e-11, and our own RK4 at
dt = 1e-2, 1e-3, 1e-4.

Here: the same two systems as MJCF (hinges about z, gravity 9.80665 along -y,
damping 0.1 on the first joint, RK4, no contacts, no limits, no armature),
run with RK4 at dt = 5e-2 ... 1e-5 to the same final time through the C loop
of mujoco.rollout.rollout (one MjData, one thread; the state is copied out
after every step, which rollout always does).

MuJoCo's timer callback: importing the Python bindings sets the global
`mjcb_time` (for the profiler's d.timer), which a C program does not have;
mj_step then reads the clock at every stage, which doubles the cost of a step
of these small models. The timings are taken with mjcb_time cleared (through
ctypes on the loaded libmujoco), as MuJoCo runs in a C program; one step size
is also timed with the bindings' default, and both are reported.

Checks, all printed:
  * MuJoCo at its smallest step against the truth (model agreement);
  * MuJoCo's RK4 against our RK4 at the same steps: the same method on the
    same ODE must agree to rounding if the models are the same;
  * rollout against a Python mj_step loop at one step (same numbers).
Then, for a few error levels, interpolates (log-log, between the two runs
that bracket the level) the time each method needs, and prints markdown on
stdout (progress on stderr).

Run with the peers' venv (numpy, mujoco): see scripts/bench.sh.
"""

import argparse
import json
import math
import os
import statistics
import subprocess
import sys
import time

import numpy as np
import mujoco

DTS = [5e-2, 2e-2, 1e-2, 5e-3, 2e-3, 1e-3, 5e-4, 2e-4, 1e-4, 5e-5, 2e-5, 1e-5]
LEVELS = [1e-4, 1e-6, 1e-8]
G = 9.80665

# BodyBox r = [0.5, 0, 0], width = height = 0.06, density 7700 (steel), solid:
# the formulas of crates/multibody/src/components/body_box.rs.
BOX_L, BOX_W = 0.5, 0.06
BOX_M = 7700.0 * BOX_L * BOX_W * BOX_W  # 13.86
BOX_I = (BOX_M * (BOX_W**2 + BOX_W**2) / 12.0, BOX_M * (BOX_L**2 + BOX_W**2) / 12.0,
         BOX_M * (BOX_L**2 + BOX_W**2) / 12.0)  # 0.008316, 0.292908, 0.292908

HEADER = f"""<mujoco model="{{name}}">
  <compiler angle="radian" inertiafromgeom="false"/>
  <option timestep="0.001" integrator="RK4" gravity="0 {-G!r} 0">
    <flag contact="disable"/>
  </option>
  <worldbody>
"""


def pendulum_xml():
    # Revolute about z at the origin; Body m = 1 with r_cm = [0.5, 0, 0] and
    # the Body's default inertia 0.001 I about its centre of mass.
    return HEADER.format(name="Pendulum") + """    <body name="body" pos="0 0 0">
      <joint name="rev" type="hinge" axis="0 0 1" pos="0 0 0" damping="0.1"/>
      <inertial pos="0.5 0 0" mass="1" diaginertia="0.001 0.001 0.001"/>
    </body>
  </worldbody>
</mujoco>
"""


def double_pendulum_xml():
    inertial = (f'<inertial pos="{BOX_L / 2!r} 0 0" mass="{BOX_M!r}" '
                f'diaginertia="{BOX_I[0]!r} {BOX_I[1]!r} {BOX_I[2]!r}"/>')
    return HEADER.format(name="DoublePendulum") + f"""    <body name="boxBody1" pos="0 0 0">
      <joint name="revolute1" type="hinge" axis="0 0 1" pos="0 0 0" damping="0.1"/>
      {inertial}
      <body name="boxBody2" pos="{BOX_L!r} 0 0">
        <joint name="revolute2" type="hinge" axis="0 0 1" pos="0 0 0"/>
        {inertial}
      </body>
    </body>
  </worldbody>
</mujoco>
"""


XML = {"Pendulum": pendulum_xml, "DoublePendulum": double_pendulum_xml}
FULL = mujoco.mjtState.mjSTATE_FULLPHYSICS
QPOS, QVEL = mujoco.mjtState.mjSTATE_QPOS, mujoco.mjtState.mjSTATE_QVEL


class TimerCallback:
    """The global mjcb_time of the loaded libmujoco, through ctypes."""

    def __init__(self):
        import ctypes
        import glob
        self.var = None
        libs = glob.glob(os.path.join(os.path.dirname(mujoco.__file__), "libmujoco.so*"))
        if libs:
            try:
                self.var = ctypes.c_void_p.in_dll(ctypes.CDLL(libs[0]), "mjcb_time")
            except (OSError, ValueError):
                self.var = None
        self.default = self.var.value if self.var is not None else None

    def native(self):
        """Clears the callback (as in a C program); False when not possible."""
        if self.var is None:
            return False
        self.var.value = None
        return True

    def bindings_default(self):
        if self.var is not None:
            self.var.value = self.default


def log(*args):
    print(*args, file=sys.stderr, flush=True)


def final_qv(m, full_state):
    """[qpos..., qvel...] from a full physics state vector."""
    out = np.zeros(m.nq + m.nv)
    mujoco.mj_extractState(m, np.ascontiguousarray(full_state), FULL, out, QPOS | QVEL)
    return out


class Runner:
    """Runs one model from rest to `stop` with RK4 at a given dt."""

    def __init__(self, xml, stop):
        self.m = mujoco.MjModel.from_xml_string(xml)
        self.d = mujoco.MjData(self.m)
        self.stop = stop
        assert self.m.opt.integrator == mujoco.mjtIntegrator.mjINT_RK4
        assert self.m.nq == self.m.nv and not self.m.jnt_limited.any() and not self.m.dof_armature.any()
        mujoco.mj_resetData(self.m, self.d)
        self.x0 = np.zeros(mujoco.mj_stateSize(self.m, FULL))
        mujoco.mj_getState(self.m, self.d, self.x0, FULL)
        try:
            from mujoco import rollout
            self.rollout = rollout.rollout
        except ImportError:  # pragma: no cover - mujoco >= 3.1 ships it
            self.rollout = None

    def steps(self, dt):
        n = round(self.stop / dt)
        assert abs(n * dt - self.stop) < 1e-9 * self.stop, (dt, self.stop)
        return n

    def run(self, dt, out=None):
        """Final [q, v]; `out` is a preallocated (1, nstep, nstate) array."""
        self.m.opt.timestep = dt
        n = self.steps(dt)
        if self.rollout is not None:
            if out is None:
                out = np.zeros((1, n, self.x0.size))
            self.rollout([self.m], [self.d], self.x0[None, :], nstep=n, state=out, skip_checks=True)
            last = out[0, -1]
            assert abs(last[0] - self.stop) < 1e-9, f"rollout ended at t = {last[0]}, not {self.stop}"
            return final_qv(self.m, last)
        return self.run_python(dt)

    def run_python(self, dt):
        self.m.opt.timestep = dt
        mujoco.mj_resetData(self.m, self.d)
        for _ in range(self.steps(dt)):
            mujoco.mj_step(self.m, self.d)
        return np.concatenate([self.d.qpos, self.d.qvel])

    def time(self, dt, budget, min_reps):
        """Median wall time of one run (seconds) and the repetitions."""
        n = self.steps(dt)
        out = np.zeros((1, n, self.x0.size))
        t0 = time.perf_counter()
        self.run(dt, out)  # warm-up and estimate
        once = time.perf_counter() - t0
        reps = max(min_reps, min(1000, int(budget / max(once, 1e-9))))
        times = []
        for _ in range(reps):
            t0 = time.perf_counter()
            self.run(dt, out)
            times.append(time.perf_counter() - t0)
        return statistics.median(times), reps


def time_to_reach(points, level):
    """Log-log interpolated time to reach `level` from (seconds, error, label)
    points; returns (seconds, label, bound) with bound '' (interpolated), '<='
    (the cheapest run already reaches it) or None (never reached)."""
    pts = sorted(points)
    for i, (t, e, label) in enumerate(pts):
        if e <= level:
            if i == 0:
                return t, label, "<="
            t0, e0, label0 = pts[i - 1]
            if e0 <= e:  # not monotone: no interpolation
                return t, label, ""
            s = (math.log(level) - math.log(e0)) / (math.log(e) - math.log(e0))
            return math.exp(math.log(t0) + s * (math.log(t) - math.log(t0))), f"{label0}..{label}", ""
    return None, None, None


def fmt_time(s):
    if s is None:
        return "not reached"
    for unit, f in (("s", 1.0), ("ms", 1e-3), ("µs", 1e-6)):
        if s >= f:
            return f"{s / f:.3g} {unit}"
    return f"{s / 1e-9:.3g} ns"


def fmt_dt(dt):
    return f"{dt:.0e}".replace("e-0", "e-")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--ours", help="JSON from the work_precision example (run it when missing)")
    ap.add_argument("--quick", action="store_true", help="few repetitions (for trying the script)")
    ap.add_argument("--json", help="also write MuJoCo's numbers here")
    ap.add_argument("--peers-csv", help="run.sh --native output: show MuJoCo C's own mj_step RK4 (N = 1) for reference")
    args = ap.parse_args()
    if args.ours:
        ours = json.load(open(args.ours))
    else:
        root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
        cmd = ["cargo", "run", "--release", "-q", "-p", "multibody", "--example", "work_precision"]
        ours = json.loads(subprocess.run(cmd + (["--", "--quick"] if args.quick else []), cwd=root,
                                         check=True, stdout=subprocess.PIPE).stdout)
    budget, min_reps = (0.05, 1) if args.quick else (1.0, 5)

    timer = TimerCallback()
    had_timer = timer.default is not None
    native = timer.native()
    log(f"work_precision.py: mjcb_time {'was set by the bindings: cleared for the timings' if had_timer and native else 'left as it is'}")
    md = []
    dump = {"mujoco": mujoco.__version__, "mjcb_time_cleared": native, "models": []}
    timer_rows = []
    summary = []
    agreement = []
    per_step = []
    raw = []
    for case in ours["models"]:
        name, stop = case["name"], case["stop"]
        truth = np.array(case["truth"])
        runner = Runner(XML[name](), stop)
        log(f"work_precision.py: {name}, MuJoCo {mujoco.__version__} RK4 to t = {stop} s"
            + ("" if runner.rollout else " (mj_step in a Python loop: rollout unavailable)"))
        # rollout and a Python mj_step loop must give the same numbers.
        loop_diff = float(np.max(np.abs(runner.run(1e-2) - runner.run_python(1e-2))))
        mj = []
        for dt in DTS:
            state = runner.run(dt)
            err = float(np.max(np.abs(state - truth)))
            secs, reps = runner.time(dt, budget, min_reps)
            n = runner.steps(dt)
            log(f"  dt {fmt_dt(dt)}: error {err:.2e}, {fmt_time(secs)} ({reps} reps)")
            mj.append({"dt": dt, "steps": n, "state": state.tolist(), "error": err, "seconds": secs,
                       "repetitions": reps})
        # One step size again with the bindings' timer callback, for the record.
        dt_check = 1e-3
        timer.bindings_default()
        with_cb, _ = runner.time(dt_check, budget, min_reps)
        timer.native()
        without_cb = [r["seconds"] for r in mj if r["dt"] == dt_check][0]
        n_check = runner.steps(dt_check)
        timer_rows.append((name, dt_check, n_check, without_cb, with_cb))
        log(f"  dt {fmt_dt(dt_check)} with the bindings' mjcb_time: {fmt_time(with_cb)}")
        dump["models"].append({"name": name, "rk4": mj, "rollout_vs_python_loop": loop_diff,
                               "seconds_with_bindings_timer_at_1e-3": with_cb})
        smallest = min(mj, key=lambda r: r["dt"])
        # The same method and step on both sides: differences are rounding
        # (and the models' differences, if any).
        same = []
        for r in case["rk4"]:
            match = [x for x in mj if abs(x["dt"] - r["dt"]) < 1e-15]
            if match:
                x = match[0]
                diff = float(np.max(np.abs(np.array(r["state"]) - np.array(x["state"]))))
                same.append(diff)
                per_step.append((name, r["dt"], r["steps"], r["seconds"], x["seconds"], diff))
        tc = case["truth_check"]
        agreement.append((name, stop, smallest["dt"], smallest["error"], max(same) if same else float("nan"),
                          tc["vs_tol_1e-13"], tc["vs_rk4"], loop_diff))
        ours_pts = [(r["seconds"], r["error"], f"tol {r['tol']:.0e}".replace("e-0", "e-")) for r in case["adaptive"]]
        mj_pts = [(r["seconds"], r["error"], f"dt {fmt_dt(r['dt'])}") for r in mj]
        for level in LEVELS:
            to, lo, bo = time_to_reach(ours_pts, level)
            tm, lm, bm = time_to_reach(mj_pts, level)
            if to is None or tm is None:
                ratio = "–"
            elif bo and bm:
                ratio = "n/a (both at their cheapest run)"
            else:  # an upper bound on one side bounds the ratio
                ratio = f"{'≤ ' if bo else '≥ ' if bm else ''}{to / tm:.2f}"
            summary.append((name, level, to, lo, bo, tm, lm, bm, ratio))
        raw.append((name, case["adaptive"], mj))

    md.append("### Work-precision: time to reach a final-state error (ours adaptive vs MuJoCo RK4)\n")
    md.append("Error: max abs difference of the joint angles (rad) and rates (rad/s) at the final time from the "
              "converged solution. Times: median wall time of one whole simulation from rest, interpolated "
              "log-log between the two runs that bracket the error level (`≤`: already the cheapest run).\n")
    md.append("| model | error | ours (DP5, adaptive) | ours: between | MuJoCo RK4 | MuJoCo: between | ours / MuJoCo |")
    md.append("|---|---|---|---|---|---|---|")
    for name, level, to, lo, bo, tm, lm, bm, ratio in summary:
        md.append(f"| {name} | {level:.0e} | {'≤ ' if bo == '<=' else ''}{fmt_time(to)} | {lo or '–'} | "
                  f"{'≤ ' if bm == '<=' else ''}{fmt_time(tm)} | {lm or '–'} | {ratio} |")
    md.append("")
    md.append("### Agreement of the converged solutions\n")
    md.append("| model | t end | MuJoCo RK4 smallest dt | MuJoCo there vs our truth | MuJoCo RK4 vs our RK4, same dt (max over dt) "
              "| our truth (tol 1e-14) vs tol 1e-13 | our truth vs our RK4 dt 1e-5 | rollout vs Python mj_step loop |")
    md.append("|---|---|---|---|---|---|---|---|")
    for name, stop, dt, err, same, c13, crk, loop in agreement:
        md.append(f"| {name} | {stop:g} s | {fmt_dt(dt)} | {err:.1e} | {same:.1e} | {c13:.1e} | {crk:.1e} | {loop:.1e} |")
    md.append("")
    md.append("### Cost of one RK4 step: our fixed-step RK4 vs MuJoCo's, same dt (same method, same ODE)\n")
    md.append("| model | dt | steps | ours | MuJoCo | ours / MuJoCo | ours per step | MuJoCo per step | final states differ by |")
    md.append("|---|---|---|---|---|---|---|---|---|")
    for name, dt, n, so, sm, diff in per_step:
        md.append(f"| {name} | {fmt_dt(dt)} | {n} | {fmt_time(so)} | {fmt_time(sm)} | {so / sm:.2f} | "
                  f"{fmt_time(so / n)} | {fmt_time(sm / n)} | {diff:.1e} |")
    md.append("")
    md.append("MuJoCo's cost per RK4 step in the Python process (`rollout`, dt = 1e-3): with `mjcb_time` cleared "
              "as in a C program (used everywhere above), and with the timer callback that importing the "
              "Python bindings installs" + (" (**could not be cleared here: all MuJoCo times above include it**)"
                                            if not native else "") + ".\n")
    md.append("| model | cleared (as in C) | bindings' default | default / cleared |")
    md.append("|---|---|---|---|")
    for name, dt, n, without_cb, with_cb in timer_rows:
        md.append(f"| {name} | {fmt_time(without_cb / n)} | {fmt_time(with_cb / n)} | {with_cb / without_cb:.2f} |")
    if args.peers_csv:
        import csv
        for r in csv.DictReader(open(args.peers_csv)):
            if r["tool"] == "mujoco-c" and r["what"] == "mj_step RK4" and r["N"] == "1":
                md.append(f"\nFor reference, MuJoCo C's own benchmark (peers' mj_bench, a C loop of mj_step on the "
                          f"1-link chain, same run): {fmt_time(float(r['median_ns'].split()[0]) * 1e-9)} per RK4 step.")
    md.append("")
    md.append("### The runs\n")
    for name, adaptive, mj in raw:
        md.append(f"{name}, ours (Dormand-Prince 5(4), reltol = abstol = tol; `simulate` with saveat = stop):\n")
        md.append("| tol | error | time | accepted steps | time per step |")
        md.append("|---|---|---|---|---|")
        for r in adaptive:
            md.append(f"| {r['tol']:.0e} | {r['error']:.2e} | {fmt_time(r['seconds'])} | {r['steps']} | "
                      f"{fmt_time(r['seconds'] / r['steps'])} |")
        md.append("")
        md.append(f"{name}, MuJoCo {mujoco.__version__} RK4 (`rollout`, C loop):\n")
        md.append("| dt | steps | error | time | time per step |")
        md.append("|---|---|---|---|---|")
        for r in mj:
            md.append(f"| {fmt_dt(r['dt'])} | {r['steps']} | {r['error']:.2e} | {fmt_time(r['seconds'])} | "
                      f"{fmt_time(r['seconds'] / r['steps'])} |")
        md.append("")
    bad = [a for a in agreement if a[3] > 1e-8]
    if bad:
        md.append(f"**WARNING: MuJoCo at its smallest step differs from our truth by more than 1e-8 for "
                  f"{', '.join(a[0] for a in bad)}: the models do not match.**\n")
    print("\n".join(md))
    if args.json:
        json.dump(dump, open(args.json, "w"), indent=1)
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
