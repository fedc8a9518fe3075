//! Fixed: a frame rigidly attached to the world at a translation `r`.

use super::spec::{ComponentSpec, ConnectorSpec, ParamSpec};
use super::{Component, ParamSet, Part};
use crate::math::{Transform, Vec3};
use crate::Error;

pub static SPEC: ComponentSpec = ComponentSpec {
    kind: "Fixed",
    doc: "A frame rigidly attached to the world frame with translation r from the world origin, resolved in the \
          world frame. Its orientation is the world's.",
    params: &[
        ParamSpec::vector(
            "r",
            &[0.0, 0.0, 0.0],
            "m",
            "Position vector from world frame to frame_b, resolved in world frame",
        ),
        ParamSpec::boolean("render", true, "Render the component in animations"),
    ],
    connectors: &[ConnectorSpec::frame("frame_b", "The fixed frame")],
    variables: &[],
    build,
    shapes: super::shapes::none,
};

#[derive(Debug)]
struct Fixed {
    r: Vec3,
}

fn build(p: &ParamSet) -> Result<Box<dyn Component>, Error> {
    Ok(Box::new(Fixed { r: p.vec3("r") }))
}

impl Component for Fixed {
    fn parts(&self) -> Vec<Part> {
        vec![Part::Ground { frame: 0, pose: Transform::translation(self.r) }]
    }
}
