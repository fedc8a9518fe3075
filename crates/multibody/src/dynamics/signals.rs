//! Evaluates the signal graph at one state: each block, in order, from
//! time, the slots it reads, and the motion after the kinematics pass.

use super::Workspace;
use crate::math::{Mat3, Vec3};
use crate::system::{Anchor, Attachment, Resolve, SignalLaw, System};

impl System {
    /// Every block's output into `ws.signals`. Needs the link velocities
    /// (and world poses when a block reads frames) of the kinematics pass.
    pub(crate) fn evaluate_signals(&self, ws: &mut Workspace, t: f64, q: &[f64], u: &[f64]) {
        for block in &self.signals {
            let input = |k: usize| ws.signals[block.inputs[k]];
            let value = match &block.law {
                SignalLaw::Source(source) => source.value(t),
                SignalLaw::Affine { gains, bias } => {
                    bias + gains[0] * input(0) + gains[1] * input(1) + gains[2] * input(2)
                }
                SignalLaw::Product => input(0) * input(1),
                SignalLaw::Division => input(0) / input(1),
                SignalLaw::FlangePosition => block.flanges[1].motion(q, u).0 - block.flanges[0].motion(q, u).0,
                SignalLaw::FlangeSpeed => block.flanges[1].motion(q, u).1 - block.flanges[0].motion(q, u).1,
                &SignalLaw::FramePosition { index, resolve } => {
                    let (a, b) = self.frame_pair(ws, &block.frames);
                    resolved(b.r - a.r, resolve, &a.rot, &b.rot)[index]
                }
                &SignalLaw::FrameVelocity { index, resolve } => {
                    let (a, b) = self.frame_pair(ws, &block.frames);
                    resolved(b.v - a.v, resolve, &a.rot, &b.rot)[index]
                }
                &SignalLaw::AngularVelocity { index, resolve } => {
                    let (a, b) = self.frame_pair(ws, &block.frames);
                    resolved(b.w - a.w, resolve, &a.rot, &b.rot)[index]
                }
            };
            ws.signals[block.output] = value;
        }
    }

    /// The motion of a sensor's frame a (the world when absent) and frame b.
    fn frame_pair(&self, ws: &Workspace, frames: &[Option<Attachment>; 2]) -> (FrameMotion, FrameMotion) {
        let at = |f: &Option<Attachment>| f.map_or(FrameMotion::WORLD, |att| self.frame_motion(ws, &att));
        (at(&frames[0]), at(&frames[1]))
    }

    fn frame_motion(&self, ws: &Workspace, att: &Attachment) -> FrameMotion {
        let p = self.point_state(ws, att);
        let w = match att.anchor {
            Anchor::Link(k) => ws.links[k].rot.tr_mul(&ws.links[k].v.ang),
            Anchor::Massless(_) => Vec3::zeros(),
        };
        FrameMotion { r: p.r, rot: p.rot, v: p.v, w }
    }
}

/// A frame's origin, world-to-frame rotation, origin velocity and angular
/// velocity (world coordinates).
#[derive(Clone, Copy)]
struct FrameMotion {
    r: Vec3,
    rot: Mat3,
    v: Vec3,
    w: Vec3,
}

impl FrameMotion {
    const WORLD: FrameMotion = FrameMotion {
        r: Vec3::new(0.0, 0.0, 0.0),
        rot: Mat3::new(1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0),
        v: Vec3::new(0.0, 0.0, 0.0),
        w: Vec3::new(0.0, 0.0, 0.0),
    };
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
