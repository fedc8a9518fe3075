//! Relative sensors: the motion of frame_b relative to frame_a, and the
//! distance between them.

use super::{
    at, at3, boxed, frame, internal, output, resolve_param, target_of, var, Group, Measure, Quantity, Sensor, Target,
    Var, GUESS_ANGLE1, RELATIVE_FRAMES, SEQUENCE,
};
use crate::components::spec::{ComponentSpec, ConnectorSpec, ParamSpec, ParamType, Shape, VarSpec};
use crate::components::{Component, ParamSet};
use crate::Error;

const FRAME_A: ConnectorSpec = frame("frame_a", "The frame measured from");
const FRAME_B: ConnectorSpec = frame("frame_b", "The frame whose motion relative to frame_a is measured");
const FRAME_RESOLVE: ConnectorSpec =
    frame("frame_resolve", "Output vectors are resolved in this frame when resolve_in_frame = FrameResolve");
const RESOLVE: ParamSpec = resolve_param(RELATIVE_FRAMES, "Frame in which the output vector is resolved");
const R_REL: VarSpec = VarSpec {
    name: "R_rel",
    shape: Shape::Matrix(3, 3),
    unit: "",
    doc: "Rotation from frame_a to frame_b, R_rel = frame_b.R * frame_a.R' (a vector in frame_a coordinates into \
          frame_b's)",
};

/// The target of `resolve_in_frame` (or of the parameter `name`) of a
/// relative sensor.
fn target(p: &ParamSet, name: &str) -> Target {
    let resolve = p.spec.connectors.iter().position(|c| c.name == "frame_resolve");
    target_of(p.variant(name), 0, Some(1), resolve)
}

pub static RELATIVE_POSITION: ComponentSpec = ComponentSpec {
    kind: "RelativePosition",
    doc: "Measures the vector from frame_a's origin to frame_b's, resolved in the world, in frame_a or in \
          frame_b, as the signals r_rel_x, r_rel_y, r_rel_z. Exerts no force.",
    params: &[resolve_param(&["World", "FrameA", "FrameB"], "Frame in which the output vector is resolved")],
    connectors: &[
        FRAME_A,
        FRAME_B,
        output("r_rel_x", "x component of the relative position"),
        output("r_rel_y", "y component of the relative position"),
        output("r_rel_z", "z component of the relative position"),
    ],
    variables: &[VarSpec::vector(
        "r_rel",
        3,
        "m",
        "Position of frame_b's origin relative to frame_a's, resolved in \
                                                   resolve_in_frame",
    )],
    build: |p: &ParamSet| {
        let spec = p.spec;
        let target = target(p, "resolve_in_frame");
        let mut s = Sensor::new(spec, Some(0), 1);
        let outputs = at3(spec, ["r_rel_x", "r_rel_y", "r_rel_z"]).to_vec();
        s.groups.push(Group {
            measure: Measure::Vector(Quantity::Position, target),
            outputs,
            internal: None,
            off: None,
        });
        s.variables.push((var(spec, "r_rel"), Var::Vector(Quantity::Position, target)));
        boxed(s)
    },
    shapes: crate::components::shapes::none,
};

