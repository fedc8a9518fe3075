//! Analytic derivatives of the forward dynamics of kinematic trees: the
//! derivatives of the recursive Newton-Euler algorithm (RNEA) of Carpentier
//! and Mansard ("Analytical Derivatives of Rigid Body Dynamics Algorithms",
//! RSS 2018), then `d ud = -M^-1 d RNEA` with `M` from the
//! composite-rigid-body algorithm.
//!
//! Everything here is in world coordinates, at the world origin: a link's
//! velocity `v`, its acceleration `a` (relative to a frame falling with the
//! uniform gravity, as in the articulated-body pass), the joint columns `S`,
//! the inertias. The reason is that moving a joint coordinate `q_j` moves
//! the whole subtree beyond joint `j` rigidly by the twist `S_j dq_j`, and a
//! world quantity carried along by a rigid motion `T` changes by `T x m`
//! (motions), `T x* f` (forces) and `T x* I - I T x` (inertias). The
//! generalised force `tau_i = S_i . F_i` (with `F_i` the force the joint
//! transmits) is a power, unchanged when both factors are carried by the
//! same motion; so only what deviates from that rigid transport enters its
//! derivative, and the deviations are the same for every link of the
//! subtree (up to one term that the inertia's variation takes in).
//!
//! With `p` the parent of joint `j` and `T = S_j` (one column):
//! - velocity: `dv_k/dq_j = T x v_k + dV_j` for every link `k` beyond `j`,
//!   with `dV_j = v_p x T` (the joint's own axis is carried, the parent is not);
//! - acceleration: `da_k/dq_j = T x a_k + dA_j + dV_j x v_k`, with
//!   `dA_j = a_p x T + v_p x dV_j`;
//! - the link's force `f_k = I_k a_k + v_k x* I_k v_k` then deviates from
//!   the transport by `I_k dA_j + B_k dV_j`, where
//!   `B_k = (v_k x*) I_k - I_k (v_k x) + (. x* h_k)` and `h_k = I_k v_k`;
//! - velocity derivatives: `dv_k/du_j = T`, `da_k/du_j = dAv_j - v_k x T`
//!   with `dAv_j = v_p x T + v_j x T`, so `df_k/du_j = I_k dAv_j + B_k T`.
//!
//! Summed over a subtree these give, with the composite inertia `Y_i`, the
//! composite `Bc_i` and the composite force `F_i` of the subtree of `i`:
//! - `i` beyond `j` (or `i = j`): `dtau_i/dq_j = (Y_i S_i) . dA_j + (Bc_i' S_i) . dV_j`
//!   and `dtau_i/du_j = (Y_i S_i) . dAv_j + (Bc_i' S_i) . S_j`;
//! - `j` beyond `i`: `S_i` stays, so `dtau_i/dq_j = S_i . D_j` with
//!   `D_j = S_j x* F_j + Y_j dA_j + Bc_j dV_j`, and
//!   `dtau_i/du_j = S_i . (Y_j dAv_j + Bc_j S_j)`;
//! - zero between different branches.
//!
//! Each pair of a link and one of its ancestors costs a few 6-D dot
//! products, so the passes cost O(n d) for n links at depth d. `B_k` has a
//! simple form (worked out in [`link_terms`]): its right half is zero, so it
//! is kept as one 3x3 block and the linear momentum.
//!
//! Joints with several coordinates: a column that is fixed in the child
//! link (a rotation about a child axis, a translation along one) is carried
//! by the motion of every coordinate of its joint; a column fixed in the
//! parent (the translations of Free and Planar along the parent's axes,
//! which come first) is not. Their joints are treated as a parent-fixed
//! group moving an intermediate frame `b`, then a child-fixed group, and
//! `v_p, a_p` above become `v_b, a_b`.

use super::{DynamicsError, Workspace};
use crate::math::{Force, Mat3, Motion, RigidInertia, Transform, Vec3};
use crate::system::{JointModel, RotationCoordinates, System, GROUND};

