//! BodyShape: a body with a second frame, frame_b, at `r` from frame_a.

use super::body::{shaped_body_shapes, MassProperties, RigidBody, COMMON_PARAMS, INERTIA_PARAMS, VARIABLES};
use super::shapes::{LocalShape, ShapeKind};
use super::spec::{concat, ComponentSpec, ConnectorSpec, ParamSpec, ParamType};
use super::{Component, ParamSet};
use crate::math::Vec3;
use crate::Error;

pub static SPEC: ComponentSpec = ComponentSpec {
    kind: "BodyShape",
    doc: "Rigid body with mass and inertia and two frames: frame_b sits at r from frame_a (resolved in frame_a), \
          with the same orientation. Set orientation_state to Euler or Quaternion for a free body.",
    params: &PARAMS,
    connectors: &[
        ConnectorSpec::frame("frame_a", "The body's first frame"),
        ConnectorSpec::frame("frame_b", "The body's second frame, at r from frame_a"),
    ],
    variables: &VARIABLES,
    build,
    shapes,
};

/// A cylinder from frame_a to frame_b and a sphere at the centre of mass.
fn shapes(p: &ParamSet) -> Vec<LocalShape> {
    let r = p.vec3("r");
    let width = match p.real("width") {
        w if w > 0.0 => w,
        _ => r.norm() / p.world.number("default_width_fraction"),
    };
    let height = if p.real("height") > 0.0 { p.real("height") } else { width };
    let mut out = shaped_body_shapes(p, ShapeKind::Cylinder, Vec3::zeros(), r, width, height);
    if !out.is_empty() {
        let r_cm = p.vec3_opt("r_cm").unwrap_or(r / 2.0);
        let d = 2.0 * p.real("radius");
        out.push(
            LocalShape::in_frame(ShapeKind::Sphere, "frame_a", r_cm, r_cm, d, d).colored(out[0].color, out[0].specular),
        );
    }
    out
}

static PARAMS: [ParamSpec; 23] = concat(
    &COMMON_PARAMS,
    &concat::<ParamSpec, 13>(
        &[
            ParamSpec::real("m", 1.0, "kg", "mass"),
            ParamSpec::vector("r", &[0.0, 0.0, 0.0], "m", "Vector from frame_a to frame_b resolved in frame_a"),
            ParamSpec::derived(
                "r_cm",
                ParamType::Vector(3),
                "r / 2",
                "m",
                "Vector from frame_a to center of mass, resolved in frame_a",
            ),
        ],
        &concat::<ParamSpec, 10>(
            &INERTIA_PARAMS,
            &[
                ParamSpec::world(
                    "radius",
                    ParamType::Real,
                    "default_body_diameter",
                    0.5,
                    "m",
                    "Radius of the sphere at the center of mass in animations",
                ),
                ParamSpec::real("width", 0.0, "m", "Width of the shape in animations (0: from the length)"),
                ParamSpec::real("height", 0.0, "m", "Height of the shape in animations (0: the width)"),
                ParamSpec::real("shape_scale", 1.0, "", "Scale of the shape in animations"),
            ],
        ),
    ),
);

fn build(p: &ParamSet) -> Result<Box<dyn Component>, Error> {
    let r = p.vec3("r");
    let mass = MassProperties::from_params(p, p.vec3_opt("r_cm").unwrap_or(r / 2.0))?;
    Ok(Box::new(RigidBody::new(p, mass, Some(r))?))
}
