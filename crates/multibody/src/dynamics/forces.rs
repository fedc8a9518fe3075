//! Force elements between frames: where their ends are, what they apply,
//! and the position of massless groups that only they hold.

use super::{DynamicsError, Workspace};
use crate::math::rotation::planar_angle;
use crate::math::surface::Surface;
use crate::math::wheel::road_contact;
use crate::math::{Force, Mat3, Transform, Vec3};
use crate::system::{resolve_input, Resolve, SlipLaw};
use crate::system::{Anchor, Attachment, ForceElement, ForceLaw, System, GROUND};

/// The motion of a frame a force element acts on.
#[derive(Clone, Copy, Debug)]
pub(crate) struct PointState {
    /// Origin, world coordinates.
    pub r: Vec3,
    /// World to frame rotation.
    pub rot: Mat3,
    /// Velocity of the origin, world coordinates.
    pub v: Vec3,
    /// Angular velocity, world coordinates.
    pub w: Vec3,
}

impl PointState {
    /// The world's origin at rest.
    pub const WORLD: PointState = PointState {
        r: Vec3::new(0.0, 0.0, 0.0),
        rot: Mat3::new(1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0),
        v: Vec3::new(0.0, 0.0, 0.0),
        w: Vec3::new(0.0, 0.0, 0.0),
    };

    /// The same motion in the coordinates of the fixed frame `plane` (world
    /// to plane).
    #[inline]
    pub fn in_plane(&self, plane: &Transform) -> PointState {
        PointState {
            r: plane.apply_point(&self.r),
            rot: self.rot * plane.rot.transpose(),
            v: plane.rot * self.v,
            w: plane.rot * self.w,
        }
    }
}

/// A force (world coordinates) at a frame's origin and a moment (world
/// coordinates) about that origin.
pub(crate) type Wrench = (Vec3, Vec3);

/// Newton iterations allowed for massless groups, and the step that counts
/// as converged relative to the group's distance from the origin.
const MASSLESS_ITERATIONS: usize = 60;
const MASSLESS_STEP_TOLERANCE: f64 = 1e-13;

impl System {
    /// The motion of an attachment, from the link kinematics of `ws`.
    #[inline]
    pub(crate) fn point_state(&self, ws: &Workspace, att: &Attachment) -> PointState {
        match att.anchor {
            Anchor::Link(k) => {
                let lw = &ws.links[k];
                let p = att.pose.trans;
                PointState {
                    r: lw.pos + lw.rot.tr_mul(&p),
                    rot: att.pose.rot * lw.rot,
                    v: lw.rot.tr_mul(&(lw.v.lin + lw.v.ang.cross(&p))),
                    w: lw.rot.tr_mul(&lw.v.ang),
                }
            }
            Anchor::Massless(m) => PointState {
                r: ws.massless_pos[m] + att.pose.trans,
                rot: att.pose.rot,
                v: ws.massless_vel[m],
                w: Vec3::zeros(),
            },
        }
    }

    /// What element `el` applies: to the frames at its ends `(on a, on b)`,
    /// and the forces pushing its flanges `[a, b]` forward.
    #[inline]
    pub(crate) fn applied(
        &self,
        ws: &Workspace,
        el: &ForceElement,
        q: &[f64],
        u: &[f64],
    ) -> (Wrench, Wrench, [f64; 2]) {
        let kb = self.point_state(ws, &el.b);
        let ka = el.a.map(|a| self.point_state(ws, &a));
        if !el.in_plane {
            return self.law_applied(ws, el, q, u, ka, kb);
        }
        // A planar law works in the plane's coordinates; its wrenches turn back.
        let plane = &self.plane;
        let (on_a, on_b, on_flanges) =
            self.law_applied(ws, el, q, u, ka.map(|a| a.in_plane(plane)), kb.in_plane(plane));
        let back = |(f, t): Wrench| (plane.rot.tr_mul(&f), plane.rot.tr_mul(&t));
        (back(on_a), back(on_b), on_flanges)
    }