/// Scratch and results of [`System::aba_derivatives`], allocated once for a
/// system (`nv` velocity coordinates). Matrices are `nv x nv`, row-major.
#[derive(Clone, Debug)]
pub struct DynamicsDerivatives {
    nv: usize,
    ddq_dq: Vec<f64>,
    ddq_dv: Vec<f64>,
    minv: Vec<f64>,
    mass: Vec<f64>,
    /// The RNEA's derivatives `dtau/dq`, `dtau/du`, and its value `tau`.
    dtau_dq: Vec<f64>,
    dtau_dv: Vec<f64>,
    tau: Vec<f64>,
    /// The Cholesky factor `L` of `M` (lower), then `L^-1` in place.
    factor: Vec<f64>,
    links: Vec<LinkTerms>,
    columns: Vec<ColumnTerms>,
    /// Per link, the bits of its joint's columns fixed in the parent.
    parent_fixed: Vec<u8>,
}

/// What the passes keep per link (world coordinates, at the world origin).
#[derive(Clone, Copy, Debug, Default)]
struct LinkTerms {
    /// World to link rotation and the link's origin in the world.
    rot: Mat3,
    pos: Vec3,
    v: Motion,
    a: Motion,
    /// The link's, then (after the backward pass reached it) its subtree's:
    /// inertia, force `I a + v x* I v`, the 3x3 block of `B`, linear momentum.
    inertia: RigidInertia,
    force: Force,
    b11: Mat3,
    momentum: Vec3,
}

/// What the passes keep per velocity coordinate (one column of a joint).
#[derive(Clone, Copy, Debug, Default)]
struct ColumnTerms {
    /// The column `S` in the world.
    s: Motion,
    /// `dV` (only its angular part matters: `B` ignores the linear part),
    /// `dA` and `dAv` of the module's notes.
    dv_ang: Vec3,
    da: Motion,
    dav: Motion,
    /// Row generators: `Y S` and the angular part of `Bc' S` (its linear part is zero).
    ys: Force,
    bs: Vec3,
    /// Column generators: `D` for positions and `Dv` for velocities.
    d: Force,
    dvel: Force,
}

impl DynamicsDerivatives {
    /// `d(ud_i)/d(q_j)` with `tau` held fixed (`nv x nv`, row-major). For a
    /// joint with a quaternion, column `j` of its rotation is the derivative
    /// along the rotation increment about the link's own axis `j` (the
    /// integral of the angular velocity coordinate `u_j`), not along a
    /// quaternion component; every other column is along `q_j` itself.
    pub fn ddq_dq(&self) -> &[f64] {
        &self.ddq_dq
    }

    /// `d(ud_i)/d(u_j)` with `tau` held fixed.
    pub fn ddq_dv(&self) -> &[f64] {
        &self.ddq_dv
    }

    /// `M(q)^-1`, which is `d(ud)/d(tau)`.
    pub fn minv(&self) -> &[f64] {
        &self.minv
    }

    /// The mass matrix `M(q)`, armature included.
    pub fn mass_matrix(&self) -> &[f64] {
        &self.mass
    }

    /// The inverse dynamics at the point of the last call:
    /// `M(q) ud + b(q, u)` (the RNEA), with `b` the velocity-product and
    /// uniform-gravity terms.
    pub fn inverse_dynamics(&self) -> &[f64] {
        &self.tau
    }

    /// `d RNEA/dq (q, u, ud)` of the last call (`-M ddq_dq`).
    pub fn dtau_dq(&self) -> &[f64] {
        &self.dtau_dq
    }

    /// `d RNEA/du (q, u, ud)` of the last call (`-M ddq_dv`).
    pub fn dtau_dv(&self) -> &[f64] {
        &self.dtau_dv
    }

    /// The number of velocity coordinates (the matrices' size).
    pub fn nv(&self) -> usize {
        self.nv
    }
}

/// Which columns of a supported joint are fixed in the parent (bits), or
/// why the joint is not supported.
fn parent_fixed_columns(joint: &JointModel, inverted: bool) -> Result<u8, &'static str> {
    let bits = match joint {
        JointModel::Revolute { .. } | JointModel::Prismatic { .. } => return Ok(0),
        JointModel::Translation | JointModel::Cylindrical { .. } => 0,
        JointModel::Spherical(RotationCoordinates::Quaternion { .. }) => 0,
        JointModel::Planar { .. } => 0b011,
        JointModel::Free(RotationCoordinates::Quaternion { .. }) => 0b000111,
        JointModel::Free(RotationCoordinates::Euler { .. }) => {
            return Err("a free joint with Euler angles (its motion subspace turns with the angles; use quaternions)")
        }
        JointModel::Spherical(RotationCoordinates::Euler { .. }) => {
            return Err("a spherical joint with Euler angles (its motion subspace turns with the angles; use quaternions)")
        }
        JointModel::Universal { .. } => {
            return Err("a universal joint (its first axis turns with the second angle)");
        }
    };
    if inverted {
        // Traversed from frame_b to frame_a, the parent- and child-fixed
        // columns trade places and come in the other order.
        return Err("a joint with several coordinates that the tree traverses from its frame_b to its frame_a");
    }
    Ok(bits)
}

