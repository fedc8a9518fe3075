//! RollingWheelSetJoint and RollingWheelSet: two wheels on one axle,
//! rolling without slipping on the ground plane y = 0.
//!
//! The axle's middle (frame_middle) moves parallel to the plane at the
//! height of the wheels' radius: a prismatic joint along x, one along z
//! and a revolute about y (coordinates x, z, phi). A revolute about z at
//! each end of the axle (track / 2 along +z and -z) turns each wheel
//! (theta1, theta2), driven through axis1 and axis2 against support. Each
//! wheel carries an upright rolling constraint; the lateral one only on
//! wheel 1 (both would say the same). Five coordinates, three velocity
//! constraints: two degrees of freedom.
//!
//! With `iscut`, the axle's middle instead hangs on a free joint that is cut
//! first: for a second wheel set on a vehicle whose first set already
//! holds the body parallel to the plane.

use super::shapes::{between, LocalShape, ShapeKind};
use super::spec::{ComponentSpec, ConnectorSpec, ConnectorType, ParamSpec, ParamType, VarSpec};
use super::wheel_common::{non_negative, positive, wheel_inertia, wheel_shapes, ISCUT, RADIUS, RENDER, SPECULAR};
use super::{AxisFlanges, Component, ConstraintKind, EvalContext, ParamSet, Part, StateNames, WheelContact};
use crate::math::{RigidInertia, Transform, Vec3};
use crate::system::joint::{JointModel, RotationCoordinates};
use crate::Error;

const CONNECTORS: &[ConnectorSpec] = &[
    ConnectorSpec::frame(
        "frame_middle",
        "In the middle of the axle (z along the axle, y up); connect the vehicle's body here",
    ),
    ConnectorSpec::frame("frame1", "At the centre of wheel 1 (+z end of the axle), turning with it (z: spin axis)"),
    ConnectorSpec::frame("frame2", "At the centre of wheel 2 (-z end of the axle), turning with it (z: spin axis)"),
    ConnectorSpec::flange("axis1", ConnectorType::Spline, "Drives wheel 1 (against support)"),
    ConnectorSpec::flange("axis2", ConnectorType::Spline, "Drives wheel 2 (against support)"),
    ConnectorSpec::flange("support", ConnectorType::Spline, "Support of the wheels' drives, fixed in the axle"),
    ConnectorSpec::internal("ground", ConnectorType::Frame),
    ConnectorSpec::internal("slider_x", ConnectorType::Frame),
    ConnectorSpec::internal("slider_z", ConnectorType::Frame),
    ConnectorSpec::internal("hub1", ConnectorType::Frame),
    ConnectorSpec::internal("hub2", ConnectorType::Frame),
];

const TRACK: ParamSpec = ParamSpec::real("track", 1.0, "m", "Distance between the two wheels (the axle track)");

pub static JOINT: ComponentSpec = ComponentSpec {
    kind: "RollingWheelSetJoint",
    doc: "Ideal rolling wheel set without mass: two wheels on one axle rolling without slipping on the ground \
          plane y = 0. frame_middle moves parallel to the plane at the wheels' height (coordinates x, z and the \
          heading phi about y); each wheel turns on the axle (theta1, theta2), driven through axis1/axis2 \
          against support. Connect the wheels' bodies to frame1 and frame2 (see RollingWheelSet). With \
          iscut = true (a second wheel set on the same body), frame_middle follows the body instead.",
    params: &[
        RADIUS,
        TRACK,
        ParamSpec::derived("width_wheel", ParamType::Real, "0.15 * radius", "m", "Width of one wheel (animations)"),
        ISCUT,
        RENDER,
        ParamSpec::vector("color", &[0.0, 1.0, 1.0, 0.1], "", "Color of the wheels in animations"),
        SPECULAR,
    ],
    connectors: CONNECTORS,
    variables: VARIABLES,
    build: |p| build(p, false),
    shapes,
};

pub static SET: ComponentSpec = ComponentSpec {
    kind: "RollingWheelSet",
    doc: "Ideal rolling wheel set: RollingWheelSetJoint with a wheel body (mass m_wheel, inertia I_axis about the \
          spin axis and I_long across it) at each wheel's centre. Connect driving torques between axis1/axis2 \
          and support, and the vehicle's body to frame_middle.",
    params: &[
        RENDER,
        ParamSpec::vector("color", &[0.118, 0.118, 0.118, 1.0], "", "Color of the wheels in animations"),
        SPECULAR,
        RADIUS,
        ParamSpec::real("m_wheel", 1.0, "kg", "Mass of one wheel"),
        ParamSpec::real("I_axis", 1.0, "kg.m2", "Moment of inertia of one wheel about its axis"),
        ParamSpec::real("I_long", 1.0, "kg.m2", "Moment of inertia of one wheel perpendicular to its axis"),
        TRACK,
        ParamSpec::real("width_wheel", 0.01, "m", "Width of one wheel (animations)"),
        ISCUT,
    ],
    connectors: CONNECTORS,
    variables: VARIABLES,
    build: |p| build(p, true),
    shapes,
};

const VARIABLES: &[VarSpec] = &[
    VarSpec::scalar("x", "m", "x coordinate of the middle of the axle"),
    VarSpec::scalar("z", "m", "z coordinate of the middle of the axle"),
    VarSpec::scalar("phi", "rad", "Heading: rotation of the axle about the y axis"),
    VarSpec::scalar("theta1", "rad", "Angle of wheel 1"),
    VarSpec::scalar("theta2", "rad", "Angle of wheel 2"),
    VarSpec::scalar("der_theta1", "rad/s", "Derivative of theta1"),
    VarSpec::scalar("der_theta2", "rad/s", "Derivative of theta2"),
];

