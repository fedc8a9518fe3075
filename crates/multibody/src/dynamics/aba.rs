//! The articulated-body algorithm (Featherstone) with force elements.
//!
//! Uniform gravity enters as an upward acceleration of the ground, so the
//! link accelerations it computes are relative to a frame falling with
//! gravity; `outputs` adds gravity back.

use super::{DynamicsError, Workspace};
use crate::math::point_gravity;
use crate::math::{Force, Motion, Vec3};
use crate::system::JointMotion;
use crate::system::{System, GROUND};

impl System {
    /// Joint accelerations `ud` at positions `q` and velocities `u`.
    pub fn forward_dynamics(
        &self,
        ws: &mut Workspace,
        t: f64,
        q: &[f64],
        u: &[f64],
        ud: &mut [f64],
    ) -> Result<(), DynamicsError> {
        self.motion_and_loads(ws, t, q, u)?;
        if !self.needs_mass_matrix(ws) {
            self.articulated_inertias(ws)?;
            self.accelerations(ws, ud);
            if !self.frictions.is_empty() {
                // All sliding: their forces are loads, and no row holds.
                ws.lambda.fill(0.0);
                self.friction_modes(ws, q, u, ud);
            }
            Ok(())
        } else {
            // Loops may leave massless links in the tree, and a line
            // force's point mass couples two branches: solve the system as
            // a whole instead of the ABA's recursion.
            self.constrained_accelerations(ws, q, ud)?;
            if !self.frictions.is_empty() {
                self.friction_modes(ws, q, u, ud);
            }
            Ok(())
        }
    }

    /// Everything before the accelerations: the kinematics pass, the
    /// signals (which may read it), the massless groups, and every load on
    /// the links and joints.
    pub(crate) fn motion_and_loads(
        &self,
        ws: &mut Workspace,
        t: f64,
        q: &[f64],
        u: &[f64],
    ) -> Result<(), DynamicsError> {
        self.kinematics_and_bias(ws, q, u)?;
        if !self.lines.is_empty() {
            self.line_motion(ws);
        }
        if !self.drives.is_empty() {
            self.evaluate_time_jets(ws, t);
        }
        if !self.servos.is_empty() {
            self.servo_targets(ws, t);
        }
        self.evaluate_signals(ws, t, q, u)?;
        if !self.drives.is_empty() {
            self.drive_accelerations(ws, q, u);
        }
        if !self.massless.is_empty() {
            self.solve_massless(ws)?;
        }
        self.apply_forces(ws, q, u);
        self.apply_force_elements(ws, q, u);
        Ok(())
    }

    /// Pass 1: link transforms, velocities, world poses (when something
    /// needs them), and the bias force of each link alone.
    pub(crate) fn kinematics_and_bias(&self, ws: &mut Workspace, q: &[f64], u: &[f64]) -> Result<(), DynamicsError> {
        let mut jm = JointMotion::default();
        let world_poses = self.needs_world_poses();
        for k in 1..self.links.len() {
            let link = &self.links[k];
            link.motion(q, u, &mut jm);
            if link.joint.singularity(link.q(q)).is_some() {
                return Err(DynamicsError::EulerSingularity { link: k, time: f64::NAN });
            }
            // Parents come before their children.
            let (done, rest) = ws.links.split_at_mut(k);
            let parent = &done[link.parent];
            let w = &mut rest[0];
            w.x_up = link.x_tree.then(&jm.x);
            w.v = w.x_up.apply_motion(&parent.v) + jm.vj;
            w.c = jm.cj + w.v.cross_motion(&jm.vj);
            if world_poses {
                w.rot = w.x_up.rot * parent.rot;
                w.pos = parent.pos + parent.rot.tr_mul(&w.x_up.trans);
            }
            w.ia = link.articulated;
            w.pa = w.v.cross_force(&link.inertia.apply(&w.v));
            if link.joint.nv() == 1 {
                w.s = jm.s[0];
            } else {
                ws.multi[ws.multi_index[k]].s = jm.s;
            }
        }
        Ok(())
    }

    /// Whether the dynamics needs each link's pose in the world (forces
    /// between frames, point gravity, massless groups, constraints).
    #[inline]
    fn needs_world_poses(&self) -> bool {
        !(self.force_elements.is_empty()
            && self.point_masses.is_empty()
            && self.massless.is_empty()
            && self.constraints.is_empty()
            && self.line_masses.is_empty()
            && self.lines.is_empty()
            && !self.signals_read_frames
            && !self.equations.reads_frames)
    }

    /// Each link's pose in the world from the transforms of pass 1 (for
    /// outputs, when the dynamics did not need them).
    pub(crate) fn world_poses(&self, ws: &mut Workspace) {
        if self.needs_world_poses() {
            return;
        }
        for k in 1..self.links.len() {
            let (done, rest) = ws.links.split_at_mut(k);
            let parent = &done[self.links[k].parent];
            let w = &mut rest[0];
            w.rot = w.x_up.rot * parent.rot;
            w.pos = parent.pos + parent.rot.tr_mul(&w.x_up.trans);
        }
    }

