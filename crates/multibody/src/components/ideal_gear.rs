//! RotationalComponents.IdealGear: a lossless gear between two splines,
//! `phi_a = ratio * phi_b` relative to the housing (support). On joint axes
//! it is a coupling of the joints' coordinates, kept by a constraint force;
//! an unconnected support is a housing fixed in the world. IdealGearR2T
//! (rack and pinion) is the same relation between a rotation and a
//! translation.

use crate::components::spec::{ComponentSpec, ConnectorSpec, ConnectorType, ParamSpec, ParamType, VarSpec};
use crate::components::{Component, EvalContext, ParamSet, Part};
use crate::Error;

pub static SPEC: ComponentSpec = ComponentSpec {
    kind: "RotationalComponents.IdealGear",
    doc: "Ideal gear with a housing: phi_a = ratio * phi_b (angles relative to the support), \
          ratio * tau_a + tau_b = 0.",
    params: &[ParamSpec::required("ratio", ParamType::Real, "", "Transmission ratio phi_a / phi_b")],
    connectors: &[
        ConnectorSpec::flange("spline_a", ConnectorType::Spline, "Driving shaft"),
        ConnectorSpec::flange("spline_b", ConnectorType::Spline, "Driven shaft"),
        ConnectorSpec::flange("support", ConnectorType::Spline, "Housing (fixed when unconnected)"),
    ],
    variables: &[
        VarSpec::scalar("phi_a", "rad", "Angle of spline_a relative to the support"),
        VarSpec::scalar("phi_b", "rad", "Angle of spline_b relative to the support"),
        VarSpec::scalar("phi_support", "rad", "Absolute angle of the support"),
    ],
    build,
    shapes: crate::components::shapes::none,
};

#[derive(Debug)]
struct IdealGear {
    ratio: f64,
}

fn build(p: &ParamSet) -> Result<Box<dyn Component>, Error> {
    Ok(Box::new(IdealGear { ratio: ratio(p)? }))
}

/// The `ratio` parameter of a gear: finite and not zero.
pub fn ratio(p: &ParamSet) -> Result<f64, Error> {
    let ratio = p.real("ratio");
    if ratio == 0.0 || !ratio.is_finite() {
        return Err(p.invalid("ratio", "a gear ratio must be a finite number other than 0"));
    }
    Ok(ratio)
}

impl Component for IdealGear {
    fn parts(&self) -> Vec<Part> {
        // phi_a - phi_s = ratio (phi_b - phi_s)
        vec![
            Part::Coupling {
                terms: vec![(0, 1.0), (1, -self.ratio), (2, self.ratio - 1.0)],
                constant: 0.0,
                measured: false,
            },
            Part::Housing { flange: 2 },
        ]
    }

    fn variables(&self) -> Vec<VarSpec> {
        SPEC.variables.to_vec()
    }

    fn evaluate(&self, ctx: &EvalContext, out: &mut Vec<f64>) {
        let support = ctx.flanges[2].s;
        out.extend([ctx.flanges[0].s - support, ctx.flanges[1].s - support, support]);
    }
}

pub static R2T: ComponentSpec = ComponentSpec {
    kind: "RotationalComponents.IdealGearR2T",
    doc: "Ideal gear from rotation to translation (a pinion on a rack): spline.phi - support_r.phi = \
          ratio * (flange.s - support_t.s), ratio * spline.tau + flange.f = 0. Also found as \
          TranslationalComponents.IdealGearR2T.",
    params: &[ParamSpec::required("ratio", ParamType::Real, "rad/m", "Angle turned per length travelled")],
    connectors: &[
        ConnectorSpec::flange("spline", ConnectorType::Spline, "Rotational shaft (the pinion)"),
        ConnectorSpec::flange("flange", ConnectorType::Flange, "Translational shaft (the rack)"),
        ConnectorSpec::flange("support_r", ConnectorType::Spline, "Rotational housing (fixed when unconnected)"),
        ConnectorSpec::flange("support_t", ConnectorType::Flange, "Translational housing (fixed when unconnected)"),
    ],
    variables: &[],
    build: |p: &ParamSet| -> Result<Box<dyn Component>, Error> { Ok(Box::new(RackAndPinion { ratio: ratio(p)? })) },
    shapes: crate::components::shapes::none,
};

#[derive(Debug)]
struct RackAndPinion {
    ratio: f64,
}

impl Component for RackAndPinion {
    fn parts(&self) -> Vec<Part> {
        vec![
            Part::Coupling {
                terms: vec![(0, 1.0), (2, -1.0), (1, -self.ratio), (3, self.ratio)],
                constant: 0.0,
                measured: false,
            },
            Part::Housing { flange: 2 },
            Part::Housing { flange: 3 },
        ]
    }
}
