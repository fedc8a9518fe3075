//! The component library: one file per component kind, and the registry
//! that lists them.
//!
//! A component kind is a [`ComponentSpec`] (its parameter, connector and
//! variable tables) and a [`Component`] built from validated parameters. A
//! component says what it adds to the mechanism as [`Part`]s (a fixed pose
//! in the world, a rigid relation between two of its frames, a mass, a
//! joint, ownership of an orientation, a 1-D force law) and computes its
//! output variables from the solved motion ([`EvalContext`]).

pub mod params;
pub mod shapes;
pub mod spec;

mod bevel_gear_1d;
pub(crate) mod blocks;
mod body;
mod body_box;
mod body_cylinder;
mod body_shape;
mod constraint_joint;
mod contact_1d;
mod coordinate_joint;
mod cut_mount;
mod cylindrical;
mod damper;
mod external_load;
mod fixed;
mod fixed_rotation;
mod fixed_translation;
mod force;
mod free_motion;
mod free_motion_scalar_init;
mod friction;
mod gear_constraint;
mod ideal_gear;
mod inertia_1d;
mod line_force;
mod line_force_with_mass;
mod loop_assemblies;
mod motion_sources;
mod mounting_1d;
pub mod one_d;
mod orientation;
mod planar;
pub mod planar_mechanics;
mod point_mass;
mod prescribed;
mod prismatic;
mod prismatic_constraint;
mod revolute;
mod revolute_constraint;
mod revolute_planar_loop_constraint;
mod rod;
mod rolling_constraint_vertical_wheel;
mod rolling_wheel;
mod rolling_wheel_set;
mod rotor_1d;
mod sensors;
mod slipping_wheel;
mod spherical;
mod spherical_constraint;
mod spherical_spherical;
mod spring;
mod spring_damper_parallel;
mod torque;
mod universal;
mod universal_constraint;
mod universal_spherical;
mod urdf_body;
mod urdf_joint;
mod visualizers;
mod wheel_common;
pub(crate) mod without_effect;
pub mod world;
mod world_force;
mod world_torque;

pub use crate::system::laws::{
    resolve_input, ConstraintKind, ForceLaw, Law1D, Resolve, RotationLock, SignalSource, SlipLaw, WheelContact,
};
pub use crate::system::{DriveLevel, DriveMap, SignalLaw};
pub use body::{ImpossibleInertia, INERTIA_PARAMS};
pub use params::ParamSet;
pub use spec::{ComponentSpec, ConnectorSpec, ConnectorType, Default, ParamSpec, ParamType, Shape, VarSpec};
pub use world::WorldSettings;

use crate::math::{Mat3, RigidInertia, Transform, Vec3};
use crate::system::JointModel;

/// Every component kind, in the order `list` shows them.
pub fn registry() -> &'static [&'static ComponentSpec] {
    REGISTRY
}