pub static RELATIVE_VELOCITY: ComponentSpec = ComponentSpec {
    kind: "RelativeVelocity",
    doc: "Measures the velocity of frame_b's origin relative to frame_a's as seen from frame_a (the rate of \
          change of the relative position resolved in frame_a), then resolved in the world, frame_a, frame_b or \
          frame_resolve, as the signals v_rel_x, v_rel_y, v_rel_z. Exerts no force.",
    params: &[RESOLVE],
    connectors: &[
        FRAME_A,
        FRAME_B,
        FRAME_RESOLVE,
        output("v_rel_x", "x component of the relative velocity"),
        output("v_rel_y", "y component of the relative velocity"),
        output("v_rel_z", "z component of the relative velocity"),
        internal("v_rel_world_x"),
        internal("v_rel_world_y"),
        internal("v_rel_world_z"),
    ],
    variables: &[
        VarSpec::vector("r_rel_a", 3, "m", "Relative position, resolved in frame_a"),
        VarSpec::vector("v_rel_a", 3, "m/s", "Rate of change of r_rel_a (resolved in frame_a)"),
        VarSpec::vector("v_rel", 3, "m/s", "v_rel_a resolved in resolve_in_frame"),
    ],
    build: |p: &ParamSet| {
        let spec = p.spec;
        let target = target(p, "resolve_in_frame");
        let seen = Quantity::Velocity(Target::Frame(0));
        let mut s = Sensor::new(spec, Some(0), 1);
        s.groups.push(Group {
            measure: Measure::Vector(seen, target),
            outputs: at3(spec, ["v_rel_x", "v_rel_y", "v_rel_z"]).to_vec(),
            internal: Some(at3(spec, ["v_rel_world_x", "v_rel_world_y", "v_rel_world_z"])),
            off: None,
        });
        s.variables.push((var(spec, "r_rel_a"), Var::Vector(Quantity::Position, Target::Frame(0))));
        s.variables.push((var(spec, "v_rel_a"), Var::Vector(seen, Target::Frame(0))));
        s.variables.push((var(spec, "v_rel"), Var::Vector(seen, target)));
        boxed(s)
    },
    shapes: crate::components::shapes::none,
};

pub static RELATIVE_ANGULAR_VELOCITY: ComponentSpec = ComponentSpec {
    kind: "RelativeAngularVelocity",
    doc: "Measures the angular velocity of frame_b relative to frame_a, resolved in the world, frame_a, frame_b \
          or frame_resolve, as the signals w_rel_x, w_rel_y, w_rel_z. Exerts no force.",
    params: &[RESOLVE],
    connectors: &[
        FRAME_A,
        FRAME_B,
        FRAME_RESOLVE,
        output("w_rel_x", "x component of the relative angular velocity"),
        output("w_rel_y", "y component of the relative angular velocity"),
        output("w_rel_z", "z component of the relative angular velocity"),
        internal("w_rel_world_x"),
        internal("w_rel_world_y"),
        internal("w_rel_world_z"),
    ],
    variables: &[
        R_REL,
        VarSpec::vector("w_rel", 3, "rad/s", "Relative angular velocity, resolved in resolve_in_frame"),
    ],
    build: |p: &ParamSet| {
        let spec = p.spec;
        let target = target(p, "resolve_in_frame");
        let mut s = Sensor::new(spec, Some(0), 1);
        s.groups.push(Group {
            measure: Measure::Vector(Quantity::AngularVelocity, target),
            outputs: at3(spec, ["w_rel_x", "w_rel_y", "w_rel_z"]).to_vec(),
            internal: Some(at3(spec, ["w_rel_world_x", "w_rel_world_y", "w_rel_world_z"])),
            off: None,
        });
        s.variables.push((R_REL, Var::RelativeRotation));
        s.variables.push((var(spec, "w_rel"), Var::Vector(Quantity::AngularVelocity, target)));
        boxed(s)
    },
    shapes: crate::components::shapes::none,
};

pub static RELATIVE_ANGLES: ComponentSpec = ComponentSpec {
    kind: "RelativeAngles",
    doc: "Measures the three angles that turn frame_a into frame_b by rotations about the axes of `sequence` \
          (R_rel = A_k(angle_3) A_j(angle_2) A_i(angle_1)), each in [-pi, pi], as the signals angle_1, angle_2, \
          angle_3. Exerts no force. `guess_angle1` (Modelica's guessAngle1) picks one of the two solutions.",
    params: &[SEQUENCE, GUESS_ANGLE1],
    connectors: &[
        FRAME_A,
        FRAME_B,
        output("angle_1", "First rotation angle"),
        output("angle_2", "Second rotation angle"),
        output("angle_3", "Third rotation angle"),
    ],
    variables: &[R_REL, VarSpec::vector("angles", 3, "rad", "The three rotation angles")],
    build: |p: &ParamSet| {
        let spec = p.spec;
        let outputs = at3(spec, ["angle_1", "angle_2", "angle_3"]);
        let mut s = Sensor::new(spec, Some(0), 1);
        let measure = Measure::Angles { sequence: p.sequence("sequence")?, guess: p.real("guess_angle1") };
        s.groups.push(Group { measure, outputs: outputs.to_vec(), internal: None, off: None });
        s.variables.push((R_REL, Var::RelativeRotation));
        s.variables.push((var(spec, "angles"), Var::Signals(outputs)));
        boxed(s)
    },
    shapes: crate::components::shapes::none,
};

