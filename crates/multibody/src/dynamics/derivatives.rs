//! The derivatives of the forward dynamics: the interface linearization
//! uses. Placeholder until the analytic derivatives land: it reports them
//! unavailable, so linearization takes differences everywhere.

use super::{DynamicsError, Workspace};
use crate::system::System;

/// Scratch and results of the derivatives, allocated once for a system.
pub struct DynamicsDerivatives {
    empty: Vec<f64>,
}

impl DynamicsDerivatives {
    pub fn ddq_dq(&self) -> &[f64] {
        &self.empty
    }
    pub fn ddq_dv(&self) -> &[f64] {
        &self.empty
    }
    pub fn minv(&self) -> &[f64] {
        &self.empty
    }
}

impl System {
    /// Why the analytic derivatives do not apply to this system.
    pub fn derivatives_unsupported(&self) -> Option<String> {
        Some("the analytic derivatives are not built yet".into())
    }
    pub fn derivatives_work(&self) -> DynamicsDerivatives {
        DynamicsDerivatives { empty: Vec::new() }
    }
    pub fn aba_derivatives(
        &self,
        _ws: &mut Workspace,
        _d: &mut DynamicsDerivatives,
        _q: &[f64],
        _u: &[f64],
        _ud: &[f64],
    ) -> Result<(), DynamicsError> {
        Err(DynamicsError::NotFinite)
    }
    pub fn generalized_forces(
        &self,
        _ws: &mut Workspace,
        _t: f64,
        _q: &[f64],
        _u: &[f64],
        _out: &mut [f64],
    ) -> Result<(), DynamicsError> {
        Err(DynamicsError::NotFinite)
    }
}