static REGISTRY: &[&ComponentSpec] = &[
    &world::SPEC,
    &body::SPEC,
    &point_mass::SPEC,
    &body_shape::SPEC,
    &body_box::SPEC,
    &body_cylinder::SPEC,
    &fixed::SPEC,
    &fixed_translation::SPEC,
    &fixed_rotation::SPEC,
    &revolute::SPEC,
    &prismatic::SPEC,
    &spherical::SPEC,
    &universal::SPEC,
    &cylindrical::SPEC,
    &planar::SPEC,
    &free_motion::SPEC,
    &free_motion_scalar_init::SPEC,
    &prescribed::POSITION,
    &prescribed::POSE,
    &prescribed::VELOCITY,
    &prescribed::ACCELERATION,
    &revolute_constraint::SPEC,
    &prismatic_constraint::SPEC,
    &spherical_constraint::SPEC,
    &universal_constraint::SPEC,
    &spherical_spherical::SPEC,
    &universal_spherical::SPEC,
    &revolute_planar_loop_constraint::SPEC,
    &cut_mount::SPEC,
    &loop_assemblies::RRR,
    &loop_assemblies::RRP,
    &loop_assemblies::USR,
    &loop_assemblies::USP,
    &loop_assemblies::SSR,
    &loop_assemblies::SSP,
    &rolling_constraint_vertical_wheel::SPEC,
    &rolling_wheel::JOINT,
    &rolling_wheel::WHEEL,
    &rolling_wheel_set::JOINT,
    &rolling_wheel_set::SET,
    &slipping_wheel::SLIP_JOINT,
    &slipping_wheel::SLIPPING_WHEEL,
    &slipping_wheel::PACEJKA_JOINT,
    &slipping_wheel::PACEJKA_WHEEL,
    &spring::SPEC,
    &damper::SPEC,
    &spring_damper_parallel::SPEC,
    &line_force_with_mass::SPEC,
    &force::SPEC,
    &torque::SPEC,
    &world_force::SPEC,
    &world_torque::SPEC,
    &one_d::rotational::DAMPER,
    &one_d::rotational::SPRING,
    &one_d::rotational::SPRING_DAMPER,
    &one_d::rotational::CONSTANT,
    &one_d::rotational::DRIVEN_BY_SIGNAL,
    &one_d::rotational::POSITION_SENSOR,
    &one_d::rotational::SPEED_SENSOR,
    &one_d::rotational::ACCELERATION_SENSOR,
    &one_d::rotational::RELATIVE_POSITION_SENSOR,
    &one_d::rotational::RELATIVE_SPEED_SENSOR,
    &one_d::rotational::FIXED,
    &inertia_1d::INERTIA,
    &motion_sources::ROTATIONAL_POSITION,
    &motion_sources::ROTATIONAL_SPEED,
    &motion_sources::ROTATIONAL_ACCELERATE,
    &one_d::translational::DAMPER,
    &one_d::translational::SPRING,
    &one_d::translational::SPRING_DAMPER,
    &one_d::translational::CONSTANT,
    &one_d::translational::DRIVEN_BY_SIGNAL,
    &one_d::translational::POSITION_SENSOR,
    &one_d::translational::SPEED_SENSOR,
    &one_d::translational::ACCELERATION_SENSOR,
    &one_d::translational::RELATIVE_POSITION_SENSOR,
    &one_d::translational::RELATIVE_SPEED_SENSOR,
    &one_d::translational::FIXED,
    &inertia_1d::MASS,
    &motion_sources::TRANSLATIONAL_POSITION,
    &motion_sources::TRANSLATIONAL_SPEED,
    &motion_sources::TRANSLATIONAL_ACCELERATE,
    &friction::CLUTCH,
    &friction::ROTATIONAL_BRAKE,
    &friction::BEARING_FRICTION,
    &friction::TRANSLATIONAL_BRAKE,
    &friction::SUPPORT_FRICTION,
    &friction::ONE_WAY_CLUTCH,
    &friction::MASS_WITH_STOP_AND_FRICTION,
    &contact_1d::ELASTO_BACKLASH,
    &contact_1d::ELASTO_GAP,
    &blocks::constant::SPEC,
    &blocks::input::SPEC,
    &blocks::step::SPEC,
    &blocks::ramp::SPEC,
    &blocks::sine::SPEC,
    &blocks::time_table::SPEC,
    &blocks::math::GAIN,
    &blocks::math::ADD,
    &blocks::math::FEEDBACK,
    &blocks::math::ADD3,
    &blocks::math::PRODUCT,
    &blocks::math::DIVISION,
    &ideal_gear::SPEC,
    &ideal_gear::R2T,
    &rotor_1d::SPEC,
    &mounting_1d::SPEC,
    &bevel_gear_1d::SPEC,
    &gear_constraint::SPEC,
    &sensors::ABSOLUTE_POSITION,
    &sensors::ABSOLUTE_VELOCITY,
    &sensors::ABSOLUTE_ANGLES,
    &sensors::ABSOLUTE_ANGULAR_VELOCITY,
    &sensors::RELATIVE_POSITION,
    &sensors::RELATIVE_VELOCITY,
    &sensors::RELATIVE_ANGLES,
    &sensors::RELATIVE_ANGULAR_VELOCITY,
    &sensors::ABSOLUTE_SENSOR,
    &sensors::RELATIVE_SENSOR,
    &sensors::CUT_FORCE,
    &sensors::CUT_TORQUE,
    &sensors::CUT_FORCE_AND_TORQUE,
    &sensors::POWER,
    &sensors::DISTANCE,
    &urdf_joint::REVOLUTE,
    &urdf_joint::PRISMATIC,
    &urdf_body::CYLINDER,
    &urdf_body::BOX,
    &urdf_body::SPHERE,
    &visualizers::SPHERE_SHAPE,
    &visualizers::BOX_SHAPE,
    &visualizers::CYLINDER_SHAPE,
    &visualizers::CONE_SHAPE,
    &visualizers::ARROW_SHAPE,
    &visualizers::BOX_VISUALIZER,
    &visualizers::CYLINDER_VISUALIZER,
    &visualizers::SPHERE_VISUALIZER,
    &visualizers::FRAME_VISUALIZER,
    &visualizers::SHAPEFILE_VISUALIZER,
    &blocks::trajectories::KINEMATIC5,
    &blocks::trajectories::KINEMATIC_PTP,
    &blocks::trajectories::KINEMATIC_PTP_BOUNDED_JERK,
    &blocks::trajectories::BLOCK_KINEMATIC_PTP,
    &planar_mechanics::world::SPEC,
    &planar_mechanics::body::BODY,
    &planar_mechanics::body::BODY_SHAPE,
    &planar_mechanics::fixed::FIXED,
    &planar_mechanics::fixed::FIXED_TRANSLATION,
    &planar_mechanics::fixed::FIXED_ROTATION,
    &planar_mechanics::joints::REVOLUTE,
    &planar_mechanics::joints::PRISMATIC,
    &planar_mechanics::forces::SPRING,
    &planar_mechanics::forces::DAMPER,
    &planar_mechanics::forces::SPRING_DAMPER,
    &planar_mechanics::forces::WORLD_FORCE_TORQUE,
    &planar_mechanics::prescribed::POSITION,
    &planar_mechanics::prescribed::POSE,
    &planar_mechanics::prescribed::VELOCITY,
    &planar_mechanics::prescribed::ACCELERATION,
    &planar_mechanics::sensors::ABSOLUTE_POSITION,
    &planar_mechanics::sensors::ABSOLUTE_VELOCITY,
    &planar_mechanics::sensors::ABSOLUTE_ACCELERATION,
    &planar_mechanics::sensors::RELATIVE_POSITION,
    &planar_mechanics::sensors::RELATIVE_VELOCITY,
    &planar_mechanics::sensors::RELATIVE_ACCELERATION,
    &planar_mechanics::sensors::DISTANCE,
    &planar_mechanics::sensors::POWER,
    &planar_mechanics::sensors::CUT_FORCE,
    &planar_mechanics::sensors::CUT_TORQUE,
    &planar_mechanics::sensors::TRANSFORM_ABSOLUTE_VECTOR,
    &planar_mechanics::sensors::TRANSFORM_RELATIVE_VECTOR,
    &planar_mechanics::adapters::PLANAR_TO_MULTIBODY,
    &planar_mechanics::adapters::FRAME_VISUALIZER,
    &planar_mechanics::wheels::ROLLING,
    &planar_mechanics::wheels::SLIPPING,
    &planar_mechanics::wheels::SLIP_BASED,
];

