//! PlanarMechanics sensors: absolute and relative positions, velocities
//! and accelerations of planar frames, their distance, the cut force,
//! cut torque and power through a planar frame, and the blocks that turn
//! planar vectors from one frame into another.
//!
//! A planar sensor's outputs come in threes, `[x, y, angle]`: a vector in
//! the plane, resolved in the world or in a frame (`resolve_in_frame`), and
//! its angular part, which turning about z leaves alone. As in the 3-D
//! sensors, outputs of positions and velocities are blocks of the signal
//! graph (other components may read them); outputs that need the
//! accelerations or the cut forces are recorded in the results, but a
//! model that reads one is refused at assembly ([`SignalLaw::Unavailable`]).
//! Every output is also a variable of the same name, so the results hold
//! them all.
//!
//! Angles are those of the frames' rotations about z, in (-pi, pi]: they
//! do not keep counting past a half turn as a body's own `phi` does.

use super::super::sensors::{at, at3};
use super::super::spec::{ComponentSpec, ConnectorSpec, ConnectorType, Default, ParamSpec, ParamType, VarSpec};
use super::super::{Component, EvalContext, FrameState, ParamSet, Part, Resolve, SignalLaw};
use super::{FRAME_A, FRAME_B, RENDER, Z_POSITION};
use crate::math::rotation::planar_angle;
use crate::math::{Mat3, Transform, Vec3};
use crate::Error;

use super::super::one_d::NEEDS_ACCELERATIONS;
const NEEDS_CUT_FORCES: &str = "depends on cut forces, which are solved after the signals \
    (reading it would make an algebraic loop through the dynamics); it is recorded in the results";
const INTERNAL: &str = "is internal";

/// The angle of a rotation about z as the signal graph computes it: the
/// last of the Cardan angles x, y, z.
const Z_ANGLE: SignalLaw = SignalLaw::FrameAngles { index: 2, sequence: [1, 2, 3], guess: 0.0 };

const FRAME_RESOLVE: ConnectorSpec = ConnectorSpec::frame_2d(
    "frame_resolve",
    "Output vectors are resolved in this frame when resolve_in_frame = FrameResolve",
);

const fn resolve_param(name: &'static str, variants: &'static [&'static str], doc: &'static str) -> ParamSpec {
    ParamSpec { name, ty: ParamType::Enum("ResolveInFrame", variants), default: Default::Enum("FrameA"), unit: "", doc }
}

const ABSOLUTE_FRAMES: &[&str] = &["World", "FrameA", "FrameResolve"];
const RELATIVE_FRAMES: &[&str] = &["World", "FrameA", "FrameB", "FrameResolve"];
const ABSOLUTE_RESOLVE: ParamSpec =
    resolve_param("resolve_in_frame", ABSOLUTE_FRAMES, "Frame in which the output vector is resolved");
const RELATIVE_RESOLVE: ParamSpec =
    resolve_param("resolve_in_frame", RELATIVE_FRAMES, "Frame in which the output vector is resolved");

const fn output(name: &'static str, doc: &'static str) -> ConnectorSpec {
    ConnectorSpec::output(name, doc)
}

const fn internal(name: &'static str) -> ConnectorSpec {
    ConnectorSpec::internal(name, ConnectorType::RealOutput)
}

/// The world or the frame at a connector.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Target {
    World,
    Frame(usize),
}

impl Target {
    /// The connector of a frame target.
    fn frame(self) -> Option<usize> {
        match self {
            Target::World => None,
            Target::Frame(c) => Some(c),
        }
    }
}

/// The target a `ResolveInFrame` variant names.
fn target_of(p: &ParamSet, name: &str, frame_a: usize, frame_b: Option<usize>) -> Target {
    let resolve = p.spec.connectors.iter().position(|c| c.name == "frame_resolve");
    match (p.variant(name), frame_b, resolve) {
        ("FrameA", ..) => Target::Frame(frame_a),
        ("FrameB", Some(b), _) => Target::Frame(b),
        ("FrameResolve", _, Some(r)) => Target::Frame(r),
        _ => Target::World,
    }
}

/// The frame state at `c`, or the world's (at rest) without one.
fn state<'a>(ctx: &'a EvalContext, c: Option<usize>, world: &'a FrameState) -> &'a FrameState {
    c.map_or(world, |c| &ctx.frames[c])
}

fn world_state() -> FrameState {
    FrameState { rot: Mat3::identity(), ..FrameState::default() }
}

