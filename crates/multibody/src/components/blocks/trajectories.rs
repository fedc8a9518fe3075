//! Trajectory sources: Kinematic5, KinematicPTP, KinematicPTPBoundedJerk
//! (MultibodyComponents) and BlockComponents.KinematicPTP (Modelica's
//! KinematicPTP2). Each output (`q`, `qd`, `qdd`, and `qddd` for the
//! jerk-limited one) is a signal source of time; the math is in
//! [`super::kinematic`].
//!
//! The library's blocks take one value per axis (`nout` axes, outputs
//! `q[1..nout]`). Here a block drives one axis (`nout = 1`): its per-axis
//! parameters are one-element arrays (`q1 = [2]`), its outputs are the
//! scalar connectors `q`, `qd`, ..., and its variables are named `q[1]`,
//! `qd[1]`, ... as the library names them. Use one block per axis.

use crate::components::spec::{ComponentSpec, ConnectorSpec, ParamSpec, ParamType, VarSpec};
use crate::components::{Component, EvalContext, ParamSet, Part, SignalLaw, SignalSource};
use crate::math::trajectory::{point_to_point, point_to_point_bounded_jerk, Piecewise, Quintic, Trajectory};
use crate::Error;

const NOUT: ParamSpec = ParamSpec::integer("nout", 1.0, "Number of output axes (one per block here)");

const fn axis(name: &'static str, default: &'static [f64], doc: &'static str) -> ParamSpec {
    ParamSpec { name, ty: ParamType::Vector(1), default: crate::components::Default::Vector(default), unit: "", doc }
}

const Q0: ParamSpec = axis("q0", &[0.0], "Initial position for each axis");
const Q1: ParamSpec = axis("q1", &[1.0], "Final position for each axis");
const QD_MAX: ParamSpec = axis("qd_max", &[1.0], "Maximum velocity for each axis");
const QDD_MAX: ParamSpec = axis("qdd_max", &[1.0], "Maximum acceleration for each axis");

const OUTPUTS: [ConnectorSpec; 3] = [
    ConnectorSpec::output("q", "Position"),
    ConnectorSpec::output("qd", "Velocity (= der(q))"),
    ConnectorSpec::output("qdd", "Acceleration (= der(qd))"),
];

const VARIABLES: [VarSpec; 3] = [
    VarSpec::vector("q", 1, "", "Position"),
    VarSpec::vector("qd", 1, "", "Velocity (= der(q))"),
    VarSpec::vector("qdd", 1, "", "Acceleration (= der(qd))"),
];

pub static KINEMATIC5: ComponentSpec = ComponentSpec {
    kind: "Kinematic5",
    doc: "Fifth-order polynomial trajectory from q0 at time 0 to q1 at time tf, meeting the given speeds and \
          accelerations at both ends; outputs position q, velocity qd and acceleration qdd. After tf the axis \
          moves on at qd1 (rests with the default qd1 = 0).",
    params: &[
        NOUT,
        ParamSpec::real("tf", 1.0, "s", "Final time for the trajectory"),
        Q0,
        Q1,
        axis("qd0", &[0.0], "Initial velocity for each axis"),
        axis("qd1", &[0.0], "Final velocity for each axis"),
        axis("qdd0", &[0.0], "Initial acceleration for each axis"),
        axis("qdd1", &[0.0], "Final acceleration for each axis"),
    ],
    connectors: &OUTPUTS,
    variables: &VARIABLES,
    build: |p: &ParamSet| {
        one_axis(p)?;
        let tf = p.real("tf");
        if tf.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
            return Err(p.invalid("tf", "the final time must be positive"));
        }
        let start = [value(p, "q0"), value(p, "qd0"), value(p, "qdd0")];
        let end = [value(p, "q1"), value(p, "qd1"), value(p, "qdd1")];
        Ok(block(Trajectory::Quintic(Quintic::new(tf, start, end)), 3, false))
    },
    shapes: crate::components::shapes::none,
};

pub static KINEMATIC_PTP: ComponentSpec = ComponentSpec {
    kind: "KinematicPTP",
    doc: "Fastest point-to-point move from q0 to q1 starting at time 0 with speed at most qd_max and acceleration \
          at most qdd_max: constant acceleration, coasting at qd_max when the distance allows, constant braking. \
          Outputs position q, velocity qd and acceleration qdd.",
    params: &[NOUT, Q0, Q1, QD_MAX, QDD_MAX],
    connectors: &OUTPUTS,
    variables: &VARIABLES,
    build: |p: &ParamSet| {
        one_axis(p)?;
        let (v, a) = (positive(p, "qd_max")?, positive(p, "qdd_max")?);
        Ok(block(Trajectory::Piecewise(point_to_point(0.0, value(p, "q0"), value(p, "q1"), v, a)), 3, false))
    },
    shapes: crate::components::shapes::none,
};

