//! The geometry of a wheel (a thin disk) touching a plane, and the tyre
//! force curves of the slipping wheels.
//!
//! The wheel's spin axis is the z axis of its frame. With `e_n` the plane's
//! unit normal: `e_long = (e_n x e_axis) / |e_n x e_axis|` points along the
//! wheel's path, `e_lat = e_long x e_n` across it, and the contact point
//! (the lowest point of the rim) is `delta = radius (e_long x e_axis)` from
//! the centre, or `-radius e_n` for a wheel held upright.

use super::surface::{Height, Surface};
use super::{Mat3, Vec3};

/// The contact frame of a wheel and its rate of change.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ContactFrame {
    /// Spin axis, world coordinates.
    pub e_axis: Vec3,
    /// Along the wheel's path, in the plane.
    pub e_long: Vec3,
    /// Across the path, in the plane (`e_long x e_n`).
    pub e_lat: Vec3,
    /// From the centre to the contact point.
    pub delta: Vec3,
    /// Time derivatives of `e_long`, `e_lat` and `delta`.
    pub e_long_dot: Vec3,
    pub e_lat_dot: Vec3,
    pub delta_dot: Vec3,
}

/// The contact frame of a wheel of `radius` whose frame has the
/// world-to-frame rotation `rot` and the angular velocity `w` (world),
/// on a plane of unit normal `e_n` (fixed). `upright`: the contact point is
/// straight below the centre (RollingConstraintVerticalWheel).
pub fn contact_frame(rot: &Mat3, w: &Vec3, radius: f64, e_n: &Vec3, upright: bool) -> ContactFrame {
    contact_frame_turning(rot, w, radius, e_n, &Vec3::zeros(), upright)
}

/// [`contact_frame`] on a plane whose normal turns at `e_n_dot`.
pub fn contact_frame_turning(
    rot: &Mat3,
    w: &Vec3,
    radius: f64,
    e_n: &Vec3,
    e_n_dot: &Vec3,
    upright: bool,
) -> ContactFrame {
    let e_axis = rot.tr_mul(&Vec3::z());
    let e_axis_dot = w.cross(&e_axis);
    let aux = e_n.cross(&e_axis);
    // A wheel lying flat has no direction of travel; keep the numbers finite.
    let n = aux.norm().max(f64::MIN_POSITIVE);
    let e_long = aux / n;
    let aux_dot = e_n.cross(&e_axis_dot) + e_n_dot.cross(&e_axis);
    let e_long_dot = (aux_dot - e_long * e_long.dot(&aux_dot)) / n;
    let e_lat = e_long.cross(e_n);
    let e_lat_dot = e_long_dot.cross(e_n) + e_long.cross(e_n_dot);
    let (delta, delta_dot) = if upright {
        (-e_n * radius, Vec3::zeros())
    } else {
        (e_long.cross(&e_axis) * radius, (e_long_dot.cross(&e_axis) + e_long.cross(&e_axis_dot)) * radius)
    };
    ContactFrame { e_axis, e_long, e_lat, delta, e_long_dot, e_lat_dot, delta_dot }
}

/// Where a wheel touches the road, and how far it is from touching.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct RoadContact {
    /// The wheel's contact frame on the road's tangent plane there.
    pub frame: ContactFrame,
    /// The road's unit normal at the contact point, and its rate.
    pub e_n: Vec3,
    pub e_n_dot: Vec3,
    /// The road's point under the wheel's lowest point.
    pub r_road: Vec3,
    /// The wheel's lowest point above the road, along the normal
    /// (negative: in the road).
    pub gap: f64,
}

/// A wheel of `radius` (centre `r` moving at `v`, rotation `rot`, angular
/// velocity `w`, all world) on the ground y = 0, or on the road
/// `y = surface(x, z)`: the rim's lowest point relative to the road's
/// tangent plane under it, found by fixed-point steps (they converge where
/// the road is less curved than the wheel).
pub fn road_contact(rot: &Mat3, w: &Vec3, r: &Vec3, v: &Vec3, radius: f64, surface: Option<&Surface>) -> RoadContact {
    let Some(surface) = surface else {
        let frame = contact_frame(rot, w, radius, &Vec3::y(), false);
        let p = r + frame.delta;
        return RoadContact {
            frame,
            e_n: Vec3::y(),
            e_n_dot: Vec3::zeros(),
            r_road: Vec3::new(p.x, 0.0, p.z),
            gap: p.y,
        };
    };
    let normal = |h: &Height| Vec3::new(-h.grad[0], 1.0, -h.grad[1]);
    let mut frame = contact_frame(rot, w, radius, &Vec3::y(), false);
    let mut p = r + frame.delta;
    let mut h = surface.height(p.x, p.z);
    for _ in 0..ROAD_ITERATIONS {
        frame = contact_frame(rot, w, radius, &normal(&h).normalize(), false);
        let next = r + frame.delta;
        let moved = (next - p).norm();
        p = next;
        h = surface.height(p.x, p.z);
        if moved <= 1e-14 * (radius + r.norm()) {
            break;
        }
    }
    let n = normal(&h);
    let e_n = n / n.norm();
    // The normal turns as the contact point moves over the road: twice, so
    // that the point's motion includes the turning.
    let mut e_n_dot = Vec3::zeros();
    for _ in 0..2 {
        frame = contact_frame_turning(rot, w, radius, &e_n, &e_n_dot, false);
        let p_dot = v + frame.delta_dot;
        let [hxx, hxz, hzz] = h.hess;
        let n_dot = Vec3::new(-(hxx * p_dot.x + hxz * p_dot.z), 0.0, -(hxz * p_dot.x + hzz * p_dot.z));
        e_n_dot = (n_dot - e_n * e_n.dot(&n_dot)) / n.norm();
    }
    frame = contact_frame_turning(rot, w, radius, &e_n, &e_n_dot, false);
    let p = r + frame.delta;
    let r_road = Vec3::new(p.x, h.value, p.z);
    RoadContact { frame, e_n, e_n_dot, r_road, gap: e_n.dot(&(p - r_road)) }
}