/// Angular velocity and acceleration about z of a frame.
fn spin(f: &FrameState) -> (f64, f64) {
    (f.rot.tr_mul(&f.w).z, f.rot.tr_mul(&f.z).z)
}

/// `w ez x r` for a turn rate `w` about z.
fn turn(w: f64, r: Vec3) -> Vec3 {
    Vec3::new(-w * r.y, w * r.x, 0.0)
}

/// A signal block.
fn block(output: usize, law: SignalLaw, inputs: [Option<usize>; 3], frames: [Option<usize>; 2]) -> Part {
    Part::Signal { output, law, inputs, frames, flanges: [None; 2] }
}

fn unavailable(output: usize, reason: &'static str) -> Part {
    block(output, SignalLaw::Unavailable { reason }, [None; 3], [None; 2])
}

// ---------------------------------------------------------------------------
// Absolute and relative kinematics.

/// The derivative a kinematic sensor measures.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Level {
    Position,
    Velocity,
    Acceleration,
}

/// The library's intermediate variables a sensor records besides its
/// outputs.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Extra {
    /// `px`, `py`, `pphi`: the world position and angle of the frame.
    WorldPosition,
    /// `vx`, `vy`, `vphi`: its world velocity and turn rate.
    WorldVelocity,
    /// `rpx`, `rpy`, `rpphi`: the relative position resolved in frame_a,
    /// and the relative angle.
    RelativePositionInA,
}

/// The motion of frame `b` relative to frame `a` (the world for absolute
/// sensors) at one level, resolved in `resolve`, on three outputs.
#[derive(Debug)]
struct Kinematic {
    a: Option<usize>,
    b: usize,
    level: Level,
    resolve: Target,
    frame_resolve: usize,
    outputs: [usize; 3],
    /// Internal outputs of the vector in world coordinates, turned into
    /// frame_resolve's by a second block.
    internal: [usize; 2],
    extras: &'static [Extra],
    /// The kind's variables: those of `extras`, then the outputs.
    variables: &'static [VarSpec],
}

impl Kinematic {
    /// The resolution of the signal laws (whose frames are `[a, b]`) for
    /// `target`, or `None` for frame_resolve.
    fn resolve_of(&self, target: Target) -> Option<Resolve> {
        match target {
            Target::World => Some(Resolve::World),
            Target::Frame(c) if Some(c) == self.a => Some(Resolve::FrameA),
            Target::Frame(c) if c == self.b => Some(Resolve::FrameB),
            Target::Frame(_) => None,
        }
    }

    /// The law of component `index` (x or y) of the vector, resolved in
    /// `resolve`.
    fn vector_law(&self, index: usize, resolve: Resolve) -> SignalLaw {
        match (self.level, self.a) {
            (Level::Position, _) => SignalLaw::FramePosition { index, resolve },
            (Level::Velocity, None) => SignalLaw::FrameVelocity { index, resolve },
            // The rate of the relative position resolved in frame_a.
            (Level::Velocity, Some(_)) => SignalLaw::RelativeVelocity { index, seen_from: Resolve::FrameA, resolve },
            (Level::Acceleration, _) => SignalLaw::Unavailable { reason: NEEDS_ACCELERATIONS },
        }
    }

    /// The vector (world coordinates) and the angular part, the vector
    /// not yet resolved.
    fn measure(&self, ctx: &EvalContext) -> (Vec3, f64) {
        let world = world_state();
        let a = state(ctx, self.a, &world);
        let b = &ctx.frames[self.b];
        let res = state(ctx, self.resolve.frame(), &world);
        let (r, rd, rdd) = (b.r_0 - a.r_0, b.v_0 - a.v_0, b.a_0 - a.a_0);
        let ((wa, za), (wb, zb)) = (spin(a), spin(b));
        match (self.level, self.a) {
            // An absolute angle is measured from the resolve frame, a
            // relative one from frame_a.
            (Level::Position, None) => (r, planar_angle(&(b.rot * res.rot.transpose()))),
            (Level::Position, Some(_)) => (r, planar_angle(&(b.rot * a.rot.transpose()))),
            (Level::Velocity, _) => (rd - turn(wa, r), wb - wa),
            (Level::Acceleration, None) => (rdd, zb),
            (Level::Acceleration, Some(_)) => {
                // The rate, seen from the resolve frame, of the velocity
                // seen from frame_a: the library differentiates after
                // turning it into the resolve frame.
                let v = rd - turn(wa, r);
                let v_rate = rdd - turn(za, r) - turn(wa, rd);
                (v_rate - turn(spin(res).0, v), zb - za)
            }
        }
    }
}

