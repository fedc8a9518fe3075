//! Joint models: how a joint's coordinates `q` and velocities `u` place and
//! move its frame_b relative to its frame_a.
//!
//! Spatial quantities are resolved in frame_b, the child frame of the tree.
//! `S` maps `u` to the spatial velocity of frame_b relative to frame_a, and
//! `c = dS/dt u` is the velocity-product part of its acceleration.

use crate::math::{
    axes_rotations, axes_rotations_rate_bias, axes_rotations_rate_matrix, from_q, omega_matrix, planar_rotation,
    Motion, Quat, Transform, Vec3,
};

/// How a free joint carries its rotation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum RotationCoordinates {
    /// Non-unit quaternion `Q_hat` with the library's norm-restoring gain `k`;
    /// velocity coordinates are the angular velocity resolved in frame_b.
    Quaternion { k: f64 },
    /// Euler angles of `sequence`; velocity coordinates are their rates.
    Euler { sequence: [usize; 3] },
}

/// The joint kinds of the tree.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum JointModel {
    /// Rotation by `q[0]` about the unit `axis` (same in both frames).
    Revolute { axis: Vec3 },
    /// Translation by `q[0]` along the unit `axis` (resolved in frame_a).
    Prismatic { axis: Vec3 },
    /// Six degrees of freedom: `q = [r (3), rotation]`, `u = [v (3), rotation rates (3)]`,
    /// with r and v the position and velocity of frame_b resolved in frame_a.
    Free(RotationCoordinates),
    /// Three translational degrees of freedom and no rotation:
    /// `q = r`, `u = v`, resolved in frame_a.
    Translation,
    /// Three rotational degrees of freedom about a common point:
    /// `q` = rotation coordinates, `u` = their rates (Euler) or the relative
    /// angular velocity resolved in frame_b (quaternion).
    Spherical(RotationCoordinates),
    /// Rotation `q[0]` about `n_a` (fixed in frame_a), then `q[1]` about
    /// `n_b` (fixed in frame_b).
    Universal { n_a: Vec3, n_b: Vec3 },
    /// Translation `q[0]` along and rotation `q[1]` about the same axis.
    Cylindrical { axis: Vec3 },
    /// Translations `q[0]` along `n_x` and `q[1]` along `n_y` (both in
    /// frame_a), then rotation `q[2]` about the plane normal `n`.
    Planar { n: Vec3, n_x: Vec3, n_y: Vec3 },
}

/// The kinematics of a joint at one state, in frame_b coordinates.
#[derive(Clone, Copy, Debug, Default)]
pub struct JointMotion {
    /// frame_a to frame_b.
    pub x: Transform,
    /// The columns of the motion subspace `S`; the first `nv` are used.
    pub s: [Motion; 6],
    /// Relative spatial velocity `S u`.
    pub vj: Motion,
    /// Velocity-product acceleration `dS/dt u`.
    pub cj: Motion,
}

/// A singular configuration of a joint's coordinates.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Singularity {
    /// `|det|` of the map from rates to angular velocity.
    pub measure: f64,
}

/// Below this `|det J|`, Euler rates are treated as singular: the rates that
/// represent a bounded angular velocity would exceed a million times it.
pub const EULER_SINGULARITY: f64 = 1e-6;

impl RotationCoordinates {
    pub fn nq(&self) -> usize {
        match self {
            RotationCoordinates::Quaternion { .. } => 4,
            RotationCoordinates::Euler { .. } => 3,
        }
    }

    /// Fills the angular columns of `S`, and returns the angular velocity
    /// (frame_b) and the angular velocity-product acceleration.
    #[inline]
    fn angular(&self, q: &[f64], rates: &Vec3, s: &mut [Motion]) -> (Vec3, Vec3) {
        match *self {
            RotationCoordinates::Quaternion { .. } => {
                for (k, col) in s.iter_mut().enumerate().take(3) {
                    *col = Motion::new(crate::math::unit(k), Vec3::zeros());
                }
                (*rates, Vec3::zeros())
            }
            RotationCoordinates::Euler { sequence } => {
                let phi = Vec3::new(q[0], q[1], q[2]);
                let j = axes_rotations_rate_matrix(sequence, &phi);
                for (k, col) in s.iter_mut().enumerate().take(3) {
                    *col = Motion::new(j.column(k).into(), Vec3::zeros());
                }
                (j * rates, axes_rotations_rate_bias(sequence, &phi, rates))
            }
        }
    }

