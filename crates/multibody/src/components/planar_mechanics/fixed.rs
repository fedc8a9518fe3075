//! PlanarMechanics.Fixed, FixedTranslation and FixedRotation: planar frames
//! held in the world or to each other.

use super::super::shapes::{look, LocalShape, ShapeKind};
use super::super::spec::{ComponentSpec, ParamSpec, ParamType, VarSpec};
use super::super::{Component, EvalContext, ParamSet, Part};
use super::{color, in_plane, lift, planar_pose, FRAME_A, FRAME_B, RENDER, SPECULAR, Z_POSITION};
use crate::math::rotation::planar_angle;
use crate::math::{Transform, Vec3};

pub static FIXED: ComponentSpec = ComponentSpec {
    kind: "PlanarMechanics.Fixed",
    doc: "frame_b is fixed in the world at r, turned by phi.",
    params: &[
        ParamSpec::vector("r", &[0.0, 0.0], "m", "Position of frame_b, world coordinates"),
        ParamSpec::real("phi", 0.0, "rad", "Angle of frame_b"),
    ],
    connectors: &[super::super::spec::ConnectorSpec::frame_2d("frame_b", "The fixed frame")],
    variables: &[],
    build: |p| Ok(Box::new(Ground(planar_pose(in_plane(p, "r"), p.real("phi"))))),
    shapes: super::super::shapes::none,
};

#[derive(Debug)]
struct Ground(Transform);

impl Component for Ground {
    fn parts(&self) -> Vec<Part> {
        vec![Part::Ground { frame: 0, pose: self.0 }]
    }
}

const VARIABLES: &[VarSpec] = &[
    VarSpec::scalar("phi", "rad", "Angle of frame_a"),
    VarSpec::scalar("w", "rad/s", "Angular velocity"),
    VarSpec::vector("r0", 2, "m", "From frame_a to frame_b, world coordinates"),
];

pub static FIXED_TRANSLATION: ComponentSpec = ComponentSpec {
    kind: "PlanarMechanics.FixedTranslation",
    doc: "A massless rod: frame_b at r from frame_a, resolved in frame_a (so it turns with frame_a), with \
          frame_a's angle.",
    params: &[
        ParamSpec::vector("r", &[1.0, 0.0], "m", "From frame_a to frame_b, resolved in frame_a"),
        ParamSpec::world("radius", ParamType::Real, "default_joint_width", 0.5, "m", "Radius of the rod drawn"),
        Z_POSITION,
        RENDER,
        color("default_rod_color"),
        SPECULAR,
    ],
    connectors: &[FRAME_A, FRAME_B],
    variables: VARIABLES,
    build: |p| Ok(Box::new(Relation { pose: planar_pose(in_plane(p, "r"), 0.0) })),
    shapes: |p: &ParamSet| {
        if !p.boolean("render") {
            return Vec::new();
        }
        let (color, specular) = look(p);
        let d = 2.0 * p.real("radius");
        vec![LocalShape::in_frame(ShapeKind::Cylinder, "frame_a", lift(p), in_plane(p, "r"), d, d)
            .colored(color, specular)]
    },
};

pub static FIXED_ROTATION: ComponentSpec = ComponentSpec {
    kind: "PlanarMechanics.FixedRotation",
    doc: "frame_b at frame_a's origin, turned by alpha from it.",
    params: &[ParamSpec::real("alpha", 0.0, "rad", "Angle from frame_a to frame_b")],
    connectors: &[FRAME_A, FRAME_B],
    variables: VARIABLES,
    build: |p| Ok(Box::new(Relation { pose: planar_pose(Vec3::zeros(), p.real("alpha")) })),
    shapes: super::super::shapes::none,
};

#[derive(Debug)]
struct Relation {
    pose: Transform,
}

impl Component for Relation {
    fn parts(&self) -> Vec<Part> {
        vec![Part::Rigid { a: 0, b: 1, pose: self.pose }]
    }

    fn variables(&self) -> Vec<VarSpec> {
        VARIABLES.to_vec()
    }

    fn evaluate(&self, ctx: &EvalContext, out: &mut Vec<f64>) {
        let (a, b) = (&ctx.frames[0], &ctx.frames[1]);
        let r0 = b.r_0 - a.r_0;
        out.extend([planar_angle(&a.rot), a.w.z, r0.x, r0.y]);
    }
}
