//! What the constraint components share: a relation between two frames
//! kept by constraint forces, with no states. Their residuals and cut
//! forces are outputs like those of every constraint.

use super::shapes::{look, LocalShape, ShapeKind};
use super::spec::ParamSpec;
use super::{Component, ConstraintKind, ParamSet, Part};
use crate::math::Vec3;

pub const X_LOCKED: ParamSpec = ParamSpec::boolean(
    "x_locked",
    true,
    "If true, lock the relative translation along the frame_a x-direction (otherwise the constraint force in that direction is zero)",
);
pub const Y_LOCKED: ParamSpec = ParamSpec::boolean("y_locked", true, "The same along the frame_a y-direction");
pub const Z_LOCKED: ParamSpec = ParamSpec::boolean("z_locked", true, "The same along the frame_a z-direction");

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
