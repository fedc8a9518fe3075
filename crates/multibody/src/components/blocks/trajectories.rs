//! Trajectory sources: Kinematic5, KinematicPTP, KinematicPTPBoundedJerk
//! (MultibodyComponents) and BlockComponents.KinematicPTP (Modelica's
//! KinematicPTP2). Each output (`q`, `qd`, `qdd`, and `qddd` for the
//! jerk-limited one) is a signal source of time; the math is in
//! [`super::kinematic`].
//!
//! The library's blocks take one value per axis (`nout` axes, outputs
//! `q[1..nout]`). The point-to-point blocks (KinematicPTP and
//! BlockComponents.KinematicPTP) drive up to [`MAX_AXES`] axes, all on one
//! profile so that they start and stop together (below); their outputs
//! are `q[i]`, `qd[i]`, `qdd[i]`, and `q`, `qd`, `qdd` are those of the
//! first axis. Kinematic5 and KinematicPTPBoundedJerk drive one axis
//! (`nout = 1`, one-element arrays `q1 = [2]`, outputs `q`, `qd`, ...):
//! use one block per axis. The variables are named `q[1]`, `qd[1]`, ... as
//! the library names them.
//!
//! Several axes of a point-to-point block move on one normalised path
//! `s(t)` from 0 to 1 (Modelica's KinematicPTP2 and the library's
//! phase-synchronised trajectory): `q[i] = q0[i] + (q1[i] - q0[i]) s(t)`,
//! where `s` is the fastest trapezoidal profile with speed at most
//! `min_i qd_max[i] / |q1[i] - q0[i]|` and acceleration at most
//! `min_i qdd_max[i] / |q1[i] - q0[i]|`: the slowest axis sets the time,
//! the others are slowed to end with it.

use crate::components::spec::{ComponentSpec, ConnectorSpec, ParamSpec, ParamType, VarSpec};
use crate::components::{Component, EvalContext, ParamSet, Part, SignalLaw, SignalSource};
use crate::math::trajectory::{point_to_point, point_to_point_bounded_jerk, Piecewise, Quintic, Trajectory};
use crate::Error;

const NOUT: ParamSpec = ParamSpec::integer("nout", 1.0, "Number of output axes (one per block here)");

const fn axis(name: &'static str, default: &'static [f64], doc: &'static str) -> ParamSpec {
    ParamSpec { name, ty: ParamType::Vector(1), default: crate::components::Default::Vector(default), unit: "", doc }
}

/// A per-axis parameter of the point-to-point blocks: one number per axis
/// (any count; a single number serves every axis).
const fn axes(name: &'static str, default: &'static [f64], doc: &'static str) -> ParamSpec {
    ParamSpec { name, ty: ParamType::Vector(0), default: crate::components::Default::Vector(default), unit: "", doc }
}

/// The most axes one point-to-point block drives.
pub const MAX_AXES: usize = 6;

const PTP_PARAMS: [ParamSpec; 5] = [
    ParamSpec::integer("nout", 1.0, "Number of output axes"),
    axes("q0", &[0.0], "Initial position for each axis"),
    axes("q1", &[1.0], "Final position for each axis"),
    axes("qd_max", &[1.0], "Maximum velocity for each axis"),
    axes("qdd_max", &[1.0], "Maximum acceleration for each axis"),
];

/// `q`, `qd`, `qdd` (the first axis), then `q[i]`, `qd[i]`, `qdd[i]` of
/// every axis.
const PTP_OUTPUTS: [ConnectorSpec; 3 + 3 * MAX_AXES] = {
    const NAMES: [[&str; 3]; MAX_AXES] = [
        ["q[1]", "qd[1]", "qdd[1]"],
        ["q[2]", "qd[2]", "qdd[2]"],
        ["q[3]", "qd[3]", "qdd[3]"],
        ["q[4]", "qd[4]", "qdd[4]"],
        ["q[5]", "qd[5]", "qdd[5]"],
        ["q[6]", "qd[6]", "qdd[6]"],
    ];
    const DOCS: [&str; 3] = ["Position of that axis", "Its velocity", "Its acceleration"];
    let mut out = [OUTPUTS[0]; 3 + 3 * MAX_AXES];
    out[1] = OUTPUTS[1];
    out[2] = OUTPUTS[2];
    let mut i = 0;
    while i < MAX_AXES {
        let mut k = 0;
        while k < 3 {
            out[3 + 3 * i + k] = ConnectorSpec::output(NAMES[i][k], DOCS[k]);
            k += 1;
        }
        i += 1;
    }
    out
};

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
          Several axes (nout) move on one profile set by the slowest and end together. Outputs position q[i], \
          velocity qd[i] and acceleration qdd[i] (q, qd, qdd: the first axis).",
    params: &PTP_PARAMS,
    connectors: &PTP_OUTPUTS,
    variables: &VARIABLES,
    build: |p: &ParamSet| Ok(Box::new(PtpBlock { paths: synchronized(p, 0.0)?, timing: false })),
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
          allows, brake at the limit. Several axes (nout) move on one profile set by the slowest and end together. \
          Outputs q[i], qd[i], qdd[i] (q, qd, qdd: the first axis); before startTime it rests at q0. The \
          variables moving (1 while the axes travel, else 0) and endTime tell when the move ends.",
    params: &[
        PTP_PARAMS[0],
        PTP_PARAMS[1],
        PTP_PARAMS[2],
        PTP_PARAMS[3],
        PTP_PARAMS[4],
        ParamSpec::real("startTime", 0.0, "s", "Time at which the movement starts"),
    ],
    connectors: &PTP_OUTPUTS,
    variables: &[
        VARIABLES[0],
        VARIABLES[1],
        VARIABLES[2],
        VarSpec::scalar("moving", "", "1 while the axis is still travelling, 0 before startTime and after endTime"),
        VarSpec::scalar("endTime", "s", "The instant the movement stops"),
    ],
    build: |p: &ParamSet| Ok(Box::new(PtpBlock { paths: synchronized(p, p.real("startTime"))?, timing: true })),
    shapes: crate::components::shapes::none,
};

