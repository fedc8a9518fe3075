//! Imposed motion (see [`crate::system::drive`]): the derivatives of the
//! signals of time, the exact positions and speeds they give, and the
//! accelerations the drives impose.

use super::Workspace;
use crate::math::{omega_matrix, Motion, Quat, Vec3};
use crate::system::drive::{DriveLevel, DriveMap, FILTER_AF, FILTER_BF};
use crate::system::{SignalLaw, System};

impl System {
    /// Values and first two derivatives of the blocks that depend on time only.
    pub(crate) fn evaluate_time_jets(&self, ws: &mut Workspace, t: f64) {
        for block in &self.signals[..self.time_signals] {
            let jet = |k: usize| {
                let slot = block.inputs[k];
                let [d1, d2] = ws.signal_rates[slot];
                [ws.signals[slot], d1, d2]
            };
            let [value, d1, d2] = match &block.law {
                SignalLaw::Source(source) => source.jet(t),
                SignalLaw::Affine { gains, bias } => {
                    let mut out = [*bias, 0.0, 0.0];
                    for (k, gain) in gains.iter().enumerate() {
                        let x = jet(k);
                        for i in 0..3 {
                            out[i] += gain * x[i];
                        }
                    }
                    out
                }
                SignalLaw::Product => {
                    let (a, b) = (jet(0), jet(1));
                    [a[0] * b[0], a[1] * b[0] + a[0] * b[1], a[2] * b[0] + 2.0 * a[1] * b[1] + a[0] * b[2]]
                }
                SignalLaw::Division => {
                    let (a, b) = (jet(0), jet(1));
                    let y = a[0] / b[0];
                    let y1 = (a[1] - y * b[1]) / b[0];
                    [y, y1, (a[2] - 2.0 * y1 * b[1] - y * b[2]) / b[0]]
                }
                // Assembly puts only blocks of time before the others.
                _ => [f64::NAN; 3],
            };
            ws.signals[block.output] = value;
            ws.signal_rates[block.output] = [d1, d2];
        }
    }

    /// Writes into `y` the positions and speeds that the drives know
    /// exactly at `t`.
    pub(crate) fn impose_drives(&self, ws: &mut Workspace, t: f64, y: &mut [f64]) {
        self.evaluate_time_jets(ws, t);
        let nq = self.states.nq;
        for drive in &self.drives {
            let link = &self.links[drive.link];
            let jet = |k: usize| {
                let slot = drive.slots[k];
                let [d1, d2] = ws.signal_rates[slot];
                [ws.signals[slot], d1, d2]
            };
            match (drive.map, drive.level) {
                (DriveMap::Linear { first, count, scale, offset }, level) => {
                    for k in 0..count {
                        let x = jet(k);
                        let (q, v) = (link.q_offset + first + k, nq + link.v_offset + first + k);
                        match level {
                            DriveLevel::Position => {
                                y[q] = (x[0] - offset) / scale;
                                y[v] = x[1] / scale;
                            }
                            DriveLevel::Speed => y[v] = x[0] / scale,
                            DriveLevel::Balance { node } => {
                                let (q_all, u_all) = y.split_at(nq);
                                let (s, speed) = self.balance_motion(ws, &self.balances[node], q_all, u_all);
                                y[q] = s;
                                y[v] = speed;
                            }
                            _ => {}
                        }
                    }
                }
                (DriveMap::Pose, _) => {
                    let (q, v) = (link.q_offset, nq + link.v_offset);
                    for k in 0..3 {
                        let x = jet(k);
                        y[q + k] = x[0];
                        y[v + k] = x[1];
                    }
                    let (quat, rate, _) = quaternion_jet(&jet);
                    y[q + 3..q + 7].copy_from_slice(quat.as_slice());
                    let w = body_rates(&quat, &rate);
                    y[v + 3..v + 6].copy_from_slice(w.as_slice());
                }
            }
        }
    }

    /// The accelerations the drives impose at `(q, u)` into `ws.imposed`,
    /// and the part they add to each driven link's acceleration into its
    /// velocity-product term (the dynamics then solves for the rest).
    /// Needs the signals evaluated.
    pub(crate) fn drive_accelerations(&self, ws: &mut Workspace, q: &[f64], u: &[f64]) {
        for drive in &self.drives {
            let link = &self.links[drive.link];
            let value = |k: usize| ws.signals[drive.slots[k]];
            let rates = |k: usize| ws.signal_rates[drive.slots[k]];
            match drive.map {
                DriveMap::Linear { first, count, scale, offset } => {
                    for k in 0..count {
                        let (qi, vi) = (link.q_offset + first + k, link.v_offset + first + k);
                        let (x, v) = (offset + scale * q[qi], scale * u[vi]);
                        let a = match drive.level {
                            DriveLevel::Position => rates(k)[1],
                            DriveLevel::Speed => rates(k)[0],
                            DriveLevel::Acceleration => value(k),
                            DriveLevel::PositionFilter { w_crit } => {
                                ((value(k) - x) * w_crit - FILTER_AF * v) * (w_crit / FILTER_BF)
                            }
                            DriveLevel::SpeedFilter { w_crit } => (value(k) - v) * w_crit,
                            // Known after the dynamics (the node moves nothing with mass).
                            DriveLevel::Balance { .. } => 0.0,
                        };
                        ws.imposed[vi] = a / scale;
                    }
                }
                DriveMap::Pose => {
                    let jet = |k: usize| {
                        let [d1, d2] = rates(k);
                        [value(k), d1, d2]
                    };
                    for k in 0..3 {
                        ws.imposed[link.v_offset + k] = jet(k)[2];
                    }
                    let (quat, _, second) = quaternion_jet(&jet);
                    let alpha = body_rates(&quat, &second);
                    ws.imposed[link.v_offset + 3..link.v_offset + 6].copy_from_slice(alpha.as_slice());
                }
            }
            let mut known = Motion::ZERO;
            for i in 0..link.joint.nv() {
                if link.driven & (1 << i) != 0 {
                    known += self.joint_column(ws, drive.link, i) * ws.imposed[link.v_offset + i];
                }
            }
            ws.links[drive.link].c += known;
        }
    }

    /// Column `i` of link `k`'s motion subspace from the last kinematics pass.
    #[inline]
    pub(crate) fn joint_column(&self, ws: &Workspace, k: usize, i: usize) -> Motion {
        if self.links[k].joint.nv() == 1 {
            ws.links[k].s
        } else {
            ws.multi[ws.multi_index[k]].s[i]
        }
    }
}

/// The quaternion of signals 3..7 and its first two derivatives.
fn quaternion_jet(jet: &impl Fn(usize) -> [f64; 3]) -> (Quat, Quat, Quat) {
    let x = [jet(3), jet(4), jet(5), jet(6)];
    let pick = |i: usize| Quat::new(x[0][i], x[1][i], x[2][i], x[3][i]);
    (pick(0), pick(1), pick(2))
}

/// The angular velocity (frame coordinates) of a quaternion moving at
/// `rate`: with `dQ/dt = B(Q) w / 2`, `w = 2 B' dQ/dt / |Q|^2`. With the
/// second derivative in place of the first it gives the angular
/// acceleration, since `B(Q)' B(dQ/dt) w = 0` for a quaternion of constant
/// norm.
fn body_rates(quat: &Quat, rate: &Quat) -> Vec3 {
    let scale = 2.0 / quat.norm_squared();
    Vec3::from_fn(|k, _| scale * (omega_matrix(&crate::math::unit(k)) * quat).dot(rate))
}
