//! FixedTranslation: a massless rod from frame_a to frame_b.

use super::spec::{ComponentSpec, ConnectorSpec, ParamSpec, ParamType};
use super::{Component, ParamSet, Part};
use crate::math::{Transform, Vec3};
use crate::Error;

pub static SPEC: ComponentSpec = ComponentSpec {
    kind: "FixedTranslation",
    doc: "Fixed translation between two frames: frame_b is displaced from frame_a by the vector r resolved in \
          frame_a; the orientation is the same. Forces and torques are balanced across it.",
    params: &[
        ParamSpec::boolean("render", true, "Render the rod in animations"),
        ParamSpec::world("color", ParamType::Vector(4), "default_rod_color", 1.0, "", "Colour (RGBA)"),
        ParamSpec::real("specular_coefficient", 1.5, "", "Reflection of light in animations"),
        ParamSpec::vector("r", &[0.0, 0.0, 0.0], "m", "position vector from frame_a to frame_b, resolved in frame_a"),
        ParamSpec::derived(
            "radius",
            ParamType::Real,
            "norm(r) / world.default_width_fraction",
            "m",
            "Radius of the rod in animations",
        ),
    ],
    connectors: &[
        ConnectorSpec::frame("frame_a", "Start of the rod"),
        ConnectorSpec::frame("frame_b", "End of the rod, at frame_a + r"),
    ],
    variables: &[],
    build,
};

#[derive(Debug)]
struct FixedTranslation {
    r: Vec3,
}

fn build(p: &ParamSet) -> Result<Box<dyn Component>, Error> {
    Ok(Box::new(FixedTranslation { r: p.vec3("r") }))
}

impl Component for FixedTranslation {
    fn parts(&self) -> Vec<Part> {
        vec![Part::Rigid { a: 0, b: 1, pose: Transform::translation(self.r) }]
    }
}