/// The kind named `kind`. Accepts the library prefix
/// (`MultibodyComponents.Body`), the sub-package level of the libraries
/// (`RotationalComponents.Components.Damper`,
/// `BlockComponents.Math.Gain`), and the other names the 1-D libraries
/// give the same component (`TorqueSource` for `Torque`, MSL's
/// `RelAngleSensor`).
pub fn lookup(kind: &str) -> Option<&'static ComponentSpec> {
    static BY_NAME: std::sync::OnceLock<std::collections::HashMap<&'static str, &'static ComponentSpec>> =
        std::sync::OnceLock::new();
    let by_name = BY_NAME.get_or_init(|| registry().iter().map(|s| (s.kind, *s)).collect());
    if let Some(spec) = by_name.get(kind) {
        return Some(spec);
    }
    // Only library names with a prefix or a sub-package need the longer way.
    if !kind.contains('.') {
        return None;
    }
    by_name.get(canonical_kind(kind).as_str()).copied()
}

/// A kind name without the optional prefixes [`lookup`] accepts.
pub fn canonical_kind(kind: &str) -> String {
    let bare = kind.strip_prefix("MultibodyComponents.").unwrap_or(kind);
    let mut bare = bare.to_string();
    for level in [".Components.", ".Sources.", ".Sensors.", ".Math.", ".Continuous.", ".Nonlinear."] {
        // Each lowering looks up every kind: no new string where nothing changes.
        if bare.contains(level) {
            bare = bare.replace(level, ".");
        }
    }
    let other_names = [
        // The translational library re-exports the rack and pinion.
        ("TranslationalComponents.IdealGearR2T", "RotationalComponents.IdealGearR2T"),
        ("RotationalComponents.TorqueSource", "RotationalComponents.Torque"),
        ("RotationalComponents.SpeedSource", "RotationalComponents.Speed"),
        ("RotationalComponents.AccelerationSource", "RotationalComponents.Accelerate"),
        ("RotationalComponents.VelocitySensor", "RotationalComponents.SpeedSensor"),
        ("RotationalComponents.RelAngleSensor", "RotationalComponents.RelativeAngleSensor"),
        ("RotationalComponents.RelSpeedSensor", "RotationalComponents.RelativeVelocitySensor"),
        ("TranslationalComponents.VelocitySensor", "TranslationalComponents.SpeedSensor"),
        ("TranslationalComponents.RelPositionSensor", "TranslationalComponents.RelativePositionSensor"),
        ("TranslationalComponents.RelSpeedSensor", "TranslationalComponents.RelativeVelocitySensor"),
    ];
    match other_names.iter().find(|(other, _)| *other == bare) {
        Some((_, kind)) => kind.to_string(),
        None => bare,
    }
}

