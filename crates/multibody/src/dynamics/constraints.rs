//! Constraints: the cuts of kinematic loops and the constraint components.
//!
//! Each constraint keeps rows `y = 0` between its frames A and B: locked
//! rotations (`d . R_A (w_B - w_A)`), locked translations of B's origin in
//! A (`d . R_A (v_B - v_A - w_A x r_AB)`), or a distance. The accelerations
//! solve `M udot = tau - C + J' lambda`, `J udot = -Jdot u`: with the free
//! accelerations of the ABA, `udot = udot_free + M^-1 J' lambda` where
//! `(J M^-1 J') lambda = -Jdot u - J udot_free`. Redundant rows (planar
//! loops of spatial joints) are handled by a pivoted LDL' that gives them
//! zero multipliers. After each integration step, positions and velocities
//! are projected back onto the constraints.

use super::{DynamicsError, Workspace};
use crate::math::dense::{cholesky, cholesky_solve, ldlt_pivoted, ldlt_solve, lu, lu_solve};
use crate::math::surface::Surface;
use crate::math::wheel::{contact_frame, road_contact};
use crate::math::{rotation_vector, Force, Mat3, Motion, RigidInertia, Vec3};
use crate::system::{Anchor, Attachment, Constraint, LineMass, System, GROUND};
use crate::system::{ConstraintKind, RotationLock, WheelContact};

/// Rows whose pivot is below this fraction of the largest are redundant.
const RANK_TOLERANCE: f64 = 1e-10;
/// Positions are projected when a residual exceeds this (m or rad) ...
const PROJECT_ABOVE: f64 = 1e-12;
/// ... in at most this many Newton steps.
const PROJECTION_ITERATIONS: usize = 10;
/// A position residual that projection leaves above this (m or rad) is a
/// loop that cannot close: where projection works it ends below
/// [`PROJECT_ABOVE`], and through a singular configuration (a
/// parallelogram's change point) still far below this.
const LOOP_OPEN: f64 = 1e-6;

/// Where a constraint end is and how it moves, in world coordinates; the
/// accelerations are those with all joint accelerations zero and no gravity.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct EndState {
    pub link: usize,
    pub r: Vec3,
    pub rot: Mat3,
    pub w: Vec3,
    pub v: Vec3,
    pub alpha: Vec3,
    pub a: Vec3,
}

impl EndState {
    /// This end seen from a ground frame `ground` that does not move: in
    /// its coordinates (a wheel's road is its plane y = 0).
    fn seen_from_ground(&self, ground: &EndState) -> EndState {
        let into = |v: Vec3| ground.rot * v;
        EndState {
            link: self.link,
            r: into(self.r - ground.r),
            rot: self.rot * ground.rot.transpose(),
            w: into(self.w),
            v: into(self.v),
            alpha: into(self.alpha),
            a: into(self.a),
        }
    }
}

/// One row of a constraint: its kind and direction (frame A coordinates).
#[derive(Clone, Copy, Debug)]
enum Row {
    Rotation(Vec3),
    Translation(Vec3),
    Distance,
    /// A wheel's contact: `e . (v_B + w_B x delta)`, the velocity along the
    /// world direction `e` of B's material point at `delta` from B's origin
    /// (relative to the ground), with the rates `e_dot` and `delta_dot`.
    Contact {
        e: Vec3,
        e_dot: Vec3,
        delta: Vec3,
        delta_dot: Vec3,
    },
}

/// The rows of a constraint at the current state, and their residuals.
fn rows(kind: &ConstraintKind, a: &EndState, b: &EndState, roads: &[Surface], out: &mut [(Row, f64)]) -> usize {
    let r_ab = b.r - a.r;
    let p = a.rot * r_ab;
    let r_rel = b.rot * a.rot.transpose();
    let mut n = 0;
    let mut push = |row: Row, residual: f64| {
        out[n] = (row, residual);
        n += 1;
    };
    match *kind {
        ConstraintKind::Locks { rotation, directions, count } => {
            match rotation {
                RotationLock::Free => {}
                RotationLock::All => {
                    let theta = rotation_vector(&r_rel);
                    for k in 0..3 {
                        push(Row::Rotation(crate::math::unit(k)), theta[k]);
                    }
                }
                RotationLock::Axes(locked) => {
                    let theta = rotation_vector(&r_rel);
                    for k in (0..3).filter(|&k| locked[k]) {
                        push(Row::Rotation(crate::math::unit(k)), theta[k]);
                    }
                }
                RotationLock::AllBut(axis) => {
                    let e1 = crate::math::width_direction(&axis);
                    let e2 = axis.cross(&e1);
                    let misalignment = axis.cross(&r_rel.tr_mul(&axis));
                    push(Row::Rotation(e1), e1.dot(&misalignment));
                    push(Row::Rotation(e2), e2.dot(&misalignment));
                }
                RotationLock::Universal { n_a, n_b } => {
                    let n_b_in_a = r_rel.tr_mul(&n_b);
                    push(Row::Rotation(n_b_in_a.cross(&n_a)), n_a.dot(&n_b_in_a) - n_a.dot(&n_b));
                }
            }
            for d in directions.iter().take(count) {
                push(Row::Translation(*d), d.dot(&p));
            }
        }
        ConstraintKind::Distance { length } => push(Row::Distance, r_ab.norm() - length),
        ConstraintKind::Wheel { radius, contact } => {
            // Frame A is the ground; the road is its plane y = 0 or a
            // surface. The contact is found in its coordinates (those of
            // the world, or of a planar World's placed plane), and its
            // directions turned back into the world's.
            let b = &b.seen_from_ground(a);
            let to_world = |v: Vec3| a.rot.tr_mul(&v);
            let mut push = |row: Row, residual: f64| {
                let row = match row {
                    Row::Contact { e, e_dot, delta, delta_dot } => Row::Contact {
                        e: to_world(e),
                        e_dot: to_world(e_dot),
                        delta: to_world(delta),
                        delta_dot: to_world(delta_dot),
                    },
                    other => other,
                };
                push(row, residual)
            };
            let (c, contact_row) = match contact {
                WheelContact::Vertical { .. } => (contact_frame(&b.rot, &b.w, radius, &Vec3::y(), true), None),
                WheelContact::Rolling { road } | WheelContact::Slipping { road, .. } => {
                    let rc = road_contact(&b.rot, &b.w, &b.r, &b.v, radius, road.map(|r| &roads[r]));
                    (rc.frame, Some((rc.e_n, rc.e_n_dot, rc.gap)))
                }
            };
            let (delta, delta_dot) = (c.delta, c.delta_dot);
            if let Some((e_n, e_n_dot, gap)) = contact_row {
                // The rim's lowest point on the road.
                push(Row::Contact { e: e_n, e_dot: e_n_dot, delta, delta_dot }, gap);
            }
            if let WheelContact::Slipping { .. } = contact {
                // No rolling rows: friction follows the contact's force.
                return n;
            }
            push(Row::Contact { e: c.e_long, e_dot: c.e_long_dot, delta, delta_dot }, 0.0);
            if contact != (WheelContact::Vertical { lateral: false }) {
                push(Row::Contact { e: c.e_lat, e_dot: c.e_lat_dot, delta, delta_dot }, 0.0);
            }
        }
    }
    n
}

