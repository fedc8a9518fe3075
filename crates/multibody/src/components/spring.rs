//! Spring: a linear spring acting as a line force between two frames.

use super::line_force::helix;
use super::line_force::{line_mass, LineForce, WithMass, FIXED_ROTATION_A, FIXED_ROTATION_B, VARIABLES};
use super::shapes::LocalShape;
use super::spec::{ComponentSpec, ConnectorSpec, ParamSpec, ParamType};
use super::{Component, ParamSet};
use crate::Error;

pub static SPEC: ComponentSpec = ComponentSpec {
    kind: "Spring",
    doc: "Linear spring acting as a line force between frame_a and frame_b: f = c (s - s_unstretched) pulls the \
          origins together along the line between them (pushes them apart when compressed). No torques. With \
          hasmass, a point mass m sits on the line at lengthfraction of the way from frame_a to frame_b; it is \
          not a degree of freedom: its inertia and weight are shared by the two ends.",
    params: &[
        FIXED_ROTATION_A,
        FIXED_ROTATION_B,
        ParamSpec::boolean(
            "hasmass",
            false,
            "Put a point mass m on the line between the frames' origins (at lengthfraction from frame_a)",
        ),
        ParamSpec::boolean("render", true, "Render the spring in animations"),
        ParamSpec::world("color", ParamType::Vector(4), "default_spring_color", 1.0, "", "Colour (RGBA)"),
        ParamSpec::real("specular_coefficient", 1.5, "", "Reflection of light in animations"),
        ParamSpec::real("c", 1.0, "N/m", "spring constant"),
        ParamSpec::real("s_unstretched", 0.0, "m", "unstretched length of spring"),
        ParamSpec::real("m", 1.0, "kg", "mass (used only with hasmass)"),
        ParamSpec::real(
            "lengthfraction",
            0.5,
            "",
            "Location of the point mass from frame_a, as a fraction of the distance to frame_b",
        ),
        ParamSpec::world(
            "radius",
            ParamType::Real,
            "default_force_width",
            1.0,
            "m",
            "Radius of spring coil when rendered",
        ),
        ParamSpec::real("num_windings", 6.0, "", "Number of spring coil windings"),
        ParamSpec::integer("N", 200.0, "Number of points used to render each winding"),
        ParamSpec::real("end_ratio", 0.1, "", "Fraction of total length used for the tapered ends"),
    ],
    connectors: &[ConnectorSpec::frame("frame_a", "First end"), ConnectorSpec::frame("frame_b", "Second end")],
    variables: VARIABLES,
    build,
    shapes,
};

/// A coil between the frames.
fn shapes(p: &ParamSet) -> Vec<LocalShape> {
    helix(p, p.real("num_windings"))
}

fn build(p: &ParamSet) -> Result<Box<dyn Component>, Error> {
    let line = LineForce {
        c: p.non_negative("c", true)?,
        d: 0.0,
        s_unstretched: p.non_negative("s_unstretched", true)?,
        s_small: 1e-10,
        fixed_rotation: [p.boolean("fixed_rotation_at_frame_a"), p.boolean("fixed_rotation_at_frame_b")],
    };
    let mass = if p.boolean("hasmass") { line_mass(p)? } else { None };
    Ok(match mass {
        Some(mass) => Box::new(WithMass { line, mass }),
        None => Box::new(line),
    })
}
