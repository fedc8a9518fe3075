//! PrismaticConstraint: a prismatic joint as a constraint, for closing loops.

use super::constraint_joint::{
    color, locked, sphere_shapes, ConstraintJoint, RENDER, SPECULAR, SPHERE_DIAMETER, X_LOCKED, Y_LOCKED, Z_LOCKED,
};
use super::spec::{ComponentSpec, ConnectorSpec};
use super::{Component, ConstraintKind, ParamSet, RotationLock};
use crate::Error;

pub static SPEC: ComponentSpec = ComponentSpec {
    kind: "PrismaticConstraint",
    doc: "Prismatic cut-joint: frame_b keeps frame_a's orientation; the translations along frame_a's axes are locked or released one by one with x_locked, y_locked, z_locked (release one to slide along it). No states (an implicit joint for closing kinematic loops).",
    params: &[
        X_LOCKED,
        Y_LOCKED,
        Z_LOCKED,
        RENDER,
        color("default_prismatic_color"),
        SPECULAR,
        SPHERE_DIAMETER,
    ],
    connectors: &[ConnectorSpec::frame("frame_a", "First frame"), ConnectorSpec::frame("frame_b", "Second frame")],
    variables: &[],
    build,
    shapes: sphere_shapes,
};

fn build(p: &ParamSet) -> Result<Box<dyn Component>, Error> {
    let kind = ConstraintKind::locking_axes(RotationLock::All, locked(p));
    Ok(Box::new(ConstraintJoint { kind }))
}
