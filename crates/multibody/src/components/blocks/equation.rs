//! The pieces assembly adds for a model's own equations (not kinds users
//! name; they are hidden from the results):
//! - a signal input given by a formula of time (`prescribed.r_x =
//!   sin(time)`): a source block;
//! - a signal input the equations write: a slot their blocks fill;
//! - the flows the equations give a frame or a 1-D connector that the
//!   mechanics moves: loads on it, from slots the equations fill.

use super::OUTPUT;
use crate::components::spec::{ComponentSpec, ConnectorSpec, ConnectorType};
use crate::components::{Component, EvalContext, ForceLaw, Law1D, Part, SignalLaw, SignalSource, VarSpec};
use crate::math::expr::TimeFunction;
use crate::Error;

fn not_by_name(_: &crate::components::ParamSet) -> Result<Box<dyn Component>, Error> {
    Err(Error::Unsupported {
        component: "Equation".into(),
        what: "a part of the model's equations by name".into(),
        fix: "write the equation in the model's relations".into(),
    })
}

pub static SPEC: ComponentSpec = ComponentSpec {
    kind: "Equation",
    doc: "A signal input's formula of time, from the model's equations.",
    params: &[],
    connectors: &OUTPUT,
    variables: &[],
    build: not_by_name,
    shapes: crate::components::shapes::none,
};

/// A signal input the model's equations write.
pub static WRITTEN: ComponentSpec = ComponentSpec {
    kind: "EquationOutput",
    doc: "A signal input that the model's equations write.",
    params: &[],
    connectors: &OUTPUT,
    variables: &[],
    build: not_by_name,
    shapes: crate::components::shapes::none,
};

const FLOW_SIGNALS: [ConnectorSpec; 6] = [
    ConnectorSpec::output("f_1", "Force on the component, x (frame coordinates)"),
    ConnectorSpec::output("f_2", "Force on the component, y"),
    ConnectorSpec::output("f_3", "Force on the component, z"),
    ConnectorSpec::output("tau_1", "Torque on the component, x (frame coordinates)"),
    ConnectorSpec::output("tau_2", "Torque on the component, y"),
    ConnectorSpec::output("tau_3", "Torque on the component, z"),
];

/// The flows the model's equations give a frame.
pub static FRAME_FLOW: ComponentSpec = ComponentSpec {
    kind: "EquationFrameFlow",
    doc: "The force and torque that the model's equations give a component at a frame.",
    params: &[],
    connectors: &[
        ConnectorSpec::frame("frame", "The frame"),
        FLOW_SIGNALS[0],
        FLOW_SIGNALS[1],
        FLOW_SIGNALS[2],
        FLOW_SIGNALS[3],
        FLOW_SIGNALS[4],
        FLOW_SIGNALS[5],
    ],
    variables: &[],
    build: not_by_name,
    shapes: crate::components::shapes::none,
};

/// The flows that the model's equations give a component at a planar frame.
pub static PLANAR_FLOW: ComponentSpec = ComponentSpec {
    kind: "EquationPlanarFlow",
    doc: "The force and torque that the model's equations give a component at a planar frame.",
    params: &[],
    connectors: &[
        ConnectorSpec::frame_2d("frame", "The planar frame"),
        ConnectorSpec::output("fx", "Force on the component, x (world coordinates)"),
        ConnectorSpec::output("fy", "Force on the component, y (world coordinates)"),
        ConnectorSpec::output("tau", "Torque on the component, about z"),
        ConnectorSpec::internal("zero", ConnectorType::RealOutput),
    ],
    variables: &[],
    build: not_by_name,
    shapes: crate::components::shapes::none,
};

