//! PrescribedPosition, PrescribedPose, PrescribedVelocity and
//! PrescribedAcceleration: frame_b moves as signal inputs say, whatever
//! force that takes.
//!
//! Each is a joint from the world (translation only, or free with a
//! quaternion when the orientation is not fixed or is prescribed too)
//! whose coordinates a drive imposes: exactly from the inputs and their
//! derivatives for positions and poses, from the integral of the inputs
//! for velocities and accelerations.

use super::spec::{ComponentSpec, ConnectorSpec, ParamSpec, VarSpec};
use super::{Component, DriveLevel, DriveMap, EvalContext, ParamSet, Part, StateNames};
use crate::system::joint::{JointModel, RotationCoordinates};

const FIXED_ORIENTATION: ParamSpec = ParamSpec::boolean(
    "fixed_orientation",
    true,
    "Keep frame_b's orientation that of the world; otherwise leave it free (no torque acts)",
);
const RENDER: ParamSpec = ParamSpec::boolean("render", true, "Render the component in animations");
const STATE_PRIORITY: ParamSpec = ParamSpec::integer("statePriority", 1.0, "Priority of the integrated states");
const R_START: ParamSpec =
    ParamSpec::vector("r_start", &[0.0, 0.0, 0.0], "m", "Start position of frame_b, resolved in the world frame");
const V_START: ParamSpec =
    ParamSpec::vector("v_start", &[0.0, 0.0, 0.0], "m/s", "Start velocity of frame_b, resolved in the world frame");

const FRAME_B: ConnectorSpec = ConnectorSpec::frame("frame_b", "The frame whose motion is prescribed");

static VARIABLES: [VarSpec; 3] = [
    VarSpec::vector("r", 3, "m", "Position of frame_b, resolved in the world frame"),
    VarSpec::vector("v", 3, "m/s", "Velocity of frame_b, resolved in the world frame"),
    VarSpec::vector("a", 3, "m/s2", "Acceleration of frame_b, resolved in the world frame"),
];

pub static POSITION: ComponentSpec = ComponentSpec {
    kind: "PrescribedPosition",
    doc: "frame_b's origin follows the inputs r_x, r_y, r_z (world frame) exactly, whatever force it takes; \
          the inputs must be signals of time. With fixed_orientation its orientation stays the world's, \
          otherwise it turns freely.",
    params: &[FIXED_ORIENTATION, RENDER],
    connectors: &[
        FRAME_B,
        ConnectorSpec::input("r_x", "x of frame_b's position"),
        ConnectorSpec::input("r_y", "y of frame_b's position"),
        ConnectorSpec::input("r_z", "z of frame_b's position"),
    ],
    variables: &VARIABLES,
    build: |p| Ok(prescribed(p, DriveLevel::Position)),
    shapes: super::shapes::none,
};

pub static POSE: ComponentSpec = ComponentSpec {
    kind: "PrescribedPose",
    doc: "frame_b follows the inputs exactly: its origin r_x, r_y, r_z (world frame) and its orientation the \
          quaternion q_w, q_x, q_y, q_z (scalar first, world to frame_b, of unit norm). The inputs must be \
          signals of time.",
    params: &[RENDER],
    connectors: &[
        FRAME_B,
        ConnectorSpec::input("r_x", "x of frame_b's position"),
        ConnectorSpec::input("r_y", "y of frame_b's position"),
        ConnectorSpec::input("r_z", "z of frame_b's position"),
        ConnectorSpec::input("q_w", "Scalar part of frame_b's orientation quaternion"),
        ConnectorSpec::input("q_x", "First vector part of the quaternion"),
        ConnectorSpec::input("q_y", "Second vector part of the quaternion"),
        ConnectorSpec::input("q_z", "Third vector part of the quaternion"),
    ],
    variables: &VARIABLES,
    build: |_| Ok(Box::new(Prescribed { level: DriveLevel::Position, free_rotation: true, pose: true, start: None })),
    shapes: super::shapes::none,
};

