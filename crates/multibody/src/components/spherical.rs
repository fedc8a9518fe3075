//! Spherical: a ball joint, three rotational degrees of freedom.

use super::orientation::{self, INITIALIZE_ORIENTATION, K, SEQUENCE, STATE_PRIORITY};
use super::shapes::{look, LocalShape, ShapeKind};
use super::spec::{ComponentSpec, ConnectorSpec, ParamSpec, ParamType, VarSpec};
use super::{Component, EvalContext, ParamSet, Part, StateNames};
use crate::math::Vec3;
use crate::system::joint::{JointModel, RotationCoordinates};
use crate::Error;

pub static SPEC: ComponentSpec = ComponentSpec {
    kind: "Spherical",
    doc: "Spherical joint (ball joint): frame_b rotates freely about the common origin of the two frames. With \
          orientation_state Euler (phi, phid) or Quaternion (Q_hat, w_rel) the joint carries the relative rotation \
          as states; with None it only keeps the origins together and the orientation comes from the bodies.",
    params: &[
        orientation::orientation_state_param(
            "Euler",
            "States of the relative rotation: Euler, Quaternion, or None (no states)",
        ),
        SEQUENCE,
        STATE_PRIORITY,
        INITIALIZE_ORIENTATION,
        ParamSpec::boolean("w_rel_a_fixed", false, "Kept for compatibility; start values are set with initial"),
        ParamSpec::boolean("z_rel_a_fixed", false, "Kept for compatibility"),
        K,
        ParamSpec::boolean("render", true, "Render the joint in animations"),
        ParamSpec::world("color", ParamType::Vector(4), "default_joint_color", 1.0, "", "Colour (RGBA)"),
        ParamSpec::real("specular_coefficient", 1.5, "", "Reflection of light in animations"),
        ParamSpec::world(
            "radius",
            ParamType::Real,
            "default_joint_width",
            1.0,
            "m",
            "Radius of the sphere in animations",
        ),
    ],
    connectors: &[
        ConnectorSpec::frame("frame_a", "The frame the joint is mounted on"),
        ConnectorSpec::frame("frame_b", "The rotating frame"),
    ],
    variables: &VARIABLES,
    build,
    shapes,
};

/// A sphere at the joint.
fn shapes(p: &ParamSet) -> Vec<LocalShape> {
    if !p.boolean("render") {
        return Vec::new();
    }
    let (color, specular) = look(p);
    let d = 2.0 * p.real("radius");
    vec![LocalShape::in_frame(ShapeKind::Sphere, "frame_a", Vec3::zeros(), Vec3::x(), d, d).colored(color, specular)]
}

const W_REL: VarSpec = VarSpec::vector(
    "w_rel",
    3,
    "rad/s",
    "Relative angular velocity of frame_b with respect to frame_a, resolved in frame_b",
);
static VARIABLES: [VarSpec; 9] = super::spec::concat(&[W_REL], orientation::VARIABLES);

#[derive(Debug)]
struct Spherical {
    rotation: Option<RotationCoordinates>,
}

fn build(p: &ParamSet) -> Result<Box<dyn Component>, Error> {
    Ok(Box::new(Spherical { rotation: orientation::coordinates(p)? }))
}

impl Component for Spherical {
    fn parts(&self) -> Vec<Part> {
        match self.rotation {
            Some(rot) => {
                let states = match rot {
                    RotationCoordinates::Quaternion { .. } => StateNames { q: &[("Q_hat", 4)], u: &[("w_rel", 3)] },
                    RotationCoordinates::Euler { .. } => StateNames { q: &[("phi", 3)], u: &[("phid", 3)] },
                };
                vec![Part::Joint { a: 0, b: 1, model: JointModel::Spherical(rot), states, flanges: None, iscut: false }]
            }
            None => vec![Part::Constraint {
                a: 0,
                b: 1,
                kind: crate::components::ConstraintKind::locking_axes(crate::components::RotationLock::Free, [true; 3]),
            }],
        }
    }

    fn variables(&self) -> Vec<VarSpec> {
        std::iter::once(W_REL).chain(orientation::variables(self.rotation)).collect()
    }

    fn evaluate(&self, ctx: &EvalContext, out: &mut Vec<f64>) {
        let (a, b) = (&ctx.frames[0], &ctx.frames[1]);
        let w_rel = b.w - b.rot * a.rot.tr_mul(&a.w);
        out.extend_from_slice(w_rel.as_slice());
        if let Some(rot) = self.rotation {
            orientation::evaluate(rot, &ctx.joints[0], 0, 0, out);
        }
    }
}
