//! Universal: two revolutes in series with perpendicular axes.

use super::coordinate_joint::CoordinateJoint;
use super::shapes::{joint_cylinder, LocalShape};
use super::spec::{ComponentSpec, ConnectorSpec, Default, ParamSpec, ParamType, VarSpec};
use super::{Component, ParamSet, StateNames};
use crate::system::joint::JointModel;
use crate::Error;

pub static SPEC: ComponentSpec = ComponentSpec {
    kind: "Universal",
    doc: "Universal joint: rotation phi_a about n_a (fixed in frame_a), then rotation phi_b about n_b (fixed in \
          frame_b). The frames coincide when both angles are zero.",
    params: &[
        ParamSpec {
            name: "rooted",
            ty: ParamType::Enum("RootedFrame", &["FrameA", "FrameB"]),
            default: Default::Enum("FrameA"),
            unit: "",
            doc: "Which frame is closer to the root of the tree (kept for compatibility; the tree is found automatically)",
        },
        ParamSpec::integer("statePriority", 10.0, "State priority (kept for compatibility)"),
        ParamSpec::boolean("render", true, "Render the joint in animations"),
        ParamSpec::world("color", ParamType::Vector(4), "default_joint_color", 1.0, "", "Colour (RGBA)"),
        ParamSpec::real("specular_coefficient", 1.5, "", "Reflection of light in animations"),
        ParamSpec::vector("n_a", &[1.0, 0.0, 0.0], "", "Axis of rotation of revolute joint a, resolved in frame_a"),
        ParamSpec::vector("n_b", &[0.0, 1.0, 0.0], "", "Axis of rotation of revolute joint b, resolved in frame_b"),
        ParamSpec::world("radius", ParamType::Real, "default_joint_width", 0.5, "m", "Radius of the revolute cylinders in animations"),
        ParamSpec::world("cylinder_length", ParamType::Real, "default_joint_length", 1.0, "m", "Length of the revolute cylinders in animations"),
    ],
    connectors: &[
        ConnectorSpec::frame("frame_a", "The frame the joint is mounted on"),
        ConnectorSpec::frame("frame_b", "The moving frame"),
    ],
    variables: VARIABLES,
    build,
    shapes,
};

/// A cylinder along each axis.
fn shapes(p: &ParamSet) -> Vec<LocalShape> {
    let (Ok(n_a), Ok(n_b)) = (p.direction("n_a"), p.direction("n_b")) else { return Vec::new() };
    let (l, d) = (p.real("cylinder_length"), 2.0 * p.real("radius"));
    let mut out = joint_cylinder(p, "frame_a", n_a, l, d);
    out.extend(joint_cylinder(p, "frame_b", n_b, l, d));
    out
}

const VARIABLES: &[VarSpec] = &[
    VarSpec::scalar("phi_a", "rad", "Angle of revolute joint a"),
    VarSpec::scalar("phi_b", "rad", "Angle of revolute joint b"),
    VarSpec::scalar("w_a", "rad/s", "Angular velocity of revolute joint a (= der(phi_a))"),
    VarSpec::scalar("w_b", "rad/s", "Angular velocity of revolute joint b (= der(phi_b))"),
    VarSpec::scalar("a_a", "rad/s2", "Angular acceleration of revolute joint a"),
    VarSpec::scalar("a_b", "rad/s2", "Angular acceleration of revolute joint b"),
];

const STATES: StateNames = StateNames { q: &[("phi_a", 1), ("phi_b", 1)], u: &[("w_a", 1), ("w_b", 1)] };

fn build(p: &ParamSet) -> Result<Box<dyn Component>, Error> {
    let (n_a, n_b) = (p.direction("n_a")?, p.direction("n_b")?);
    if n_a.cross(&n_b).norm() < 1e-6 {
        return Err(p.invalid("n_b", "the two axes must differ (ideally be perpendicular)"));
    }
    Ok(Box::new(CoordinateJoint {
        model: JointModel::Universal { n_a, n_b },
        states: STATES,
        variables: VARIABLES,
        flanges: None,
        iscut: false,
    }))
}
