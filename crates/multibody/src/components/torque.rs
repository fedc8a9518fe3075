//! Torque: a torque between two frames from three signal inputs.

use super::external_load::{cut_vector_arrow, resolve_param, ExternalLoad};
use super::shapes::LocalShape;
use super::spec::{ComponentSpec, ConnectorSpec, VarSpec};
use super::{Component, ParamSet, Resolve};
use crate::Error;

pub static SPEC: ComponentSpec = ComponentSpec {
    kind: "Torque",
    doc: "Torque acting between two frames, defined by the inputs torque_x, torque_y, torque_z resolved in the \
          frame resolve_in_frame: it acts on frame_b, and the opposite torque on frame_a. No force.",
    params: &[resolve_param("FrameB", Resolve::VARIANTS)],
    connectors: &[
        ConnectorSpec::frame("frame_a", "Reaction side"),
        ConnectorSpec::frame("frame_b", "The torque acts on this frame"),
        ConnectorSpec::input("torque_x", "x component of the torque"),
        ConnectorSpec::input("torque_y", "y component of the torque"),
        ConnectorSpec::input("torque_z", "z component of the torque"),
    ],
    variables: VARIABLES,
    build,
    shapes,
};

/// An arrow along the applied vector (the opposite of the cut vector at frame_b).
fn shapes(p: &ParamSet) -> Vec<LocalShape> {
    cut_vector_arrow(p, "t_b_0", "default_Nm_to_m")
}

const VARIABLES: &[VarSpec] = &[
    VarSpec::vector("r_0", 3, "m", "Position vector from frame_a to frame_b in world frame"),
    VarSpec::vector(
        "t_b_0",
        3,
        "N.m",
        "Torque at frame_b resolved in world frame (cut torque: the opposite of the applied torque)",
    ),
];

fn build(p: &ParamSet) -> Result<Box<dyn Component>, Error> {
    let resolve = Resolve::from_variant(p.variant("resolve_in_frame"));
    Ok(Box::new(ExternalLoad { torque: true, resolve, two_frames: true, variables: VARIABLES }))
}
