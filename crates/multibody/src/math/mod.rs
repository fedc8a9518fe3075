//! Fixed-size math: the library's rotation conventions and spatial algebra.

pub mod rotation;
pub mod spatial;

pub use rotation::*;
pub use spatial::{ArticulatedInertia, Force, Motion, RigidInertia, Transform};

pub type Vec3 = nalgebra::Vector3<f64>;
pub type Mat3 = nalgebra::Matrix3<f64>;
/// A quaternion `[w, i, j, k]`, scalar first.
pub type Quat = nalgebra::Vector4<f64>;

/// The cross-product matrix: `skew(a) * b = a x b`.
#[inline]
pub fn skew(a: &Vec3) -> Mat3 {
    Mat3::new(0.0, -a[2], a[1], a[2], 0.0, -a[0], -a[1], a[0], 0.0)
}
