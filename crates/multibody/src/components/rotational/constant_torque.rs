//! RotationalComponents.ConstantTorque: a constant driving torque.

use crate::components::one_d::Element1D;
use crate::components::spec::{ComponentSpec, ConnectorSpec, ConnectorType, ParamSpec, ParamType, VarSpec};
use crate::components::{Component, Law1D, ParamSet};
use crate::Error;

pub static SPEC: ComponentSpec = ComponentSpec {
    kind: "RotationalComponents.ConstantTorque",
    doc: "Constant torque tau_constant driving spline relative to support (if negative, the torque acts as a load).",
    params: &[ParamSpec::required("tau_constant", ParamType::Real, "N.m", "Constant torque")],
    connectors: &[
        ConnectorSpec::flange("spline", ConnectorType::Spline, "Driven spline"),
        ConnectorSpec::flange("support", ConnectorType::Spline, "Support spline (reaction)"),
    ],
    variables: &[
        VarSpec::scalar("phi", "rad", "Angle of spline with respect to support"),
        VarSpec::scalar("w", "rad/s", "Angular velocity of spline with respect to support (= der(phi))"),
        VarSpec::scalar("tau", "N.m", "Accelerating torque acting at spline"),
    ],
    build,
    shapes: crate::components::shapes::none,
};

fn build(p: &ParamSet) -> Result<Box<dyn Component>, Error> {
    Ok(Box::new(Element1D {
        law: Law1D::Source { value: p.real("tau_constant") },
        a: 1,
        b: 0,
        variables: SPEC.variables,
    }))
}
