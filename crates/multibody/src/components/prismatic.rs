//! Prismatic: translation along one axis.

use super::coordinate_joint::{CoordinateJoint, FLANGES};
use super::shapes::{between, look, LocalShape, ShapeKind};
use super::spec::{ComponentSpec, ConnectorSpec, ConnectorType, ParamSpec, ParamType, VarSpec};
use super::{Component, ParamSet, StateNames};
use crate::system::joint::JointModel;
use crate::Error;

pub static SPEC: ComponentSpec = ComponentSpec {
    kind: "Prismatic",
    doc: "Prismatic joint: frame_b translates relative to frame_a by s along the axis n (resolved in frame_a); \
          the orientation is the same. 1-D translational elements act on the joint through its axis and \
          support flanges.",
    params: &[
        ParamSpec::boolean("iscut", false, "Prefer this joint as the cut of a kinematic loop"),
        ParamSpec::integer("statePriority", 3.0, "State priority of s and v (kept for compatibility)"),
        ParamSpec::boolean("axisflange", false, "Use the axis and support flanges (they are always available here)"),
        ParamSpec::boolean("render", true, "Render the joint in animations"),
        ParamSpec::world("color", ParamType::Vector(4), "default_prismatic_color", 1.0, "", "Colour (RGBA)"),
        ParamSpec::real("specular_coefficient", 1.5, "", "Reflection of light in animations"),
        ParamSpec::vector("n", &[0.0, 0.0, 1.0], "", "axis of motion"),
        ParamSpec::world(
            "box_width",
            ParamType::Real,
            "default_joint_width",
            1.0,
            "m",
            "Width of the box in animations",
        ),
        ParamSpec::world(
            "box_height",
            ParamType::Real,
            "default_joint_width",
            1.0,
            "m",
            "Height of the box in animations",
        ),
    ],
    connectors: &[
        ConnectorSpec::frame("frame_a", "The frame the joint is mounted on"),
        ConnectorSpec::frame("frame_b", "The sliding frame"),
        ConnectorSpec::flange("axis", ConnectorType::Flange, "Flange that moves with the joint coordinate"),
        ConnectorSpec::flange("support", ConnectorType::Flange, "Flange fixed to frame_a (reaction side)"),
    ],
    variables: VARIABLES,
    build,
    shapes,
};

/// A box from frame_a to frame_b.
fn shapes(p: &ParamSet) -> Vec<LocalShape> {
    if !p.boolean("render") {
        return Vec::new();
    }
    let (color, specular) = look(p);
    vec![between(ShapeKind::Box, "frame_a", "frame_b", p.real("box_width"), p.real("box_height"))
        .colored(color, specular)]
}

pub(crate) const VARIABLES: &[VarSpec] = &[
    VarSpec::scalar("s", "m", "Relative distance between frame_a and frame_b along n"),
    VarSpec::scalar("v", "m/s", "Relative velocity (= der(s))"),
    VarSpec::scalar("a", "m/s2", "Relative acceleration (= der(v))"),
    VarSpec::scalar("f", "N", "Actuation force in the direction of the axis, from the elements on the axis"),
];

const STATES: StateNames = StateNames { q: &[("s", 1)], u: &[("v", 1)] };

fn build(p: &ParamSet) -> Result<Box<dyn Component>, Error> {
    Ok(Box::new(joint(p.direction("n")?, p.boolean("iscut"))))
}

/// The joint along the unit `axis`, with its states, variables and flanges
/// (URDFPrismatic reuses it behind a fixed offset).
pub(crate) fn joint(axis: crate::math::Vec3, iscut: bool) -> CoordinateJoint {
    CoordinateJoint {
        model: JointModel::Prismatic { axis },
        states: STATES,
        variables: VARIABLES,
        flanges: Some(FLANGES),
        iscut,
    }
}
