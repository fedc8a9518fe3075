//! The 3-D sensors: absolute and relative kinematics of frames, Euler
//! angles, distance, cut forces and torques, and power.
//!
//! Every sensor is a [`Sensor`]: a list of output groups (a vector of three
//! `RealOutput`s, three angles, or one scalar), each a block of the signal
//! graph, and the variables recorded in the results. Outputs of positions,
//! velocities, angles and distances are computed in the signal graph, so
//! they can feed back into the model (a PD force from a position, say).
//! Outputs that need the accelerations (accelerations, cut forces and
//! torques, power) are recorded in the results, but the signal graph is
//! evaluated before the accelerations are known: a model that reads one of
//! them is refused at assembly with a message that names it
//! ([`SignalLaw::Unavailable`]).
//!
//! A vector resolved in `frame_resolve` is computed in world coordinates
//! into internal outputs, then turned into `frame_resolve`'s coordinates by
//! a second block ([`SignalLaw::ResolveVector`]).

mod absolute;
mod cut;
mod relative;

pub use absolute::{ABSOLUTE_ANGLES, ABSOLUTE_ANGULAR_VELOCITY, ABSOLUTE_POSITION, ABSOLUTE_SENSOR, ABSOLUTE_VELOCITY};
pub use cut::{CUT_FORCE, CUT_FORCE_AND_TORQUE, CUT_TORQUE, POWER};
pub use relative::{
    DISTANCE, RELATIVE_ANGLES, RELATIVE_ANGULAR_VELOCITY, RELATIVE_POSITION, RELATIVE_SENSOR, RELATIVE_VELOCITY,
};

use super::spec::{ComponentSpec, ConnectorSpec, ConnectorType, Default, ParamSpec, ParamType, VarSpec};
use super::{Component, EvalContext, FrameState, Part, Resolve, SignalLaw};
use crate::math::{Mat3, Transform, Vec3};
use crate::Error;

/// Why an output that needs the accelerations cannot be read in the model.
const NEEDS_ACCELERATIONS: &str = "depends on the accelerations, which are solved after the signals \
    (reading it would make an algebraic loop through the dynamics); it is recorded in the results";
const NEEDS_CUT_FORCES: &str = "depends on cut forces, which are solved after the signals \
    (reading it would make an algebraic loop through the dynamics); it is recorded in the results";
const INTERNAL: &str = "is internal";
/// Why a sensor's frame_resolve cannot be connected while its
/// resolve_in_frame names another frame.
pub(crate) const RESOLVE_IN_IT: &str = "the sensor resolves in the frame its resolve_in_frame names, not in \
     frame_resolve; give resolve_in_frame = ResolveInFrame.FrameResolve to resolve in the frame connected there, or \
     leave frame_resolve unconnected";
const SEEN_FROM_RESOLVE: &str = "is differentiated in frame_resolve, which the signal graph does not support yet \
    (differentiate in World, FrameA or FrameB); it is recorded in the results";

/// Where a vector is resolved (or from where it is differentiated): the
/// world or the frame at a connector.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Target {
    World,
    Frame(usize),
}

/// A vector a sensor measures, of frame `b` relative to frame `a` (the
/// world when absent).
#[derive(Clone, Copy, Debug, PartialEq)]
enum Quantity {
    /// `r_b - r_a`.
    Position,
    /// The derivative of the relative position as an observer fixed in the
    /// target sees it.
    Velocity(Target),
    /// The second derivative of the relative position, seen from the target.
    Acceleration(Target),
    /// `w_b - w_a`.
    AngularVelocity,
    /// The derivative of the relative angular velocity, seen from the target.
    AngularAcceleration(Target),
    /// The cut force on the sensor at frame `b` (its frame_a).
    CutForce,
    /// The cut torque on the sensor at frame `b` (its frame_a).
    CutTorque,
}

/// What an output group measures.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Measure {
    /// A vector resolved in a target.
    Vector(Quantity, Target),
    /// The Euler angles of frame b relative to frame a.
    Angles { sequence: [usize; 3], guess: f64 },
    /// The distance between the origins.
    Distance { s_small: f64 },
    /// The power flowing from frame_a to frame_b.
    Power,
}

/// A group of output connectors that measure one thing.
#[derive(Clone, Debug)]
struct Group {
    measure: Measure,
    /// Output connectors: three for vectors and angles, one for scalars.
    outputs: Vec<usize>,
    /// Internal outputs for the world-resolved vector, when the kind can
    /// resolve in `frame_resolve`.
    internal: Option<[usize; 3]>,
    /// Why the group is switched off (its outputs read NaN and cannot be
    /// read in the model), if it is.
    off: Option<&'static str>,
}

