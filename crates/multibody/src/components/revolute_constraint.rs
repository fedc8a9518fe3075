//! RevoluteConstraint: a revolute joint as a constraint, for closing loops.

use super::constraint_joint::{locked, sphere_shapes, ConstraintJoint, X_LOCKED, Y_LOCKED, Z_LOCKED};
use super::spec::{ComponentSpec, ConnectorSpec, ParamSpec, ParamType};
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
        ParamSpec::boolean("render", true, "Render the joint in animations"),
        ParamSpec::world("color", ParamType::Vector(4), "default_joint_color", 1.0, "", "Colour (RGBA)"),
        ParamSpec::real("specular_coefficient", 1.5, "", "Reflection of light in animations"),
        ParamSpec::world("sphere_diameter", ParamType::Real, "default_joint_length", 1.0 / 3.0, "m", "Diameter of the sphere in animations"),
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
