//! PlanarMechanics.Revolute and Prismatic: the plane's joints.

use super::super::coordinate_joint::{CoordinateJoint, FLANGES};
use super::super::shapes::{joint_cylinder, look, LocalShape, ShapeKind};
use super::super::spec::{ComponentSpec, ConnectorSpec, ConnectorType, ParamSpec, ParamType, VarSpec};
use super::super::{Component, EvalContext, ParamSet, Part, StateNames};
use super::{color, in_plane, lift, FRAME_A, FRAME_B, NORMAL, RENDER, SPECULAR, Z_POSITION};
use crate::math::Vec3;
use crate::system::JointModel;
use crate::Error;

const ISCUT: ParamSpec = ParamSpec::boolean("iscut", false, "Prefer this joint as the cut of a kinematic loop");

const REVOLUTE_VARIABLES: &[VarSpec] = &[
    VarSpec::scalar("phi", "rad", "Angle from frame_a to frame_b"),
    VarSpec::scalar("w", "rad/s", "Relative angular velocity (= der(phi))"),
    VarSpec::scalar("alpha", "rad/s2", "Relative angular acceleration (= der(w))"),
    VarSpec::scalar("tau", "N.m", "Torque of the elements on flange_a, driving the joint"),
];

pub static REVOLUTE: ComponentSpec = ComponentSpec {
    kind: "PlanarMechanics.Revolute",
    doc: "A planar revolute joint: frame_b turns by phi from frame_a about z, at the same point. Rotational \
          elements on flange_a drive it (their support is frame_a); left unconnected, it turns freely.",
    params: &[
        ISCUT,
        ParamSpec::integer("statePriority", 10.0, "State priority of phi and w (kept for compatibility)"),
        ParamSpec::world("radius", ParamType::Real, "default_joint_width", 1.0, "m", "Radius of the cylinder drawn"),
        ParamSpec::world("cylinder_length", ParamType::Real, "default_joint_length", 1.0, "m", "Its length"),
        Z_POSITION,
        RENDER,
        color("default_joint_color"),
        SPECULAR,
    ],
    connectors: &[
        FRAME_A,
        FRAME_B,
        ConnectorSpec::flange("flange_a", ConnectorType::Spline, "Turns with phi; what acts on it drives the joint"),
        ConnectorSpec::internal("support", ConnectorType::Spline),
    ],
    variables: REVOLUTE_VARIABLES,
    build: |p| {
        Ok(Box::new(CoordinateJoint {
            model: JointModel::Revolute { axis: NORMAL },
            states: StateNames { q: &[("phi", 1)], u: &[("w", 1)] },
            variables: REVOLUTE_VARIABLES,
            flanges: Some(FLANGES),
            iscut: p.boolean("iscut"),
        }))
    },
    shapes: |p| {
        let mut shapes = joint_cylinder(p, "frame_a", NORMAL, p.real("cylinder_length"), 2.0 * p.real("radius"));
        for s in &mut shapes {
            if let super::super::shapes::Placement::InFrame { origin, .. } = &mut s.placement {
                *origin += lift(p);
            }
        }
        shapes
    },
};

const PRISMATIC_VARIABLES: &[VarSpec] = &[
    VarSpec::scalar("s", "m", "Distance from frame_a to frame_b along the axis"),
    VarSpec::scalar("v", "m/s", "Relative speed (= der(s))"),
    VarSpec::scalar("a", "m/s2", "Relative acceleration (= der(v))"),
    VarSpec::scalar("f", "N", "Force along the axis at frame_a (what drives the joint through axis)"),
    VarSpec::vector("e0", 2, "", "The unit axis, world coordinates"),
    VarSpec::vector("r0", 2, "m", "From frame_a to frame_b, world coordinates"),
];

pub static PRISMATIC: ComponentSpec = ComponentSpec {
    kind: "PlanarMechanics.Prismatic",
    doc: "A planar prismatic joint: frame_b slides by s along r (resolved in frame_a, so it turns with frame_a), \
          with frame_a's angle. Translational elements between axis (which moves with s) and support (fixed \
          to frame_a) drive it; left unconnected, it slides freely (f = 0).",
    params: &[
        ISCUT,
        ParamSpec::vector("r", &[1.0, 0.0], "", "Direction of sliding, resolved in frame_a"),
        ParamSpec::boolean("axisflange", false, "Use axis and support (they are always available here)"),
        ParamSpec::integer("statePriority", 2.0, "State priority of s and v (kept for compatibility)"),
        ParamSpec::world("box_width", ParamType::Real, "default_joint_width", 1.0, "m", "Width of the box drawn"),
        ParamSpec::world("box_height", ParamType::Real, "default_joint_width", 1.0, "m", "Height of the box drawn"),
        Z_POSITION,
        RENDER,
        color("default_prismatic_color"),
        SPECULAR,
    ],
    connectors: &[
        FRAME_A,
        FRAME_B,
        ConnectorSpec::flange("axis", ConnectorType::Flange, "Moves with s; what acts on it drives the joint"),
        ConnectorSpec::flange("support", ConnectorType::Flange, "Fixed to frame_a (the reaction side)"),
    ],
    variables: PRISMATIC_VARIABLES,
    build: |p| Ok(Box::new(PlanarPrismatic { axis: direction(p)?, iscut: p.boolean("iscut") })),
    shapes: prismatic_shapes,
};

fn prismatic_shapes(p: &ParamSet) -> Vec<LocalShape> {
    if !p.boolean("render") {
        return Vec::new();
    }
    let (color, specular) = look(p);
    let Ok(axis) = direction(p) else { return Vec::new() };
    let length = p.real_opt("box_width").unwrap_or(0.05) * 4.0;
    vec![LocalShape::in_frame(
        ShapeKind::Box,
        "frame_a",
        lift(p),
        axis * length,
        p.real("box_width"),
        p.real("box_height"),
    )
    .colored(color, specular)]
}

fn direction(p: &ParamSet) -> Result<Vec3, Error> {
    let r = in_plane(p, "r");
    if r.norm() == 0.0 {
        return Err(p.invalid("r", "the direction of sliding must not be zero"));
    }
    Ok(r.normalize())
}

#[derive(Debug)]
struct PlanarPrismatic {
    axis: Vec3,
    iscut: bool,
}

impl Component for PlanarPrismatic {
    fn parts(&self) -> Vec<Part> {
        vec![Part::Joint {
            a: 0,
            b: 1,
            model: JointModel::Prismatic { axis: self.axis },
            states: StateNames { q: &[("s", 1)], u: &[("v", 1)] },
            flanges: Some(FLANGES),
            iscut: self.iscut,
        }]
    }

    fn variables(&self) -> Vec<VarSpec> {
        PRISMATIC_VARIABLES.to_vec()
    }

    fn evaluate(&self, ctx: &EvalContext, out: &mut Vec<f64>) {
        let (a, b, j) = (&ctx.frames[0], &ctx.frames[1], &ctx.joints[0]);
        let e0 = a.rot.tr_mul(&self.axis);
        let r0 = b.r_0 - a.r_0;
        out.extend([j.q[0], j.u[0], j.udot[0], e0.dot(&a.rot.tr_mul(&a.f)), e0.x, e0.y, r0.x, r0.y]);
    }
}
