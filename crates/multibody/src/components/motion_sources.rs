//! Motion sources of the 1-D libraries: Position, Speed and Accelerate
//! (RotationalComponents and TranslationalComponents). They impose the
//! motion of their flange relative to the support from a signal; on a
//! joint's axis the joint becomes rheonomic (its coordinate follows the
//! signal whatever torque or force that takes).

use super::spec::{ComponentSpec, ConnectorSpec, ConnectorType, ParamSpec, VarSpec};
use super::{Component, DriveLevel, EvalContext, ParamSet, Part};
use crate::Error;

const EXACT: ParamSpec = ParamSpec::boolean(
    "exact",
    false,
    "Follow the reference exactly (it must be a signal of time); otherwise through a filter of cut-off f_crit",
);
const F_CRIT: ParamSpec =
    ParamSpec::real("f_crit", 50.0, "Hz", "Cut-off frequency of the filter the inexact source follows");

/// The names that differ between the rotational and translational libraries.
struct Words {
    flange: ConnectorSpec,
    support: ConnectorSpec,
    variables: [VarSpec; 3],
}

const ROTATIONAL: Words = Words {
    flange: ConnectorSpec::flange("spline", ConnectorType::Spline, "The driven spline"),
    support: ConnectorSpec::flange("support", ConnectorType::Spline, "Support (housing) the motion is measured from"),
    variables: [
        VarSpec::scalar("phi", "rad", "Angle of the spline relative to the support"),
        VarSpec::scalar("w", "rad/s", "Its angular velocity"),
        VarSpec::scalar("a", "rad/s2", "Its angular acceleration"),
    ],
};

const TRANSLATIONAL: Words = Words {
    flange: ConnectorSpec::flange("flange", ConnectorType::Flange, "The driven flange"),
    support: ConnectorSpec::flange("support", ConnectorType::Flange, "Support (housing) the motion is measured from"),
    variables: [
        VarSpec::scalar("s", "m", "Position of the flange relative to the support"),
        VarSpec::scalar("v", "m/s", "Its velocity"),
        VarSpec::scalar("a", "m/s2", "Its acceleration"),
    ],
};

pub static ROTATIONAL_POSITION: ComponentSpec = ComponentSpec {
    kind: "RotationalComponents.Position",
    doc: "Turns the spline to the angle phi_ref relative to the support: exactly (exact = true, phi_ref a signal \
          of time), or through a critically damped second-order filter of cut-off f_crit.",
    params: &[EXACT, F_CRIT],
    connectors: &[ROTATIONAL.flange, ROTATIONAL.support, ConnectorSpec::input("phi_ref", "Reference angle")],
    variables: &ROTATIONAL.variables,
    build: |p| position(p, &ROTATIONAL.variables),
    shapes: super::shapes::none,
};

pub static ROTATIONAL_SPEED: ComponentSpec = ComponentSpec {
    kind: "RotationalComponents.Speed",
    doc: "Turns the spline at the speed w_ref relative to the support: exactly (exact = true, w_ref a signal of \
          time), or through a first-order filter of cut-off f_crit. The angle integrates the speed.",
    params: &[EXACT, F_CRIT],
    connectors: &[ROTATIONAL.flange, ROTATIONAL.support, ConnectorSpec::input("w_ref", "Reference speed")],
    variables: &ROTATIONAL.variables,
    build: |p| speed(p, &ROTATIONAL.variables),
    shapes: super::shapes::none,
};

pub static ROTATIONAL_ACCELERATE: ComponentSpec = ComponentSpec {
    kind: "RotationalComponents.Accelerate",
    doc: "Turns the spline with the angular acceleration a_ref relative to the support (any signal); speed and \
          angle integrate it.",
    params: &[],
    connectors: &[ROTATIONAL.flange, ROTATIONAL.support, ConnectorSpec::input("a_ref", "Angular acceleration")],
    variables: &ROTATIONAL.variables,
    build: |_| Ok(source(DriveLevel::Acceleration, &ROTATIONAL.variables)),
    shapes: super::shapes::none,
};