    /// Rates of the rotation coordinates `q` for the velocity coordinates `rates`.
    #[inline]
    fn qdot(&self, q: &[f64], rates: &[f64], qd: &mut [f64]) {
        match *self {
            RotationCoordinates::Quaternion { k } => {
                let qh = Quat::new(q[0], q[1], q[2], q[3]);
                let d = quaternion_rate(&qh, &Vec3::new(rates[0], rates[1], rates[2]), k);
                qd[..4].copy_from_slice(d.as_slice());
            }
            RotationCoordinates::Euler { .. } => qd[..3].copy_from_slice(&rates[..3]),
        }
    }

    fn singularity(&self, q: &[f64]) -> Option<Singularity> {
        if let RotationCoordinates::Euler { sequence } = self {
            let measure = axes_rotations_rate_matrix(*sequence, &Vec3::new(q[0], q[1], q[2])).determinant().abs();
            if measure < EULER_SINGULARITY {
                return Some(Singularity { measure });
            }
        }
        None
    }
}

impl JointModel {
    pub fn nq(&self) -> usize {
        match self {
            JointModel::Revolute { .. } | JointModel::Prismatic { .. } => 1,
            JointModel::Free(rot) => 3 + rot.nq(),
            JointModel::Spherical(rot) => rot.nq(),
            JointModel::Translation | JointModel::Planar { .. } => 3,
            JointModel::Universal { .. } | JointModel::Cylindrical { .. } => 2,
        }
    }

    pub fn nv(&self) -> usize {
        match self {
            JointModel::Revolute { .. } | JointModel::Prismatic { .. } => 1,
            JointModel::Free(_) => 6,
            JointModel::Translation | JointModel::Spherical(_) | JointModel::Planar { .. } => 3,
            JointModel::Universal { .. } | JointModel::Cylindrical { .. } => 2,
        }
    }

    /// Where the rotation coordinates start in `q`, for joints that have them.
    pub fn rotation_coordinates(&self) -> Option<(usize, RotationCoordinates)> {
        match *self {
            JointModel::Free(rot) => Some((3, rot)),
            JointModel::Spherical(rot) => Some((0, rot)),
            _ => None,
        }
    }

    /// Coordinates of the zero displacement.
    pub fn neutral(&self, q: &mut [f64]) {
        q.fill(0.0);
        if let Some((k, RotationCoordinates::Quaternion { .. })) = self.rotation_coordinates() {
            q[k] = 1.0;
        }
    }

    /// The same joint with frame_a and frame_b exchanged, when it can be
    /// expressed in the same coordinates.
    pub fn reversed(&self) -> Option<JointModel> {
        match *self {
            JointModel::Revolute { axis } => Some(JointModel::Revolute { axis: -axis }),
            JointModel::Prismatic { axis } => Some(JointModel::Prismatic { axis: -axis }),
            _ => None,
        }
    }

    /// frame_a to frame_b at coordinates `q`.
    pub fn transform(&self, q: &[f64]) -> Transform {
        match *self {
            JointModel::Revolute { axis } => Transform::rotation(planar_rotation(&axis, q[0])),
            JointModel::Prismatic { axis } => Transform::translation(axis * q[0]),
            JointModel::Free(rot) => Transform::new(rotation_of(&rot, &q[3..]), Vec3::new(q[0], q[1], q[2])),
            JointModel::Translation => Transform::translation(Vec3::new(q[0], q[1], q[2])),
            JointModel::Spherical(rot) => Transform::rotation(rotation_of(&rot, q)),
            JointModel::Universal { n_a, n_b } => {
                Transform::rotation(planar_rotation(&n_b, q[1]) * planar_rotation(&n_a, q[0]))
            }
            JointModel::Cylindrical { axis } => Transform::new(planar_rotation(&axis, q[1]), axis * q[0]),
            JointModel::Planar { n, n_x, n_y } => Transform::new(planar_rotation(&n, q[2]), n_x * q[0] + n_y * q[1]),
        }
    }