/// A component built from its parameters.
pub trait Component: Send + Sync + std::fmt::Debug {
    /// What the component adds to the mechanism. Connector numbers are
    /// positions in its kind's connector table.
    fn parts(&self) -> Vec<Part>;

    /// The variables this component has with its parameters, besides the
    /// `r_0`, `R`, `f` and `tau` of its frame connectors, which every
    /// component has.
    fn variables(&self) -> Vec<VarSpec> {
        Vec::new()
    }

    /// Pushes the values of [`Component::variables`], in that order.
    fn evaluate(&self, _ctx: &EvalContext, _out: &mut Vec<f64>) {}

    /// Start values of some of its states where the model gives none (a
    /// wheel's centre starts at the height of its radius), by state name.
    /// They are not fixed: closing loops may move them.
    fn default_starts(&self) -> Vec<(&'static str, Vec<f64>)> {
        Vec::new()
    }

    /// For a loop assembly whose prismatic joint closes the loop in one of
    /// two ways: which one it starts on.
    fn prismatic_branch(&self) -> Option<PrismaticBranch> {
        None
    }
}

/// The start branch of a prismatic joint that closes a loop with a rod of
/// fixed length (JointRRP's `positive_branch`, the library's and
/// Modelica's `PrismaticWithLengthConstraint`). The rod turns about
/// `normal` (fixed in frame_a) at frame_a's origin and reaches, `length`
/// away across `normal`, the point `rod2` of the slider, which sits at
/// `d = s + offset` along `axis` from frame_b (both in frame_b). With
/// `k1 = e . w` (`e` the axis and `w` the slider's point at `d = 0` from
/// frame_a's origin, across `normal`, in the world), the two closures are
/// `d = -k1 +- sqrt(k1^2 - |w|^2 + length^2)`: the positive branch takes
/// `+`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PrismaticBranch {
    pub frame_a: usize,
    pub frame_b: usize,
    /// Which of the component's joints (in the order of its parts) slides.
    pub joint: usize,
    /// Which turns the rod about `normal` at frame_a.
    pub turn: usize,
    pub axis: Vec3,
    pub offset: f64,
    pub rod2: Vec3,
    pub normal: Vec3,
    pub length: f64,
    pub positive: bool,
}

/// Names of a joint's position and velocity coordinates, with their sizes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StateNames {
    pub q: &'static [(&'static str, usize)],
    pub u: &'static [(&'static str, usize)],
}

/// A joint's 1-D connectors: the axis follows the joint coordinate, the
/// support stays with frame_a.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AxisFlanges {
    pub axis: usize,
    pub support: usize,
}

