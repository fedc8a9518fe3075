//! Friction with modes in the 1-D libraries (Modelica's names and
//! parameters, which Dyad's libraries follow): `RotationalComponents.Clutch`,
//! `.Brake` and `.BearingFriction`, and `TranslationalComponents.Brake` and
//! `.SupportFriction`. Each slides with `cgeo fn mu(v)` (or a torque or
//! force table), sticks when the relative speed reaches zero and holds up to
//! `peak` times its sliding force at rest, as a constraint (see
//! [`crate::system::friction`]).

use super::spec::{ComponentSpec, ConnectorSpec, ConnectorType, Default, ParamSpec, ParamType, VarSpec};
use super::{Component, EvalContext, ParamSet, Part};
use crate::system::friction::FrictionLaw;
use crate::Error;

/// Which element, for its geometry and names.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Kind {
    /// Between two shafts, pressed by a signal.
    Clutch,
    /// Between a flange (both flanges are one) and the support, pressed by
    /// a signal.
    Brake,
    /// Between a flange and the support, always engaged.
    Bearing,
}

#[derive(Debug)]
struct FrictionElement {
    kind: Kind,
    law: FrictionLaw,
    /// The law's scale is `cgeo fn_max`; `fn` is reported without `cgeo`.
    cgeo: f64,
    variables: &'static [VarSpec],
}

const FLANGE_A: usize = 0;
const FLANGE_B: usize = 1;
/// The support of brakes and bearings; the clutch's third connector is its input.
const SUPPORT: usize = 2;

impl Component for FrictionElement {
    fn parts(&self) -> Vec<Part> {
        let law = self.law.clone();
        match self.kind {
            Kind::Clutch => vec![Part::Friction { a: FLANGE_A, b: FLANGE_B, law, normal: Some(2) }],
            Kind::Brake | Kind::Bearing => vec![
                // Both flanges are the one rubbing against the support.
                Part::Coupling { terms: vec![(FLANGE_A, 1.0), (FLANGE_B, -1.0)] },
                Part::Housing { flange: SUPPORT },
                Part::Friction { a: SUPPORT, b: FLANGE_A, law, normal: (self.kind == Kind::Brake).then_some(3) },
            ],
        }
    }

    fn variables(&self) -> Vec<VarSpec> {
        self.variables.to_vec()
    }

    fn evaluate(&self, ctx: &EvalContext, out: &mut Vec<f64>) {
        let st = &ctx.frictions[0];
        let v = &st.values;
        let truth = |b: bool| if b { 1.0 } else { 0.0 };
        for var in self.variables {
            out.push(match var.name {
                "phi_rel" | "s_rel" | "phi" | "s" => v.s_rel,
                "w_rel" | "v_rel" | "w" | "v" => v.v_rel,
                "a_rel" | "a" => v.a_rel,
                "tau" | "f" => v.force,
                "fn" => v.normal / self.cgeo,
                "tau0" | "f0" => v.f0,
                "tau0_max" | "f0_max" => v.f0_max,
                "sa" => v.sa,
                "mode" => st.mode,
                "startForward" => truth(st.start_forward),
                "startBackward" => truth(st.start_backward),
                "locked" => truth(v.locked),
                "free" => truth(v.free),
                "lossPower" => v.force * v.v_rel,
                _ => f64::NAN,
            });
        }
    }
}

/// The friction table of parameter `name` (`[v, mu]` rows, `v >= 0`
/// ascending), or `default` where the model gives none.
fn table(p: &ParamSet, name: &str, default: (f64, f64)) -> Result<Vec<(f64, f64)>, Error> {
    let rows = p.matrix(name);
    if rows.is_empty() {
        return Ok(vec![default]);
    }
    let table: Vec<(f64, f64)> = rows.iter().map(|r| (r[0], r[1])).collect();
    if table[0].0 < 0.0 || table.windows(2).any(|w| w[1].0 < w[0].0) {
        return Err(p.invalid(name, "its first column (the speed) must start at 0 or above and increase"));
    }
    if table.iter().any(|r| r.1 < 0.0) {
        return Err(p.invalid(name, "friction must not be negative"));
    }
    Ok(table)
}

/// A clutch or brake: `cgeo fn_max f_normalized mu(v)`.
fn pressed(
    p: &ParamSet,
    kind: Kind,
    v_small: &str,
    variables: &'static [VarSpec],
) -> Result<Box<dyn Component>, Error> {
    let cgeo = p.non_negative("cgeo", false)?;
    let fn_max = p.non_negative("fn_max", true)?;
    let law = FrictionLaw {
        table: table(p, "mu_pos", (0.0, 0.5))?,
        peak: peak(p)?,
        scale: cgeo * fn_max,
        v_small: p.non_negative(v_small, false)?,
    };
    Ok(Box::new(FrictionElement { kind, law, cgeo, variables }))
}

