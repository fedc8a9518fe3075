//! What the wheel components share: their parameters, the check of a
//! radius, and the shape that makes rolling visible (a tyre with spokes).
//!
//! Every wheel rolls on the ground plane y = 0 (the x-z plane of the world,
//! y up) with its spin axis along the z axis of the frame that turns with
//! it, as in the library.

use super::shapes::{LocalShape, ShapeKind};
use super::spec::{ParamSpec, ParamType};
use super::ParamSet;
use crate::math::surface::Surface;
use crate::math::Vec3;
use crate::Error;

pub const RADIUS: ParamSpec = ParamSpec::real("radius", 0.3, "m", "Radius of the wheel");
pub const RENDER: ParamSpec = ParamSpec::boolean("render", true, "Render the wheel in animations");
pub const SPECULAR: ParamSpec = ParamSpec::real("specular_coefficient", 1.5, "", "Reflection of light in animations");
pub const COLOR: ParamSpec = ParamSpec::vector("color", &[1.0, 0.0, 0.0, 1.0], "", "Color of the wheel in animations");
pub const WIDTH: ParamSpec = ParamSpec::real("width", 0.035, "m", "Width of the wheel (animations)");
pub const ISCUT: ParamSpec = ParamSpec::boolean(
    "iscut",
    false,
    "Cut the wheel's own coordinates first when the wheel closes a kinematic loop (a wheel on an axle of a vehicle)",
);
pub const SEQUENCE: ParamSpec = ParamSpec {
    name: "sequence",
    ty: ParamType::IntVector(3),
    default: super::spec::Default::Vector(&[2.0, 3.0, 1.0]),
    unit: "",
    doc: "Axes of the Cardan angles that rotate the world into frame_a (the library's [2, 3, 1]: about y, the \
          heading; about z, the spin; about x). Their middle angle, the spin, passes a singular value every half \
          turn; there the run goes on in an internal chart and the angles are still reported. [2, 1, 3] makes \
          them heading, lean, spin (singular only when the wheel lies flat)",
};
pub const SURFACE: ParamSpec = ParamSpec::boolean(
    "surface",
    false,
    "Roll on the road y = surface(x, z) that the model's relations give (`wheel.surface = 0.1 * sin(x)`, a formula \
     of the world's x and z), instead of the ground y = 0. Setting the formula sets this",
);
pub const M: ParamSpec = ParamSpec::real("m", 1.0, "kg", "Mass of the wheel");
pub const I_AXIS: ParamSpec =
    ParamSpec::real("I_axis", 0.06, "kg.m2", "Moment of inertia of the wheel about its spin axis");
pub const I_LONG: ParamSpec =
    ParamSpec::real("I_long", 0.12, "kg.m2", "Moment of inertia of the wheel perpendicular to its spin axis");

/// A parameter that must be a positive, finite number.
pub fn positive(p: &ParamSet, name: &str, what: &str) -> Result<f64, Error> {
    let x = p.real(name);
    if x.is_finite() && x > 0.0 {
        Ok(x)
    } else {
        Err(p.invalid(name, format!("{what} must be a positive number (it is {x})")))
    }
}

/// A parameter that must be a finite number, zero or more.
pub fn non_negative(p: &ParamSet, name: &str, what: &str) -> Result<f64, Error> {
    let x = p.real(name);
    if x.is_finite() && x >= 0.0 {
        Ok(x)
    } else {
        Err(p.invalid(name, format!("{what} must be zero or more (it is {x})")))
    }
}

/// The road the model gives the wheel, compiled; `None` for the ground.
pub fn road(p: &ParamSet) -> Result<Option<Surface>, Error> {
    match p.surface {
        Some(expr) => Ok(Some(Surface::new(expr).map_err(|reason| p.invalid("surface", reason))?)),
        None if p.boolean("surface") => Err(p.invalid(
            "surface",
            "give the road as a formula of x and z in the model's relations, e.g. `wheel.surface = 0.1 * sin(x)`",
        )),
        None => Ok(None),
    }
}

/// The mass properties of a wheel: a diagonal inertia, `I_axis` about the
/// spin axis (z), `I_long` about the other two.
pub fn wheel_inertia(p: &ParamSet, m: &str, i_axis: &str, i_long: &str) -> Result<crate::math::RigidInertia, Error> {
    let m = non_negative(p, m, "the wheel's mass")?;
    let a = non_negative(p, i_axis, "the moment of inertia about the spin axis")?;
    let l = non_negative(p, i_long, "the moment of inertia across the spin axis")?;
    let inertia = crate::math::Mat3::from_diagonal(&Vec3::new(l, l, a));
    Ok(crate::math::RigidInertia::from_com(m, Vec3::zeros(), inertia))
}

/// A wheel in `frame` (its centre, spin axis z): a tyre of `radius` and
/// `width`, and three spokes across it, lighter, standing out of both faces
/// so that the rotation shows.
pub fn wheel_shapes(frame: &str, radius: f64, width: f64, color: [f64; 4], specular: f64) -> Vec<LocalShape> {
    let axis = Vec3::z();
    let mut shapes = vec![LocalShape::in_frame(
        ShapeKind::Cylinder,
        frame,
        -axis * (width / 2.0),
        axis * width,
        2.0 * radius,
        2.0 * radius,
    )
    .colored(color, specular)];
    let light = [0.5 + color[0] / 2.0, 0.5 + color[1] / 2.0, 0.5 + color[2] / 2.0, color[3]];
    for k in 0..3 {
        let angle = k as f64 * std::f64::consts::PI / 3.0;
        let along = Vec3::new(angle.cos(), angle.sin(), 0.0) * (1.9 * radius);
        let mut spoke = LocalShape::in_frame(ShapeKind::Box, frame, -along / 2.0, along, 0.12 * radius, 1.4 * width)
            .colored(light, specular);
        if let super::shapes::Placement::InFrame { width_dir, .. } = &mut spoke.placement {
            // The spoke's width lies in the wheel's plane; its height along the axis.
            *width_dir = axis.cross(&along).normalize();
        }
        shapes.push(spoke);
    }
    shapes
}
