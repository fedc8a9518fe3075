//! Analytic derivatives of the forward dynamics of kinematic trees: the
//! derivatives of the recursive Newton-Euler algorithm (RNEA) of Carpentier
//! and Mansard ("Analytical Derivatives of Rigid Body Dynamics Algorithms",
//! RSS 2018), then `d ud = -M^-1 d RNEA`, with `M` from the
//! composite-rigid-body algorithm and `M^-1` from the articulated-body one.
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
//! - `i` beyond `j`: `dtau_i/dq_j = G_i . Hq_j` and `dtau_i/du_j = G_i . Hv_j`
//!   with the row generator `G_i = (Y_i S_i, Bc_i' S_i)` and the column
//!   generators `Hq_j = (dA_j, dV_j)`, `Hv_j = (dAv_j, S_j)`;
//! - `j` beyond `i`: `S_i` stays, so `dtau_i/dq_j = S_i . D_j` with
//!   `D_j = S_j x* F_j + Y_j dA_j + Bc_j dV_j`, and
//!   `dtau_i/du_j = S_i . Dv_j` with `Dv_j = Y_j dAv_j + Bc_j S_j`;
//! - zero between different branches.
//!
//! `B_k` has a simple form (see [`link_terms`]): its right half is zero,
//! so it is kept as one 3x3 block and the linear momentum, and `Bc' S` has
//! only an angular part (so `G` and `H` have 9 entries, not 12).
//!
//! That structure also makes the products with `M^-1` cheap: column `j` of
//! `M^-1 dtau/dq` is `Psi_j Hq_j + Phi_j D_j` plus the joint's own block,
//! where `Psi_j = sum over i beyond j of M^-1[:, i] G_i'` and
//! `Phi_j = sum over i before j of M^-1[:, i] S_i'`. Both are sums along
//! the tree, updated by one outer product per joint, so the products cost
//! O(nv^2) (times 9 and 6) instead of the dense O(nv^3), and `dtau/dq` is
//! never formed; `M^-1` itself comes from the articulated-body algorithm
//! with unit torques (Carpentier's `computeMinverse`), also O(nv^2) on a
//! chain. Links are visited in depth-first order so that every subtree's
//! columns are contiguous, and the running sums need one buffer per level
//! of branching, not one per link.
//!
//! Joints with several coordinates: a column that is fixed in the child
//! link (a rotation about a child axis, a translation along one) is carried
//! by the motion of every coordinate of its joint; a column fixed in the
//! parent (the translations of Free and Planar along the parent's axes,
//! which come first) is not. Their joints are treated as a parent-fixed
//! group moving an intermediate frame `b`, then a child-fixed group, and
//! `v_p, a_p` above become `v_b, a_b`.

use super::{DynamicsError, Workspace};
use crate::math::{ArticulatedInertia, Force, Mat3, Motion, RigidInertia, Transform, Vec3};
use crate::system::{JointModel, JointMotion, RotationCoordinates, System, GROUND};
use nalgebra::Matrix6;

/// Scratch and results of [`System::aba_derivatives`], allocated once for a
/// system (`nv` velocity coordinates). Matrices are `nv x nv`, row-major,
/// indexed by velocity coordinate.
#[derive(Clone, Debug)]
pub struct DynamicsDerivatives {
    nv: usize,
    ddq_dq: Vec<f64>,
    ddq_dv: Vec<f64>,
    minv: Vec<f64>,
    mass: Vec<f64>,
    tau: Vec<f64>,
    /// The rest in the internal (depth-first) order of the columns:
    /// `M^-1`, and `ddq_dq'`, `ddq_dv'` (row `j` is column `j`).
    minv_t: Vec<f64>,
    xq: Vec<f64>,
    xv: Vec<f64>,
    /// The articulated-body pass's forces per unit torque (6 x nv).
    unit_forces: Vec<f64>,
    /// The columns `S` as six rows (6 x nv), and a scratch row (nv).
    s_rows: Vec<f64>,
    scratch: Vec<f64>,
    /// Running sums: `Psi` (9 x nv per slot) and `Phi` or the accelerations
    /// per unit torque (6 x nv per slot).
    psi: Vec<f64>,
    phi: Vec<f64>,
    links: Vec<LinkTerms>,
    /// Per link, `D^-1` of its joint (the top-left block).
    dinv: Vec<Matrix6<f64>>,
    columns: Vec<ColumnTerms>,
    tree: TreeOrder,
}

