//! The coordinates a linear model is written in: one position and one
//! velocity coordinate per degree of freedom, plus the states of the
//! model's own equations.
//!
//! - A joint's own coordinates are kept where they add (angles, lengths,
//!   Euler angles): `q = q0 + dq`.
//! - A quaternion is not a coordinate (four numbers, three freedoms): its
//!   block moves by a small rotation `theta` about the moving frame's own
//!   axes, `Q = Q0 (x) exp(theta / 2)`, the same way the state equation
//!   `der(Q) = Omega(w) Q / 2` moves it at a constant `w`.
//! - A coordinate a drive imposes is a function of time, not a state.
//! - In a loop, as many coordinates as the constraints decide are
//!   dependent: the others are held and the dependent ones solved from the
//!   constraints (positions by Newton, velocities linearly). That is a basis
//!   of the null space of the constraint Jacobian whose coordinates are
//!   state names.

use crate::math::{skew, Mat3, Quat, Vec3};
use crate::system::joint::RotationCoordinates;
use crate::system::{JointModel, System};
use crate::Workspace;

/// How the position coordinate that belongs to a velocity coordinate moves.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Position {
    /// `q[index] += dq`.
    Additive { q: usize },
    /// One axis of a small rotation of the quaternion at `q` (4 values),
    /// whose angular velocity is the 3 velocity coordinates from `v`.
    Rotation { q: usize, v: usize, axis: usize },
}

/// The tangent space of a system's state at an operating point.
#[derive(Clone, Debug)]
pub(crate) struct Tangent {
    /// The velocity coordinates that are coordinates of the linear model.
    kept: Vec<usize>,
    /// Per velocity coordinate, how its position moves.
    position: Vec<Position>,
    /// Per velocity coordinate, whether the constraints decide it (loops).
    dependent: Vec<bool>,
    nq: usize,
    nv: usize,
    nx: usize,
    /// The names of the coordinates: positions, velocities, equation states.
    pub names: Vec<String>,
    /// What the coordinates are, in words (for the result's notes).
    pub notes: Vec<String>,
}

/// Why the tangent space could not be made.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum TangentError {
    Dynamics(crate::DynamicsError),
    /// A loop passes a joint whose coordinates do not add (quaternions).
    LoopThroughQuaternion(String),
    /// The constraints have lost rank at this configuration.
    SingularLoop {
        rank: usize,
        expected: usize,
    },
}

