//! What the constraint components share: a relation between two frames
//! kept by constraint forces, with no states. Their residuals and cut
//! forces are outputs like those of every constraint.

use super::shapes::{look, LocalShape, ShapeKind};
use super::spec::{ParamSpec, ParamType};
use super::{Component, ConstraintKind, ParamSet, Part};
use crate::math::Vec3;

pub const X_LOCKED: ParamSpec = ParamSpec::boolean(
    "x_locked",
    true,
    "If true, lock the relative translation along the frame_a x-direction (otherwise the constraint force in that direction is zero)",
);
pub const Y_LOCKED: ParamSpec = ParamSpec::boolean("y_locked", true, "The same along the frame_a y-direction");
pub const Z_LOCKED: ParamSpec = ParamSpec::boolean("z_locked", true, "The same along the frame_a z-direction");

/// The visual parameters of the constraint components (the sphere they draw).
pub const RENDER: ParamSpec = ParamSpec::boolean("render", true, "Render the joint in animations");
pub const SPECULAR: ParamSpec = ParamSpec::real("specular_coefficient", 1.5, "", "Reflection of light in animations");
pub const SPHERE_DIAMETER: ParamSpec = ParamSpec::world(
    "sphere_diameter",
    ParamType::Real,
    "default_joint_length",
    1.0 / 3.0,
    "m",
    "Diameter of the sphere in animations",
);

/// The `color` parameter, defaulting to the world's colour `world_default`.
pub const fn color(world_default: &'static str) -> ParamSpec {
    ParamSpec::world("color", ParamType::Vector(4), world_default, 1.0, "", "Colour (RGBA)")
}

/// The locked axes of frame_a.
pub fn locked(p: &ParamSet) -> [bool; 3] {
    [p.boolean("x_locked"), p.boolean("y_locked"), p.boolean("z_locked")]
}

#[derive(Debug)]
pub struct ConstraintJoint {
    pub kind: ConstraintKind,
}

impl Component for ConstraintJoint {
    fn parts(&self) -> Vec<Part> {
        vec![Part::Constraint { a: 0, b: 1, kind: self.kind }]
    }
}

/// A small sphere at frame_a, as the constraint components draw themselves.
pub fn sphere_shapes(p: &ParamSet) -> Vec<LocalShape> {
    if !p.boolean("render") {
        return Vec::new();
    }
    let (color, specular) = look(p);
    let d = p.real("sphere_diameter");
    vec![LocalShape::in_frame(ShapeKind::Sphere, "frame_a", Vec3::zeros(), Vec3::x(), d, d).colored(color, specular)]
}
