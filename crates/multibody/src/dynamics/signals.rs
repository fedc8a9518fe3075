//! Evaluates the signal graph at one state: each block, in order, from
//! time, the slots it reads, and the motion after the kinematics pass.

use super::forces::PointState;
use super::Workspace;
use crate::math::{Mat3, Vec3};
use crate::system::{Attachment, Resolve, SignalBlock, SignalLaw, System};

impl System {
    /// The first time after `t` at which a source of time switches.
    pub(crate) fn next_time_event(&self, t: f64) -> f64 {
        let sources = self.signals.iter().filter_map(|b| match &b.law {
            SignalLaw::Source(source) => Some(source.next_switch(t)),
            _ => None,
        });
        let samples = self.equations.samples.iter().map(|s| s.next_after(t));
        sources.chain(samples).fold(f64::INFINITY, f64::min)
    }

    /// Every block's output into `ws.signals`, with the blocks of the
    /// model's own equations at their places among them. Needs the link
    /// velocities (and world poses when a block reads frames) of the
    /// kinematics pass.
    pub(crate) fn evaluate_signals(
        &self,
        ws: &mut Workspace,
        t: f64,
        q: &[f64],
        u: &[f64],
    ) -> Result<(), super::DynamicsError> {
        let positions = &self.equations.positions;
        if !self.equations.is_empty() {
            self.gather_equation_inputs(ws, t, q, u);
        }
        let mut next = 0;
        for (index, block) in self.signals.iter().enumerate() {
            while next < positions.len() && positions[next] == index {
                self.run_equation_block(ws, next)?;
                next += 1;
            }
            let input = |k: usize| ws.signals[block.inputs[k]];
            let value = match &block.law {
                SignalLaw::Source(source) if t == ws.left_limit_at => source.value_before(t),
                SignalLaw::Source(source) => source.value(t),
                &SignalLaw::Input { index, .. } => ws.inputs[index],
                SignalLaw::Affine { gains, bias } => {
                    bias + gains[0] * input(0) + gains[1] * input(1) + gains[2] * input(2)
                }
                SignalLaw::Product => input(0) * input(1),
                SignalLaw::Division => input(0) / input(1),
                SignalLaw::FlangePosition => {
                    block.flanges[1].motion(q, u, &ws.lines).0 - block.flanges[0].motion(q, u, &ws.lines).0
                }
                SignalLaw::FlangeSpeed => {
                    block.flanges[1].motion(q, u, &ws.lines).1 - block.flanges[0].motion(q, u, &ws.lines).1
                }
                &SignalLaw::FramePosition { index, resolve } => {
                    let (a, b) = self.frame_pair(ws, block);
                    resolved(b.r - a.r, resolve, &a.rot, &b.rot)[index]
                }
                &SignalLaw::FrameVelocity { index, resolve } => {
                    let (a, b) = self.frame_pair(ws, block);
                    resolved(b.v - a.v, resolve, &a.rot, &b.rot)[index]
                }
                &SignalLaw::AngularVelocity { index, resolve } => {
                    let (a, b) = self.frame_pair(ws, block);
                    resolved(b.w - a.w, resolve, &a.rot, &b.rot)[index]
                }
                &SignalLaw::RelativeVelocity { index, seen_from, resolve } => {
                    let (a, b) = self.frame_pair(ws, block);
                    let w = match seen_from {
                        Resolve::World => Vec3::zeros(),
                        Resolve::FrameA => a.w,
                        Resolve::FrameB => b.w,
                    };
                    resolved(b.v - a.v - w.cross(&(b.r - a.r)), resolve, &a.rot, &b.rot)[index]
                }
                &SignalLaw::FrameAngles { index, sequence, guess } => {
                    let (a, b) = self.frame_pair(ws, block);
                    axes_rotations_angles_near(&(b.rot * a.rot.transpose()), sequence, guess)[index]
                }
                &SignalLaw::FrameDistance { s_small } => {
                    let (a, b) = self.frame_pair(ws, block);
                    smooth_distance((b.r - a.r).norm_squared(), s_small)
                }
                &SignalLaw::ResolveVector { index } => {
                    let (a, b) = self.frame_pair(ws, block);
                    (b.rot * a.rot.tr_mul(&Vec3::new(input(0), input(1), input(2))))[index]
                }
                SignalLaw::Unavailable { .. } => f64::NAN,
                SignalLaw::Written => continue,
            };
            ws.signals[block.output] = value;
        }
        while next < self.equations.first_post {
            self.run_equation_block(ws, next)?;
            next += 1;
        }
        if !self.equations.when_conditions.is_empty() || !self.equations.when_actions.is_empty() {
            self.run_when_clauses(ws);
        }
        Ok(())
    }