    /// Transform, motion subspace, velocity and bias acceleration at `(q, u)`.
    #[inline]
    pub fn motion(&self, q: &[f64], u: &[f64], m: &mut JointMotion) {
        match *self {
            JointModel::Revolute { axis } => {
                m.x = Transform::rotation(planar_rotation(&axis, q[0]));
                m.s[0] = Motion::new(axis, Vec3::zeros());
                m.vj = Motion::new(axis * u[0], Vec3::zeros());
                m.cj = Motion::ZERO;
            }
            JointModel::Prismatic { axis } => {
                m.x = Transform::translation(axis * q[0]);
                m.s[0] = Motion::new(Vec3::zeros(), axis);
                m.vj = Motion::new(Vec3::zeros(), axis * u[0]);
                m.cj = Motion::ZERO;
            }
            JointModel::Free(rot) => {
                let r = rotation_of(&rot, &q[3..]);
                m.x = Transform::new(r, Vec3::new(q[0], q[1], q[2]));
                let v_b = r * Vec3::new(u[0], u[1], u[2]);
                for k in 0..3 {
                    m.s[k] = Motion::new(Vec3::zeros(), r.column(k).into());
                }
                let (w, bias) = rot.angular(&q[3..], &Vec3::new(u[3], u[4], u[5]), &mut m.s[3..6]);
                m.vj = Motion::new(w, v_b);
                m.cj = Motion::new(bias, -w.cross(&v_b));
            }
            JointModel::Spherical(rot) => {
                m.x = Transform::rotation(rotation_of(&rot, q));
                let (w, bias) = rot.angular(q, &Vec3::new(u[0], u[1], u[2]), &mut m.s[0..3]);
                m.vj = Motion::new(w, Vec3::zeros());
                m.cj = Motion::new(bias, Vec3::zeros());
            }
            JointModel::Universal { n_a, n_b } => {
                let rb = planar_rotation(&n_b, q[1]);
                m.x = Transform::rotation(rb * planar_rotation(&n_a, q[0]));
                let a_in_b = rb * n_a;
                m.s[0] = Motion::new(a_in_b, Vec3::zeros());
                m.s[1] = Motion::new(n_b, Vec3::zeros());
                m.vj = Motion::new(a_in_b * u[0] + n_b * u[1], Vec3::zeros());
                // d(rb n_a)/dt = -w_b n_b x (rb n_a)
                m.cj = Motion::new(-n_b.cross(&a_in_b) * (u[0] * u[1]), Vec3::zeros());
            }
            JointModel::Cylindrical { axis } => {
                m.x = Transform::new(planar_rotation(&axis, q[1]), axis * q[0]);
                m.s[0] = Motion::new(Vec3::zeros(), axis);
                m.s[1] = Motion::new(axis, Vec3::zeros());
                m.vj = Motion::new(axis * u[1], axis * u[0]);
                m.cj = Motion::ZERO;
            }
            JointModel::Planar { n, n_x, n_y } => {
                let r = planar_rotation(&n, q[2]);
                m.x = Transform::new(r, n_x * q[0] + n_y * q[1]);
                let (ex, ey) = (r * n_x, r * n_y);
                m.s[0] = Motion::new(Vec3::zeros(), ex);
                m.s[1] = Motion::new(Vec3::zeros(), ey);
                m.s[2] = Motion::new(n, Vec3::zeros());
                let v_b = ex * u[0] + ey * u[1];
                let w = n * u[2];
                m.vj = Motion::new(w, v_b);
                m.cj = Motion::new(Vec3::zeros(), -w.cross(&v_b));
            }
            JointModel::Translation => {
                m.x = Transform::translation(Vec3::new(q[0], q[1], q[2]));
                for k in 0..3 {
                    m.s[k] = Motion::new(Vec3::zeros(), crate::math::unit(k));
                }
                m.vj = Motion::new(Vec3::zeros(), Vec3::new(u[0], u[1], u[2]));
                m.cj = Motion::ZERO;
            }
        }
    }

    /// `dq/dt` at `(q, u)`.
    #[inline]
    pub fn qdot(&self, q: &[f64], u: &[f64], qd: &mut [f64]) {
        match *self {
            JointModel::Revolute { .. } | JointModel::Prismatic { .. } => qd[0] = u[0],
            JointModel::Translation | JointModel::Planar { .. } => qd[..3].copy_from_slice(&u[..3]),
            JointModel::Universal { .. } | JointModel::Cylindrical { .. } => qd[..2].copy_from_slice(&u[..2]),
            JointModel::Free(rot) => {
                qd[..3].copy_from_slice(&u[..3]);
                rot.qdot(&q[3..], &u[3..6], &mut qd[3..]);
            }
            JointModel::Spherical(rot) => rot.qdot(q, &u[..3], qd),
        }
    }