/// What the passes keep per link (world coordinates, at the world origin).
#[derive(Clone, Copy, Debug)]
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
    /// Articulated inertia (the link's, then its subtree's).
    ia: ArticulatedInertia,
}

impl Default for LinkTerms {
    fn default() -> Self {
        LinkTerms {
            rot: Mat3::identity(),
            pos: Vec3::zeros(),
            v: Motion::ZERO,
            a: Motion::ZERO,
            inertia: RigidInertia::ZERO,
            force: Force::ZERO,
            b11: Mat3::zeros(),
            momentum: Vec3::zeros(),
            ia: ArticulatedInertia::default(),
        }
    }
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
    /// `U = IA S` of the articulated-body pass.
    u_force: Force,
    /// `dtau/dq` and `dtau/du` of the joint's own rows against this column.
    own_q: [f64; 6],
    own_v: [f64; 6],
}

/// How a link's backward running sum reaches its parent's.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Merge {
    /// Same buffer (an only child), or no parent.
    InPlace,
    /// The first child of a branching parent to finish: copy.
    Copy,
    /// A later child: add.
    Add,
}

/// The tree in depth-first preorder, with the buffers of the running sums.
#[derive(Clone, Debug)]
struct TreeOrder {
    /// The links (not the ground) in depth-first preorder.
    order: Vec<usize>,
    /// Per link: its first column in the internal order, and the end of
    /// its subtree's columns.
    start: Vec<usize>,
    end: Vec<usize>,
    /// Per link: the buffer of its running sums (its level of branching).
    slot: Vec<usize>,
    leaf: Vec<bool>,
    merge: Vec<Merge>,
    /// Per internal column, its velocity coordinate.
    coordinate: Vec<usize>,
    /// Whether the internal order is the coordinates' own.
    identity: bool,
    /// Per link, the bits of its joint's columns fixed in the parent.
    parent_fixed: Vec<u8>,
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

    /// The number of velocity coordinates (the matrices' size).
    pub fn nv(&self) -> usize {
        self.nv
    }
}

