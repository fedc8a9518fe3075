//! BodyBox: a body whose mass and inertia come from a (possibly hollow) box.

use super::body::{shaped_body_shapes, MassProperties, RigidBody, COMMON_PARAMS, VARIABLES};
use super::shapes::{LocalShape, ShapeKind};
use super::spec::{concat, ComponentSpec, ConnectorSpec, ParamSpec, ParamType};
use super::{Component, ParamSet};
use crate::math::{from_nxy, Mat3};
use crate::Error;

pub static SPEC: ComponentSpec = ComponentSpec {
    kind: "BodyBox",
    doc: "Rigid body with box shape: mass, centre of mass and inertia are computed from the box (length along \
          r - r_shape, width along width_dir) and the density. Hollow with inner_width > 0. frame_b sits at r.",
    params: &PARAMS,
    connectors: &[
        ConnectorSpec::frame("frame_a", "The body's first frame"),
        ConnectorSpec::frame("frame_b", "The body's second frame, at r from frame_a"),
    ],
    variables: &VARIABLES,
    build,
    shapes,
};

/// The box.
fn shapes(p: &ParamSet) -> Vec<LocalShape> {
    let (r, r_shape) = (p.vec3("r"), p.vec3("r_shape"));
    let width = p.real_opt("width").unwrap_or(0.3 * (r - r_shape).norm());
    let height = p.real_opt("height").unwrap_or(width);
    shaped_body_shapes(p, ShapeKind::Box, r_shape, r - r_shape, width, height)
}

static PARAMS: [ParamSpec; 18] = concat(
    &COMMON_PARAMS,
    &[
        ParamSpec::vector("r", &[0.1, 0.0, 0.0], "m", "Vector from frame_a to frame_b resolved in frame_a"),
        ParamSpec::vector("r_shape", &[0.0, 0.0, 0.0], "m", "Vector from frame_a to box origin, resolved in frame_a"),
        ParamSpec::vector("width_dir", &[0.0, 1.0, 0.0], "", "Vector in width direction of box, resolved in frame_a"),
        ParamSpec::derived("width", ParamType::Real, "0.3 * norm(r - r_shape)", "m", "Width of box"),
        ParamSpec::derived("height", ParamType::Real, "width", "m", "Height of box"),
        ParamSpec::real("inner_width", 0.0, "m", "Width of inner box surface (0 <= inner_width < width)"),
        ParamSpec::derived(
            "inner_height",
            ParamType::Real,
            "inner_width",
            "m",
            "Height of inner box surface (0 <= inner_height < height)",
        ),
        ParamSpec::real("density", 7700.0, "kg/m3", "Density of the box (steel: 7700)"),
    ],
);

fn build(p: &ParamSet) -> Result<Box<dyn Component>, Error> {
    let (r, r_shape) = (p.vec3("r"), p.vec3("r_shape"));
    let dir = r - r_shape;
    let length = dir.norm();
    let width = p.real_opt("width").unwrap_or(0.3 * length);
    let height = p.real_opt("height").unwrap_or(width);
    // Sizes given must not be negative (a negative width would make a negative mass).
    for name in ["width", "height", "inner_height"] {
        if p.real_opt(name).is_some_and(|x| x < 0.0) {
            return Err(p.invalid(name, "a size must not be negative"));
        }
    }
    let inner_width = p.non_negative("inner_width", true)?;
    let inner_height = p.real_opt("inner_height").unwrap_or(inner_width);
    let density = p.non_negative("density", true)?;
    for (name, outer, inner) in [("inner_width", width, inner_width), ("inner_height", height, inner_height)] {
        if inner > outer {
            return Err(p.invalid(name, format!("the hollow must fit inside the box ({outer})")));
        }
    }
    let mo = density * length * width * height;
    let mi = density * length * inner_width * inner_height;
    let diag = Mat3::from_diagonal(&crate::math::Vec3::new(
        (mo * (width * width + height * height) - mi * (inner_width.powi(2) + inner_height.powi(2))) / 12.0,
        (mo * (length * length + height * height) - mi * (length * length + inner_height.powi(2))) / 12.0,
        (mo * (length * length + width * width) - mi * (length * length + inner_width.powi(2))) / 12.0,
    ));
    // The box frame: x along the length, y in the plane of width_dir.
    let box_frame = from_nxy(&dir, &p.vec3("width_dir"));
    let inertia = box_frame.transpose() * diag * box_frame;
    let r_cm = r_shape + if length > 0.0 { dir / length * (length / 2.0) } else { dir };
    let mass = MassProperties { m: mo - mi, r_cm, inertia };
    Ok(Box::new(RigidBody::new(p, mass, Some(r))?))
}