impl Component for Kinematic {
    fn parts(&self) -> Vec<Part> {
        let mut parts = Vec::new();
        let frames = [self.a, Some(self.b)];
        if self.resolve != Target::Frame(self.frame_resolve) {
            // Unused, it stays at the world's origin (so it is not a loose frame).
            parts.push(Part::Unused { frame: self.frame_resolve, use_it: crate::components::sensors::RESOLVE_IN_IT });
        }
        let [ix, iy] = self.internal;
        match self.resolve_of(self.resolve) {
            Some(resolve) => {
                for index in 0..2 {
                    parts.push(block(self.outputs[index], self.vector_law(index, resolve), [None; 3], frames));
                }
                parts.extend([unavailable(ix, INTERNAL), unavailable(iy, INTERNAL)]);
            }
            None if self.level == Level::Acceleration => {
                for index in 0..2 {
                    parts.push(unavailable(self.outputs[index], NEEDS_ACCELERATIONS));
                }
                parts.extend([unavailable(ix, INTERNAL), unavailable(iy, INTERNAL)]);
            }
            None => {
                for (index, i) in [ix, iy].into_iter().enumerate() {
                    parts.push(block(i, self.vector_law(index, Resolve::World), [None; 3], frames));
                    let law = SignalLaw::ResolveVector { index };
                    parts.push(block(
                        self.outputs[index],
                        law,
                        [Some(ix), Some(iy), None],
                        [None, Some(self.frame_resolve)],
                    ));
                }
            }
        }
        let angle = self.outputs[2];
        parts.push(match (self.level, self.a) {
            (Level::Position, None) => block(angle, Z_ANGLE, [None; 3], [self.resolve.frame(), Some(self.b)]),
            (Level::Position, Some(_)) => block(angle, Z_ANGLE, [None; 3], frames),
            (Level::Velocity, _) => {
                block(angle, SignalLaw::AngularVelocity { index: 2, resolve: Resolve::World }, [None; 3], frames)
            }
            (Level::Acceleration, _) => unavailable(angle, NEEDS_ACCELERATIONS),
        });
        parts
    }

    fn variables(&self) -> Vec<VarSpec> {
        self.variables.to_vec()
    }

    fn evaluate(&self, ctx: &EvalContext, out: &mut Vec<f64>) {
        let world = world_state();
        let b = &ctx.frames[self.b];
        for extra in self.extras {
            match extra {
                Extra::WorldPosition => out.extend([b.r_0.x, b.r_0.y, planar_angle(&b.rot)]),
                Extra::WorldVelocity => out.extend([b.v_0.x, b.v_0.y, spin(b).0]),
                Extra::RelativePositionInA => {
                    let a = state(ctx, self.a, &world);
                    let r = a.rot * (b.r_0 - a.r_0);
                    out.extend([r.x, r.y, planar_angle(&(b.rot * a.rot.transpose()))]);
                }
            }
        }
        let (v, s) = self.measure(ctx);
        let v = state(ctx, self.resolve.frame(), &world).rot * v;
        out.extend([v.x, v.y, s]);
    }
}

/// Builds a kinematic sensor of `p.spec`: absolute (frame_a measured from
/// the world) or relative (frame_b from frame_a).
fn kinematic(
    p: &ParamSet,
    level: Level,
    outputs: [&str; 3],
    extras: &'static [Extra],
) -> Result<Box<dyn Component>, Error> {
    let spec = p.spec;
    let frame_a = at(spec, "frame_a");
    let frame_b = spec.connectors.iter().position(|c| c.name == "frame_b");
    let (a, b) = match frame_b {
        Some(b) => (Some(frame_a), b),
        None => (None, frame_a),
    };
    Ok(Box::new(Kinematic {
        a,
        b,
        level,
        resolve: target_of(p, "resolve_in_frame", frame_a, frame_b),
        frame_resolve: at(spec, "frame_resolve"),
        outputs: at3(spec, outputs),
        internal: [at(spec, "world_x"), at(spec, "world_y")],
        extras,
        variables: spec.variables,
    }))
}

