//! Rotations in the library's convention.
//!
//! A rotation is stored as the matrix `R` that maps world coordinates into
//! frame coordinates, `v_frame = R * v_world` (Modelica's `T`). Angular
//! velocities are resolved in the rotated frame unless a name says otherwise.

use super::{skew, Mat3, Quat, Vec3};

/// `resolve1(R, v) = R' * v`: frame coordinates to world coordinates.
#[inline]
pub fn resolve1(r: &Mat3, v: &Vec3) -> Vec3 {
    r.tr_mul(v)
}

/// `resolve2(R, v) = R * v`: world coordinates to frame coordinates.
#[inline]
pub fn resolve2(r: &Mat3, v: &Vec3) -> Vec3 {
    r * v
}

/// Unit vector of axis `axis` (0, 1 or 2).
#[inline]
pub fn unit(axis: usize) -> Vec3 {
    let mut e = Vec3::zeros();
    e[axis] = 1.0;
    e
}

/// Rotation by `angle` about coordinate axis `axis` (0 = x, 1 = y, 2 = z):
/// `A_x(a) = [1 0 0; 0 c s; 0 -s c]` and likewise for y and z.
pub fn axis_rotation(axis: usize, angle: f64) -> Mat3 {
    let (s, c) = angle.sin_cos();
    match axis {
        0 => Mat3::new(1.0, 0.0, 0.0, 0.0, c, s, 0.0, -s, c),
        1 => Mat3::new(c, 0.0, -s, 0.0, 1.0, 0.0, s, 0.0, c),
        2 => Mat3::new(c, s, 0.0, -s, c, 0.0, 0.0, 0.0, 1.0),
        _ => panic!("axis index {axis} is not 0, 1 or 2"),
    }
}

/// The angle about z of a rotation about z (a planar frame's `phi`), in
/// (-pi, pi]: the inverse of `axis_rotation(2, phi)`.
pub fn planar_angle(r: &Mat3) -> f64 {
    r[(0, 1)].atan2(r[(0, 0)])
}

/// Rotation by `angle` about the unit axis `n`:
/// `R = n n' + (I - n n') cos(angle) - [n]x sin(angle)`.
pub fn planar_rotation(n: &Vec3, angle: f64) -> Mat3 {
    let (s, c) = angle.sin_cos();
    let nn = n * n.transpose();
    nn + (Mat3::identity() - nn) * c - skew(n) * s
}

/// The rotation of an Euler sequence `[i, j, k]` (1-based axis numbers, as the
/// library writes them): `R = A_k(phi3) * A_j(phi2) * A_i(phi1)`.
pub fn axes_rotations(sequence: [usize; 3], phi: &Vec3) -> Mat3 {
    let [i, j, k] = zero_based(sequence);
    axis_rotation(k, phi[2]) * axis_rotation(j, phi[1]) * axis_rotation(i, phi[0])
}

/// The matrix `J(phi)` that maps Euler angle rates to the angular velocity
/// resolved in the rotated frame: `w = J * phid`, with columns
/// `A_k A_j e_i`, `A_k e_j` and `e_k`.
pub fn axes_rotations_rate_matrix(sequence: [usize; 3], phi: &Vec3) -> Mat3 {
    let [i, j, k] = zero_based(sequence);
    let ak = axis_rotation(k, phi[2]);
    let c2 = ak * unit(j);
    let c1 = ak * axis_rotation(j, phi[1]) * unit(i);
    Mat3::from_columns(&[c1, c2, unit(k)])
}

/// The time derivative of [`axes_rotations_rate_matrix`] times the rates,
/// `dJ/dt * phid`: the part of the angular acceleration that the angle
/// accelerations do not explain.
pub fn axes_rotations_rate_bias(sequence: [usize; 3], phi: &Vec3, phid: &Vec3) -> Vec3 {
    let j = axes_rotations_rate_matrix(sequence, phi);
    let (c1, c2, c3) = (j.column(0), j.column(1), j.column(2));
    // d(c2)/dt = -phid3 c3 x c2, d(c1)/dt = -phid3 c3 x c1 - phid2 c2 x c1.
    -(c3.cross(&c1) * (phid[2] * phid[0]) + c2.cross(&c1) * (phid[1] * phid[0]) + c3.cross(&c2) * (phid[2] * phid[1]))
}

/// Whether an Euler sequence is of the valid kind: each axis 1, 2 or 3, and
/// neighbouring axes different.
pub fn is_valid_sequence(sequence: [usize; 3]) -> bool {
    sequence.iter().all(|&a| (1..=3).contains(&a)) && sequence[0] != sequence[1] && sequence[1] != sequence[2]
}