pub static TRANSLATIONAL_POSITION: ComponentSpec = ComponentSpec {
    kind: "TranslationalComponents.Position",
    doc: "Moves the flange to s_ref relative to the support: exactly (exact = true, s_ref a signal of time), or \
          through a critically damped second-order filter of cut-off f_crit.",
    params: &[EXACT, F_CRIT],
    connectors: &[TRANSLATIONAL.flange, TRANSLATIONAL.support, ConnectorSpec::input("s_ref", "Reference position")],
    variables: &TRANSLATIONAL.variables,
    build: |p| position(p, &TRANSLATIONAL.variables),
    shapes: super::shapes::none,
};

pub static TRANSLATIONAL_SPEED: ComponentSpec = ComponentSpec {
    kind: "TranslationalComponents.Speed",
    doc: "Moves the flange at the speed v_ref relative to the support: exactly (exact = true, v_ref a signal of \
          time), or through a first-order filter of cut-off f_crit. The position integrates the speed.",
    params: &[EXACT, F_CRIT],
    connectors: &[TRANSLATIONAL.flange, TRANSLATIONAL.support, ConnectorSpec::input("v_ref", "Reference speed")],
    variables: &TRANSLATIONAL.variables,
    build: |p| speed(p, &TRANSLATIONAL.variables),
    shapes: super::shapes::none,
};

pub static TRANSLATIONAL_ACCELERATE: ComponentSpec = ComponentSpec {
    kind: "TranslationalComponents.Accelerate",
    doc: "Moves the flange with the acceleration a_ref relative to the support (any signal); speed and position \
          integrate it.",
    params: &[],
    connectors: &[TRANSLATIONAL.flange, TRANSLATIONAL.support, ConnectorSpec::input("a_ref", "Acceleration")],
    variables: &TRANSLATIONAL.variables,
    build: |_| Ok(source(DriveLevel::Acceleration, &TRANSLATIONAL.variables)),
    shapes: super::shapes::none,
};

/// The filter's cut-off as an angular frequency, checked.
fn w_crit(p: &ParamSet) -> Result<f64, Error> {
    let f = p.real("f_crit");
    if f.is_finite() && f > 0.0 {
        Ok(2.0 * std::f64::consts::PI * f)
    } else {
        Err(p.invalid("f_crit", "the filter's cut-off frequency must be positive"))
    }
}

type Variables = &'static [VarSpec; 3];

fn position(p: &ParamSet, variables: Variables) -> Result<Box<dyn Component>, Error> {
    let level =
        if p.boolean("exact") { DriveLevel::Position } else { DriveLevel::PositionFilter { w_crit: w_crit(p)? } };
    Ok(source(level, variables))
}

fn speed(p: &ParamSet, variables: Variables) -> Result<Box<dyn Component>, Error> {
    let level = if p.boolean("exact") { DriveLevel::Speed } else { DriveLevel::SpeedFilter { w_crit: w_crit(p)? } };
    Ok(source(level, variables))
}

fn source(level: DriveLevel, variables: Variables) -> Box<dyn Component> {
    Box::new(MotionSource { level, variables })
}

#[derive(Debug)]
struct MotionSource {
    level: DriveLevel,
    variables: Variables,
}

impl Component for MotionSource {
    fn parts(&self) -> Vec<Part> {
        vec![Part::AxisDrive { flange: 0, support: 1, input: 2, level: self.level }, Part::Housing { flange: 1 }]
    }

    fn variables(&self) -> Vec<VarSpec> {
        self.variables.to_vec()
    }

    fn evaluate(&self, ctx: &EvalContext, out: &mut Vec<f64>) {
        let (f, s) = (&ctx.flanges[0], &ctx.flanges[1]);
        out.extend([f.s - s.s, f.v - s.v, f.a - s.a]);
    }
}