/// What a component adds to the mechanism.
#[derive(Clone, Debug, PartialEq)]
pub enum Part {
    /// The frame is fixed in the world at `pose` (world to frame).
    Ground { frame: usize, pose: Transform },
    /// A frame the component does not use as its parameters set it (a
    /// sensor's frame_resolve when resolve_in_frame names another frame):
    /// at the world's origin while nothing is connected to it; a model that
    /// connects it is told to use it or leave it (`use_it` says how).
    Unused { frame: usize, use_it: &'static str },
    /// Frame `b` is fixed relative to frame `a` at `pose` (a to b).
    Rigid { a: usize, b: usize, pose: Transform },
    /// A mass fixed to `frame`, its inertia given in that frame.
    Mass { frame: usize, inertia: RigidInertia, point_gravity: bool },
    /// A joint moving frame `b` relative to frame `a`; `iscut` asks for it
    /// to be the one cut when it closes a kinematic loop.
    Joint { a: usize, b: usize, model: JointModel, states: StateNames, flanges: Option<AxisFlanges>, iscut: bool },
    /// Ownership of the orientation (and position) of `frame`: a joint from
    /// the world with the component's states. A `fallback` owner (a planar
    /// Body's) is used only where nothing else places the frame: no joints
    /// from the ground and no other owner in its group.
    Owner { frame: usize, model: JointModel, states: StateNames, fallback: bool },
    /// A 1-D force element between two flanges.
    Element1D { a: usize, b: usize, law: Law1D },
    /// A 1-D friction element with modes between flanges `a` (the fixed
    /// ground when `None`) and `b` (sliding, stuck as a constraint, free),
    /// pressed by the signal at the input connector `normal` (always,
    /// without one).
    Friction { a: Option<usize>, b: usize, law: crate::system::friction::FrictionLaw, normal: Option<usize> },
    /// A signal block driving the output connector `output`: a function of
    /// time, of the signals at the input connectors `inputs`, or of the
    /// motion of `frames` (frame a, or the world when `None`; frame b) or
    /// of `flanges` (flange a, or the fixed support when `None`; flange b).
    Signal {
        output: usize,
        law: SignalLaw,
        inputs: [Option<usize>; 3],
        frames: [Option<usize>; 2],
        flanges: [Option<usize>; 2],
    },
    /// A linear relation `sum c_k phi_k + constant = 0` between the
    /// positions of 1-D connectors: an ideal gear, or a rod of length
    /// `-constant`. Where it can, assembly makes it rigid (the driven side
    /// follows the driving one, with no constraint force to solve for);
    /// otherwise it is a constraint. A `measured` one (an in-line sensor
    /// reads the flow through it) always stays a constraint, whose
    /// multiplier is that flow.
    Coupling { terms: Vec<(usize, f64)>, constant: f64, measured: bool },
    /// A rigid 1-D body from connector `a` to connector `b` (`b` sits at
    /// `a + length`) with inertia `inertia` (kg.m2 or kg) and a constant
    /// force `weight` along its axis. If nothing else moves it, its centre
    /// becomes a state named by `states`.
    Inertia1D { a: usize, b: usize, length: f64, inertia: f64, weight: f64, states: StateNames },
    /// The 1-D connector is fixed at `at`.
    Fixed1D { flange: usize, at: f64 },
    /// A rotor turning about `axis` (a unit vector in `frame`'s
    /// coordinates) relative to `frame`, with the 1-D connectors `a` and
    /// `b` on its shaft: a joint of its own, whose angle and speed `states`
    /// name, and spin inertia `inertia`. It adds the kinetic energy of its
    /// spin relative to the carrier, `J w^2 / 2 + J w (e . omega)`: the
    /// carrier's own body is expected to hold the rotor's mass and inertia
    /// (Modelica's Rotor1D).
    Rotor1D { frame: usize, axis: Vec3, inertia: f64, a: usize, b: usize, states: StateNames },
    /// The 1-D connectors `flanges` are mounted on `frame`: their angles
    /// are measured from it and their reactions go into it (a Mounting1D,
    /// a BevelGear1D's housing).
    Mount1D { frame: usize, flanges: Vec<usize> },
    /// A support (housing) that is fixed in the world when nothing but other
    /// housings is connected to it.
    Housing { flange: usize },
    /// A force element on frame `b` with its reaction on frame `a` (or on
    /// the world when `a` is `None`), reading the signals at the input
    /// connectors `inputs` (zero where `None`) and acting on the 1-D
    /// connectors `flanges` (a, b) where its law says: see [`ForceLaw`].
    Force { a: Option<usize>, b: usize, law: ForceLaw, inputs: [Option<usize>; 6], flanges: [Option<usize>; 2] },
    /// A relation between two frames kept by constraint forces (a joint
    /// without states, or the cut of a kinematic loop).
    Constraint { a: usize, b: usize, kind: ConstraintKind },
    /// A point mass `m` on the line from frame `a`'s origin to frame `b`'s,
    /// at the fraction `h` of the way; no degree of freedom (its ends move
    /// it). It feels point gravity with `point_gravity`.
    LineMass { a: usize, b: usize, m: f64, h: f64, point_gravity: bool },
    /// The 1-D connectors of a line between frames `a` and `b`:
    /// `flange_a` sits at 0 and `flange_b` at the distance between the
    /// frames' origins (at least `s_small`); what the 1-D elements push
    /// `flange_b` with acts along the line on frame `b`, and oppositely on
    /// frame `a` (a LineForceWithMass).
    LineFlanges { a: usize, b: usize, flange_a: usize, flange_b: usize, s_small: f64 },
    /// A line-force end that fixes its frame's orientation to the world's
    /// (`fixed_rotation_at_frame_a/b`): it owns the orientation of a
    /// group that nothing else orients.
    FixedRotationEnd { frame: usize },
    /// A road the component's wheels roll on, `y = surface(x, z)`: its
    /// wheel laws refer to it by its number among the component's roads.
    Road { surface: Box<crate::math::surface::Surface> },
    /// The joint (or owner) that is this component's part number `part`
    /// moves as the signals at the input connectors `inputs` impose, at
    /// `level` (see [`DriveMap`] for which coordinates they set). `start`
    /// gives the start positions and speeds of the integrated levels
    /// (where the model sets none).
    Drive {
        part: usize,
        level: DriveLevel,
        map: DriveMap,
        inputs: [Option<usize>; 7],
        start: Option<([f64; 3], [f64; 3])>,
    },
    /// Initial values given on this component's `r_rel_a_k` (with
    /// `position`) and `v_rel_a_k` (with `velocity`) are initial equations
    /// on the motion of frame `b` relative to frame `a`, resolved in `a`.
    InitialMotion { a: usize, b: usize, position: bool, velocity: bool },
    /// A 1-D source imposing the motion of `flange` relative to `support`
    /// (a housing) from the signal at the input connector `input`: on a
    /// joint's axis it makes the joint rheonomic.
    AxisDrive { flange: usize, support: usize, input: usize, level: DriveLevel },
    /// The rows of this component's constraint (its one `Constraint`
    /// part) follow `targets`, and their multipliers are the signals at
    /// the output connectors `efforts`, which drive 1-D sources: see
    /// [`crate::system::Servo`].
    Servo { targets: Vec<crate::math::expr::TimeFunction>, efforts: Vec<usize> },
}

impl Part {
    /// A force element between frames only, without inputs.
    pub(crate) fn force(a: Option<usize>, b: usize, law: ForceLaw) -> Part {
        Part::Force { a, b, law, inputs: [None; 6], flanges: [None; 2] }
    }

