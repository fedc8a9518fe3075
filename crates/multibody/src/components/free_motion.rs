//! FreeMotion: six degrees of freedom between two frames.

use super::orientation::{self, K, SEQUENCE, STATE_PRIORITY};
use super::spec::{concat, ComponentSpec, ConnectorSpec, VarSpec};
use super::{Component, EvalContext, ParamSet, Part, StateNames};
use crate::system::joint::{JointModel, RotationCoordinates};
use crate::Error;

pub static SPEC: ComponentSpec = ComponentSpec {
    kind: "FreeMotion",
    doc: "Free motion of frame_b relative to frame_a: no forces act through it, and it carries the relative \
          position r_rel_a and velocity v_rel_a (resolved in frame_a) and the relative rotation (Euler angles \
          phi, phid, or a quaternion Q_hat with w_rel_b) as states.",
    params: &[
        orientation::orientation_state_param("Euler", "States of the relative rotation: Euler or Quaternion"),
        SEQUENCE,
        K,
        STATE_PRIORITY,
    ],
    connectors: &[
        ConnectorSpec::frame("frame_a", "The reference frame"),
        ConnectorSpec::frame("frame_b", "The moving frame"),
    ],
    variables: &VARIABLES,
    build,
    shapes: super::shapes::none,
};

const MOTION: [VarSpec; 4] = [
    VarSpec::vector(
        "r_rel_a",
        3,
        "m",
        "Position vector from origin of frame_a to origin of frame_b, resolved in frame_a",
    ),
    VarSpec::vector(
        "v_rel_a",
        3,
        "m/s",
        "= der(r_rel_a), i.e., velocity of origin of frame_b with respect to origin of frame_a, resolved in frame_a",
    ),
    VarSpec::vector("a_rel_a", 3, "m/s2", "= der(v_rel_a)"),
    VarSpec::vector(
        "w_rel_b",
        3,
        "rad/s",
        "Relative angular velocity of frame_b with respect to frame_a, resolved in frame_b",
    ),
];
static VARIABLES: [VarSpec; 12] = concat(&MOTION, orientation::VARIABLES);

#[derive(Debug)]
struct FreeMotion {
    rotation: RotationCoordinates,
}

fn build(p: &ParamSet) -> Result<Box<dyn Component>, Error> {
    let rotation = orientation::coordinates(p)?.ok_or_else(|| {
        p.invalid("orientation_state", "FreeMotion carries its rotation as states: use Euler or Quaternion")
    })?;
    Ok(Box::new(FreeMotion { rotation }))
}

impl Component for FreeMotion {
    fn parts(&self) -> Vec<Part> {
        let states = match self.rotation {
            RotationCoordinates::Quaternion { .. } => {
                StateNames { q: &[("r_rel_a", 3), ("Q_hat", 4)], u: &[("v_rel_a", 3), ("w_rel_b", 3)] }
            }
            RotationCoordinates::Euler { .. } => {
                StateNames { q: &[("r_rel_a", 3), ("phi", 3)], u: &[("v_rel_a", 3), ("phid", 3)] }
            }
        };
        vec![Part::Joint { a: 0, b: 1, model: JointModel::Free(self.rotation), states, flanges: None, iscut: false }]
    }

    fn variables(&self) -> Vec<VarSpec> {
        MOTION.iter().copied().chain(orientation::variables(Some(self.rotation))).collect()
    }

    fn evaluate(&self, ctx: &EvalContext, out: &mut Vec<f64>) {
        let j = &ctx.joints[0];
        let (a, b) = (&ctx.frames[0], &ctx.frames[1]);
        out.extend_from_slice(&j.q[..3]);
        out.extend_from_slice(&j.u[..3]);
        out.extend_from_slice(&j.udot[..3]);
        let w_rel = b.w - b.rot * a.rot.tr_mul(&a.w);
        out.extend_from_slice(w_rel.as_slice());
        orientation::evaluate(self.rotation, j, 3, 3, out);
    }
}
