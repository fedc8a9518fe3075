//! Absolute sensors: the motion of one frame relative to the world.

use super::{
    at, at3, boxed, frame, internal, output, resolve_param, target_of, var, Group, Measure, Quantity, Sensor, Target,
    Var, ABSOLUTE_FRAMES, GUESS_ANGLE1, SEQUENCE,
};
use crate::components::spec::{ComponentSpec, ConnectorSpec, ParamSpec, VarSpec};
use crate::components::{Component, ParamSet};
use crate::Error;

const FRAME_A: ConnectorSpec = frame("frame_a", "The frame whose motion is measured");
const FRAME_RESOLVE: ConnectorSpec =
    frame("frame_resolve", "Output vectors are resolved in this frame when resolve_in_frame = FrameResolve");
const RESOLVE: ParamSpec = resolve_param(ABSOLUTE_FRAMES, "Frame in which the output vector is resolved");

/// A sensor with one vector output group `names` (internal outputs
/// `internals`) measuring `quantity`, recorded as `vars` (each with the
/// frame it is resolved in; `None` for resolve_in_frame's).
fn vector_sensor(
    p: &ParamSet,
    quantity: Quantity,
    names: [&str; 3],
    internals: [&str; 3],
    vars: &[(&str, Option<Target>)],
) -> Result<Box<dyn Component>, Error> {
    let spec = p.spec;
    let target = target_of(p.variant("resolve_in_frame"), 0, None, Some(at(spec, "frame_resolve")));
    let mut s = Sensor::new(spec, None, 0);
    s.groups.push(Group {
        measure: Measure::Vector(quantity, target),
        outputs: at3(spec, names).to_vec(),
        internal: Some(at3(spec, internals)),
        off: None,
    });
    for &(name, resolved) in vars {
        s.variables.push((var(spec, name), Var::Vector(quantity, resolved.unwrap_or(target))));
    }
    boxed(s)
}

pub static ABSOLUTE_POSITION: ComponentSpec = ComponentSpec {
    kind: "AbsolutePosition",
    doc: "Measures where the origin of frame_a is (from the world's origin), resolved in the world, in frame_a \
          or in frame_resolve, as the signals r_x, r_y, r_z. Exerts no force.",
    params: &[RESOLVE],
    connectors: &[
        FRAME_A,
        FRAME_RESOLVE,
        output("r_x", "x component of the position"),
        output("r_y", "y component of the position"),
        output("r_z", "z component of the position"),
        internal("r_world_x"),
        internal("r_world_y"),
        internal("r_world_z"),
    ],
    variables: &[VarSpec::vector("r", 3, "m", "Position of frame_a's origin, resolved in resolve_in_frame")],
    build: |p: &ParamSet| {
        vector_sensor(
            p,
            Quantity::Position,
            ["r_x", "r_y", "r_z"],
            ["r_world_x", "r_world_y", "r_world_z"],
            &[("r", None)],
        )
    },
    shapes: crate::components::shapes::none,
};

pub static ABSOLUTE_VELOCITY: ComponentSpec = ComponentSpec {
    kind: "AbsoluteVelocity",
    doc: "Measures the velocity of frame_a's origin (the rate of change of its world position), resolved in the \
          world, in frame_a or in frame_resolve, as the signals v_x, v_y, v_z. Exerts no force.",
    params: &[RESOLVE],
    connectors: &[
        FRAME_A,
        FRAME_RESOLVE,
        output("v_x", "x component of the velocity"),
        output("v_y", "y component of the velocity"),
        output("v_z", "z component of the velocity"),
        internal("v_world_x"),
        internal("v_world_y"),
        internal("v_world_z"),
    ],
    variables: &[
        VarSpec::vector("v0", 3, "m/s", "Velocity of frame_a's origin, world coordinates"),
        VarSpec::vector("v", 3, "m/s", "Velocity of frame_a's origin, resolved in resolve_in_frame"),
    ],
    build: |p: &ParamSet| {
        vector_sensor(
            p,
            Quantity::Velocity(Target::World),
            ["v_x", "v_y", "v_z"],
            ["v_world_x", "v_world_y", "v_world_z"],
            &[("v0", Some(Target::World)), ("v", None)],
        )
    },
    shapes: crate::components::shapes::none,
};