pub static KINEMATIC_PTP_BOUNDED_JERK: ComponentSpec = ComponentSpec {
    kind: "KinematicPTPBoundedJerk",
    doc: "Time-optimal point-to-point move from rest at q0 to rest at q1 starting at time 0 with speed, \
          acceleration and jerk at most qd_max, qdd_max, qddd_max (the seven-phase double-S profile). Outputs \
          position q, velocity qd, acceleration qdd and jerk qddd.",
    params: &[NOUT, Q0, Q1, QD_MAX, QDD_MAX, axis("qddd_max", &[10.0], "Maximum jerk for each axis")],
    connectors: &[OUTPUTS[0], OUTPUTS[1], OUTPUTS[2], ConnectorSpec::output("qddd", "Jerk (= der(qdd))")],
    variables: &[VARIABLES[0], VARIABLES[1], VARIABLES[2], VarSpec::vector("qddd", 1, "", "Jerk (= der(qdd))")],
    build: |p: &ParamSet| {
        one_axis(p)?;
        let (v, a, j) = (positive(p, "qd_max")?, positive(p, "qdd_max")?, positive(p, "qddd_max")?);
        let path = point_to_point_bounded_jerk(0.0, value(p, "q0"), value(p, "q1"), v, a, j);
        Ok(block(Trajectory::Piecewise(path), 4, false))
    },
    shapes: crate::components::shapes::none,
};

pub static BLOCK_KINEMATIC_PTP: ComponentSpec = ComponentSpec {
    kind: "BlockComponents.KinematicPTP",
    doc: "Move as fast as possible from q0 to q1 from startTime on, with speed at most qd_max and acceleration at \
          most qdd_max (Modelica's KinematicPTP2): accelerate at the limit, coast at qd_max when the distance \
          allows, brake at the limit. Outputs q, qd, qdd; before startTime it rests at q0. The variables moving \
          (1 while the axis travels, else 0) and endTime tell when the move ends.",
    params: &[
        NOUT,
        Q0,
        Q1,
        QD_MAX,
        QDD_MAX,
        ParamSpec::real("startTime", 0.0, "s", "Time at which the movement starts"),
    ],
    connectors: &OUTPUTS,
    variables: &[
        VARIABLES[0],
        VARIABLES[1],
        VARIABLES[2],
        VarSpec::scalar("moving", "", "1 while the axis is still travelling, 0 before startTime and after endTime"),
        VarSpec::scalar("endTime", "s", "The instant the movement stops"),
    ],
    build: |p: &ParamSet| {
        one_axis(p)?;
        let (v, a) = (positive(p, "qd_max")?, positive(p, "qdd_max")?);
        let path = point_to_point(p.real("startTime"), value(p, "q0"), value(p, "q1"), v, a);
        Ok(block(Trajectory::Piecewise(path), 3, true))
    },
    shapes: crate::components::shapes::none,
};

/// Only one axis per block: say so for any other `nout`.
fn one_axis(p: &ParamSet) -> Result<(), Error> {
    if p.integer("nout") != 1 {
        return Err(p.invalid("nout", "a block drives one axis here (nout = 1); use one block per axis"));
    }
    Ok(())
}

/// A per-axis parameter (a one-element array).
fn value(p: &ParamSet, name: &str) -> f64 {
    p.vector(name).first().copied().unwrap_or(0.0)
}

/// A per-axis limit, which must be positive.
fn positive(p: &ParamSet, name: &str) -> Result<f64, Error> {
    let x = value(p, name);
    if x.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
        return Err(p.invalid(name, "a limit must be positive"));
    }
    Ok(x)
}

fn block(path: Trajectory, outputs: usize, timing: bool) -> Box<dyn Component> {
    Box::new(TrajectoryBlock { path, outputs, timing })
}

/// The derivatives `0..outputs` of one trajectory on the output connectors
/// of the same numbers.
#[derive(Debug)]
struct TrajectoryBlock {
    path: Trajectory,
    outputs: usize,
    /// Also the variables `moving` and `endTime`.
    timing: bool,
}

impl Component for TrajectoryBlock {
    fn parts(&self) -> Vec<Part> {
        (0..self.outputs)
            .map(|order| Part::Signal {
                output: order,
                law: SignalLaw::Source(SignalSource::Trajectory { path: self.path.clone(), order }),
                inputs: [None; 3],
                frames: [None; 2],
                flanges: [None; 2],
            })
            .collect()
    }

    fn variables(&self) -> Vec<VarSpec> {
        let mut vars = vec![VARIABLES[0], VARIABLES[1], VARIABLES[2]];
        if self.outputs == 4 {
            vars.push(VarSpec::vector("qddd", 1, "", "Jerk (= der(qdd))"));
        }
        if self.timing {
            vars.push(VarSpec::scalar("moving", "", "1 while the axis is still travelling"));
            vars.push(VarSpec::scalar("endTime", "s", "The instant the movement stops"));
        }
        vars
    }

    fn evaluate(&self, ctx: &EvalContext, out: &mut Vec<f64>) {
        let jet = self.path.jet(ctx.time);
        out.extend_from_slice(&jet[..self.outputs]);
        if self.timing {
            let end = self.path.end_time();
            let start = match &self.path {
                Trajectory::Piecewise(Piecewise { t_start, .. }) => *t_start,
                Trajectory::Quintic(_) => 0.0,
            };
            out.push(if ctx.time >= start && ctx.time < end { 1.0 } else { 0.0 });
            out.push(end);
        }
    }
}
