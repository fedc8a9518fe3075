//! The 1-D rotational and translational libraries from one definition.
//!
//! Both libraries have the same elements (springs, dampers, sources driven
//! by a constant or a signal, sensors, gears) and differ only in names and
//! units: a rotational element has splines, angles `phi`, speeds `w` and
//! torques `tau`; a translational one flanges, positions `s`, velocities `v`
//! and forces `f`. [`one_d_library!`] writes each element's spec once for
//! both, and [`Element1D`] evaluates them.

use super::spec::VarSpec;
use super::{Component, Element1DState, EvalContext, Law1D, Part};
use crate::system::SignalLaw;

/// A 1-D element: `law` acts between connector `a` (flange_a, or a source's
/// support) and connector `b` (flange_b, or a source's driven flange).
#[derive(Debug)]
pub struct Element1D {
    pub law: Law1D,
    pub a: usize,
    pub b: usize,
    pub variables: &'static [VarSpec],
}

impl Component for Element1D {
    fn parts(&self) -> Vec<Part> {
        let mut parts = vec![Part::Element1D { a: self.a, b: self.b, law: self.law }];
        if matches!(self.law, Law1D::Source { .. } | Law1D::Input { .. } | Law1D::Flow { .. }) {
            // A source's support is the housing it pushes against.
            parts.push(Part::Housing { flange: self.a });
        }
        parts
    }

    fn variables(&self) -> Vec<VarSpec> {
        self.variables.to_vec()
    }

    fn evaluate(&self, ctx: &EvalContext, out: &mut Vec<f64>) {
        let st = &ctx.elements[0];
        out.extend(self.variables.iter().map(|v| self.value(v.name, st)));
    }
}

impl Element1D {
    /// The value of a variable, by the names both libraries use.
    fn value(&self, name: &str, st: &Element1DState) -> f64 {
        let (c, d, s0) = match self.law {
            Law1D::Spring { c, s_rel0 } => (c, 0.0, s_rel0),
            Law1D::Damper { d } => (0.0, d, 0.0),
            Law1D::SpringDamper { c, d, s_rel0 } => (c, d, s_rel0),
            // Contact laws have their own component (contact_1d).
            Law1D::Source { .. } | Law1D::Input { .. } | Law1D::Flow { .. } | Law1D::Contact { .. } => (0.0, 0.0, 0.0),
        };
        let source = matches!(self.law, Law1D::Source { .. } | Law1D::Input { .. } | Law1D::Flow { .. });
        match name {
            "phi_rel" | "s_rel" | "phi" | "s" => st.s_rel,
            "w_rel" | "v_rel" | "w" | "v" => st.v_rel,
            "a_rel" => st.a_rel,
            // A source reports the force it drives with; a compliant element its internal force.
            "tau" | "f" if source => -st.force,
            "tau" | "f" => st.force,
            "tau_c" | "f_c" => c * (st.s_rel - s0),
            "tau_d" | "f_d" => d * st.v_rel,
            "lossPower" => d * st.v_rel * st.v_rel,
            _ => f64::NAN,
        }
    }
}

/// A 1-D sensor: its output reads the motion of connector `b` relative to
/// connector `a` (the fixed support when `a` is `None`).
#[derive(Debug)]
pub struct Sensor1D {
    pub law: SignalLaw,
    pub output: usize,
    pub a: Option<usize>,
    pub b: usize,
    pub variables: &'static [VarSpec],
}

/// A sensor's block: `output` from `law` on flanges `a` (the fixed ground
/// when absent) and `b`.
fn sensor_part(output: usize, law: SignalLaw, a: Option<usize>, b: usize) -> Part {
    Part::Signal { output, law, inputs: [None; 3], frames: [None; 2], flanges: [a, Some(b)] }
}

impl Component for Sensor1D {
    fn parts(&self) -> Vec<Part> {
        vec![sensor_part(self.output, self.law.clone(), self.a, self.b)]
    }

