//! SphericalSpherical: a rod of fixed length with a ball joint at each end.

use super::constraint_joint::ConstraintJoint;
use super::rod::{rod_length, rod_shapes};
use super::spec::{ComponentSpec, ConnectorSpec, ParamSpec};
use super::{Component, ConstraintKind, ParamSet};
use crate::Error;

pub static SPEC: ComponentSpec = ComponentSpec {
    kind: "SphericalSpherical",
    doc: "Joint assembly: a spherical joint at each end of a massless rod of fixed length |r_0| between the \
          origins of frame_a and frame_b (one constraint equation). No torques are transmitted.",
    params: &[
        ParamSpec::boolean("has_mass", false, "Put a point mass m at the rod midpoint (not supported yet)"),
        ParamSpec::boolean("kinematic_constraint", true, "Kept for compatibility"),
        ParamSpec::boolean("constraint_residue_external", false, "Kept for compatibility"),
        ParamSpec::boolean("point_gravity", false, "Kept for compatibility (the rod is massless)"),
        ParamSpec::boolean("render", true, "Render the rod in animations"),
        ParamSpec::vector("color", &[1.0, 1.0, 0.0, 1.0], "", "Colour (RGBA)"),
        ParamSpec::real("specular_coefficient", 1.5, "", "Reflection of light in animations"),
        ParamSpec::vector(
            "r_0",
            &[1.0, 0.0, 0.0],
            "m",
            "Nominal vector from frame_a to frame_b: its length is the rod length",
        ),
        ParamSpec::real("m", 1.0, "kg", "Rod mass (used only with has_mass)"),
        ParamSpec::real("radius", 0.1, "m", "Radius of the rod in animations"),
    ],
    connectors: &[ConnectorSpec::frame("frame_a", "First end"), ConnectorSpec::frame("frame_b", "Second end")],
    variables: &[],
    build,
    shapes: |p| rod_shapes(p, p.real("radius")),
};

fn build(p: &ParamSet) -> Result<Box<dyn Component>, Error> {
    if p.boolean("has_mass") {
        return Err(Error::Unsupported {
            component: p.component.into(),
            what: "a rod with mass (has_mass = true)".into(),
            fix: "put a PointMass between two SphericalSpherical rods instead".into(),
        });
    }
    Ok(Box::new(ConstraintJoint { kind: ConstraintKind::Distance { length: rod_length(p, "r_0")? } }))
}
