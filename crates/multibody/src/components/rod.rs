//! What SphericalSpherical and UniversalSpherical share: a massless rod of
//! fixed length between the frames' origins.

use super::shapes::{between, look, LocalShape, ShapeKind};
use super::ParamSet;

/// A cylinder between the frames.
pub fn rod_shapes(p: &ParamSet, diameter: f64) -> Vec<LocalShape> {
    if !p.boolean("render") {
        return Vec::new();
    }
    let (color, specular) = look(p);
    vec![between(ShapeKind::Cylinder, "frame_a", "frame_b", diameter, diameter).colored(color, specular)]
}

/// The rod length from a vector parameter; a rod must have length.
pub fn rod_length(p: &ParamSet, name: &str) -> Result<f64, crate::Error> {
    let length = p.vec3(name).norm();
    if length < 1e-12 {
        return Err(p.invalid(name, "a rod must have a length (a non-zero vector)"));
    }
    Ok(length)
}