    /// Whether the coordinates are at (or too near) a singular configuration.
    pub fn singularity(&self, q: &[f64]) -> Option<Singularity> {
        let (k, rot) = self.rotation_coordinates()?;
        rot.singularity(&q[k..])
    }

    /// Coordinates `q` with `transform(q) = x`, the ones nearest `guess`
    /// where several exist (angles differing by turns, quaternion signs).
    pub fn coordinates_of(&self, x: &Transform, guess: &[f64], q: &mut [f64]) {
        let p = x.trans;
        match *self {
            JointModel::Revolute { axis } => q[0] = angle_about(&axis, &x.rot, guess[0]),
            JointModel::Prismatic { axis } => q[0] = axis.dot(&p),
            JointModel::Translation => q[..3].copy_from_slice(p.as_slice()),
            JointModel::Free(rot) => {
                q[..3].copy_from_slice(p.as_slice());
                rotation_coordinates_of(&rot, &x.rot, &guess[3..], &mut q[3..]);
            }
            JointModel::Spherical(rot) => rotation_coordinates_of(&rot, &x.rot, guess, q),
            JointModel::Universal { n_a, n_b } => {
                // R' n_b is n_b turned by phi_a about n_a; R n_a is n_a turned by -phi_b about n_b.
                q[0] = signed_angle(&n_a, &n_b, &x.rot.tr_mul(&n_b), guess[0]);
                q[1] = -signed_angle(&n_b, &n_a, &(x.rot * n_a), -guess[1]);
            }
            JointModel::Cylindrical { axis } => {
                q[0] = axis.dot(&p);
                q[1] = angle_about(&axis, &x.rot, guess[1]);
            }
            JointModel::Planar { n, n_x, n_y } => {
                q[0] = n_x.dot(&p);
                q[1] = n_y.dot(&p);
                q[2] = angle_about(&n, &x.rot, guess[2]);
            }
        }
    }

    /// The motion of frame_a relative to frame_b, in frame_a coordinates,
    /// from the motion `m` of frame_b relative to frame_a: a joint traversed
    /// backwards. `S' = -X^-1 S`, `c' = -X^-1 c` (the cross term of the
    /// apparent derivative vanishes).
    pub fn invert(m: &mut JointMotion, nv: usize) {
        let x = m.x;
        for s in m.s.iter_mut().take(nv) {
            *s = -x.inv_apply_motion(s);
        }
        m.vj = -x.inv_apply_motion(&m.vj);
        m.cj = -x.inv_apply_motion(&m.cj);
        m.x = x.inverse();
    }
}

/// The rotation (world-to-frame convention) of a free joint's rotation
/// coordinates; a quaternion is normalised first (`Q = Q_hat / |Q_hat|`).
pub fn rotation_of(rot: &RotationCoordinates, q: &[f64]) -> crate::math::Mat3 {
    match rot {
        RotationCoordinates::Quaternion { .. } => {
            let qh = Quat::new(q[0], q[1], q[2], q[3]);
            from_q(&(qh / qh.norm()))
        }
        RotationCoordinates::Euler { sequence } => axes_rotations(*sequence, &Vec3::new(q[0], q[1], q[2])),
    }
}

/// The angle `phi` with `planar_rotation(n, phi) = r` about the unit axis
/// `n`, the one nearest `near`.
pub fn angle_about(n: &Vec3, r: &crate::math::Mat3, near: f64) -> f64 {
    let e = crate::math::width_direction(n);
    signed_angle(n, &e, &r.tr_mul(&e), near)
}

/// The angle by which `from` turns into `to` about the unit axis `n`
/// (both projected onto the plane normal to `n`), nearest `near`.
fn signed_angle(n: &Vec3, from: &Vec3, to: &Vec3, near: f64) -> f64 {
    let (f, t) = (from - n * n.dot(from), to - n * n.dot(to));
    let angle = n.dot(&f.cross(&t)).atan2(f.dot(&t));
    let turns = ((near - angle) / std::f64::consts::TAU).round();
    angle + turns * std::f64::consts::TAU
}