/// A slipping wheel's friction per unit normal force (world), which acts
/// at the contact point; `None` for other constraints.
pub(crate) fn friction_per_normal_force(
    kind: &ConstraintKind,
    ground: &EndState,
    b: &EndState,
    roads: &[Surface],
) -> Option<Vec3> {
    let ConstraintKind::Wheel { radius, contact: WheelContact::Slipping { law, road } } = *kind else {
        return None;
    };
    // In the ground's coordinates, as the wheel's rows.
    let b = &b.seen_from_ground(ground);
    let c = road_contact(&b.rot, &b.w, &b.r, &b.v, radius, road.map(|r| &roads[r])).frame;
    // The slipping wheels' lateral direction is the rolling ones' turned round.
    let e_lat = -c.e_lat;
    let v_contact = b.v + b.w.cross(&c.delta);
    let (v_long, v_lat) = (v_contact.dot(&c.e_long), v_contact.dot(&e_lat));
    let v_roll = radius * b.w.dot(&c.e_axis);
    let (mu_long, mu_lat) = law.coefficients(v_long, v_lat, v_roll);
    Some(ground.rot.tr_mul(&-(c.e_long * mu_long + e_lat * mu_lat)))
}

impl System {
    /// Whether a slipping wheel's friction follows a constraint force.
    pub(crate) fn has_friction(&self) -> bool {
        self.constraints.iter().any(|c| c.kind.slip_law().is_some())
    }

    /// World kinematics of a constraint end from the workspace's links.
    pub(crate) fn end_state(&self, ws: &Workspace, att: &Attachment) -> EndState {
        let Anchor::Link(k) = att.anchor else { return EndState::default() };
        let lw = &ws.links[k];
        let p = att.pose.trans;
        let (v, a) = if k == GROUND { (Motion::ZERO, Motion::ZERO) } else { (lw.v, ws.bias_acc[k]) };
        let w = lw.rot.tr_mul(&v.ang);
        let v_point = v.lin + v.ang.cross(&p);
        // Classical acceleration of the point: a_lin + alpha x p + w x v_point (link coordinates).
        let a_point = a.lin + a.ang.cross(&p) + v.ang.cross(&v_point);
        EndState {
            link: k,
            r: lw.pos + lw.rot.tr_mul(&p),
            rot: att.pose.rot * lw.rot,
            w,
            v: lw.rot.tr_mul(&v_point),
            alpha: lw.rot.tr_mul(&a.ang),
            a: lw.rot.tr_mul(&a_point),
        }
    }

