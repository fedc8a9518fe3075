//! RevoluteConstraint: a revolute joint as a constraint, for closing loops.

use super::constraint_joint::{
    color, locked, sphere_shapes, ConstraintJoint, RENDER, SPECULAR, SPHERE_DIAMETER, X_LOCKED, Y_LOCKED, Z_LOCKED,
};
use super::spec::{ComponentSpec, ConnectorSpec, ParamSpec};
use super::{Component, ConstraintKind, ParamSet, RotationLock};
use crate::Error;

pub static SPEC: ComponentSpec = ComponentSpec {
    kind: "RevoluteConstraint",
    doc: "Revolute cut-joint: frame_b keeps one rotational degree of freedom about the axis n relative to frame_a, without states (an implicit joint for closing kinematic loops). The translations along frame_a's axes can be released one by one with x_locked, y_locked, z_locked.",
    params: &[
        ParamSpec::vector("n", &[0.0, 0.0, 1.0], "", "Axis of rotation, resolved in frame_a"),
        X_LOCKED,
        Y_LOCKED,
        Z_LOCKED,
        RENDER,
        color("default_joint_color"),
        SPECULAR,
        SPHERE_DIAMETER,
    ],
    connectors: &[ConnectorSpec::frame("frame_a", "First frame"), ConnectorSpec::frame("frame_b", "Second frame")],
    variables: &[],
    build,
    shapes: sphere_shapes,
};

fn build(p: &ParamSet) -> Result<Box<dyn Component>, Error> {
    let kind = ConstraintKind::locking_axes(RotationLock::AllBut(p.direction("n")?), locked(p));
    Ok(Box::new(ConstraintJoint { kind }))
}