    /// The motion of a sensor's frame a (the world when absent) and frame b,
    /// in the plane's coordinates for a sensor of a placed plane (whose
    /// world is the plane).
    fn frame_pair(&self, ws: &Workspace, block: &SignalBlock) -> (PointState, PointState) {
        let at = |f: &Option<Attachment>| match f {
            None => PointState::WORLD,
            Some(att) if block.in_plane => self.point_state(ws, att).in_plane(&self.plane),
            Some(att) => self.point_state(ws, att),
        };
        (at(&block.frames[0]), at(&block.frames[1]))
    }
}

/// A world vector resolved in the world, frame a or frame b.
#[inline]
fn resolved(v: Vec3, resolve: Resolve, rot_a: &Mat3, rot_b: &Mat3) -> Vec3 {
    match resolve {
        Resolve::World => v,
        Resolve::FrameA => rot_a * v,
        Resolve::FrameB => rot_b * v,
    }
}

/// The distance `sqrt(l2)` of a squared distance `l2`, replaced below
/// `s_small` by a smooth polynomial that is zero at zero (Modelica's
/// Distance sensor), so that it stays differentiable there.
pub(crate) fn smooth_distance(l2: f64, s_small: f64) -> f64 {
    let s2 = s_small * s_small;
    if l2 > s2 {
        l2.sqrt()
    } else {
        l2 / (2.0 * s_small) * (3.0 - l2 / s2)
    }
}

/// The angles `phi` of `r = axes_rotations(sequence, phi)` (each in
/// `[-pi, pi]`), of the two solutions the one whose first angle is nearest
/// `guess`; in a singular configuration (first and third axes aligned) the
/// first angle is `guess` itself.
pub(crate) fn axes_rotations_angles_near(r: &Mat3, sequence: [usize; 3], guess: f64) -> Vec3 {
    use crate::math::rotation::{axes_rotations_angles, axis_rotation};
    use std::f64::consts::PI;
    let wrap = |x: f64| {
        if x > PI {
            x - 2.0 * PI
        } else if x < -PI {
            x + 2.0 * PI
        } else {
            x
        }
    };
    let base = axes_rotations_angles(r, sequence);
    let cardan = sequence[0] != sequence[2];
    // Distance from the singular middle angle (+-pi/2 for Cardan, 0 or pi for Euler).
    let off_singular = if cardan { base[1].cos().abs() } else { base[1].sin().abs() };
    if off_singular < 1e-10 {
        // Only phi1 + phi3 (or their difference) is defined: take phi1 = guess.
        let phi2 = base[1];
        let rest = r * axis_rotation(sequence[0] - 1, guess).transpose();
        let a_k = rest * axis_rotation(sequence[1] - 1, phi2).transpose();
        let k = sequence[2] - 1;
        let (p, q) = ((k + 1) % 3, (k + 2) % 3);
        return Vec3::new(guess, phi2, a_k[(p, q)].atan2(a_k[(p, p)]));
    }
    // The other solution: phi1 + pi, the middle angle mirrored, phi3 + pi.
    let phi2 = if cardan { wrap(PI - base[1]) } else { -base[1] };
    let other = Vec3::new(wrap(base[0] + PI), phi2, wrap(base[2] + PI));
    if (other[0] - guess).abs() < (base[0] - guess).abs() {
        other
    } else {
        base
    }
}