    /// Residuals, and if `with_jacobian` the Jacobian rows and the
    /// velocity-product terms `Jdot u`, of every constraint at positions `q`.
    pub(crate) fn constraint_terms(&self, ws: &mut Workspace, q: &[f64], with_jacobian: bool) {
        let nv = self.states.nv;
        let mut buffer = [(Row::Distance, 0.0); 6];
        if with_jacobian {
            ws.jac.fill(0.0);
            ws.jac_force.fill(0.0);
        }
        for c in &self.constraints {
            let (a, b) = (self.end_state(ws, &c.a), self.end_state(ws, &c.b));
            let count = rows(&c.kind, &a, &b, &self.roads, &mut buffer);
            let friction = if with_jacobian { friction_per_normal_force(&c.kind, &a, &b, &self.roads) } else { None };
            let r_ab = b.r - a.r;
            let w_rel = b.w - a.w;
            let dv = b.v - a.v;
            let dr = dv - a.w.cross(&r_ab);
            for (i, &(row, residual)) in buffer[..count].iter().enumerate() {
                ws.residual[c.row + i] = residual;
                if !with_jacobian {
                    continue;
                }
                ws.bias[c.row + i] = match row {
                    Row::Rotation(d) => {
                        let mut bias = d.dot(&(a.rot * (b.alpha - a.alpha - a.w.cross(&w_rel))));
                        if let ConstraintKind::Locks { rotation: RotationLock::Universal { n_a, n_b }, .. } = c.kind {
                            // The row's direction turns with frame B.
                            let w_rel_a = a.rot * w_rel;
                            let n_b_in_a = (b.rot * a.rot.transpose()).tr_mul(&n_b);
                            bias += w_rel_a.cross(&n_b_in_a).cross(&n_a).dot(&w_rel_a);
                        }
                        bias
                    }
                    Row::Translation(d) => {
                        let ddr = b.a - a.a - a.alpha.cross(&r_ab) - a.w.cross(&dv);
                        d.dot(&(a.rot * (ddr - a.w.cross(&dr))))
                    }
                    Row::Distance => {
                        let length = r_ab.norm().max(f64::MIN_POSITIVE);
                        let e = r_ab / length;
                        e.dot(&(b.a - a.a)) + (dv.norm_squared() - e.dot(&dv).powi(2)) / length
                    }
                    // d/dt [e . (v_B + w_B x delta)] at zero joint accelerations (A is the ground).
                    Row::Contact { e, e_dot, delta, delta_dot } => {
                        e_dot.dot(&(b.v + b.w.cross(&delta)))
                            + e.dot(&(b.a + b.alpha.cross(&delta) + b.w.cross(&delta_dot)))
                    }
                };
                let row_start = (c.row + i) * nv;
                for (end, sign) in [(&b, 1.0), (&a, -1.0)] {
                    // Translations are of B's origin relative to A's frame: for A, at B's origin too.
                    let point = match row {
                        Row::Distance => end.r,
                        Row::Contact { delta, .. } => b.r + delta,
                        _ => b.r,
                    };
                    let mut k = end.link;
                    while k != GROUND {
                        let link = &self.links[k];
                        let lw = &ws.links[k];
                        for dof in 0..link.joint.nv() {
                            let s = self.subspace(ws, k, dof);
                            let dw = lw.rot.tr_mul(&s.ang);
                            let dv_point = lw.rot.tr_mul(&s.lin) + dw.cross(&(point - lw.pos));
                            let value = match row {
                                Row::Rotation(d) => d.dot(&(a.rot * dw)),
                                Row::Translation(d) => d.dot(&(a.rot * dv_point)),
                                Row::Distance => (r_ab / r_ab.norm().max(f64::MIN_POSITIVE)).dot(&dv_point),
                                Row::Contact { e, .. } => e.dot(&dv_point),
                            };
                            ws.jac[row_start + link.v_offset + dof] += sign * value;
                            if let Some(fr) = &friction {
                                // The generalised force of the friction per unit normal force.
                                ws.jac_force[row_start + link.v_offset + dof] += sign * fr.dot(&dv_point);
                            }
                        }
                        k = link.parent;
                    }
                }
            }
        }
        self.servo_terms(ws, with_jacobian);
        self.coupling_terms(ws, q, with_jacobian);
        if !self.frictions.is_empty() {
            self.friction_terms(ws, with_jacobian);
        }
    }

    /// The formulas of time of the servos' rows at `t`, with their first
    /// two derivatives (see [`Workspace::targets`]).
    pub(crate) fn servo_targets(&self, ws: &mut Workspace, t: f64) {
        for s in &self.servos {
            let row = self.constraints[s.constraint].row;
            for (i, target) in s.targets.iter().enumerate() {
                ws.targets[row + i] = target.jet(t);
            }
        }
    }

    /// A servo's rows keep `g(q) - p(t)`, accelerate as `p''`, and act
    /// through the efforts' generalised forces `B`, not through `J'`.
    fn servo_terms(&self, ws: &mut Workspace, with_jacobian: bool) {
        let nv = self.states.nv;
        for s in &self.servos {
            let row = self.constraints[s.constraint].row;
            for i in 0..s.targets.len() {
                let r = row + i;
                let [value, _, acceleration] = ws.targets[r];
                ws.residual[r] -= value;
                if with_jacobian {
                    ws.bias[r] -= acceleration;
                    let (jac, force) = (&ws.jac[r * nv..(r + 1) * nv], &mut ws.jac_force[r * nv..(r + 1) * nv]);
                    for ((g, j), b) in force.iter_mut().zip(jac).zip(&s.forces[i * nv..(i + 1) * nv]) {
                        *g = b - j;
                    }
                }
            }
        }
    }

    /// The rows of the couplings: `sum c_k q_k`, constant Jacobian, no
    /// velocity-product term.
    fn coupling_terms(&self, ws: &mut Workspace, q: &[f64], with_jacobian: bool) {
        let nv = self.states.nv;
        for c in &self.couplings {
            ws.residual[c.row] = c.constant + c.terms.iter().map(|&(iq, _, k)| k * q[iq]).sum::<f64>();
            if with_jacobian {
                ws.bias[c.row] = 0.0;
                for &(_, v, k) in &c.terms {
                    ws.jac[c.row * nv + v] += k;
                }
            }
        }
    }

    /// Link accelerations with every joint acceleration zero and no
    /// gravity: what `Jdot u` is made of.
    fn bias_accelerations(&self, ws: &mut Workspace) {
        ws.bias_acc[GROUND] = Motion::ZERO;
        for k in 1..self.links.len() {
            let parent = ws.bias_acc[self.links[k].parent];
            ws.bias_acc[k] = ws.links[k].x_up.apply_motion(&parent) + ws.links[k].c;
        }
    }

    /// The joint-space mass matrix `mass` (row-major, `nv x nv`) and the
    /// generalised forces `f = tau - C(q, u)` that leave every joint
    /// unaccelerated, at `(t, q, u)`, by the composite-rigid-body and
    /// recursive Newton-Euler algorithms (independent of the ABA). Without
    /// constraints the ABA's accelerations solve `M ud = f`; with them,
    /// `M ud = f + J' lambda` (see [`Workspace::constraint_jacobian`]).
    pub fn mass_matrix_and_bias(
        &self,
        ws: &mut Workspace,
        t: f64,
        q: &[f64],
        u: &[f64],
        mass: &mut [f64],
        f: &mut [f64],
    ) -> Result<(), DynamicsError> {
        self.motion_and_loads(ws, t, q, u)?;
        self.bias_forces(ws, f);
        self.mass_matrix(ws, mass);
        Ok(())
    }