    fn variables(&self) -> Vec<VarSpec> {
        self.variables.to_vec()
    }

    fn evaluate(&self, ctx: &EvalContext, out: &mut Vec<f64>) {
        out.push(ctx.signals[self.output]);
    }
}

/// Why an output that depends on the accelerations cannot be read by
/// blocks or equations (it is recorded).
pub(crate) const NEEDS_ACCELERATIONS: &str = "depends on the accelerations, which are solved after the signals \
    (reading it would make an algebraic loop through the dynamics); it is recorded in the results";

/// The acceleration of a 1-D connector, recorded: its output exists for
/// the library's connector, but nothing may read it (see
/// [`NEEDS_ACCELERATIONS`]).
#[derive(Debug)]
pub struct Acceleration1D {
    pub variables: &'static [VarSpec],
}

impl Component for Acceleration1D {
    fn parts(&self) -> Vec<Part> {
        vec![sensor_part(1, SignalLaw::Unavailable { reason: NEEDS_ACCELERATIONS }, None, 0)]
    }

    fn variables(&self) -> Vec<VarSpec> {
        self.variables.to_vec()
    }

    fn evaluate(&self, ctx: &EvalContext, out: &mut Vec<f64>) {
        out.push(ctx.flanges[0].a);
    }
}

/// A 1-D connector held at a fixed position.
#[derive(Debug)]
pub struct Fixed1D {
    pub at: f64,
}

impl Component for Fixed1D {
    fn parts(&self) -> Vec<Part> {
        vec![Part::Fixed1D { flange: 0, at: self.at }]
    }
}

