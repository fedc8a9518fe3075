"""Robots from URDF in Python: Model.joint_space() of the test robots of
crates/multibody-dyad/tests/urdf, with a fixed and a floating base, against
Pinocchio's values kept there (scripts/urdf_goldens.py): mass matrix,
forward and inverse dynamics and link poses; and a bad file's message."""

import json
from pathlib import Path

import numpy as np
import pytest

import multibody

FOLDER = Path(__file__).resolve().parents[2] / "multibody-dyad" / "tests" / "urdf"
GOLDENS = json.loads((FOLDER / "goldens.json").read_text())
# The files' joint and link names are Dyad names as they are.
ROOTS = {"arm6.urdf": "base", "damped.urdf": "base", "free_joints.urdf": "table"}


def ours(space, golden):
    """Where each of Pinocchio's coordinates is in ours, in its order."""
    root = ROOTS[golden["file"]]
    q_at, v_at = [], []
    for joint in golden["joints"]:
        name = root if joint["name"] == "root_joint" else joint["name"]
        q_at += [k for k, c in enumerate(space.coordinates) if c.startswith(name + ".")]
        v_at += [k for k, c in enumerate(space.velocities) if c.startswith(name + ".")]
    assert len(q_at) == len(space.coordinates) and len(v_at) == len(space.velocities)
    return np.array(q_at), np.array(v_at)


# The damped variant's values have the file's damping (which the import
# keeps by default) as joint torques.
@pytest.mark.parametrize(
    "variant", ["arm6.urdf", "arm6.urdf floating", "damped.urdf damped", "free_joints.urdf", "free_joints.urdf floating"]
)
def test_joint_space_equals_pinocchio(variant):
    golden = dict(GOLDENS[variant], file=variant.split(" ")[0])
    model = multibody.load(FOLDER / golden["file"], floating=golden["floating"])
    space = model.joint_space()
    q_at, v_at = ours(space, golden)
    worst = 0.0
    for state in golden["states"]:
        q = np.zeros(len(q_at))
        q[q_at] = state["q"]
        v, a = np.zeros(len(v_at)), np.zeros(len(v_at))
        v[v_at], a[v_at] = state["v"], state["a"]
        mass = space.mass_matrix(q)[np.ix_(v_at, v_at)]
        worst = max(worst, np.abs(mass - np.array(state["M"])).max() / np.abs(state["M"]).max())
        tau = space.inverse_dynamics(q, v, a)[v_at]
        worst = max(worst, np.abs(tau - state["tau"]).max() / max(1.0, np.abs(state["tau"]).max()))
        ddq = space.forward_dynamics(q, v)[v_at]
        worst = max(worst, np.abs(ddq - state["ddq"]).max() / max(1.0, np.abs(state["ddq"]).max()))
        for link, pose in state["poses"].items():
            r, rotation = space.frame_pose(link, q)
            worst = max(worst, np.abs(np.concatenate([r, rotation.ravel()]) - pose).max())
    assert worst < 1e-10, worst


def test_a_bad_urdf_file_names_its_place(tmp_path):
    bad = tmp_path / "bad.urdf"
    bad.write_text('<robot name="r">\n  <link name="a">\n    <inertial><mass value="-1"/></inertial>\n  </link>\n</robot>\n')
    with pytest.raises(multibody.ModelError) as raised:
        multibody.load(bad)
    assert raised.value.line == 3 and "negative mass" in raised.value.message


def test_joint_space_errors_are_value_errors():
    space = multibody.load(FOLDER / "arm6.urdf").joint_space()
    with pytest.raises(ValueError, match="q has 2 values for 5 position coordinates"):
        space.mass_matrix([0.0, 0.0])
    with pytest.raises(ValueError, match="no component or frame `elbo`"):
        space.frame_pose("elbo", np.zeros(5))