/// A kinematic sensor's kind: its resolve parameter, its frames, its
/// outputs (also recorded as variables, after the library's variables
/// `vars`), and the two internal outputs of the world-resolved vector.
macro_rules! kinematic_spec {
    ($static:ident, $kind:literal, $doc:literal, $resolve:expr, [$($frame:expr),*], $level:expr, $extras:expr,
     [$(($out:literal, $unit:literal, $out_doc:literal)),*], [$($var:expr),*]) => {
        pub static $static: ComponentSpec = ComponentSpec {
            kind: $kind,
            doc: $doc,
            params: &[$resolve],
            connectors: &[
                $($frame,)*
                FRAME_RESOLVE,
                $(output($out, $out_doc),)*
                internal("world_x"),
                internal("world_y"),
            ],
            variables: &[$($var,)* $(VarSpec::scalar($out, $unit, $out_doc)),*],
            build: |p| kinematic(p, $level, [$($out),*], $extras),
            shapes: super::super::shapes::none,
        };
    };
}

const MEASURED: ConnectorSpec = ConnectorSpec::frame_2d("frame_a", "The planar frame whose motion is measured");

const WORLD_POSITION: [VarSpec; 3] = [
    VarSpec::scalar("px", "m", "x of frame_a, world coordinates"),
    VarSpec::scalar("py", "m", "y of frame_a, world coordinates"),
    VarSpec::scalar("pphi", "rad", "Angle of frame_a"),
];
const WORLD_VELOCITY: [VarSpec; 3] = [
    VarSpec::scalar("vx", "m/s", "x of frame_a's velocity, world coordinates"),
    VarSpec::scalar("vy", "m/s", "y of frame_a's velocity, world coordinates"),
    VarSpec::scalar("vphi", "rad/s", "Angular velocity of frame_a"),
];
const RELATIVE_IN_A: [VarSpec; 3] = [
    VarSpec::scalar("rpx", "m", "x of frame_b relative to frame_a, resolved in frame_a"),
    VarSpec::scalar("rpy", "m", "y of frame_b relative to frame_a, resolved in frame_a"),
    VarSpec::scalar("rpphi", "rad", "Angle from frame_a to frame_b"),
];

kinematic_spec!(
    ABSOLUTE_POSITION,
    "PlanarMechanics.AbsolutePosition",
    "Measures the position of frame_a's origin, resolved in the world, in frame_a or in frame_resolve, and \
     its angle from that frame (World: frame_a's angle; FrameA: 0), as x, y, phi. Exerts no force.",
    ABSOLUTE_RESOLVE,
    [MEASURED],
    Level::Position,
    &[],
    [("x", "m", "x of the position"), ("y", "m", "y of the position"), ("phi", "rad", "Angle from the resolve frame")],
    []
);

kinematic_spec!(
    ABSOLUTE_VELOCITY,
    "PlanarMechanics.AbsoluteVelocity",
    "Measures the velocity of frame_a's origin (the rate of its world position), resolved in the world, in \
     frame_a or in frame_resolve, and its angular velocity, as v_x, v_y, w. Exerts no force.",
    ABSOLUTE_RESOLVE,
    [MEASURED],
    Level::Velocity,
    &[Extra::WorldPosition],
    [("v_x", "m/s", "x of the velocity"), ("v_y", "m/s", "y of the velocity"), ("w", "rad/s", "Angular velocity")],
    [WORLD_POSITION[0], WORLD_POSITION[1], WORLD_POSITION[2]]
);

kinematic_spec!(
    ABSOLUTE_ACCELERATION,
    "PlanarMechanics.AbsoluteAcceleration",
    "Measures the acceleration of frame_a's origin (the second rate of its world position), resolved in the \
     world, in frame_a or in frame_resolve, and its angular acceleration, as a_x, a_y, alpha. Exerts no force. \
     The outputs depend on the accelerations: recorded in the results, they cannot be read by other components.",
    ABSOLUTE_RESOLVE,
    [MEASURED],
    Level::Acceleration,
    &[Extra::WorldPosition, Extra::WorldVelocity],
    [
        ("a_x", "m/s2", "x of the acceleration (recorded only)"),
        ("a_y", "m/s2", "y of the acceleration (recorded only)"),
        ("alpha", "rad/s2", "Angular acceleration (recorded only)")
    ],
    [WORLD_POSITION[0], WORLD_POSITION[1], WORLD_POSITION[2], WORLD_VELOCITY[0], WORLD_VELOCITY[1], WORLD_VELOCITY[2]]
);

