//! PlanarMechanics.Body and BodyShape: masses that move in the plane.
//!
//! A planar body has its mass and its inertia about z. Where no joint from
//! the ground places it, it is free in the plane: its `r`, `phi`, `v` and
//! `w` become states (a planar joint from the world, x and y along the
//! world's axes, then the turn about z).

use super::super::shapes::{look, LocalShape, ShapeKind};
use super::super::spec::{ComponentSpec, ParamSpec, ParamType, VarSpec};
use super::super::{Component, EvalContext, FrameState, Part, StateNames};
use super::{color, in_plane, lift, FRAME_A, FRAME_B, NORMAL, RENDER, SPECULAR, Z_POSITION};
use crate::math::rotation::planar_angle;
use crate::math::{Mat3, RigidInertia, Transform, Vec3};
use crate::system::JointModel;

const STATES: StateNames = StateNames { q: &[("r", 2), ("phi", 1)], u: &[("v", 2), ("w", 1)] };

const VARIABLES: &[VarSpec] = &[
    VarSpec::vector("f", 2, "N", "Force on the body at frame_a, world coordinates"),
    VarSpec::vector("r", 2, "m", "Position of frame_a, world coordinates"),
    VarSpec::vector("v", 2, "m/s", "Velocity of frame_a, world coordinates"),
    VarSpec::vector("a", 2, "m/s2", "Acceleration of frame_a, world coordinates"),
    VarSpec::scalar("phi", "rad", "Angle of frame_a"),
    VarSpec::scalar("w", "rad/s", "Angular velocity (= der(phi))"),
    VarSpec::scalar("alpha", "rad/s2", "Angular acceleration (= der(w))"),
    VarSpec::scalar("KE", "J", "Kinetic energy"),
    VarSpec::scalar("PE", "J", "Potential energy of gravity (zero at the world's origin)"),
];

const STATE_PRIORITIES: [ParamSpec; 2] = [
    ParamSpec::integer("statePriority", 2.0, "State priority (kept for compatibility)"),
    ParamSpec::integer("linearStatePriority", 1.0, "State priority of r and v (kept for compatibility)"),
];

pub static BODY: ComponentSpec = ComponentSpec {
    kind: "PlanarMechanics.Body",
    doc: "A planar body: mass m at frame_a's origin and inertia I about it. Gravity of the planar World acts on \
          it. Free in the plane where no joint holds it (then r, phi, v and w are its states).",
    params: &[
        ParamSpec::required("m", ParamType::Real, "kg", "Mass"),
        ParamSpec::required("I", ParamType::Real, "kg.m2", "Moment of inertia about z at frame_a's origin"),
        ParamSpec::world("radius", ParamType::Real, "default_body_diameter", 0.5, "m", "Radius of the sphere drawn"),
        Z_POSITION,
        RENDER,
        color("default_body_color"),
        SPECULAR,
        STATE_PRIORITIES[0],
        STATE_PRIORITIES[1],
    ],
    connectors: &[FRAME_A],
    variables: VARIABLES,
    build: |p| {
        let (m, i) = (p.non_negative("m", true)?, p.non_negative("I", true)?);
        Ok(Box::new(PlanarBody { m, i, r_cm: Vec3::zeros(), frame_b: None }))
    },
    shapes: |p| {
        if !p.boolean("render") {
            return Vec::new();
        }
        let (color, specular) = look(p);
        let d = 2.0 * p.real("radius");
        vec![LocalShape::in_frame(ShapeKind::Sphere, "frame_a", lift(p), Vec3::zeros(), d, d).colored(color, specular)]
    },
};