/// Fixed-point steps of the contact point on a road.
const ROAD_ITERATIONS: usize = 30;

/// An S-shaped step from `(x_min, y_min)` to `(x_max, y_max)`: the cubic
/// `-x^3/2 + 3x/2` on the scaled interval, constant outside it; continuous
/// with its first derivative.
pub fn limit_s_form(x_min: f64, x_max: f64, y_min: f64, y_max: f64, x: f64) -> f64 {
    let x3 = (2.0 * x - x_max - x_min) / (x_max - x_min);
    let y1 = if x3 > 1.0 {
        1.0
    } else if x3 < -1.0 {
        -1.0
    } else {
        1.5 * x3 - 0.5 * x3 * x3 * x3
    };
    y1 * (y_max - y_min) / 2.0 + (y_max + y_min) / 2.0
}

/// The library's slip law (`limit_S_triple`): odd in `x`, rising from 0 to
/// the peak `y_max` at `x_max` (adhesion) and falling to the plateau `y_sat`
/// from `x_sat` on (sliding).
pub fn limit_s_triple(x_max: f64, x_sat: f64, y_max: f64, y_sat: f64, x: f64) -> f64 {
    if x > x_max {
        limit_s_form(x_max, x_sat, y_max, y_sat, x)
    } else if x < -x_max {
        limit_s_form(-x_max, -x_sat, -y_max, -y_sat, x)
    } else {
        limit_s_form(-x_max, x_max, -y_max, y_max, x)
    }
}

/// Pacejka's magic formula `D sin(C atan(B x - E (B x - atan(B x))))`.
pub fn pacejka_magic(x: f64, b: f64, c: f64, d: f64, e: f64) -> f64 {
    let bx = b * x;
    d * (c * (bx - e * (bx - bx.atan())).atan()).sin()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_contact_of_an_upright_wheel_is_below_its_centre() {
        // Spin axis along world z, heading x: delta = -R y.
        let c = contact_frame(&Mat3::identity(), &Vec3::new(0.0, 0.0, 3.0), 0.3, &Vec3::y(), false);
        assert!((c.delta - Vec3::new(0.0, -0.3, 0.0)).norm() < 1e-15);
        assert!((c.e_long - Vec3::x()).norm() < 1e-15);
        assert!((c.e_lat - Vec3::z()).norm() < 1e-15);
        // Spinning about its own axis moves none of them.
        assert!(c.delta_dot.norm() + c.e_long_dot.norm() < 1e-15);
    }

    #[test]
    fn rates_are_the_derivatives_of_the_frame() {
        // Central differences of a rotation turning at w: error h^2 |w|^3 ~ 1e-9.
        let w = Vec3::new(0.3, -0.7, 1.1);
        let rot_at = |t: f64| {
            let base = crate::math::planar_rotation(&Vec3::new(1.0, 2.0, 0.5).normalize(), 0.4);
            // World-to-frame R(t) = R0 P(w t): the frame turns at w (world).
            base * crate::math::planar_rotation(&w.normalize(), w.norm() * t)
        };
        for upright in [false, true] {
            let h = 1e-5;
            let c = contact_frame(&rot_at(0.0), &w, 0.25, &Vec3::y(), upright);
            let p = contact_frame(&rot_at(h), &w, 0.25, &Vec3::y(), upright);
            let m = contact_frame(&rot_at(-h), &w, 0.25, &Vec3::y(), upright);
            for (d, plus, minus) in
                [(c.e_long_dot, p.e_long, m.e_long), (c.e_lat_dot, p.e_lat, m.e_lat), (c.delta_dot, p.delta, m.delta)]
            {
                assert!((d - (plus - minus) / (2.0 * h)).norm() < 1e-8, "{d} vs {}", (plus - minus) / (2.0 * h));
            }
        }
    }

    #[test]
    fn the_slip_law_peaks_at_adhesion_and_settles_at_sliding() {
        assert_eq!(limit_s_triple(0.1, 0.3, 0.8, 0.6, 0.0), 0.0);
        assert!((limit_s_triple(0.1, 0.3, 0.8, 0.6, 0.1) - 0.8).abs() < 1e-15);
        assert!((limit_s_triple(0.1, 0.3, 0.8, 0.6, 0.5) - 0.6).abs() < 1e-15);
        assert!((limit_s_triple(0.1, 0.3, 0.8, 0.6, -0.5) + 0.6).abs() < 1e-15);
        // Pacejka: the peak D at B x = tan(pi / (2 C)) when E = 0.
        let (b, c, d) = (10.0, 1.9, 1.0);
        let x = (std::f64::consts::PI / (2.0 * c)).tan() / b;
        assert!((pacejka_magic(x, b, c, d, 0.0) - d).abs() < 1e-12);
    }
}
