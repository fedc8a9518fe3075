//! The rigid 1-D bodies: RotationalComponents.Inertia and
//! TranslationalComponents.Mass. Each moves its two flanges together; with
//! nothing else to move it, its angle (position) and speed are states,
//! otherwise it turns with what drives it (a joint's axis, through gears)
//! and adds its reflected inertia there.

use crate::components::spec::{ComponentSpec, ConnectorSpec, ConnectorType, ParamSpec, ParamType, VarSpec};
use crate::components::{Component, EvalContext, ParamSet, Part, StateNames};
use crate::Error;

pub static INERTIA: ComponentSpec = ComponentSpec {
    kind: "RotationalComponents.Inertia",
    doc: "A rotating body with moment of inertia J between two splines: J * a = spline_a.tau + spline_b.tau.",
    params: &[ParamSpec::required("J", ParamType::Real, "kg.m2", "Moment of inertia")],
    connectors: &[
        ConnectorSpec::flange("spline_a", ConnectorType::Spline, "First spline"),
        ConnectorSpec::flange("spline_b", ConnectorType::Spline, "Second spline"),
    ],
    variables: &[
        VarSpec::scalar("phi", "rad", "Absolute rotation angle"),
        VarSpec::scalar("w", "rad/s", "Absolute angular velocity"),
        VarSpec::scalar("a", "rad/s2", "Absolute angular acceleration"),
    ],
    build: |p: &ParamSet| -> Result<Box<dyn Component>, Error> {
        let inertia = p.non_negative("J", true)?;
        Ok(Box::new(RigidBody1D { inertia, length: 0.0, weight: 0.0, states: ROTATION, variables: INERTIA.variables }))
    },
    shapes: crate::components::shapes::none,
};

pub static MASS: ComponentSpec = ComponentSpec {
    kind: "TranslationalComponents.Mass",
    doc: "A sliding mass m of length L between two flanges (flange_a at s - L/2, flange_b at s + L/2): \
          m * (a + g * sin(theta)) = flange_a.f + flange_b.f.",
    params: &[
        ParamSpec::required("m", ParamType::Real, "kg", "Mass of the sliding body"),
        ParamSpec::real("L", 0.0, "m", "Length, from flange_a to flange_b"),
        ParamSpec::real("g", -9.80665, "m/s2", "Gravity acceleration, acting through sin(theta)"),
        ParamSpec::real("theta", 0.0, "rad", "Inclination of the path (0: horizontal)"),
    ],
    connectors: &[
        ConnectorSpec::flange("flange_a", ConnectorType::Flange, "Left flange"),
        ConnectorSpec::flange("flange_b", ConnectorType::Flange, "Right flange"),
    ],
    variables: &[
        VarSpec::scalar("s", "m", "Absolute position of the centre"),
        VarSpec::scalar("v", "m/s", "Absolute velocity"),
        VarSpec::scalar("a", "m/s2", "Absolute acceleration"),
    ],
    build: |p: &ParamSet| -> Result<Box<dyn Component>, Error> {
        let m = p.non_negative("m", true)?;
        let weight = -m * p.real("g") * p.real("theta").sin();
        Ok(Box::new(RigidBody1D {
            inertia: m,
            length: p.real("L"),
            weight,
            states: TRANSLATION,
            variables: MASS.variables,
        }))
    },
    shapes: crate::components::shapes::none,
};

const ROTATION: StateNames = StateNames { q: &[("phi", 1)], u: &[("w", 1)] };
const TRANSLATION: StateNames = StateNames { q: &[("s", 1)], u: &[("v", 1)] };

#[derive(Debug)]
struct RigidBody1D {
    inertia: f64,
    length: f64,
    weight: f64,
    states: StateNames,
    variables: &'static [VarSpec],
}

impl Component for RigidBody1D {
    fn parts(&self) -> Vec<Part> {
        vec![Part::Inertia1D {
            a: 0,
            b: 1,
            length: self.length,
            inertia: self.inertia,
            weight: self.weight,
            states: self.states,
        }]
    }

    fn variables(&self) -> Vec<VarSpec> {
        self.variables.to_vec()
    }

    fn evaluate(&self, ctx: &EvalContext, out: &mut Vec<f64>) {
        let a = ctx.flanges[0];
        out.extend([a.s + self.length / 2.0, a.v, a.a]);
    }
}