/// How a recorded variable is computed.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Var {
    /// A vector from the frame states.
    Vector(Quantity, Target),
    /// The three signals at these output connectors.
    Signals([usize; 3]),
    /// The signal at this output connector.
    Signal(usize),
    /// The power flowing through frame_a.
    Power,
    /// The squared distance of the origins.
    SquaredDistance,
    /// The rotation from frame a to frame b, `R_b * R_a'`.
    RelativeRotation,
}

/// A 3-D sensor (see the module documentation).
#[derive(Debug)]
struct Sensor {
    /// Frame a (the world when `None`) and frame b of the measurement.
    a: Option<usize>,
    b: usize,
    /// Frame_a and frame_b are one frame (cut sensors, Power).
    rigid: bool,
    /// `-1` reports the cut force and torque of the other side.
    sign: f64,
    groups: Vec<Group>,
    variables: Vec<(VarSpec, Var)>,
    /// The kind's frame_resolve connector, if it has one. Unused, it is
    /// fixed at the world's origin (as Modelica does with its ZeroPosition),
    /// so that an unconnected one is not a loose frame.
    frame_resolve: Option<usize>,
}

impl Sensor {
    /// Whether anything is resolved in, or differentiated in, connector `c`.
    fn uses(&self, c: usize) -> bool {
        let at = |t: Target| t == Target::Frame(c);
        let quantity = |q: Quantity| match q {
            Quantity::Velocity(t) | Quantity::Acceleration(t) | Quantity::AngularAcceleration(t) => at(t),
            _ => false,
        };
        let groups = self.groups.iter().any(|g| match g.measure {
            Measure::Vector(q, t) => g.off.is_none() && (quantity(q) || at(t)),
            _ => false,
        });
        let vars = self.variables.iter().any(|(_, v)| matches!(*v, Var::Vector(q, t) if quantity(q) || at(t)));
        groups || vars
    }

    fn new(spec: &ComponentSpec, a: Option<usize>, b: usize) -> Self {
        let frame_resolve = spec.connectors.iter().position(|c| c.name == "frame_resolve");
        Sensor { a, b, rigid: false, sign: 1.0, groups: Vec::new(), variables: Vec::new(), frame_resolve }
    }

    /// The resolution of the signal laws for `target`, or `None` for a
    /// frame that is neither frame a nor frame b (frame_resolve).
    fn resolve_of(&self, target: Target) -> Option<Resolve> {
        match target {
            Target::World => Some(Resolve::World),
            Target::Frame(c) if Some(c) == self.a => Some(Resolve::FrameA),
            Target::Frame(c) if c == self.b => Some(Resolve::FrameB),
            Target::Frame(_) => None,
        }
    }

