//! LineForceWithMass: a line between two frames whose force comes from
//! 1-D translational elements (springs, dampers, forces) connected to its
//! flanges, with an optional point mass on the line.

use super::line_force::{
    line_mass, mass_outputs, LineMass, FIXED_ROTATION_A, FIXED_ROTATION_B, MASS_VARIABLES, S_SMALL,
};
use super::spec::{ComponentSpec, ConnectorSpec, ParamSpec, VarSpec};
use super::{Component, ConnectorType, EvalContext, ParamSet, Part};
use crate::Error;

pub static SPEC: ComponentSpec = ComponentSpec {
    kind: "LineForceWithMass",
    doc: "A force along the line between the origins of frame_a and frame_b, made by 1-D translational \
          components (springs, dampers, forces) connected to flange_a and flange_b: flange_a sits at 0 and \
          flange_b at the distance between the frames, and what pushes flange_b forward pushes frame_b away \
          from frame_a (and frame_a back). With hasmass, a point mass m sits on the line at lengthfraction of \
          the way from frame_a; it is no degree of freedom: its inertia and weight are shared by the ends.",
    params: &[
        FIXED_ROTATION_A,
        FIXED_ROTATION_B,
        ParamSpec::boolean("hasmass", true, "Put a point mass m on the line (at lengthfraction from frame_a)"),
        ParamSpec::boolean(
            "point_gravity",
            false,
            "The point mass feels a point-gravity field towards the world's origin (see Body)",
        ),
        S_SMALL,
        ParamSpec::real("m", 1.0, "kg", "mass of the point mass (used only with hasmass)"),
        ParamSpec::real(
            "lengthfraction",
            0.5,
            "",
            "Location of the point mass from frame_a, as a fraction of the distance to frame_b",
        ),
    ],
    connectors: &[
        ConnectorSpec::frame("frame_a", "First end"),
        ConnectorSpec::frame("frame_b", "Second end"),
        ConnectorSpec::flange("flange_a", ConnectorType::Flange, "1-D flange at 0 (the frame_a end)"),
        ConnectorSpec::flange("flange_b", ConnectorType::Flange, "1-D flange at the distance between the frames"),
    ],
    variables: VARIABLES,
    build,
    shapes: |_| Vec::new(),
};

const VARIABLES: &[VarSpec] = &[
    VarSpec::scalar("length", "m", "Distance between the origin of frame_a and the origin of frame_b"),
    VarSpec::scalar(
        "s",
        "m",
        "(Guarded) distance between the origin of frame_a and the origin of frame_b (>= s_small)",
    ),
    VarSpec::vector("r_rel_0", 3, "m", "Position vector from frame_a to frame_b resolved in world frame"),
    VarSpec::vector("e_rel_0", 3, "", "Unit vector in direction from frame_a to frame_b, resolved in world frame"),
];

#[derive(Debug)]
struct LineForceWithMass {
    s_small: f64,
    fixed_rotation: [bool; 2],
    mass: Option<LineMass>,
}

fn build(p: &ParamSet) -> Result<Box<dyn Component>, Error> {
    Ok(Box::new(LineForceWithMass {
        s_small: p.non_negative("s_small", false)?,
        fixed_rotation: [p.boolean("fixed_rotation_at_frame_a"), p.boolean("fixed_rotation_at_frame_b")],
        mass: if p.boolean("hasmass") { line_mass(p)? } else { None },
    }))
}

impl Component for LineForceWithMass {
    fn parts(&self) -> Vec<Part> {
        let mut parts = vec![Part::LineFlanges { a: 0, b: 1, flange_a: 2, flange_b: 3, s_small: self.s_small }];
        if let Some(LineMass { m, h, point_gravity }) = self.mass {
            parts.push(Part::LineMass { a: 0, b: 1, m, h, point_gravity });
        }
        for (frame, fixed) in self.fixed_rotation.iter().enumerate() {
            if *fixed {
                parts.push(Part::FixedRotationEnd { frame });
            }
        }
        parts
    }

    fn variables(&self) -> Vec<VarSpec> {
        let mut vars = VARIABLES.to_vec();
        if self.mass.is_some() {
            vars.extend_from_slice(MASS_VARIABLES);
        }
        vars
    }

    fn evaluate(&self, ctx: &EvalContext, out: &mut Vec<f64>) {
        let (a, b) = (&ctx.frames[0], &ctx.frames[1]);
        let r_rel = b.r_0 - a.r_0;
        let s = r_rel.norm().max(self.s_small);
        out.extend([r_rel.norm(), s]);
        out.extend_from_slice(r_rel.as_slice());
        out.extend_from_slice((r_rel / s).as_slice());
        if let Some(LineMass { h, .. }) = self.mass {
            mass_outputs(h, ctx, out);
        }
    }
}