    /// What the law of `el` applies, with its ends' motion `ka`, `kb` in the
    /// coordinates it works in.
    #[inline]
    fn law_applied(
        &self,
        ws: &Workspace,
        el: &ForceElement,
        q: &[f64],
        u: &[f64],
        ka: Option<PointState>,
        kb: PointState,
    ) -> (Wrench, Wrench, [f64; 2]) {
        let zero = Vec3::zeros();
        let input = |k: usize| ws.signals[el.inputs[k]];
        let vector = |k: usize| Vec3::new(input(k), input(k + 1), input(k + 2));
        let resolved = |u: Vec3, resolve: Resolve| resolve_input(u, resolve, ka.as_ref().map(|a| &a.rot), &kb.rot);
        let frames_only = |(on_a, on_b): (Wrench, Wrench)| (on_a, on_b, [0.0; 2]);
        match el.law {
            ForceLaw::Line { c, d, s_unstretched, s_small } => {
                let ka = ka.expect("line forces have two ends");
                let f = line_force(c, d, s_unstretched, s_small, &ka, &kb).1;
                frames_only(((f, zero), (-f, zero)))
            }
            ForceLaw::Force { resolve } => {
                let f = resolved(vector(0), resolve);
                let lever = ka.map_or(zero, |a| kb.r - a.r);
                frames_only(((-f, -lever.cross(&f)), (f, zero)))
            }
            ForceLaw::Torque { resolve } => {
                let t = resolved(vector(0), resolve);
                frames_only(((zero, -t), (zero, t)))
            }
            ForceLaw::Flow { world } => {
                let at = |k: usize| if world { vector(k) } else { kb.rot.tr_mul(&vector(k)) };
                frames_only(((zero, zero), (-at(0), -at(3))))
            }
            ForceLaw::PlanarAxes { c, d, rel0 } => {
                let ka = ka.expect("planar springs have two ends");
                let (dr, dv) = (kb.r - ka.r, kb.v - ka.v);
                let dphi = planar_angle(&(kb.rot * ka.rot.transpose()));
                let pull = |k: usize, s: f64, v: f64| c[k] * (s - rel0[k]) + d[k] * v;
                let f = Vec3::new(pull(0, dr.x, dv.x), pull(1, dr.y, dv.y), 0.0);
                let t = Vec3::new(0.0, 0.0, pull(2, dphi, kb.w.z - ka.w.z));
                frames_only(((f, t), (-f, -t)))
            }
            ForceLaw::Tyre { radius, law, c_z, d_z, road } => {
                let (f, delta) = tyre_force(radius, &law, c_z, d_z, road.map(|r| &self.roads[r]), &kb);
                frames_only(((-f, zero), (f, delta.cross(&f))))
            }
            ForceLaw::PlanarSlip { radius, axis, n, law } => {
                let w_roll = el.flanges[1].motion(q, u, &ws.lines).1;
                let e_long = kb.rot.tr_mul(&axis);
                let e_lat = Vec3::new(-e_long.y, e_long.x, 0.0);
                let v_roll = radius * w_roll;
                let (mu_long, mu_lat) = law.coefficients(kb.v.dot(&e_long) - v_roll, kb.v.dot(&e_lat), v_roll);
                let f_n = (n + input(0)).max(0.0);
                // The ground pushes the wheel against its slip, and the
                // rolling flange by the longitudinal force at the radius.
                let on_wheel = -(e_long * mu_long + e_lat * mu_lat) * f_n;
                ((zero, zero), (on_wheel, zero), [0.0, radius * f_n * mu_long])
            }
        }
    }

    /// Adds the force elements' wrenches to the links' bias forces and
    /// their flange forces to the coordinates', and the lines' forces (from
    /// the 1-D elements on their flanges).
    pub(crate) fn apply_force_elements(&self, ws: &mut Workspace, q: &[f64], u: &[f64]) {
        for el in &self.force_elements {
            let (on_a, on_b, on_flanges) = self.applied(ws, el, q, u);
            apply(ws, &el.b, on_b);
            if let Some(a) = &el.a {
                apply(ws, a, on_a);
            }
            for (flange, force) in el.flanges.iter().zip(on_flanges) {
                if force != 0.0 {
                    flange.push(&mut ws.tau, &mut ws.lines, force);
                }
            }
        }
        for (line, k) in self.lines.iter().zip(0..) {
            let f = ws.lines[k].e * ws.lines[k].force;
            apply(ws, &line.b, (f, Vec3::zeros()));
            apply(ws, &line.a, (-f, Vec3::zeros()));
        }
    }

    /// Each line's length, rate and direction (world poses known).
    pub(crate) fn line_motion(&self, ws: &mut Workspace) {
        for (line, k) in self.lines.iter().zip(0..) {
            let (a, b) = (self.point_state(ws, &line.a), self.point_state(ws, &line.b));
            let (e, s, v) = line_geometry(line.s_small, &a, &b);
            let state = &mut ws.lines[k];
            (state.s, state.v, state.e) = (s, v, e);
        }
    }

    /// Positions (and velocities) of the massless groups: each group sits
    /// where the forces on it balance. Newton's method with the springs'
    /// stiffness, started from the last solution.
    pub(crate) fn solve_massless(&self, ws: &mut Workspace) -> Result<(), DynamicsError> {
        for (m, group) in self.massless.iter().enumerate() {
            let mut converged = false;
            for _ in 0..MASSLESS_ITERATIONS {
                let (force, stiffness, _) = self.balance(ws, m, &group.elements);
                let Some(k_inv) = stiffness.try_inverse() else { break };
                let step = k_inv * force;
                let before = force.norm();
                // Halve the step while it does not reduce the imbalance.
                let x0 = ws.massless_pos[m];
                let mut scale = 1.0;
                loop {
                    ws.massless_pos[m] = x0 + step * scale;
                    if self.balance(ws, m, &group.elements).0.norm() <= before || scale < 1e-3 {
                        break;
                    }
                    scale *= 0.5;
                }
                if (step * scale).norm() <= MASSLESS_STEP_TOLERANCE * (1.0 + x0.norm()) {
                    converged = true;
                    break;
                }
            }
            let (force, stiffness, coupling) = self.balance(ws, m, &group.elements);
            let scale = group.elements.len() as f64 * (1.0 + stiffness.norm() * (1.0 + ws.massless_pos[m].norm()));
            if !converged && force.norm() > 1e-9 * scale {
                return Err(DynamicsError::MasslessWithoutBalance { group: m });
            }
            // Differentiating the balance K (v - v_j) = 0 gives the velocity.
            ws.massless_vel[m] = stiffness.try_inverse().map_or(Vec3::zeros(), |k| k * coupling);
        }
        Ok(())
    }