/// Rotation coordinates of `r`, nearest `guess`.
fn rotation_coordinates_of(rot: &RotationCoordinates, r: &crate::math::Mat3, guess: &[f64], q: &mut [f64]) {
    match *rot {
        RotationCoordinates::Quaternion { .. } => {
            let g = Quat::new(guess[0], guess[1], guess[2], guess[3]);
            q[..4].copy_from_slice(crate::math::to_q(r, &g).as_slice());
        }
        RotationCoordinates::Euler { sequence } => {
            // Of the two triples of angles of r (the other: phi1 + pi, the
            // middle mirrored, phi3 + pi), each angle within pi of its
            // guess, the one nearer the guess: continuous along a motion,
            // also where the middle angle passes a singular value (a
            // wheel's spin in the library's sequence [2, 3, 1]).
            use std::f64::consts::{PI, TAU};
            let first = crate::math::axes_rotations_angles(r, sequence);
            let mirrored = if sequence[0] == sequence[2] { -first[1] } else { PI - first[1] };
            let second = Vec3::new(first[0] + PI, mirrored, first[2] + PI);
            let g = Vec3::new(guess[0], guess[1], guess[2]);
            let near = |a: Vec3| a.zip_map(&g, |x, g| x + ((g - x) / TAU).round() * TAU);
            let (a, b) = (near(first), near(second));
            q[..3].copy_from_slice(if (a - g).norm() <= (b - g).norm() { a.as_slice() } else { b.as_slice() });
        }
    }
}

