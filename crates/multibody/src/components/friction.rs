//! Friction with modes in the 1-D libraries (Modelica's names and
//! parameters, which Dyad's libraries follow): `RotationalComponents.Clutch`,
//! `.OneWayClutch`, `.Brake` and `.BearingFriction`, and
//! `TranslationalComponents.Brake`, `.SupportFriction` and
//! `.MassWithStopAndFriction`. Each slides with `cgeo fn mu(v)` (or a
//! torque or force table, or Stribeck's curve), sticks when the relative
//! speed reaches zero and holds up to `peak` times its sliding force at
//! rest, as a constraint (see [`crate::system::friction`]).

use super::spec::{ComponentSpec, ConnectorSpec, ConnectorType, Default, ParamSpec, ParamType, VarSpec};
use super::{Component, EvalContext, ParamSet, Part, StateNames};
use crate::system::friction::{FrictionLaw, Stribeck};
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
    /// A clutch in parallel with a freewheel: spline_b may overrun
    /// spline_a, never lag behind it.
    OneWay,
    /// A sliding mass of its own between hard stops, with friction against
    /// the fixed ground.
    MassWithStop { m: f64, length: f64 },
}

#[derive(Debug)]
struct FrictionElement {
    kind: Kind,
    law: FrictionLaw,
    /// The law's scale is `cgeo fn_max`; `fn` is reported without `cgeo`.
    cgeo: f64,
    variables: &'static [VarSpec],
}

/// The states of a mass with stops: its centre's position and speed.
const MASS_STATES: StateNames = StateNames { q: &[("s", 1)], u: &[("v", 1)] };

const FLANGE_A: usize = 0;
const FLANGE_B: usize = 1;
/// The support of brakes and bearings; the clutch's third connector is its input.
const SUPPORT: usize = 2;