/// Writes the specs of the 1-D elements of one library (`$lib`) in module
/// `$module`, with that library's connector type, names and units.
macro_rules! one_d_library {
    (
        $module:ident, $lib:literal, $connector:expr,
        connector: $conn:literal, connectors: $conns:literal,
        a: $a:literal, b: $b:literal, driven: $driven:literal,
        position: $pos:literal, speed: $speed:literal, effort: $effort:literal, effort_word: $effort_word:literal,
        units: [$u_pos:literal, $u_speed:literal, $u_acc:literal, $u_effort:literal, $u_c:literal, $u_d:literal],
        rest_param: $rest:literal, rest_doc: $rest_doc:literal, damping_doc: $damping_doc:literal, constant_param: $constant:literal,
        source: $source:literal, angle_sensor: $angle_sensor:literal, rel_position_sensor: $rel_position_sensor:literal,
    ) => {
        pub mod $module {
            use $crate::components::one_d::{Acceleration1D, Element1D, Fixed1D, Sensor1D};
            use $crate::components::spec::{ComponentSpec, ConnectorSpec, ParamSpec, ParamType, VarSpec};
            use $crate::components::{Component, Law1D, ParamSet};
            use $crate::system::SignalLaw;
            use $crate::Error;

            const TWO: [ConnectorSpec; 2] = [
                ConnectorSpec::flange($a, $connector, concat!("First ", $conn)),
                ConnectorSpec::flange($b, $connector, concat!("Second ", $conn)),
            ];
            const DRIVEN: [ConnectorSpec; 2] = [
                ConnectorSpec::flange($driven, $connector, concat!("Driven ", $conn)),
                ConnectorSpec::flange("support", $connector, concat!("Support ", $conn, " (reaction)")),
            ];
            const REL_POSITION: VarSpec = VarSpec::scalar(
                concat!($pos, "_rel"),
                $u_pos,
                concat!("Relative position of ", $b, " with respect to ", $a),
            );
            const REL_SPEED: VarSpec =
                VarSpec::scalar(concat!($speed, "_rel"), $u_speed, concat!("Relative speed between the ", $conns));
            const REL_ACC: VarSpec =
                VarSpec::scalar("a_rel", $u_acc, concat!("Relative acceleration between the ", $conns));
            const EFFORT: VarSpec =
                VarSpec::scalar($effort, $u_effort, concat!("The ", $effort_word, " transmitted between the ", $conns));
            const C: ParamSpec = ParamSpec::required("c", ParamType::Real, $u_c, "Spring constant");
            const D: ParamSpec = ParamSpec::required("d", ParamType::Real, $u_d, $damping_doc);
            const REST: ParamSpec = ParamSpec::real($rest, 0.0, $u_pos, $rest_doc);

            pub static SPRING: ComponentSpec = ComponentSpec {
                kind: concat!($lib, ".Spring"),
                doc: concat!(
                    "Linear spring between two ",
                    $conns,
                    ": ",
                    $effort,
                    " = c * (",
                    $pos,
                    "_rel - ",
                    $rest,
                    ")."
                ),
                params: &[C, REST],
                connectors: &TWO,
                variables: &[REL_POSITION, EFFORT],
                build: |p: &ParamSet| {
                    let law = Law1D::Spring { c: p.non_negative("c", true)?, s_rel0: p.real($rest) };
                    Ok(Box::new(Element1D { law, a: 0, b: 1, variables: SPRING.variables }))
                },
                shapes: $crate::components::shapes::none,
            };

            pub static DAMPER: ComponentSpec = ComponentSpec {
                kind: concat!($lib, ".Damper"),
                doc: concat!("Linear damper between two ", $conns, ": ", $effort, " = d * ", $speed, "_rel."),
                params: &[D],
                connectors: &TWO,
                variables: &[REL_POSITION, REL_SPEED, REL_ACC, EFFORT],
                build: |p: &ParamSet| {
                    let law = Law1D::Damper { d: p.non_negative("d", true)? };
                    Ok(Box::new(Element1D { law, a: 0, b: 1, variables: DAMPER.variables }))
                },
                shapes: $crate::components::shapes::none,
            };

            pub static SPRING_DAMPER: ComponentSpec = ComponentSpec {
                kind: concat!($lib, ".SpringDamper"),
                doc: concat!(
                    "Linear spring and damper in parallel between two ",
                    $conns,
                    ": ",
                    $effort,
                    " = c * (",
                    $pos,
                    "_rel - ",
                    $rest,
                    ") + d * ",
                    $speed,
                    "_rel."
                ),
                params: &[D, C, REST],
                connectors: &TWO,
                variables: &[
                    REL_POSITION,
                    REL_SPEED,
                    REL_ACC,
                    EFFORT,
                    VarSpec::scalar(concat!($effort, "_c"), $u_effort, concat!("The spring's ", $effort_word)),
                    VarSpec::scalar(concat!($effort, "_d"), $u_effort, concat!("The damper's ", $effort_word)),
                ],
                build: |p: &ParamSet| {
                    let law = Law1D::SpringDamper {
                        c: p.non_negative("c", true)?,
                        d: p.non_negative("d", true)?,
                        s_rel0: p.real($rest),
                    };
                    Ok(Box::new(Element1D { law, a: 0, b: 1, variables: SPRING_DAMPER.variables }))
                },
                shapes: $crate::components::shapes::none,
            };

            const SOURCE_VARIABLES: [VarSpec; 3] = [
                VarSpec::scalar($pos, $u_pos, concat!("Position of ", $driven, " with respect to the support")),
                VarSpec::scalar($speed, $u_speed, concat!("Speed of ", $driven, " with respect to the support")),
                VarSpec::scalar($effort, $u_effort, concat!("The ", $effort_word, " driving ", $driven)),
            ];

            pub static CONSTANT: ComponentSpec = ComponentSpec {
                kind: concat!($lib, ".Constant", $source),
                doc: concat!(
                    "A constant ",
                    $effort_word,
                    " ",
                    $constant,
                    " driving ",
                    $driven,
                    " against its support (a negative value acts as a load)."
                ),
                params: &[ParamSpec::required(
                    $constant,
                    ParamType::Real,
                    $u_effort,
                    concat!("The constant ", $effort_word),
                )],
                connectors: &DRIVEN,
                variables: &SOURCE_VARIABLES,
                build: |p: &ParamSet| {
                    let law = Law1D::Source { value: p.real($constant) };
                    Ok(Box::new(Element1D { law, a: 1, b: 0, variables: &SOURCE_VARIABLES }))
                },
                shapes: $crate::components::shapes::none,
            };

            pub static DRIVEN_BY_SIGNAL: ComponentSpec = ComponentSpec {
                kind: concat!($lib, ".", $source),
                doc: concat!(
                    "A ",
                    $effort_word,
                    " given by the signal input `",
                    $effort,
                    "` driving ",
                    $driven,
                    " against its support."
                ),
                params: &[],
                connectors: &[
                    DRIVEN[0],
                    DRIVEN[1],
                    ConnectorSpec::input($effort, concat!("The ", $effort_word, " (signal)")),
                ],
                variables: &SOURCE_VARIABLES,
                build: |_: &ParamSet| {
                    let law = Law1D::Input { signal: 2 };
                    Ok(Box::new(Element1D { law, a: 1, b: 0, variables: &SOURCE_VARIABLES }))
                },
                shapes: $crate::components::shapes::none,
            };

            pub static FIXED: ComponentSpec = ComponentSpec {
                kind: concat!($lib, ".Fixed"),
                doc: concat!("Holds its ", $conn, " fixed at ", $pos, "0 (a housing or a wall)."),
                params: &[ParamSpec::real(concat!($pos, "0"), 0.0, $u_pos, "The fixed position")],
                connectors: &[ConnectorSpec::flange($driven, $connector, concat!("The fixed ", $conn))],
                variables: &[],
                build: |p: &ParamSet| -> Result<Box<dyn Component>, Error> {
                    Ok(Box::new(Fixed1D { at: p.real(concat!($pos, "0")) }))
                },
                shapes: $crate::components::shapes::none,
            };

            fn sensor(law: SignalLaw, variables: &'static [VarSpec]) -> Result<Box<dyn Component>, Error> {
                Ok(Box::new(Sensor1D { law, output: 1, a: None, b: 0, variables }))
            }

            const SENSED: ConnectorSpec = ConnectorSpec::flange($driven, $connector, concat!("The sensed ", $conn));

            pub static POSITION_SENSOR: ComponentSpec = ComponentSpec {
                kind: concat!($lib, ".", $angle_sensor),
                doc: concat!("Measures the absolute position `", $pos, "` of its ", $conn, " as a signal."),
                params: &[],
                connectors: &[SENSED, ConnectorSpec::output($pos, "The measured position")],
                variables: &[VarSpec::scalar($pos, $u_pos, "The measured position")],
                build: |_: &ParamSet| sensor(SignalLaw::FlangePosition, POSITION_SENSOR.variables),
                shapes: $crate::components::shapes::none,
            };

            const RELATIVE: [ConnectorSpec; 2] = [
                ConnectorSpec::flange($a, $connector, concat!("The ", $conn, " measured from")),
                ConnectorSpec::flange($b, $connector, concat!("The ", $conn, " measured")),
            ];

            pub static RELATIVE_POSITION_SENSOR: ComponentSpec = ComponentSpec {
                kind: concat!($lib, ".", $rel_position_sensor),
                doc: concat!("Measures the position of ", $b, " relative to ", $a, ", `", $pos, "_rel`, as a signal."),
                params: &[],
                connectors: &[
                    RELATIVE[0],
                    RELATIVE[1],
                    ConnectorSpec::output(concat!($pos, "_rel"), "The relative position"),
                ],
                variables: &[VarSpec::scalar(concat!($pos, "_rel"), $u_pos, "The relative position")],
                build: |_: &ParamSet| -> Result<Box<dyn Component>, Error> {
                    let variables = RELATIVE_POSITION_SENSOR.variables;
                    Ok(Box::new(Sensor1D { law: SignalLaw::FlangePosition, output: 2, a: Some(0), b: 1, variables }))
                },
                shapes: $crate::components::shapes::none,
            };

            pub static RELATIVE_SPEED_SENSOR: ComponentSpec = ComponentSpec {
                kind: concat!($lib, ".RelativeVelocitySensor"),
                doc: concat!("Measures the speed of ", $b, " relative to ", $a, ", `", $speed, "_rel`, as a signal."),
                params: &[],
                connectors: &[
                    RELATIVE[0],
                    RELATIVE[1],
                    ConnectorSpec::output(concat!($speed, "_rel"), "The relative speed"),
                ],
                variables: &[VarSpec::scalar(concat!($speed, "_rel"), $u_speed, "The relative speed")],
                build: |_: &ParamSet| -> Result<Box<dyn Component>, Error> {
                    let variables = RELATIVE_SPEED_SENSOR.variables;
                    Ok(Box::new(Sensor1D { law: SignalLaw::FlangeSpeed, output: 2, a: Some(0), b: 1, variables }))
                },
                shapes: $crate::components::shapes::none,
            };

            pub static SPEED_SENSOR: ComponentSpec = ComponentSpec {
                kind: concat!($lib, ".SpeedSensor"),
                doc: concat!("Measures the absolute speed `", $speed, "` of its ", $conn, " as a signal."),
                params: &[],
                connectors: &[SENSED, ConnectorSpec::output($speed, "The measured speed")],
                variables: &[VarSpec::scalar($speed, $u_speed, "The measured speed")],
                build: |_: &ParamSet| sensor(SignalLaw::FlangeSpeed, SPEED_SENSOR.variables),
                shapes: $crate::components::shapes::none,
            };

            pub static ACCELERATION_SENSOR: ComponentSpec = ComponentSpec {
                kind: concat!($lib, ".AccelerationSensor"),
                doc: concat!(
                    "Measures the absolute acceleration `a` of its ",
                    $conn,
                    ". It is recorded in the results; ",
                    "blocks and equations cannot read it (the accelerations are solved after the signals)."
                ),
                params: &[],
                connectors: &[SENSED, ConnectorSpec::output("a", "The measured acceleration (recorded only)")],
                variables: &[VarSpec::scalar("a", $u_acc, "The measured acceleration")],
                build: |_: &ParamSet| Ok(Box::new(Acceleration1D { variables: ACCELERATION_SENSOR.variables })),
                shapes: $crate::components::shapes::none,
            };
        }
    };
}