impl Tangent {
    /// The coordinates of `system` at the state `y` (on its constraints).
    pub(crate) fn new(system: &System, ws: &mut Workspace, y: &[f64]) -> Result<Self, TangentError> {
        let states = &system.states;
        let (nq, nv, nx) = (states.nq, states.nv, states.nx);
        let mut position = vec![Position::Additive { q: 0 }; nv];
        let mut rotation_blocks = Vec::new();
        for link in &system.links[1..] {
            let (qo, vo) = (link.q_offset, link.v_offset);
            let (rot_q, rot_v) = match link.joint {
                JointModel::Free(RotationCoordinates::Quaternion { .. }) => (Some(qo + 3), Some(vo + 3)),
                JointModel::Spherical(RotationCoordinates::Quaternion { .. }) => (Some(qo), Some(vo)),
                _ => (None, None),
            };
            for i in 0..link.joint.nv() {
                let v = vo + i;
                position[v] = match (rot_q, rot_v) {
                    (Some(q), Some(rv)) if v >= rv && v < rv + 3 => Position::Rotation { q, v: rv, axis: v - rv },
                    _ => Position::Additive { q: qo + i },
                };
            }
            if let (Some(q), Some(_)) = (rot_q, rot_v) {
                rotation_blocks.push(q);
            }
        }
        let free = |k: usize| system.free_coordinates.get(k).copied().unwrap_or(true);
        let mut dependent = vec![false; nv];
        let mut notes = Vec::new();
        if system.constraint_rows > 0 {
            let chosen = dependent_coordinates(system, ws, y, &free)?;
            for &k in &chosen {
                if matches!(position[k], Position::Rotation { .. }) {
                    return Err(TangentError::LoopThroughQuaternion(states.names[nq + k].clone()));
                }
                dependent[k] = true;
            }
            let expected = system.dof;
            let kept = (0..nv).filter(|&k| free(k) && !dependent[k]).count();
            if kept != expected {
                return Err(TangentError::SingularLoop { rank: chosen.len(), expected: nv - expected });
            }
            if !chosen.is_empty() {
                let names: Vec<&str> = chosen.iter().map(|&k| states.names[nq + k].as_str()).collect();
                notes.push(format!(
                    "the constraints decide {} (solved from the others: not coordinates of the linear model)",
                    names.join(", ")
                ));
            }
        }
        let driven: Vec<&str> = (0..nv).filter(|&k| !free(k)).map(|k| states.names[nq + k].as_str()).collect();
        if !driven.is_empty() {
            notes.push(format!("imposed by drives, not coordinates: {}", driven.join(", ")));
        }
        let kept: Vec<usize> = (0..nv).filter(|&k| free(k) && !dependent[k]).collect();
        let mut names = Vec::with_capacity(2 * kept.len() + nx);
        for &k in &kept {
            names.push(match position[k] {
                Position::Additive { q } => states.names[q].clone(),
                Position::Rotation { q, axis, .. } => format!("{}.rotation[{}]", owner(&states.names[q]), axis + 1),
            });
        }
        for &k in &kept {
            names.push(states.names[nq + k].clone());
        }
        names.extend(states.names[nq + nv..].iter().cloned());
        for q in rotation_blocks {
            if kept.iter().any(|&k| matches!(position[k], Position::Rotation { q: b, .. } if b == q)) {
                notes.push(format!(
                    "{0}.rotation[1..3]: a small rotation about {0}'s own axes stands for its quaternion (4 values, 3 freedoms)",
                    owner(&states.names[q])
                ));
            }
        }
        Ok(Self { kept, position, dependent, nq, nv, nx, names, notes })
    }

    /// How many coordinates there are.
    pub(crate) fn len(&self) -> usize {
        2 * self.kept.len() + self.nx
    }

    /// The state at the coordinates `dx` from `y0`, into `y`, with the
    /// dependent coordinates of loops solved from the constraints.
    pub(crate) fn retract(
        &self,
        system: &System,
        ws: &mut Workspace,
        y0: &[f64],
        dx: &[f64],
        y: &mut [f64],
    ) -> Result<(), crate::DynamicsError> {
        y.copy_from_slice(y0);
        let n = self.kept.len();
        let (nq, nv) = (self.nq, self.nv);
        for (i, &k) in self.kept.iter().enumerate() {
            match self.position[k] {
                Position::Additive { q } => y[q] += dx[i],
                Position::Rotation { q, axis: 0, .. } => {
                    let theta = self.rotation_of(q, dx);
                    let q0 = Quat::new(y0[q], y0[q + 1], y0[q + 2], y0[q + 3]);
                    y[q..q + 4].copy_from_slice(times(&q0, &exp_half(&theta)).as_slice());
                }
                Position::Rotation { .. } => {}
            }
            y[nq + k] += dx[n + i];
        }
        for i in 0..self.nx {
            y[nq + nv + i] += dx[2 * n + i];
        }
        if self.dependent.iter().any(|d| *d) {
            self.complete(system, ws, y)?;
        }
        Ok(())
    }

    /// The rotation a quaternion block at `q` is moved by in `dx`.
    fn rotation_of(&self, q: usize, dx: &[f64]) -> Vec3 {
        let mut theta = Vec3::zeros();
        for (i, &k) in self.kept.iter().enumerate() {
            if let Position::Rotation { q: b, axis, .. } = self.position[k] {
                if b == q {
                    theta[axis] = dx[i];
                }
            }
        }
        theta
    }