    /// The joint-space mass matrix by the composite-rigid-body algorithm,
    /// into `mass` (from the transforms of the last kinematics pass).
    fn mass_matrix(&self, ws: &mut Workspace, mass: &mut [f64]) {
        let nv = self.states.nv;
        mass.fill(0.0);
        for (k, link) in self.links.iter().enumerate() {
            ws.composite[k] = link.inertia;
        }
        for k in (1..self.links.len()).rev() {
            let link = &self.links[k];
            for dof in 0..link.joint.nv() {
                let mut f: Force = ws.composite[k].apply(&self.subspace(ws, k, dof));
                let col = link.v_offset + dof;
                let mut j = k;
                loop {
                    let lj = &self.links[j];
                    for d in 0..lj.joint.nv() {
                        let value = self.subspace(ws, j, d).dot(&f);
                        mass[(lj.v_offset + d) * nv + col] = value;
                        mass[col * nv + lj.v_offset + d] = value;
                    }
                    if lj.parent == GROUND {
                        break;
                    }
                    f = ws.links[j].x_up.inv_apply_force(&f);
                    j = lj.parent;
                }
            }
            if link.armature != 0.0 {
                mass[link.v_offset * nv + link.v_offset] += link.armature;
            }
            if link.parent != GROUND {
                let c: RigidInertia = ws.composite[k].expressed_in_parent(&ws.links[k].x_up);
                ws.composite[link.parent] += c;
            }
        }
        // Point masses of line forces: `m J_m' J_m`, with the mass's
        // velocity Jacobian `J_m = (1 - h) J_a + h J_b`.
        for lm in &self.line_masses {
            let (m, h) = (lm.m, lm.h);
            let ends = [(self.end_point(ws, &lm.a), 1.0 - h), (self.end_point(ws, &lm.b), h)];
            for &((ki, ri), wi) in &ends {
                self.point_columns(ws, ki, &ri, |i, ci| {
                    for &((kj, rj), wj) in &ends {
                        self.point_columns(ws, kj, &rj, |j, cj| mass[i * nv + j] += m * wi * wj * ci.dot(&cj));
                    }
                });
            }
        }
    }

    /// The link and world position of an attachment's origin (the ground's
    /// for a massless group, which assembly keeps away from line masses).
    fn end_point(&self, ws: &Workspace, att: &Attachment) -> (usize, Vec3) {
        let Anchor::Link(k) = att.anchor else { return (GROUND, Vec3::zeros()) };
        let lw = &ws.links[k];
        (k, lw.pos + lw.rot.tr_mul(&att.pose.trans))
    }

    /// Calls `each(i, column)` for every velocity coordinate `i` that moves
    /// the point at `point` (world) fixed to link `k`: `column` is the
    /// point's world velocity per unit `u_i`.
    fn point_columns(&self, ws: &Workspace, mut k: usize, point: &Vec3, mut each: impl FnMut(usize, Vec3)) {
        while k != GROUND {
            let link = &self.links[k];
            let lw = &ws.links[k];
            for dof in 0..link.joint.nv() {
                let s = self.subspace(ws, k, dof);
                let dw = lw.rot.tr_mul(&s.ang);
                each(link.v_offset + dof, lw.rot.tr_mul(&s.lin) + dw.cross(&(point - lw.pos)));
            }
            k = link.parent;
        }
    }

    /// The world acceleration of the point at `point` (world) fixed to link
    /// `k`, from the links' spatial accelerations in the workspace (in the
    /// dynamics they include the ground's acceleration `-uniform_gravity`).
    fn point_acceleration(&self, ws: &Workspace, k: usize, point: &Vec3) -> Vec3 {
        let lw = &ws.links[k];
        let p = lw.rot * (point - lw.pos);
        let (v, a) = (lw.v, lw.a);
        let v_point = v.lin + v.ang.cross(&p);
        lw.rot.tr_mul(&(a.lin + a.ang.cross(&p) + v.ang.cross(&v_point)))
    }

    /// The force (world) that a line force's point mass needs to move as
    /// its ends do against gravity, `m (a_m - g(r_m))`, from the links'
    /// accelerations in the workspace: relative to a frame falling with
    /// the uniform gravity (`falling`, as the dynamics has them) or true
    /// accelerations (as outputs have them).
    fn line_mass_force(&self, ws: &Workspace, lm: &LineMass, falling: bool) -> Vec3 {
        let LineMass { m, h, point_gravity, .. } = *lm;
        let ((ka, ra), (kb, rb)) = (self.end_point(ws, &lm.a), self.end_point(ws, &lm.b));
        let r_m = ra * (1.0 - h) + rb * h;
        let a_m = self.point_acceleration(ws, ka, &ra) * (1.0 - h) + self.point_acceleration(ws, kb, &rb) * h;
        let field = if point_gravity { crate::math::point_gravity(self.mu, &r_m) } else { self.uniform_gravity };
        // Falling links' accelerations hold `- uniform_gravity` already.
        let field = if falling { field - self.uniform_gravity } else { field };
        (a_m - field) * m
    }

