//! Cut sensors: frame_a and frame_b are one frame, and the sensor reports
//! what passes through it (the cut force, the cut torque, the power).
//!
//! They depend on the accelerations, which the signal graph does not know:
//! their outputs are recorded in the results, and a model that reads them
//! in another component is refused at assembly.

use super::{at, at3, boxed, frame, output, resolve_param, target_of, var, Group, Measure, Quantity, Sensor, Var};
use crate::components::spec::{ComponentSpec, ConnectorSpec, ParamSpec, VarSpec};
use crate::components::{Component, ParamSet};
use crate::Error;

const FRAME_A: ConnectorSpec = frame("frame_a", "The side the measured force and torque act on the sensor from");
const FRAME_B: ConnectorSpec = frame("frame_b", "The other side: the same frame as frame_a");
const RESOLVE: ParamSpec =
    resolve_param(&["World", "FrameA", "FrameB"], "Frame in which the output vector is resolved");

/// A cut sensor measuring `quantities` into the output groups `groups`,
/// recorded as `vars`.
fn cut_sensor(p: &ParamSet, groups: &[(Quantity, [&str; 3], &str)], sign: f64) -> Result<Box<dyn Component>, Error> {
    let spec = p.spec;
    let resolve = spec.connectors.iter().position(|c| c.name == "frame_resolve");
    let target = target_of(p.variant("resolve_in_frame"), 0, Some(1), resolve);
    let mut s = Sensor::new(spec, None, 0);
    s.rigid = true;
    s.sign = sign;
    for &(quantity, outputs, name) in groups {
        s.groups.push(Group {
            measure: Measure::Vector(quantity, target),
            outputs: at3(spec, outputs).to_vec(),
            internal: None,
            off: None,
        });
        s.variables.push((var(spec, name), Var::Vector(quantity, target)));
    }
    boxed(s)
}

pub static CUT_FORCE: ComponentSpec = ComponentSpec {
    kind: "CutForce",
    doc: "Sits between two parts (frame_a and frame_b are one frame) and reports the force that acts on it at \
          frame_a, resolved in the world, frame_a or frame_b, as force_x, force_y, force_z. The outputs depend on \
          the accelerations: they are recorded in the results but cannot be read by other components.",
    params: &[RESOLVE],
    connectors: &[
        FRAME_A,
        FRAME_B,
        output("force_x", "x component of the cut force (recorded only)"),
        output("force_y", "y component of the cut force (recorded only)"),
        output("force_z", "z component of the cut force (recorded only)"),
    ],
    variables: &[VarSpec::vector("force", 3, "N", "Cut force at frame_a, resolved in resolve_in_frame")],
    build: |p: &ParamSet| cut_sensor(p, &[(Quantity::CutForce, ["force_x", "force_y", "force_z"], "force")], 1.0),
    shapes: crate::components::shapes::none,
};

pub static CUT_TORQUE: ComponentSpec = ComponentSpec {
    kind: "CutTorque",
    doc: "Sits between two parts (frame_a and frame_b are one frame) and reports the torque that acts on it at \
          frame_a, resolved in the world, frame_a or frame_b, as torque_x, torque_y, torque_z. The outputs \
          depend on the accelerations: they are recorded in the results but cannot be read by other components.",
    params: &[RESOLVE],
    connectors: &[
        FRAME_A,
        FRAME_B,
        output("torque_x", "x component of the cut torque (recorded only)"),
        output("torque_y", "y component of the cut torque (recorded only)"),
        output("torque_z", "z component of the cut torque (recorded only)"),
    ],
    variables: &[VarSpec::vector("torque", 3, "N.m", "Cut torque at frame_a, resolved in resolve_in_frame")],
    build: |p: &ParamSet| cut_sensor(p, &[(Quantity::CutTorque, ["torque_x", "torque_y", "torque_z"], "torque")], 1.0),
    shapes: crate::components::shapes::none,
};

pub static CUT_FORCE_AND_TORQUE: ComponentSpec = ComponentSpec {
    kind: "CutForceAndTorque",
    doc: "Sits between two parts (frame_a and frame_b are one frame) and reports the force and torque that act \
          on it at frame_a (their negatives with positive_sign = false), resolved in the world, frame_a, frame_b \
          or frame_resolve. The outputs depend on the accelerations: they are recorded in the results but cannot \
          be read by other components.",
    params: &[
        resolve_param(&["World", "FrameA", "FrameB", "FrameResolve"], "Frame in which the output vectors are resolved"),
        ParamSpec::boolean(
            "positive_sign",
            true,
            "true: the force and torque acting at frame_a; false: their negatives (those at frame_b)",
        ),
    ],
    connectors: &[
        FRAME_A,
        FRAME_B,
        frame("frame_resolve", "Output vectors are resolved in this frame when resolve_in_frame = FrameResolve"),
        output("force_x", "x component of the cut force (recorded only)"),
        output("force_y", "y component of the cut force (recorded only)"),
        output("force_z", "z component of the cut force (recorded only)"),
        output("torque_x", "x component of the cut torque (recorded only)"),
        output("torque_y", "y component of the cut torque (recorded only)"),
        output("torque_z", "z component of the cut torque (recorded only)"),
    ],
    variables: &[
        VarSpec::vector("force", 3, "N", "Cut force, resolved in resolve_in_frame"),
        VarSpec::vector("torque", 3, "N.m", "Cut torque, resolved in resolve_in_frame"),
    ],
    build: |p: &ParamSet| {
        let sign = if p.boolean("positive_sign") { 1.0 } else { -1.0 };
        cut_sensor(
            p,
            &[
                (Quantity::CutForce, ["force_x", "force_y", "force_z"], "force"),
                (Quantity::CutTorque, ["torque_x", "torque_y", "torque_z"], "torque"),
            ],
            sign,
        )
    },
    shapes: crate::components::shapes::none,
};

pub static POWER: ComponentSpec = ComponentSpec {
    kind: "Power",
    doc: "Sits between two parts (frame_a and frame_b are one frame) and reports the power flowing from frame_a \
          to frame_b, f . v + tau . w at frame_a, as `power`. It depends on the cut forces: it is recorded in the \
          results but cannot be read by other components.",
    params: &[],
    connectors: &[FRAME_A, FRAME_B, output("power", "Power flowing from frame_a to frame_b (recorded only)")],
    variables: &[VarSpec::scalar("power", "W", "Power flowing from frame_a to frame_b")],
    build: |p: &ParamSet| {
        let spec = p.spec;
        let mut s = Sensor::new(spec, None, 0);
        s.rigid = true;
        s.groups.push(Group { measure: Measure::Power, outputs: vec![at(spec, "power")], internal: None, off: None });
        s.variables.push((var(spec, "power"), Var::Power));
        boxed(s)
    },
    shapes: crate::components::shapes::none,
};