#[derive(Debug)]
struct WheelSet {
    radius: f64,
    track: f64,
    iscut: bool,
    wheel: Option<RigidInertia>,
}

fn build(p: &ParamSet, with_mass: bool) -> Result<Box<dyn Component>, Error> {
    let radius = positive(p, "radius", "the wheels' radius")?;
    let track = positive(p, "track", "the axle track")?;
    let wheel = if with_mass {
        non_negative(p, "width_wheel", "the wheels' width")?;
        Some(wheel_inertia(p, "m_wheel", "I_axis", "I_long")?)
    } else {
        None
    };
    Ok(Box::new(WheelSet { radius, track, iscut: p.boolean("iscut"), wheel }))
}

fn shapes(p: &ParamSet) -> Vec<LocalShape> {
    if !p.boolean("render") {
        return Vec::new();
    }
    let (color, specular) = super::shapes::look(p);
    let radius = p.real("radius");
    let width = p.real_opt("width_wheel").unwrap_or(0.15 * radius);
    let mut shapes = wheel_shapes("frame1", radius, width, color, specular);
    shapes.extend(wheel_shapes("frame2", radius, width, color, specular));
    shapes.push(between(ShapeKind::Cylinder, "frame1", "frame2", 0.1 * radius, 0.1 * radius).colored(color, specular));
    shapes
}

impl Component for WheelSet {
    fn parts(&self) -> Vec<Part> {
        // frame_middle 0, frame1 1, frame2 2, axis1 3, axis2 4, support 5,
        // ground 6, slider_x 7, slider_z 8, hub1 9, hub2 10.
        let joint = |a, b, model, states, flanges, iscut| Part::Joint { a, b, model, states, flanges, iscut };
        let mut parts = vec![Part::Ground { frame: 6, pose: Transform::translation(Vec3::new(0.0, self.radius, 0.0)) }];
        if self.iscut {
            let free = JointModel::Free(RotationCoordinates::Euler { sequence: [2, 1, 3] });
            let states = StateNames { q: &[("r_rel", 3), ("angles_rel", 3)], u: &[("v_rel", 3), ("w_rel", 3)] };
            parts.push(joint(6, 0, free, states, None, true));
            // The sliders' frames are unused: keep them with the ground.
            parts.push(Part::Rigid { a: 6, b: 7, pose: Transform::IDENTITY });
            parts.push(Part::Rigid { a: 6, b: 8, pose: Transform::IDENTITY });
        } else {
            let prismatic = |axis| JointModel::Prismatic { axis };
            parts.extend([
                joint(6, 7, prismatic(Vec3::x()), StateNames { q: &[("x", 1)], u: &[("der_x", 1)] }, None, false),
                joint(7, 8, prismatic(Vec3::z()), StateNames { q: &[("z", 1)], u: &[("der_z", 1)] }, None, false),
                joint(
                    8,
                    0,
                    JointModel::Revolute { axis: Vec3::y() },
                    StateNames { q: &[("phi", 1)], u: &[("der_phi", 1)] },
                    None,
                    false,
                ),
            ]);
        }
        let spin = JointModel::Revolute { axis: Vec3::z() };
        let half = Vec3::new(0.0, 0.0, self.track / 2.0);
        let wheel =
            |lateral| ConstraintKind::Wheel { radius: self.radius, contact: WheelContact::Vertical { lateral } };
        parts.extend([
            Part::Rigid { a: 0, b: 9, pose: Transform::translation(half) },
            Part::Rigid { a: 0, b: 10, pose: Transform::translation(-half) },
            joint(
                9,
                1,
                spin,
                StateNames { q: &[("theta1", 1)], u: &[("der_theta1", 1)] },
                Some(AxisFlanges { axis: 3, support: 5 }),
                false,
            ),
            joint(
                10,
                2,
                spin,
                StateNames { q: &[("theta2", 1)], u: &[("der_theta2", 1)] },
                Some(AxisFlanges { axis: 4, support: 5 }),
                false,
            ),
            Part::Constraint { a: 6, b: 1, kind: wheel(true) },
            Part::Constraint { a: 6, b: 2, kind: wheel(false) },
        ]);
        if let Some(inertia) = self.wheel {
            parts.push(Part::Mass { frame: 1, inertia, point_gravity: false });
            parts.push(Part::Mass { frame: 2, inertia, point_gravity: false });
        }
        parts
    }

    fn variables(&self) -> Vec<VarSpec> {
        VARIABLES.to_vec()
    }

    fn evaluate(&self, ctx: &EvalContext, out: &mut Vec<f64>) {
        let j = ctx.joints;
        let (wheels, (x, z, phi)) = if self.iscut {
            // The middle follows the body: its heading from its orientation (in (-pi, pi]).
            let m = &ctx.frames[0];
            (&j[1..3], (m.r_0[0], m.r_0[2], m.rot[(2, 0)].atan2(m.rot[(0, 0)])))
        } else {
            (&j[3..5], (j[0].q[0], j[1].q[0], j[2].q[0]))
        };
        out.extend_from_slice(&[x, z, phi, wheels[0].q[0], wheels[1].q[0], wheels[0].u[0], wheels[1].u[0]]);
    }
}
