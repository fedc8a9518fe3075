//! Cylindrical: translation along and rotation about one axis.

use super::coordinate_joint::CoordinateJoint;
use super::shapes::{joint_cylinder, LocalShape};
use super::spec::{ComponentSpec, ConnectorSpec, ParamSpec, ParamType, VarSpec};
use super::{Component, ParamSet, StateNames};
use crate::system::joint::JointModel;
use crate::Error;

pub static SPEC: ComponentSpec = ComponentSpec {
    kind: "Cylindrical",
    doc: "Cylindrical joint: frame_b translates by s along and rotates by phi about the axis n (resolved in \
          frame_a, the same in frame_b).",
    params: &[
        ParamSpec::integer("statePriority", 10.0, "State priority (kept for compatibility)"),
        ParamSpec::boolean("render", true, "Render the joint in animations"),
        ParamSpec::world("color", ParamType::Vector(4), "default_joint_color", 1.0, "", "Colour (RGBA)"),
        ParamSpec::real("specular_coefficient", 1.5, "", "Reflection of light in animations"),
        ParamSpec::vector("n", &[1.0, 0.0, 0.0], "", "Joint axis resolved in frame_a (= same as in frame_b)"),
        ParamSpec::world(
            "cylinder_diameter",
            ParamType::Real,
            "default_joint_width",
            1.0,
            "m",
            "Diameter of the cylinder in animations",
        ),
    ],
    connectors: &[
        ConnectorSpec::frame("frame_a", "The frame the joint is mounted on"),
        ConnectorSpec::frame("frame_b", "The moving frame"),
    ],
    variables: VARIABLES,
    build,
    shapes,
};

/// A cylinder along the axis, centred on frame_a.
fn shapes(p: &ParamSet) -> Vec<LocalShape> {
    let Ok(n) = p.direction("n") else { return Vec::new() };
    let d = p.real("cylinder_diameter");
    joint_cylinder(p, "frame_a", n, p.world.number("default_joint_length"), d)
}

const VARIABLES: &[VarSpec] = &[
    VarSpec::scalar("s", "m", "Translational displacement"),
    VarSpec::scalar("phi", "rad", "Rotation angle"),
    VarSpec::scalar("v", "m/s", "Translational velocity"),
    VarSpec::scalar("w", "rad/s", "Angular velocity"),
    VarSpec::scalar("a", "m/s2", "Translational acceleration"),
    VarSpec::scalar("wd", "rad/s2", "Angular acceleration"),
];

const STATES: StateNames = StateNames { q: &[("s", 1), ("phi", 1)], u: &[("v", 1), ("w", 1)] };

fn build(p: &ParamSet) -> Result<Box<dyn Component>, Error> {
    let axis = p.direction("n")?;
    Ok(Box::new(CoordinateJoint {
        model: JointModel::Cylindrical { axis },
        states: STATES,
        variables: VARIABLES,
        flanges: None,
        iscut: false,
    }))
}
