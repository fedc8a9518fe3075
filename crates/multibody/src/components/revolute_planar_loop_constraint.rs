//! RevolutePlanarLoopConstraint: the in-plane position constraints of a revolute.

use super::constraint_joint::ConstraintJoint;
use super::spec::{ComponentSpec, ConnectorSpec, ParamSpec, ParamType};
use super::{Component, ConstraintKind, ParamSet, RotationLock};
use crate::Error;

pub static SPEC: ComponentSpec = ComponentSpec {
    kind: "RevolutePlanarLoopConstraint",
    doc: "Revolute joint for closing planar loops in other tools: it keeps only the two in-plane position \
          constraints (perpendicular to n). Accepted for compatibility: loops close here without it, since \
          redundant constraints are handled automatically.",
    params: &[
        ParamSpec::boolean("render", true, "Render the joint in animations"),
        ParamSpec::world("color", ParamType::Vector(4), "default_joint_color", 1.0, "", "Colour (RGBA)"),
        ParamSpec::real("specular_coefficient", 1.5, "", "Reflection of light in animations"),
        ParamSpec::vector("n", &[0.0, 0.0, 1.0], "", "axis of rotation (unit vector) resolved in frame_a"),
        ParamSpec::world(
            "radius",
            ParamType::Real,
            "default_joint_width",
            0.5,
            "m",
            "Radius of the revolute cylinder in animations",
        ),
        ParamSpec::world(
            "cylinder_length",
            ParamType::Real,
            "default_joint_length",
            1.0,
            "m",
            "Length of the revolute cylinder in animations",
        ),
    ],
    connectors: &[ConnectorSpec::frame("frame_a", "First frame"), ConnectorSpec::frame("frame_b", "Second frame")],
    variables: &[],
    build,
    shapes,
};

fn build(p: &ParamSet) -> Result<Box<dyn Component>, Error> {
    let n = p.direction("n")?;
    let e1 = crate::math::width_direction(&n);
    let kind =
        ConstraintKind::Locks { rotation: RotationLock::Free, directions: [e1, n.cross(&e1), n * 0.0], count: 2 };
    Ok(Box::new(ConstraintJoint { kind }))
}

fn shapes(p: &ParamSet) -> Vec<super::shapes::LocalShape> {
    let Ok(n) = p.direction("n") else { return Vec::new() };
    super::shapes::joint_cylinder(p, "frame_a", n, p.real("cylinder_length"), 2.0 * p.real("radius"))
}
