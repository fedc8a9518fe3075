//! RotationalComponents.Spring: linear rotational spring.

use crate::components::one_d::Element1D;
use crate::components::spec::{ComponentSpec, ConnectorSpec, ConnectorType, ParamSpec, ParamType, VarSpec};
use crate::components::{Component, Law1D, ParamSet};
use crate::Error;

pub static SPEC: ComponentSpec = ComponentSpec {
    kind: "RotationalComponents.Spring",
    doc: "Linear rotational spring between two splines: tau = c * (phi_rel - phi_rel0).",
    params: &[
        ParamSpec::required("c", ParamType::Real, "N.m/rad", "Spring constant"),
        ParamSpec::real("phi_rel0", 0.0, "rad", "Unstretched spring angle"),
    ],
    connectors: &[
        ConnectorSpec::flange("spline_a", ConnectorType::Spline, "First spline"),
        ConnectorSpec::flange("spline_b", ConnectorType::Spline, "Second spline"),
    ],
    variables: &[
        VarSpec::scalar("phi_rel", "rad", "Relative rotation angle between spline_b and spline_a"),
        VarSpec::scalar("tau", "N.m", "Torque transmitted between the splines"),
    ],
    build,
    shapes: crate::components::shapes::none,
};

fn build(p: &ParamSet) -> Result<Box<dyn Component>, Error> {
    let law = Law1D::Spring { c: p.real("c"), s_rel0: p.real("phi_rel0") };
    Ok(Box::new(Element1D { law, a: 0, b: 1, variables: SPEC.variables }))
}