/// A bearing or support friction: a force or torque table.
fn bearing(p: &ParamSet, name: &str, v_small: f64, variables: &'static [VarSpec]) -> Result<Box<dyn Component>, Error> {
    let law = FrictionLaw { table: table(p, name, (0.0, 1.0))?, peak: peak(p)?, scale: 1.0, v_small };
    Ok(Box::new(FrictionElement { kind: Kind::Bearing, law, cgeo: 1.0, variables }))
}

fn peak(p: &ParamSet) -> Result<f64, Error> {
    let peak = p.real("peak");
    if peak < 1.0 {
        return Err(p.invalid("peak", "the holding force must be at least the sliding one: peak >= 1"));
    }
    Ok(peak)
}

const fn table_param(name: &'static str, default: &'static str, unit: &'static str, doc: &'static str) -> ParamSpec {
    ParamSpec { name, ty: ParamType::Matrix(2), default: Default::Derived(default), unit, doc }
}

const MU_POS: ParamSpec = table_param(
    "mu_pos",
    "[[0, 0.5]]",
    "",
    "Rows [v, mu]: the friction coefficient at relative speeds v >= 0, interpolated linearly",
);
const PEAK: ParamSpec = ParamSpec::real("peak", 1.0, "", "Holding force at rest over the sliding one (peak >= 1)");
const CGEO: ParamSpec = ParamSpec::real("cgeo", 1.0, "", "Geometry constant: friction force (torque) per normal force");
const FN_MAX: ParamSpec = ParamSpec::required("fn_max", ParamType::Real, "N", "Largest normal force");
const F_NORMALIZED: ConnectorSpec = ConnectorSpec::input("f_normalized", "Normal force over fn_max (0..1)");

macro_rules! friction_variables {
    ($pos:literal, $speed:literal, $acc:literal, $force:literal, $pos_unit:literal, $speed_unit:literal,
     $acc_unit:literal, $force_unit:literal $(, $extra:expr)*) => {
        &[
            VarSpec::scalar($pos, $pos_unit, "Relative position (to the support, or flange_b - flange_a)"),
            VarSpec::scalar($speed, $speed_unit, "Relative speed"),
            VarSpec::scalar($acc, $acc_unit, "Relative acceleration"),
            VarSpec::scalar($force, $force_unit, "Friction force: it slows the relative motion"),
            $($extra,)*
            VarSpec::scalar("sa", "", "Path parameter: the holding force while stuck"),
            VarSpec::scalar("mode", "", "-1 backward, 0 stuck, 1 forward, 2 free"),
            VarSpec::scalar("startForward", "", "1 while breaking away forward"),
            VarSpec::scalar("startBackward", "", "1 while breaking away backward"),
            VarSpec::scalar("locked", "", "1 while stuck (a constraint)"),
            VarSpec::scalar("free", "", "1 without normal force"),
            VarSpec::scalar("lossPower", "W", "Power turned into heat"),
        ]
    };
}

const W_SMALL: ParamSpec = ParamSpec::real(
    "w_small",
    1e10,
    "rad/s",
    "Relative speed beyond which a sliding element reverses without sticking (large: never)",
);
const V_SMALL: ParamSpec =
    ParamSpec::real("v_small", 1e-3, "m/s", "Relative speed beyond which a sliding element reverses without sticking");

pub static CLUTCH: ComponentSpec = ComponentSpec {
    kind: "RotationalComponents.Clutch",
    doc: "A clutch between two shafts pressed with fn = fn_max * f_normalized: it slides with \
          tau = cgeo * fn * mu(|w_rel|) against the relative motion, sticks when w_rel reaches 0 and holds \
          up to peak times that torque (Modelica's Clutch, with its modes and events).",
    params: &[MU_POS, PEAK, CGEO, FN_MAX, W_SMALL],
    connectors: &[
        ConnectorSpec::flange("spline_a", ConnectorType::Spline, "Driving shaft"),
        ConnectorSpec::flange("spline_b", ConnectorType::Spline, "Driven shaft"),
        F_NORMALIZED,
    ],
    variables: friction_variables!(
        "phi_rel",
        "w_rel",
        "a_rel",
        "tau",
        "rad",
        "rad/s",
        "rad/s2",
        "N.m",
        VarSpec::scalar("fn", "N", "Normal force"),
        VarSpec::scalar("tau0", "N.m", "Sliding torque at rest"),
        VarSpec::scalar("tau0_max", "N.m", "Largest torque held while stuck")
    ),
    build: |p| pressed(p, Kind::Clutch, "w_small", CLUTCH.variables),
    shapes: super::shapes::none,
};

