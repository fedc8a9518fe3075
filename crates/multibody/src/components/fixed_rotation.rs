//! FixedRotation: frame_b translated by `r` and rotated by `angle` about `n`.

use super::spec::{ComponentSpec, ConnectorSpec, Default, ParamSpec, ParamType};
use super::{Component, ParamSet, Part};
use crate::math::{planar_rotation, Transform};
use crate::Error;

pub static SPEC: ComponentSpec = ComponentSpec {
    kind: "FixedRotation",
    doc: "Fixed translation and rotation of frame_b with respect to frame_a: frame_b's origin is at r \
          (resolved in frame_a) and frame_b is rotated by angle (radians) about the axis n.",
    params: &[
        ParamSpec {
            name: "rooted",
            ty: ParamType::Enum("RootedFrame", &["FrameA", "FrameB"]),
            default: Default::Enum("FrameA"),
            unit: "",
            doc: "Which frame is closer to the root of the tree (kept for compatibility; the tree is found automatically)",
        },
        ParamSpec::vector("r", &[0.0, 0.0, 0.0], "m", "Position vector from frame_a to frame_b, resolved in frame_a"),
        ParamSpec::vector("n", &[1.0, 0.0, 0.0], "", "Axis of rotation resolved in frame_a"),
        ParamSpec::real("angle", 0.0, "rad", "Angle of rotation around n"),
        ParamSpec::boolean("render", true, "Render the component in animations"),
    ],
    connectors: &[
        ConnectorSpec::frame("frame_a", "The reference frame"),
        ConnectorSpec::frame("frame_b", "The translated and rotated frame"),
    ],
    variables: &[],
    build,
    shapes: super::shapes::none,
};

#[derive(Debug)]
struct FixedRotation {
    pose: Transform,
}

fn build(p: &ParamSet) -> Result<Box<dyn Component>, Error> {
    let n = p.direction("n")?;
    Ok(Box::new(FixedRotation { pose: Transform::new(planar_rotation(&n, p.real("angle")), p.vec3("r")) }))
}

impl Component for FixedRotation {
    fn parts(&self) -> Vec<Part> {
        vec![Part::Rigid { a: 0, b: 1, pose: self.pose }]
    }
}