    /// A force element reading the input connectors `inputs` (in order).
    pub(crate) fn driven_force(a: Option<usize>, b: usize, law: ForceLaw, inputs: &[usize]) -> Part {
        let mut slots = [None; 6];
        for (slot, &i) in slots.iter_mut().zip(inputs) {
            *slot = Some(i);
        }
        Part::Force { a, b, law, inputs: slots, flanges: [None; 2] }
    }

    /// A signal that is always zero, at the (internal) output connector
    /// `output`: the unused components of a force that takes three inputs.
    pub(crate) fn zero_signal(output: usize) -> Part {
        Part::Signal {
            output,
            law: SignalLaw::Source(SignalSource::Constant { k: 0.0 }),
            inputs: [None; 3],
            frames: [None; 2],
            flanges: [None; 2],
        }
    }
}

/// The motion of one frame connector and the cut force on it.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FrameState {
    /// Origin, world coordinates.
    pub r_0: Vec3,
    /// World to frame rotation.
    pub rot: Mat3,
    /// Velocity of the origin, world coordinates.
    pub v_0: Vec3,
    /// Angular velocity, frame coordinates.
    pub w: Vec3,
    /// Acceleration of the origin, world coordinates.
    pub a_0: Vec3,
    /// Angular acceleration, frame coordinates.
    pub z: Vec3,
    /// Cut force on the component at this frame, frame coordinates.
    pub f: Vec3,
    /// Cut torque on the component at this frame, frame coordinates.
    pub tau: Vec3,
}

impl FrameState {
    /// The same state in the coordinates of the fixed frame `plane` (world
    /// to plane): what a planar component reads of its frames.
    pub fn in_plane(&self, plane: &Transform) -> FrameState {
        FrameState {
            r_0: plane.apply_point(&self.r_0),
            rot: self.rot * plane.rot.transpose(),
            v_0: plane.rot * self.v_0,
            a_0: plane.rot * self.a_0,
            ..*self
        }
    }
}