/// Which columns of a supported joint are fixed in the parent (bits), or
/// why the joint is not supported.
fn parent_fixed_columns(joint: &JointModel, inverted: bool) -> Result<u8, &'static str> {
    let bits = match joint {
        // Their columns are fixed in both frames (an axis through both
        // origins, or translations), whichever way the tree traverses them.
        JointModel::Revolute { .. } | JointModel::Prismatic { .. } => return Ok(0),
        JointModel::Translation | JointModel::Cylindrical { .. } => return Ok(0),
        JointModel::Spherical(RotationCoordinates::Quaternion { .. }) => 0,
        JointModel::Planar { .. } => 0b011,
        JointModel::Free(RotationCoordinates::Quaternion { .. }) => 0b000111,
        JointModel::Free(RotationCoordinates::Euler { .. }) => {
            return Err("a free joint with Euler angles (its motion subspace turns with the angles; use quaternions)")
        }
        JointModel::Spherical(RotationCoordinates::Euler { .. }) => {
            return Err(
                "a spherical joint with Euler angles (its motion subspace turns with the angles; use quaternions)",
            )
        }
        JointModel::Universal { .. } => {
            return Err("a universal joint (its first axis turns with the second angle)");
        }
    };
    if inverted {
        // Traversed from frame_b to frame_a, the columns fixed in the child
        // become fixed in the parent and come first.
        return Err("a joint with rotations among several coordinates that the tree traverses from its frame_b to \
                    its frame_a (mount it the other way round)");
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
            // The component that carries the joint's states, for the message.
            let name = state(link.v_offset);
            let owner = name.rsplit_once('.').map_or(name.as_str(), |(c, _)| c);
            if let Err(why) = parent_fixed_columns(&link.joint, link.inverted) {
                return Some(format!("the joint of `{owner}` (state `{name}`) is {why}"));
            }
            if link.chart.is_some() {
                return Some(format!("the joint of `{owner}` (state `{name}`) uses an Euler-angle chart"));
            }
        }
        None
    }

    /// Scratch and results for [`System::aba_derivatives`], sized for this system.
    pub fn derivatives_work(&self) -> DynamicsDerivatives {
        let nv = self.states.nv;
        let tree = self.tree_order();
        let slots = tree.slot.iter().copied().max().map_or(0, |s| s + 1);
        DynamicsDerivatives {
            nv,
            ddq_dq: vec![0.0; nv * nv],
            ddq_dv: vec![0.0; nv * nv],
            minv: vec![0.0; nv * nv],
            mass: vec![0.0; nv * nv],
            tau: vec![0.0; nv],
            minv_t: vec![0.0; nv * nv],
            xq: vec![0.0; nv * nv],
            xv: vec![0.0; nv * nv],
            unit_forces: vec![0.0; 6 * nv],
            s_rows: vec![0.0; 6 * nv],
            scratch: vec![0.0; nv],
            psi: vec![0.0; 9 * nv * slots],
            phi: vec![0.0; 6 * nv * slots],
            links: vec![LinkTerms::default(); self.links.len()],
            dinv: vec![Matrix6::zeros(); self.links.len()],
            columns: vec![ColumnTerms::default(); nv],
            tree,
        }
    }

    /// The links in depth-first preorder and the buffers of the running sums.
    fn tree_order(&self) -> TreeOrder {
        let n = self.links.len();
        let mut children = vec![Vec::new(); n];
        for k in 1..n {
            children[self.links[k].parent].push(k);
        }
        let mut order = Vec::with_capacity(n);
        let mut stack: Vec<usize> = children[GROUND].iter().rev().copied().collect();
        while let Some(k) = stack.pop() {
            order.push(k);
            stack.extend(children[k].iter().rev());
        }
        let mut subtree = vec![0; n];
        for k in (1..n).rev() {
            subtree[k] += self.links[k].joint.nv();
            let p = self.links[k].parent;
            subtree[p] += subtree[k];
        }
        let (mut start, mut end, mut slot) = (vec![0; n], vec![0; n], vec![0; n]);
        let mut coordinate = vec![0; self.states.nv];
        let mut next = 0;
        for &k in &order {
            let link = &self.links[k];
            start[k] = next;
            end[k] = next + subtree[k];
            for c in 0..link.joint.nv() {
                coordinate[next + c] = link.v_offset + c;
            }
            next += link.joint.nv();
            // An only child shares its parent's buffer; the children of a
            // branching link take the next level's, one after the other.
            slot[k] = match link.parent {
                GROUND => 0,
                p if children[p].len() == 1 => slot[p],
                p => slot[p] + 1,
            };
        }
        let merge = (0..n)
            .map(|k| {
                let p = self.links[k].parent;
                if k == GROUND || p == GROUND || slot[p] == slot[k] {
                    Merge::InPlace
                } else if children[p].iter().all(|&c| start[c] <= start[k]) {
                    // Last in preorder, so first in the backward pass.
                    Merge::Copy
                } else {
                    Merge::Add
                }
            })
            .collect();
        TreeOrder {
            identity: coordinate.iter().enumerate().all(|(i, &c)| i == c),
            order,
            start,
            end,
            slot,
            leaf: children.iter().map(|c| c.is_empty()).collect(),
            merge,
            coordinate,
            parent_fixed: self.links.iter().map(|l| parent_fixed_columns(&l.joint, l.inverted).unwrap_or(0)).collect(),
        }
    }

    /// Derivatives of `ud = M(q)^-1 (tau - b(q, u))` at `(q, u)` with `tau`
    /// held fixed, where `b` holds the velocity-product and uniform-gravity
    /// terms and `ud` are the accelerations at that point (e.g. from `rhs`):
    /// `ddq_dq = -M^-1 dRNEA/dq(q, u, ud)`, `ddq_dv = -M^-1 dRNEA/du(q, u, ud)`;
    /// also `M`, `M^-1` and the RNEA's value. Forces of other elements
    /// (springs, dampers, point gravity, ...) are part of `tau` here: see
    /// [`System::generalized_forces`] for their value.
    ///
    /// For joints with a quaternion, the columns of `ddq_dq` of its rotation
    /// are along the rotation increment (see [`DynamicsDerivatives::ddq_dq`]).
    /// Valid where [`System::derivatives_unsupported`] is `None`. The passes
    /// keep their own scratch in `d` (they leave `ws` as it is). Allocates
    /// nothing. Cost: O(n d) for the RNEA's derivatives (n links, depth d),
    /// and O(nv^2) for `M^-1` and the products on a chain (at most
    /// O(nv^2 d) on a tree).
    pub fn aba_derivatives(
        &self,
        _ws: &mut Workspace,
        d: &mut DynamicsDerivatives,
        q: &[f64],
        u: &[f64],
        ud: &[f64],
    ) -> Result<(), DynamicsError> {
        debug_assert!(self.derivatives_unsupported().is_none(), "{:?}", self.derivatives_unsupported());
        let nv = self.states.nv;
        assert!(d.nv == nv && u.len() == nv && ud.len() == nv && q.len() == self.states.nq);
        // Finite inputs and positive pivots keep every result finite.
        if q.iter().chain(u).chain(ud).any(|x| !x.is_finite()) {
            return Err(DynamicsError::NotFinite);
        }
        self.forward_terms(d, q, u, ud);
        self.backward_terms(d)?;
        self.forward_products(d);
        self.backward_products(d);
        d.write_results();
        Ok(())
    }

    /// Forward pass: world poses, columns, velocities and accelerations,
    /// each column's `dV`, `dA`, `dAv`, and each link's own terms.
    fn forward_terms(&self, d: &mut DynamicsDerivatives, q: &[f64], u: &[f64], ud: &[f64]) {
        // Uniform gravity as an acceleration of the ground, as in the ABA.
        d.links[GROUND] = LinkTerms { a: Motion::new(Vec3::zeros(), -self.uniform_gravity), ..LinkTerms::default() };
        let mut jm = JointMotion::default();
        for k in 1..self.links.len() {
            let link = &self.links[k];
            link.motion(q, u, &mut jm);
            let x_up = link.x_tree.then(&jm.x);
            let p = &d.links[link.parent];
            let (pv, pa) = (p.v, p.a);
            let rot = x_up.rot * p.rot;
            let pos = p.pos + p.rot.tr_mul(&x_up.trans);
            let to_link = Transform::new(rot, pos);
            let (v0, c0, nvj) = (link.v_offset, d.tree.start[k], link.joint.nv());
            let fixed = d.tree.parent_fixed[k];
            let columns = &mut d.columns[c0..c0 + nvj];
            // The velocity and acceleration of the frame between the joint's
            // parent-fixed and child-fixed columns (the parent's for most joints).
            let (mut vb, mut ab) = (pv, pa);
            for (c, col) in columns.iter_mut().enumerate() {
                col.s = to_link.inv_apply_motion(&jm.s[c]);
                for (r, x) in motion6(&col.s).into_iter().enumerate() {
                    d.s_rows[r * d.nv + c0 + c] = x;
                }
                if fixed >> c & 1 == 1 {
                    // A column fixed in the parent changes at the parent's rate.
                    vb += col.s * u[v0 + c];
                    ab += col.s * ud[v0 + c] + pv.cross_motion(&col.s) * u[v0 + c];
                }
            }
            let mut v = vb;
            for (c, col) in columns.iter().enumerate().filter(|(c, _)| fixed >> c & 1 == 0) {
                v += col.s * u[v0 + c];
            }
            let mut a = ab;
            for (c, col) in columns.iter().enumerate().filter(|(c, _)| fixed >> c & 1 == 0) {
                // A column fixed in the link changes at the link's rate.
                a += col.s * ud[v0 + c] + v.cross_motion(&col.s) * u[v0 + c];
            }
            for (c, col) in columns.iter_mut().enumerate() {
                let s = col.s;
                let dv = vb.cross_motion(&s);
                col.dv_ang = dv.ang;
                col.da = ab.cross_motion(&s) + vb.cross_motion(&dv);
                let own = if fixed >> c & 1 == 1 { vb } else { v };
                col.dav = dv + own.cross_motion(&s);
            }
            let inertia = world_inertia(&link.inertia, &rot, &pos);
            let (force, b11, momentum) = link_terms(&inertia, &v, &a);
            d.links[k] =
                LinkTerms { rot, pos, v, a, inertia, force, b11, momentum, ia: ArticulatedInertia::from(&inertia) };
        }
    }

    /// Backward pass: composites from the leaves inwards; each column's
    /// generators; `tau`, `M`, the joint's own block of `dtau`; and the
    /// backward half of the articulated-body pass for `M^-1` with unit
    /// torques (rows of `M^-1` over the link's subtree, before the forward
    /// pass corrects them).
    fn backward_terms(&self, d: &mut DynamicsDerivatives) -> Result<(), DynamicsError> {
        let n = d.nv;
        let DynamicsDerivatives { links, columns, dinv, mass, tau, minv_t, unit_forces, s_rows, scratch, tree, .. } = d;
        unit_forces.fill(0.0);
        for &k in tree.order.iter().rev() {
            let link = &self.links[k];
            let (v0, c0, e, nvj) = (link.v_offset, tree.start[k], tree.end[k], link.joint.nv());
            let lt = &links[k];
            for (c, col) in columns[c0..c0 + nvj].iter_mut().enumerate() {
                let s = col.s;
                col.ys = lt.inertia.apply(&s);
                col.bs = lt.b11.tr_mul(&s.ang) + lt.momentum.cross(&s.lin) * 2.0;
                col.d =
                    s.cross_force(&lt.force) + lt.inertia.apply(&col.da) + b_apply(&lt.b11, &lt.momentum, &col.dv_ang);
                col.dvel = lt.inertia.apply(&col.dav) + b_apply(&lt.b11, &lt.momentum, &s.ang);
                col.u_force = lt.ia.apply(&s);
                tau[v0 + c] = s.dot(&lt.force);
            }
            // The joint's own block, and D^-1 of the articulated-body pass.
            let mut ia = lt.ia;
            if nvj == 1 {
                let col = &mut columns[c0];
                col.own_q[0] = col.da.dot(&col.ys) + col.bs.dot(&col.dv_ang);
                col.own_v[0] = col.dav.dot(&col.ys) + col.bs.dot(&col.s.ang);
                mass[v0 * n + v0] = col.s.dot(&col.ys) + link.armature;
                let dd = col.s.dot(&col.u_force) + link.armature;
                if dd.is_nan() || dd <= 0.0 {
                    return Err(DynamicsError::SingularInertia { link: k });
                }
                dinv[k][(0, 0)] = 1.0 / dd;
                ia.sub_outer(&col.u_force, 1.0 / dd);
            } else {
                let fixed = tree.parent_fixed[k];
                let mut dm = Matrix6::<f64>::identity();
                for r in 0..nvj {
                    for c in 0..nvj {
                        let (row, col) = (&columns[c0 + r], &columns[c0 + c]);
                        // A parent-fixed row stays when a child-fixed column moves.
                        let stays = fixed >> r & 1 == 1 && fixed >> c & 1 == 0;
                        let q_entry =
                            if stays { row.s.dot(&col.d) } else { col.da.dot(&row.ys) + row.bs.dot(&col.dv_ang) };
                        let v_entry = col.dav.dot(&row.ys) + row.bs.dot(&col.s.ang);
                        mass[(v0 + r) * n + v0 + c] = col.s.dot(&row.ys);
                        dm[(r, c)] = row.s.dot(&col.u_force);
                        let col = &mut columns[c0 + c];
                        col.own_q[r] = q_entry;
                        col.own_v[r] = v_entry;
                    }
                }
                dinv[k] = dm.cholesky().ok_or(DynamicsError::SingularInertia { link: k })?.inverse();
                for c in 0..nvj {
                    let mut w = Force::ZERO;
                    for r in 0..nvj {
                        w += columns[c0 + r].u_force * dinv[k][(r, c)];
                    }
                    ia.sub_product(&w, &columns[c0 + c].u_force);
                }
            }
            // M against the ancestors (the composite-rigid-body algorithm):
            // `S_r . Y S_c` for every column before the link (in one pass
            // over the rows of S), kept for the ancestors.
            for c in 0..nvj {
                let row = &mut scratch[..c0];
                combine(row, 1.0, &force6(&columns[c0 + c].ys), s_rows, n, 0, false);
                let mut i = link.parent;
                while i != GROUND {
                    let anc = &self.links[i];
                    for r in 0..anc.joint.nv() {
                        let m = row[tree.start[i] + r];
                        mass[(v0 + c) * n + anc.v_offset + r] = m;
                        mass[(anc.v_offset + r) * n + v0 + c] = m;
                    }
                    i = anc.parent;
                }
            }
            // M^-1 by the articulated-body algorithm with unit torques: the
            // joint's own block is D^-1; a torque in the subtree reaches the
            // joint as the force `unit_forces` and gives -D^-1 S' F there.
            for r in 0..nvj {
                let row = &mut minv_t[(c0 + r) * n..(c0 + r + 1) * n];
                // Torques beyond the subtree do not reach it in this pass.
                row[e..].fill(0.0);
                let mut w = Motion::ZERO;
                for c in 0..nvj {
                    row[c0 + c] = dinv[k][(r, c)];
                    w += columns[c0 + c].s * dinv[k][(r, c)];
                }
                if e > c0 + nvj {
                    combine(&mut row[c0 + nvj..e], -1.0, &motion6(&w), unit_forces, n, c0 + nvj, false);
                }
            }
            for c in 0..nvj {
                let u6 = force6(&columns[c0 + c].u_force);
                let row = &minv_t[(c0 + c) * n + c0..(c0 + c) * n + e];
                for (r, &x) in u6.iter().enumerate() {
                    axpy(&mut unit_forces[r * n + c0..r * n + e], x, row);
                }
            }
            // What the joint passes on: IA - U D^-1 U', and the composites.
            let (inertia, force, b11, momentum) = (lt.inertia, lt.force, lt.b11, lt.momentum);
            if link.parent != GROUND {
                let p = &mut links[link.parent];
                p.inertia += inertia;
                p.force += force;
                p.b11 += b11;
                p.momentum += momentum;
                p.ia += ia;
            }
        }
        Ok(())
    }

    /// Forward over the tree, two things in one running sum `A` (6 x nv,
    /// in the `phi` buffers), the sum of `S_i M^-1[i, :]` over the columns
    /// before the link: in the articulated-body pass for `M^-1` it is the
    /// parent's acceleration per unit torque, which corrects the link's rows
    /// by `-D^-1 U' A` (upper triangle; the rest of the rows comes from the
    /// rows before, by symmetry); and it is `Phi_j`, which gives the part of
    /// column `j` of `ddq_dq` and `ddq_dv` from the rows before `j`. The
    /// joint's own block adds its part.
    fn forward_products(&self, d: &mut DynamicsDerivatives) {
        let n = d.nv;
        let DynamicsDerivatives { columns, dinv, minv_t, phi, xq, xv, tree, .. } = d;
        for &k in &tree.order {
            let link = &self.links[k];
            let (c0, nvj, s) = (tree.start[k], link.joint.nv(), tree.slot[k]);
            let buf = 6 * n * s;
            if link.parent == GROUND {
                phi[buf..buf + 6 * n].fill(0.0);
            } else {
                let from = 6 * n * tree.slot[link.parent];
                if from != buf {
                    phi.copy_within(from..from + 6 * n, buf);
                }
            }
            let sums = &phi[buf..buf + 6 * n];
            for r in 0..nvj {
                let row = c0 + r;
                if link.parent != GROUND {
                    let mut w = Force::ZERO;
                    for c in 0..nvj {
                        w += columns[c0 + c].u_force * dinv[k][(r, c)];
                    }
                    combine(&mut minv_t[row * n + c0..(row + 1) * n], -1.0, &force6(&w), sums, n, c0, true);
                }
                for col in 0..c0 {
                    minv_t[row * n + col] = minv_t[col * n + row];
                }
            }
            for c in c0..c0 + nvj {
                let col = &columns[c];
                if link.parent != GROUND {
                    combine(&mut xq[c * n..(c + 1) * n], -1.0, &force6(&col.d), sums, n, 0, false);
                    combine(&mut xv[c * n..(c + 1) * n], -1.0, &force6(&col.dvel), sums, n, 0, false);
                } else {
                    xq[c * n..(c + 1) * n].fill(0.0);
                    xv[c * n..(c + 1) * n].fill(0.0);
                }
                for t in 0..nvj {
                    let row = &minv_t[(c0 + t) * n..(c0 + t + 1) * n];
                    axpy(&mut xq[c * n..(c + 1) * n], -col.own_q[t], row);
                    axpy(&mut xv[c * n..(c + 1) * n], -col.own_v[t], row);
                }
            }
            let sums = &mut phi[buf..buf + 6 * n];
            for c in c0..c0 + nvj {
                let s6 = motion6(&columns[c].s);
                let row = &minv_t[c * n..(c + 1) * n];
                for (r, &x) in s6.iter().enumerate() {
                    axpy(&mut sums[r * n..(r + 1) * n], x, row);
                }
            }
        }
    }

    /// Backward over the tree: `Psi_j` (9 x nv), the sum of `G_i M^-1[i, :]`
    /// over the columns beyond `j`, gives the part of column `j` of
    /// `ddq_dq` and `ddq_dv` from the rows beyond it.
    fn backward_products(&self, d: &mut DynamicsDerivatives) {
        let n = d.nv;
        let DynamicsDerivatives { columns, minv_t, psi, xq, xv, tree, .. } = d;
        for &k in tree.order.iter().rev() {
            let link = &self.links[k];
            let (c0, nvj, s) = (tree.start[k], link.joint.nv(), tree.slot[k]);
            let buf = 9 * n * s;
            if tree.leaf[k] {
                psi[buf..buf + 9 * n].fill(0.0);
            } else {
                let sums = &psi[buf..buf + 9 * n];
                for c in c0..c0 + nvj {
                    let col = &columns[c];
                    let hq = generator9(&col.da, &col.dv_ang);
                    let hv = generator9(&col.dav, &col.s.ang);
                    combine(&mut xq[c * n..(c + 1) * n], -1.0, &hq, sums, n, 0, true);
                    combine(&mut xv[c * n..(c + 1) * n], -1.0, &hv, sums, n, 0, true);
                }
            }
            if link.parent == GROUND {
                continue;
            }
            let sums = &mut psi[buf..buf + 9 * n];
            for c in c0..c0 + nvj {
                let col = &columns[c];
                let g = [
                    col.ys.ang.x,
                    col.ys.ang.y,
                    col.ys.ang.z,
                    col.ys.lin.x,
                    col.ys.lin.y,
                    col.ys.lin.z,
                    col.bs.x,
                    col.bs.y,
                    col.bs.z,
                ];
                let row = &minv_t[c * n..(c + 1) * n];
                for (r, &x) in g.iter().enumerate() {
                    axpy(&mut sums[r * n..(r + 1) * n], x, row);
                }
            }
            let to = 9 * n * tree.slot[link.parent];
            match tree.merge[k] {
                Merge::InPlace => {}
                Merge::Copy => psi.copy_within(buf..buf + 9 * n, to),
                Merge::Add => {
                    let (lo, hi) = psi.split_at_mut(buf);
                    axpy(&mut lo[to..to + 9 * n], 1.0, &hi[..9 * n]);
                }
            }
        }
    }

    /// The generalised forces of everything except the links' inertia and
    /// uniform gravity (1-D elements on the axes, forces between frames,
    /// point gravity, constant axis forces, ...), as the articulated-body
    /// pass sees them after `motion_and_loads(ws, t, q, u)`: `Q` with
    /// `M ud + b(q, u) = Q`, the `tau` that [`System::aba_derivatives`]
    /// holds fixed. Writes `out` (nv). Allocates nothing. Meant for the
    /// systems the derivatives support (a tree whose accelerations the
    /// articulated-body pass gives); its own derivatives are the caller's
    /// (by differences: `d ud/dq = ddq_dq + M^-1 dQ/dq`, likewise for `u`).
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

