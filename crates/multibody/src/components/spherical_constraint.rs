//! SphericalConstraint: a ball joint as a constraint, for closing loops.

use super::constraint_joint::{
    color, locked, sphere_shapes, ConstraintJoint, RENDER, SPECULAR, SPHERE_DIAMETER, X_LOCKED, Y_LOCKED, Z_LOCKED,
};
use super::spec::{ComponentSpec, ConnectorSpec};
use super::{Component, ConstraintKind, ParamSet, RotationLock};
use crate::Error;

pub static SPEC: ComponentSpec = ComponentSpec {
    kind: "SphericalConstraint",
    doc: "Spherical cut-joint (ball joint): the origins of the frames coincide along the locked axes of frame_a (x_locked, y_locked, z_locked); the rotation is free and no torque is transmitted. No states (an implicit joint for closing kinematic loops).",
    params: &[
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
    Ok(Box::new(ConstraintJoint { kind: ConstraintKind::locking_axes(RotationLock::Free, locked(p)) }))
}
