//! CutMount: a mount between two frames that locks the chosen relative
//! translations and rotations (along and about frame_a's axes) and
//! transmits no reaction in the others. Releasing exactly the redundant
//! directions of a loop leaves a stress-free, statically determinate
//! closure; both frames must be positioned by other paths.

use super::constraint_joint::ConstraintJoint;
use super::spec::{ComponentSpec, ConnectorSpec, ParamSpec};
use super::{Component, ConstraintKind, ParamSet, RotationLock};
use crate::Error;

pub static SPEC: ComponentSpec = ComponentSpec {
    kind: "CutMount",
    doc: "Locks the relative translations along, and rotations about, frame_a's axes that are marked locked \
          (all by default); a released direction carries no reaction, and the rest of the mechanism must \
          decide it. It closes loops only: it positions neither frame.",
    params: &[
        ParamSpec::boolean("x_locked", true, "Lock the relative translation along frame_a's x axis"),
        ParamSpec::boolean("y_locked", true, "Lock the relative translation along frame_a's y axis"),
        ParamSpec::boolean("z_locked", true, "Lock the relative translation along frame_a's z axis"),
        ParamSpec::boolean("rx_locked", true, "Lock the relative rotation about frame_a's x axis"),
        ParamSpec::boolean("ry_locked", true, "Lock the relative rotation about frame_a's y axis"),
        ParamSpec::boolean("rz_locked", true, "Lock the relative rotation about frame_a's z axis"),
    ],
    connectors: &[
        ConnectorSpec::frame("frame_a", "The frame whose axes the locks follow"),
        ConnectorSpec::frame("frame_b", "The mounted frame"),
    ],
    variables: &[],
    build,
    shapes: super::shapes::none,
};

fn build(p: &ParamSet) -> Result<Box<dyn Component>, Error> {
    let translations = ["x_locked", "y_locked", "z_locked"].map(|n| p.boolean(n));
    let rotations = ["rx_locked", "ry_locked", "rz_locked"].map(|n| p.boolean(n));
    if !translations.iter().chain(&rotations).any(|l| *l) {
        return Err(p.invalid("x_locked", "a mount that locks nothing does nothing: lock at least one direction"));
    }
    Ok(Box::new(ConstraintJoint { kind: ConstraintKind::locking_axes(RotationLock::Axes(rotations), translations) }))
}
