//! TranslationalComponents.Damper: linear translational damper.

use crate::components::one_d::Element1D;
use crate::components::spec::{ComponentSpec, ConnectorSpec, ConnectorType, ParamSpec, ParamType, VarSpec};
use crate::components::{Component, Law1D, ParamSet};
use crate::Error;

pub static SPEC: ComponentSpec = ComponentSpec {
    kind: "TranslationalComponents.Damper",
    doc: "Linear translational damper between two flanges: f = d * v_rel.",
    params: &[ParamSpec::required(
        "d",
        ParamType::Real,
        "N.s/m",
        "Damping coefficient, relating force to relative velocity",
    )],
    connectors: &[
        ConnectorSpec::flange("flange_a", ConnectorType::Flange, "First flange"),
        ConnectorSpec::flange("flange_b", ConnectorType::Flange, "Second flange"),
    ],
    variables: &[
        VarSpec::scalar("s_rel", "m", "Relative displacement between flange_b and flange_a"),
        VarSpec::scalar("v_rel", "m/s", "Relative velocity between flanges"),
        VarSpec::scalar("a_rel", "m/s2", "Relative acceleration between flanges"),
        VarSpec::scalar("f", "N", "Force transmitted between the flanges"),
    ],
    build,
    shapes: crate::components::shapes::none,
};

fn build(p: &ParamSet) -> Result<Box<dyn Component>, Error> {
    Ok(Box::new(Element1D { law: Law1D::Damper { d: p.real("d") }, a: 0, b: 1, variables: SPEC.variables }))
}
