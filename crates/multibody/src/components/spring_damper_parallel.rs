//! SpringDamperParallel: a linear spring and damper in parallel, as a line force.

use super::line_force::helix;
use super::line_force::{LineForce, FIXED_ROTATION_A, FIXED_ROTATION_B, S_SMALL, VARIABLES};
use super::shapes::LocalShape;
use super::spec::{ComponentSpec, ConnectorSpec, ParamSpec, ParamType};
use super::{Component, ParamSet};
use crate::Error;

pub static SPEC: ComponentSpec = ComponentSpec {
    kind: "SpringDamperParallel",
    doc: "Linear spring and linear damper in parallel, acting as a line force between frame_a and frame_b: \
          f = c (s - s_unstretched) + d der(s). No torques.",
    params: &[
        FIXED_ROTATION_A,
        FIXED_ROTATION_B,
        S_SMALL,
        ParamSpec::boolean("render", true, "Render the element in animations"),
        ParamSpec::world("color", ParamType::Vector(4), "default_spring_color", 1.0, "", "Colour (RGBA)"),
        ParamSpec::real("specular_coefficient", 1.5, "", "Reflection of light in animations"),
        ParamSpec::real("c", 1.0, "N/m", "Spring constant"),
        ParamSpec::real("d", 1.0, "N.s/m", "Damping coefficient"),
        ParamSpec::real("s_unstretched", 0.0, "m", "Unstretched spring length"),
        ParamSpec::world("radius", ParamType::Real, "default_force_width", 1.0, "m", "Radius in animations"),
        ParamSpec::real("num_windings", 6.0, "", "Number of windings in animations"),
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
    Ok(Box::new(LineForce {
        c: p.non_negative("c", true)?,
        d: p.non_negative("d", true)?,
        s_unstretched: p.non_negative("s_unstretched", true)?,
        s_small: p.non_negative("s_small", false)?,
        fixed_rotation: [p.boolean("fixed_rotation_at_frame_a"), p.boolean("fixed_rotation_at_frame_b")],
    }))
}