impl System {
    /// Why the analytic derivatives ([`System::aba_derivatives`]) do not
    /// apply to this system, in words for a user; `None` when they do.
    pub fn derivatives_unsupported(&self) -> Option<String> {
        let state = |v: usize| self.states.names.get(self.states.nq + v).cloned().unwrap_or_default();
        if !self.constraints.is_empty() || !self.couplings.is_empty() || self.constraint_rows > 0 {
            return Some(format!(
                "the model has constraints ({} constraint rows: a kinematic loop, a constraint component or a gear \
                 between joints); the analytic derivatives handle open kinematic trees only",
                self.constraint_rows
            ));
        }
        if !self.line_masses.is_empty() {
            return Some(
                "the model has line forces with mass, whose point masses couple two links outside the tree's \
                 recursion; the analytic derivatives handle trees of rigid links only"
                    .into(),
            );
        }
        if !self.drives.is_empty() || self.links.iter().any(|l| l.driven != 0) {
            return Some(
                "the model has drives (motion imposed on joints by signals, or 1-D nodes without mass held by \
                 their balance); the analytic derivatives need every coordinate to follow the dynamics"
                    .into(),
            );
        }
        if !self.balances.is_empty() {
            return Some("the model has 1-D nodes without mass held by the balance of forces on them".into());
        }
        if !self.frictions.is_empty() {
            return Some(
                "the model has friction elements with stuck and sliding modes, whose forces are not smooth".into(),
            );
        }
        if self.states.nx > 0 {
            return Some(format!(
                "the model has {} states of its own equations besides the joints' (the derivatives cover the \
                 joints' positions and velocities only)",
                self.states.nx
            ));
        }
        if !self.massless.is_empty() {
            return Some("the model has frames without mass placed by the forces on them (massless groups)".into());
        }
        for link in &self.links[1..] {
            if let Err(why) = parent_fixed_columns(&link.joint, link.inverted) {
                return Some(format!("the joint whose velocity is `{}` is {why}", state(link.v_offset)));
            }
            if link.chart.is_some() {
                return Some(format!("the joint whose velocity is `{}` uses an Euler-angle chart", state(link.v_offset)));
            }
        }
        None
    }

    /// Scratch and results for [`System::aba_derivatives`], sized for this system.
    pub fn derivatives_work(&self) -> DynamicsDerivatives {
        let nv = self.states.nv;
        let n = self.links.len();
        DynamicsDerivatives {
            nv,
            ddq_dq: vec![0.0; nv * nv],
            ddq_dv: vec![0.0; nv * nv],
            minv: vec![0.0; nv * nv],
            mass: vec![0.0; nv * nv],
            dtau_dq: vec![0.0; nv * nv],
            dtau_dv: vec![0.0; nv * nv],
            tau: vec![0.0; nv],
            factor: vec![0.0; nv * nv],
            links: vec![LinkTerms { rot: Mat3::identity(), ..LinkTerms::default() }; n],
            columns: vec![ColumnTerms::default(); nv],
            parent_fixed: self.links.iter().map(|l| parent_fixed_columns(&l.joint, l.inverted).unwrap_or(0)).collect(),
        }
    }