    /// The law of component `index` of `quantity` resolved in `resolve`,
    /// or why the signal graph cannot compute it.
    fn vector_law(&self, quantity: Quantity, index: usize, resolve: Resolve) -> Result<SignalLaw, &'static str> {
        match quantity {
            Quantity::Position => Ok(SignalLaw::FramePosition { index, resolve }),
            Quantity::Velocity(Target::World) => Ok(SignalLaw::FrameVelocity { index, resolve }),
            Quantity::Velocity(seen) => match self.resolve_of(seen) {
                Some(seen_from) => Ok(SignalLaw::RelativeVelocity { index, seen_from, resolve }),
                None => Err(SEEN_FROM_RESOLVE),
            },
            Quantity::AngularVelocity => Ok(SignalLaw::AngularVelocity { index, resolve }),
            Quantity::CutForce | Quantity::CutTorque => Err(NEEDS_CUT_FORCES),
            Quantity::Acceleration(_) | Quantity::AngularAcceleration(_) => Err(NEEDS_ACCELERATIONS),
        }
    }

    /// The blocks of one group.
    fn group_parts(&self, g: &Group, parts: &mut Vec<Part>) {
        let frames = [self.a, Some(self.b)];
        let block = |output: usize, law: SignalLaw, inputs: [Option<usize>; 3], frames: [Option<usize>; 2]| {
            Part::Signal { output, law, inputs, frames, flanges: [None; 2] }
        };
        let unavailable = |reason: &'static str| SignalLaw::Unavailable { reason };
        let mut internal_done = false;
        match (g.off, g.measure) {
            (Some(reason), _) => {
                for &o in &g.outputs {
                    parts.push(block(o, unavailable(reason), [None; 3], [None; 2]));
                }
            }
            (None, Measure::Vector(quantity, target)) => match self.resolve_of(target) {
                Some(resolve) => {
                    for (index, &o) in g.outputs.iter().enumerate() {
                        match self.vector_law(quantity, index, resolve) {
                            Ok(law) => parts.push(block(o, law, [None; 3], frames)),
                            Err(reason) => parts.push(block(o, unavailable(reason), [None; 3], [None; 2])),
                        }
                    }
                }
                None if g.internal.is_none() => {
                    // Only outputs the signal graph cannot compute lack internal outputs.
                    let reason = self.vector_law(quantity, 0, Resolve::World).err().unwrap_or(INTERNAL);
                    for &o in &g.outputs {
                        parts.push(block(o, unavailable(reason), [None; 3], [None; 2]));
                    }
                }
                None => {
                    let internal = g.internal.unwrap_or_default();
                    for (index, (&o, &i)) in g.outputs.iter().zip(&internal).enumerate() {
                        match self.vector_law(quantity, index, Resolve::World) {
                            Ok(law) => {
                                parts.push(block(i, law, [None; 3], frames));
                                let to_frame = [
                                    None,
                                    Some(match target {
                                        Target::Frame(c) => c,
                                        Target::World => unreachable!("the world resolves directly"),
                                    }),
                                ];
                                let inputs = internal.map(Some);
                                parts.push(block(o, SignalLaw::ResolveVector { index }, inputs, to_frame));
                            }
                            Err(reason) => {
                                parts.push(block(i, unavailable(INTERNAL), [None; 3], [None; 2]));
                                parts.push(block(o, unavailable(reason), [None; 3], [None; 2]));
                            }
                        }
                    }
                    internal_done = true;
                }
            },
            (None, Measure::Angles { sequence, guess }) => {
                for (index, &o) in g.outputs.iter().enumerate() {
                    parts.push(block(o, SignalLaw::FrameAngles { index, sequence, guess }, [None; 3], frames));
                }
            }
            (None, Measure::Distance { s_small }) => {
                parts.push(block(g.outputs[0], SignalLaw::FrameDistance { s_small }, [None; 3], frames));
            }
            (None, Measure::Power) => {
                parts.push(block(g.outputs[0], unavailable(NEEDS_CUT_FORCES), [None; 3], [None; 2]));
            }
        }
        // Every output connector needs a block, the unused internal ones too.
        if let (Some(internal), false) = (g.internal, internal_done) {
            for i in internal {
                parts.push(block(i, unavailable(INTERNAL), [None; 3], [None; 2]));
            }
        }
    }

    /// The frame state at connector `c`, or the world at rest.
    fn frame<'a>(ctx: &'a EvalContext, c: Option<usize>, world: &'a FrameState) -> &'a FrameState {
        c.map_or(world, |c| &ctx.frames[c])
    }

    /// The angular velocity and acceleration (world coordinates) of `seen`.
    fn spin(ctx: &EvalContext, seen: Target) -> (Vec3, Vec3) {
        match seen {
            Target::World => (Vec3::zeros(), Vec3::zeros()),
            Target::Frame(c) => {
                let f = &ctx.frames[c];
                (f.rot.tr_mul(&f.w), f.rot.tr_mul(&f.z))
            }
        }
    }

    /// `quantity` in world coordinates.
    fn measure(&self, ctx: &EvalContext, quantity: Quantity) -> Vec3 {
        let world = FrameState { rot: Mat3::identity(), ..FrameState::default() };
        let a = Self::frame(ctx, self.a, &world);
        let b = &ctx.frames[self.b];
        let (r, rd, rdd) = (b.r_0 - a.r_0, b.v_0 - a.v_0, b.a_0 - a.a_0);
        let (wa, wb) = (a.rot.tr_mul(&a.w), b.rot.tr_mul(&b.w));
        let (za, zb) = (a.rot.tr_mul(&a.z), b.rot.tr_mul(&b.z));
        match quantity {
            Quantity::Position => r,
            Quantity::Velocity(seen) => rd - Self::spin(ctx, seen).0.cross(&r),
            Quantity::Acceleration(seen) => {
                let (w, wd) = Self::spin(ctx, seen);
                rdd - wd.cross(&r) - 2.0 * w.cross(&rd) + w.cross(&w.cross(&r))
            }
            Quantity::AngularVelocity => wb - wa,
            Quantity::AngularAcceleration(seen) => (zb - za) - Self::spin(ctx, seen).0.cross(&(wb - wa)),
            Quantity::CutForce => b.rot.tr_mul(&b.f) * self.sign,
            Quantity::CutTorque => b.rot.tr_mul(&b.tau) * self.sign,
        }
    }
}

impl Component for Sensor {
    fn parts(&self) -> Vec<Part> {
        let mut parts = Vec::new();
        if self.rigid {
            parts.push(Part::Rigid { a: 0, b: 1, pose: Transform::IDENTITY });
        }
        if let Some(r) = self.frame_resolve.filter(|&r| !self.uses(r)) {
            parts.push(Part::Unused { frame: r, use_it: RESOLVE_IN_IT });
        }
        for g in &self.groups {
            self.group_parts(g, &mut parts);
        }
        parts
    }

