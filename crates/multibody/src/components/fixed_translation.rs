//! FixedTranslation: a massless rod from frame_a to frame_b.

use super::shapes::{look, LocalShape, ShapeKind};
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
    shapes,
};

/// A rod (cylinder) from frame_a to frame_b.
fn shapes(p: &ParamSet) -> Vec<LocalShape> {
    let r = p.vec3("r");
    if !p.boolean("render") || r.norm() < 1e-10 {
        return Vec::new();
    }
    let (color, specular) = look(p);
    let d = 2.0 * p.real_opt("radius").unwrap_or(r.norm() / p.world.number("default_width_fraction"));
    vec![LocalShape::in_frame(ShapeKind::Cylinder, "frame_a", Vec3::zeros(), r, d, d).colored(color, specular)]
}

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
