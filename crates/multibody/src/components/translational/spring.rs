//! TranslationalComponents.Spring: linear translational spring.

use crate::components::one_d::Element1D;
use crate::components::spec::{ComponentSpec, ConnectorSpec, ConnectorType, ParamSpec, ParamType, VarSpec};
use crate::components::{Component, Law1D, ParamSet};
use crate::Error;

pub static SPEC: ComponentSpec = ComponentSpec {
    kind: "TranslationalComponents.Spring",
    doc: "Linear translational spring between two flanges: f = c * (s_rel - s_rel0).",
    params: &[
        ParamSpec::required("c", ParamType::Real, "N/m", "Spring constant"),
        ParamSpec::real("s_rel0", 0.0, "m", "Unstretched spring length"),
    ],
    connectors: &[
        ConnectorSpec::flange("flange_a", ConnectorType::Flange, "First flange"),
        ConnectorSpec::flange("flange_b", ConnectorType::Flange, "Second flange"),
    ],
    variables: &[
        VarSpec::scalar("s_rel", "m", "Relative displacement between flange_b and flange_a"),
        VarSpec::scalar("f", "N", "Force transmitted between the flanges"),
    ],
    build,
    shapes: crate::components::shapes::none,
};

fn build(p: &ParamSet) -> Result<Box<dyn Component>, Error> {
    let law = Law1D::Spring { c: p.real("c"), s_rel0: p.real("s_rel0") };
    Ok(Box::new(Element1D { law, a: 0, b: 1, variables: SPEC.variables }))
}