/// The Euler angles of `r` for `sequence`, with the middle angle chosen in
/// the branch that is continuous through the identity (`|phi2| <= pi/2` for
/// Cardan sequences, `0 <= phi2 <= pi` for proper Euler sequences). Inverse
/// of [`axes_rotations`] away from the singular configurations.
pub fn axes_rotations_angles(r: &Mat3, sequence: [usize; 3]) -> Vec3 {
    let [i, j, k] = zero_based(sequence);
    if i != k {
        // Cardan (Tait-Bryan) sequence, i, j, k all different.
        // Sign of the permutation (i, j, k).
        let sgn = if (j + 3 - i) % 3 == 1 { 1.0 } else { -1.0 };
        // For these passive rotations r[(k, i)] = sgn * sin(phi2).
        let s2 = (sgn * r[(k, i)]).clamp(-1.0, 1.0);
        let phi2 = s2.asin();
        let phi1 = (-sgn * r[(k, j)]).atan2(r[(k, k)]);
        let phi3 = (-sgn * r[(j, i)]).atan2(r[(i, i)]);
        Vec3::new(phi1, phi2, phi3)
    } else {
        // Proper Euler sequence, first and third axes equal.
        let l = 3 - i - j; // the remaining axis
        let sgn = if (j + 3 - i) % 3 == 1 { 1.0 } else { -1.0 };
        let c2 = r[(i, i)].clamp(-1.0, 1.0);
        let phi2 = c2.acos();
        let phi1 = r[(i, j)].atan2(-sgn * r[(i, l)]);
        let phi3 = r[(j, i)].atan2(sgn * r[(l, i)]);
        Vec3::new(phi1, phi2, phi3)
    }
}

fn zero_based(sequence: [usize; 3]) -> [usize; 3] {
    debug_assert!(is_valid_sequence(sequence), "invalid Euler sequence {sequence:?}");
    [sequence[0] - 1, sequence[1] - 1, sequence[2] - 1]
}

/// The rotation of a unit quaternion `Q = [w, i, j, k]`:
/// `R = (2 p0^2 - 1) I + 2 (p p' - p0 [p]x)`.
pub fn from_q(q: &Quat) -> Mat3 {
    let p0 = q[0];
    let p = Vec3::new(q[1], q[2], q[3]);
    Mat3::identity() * (2.0 * p0 * p0 - 1.0) + (p * p.transpose() - skew(&p) * p0) * 2.0
}

/// The unit quaternion `[w, i, j, k]` of a rotation, with the sign that makes
/// it closest to `guess` (the library's `to_Q`).
pub fn to_q(r: &Mat3, guess: &Quat) -> Quat {
    // Pick the numerically largest of the four candidate components.
    let t = r.trace();
    let candidates = [t, r[(0, 0)], r[(1, 1)], r[(2, 2)]];
    let (best, _) =
        candidates.iter().enumerate().fold((0, f64::NEG_INFINITY), |acc, (i, &v)| if v > acc.1 { (i, v) } else { acc });
    let q = match best {
        0 => {
            let p0 = 0.5 * (1.0 + t).sqrt();
            let c = 0.25 / p0;
            Quat::new(p0, c * (r[(1, 2)] - r[(2, 1)]), c * (r[(2, 0)] - r[(0, 2)]), c * (r[(0, 1)] - r[(1, 0)]))
        }
        1 => {
            let p1 = 0.5 * (1.0 + 2.0 * r[(0, 0)] - t).sqrt();
            let c = 0.25 / p1;
            Quat::new(c * (r[(1, 2)] - r[(2, 1)]), p1, c * (r[(0, 1)] + r[(1, 0)]), c * (r[(0, 2)] + r[(2, 0)]))
        }
        2 => {
            let p2 = 0.5 * (1.0 + 2.0 * r[(1, 1)] - t).sqrt();
            let c = 0.25 / p2;
            Quat::new(c * (r[(2, 0)] - r[(0, 2)]), c * (r[(0, 1)] + r[(1, 0)]), p2, c * (r[(1, 2)] + r[(2, 1)]))
        }
        _ => {
            let p3 = 0.5 * (1.0 + 2.0 * r[(2, 2)] - t).sqrt();
            let c = 0.25 / p3;
            Quat::new(c * (r[(0, 1)] - r[(1, 0)]), c * (r[(0, 2)] + r[(2, 0)]), c * (r[(1, 2)] + r[(2, 1)]), p3)
        }
    };
    if q.dot(guess) < 0.0 {
        -q
    } else {
        q
    }
}

/// `Omega(w)` with `der(Q) = Omega(w) * Q / 2` for the angular velocity `w`
/// resolved in the rotated frame.
pub fn omega_matrix(w: &Vec3) -> nalgebra::Matrix4<f64> {
    let (a, b, c) = (w[0], w[1], w[2]);
    nalgebra::Matrix4::new(
        0.0, -a, -b, -c, //
        a, 0.0, c, -b, //
        b, -c, 0.0, a, //
        c, b, -a, 0.0,
    )
}

