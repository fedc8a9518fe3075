//! Charts for Euler-angle states near their singular configuration.
//!
//! Euler angles of a sequence `[i, j, k]` are singular where the first and
//! third axes line up: the middle angle at `pi/2 + n pi` for a Cardan
//! (Tait-Bryan) sequence, at `n pi` for a proper Euler one. There the rates
//! that represent a bounded angular velocity grow without bound. A
//! simulator that sees the middle angle come within [`CHART_BAND`] of such
//! a value moves that joint to a chart: the same sequence measured from a
//! turned base `B` (on the joint's parent side), `R = A(psi) B`, with `B`
//! chosen so that `psi` starts with its middle angle as far from singular
//! as it can be. The angular velocity in frame_b is `J(psi) psid` as before
//! (B is constant), so the dynamics are those of Euler angles; only the
//! joint's fixed parent-side transform turns by `B`. The library's angles
//! are still reported: computed from `R`, their rates from the angular
//! velocity.

use crate::math::rotation::{axes_rotations, axes_rotations_rate_bias, axes_rotations_rate_matrix};
use crate::math::{Mat3, Vec3};
pub use crate::system::chart::EulerChart;
use std::f64::consts::{FRAC_PI_2, PI};

/// How close (in radians of the middle angle) a joint may come to its
/// singular configuration before it moves to a chart: `|cos phi2| < sin 0.1`
/// (Cardan), `|sin phi2| < sin 0.1` (proper Euler). The rates there are at
/// most about ten times the angular velocity.
pub const CHART_BAND: f64 = 0.1;

/// The first singular value of the middle angle: `pi/2` for a Cardan
/// sequence (three different axes), 0 for a proper Euler one.
pub fn singular_middle(sequence: [usize; 3]) -> f64 {
    if sequence[0] == sequence[2] {
        0.0
    } else {
        FRAC_PI_2
    }
}

/// The interval of the middle angle, around `middle`, that keeps
/// [`CHART_BAND`] from the singular values on either side.
pub fn safe_interval(sequence: [usize; 3], middle: f64) -> (f64, f64) {
    let first = singular_middle(sequence);
    let below = first + ((middle - first) / PI).floor() * PI;
    (below + CHART_BAND, below + PI - CHART_BAND)
}

/// The coordinates of a chart started at the rotation `r` (frame_a to
/// frame_b) turning at `w` (frame_b): its base, and `psi`, `psid` there
/// (the middle angle half way between singular values, the others 0).
pub fn chart_at(sequence: [usize; 3], r: &Mat3, w: &Vec3) -> (Mat3, Vec3, Vec3) {
    let psi = Vec3::new(0.0, singular_middle(sequence) + FRAC_PI_2, 0.0);
    let base = axes_rotations(sequence, &psi).transpose() * r;
    let j = axes_rotations_rate_matrix(sequence, &psi);
    let psid = j.try_inverse().expect("a chart's start is far from singular") * w;
    (base, psi, psid)
}

/// The library's angles of `r` for `sequence`, in the branch nearest
/// `guess` (each angle within pi of it; of the two solutions, the one
/// nearer): continuous along a motion when `guess` is the last value.
pub fn angles_near(r: &Mat3, sequence: [usize; 3], guess: &Vec3) -> Vec3 {
    let near = |x: f64, g: f64| x + ((g - x) / (2.0 * PI)).round() * 2.0 * PI;
    let unwrap = |a: Vec3| Vec3::new(near(a[0], guess[0]), near(a[1], guess[1]), near(a[2], guess[2]));
    let first = crate::dynamics::signals::axes_rotations_angles_near(r, sequence, near(guess[0], 0.0));
    // The other solution: phi1 + pi, the middle angle mirrored, phi3 + pi.
    let mirrored = if sequence[0] == sequence[2] { -first[1] } else { PI - first[1] };
    let second = Vec3::new(first[0] + PI, mirrored, first[2] + PI);
    let (a, b) = (unwrap(first), unwrap(second));
    if (a - guess).norm() <= (b - guess).norm() {
        a
    } else {
        b
    }
}

/// The library's angles, rates and accelerations of a joint integrated in
/// `chart` at `psi`, `psid`, `psidd`, the angles in the branch nearest
/// `guess`. At the singular configuration itself the rates are not finite.
pub fn library_coordinates(
    sequence: [usize; 3],
    chart: &EulerChart,
    (psi, psid, psidd): (&Vec3, &Vec3, &Vec3),
    guess: &Vec3,
) -> (Vec3, Vec3, Vec3) {
    let r = axes_rotations(sequence, psi) * chart.base;
    let phi = angles_near(&r, sequence, guess);
    let j_psi = axes_rotations_rate_matrix(sequence, psi);
    let w = j_psi * psid;
    let z = j_psi * psidd + axes_rotations_rate_bias(sequence, psi, psid);
    let j_inv = axes_rotations_rate_matrix(sequence, &phi).try_inverse().unwrap_or(Mat3::from_element(f64::NAN));
    let phid = j_inv * w;
    let phidd = j_inv * (z - axes_rotations_rate_bias(sequence, &phi, &phid));
    (phi, phid, phidd)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_chart_keeps_the_rotation_and_the_angular_velocity() {
        for sequence in [[1, 2, 3], [3, 1, 3], [2, 3, 1], [1, 2, 1]] {
            let phi = Vec3::new(0.4, singular_middle(sequence) + 0.05, -1.1);
            let phid = Vec3::new(0.3, -0.7, 0.2);
            let r = axes_rotations(sequence, &phi);
            let w = axes_rotations_rate_matrix(sequence, &phi) * phid;
            let (base, psi, psid) = chart_at(sequence, &r, &w);
            assert!((axes_rotations(sequence, &psi) * base - r).norm() < 1e-14);
            assert!((axes_rotations_rate_matrix(sequence, &psi) * psid - w).norm() < 1e-14);
            let chart = EulerChart { base, phi };
            let (back, rates, _) = library_coordinates(sequence, &chart, (&psi, &psid, &Vec3::zeros()), &phi);
            assert!((back - phi).norm() < 1e-12, "{sequence:?}: {back} vs {phi}");
            assert!((rates - phid).norm() < 1e-10, "{sequence:?}: {rates} vs {phid}");
            let (lo, hi) = safe_interval(sequence, psi[1]);
            assert!(lo < psi[1] && psi[1] < hi && (hi - lo - (PI - 2.0 * CHART_BAND)).abs() < 1e-15);
        }
    }

    #[test]
    fn angles_follow_the_branch_of_the_guess() {
        let sequence = [1, 2, 3];
        let phi = Vec3::new(7.0, 0.3, -4.0);
        let r = axes_rotations(sequence, &phi);
        let found = angles_near(&r, sequence, &Vec3::new(6.9, 0.31, -4.1));
        assert!((found - phi).norm() < 1e-12, "{found}");
    }
}