kinematic_spec!(
    RELATIVE_POSITION,
    "PlanarMechanics.RelativePosition",
    "Measures the vector from frame_a's origin to frame_b's, resolved in the world, frame_a, frame_b or \
     frame_resolve, and the angle from frame_a to frame_b, as rel_x, rel_y, rel_phi. Exerts no force.",
    RELATIVE_RESOLVE,
    [FRAME_A, FRAME_B],
    Level::Position,
    &[],
    [
        ("rel_x", "m", "x of the relative position"),
        ("rel_y", "m", "y of the relative position"),
        ("rel_phi", "rad", "Angle from frame_a to frame_b")
    ],
    []
);

kinematic_spec!(
    RELATIVE_VELOCITY,
    "PlanarMechanics.RelativeVelocity",
    "Measures the rate of the relative position of frame_b's origin resolved in frame_a (its velocity as \
     frame_a sees it), then resolved in the world, frame_a, frame_b or frame_resolve, and the relative \
     angular velocity, as rel_v_x, rel_v_y, rel_w. Exerts no force.",
    RELATIVE_RESOLVE,
    [FRAME_A, FRAME_B],
    Level::Velocity,
    &[Extra::RelativePositionInA],
    [
        ("rel_v_x", "m/s", "x of the relative velocity"),
        ("rel_v_y", "m/s", "y of the relative velocity"),
        ("rel_w", "rad/s", "Relative angular velocity")
    ],
    [RELATIVE_IN_A[0], RELATIVE_IN_A[1], RELATIVE_IN_A[2]]
);

kinematic_spec!(
    RELATIVE_ACCELERATION,
    "PlanarMechanics.RelativeAcceleration",
    "Measures the rate, in the resolve frame, of RelativeVelocity's vector (the relative position \
     differentiated in frame_a, resolved in the world, frame_a, frame_b or frame_resolve, then differentiated \
     again), and the relative angular acceleration, as rel_a_x, rel_a_y, rel_alpha. Exerts no force. The \
     outputs depend on the accelerations: recorded in the results, they cannot be read by other components.",
    RELATIVE_RESOLVE,
    [FRAME_A, FRAME_B],
    Level::Acceleration,
    &[],
    [
        ("rel_a_x", "m/s2", "x of the relative acceleration (recorded only)"),
        ("rel_a_y", "m/s2", "y of the relative acceleration (recorded only)"),
        ("rel_alpha", "rad/s2", "Relative angular acceleration (recorded only)")
    ],
    []
);

// ---------------------------------------------------------------------------
// Distance.

const DRAWING: [ParamSpec; 2] =
    [ParamSpec::real("arrow_diameter", 0.03, "m", "Diameter of the arrow drawn (kept for compatibility)"), Z_POSITION];

pub static DISTANCE: ComponentSpec = ComponentSpec {
    kind: "PlanarMechanics.Distance",
    doc: "Measures the distance between the origins of frame_a and frame_b as `distance`; below s_small a \
          polynomial replaces the square root (no infinite derivative at zero). Exerts no force.",
    params: &[
        ParamSpec::real("s_small", 1e-10, "m", "Below this distance the square root is smoothed"),
        DRAWING[0],
        DRAWING[1],
        RENDER,
    ],
    connectors: &[FRAME_A, FRAME_B, output("distance", "Distance between the origins")],
    variables: &[
        VarSpec::scalar("L2", "m2", "Squared distance between the origins"),
        VarSpec::scalar("s_small2", "m2", "s_small squared"),
        VarSpec::scalar("distance", "m", "Distance between the origins"),
    ],
    build: |p| Ok(Box::new(Distance { s_small: p.non_negative("s_small", false)? })),
    shapes: super::super::shapes::none,
};

#[derive(Debug)]
struct Distance {
    s_small: f64,
}

impl Component for Distance {
    fn parts(&self) -> Vec<Part> {
        vec![block(2, SignalLaw::FrameDistance { s_small: self.s_small }, [None; 3], [Some(0), Some(1)])]
    }

    fn variables(&self) -> Vec<VarSpec> {
        DISTANCE.variables.to_vec()
    }

    fn evaluate(&self, ctx: &EvalContext, out: &mut Vec<f64>) {
        out.extend([(ctx.frames[1].r_0 - ctx.frames[0].r_0).norm_squared(), self.s_small * self.s_small]);
        out.push(ctx.signals[2]);
    }
}