pub static BODY_SHAPE: ComponentSpec = ComponentSpec {
    kind: "PlanarMechanics.BodyShape",
    doc: "A planar rod with a body: frame_b at r from frame_a (in frame_a), mass m at r_cm with inertia I about \
          its centre of mass. Free in the plane where no joint holds it.",
    params: &[
        ParamSpec::vector("r", &[1.0, 0.0], "m", "From frame_a to frame_b, resolved in frame_a"),
        ParamSpec::derived(
            "r_cm",
            ParamType::Vector(2),
            "r / 2",
            "m",
            "From frame_a to the centre of mass, in frame_a",
        ),
        ParamSpec::real("m", 1.0, "kg", "Mass"),
        ParamSpec::real("I", 0.1, "kg.m2", "Moment of inertia about z at the centre of mass"),
        ParamSpec::world("radius", ParamType::Real, "default_body_diameter", 0.5, "m", "Radius of the rod drawn"),
        Z_POSITION,
        RENDER,
        color("default_body_color"),
        SPECULAR,
    ],
    connectors: &[FRAME_A, FRAME_B],
    variables: VARIABLES,
    build: |p| {
        let r = in_plane(p, "r");
        let r_cm = p.vector_opt("r_cm").map_or(r / 2.0, |v| Vec3::new(v[0], v[1], 0.0));
        let (m, i) = (p.non_negative("m", true)?, p.non_negative("I", true)?);
        Ok(Box::new(PlanarBody { m, i, r_cm, frame_b: Some(r) }))
    },
    shapes: |p| {
        if !p.boolean("render") {
            return Vec::new();
        }
        let (color, specular) = look(p);
        let r = in_plane(p, "r");
        let d = p.real("radius");
        vec![LocalShape::in_frame(ShapeKind::Cylinder, "frame_a", lift(p), r, d, d).colored(color, specular)]
    },
};

#[derive(Debug)]
struct PlanarBody {
    m: f64,
    /// About z, at the centre of mass.
    i: f64,
    /// The centre of mass in frame_a.
    r_cm: Vec3,
    frame_b: Option<Vec3>,
}

/// A world vector's in-plane components.
fn xy(v: Vec3) -> [f64; 2] {
    [v.x, v.y]
}

/// A planar frame's angle: from the body's own planar joint where it has
/// one (it then keeps counting past a half turn), else from its rotation.
pub(crate) fn frame_angle(frame: &FrameState, ctx: &EvalContext) -> f64 {
    ctx.joints.first().filter(|j| j.q.len() == 3).map_or_else(|| planar_angle(&frame.rot), |j| j.q[2])
}

impl Component for PlanarBody {
    fn parts(&self) -> Vec<Part> {
        let inertia = Mat3::from_diagonal(&Vec3::new(0.0, 0.0, self.i));
        let mut parts = vec![
            Part::Owner {
                frame: 0,
                model: JointModel::Planar { n: NORMAL, n_x: Vec3::x(), n_y: Vec3::y() },
                states: STATES,
                fallback: true,
            },
            Part::Mass { frame: 0, inertia: RigidInertia::from_com(self.m, self.r_cm, inertia), point_gravity: false },
        ];
        if let Some(r) = self.frame_b {
            parts.push(Part::Rigid { a: 0, b: 1, pose: Transform::translation(r) });
        }
        parts
    }

    fn variables(&self) -> Vec<VarSpec> {
        VARIABLES.to_vec()
    }

    fn evaluate(&self, ctx: &EvalContext, out: &mut Vec<f64>) {
        let a = &ctx.frames[0];
        let w = a.w.z;
        let r_cm = a.rot.tr_mul(&self.r_cm);
        let v_cm = a.v_0 + NORMAL.cross(&r_cm) * w;
        // Frames and gravity in the plane's coordinates.
        let g = ctx.world.plane.rot * ctx.world.uniform_gravity();
        out.extend(xy(a.rot.tr_mul(&a.f)));
        out.extend(xy(a.r_0));
        out.extend(xy(a.v_0));
        out.extend(xy(a.a_0));
        out.extend([frame_angle(a, ctx), w, a.z.z]);
        out.push(0.5 * self.m * v_cm.norm_squared() + 0.5 * self.i * w * w);
        out.push(-self.m * g.dot(&(a.r_0 + r_cm)));
    }
}
