//! WorldTorque: an external torque on one frame from three signal inputs.

use super::external_load::{applied_vector_arrow, resolve_param, ExternalLoad};
use super::shapes::LocalShape;
use super::spec::{ComponentSpec, ConnectorSpec, ParamSpec, ParamType, VarSpec};
use super::{Component, ParamSet, Resolve};
use crate::Error;

pub static SPEC: ComponentSpec = ComponentSpec {
    kind: "WorldTorque",
    doc: "External torque acting on frame_b, defined by the inputs torque_x, torque_y, torque_z resolved in the \
          world frame (default) or in frame_b. No force.",
    params: &[
        resolve_param("World", &["World", "FrameB"]),
        ParamSpec::real("scale", 0.1, "m/(N.m)", "Scale factor for visualization"),
        ParamSpec::world(
            "color",
            ParamType::Vector(4),
            "default_force_color",
            1.0,
            "",
            "Colour of torque arrow (RGBA)",
        ),
        ParamSpec::world("radius", ParamType::Real, "default_arrow_diameter", 1.0, "m", "Radius of torque arrow"),
    ],
    connectors: &[
        ConnectorSpec::frame("frame_b", "The torque acts on this frame"),
        ConnectorSpec::input("torque_x", "x component of the torque"),
        ConnectorSpec::input("torque_y", "y component of the torque"),
        ConnectorSpec::input("torque_z", "z component of the torque"),
    ],
    variables: VARIABLES,
    build,
    shapes,
};

/// An arrow along the applied vector.
fn shapes(p: &ParamSet) -> Vec<LocalShape> {
    applied_vector_arrow(p, "t_world")
}

const VARIABLES: &[VarSpec] = &[VarSpec::vector("t_world", 3, "N.m", "Applied torque in world frame")];

fn build(p: &ParamSet) -> Result<Box<dyn Component>, Error> {
    let resolve = Resolve::from_variant(p.variant("resolve_in_frame"));
    Ok(Box::new(ExternalLoad { torque: true, resolve, two_frames: false, variables: VARIABLES }))
}
