//! WorldForce: an external force on one frame from three signal inputs.

use super::external_load::{applied_vector_arrow, resolve_param, ExternalLoad};
use super::shapes::LocalShape;
use super::spec::{ComponentSpec, ConnectorSpec, ParamSpec, ParamType, VarSpec};
use super::{Component, ParamSet, Resolve};
use crate::Error;

pub static SPEC: ComponentSpec = ComponentSpec {
    kind: "WorldForce",
    doc: "External force acting at the origin of frame_b, defined by the inputs force_x, force_y, force_z \
          resolved in the world frame (default) or in frame_b. No torque.",
    params: &[
        resolve_param("World", &["World", "FrameB"]),
        ParamSpec::boolean("render", true, "Render the force arrow in animations"),
        ParamSpec::world("color", ParamType::Vector(4), "default_force_color", 1.0, "", "Colour (RGBA)"),
        ParamSpec::real("specular_coefficient", 1.5, "", "Reflection of light in animations"),
        ParamSpec::real("scale", 0.1, "m/N", "Scale factor for visualization"),
        ParamSpec::world("radius", ParamType::Real, "default_arrow_diameter", 1.0, "m", "Radius of force arrow"),
    ],
    connectors: &[
        ConnectorSpec::frame("frame_b", "The force acts at this frame's origin"),
        ConnectorSpec::input("force_x", "x component of the force"),
        ConnectorSpec::input("force_y", "y component of the force"),
        ConnectorSpec::input("force_z", "z component of the force"),
    ],
    variables: VARIABLES,
    build,
    shapes,
};

/// An arrow along the applied vector.
fn shapes(p: &ParamSet) -> Vec<LocalShape> {
    applied_vector_arrow(p, "f_world")
}

const VARIABLES: &[VarSpec] = &[VarSpec::vector("f_world", 3, "N", "Applied force in world frame")];

fn build(p: &ParamSet) -> Result<Box<dyn Component>, Error> {
    let resolve = Resolve::from_variant(p.variant("resolve_in_frame"));
    Ok(Box::new(ExternalLoad { torque: false, resolve, two_frames: false, variables: VARIABLES }))
}
