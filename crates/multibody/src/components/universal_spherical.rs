//! UniversalSpherical: a rod of fixed length with a universal joint at frame_a
//! and a ball joint at frame_b.
//!
//! It is its parts: a universal joint from frame_a to the rod frame
//! frame_ia (axis 1 `n1_a`, axis 2 across `n1_a` and the rod, so the rod
//! cannot spin about itself), the rod, and a ball joint at its tip that
//! closes the loop through frame_b (three constraint rows). A body on
//! frame_ia rides on the rod; left unconnected, the rod is massless.

use super::rod::{rod_length, rod_shapes};
use super::spec::{ComponentSpec, ConnectorSpec, ConnectorType, ParamSpec};
use super::{Component, ConstraintKind, ParamSet, Part, RotationLock, StateNames};
use crate::math::{Transform, Vec3};
use crate::system::JointModel;
use crate::Error;

pub static SPEC: ComponentSpec = ComponentSpec {
    kind: "UniversalSpherical",
    doc: "Joint assembly: a universal joint at frame_a and a spherical joint at frame_b, joined by a rod \
          rRod_ia (resolved in the rod frame frame_ia, which sits at frame_a's origin). The universal joint turns \
          about n1_a and about the axis across n1_a and the rod; a body on frame_ia gives the rod mass.",
    params: &[
        ParamSpec::boolean("kinematic_constraint", true, "Kept for compatibility"),
        ParamSpec::boolean("constraint_residue_external", false, "Kept for compatibility"),
        ParamSpec::boolean("render", true, "Render the rod in animations"),
        ParamSpec::vector("color", &[0.0, 0.1, 1.0, 0.9], "", "Colour (RGBA)"),
        ParamSpec::real("specular_coefficient", 1.5, "", "Reflection of light in animations"),
        ParamSpec::vector("n1_a", &[0.0, 0.0, 1.0], "", "Axis 1 of the universal joint, resolved in frame_a"),
        ParamSpec::vector(
            "rRod_ia",
            &[1.0, 0.0, 0.0],
            "m",
            "Vector from frame_a to frame_b, resolved in frame_ia: its length is the rod length",
        ),
        ParamSpec::real("rod_radius", 0.05, "m", "Radius of the rod in animations"),
        ParamSpec::real("sphere_diameter", 0.1, "m", "Diameter of the spheres in animations"),
    ],
    connectors: &[
        ConnectorSpec::frame("frame_a", "The universal end"),
        ConnectorSpec::frame("frame_b", "The spherical end"),
        ConnectorSpec::frame("frame_ia", "The rod frame, at frame_a's origin"),
        ConnectorSpec::internal("rod_tip", ConnectorType::Frame),
    ],
    variables: &[],
    build,
    shapes: |p| rod_shapes(p, 2.0 * p.real("rod_radius")),
};

fn build(p: &ParamSet) -> Result<Box<dyn Component>, Error> {
    rod_length(p, "rRod_ia")?;
    let n1 = p.direction("n1_a")?;
    let rod = p.vec3("rRod_ia");
    let across = n1.cross(&rod);
    if across.norm() < 1e-10 * rod.norm() {
        return Err(p.invalid("n1_a", "the universal joint's first axis must not lie along the rod"));
    }
    Ok(Box::new(UniversalSpherical { n1, n2: across.normalize(), rod }))
}

#[derive(Debug)]
struct UniversalSpherical {
    n1: Vec3,
    n2: Vec3,
    rod: Vec3,
}

impl Component for UniversalSpherical {
    fn parts(&self) -> Vec<Part> {
        // frame_a 0, frame_b 1, frame_ia 2, rod_tip 3.
        vec![
            Part::Joint {
                a: 0,
                b: 2,
                model: JointModel::Universal { n_a: self.n1, n_b: self.n2 },
                states: StateNames { q: &[("phi_a", 1), ("phi_b", 1)], u: &[("w_a", 1), ("w_b", 1)] },
                flanges: None,
                iscut: false,
            },
            Part::Rigid { a: 2, b: 3, pose: Transform::translation(self.rod) },
            Part::Constraint { a: 3, b: 1, kind: ConstraintKind::locking_axes(RotationLock::Free, [true; 3]) },
        ]
    }
}
