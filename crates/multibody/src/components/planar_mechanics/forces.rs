//! PlanarMechanics.Spring, SpringDamper, Damper and WorldForceTorque.
//!
//! As in the library, Spring and SpringDamper act per world axis (x, y and
//! the angle), not along the line between their frames; Damper acts along
//! that line.

use super::super::line_force::helix;
use super::super::shapes::{between, look, LocalShape, ShapeKind};
use super::super::spec::{concat, ComponentSpec, ConnectorSpec, ParamSpec, ParamType, VarSpec};
use super::super::{Component, EvalContext, ForceLaw, ParamSet, Part, Resolve};
use super::{FRAME_A, FRAME_B, RENDER, SPECULAR, Z_POSITION};
use crate::math::rotation::planar_angle;
use crate::Error;

const STIFFNESS: [ParamSpec; 3] = [
    ParamSpec::real("c_x", 1.0, "N/m", "Stiffness along the world's x"),
    ParamSpec::real("c_y", 1.0, "N/m", "Stiffness along the world's y"),
    ParamSpec::real("c_phi", 1.0e5, "N.m/rad", "Stiffness of the relative angle"),
];

const DAMPING: [ParamSpec; 3] = [
    ParamSpec::real("d_x", 1.0, "N.s/m", "Damping along the world's x"),
    ParamSpec::real("d_y", 1.0, "N.s/m", "Damping along the world's y"),
    ParamSpec::real("d_phi", 1.0, "N.m.s/rad", "Damping of the relative angle"),
];

/// The unstretched offsets, then how the coil is drawn.
const REST_AND_LOOK: [ParamSpec; 11] = [
    ParamSpec::real("s_relx0", 0.0, "m", "Unstretched x distance from frame_a to frame_b"),
    ParamSpec::real("s_rely0", 0.0, "m", "Unstretched y distance from frame_a to frame_b"),
    ParamSpec::real("phi_rel0", 0.0, "rad", "Unstretched angle from frame_a to frame_b"),
    ParamSpec::world("radius", ParamType::Real, "default_force_width", 1.0, "m", "Radius of the coil drawn"),
    ParamSpec::real("num_windings", 6.0, "", "Windings of the coil drawn"),
    ParamSpec::integer("N", 200.0, "Points of the coil drawn (kept for compatibility)"),
    ParamSpec::real("end_ratio", 0.1, "", "Straight ends of the coil drawn (kept for compatibility)"),
    Z_POSITION,
    RENDER,
    ParamSpec::vector("color", &[0.0, 0.0, 1.0, 1.0], "", "Colour (RGBA)"),
    SPECULAR,
];

const SPRING_VARIABLES: &[VarSpec] = &[
    VarSpec::scalar("s_relx", "m", "x distance from frame_a to frame_b"),
    VarSpec::scalar("s_rely", "m", "y distance from frame_a to frame_b"),
    VarSpec::scalar("phi_rel", "rad", "Angle from frame_a to frame_b"),
    VarSpec::scalar("f_x", "N", "Force along x (on frame_b it pulls back)"),
    VarSpec::scalar("f_y", "N", "Force along y"),
];

const SPRING_DAMPER_VARIABLES: &[VarSpec] = &[
    VarSpec::scalar("s_relx", "m", "x distance from frame_a to frame_b"),
    VarSpec::scalar("s_rely", "m", "y distance from frame_a to frame_b"),
    VarSpec::scalar("phi_rel", "rad", "Angle from frame_a to frame_b"),
    VarSpec::scalar("v_relx", "m/s", "der(s_relx)"),
    VarSpec::scalar("v_rely", "m/s", "der(s_rely)"),
    VarSpec::scalar("w_rel", "rad/s", "der(phi_rel)"),
    VarSpec::scalar("f_x", "N", "Force along x (on frame_b it pulls back)"),
    VarSpec::scalar("f_y", "N", "Force along y"),
    VarSpec::scalar("tau", "N.m", "Torque about z (on frame_b it turns back)"),
];

pub static SPRING: ComponentSpec = ComponentSpec {
    kind: "PlanarMechanics.Spring",
    doc: "A planar spring per world axis: frame_b is pulled back by c_x (s_relx - s_relx0) along x and \
          c_y (s_rely - s_rely0) along y, frame_a the other way. As in the library, c_phi is kept but no torque acts.",
    params: &concat::<ParamSpec, 14>(&STIFFNESS, &REST_AND_LOOK),
    connectors: &[FRAME_A, FRAME_B],
    variables: SPRING_VARIABLES,
    build: |p| axes(p, false),
    shapes: |p| helix(p, p.real("num_windings")),
};

