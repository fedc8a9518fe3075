//! PlanarMechanics.PrescribedPosition, PrescribedPose, PrescribedVelocity
//! and PrescribedAcceleration: frame_b moves in the plane as signal inputs
//! say, whatever force that takes.
//!
//! Each owns frame_b with a planar joint from the world (x and y along the
//! world's axes, then the turn about z) and drives its coordinates from
//! the inputs. With `fixed_orientation` the angle is driven too, by an
//! input left unconnected (it reads zero), so phi stays 0; otherwise the
//! angle is a free coordinate on which no torque acts.

use super::super::spec::{ComponentSpec, ConnectorSpec, ParamSpec, VarSpec};
use super::super::{Component, DriveLevel, DriveMap, EvalContext, ParamSet, Part, StateNames};
use super::NORMAL;
use crate::math::Vec3;
use crate::system::JointModel;

const FIXED_ORIENTATION: ParamSpec = ParamSpec::boolean(
    "fixed_orientation",
    true,
    "Keep frame_b's angle at 0; otherwise it turns freely (no torque acts on it)",
);
const STATE_PRIORITY: ParamSpec = ParamSpec::integer("statePriority", 2.0, "Priority of the integrated states");
const R_START: ParamSpec =
    ParamSpec::vector("r_start", &[0.0, 0.0], "m", "Start position of frame_b, world coordinates");
const V_START: ParamSpec =
    ParamSpec::vector("v_start", &[0.0, 0.0], "m/s", "Start velocity of frame_b, world coordinates");

const FRAME_B: ConnectorSpec = ConnectorSpec::frame_2d("frame_b", "The planar frame whose motion is prescribed");

const STATES: StateNames = StateNames { q: &[("r", 2), ("phi", 1)], u: &[("v", 2), ("w", 1)] };

static VARIABLES: [VarSpec; 3] = [
    VarSpec::vector("r", 2, "m", "Position of frame_b, world coordinates"),
    VarSpec::vector("v", 2, "m/s", "Velocity of frame_b, world coordinates"),
    VarSpec::vector("a", 2, "m/s2", "Acceleration of frame_b, world coordinates"),
];

pub static POSITION: ComponentSpec = ComponentSpec {
    kind: "PlanarMechanics.PrescribedPosition",
    doc: "frame_b's origin follows the inputs r_x, r_y (world coordinates) exactly, whatever force it takes; \
          the inputs must be signals of time. With fixed_orientation its angle stays 0, otherwise it turns \
          freely.",
    params: &[
        FIXED_ORIENTATION,
        ParamSpec::boolean(
            "apply_force",
            true,
            "The position is imposed by force at frame_b (only true is supported: the inverse-model mode is not)",
        ),
    ],
    connectors: &[
        FRAME_B,
        ConnectorSpec::input("r_x", "x of frame_b's position"),
        ConnectorSpec::input("r_y", "y of frame_b's position"),
    ],
    variables: &VARIABLES,
    build: |p| {
        if !p.boolean("apply_force") {
            return Err(p.invalid(
                "apply_force",
                "the inverse-model mode (no force at frame_b) is not supported: leave apply_force = true",
            ));
        }
        Ok(prescribed(p, DriveLevel::Position))
    },
    shapes: super::super::shapes::none,
};

pub static POSE: ComponentSpec = ComponentSpec {
    kind: "PlanarMechanics.PrescribedPose",
    doc: "frame_b follows the inputs exactly: its origin r_x, r_y (world coordinates) and its angle phi \
          (counter-clockwise about z). The inputs must be signals of time.",
    params: &[],
    connectors: &[
        FRAME_B,
        ConnectorSpec::input("r_x", "x of frame_b's position"),
        ConnectorSpec::input("r_y", "y of frame_b's position"),
        ConnectorSpec::input("phi", "Angle of frame_b"),
    ],
    variables: &VARIABLES,
    build: |_| Ok(Box::new(Prescribed { level: DriveLevel::Position, driven: 3, angle_input: true, start: None })),
    shapes: super::super::shapes::none,
};