    /// Net force on massless group `m`, its stiffness `-dF/dx`, and the
    /// stiffness-weighted velocities of the other ends.
    fn balance(&self, ws: &Workspace, m: usize, elements: &[usize]) -> (Vec3, Mat3, Vec3) {
        let (mut force, mut stiffness, mut coupling) = (Vec3::zeros(), Mat3::zeros(), Vec3::zeros());
        for &e in elements {
            let el = &self.force_elements[e];
            // Massless groups carry no flanges: no coordinates are needed.
            let (on_a, on_b, _) = self.applied(ws, el, &[], &[]);
            let a_here = el.a.is_some_and(|a| a.anchor == Anchor::Massless(m));
            let b_here = el.b.anchor == Anchor::Massless(m);
            if a_here {
                force += on_a.0;
            }
            if b_here {
                force += on_b.0;
            }
            if let (ForceLaw::Line { c, s_unstretched, s_small, .. }, Some(a)) = (el.law, el.a) {
                if a_here != b_here {
                    let (ka, kb) = (self.point_state(ws, &a), self.point_state(ws, &el.b));
                    let k = line_stiffness(c, s_unstretched, s_small, &ka, &kb);
                    stiffness += k;
                    coupling += k * if a_here { kb.v } else { ka.v };
                }
            }
        }
        (force, stiffness, coupling)
    }
}

/// The line force's geometry and the force it applies on frame_a:
/// `(unit vector a to b, force on a)`; the force on b is the opposite.
/// The force (world) of an elastic tyre contact on the wheel at `b`, and
/// where it acts: at `delta` from the wheel's centre (see [`ForceLaw::Tyre`]).
#[inline]
pub(crate) fn tyre_force(
    radius: f64,
    law: &SlipLaw,
    c_z: f64,
    d_z: f64,
    surface: Option<&Surface>,
    b: &PointState,
) -> (Vec3, Vec3) {
    let rc = road_contact(&b.rot, &b.w, &b.r, &b.v, radius, surface);
    let (c, e_n) = (rc.frame, rc.e_n);
    let v_contact = b.v + b.w.cross(&c.delta);
    let penetration = -rc.gap;
    // The rim's lowest point moves vertically as the wheel's point there does.
    let f_n = (c_z * penetration - d_z * e_n.dot(&v_contact)).max(0.0);
    // The slipping wheels' lateral direction is the rolling ones' turned round.
    let e_lat = -c.e_lat;
    let v_roll = radius * b.w.dot(&c.e_axis);
    let (mu_long, mu_lat) = law.coefficients(v_contact.dot(&c.e_long), v_contact.dot(&e_lat), v_roll);
    ((e_n - c.e_long * mu_long - e_lat * mu_lat) * f_n, c.delta)
}

#[inline]
pub(crate) fn line_force(c: f64, d: f64, s0: f64, s_small: f64, a: &PointState, b: &PointState) -> (Vec3, Vec3) {
    let (e, s, s_dot) = line_geometry(s_small, a, b);
    let f = c * (s - s0) + d * s_dot;
    (e, e * f)
}

/// The unit vector from a to b, their (guarded) distance and its rate.
#[inline]
pub(crate) fn line_geometry(s_small: f64, a: &PointState, b: &PointState) -> (Vec3, f64, f64) {
    let r_ab = b.r - a.r;
    let s = r_ab.norm().max(s_small);
    let e = r_ab / s;
    (e, s, e.dot(&(b.v - a.v)))
}

/// `-dF/dr` of a spring's force on one end with respect to that end's
/// position: `c e e' + (f / s) (I - e e')`.
fn line_stiffness(c: f64, s0: f64, s_small: f64, a: &PointState, b: &PointState) -> Mat3 {
    let r_ab = b.r - a.r;
    let s = r_ab.norm().max(s_small);
    let e = r_ab / s;
    let ee = e * e.transpose();
    ee * c + (Mat3::identity() - ee) * (c * (s - s0) / s)
}

#[inline]
fn apply(ws: &mut Workspace, att: &Attachment, (force, moment): Wrench) {
    if let Anchor::Link(k) = att.anchor {
        if k != GROUND {
            let lw = &mut ws.links[k];
            let f = lw.rot * force;
            let n = att.pose.trans.cross(&f) + lw.rot * moment;
            lw.pa -= Force::new(n, f);
        }
    }
}