// ---------------------------------------------------------------------------
// Cut force, cut torque and power: frame_a and frame_b are one frame.

const CUT_A: ConnectorSpec =
    ConnectorSpec::frame_2d("frame_a", "The side the measured force and torque act on the sensor from");
const CUT_B: ConnectorSpec = ConnectorSpec::frame_2d("frame_b", "The other side: the same frame as frame_a");
const POSITIVE_SIGN: ParamSpec = ParamSpec::boolean(
    "positive_sign",
    true,
    "true: the force (torque) acting on the sensor at frame_a; false: its negative (that at frame_b)",
);
const ARROWS: [ParamSpec; 2] = [
    ParamSpec::real("scale", 0.1, "m/N", "Length of the arrow drawn per newton (kept for compatibility)"),
    ParamSpec::real("arrow_diameter", 0.03, "m", "Diameter of the arrow drawn (kept for compatibility)"),
];

#[derive(Clone, Copy, Debug, PartialEq)]
enum Through {
    /// `[force_x, force_y]`, then `f0x`, `f0y`, `phi_resolve`.
    Force { sign: f64, resolve: Target },
    /// `torque`.
    Torque { sign: f64 },
    /// `power`.
    Power,
}

#[derive(Debug)]
struct Inline {
    through: Through,
    outputs: Vec<usize>,
}

impl Component for Inline {
    fn parts(&self) -> Vec<Part> {
        let mut parts = vec![Part::Rigid { a: 0, b: 1, pose: Transform::IDENTITY }];
        parts.extend(self.outputs.iter().map(|&o| unavailable(o, NEEDS_CUT_FORCES)));
        parts
    }

    fn variables(&self) -> Vec<VarSpec> {
        match self.through {
            Through::Force { .. } => CUT_FORCE.variables,
            Through::Torque { .. } => CUT_TORQUE.variables,
            Through::Power => POWER.variables,
        }
        .to_vec()
    }

    fn evaluate(&self, ctx: &EvalContext, out: &mut Vec<f64>) {
        let a = &ctx.frames[0];
        // The cut force and torque on the sensor at frame_a, world coordinates.
        let (f, tau) = (a.rot.tr_mul(&a.f), a.rot.tr_mul(&a.tau).z);
        match self.through {
            Through::Force { sign, resolve } => {
                let f0 = f * sign;
                let rot = if resolve == Target::World { Mat3::identity() } else { a.rot };
                let out_f = rot * f0;
                let phi = if resolve == Target::World { 0.0 } else { planar_angle(&a.rot) };
                out.extend([out_f.x, out_f.y, f0.x, f0.y, phi]);
            }
            Through::Torque { sign } => out.push(sign * tau),
            Through::Power => out.push(f.x * a.v_0.x + f.y * a.v_0.y + tau * spin(a).0),
        }
    }
}

fn sign(p: &ParamSet) -> f64 {
    if p.boolean("positive_sign") {
        1.0
    } else {
        -1.0
    }
}

pub static CUT_FORCE: ComponentSpec = ComponentSpec {
    kind: "PlanarMechanics.CutForce",
    doc: "Sits between two parts (frame_a and frame_b are one frame) and reports the force that acts on it at \
          frame_a (its negative with positive_sign = false), resolved in the world, frame_a or frame_b, as \
          force_x, force_y. The outputs depend on the cut forces: recorded in the results, they cannot be read \
          by other components.",
    params: &[
        resolve_param("resolve_in_frame", &["World", "FrameA", "FrameB"], "Frame in which the force is resolved"),
        POSITIVE_SIGN,
        ARROWS[0],
        ARROWS[1],
        Z_POSITION,
        RENDER,
    ],
    connectors: &[
        CUT_A,
        CUT_B,
        output("force_x", "x of the cut force (recorded only)"),
        output("force_y", "y of the cut force (recorded only)"),
    ],
    variables: &[
        VarSpec::scalar("force_x", "N", "x of the cut force, resolved in resolve_in_frame"),
        VarSpec::scalar("force_y", "N", "y of the cut force, resolved in resolve_in_frame"),
        VarSpec::scalar("f0x", "N", "x of the cut force, world coordinates"),
        VarSpec::scalar("f0y", "N", "y of the cut force, world coordinates"),
        VarSpec::scalar("phi_resolve", "rad", "Angle of the frame the force is resolved in"),
    ],
    build: |p| {
        let resolve = target_of(p, "resolve_in_frame", 0, Some(1));
        Ok(Box::new(Inline { through: Through::Force { sign: sign(p), resolve }, outputs: vec![2, 3] }))
    },
    shapes: super::super::shapes::none,
};