    /// The joint accelerations under the constraints, with the multipliers
    /// kept in `ws.lambda` and the link accelerations updated. Solves
    /// `M ud = f + J' lambda`, `J ud = gamma` through the augmented
    /// `M_a = M + w J' J`, positive definite whenever the constraints
    /// determine what has no mass (the massless links of a loop of
    /// joints): `M_a ud = f + J' lambda'` with `lambda' = lambda + w gamma`.
    pub(crate) fn constrained_accelerations(
        &self,
        ws: &mut Workspace,
        q: &[f64],
        ud: &mut [f64],
    ) -> Result<(), DynamicsError> {
        let (nv, m) = (self.states.nv, self.constraint_rows);
        self.bias_accelerations(ws);
        self.constraint_terms(ws, q, true);
        self.bias_forces(ws, ud);
        // Driven coordinates: their imposed accelerations are already in
        // the velocity-product terms (so in `f` and `Jdot u`); what is
        // solved for is the rest, zero for them.
        for (i, _) in self.free_coordinates.iter().enumerate().filter(|(_, free)| !**free) {
            ud[i] = 0.0;
            for r in 0..m {
                ws.jac[r * nv + i] = 0.0;
                ws.jac_force[r * nv + i] = 0.0;
            }
        }
        let w = self.augmented_mass_matrix(ws);
        // A slipping wheel's friction is its normal force times a
        // coefficient, and a servo's multipliers act through the sources
        // they drive: generalised forces `G' lambda` beside `J' lambda`.
        // Then `M_a ud = f - w G' gamma + (J + G)' lambda'`, and the
        // multipliers solve an unsymmetric system.
        let friction = self.has_friction() || !self.servos.is_empty();
        if friction {
            for r in 0..m {
                // gamma = -Jdot u = -bias.
                let wg = w * ws.bias[r];
                for (udi, g) in ud.iter_mut().zip(&ws.jac_force[r * nv..(r + 1) * nv]) {
                    *udi += wg * g;
                }
            }
        }
        // A rotor's spin coupled to a light carrier (Modelica's Rotor1D) can
        // make M indefinite, though regular: LU solves it when Cholesky cannot.
        let definite = cholesky(&mut ws.mass, nv);
        if !definite {
            self.augmented_mass_matrix(ws);
            if !lu(&mut ws.mass, nv, &mut ws.pivots) {
                return Err(DynamicsError::SingularMotion { dof: self.weakest_dof(ws) });
            }
        }
        let solve = |ws: &mut Workspace, b: &mut [f64]| {
            if definite {
                cholesky_solve(&ws.mass, nv, b)
            } else {
                lu_solve(&ws.mass, nv, &ws.pivots, b, &mut ws.work)
            }
        };
        // ud0 = M_a^-1 f, Y' = (M_a^-1 (J + G)')'.
        solve(ws, ud);
        let mut y_rows = std::mem::take(&mut ws.y_rows);
        y_rows.copy_from_slice(&ws.jac);
        if friction {
            for (y, g) in y_rows.iter_mut().zip(&ws.jac_force) {
                *y += g;
            }
        }
        for r in 0..m {
            solve(ws, &mut y_rows[r * nv..(r + 1) * nv]);
        }
        ws.y_rows = y_rows;
        for r in 0..m {
            let columns = if friction { m } else { r + 1 };
            for s in 0..columns {
                let v: f64 = (0..nv).map(|i| ws.jac[r * nv + i] * ws.y_rows[s * nv + i]).sum();
                ws.schur[r * m + s] = v;
                if !friction {
                    ws.schur[s * m + r] = v;
                }
            }
            let j_ud: f64 = (0..nv).map(|i| ws.jac[r * nv + i] * ud[i]).sum();
            ws.lambda[r] = -ws.bias[r] - j_ud;
        }
        if friction {
            if !lu(&mut ws.schur, m, &mut ws.perm) {
                return Err(DynamicsError::ContactIndeterminate { link: self.massless_link(ws) });
            }
            lu_solve(&ws.schur, m, &ws.perm, &mut ws.lambda, &mut ws.work);
        } else {
            let rank = ldlt_pivoted(&mut ws.schur, m, &mut ws.perm, RANK_TOLERANCE);
            ldlt_solve(&ws.schur, m, &ws.perm, rank, &mut ws.lambda, &mut ws.work);
        }
        for r in 0..m {
            let l = ws.lambda[r];
            for (udi, yi) in ud.iter_mut().zip(&ws.y_rows[r * nv..(r + 1) * nv]) {
                *udi += yi * l;
            }
            // The physical multiplier: lambda = lambda' - w gamma, gamma = -Jdot u.
            ws.lambda[r] = l + w * ws.bias[r];
        }
        // A servo's efforts are its multipliers: the signals its sources read.
        for s in &self.servos {
            let row = self.constraints[s.constraint].row;
            for (i, &slot) in s.slots.iter().enumerate() {
                ws.signals[slot] = ws.lambda[row + i];
            }
        }
        // What the couplings apply to their coordinates counts as the joints' drive torques.
        for c in &self.couplings {
            for &(_, v, k) in &c.terms {
                ws.tau[v] += k * ws.lambda[c.row];
            }
        }
        // Link accelerations with the constrained joint accelerations.
        ws.links[GROUND].a = Motion::new(Vec3::zeros(), -self.uniform_gravity);
        for k in 1..self.links.len() {
            let link = &self.links[k];
            let mut a = ws.links[k].x_up.apply_motion(&ws.links[link.parent].a) + ws.links[k].c;
            for d in 0..link.joint.nv() {
                if link.driven & (1 << d) == 0 {
                    a += self.subspace(ws, k, d) * ud[link.v_offset + d];
                } else {
                    ud[link.v_offset + d] = ws.imposed[link.v_offset + d];
                }
            }
            ws.links[k].a = a;
        }
        Ok(())
    }

