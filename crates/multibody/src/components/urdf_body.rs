//! URDFBodyCylinder, URDFBodyBox, URDFBodySphere: a URDF link, as a URDF
//! importer emits it: the `<inertial>` mass, centre of mass and inertia on
//! the link frame (a Body), drawn with the `<visual>` geometry at its own
//! origin (the shape adds no mass).

use super::body::{MassProperties, RigidBody, INERTIA_PARAMS};
use super::shapes::{look, LocalShape, Placement, ShapeKind};
use super::spec::{concat, ComponentSpec, ConnectorSpec, ParamSpec, ParamType};
use super::{Component, ParamSet};
use crate::math::Vec3;
use crate::Error;

/// Look, mass, centre of mass and inertia (about the centre of mass, in
/// the link frame), and the visual's centre.
const COMMON: [ParamSpec; 12] = concat(
    &concat::<ParamSpec, 11>(
        &[
            ParamSpec::boolean("render", true, "Draw the link in animations"),
            ParamSpec::world("color", ParamType::Vector(4), "default_body_color", 1.0, "", "Colour (RGBA)"),
            ParamSpec::real("specular_coefficient", 1.5, "", "Reflection of light in animations"),
            ParamSpec::real("m", 1.0, "kg", "mass"),
            ParamSpec::vector(
                "r_cm",
                &[0.0, 0.0, 0.0],
                "m",
                "Vector from frame_a to center of mass, resolved in frame_a",
            ),
        ],
        &INERTIA_PARAMS,
    ),
    &[ParamSpec::vector("r_visual", &[0.0, 0.0, 0.0], "m", "Centre of the visual shape, resolved in frame_a")],
);

const FRAME: [ConnectorSpec; 1] = [ConnectorSpec::frame("frame_a", "The link frame")];

pub static CYLINDER: ComponentSpec = ComponentSpec {
    kind: "URDFBodyCylinder",
    doc: "URDF link drawn as a cylinder: a Body (m, r_cm, I_11 ... I_32 about the centre of mass, in the link \
          frame) with a cylinder of the given length and radius centred on r_visual along length_direction. \
          The shape adds no mass.",
    params: &concat::<ParamSpec, 15>(
        &COMMON,
        &[
            ParamSpec::vector(
                "length_direction",
                &[0.0, 0.0, 1.0],
                "",
                "Cylinder axis in frame_a (the visual's local z axis)",
            ),
            ParamSpec::real("length", 1.0, "m", "Length of the cylinder"),
            ParamSpec::real("radius", 0.05, "m", "Radius of the cylinder"),
        ],
    ),
    connectors: &FRAME,
    variables: &super::body::VARIABLES,
    build,
    shapes: cylinder_shapes,
};

pub static BOX: ComponentSpec = ComponentSpec {
    kind: "URDFBodyBox",
    doc: "URDF link drawn as a box: a Body (m, r_cm, I_11 ... I_32 about the centre of mass, in the link frame) \
          with a box of length x width x height centred on r_visual, its length along length_direction and its \
          width along width_direction. The shape adds no mass.",
    params: &concat::<ParamSpec, 17>(
        &COMMON,
        &[
            ParamSpec::vector("length_direction", &[1.0, 0.0, 0.0], "", "Box length direction in frame_a (local x)"),
            ParamSpec::vector("width_direction", &[0.0, 1.0, 0.0], "", "Box width direction in frame_a (local y)"),
            ParamSpec::real("length", 1.0, "m", "Length of the box (along local x)"),
            ParamSpec::real("width", 1.0, "m", "Width of the box (along local y)"),
            ParamSpec::real("height", 1.0, "m", "Height of the box (along local z)"),
        ],
    ),
    connectors: &FRAME,
    variables: &super::body::VARIABLES,
    build,
    shapes: box_shapes,
};

pub static SPHERE: ComponentSpec = ComponentSpec {
    kind: "URDFBodySphere",
    doc: "URDF link drawn as a sphere: a Body (m, r_cm, I_11 ... I_32 about the centre of mass, in the link \
          frame) with a sphere of the given radius centred on r_visual. The shape adds no mass.",
    params: &concat::<ParamSpec, 13>(&COMMON, &[ParamSpec::real("radius", 0.1, "m", "Radius of the sphere")]),
    connectors: &FRAME,
    variables: &super::body::VARIABLES,
    build,
    shapes: sphere_shapes,
};

/// The Body: its mass properties, checked as Body checks them.
fn build(p: &ParamSet) -> Result<Box<dyn Component>, Error> {
    let mass = MassProperties::from_params(p, p.vec3("r_cm"))?;
    Ok(Box::new(RigidBody { mass, point_gravity: false, rotation: None, frame_b: None }))
}

/// A shape of `kind` centred on r_visual, `length` long along `dir`.
fn centred(p: &ParamSet, kind: ShapeKind, dir: Vec3, length: f64, width: f64, height: f64) -> LocalShape {
    let (color, specular) = look(p);
    let e = dir.try_normalize(1e-12).unwrap_or_else(Vec3::z);
    let start = p.vec3("r_visual") - e * (length / 2.0);
    LocalShape::in_frame(kind, "frame_a", start, e * length, width, height).colored(color, specular)
}

fn cylinder_shapes(p: &ParamSet) -> Vec<LocalShape> {
    if !p.boolean("render") {
        return Vec::new();
    }
    let d = 2.0 * p.real("radius");
    vec![centred(p, ShapeKind::Cylinder, p.vec3("length_direction"), p.real("length"), d, d)]
}

fn box_shapes(p: &ParamSet) -> Vec<LocalShape> {
    if !p.boolean("render") {
        return Vec::new();
    }
    let dir = p.vec3("length_direction");
    let mut shape = centred(p, ShapeKind::Box, dir, p.real("length"), p.real("width"), p.real("height"));
    set_width_direction(&mut shape, p.vec3("width_direction"));
    vec![shape]
}

fn sphere_shapes(p: &ParamSet) -> Vec<LocalShape> {
    if !p.boolean("render") {
        return Vec::new();
    }
    let d = 2.0 * p.real("radius");
    let (color, specular) = look(p);
    let centre = p.vec3("r_visual");
    vec![LocalShape::in_frame(ShapeKind::Sphere, "frame_a", centre, Vec3::x() * d, d, d).colored(color, specular)]
}

/// Points a shape's width along `dir`, made perpendicular to its length
/// (kept as it is when `dir` is along the length).
pub(crate) fn set_width_direction(shape: &mut LocalShape, dir: Vec3) {
    if let Placement::InFrame { length, width_dir, .. } = &mut shape.placement {
        let e = length.try_normalize(1e-12).unwrap_or_else(Vec3::x);
        let w = dir - e * e.dot(&dir);
        if w.norm() > 1e-10 {
            *width_dir = w.normalize();
        }
    }
}