pub static SPRING_DAMPER: ComponentSpec = ComponentSpec {
    kind: "PlanarMechanics.SpringDamper",
    doc: "A planar spring and damper per world axis: frame_b is pulled back by c_x (s_relx - s_relx0) + \
          d_x v_relx along x, likewise along y, and turned back by c_phi (phi_rel - phi_rel0) + d_phi w_rel; \
          frame_a the other way.",
    params: &concat::<ParamSpec, 17>(&concat::<ParamSpec, 6>(&STIFFNESS, &DAMPING), &REST_AND_LOOK),
    connectors: &[FRAME_A, FRAME_B],
    variables: SPRING_DAMPER_VARIABLES,
    build: |p| axes(p, true),
    shapes: |p| helix(p, p.real("num_windings")),
};

fn axes(p: &ParamSet, damped: bool) -> Result<Box<dyn Component>, Error> {
    let c = [p.non_negative("c_x", true)?, p.non_negative("c_y", true)?, p.non_negative("c_phi", true)?];
    let d = if damped {
        [p.non_negative("d_x", true)?, p.non_negative("d_y", true)?, p.non_negative("d_phi", true)?]
    } else {
        [0.0; 3]
    };
    // The library's Spring applies no torque whatever c_phi is.
    let c = if damped { c } else { [c[0], c[1], 0.0] };
    let rel0 = [p.real("s_relx0"), p.real("s_rely0"), p.real("phi_rel0")];
    Ok(Box::new(Axes { c, d, rel0, damped }))
}

#[derive(Debug)]
struct Axes {
    c: [f64; 3],
    d: [f64; 3],
    rel0: [f64; 3],
    damped: bool,
}

impl Component for Axes {
    fn parts(&self) -> Vec<Part> {
        vec![Part::force(Some(0), 1, ForceLaw::PlanarAxes { c: self.c, d: self.d, rel0: self.rel0 })]
    }

    fn variables(&self) -> Vec<VarSpec> {
        if self.damped { SPRING_DAMPER_VARIABLES } else { SPRING_VARIABLES }.to_vec()
    }

    fn evaluate(&self, ctx: &EvalContext, out: &mut Vec<f64>) {
        let (a, b) = (&ctx.frames[0], &ctx.frames[1]);
        let (s, v) = (b.r_0 - a.r_0, b.v_0 - a.v_0);
        let phi = planar_angle(&(b.rot * a.rot.transpose()));
        let w = b.w.z - a.w.z;
        let pull = |k: usize, s: f64, v: f64| self.c[k] * (s - self.rel0[k]) + self.d[k] * v;
        out.extend([s.x, s.y, phi]);
        if self.damped {
            out.extend([v.x, v.y, w]);
        }
        out.extend([pull(0, s.x, v.x), pull(1, s.y, v.y)]);
        if self.damped {
            out.push(pull(2, phi, w));
        }
    }
}

const DAMPER_VARIABLES: &[VarSpec] = &[
    VarSpec::scalar("r0x", "m", "x distance from frame_a to frame_b"),
    VarSpec::scalar("r0y", "m", "y distance from frame_a to frame_b"),
    VarSpec::scalar("d0x", "", "x of the unit line from frame_a to frame_b"),
    VarSpec::scalar("d0y", "", "y of the unit line from frame_a to frame_b"),
    VarSpec::scalar("vx", "m/s", "x of frame_b's velocity relative to frame_a's"),
    VarSpec::scalar("vy", "m/s", "y of frame_b's velocity relative to frame_a's"),
    VarSpec::scalar("v", "m/s", "Speed of lengthening"),
    VarSpec::scalar("f", "N", "Damping force (-d v)"),
];

pub static DAMPER: ComponentSpec = ComponentSpec {
    kind: "PlanarMechanics.Damper",
    doc: "A planar linear damper along the line between the frames' origins: it resists their lengthening with \
          d v. No torques.",
    params: &[
        ParamSpec::real("d", 1.0, "N.s/m", "Damping coefficient"),
        ParamSpec::real("s_small", 1e-10, "m", "Below this distance the line's direction is not normalised"),
        ParamSpec::world("radius", ParamType::Real, "default_force_width", 1.0, "m", "Radius drawn"),
        Z_POSITION,
        RENDER,
        ParamSpec::vector("color", &[0.5, 0.5, 0.5, 1.0], "", "Colour (RGBA)"),
        SPECULAR,
    ],
    connectors: &[FRAME_A, FRAME_B],
    variables: DAMPER_VARIABLES,
    build: |p| Ok(Box::new(Damper { d: p.non_negative("d", true)?, s_small: p.non_negative("s_small", false)? })),
    shapes: |p: &ParamSet| -> Vec<LocalShape> {
        if !p.boolean("render") {
            return Vec::new();
        }
        let (color, specular) = look(p);
        let d = 2.0 * p.real("radius");
        vec![between(ShapeKind::Cylinder, "frame_a", "frame_b", d, d).colored(color, specular)]
    },
};