/// The angular velocity, resolved in the rotated frame, of a unit quaternion
/// moving at `qd`: the inverse of `qd = Omega(w) q / 2`.
pub fn angular_velocity_of_q(q: &Quat, qd: &Quat) -> Vec3 {
    let (p0, p1, p2, p3) = (q[0], q[1], q[2], q[3]);
    let (d0, d1, d2, d3) = (qd[0], qd[1], qd[2], qd[3]);
    2.0 * Vec3::new(
        p0 * d1 - p1 * d0 + p3 * d2 - p2 * d3,
        p0 * d2 - p2 * d0 + p1 * d3 - p3 * d1,
        p0 * d3 - p3 * d0 + p2 * d1 - p1 * d2,
    )
}

/// The rotation whose x axis is along `n_x` and whose y axis is `n_y` made
/// orthogonal to it (Modelica's `from_nxy`); when `n_y` is parallel to
/// `n_x`, another axis stands in for it.
pub fn from_nxy(n_x: &Vec3, n_y: &Vec3) -> Mat3 {
    let e_x = if n_x.norm() < 1e-10 { Vec3::new(1.0, 0.0, 0.0) } else { n_x.normalize() };
    let n_z_aux = e_x.cross(n_y);
    let n_y_aux = if n_z_aux.norm_squared() > 1e-6 {
        *n_y
    } else if e_x[0].abs() > 1e-6 {
        Vec3::new(0.0, 1.0, 0.0)
    } else {
        Vec3::new(1.0, 0.0, 0.0)
    };
    let e_z = e_x.cross(&n_y_aux).normalize();
    let e_y = e_z.cross(&e_x);
    Mat3::from_rows(&[e_x.transpose(), e_y.transpose(), e_z.transpose()])
}