pub static ABSOLUTE_ANGULAR_VELOCITY: ComponentSpec = ComponentSpec {
    kind: "AbsoluteAngularVelocity",
    doc: "Measures the angular velocity of frame_a relative to the world, resolved in the world, in frame_a or in \
          frame_resolve, as the signals w_x, w_y, w_z. Exerts no force.",
    params: &[RESOLVE],
    connectors: &[
        FRAME_A,
        FRAME_RESOLVE,
        output("w_x", "x component of the angular velocity"),
        output("w_y", "y component of the angular velocity"),
        output("w_z", "z component of the angular velocity"),
        internal("w_world_x"),
        internal("w_world_y"),
        internal("w_world_z"),
    ],
    variables: &[VarSpec::vector("w", 3, "rad/s", "Angular velocity of frame_a, resolved in resolve_in_frame")],
    build: |p: &ParamSet| {
        vector_sensor(
            p,
            Quantity::AngularVelocity,
            ["w_x", "w_y", "w_z"],
            ["w_world_x", "w_world_y", "w_world_z"],
            &[("w", None)],
        )
    },
    shapes: crate::components::shapes::none,
};

pub static ABSOLUTE_ANGLES: ComponentSpec = ComponentSpec {
    kind: "AbsoluteAngles",
    doc: "Measures the three angles that turn the world frame into frame_a by rotations about the axes of \
          `sequence` (R = A_k(angle_3) A_j(angle_2) A_i(angle_1)), each in [-pi, pi], as the signals angle_1, \
          angle_2, angle_3. Exerts no force. `guess_angle1` (Modelica's guessAngle1) picks one of the two \
          solutions.",
    params: &[SEQUENCE, GUESS_ANGLE1],
    connectors: &[
        FRAME_A,
        output("angle_1", "First rotation angle"),
        output("angle_2", "Second rotation angle"),
        output("angle_3", "Third rotation angle"),
    ],
    variables: &[VarSpec::vector("angles", 3, "rad", "The three rotation angles")],
    build: |p: &ParamSet| {
        let spec = p.spec;
        let outputs = at3(spec, ["angle_1", "angle_2", "angle_3"]);
        let mut s = Sensor::new(spec, None, 0);
        let measure = Measure::Angles { sequence: p.sequence("sequence")?, guess: p.real("guess_angle1") };
        s.groups.push(Group { measure, outputs: outputs.to_vec(), internal: None, off: None });
        s.variables.push((var(spec, "angles"), Var::Signals(outputs)));
        boxed(s)
    },
    shapes: crate::components::shapes::none,
};

