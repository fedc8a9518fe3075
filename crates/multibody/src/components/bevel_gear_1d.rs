//! BevelGear1D: an ideal gear between two shafts whose axes differ, with
//! its housing on a 3-D frame. The shafts' angles are relative to the
//! housing, `flange_a.phi = ratio * flange_b.phi`; the housing takes the
//! reaction `-e_a flange_a.tau - e_b flange_b.tau`, which reaches it
//! through the joints of the Rotor1D shafts the gear couples (so `n_a` and
//! `n_b` must be those rotors' axes).

use super::spec::{ComponentSpec, ConnectorSpec, ConnectorType, ParamSpec, VarSpec};
use super::{Component, EvalContext, ParamSet, Part};
use crate::Error;

pub static SPEC: ComponentSpec = ComponentSpec {
    kind: "BevelGear1D",
    doc: "Ideal gear between two shafts with different axes n_a and n_b (resolved in frame_a, the housing): \
          flange_a.phi = ratio * flange_b.phi, ratio * flange_a.tau + flange_b.tau = 0, angles relative to \
          frame_a. The housing's reaction torque goes into frame_a.",
    params: &[
        ParamSpec::boolean(
            "drive_train_mechanics_3d",
            true,
            "Mount the housing on frame_a (false: fixed in the world)",
        ),
        ParamSpec::real("ratio", 1.0, "", "Gear speed ratio (flange_a.phi = ratio * flange_b.phi)"),
        ParamSpec::vector("n_a", &[1.0, 0.0, 0.0], "", "Axis of rotation of flange_a, resolved in frame_a"),
        ParamSpec::vector("n_b", &[1.0, 0.0, 0.0], "", "Axis of rotation of flange_b, resolved in frame_a"),
    ],
    connectors: &[
        ConnectorSpec::flange("flange_a", ConnectorType::Spline, "Shaft a"),
        ConnectorSpec::flange("flange_b", ConnectorType::Spline, "Shaft b"),
        ConnectorSpec::frame("frame_a", "The housing (bearing frame)"),
    ],
    variables: &[
        VarSpec::scalar("phi_a", "rad", "Angle of flange_a relative to frame_a"),
        VarSpec::scalar("phi_b", "rad", "Angle of flange_b relative to frame_a"),
    ],
    build,
    shapes: crate::components::shapes::none,
};

#[derive(Debug)]
struct BevelGear1D {
    ratio: f64,
    mounted: bool,
}

fn build(p: &ParamSet) -> Result<Box<dyn Component>, Error> {
    let ratio = super::ideal_gear::ratio(p)?;
    p.direction("n_a")?;
    p.direction("n_b")?;
    Ok(Box::new(BevelGear1D { ratio, mounted: p.boolean("drive_train_mechanics_3d") }))
}

impl Component for BevelGear1D {
    fn parts(&self) -> Vec<Part> {
        let mut parts =
            vec![Part::Coupling { terms: vec![(0, 1.0), (1, -self.ratio)], constant: 0.0, measured: false }];
        if self.mounted {
            parts.push(Part::Mount1D { frame: 2, flanges: vec![0, 1] });
        }
        parts
    }

    fn variables(&self) -> Vec<VarSpec> {
        SPEC.variables.to_vec()
    }

    fn evaluate(&self, ctx: &EvalContext, out: &mut Vec<f64>) {
        out.extend([ctx.flanges[0].s, ctx.flanges[1].s]);
    }
}
