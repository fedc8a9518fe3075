//! Dyad's BlockComponents sources: signals of time on an output `y`.

pub mod constant;
pub mod equation;
pub mod input;
pub mod math;
pub mod ramp;
pub mod sine;
pub mod step;
pub mod time_table;
pub mod trajectories;

use super::spec::{ConnectorSpec, ParamSpec, VarSpec};
use super::{Component, EvalContext, Part, SignalLaw, SignalSource};

pub const OUTPUT: [ConnectorSpec; 1] = [ConnectorSpec::output("y", "The signal")];
pub const VARIABLES: [VarSpec; 1] = [VarSpec::scalar("y", "", "The signal")];
pub const START_TIME: ParamSpec =
    ParamSpec::real("start_time", 0.0, "s", "Time at which the signal starts changing from its offset value");
pub const OFFSET: ParamSpec = ParamSpec::real("offset", 0.0, "", "Constant value added to the signal output");

#[derive(Debug)]
pub struct SourceBlock {
    pub signal: SignalSource,
}

impl Component for SourceBlock {
    fn parts(&self) -> Vec<Part> {
        vec![Part::Signal {
            output: 0,
            law: SignalLaw::Source(self.signal.clone()),
            inputs: [None; 3],
            frames: [None; 2],
            flanges: [None; 2],
        }]
    }

    fn variables(&self) -> Vec<VarSpec> {
        VARIABLES.to_vec()
    }

    fn evaluate(&self, ctx: &EvalContext, out: &mut Vec<f64>) {
        out.push(self.signal.value(ctx.time));
    }
}