/// The rotation vector (axis times angle, resolved in either frame) of a
/// rotation matrix: small-rotation residue used by equality constraints.
pub fn rotation_vector(r: &Mat3) -> Vec3 {
    let q = to_q(r, &Quat::new(1.0, 0.0, 0.0, 0.0));
    let v = Vec3::new(q[1], q[2], q[3]);
    let s = v.norm();
    if s < 1e-12 {
        // R ~ I - [theta]x for passive rotations, and theta ~ 2 v.
        return 2.0 * v;
    }
    let angle = 2.0 * s.atan2(q[0]);
    v * (angle / s)
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    const SEQUENCES: [[usize; 3]; 12] = [
        [1, 2, 3],
        [1, 3, 2],
        [2, 1, 3],
        [2, 3, 1],
        [3, 1, 2],
        [3, 2, 1],
        [1, 2, 1],
        [1, 3, 1],
        [2, 1, 2],
        [2, 3, 2],
        [3, 1, 3],
        [3, 2, 3],
    ];

    #[test]
    fn axis_rotations_match_planar_rotation_about_unit_axes() {
        for axis in 0..3 {
            let a = 0.37;
            assert_relative_eq!(axis_rotation(axis, a), planar_rotation(&unit(axis), a), epsilon = 1e-15);
        }
        // A_x(a) written out, from the library's definition.
        let (s, c) = 0.3f64.sin_cos();
        assert_relative_eq!(axis_rotation(0, 0.3), Mat3::new(1.0, 0.0, 0.0, 0.0, c, s, 0.0, -s, c));
    }

    #[test]
    fn planar_rotation_leaves_its_axis_fixed_and_is_orthonormal() {
        let n = Vec3::new(1.0, -2.0, 0.5).normalize();
        let r = planar_rotation(&n, 1.1);
        assert_relative_eq!(r * n, n, epsilon = 1e-15);
        assert_relative_eq!(r * r.transpose(), Mat3::identity(), epsilon = 1e-15);
        assert_relative_eq!(r.determinant(), 1.0, epsilon = 1e-15);
    }

    #[test]
    fn euler_angles_round_trip_for_all_twelve_sequences() {
        let phi = Vec3::new(0.3, -0.4, 1.2);
        for seq in SEQUENCES {
            let mut angles = phi;
            if seq[0] == seq[2] {
                angles[1] = 0.7; // proper Euler: middle angle in (0, pi)
            }
            let r = axes_rotations(seq, &angles);
            let back = axes_rotations_angles(&r, seq);
            assert_relative_eq!(back, angles, epsilon = 1e-12);
        }
    }

    #[test]
    fn euler_rate_matrix_matches_finite_differences_of_the_rotation() {
        let phi = Vec3::new(0.3, -0.4, 1.2);
        let phid = Vec3::new(0.7, -1.3, 0.4);
        let h = 1e-6;
        for seq in SEQUENCES {
            // w from dR/dt: Rdot = -[w]x R, so [w]x = -Rdot R'.
            let r = axes_rotations(seq, &phi);
            let rdot = (axes_rotations(seq, &(phi + phid * h)) - axes_rotations(seq, &(phi - phid * h))) / (2.0 * h);
            let wx = -rdot * r.transpose();
            let w_fd = Vec3::new(wx[(2, 1)], wx[(0, 2)], wx[(1, 0)]);
            let w = axes_rotations_rate_matrix(seq, &phi) * phid;
            assert_relative_eq!(w, w_fd, epsilon = 1e-8);
            // dJ/dt * phid by finite differences of J along the path.
            let jdot = (axes_rotations_rate_matrix(seq, &(phi + phid * h))
                - axes_rotations_rate_matrix(seq, &(phi - phid * h)))
                / (2.0 * h);
            assert_relative_eq!(axes_rotations_rate_bias(seq, &phi, &phid), jdot * phid, epsilon = 1e-7);
        }
    }

    #[test]
    fn quaternion_round_trip_and_sign_choice() {
        let r = axes_rotations([1, 2, 3], &Vec3::new(0.3, -0.4, 2.9));
        let q = to_q(&r, &Quat::new(1.0, 0.0, 0.0, 0.0));
        assert_relative_eq!(q.norm(), 1.0, epsilon = 1e-15);
        assert_relative_eq!(from_q(&q), r, epsilon = 1e-14);
        let q_neg = to_q(&r, &(-q));
        assert_relative_eq!(q_neg, -q, epsilon = 1e-15);
    }

    #[test]
    fn spinning_about_x_for_half_pi_gives_the_documented_matrix() {
        // DESIGN.md: w_a = [1,0,0] for pi/2 s gives R = [1 0 0; 0 0 1; 0 -1 0].
        // Integrate der(Q) = Omega(w) Q / 2 in closed form: Q = expm(Omega t / 2) Q0.
        let w = Vec3::new(1.0, 0.0, 0.0);
        let t = std::f64::consts::FRAC_PI_2;
        let mut q = Quat::new(1.0, 0.0, 0.0, 0.0);
        let n = 100_000;
        let h = t / n as f64;
        let om = omega_matrix(&w);
        for _ in 0..n {
            // RK4 on the linear ODE
            let k1 = om * q * 0.5;
            let k2 = om * (q + k1 * (h / 2.0)) * 0.5;
            let k3 = om * (q + k2 * (h / 2.0)) * 0.5;
            let k4 = om * (q + k3 * h) * 0.5;
            q += (k1 + 2.0 * k2 + 2.0 * k3 + k4) * (h / 6.0);
        }
        let expected = Mat3::new(1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, -1.0, 0.0);
        assert_relative_eq!(from_q(&q), expected, epsilon = 1e-12);
        assert_relative_eq!(axis_rotation(0, t), expected, epsilon = 1e-15);
    }

    #[test]
    fn angular_velocity_of_q_inverts_omega_matrix() {
        let q = to_q(&axes_rotations([3, 1, 3], &Vec3::new(0.2, 0.9, -0.5)), &Quat::new(1.0, 0.0, 0.0, 0.0));
        let w = Vec3::new(0.3, -2.0, 0.8);
        let qd = omega_matrix(&w) * q * 0.5;
        assert_relative_eq!(angular_velocity_of_q(&q, &qd), w, epsilon = 1e-14);
    }

    #[test]
    fn from_nxy_puts_x_along_n_x_and_y_in_the_plane() {
        let r = from_nxy(&Vec3::new(1.0, 1.0, 0.0), &Vec3::new(0.0, 1.0, 0.0));
        let s = 0.5f64.sqrt();
        assert_relative_eq!(r.transpose() * Vec3::x(), Vec3::new(s, s, 0.0), epsilon = 1e-15);
        assert_relative_eq!(r.transpose() * Vec3::z(), Vec3::z(), epsilon = 1e-15);
        assert_relative_eq!(r * r.transpose(), Mat3::identity(), epsilon = 1e-15);
        // Parallel n_y: a valid rotation all the same.
        let r = from_nxy(&Vec3::new(0.0, 2.0, 0.0), &Vec3::new(0.0, 1.0, 0.0));
        assert_relative_eq!(r.determinant(), 1.0, epsilon = 1e-15);
        assert_relative_eq!(r.transpose() * Vec3::x(), Vec3::y(), epsilon = 1e-15);
    }

    #[test]
    fn rotation_vector_of_small_rotation() {
        let theta = Vec3::new(1e-3, -2e-3, 0.5e-3);
        let r = planar_rotation(&theta.normalize(), theta.norm());
        assert_relative_eq!(rotation_vector(&r), theta, epsilon = 1e-12);
        let big = Vec3::new(0.4, -1.0, 0.3);
        let r = planar_rotation(&big.normalize(), big.norm());
        assert_relative_eq!(rotation_vector(&r), big, epsilon = 1e-12);
    }
}