/// The torque the model's equations give a component at a spline.
pub static SPLINE_FLOW: ComponentSpec = ComponentSpec {
    kind: "EquationSplineFlow",
    doc: "The torque that the model's equations give a component at a spline.",
    params: &[],
    connectors: &[
        ConnectorSpec::flange("spline", ConnectorType::Spline, "The spline"),
        ConnectorSpec::flange("support", ConnectorType::Spline, "Where the reaction goes (fixed)"),
        ConnectorSpec::output("y", "The torque on the component"),
    ],
    variables: &[],
    build: not_by_name,
    shapes: crate::components::shapes::none,
};

/// The force the model's equations give a component at a flange.
pub static FLANGE_FLOW: ComponentSpec = ComponentSpec {
    kind: "EquationFlangeFlow",
    doc: "The force that the model's equations give a component at a flange.",
    params: &[],
    connectors: &[
        ConnectorSpec::flange("flange", ConnectorType::Flange, "The flange"),
        ConnectorSpec::flange("support", ConnectorType::Flange, "Where the reaction goes (fixed)"),
        ConnectorSpec::output("y", "The force on the component"),
    ],
    variables: &[],
    build: not_by_name,
    shapes: crate::components::shapes::none,
};

/// An equation between positions of 1-D connectors, as a coupling of up to
/// four rotational (`spline_1` ... `spline_4`, local numbers 0 to 3) and
/// four translational (`flange_1` ... `flange_4`, 4 to 7) connectors.
pub static COUPLING: ComponentSpec = ComponentSpec {
    kind: "EquationCoupling",
    doc: "An equation between positions of 1-D connectors, held as a constraint.",
    params: &[],
    connectors: &[
        ConnectorSpec::flange("spline_1", ConnectorType::Spline, "A rotational connector of the equation"),
        ConnectorSpec::flange("spline_2", ConnectorType::Spline, "A rotational connector of the equation"),
        ConnectorSpec::flange("spline_3", ConnectorType::Spline, "A rotational connector of the equation"),
        ConnectorSpec::flange("spline_4", ConnectorType::Spline, "A rotational connector of the equation"),
        ConnectorSpec::flange("flange_1", ConnectorType::Flange, "A translational connector of the equation"),
        ConnectorSpec::flange("flange_2", ConnectorType::Flange, "A translational connector of the equation"),
        ConnectorSpec::flange("flange_3", ConnectorType::Flange, "A translational connector of the equation"),
        ConnectorSpec::flange("flange_4", ConnectorType::Flange, "A translational connector of the equation"),
    ],
    variables: &[],
    build: not_by_name,
    shapes: crate::components::shapes::none,
};

/// Positions of a frame that equations prescribe as formulas of time,
/// held by efforts that nothing else decides (a servo constraint): the
/// frame, the world (internal), and one effort per row.
pub static SERVO: ComponentSpec = ComponentSpec {
    kind: "EquationServo",
    doc: "Positions of a frame prescribed by the model's equations, held by the efforts they leave unknown.",
    params: &[],
    connectors: &[
        ConnectorSpec::frame("frame", "The frame whose position is prescribed"),
        ConnectorSpec::internal("world", ConnectorType::Frame),
        ConnectorSpec::output("effort_1", "The effort of the first row"),
        ConnectorSpec::output("effort_2", "The effort of the second row"),
        ConnectorSpec::output("effort_3", "The effort of the third row"),
    ],
    variables: &[],
    build: not_by_name,
    shapes: crate::components::shapes::none,
};

/// The most rows a servo of the equations holds (a frame's position).
pub const SERVO_ROWS: usize = 3;

/// How many connectors of each kind a coupling of the equations holds.
pub const COUPLING_CONNECTORS: usize = 4;

