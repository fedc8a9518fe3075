//! SphericalSpherical: a rod of fixed length with a ball joint at each end.

use super::constraint_joint::ConstraintJoint;
use super::rod::{rod_length, rod_shapes};
use super::spec::{ComponentSpec, ConnectorSpec, ParamSpec};
use super::{Component, ConstraintKind, ParamSet, Part};
use crate::Error;

pub static SPEC: ComponentSpec = ComponentSpec {
    kind: "SphericalSpherical",
    doc: "Joint assembly: a spherical joint at each end of a rod of fixed length |r_0| between the origins of \
          frame_a and frame_b (one constraint equation). No torques are transmitted. The rod is massless, or with \
          has_mass a point mass m at its midpoint (no degree of freedom: its inertia and weight load the ends).",
    params: &[
        ParamSpec::boolean("has_mass", false, "Put a point mass m at the rod midpoint"),
        ParamSpec::boolean("kinematic_constraint", true, "Kept for compatibility"),
        ParamSpec::boolean("constraint_residue_external", false, "Kept for compatibility"),
        ParamSpec::boolean("point_gravity", false, "The rod's point mass feels point gravity"),
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
    let rod = ConstraintJoint { kind: ConstraintKind::Distance { length: rod_length(p, "r_0")? } };
    if !p.boolean("has_mass") {
        return Ok(Box::new(rod));
    }
    let m = p.non_negative("m", true)?;
    let point_gravity = p.boolean("point_gravity") || p.world.point_gravity;
    Ok(Box::new(RodWithMass { rod, m, point_gravity }))
}

/// The rod with a point mass at its midpoint.
#[derive(Debug)]
struct RodWithMass {
    rod: ConstraintJoint,
    m: f64,
    point_gravity: bool,
}

impl Component for RodWithMass {
    fn parts(&self) -> Vec<Part> {
        let mut parts = self.rod.parts();
        if self.m > 0.0 {
            parts.push(Part::LineMass { a: 0, b: 1, m: self.m, h: 0.5, point_gravity: self.point_gravity });
        }
        parts
    }
}
