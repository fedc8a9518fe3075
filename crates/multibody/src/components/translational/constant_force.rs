//! TranslationalComponents.ConstantForce: a constant driving force.

use crate::components::one_d::Element1D;
use crate::components::spec::{ComponentSpec, ConnectorSpec, ConnectorType, ParamSpec, ParamType, VarSpec};
use crate::components::{Component, Law1D, ParamSet};
use crate::Error;

pub static SPEC: ComponentSpec = ComponentSpec {
    kind: "TranslationalComponents.ConstantForce",
    doc: "Constant force f_constant driving flange relative to support (if negative, the force acts as a load).",
    params: &[ParamSpec::required("f_constant", ParamType::Real, "N", "Constant force")],
    connectors: &[
        ConnectorSpec::flange("flange", ConnectorType::Flange, "Driven flange"),
        ConnectorSpec::flange("support", ConnectorType::Flange, "Support flange (reaction)"),
    ],
    variables: &[
        VarSpec::scalar("s", "m", "Position of flange with respect to support"),
        VarSpec::scalar("v", "m/s", "Velocity of flange with respect to support (= der(s))"),
        VarSpec::scalar("f", "N", "Accelerating force acting at flange"),
    ],
    build,
    shapes: crate::components::shapes::none,
};

fn build(p: &ParamSet) -> Result<Box<dyn Component>, Error> {
    Ok(Box::new(Element1D {
        law: Law1D::Source { value: p.real("f_constant") },
        a: 1,
        b: 0,
        variables: SPEC.variables,
    }))
}