    /// Derivatives of `ud = M(q)^-1 (tau - b(q, u))` at `(q, u)` with `tau`
    /// held fixed, where `b` holds the velocity-product and uniform-gravity
    /// terms and `ud` are the accelerations at that point (e.g. from `rhs`):
    /// `ddq_dq = -M^-1 dRNEA/dq(q, u, ud)`, `ddq_dv = -M^-1 dRNEA/du(q, u, ud)`;
    /// also `M`, `M^-1`, and the RNEA's value and derivatives. Forces of
    /// other elements (springs, dampers, point gravity, ...) are part of
    /// `tau` here: see [`System::generalized_forces`] for their value.
    ///
    /// For joints with a quaternion, the columns of `ddq_dq` of its rotation
    /// are along the rotation increment (see [`DynamicsDerivatives::ddq_dq`]).
    /// Valid where [`System::derivatives_unsupported`] is `None`. Allocates
    /// nothing; the passes cost O(n d) for n links at depth d, the dense
    /// solve O(nv^3).
    pub fn aba_derivatives(
        &self,
        ws: &mut Workspace,
        d: &mut DynamicsDerivatives,
        q: &[f64],
        u: &[f64],
        ud: &[f64],
    ) -> Result<(), DynamicsError> {
        debug_assert!(self.derivatives_unsupported().is_none(), "{:?}", self.derivatives_unsupported());
        let nv = self.states.nv;
        assert!(d.nv == nv && u.len() == nv && ud.len() == nv && q.len() == self.states.nq);
        self.kinematics_and_bias(ws, q, u)?;
        self.forward_terms(ws, d, u, ud);
        self.backward_terms(d);
        let n = nv;
        cholesky(&d.mass, &mut d.factor, n).map_err(|col| DynamicsError::SingularInertia { link: self.link_of(col) })?;
        invert_from_cholesky(&mut d.factor, &mut d.minv, n);
        multiply_negated(&d.minv, &d.dtau_dq, &mut d.ddq_dq, n);
        multiply_negated(&d.minv, &d.dtau_dv, &mut d.ddq_dv, n);
        if d.ddq_dq.iter().chain(&d.ddq_dv).any(|x| !x.is_finite()) {
            return Err(DynamicsError::NotFinite);
        }
        Ok(())
    }

    /// The link whose joint has velocity coordinate `col`.
    fn link_of(&self, col: usize) -> usize {
        (1..self.links.len())
            .find(|&k| (self.links[k].v_offset..self.links[k].v_offset + self.links[k].joint.nv()).contains(&col))
            .unwrap_or(GROUND)
    }

    /// Forward pass: world poses, columns, velocities and accelerations,
    /// each column's `dV`, `dA`, `dAv`, and each link's own terms.
    fn forward_terms(&self, ws: &Workspace, d: &mut DynamicsDerivatives, u: &[f64], ud: &[f64]) {
        // Uniform gravity as an acceleration of the ground, as in the ABA.
        let ground = LinkTerms {
            rot: Mat3::identity(),
            a: Motion::new(Vec3::zeros(), -self.uniform_gravity),
            ..LinkTerms::default()
        };
        d.links[GROUND] = ground;
        for k in 1..self.links.len() {
            let link = &self.links[k];
            let w = &ws.links[k];
            let p = d.links[link.parent];
            let rot = w.x_up.rot * p.rot;
            let pos = p.pos + p.rot.tr_mul(&w.x_up.trans);
            let to_link = Transform::new(rot, pos);
            let (v0, nvj) = (link.v_offset, link.joint.nv());
            let fixed = d.parent_fixed[k];
            // The velocity and acceleration of the frame between the joint's
            // parent-fixed and child-fixed columns (the parent's for most joints).
            let (mut vb, mut ab) = (p.v, p.a);
            for c in 0..nvj {
                let local = if nvj == 1 { w.s } else { ws.multi[ws.multi_index[k]].s[c] };
                let s = to_link.inv_apply_motion(&local);
                d.columns[v0 + c].s = s;
                if fixed >> c & 1 == 1 {
                    // A column fixed in the parent changes at the parent's rate.
                    vb += s * u[v0 + c];
                    ab += s * ud[v0 + c] + p.v.cross_motion(&s) * u[v0 + c];
                }
            }
            let mut v = vb;
            for c in (0..nvj).filter(|c| fixed >> c & 1 == 0) {
                v += d.columns[v0 + c].s * u[v0 + c];
            }
            let mut a = ab;
            for c in (0..nvj).filter(|c| fixed >> c & 1 == 0) {
                // A column fixed in the link changes at the link's rate.
                let s = d.columns[v0 + c].s;
                a += s * ud[v0 + c] + v.cross_motion(&s) * u[v0 + c];
            }
            for c in 0..nvj {
                let col = &mut d.columns[v0 + c];
                let s = col.s;
                let dv = vb.cross_motion(&s);
                col.dv_ang = dv.ang;
                col.da = ab.cross_motion(&s) + vb.cross_motion(&dv);
                let own = if fixed >> c & 1 == 1 { vb } else { v };
                col.dav = dv + own.cross_motion(&s);
            }
            let inertia = link.inertia.expressed_in_parent(&to_link);
            let (force, b11, momentum) = link_terms(&inertia, &v, &a);
            d.links[k] = LinkTerms { rot, pos, v, a, inertia, force, b11, momentum };
        }
    }