pub static VELOCITY: ComponentSpec = ComponentSpec {
    kind: "PlanarMechanics.PrescribedVelocity",
    doc: "frame_b's origin moves with the velocity v_x, v_y (world coordinates) from r_start; the inputs must \
          be signals of time. With fixed_orientation its angle stays 0, otherwise it turns freely.",
    params: &[FIXED_ORIENTATION, STATE_PRIORITY, R_START],
    connectors: &[
        FRAME_B,
        ConnectorSpec::input("v_x", "x of frame_b's velocity"),
        ConnectorSpec::input("v_y", "y of frame_b's velocity"),
    ],
    variables: &VARIABLES,
    build: |p| Ok(prescribed(p, DriveLevel::Speed)),
    shapes: super::super::shapes::none,
};

pub static ACCELERATION: ComponentSpec = ComponentSpec {
    kind: "PlanarMechanics.PrescribedAcceleration",
    doc: "frame_b's origin accelerates with a_x, a_y (world coordinates) from r_start and v_start; the inputs \
          may be any signals, feedback included. With fixed_orientation its angle stays 0, otherwise it turns \
          freely.",
    params: &[FIXED_ORIENTATION, STATE_PRIORITY, R_START, V_START],
    connectors: &[
        FRAME_B,
        ConnectorSpec::input("a_x", "x of frame_b's acceleration"),
        ConnectorSpec::input("a_y", "y of frame_b's acceleration"),
    ],
    variables: &VARIABLES,
    build: |p| Ok(prescribed(p, DriveLevel::Acceleration)),
    shapes: super::super::shapes::none,
};

fn prescribed(p: &ParamSet, level: DriveLevel) -> Box<dyn Component> {
    let start = match level {
        DriveLevel::Position => None,
        _ => {
            let r = p.vector("r_start");
            let v = if level == DriveLevel::Acceleration { p.vector("v_start") } else { vec![0.0, 0.0] };
            Some(([r[0], r[1], 0.0], [v[0], v[1], 0.0]))
        }
    };
    let driven = if p.boolean("fixed_orientation") { 3 } else { 2 };
    Box::new(Prescribed { level, driven, angle_input: false, start })
}

#[derive(Debug)]
struct Prescribed {
    level: DriveLevel,
    /// How many of x, y and phi the drive sets: 3 holds (or, with
    /// `angle_input`, drives) the angle, 2 leaves it free.
    driven: usize,
    /// The angle follows the third input (a pose); otherwise a driven
    /// angle reads the zero of an unconnected input.
    angle_input: bool,
    /// Start position and velocity of the integrated levels.
    start: Option<([f64; 3], [f64; 3])>,
}

impl Component for Prescribed {
    fn parts(&self) -> Vec<Part> {
        // Connectors: frame_b 0, then the inputs from 1.
        let mut inputs = [None; 7];
        inputs[0] = Some(1);
        inputs[1] = Some(2);
        if self.angle_input {
            inputs[2] = Some(3);
        }
        vec![
            Part::Owner {
                frame: 0,
                model: JointModel::Planar { n: NORMAL, n_x: Vec3::x(), n_y: Vec3::y() },
                states: STATES,
                fallback: false,
            },
            Part::Drive {
                part: 0,
                level: self.level,
                map: DriveMap::Linear { first: 0, count: self.driven, scale: 1.0, offset: 0.0 },
                inputs,
                start: self.start,
            },
        ]
    }

    fn variables(&self) -> Vec<VarSpec> {
        VARIABLES.to_vec()
    }

    fn evaluate(&self, ctx: &EvalContext, out: &mut Vec<f64>) {
        let b = &ctx.frames[0];
        out.extend([b.r_0.x, b.r_0.y, b.v_0.x, b.v_0.y, b.a_0.x, b.a_0.y]);
    }
}
