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

impl JointModel {
    pub fn nq(&self) -> usize {
        match self {
            JointModel::Revolute { .. } | JointModel::Prismatic { .. } => 1,
            JointModel::Free(RotationCoordinates::Quaternion { .. }) => 7,
            JointModel::Free(RotationCoordinates::Euler { .. }) => 6,
            JointModel::Translation => 3,
        }
    }

    pub fn nv(&self) -> usize {
        match self {
            JointModel::Revolute { .. } | JointModel::Prismatic { .. } => 1,
            JointModel::Free(_) => 6,
            JointModel::Translation => 3,
        }
    }

    /// Coordinates of the zero displacement.
    pub fn neutral(&self, q: &mut [f64]) {
        q.fill(0.0);
        if let JointModel::Free(RotationCoordinates::Quaternion { .. }) = self {
            q[3] = 1.0;
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
                let rates = Vec3::new(u[3], u[4], u[5]);
                let (w, bias) = match rot {
                    RotationCoordinates::Quaternion { .. } => {
                        for k in 0..3 {
                            m.s[3 + k] = Motion::new(crate::math::unit(k), Vec3::zeros());
                        }
                        (rates, Vec3::zeros())
                    }
                    RotationCoordinates::Euler { sequence } => {
                        let phi = Vec3::new(q[3], q[4], q[5]);
                        let j = axes_rotations_rate_matrix(sequence, &phi);
                        for k in 0..3 {
                            m.s[3 + k] = Motion::new(j.column(k).into(), Vec3::zeros());
                        }
                        (j * rates, axes_rotations_rate_bias(sequence, &phi, &rates))
                    }
                };
                m.vj = Motion::new(w, v_b);
                m.cj = Motion::new(bias, -w.cross(&v_b));
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
            JointModel::Translation => qd[..3].copy_from_slice(&u[..3]),
            JointModel::Free(rot) => {
                qd[..3].copy_from_slice(&u[..3]);
                match rot {
                    RotationCoordinates::Quaternion { k } => {
                        let qh = Quat::new(q[3], q[4], q[5], q[6]);
                        let d = quaternion_rate(&qh, &Vec3::new(u[3], u[4], u[5]), k);
                        qd[3..7].copy_from_slice(d.as_slice());
                    }
                    RotationCoordinates::Euler { .. } => qd[3..6].copy_from_slice(&u[3..6]),
                }
            }
        }
    }

    /// Whether the coordinates are at (or too near) a singular configuration.
    pub fn singularity(&self, q: &[f64]) -> Option<Singularity> {
        if let JointModel::Free(RotationCoordinates::Euler { sequence }) = self {
            let measure = axes_rotations_rate_matrix(*sequence, &Vec3::new(q[3], q[4], q[5])).determinant().abs();
            if measure < EULER_SINGULARITY {
                return Some(Singularity { measure });
            }
        }
        None
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

    /// Spatial velocity of frame_b relative to frame_a, in frame_b, by
    /// finite differences of the transform along the motion.
    fn velocity_by_differences(model: &JointModel, q: &[f64], u: &[f64]) -> Motion {
        let h = 1e-6;
        let mut qd = vec![0.0; q.len()];
        model.qdot(q, u, &mut qd);
        let plus: Vec<f64> = q.iter().zip(&qd).map(|(a, b)| a + h * b).collect();
        let minus: Vec<f64> = q.iter().zip(&qd).map(|(a, b)| a - h * b).collect();
        let (xp, xm, x) = (model.transform(&plus), model.transform(&minus), model.transform(q));
        let rdot = (xp.rot - xm.rot) / (2.0 * h);
        let wx = -rdot * x.rot.transpose();
        let w = Vec3::new(wx[(2, 1)], wx[(0, 2)], wx[(1, 0)]);
        let rdot_origin = (xp.trans - xm.trans) / (2.0 * h);
        Motion::new(w, x.rot * rdot_origin)
    }

    #[test]
    fn subspace_velocity_matches_finite_differences() {
        let models = [
            (JointModel::Revolute { axis: Vec3::new(1.0, 2.0, -1.0).normalize() }, vec![0.4], vec![1.3]),
            (JointModel::Prismatic { axis: Vec3::new(0.0, -1.0, 0.0) }, vec![0.4], vec![-0.7]),
            (
                JointModel::Free(RotationCoordinates::Euler { sequence: [3, 1, 2] }),
                vec![0.1, -0.2, 0.3, 0.4, -0.5, 0.6],
                vec![0.3, 0.1, -0.2, 1.0, -0.4, 0.7],
            ),
            (
                JointModel::Free(RotationCoordinates::Quaternion { k: 0.0 }),
                vec![0.1, -0.2, 0.3, 0.9, 0.1, -0.3, 0.2],
                vec![0.3, 0.1, -0.2, 1.0, -0.4, 0.7],
            ),
            (JointModel::Translation, vec![1.0, 2.0, 3.0], vec![0.5, -0.5, 0.25]),
        ];
        for (model, q, u) in models {
            let mut q = q;
            if let JointModel::Free(RotationCoordinates::Quaternion { .. }) = model {
                let n = Quat::new(q[3], q[4], q[5], q[6]).norm();
                q[3..7].iter_mut().for_each(|x| *x /= n);
            }
            let mut m = JointMotion::default();
            model.motion(&q, &u, &mut m);
            let fd = velocity_by_differences(&model, &q, &u);
            assert_relative_eq!(m.vj.ang, fd.ang, epsilon = 1e-7);
            assert_relative_eq!(m.vj.lin, fd.lin, epsilon = 1e-7);
            // vj = S u
            let su = (0..model.nv()).fold(Motion::ZERO, |acc, k| acc + m.s[k] * u[k]);
            assert_relative_eq!(su.ang, m.vj.ang, epsilon = 1e-14);
            assert_relative_eq!(su.lin, m.vj.lin, epsilon = 1e-14);
        }
    }

    #[test]
    fn bias_acceleration_matches_differentiated_subspace() {
        // cj = (d/dt S) u with u held fixed, in frame_b coordinates.
        let model = JointModel::Free(RotationCoordinates::Euler { sequence: [1, 2, 3] });
        let q = [0.1, -0.2, 0.3, 0.4, -0.5, 0.6];
        let u = [0.3, 0.1, -0.2, 1.0, -0.4, 0.7];
        let h = 1e-6;
        let mut qd = [0.0; 6];
        model.qdot(&q, &u, &mut qd);
        let step = |s: f64| -> Vec<f64> { q.iter().zip(&qd).map(|(a, b)| a + s * h * b).collect() };
        let (mut mp, mut mm, mut m) = (JointMotion::default(), JointMotion::default(), JointMotion::default());
        model.motion(&step(1.0), &u, &mut mp);
        model.motion(&step(-1.0), &u, &mut mm);
        model.motion(&q, &u, &mut m);
        // The derivative of vj in frame_b coordinates, as seen from frame_b (apparent derivative).
        let dv = (mp.vj - mm.vj) * (0.5 / h);
        assert_relative_eq!(m.cj.ang, dv.ang, epsilon = 1e-7);
        assert_relative_eq!(m.cj.lin, dv.lin, epsilon = 1e-7);
    }

    #[test]
    fn euler_singularity_is_detected() {
        let model = JointModel::Free(RotationCoordinates::Euler { sequence: [1, 2, 3] });
        assert!(model.singularity(&[0.0, 0.0, 0.0, 0.3, 0.2, 0.1]).is_none());
        let q = [0.0, 0.0, 0.0, 0.3, std::f64::consts::FRAC_PI_2, 0.1];
        assert!(model.singularity(&q).is_some());
    }
}
