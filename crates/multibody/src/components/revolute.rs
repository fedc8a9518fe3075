//! Revolute: rotation about one axis.

use super::coordinate_joint::{CoordinateJoint, FLANGES};
use super::shapes::{joint_cylinder, LocalShape};
use super::spec::{ComponentSpec, ConnectorSpec, ConnectorType, Default, ParamSpec, ParamType, VarSpec};
use super::{Component, ParamSet, StateNames};
use crate::system::joint::JointModel;
use crate::Error;

pub static SPEC: ComponentSpec = ComponentSpec {
    kind: "Revolute",
    doc: "Revolute joint: frame_b rotates relative to frame_a by the angle phi about the axis n (resolved in \
          frame_a, the same in frame_b). 1-D rotational elements (dampers, springs, torque sources) act on the \
          joint through its axis and support splines.",
    params: &[
        ParamSpec::boolean("iscut", false, "Prefer this joint as the cut of a kinematic loop"),
        ParamSpec::integer("statePriority", 4.0, "State priority of phi and w (kept for compatibility)"),
        ParamSpec {
            name: "rooted",
            ty: ParamType::Enum("RootedFrame", &["FrameA", "FrameB"]),
            default: Default::Enum("FrameA"),
            unit: "",
            doc: "Which frame is closer to the root of the tree (kept for compatibility; the tree is found automatically)",
        },
        ParamSpec::boolean("axisflange", false, "Use the axis and support splines (they are always available here)"),
        ParamSpec::boolean("render", true, "Render the joint in animations"),
        ParamSpec::world("color", ParamType::Vector(4), "default_joint_color", 1.0, "", "Colour (RGBA)"),
        ParamSpec::real("specular_coefficient", 1.5, "", "Reflection of light in animations"),
        ParamSpec::vector("n", &[0.0, 0.0, 1.0], "", "axis of rotation"),
        ParamSpec::world("radius", ParamType::Real, "default_joint_width", 0.5, "m", "Radius of the revolute cylinder in animations"),
        ParamSpec::world("cylinder_length", ParamType::Real, "default_joint_length", 1.0, "m", "Length of the revolute cylinder in animations"),
    ],
    connectors: &[
        ConnectorSpec::frame("frame_a", "The frame the joint is mounted on"),
        ConnectorSpec::frame("frame_b", "The rotating frame"),
        ConnectorSpec::flange("axis", ConnectorType::Spline, "Spline that rotates with the joint angle"),
        ConnectorSpec::flange("support", ConnectorType::Spline, "Spline fixed to frame_a (reaction side)"),
    ],
    variables: VARIABLES,
    build,
    shapes,
};

/// A cylinder along the axis, centred on the joint.
fn shapes(p: &ParamSet) -> Vec<LocalShape> {
    let Ok(n) = p.direction("n") else { return Vec::new() };
    joint_cylinder(p, "frame_a", n, p.real("cylinder_length"), 2.0 * p.real("radius"))
}

pub(crate) const VARIABLES: &[VarSpec] = &[
    VarSpec::scalar("phi", "rad", "Relative rotation angle from frame_a to frame_b"),
    VarSpec::scalar("w", "rad/s", "Relative angular velocity (= der(phi))"),
    VarSpec::scalar("a", "rad/s2", "Relative angular acceleration (= der(w))"),
    VarSpec::scalar("tau", "N.m", "Driving torque in the direction of the axis, from the elements on the axis"),
];

const STATES: StateNames = StateNames { q: &[("phi", 1)], u: &[("w", 1)] };

fn build(p: &ParamSet) -> Result<Box<dyn Component>, Error> {
    Ok(Box::new(joint(p.direction("n")?, p.boolean("iscut"))))
}

/// The joint along the unit `axis`, with its states, variables and flanges
/// (URDFRevolute reuses it behind a fixed offset).
pub(crate) fn joint(axis: crate::math::Vec3, iscut: bool) -> CoordinateJoint {
    CoordinateJoint {
        model: JointModel::Revolute { axis },
        states: STATES,
        variables: VARIABLES,
        flanges: Some(FLANGES),
        iscut,
    }
}
