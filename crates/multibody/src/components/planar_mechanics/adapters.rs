//! PlanarMechanics.PlanarToMultiBody (a planar frame drives a 3-D one) and
//! FrameVisualizer2D.

use super::super::shapes::{LocalShape, ShapeKind};
use super::super::spec::{ComponentSpec, ConnectorSpec, ParamSpec, VarSpec};
use super::super::{Component, EvalContext, Part};
use super::{lift, FRAME_A, RENDER, Z_POSITION};
use crate::math::rotation::planar_angle;
use crate::math::{Transform, Vec3};

pub static PLANAR_TO_MULTIBODY: ComponentSpec = ComponentSpec {
    kind: "PlanarMechanics.PlanarToMultiBody",
    doc: "Joins a planar frame to a 3-D one: frame_b sits at (x, y, z_position) turned by phi about z. The \
          planar side moves the 3-D side; the 3-D side's forces in the plane act on the planar side, and the \
          plane takes the rest (the force along z and the torques about x and y).",
    params: &[ParamSpec::real("z_position", 0.0, "m", "Where frame_b sits along z")],
    connectors: &[FRAME_A, ConnectorSpec::frame("frame_b", "The 3-D frame")],
    variables: &[
        VarSpec::scalar("fz", "N", "Force along z with which the plane holds the 3-D side, at frame_a"),
        VarSpec::vector(
            "tau_perp",
            2,
            "N.m",
            "Torques about frame_a's x and y with which the plane holds the 3-D side",
        ),
    ],
    build: |p| Ok(Box::new(PlanarToMultiBody { z: p.real("z_position") })),
    shapes: super::super::shapes::none,
};

#[derive(Debug)]
struct PlanarToMultiBody {
    z: f64,
}

impl Component for PlanarToMultiBody {
    fn parts(&self) -> Vec<Part> {
        vec![Part::Rigid { a: 0, b: 1, pose: Transform::translation(Vec3::new(0.0, 0.0, self.z)) }]
    }

    fn variables(&self) -> Vec<VarSpec> {
        PLANAR_TO_MULTIBODY.variables.to_vec()
    }

    fn evaluate(&self, ctx: &EvalContext, out: &mut Vec<f64>) {
        // The plane's reaction on the adapter at frame_a, out of the plane.
        let a = &ctx.frames[0];
        out.extend([a.f.z, a.tau.x, a.tau.y]);
    }
}

pub static FRAME_VISUALIZER: ComponentSpec = ComponentSpec {
    kind: "PlanarMechanics.FrameVisualizer2D",
    doc: "Draws frame_a's x and y axes; adds no force.",
    params: &[
        ParamSpec::world(
            "axis_length",
            super::super::spec::ParamType::Real,
            "default_joint_length",
            1.0,
            "m",
            "Length of the axes drawn",
        ),
        ParamSpec::derived("axis_radius", super::super::spec::ParamType::Real, "axis_length / 20", "m", "Their radius"),
        Z_POSITION,
        RENDER,
        ParamSpec::vector("color", &[0.5, 0.5, 0.5, 1.0], "", "Colour (RGBA)"),
    ],
    connectors: &[FRAME_A],
    variables: &[VarSpec::scalar("phi", "rad", "Angle of frame_a")],
    build: |_| Ok(Box::new(Visualizer)),
    shapes: |p| {
        if !p.boolean("render") {
            return Vec::new();
        }
        let length = p.real("axis_length");
        let d = 2.0 * p.real_opt("axis_radius").unwrap_or(length / 20.0);
        let color = p.color("color");
        [Vec3::x(), Vec3::y()]
            .into_iter()
            .map(|e| {
                LocalShape::in_frame(ShapeKind::Cylinder, "frame_a", lift(p), e * length, d, d).colored(color, 0.7)
            })
            .collect()
    },
};

#[derive(Debug)]
struct Visualizer;

impl Component for Visualizer {
    fn parts(&self) -> Vec<Part> {
        Vec::new()
    }

    fn variables(&self) -> Vec<VarSpec> {
        FRAME_VISUALIZER.variables.to_vec()
    }

    fn evaluate(&self, ctx: &EvalContext, out: &mut Vec<f64>) {
        out.push(planar_angle(&ctx.frames[0].rot));
    }
}
