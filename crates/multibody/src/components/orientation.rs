//! Dyad's PartialOrientation: how a component carries an orientation as
//! states (Euler angles or a non-unit quaternion), and the variables that
//! come with them. Body, the shaped bodies, Spherical and FreeMotion share it.

use super::spec::{Default, ParamSpec, ParamType, VarSpec};
use super::{JointState, ParamSet};
use crate::model::OrientationState;
use crate::system::joint::RotationCoordinates;
use crate::Error;

/// The `orientation_state` parameter with a given default.
pub const fn orientation_state_param(default: &'static str, doc: &'static str) -> ParamSpec {
    ParamSpec {
        name: "orientation_state",
        ty: ParamType::Enum("OrientationState", OrientationState::VARIANTS),
        default: Default::Enum(default),
        unit: "",
        doc,
    }
}

pub const SEQUENCE: ParamSpec = ParamSpec {
    name: "sequence",
    ty: ParamType::IntVector(3),
    default: Default::Vector(&[1.0, 2.0, 3.0]),
    unit: "",
    doc: "Euler angle sequence used when orientation_state = Euler",
};
pub const K: ParamSpec = ParamSpec::real("k", 0.1, "1/s", "Gain that pulls |Q_hat| back towards 1 (quaternion state)");
pub const STATE_PRIORITY: ParamSpec = ParamSpec::integer(
    "statePriority",
    10.0,
    "State priority of the rotational states (kept for compatibility; states are chosen structurally)",
);
pub const INITIALIZE_ORIENTATION: ParamSpec =
    ParamSpec::boolean("initialize_orientation", true, "Give the orientation states their start values");

/// The quaternion variables, then the Euler ones, as in the seed's table.
pub const VARIABLES: &[VarSpec] = &[
    VarSpec::vector("Q", 4, "", "Unit quaternion with [w,i,j,k] (orientation_state = Quaternion)"),
    VarSpec::vector("Q_hat", 4, "", "Non-unit quaternion with [w,i,j,k] (orientation_state = Quaternion)"),
    VarSpec::vector("Q_hat_d", 4, "1/s", "der(Q_hat) (orientation_state = Quaternion)"),
    VarSpec::scalar("n_q", "", "|Q_hat|^2 (orientation_state = Quaternion)"),
    VarSpec::scalar("c_q", "1/s", "k (1 - n_q) (orientation_state = Quaternion)"),
    VarSpec::vector("phi", 3, "rad", "Euler angles (orientation_state = Euler)"),
    VarSpec::vector("phid", 3, "rad/s", "der(phi) (orientation_state = Euler)"),
    VarSpec::vector("phidd", 3, "rad/s2", "der(phid) (orientation_state = Euler)"),
];

/// The rotation coordinates `orientation_state` asks for, if any.
pub fn coordinates(p: &ParamSet) -> Result<Option<RotationCoordinates>, Error> {
    Ok(match p.variant("orientation_state") {
        "Quaternion" => Some(RotationCoordinates::Quaternion { k: p.real("k") }),
        "Euler" => Some(RotationCoordinates::Euler { sequence: p.sequence("sequence")? }),
        _ => None,
    })
}

/// The names of the variables that exist with these coordinates.
pub fn variable_names(rot: Option<RotationCoordinates>) -> &'static [&'static str] {
    match rot {
        Some(RotationCoordinates::Quaternion { .. }) => &["Q", "Q_hat", "Q_hat_d", "n_q", "c_q"],
        Some(RotationCoordinates::Euler { .. }) => &["phi", "phid", "phidd"],
        None => &[],
    }
}

/// The variables of `variable_names(rot)`, as specs.
pub fn variables(rot: Option<RotationCoordinates>) -> impl Iterator<Item = VarSpec> {
    let names = variable_names(rot);
    VARIABLES.iter().filter(move |v| names.contains(&v.name)).copied()
}

/// Pushes the values of `variables(rot)` from the rotation part of a
/// joint's coordinates (`offset` = where they start in `q`; the rates start
/// at `rate_offset` in `u`).
pub fn evaluate(rot: RotationCoordinates, joint: &JointState, offset: usize, rate_offset: usize, out: &mut Vec<f64>) {
    match rot {
        RotationCoordinates::Quaternion { k } => {
            let q_hat = &joint.q[offset..offset + 4];
            let n_q: f64 = q_hat.iter().map(|x| x * x).sum();
            out.extend(q_hat.iter().map(|x| x / n_q.sqrt()));
            out.extend_from_slice(q_hat);
            out.extend_from_slice(&joint.qdot[offset..offset + 4]);
            out.extend([n_q, k * (1.0 - n_q)]);
        }
        RotationCoordinates::Euler { .. } => {
            out.extend_from_slice(&joint.q[offset..offset + 3]);
            out.extend_from_slice(&joint.u[rate_offset..rate_offset + 3]);
            out.extend_from_slice(&joint.udot[rate_offset..rate_offset + 3]);
        }
    }
}
