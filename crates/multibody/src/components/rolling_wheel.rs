//! RollingWheelJoint and RollingWheel: a wheel that may lean, rolling
//! without slipping on the ground plane y = 0.
//!
//! The wheel's frame hangs on a free joint from the world whose coordinates
//! are the library's states: the centre's position x, y, z and Cardan
//! angles `angles` (their rates `der_angles`; the centre's velocity `v_0`).
//! A contact constraint keeps the lowest point of the rim on the plane (on
//! positions: y follows from the lean) and stops it slipping along or
//! across the path (on velocities). Six coordinates, one constraint on
//! positions and two more on velocities: five positional and three velocity
//! degrees of freedom.

use super::shapes::LocalShape;
use super::spec::{ComponentSpec, ConnectorSpec, ConnectorType, VarSpec};
use super::wheel_common::{
    positive, road, wheel_inertia, wheel_shapes, COLOR, ISCUT, I_AXIS, I_LONG, M, RADIUS, RENDER, SEQUENCE, SPECULAR,
    SURFACE, WIDTH,
};
use super::{Component, ConstraintKind, EvalContext, ParamSet, Part, StateNames, WheelContact};
use crate::math::surface::Surface;
use crate::math::wheel::{road_contact, RoadContact};
use crate::math::{RigidInertia, Transform, Vec3};
use crate::system::joint::{JointModel, RotationCoordinates};
use crate::Error;

const CONNECTORS: &[ConnectorSpec] = &[
    ConnectorSpec::frame("frame_a", "At the wheel's centre, turning with it (z: spin axis)"),
    ConnectorSpec::internal("ground", ConnectorType::Frame),
];

pub static JOINT: ComponentSpec = ComponentSpec {
    kind: "RollingWheelJoint",
    doc: "Joint without mass for an ideal rolling wheel on the ground plane y = 0: the wheel may lean but not \
          slip, and it cannot lift off (one constraint on positions, two on velocities). frame_a is at the \
          wheel's centre and turns with it; its z axis is the spin axis. Connect a body with the wheel's mass \
          to frame_a (see RollingWheel). States: x, y, z, angles (Cardan angles of sequence), v_0, der_angles.",
    params: &[SEQUENCE, ISCUT, SURFACE, RENDER, COLOR, SPECULAR, RADIUS, WIDTH],
    connectors: CONNECTORS,
    variables: VARIABLES,
    build: |p| build(p, false),
    shapes,
};

pub static WHEEL: ComponentSpec = ComponentSpec {
    kind: "RollingWheel",
    doc: "Ideal rolling wheel with mass on the ground plane y = 0 (5 positional and 3 velocity degrees of \
          freedom): RollingWheelJoint with a body of mass m and a diagonal inertia (I_axis about the spin axis, \
          z of frame_a; I_long across it) at the centre. To mount it on an axle, connect frame_a to a Revolute \
          about the axle.",
    params: &[SEQUENCE, ISCUT, SURFACE, RENDER, COLOR, SPECULAR, RADIUS, M, I_AXIS, I_LONG, WIDTH],
    connectors: CONNECTORS,
    variables: VARIABLES,
    build: |p| build(p, true),
    shapes,
};

pub(crate) const VARIABLES: &[VarSpec] = &[
    VarSpec::scalar("x", "m", "x-position of the wheel's centre"),
    VarSpec::scalar("y", "m", "y-position of the wheel's centre"),
    VarSpec::scalar("z", "m", "z-position of the wheel's centre"),
    VarSpec::vector("angles", 3, "rad", "Cardan angles (of sequence) that rotate the world into frame_a"),
    VarSpec::vector("der_angles", 3, "rad/s", "Derivatives of angles"),
    VarSpec::vector("r_road_0", 3, "m", "Position of the contact point on the road, resolved in the world"),
    VarSpec::vector("f_wheel_0", 3, "N", "Contact force on the wheel, resolved in the world"),
    VarSpec::scalar("f_n", "N", "Contact force on the wheel in the normal direction"),
    VarSpec::scalar("f_lat", "N", "Contact force on the wheel in the lateral direction"),
    VarSpec::scalar("f_long", "N", "Contact force on the wheel in the longitudinal direction"),
    VarSpec::vector("e_axis_0", 3, "", "Unit vector along the wheel's axis, resolved in the world"),
    VarSpec::vector("delta_0", 3, "m", "From the wheel's centre to the contact point, resolved in the world"),
    VarSpec::vector("e_n_0", 3, "", "Unit normal of the road at the contact point, resolved in the world"),
    VarSpec::vector("e_lat_0", 3, "", "Unit vector in the lateral direction at the contact point, in the world"),
    VarSpec::vector("e_long_0", 3, "", "Unit vector in the longitudinal direction at the contact point, in the world"),
    VarSpec::vector("v_0", 3, "m/s", "Velocity of the wheel's centre, resolved in the world"),
    VarSpec::vector("w_0", 3, "rad/s", "Angular velocity of the wheel, resolved in the world"),
    VarSpec::vector("v_contact_0", 3, "m/s", "Velocity of the wheel's point at the contact, resolved in the world"),
];

