#!/usr/bin/env python3
"""Golden values of URDF robots' dynamics from Pinocchio (PyPI's `pin`),
which the URDF tests compare with, at random states (seeded): the forward
dynamics (ABA), the mass matrix (CRBA), the inverse dynamics (RNEA) at
random accelerations, and the pose of every link, with gravity
9.80665 m/s^2 along -z, for a fixed base and for a floating one
(Pinocchio's free-flyer).

Everything is written in the coordinates of our joint space
(multibody::JointSpace), converted here from Pinocchio's:
- a revolute or continuous joint: its angle (Pinocchio keeps cos and sin
  for a continuous one), its rate, its acceleration, its torque;
- a planar joint: [x, y, angle] (Pinocchio's [x, y, cos, sin]), with the
  velocities in the plane's fixed axes, where Pinocchio's are in the
  turned ones (converted as for the floating base, in two dimensions);
- the floating base (and a floating joint, relative to its parent):
  q = [r_0 (3), quaternion [w, i, j, k]] where
  Pinocchio has [x, y, z, i, j, k, w] (the same rotation: Pinocchio's
  matrix maps body to world, ours world to body, with one formula apart
  from that transpose); v = [v_0 in the world, angular velocity in the
  body], where Pinocchio's linear velocity is in the body; accelerations
  the world acceleration of the origin and der(w), where Pinocchio's are
  the spatial acceleration in the body; forces a world force and a body
  torque; and the mass matrix T' M T with v_pinocchio = T v;
- a link's pose: its origin in the world and R = oMf.rotation' (R maps
  world coordinates to the link's).

Joint damping is not in Pinocchio's dynamics. With `damped`, the forward
dynamics are Pinocchio's under the joint torques -damping * v and the
inverse dynamics its torques plus damping * v, which is what a damper on
each axis gives, so that the file's damping is compared.

Usage: scripts/urdf_goldens.py FILE.urdf... > goldens.json
Needs `pip install pin`.
"""

import json
import sys

import numpy as np
import pinocchio as pin

STATES = 10


def skew(w):
    return np.array([[0.0, -w[2], w[1]], [w[2], 0.0, -w[0]], [-w[1], w[0], 0.0]])