    /// Backward pass: composites from the leaves inwards, each column's
    /// generators, and the entries of `M`, `dtau/dq`, `dtau/du` and `tau`
    /// for the column against its own joint and every ancestor.
    fn backward_terms(&self, d: &mut DynamicsDerivatives) {
        let n = d.nv;
        let DynamicsDerivatives { links, columns, mass, dtau_dq, dtau_dv, tau, parent_fixed, .. } = d;
        for k in (1..self.links.len()).rev() {
            let link = &self.links[k];
            let lt = links[k];
            let (v0, nvj) = (link.v_offset, link.joint.nv());
            for c in v0..v0 + nvj {
                let col = &mut columns[c];
                let s = col.s;
                col.ys = lt.inertia.apply(&s);
                col.bs = lt.b11.tr_mul(&s.ang) + lt.momentum.cross(&s.lin) * 2.0;
                col.d = s.cross_force(&lt.force) + lt.inertia.apply(&col.da) + b_apply(&lt.b11, &lt.momentum, &col.dv_ang);
                col.dvel = lt.inertia.apply(&col.dav) + b_apply(&lt.b11, &lt.momentum, &s.ang);
                tau[c] = s.dot(&lt.force);
            }
            // The joint's own block.
            let fixed = parent_fixed[k];
            for r in v0..v0 + nvj {
                let row = columns[r];
                for c in v0..v0 + nvj {
                    let col = &columns[c];
                    // A parent-fixed row stays when a child-fixed column moves.
                    let stays = fixed >> (r - v0) & 1 == 1 && fixed >> (c - v0) & 1 == 0;
                    dtau_dq[r * n + c] = if stays {
                        row.s.dot(&col.d)
                    } else {
                        col.da.dot(&row.ys) + row.bs.dot(&col.dv_ang)
                    };
                    dtau_dv[r * n + c] = col.dav.dot(&row.ys) + row.bs.dot(&col.s.ang);
                    mass[r * n + c] = col.s.dot(&row.ys);
                }
            }
            if nvj == 1 {
                mass[v0 * n + v0] += link.armature;
            }
            // Against the ancestors: row `c` (this joint) with column `r`
            // (an ancestor's) in the ancestor form, row `r` with column `c`
            // in the descendant form.
            let mut i = link.parent;
            while i != GROUND {
                let anc = &self.links[i];
                for c in v0..v0 + nvj {
                    let gen = columns[c];
                    let (row_q, row_v, row_m) = (c * n, c * n, c * n);
                    for r in anc.v_offset..anc.v_offset + anc.joint.nv() {
                        let a = &columns[r];
                        dtau_dq[row_q + r] = a.da.dot(&gen.ys) + gen.bs.dot(&a.dv_ang);
                        dtau_dq[r * n + c] = a.s.dot(&gen.d);
                        dtau_dv[row_v + r] = a.dav.dot(&gen.ys) + gen.bs.dot(&a.s.ang);
                        dtau_dv[r * n + c] = a.s.dot(&gen.dvel);
                        let m = a.s.dot(&gen.ys);
                        mass[row_m + r] = m;
                        mass[r * n + c] = m;
                    }
                }
                i = anc.parent;
            }
            if link.parent != GROUND {
                let p = &mut links[link.parent];
                p.inertia += lt.inertia;
                p.force += lt.force;
                p.b11 += lt.b11;
                p.momentum += lt.momentum;
            }
        }
        // Links in different branches do not interact: zero their entries.
        // (Set once per call: cheap next to the dense solve, and it keeps
        // the entries exact whatever the tree.)
        if !self.is_chain() {
            self.zero_cross_branch(mass, dtau_dq, dtau_dv);
        }
    }

    /// Whether every link's parent is the link before it (a serial chain,
    /// where every pair of joints is an ancestor pair).
    fn is_chain(&self) -> bool {
        self.links.iter().enumerate().skip(1).all(|(k, l)| l.parent == k - 1)
    }

