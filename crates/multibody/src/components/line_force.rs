//! What the line forces (Spring, Damper, SpringDamperParallel) share: a
//! force along the line between the frames' origins, no torques, and
//! optionally ends that fix their frame's orientation.

use super::spec::{ParamSpec, VarSpec};
use super::{Component, EvalContext, ForceLaw, ParamSet, Part};
use crate::dynamics::forces::{line_force, PointState};
use crate::Error;

pub const FIXED_ROTATION_A: ParamSpec = ParamSpec::boolean(
    "fixed_rotation_at_frame_a",
    false,
    "Fix frame_a's orientation to the world's (for frames nothing else orients, e.g. a point mass held by springs)",
);
pub const FIXED_ROTATION_B: ParamSpec = ParamSpec::boolean(
    "fixed_rotation_at_frame_b",
    false,
    "Fix frame_b's orientation to the world's (for frames nothing else orients, e.g. a point mass held by springs)",
);
pub const S_SMALL: ParamSpec =
    ParamSpec::real("s_small", 1e-10, "m", "Prevents a division by zero when the frames' origins coincide");

pub const VARIABLES: &[VarSpec] = &[
    VarSpec::scalar("length", "m", "Distance between the origin of frame_a and the origin of frame_b"),
    VarSpec::scalar(
        "s",
        "m",
        "(Guarded) distance between the origin of frame_a and the origin of frame_b (>= s_small)",
    ),
    VarSpec::scalar("f", "N", "Line force, positive when it pulls the frames together"),
    VarSpec::vector("r_rel_0", 3, "m", "Position vector from frame_a to frame_b resolved in world frame"),
    VarSpec::vector("e_rel_0", 3, "", "Unit vector in direction from frame_a to frame_b, resolved in world frame"),
];

#[derive(Debug)]
pub struct LineForce {
    pub c: f64,
    pub d: f64,
    pub s_unstretched: f64,
    pub s_small: f64,
    pub fixed_rotation: [bool; 2],
}

/// A line force's point mass: `m` at `r_a + h (r_b - r_a)`, with whether
/// it feels point gravity.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LineMass {
    pub m: f64,
    pub h: f64,
    pub point_gravity: bool,
}

/// The point mass of a line force with `hasmass = true`, from the
/// parameters `m`, `lengthfraction` and, where the kind has it,
/// `point_gravity` (or the world's point gravity);
/// `None` when `m = 0`.
pub fn line_mass(p: &ParamSet) -> Result<Option<LineMass>, Error> {
    let m = p.non_negative("m", true)?;
    let h = p.real("lengthfraction");
    if !(0.0..=1.0).contains(&h) {
        return Err(
            p.invalid("lengthfraction", "the point mass must lie between the frames (0 <= lengthfraction <= 1)")
        );
    }
    let own = p.spec.params.iter().any(|q| q.name == "point_gravity") && p.boolean("point_gravity");
    let point_gravity = own || p.world.point_gravity;
    Ok((m > 0.0).then_some(LineMass { m, h, point_gravity }))
}

impl Component for LineForce {
    fn parts(&self) -> Vec<Part> {
        let law = ForceLaw::Line { c: self.c, d: self.d, s_unstretched: self.s_unstretched, s_small: self.s_small };
        let mut parts = vec![Part::force(Some(0), 1, law)];
        for (frame, fixed) in self.fixed_rotation.iter().enumerate() {
            if *fixed {
                parts.push(Part::FixedRotationEnd { frame });
            }
        }
        parts
    }

    fn variables(&self) -> Vec<VarSpec> {
        VARIABLES.to_vec()
    }

    fn evaluate(&self, ctx: &EvalContext, out: &mut Vec<f64>) {
        let point = |k: usize| PointState {
            r: ctx.frames[k].r_0,
            rot: ctx.frames[k].rot,
            v: ctx.frames[k].v_0,
            w: ctx.frames[k].rot.tr_mul(&ctx.frames[k].w),
        };
        let (a, b) = (point(0), point(1));
        let (e, on_a) = line_force(self.c, self.d, self.s_unstretched, self.s_small, &a, &b);
        let r_rel = b.r - a.r;
        out.extend([r_rel.norm(), r_rel.norm().max(self.s_small), on_a.dot(&e)]);
        out.extend_from_slice(r_rel.as_slice());
        out.extend_from_slice(e.as_slice());
    }
}

/// A coil of `windings` between the frames, with the line force's colour and radius.
pub fn helix(p: &super::ParamSet, windings: f64) -> Vec<super::shapes::LocalShape> {
    if !p.boolean("render") {
        return Vec::new();
    }
    let (color, specular) = super::shapes::look(p);
    let d = 2.0 * p.real("radius");
    vec![super::shapes::between(super::shapes::ShapeKind::Helix { windings }, "frame_a", "frame_b", d, d / 10.0)
        .colored(color, specular)]
}

/// A line force with a point mass on its line (Modelica's
/// LineForceWithMass): the mass is no degree of freedom; the dynamics adds
/// its inertia and weight to the mass matrix and shares them between the
/// ends.
#[derive(Debug)]
pub struct WithMass {
    pub line: LineForce,
    pub mass: LineMass,
}

impl Component for WithMass {
    fn parts(&self) -> Vec<Part> {
        let LineMass { m, h, point_gravity } = self.mass;
        let mut parts = self.line.parts();
        parts.push(Part::LineMass { a: 0, b: 1, m, h, point_gravity });
        parts
    }

    fn variables(&self) -> Vec<VarSpec> {
        let mut vars = self.line.variables();
        vars.extend_from_slice(MASS_VARIABLES);
        vars
    }

    fn evaluate(&self, ctx: &EvalContext, out: &mut Vec<f64>) {
        self.line.evaluate(ctx, out);
        mass_outputs(self.mass.h, ctx, out);
    }
}

/// The values of [`MASS_VARIABLES`] for a point mass at the fraction `h`
/// of the way from frame_a (the first frame) to frame_b.
pub fn mass_outputs(h: f64, ctx: &EvalContext, out: &mut Vec<f64>) {
    let (a, b) = (&ctx.frames[0], &ctx.frames[1]);
    out.extend_from_slice((a.r_0 * (1.0 - h) + b.r_0 * h).as_slice());
    out.extend_from_slice((a.v_0 * (1.0 - h) + b.v_0 * h).as_slice());
    out.extend_from_slice((a.a_0 * (1.0 - h) + b.a_0 * h).as_slice());
}

/// The point mass's motion, as outputs.
pub const MASS_VARIABLES: &[VarSpec] = &[
    VarSpec::vector("r_CM_0", 3, "m", "Position of the point mass, resolved in world frame"),
    VarSpec::vector("v_CM_0", 3, "m/s", "Velocity of the point mass, resolved in world frame"),
    VarSpec::vector("a_CM_0", 3, "m/s2", "Acceleration of the point mass, resolved in world frame"),
];