/// The seed's quaternion equation:
/// `der(Q_hat) = Omega(w) Q_hat / 2 + k (1 - |Q_hat|^2) Q_hat`.
#[inline]
pub fn quaternion_rate(q_hat: &Quat, w: &Vec3, k: f64) -> Quat {
    let c_q = k * (1.0 - q_hat.norm_squared());
    omega_matrix(w) * q_hat * 0.5 + q_hat * c_q
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    fn samples() -> Vec<(JointModel, Vec<f64>, Vec<f64>)> {
        let unit = |x: f64, y: f64, z: f64| Vec3::new(x, y, z).normalize();
        let quat = |v: [f64; 4]| {
            let n = Quat::from(v).norm();
            v.iter().map(|x| x / n).collect::<Vec<f64>>()
        };
        let mut free_q = vec![0.1, -0.2, 0.3];
        free_q.extend(quat([0.9, 0.1, -0.3, 0.2]));
        vec![
            (JointModel::Revolute { axis: unit(1.0, 2.0, -1.0) }, vec![0.4], vec![1.3]),
            (JointModel::Prismatic { axis: Vec3::new(0.0, -1.0, 0.0) }, vec![0.4], vec![-0.7]),
            (
                JointModel::Free(RotationCoordinates::Euler { sequence: [3, 1, 2] }),
                vec![0.1, -0.2, 0.3, 0.4, -0.5, 0.6],
                vec![0.3, 0.1, -0.2, 1.0, -0.4, 0.7],
            ),
            (
                JointModel::Free(RotationCoordinates::Quaternion { k: 0.0 }),
                free_q,
                vec![0.3, 0.1, -0.2, 1.0, -0.4, 0.7],
            ),
            (JointModel::Translation, vec![1.0, 2.0, 3.0], vec![0.5, -0.5, 0.25]),
            (
                JointModel::Spherical(RotationCoordinates::Euler { sequence: [1, 2, 3] }),
                vec![0.3, -0.6, 1.1],
                vec![0.7, 0.2, -0.9],
            ),
            (
                JointModel::Spherical(RotationCoordinates::Quaternion { k: 0.0 }),
                quat([0.5, -0.5, 0.1, 0.7]),
                vec![0.7, 0.2, -0.9],
            ),
            (
                JointModel::Universal { n_a: unit(1.0, 0.0, 0.0), n_b: unit(0.0, 1.0, 0.2) },
                vec![0.8, -0.4],
                vec![1.1, 0.6],
            ),
            (JointModel::Cylindrical { axis: unit(0.0, 1.0, 1.0) }, vec![0.3, 0.9], vec![-0.4, 1.5]),
            (
                JointModel::Planar { n: Vec3::z(), n_x: Vec3::x(), n_y: Vec3::y() },
                vec![0.3, -0.2, 0.7],
                vec![0.5, 0.4, -1.2],
            ),
        ]
    }

    /// Motion of the joint, forward or traversed backwards.
    fn motion(model: &JointModel, q: &[f64], u: &[f64], inverted: bool) -> JointMotion {
        let mut m = JointMotion::default();
        model.motion(q, u, &mut m);
        if inverted {
            JointModel::invert(&mut m, model.nv());
        }
        m
    }

    /// Spatial velocity of the child frame relative to the parent frame, in
    /// child coordinates, by central differences of the transform.
    fn velocity_by_differences(model: &JointModel, q: &[f64], u: &[f64], inverted: bool) -> Motion {
        let h = 1e-6;
        let mut qd = vec![0.0; q.len()];
        model.qdot(q, u, &mut qd);
        let at = |sign: f64| -> Transform {
            let shifted: Vec<f64> = q.iter().zip(&qd).map(|(a, b)| a + sign * h * b).collect();
            let x = model.transform(&shifted);
            if inverted {
                x.inverse()
            } else {
                x
            }
        };
        let (xp, xm, x) = (at(1.0), at(-1.0), at(0.0));
        let rdot = (xp.rot - xm.rot) / (2.0 * h);
        let wx = -rdot * x.rot.transpose();
        let w = Vec3::new(wx[(2, 1)], wx[(0, 2)], wx[(1, 0)]);
        Motion::new(w, x.rot * ((xp.trans - xm.trans) / (2.0 * h)))
    }

    #[test]
    fn subspace_velocity_matches_finite_differences() {
        for (model, q, u) in samples() {
            for inverted in [false, true] {
                let m = motion(&model, &q, &u, inverted);
                let fd = velocity_by_differences(&model, &q, &u, inverted);
                assert_relative_eq!(m.vj.ang, fd.ang, epsilon = 1e-7);
                assert_relative_eq!(m.vj.lin, fd.lin, epsilon = 1e-7);
                let su = (0..model.nv()).fold(Motion::ZERO, |acc, k| acc + m.s[k] * u[k]);
                assert_relative_eq!(su.ang, m.vj.ang, epsilon = 1e-14);
                assert_relative_eq!(su.lin, m.vj.lin, epsilon = 1e-14);
            }
        }
    }

    #[test]
    fn bias_acceleration_matches_differentiated_subspace() {
        // cj = (d/dt S) u with u held fixed, in child coordinates: the
        // apparent derivative of vj.
        for (model, q, u) in samples() {
            for inverted in [false, true] {
                let h = 1e-6;
                let mut qd = vec![0.0; q.len()];
                model.qdot(&q, &u, &mut qd);
                let step = |s: f64| -> Vec<f64> { q.iter().zip(&qd).map(|(a, b)| a + s * h * b).collect() };
                let (mp, mm) = (motion(&model, &step(1.0), &u, inverted), motion(&model, &step(-1.0), &u, inverted));
                let m = motion(&model, &q, &u, inverted);
                let dv = (mp.vj - mm.vj) * (0.5 / h);
                assert_relative_eq!(m.cj.ang, dv.ang, epsilon = 1e-7);
                assert_relative_eq!(m.cj.lin, dv.lin, epsilon = 1e-7);
            }
        }
    }

    #[test]
    fn coordinates_of_inverts_transform() {
        for (model, q, _) in samples() {
            let x = model.transform(&q);
            let mut back = vec![0.0; q.len()];
            model.coordinates_of(&x, &q, &mut back);
            for (a, b) in back.iter().zip(&q) {
                assert!((a - b).abs() < 1e-12, "{model:?}: {back:?} vs {q:?}");
            }
        }
    }

    #[test]
    fn euler_singularity_is_detected() {
        let model = JointModel::Free(RotationCoordinates::Euler { sequence: [1, 2, 3] });
        assert!(model.singularity(&[0.0, 0.0, 0.0, 0.3, 0.2, 0.1]).is_none());
        let q = [0.0, 0.0, 0.0, 0.3, std::f64::consts::FRAC_PI_2, 0.1];
        assert!(model.singularity(&q).is_some());
    }
}