/// The paths of the `nout` axes of a point-to-point block starting at
/// `start`: one trapezoidal profile `s(t)` from 0 to 1, scaled by each
/// axis's travel (see the module's documentation).
fn synchronized(p: &ParamSet, start: f64) -> Result<Vec<Piecewise>, Error> {
    let n = p.integer("nout");
    if !(1..=MAX_AXES as i64).contains(&n) {
        return Err(p.invalid("nout", format!("a block drives 1 to {MAX_AXES} axes")));
    }
    let n = n as usize;
    let per_axis = |name: &str| -> Result<Vec<f64>, Error> {
        let v = p.vector(name);
        match v.len() {
            1 => Ok(vec![v[0]; n]),
            len if len == n => Ok(v),
            len => Err(p.invalid(name, format!("one number per axis: nout = {n}, and it has {len}"))),
        }
    };
    let (q0, q1, v, a) = (per_axis("q0")?, per_axis("q1")?, per_axis("qd_max")?, per_axis("qdd_max")?);
    for (name, limits) in [("qd_max", &v), ("qdd_max", &a)] {
        if limits.iter().any(|x| x.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater)) {
            return Err(p.invalid(name, "a limit must be positive"));
        }
    }
    // The normalised limits: the tightest axis's.
    let (mut sd, mut sdd) = (f64::INFINITY, f64::INFINITY);
    for i in 0..n {
        let d = (q1[i] - q0[i]).abs();
        if d > 0.0 {
            sd = sd.min(v[i] / d);
            sdd = sdd.min(a[i] / d);
        }
    }
    if !sd.is_finite() {
        return Ok((0..n).map(|i| Piecewise::chain(start, q0[i], &[])).collect());
    }
    let s = point_to_point(start, 0.0, 1.0, sd, sdd);
    Ok((0..n)
        .map(|i| {
            let travel = q1[i] - q0[i];
            let pieces: Vec<(f64, f64, f64)> =
                pieces(&s).into_iter().map(|(d, a, j)| (d, a * travel, j * travel)).collect();
            let mut path = Piecewise::chain(start, q0[i], &pieces);
            path.q_end = q1[i];
            path
        })
        .collect())
}

/// The pieces `(duration, acceleration at start, jerk)` of a path.
fn pieces(s: &Piecewise) -> Vec<(f64, f64, f64)> {
    let ends = s.segments.iter().skip(1).map(|g| g.t).chain([s.t_end]);
    s.segments.iter().zip(ends).map(|(g, end)| (end - g.t, g.a, g.j)).collect()
}

/// A point-to-point block: one path per axis, each giving its position,
/// speed and acceleration.
#[derive(Debug)]
struct PtpBlock {
    paths: Vec<Piecewise>,
    /// Also the variables `moving` and `endTime`.
    timing: bool,
}

impl Component for PtpBlock {
    fn parts(&self) -> Vec<Part> {
        let signal = |output: usize, path: &Piecewise, order: usize| Part::Signal {
            output,
            law: SignalLaw::Source(SignalSource::Trajectory { path: Trajectory::Piecewise(path.clone()), order }),
            inputs: [None; 3],
            frames: [None; 2],
            flanges: [None; 2],
        };
        let mut parts: Vec<Part> = (0..3).map(|order| signal(order, &self.paths[0], order)).collect();
        for (i, path) in self.paths.iter().enumerate() {
            parts.extend((0..3).map(|order| signal(3 + 3 * i + order, path, order)));
        }
        // The outputs of the axes it does not have read as unavailable.
        for output in 3 + 3 * self.paths.len()..3 + 3 * MAX_AXES {
            parts.push(Part::Signal {
                output,
                law: SignalLaw::Unavailable { reason: "belongs to an axis beyond the block's nout" },
                inputs: [None; 3],
                frames: [None; 2],
                flanges: [None; 2],
            });
        }
        parts
    }

    fn variables(&self) -> Vec<VarSpec> {
        let n = self.paths.len();
        let mut vars = vec![
            VarSpec::vector("q", n, "", "Position"),
            VarSpec::vector("qd", n, "", "Velocity (= der(q))"),
            VarSpec::vector("qdd", n, "", "Acceleration (= der(qd))"),
        ];
        if self.timing {
            vars.push(VarSpec::scalar("moving", "", "1 while the axes are still travelling"));
            vars.push(VarSpec::scalar("endTime", "s", "The instant the movement stops"));
        }
        vars
    }

    fn evaluate(&self, ctx: &EvalContext, out: &mut Vec<f64>) {
        let jets: Vec<[f64; 5]> = self.paths.iter().map(|p| p.jet(ctx.time)).collect();
        for order in 0..3 {
            out.extend(jets.iter().map(|j| j[order]));
        }
        if self.timing {
            let (start, end) = (self.paths[0].t_start, self.paths[0].end_time());
            out.push(if ctx.time >= start && ctx.time < end { 1.0 } else { 0.0 });
            out.push(end);
        }
    }
}

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
