//! Damper: a linear damper acting as a line force between two frames.

use super::line_force::{LineForce, FIXED_ROTATION_A, FIXED_ROTATION_B, S_SMALL, VARIABLES};
use super::shapes::{between, look, LocalShape, ShapeKind};
use super::spec::{ComponentSpec, ConnectorSpec, ParamSpec, ParamType};
use super::{Component, ParamSet};
use crate::Error;

pub static SPEC: ComponentSpec = ComponentSpec {
    kind: "Damper",
    doc: "Linear damper acting as a line force between frame_a and frame_b: f = d der(s), with s the distance \
          between the origins, along the line between them. No torques.",
    params: &[
        FIXED_ROTATION_A,
        FIXED_ROTATION_B,
        S_SMALL,
        ParamSpec::boolean("render", true, "Render the damper in animations"),
        ParamSpec::vector("color", &[0.5, 0.5, 0.5, 1.0], "", "Colour (RGBA)"),
        ParamSpec::real("specular_coefficient", 1.5, "", "Reflection of light in animations"),
        ParamSpec::real("d", 1.0, "N.s/m", "Damping coefficient"),
        ParamSpec::world("radius", ParamType::Real, "default_force_width", 1.0, "m", "Radius of damper in animations"),
        ParamSpec::world(
            "length_fraction",
            ParamType::Real,
            "default_force_length",
            1.0,
            "",
            "Fraction of the length rendered",
        ),
    ],
    connectors: &[ConnectorSpec::frame("frame_a", "First end"), ConnectorSpec::frame("frame_b", "Second end")],
    variables: VARIABLES,
    build,
    shapes,
};

/// A cylinder between the frames.
fn shapes(p: &ParamSet) -> Vec<LocalShape> {
    if !p.boolean("render") {
        return Vec::new();
    }
    let (color, specular) = look(p);
    let d = 2.0 * p.real("radius");
    vec![between(ShapeKind::Cylinder, "frame_a", "frame_b", d, d).colored(color, specular)]
}

fn build(p: &ParamSet) -> Result<Box<dyn Component>, Error> {
    Ok(Box::new(LineForce {
        c: 0.0,
        d: p.non_negative("d", true)?,
        s_unstretched: 0.0,
        s_small: p.non_negative("s_small", false)?,
        fixed_rotation: [p.boolean("fixed_rotation_at_frame_a"), p.boolean("fixed_rotation_at_frame_b")],
    }))
}