pub static VELOCITY: ComponentSpec = ComponentSpec {
    kind: "PrescribedVelocity",
    doc: "frame_b's origin moves with the velocity v_x, v_y, v_z (world frame) from r_start; the inputs must be \
          signals of time. With fixed_orientation its orientation stays the world's, otherwise it turns freely.",
    params: &[FIXED_ORIENTATION, STATE_PRIORITY, RENDER, R_START],
    connectors: &[
        FRAME_B,
        ConnectorSpec::input("v_x", "x of frame_b's velocity"),
        ConnectorSpec::input("v_y", "y of frame_b's velocity"),
        ConnectorSpec::input("v_z", "z of frame_b's velocity"),
    ],
    variables: &VARIABLES,
    build: |p| Ok(prescribed(p, DriveLevel::Speed)),
    shapes: super::shapes::none,
};

pub static ACCELERATION: ComponentSpec = ComponentSpec {
    kind: "PrescribedAcceleration",
    doc: "frame_b's origin accelerates with a_x, a_y, a_z (world frame) from r_start and v_start; the inputs may \
          be any signals, feedback included. With fixed_orientation its orientation stays the world's, \
          otherwise it turns freely.",
    params: &[FIXED_ORIENTATION, STATE_PRIORITY, RENDER, R_START, V_START],
    connectors: &[
        FRAME_B,
        ConnectorSpec::input("a_x", "x of frame_b's acceleration"),
        ConnectorSpec::input("a_y", "y of frame_b's acceleration"),
        ConnectorSpec::input("a_z", "z of frame_b's acceleration"),
    ],
    variables: &VARIABLES,
    build: |p| Ok(prescribed(p, DriveLevel::Acceleration)),
    shapes: super::shapes::none,
};

fn prescribed(p: &ParamSet, level: DriveLevel) -> Box<dyn Component> {
    let start = match level {
        DriveLevel::Position => None,
        _ => {
            let r = p.vec3("r_start");
            let v = if level == DriveLevel::Acceleration { p.vec3("v_start") } else { Default::default() };
            Some(([r.x, r.y, r.z], [v.x, v.y, v.z]))
        }
    };
    Box::new(Prescribed { level, free_rotation: !p.boolean("fixed_orientation"), pose: false, start })
}

#[derive(Debug)]
struct Prescribed {
    level: DriveLevel,
    /// A free joint with quaternion states instead of a translation.
    free_rotation: bool,
    /// The quaternion inputs set the orientation too.
    pose: bool,
    /// Start position and velocity of the integrated levels.
    start: Option<([f64; 3], [f64; 3])>,
}

impl Component for Prescribed {
    fn parts(&self) -> Vec<Part> {
        let (model, states) = if self.free_rotation {
            (
                JointModel::Free(RotationCoordinates::Quaternion { k: 0.0 }),
                StateNames { q: &[("r", 3), ("Q_hat", 4)], u: &[("v", 3), ("w_b", 3)] },
            )
        } else {
            (JointModel::Translation, StateNames { q: &[("r", 3)], u: &[("v", 3)] })
        };
        let map =
            if self.pose { DriveMap::Pose } else { DriveMap::Linear { first: 0, count: 3, scale: 1.0, offset: 0.0 } };
        let inputs = std::array::from_fn(|k| if k < if self.pose { 7 } else { 3 } { Some(k + 1) } else { None });
        vec![
            Part::Owner { frame: 0, model, states, fallback: false },
            Part::Drive { part: 0, level: self.level, map, inputs, start: self.start },
        ]
    }

    fn variables(&self) -> Vec<VarSpec> {
        VARIABLES.to_vec()
    }

    fn evaluate(&self, ctx: &EvalContext, out: &mut Vec<f64>) {
        let b = &ctx.frames[0];
        out.extend(b.r_0.iter().chain(b.v_0.iter()).chain(b.a_0.iter()));
    }
}