    /// The rates of the coordinates at `dx` (the state `y` there) from the
    /// state's rates `dy`, into `rates`.
    pub(crate) fn rates(&self, dx: &[f64], y: &[f64], dy: &[f64], rates: &mut [f64]) {
        let n = self.kept.len();
        let (nq, nv) = (self.nq, self.nv);
        for (i, &k) in self.kept.iter().enumerate() {
            rates[i] = match self.position[k] {
                Position::Additive { q } => dy[q],
                Position::Rotation { q, v, axis } => {
                    // d(theta)/dt = Jr(theta)^-1 w for Q = Q0 (x) exp(theta / 2).
                    let theta = self.rotation_of(q, dx);
                    let w = Vec3::new(y[nq + v], y[nq + v + 1], y[nq + v + 2]);
                    (right_jacobian_inverse(&theta) * w)[axis]
                }
            };
            rates[n + i] = dy[nq + k];
        }
        rates[2 * n..2 * n + self.nx].copy_from_slice(&dy[nq + nv..nq + nv + self.nx]);
    }

    /// The rows of the positions' rates in the linear model at the
    /// operating point `y` (`dx = 0`), as `(row, column, value)`: an
    /// additive coordinate's rate is its velocity coordinate; a rotation's,
    /// `Jr(theta)^-1 w`, has `d/dtheta = -[w]x / 2` and `d/dw = I` at zero.
    pub(crate) fn kinematic_rows(&self, y: &[f64], mut set: impl FnMut(usize, usize, f64)) {
        let n = self.kept.len();
        for (i, &k) in self.kept.iter().enumerate() {
            set(i, n + i, 1.0);
            if let Position::Rotation { v, axis, .. } = self.position[k] {
                let w = Vec3::new(y[self.nq + v], y[self.nq + v + 1], y[self.nq + v + 2]);
                let half = skew(&w) * -0.5;
                // The block's other axes, by their places among the kept coordinates.
                for (j, &other) in self.kept.iter().enumerate() {
                    if let Position::Rotation { v: ov, axis: oa, .. } = self.position[other] {
                        if ov == v {
                            set(i, j, half[(axis, oa)]);
                        }
                    }
                }
            }
        }
    }

    /// Solves the dependent coordinates of loops with the others held:
    /// positions by Newton steps (to rounding), then velocities.
    fn complete(&self, system: &System, ws: &mut Workspace, y: &mut [f64]) -> Result<(), crate::DynamicsError> {
        let mut best = f64::INFINITY;
        for _ in 0..40 {
            system.constraint_state(ws, y)?;
            let residual = ws.residual[..system.constraint_rows].iter().fold(0.0f64, |a, r| a.max(r.abs()));
            // Newton converges quadratically; stop where rounding stops it.
            if residual == 0.0 || residual >= best * 0.5 && residual < 1e-12 {
                break;
            }
            best = best.min(residual);
            system.least_norm_step(ws, Some(&self.dependent), true);
            system.retract(y, ws);
        }
        system.velocity_residual(ws, y)?;
        system.least_norm_step(ws, Some(&self.dependent), false);
        for i in 0..self.nv {
            y[self.nq + i] += ws.du[i];
        }
        Ok(())
    }
}

/// The component part of a state name (`body.Q_hat[1]` -> `body`).
fn owner(name: &str) -> &str {
    name.rsplit_once('.').map_or(name, |(owner, _)| owner)
}

