//! Force: a force between two frames from three signal inputs.

use super::external_load::{cut_vector_arrow, resolve_param, ExternalLoad};
use super::shapes::LocalShape;
use super::spec::{ComponentSpec, ConnectorSpec, VarSpec};
use super::{Component, ParamSet, Resolve};
use crate::Error;

pub static SPEC: ComponentSpec = ComponentSpec {
    kind: "Force",
    doc: "Force acting between two frames, defined by the inputs force_x, force_y, force_z resolved in the frame \
          resolve_in_frame. The force acts at the origin of frame_b; the reaction (force and lever-arm torque) acts \
          on frame_a.",
    params: &[resolve_param("FrameB", Resolve::VARIANTS)],
    connectors: &[
        ConnectorSpec::frame("frame_a", "Reaction side"),
        ConnectorSpec::frame("frame_b", "The force acts at this frame's origin"),
        ConnectorSpec::input("force_x", "x component of the force"),
        ConnectorSpec::input("force_y", "y component of the force"),
        ConnectorSpec::input("force_z", "z component of the force"),
    ],
    variables: VARIABLES,
    build,
    shapes,
};

/// An arrow along the applied vector (the opposite of the cut vector at frame_b).
fn shapes(p: &ParamSet) -> Vec<LocalShape> {
    cut_vector_arrow(p, "f_b_0", "default_N_to_m")
}

const VARIABLES: &[VarSpec] = &[
    VarSpec::vector("r_0", 3, "m", "Position vector from frame_a to frame_b in world frame"),
    VarSpec::vector(
        "f_b_0",
        3,
        "N",
        "Force at frame_b resolved in world frame (cut force: the opposite of the applied force)",
    ),
];

fn build(p: &ParamSet) -> Result<Box<dyn Component>, Error> {
    let resolve = Resolve::from_variant(p.variant("resolve_in_frame"));
    Ok(Box::new(ExternalLoad { torque: false, resolve, two_frames: true, variables: VARIABLES }))
}