#[derive(Debug)]
struct Wheel {
    radius: f64,
    sequence: [usize; 3],
    iscut: bool,
    mass: Option<RigidInertia>,
    /// The road, if not the plane y = 0.
    surface: Option<Surface>,
}

fn build(p: &ParamSet, with_mass: bool) -> Result<Box<dyn Component>, Error> {
    let radius = positive(p, "radius", "the wheel's radius")?;
    let mass = if with_mass { Some(wheel_inertia(p, "m", "I_axis", "I_long")?) } else { None };
    let surface = road(p)?;
    Ok(Box::new(Wheel { radius, sequence: p.sequence("sequence")?, iscut: p.boolean("iscut"), mass, surface }))
}

pub(crate) fn shapes(p: &ParamSet) -> Vec<LocalShape> {
    if !p.boolean("render") {
        return Vec::new();
    }
    let (color, specular) = super::shapes::look(p);
    wheel_shapes("frame_a", p.real("radius"), p.real("width"), color, specular)
}

/// The wheel's own joint: a free joint from the world with the library's state names.
pub(crate) fn free_joint(sequence: [usize; 3], iscut: bool) -> Part {
    Part::Joint {
        a: 1,
        b: 0,
        model: JointModel::Free(RotationCoordinates::Euler { sequence }),
        states: StateNames { q: &[("x", 1), ("y", 1), ("z", 1), ("angles", 3)], u: &[("v_0", 3), ("der_angles", 3)] },
        flanges: None,
        iscut,
    }
}

impl Component for Wheel {
    fn parts(&self) -> Vec<Part> {
        let mut parts = vec![
            Part::Ground { frame: 1, pose: Transform::IDENTITY },
            free_joint(self.sequence, self.iscut),
            Part::Constraint {
                a: 1,
                b: 0,
                kind: ConstraintKind::Wheel {
                    radius: self.radius,
                    contact: WheelContact::Rolling { road: self.surface.as_ref().map(|_| 0) },
                },
            },
        ];
        if let Some(inertia) = self.mass {
            parts.push(Part::Mass { frame: 0, inertia, point_gravity: false });
        }
        if let Some(surface) = self.surface.clone() {
            parts.push(Part::Road { surface: Box::new(surface) });
        }
        parts
    }

    /// The library's start: the centre at the height of the radius.
    fn default_starts(&self) -> Vec<(&'static str, Vec<f64>)> {
        vec![("y", vec![self.radius])]
    }

    fn variables(&self) -> Vec<VarSpec> {
        VARIABLES.to_vec()
    }

    fn evaluate(&self, ctx: &EvalContext, out: &mut Vec<f64>) {
        let f = &ctx.frames[0];
        let j = &ctx.joints[0];
        out.extend_from_slice(f.r_0.as_slice());
        out.extend_from_slice(&j.q[3..6]);
        out.extend_from_slice(&j.u[3..6]);
        let f_wheel_0 = contact_force(ctx, f, &self.mass);
        let w_0 = f.rot.tr_mul(&f.w);
        let road = road_contact(&f.rot, &w_0, &f.r_0, &f.v_0, self.radius, self.surface.as_ref());
        evaluate_contact(f, &road, 1.0, f_wheel_0, out);
    }
}

/// The force of the ground on the wheel (world) at frame `f`. frame_a's
/// cut force is what the rest of the model applies through it; with the
/// wheel's own body in the component, the contact force is what moves that
/// body (centre of mass at frame_a) less what comes through frame_a.
pub(crate) fn contact_force(ctx: &EvalContext, f: &super::FrameState, mass: &Option<RigidInertia>) -> Vec3 {
    let through_frame = -f.rot.tr_mul(&f.f);
    match mass {
        Some(body) => (f.a_0 - ctx.world.gravity(&f.r_0, false)) * body.mass + through_frame,
        None => through_frame,
    }
}

/// The contact variables from `r_road_0` on (see VARIABLES) of a wheel at
/// frame `f` touching the road at `road`; `lat_sign` turns the lateral
/// direction round (the slipping wheels' convention).
pub(crate) fn evaluate_contact(
    f: &super::FrameState,
    road: &RoadContact,
    lat_sign: f64,
    f_wheel_0: Vec3,
    out: &mut Vec<f64>,
) {
    let w_0 = f.rot.tr_mul(&f.w);
    let (c, e_n) = (&road.frame, &road.e_n);
    let e_lat = c.e_lat * lat_sign;
    out.extend_from_slice(road.r_road.as_slice());
    out.extend_from_slice(f_wheel_0.as_slice());
    out.extend_from_slice(&[f_wheel_0.dot(e_n), f_wheel_0.dot(&e_lat), f_wheel_0.dot(&c.e_long)]);
    for v in [c.e_axis, c.delta, *e_n, e_lat, c.e_long, f.v_0, w_0, f.v_0 + w_0.cross(&c.delta)] {
        out.extend_from_slice(v.as_slice());
    }
}