impl DynamicsDerivatives {
    /// The results in the coordinates' order: `ddq_dq[i][j]` is row `j` of
    /// `xq` at `i`, and `M^-1` is `minv_t`, both permuted back.
    fn write_results(&mut self) {
        let n = self.nv;
        let at = &self.tree.coordinate;
        if self.tree.identity {
            for j in 0..n {
                for i in 0..n {
                    self.ddq_dq[i * n + j] = self.xq[j * n + i];
                    self.ddq_dv[i * n + j] = self.xv[j * n + i];
                }
            }
            self.minv.copy_from_slice(&self.minv_t);
        } else {
            for j in 0..n {
                for i in 0..n {
                    let out = at[i] * n + at[j];
                    self.ddq_dq[out] = self.xq[j * n + i];
                    self.ddq_dv[out] = self.xv[j * n + i];
                    self.minv[out] = self.minv_t[i * n + j];
                }
            }
        }
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

/// A link's inertia (about its origin, in its coordinates) in the world,
/// about the world origin, for the link at `pos` with world-to-link rotation
/// `rot`: with `h' = R' h` and `J = R' I R` about the link's origin,
/// `I_o = J - m [p]x [p]x - [p]x [h']x - [h']x [p]x`.
#[inline]
fn world_inertia(inertia: &RigidInertia, rot: &Mat3, pos: &Vec3) -> RigidInertia {
    let (m, p) = (inertia.mass, pos);
    let hr = rot.tr_mul(&inertia.h);
    let j = rot.tr_mul(&(inertia.rot * rot));
    let hp = hr * p.transpose();
    let diag = m * p.norm_squared() + 2.0 * p.dot(&hr);
    let mut r = j - p * p.transpose() * m - hp - hp.transpose();
    for i in 0..3 {
        r[(i, i)] += diag;
    }
    // Keep it exactly symmetric.
    RigidInertia { mass: m, h: hr + p * m, rot: (r + r.transpose()) * 0.5 }
}

/// `Bc m` for a motion `m` with angular part `m_ang`: `(B11 m_ang, -2 h_l x m_ang)`.
#[inline]
fn b_apply(b11: &Mat3, momentum: &Vec3, m_ang: &Vec3) -> Force {
    Force::new(b11 * m_ang, -momentum.cross(m_ang) * 2.0)
}

/// A motion's or a force's six numbers, angular first.
#[inline]
fn motion6(m: &Motion) -> [f64; 6] {
    [m.ang.x, m.ang.y, m.ang.z, m.lin.x, m.lin.y, m.lin.z]
}

#[inline]
fn force6(f: &Force) -> [f64; 6] {
    [f.ang.x, f.ang.y, f.ang.z, f.lin.x, f.lin.y, f.lin.z]
}

/// A column generator's nine numbers: a motion and an angular part.
#[inline]
fn generator9(m: &Motion, ang: &Vec3) -> [f64; 9] {
    [m.ang.x, m.ang.y, m.ang.z, m.lin.x, m.lin.y, m.lin.z, ang.x, ang.y, ang.z]
}

/// `out = scale * sum_r w[r] rows[r][from..]` (or `out +=` that with
/// `add`), where row `r` of `rows` starts at `r * n`: a combination of K
/// rows of a K x n block, one pass over `out`.
#[inline]
fn combine<const K: usize>(out: &mut [f64], scale: f64, w: &[f64; K], rows: &[f64], n: usize, from: usize, add: bool) {
    let m = out.len();
    let r: [&[f64]; K] = std::array::from_fn(|k| &rows[k * n + from..k * n + from + m]);
    let w: [f64; K] = std::array::from_fn(|k| w[k] * scale);
    if add {
        for j in 0..m {
            let mut s = out[j];
            for k in 0..K {
                s += w[k] * r[k][j];
            }
            out[j] = s;
        }
    } else {
        for j in 0..m {
            let mut s = 0.0;
            for k in 0..K {
                s += w[k] * r[k][j];
            }
            out[j] = s;
        }
    }
}

/// `y += alpha x`.
#[inline]
fn axpy(y: &mut [f64], alpha: f64, x: &[f64]) {
    for (y, x) in y.iter_mut().zip(x) {
        *y += alpha * x;
    }
}
