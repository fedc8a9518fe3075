//! Planar: motion in a plane and rotation about its normal.

use super::coordinate_joint::CoordinateJoint;
use super::spec::{ComponentSpec, ConnectorSpec, ParamSpec, ParamType, VarSpec};
use super::{Component, ParamSet, StateNames};
use crate::system::joint::JointModel;
use crate::Error;

pub static SPEC: ComponentSpec = ComponentSpec {
    kind: "Planar",
    doc: "Planar joint: frame_b translates by s_x along n_x and by s_y along n x n_x in the plane with normal n, \
          then rotates by phi about n (all resolved in frame_a).",
    params: &[
        ParamSpec::vector("n", &[0.0, 0.0, 1.0], "", "Plane normal, resolved in frame_a"),
        ParamSpec::vector("n_x", &[1.0, 0.0, 0.0], "", "Direction of the x axis in the plane, resolved in frame_a"),
        ParamSpec::integer("statePriority", 3.0, "State priority (kept for compatibility)"),
        ParamSpec::boolean("render", true, "Render the joint in animations"),
        ParamSpec::world("color", ParamType::Vector(4), "default_joint_color", 1.0, "", "Colour (RGBA)"),
        ParamSpec::real("specular_coefficient", 1.5, "", "Reflection of light in animations"),
    ],
    connectors: &[
        ConnectorSpec::frame("frame_a", "The frame the joint is mounted on"),
        ConnectorSpec::frame("frame_b", "The moving frame"),
    ],
    variables: VARIABLES,
    build,
    shapes: super::shapes::none,
};

const VARIABLES: &[VarSpec] = &[
    VarSpec::scalar("s_x", "m", "Translation along the x axis in the plane"),
    VarSpec::scalar("s_y", "m", "Translation along the y axis in the plane"),
    VarSpec::scalar("phi", "rad", "Rotation angle around the plane normal"),
    VarSpec::scalar("v_x", "m/s", "Velocity along the x axis"),
    VarSpec::scalar("v_y", "m/s", "Velocity along the y axis"),
    VarSpec::scalar("w", "rad/s", "Angular velocity"),
    VarSpec::scalar("a_x", "m/s2", "Acceleration along the x axis"),
    VarSpec::scalar("a_y", "m/s2", "Acceleration along the y axis"),
    VarSpec::scalar("wd", "rad/s2", "Angular acceleration"),
];

const STATES: StateNames =
    StateNames { q: &[("s_x", 1), ("s_y", 1), ("phi", 1)], u: &[("v_x", 1), ("v_y", 1), ("w", 1)] };

fn build(p: &ParamSet) -> Result<Box<dyn Component>, Error> {
    let n = p.direction("n")?;
    let n_x_given = p.direction("n_x")?;
    // The in-plane x axis: n_x made orthogonal to n.
    let n_x = n_x_given - n * n.dot(&n_x_given);
    if n_x.norm() < 1e-6 {
        return Err(p.invalid("n_x", "n_x must not be parallel to the plane normal n"));
    }
    let n_x = n_x.normalize();
    let model = JointModel::Planar { n, n_x, n_y: n.cross(&n_x) };
    Ok(Box::new(CoordinateJoint { model, states: STATES, variables: VARIABLES, flanges: None, iscut: false }))
}