/// The coordinates of one of a component's joints (or owned orientation).
#[derive(Clone, Copy, Debug, Default)]
pub struct JointState<'a> {
    pub q: &'a [f64],
    pub u: &'a [f64],
    pub qdot: &'a [f64],
    pub udot: &'a [f64],
    /// Generalised forces of the 1-D elements on the joint's axis.
    pub tau: &'a [f64],
}

/// The position, speed and acceleration of a 1-D connector.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FlangeState {
    pub s: f64,
    pub v: f64,
    pub a: f64,
}

/// The state of one of a component's 1-D elements.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Element1DState {
    pub s_rel: f64,
    pub v_rel: f64,
    pub a_rel: f64,
    pub force: f64,
}

/// The state of one of a component's friction elements.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FrictionState {
    pub values: crate::system::friction::FrictionValues,
    /// Modelica's numbering: -1 backward, 0 stuck, 1 forward, 2 free.
    pub mode: f64,
    pub start_forward: bool,
    pub start_backward: bool,
}

/// What a component sees when it computes its variables.
pub struct EvalContext<'a> {
    pub time: f64,
    pub world: &'a WorldSettings,
    /// By connector number; entries of non-frame connectors are unused.
    pub frames: &'a [FrameState],
    /// One per `Joint` or `Owner` part, in the order of `parts()`.
    pub joints: &'a [JointState<'a>],
    /// One per `Element1D` part, in the order of `parts()`.
    pub elements: &'a [Element1DState],
    /// One per `Friction` part, in the order of `parts()`.
    pub frictions: &'a [FrictionState],
    /// By connector number: the value of each signal connector.
    pub signals: &'a [f64],
    /// By connector number: the motion of each 1-D connector (zero for the
    /// others).
    pub flanges: &'a [FlangeState],
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_kind_is_unique_and_found_with_prefixes() {
        let kinds: Vec<&str> = registry().iter().map(|s| s.kind).collect();
        let mut sorted = kinds.clone();
        sorted.sort();
        sorted.dedup();
        assert_eq!(sorted.len(), kinds.len());
        assert_eq!(lookup("MultibodyComponents.Body").map(|s| s.kind), Some("Body"));
        assert_eq!(
            lookup("RotationalComponents.Components.Damper").map(|s| s.kind),
            Some("RotationalComponents.Damper")
        );
    }

    #[test]
    fn every_kind_builds_with_its_defaults_and_defaults_fit_their_types() {
        let world = WorldSettings::default();
        for spec in registry() {
            // Parameters without a default get 1 (or a one-row table).
            let required = spec.params.iter().filter(|p| p.default == Default::Required);
            let one = |p: &ParamSpec| match p.ty {
                ParamType::Matrix(n) => crate::Value::Matrix(vec![vec![1.0; n]]),
                _ => crate::Value::Number(1.0),
            };
            let instance = crate::ComponentInstance {
                name: "c".into(),
                kind: spec.kind.into(),
                params: required.map(|p| (p.name.to_string(), one(p))).collect(),
                initial: vec![],
                guess: vec![],
                surface: None,
            };
            let params = ParamSet::resolve(&instance, spec, &world).unwrap();
            for p in spec.params.iter().filter(|p| !matches!(p.default, Default::Derived(_) | Default::Required)) {
                let value = match p.ty {
                    ParamType::Real | ParamType::Integer => crate::Value::Number(params.real(p.name)),
                    ParamType::Vector(_) | ParamType::IntVector(_) => crate::Value::Array(params.vector(p.name)),
                    ParamType::Bool => crate::Value::Bool(params.boolean(p.name)),
                    ParamType::Enum(..) => crate::Value::Enum(params.variant(p.name).into()),
                    ParamType::Matrix(_) | ParamType::FixedMatrix(..) => crate::Value::Matrix(params.matrix(p.name)),
                    ParamType::Text => crate::Value::Str(params.text(p.name).into()),
                };
                if let Err(e) = params::check_value("c", p.name, p.ty, &value) {
                    panic!("{}.{}: default does not fit: {e}", spec.kind, p.name);
                }
            }
            assert!((spec.build)(&params).is_ok(), "{} does not build with its defaults", spec.kind);
        }
    }
}