    /// `M + w J'J` into `ws.mass`; returns `w` (from [`Self::augmentation`]).
    fn augmented_mass_matrix(&self, ws: &mut Workspace) -> f64 {
        let (nv, m) = (self.states.nv, self.constraint_rows);
        let mut mass = std::mem::take(&mut ws.mass);
        self.mass_matrix(ws, &mut mass);
        ws.mass = mass;
        let w = self.augmentation(ws);
        for i in 0..nv {
            for j in 0..nv {
                let jtj: f64 = (0..m).map(|r| ws.jac[r * nv + i] * ws.jac[r * nv + j]).sum();
                ws.mass[i * nv + j] += w * jtj;
            }
        }
        // A driven coordinate is not solved for: a unit row and column.
        for (i, _) in self.free_coordinates.iter().enumerate().filter(|(_, free)| !**free) {
            for j in 0..nv {
                ws.mass[i * nv + j] = 0.0;
                ws.mass[j * nv + i] = 0.0;
            }
            ws.mass[i * nv + i] = w;
        }
        w
    }

    /// `f = tau - C`: the generalised forces that leave the joints
    /// unaccelerated, by the recursive Newton-Euler algorithm with gravity
    /// as an acceleration of the ground (into `f`).
    fn bias_forces(&self, ws: &mut Workspace, f: &mut [f64]) {
        ws.links[GROUND].a = Motion::new(Vec3::zeros(), -self.uniform_gravity);
        for k in 1..self.links.len() {
            let parent = ws.links[self.links[k].parent].a;
            let a = ws.links[k].x_up.apply_motion(&parent) + ws.links[k].c;
            ws.links[k].a = a;
            // pa already holds v x* I v minus the external forces.
            ws.links[k].pa += self.links[k].inertia.apply(&a);
        }
        for k in (1..self.links.len()).rev() {
            let link = &self.links[k];
            let force = ws.links[k].pa;
            for d in 0..link.joint.nv() {
                f[link.v_offset + d] = ws.tau[link.v_offset + d] - self.subspace(ws, k, d).dot(&force);
            }
            if link.parent != GROUND {
                let up = ws.links[k].x_up.inv_apply_force(&force);
                ws.links[link.parent].pa += up;
            }
        }
        // Point masses of line forces: `- J_m' m (a_m - g)` with the
        // accelerations of zero joint accelerations.
        for lm in &self.line_masses {
            let force = self.line_mass_force(ws, lm, true);
            for (end, w) in [(&lm.a, 1.0 - lm.h), (&lm.b, lm.h)] {
                let (k, r) = self.end_point(ws, end);
                self.point_columns(ws, k, &r, |i, column| f[i] -= w * column.dot(&force));
            }
        }
    }

    /// Column `d` of link `k`'s motion subspace (link coordinates).
    #[inline]
    fn subspace(&self, ws: &Workspace, k: usize, d: usize) -> Motion {
        if self.links[k].joint.nv() == 1 {
            ws.links[k].s
        } else {
            ws.multi[ws.multi_index[k]].s[d]
        }
    }

    /// The weight of `J' J` in the augmented mass matrix: the mass
    /// matrix's scale, so that the two are of similar size.
    fn augmentation(&self, ws: &Workspace) -> f64 {
        let nv = self.states.nv;
        let trace: f64 = (0..nv).map(|i| ws.mass[i * nv + i]).sum();
        if trace > 0.0 {
            trace / nv as f64
        } else {
            1.0
        }
    }

    /// The link of the coordinate with the least inertia, for a message.
    fn massless_link(&self, ws: &Workspace) -> usize {
        let i = self.weakest_dof(ws);
        self.links.iter().position(|l| l.v_offset <= i && i < l.v_offset + l.joint.nv()).unwrap_or(1)
    }

    /// The velocity coordinate with the least inertia (the smallest diagonal of `ws.mass`).
    fn weakest_dof(&self, ws: &Workspace) -> usize {
        let nv = self.states.nv;
        (0..nv).min_by(|&a, &b| ws.mass[a * nv + a].total_cmp(&ws.mass[b * nv + b])).unwrap_or(0)
    }

    /// Moves `y` onto the constraints: positions by Newton steps of least
    /// norm, then velocities by removing their constraint-violating part.
    /// Returns whether anything changed.
    ///
    /// With `impact` (at an event, where a friction element locks or a
    /// `reinit` moved the state, the velocities may be far off), the
    /// velocity step is a plastic impact: the change of least kinetic
    /// energy, which keeps the momentum no constraint acts on (a one-way
    /// clutch catching its load shares the momentum, as colliding bodies
    /// do); between events, a drift of the size of the tolerances, the
    /// least-norm step.
    pub fn project(&self, ws: &mut Workspace, t: f64, y: &mut [f64], impact: bool) -> Result<bool, DynamicsError> {
        if self.constraint_rows == 0 {
            return Ok(false);
        }
        let (nq, nv) = (self.states.nq, self.states.nv);
        let mut changed = false;
        self.servo_targets(ws, t);
        let free = if self.drives.is_empty() {
            None
        } else {
            // Driven coordinates are exact and stay so: only the others move.
            self.impose_drives(ws, t, y);
            changed = true;
            Some(self.free_coordinates.as_slice())
        };
        let mut closed = false;
        for _ in 0..PROJECTION_ITERATIONS {
            self.constraint_state(ws, y)?;
            if ws.residual.iter().all(|r| r.abs() <= PROJECT_ABOVE) {
                closed = true;
                break;
            }
            self.least_norm_step(ws, free, true);
            self.retract(y, ws);
            changed = true;
        }
        if !closed {
            // A loop that cannot close stops the run rather than open.
            self.constraint_state(ws, y)?;
            let worst = self
                .constraints
                .iter()
                .enumerate()
                .map(|(k, c)| (k, ws.residual[c.row..c.row + c.rows].iter().fold(0.0f64, |m, r| m.max(r.abs()))));
            if let Some((constraint, residual)) =
                worst.filter(|&(_, r)| r > LOOP_OPEN).max_by(|a, b| a.1.total_cmp(&b.1))
            {
                return Err(DynamicsError::LoopOpen { constraint, residual });
            }
        }
        self.velocity_residual(ws, y)?;
        if ws.lambda.iter().any(|v| *v != 0.0) {
            if !(impact && self.impact_step(ws, free)) {
                self.least_norm_step(ws, free, false);
            }
            for i in 0..nv {
                y[nq + i] += ws.du[i];
            }
            changed = true;
        }
        Ok(changed)
    }

