//! GearConstraint: an ideal gear between two shafts in 3-D. Shaft a turns
//! frame_a about n_a and shaft b turns frame_b about n_b, both in bearings
//! on the bearing frame (at r_a and r_b from it), with
//! `phi_a = ratio * phi_b`: two revolute joints whose coordinates are
//! coupled by a constraint, so the bearing takes every reaction.

use super::spec::{ComponentSpec, ConnectorSpec, ConnectorType, ParamSpec, ParamType, VarSpec};
use super::{AxisFlanges, Component, EvalContext, ParamSet, Part, StateNames};
use crate::math::{Transform, Vec3};
use crate::system::joint::JointModel;
use crate::Error;

pub static SPEC: ComponentSpec = ComponentSpec {
    kind: "GearConstraint",
    doc: "Ideal massless gear between two shafts with arbitrary axes: frame_a turns about n_a (through bearing + \
          r_a) and frame_b about n_b (through bearing + r_b), relative to the bearing frame, with phi_a = ratio * \
          phi_b. The bearing must be connected; it takes the reactions.",
    params: &[
        ParamSpec::boolean("checkTotalPower", false, "Kept for compatibility (power balance is a test here)"),
        ParamSpec::integer("statePriority", 1.0, "State priority of phi_b and w_b (kept for compatibility)"),
        ParamSpec::required("ratio", ParamType::Real, "", "Gear speed ratio phi_a / phi_b"),
        ParamSpec::vector(
            "n_a",
            &[1.0, 0.0, 0.0],
            "",
            "Axis of rotation of shaft a (same in frame_a, frame_b and bearing)",
        ),
        ParamSpec::vector(
            "n_b",
            &[1.0, 0.0, 0.0],
            "",
            "Axis of rotation of shaft b (same in frame_a, frame_b and bearing)",
        ),
        ParamSpec::vector("r_a", &[0.0, 0.0, 0.0], "m", "Vector from bearing to frame_a, resolved in bearing"),
        ParamSpec::vector("r_b", &[0.0, 0.0, 0.0], "m", "Vector from bearing to frame_b, resolved in bearing"),
    ],
    connectors: &[
        ConnectorSpec::frame("frame_a", "Shaft a"),
        ConnectorSpec::frame("frame_b", "Shaft b"),
        ConnectorSpec::frame("bearing", "The housing both shafts turn in"),
        ConnectorSpec::internal("bearing_a", ConnectorType::Frame),
        ConnectorSpec::internal("bearing_b", ConnectorType::Frame),
        ConnectorSpec::internal("axis_a", ConnectorType::Spline),
        ConnectorSpec::internal("axis_b", ConnectorType::Spline),
        ConnectorSpec::internal("support", ConnectorType::Spline),
    ],
    variables: &[
        VarSpec::scalar("phi_a", "rad", "Rotation angle of shaft a relative to the bearing"),
        VarSpec::scalar("phi_b", "rad", "Rotation angle of shaft b relative to the bearing"),
        VarSpec::scalar("w_b", "rad/s", "Angular velocity of shaft b relative to the bearing"),
        VarSpec::scalar("a_b", "rad/s2", "Angular acceleration of shaft b relative to the bearing"),
    ],
    build,
    shapes: crate::components::shapes::none,
};

const SHAFT_A: StateNames = StateNames { q: &[("phi_a", 1)], u: &[("w_a", 1)] };
const SHAFT_B: StateNames = StateNames { q: &[("phi_b", 1)], u: &[("w_b", 1)] };

#[derive(Debug)]
struct GearConstraint {
    ratio: f64,
    n: [Vec3; 2],
    r: [Vec3; 2],
}

fn build(p: &ParamSet) -> Result<Box<dyn Component>, Error> {
    let ratio = super::ideal_gear::ratio(p)?;
    Ok(Box::new(GearConstraint {
        ratio,
        n: [p.direction("n_a")?, p.direction("n_b")?],
        r: [p.vec3("r_a"), p.vec3("r_b")],
    }))
}

impl Component for GearConstraint {
    fn parts(&self) -> Vec<Part> {
        let (bearing, support) = (2, 7);
        let shaft = |side: usize, states| {
            let inner = 3 + side;
            [
                Part::Rigid { a: bearing, b: inner, pose: Transform::translation(self.r[side]) },
                Part::Joint {
                    a: inner,
                    b: side,
                    model: JointModel::Revolute { axis: self.n[side] },
                    states,
                    flanges: Some(AxisFlanges { axis: 5 + side, support }),
                    iscut: false,
                },
            ]
        };
        let mut parts: Vec<Part> = shaft(0, SHAFT_A).into_iter().chain(shaft(1, SHAFT_B)).collect();
        parts.push(Part::Coupling { terms: vec![(5, 1.0), (6, -self.ratio)], constant: 0.0, measured: false });
        parts
    }

    fn variables(&self) -> Vec<VarSpec> {
        SPEC.variables.to_vec()
    }

    fn evaluate(&self, ctx: &EvalContext, out: &mut Vec<f64>) {
        let (a, b) = (&ctx.joints[0], &ctx.joints[1]);
        out.extend([a.q[0], b.q[0], b.u[0], b.udot[0]]);
    }
}
