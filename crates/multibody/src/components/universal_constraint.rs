//! UniversalConstraint: a universal joint as a constraint, for closing loops.

use super::constraint_joint::{
    color, locked, sphere_shapes, ConstraintJoint, RENDER, SPECULAR, SPHERE_DIAMETER, X_LOCKED, Y_LOCKED, Z_LOCKED,
};
use super::spec::{ComponentSpec, ConnectorSpec, ParamSpec};
use super::{Component, ConstraintKind, ParamSet, RotationLock};
use crate::Error;

pub static SPEC: ComponentSpec = ComponentSpec {
    kind: "UniversalConstraint",
    doc: "Universal cut-joint: frame_b keeps two rotational degrees of freedom, about n_a (fixed in frame_a) and n_b (fixed in frame_b); translations along frame_a's axes are locked with x_locked, y_locked, z_locked. No states (an implicit joint for closing kinematic loops).",
    params: &[
        ParamSpec::vector("n_a", &[1.0, 0.0, 0.0], "", "Axis of rotation fixed in frame_a"),
        ParamSpec::vector("n_b", &[0.0, 1.0, 0.0], "", "Axis of rotation fixed in frame_b"),
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
    let (n_a, n_b) = (p.direction("n_a")?, p.direction("n_b")?);
    if n_a.cross(&n_b).norm() < 1e-6 {
        return Err(p.invalid("n_b", "the two axes must differ (ideally be perpendicular)"));
    }
    Ok(Box::new(ConstraintJoint {
        kind: ConstraintKind::locking_axes(RotationLock::Universal { n_a, n_b }, locked(p)),
    }))
}
