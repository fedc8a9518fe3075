//! JointRRR: three revolutes with parallel axes joined by two rods, the
//! usual way to close a planar loop.
//!
//! Modelica and the Dyad library solve its closure in closed form. Here it
//! is its three revolutes and two rods: the loop it closes is cut and kept
//! by the constraint solver like any other, which gives the same motion
//! (the assembly has no mass) at the cost of a few constraint rows. The
//! branch is the one the start configuration is on.

use super::spec::{ComponentSpec, ConnectorSpec, ConnectorType, ParamSpec, VarSpec};
use super::{AxisFlanges, Component, EvalContext, ParamSet, Part, StateNames};
use crate::math::{Transform, Vec3};
use crate::system::JointModel;
use crate::Error;

pub static SPEC: ComponentSpec = ComponentSpec {
    kind: "JointRRR",
    doc: "Three revolutes with parallel axes n_a joined by two massless rods: rod 1 from frame_a to the middle \
          revolute (rRod1_ia, fixed in frame_ia) and rod 2 from frame_b's revolute to it (rRod2_ib, fixed in \
          frame_ib; frame_im sits at the middle revolute on rod 2). It closes planar loops; axis and bearing \
          drive the revolute at frame_b.",
    params: &[
        ParamSpec::boolean("positive_branch", true, "Kept for compatibility: the branch is the start configuration's"),
        ParamSpec::vector("n_a", &[0.0, 0.0, 1.0], "", "Axis of the revolutes, resolved in frame_a"),
        ParamSpec::vector("n_b", &[0.0, 0.0, 1.0], "", "Axis of the revolute at frame_b, resolved in frame_b"),
        ParamSpec::vector("rRod1_ia", &[1.0, 0.0, 0.0], "m", "From frame_a to the middle revolute, in frame_ia"),
        ParamSpec::vector("rRod2_ib", &[-1.0, 0.0, 0.0], "m", "From frame_ib to the middle revolute, in frame_ib"),
        ParamSpec::real("phi_offset", 0.0, "rad", "Angle offset of the revolute at frame_b"),
        ParamSpec::real("phi_guess", 0.0, "rad", "Start guess of the revolute angle at frame_b"),
        ParamSpec::real("rod_radius", 0.05, "m", "Radius of the rods in animations"),
        ParamSpec::vector("rod_color", &[0.5, 0.0, 0.5, 1.0], "", "Colour of the rods (RGBA)"),
    ],
    connectors: &[
        ConnectorSpec::frame("frame_a", "The first revolute's outer side"),
        ConnectorSpec::frame("frame_b", "The frame_b revolute's outer side"),
        ConnectorSpec::frame("frame_ia", "Fixed in rod 1 at frame_a's origin"),
        ConnectorSpec::frame("frame_ib", "Fixed in rod 2 at frame_b's origin"),
        ConnectorSpec::frame("frame_im", "Fixed in rod 2 at the middle revolute"),
        ConnectorSpec::flange("axis", ConnectorType::Spline, "Drives the revolute at frame_b"),
        ConnectorSpec::flange("bearing", ConnectorType::Spline, "Support of that drive"),
        ConnectorSpec::internal("rod1_tip", ConnectorType::Frame),
    ],
    variables: &[],
    build,
    shapes: super::shapes::none,
};

const ROD1_TIP: usize = 7;

fn build(p: &ParamSet) -> Result<Box<dyn Component>, Error> {
    let n_a = p.direction("n_a")?;
    let n_b = p.direction("n_b")?;
    let rod1 = p.vec3("rRod1_ia");
    if rod1.norm() == 0.0 {
        return Err(p.invalid("rRod1_ia", "rod 1 must have a length"));
    }
    Ok(Box::new(JointRrr { n_a, n_b, rod1, rod2: p.vec3("rRod2_ib") }))
}

#[derive(Debug)]
struct JointRrr {
    n_a: Vec3,
    n_b: Vec3,
    rod1: Vec3,
    rod2: Vec3,
}

impl Component for JointRrr {
    fn parts(&self) -> Vec<Part> {
        let revolute = |a, b, axis, states, flanges| Part::Joint {
            a,
            b,
            model: JointModel::Revolute { axis },
            states,
            flanges,
            iscut: false,
        };
        vec![
            revolute(0, 2, self.n_a, StateNames { q: &[("phi_a", 1)], u: &[("w_a", 1)] }, None),
            Part::Rigid { a: 2, b: ROD1_TIP, pose: Transform::translation(self.rod1) },
            revolute(ROD1_TIP, 4, self.n_a, StateNames { q: &[("phi_m", 1)], u: &[("w_m", 1)] }, None),
            revolute(
                1,
                3,
                self.n_b,
                StateNames { q: &[("phi", 1)], u: &[("w", 1)] },
                Some(AxisFlanges { axis: 5, support: 6 }),
            ),
            Part::Rigid { a: 3, b: 4, pose: Transform::translation(self.rod2) },
        ]
    }

    fn variables(&self) -> Vec<VarSpec> {
        Vec::new()
    }

    fn evaluate(&self, _: &EvalContext, _: &mut Vec<f64>) {}
}
