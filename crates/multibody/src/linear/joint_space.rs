//! A mechanism's dynamics by joint coordinate, as robotics libraries give
//! them: the mass matrix `M(q)`, the inverse dynamics `M(q) a + C(q, v)`,
//! the forward dynamics `M(q)^-1 (tau - C(q, v))` and the pose of any frame
//! at `q`, with the joints named (`elbow` for `elbow.phi`) and in the
//! mechanism's tree order. For mechanisms without loops or constraints
//! (URDF robots, with a fixed or a floating base).
//!
//! The coordinates are the simulation's states: `q` the position states,
//! `v` the velocity states, in the order of [`JointSpace::coordinates`] and
//! [`JointSpace::velocities`]. A revolute or prismatic joint has one of
//! each; a floating base (a root Body with quaternion state) has
//! `q = [r_0 (3), Q_hat (4)]` (position in the world, quaternion
//! `[w, i, j, k]`, normalised where used) and `v = [v_0 (3), w_a (3)]`
//! (velocity in the world, angular velocity in the body), so its
//! accelerations are the world acceleration and `der(w_a)`, and its joint
//! forces a force in world coordinates and a torque in body coordinates.
//!
//! `C(q, v)` holds the velocity-product terms, gravity and the model's own
//! joint forces (springs, dampers on the axes); `tau` are joint forces
//! added to them. Allocation happens once, in [`JointSpace::new`].

use crate::assembly::Mechanism;
use crate::dynamics::Workspace;
use crate::math::dense::{cholesky, cholesky_solve};
use crate::system::Anchor;
use std::ops::Range;
use std::sync::Arc;

/// The pose of a frame: its origin in world coordinates and its rotation
/// `R` as the frame's `R` signals have it (`v_frame = R * v_world`; the
/// transpose of the rotation robotics libraries call the frame's
/// orientation in the world).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FramePose {
    pub r_0: [f64; 3],
    pub rotation: [[f64; 3]; 3],
}

/// The joint-space dynamics of a mechanism (see the module's doc).
pub struct JointSpace {
    mechanism: Arc<Mechanism>,
    ws: Workspace,
    /// Each joint's name and where its coordinates are in `q` and `v`.
    joints: Vec<(String, Range<usize>, Range<usize>)>,
    names: Vec<String>,
    /// The state at which positions and velocities are set.
    y: Vec<f64>,
    mass: Vec<f64>,
    bias: Vec<f64>,
}

impl JointSpace {
    /// The joint space of `mechanism`; an error says why it has none (a
    /// loop or constraint, states of its own equations).
    pub fn new(mechanism: Arc<Mechanism>) -> Result<JointSpace, String> {
        let system = &mechanism.system;
        let states = &system.states;
        if system.uses_mass_matrix() {
            return Err("the mechanism has loops or constraints (or mimic joints): its joint coordinates are not \
                        independent"
                .into());
        }
        if states.nx > 0 {
            return Err("the model has states of its own equations besides the joints'".into());
        }
        let mut joints = Vec::new();
        for link in system.links.iter().skip(1) {
            let (nq, nv) = (link.joint.nq(), link.joint.nv());
            if nv == 0 {
                continue;
            }
            let name = &states.names[link.q_offset];
            let joint = name.rsplit_once('.').map_or(name.as_str(), |(owner, _)| owner);
            joints.push((joint.to_string(), link.q_offset..link.q_offset + nq, link.v_offset..link.v_offset + nv));
        }
        joints.sort_by_key(|(_, q, _)| q.start);
        let nv = states.nv;
        Ok(JointSpace {
            ws: mechanism.workspace(),
            names: joints.iter().map(|(n, _, _)| n.clone()).collect(),
            joints,
            y: states.start.clone(),
            mass: vec![0.0; nv * nv],
            bias: vec![0.0; nv],
            mechanism,
        })
    }

    /// The joints, in tree order (a floating base first).
    pub fn joints(&self) -> &[String] {
        &self.names
    }

    /// Where the coordinates of the joint `name` are in `q` and in `v`.
    pub fn joint(&self, name: &str) -> Option<(Range<usize>, Range<usize>)> {
        self.joints.iter().find(|(n, _, _)| n == name).map(|(_, q, v)| (q.clone(), v.clone()))
    }

    /// The names of the position coordinates `q` (`elbow.phi`).
    pub fn coordinates(&self) -> &[String] {
        &self.mechanism.system.states.names[..self.mechanism.system.states.nq]
    }

