//! RollingConstraintVerticalWheel: an upright wheel rolls without slipping
//! on the ground plane y = 0 (velocity constraints only).

use super::spec::{ComponentSpec, ConnectorSpec, ConnectorType, ParamSpec, VarSpec};
use super::wheel_common::positive;
use super::{Component, ConstraintKind, EvalContext, ParamSet, Part, WheelContact};
use crate::math::wheel::contact_frame;
use crate::math::{Transform, Vec3};
use crate::Error;

pub static SPEC: ComponentSpec = ComponentSpec {
    kind: "RollingConstraintVerticalWheel",
    doc: "Rolling constraint for a wheel held upright on the ground plane y = 0 (the x-z plane): frame_a is at the \
          wheel's centre and turns with it, its z axis the spin axis; the contact point is radius straight below \
          it. The point of the wheel at the contact does not slip along the wheel, and with \
          lateral_sliding_constraint not across it either (leave it off on one wheel of an axle, which would \
          otherwise be constrained twice). Constraints on velocities: the wheel must be held upright by its \
          joints.",
    params: &[
        ParamSpec::boolean(
            "lateral_sliding_constraint",
            true,
            "Also no sliding across the wheel (false: the lateral force is zero)",
        ),
        ParamSpec::real("radius", 0.3, "m", "Radius of the wheel"),
    ],
    connectors: &[
        ConnectorSpec::frame("frame_a", "At the wheel's centre, turning with it (z: spin axis)"),
        ConnectorSpec::internal("ground", ConnectorType::Frame),
    ],
    variables: VARIABLES,
    build,
    shapes: super::shapes::none,
};

pub(crate) const VARIABLES: &[VarSpec] = &[
    VarSpec::vector("f_wheel_0", 3, "N", "Contact force acting on the wheel, resolved in the world"),
    VarSpec::scalar("f_lat", "N", "Contact force acting on the wheel in the lateral direction"),
    VarSpec::scalar("f_long", "N", "Contact force acting on the wheel in the longitudinal direction"),
    VarSpec::vector("e_axis_0", 3, "", "Unit vector along the wheel's axis, resolved in the world"),
    VarSpec::vector("e_lat_0", 3, "", "Unit vector in the lateral direction at the contact point, in the world"),
    VarSpec::vector("e_long_0", 3, "", "Unit vector in the longitudinal direction at the contact point, in the world"),
    VarSpec::vector("v_0", 3, "m/s", "Velocity of the wheel's centre, resolved in the world"),
    VarSpec::vector("w_0", 3, "rad/s", "Angular velocity of the wheel, resolved in the world"),
    VarSpec::vector("v_contact_0", 3, "m/s", "Velocity of the wheel's point at the contact, resolved in the world"),
];

#[derive(Debug)]
struct VerticalWheel {
    radius: f64,
    lateral: bool,
}

fn build(p: &ParamSet) -> Result<Box<dyn Component>, Error> {
    let radius = positive(p, "radius", "the wheel's radius")?;
    Ok(Box::new(VerticalWheel { radius, lateral: p.boolean("lateral_sliding_constraint") }))
}

impl Component for VerticalWheel {
    fn parts(&self) -> Vec<Part> {
        let kind =
            ConstraintKind::Wheel { radius: self.radius, contact: WheelContact::Vertical { lateral: self.lateral } };
        vec![Part::Ground { frame: 1, pose: Transform::IDENTITY }, Part::Constraint { a: 1, b: 0, kind }]
    }

    fn variables(&self) -> Vec<VarSpec> {
        VARIABLES.to_vec()
    }

    fn evaluate(&self, ctx: &EvalContext, out: &mut Vec<f64>) {
        evaluate_upright(&ctx.frames[0], self.radius, out);
    }
}

/// The variables of an upright wheel's contact at the wheel frame `f`.
pub(crate) fn evaluate_upright(f: &super::FrameState, radius: f64, out: &mut Vec<f64>) {
    let w_0 = f.rot.tr_mul(&f.w);
    let c = contact_frame(&f.rot, &w_0, radius, &Vec3::y(), true);
    // The cut force on this component at frame_a is the reaction of the force on the wheel.
    let f_wheel_0 = -f.rot.tr_mul(&f.f);
    out.extend_from_slice(f_wheel_0.as_slice());
    out.push(f_wheel_0.dot(&c.e_lat));
    out.push(f_wheel_0.dot(&c.e_long));
    for v in [c.e_axis, c.e_lat, c.e_long, f.v_0, w_0, f.v_0 + w_0.cross(&c.delta)] {
        out.extend_from_slice(v.as_slice());
    }
}
