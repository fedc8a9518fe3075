#!/usr/bin/env python3
"""Golden values of URDF robots' dynamics from Pinocchio (PyPI's `pin`),
which the URDF tests compare with: per file, the moving joints in
Pinocchio's order and, at random states (seeded), the forward dynamics
(ABA) with no joint torque, the joint-space mass matrix (CRBA) and the
inverse dynamics (RNEA) at random accelerations, with
gravity 9.80665 m/s^2 along -z and a fixed base.

Usage: scripts/urdf_goldens.py FILE.urdf... > goldens.json
Needs `pip install pin`. Joint damping is not in Pinocchio's dynamics; the
files compared have none, or the test zeroes it.
"""

import json
import sys

import numpy as np
import pinocchio as pin

STATES = 10


def goldens(path, seed=2026):
    model = pin.buildModelFromUrdf(path)
    model.gravity.linear = np.array([0.0, 0.0, -9.80665])
    data = model.createData()
    rng = np.random.default_rng(seed)
    joints = []
    for j in range(1, model.njoints):
        joint = model.joints[j]
        if joint.nv != 1:
            raise SystemExit(f"{path}: joint {model.names[j]} has {joint.nv} degrees of freedom")
        joints.append({"name": model.names[j], "nq": joint.nq, "idx_q": joint.idx_q, "idx_v": joint.idx_v})
    out = []
    for _ in range(STATES):
        angles = rng.uniform(-np.pi, np.pi, model.nv)
        v = rng.uniform(-1.0, 1.0, model.nv)
        q = np.zeros(model.nq)
        for k, j in enumerate(joints):
            if j["nq"] == 2:  # continuous: cos, sin
                q[j["idx_q"]] = np.cos(angles[k])
                q[j["idx_q"] + 1] = np.sin(angles[k])
            else:
                q[j["idx_q"]] = angles[k]
        ddq = pin.aba(model, data, q, v, np.zeros(model.nv))
        a = rng.uniform(-1.0, 1.0, model.nv)
        tau = pin.rnea(model, data, q, v, a)
        mass = pin.crba(model, data, q)
        mass = np.triu(mass) + np.triu(mass, 1).T
        if not (np.all(np.isfinite(ddq)) and np.all(np.isfinite(mass))):
            # A joint with no inertia behind it: the mass matrix is singular.
            return {"joints": [j["name"] for j in joints], "states": [], "singular": True,
                    "pinocchio": pin.__version__}
        # How much rounding the forward dynamics amplify: solving M x = b
        # loses up to cond(M) times the precision.
        out.append({"q": angles.tolist(), "v": v.tolist(), "ddq": ddq.tolist(), "M": mass.tolist(),
                    "a": a.tolist(), "tau": tau.tolist(), "cond": float(np.linalg.cond(mass)) if model.nv else 1.0})
    return {"joints": [j["name"] for j in joints], "states": out, "pinocchio": pin.__version__}


if __name__ == "__main__":
    json.dump({p.rsplit("/", 1)[-1]: goldens(p) for p in sys.argv[1:]}, sys.stdout, indent=1, allow_nan=False)
    print()
