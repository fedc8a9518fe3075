//! Rotor1D: a 1-D rotational inertia whose shaft turns about an axis fixed
//! in a 3-D frame (its carrier). Its angle and speed are relative to the
//! carrier, and it adds the gyroscopic torque of its spin on the carrier.
//! As in the Dyad and Modelica libraries, the rotor's mass and full inertia
//! belong to an ordinary body on the same frame; the Rotor1D adds only the
//! momentum of its spin relative to the carrier, `J e w`.

use super::shapes::{look, LocalShape, ShapeKind};
use super::spec::{ComponentSpec, ConnectorSpec, ConnectorType, ParamSpec, ParamType, VarSpec};
use super::{Component, EvalContext, ParamSet, Part, StateNames};
use crate::math::Vec3;
use crate::Error;

pub static SPEC: ComponentSpec = ComponentSpec {
    kind: "Rotor1D",
    doc: "1-D inertia J turning about the axis n fixed in frame_a (the bearing, or carrier): phi, w and a are \
          relative to frame_a, and J * (a + n . dw_a/dt) = flange_a.tau + flange_b.tau. The carrier receives the \
          gyroscopic torque of the spin; the rotor's mass and full inertia tensor must be a body on frame_a \
          (a BodyCylinder, say). With drive_train_mechanics_3d = false it is a plain Inertia and frame_a is unused.",
    params: &[
        ParamSpec::boolean("drive_train_mechanics_3d", true, "Take the 3-D effects of the rotor into account"),
        ParamSpec::boolean("exact", true, "Keep the carrier's angular acceleration in the rotor equation"),
        ParamSpec::boolean("render", true, "Render the rotor in animations"),
        ParamSpec::world("color", ParamType::Vector(4), "default_rod_color", 1.0, "", "Colour (RGBA)"),
        ParamSpec::real("specular_coefficient", 1.5, "", "Reflection of light in animations"),
        ParamSpec::real("J", 1.0, "kg.m2", "Moment of inertia of the rotor about its axis"),
        ParamSpec::vector("n", &[1.0, 0.0, 0.0], "", "Axis of rotation, resolved in frame_a"),
        ParamSpec::vector(
            "r_center",
            &[0.0, 0.0, 0.0],
            "m",
            "Centre of the rotor's cylinder in animations, from frame_a",
        ),
        ParamSpec::world(
            "cylinder_length",
            ParamType::Real,
            "default_joint_length",
            1.0,
            "m",
            "Length of the rotor's cylinder in animations",
        ),
        ParamSpec::world(
            "radius",
            ParamType::Real,
            "default_joint_width",
            0.5,
            "m",
            "Radius of the rotor's cylinder in animations",
        ),
    ],
    connectors: &[
        ConnectorSpec::frame("frame_a", "Bearing: the frame the rotor axis is fixed in"),
        ConnectorSpec::flange("flange_a", ConnectorType::Spline, "Shaft end a"),
        ConnectorSpec::flange("flange_b", ConnectorType::Spline, "Shaft end b"),
    ],
    variables: &[
        VarSpec::scalar("phi", "rad", "Rotation angle relative to frame_a"),
        VarSpec::scalar("w", "rad/s", "Angular velocity relative to frame_a"),
        VarSpec::scalar("a", "rad/s2", "Angular acceleration relative to frame_a"),
    ],
    build,
    shapes,
};

const STATES: StateNames = StateNames { q: &[("phi", 1)], u: &[("w", 1)] };

/// A cylinder along the axis, centred on `r_center`.
fn shapes(p: &ParamSet) -> Vec<LocalShape> {
    let Ok(n) = p.direction("n") else { return Vec::new() };
    if !p.boolean("render") {
        return Vec::new();
    }
    let (color, specular) = look(p);
    let (length, diameter) = (p.real("cylinder_length"), 2.0 * p.real("radius"));
    let start = p.vec3("r_center") - n * (length / 2.0);
    vec![LocalShape::in_frame(ShapeKind::Cylinder, "frame_a", start, n * length, diameter, diameter)
        .colored(color, specular)]
}

#[derive(Debug)]
struct Rotor1D {
    inertia: f64,
    /// The unit axis in frame_a; `None` without 3-D effects.
    axis: Option<Vec3>,
}

fn build(p: &ParamSet) -> Result<Box<dyn Component>, Error> {
    let inertia = p.non_negative("J", false)?;
    let axis = p.direction("n")?;
    if !p.boolean("exact") {
        return Err(p.invalid(
            "exact",
            "exact = false (dropping the carrier's acceleration from the rotor equation) is not supported yet; \
             the exact rotor costs no more here",
        ));
    }
    Ok(Box::new(Rotor1D { inertia, axis: p.boolean("drive_train_mechanics_3d").then_some(axis) }))
}

impl Component for Rotor1D {
    fn parts(&self) -> Vec<Part> {
        match self.axis {
            Some(axis) => vec![Part::Rotor1D { frame: 0, axis, inertia: self.inertia, a: 1, b: 2, states: STATES }],
            None => {
                vec![Part::Inertia1D { a: 1, b: 2, length: 0.0, inertia: self.inertia, weight: 0.0, states: STATES }]
            }
        }
    }

    fn variables(&self) -> Vec<VarSpec> {
        SPEC.variables.to_vec()
    }

    fn evaluate(&self, ctx: &EvalContext, out: &mut Vec<f64>) {
        let shaft = ctx.flanges[1];
        out.extend([shaft.s, shaft.v, shaft.a]);
    }
}