/// A piece of the model's equations, as a component.
#[derive(Clone, Debug)]
pub enum EquationPart {
    /// A formula of time for a signal input.
    Formula(TimeFunction),
    /// A signal input the equations write.
    Written,
    /// Flows at a frame.
    FrameFlow,
    /// Flows at a planar frame (world coordinates).
    PlanarFlow,
    /// A flow at a 1-D connector.
    AxisFlow,
    /// `sum c_k x_k + constant = 0` over the connectors of [`COUPLING`]
    /// (by local number); `measured` when the equations read its reaction.
    Coupling { terms: Vec<(usize, f64)>, constant: f64, measured: bool },
    /// The world position components `axes` (0 = x) of the frame follow
    /// `targets`; the efforts (outputs `effort_1`, ...) are what holds them.
    Servo { axes: Vec<usize>, targets: Vec<TimeFunction> },
}

impl EquationPart {
    pub fn spec(&self, rotational: bool) -> &'static ComponentSpec {
        match self {
            EquationPart::Formula(_) => &SPEC,
            EquationPart::Written => &WRITTEN,
            EquationPart::FrameFlow => &FRAME_FLOW,
            EquationPart::PlanarFlow => &PLANAR_FLOW,
            EquationPart::AxisFlow if rotational => &SPLINE_FLOW,
            EquationPart::AxisFlow => &FLANGE_FLOW,
            EquationPart::Coupling { .. } => &COUPLING,
            EquationPart::Servo { .. } => &SERVO,
        }
    }
}

fn written(output: usize) -> Part {
    Part::Signal { output, law: SignalLaw::Written, inputs: [None; 3], frames: [None; 2], flanges: [None; 2] }
}

impl Component for EquationPart {
    fn parts(&self) -> Vec<Part> {
        match self {
            EquationPart::Formula(formula) => vec![Part::Signal {
                output: 0,
                law: SignalLaw::Source(SignalSource::Formula(formula.clone())),
                inputs: [None; 3],
                frames: [None; 2],
                flanges: [None; 2],
            }],
            EquationPart::Written => vec![written(0)],
            EquationPart::FrameFlow => {
                let mut parts: Vec<Part> = (1..=6).map(written).collect();
                parts.push(Part::driven_force(None, 0, ForceLaw::Flow { world: false }, &[1, 2, 3, 4, 5, 6]));
                parts
            }
            EquationPart::PlanarFlow => {
                // Connectors: frame 0, fx 1, fy 2, tau 3, zero 4 (world coordinates).
                let mut parts: Vec<Part> = (1..=3).map(written).collect();
                parts.push(Part::zero_signal(4));
                parts.push(Part::Force {
                    a: None,
                    b: 0,
                    law: ForceLaw::Flow { world: true },
                    inputs: [Some(1), Some(2), None, None, None, Some(3)],
                    flanges: [None; 2],
                });
                parts
            }
            EquationPart::AxisFlow => vec![
                written(2),
                Part::Element1D { a: 1, b: 0, law: Law1D::Flow { signal: 2 } },
                Part::Housing { flange: 1 },
            ],
            EquationPart::Coupling { terms, constant, measured } => {
                vec![Part::Coupling { terms: terms.clone(), constant: *constant, measured: *measured }]
            }
            EquationPart::Servo { axes, targets } => {
                // Connectors: frame 0, world 1, efforts from 2.
                let mut locked = [false; 3];
                axes.iter().for_each(|&k| locked[k] = true);
                let efforts: Vec<usize> = (2..2 + axes.len()).collect();
                let mut parts = vec![
                    Part::Ground { frame: 1, pose: crate::math::Transform::IDENTITY },
                    Part::Constraint {
                        a: 1,
                        b: 0,
                        kind: crate::system::ConstraintKind::locking_axes(crate::system::RotationLock::Free, locked),
                    },
                ];
                parts.extend(efforts.iter().map(|&k| written(k)));
                parts.extend((2 + efforts.len()..2 + SERVO_ROWS).map(Part::zero_signal));
                parts.push(Part::Servo { targets: targets.clone(), efforts });
                parts
            }
        }
    }

    fn variables(&self) -> Vec<VarSpec> {
        Vec::new()
    }

    fn evaluate(&self, _: &EvalContext, _: &mut Vec<f64>) {}
}
