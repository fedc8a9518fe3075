//! A mechanism's dynamics by joint coordinate, as robotics libraries give
//! them: the mass matrix `M(q)`, the inverse dynamics `M(q) a + C(q, v)`
//! and the forward dynamics `M(q)^-1 (tau - C(q, v))`, with the joint
//! coordinates named (`elbow` for `elbow.phi`) and in the mechanism's tree
//! order. For mechanisms without loops whose joints each have one
//! coordinate (revolutes and prismatics, as URDF robots with a fixed base).
//!
//! `C(q, v)` holds the velocity-product terms, gravity and the model's own
//! joint forces (springs, dampers on the axes); `tau` are joint forces
//! added to them. Allocation happens once, in [`JointSpace::new`].

use crate::assembly::Mechanism;
use crate::dynamics::Workspace;
use crate::math::dense::{cholesky, cholesky_solve};

/// The joint-space dynamics of a mechanism (see the module's doc).
pub struct JointSpace<'m> {
    mechanism: &'m Mechanism,
    ws: Workspace,
    names: Vec<String>,
    /// The state at which positions and velocities are set: the start
    /// state (for coordinates that are not the joints', if any).
    y: Vec<f64>,
    mass: Vec<f64>,
    bias: Vec<f64>,
}

impl<'m> JointSpace<'m> {
    /// The joint space of `mechanism`; an error says why it has none (a
    /// loop, a joint with several coordinates, states of its own equations).
    pub fn new(mechanism: &'m Mechanism) -> Result<JointSpace<'m>, String> {
        let system = &mechanism.system;
        let states = &system.states;
        if system.uses_mass_matrix() {
            return Err("the mechanism has loops or constraints: its joint coordinates are not independent".into());
        }
        if states.nq != states.nv || states.nx > 0 {
            return Err("every joint must have one coordinate (revolute or prismatic), and the model no states of \
                        its own equations"
                .into());
        }
        let mut names = Vec::with_capacity(states.nv);
        for link in system.links.iter().skip(1) {
            if link.joint.nq() != link.joint.nv() || link.joint.nv() > 1 {
                let owner = &mechanism.components[link.states_of].name;
                return Err(format!("`{owner}` has {} coordinates; joint space needs one per joint", link.joint.nq()));
            }
            if link.joint.nv() == 1 {
                let name = &states.names[link.q_offset];
                let joint = name.rsplit_once('.').map_or(name.as_str(), |(owner, _)| owner);
                names.push((link.q_offset, joint.to_string()));
            }
        }
        names.sort_by_key(|(k, _)| *k);
        let nv = states.nv;
        Ok(JointSpace {
            mechanism,
            ws: mechanism.workspace(),
            names: names.into_iter().map(|(_, n)| n).collect(),
            y: states.start.clone(),
            mass: vec![0.0; nv * nv],
            bias: vec![0.0; nv],
        })
    }

    /// The joints, in the order of every vector here.
    pub fn joints(&self) -> &[String] {
        &self.names
    }

    fn check(&self, vectors: &[(&str, usize)]) -> Result<(), String> {
        let n = self.names.len();
        match vectors.iter().find(|(_, len)| *len != n) {
            Some((what, len)) => Err(format!("{what} has {len} values for {n} joints")),
            None => Ok(()),
        }
    }

    /// `M(q)` and `C(q, v)` into the scratch (`v` zero when `None`).
    fn terms(&mut self, q: &[f64], v: Option<&[f64]>) -> Result<(), String> {
        let n = self.names.len();
        self.y[..n].copy_from_slice(q);
        match v {
            Some(v) => self.y[n..2 * n].copy_from_slice(v),
            None => self.y[n..2 * n].fill(0.0),
        }
        let (qs, vs) = self.y.split_at(n);
        let m = self.mechanism;
        m.system
            .mass_matrix_and_bias(&mut self.ws, 0.0, qs, &vs[..n], &mut self.mass, &mut self.bias)
            .map_err(|e| m.describe(&e))
    }

    /// The mass matrix at `q`, row-major `n x n`.
    pub fn mass_matrix(&mut self, q: &[f64], out: &mut [f64]) -> Result<(), String> {
        let n = self.names.len();
        self.check(&[("q", q.len())])?;
        if out.len() != n * n {
            return Err(format!("the mass matrix has {} values, not {}", n * n, out.len()));
        }
        self.terms(q, None)?;
        out.copy_from_slice(&self.mass);
        Ok(())
    }

    /// The joint forces that give the accelerations `a` at `(q, v)`.
    pub fn inverse_dynamics(&mut self, q: &[f64], v: &[f64], a: &[f64], tau: &mut [f64]) -> Result<(), String> {
        self.check(&[("q", q.len()), ("v", v.len()), ("a", a.len()), ("tau", tau.len())])?;
        self.terms(q, Some(v))?;
        let n = self.names.len();
        for ((t, row), b) in tau.iter_mut().zip(self.mass.chunks_exact(n)).zip(&self.bias) {
            // `bias` is the force that leaves the joints unaccelerated, -C.
            *t = row.iter().zip(a).map(|(m, x)| m * x).sum::<f64>() - b;
        }
        Ok(())
    }

    /// The accelerations at `(q, v)` under the joint forces `tau`.
    pub fn forward_dynamics(&mut self, q: &[f64], v: &[f64], tau: &[f64], a: &mut [f64]) -> Result<(), String> {
        self.check(&[("q", q.len()), ("v", v.len()), ("tau", tau.len()), ("a", a.len())])?;
        self.terms(q, Some(v))?;
        let n = self.names.len();
        if !cholesky(&mut self.mass, n) {
            return Err("the mass matrix is not positive definite here: a joint has no inertia behind it".into());
        }
        for ((x, t), b) in a.iter_mut().zip(tau).zip(&self.bias) {
            *x = t + b;
        }
        cholesky_solve(&self.mass, n, a);
        Ok(())
    }
}