pub static CUT_TORQUE: ComponentSpec = ComponentSpec {
    kind: "PlanarMechanics.CutTorque",
    doc: "Sits between two parts (frame_a and frame_b are one frame) and reports the torque about z that acts \
          on it at frame_a (its negative with positive_sign = false) as `torque`. The output depends on the cut \
          forces: recorded in the results, it cannot be read by other components.",
    params: &[POSITIVE_SIGN, ARROWS[0], ARROWS[1], Z_POSITION, RENDER],
    connectors: &[CUT_A, CUT_B, output("torque", "The cut torque (recorded only)")],
    variables: &[VarSpec::scalar("torque", "N.m", "The cut torque about z")],
    build: |p| Ok(Box::new(Inline { through: Through::Torque { sign: sign(p) }, outputs: vec![2] })),
    shapes: super::super::shapes::none,
};

pub static POWER: ComponentSpec = ComponentSpec {
    kind: "PlanarMechanics.Power",
    doc: "Sits between two parts (frame_a and frame_b are one frame) and reports the power flowing from \
          frame_a to frame_b, fx vx + fy vy + tau w at frame_a, as `power`. It depends on the cut forces: \
          recorded in the results, it cannot be read by other components.",
    params: &[],
    connectors: &[CUT_A, CUT_B, output("power", "Power flowing from frame_a to frame_b (recorded only)")],
    variables: &[VarSpec::scalar("power", "W", "Power flowing from frame_a to frame_b")],
    build: |_| Ok(Box::new(Inline { through: Through::Power, outputs: vec![2] })),
    shapes: super::super::shapes::none,
};

// ---------------------------------------------------------------------------
// Transforming planar vectors between frames.

const IN_OUT: [ConnectorSpec; 6] = [
    ConnectorSpec::input("x_in", "x of the vector, in frame_in"),
    ConnectorSpec::input("y_in", "y of the vector, in frame_in"),
    ConnectorSpec::input("phi_in", "Angular part of the vector"),
    output("x_out", "x of the vector, in frame_out"),
    output("y_out", "y of the vector, in frame_out"),
    output("phi_out", "Angular part of the vector"),
];

const IN_OUT_VARIABLES: &[VarSpec] = &[
    VarSpec::scalar("x_out", "", "x of the vector, in frame_out"),
    VarSpec::scalar("y_out", "", "y of the vector, in frame_out"),
    VarSpec::scalar("phi_out", "", "Angular part of the vector"),
];

pub static TRANSFORM_ABSOLUTE_VECTOR: ComponentSpec = ComponentSpec {
    kind: "PlanarMechanics.TransformAbsoluteVector",
    doc: "Turns the planar vector [x_in, y_in] given in frame_in (the world, frame_a or frame_resolve) into \
          frame_out's coordinates as [x_out, y_out]. As in the library, the angular part gains the angle of \
          frame_in when frame_in is a frame and differs from frame_out (phi_out = phi_in + its angle); with \
          frame_in = frame_out everything passes unchanged. Exerts no force.",
    params: &[
        resolve_param("frame_in", ABSOLUTE_FRAMES, "Frame the input vector is resolved in"),
        resolve_param("frame_out", ABSOLUTE_FRAMES, "Frame the output vector is resolved in"),
    ],
    connectors: &[
        ConnectorSpec::frame_2d("frame_a", "The frame of frame_in or frame_out = FrameA"),
        FRAME_RESOLVE,
        IN_OUT[0],
        IN_OUT[1],
        IN_OUT[2],
        IN_OUT[3],
        IN_OUT[4],
        IN_OUT[5],
        internal("angle_in"),
    ],
    variables: IN_OUT_VARIABLES,
    build: |p| transform(p, true),
    shapes: super::super::shapes::none,
};