pub static ABSOLUTE_SENSOR: ComponentSpec = ComponentSpec {
    kind: "AbsoluteSensor",
    doc: "Measures what its get_* parameters switch on, of frame_a relative to the world: position r, velocity \
          v, acceleration a, angular velocity w, angular acceleration z (vectors resolved in resolve_in_frame) \
          and the angles of `sequence`. The outputs of a switched-off group, and a and z (which depend on the \
          accelerations), cannot be read by other components; all are recorded in the results. Exerts no force.",
    params: &[
        RESOLVE,
        SEQUENCE,
        ParamSpec::boolean("get_r", false, "Output the position r"),
        ParamSpec::boolean("get_v", false, "Output the velocity v"),
        ParamSpec::boolean("get_a", false, "Output the acceleration a (recorded only)"),
        ParamSpec::boolean("get_w", false, "Output the angular velocity w"),
        ParamSpec::boolean("get_z", false, "Output the angular acceleration z (recorded only)"),
        ParamSpec::boolean("get_angles", false, "Output the angles of `sequence`"),
    ],
    connectors: &[
        FRAME_A,
        FRAME_RESOLVE,
        output("r_x", "x component of the position"),
        output("r_y", "y component of the position"),
        output("r_z", "z component of the position"),
        output("v_x", "x component of the velocity"),
        output("v_y", "y component of the velocity"),
        output("v_z", "z component of the velocity"),
        output("a_x", "x component of the acceleration (recorded only)"),
        output("a_y", "y component of the acceleration (recorded only)"),
        output("a_z", "z component of the acceleration (recorded only)"),
        output("w_x", "x component of the angular velocity"),
        output("w_y", "y component of the angular velocity"),
        output("w_z", "z component of the angular velocity"),
        output("z_x", "x component of the angular acceleration (recorded only)"),
        output("z_y", "y component of the angular acceleration (recorded only)"),
        output("z_z", "z component of the angular acceleration (recorded only)"),
        output("angle_1", "First rotation angle"),
        output("angle_2", "Second rotation angle"),
        output("angle_3", "Third rotation angle"),
        internal("r_world_x"),
        internal("r_world_y"),
        internal("r_world_z"),
        internal("v_world_x"),
        internal("v_world_y"),
        internal("v_world_z"),
        internal("w_world_x"),
        internal("w_world_y"),
        internal("w_world_z"),
    ],
    variables: &[
        VarSpec::vector("r", 3, "m", "Position of frame_a's origin (get_r)"),
        VarSpec::vector("v", 3, "m/s", "Velocity of frame_a's origin (get_v)"),
        VarSpec::vector("a", 3, "m/s2", "Acceleration of frame_a's origin (get_a)"),
        VarSpec::vector("w", 3, "rad/s", "Angular velocity of frame_a (get_w)"),
        VarSpec::vector("z", 3, "rad/s2", "Angular acceleration of frame_a (get_z)"),
        VarSpec::vector("angles", 3, "rad", "Angles of `sequence` from the world to frame_a (get_angles)"),
    ],
    build: build_absolute_sensor,
    shapes: crate::components::shapes::none,
};

fn build_absolute_sensor(p: &ParamSet) -> Result<Box<dyn Component>, Error> {
    let spec = p.spec;
    let target = target_of(p.variant("resolve_in_frame"), 0, None, Some(at(spec, "frame_resolve")));
    let mut s = Sensor::new(spec, None, 0);
    type Row<'a> = (&'a str, &'a str, Quantity, [&'a str; 3], Option<[&'a str; 3]>, &'static str);
    let groups: [Row; 5] = [
        (
            "get_r",
            "r",
            Quantity::Position,
            ["r_x", "r_y", "r_z"],
            Some(["r_world_x", "r_world_y", "r_world_z"]),
            "is switched off (get_r = false)",
        ),
        (
            "get_v",
            "v",
            Quantity::Velocity(Target::World),
            ["v_x", "v_y", "v_z"],
            Some(["v_world_x", "v_world_y", "v_world_z"]),
            "is switched off (get_v = false)",
        ),
        (
            "get_a",
            "a",
            Quantity::Acceleration(Target::World),
            ["a_x", "a_y", "a_z"],
            None,
            "is switched off (get_a = false)",
        ),
        (
            "get_w",
            "w",
            Quantity::AngularVelocity,
            ["w_x", "w_y", "w_z"],
            Some(["w_world_x", "w_world_y", "w_world_z"]),
            "is switched off (get_w = false)",
        ),
        (
            "get_z",
            "z",
            Quantity::AngularAcceleration(Target::World),
            ["z_x", "z_y", "z_z"],
            None,
            "is switched off (get_z = false)",
        ),
    ];
    for (flag, name, quantity, outputs, internals, off) in groups {
        let on = p.boolean(flag);
        s.groups.push(Group {
            measure: Measure::Vector(quantity, target),
            outputs: at3(spec, outputs).to_vec(),
            internal: internals.map(|i| at3(spec, i)),
            off: (!on).then_some(off),
        });
        if on {
            s.variables.push((var(spec, name), Var::Vector(quantity, target)));
        }
    }
    let outputs = at3(spec, ["angle_1", "angle_2", "angle_3"]);
    let on = p.boolean("get_angles");
    s.groups.push(Group {
        measure: Measure::Angles { sequence: p.sequence("sequence")?, guess: 0.0 },
        outputs: outputs.to_vec(),
        internal: None,
        off: (!on).then_some("is switched off (get_angles = false)"),
    });
    if on {
        s.variables.push((var(spec, "angles"), Var::Signals(outputs)));
    }
    boxed(s)
}
