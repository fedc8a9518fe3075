//! URDFRevolute and URDFPrismatic: a joint behind the fixed origin
//! transform that a URDF `<joint>` carries, as a URDF importer emits them.
//!
//! frame_a -> (translation r, then rotation by angle about n) -> joint
//! frame -> (the Revolute or Prismatic along joint_n) -> frame_b. The fixed
//! part is a rigid relation to an internal frame, the joint is exactly the
//! library's Revolute or Prismatic (same states, variables and flanges).

use super::coordinate_joint::CoordinateJoint;
use super::shapes::{between, joint_cylinder, look, LocalShape, ShapeKind};
use super::spec::{ComponentSpec, ConnectorSpec, ConnectorType, ParamSpec, ParamType, VarSpec};
use super::{prismatic, revolute, Component, EvalContext, ParamSet, Part};
use crate::math::{planar_rotation, Transform};
use crate::Error;

/// The internal joint frame comes after frame_a, frame_b, axis, support.
const JOINT_FRAME: usize = 4;

const R: ParamSpec = ParamSpec::vector("r", &[0.0, 0.0, 0.0], "m", "Translation from frame_a to the joint origin");
const N: ParamSpec = ParamSpec::vector("n", &[1.0, 0.0, 0.0], "", "Axis of the fixed rotation, resolved in frame_a");
const ANGLE: ParamSpec =
    ParamSpec::real("angle", 0.0, "rad", "Angle of the fixed rotation about n (frame_a to joint frame)");

pub static REVOLUTE: ComponentSpec = ComponentSpec {
    kind: "URDFRevolute",
    doc: "Revolute joint behind a fixed origin transform, as imported from URDF: the joint frame sits at r from \
          frame_a, rotated by angle about n; frame_b turns relative to it by phi about joint_n (resolved in the \
          joint frame). States and variables are the Revolute's.",
    params: &[
        ParamSpec::boolean(
            "axisflange",
            false,
            "Expose the axis and support splines for torque actuation (they are always available here)",
        ),
        ParamSpec::boolean("render", true, "Render the joint in animations"),
        ParamSpec::world("color", ParamType::Vector(4), "default_joint_color", 1.0, "", "Colour (RGBA)"),
        ParamSpec::real("specular_coefficient", 1.5, "", "Reflection of light in animations"),
        R,
        N,
        ANGLE,
        ParamSpec::vector("joint_n", &[0.0, 0.0, 1.0], "", "Axis of the revolute joint, resolved in the joint frame"),
    ],
    connectors: &[
        ConnectorSpec::frame("frame_a", "The frame the joint's origin transform starts from (URDF parent link)"),
        ConnectorSpec::frame("frame_b", "The rotating frame (URDF child link)"),
        ConnectorSpec::flange("axis", ConnectorType::Spline, "Spline that rotates with the joint angle"),
        ConnectorSpec::flange("support", ConnectorType::Spline, "Spline fixed to the joint frame (reaction side)"),
        ConnectorSpec::internal("joint_frame", ConnectorType::Frame),
    ],
    variables: revolute::VARIABLES,
    build: |p| build(p, revolute::joint(p.direction("joint_n")?, false)),
    shapes: revolute_shapes,
};

pub static PRISMATIC: ComponentSpec = ComponentSpec {
    kind: "URDFPrismatic",
    doc: "Prismatic joint behind a fixed origin transform, as imported from URDF: the joint frame sits at r from \
          frame_a, rotated by angle about n; frame_b slides relative to it by s along joint_n (resolved in the \
          joint frame). States and variables are the Prismatic's.",
    params: &[
        ParamSpec::boolean(
            "axisflange",
            false,
            "Expose the axis and support flanges for force actuation (they are always available here)",
        ),
        ParamSpec::boolean("render", true, "Render the joint in animations"),
        ParamSpec::world("color", ParamType::Vector(4), "default_prismatic_color", 1.0, "", "Colour (RGBA)"),
        ParamSpec::real("specular_coefficient", 1.5, "", "Reflection of light in animations"),
        R,
        N,
        ANGLE,
        ParamSpec::vector("joint_n", &[0.0, 0.0, 1.0], "", "Axis of the prismatic joint, resolved in the joint frame"),
    ],
    connectors: &[
        ConnectorSpec::frame("frame_a", "The frame the joint's origin transform starts from (URDF parent link)"),
        ConnectorSpec::frame("frame_b", "The sliding frame (URDF child link)"),
        ConnectorSpec::flange("axis", ConnectorType::Flange, "Flange that moves with the joint coordinate"),
        ConnectorSpec::flange("support", ConnectorType::Flange, "Flange fixed to the joint frame (reaction side)"),
        ConnectorSpec::internal("joint_frame", ConnectorType::Frame),
    ],
    variables: prismatic::VARIABLES,
    build: |p| build(p, prismatic::joint(p.direction("joint_n")?, false)),
    shapes: prismatic_shapes,
};

/// The joint's cylinder about joint_n at frame_b's origin (the joint origin:
/// a revolute joint does not move it), sized by the World's joint defaults.
fn revolute_shapes(p: &ParamSet) -> Vec<LocalShape> {
    let Ok(n) = p.direction("joint_n") else { return Vec::new() };
    // joint_n is resolved in the joint frame; the rotation about it leaves
    // it the same in frame_b.
    let length = p.world.number("default_joint_length");
    let diameter = p.world.number("default_joint_width");
    joint_cylinder(p, "frame_b", n, length, diameter)
}

/// A box from frame_a to frame_b.
fn prismatic_shapes(p: &ParamSet) -> Vec<LocalShape> {
    if !p.boolean("render") {
        return Vec::new();
    }
    let (color, specular) = look(p);
    let w = p.world.number("default_joint_width");
    vec![between(ShapeKind::Box, "frame_a", "frame_b", w, w).colored(color, specular)]
}

#[derive(Debug)]
struct UrdfJoint {
    /// frame_a to the joint frame.
    origin: Transform,
    joint: CoordinateJoint,
}

fn build(p: &ParamSet, joint: CoordinateJoint) -> Result<Box<dyn Component>, Error> {
    let n = p.direction("n")?;
    let origin = Transform::new(planar_rotation(&n, p.real("angle")), p.vec3("r"));
    Ok(Box::new(UrdfJoint { origin, joint }))
}

impl Component for UrdfJoint {
    fn parts(&self) -> Vec<Part> {
        let mut parts = vec![Part::Rigid { a: 0, b: JOINT_FRAME, pose: self.origin }];
        // The library joint, from the internal joint frame instead of frame_a.
        parts.extend(self.joint.parts().into_iter().map(|part| match part {
            Part::Joint { a: 0, b, model, states, flanges, iscut } => {
                Part::Joint { a: JOINT_FRAME, b, model, states, flanges, iscut }
            }
            other => other,
        }));
        parts
    }

    fn variables(&self) -> Vec<VarSpec> {
        self.joint.variables()
    }

    fn evaluate(&self, ctx: &EvalContext, out: &mut Vec<f64>) {
        self.joint.evaluate(ctx, out)
    }
}