def goldens(path, floating=False, damped=False, seed=2026, states=STATES):
    model = pin.buildModelFromUrdf(path, pin.JointModelFreeFlyer()) if floating else pin.buildModelFromUrdf(path)
    model.gravity.linear = np.array([0.0, 0.0, -9.80665])
    data = model.createData()
    rng = np.random.default_rng(seed)
    joints = []
    for j in range(1, model.njoints):
        joint = model.joints[j]
        free, planar = joint.shortname() == "JointModelFreeFlyer", joint.shortname() == "JointModelPlanar"
        if joint.nv != 1 and not (free or planar):
            raise SystemExit(f"{path}: joint {model.names[j]} has {joint.nv} degrees of freedom")
        joints.append({"name": model.names[j], "free": free, "planar": planar, "nq_pin": joint.nq,
                       "idx_q": joint.idx_q, "idx_v": joint.idx_v, "nv": joint.nv})
    links = [f.name for f in model.frames if f.type == pin.FrameType.BODY]
    damping = np.array(model.damping) if damped else np.zeros(model.nv)
    out = []
    for _ in range(states):
        q = np.zeros(model.nq)
        ours_q = []
        for j in joints:
            if j["free"]:
                position = rng.uniform(-1.0, 1.0, 3)
                quaternion = rng.normal(size=4)
                quaternion /= np.linalg.norm(quaternion)  # [i, j, k, w] as Pinocchio stores it
                q[j["idx_q"]:j["idx_q"] + 7] = np.concatenate([position, quaternion])
                ours_q += list(position) + [quaternion[3], quaternion[0], quaternion[1], quaternion[2]]
                continue
            if j["planar"]:  # x, y, cos, sin; ours x, y, angle
                x, y, angle = rng.uniform(-1.0, 1.0), rng.uniform(-1.0, 1.0), rng.uniform(-np.pi, np.pi)
                q[j["idx_q"]:j["idx_q"] + 4] = [x, y, np.cos(angle), np.sin(angle)]
                ours_q += [x, y, angle]
                continue
            angle = rng.uniform(-np.pi, np.pi)
            if j["nq_pin"] == 2:  # continuous: cos, sin
                q[j["idx_q"]:j["idx_q"] + 2] = [np.cos(angle), np.sin(angle)]
            else:
                q[j["idx_q"]] = angle
            ours_q.append(angle)
        v = rng.uniform(-1.0, 1.0, model.nv)
        a = rng.uniform(-1.0, 1.0, model.nv)
        ddq = pin.aba(model, data, q, v, -damping * v)
        tau = pin.rnea(model, data, q, v, a) + damping * v
        mass = pin.crba(model, data, q)
        mass = np.triu(mass) + np.triu(mass, 1).T
        if not (np.all(np.isfinite(ddq)) and np.all(np.isfinite(mass))):
            # A joint with no inertia behind it: the mass matrix is singular.
            return {"joints": joints, "states": [], "singular": True, "pinocchio": pin.__version__}
        pin.framesForwardKinematics(model, data, q)
        poses = {name: list(data.oMf[model.getFrameId(name, pin.FrameType.BODY)].translation)
                 + list(data.oMf[model.getFrameId(name, pin.FrameType.BODY)].rotation.T.flatten())
                 for name in links}
        # Into our coordinates (the module's doc): v_pin = T v, a_pin = T a + dT v.
        T = np.eye(model.nv)
        ours_v, ours_a, ours_ddq = v.copy(), a.copy(), ddq.copy()
        for j in joints:
            k = j["idx_v"]
            if j["free"]:
                # The joint's own rotation, child to parent (the world's for a base).
                R = pin.XYZQUATToSE3(q[j["idx_q"]:j["idx_q"] + 7]).rotation
                w = v[k + 3:k + 6]
                T[k:k + 3, k:k + 3] = R.T
                ours_v[k:k + 3] = R @ v[k:k + 3]
                ours_a[k:k + 3] = R @ (a[k:k + 3] + np.cross(w, v[k:k + 3]))
                ours_ddq[k:k + 3] = R @ (ddq[k:k + 3] + np.cross(w, v[k:k + 3]))
            elif j["planar"]:
                # In the plane: Pinocchio's velocity is in the turned frame.
                c, s_ = q[j["idx_q"] + 2], q[j["idx_q"] + 3]
                R = np.array([[c, -s_], [s_, c]])
                w, vp = v[k + 2], v[k:k + 2]
                T[k:k + 2, k:k + 2] = R.T
                ours_v[k:k + 2] = R @ vp
                ours_a[k:k + 2] = R @ (a[k:k + 2] + w * np.array([-vp[1], vp[0]]))
                ours_ddq[k:k + 2] = R @ (ddq[k:k + 2] + w * np.array([-vp[1], vp[0]]))
        ours_tau = T.T @ tau
        ours_mass = T.T @ mass @ T
        # How much rounding the forward dynamics amplify: solving M x = b
        # loses up to cond(M) times the precision.
        out.append({"q": ours_q, "v": ours_v.tolist(), "ddq": ours_ddq.tolist(), "M": ours_mass.tolist(),
                    "a": ours_a.tolist(), "tau": ours_tau.tolist(), "poses": poses,
                    "cond": float(np.linalg.cond(mass)) if model.nv else 1.0})
    described = [{"name": j["name"], "nq": 7 if j["free"] else 3 if j["planar"] else 1, "nv": j["nv"]} for j in joints]
    return {"joints": described, "floating": floating, "damped": damped, "states": out,
            "pinocchio": pin.__version__}


def variants(path, states=STATES):
    """The fixed and floating variants of a file, and the damped one if it
    has damping, keyed as the tests read them."""
    name = path.rsplit("/", 1)[-1]
    out = {name: goldens(path, states=states), f"{name} floating": goldens(path, floating=True, states=states)}
    if np.any(np.array(pin.buildModelFromUrdf(path).damping) != 0):
        out[f"{name} damped"] = goldens(path, damped=True, states=states)
    return out


if __name__ == "__main__":
    result = {}
    for p in sys.argv[1:]:
        result.update(variants(p))
    json.dump(result, sys.stdout, indent=1, allow_nan=False)
    print()