    /// Kinematics, constraint residuals and Jacobian at the state `y`.
    pub(crate) fn constraint_state(&self, ws: &mut Workspace, y: &[f64]) -> Result<(), DynamicsError> {
        let (q, u) = y.split_at(self.states.nq);
        self.kinematics_and_bias(ws, q, u)?;
        ws.bias_acc.fill(Motion::ZERO);
        self.constraint_terms(ws, q, true);
        Ok(())
    }

    /// The constraint velocities `J u` at the state `y`, into `ws.lambda`.
    pub(crate) fn velocity_residual(&self, ws: &mut Workspace, y: &[f64]) -> Result<(), DynamicsError> {
        self.constraint_state(ws, y)?;
        let (nq, nv, m) = (self.states.nq, self.states.nv, self.constraint_rows);
        for r in 0..m {
            ws.lambda[r] = (0..nv).map(|i| ws.jac[r * nv + i] * y[nq + i]).sum::<f64>() - ws.targets[r][1];
        }
        Ok(())
    }

    /// The least-norm step `du = -J' (J J')^+ e` in the velocity
    /// coordinates marked `free` (all if `None`) that removes the position
    /// residuals (`positions`) or the velocity residuals in `ws.lambda`.
    pub(crate) fn least_norm_step(&self, ws: &mut Workspace, free: Option<&[bool]>, positions: bool) {
        let (nv, m) = (self.states.nv, self.constraint_rows);
        if nv == 0 {
            // Nothing can move (a constraint on grounded frames): the
            // residuals stay, and one that cannot close is reported as such.
            return;
        }
        if let Some(free) = free {
            for row in ws.jac[..m * nv].chunks_exact_mut(nv) {
                for (x, &is_free) in row.iter_mut().zip(free) {
                    if !is_free {
                        *x = 0.0;
                    }
                }
            }
        }
        if positions {
            ws.lambda.copy_from_slice(&ws.residual);
            // Rows on velocities only say nothing about positions.
            for c in &self.constraints {
                for i in (0..c.rows).filter(|&i| c.kind.is_velocity_row(i)) {
                    ws.jac[(c.row + i) * nv..(c.row + i + 1) * nv].fill(0.0);
                    ws.lambda[c.row + i] = 0.0;
                }
            }
        }
        for r in 0..m {
            for s in 0..=r {
                let v: f64 = (0..nv).map(|i| ws.jac[r * nv + i] * ws.jac[s * nv + i]).sum();
                ws.schur[r * m + s] = v;
                ws.schur[s * m + r] = v;
            }
        }
        let rank = ldlt_pivoted(&mut ws.schur, m, &mut ws.perm, RANK_TOLERANCE);
        ldlt_solve(&ws.schur, m, &ws.perm, rank, &mut ws.lambda, &mut ws.work);
        for i in 0..nv {
            ws.du[i] = -(0..m).map(|r| ws.jac[r * nv + i] * ws.lambda[r]).sum::<f64>();
        }
    }

    /// The velocity step of a plastic impact, `du = -M_a^-1 J' (J M_a^-1
    /// J')^+ e` with the velocity residuals `e` in `ws.lambda` (at the
    /// kinematics of the last pass): the least kinetic energy `du' M du`
    /// among the steps that remove them (`M_a = M + w J'J` gives the same
    /// step, and is definite where the constraints hold what has no
    /// mass). False, and nothing done, where `M_a` is not definite.
    fn impact_step(&self, ws: &mut Workspace, free: Option<&[bool]>) -> bool {
        let (nv, m) = (self.states.nv, self.constraint_rows);
        if let Some(free) = free {
            for row in ws.jac[..m * nv].chunks_exact_mut(nv) {
                for (x, &is_free) in row.iter_mut().zip(free) {
                    if !is_free {
                        *x = 0.0;
                    }
                }
            }
        }
        self.augmented_mass_matrix(ws);
        if !cholesky(&mut ws.mass, nv) {
            return false;
        }
        // Y' = M_a^-1 J', then the Schur complement J Y'.
        let mut y_rows = std::mem::take(&mut ws.y_rows);
        y_rows[..m * nv].copy_from_slice(&ws.jac[..m * nv]);
        for r in 0..m {
            cholesky_solve(&ws.mass, nv, &mut y_rows[r * nv..(r + 1) * nv]);
        }
        for r in 0..m {
            for s in 0..=r {
                let v: f64 = (0..nv).map(|i| ws.jac[r * nv + i] * y_rows[s * nv + i]).sum();
                ws.schur[r * m + s] = v;
                ws.schur[s * m + r] = v;
            }
        }
        let rank = ldlt_pivoted(&mut ws.schur, m, &mut ws.perm, RANK_TOLERANCE);
        ldlt_solve(&ws.schur, m, &ws.perm, rank, &mut ws.lambda, &mut ws.work);
        for i in 0..nv {
            ws.du[i] = -(0..m).map(|r| y_rows[r * nv + i] * ws.lambda[r]).sum::<f64>();
        }
        ws.y_rows = y_rows;
        true
    }

    /// `q <- q (+) du`: moves the positions by the velocity-coordinate step
    /// `ws.du` (the linear part of each joint's `dq/dt`).
    pub(crate) fn retract(&self, y: &mut [f64], ws: &mut Workspace) {
        for link in &self.links[1..] {
            let (nq, nv) = (link.joint.nq(), link.joint.nv());
            let q = &y[link.q_offset..link.q_offset + nq];
            let mut with = [0.0; 7];
            let mut without = [0.0; 7];
            link.joint.qdot(q, &ws.du[link.v_offset..link.v_offset + nv], &mut with[..nq]);
            link.joint.qdot(q, &[0.0; 6][..nv], &mut without[..nq]);
            for i in 0..nq {
                y[link.q_offset + i] += with[i] - without[i];
            }
        }
    }

