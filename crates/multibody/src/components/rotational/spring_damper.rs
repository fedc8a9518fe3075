//! RotationalComponents.SpringDamper: linear spring and damper in parallel.

use crate::components::one_d::Element1D;
use crate::components::spec::{ComponentSpec, ConnectorSpec, ConnectorType, ParamSpec, ParamType, VarSpec};
use crate::components::{Component, Law1D, ParamSet};
use crate::Error;

pub static SPEC: ComponentSpec = ComponentSpec {
    kind: "RotationalComponents.SpringDamper",
    doc: "Linear rotational spring and damper in parallel: tau = c * (phi_rel - phi_rel0) + d * w_rel.",
    params: &[
        ParamSpec::required("d", ParamType::Real, "N.m.s/rad", "Damping constant"),
        ParamSpec::required("c", ParamType::Real, "N.m/rad", "Spring constant"),
        ParamSpec::real("phi_rel0", 0.0, "rad", "Unstretched spring angle"),
    ],
    connectors: &[
        ConnectorSpec::flange("spline_a", ConnectorType::Spline, "First spline"),
        ConnectorSpec::flange("spline_b", ConnectorType::Spline, "Second spline"),
    ],
    variables: &[
        VarSpec::scalar("phi_rel", "rad", "Relative rotation angle between spline_b and spline_a"),
        VarSpec::scalar("w_rel", "rad/s", "Relative angular velocity between splines"),
        VarSpec::scalar("a_rel", "rad/s2", "Relative angular acceleration between splines"),
        VarSpec::scalar("tau", "N.m", "Torque transmitted between the splines"),
        VarSpec::scalar("tau_c", "N.m", "Spring torque"),
        VarSpec::scalar("tau_d", "N.m", "Damper torque"),
    ],
    build,
    shapes: crate::components::shapes::none,
};

fn build(p: &ParamSet) -> Result<Box<dyn Component>, Error> {
    let law = Law1D::SpringDamper { c: p.real("c"), d: p.real("d"), s_rel0: p.real("phi_rel0") };
    Ok(Box::new(Element1D { law, a: 0, b: 1, variables: SPEC.variables }))
}
