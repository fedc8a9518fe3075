//! Mounting1D: the housing of a 1-D drive train fixed in a 3-D frame. The
//! support angle stays at `phi0` relative to frame_a, and the torques the
//! drive train puts on its supports go into frame_a: through the joints of
//! the Rotor1D shafts the drive train turns, which is why `n` must be the
//! axis of those rotors.

use super::spec::{ComponentSpec, ConnectorSpec, ConnectorType, ParamSpec};
use super::{Component, ParamSet, Part};
use crate::math::Transform;
use crate::Error;

pub static SPEC: ComponentSpec = ComponentSpec {
    kind: "Mounting1D",
    doc: "Fixes the 1-D support flange_b at the angle phi0 relative to frame_a and passes its reaction torque, \
          about the axis n, into frame_a (and housing_frame_a, rigidly joined to it). On a moving frame, the \
          drive train it supports must turn on Rotor1D shafts mounted on the same body.",
    params: &[
        ParamSpec::boolean(
            "drive_train_mechanics_3d",
            true,
            "Pass the reaction into frame_a (false: fixed in the world)",
        ),
        ParamSpec::real("phi0", 0.0, "rad", "Fixed offset angle of housing"),
        ParamSpec::vector("n", &[1.0, 0.0, 0.0], "", "Axis of rotation = axis of support torque (resolved in frame_a)"),
    ],
    connectors: &[
        ConnectorSpec::frame("frame_a", "The frame the housing is fixed in"),
        ConnectorSpec::frame("housing_frame_a", "The housing, rigidly on frame_a"),
        ConnectorSpec::flange("flange_b", ConnectorType::Spline, "The support flange, fixed at phi0"),
    ],
    variables: &[],
    build,
    shapes: crate::components::shapes::none,
};

#[derive(Debug)]
struct Mounting1D {
    phi0: f64,
    mounted: bool,
}

fn build(p: &ParamSet) -> Result<Box<dyn Component>, Error> {
    p.direction("n")?;
    Ok(Box::new(Mounting1D { phi0: p.real("phi0"), mounted: p.boolean("drive_train_mechanics_3d") }))
}

impl Component for Mounting1D {
    fn parts(&self) -> Vec<Part> {
        let mut parts =
            vec![Part::Rigid { a: 0, b: 1, pose: Transform::IDENTITY }, Part::Fixed1D { flange: 2, at: self.phi0 }];
        if self.mounted {
            parts.push(Part::Mount1D { frame: 0, flanges: vec![2] });
        }
        parts
    }
}
