//! TranslationalComponents.SpringDamper: linear spring and damper in parallel.

use crate::components::one_d::Element1D;
use crate::components::spec::{ComponentSpec, ConnectorSpec, ConnectorType, ParamSpec, ParamType, VarSpec};
use crate::components::{Component, Law1D, ParamSet};
use crate::Error;

pub static SPEC: ComponentSpec = ComponentSpec {
    kind: "TranslationalComponents.SpringDamper",
    doc: "Linear translational spring and damper in parallel: f = c * (s_rel - s_rel0) + d * v_rel.",
    params: &[
        ParamSpec::required("d", ParamType::Real, "N.s/m", "Damping constant"),
        ParamSpec::required("c", ParamType::Real, "N/m", "Spring constant"),
        ParamSpec::real("s_rel0", 0.0, "m", "Unstretched spring length"),
    ],
    connectors: &[
        ConnectorSpec::flange("flange_a", ConnectorType::Flange, "First flange"),
        ConnectorSpec::flange("flange_b", ConnectorType::Flange, "Second flange"),
    ],
    variables: &[
        VarSpec::scalar("s_rel", "m", "Relative displacement between flange_b and flange_a"),
        VarSpec::scalar("v_rel", "m/s", "Relative velocity between flanges"),
        VarSpec::scalar("a_rel", "m/s2", "Relative acceleration between flanges"),
        VarSpec::scalar("f", "N", "Force transmitted between the flanges"),
        VarSpec::scalar("f_c", "N", "Spring force"),
        VarSpec::scalar("f_d", "N", "Damper force"),
    ],
    build,
    shapes: crate::components::shapes::none,
};

fn build(p: &ParamSet) -> Result<Box<dyn Component>, Error> {
    let law = Law1D::SpringDamper { c: p.real("c"), d: p.real("d"), s_rel0: p.real("s_rel0") };
    Ok(Box::new(Element1D { law, a: 0, b: 1, variables: SPEC.variables }))
}