#[derive(Debug)]
struct Damper {
    d: f64,
    s_small: f64,
}

impl Component for Damper {
    fn parts(&self) -> Vec<Part> {
        let law = ForceLaw::Line { c: 0.0, d: self.d, s_unstretched: 0.0, s_small: self.s_small };
        vec![Part::force(Some(0), 1, law)]
    }

    fn variables(&self) -> Vec<VarSpec> {
        DAMPER_VARIABLES.to_vec()
    }

    fn evaluate(&self, ctx: &EvalContext, out: &mut Vec<f64>) {
        let (a, b) = (&ctx.frames[0], &ctx.frames[1]);
        let (r0, dv) = (b.r_0 - a.r_0, b.v_0 - a.v_0);
        let e = if r0.norm() < self.s_small { r0 } else { r0 / r0.norm() };
        let v = dv.dot(&e);
        out.extend([r0.x, r0.y, e.x, e.y, dv.x, dv.y, v, -self.d * v]);
    }
}

pub static WORLD_FORCE_TORQUE: ComponentSpec = ComponentSpec {
    kind: "PlanarMechanics.WorldForceTorque",
    doc: "Applies the force [force_x, force_y] (resolved in the world, or in frame_b) and the torque `torque` \
          to what frame_b is connected to; the reaction goes to the world.",
    params: &[
        ParamSpec {
            name: "resolve_in_frame",
            ty: ParamType::Enum("ResolveInFrame", &["World", "FrameB"]),
            default: super::super::spec::Default::Enum("World"),
            unit: "",
            doc: "Frame the force is resolved in",
        },
        ParamSpec::real("scale", 0.1, "m/N", "Length of the arrow drawn per newton"),
        ParamSpec::real("arrow_diameter", 0.05, "m", "Diameter of the arrow drawn"),
        Z_POSITION,
        RENDER,
        ParamSpec::vector("color", &[0.0, 1.0, 0.0, 0.5], "", "Colour (RGBA)"),
        SPECULAR,
    ],
    connectors: &[
        ConnectorSpec::frame_2d("frame_b", "Where the force and torque act"),
        ConnectorSpec::input("force_x", "x of the force"),
        ConnectorSpec::input("force_y", "y of the force"),
        ConnectorSpec::input("torque", "Torque about z"),
        ConnectorSpec::internal("zero", super::super::spec::ConnectorType::RealOutput),
    ],
    variables: &[VarSpec::scalar("phi", "rad", "Angle of the frame the force is resolved in")],
    build: |p| {
        let resolve = if p.variant("resolve_in_frame") == "FrameB" { Resolve::FrameB } else { Resolve::World };
        Ok(Box::new(WorldForceTorque { resolve }))
    },
    shapes: super::super::shapes::none,
};

#[derive(Debug)]
struct WorldForceTorque {
    resolve: Resolve,
}

impl Component for WorldForceTorque {
    fn parts(&self) -> Vec<Part> {
        // Connectors: frame_b 0, force_x 1, force_y 2, torque 3, zero 4.
        vec![
            // The internal connector 4 stays a zero signal (unused now).
            Part::zero_signal(4),
            Part::Force {
                a: None,
                b: 0,
                law: ForceLaw::Force { resolve: self.resolve },
                inputs: [Some(1), Some(2), None, None, None, None],
                flanges: [None; 2],
            },
            Part::Force {
                a: None,
                b: 0,
                law: ForceLaw::Torque { resolve: Resolve::World },
                inputs: [None, None, Some(3), None, None, None],
                flanges: [None; 2],
            },
        ]
    }

    fn variables(&self) -> Vec<VarSpec> {
        vec![VarSpec::scalar("phi", "rad", "Angle of the frame the force is resolved in")]
    }

    fn evaluate(&self, ctx: &EvalContext, out: &mut Vec<f64>) {
        out.push(if self.resolve == Resolve::World { 0.0 } else { planar_angle(&ctx.frames[0].rot) });
    }
}
