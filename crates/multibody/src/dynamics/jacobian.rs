//! The Jacobian of the right-hand side in the state's own coordinates for
//! the implicit integrator: `d[dq/dt, du/dt]/d[q, u]` of a tree of
//! one-coordinate joints, from the analytic derivatives of the rigid-body
//! dynamics (`derivatives`) and forward differences of the loads alone
//! (springs, dampers, forces), where they change with the state.

use super::derivatives::DynamicsDerivatives;
use super::{DynamicsError, Workspace};
use crate::system::System;

/// What the Jacobian needs, allocated once for a system.
pub struct StateJacobian {
    derivatives: DynamicsDerivatives,
    dy: Vec<f64>,
    y: Vec<f64>,
    loads: Vec<f64>,
    moved: Vec<f64>,
    /// `dQ/d[q, u]`, nv x 2 nv, row-major.
    load_jacobian: Vec<f64>,
}

impl System {
    /// The work of [`System::state_jacobian`], for a system it covers: a
    /// tree the analytic derivatives cover whose coordinates are its state
    /// (no quaternions, whose four numbers move in three directions).
    pub fn state_jacobian_work(&self) -> Option<StateJacobian> {
        let (nq, nv) = (self.states.nq, self.states.nv);
        if self.derivatives_unsupported().is_some() || nq != nv || self.states.nx != 0 {
            return None;
        }
        Some(StateJacobian {
            derivatives: self.derivatives_work(),
            dy: vec![0.0; nq + nv],
            y: vec![0.0; nq + nv],
            loads: vec![0.0; nv],
            moved: vec![0.0; nv],
            load_jacobian: if self.has_state_dependent_loads() { vec![0.0; 2 * nv * nv] } else { Vec::new() },
        })
    }

    /// `df/dy` at `(t, y)` into `jac` (row-major, square): `dq/dt = u`, and
    /// `du/dt = M^-1 (Q - b)` whose derivative at fixed `Q` is analytic,
    /// plus `M^-1 dQ/dy` by forward differences of the loads.
    pub fn state_jacobian(
        &self,
        ws: &mut Workspace,
        work: &mut StateJacobian,
        t: f64,
        y: &[f64],
        jac: &mut [f64],
    ) -> Result<(), DynamicsError> {
        let nv = self.states.nv;
        let n = 2 * nv;
        self.rhs(ws, t, y, &mut work.dy)?;
        let (q, u) = y.split_at(nv);
        self.aba_derivatives(ws, &mut work.derivatives, q, u, &work.dy[nv..])?;
        jac.fill(0.0);
        let d = &work.derivatives;
        for i in 0..nv {
            jac[i * n + nv + i] = 1.0;
            let row = &mut jac[(nv + i) * n..(nv + i + 1) * n];
            row[..nv].copy_from_slice(&d.ddq_dq()[i * nv..(i + 1) * nv]);
            row[nv..].copy_from_slice(&d.ddq_dv()[i * nv..(i + 1) * nv]);
        }
        if work.load_jacobian.is_empty() {
            return Ok(());
        }
        self.generalized_forces(ws, t, q, u, &mut work.loads)?;
        work.y.copy_from_slice(y);
        for (j, &yj) in y.iter().enumerate().take(n) {
            work.y[j] = yj + (f64::EPSILON * yj.abs().max(1e-5)).sqrt();
            let delta = work.y[j] - yj;
            let (q, u) = work.y.split_at(nv);
            self.generalized_forces(ws, t, q, u, &mut work.moved)?;
            work.y[j] = yj;
            for i in 0..nv {
                work.load_jacobian[i * n + j] = (work.moved[i] - work.loads[i]) / delta;
            }
        }
        let minv = work.derivatives.minv();
        for i in 0..nv {
            for k in 0..nv {
                let m = minv[i * nv + k];
                if m != 0.0 {
                    let (row, dq) = (&mut jac[(nv + i) * n..(nv + i + 1) * n], &work.load_jacobian[k * n..(k + 1) * n]);
                    for (r, x) in row.iter_mut().zip(dq) {
                        *r += m * x;
                    }
                }
            }
        }
        Ok(())
    }
}