one_d_library!(
    rotational, "RotationalComponents", crate::components::spec::ConnectorType::Spline,
    connector: "spline", connectors: "splines",
    a: "spline_a", b: "spline_b", driven: "spline",
    position: "phi", speed: "w", effort: "tau", effort_word: "torque",
    units: ["rad", "rad/s", "rad/s2", "N.m", "N.m/rad", "N.m.s/rad"],
    rest_param: "phi_rel0", rest_doc: "Unstretched spring angle",
    damping_doc: "Damping coefficient, relating torque to relative angular velocity", constant_param: "tau_constant",
    source: "Torque", angle_sensor: "AngleSensor", rel_position_sensor: "RelativeAngleSensor",
);

one_d_library!(
    translational, "TranslationalComponents", crate::components::spec::ConnectorType::Flange,
    connector: "flange", connectors: "flanges",
    a: "flange_a", b: "flange_b", driven: "flange",
    position: "s", speed: "v", effort: "f", effort_word: "force",
    units: ["m", "m/s", "m/s2", "N", "N/m", "N.s/m"],
    rest_param: "s_rel0", rest_doc: "Unstretched spring length",
    damping_doc: "Damping coefficient, relating force to relative velocity", constant_param: "f_constant",
    source: "Force", angle_sensor: "PositionSensor", rel_position_sensor: "RelativePositionSensor",
);
