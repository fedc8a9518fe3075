//! UniversalSpherical: a rod of fixed length with a universal joint at frame_a
//! and a ball joint at frame_b.

use super::constraint_joint::ConstraintJoint;
use super::rod::{rod_length, rod_shapes};
use super::spec::{ComponentSpec, ConnectorSpec, ParamSpec};
use super::{Component, ConstraintKind, ParamSet};
use crate::Error;

pub static SPEC: ComponentSpec = ComponentSpec {
    kind: "UniversalSpherical",
    doc: "Joint assembly: a universal joint at frame_a and a spherical joint at frame_b, joined by a massless \
          rod of length |rRod_ia| (one constraint equation). The rod frame frame_ia is not available yet: a rod \
          mass attached there is not supported.",
    params: &[
        ParamSpec::boolean("kinematic_constraint", true, "Kept for compatibility"),
        ParamSpec::boolean("constraint_residue_external", false, "Kept for compatibility"),
        ParamSpec::boolean("render", true, "Render the rod in animations"),
        ParamSpec::vector("color", &[0.0, 0.1, 1.0, 0.9], "", "Colour (RGBA)"),
        ParamSpec::real("specular_coefficient", 1.5, "", "Reflection of light in animations"),
        ParamSpec::vector("n1_a", &[0.0, 0.0, 1.0], "", "Axis 1 of the universal joint, resolved in frame_a"),
        ParamSpec::vector(
            "rRod_ia",
            &[1.0, 0.0, 0.0],
            "m",
            "Vector from frame_a to frame_b, resolved in frame_ia: its length is the rod length",
        ),
        ParamSpec::real("rod_radius", 0.05, "m", "Radius of the rod in animations"),
        ParamSpec::real("sphere_diameter", 0.1, "m", "Diameter of the spheres in animations"),
    ],
    connectors: &[
        ConnectorSpec::frame("frame_a", "The universal end"),
        ConnectorSpec::frame("frame_b", "The spherical end"),
        ConnectorSpec::frame("frame_ia", "The rod frame (not supported yet: leave it unconnected)"),
    ],
    variables: &[],
    build,
    shapes: |p| rod_shapes(p, 2.0 * p.real("rod_radius")),
};

fn build(p: &ParamSet) -> Result<Box<dyn Component>, Error> {
    Ok(Box::new(ConstraintJoint { kind: ConstraintKind::Distance { length: rod_length(p, "rRod_ia")? } }))
}