    /// Zeroes the entries of joints in different branches.
    fn zero_cross_branch(&self, mass: &mut [f64], dq: &mut [f64], dv: &mut [f64]) {
        let n = self.states.nv;
        for k in 1..self.links.len() {
            for j in 1..self.links.len() {
                if self.is_ancestor_or_self(k, j) || self.is_ancestor_or_self(j, k) {
                    continue;
                }
                let (lk, lj) = (&self.links[k], &self.links[j]);
                for r in lk.v_offset..lk.v_offset + lk.joint.nv() {
                    for c in lj.v_offset..lj.v_offset + lj.joint.nv() {
                        mass[r * n + c] = 0.0;
                        dq[r * n + c] = 0.0;
                        dv[r * n + c] = 0.0;
                    }
                }
            }
        }
    }

    /// Whether link `a` is link `b` or one of its ancestors.
    fn is_ancestor_or_self(&self, a: usize, mut b: usize) -> bool {
        while b > a {
            b = self.links[b].parent;
        }
        a == b
    }

    /// The generalised forces of everything except the links' inertia and
    /// uniform gravity (1-D elements on the axes, forces between frames,
    /// point gravity, constant axis forces, ...), as the articulated-body
    /// pass sees them after `motion_and_loads(ws, t, q, u)`: `Q` with
    /// `M ud + b(q, u) = Q`. Writes `out` (nv). Allocates nothing.
    pub fn generalized_forces(
        &self,
        ws: &mut Workspace,
        t: f64,
        q: &[f64],
        u: &[f64],
        out: &mut [f64],
    ) -> Result<(), DynamicsError> {
        self.motion_and_loads(ws, t, q, u)?;
        out.copy_from_slice(&ws.tau);
        // After the loads, `pa` is `v x* I v` less the external forces on
        // the link: take those back out and carry them up the tree.
        for k in 1..self.links.len() {
            let w = &mut ws.links[k];
            let bias = w.v.cross_force(&self.links[k].inertia.apply(&w.v));
            w.pa = bias - w.pa;
        }
        for k in (1..self.links.len()).rev() {
            let link = &self.links[k];
            let f = ws.links[k].pa;
            for c in 0..link.joint.nv() {
                let s = if link.joint.nv() == 1 { ws.links[k].s } else { ws.multi[ws.multi_index[k]].s[c] };
                out[link.v_offset + c] += s.dot(&f);
            }
            if link.parent != GROUND {
                let up = ws.links[k].x_up.inv_apply_force(&f);
                ws.links[link.parent].pa += up;
            }
        }
        Ok(())
    }
}

/// A link's force `f = I a + v x* I v`, the 3x3 block `B11` of
/// `B = (v x*) I - I (v x) + (. x* h)` (`h = I v`), and its linear momentum.
///
/// With `I = [A, [c]; -[c], m]` (`c` the first moment) and `v = (w, n)`,
/// `(v x*) = [[w], [n]; 0, [w]]`, `(v x) = [[w], 0; [n], [w]]` and
/// `(. x* h) = [-[h_a], -[h_l]; -[h_l], 0]`, the blocks of `B` are
/// `B11 = [w] A - A [w] - [n][c] - [c][n] - [h_a]`,
/// `B12 = [w x c] + m [n] - [h_l] = 0` (as `h_l = m n - c x w`),
/// `B21 = -2 [h_l]`, `B22 = 0`.
#[inline]
fn link_terms(inertia: &RigidInertia, v: &Motion, a: &Motion) -> (Force, Mat3, Vec3) {
    let h = inertia.apply(v);
    let force = inertia.apply(a) + v.cross_force(&h);
    let (w, n, c) = (v.ang, v.lin, inertia.h);
    let wa = crate::math::skew(&w) * inertia.rot;
    // [n][c] + [c][n] = n c' + c n' - 2 (n . c) 1
    let nc = n * c.transpose();
    let sym = nc + nc.transpose() - Mat3::from_diagonal_element(2.0 * n.dot(&c));
    let b11 = wa + wa.transpose() - sym - crate::math::skew(&h.ang);
    // [w] A - A [w] = [w] A + ([w] A)' since A is symmetric and [w]' = -[w].
    (force, b11, h.lin)
}

/// `Bc m` for a motion `m` with angular part `m_ang`: `(B11 m_ang, -2 h_l x m_ang)`.
#[inline]
fn b_apply(b11: &Mat3, momentum: &Vec3, m_ang: &Vec3) -> Force {
    Force::new(b11 * m_ang, -momentum.cross(m_ang) * 2.0)
}

