//! A signal input given by a formula of time in the model's equations
//! (`prescribed.r_x = sin(time)`): a source block the assembly adds for
//! each such equation, not a kind users name.

use super::OUTPUT;
use crate::components::spec::ComponentSpec;
use crate::components::{Component, EvalContext, Part, SignalLaw, SignalSource, VarSpec};
use crate::math::expr::TimeFunction;
use crate::Error;

pub static SPEC: ComponentSpec = ComponentSpec {
    kind: "Equation",
    doc: "A signal input's formula of time, from the model's equations.",
    params: &[],
    connectors: &OUTPUT,
    variables: &[],
    build: |_| {
        Err(Error::Unsupported {
            component: "Equation".into(),
            what: "an equation block by name".into(),
            fix: "write the formula as an equation: `component.input = formula`".into(),
        })
    },
    shapes: crate::components::shapes::none,
};

#[derive(Debug)]
pub struct EquationBlock {
    pub formula: TimeFunction,
}

impl Component for EquationBlock {
    fn parts(&self) -> Vec<Part> {
        vec![Part::Signal {
            output: 0,
            law: SignalLaw::Source(SignalSource::Formula(self.formula.clone())),
            inputs: [None; 3],
            frames: [None; 2],
            flanges: [None; 2],
        }]
    }

    fn variables(&self) -> Vec<VarSpec> {
        Vec::new()
    }

    fn evaluate(&self, _: &EvalContext, _: &mut Vec<f64>) {}
}
