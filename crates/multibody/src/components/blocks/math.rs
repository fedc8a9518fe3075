//! BlockComponents math blocks: Gain, Add, Add3 and Feedback (affine in
//! their inputs), Product and Division. They feed through: a loop of them
//! is an algebraic loop, which assembly reports.

use crate::components::spec::{ComponentSpec, ConnectorSpec, ParamSpec, VarSpec};
use crate::components::{Component, EvalContext, ParamSet, Part, SignalLaw};
use crate::Error;

/// `y = bias + sum gains[k] * u_k`, with inputs at connectors `0..n` and
/// the output at connector `n`.
#[derive(Debug)]
struct Affine {
    gains: [f64; 3],
    bias: f64,
    inputs: usize,
}

impl Component for Affine {
    fn parts(&self) -> Vec<Part> {
        let mut inputs = [None; 3];
        for (k, input) in inputs.iter_mut().enumerate().take(self.inputs) {
            *input = Some(k);
        }
        let law = SignalLaw::Affine { gains: self.gains, bias: self.bias };
        vec![Part::Signal { output: self.inputs, law, inputs, frames: [None; 2], flanges: [None; 2] }]
    }

    fn variables(&self) -> Vec<VarSpec> {
        vec![VarSpec::scalar("y", "", "The output signal")]
    }

    fn evaluate(&self, ctx: &EvalContext, out: &mut Vec<f64>) {
        out.push(ctx.signals[self.inputs]);
    }
}

const Y: ConnectorSpec = ConnectorSpec::output("y", "The output signal");
const VARIABLES: [VarSpec; 1] = [VarSpec::scalar("y", "", "The output signal")];

pub static GAIN: ComponentSpec = ComponentSpec {
    kind: "BlockComponents.Gain",
    doc: "Output the input times a gain: y = k * u.",
    params: &[ParamSpec::real("k", 1.0, "", "The gain")],
    connectors: &[ConnectorSpec::input("u", "The input signal"), Y],
    variables: &VARIABLES,
    build: |p: &ParamSet| -> Result<Box<dyn Component>, Error> {
        Ok(Box::new(Affine { gains: [p.real("k"), 0.0, 0.0], bias: 0.0, inputs: 1 }))
    },
    shapes: crate::components::shapes::none,
};

pub static ADD: ComponentSpec = ComponentSpec {
    kind: "BlockComponents.Add",
    doc: "Output the weighted sum of two inputs: y = k1 * u1 + k2 * u2.",
    params: &[ParamSpec::real("k1", 1.0, "", "Gain of u1"), ParamSpec::real("k2", 1.0, "", "Gain of u2")],
    connectors: &[ConnectorSpec::input("u1", "First input"), ConnectorSpec::input("u2", "Second input"), Y],
    variables: &VARIABLES,
    build: |p: &ParamSet| -> Result<Box<dyn Component>, Error> {
        Ok(Box::new(Affine { gains: [p.real("k1"), p.real("k2"), 0.0], bias: 0.0, inputs: 2 }))
    },
    shapes: crate::components::shapes::none,
};

pub static FEEDBACK: ComponentSpec = ComponentSpec {
    kind: "BlockComponents.Feedback",
    doc: "Output the difference of a command and a feedback: y = u1 - u2.",
    params: &[],
    connectors: &[ConnectorSpec::input("u1", "The command"), ConnectorSpec::input("u2", "The feedback"), Y],
    variables: &VARIABLES,
    build: |_: &ParamSet| -> Result<Box<dyn Component>, Error> {
        Ok(Box::new(Affine { gains: [1.0, -1.0, 0.0], bias: 0.0, inputs: 2 }))
    },
    shapes: crate::components::shapes::none,
};

pub static ADD3: ComponentSpec = ComponentSpec {
    kind: "BlockComponents.Add3",
    doc: "Output the weighted sum of three inputs: y = k1 * u1 + k2 * u2 + k3 * u3.",
    params: &[
        ParamSpec::real("k1", 1.0, "", "Gain of u1"),
        ParamSpec::real("k2", 1.0, "", "Gain of u2"),
        ParamSpec::real("k3", 1.0, "", "Gain of u3"),
    ],
    connectors: &[
        ConnectorSpec::input("u1", "First input"),
        ConnectorSpec::input("u2", "Second input"),
        ConnectorSpec::input("u3", "Third input"),
        Y,
    ],
    variables: &VARIABLES,
    build: |p: &ParamSet| -> Result<Box<dyn Component>, Error> {
        Ok(Box::new(Affine { gains: [p.real("k1"), p.real("k2"), p.real("k3")], bias: 0.0, inputs: 3 }))
    },
    shapes: crate::components::shapes::none,
};

/// `y = u1 * u2` or `y = u1 / u2`.
#[derive(Debug)]
struct TwoInputs {
    law: SignalLaw,
}

impl Component for TwoInputs {
    fn parts(&self) -> Vec<Part> {
        let inputs = [Some(0), Some(1), None];
        vec![Part::Signal { output: 2, law: self.law.clone(), inputs, frames: [None; 2], flanges: [None; 2] }]
    }

    fn variables(&self) -> Vec<VarSpec> {
        VARIABLES.to_vec()
    }

    fn evaluate(&self, ctx: &EvalContext, out: &mut Vec<f64>) {
        out.push(ctx.signals[2]);
    }
}

pub static PRODUCT: ComponentSpec = ComponentSpec {
    kind: "BlockComponents.Product",
    doc: "Output the product of two inputs: y = u1 * u2.",
    params: &[],
    connectors: &[ConnectorSpec::input("u1", "First factor"), ConnectorSpec::input("u2", "Second factor"), Y],
    variables: &VARIABLES,
    build: |_: &ParamSet| -> Result<Box<dyn Component>, Error> { Ok(Box::new(TwoInputs { law: SignalLaw::Product })) },
    shapes: crate::components::shapes::none,
};

pub static DIVISION: ComponentSpec = ComponentSpec {
    kind: "BlockComponents.Division",
    doc: "Output the quotient of two inputs: y = u1 / u2.",
    params: &[],
    connectors: &[ConnectorSpec::input("u1", "The dividend"), ConnectorSpec::input("u2", "The divisor"), Y],
    variables: &VARIABLES,
    build: |_: &ParamSet| -> Result<Box<dyn Component>, Error> { Ok(Box::new(TwoInputs { law: SignalLaw::Division })) },
    shapes: crate::components::shapes::none,
};
