//! PointMass: mass without an inertia tensor, with a single frame connector.

use super::shapes::{look, LocalShape, ShapeKind};
use super::spec::{ComponentSpec, ConnectorSpec, ParamSpec, ParamType, VarSpec};
use super::{Component, EvalContext, ParamSet, Part, StateNames};
use crate::math::{Mat3, RigidInertia, Vec3};
use crate::system::joint::JointModel;
use crate::Error;

pub static SPEC: ComponentSpec = ComponentSpec {
    kind: "PointMass",
    doc: "Point mass: mass without an inertia tensor, with a single frame connector. It transmits no torque \
          and reads its orientation from what it is attached to. With isroot = true an unconnected point mass \
          owns its frame (orientation fixed to the world's) and carries r_0 and v_0 as states.",
    params: &[
        ParamSpec::boolean(
            "isroot",
            false,
            "Fix frame_a's orientation to the world orientation. Use only when frame_a is unconnected",
        ),
        ParamSpec::integer(
            "linearStatePriority",
            0.0,
            "State priority of the position and velocity states (kept for compatibility)",
        ),
        ParamSpec::boolean(
            "point_gravity",
            false,
            "Use a point-gravity field pointing towards the world origin instead of the uniform field g*n",
        ),
        ParamSpec::boolean("render", true, "Draw the point mass in animations"),
        ParamSpec::world("color", ParamType::Vector(4), "default_body_color", 1.0, "", "Colour (RGBA)"),
        ParamSpec::real("specular_coefficient", 1.5, "", "Reflection of light in animations"),
        ParamSpec::real("m", 1.0, "kg", "mass"),
        ParamSpec::world(
            "radius",
            ParamType::Real,
            "default_body_diameter",
            0.5,
            "m",
            "Radius of the sphere in animations",
        ),
    ],
    connectors: &[ConnectorSpec::frame("frame_a", "The point mass sits at the origin of this frame")],
    variables: &[
        VarSpec::vector("r_0", 3, "m", "Position vector from origin of world frame to origin of frame_a"),
        VarSpec::vector("v_0", 3, "m/s", "Absolute velocity of frame_a, resolved in world frame (= D(r_0))"),
        VarSpec::vector("a_0", 3, "m/s2", "Absolute acceleration of frame_a resolved in world frame (= D(v_0))"),
        VarSpec::vector("g_0", 3, "m/s2", "gravity acceleration"),
    ],
    build,
    shapes,
};

/// A sphere at frame_a.
fn shapes(p: &ParamSet) -> Vec<LocalShape> {
    if !p.boolean("render") {
        return Vec::new();
    }
    let (color, specular) = look(p);
    let d = 2.0 * p.real("radius");
    vec![LocalShape::in_frame(ShapeKind::Sphere, "frame_a", Vec3::zeros(), Vec3::x(), d, d).colored(color, specular)]
}

const ROOT_STATES: StateNames = StateNames { q: &[("r_0", 3)], u: &[("v_0", 3)] };

#[derive(Debug)]
struct PointMass {
    m: f64,
    point_gravity: bool,
    isroot: bool,
}

fn build(p: &ParamSet) -> Result<Box<dyn Component>, Error> {
    Ok(Box::new(PointMass {
        m: p.non_negative("m", true)?,
        point_gravity: p.boolean("point_gravity"),
        isroot: p.boolean("isroot"),
    }))
}

impl Component for PointMass {
    fn parts(&self) -> Vec<Part> {
        let inertia = RigidInertia::from_com(self.m, Vec3::zeros(), Mat3::zeros());
        let mut parts = vec![Part::Mass { frame: 0, inertia, point_gravity: self.point_gravity }];
        if self.isroot {
            parts.push(Part::Owner { frame: 0, model: JointModel::Translation, states: ROOT_STATES, fallback: false });
        }
        parts
    }

    fn variables(&self) -> Vec<VarSpec> {
        SPEC.variables.to_vec()
    }

    fn evaluate(&self, ctx: &EvalContext, out: &mut Vec<f64>) {
        let frame = &ctx.frames[0];
        let g_0 = ctx.world.gravity(&frame.r_0, self.point_gravity);
        for v in [frame.r_0, frame.v_0, frame.a_0, g_0] {
            out.extend_from_slice(v.as_slice());
        }
    }
}
