//! BodyCylinder: a body whose mass and inertia come from a (possibly hollow)
//! cylinder.

use super::body::{shaped_body_shapes, MassProperties, RigidBody, COMMON_PARAMS, VARIABLES};
use super::shapes::{LocalShape, ShapeKind};
use super::spec::{concat, ComponentSpec, ConnectorSpec, ParamSpec};
use super::{Component, ParamSet};
use crate::math::Mat3;
use crate::Error;

pub static SPEC: ComponentSpec = ComponentSpec {
    kind: "BodyCylinder",
    doc: "Rigid body with cylinder shape along r - r_shape: mass, centre of mass and inertia are computed from the \
          cylinder and the density. Hollow with inner_diameter > 0. frame_b sits at r.",
    params: &PARAMS,
    connectors: &[
        ConnectorSpec::frame("frame_a", "The body's first frame"),
        ConnectorSpec::frame("frame_b", "The body's second frame, at r from frame_a"),
    ],
    variables: &VARIABLES,
    build,
    shapes,
};

/// The cylinder.
fn shapes(p: &ParamSet) -> Vec<LocalShape> {
    let (r, r_shape) = (p.vec3("r"), p.vec3("r_shape"));
    let d = p.real("diameter");
    shaped_body_shapes(p, ShapeKind::Cylinder, r_shape, r - r_shape, d, d)
}

static PARAMS: [ParamSpec; 15] = concat(
    &COMMON_PARAMS,
    &[
        ParamSpec::vector("r", &[0.1, 0.0, 0.0], "m", "Vector from frame_a to frame_b, resolved in frame_a"),
        ParamSpec::vector(
            "r_shape",
            &[0.0, 0.0, 0.0],
            "m",
            "Vector from frame_a to cylinder origin, resolved in frame_a",
        ),
        ParamSpec::real("diameter", 0.05, "m", "Diameter of cylinder"),
        ParamSpec::real("inner_diameter", 0.0, "m", "Inner diameter of cylinder (0 <= inner_diameter < diameter)"),
        ParamSpec::real("density", 7700.0, "kg/m3", "Density of cylinder (steel: 7700)"),
    ],
);

fn build(p: &ParamSet) -> Result<Box<dyn Component>, Error> {
    let (r, r_shape) = (p.vec3("r"), p.vec3("r_shape"));
    let dir = r - r_shape;
    let length = dir.norm();
    let radius = p.non_negative("diameter", true)? / 2.0;
    let inner = p.non_negative("inner_diameter", true)? / 2.0;
    if inner > radius {
        return Err(p.invalid("inner_diameter", "the hollow must fit inside the cylinder (inner_diameter <= diameter)"));
    }
    let density = p.non_negative("density", true)?;
    let mo = density * std::f64::consts::PI * length * radius * radius;
    let mi = density * std::f64::consts::PI * length * inner * inner;
    let axial = (mo * radius * radius - mi * inner * inner) / 2.0;
    let transverse =
        (mo * (length * length + 3.0 * radius * radius) - mi * (length * length + 3.0 * inner * inner)) / 12.0;
    let e = if length > 0.0 { dir / length } else { crate::math::Vec3::x() };
    let ee = e * e.transpose();
    let inertia = (Mat3::identity() - ee) * transverse + ee * axial;
    let mass = MassProperties { m: mo - mi, r_cm: r_shape + e * (length / 2.0), inertia };
    Ok(Box::new(RigidBody::new(p, mass, Some(r))?))
}
