//! RotationalComponents.Damper: linear rotational damper.

use crate::components::one_d::Element1D;
use crate::components::spec::{ComponentSpec, ConnectorSpec, ConnectorType, ParamSpec, ParamType, VarSpec};
use crate::components::{Component, Law1D, ParamSet};
use crate::Error;

pub static SPEC: ComponentSpec = ComponentSpec {
    kind: "RotationalComponents.Damper",
    doc: "Linear rotational damper between two splines: tau = d * w_rel.",
    params: &[ParamSpec::required(
        "d",
        ParamType::Real,
        "N.m.s/rad",
        "Damping coefficient, relating torque to relative angular velocity",
    )],
    connectors: &[
        ConnectorSpec::flange("spline_a", ConnectorType::Spline, "First spline"),
        ConnectorSpec::flange("spline_b", ConnectorType::Spline, "Second spline"),
    ],
    variables: &[
        VarSpec::scalar("phi_rel", "rad", "Relative rotation angle between spline_b and spline_a"),
        VarSpec::scalar("w_rel", "rad/s", "Relative angular velocity between splines"),
        VarSpec::scalar("a_rel", "rad/s2", "Relative angular acceleration between splines"),
        VarSpec::scalar("tau", "N.m", "Torque transmitted between the splines"),
    ],
    build,
    shapes: crate::components::shapes::none,
};

fn build(p: &ParamSet) -> Result<Box<dyn Component>, Error> {
    Ok(Box::new(Element1D { law: Law1D::Damper { d: p.real("d") }, a: 0, b: 1, variables: SPEC.variables }))
}