/// The velocity coordinates the constraints decide at `y`: columns of the
/// constraint Jacobian chosen by Gram-Schmidt with the largest remaining
/// norm first (a well-conditioned dependent block), later coordinates
/// first among equals (so a mechanism is described by the joints nearest
/// the world, as one draws it).
fn dependent_coordinates(
    system: &System,
    ws: &mut Workspace,
    y: &[f64],
    free: &dyn Fn(usize) -> bool,
) -> Result<Vec<usize>, TangentError> {
    system.constraint_state(ws, y).map_err(TangentError::Dynamics)?;
    let (m, nv) = (system.constraint_rows, system.states.nv);
    let mut columns: Vec<(usize, Vec<f64>)> =
        (0..nv).filter(|&k| free(k)).map(|k| (k, (0..m).map(|r| ws.jac[r * nv + k]).collect())).collect();
    let norm = |c: &[f64]| c.iter().map(|x| x * x).sum::<f64>().sqrt();
    let largest = columns.iter().map(|(_, c)| norm(c)).fold(0.0, f64::max);
    let mut chosen = Vec::new();
    while !columns.is_empty() {
        let (mut pick, mut pick_norm) = (0, -1.0);
        for (i, (_, c)) in columns.iter().enumerate() {
            let n = norm(c);
            if n >= pick_norm * (1.0 + 1e-9) || (n >= pick_norm * (1.0 - 1e-9) && i > pick) {
                (pick, pick_norm) = (i, n);
            }
        }
        if pick_norm <= 1e-9 * largest || pick_norm == 0.0 {
            break;
        }
        let (k, mut e) = columns.swap_remove(pick);
        e.iter_mut().for_each(|x| *x /= pick_norm);
        for (_, c) in columns.iter_mut() {
            let dot: f64 = c.iter().zip(&e).map(|(a, b)| a * b).sum();
            c.iter_mut().zip(&e).for_each(|(a, b)| *a -= dot * b);
        }
        chosen.push(k);
    }
    chosen.sort_unstable();
    Ok(chosen)
}

/// The Hamilton product `a (x) b` of quaternions `[w, i, j, k]`.
fn times(a: &Quat, b: &Quat) -> Quat {
    let (a0, av) = (a[0], Vec3::new(a[1], a[2], a[3]));
    let (b0, bv) = (b[0], Vec3::new(b[1], b[2], b[3]));
    let v = bv * a0 + av * b0 + av.cross(&bv);
    Quat::new(a0 * b0 - av.dot(&bv), v[0], v[1], v[2])
}

/// `exp(theta / 2)` as a unit quaternion: the turn by `|theta|` about `theta`.
fn exp_half(theta: &Vec3) -> Quat {
    let angle = theta.norm();
    let s = if angle < 1e-8 { 0.5 - angle * angle / 48.0 } else { (0.5 * angle).sin() / angle };
    Quat::new((0.5 * angle).cos(), s * theta[0], s * theta[1], s * theta[2])
}

/// The inverse right Jacobian of the rotation group: with
/// `Q = Q0 (x) exp(theta / 2)` and `der(Q) = Q (x) [0, w] / 2`,
/// `der(theta) = Jr(theta)^-1 w`.
fn right_jacobian_inverse(theta: &Vec3) -> Mat3 {
    let angle = theta.norm();
    let k = skew(theta);
    let c = if angle < 1e-4 {
        1.0 / 12.0 + angle * angle / 720.0
    } else {
        1.0 / (angle * angle) - (1.0 + angle.cos()) / (2.0 * angle * angle.sin())
    };
    Mat3::identity() + k * 0.5 + k * k * c
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::system::joint::quaternion_rate;

    /// The rate formula matches the quaternion's own equation: moving the
    /// state by `der(Q) dt` moves `theta` by `Jr^-1 w dt`.
    #[test]
    fn rotation_rate_follows_the_quaternion_equation() {
        let q0 = Quat::new(0.8, -0.2, 0.5, 0.1).normalize();
        let theta = Vec3::new(0.3, -0.7, 0.4);
        let w = Vec3::new(1.3, 0.2, -0.9);
        let q = times(&q0, &exp_half(&theta));
        let dt = 1e-6;
        let rate = quaternion_rate(&q, &w, 0.0);
        // theta of a quaternion near q: log of q0^-1 (x) q, doubled.
        let log2 = |p: &Quat| {
            let conj = Quat::new(q0[0], -q0[1], -q0[2], -q0[3]);
            let r = times(&conj, p).normalize();
            let v = Vec3::new(r[1], r[2], r[3]);
            let angle = 2.0 * v.norm().atan2(r[0]);
            v.normalize() * angle
        };
        let numeric = (log2(&(q + rate * dt)) - log2(&(q - rate * dt))) / (2.0 * dt);
        let formula = right_jacobian_inverse(&theta) * w;
        assert!((numeric - formula).norm() < 1e-8, "{numeric} vs {formula}");
        assert!((log2(&q) - theta).norm() < 1e-12);
    }
}