pub static DISTANCE: ComponentSpec = ComponentSpec {
    kind: "Distance",
    doc: "Measures the distance between the origins of frame_a and frame_b as the signal `distance`; below \
          s_small a smooth polynomial replaces the square root so that it stays differentiable at zero. Exerts no \
          force.",
    params: &[ParamSpec::real(
        "s_small",
        1e-10,
        "m",
        "Below this distance a smooth polynomial replaces the square root (no infinite derivative at zero)",
    )],
    connectors: &[FRAME_A, FRAME_B, output("distance", "Distance between the origins")],
    variables: &[
        VarSpec::scalar("L2", "m2", "Squared distance between the origins"),
        VarSpec::scalar("distance", "m", "Distance between the origins (the output)"),
    ],
    build: |p: &ParamSet| {
        let spec = p.spec;
        let s_small = p.non_negative("s_small", false)?;
        let mut s = Sensor::new(spec, Some(0), 1);
        let output = at(spec, "distance");
        s.groups.push(Group {
            measure: Measure::Distance { s_small },
            outputs: vec![output],
            internal: None,
            off: None,
        });
        s.variables.push((var(spec, "L2"), Var::SquaredDistance));
        s.variables.push((var(spec, "distance"), Var::Signal(output)));
        boxed(s)
    },
    shapes: crate::components::shapes::none,
};

pub static RELATIVE_SENSOR: ComponentSpec = ComponentSpec {
    kind: "RelativeSensor",
    doc: "Measures what its get_* parameters switch on, of frame_b relative to frame_a: position r_rel and \
          angular velocity w_rel (resolved in resolve_in_frame), velocity v_rel, acceleration a_rel and angular \
          acceleration z_rel (differentiated in resolve_in_frame, then resolved in \
          resolve_in_frame_after_differentiation), and the angles of `sequence`. The outputs of a switched-off \
          group, and a_rel and z_rel (which depend on the accelerations), cannot be read by other components; \
          all are recorded in the results. Exerts no force.",
    params: &[
        RESOLVE,
        ParamSpec::derived(
            "resolve_in_frame_after_differentiation",
            ParamType::Enum("ResolveInFrame", RELATIVE_FRAMES),
            "resolve_in_frame",
            "",
            "Frame in which v_rel, a_rel and z_rel are resolved after differentiation",
        ),
        SEQUENCE,
        ParamSpec::boolean("get_r_rel", false, "Output the relative position r_rel"),
        ParamSpec::boolean("get_v_rel", false, "Output the relative velocity v_rel"),
        ParamSpec::boolean("get_a_rel", false, "Output the relative acceleration a_rel (recorded only)"),
        ParamSpec::boolean("get_w_rel", false, "Output the relative angular velocity w_rel"),
        ParamSpec::boolean("get_z_rel", false, "Output the relative angular acceleration z_rel (recorded only)"),
        ParamSpec::boolean("get_angles", false, "Output the angles of `sequence` from frame_a to frame_b"),
        ParamSpec::derived(
            "need_pos",
            ParamType::Bool,
            "get_r_rel or get_v_rel or get_a_rel",
            "",
            "Whether the relative position is needed (computed; a value given is ignored)",
        ),
        ParamSpec::derived(
            "need_angvel",
            ParamType::Bool,
            "get_w_rel or get_z_rel",
            "",
            "Whether the relative angular velocity is needed (computed; a value given is ignored)",
        ),
    ],
    connectors: &[
        FRAME_A,
        FRAME_B,
        FRAME_RESOLVE,
        output("r_rel_x", "x component of the relative position"),
        output("r_rel_y", "y component of the relative position"),
        output("r_rel_z", "z component of the relative position"),
        output("v_rel_x", "x component of the relative velocity"),
        output("v_rel_y", "y component of the relative velocity"),
        output("v_rel_z", "z component of the relative velocity"),
        output("a_rel_x", "x component of the relative acceleration (recorded only)"),
        output("a_rel_y", "y component of the relative acceleration (recorded only)"),
        output("a_rel_z", "z component of the relative acceleration (recorded only)"),
        output("w_rel_x", "x component of the relative angular velocity"),
        output("w_rel_y", "y component of the relative angular velocity"),
        output("w_rel_z", "z component of the relative angular velocity"),
        output("z_rel_x", "x component of the relative angular acceleration (recorded only)"),
        output("z_rel_y", "y component of the relative angular acceleration (recorded only)"),
        output("z_rel_z", "z component of the relative angular acceleration (recorded only)"),
        output("angle_1", "First rotation angle"),
        output("angle_2", "Second rotation angle"),
        output("angle_3", "Third rotation angle"),
        internal("r_rel_world_x"),
        internal("r_rel_world_y"),
        internal("r_rel_world_z"),
        internal("v_rel_world_x"),
        internal("v_rel_world_y"),
        internal("v_rel_world_z"),
        internal("w_rel_world_x"),
        internal("w_rel_world_y"),
        internal("w_rel_world_z"),
    ],
    variables: &[
        VarSpec::vector("r_rel", 3, "m", "Relative position (get_r_rel)"),
        VarSpec::vector("v_rel", 3, "m/s", "Relative velocity (get_v_rel)"),
        VarSpec::vector("a_rel", 3, "m/s2", "Relative acceleration (get_a_rel)"),
        VarSpec::vector("w_rel", 3, "rad/s", "Relative angular velocity (get_w_rel)"),
        VarSpec::vector("z_rel", 3, "rad/s2", "Relative angular acceleration (get_z_rel)"),
        VarSpec::vector("angles", 3, "rad", "Angles of `sequence` from frame_a to frame_b (get_angles)"),
    ],
    build: build_relative_sensor,
    shapes: crate::components::shapes::none,
};