pub static TRANSFORM_RELATIVE_VECTOR: ComponentSpec = ComponentSpec {
    kind: "PlanarMechanics.TransformRelativeVector",
    doc: "Turns the planar vector [x_in, y_in] given in frame_in (the world, frame_a, frame_b or \
          frame_resolve) into frame_out's coordinates as [x_out, y_out]; the angular part passes unchanged. \
          Exerts no force.",
    params: &[
        resolve_param("frame_in", RELATIVE_FRAMES, "Frame the input vector is resolved in"),
        resolve_param("frame_out", RELATIVE_FRAMES, "Frame the output vector is resolved in"),
    ],
    connectors: &[
        FRAME_A,
        FRAME_B,
        FRAME_RESOLVE,
        IN_OUT[0],
        IN_OUT[1],
        IN_OUT[2],
        IN_OUT[3],
        IN_OUT[4],
        IN_OUT[5],
        internal("angle_in"),
    ],
    variables: IN_OUT_VARIABLES,
    build: |p| transform(p, false),
    shapes: super::super::shapes::none,
};

fn transform(p: &ParamSet, absolute: bool) -> Result<Box<dyn Component>, Error> {
    let spec = p.spec;
    let frame_a = at(spec, "frame_a");
    let frame_b = spec.connectors.iter().position(|c| c.name == "frame_b");
    Ok(Box::new(TransformVector {
        frame_in: target_of(p, "frame_in", frame_a, frame_b),
        frame_out: target_of(p, "frame_out", frame_a, frame_b),
        frame_resolve: at(spec, "frame_resolve"),
        inputs: at3(spec, ["x_in", "y_in", "phi_in"]),
        outputs: at3(spec, ["x_out", "y_out", "phi_out"]),
        angle_in: at(spec, "angle_in"),
        absolute,
    }))
}

#[derive(Debug)]
struct TransformVector {
    frame_in: Target,
    frame_out: Target,
    frame_resolve: usize,
    inputs: [usize; 3],
    outputs: [usize; 3],
    /// An internal output: the angle of frame_in (absolute vectors).
    angle_in: usize,
    /// TransformAbsoluteVector (adds frame_in's angle to the angular part).
    absolute: bool,
}

impl TransformVector {
    /// Whether the angular part gains frame_in's angle.
    fn adds_angle(&self) -> bool {
        self.absolute && self.frame_in != self.frame_out && self.frame_in != Target::World
    }
}

impl Component for TransformVector {
    fn parts(&self) -> Vec<Part> {
        let mut parts = Vec::new();
        let r = Target::Frame(self.frame_resolve);
        if self.frame_in != r && self.frame_out != r {
            parts.push(Part::Unused { frame: self.frame_resolve, use_it: crate::components::sensors::RESOLVE_IN_IT });
        }
        let [x_in, y_in, phi_in] = self.inputs.map(Some);
        let pass = SignalLaw::Affine { gains: [1.0, 0.0, 0.0], bias: 0.0 };
        for index in 0..2 {
            let output = self.outputs[index];
            parts.push(if self.frame_in == self.frame_out {
                block(output, pass.clone(), [Some(self.inputs[index]), None, None], [None; 2])
            } else {
                let frames = [self.frame_in.frame(), self.frame_out.frame()];
                block(output, SignalLaw::ResolveVector { index }, [x_in, y_in, None], frames)
            });
        }
        if self.adds_angle() {
            parts.push(block(self.angle_in, Z_ANGLE, [None; 3], [None, self.frame_in.frame()]));
            let sum = SignalLaw::Affine { gains: [1.0, 1.0, 0.0], bias: 0.0 };
            parts.push(block(self.outputs[2], sum, [phi_in, Some(self.angle_in), None], [None; 2]));
        } else {
            parts.push(unavailable(self.angle_in, INTERNAL));
            parts.push(block(self.outputs[2], pass, [phi_in, None, None], [None; 2]));
        }
        parts
    }

    fn variables(&self) -> Vec<VarSpec> {
        IN_OUT_VARIABLES.to_vec()
    }

    fn evaluate(&self, ctx: &EvalContext, out: &mut Vec<f64>) {
        let world = world_state();
        let [x, y, phi] = self.inputs.map(|i| ctx.signals[i]);
        if self.frame_in == self.frame_out {
            out.extend([x, y, phi]);
            return;
        }
        let from = state(ctx, self.frame_in.frame(), &world);
        let to = state(ctx, self.frame_out.frame(), &world);
        let v = to.rot * from.rot.tr_mul(&Vec3::new(x, y, 0.0));
        let phi = if self.adds_angle() { phi + planar_angle(&from.rot) } else { phi };
        out.extend([v.x, v.y, phi]);
    }
}