    /// Generalised forces of 1-D elements, and external forces on links
    /// (point gravity), subtracted from the bias forces.
    fn apply_forces(&self, ws: &mut Workspace, q: &[f64], u: &[f64]) {
        ws.tau.fill(0.0);
        // A servo's efforts come out of the accelerations: none before.
        for s in &self.servos {
            for &slot in &s.slots {
                ws.signals[slot] = 0.0;
            }
        }
        for line in ws.lines.iter_mut() {
            line.force = 0.0;
        }
        for e in &self.axis_elements {
            // Sources (the flows equations give among them) need no motion.
            let force = e.law.source_force(&ws.signals).unwrap_or_else(|| {
                let (s_a, v_a) = e.a.motion(q, u, &ws.lines);
                let (s_b, v_b) = e.b.motion(q, u, &ws.lines);
                let watched = e.law.indicator_count();
                if watched > 0 {
                    e.law.indicators(s_b - s_a, &mut ws.indicators[e.indicator..e.indicator + watched]);
                }
                e.law.force(s_b - s_a, v_b - v_a, &ws.signals)
            });
            e.b.push(&mut ws.tau, &mut ws.lines, -force);
            e.a.push(&mut ws.tau, &mut ws.lines, force);
        }
        for &(v, force) in &self.axis_forces {
            ws.tau[v] += force;
        }
        if !self.frictions.is_empty() {
            self.friction_forces(ws, q, u);
        }
        for pm in &self.point_masses {
            let w = &mut ws.links[pm.link];
            let r = w.pos + w.rot.tr_mul(&pm.com);
            let f_world = (point_gravity(self.mu, &r) - self.uniform_gravity) * pm.mass;
            let f = w.rot * f_world;
            w.pa -= Force::new(pm.com.cross(&f), f);
        }
    }

    /// Pass 2: articulated inertias and bias forces from the leaves inwards.
    fn articulated_inertias(&self, ws: &mut Workspace) -> Result<(), DynamicsError> {
        let Workspace { links, multi, multi_index, tau, .. } = ws;
        for k in (1..self.links.len()).rev() {
            let link = &self.links[k];
            let nv = link.joint.nv();
            let (done, rest) = links.split_at_mut(k);
            let w = &mut rest[0];
            let (mut ia, mut pa);
            if link.driven != 0 && nv == 1 {
                // Its acceleration is known (in `c`): the link moves with its parent rigidly.
                if link.parent == GROUND {
                    continue;
                }
                ia = w.ia;
                pa = w.pa + ia.apply(&w.c);
            } else if nv == 1 {
                w.u_force = w.ia.apply(&w.s);
                let d = w.s.dot(&w.u_force) + link.armature;
                if d.is_nan() || d <= 0.0 {
                    return Err(DynamicsError::SingularInertia { link: k });
                }
                w.d_inv = 1.0 / d;
                w.u = tau[link.v_offset] - w.s.dot(&w.pa);
                if link.parent == GROUND {
                    continue;
                }
                ia = w.ia;
                ia.sub_outer(&w.u_force, w.d_inv);
                pa = w.pa + ia.apply(&w.c) + w.u_force * (w.u * w.d_inv);
            } else {
                let m = &mut multi[multi_index[k]];
                let mut d = nalgebra::Matrix6::<f64>::identity();
                // Driven columns carry no force of their own: zero U and u
                // leave them out (D is the identity there).
                for i in 0..nv {
                    let free = link.driven & (1 << i) == 0;
                    m.u_force[i] = if free { w.ia.apply(&m.s[i]) } else { Force::ZERO };
                    m.u[i] = if free { tau[link.v_offset + i] - m.s[i].dot(&w.pa) } else { 0.0 };
                }
                for i in 0..nv {
                    for j in 0..nv {
                        if (link.driven >> i | link.driven >> j) & 1 == 0 {
                            d[(i, j)] = m.s[i].dot(&m.u_force[j]);
                        }
                    }
                }
                m.d_inv = d.cholesky().ok_or(DynamicsError::SingularInertia { link: k })?.inverse();
                if link.parent == GROUND {
                    continue;
                }
                ia = w.ia;
                pa = w.pa;
                let dinv_u = m.d_inv * m.u;
                for j in 0..nv {
                    let mut wj = Force::ZERO;
                    for i in 0..nv {
                        wj += m.u_force[i] * m.d_inv[(i, j)];
                    }
                    ia.sub_product(&wj, &m.u_force[j]);
                    pa += m.u_force[j] * dinv_u[j];
                }
                pa += ia.apply(&w.c);
            }
            let parent = &mut done[link.parent];
            parent.ia += ia.expressed_in_parent(&w.x_up);
            parent.pa += w.x_up.inv_apply_force(&pa);
        }
        Ok(())
    }

    /// Pass 3: accelerations from the ground outwards.
    fn accelerations(&self, ws: &mut Workspace, ud: &mut [f64]) {
        let Workspace { links, multi, multi_index, imposed, .. } = ws;
        links[GROUND].a = Motion::new(Vec3::zeros(), -self.uniform_gravity);
        for k in 1..self.links.len() {
            let link = &self.links[k];
            let nv = link.joint.nv();
            let (done, rest) = links.split_at_mut(k);
            let w = &mut rest[0];
            let a_in = w.x_up.apply_motion(&done[link.parent].a) + w.c;
            w.a = if link.driven != 0 && nv == 1 {
                ud[link.v_offset] = imposed[link.v_offset];
                a_in
            } else if nv == 1 {
                let qdd = w.d_inv * (w.u - a_in.dot(&w.u_force));
                ud[link.v_offset] = qdd;
                a_in + w.s * qdd
            } else {
                let m = &multi[multi_index[k]];
                let mut rhs = nalgebra::Vector6::<f64>::zeros();
                for i in 0..nv {
                    rhs[i] = m.u[i] - a_in.dot(&m.u_force[i]);
                }
                let qdd = m.d_inv * rhs;
                let mut a = a_in;
                for i in 0..nv {
                    if link.driven & (1 << i) == 0 {
                        ud[link.v_offset + i] = qdd[i];
                        a += m.s[i] * qdd[i];
                    } else {
                        ud[link.v_offset + i] = imposed[link.v_offset + i];
                    }
                }
                a
            };
        }
    }
}