pub static ROTATIONAL_BRAKE: ComponentSpec = ComponentSpec {
    kind: "RotationalComponents.Brake",
    doc: "A brake between a shaft (spline_a and spline_b are one) and its support, pressed with \
          fn = fn_max * f_normalized: it slides with tau = cgeo * fn * mu(|w|), sticks at w = 0 and holds up \
          to peak times that torque.",
    params: &[MU_POS, PEAK, CGEO, FN_MAX, W_SMALL],
    connectors: &[
        ConnectorSpec::flange("spline_a", ConnectorType::Spline, "Braked shaft"),
        ConnectorSpec::flange("spline_b", ConnectorType::Spline, "The same shaft, other side"),
        ConnectorSpec::flange("support", ConnectorType::Spline, "Housing (fixed when unconnected)"),
        F_NORMALIZED,
    ],
    variables: friction_variables!(
        "phi",
        "w",
        "a",
        "tau",
        "rad",
        "rad/s",
        "rad/s2",
        "N.m",
        VarSpec::scalar("fn", "N", "Normal force"),
        VarSpec::scalar("tau0", "N.m", "Sliding torque at rest"),
        VarSpec::scalar("tau0_max", "N.m", "Largest torque held while stuck")
    ),
    build: |p| pressed(p, Kind::Brake, "w_small", ROTATIONAL_BRAKE.variables),
    shapes: super::shapes::none,
};

pub static BEARING_FRICTION: ComponentSpec = ComponentSpec {
    kind: "RotationalComponents.BearingFriction",
    doc: "Coulomb friction in a bearing between a shaft (spline_a and spline_b are one) and its support: \
          tau = tau_pos(|w|) against the motion, stuck at w = 0 up to peak * tau_pos(0).",
    params: &[table_param("tau_pos", "[[0, 1]]", "N.m", "Rows [w, tau]: the friction torque at speeds w >= 0"), PEAK],
    connectors: &[
        ConnectorSpec::flange("spline_a", ConnectorType::Spline, "The shaft"),
        ConnectorSpec::flange("spline_b", ConnectorType::Spline, "The same shaft, other side"),
        ConnectorSpec::flange("support", ConnectorType::Spline, "Housing (fixed when unconnected)"),
    ],
    variables: friction_variables!(
        "phi",
        "w",
        "a",
        "tau",
        "rad",
        "rad/s",
        "rad/s2",
        "N.m",
        VarSpec::scalar("tau0", "N.m", "Sliding torque at rest"),
        VarSpec::scalar("tau0_max", "N.m", "Largest torque held while stuck")
    ),
    build: |p| bearing(p, "tau_pos", 1e10, BEARING_FRICTION.variables),
    shapes: super::shapes::none,
};

pub static TRANSLATIONAL_BRAKE: ComponentSpec = ComponentSpec {
    kind: "TranslationalComponents.Brake",
    doc: "A brake between a slider (flange_a and flange_b are one) and its support, pressed with \
          fn = fn_max * f_normalized: it slides with f = cgeo * fn * mu(|v|), sticks at v = 0 and holds up \
          to peak times that force.",
    params: &[MU_POS, PEAK, CGEO, FN_MAX, V_SMALL],
    connectors: &[
        ConnectorSpec::flange("flange_a", ConnectorType::Flange, "Braked slider"),
        ConnectorSpec::flange("flange_b", ConnectorType::Flange, "The same slider, other side"),
        ConnectorSpec::flange("support", ConnectorType::Flange, "Housing (fixed when unconnected)"),
        F_NORMALIZED,
    ],
    variables: friction_variables!(
        "s",
        "v",
        "a",
        "f",
        "m",
        "m/s",
        "m/s2",
        "N",
        VarSpec::scalar("fn", "N", "Normal force"),
        VarSpec::scalar("f0", "N", "Sliding force at rest"),
        VarSpec::scalar("f0_max", "N", "Largest force held while stuck")
    ),
    build: |p| pressed(p, Kind::Brake, "v_small", TRANSLATIONAL_BRAKE.variables),
    shapes: super::shapes::none,
};

pub static SUPPORT_FRICTION: ComponentSpec = ComponentSpec {
    kind: "TranslationalComponents.SupportFriction",
    doc: "Coulomb friction between a slider (flange_a and flange_b are one) and its support: \
          f = f_pos(|v|) against the motion, stuck at v = 0 up to peak * f_pos(0).",
    params: &[table_param("f_pos", "[[0, 1]]", "N", "Rows [v, f]: the friction force at speeds v >= 0"), PEAK],
    connectors: &[
        ConnectorSpec::flange("flange_a", ConnectorType::Flange, "The slider"),
        ConnectorSpec::flange("flange_b", ConnectorType::Flange, "The same slider, other side"),
        ConnectorSpec::flange("support", ConnectorType::Flange, "Housing (fixed when unconnected)"),
    ],
    variables: friction_variables!(
        "s",
        "v",
        "a",
        "f",
        "m",
        "m/s",
        "m/s2",
        "N",
        VarSpec::scalar("f0", "N", "Sliding force at rest"),
        VarSpec::scalar("f0_max", "N", "Largest force held while stuck")
    ),
    build: |p| bearing(p, "f_pos", 1e-3, SUPPORT_FRICTION.variables),
    shapes: super::shapes::none,
};
