//! Fixed-size math: the library's rotation conventions, spatial algebra,
//! small dense and sparse factorizations, geometry helpers and a union-find.

pub mod dense;
pub mod expr;
pub mod graph;
pub mod rotation;
pub mod sparse;
pub mod spatial;
pub mod surface;
pub mod symbolic;
pub mod tape;
pub mod trajectory;
pub mod union_find;
pub mod wheel;

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

/// A unit vector perpendicular to `length` (y unless `length` is along y).
pub fn width_direction(length: &Vec3) -> Vec3 {
    let n = length.norm();
    if n < 1e-12 {
        return Vec3::y();
    }
    let e = length / n;
    let candidate = if e.y.abs() < 0.99 { Vec3::y() } else { Vec3::x() };
    (candidate - e * e.dot(&candidate)).normalize()
}

/// `-mu r / |r|^3`; zero at the origin, where the field is undefined.
#[inline]
pub fn point_gravity(mu: f64, r: &Vec3) -> Vec3 {
    let d2 = r.norm_squared();
    if d2 == 0.0 {
        return Vec3::zeros();
    }
    -r * (mu / (d2 * d2.sqrt()))
}