/// Dot product of two slices of equal length, with four partial sums (so
/// that the compiler may keep them in vector registers).
#[inline]
fn dot(a: &[f64], b: &[f64]) -> f64 {
    let mut s = [0.0; 4];
    let (ca, cb) = (a.chunks_exact(4), b.chunks_exact(4));
    let (ra, rb) = (ca.remainder(), cb.remainder());
    for (x, y) in ca.zip(cb) {
        for k in 0..4 {
            s[k] += x[k] * y[k];
        }
    }
    let mut tail = 0.0;
    for (x, y) in ra.iter().zip(rb) {
        tail += x * y;
    }
    (s[0] + s[1]) + (s[2] + s[3]) + tail
}

/// `y += alpha x`.
#[inline]
fn axpy(y: &mut [f64], alpha: f64, x: &[f64]) {
    for (y, x) in y.iter_mut().zip(x) {
        *y += alpha * x;
    }
}

/// The Cholesky factor `L` (lower, row-major) of the symmetric `m`;
/// `Err(column)` where a pivot is not positive.
fn cholesky(m: &[f64], l: &mut [f64], n: usize) -> Result<(), usize> {
    for i in 0..n {
        for j in 0..=i {
            let s = m[i * n + j] - dot(&l[i * n..i * n + j], &l[j * n..j * n + j]);
            if i == j {
                if s.is_nan() || s <= 0.0 {
                    return Err(i);
                }
                l[i * n + i] = s.sqrt();
            } else {
                l[i * n + j] = s / l[j * n + j];
            }
        }
        l[i * n + i + 1..(i + 1) * n].fill(0.0);
    }
    Ok(())
}

/// `minv = M^-1 = L^-T L^-1` from the factor `l`, which becomes `L^-1`.
fn invert_from_cholesky(l: &mut [f64], minv: &mut [f64], n: usize) {
    // Row i of W = L^-1: (e_i - sum_{k<i} L[i][k] W[k]) / L[i][i]; rows of
    // W below i are done, and row i's L entries are read before written.
    for i in 0..n {
        let (done, rest) = l.split_at_mut(i * n);
        let row = &mut rest[..n];
        let diag = 1.0 / row[i];
        // Accumulate W[i][..i] in place: step k reads L[i][k], then adds
        // into entries ..=k, whose L values are all consumed by then.
        for k in 0..i {
            let lik = row[k];
            row[k] = 0.0;
            axpy(&mut row[..=k], -lik, &done[k * n..k * n + k + 1]);
        }
        for x in row[..i].iter_mut() {
            *x *= diag;
        }
        row[i] = diag;
    }
    // M^-1 = W' W: M^-1[a][b] = sum_{k >= max(a, b)} W[k][a] W[k][b]; the
    // upper triangle by rank-one updates of rows, then mirrored.
    minv.fill(0.0);
    for k in 0..n {
        let wk = &l[k * n..k * n + k + 1];
        for a in 0..=k {
            let wa = wk[a];
            axpy(&mut minv[a * n + a..a * n + k + 1], wa, &wk[a..]);
        }
    }
    for a in 0..n {
        for b in 0..a {
            minv[a * n + b] = minv[b * n + a];
        }
    }
}

/// `out = -a b` for `n x n` row-major matrices, four rows of `out` at a
/// time (each row of `b` is read once per four rows).
fn multiply_negated(a: &[f64], b: &[f64], out: &mut [f64], n: usize) {
    out.fill(0.0);
    let mut i0 = 0;
    while i0 < n {
        let rows = (n - i0).min(4);
        let (o, _) = out[i0 * n..].split_at_mut(rows * n);
        if rows == 4 {
            let (o0, o123) = o.split_at_mut(n);
            let (o1, o23) = o123.split_at_mut(n);
            let (o2, o3) = o23.split_at_mut(n);
            for k in 0..n {
                let (a0, a1, a2, a3) =
                    (-a[i0 * n + k], -a[(i0 + 1) * n + k], -a[(i0 + 2) * n + k], -a[(i0 + 3) * n + k]);
                let bk = &b[k * n..(k + 1) * n];
                for j in 0..n {
                    let x = bk[j];
                    o0[j] += a0 * x;
                    o1[j] += a1 * x;
                    o2[j] += a2 * x;
                    o3[j] += a3 * x;
                }
            }
        } else {
            for r in 0..rows {
                let orow = &mut o[r * n..(r + 1) * n];
                for k in 0..n {
                    axpy(orow, -a[(i0 + r) * n + k], &b[k * n..(k + 1) * n]);
                }
            }
        }
        i0 += rows;
    }
}