impl Component for FrictionElement {
    fn parts(&self) -> Vec<Part> {
        let law = self.law.clone();
        match self.kind {
            Kind::Clutch | Kind::OneWay => {
                vec![Part::Friction { a: Some(FLANGE_A), b: FLANGE_B, law, normal: Some(2) }]
            }
            Kind::MassWithStop { m, length } => vec![
                Part::Inertia1D { a: FLANGE_A, b: FLANGE_B, length, inertia: m, weight: 0.0, states: MASS_STATES },
                // Flange a, at s - L/2, rubs on the ground.
                Part::Friction { a: None, b: FLANGE_A, law, normal: None },
            ],
            Kind::Brake | Kind::Bearing => vec![
                // Both flanges are the one rubbing against the support.
                Part::Coupling { terms: vec![(FLANGE_A, 1.0), (FLANGE_B, -1.0)], constant: 0.0, measured: false },
                Part::Housing { flange: SUPPORT },
                Part::Friction { a: Some(SUPPORT), b: FLANGE_A, law, normal: (self.kind == Kind::Brake).then_some(3) },
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
        // A mass with stops reports its centre, L/2 beyond its flange a.
        let (centre, stopped) = match (self.kind, self.law.stops) {
            (Kind::MassWithStop { length, .. }, Some((lo, hi))) => (
                length / 2.0,
                if v.s_rel <= lo {
                    -1.0
                } else if v.s_rel >= hi {
                    1.0
                } else {
                    0.0
                },
            ),
            _ => (0.0, 0.0),
        };
        for var in self.variables {
            out.push(match var.name {
                "s" if centre != 0.0 => v.s_rel + centre,
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
                "stuck" => truth(st.mode == 0.0),
                "stopped" => stopped,
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
    let law = FrictionLaw::from_table(
        table(p, "mu_pos", (0.0, 0.5))?,
        peak(p)?,
        cgeo * fn_max,
        p.non_negative(v_small, false)?,
    );
    Ok(Box::new(FrictionElement { kind, law, cgeo, variables }))
}

/// A one-way clutch: a clutch whose table, normal force and peak act
/// forward only; backwards it is a freewheel that holds.
fn one_way(p: &ParamSet) -> Result<Box<dyn Component>, Error> {
    let cgeo = p.non_negative("cgeo", false)?;
    let fn_max = p.non_negative("fn_max", true)?;
    let law = FrictionLaw {
        one_way: true,
        ..FrictionLaw::from_table(
            table(p, "mu_pos", (0.0, 0.5))?,
            peak(p)?,
            cgeo * fn_max,
            p.non_negative("w_small", false)?,
        )
    };
    Ok(Box::new(FrictionElement { kind: Kind::OneWay, law, cgeo, variables: ONE_WAY_CLUTCH.variables }))
}

/// A sliding mass between hard stops with Stribeck friction; its law acts
/// on flange a's position `s - L/2`, which stays within `[smin, smax - L]`.
fn mass_with_stop(p: &ParamSet) -> Result<Box<dyn Component>, Error> {
    let m = p.non_negative("m", false)?;
    let length = p.non_negative("L", true)?;
    let (smin, smax) = (p.real("smin"), p.real("smax"));
    if (smax - smin).is_nan() || smax - smin < length {
        return Err(p.invalid(
            "smax",
            format!("the stops must leave room for the mass: smax - smin >= L (smin = {smin}, L = {length})"),
        ));
    }
    let stribeck = Stribeck {
        f_prop: p.non_negative("F_prop", true)?,
        f_coulomb: p.non_negative("F_Coulomb", true)?,
        f_stribeck: p.non_negative("F_Stribeck", true)?,
        fexp: p.non_negative("fexp", true)?,
    };
    // Modelica's holding force: 1.001 times the sliding force at rest.
    let law = FrictionLaw {
        stribeck: Some(stribeck),
        stops: Some((smin, smax - length)),
        ..FrictionLaw::from_table(Vec::new(), 1.001, 1.0, p.non_negative("v_small", false)?)
    };
    Ok(Box::new(FrictionElement {
        kind: Kind::MassWithStop { m, length },
        law,
        cgeo: 1.0,
        variables: MASS_WITH_STOP_AND_FRICTION.variables,
    }))
}

/// A bearing or support friction: a force or torque table.
fn bearing(p: &ParamSet, name: &str, v_small: f64, variables: &'static [VarSpec]) -> Result<Box<dyn Component>, Error> {
    let law = FrictionLaw::from_table(table(p, name, (0.0, 1.0))?, peak(p)?, 1.0, v_small);
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
    (rotational $(, $extra:expr)*) => {
        friction_variables!("phi", "w", "a", "tau", "rad", "rad/s", "rad/s2", "N.m" $(, $extra)*)
    };
    (translational $(, $extra:expr)*) => {
        friction_variables!("s", "v", "a", "f", "m", "m/s", "m/s2", "N" $(, $extra)*)
    };
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

pub static ONE_WAY_CLUTCH: ComponentSpec = ComponentSpec {
    kind: "RotationalComponents.OneWayClutch",
    doc: "A clutch in parallel with a freewheel (Modelica's OneWayClutch): spline_b may turn faster than \
          spline_a (w_rel > 0), sliding against tau = cgeo * fn * mu(w_rel) with fn = fn_max * f_normalized, \
          but never slower: at w_rel = 0 it locks, holding any torque that drives spline_b forward and up to \
          peak times the sliding torque that holds it back (a tiny torque when disengaged). Start it with \
          w_rel >= 0.",
    params: &[MU_POS, PEAK, CGEO, FN_MAX, W_SMALL],
    connectors: &[
        ConnectorSpec::flange("spline_a", ConnectorType::Spline, "Driving shaft"),
        ConnectorSpec::flange("spline_b", ConnectorType::Spline, "Driven shaft, which may overrun"),
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
        VarSpec::scalar("tau0_max", "N.m", "Largest torque held back while stuck"),
        VarSpec::scalar("stuck", "", "1 at w_rel = 0 (locked, or breaking away forward)")
    ),
    build: one_way,
    shapes: super::shapes::none,
};

pub static MASS_WITH_STOP_AND_FRICTION: ComponentSpec = ComponentSpec {
    kind: "TranslationalComponents.MassWithStopAndFriction",
    doc: "A sliding mass m of length L between hard stops (flange_a >= smin, flange_b <= smax) with \
          Stribeck friction against the ground (Modelica's MassWithStopAndFriction): sliding at v it feels \
          F_prop * v + F_Coulomb + F_Stribeck * exp(-fexp * |v|) against the motion; at rest it sticks and \
          holds up to 1.001 * (F_Coulomb + F_Stribeck); reaching a stop it stops dead (v is set to 0) and \
          stays while pushed against it.",
    params: &[
        ParamSpec::required("m", ParamType::Real, "kg", "Mass"),
        ParamSpec::real("L", 0.0, "m", "Length, from flange_a to flange_b"),
        ParamSpec::real("smax", 25.0, "m", "Right stop for the right end (flange_b)"),
        ParamSpec::real("smin", -25.0, "m", "Left stop for the left end (flange_a)"),
        ParamSpec::real("F_prop", 1.0, "N.s/m", "Velocity dependent friction"),
        ParamSpec::real("F_Coulomb", 5.0, "N", "Constant friction: Coulomb force"),
        ParamSpec::real("F_Stribeck", 10.0, "N", "Stribeck effect"),
        ParamSpec::real("fexp", 2.0, "s/m", "Exponential decay of the Stribeck effect"),
        V_SMALL,
    ],
    connectors: &[
        ConnectorSpec::flange("flange_a", ConnectorType::Flange, "Left flange (at s - L/2)"),
        ConnectorSpec::flange("flange_b", ConnectorType::Flange, "Right flange (at s + L/2)"),
    ],
    variables: friction_variables!(
        translational,
        VarSpec::scalar("f0", "N", "Sliding force at rest"),
        VarSpec::scalar("f0_max", "N", "Largest force held while stuck"),
        VarSpec::scalar("stopped", "", "-1 at the left stop, 1 at the right stop, 0 between")
    ),
    build: mass_with_stop,
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
        rotational,
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
        rotational,
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
        translational,
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
        translational,
        VarSpec::scalar("f0", "N", "Sliding force at rest"),
        VarSpec::scalar("f0_max", "N", "Largest force held while stuck")
    ),
    build: |p| bearing(p, "f_pos", 1e-3, SUPPORT_FRICTION.variables),
    shapes: super::shapes::none,
};
