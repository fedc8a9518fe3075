//! What Force, Torque, WorldForce and WorldTorque share: a vector from
//! three signal inputs, resolved in a chosen frame, applied at frame_b with
//! its reaction on frame_a (or on the world).

use super::shapes::{LocalShape, Placement, ShapeKind};
use super::spec::{Default, ParamSpec, ParamType, VarSpec};
use super::{resolve_input, Component, EvalContext, ForceLaw, ParamSet, Part, Resolve};
use crate::math::Vec3;

/// The `resolve_in_frame` parameter with a given default.
pub const fn resolve_param(default: &'static str, variants: &'static [&'static str]) -> ParamSpec {
    ParamSpec {
        name: "resolve_in_frame",
        ty: ParamType::Enum("ResolveInFrame", variants),
        default: Default::Enum(default),
        unit: "",
        doc: "Frame in which the input vector is resolved",
    }
}

/// An arrow at frame_b along the output `vector`, `scale` metres per unit.
fn arrow(vector: &str, diameter: f64, color: [f64; 4], scale: f64) -> LocalShape {
    LocalShape {
        kind: ShapeKind::Arrow,
        color,
        specular: 0.7,
        width: diameter,
        height: diameter,
        placement: Placement::Vector { frame: "frame_b".into(), vector: vector.into(), scale },
    }
}

/// The arrow of Force and Torque, drawn with the world's defaults along the
/// applied vector: the opposite of the cut vector `vector` at frame_b, with
/// `units_per_metre` the world's length scale (`default_N_to_m`, ...).
pub fn cut_vector_arrow(p: &ParamSet, vector: &str, units_per_metre: &str) -> Vec<LocalShape> {
    let world = p.world;
    let color = match world.scaled("default_force_color", 1.0) {
        crate::Value::Array(c) if c.len() == 4 => [c[0], c[1], c[2], c[3]],
        _ => [0.0, 1.0, 0.0, 0.5],
    };
    let scale = -1.0 / world.number(units_per_metre);
    vec![arrow(vector, world.number("default_arrow_diameter"), color, scale)]
}

/// The arrow of WorldForce and WorldTorque along the applied `vector`, from
/// their own `render`, `color`, `radius` and `scale`.
pub fn applied_vector_arrow(p: &ParamSet, vector: &str) -> Vec<LocalShape> {
    if p.spec.param("render").is_some() && !p.boolean("render") {
        return Vec::new();
    }
    vec![arrow(vector, 2.0 * p.real("radius"), p.color("color"), p.real("scale"))]
}

#[derive(Debug)]
pub struct ExternalLoad {
    /// A torque rather than a force.
    pub torque: bool,
    pub resolve: Resolve,
    /// Between frame_a and frame_b (connectors 0, 1, inputs 2..5), or on
    /// frame_b alone (connector 0, inputs 1..4).
    pub two_frames: bool,
    pub variables: &'static [VarSpec],
}

impl ExternalLoad {
    fn inputs(&self) -> [usize; 3] {
        if self.two_frames {
            [2, 3, 4]
        } else {
            [1, 2, 3]
        }
    }
}

impl Component for ExternalLoad {
    fn parts(&self) -> Vec<Part> {
        let (inputs, resolve) = (self.inputs(), self.resolve);
        let law = if self.torque { ForceLaw::Torque { resolve } } else { ForceLaw::Force { resolve } };
        if self.two_frames {
            vec![Part::driven_force(Some(0), 1, law, &inputs)]
        } else {
            vec![Part::driven_force(None, 0, law, &inputs)]
        }
    }

    fn variables(&self) -> Vec<VarSpec> {
        self.variables.to_vec()
    }

    /// Between two frames: the vector from frame_a to frame_b and the cut
    /// force (or torque) at frame_b in world coordinates; on one frame: the
    /// applied vector in world coordinates.
    fn evaluate(&self, ctx: &EvalContext, out: &mut Vec<f64>) {
        let [x, y, z] = self.inputs().map(|i| ctx.signals[i]);
        let b = if self.two_frames { &ctx.frames[1] } else { &ctx.frames[0] };
        let a = self.two_frames.then(|| &ctx.frames[0]);
        let applied = resolve_input(Vec3::new(x, y, z), self.resolve, a.map(|a| &a.rot), &b.rot);
        if let Some(a) = a {
            out.extend_from_slice((b.r_0 - a.r_0).as_slice());
            out.extend_from_slice((-applied).as_slice());
        } else {
            out.extend_from_slice(applied.as_slice());
        }
    }
}