    /// Velocity coordinates that neither a drive nor a constraint decides,
    /// at the workspace's state.
    pub(crate) fn free_degrees_of_freedom(&self, ws: &mut Workspace) -> usize {
        let (nv, m) = (self.states.nv, self.constraint_rows);
        for (i, _) in self.free_coordinates.iter().enumerate().filter(|(_, free)| !**free) {
            for r in 0..m {
                ws.jac[r * nv + i] = 0.0;
            }
        }
        self.free_coordinates.iter().filter(|free| **free).count() - self.constraint_rank(ws)
    }

    /// How close the loops are to a singular configuration at the state
    /// `y`: the constraint Jacobian's singular value at the rank the model
    /// was assembled with, as a fraction of its largest, and the
    /// constraint that its direction loads most. A dead point drives the
    /// fraction to zero. `None` without constraints. (For diagnosis only:
    /// it allocates.)
    pub(crate) fn loop_singularity(
        &self,
        ws: &mut Workspace,
        y: &[f64],
    ) -> Result<Option<(usize, f64)>, DynamicsError> {
        let (nv, m) = (self.states.nv, self.constraint_rows);
        let free: Vec<usize> = (0..nv).filter(|&i| self.free_coordinates.get(i).copied().unwrap_or(true)).collect();
        let rank = free.len().saturating_sub(self.dof);
        if m == 0 || rank == 0 || self.constraints.is_empty() {
            return Ok(None);
        }
        self.constraint_state(ws, y)?;
        let jac = nalgebra::DMatrix::from_fn(m, free.len(), |r, k| ws.jac[r * nv + free[k]]);
        let svd = jac.svd(true, false);
        let mut order: Vec<usize> = (0..svd.singular_values.len()).collect();
        order.sort_by(|&a, &b| svd.singular_values[b].total_cmp(&svd.singular_values[a]));
        let (Some(&largest), Some(&weakest)) = (order.first(), order.get(rank - 1)) else { return Ok(None) };
        let fraction = svd.singular_values[weakest] / svd.singular_values[largest].max(f64::MIN_POSITIVE);
        let Some(u) = svd.u.as_ref() else { return Ok(None) };
        let loaded = |c: &Constraint| (c.row..c.row + c.rows).map(|r| u[(r, weakest)].powi(2)).sum::<f64>();
        let constraint = (0..self.constraints.len())
            .max_by(|&a, &b| loaded(&self.constraints[a]).total_cmp(&loaded(&self.constraints[b])))
            .unwrap_or(0);
        Ok(Some((constraint, fraction)))
    }

    /// Rank of the constraint Jacobian at the workspace's state.
    pub(crate) fn constraint_rank(&self, ws: &mut Workspace) -> usize {
        let (nv, m) = (self.states.nv, self.constraint_rows);
        for r in 0..m {
            for s in 0..=r {
                let v: f64 = (0..nv).map(|i| ws.jac[r * nv + i] * ws.jac[s * nv + i]).sum();
                ws.schur[r * m + s] = v;
                ws.schur[s * m + r] = v;
            }
        }
        ldlt_pivoted(&mut ws.schur, m, &mut ws.perm, RANK_TOLERANCE)
    }

    /// The wrenches (world force and moment about each end's origin) that
    /// constraint `c` applies to its ends, from the multipliers.
    pub(crate) fn constraint_wrenches(&self, ws: &Workspace, c: &Constraint) -> ((Vec3, Vec3), (Vec3, Vec3)) {
        let (a, b) = (self.end_state(ws, &c.a), self.end_state(ws, &c.b));
        let mut buffer = [(Row::Distance, 0.0); 6];
        let count = rows(&c.kind, &a, &b, &self.roads, &mut buffer);
        let (mut force, mut torque) = (Vec3::zeros(), Vec3::zeros());
        for (i, &(row, _)) in buffer[..count].iter().enumerate() {
            let l = ws.lambda[c.row + i];
            match row {
                Row::Rotation(d) => torque += a.rot.tr_mul(&d) * l,
                Row::Translation(d) => force += a.rot.tr_mul(&d) * l,
                Row::Distance => force += (b.r - a.r) / (b.r - a.r).norm().max(f64::MIN_POSITIVE) * l,
                // A force at the contact point: its moment about B's origin.
                Row::Contact { e, delta, .. } => {
                    let mut f = e * l;
                    if let Some(fr) = friction_per_normal_force(&c.kind, &a, &b, &self.roads) {
                        f += fr * l;
                    }
                    force += f;
                    torque += delta.cross(&f);
                }
            }
        }
        let r_ab = b.r - a.r;
        let on_b = (force, torque);
        let on_a = match c.kind {
            ConstraintKind::Distance { .. } => (-force, Vec3::zeros()),
            _ => (-force, -torque - r_ab.cross(&force)),
        };
        (on_a, on_b)
    }
}

impl System {
    /// The forces (world, at each end's origin, no moments) that a line
    /// force's point mass applies to its ends: its inertia and weight,
    /// shared in the ratio of its place on the line. Outputs call this with
    /// the links' true accelerations (gravity added back).
    pub(crate) fn line_mass_wrenches(&self, ws: &Workspace, lm: &LineMass) -> ((Vec3, Vec3), (Vec3, Vec3)) {
        let force = self.line_mass_force(ws, lm, false);
        ((-force * (1.0 - lm.h), Vec3::zeros()), (-force * lm.h, Vec3::zeros()))
    }
}