fn build_relative_sensor(p: &ParamSet) -> Result<Box<dyn Component>, Error> {
    let spec = p.spec;
    let resolve = target(p, "resolve_in_frame");
    let after_name = "resolve_in_frame_after_differentiation";
    let after = if p.is_given(after_name) { target(p, after_name) } else { resolve };
    let mut s = Sensor::new(spec, Some(0), 1);
    type Row<'a> = (&'a str, &'a str, Quantity, Target, [&'a str; 3], Option<[&'a str; 3]>, &'static str);
    let groups: [Row; 5] = [
        (
            "get_r_rel",
            "r_rel",
            Quantity::Position,
            resolve,
            ["r_rel_x", "r_rel_y", "r_rel_z"],
            Some(["r_rel_world_x", "r_rel_world_y", "r_rel_world_z"]),
            "is switched off (get_r_rel = false)",
        ),
        (
            "get_v_rel",
            "v_rel",
            Quantity::Velocity(resolve),
            after,
            ["v_rel_x", "v_rel_y", "v_rel_z"],
            Some(["v_rel_world_x", "v_rel_world_y", "v_rel_world_z"]),
            "is switched off (get_v_rel = false)",
        ),
        (
            "get_a_rel",
            "a_rel",
            Quantity::Acceleration(resolve),
            after,
            ["a_rel_x", "a_rel_y", "a_rel_z"],
            None,
            "is switched off (get_a_rel = false)",
        ),
        (
            "get_w_rel",
            "w_rel",
            Quantity::AngularVelocity,
            resolve,
            ["w_rel_x", "w_rel_y", "w_rel_z"],
            Some(["w_rel_world_x", "w_rel_world_y", "w_rel_world_z"]),
            "is switched off (get_w_rel = false)",
        ),
        (
            "get_z_rel",
            "z_rel",
            Quantity::AngularAcceleration(resolve),
            after,
            ["z_rel_x", "z_rel_y", "z_rel_z"],
            None,
            "is switched off (get_z_rel = false)",
        ),
    ];
    for (flag, name, quantity, target, outputs, internals, off) in groups {
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
