//! Input: a signal the host sets while the model runs (a Python
//! controller, a table given on the command line, an FMU's importer). A
//! model file's top-level `RealInput` becomes one, named like it.

use super::OUTPUT;
use crate::components::spec::VarSpec;
use crate::components::spec::{ComponentSpec, ParamSpec};
use crate::components::{Component, EvalContext, ParamSet, Part, SignalLaw};
use crate::Error;

pub static SPEC: ComponentSpec = ComponentSpec {
    kind: "Input",
    doc: "An input of the model: a signal y that the host sets while the model runs (Simulator::set_input, \
          --input NAME=table.csv); it holds `start` until set.",
    params: &[ParamSpec::real("start", 0.0, "", "The value before the host sets one")],
    connectors: &OUTPUT,
    variables: &VALUE,
    build,
    shapes: crate::components::shapes::none,
};

/// The input's value, named as the input itself (`u`, not `u.y`): the
/// variable without a name is the component's own value.
const VALUE: [VarSpec; 1] = [VarSpec::scalar("", "", "The input's value")];

#[derive(Debug)]
struct Input {
    start: f64,
}

fn build(p: &ParamSet) -> Result<Box<dyn Component>, Error> {
    Ok(Box::new(Input { start: p.real("start") }))
}

impl Component for Input {
    fn parts(&self) -> Vec<Part> {
        // Assembly numbers the inputs of the model in component order.
        vec![Part::Signal {
            output: 0,
            law: SignalLaw::Input { index: 0, start: self.start },
            inputs: [None; 3],
            frames: [None; 2],
            flanges: [None; 2],
        }]
    }

    fn variables(&self) -> Vec<crate::components::spec::VarSpec> {
        VALUE.to_vec()
    }

    fn evaluate(&self, ctx: &EvalContext, out: &mut Vec<f64>) {
        out.push(ctx.signals[0]);
    }
}
