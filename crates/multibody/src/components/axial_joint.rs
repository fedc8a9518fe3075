//! What Revolute and Prismatic share: one coordinate along or about an axis,
//! with a 1-D `axis` flange that follows it and a `support` flange that stays
//! with frame_a.

use super::spec::VarSpec;
use super::{AxisFlanges, Component, EvalContext, Part, StateNames};
use crate::dynamics::joint::JointModel;

/// Connector numbers shared by both kinds: frame_a, frame_b, axis, support.
pub const FLANGES: AxisFlanges = AxisFlanges { axis: 2, support: 3 };

#[derive(Debug)]
pub struct AxialJoint {
    pub model: JointModel,
    pub states: StateNames,
    /// Position, velocity, acceleration and drive force, in that order.
    pub variables: &'static [VarSpec],
}

impl Component for AxialJoint {
    fn parts(&self) -> Vec<Part> {
        vec![Part::Joint { a: 0, b: 1, model: self.model, states: self.states, flanges: Some(FLANGES) }]
    }

    fn variables(&self) -> Vec<VarSpec> {
        self.variables.to_vec()
    }

    fn evaluate(&self, ctx: &EvalContext, out: &mut Vec<f64>) {
        let j = &ctx.joints[0];
        out.extend([j.q[0], j.u[0], j.udot[0], j.tau[0]]);
    }
}