    /// The names of the velocity coordinates `v` (`elbow.w`).
    pub fn velocities(&self) -> &[String] {
        let states = &self.mechanism.system.states;
        &states.names[states.nq..states.nq + states.nv]
    }

    fn check(&self, vectors: &[(&str, usize, bool)]) -> Result<(), String> {
        let states = &self.mechanism.system.states;
        for &(what, len, position) in vectors {
            let (n, kind) = if position { (states.nq, "position") } else { (states.nv, "velocity") };
            if len != n {
                return Err(format!("{what} has {len} values for {n} {kind} coordinates"));
            }
        }
        Ok(())
    }

    /// The kinematics, signals and loads at `(q, v)` (`v` zero when `None`).
    fn motion(&mut self, q: &[f64], v: Option<&[f64]>) -> Result<(), String> {
        let states = &self.mechanism.system.states;
        let (nq, nv) = (states.nq, states.nv);
        self.y[..nq].copy_from_slice(q);
        match v {
            Some(v) => self.y[nq..nq + nv].copy_from_slice(v),
            None => self.y[nq..nq + nv].fill(0.0),
        }
        let (qs, vs) = self.y.split_at(nq);
        let m = &self.mechanism;
        m.system
            .mass_matrix_and_bias(&mut self.ws, 0.0, qs, &vs[..nv], &mut self.mass, &mut self.bias)
            .map_err(|e| m.describe(&e))
    }

    /// The mass matrix at `q`, row-major `nv x nv`.
    pub fn mass_matrix(&mut self, q: &[f64], out: &mut [f64]) -> Result<(), String> {
        self.check(&[("q", q.len(), true)])?;
        if out.len() != self.mass.len() {
            return Err(format!("the mass matrix has {} values, not {}", self.mass.len(), out.len()));
        }
        self.motion(q, None)?;
        out.copy_from_slice(&self.mass);
        Ok(())
    }

    /// The joint forces that give the accelerations `a` at `(q, v)`.
    pub fn inverse_dynamics(&mut self, q: &[f64], v: &[f64], a: &[f64], tau: &mut [f64]) -> Result<(), String> {
        self.check(&[("q", q.len(), true), ("v", v.len(), false), ("a", a.len(), false), ("tau", tau.len(), false)])?;
        self.motion(q, Some(v))?;
        let n = self.bias.len();
        for ((t, row), b) in tau.iter_mut().zip(self.mass.chunks_exact(n.max(1))).zip(&self.bias) {
            // `bias` is the force that leaves the joints unaccelerated, -C.
            *t = row.iter().zip(a).map(|(m, x)| m * x).sum::<f64>() - b;
        }
        Ok(())
    }

    /// The accelerations at `(q, v)` under the joint forces `tau`.
    pub fn forward_dynamics(&mut self, q: &[f64], v: &[f64], tau: &[f64], a: &mut [f64]) -> Result<(), String> {
        self.check(&[("q", q.len(), true), ("v", v.len(), false), ("tau", tau.len(), false), ("a", a.len(), false)])?;
        self.motion(q, Some(v))?;
        let n = self.bias.len();
        if !cholesky(&mut self.mass, n) {
            return Err("the mass matrix is not positive definite here: a joint has no inertia behind it".into());
        }
        for ((x, t), b) in a.iter_mut().zip(tau).zip(&self.bias) {
            *x = t + b;
        }
        cholesky_solve(&self.mass, n, a);
        Ok(())
    }

    /// The pose at `q` of the frame `frame`: a connector (`elbow.frame_b`),
    /// or a component, whose `frame_a` (or only frame connector) is meant.
    pub fn frame_pose(&mut self, frame: &str, q: &[f64]) -> Result<FramePose, String> {
        self.check(&[("q", q.len(), true)])?;
        let m = self.mechanism.clone();
        let node = m.frame_node(frame)?;
        self.motion(q, None)?;
        m.system.world_poses(&mut self.ws);
        let node = &m.nodes[node];
        let x = &node.pose;
        let (r_0, rot) = match node.anchor {
            Anchor::Massless(g) => (self.ws.massless_pos[g] + x.trans, x.rot),
            Anchor::Link(k) => {
                let link = &self.ws.links[k];
                (link.pos + link.rot.tr_mul(&x.trans), x.rot * link.rot)
            }
        };
        Ok(FramePose {
            r_0: [r_0.x, r_0.y, r_0.z],
            rotation: std::array::from_fn(|i| std::array::from_fn(|j| rot[(i, j)])),
        })
    }
}
