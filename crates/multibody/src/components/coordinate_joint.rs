//! Joints whose coordinates are plain numbers (angles and distances):
//! Revolute, Prismatic, Universal, Cylindrical, Planar. Their variables are
//! the coordinates, then the rates, then the accelerations, and for the
//! 1-DOF joints the drive force of the elements on their axis.

use super::spec::VarSpec;
use super::{AxisFlanges, Component, EvalContext, Part, StateNames};
use crate::system::joint::JointModel;

/// Connector numbers of the 1-DOF joints' flanges: after frame_a, frame_b.
pub const FLANGES: AxisFlanges = AxisFlanges { axis: 2, support: 3 };

#[derive(Debug)]
pub struct CoordinateJoint {
    pub model: JointModel,
    pub states: StateNames,
    /// Coordinates, rates, accelerations (and the drive force with flanges).
    pub variables: &'static [VarSpec],
    pub flanges: Option<AxisFlanges>,
    /// Prefer cutting this joint when it closes a loop.
    pub iscut: bool,
}

impl Component for CoordinateJoint {
    fn parts(&self) -> Vec<Part> {
        vec![Part::Joint {
            a: 0,
            b: 1,
            model: self.model,
            states: self.states,
            flanges: self.flanges,
            iscut: self.iscut,
        }]
    }

    fn variables(&self) -> Vec<VarSpec> {
        self.variables.to_vec()
    }

    fn evaluate(&self, ctx: &EvalContext, out: &mut Vec<f64>) {
        let j = &ctx.joints[0];
        out.extend_from_slice(j.q);
        out.extend_from_slice(j.u);
        out.extend_from_slice(j.udot);
        if self.flanges.is_some() {
            out.push(j.tau[0]);
        }
    }
}