    fn variables(&self) -> Vec<VarSpec> {
        self.variables.iter().map(|(v, _)| *v).collect()
    }

    fn evaluate(&self, ctx: &EvalContext, out: &mut Vec<f64>) {
        for (_, var) in &self.variables {
            match *var {
                Var::Vector(quantity, target) => {
                    let v = self.measure(ctx, quantity);
                    let v = match target {
                        Target::World => v,
                        Target::Frame(c) => ctx.frames[c].rot * v,
                    };
                    out.extend_from_slice(v.as_slice());
                }
                Var::Signals(outputs) => out.extend(outputs.iter().map(|&o| ctx.signals[o])),
                Var::Signal(o) => out.push(ctx.signals[o]),
                Var::Power => {
                    let a = &ctx.frames[0];
                    out.push(a.f.dot(&(a.rot * a.v_0)) + a.tau.dot(&a.w));
                }
                Var::SquaredDistance => out.push((ctx.frames[self.b].r_0 - ctx.frames[0].r_0).norm_squared()),
                Var::RelativeRotation => {
                    let world = FrameState { rot: Mat3::identity(), ..FrameState::default() };
                    let a = Self::frame(ctx, self.a, &world);
                    let r_rel = ctx.frames[self.b].rot * a.rot.transpose();
                    out.extend(r_rel.transpose().iter()); // row-major R_rel[i,j]
                }
            }
        }
    }
}

/// The connector `name` of `spec` (public or internal).
pub(crate) fn at(spec: &ComponentSpec, name: &str) -> usize {
    spec.connectors
        .iter()
        .position(|c| c.name == name)
        .unwrap_or_else(|| panic!("{} has no connector {name}", spec.kind))
}

/// The connectors `names` of `spec`.
pub(crate) fn at3(spec: &ComponentSpec, names: [&str; 3]) -> [usize; 3] {
    names.map(|n| at(spec, n))
}

/// The `resolve_in_frame` parameter of the sensors.
const fn resolve_param(variants: &'static [&'static str], doc: &'static str) -> ParamSpec {
    ParamSpec {
        name: "resolve_in_frame",
        ty: ParamType::Enum("ResolveInFrame", variants),
        default: Default::Enum("FrameA"),
        unit: "",
        doc,
    }
}

/// The resolution variants of absolute sensors and of relative ones.
const ABSOLUTE_FRAMES: &[&str] = &["World", "FrameA", "FrameResolve"];
const RELATIVE_FRAMES: &[&str] = &["World", "FrameA", "FrameB", "FrameResolve"];

/// The target named by a `ResolveInFrame` variant, with the connectors of
/// frame_a, frame_b and frame_resolve.
fn target_of(variant: &str, frame_a: usize, frame_b: Option<usize>, frame_resolve: Option<usize>) -> Target {
    match (variant, frame_b, frame_resolve) {
        ("FrameA", ..) => Target::Frame(frame_a),
        ("FrameB", Some(b), _) => Target::Frame(b),
        ("FrameResolve", _, Some(r)) => Target::Frame(r),
        _ => Target::World,
    }
}

/// The Euler sequence of the angle sensors.
const SEQUENCE: ParamSpec = ParamSpec {
    name: "sequence",
    ty: ParamType::IntVector(3),
    default: Default::Vector(&[1.0, 2.0, 3.0]),
    unit: "",
    doc: "Axes (1 = x, 2 = y, 3 = z) of the three rotations, in order",
};

/// The first angle's branch of the angle sensors (Modelica's guessAngle1).
const GUESS_ANGLE1: ParamSpec = ParamSpec::real(
    "guess_angle1",
    0.0,
    "rad",
    "Of the two solutions, return the one whose first angle is nearest this value (and this value where the \
     first angle is undefined)",
);

/// A frame connector.
const fn frame(name: &'static str, doc: &'static str) -> ConnectorSpec {
    ConnectorSpec::frame(name, doc)
}

/// An output connector.
const fn output(name: &'static str, doc: &'static str) -> ConnectorSpec {
    ConnectorSpec::output(name, doc)
}

/// An internal output connector.
const fn internal(name: &'static str) -> ConnectorSpec {
    ConnectorSpec::internal(name, ConnectorType::RealOutput)
}

/// The `VarSpec` named `name` of `spec`.
fn var(spec: &ComponentSpec, name: &str) -> VarSpec {
    *spec.variables.iter().find(|v| v.name == name).unwrap_or_else(|| panic!("{} has no variable {name}", spec.kind))
}

fn boxed(s: Sensor) -> Result<Box<dyn Component>, Error> {
    Ok(Box::new(s))
}
