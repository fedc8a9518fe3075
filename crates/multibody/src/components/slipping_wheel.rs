//! The slipping wheels: SlipWheelJoint and SlippingWheel (the library's
//! slip law), PacejkaWheelJoint and PacejkaSlippingWheel (Pacejka's magic
//! formula), on the ground plane y = 0.
//!
//! The wheel's frame hangs on a free joint from the world (the library's
//! states x, y, z, angles, der_angles), or, with `angular_state = false`, on
//! whatever else holds it (an axle). Its contact keeps the rim's lowest
//! point on the plane: a constraint on positions whose force is the normal
//! force `f_n`, or, with `elastic_contact`, a stiff spring-damper. The
//! friction is no constraint but a force law: `f_n` times the coefficients
//! of the slip law at the contact point's slip velocity, against the slip.

use super::rolling_wheel::{contact_force, evaluate_contact, free_joint, shapes, VARIABLES as CONTACT_VARIABLES};
use super::spec::{ComponentSpec, ConnectorSpec, ConnectorType, ParamSpec, VarSpec};
use super::wheel_common::{
    non_negative, positive, road, wheel_inertia, COLOR, ISCUT, I_AXIS, I_LONG, M, RADIUS, RENDER, SEQUENCE, SPECULAR,
    SURFACE, WIDTH,
};
use super::{Component, ConstraintKind, EvalContext, ForceLaw, ParamSet, Part, SlipLaw, WheelContact};
use crate::math::surface::Surface;
use crate::math::wheel::road_contact;
use crate::math::{RigidInertia, Transform};
use crate::Error;

const CONNECTORS: &[ConnectorSpec] = &[
    ConnectorSpec::frame("frame_a", "At the wheel's centre, turning with it (z: spin axis)"),
    ConnectorSpec::internal("ground", ConnectorType::Frame),
];

const ANGULAR_STATE: ParamSpec = ParamSpec::boolean(
    "angular_state",
    true,
    "Give the wheel its own states (position and Cardan angles). Set false when the wheel is mounted on an axle \
     that already positions it: frame_a then follows the axle",
);
const ELASTIC: ParamSpec = ParamSpec::boolean(
    "elastic_contact",
    false,
    "A compliant normal contact, f_n = max(0, c_z pen + d_z der(pen)) for a penetration pen, instead of the rigid one",
);
const C_Z: ParamSpec = ParamSpec::real("c_z", 250000.0, "N/m", "Vertical contact stiffness (elastic_contact)");
const D_Z: ParamSpec = ParamSpec::real("d_z", 500.0, "N.s/m", "Vertical contact damping (elastic_contact)");
const V_SMALL: ParamSpec =
    ParamSpec::real("v_small", 1e-5, "m/s", "Added to the slip speed to avoid a division by zero in the slip law");

const TRIPLE_PARAMS: [ParamSpec; 6] = [
    ParamSpec::real(
        "vAdhesion_min",
        0.05,
        "m/s",
        "Minimum slip velocity of the peak of the adhesion curve (near standstill)",
    ),
    ParamSpec::real(
        "vSlide_min",
        0.15,
        "m/s",
        "Minimum slip velocity where the flat sliding part starts (near standstill)",
    ),
    ParamSpec::real(
        "sAdhesion",
        0.04,
        "",
        "Adhesion slippage: the peak is at a slip of sAdhesion times the rolling speed",
    ),
    ParamSpec::real("sSlide", 0.12, "", "Sliding slippage: sliding starts at a slip of sSlide times the rolling speed"),
    ParamSpec::real("mu_A", 0.8, "", "Friction coefficient at adhesion (the peak)"),
    ParamSpec::real("mu_S", 0.6, "", "Friction coefficient at sliding"),
];

const PACEJKA_PARAMS: [ParamSpec; 8] = [
    ParamSpec::real("Bx", 10.0, "s/m", "Longitudinal magic-formula stiffness factor (initial slope)"),
    ParamSpec::real("Cx", 1.9, "", "Longitudinal magic-formula shape factor"),
    ParamSpec::real("Dx", 1.0, "", "Longitudinal magic-formula peak friction coefficient"),
    ParamSpec::real("Ex", 0.97, "", "Longitudinal magic-formula curvature factor"),
    ParamSpec::real("By", 10.0, "s/m", "Lateral magic-formula stiffness factor (initial slope)"),
    ParamSpec::real("Cy", 1.3, "", "Lateral magic-formula shape factor"),
    ParamSpec::real("Dy", 0.9, "", "Lateral magic-formula peak friction coefficient"),
    ParamSpec::real("Ey", 0.97, "", "Lateral magic-formula curvature factor"),
];
const ELLIPSE: ParamSpec = ParamSpec::boolean(
    "friction_ellipse",
    true,
    "Share grip between the directions: both curves at the slip speed, along the slip (false: each curve at its own \
     slip component)",
);

pub static SLIP_JOINT: ComponentSpec = ComponentSpec {
    kind: "SlipWheelJoint",
    doc: "Joint without mass for a wheel with slip-dependent friction on the ground plane y = 0. The contact point \
          may slip; the ground pushes it against the slip with f_n times the library's slip law (limit_S_triple: \
          rising to mu_A at the adhesion slip velocity, settling at mu_S from the sliding one). The wheel may \
          lean; it cannot lift off (make sure f_n stays positive). frame_a is at the wheel's centre and turns \
          with it (z: spin axis); connect the wheel's body there (see SlippingWheel).",
    params: &[
        SEQUENCE,
        ISCUT,
        SURFACE,
        ELASTIC,
        ANGULAR_STATE,
        RENDER,
        COLOR,
        SPECULAR,
        RADIUS,
        WIDTH,
        C_Z,
        D_Z,
        TRIPLE_PARAMS[0],
        TRIPLE_PARAMS[1],
        TRIPLE_PARAMS[2],
        TRIPLE_PARAMS[3],
        TRIPLE_PARAMS[4],
        TRIPLE_PARAMS[5],
        V_SMALL,
    ],
    connectors: CONNECTORS,
    variables: &SLIP_VARIABLES,
    build: |p| build(p, Law::Triple, false),
    shapes,
};

pub static SLIPPING_WHEEL: ComponentSpec = ComponentSpec {
    kind: "SlippingWheel",
    doc: "Wheel with mass, inertia and slip-dependent friction on the ground plane y = 0: SlipWheelJoint with a \
          body of mass m and a diagonal inertia (I_axis about the spin axis, I_long across it) at its centre.",
    params: &[
        SEQUENCE,
        ISCUT,
        SURFACE,
        ELASTIC,
        ANGULAR_STATE,
        RENDER,
        COLOR,
        RADIUS,
        M,
        I_AXIS,
        I_LONG,
        WIDTH,
        C_Z,
        D_Z,
        TRIPLE_PARAMS[0],
        TRIPLE_PARAMS[1],
        TRIPLE_PARAMS[2],
        TRIPLE_PARAMS[3],
        TRIPLE_PARAMS[4],
        TRIPLE_PARAMS[5],
        V_SMALL,
        SPECULAR,
    ],
    connectors: CONNECTORS,
    variables: &SLIP_VARIABLES,
    build: |p| build(p, Law::Triple, true),
    shapes,
};

pub static PACEJKA_JOINT: ComponentSpec = ComponentSpec {
    kind: "PacejkaWheelJoint",
    doc: "Joint without mass for a wheel with Pacejka magic-formula friction on the ground plane y = 0: the \
          counterpart of SlipWheelJoint whose friction coefficients are D sin(C atan(B v - E (B v - atan(B v)))) \
          of the slip velocity v, with factors Bx, Cx, Dx, Ex along the path and By, Cy, Dy, Ey across it. Smooth \
          in all derivatives. The wheel cannot lift off (make sure f_n stays positive).",
    params: &[
        SEQUENCE,
        ISCUT,
        SURFACE,
        ELASTIC,
        ANGULAR_STATE,
        ELLIPSE,
        RENDER,
        COLOR,
        SPECULAR,
        RADIUS,
        WIDTH,
        C_Z,
        D_Z,
        PACEJKA_PARAMS[0],
        PACEJKA_PARAMS[1],
        PACEJKA_PARAMS[2],
        PACEJKA_PARAMS[3],
        PACEJKA_PARAMS[4],
        PACEJKA_PARAMS[5],
        PACEJKA_PARAMS[6],
        PACEJKA_PARAMS[7],
        V_SMALL,
    ],
    connectors: CONNECTORS,
    variables: &PACEJKA_VARIABLES,
    build: |p| build(p, Law::Pacejka, false),
    shapes,
};

pub static PACEJKA_WHEEL: ComponentSpec = ComponentSpec {
    kind: "PacejkaSlippingWheel",
    doc: "Wheel with mass, inertia and Pacejka magic-formula friction on the ground plane y = 0: PacejkaWheelJoint \
          with a body of mass m and a diagonal inertia (I_axis about the spin axis, I_long across it) at its centre.",
    params: &[
        SEQUENCE,
        ISCUT,
        SURFACE,
        ELASTIC,
        ANGULAR_STATE,
        ELLIPSE,
        RENDER,
        COLOR,
        RADIUS,
        M,
        I_AXIS,
        I_LONG,
        WIDTH,
        C_Z,
        D_Z,
        PACEJKA_PARAMS[0],
        PACEJKA_PARAMS[1],
        PACEJKA_PARAMS[2],
        PACEJKA_PARAMS[3],
        PACEJKA_PARAMS[4],
        PACEJKA_PARAMS[5],
        PACEJKA_PARAMS[6],
        PACEJKA_PARAMS[7],
        V_SMALL,
        SPECULAR,
    ],
    connectors: CONNECTORS,
    variables: &PACEJKA_VARIABLES,
    build: |p| build(p, Law::Pacejka, true),
    shapes,
};

const SLIP: [VarSpec; 6] = [
    VarSpec::scalar("w_roll", "rad/s", "Spin rate of the wheel about its axis"),
    VarSpec::scalar("v_slip_long", "m/s", "Slip velocity along the wheel's path"),
    VarSpec::scalar("v_slip_lat", "m/s", "Slip velocity across the wheel's path"),
    VarSpec::scalar("v_slip", "m/s", "Slip speed: the norm of the slip velocity, plus v_small"),
    VarSpec::scalar(
        "slip_ratio",
        "",
        "v_slip_long over the centre's speed along the path (0 while the centre does not move along it)",
    ),
    VarSpec::scalar("f", "N", "Total traction force (the friction force's magnitude)"),
];
const TRIPLE_VARIABLES: [VarSpec; 2] = [
    VarSpec::scalar("vAdhesion", "m/s", "Slip velocity of the adhesion peak"),
    VarSpec::scalar("vSlide", "m/s", "Slip velocity where sliding starts"),
];

/// x, y, z, angles, der_angles, the contact's, then the slip's.
static SLIP_VARIABLES: [VarSpec; 26] = {
    let mut v = [SLIP[0]; 26];
    let mut i = 0;
    while i < 18 {
        v[i] = CONTACT_VARIABLES[i];
        i += 1;
    }
    while i < 24 {
        v[i] = SLIP[i - 18];
        i += 1;
    }
    v[24] = TRIPLE_VARIABLES[0];
    v[25] = TRIPLE_VARIABLES[1];
    v
};
static PACEJKA_VARIABLES: [VarSpec; 24] = {
    let mut v = [SLIP[0]; 24];
    let mut i = 0;
    while i < 18 {
        v[i] = CONTACT_VARIABLES[i];
        i += 1;
    }
    while i < 24 {
        v[i] = SLIP[i - 18];
        i += 1;
    }
    v
};

#[derive(Clone, Copy, Debug, PartialEq)]
enum Law {
    Triple,
    Pacejka,
}

#[derive(Debug)]
struct SlippingWheel {
    radius: f64,
    law: SlipLaw,
    sequence: [usize; 3],
    iscut: bool,
    angular_state: bool,
    /// `(c_z, d_z)` of an elastic contact.
    elastic: Option<(f64, f64)>,
    /// The road, if not the plane y = 0.
    surface: Option<Surface>,
    mass: Option<RigidInertia>,
}

fn build(p: &ParamSet, law: Law, with_mass: bool) -> Result<Box<dyn Component>, Error> {
    let radius = positive(p, "radius", "the wheel's radius")?;
    let v_small = positive(p, "v_small", "v_small")?;
    let law = match law {
        Law::Triple => {
            let v_adhesion_min = positive(p, "vAdhesion_min", "the adhesion velocity")?;
            let v_slide_min = positive(p, "vSlide_min", "the sliding velocity")?;
            let s_adhesion = non_negative(p, "sAdhesion", "the adhesion slippage")?;
            let s_slide = non_negative(p, "sSlide", "the sliding slippage")?;
            if v_slide_min <= v_adhesion_min || s_slide < s_adhesion {
                return Err(p.invalid(
                    "vSlide_min",
                    "sliding must start beyond the adhesion peak: make vSlide_min > vAdhesion_min and sSlide >= sAdhesion",
                ));
            }
            let mu_a = non_negative(p, "mu_A", "the adhesion friction coefficient")?;
            let mu_s = non_negative(p, "mu_S", "the sliding friction coefficient")?;
            SlipLaw::Triple { v_adhesion_min, v_slide_min, s_adhesion, s_slide, mu_a, mu_s, v_small }
        }
        Law::Pacejka => {
            let factors = |names: [&str; 4]| -> Result<[f64; 4], Error> {
                let mut out = [0.0; 4];
                for (o, name) in out.iter_mut().zip(names) {
                    *o = p.real(name);
                    if !o.is_finite() {
                        return Err(p.invalid(name, "a magic-formula factor must be a finite number"));
                    }
                }
                Ok(out)
            };
            SlipLaw::Pacejka {
                x: factors(["Bx", "Cx", "Dx", "Ex"])?,
                y: factors(["By", "Cy", "Dy", "Ey"])?,
                v_small,
                ellipse: p.boolean("friction_ellipse"),
            }
        }
    };
    let elastic = if p.boolean("elastic_contact") {
        Some((positive(p, "c_z", "the contact stiffness")?, non_negative(p, "d_z", "the contact damping")?))
    } else {
        None
    };
    let mass = if with_mass { Some(wheel_inertia(p, "m", "I_axis", "I_long")?) } else { None };
    let surface = road(p)?;
    Ok(Box::new(SlippingWheel {
        surface,
        radius,
        law,
        sequence: p.sequence("sequence")?,
        iscut: p.boolean("iscut"),
        angular_state: p.boolean("angular_state"),
        elastic,
        mass,
    }))
}

impl Component for SlippingWheel {
    fn parts(&self) -> Vec<Part> {
        let mut parts = vec![Part::Ground { frame: 1, pose: Transform::IDENTITY }];
        if self.angular_state {
            parts.push(free_joint(self.sequence, self.iscut));
        }
        parts.push(match self.elastic {
            Some((c_z, d_z)) => Part::force(
                None,
                0,
                ForceLaw::Tyre { radius: self.radius, law: self.law, c_z, d_z, road: self.surface.as_ref().map(|_| 0) },
            ),
            None => Part::Constraint {
                a: 1,
                b: 0,
                kind: ConstraintKind::Wheel {
                    radius: self.radius,
                    contact: WheelContact::Slipping { law: self.law, road: self.surface.as_ref().map(|_| 0) },
                },
            },
        });
        if let Some(inertia) = self.mass {
            parts.push(Part::Mass { frame: 0, inertia, point_gravity: false });
        }
        if let Some(surface) = self.surface.clone() {
            parts.push(Part::Road { surface: Box::new(surface) });
        }
        parts
    }

    /// The library's start: the centre at the height of the radius.
    fn default_starts(&self) -> Vec<(&'static str, Vec<f64>)> {
        vec![("y", vec![self.radius])]
    }

    fn variables(&self) -> Vec<VarSpec> {
        let all: &[VarSpec] = match self.law {
            SlipLaw::Triple { .. } => &SLIP_VARIABLES,
            SlipLaw::Pacejka { .. } => &PACEJKA_VARIABLES,
        };
        // Without angular states there are no angles.
        all.iter().copied().filter(|v| self.angular_state || !matches!(v.name, "angles" | "der_angles")).collect()
    }

    fn evaluate(&self, ctx: &EvalContext, out: &mut Vec<f64>) {
        let f = &ctx.frames[0];
        out.extend_from_slice(f.r_0.as_slice());
        if self.angular_state {
            let j = &ctx.joints[0];
            out.extend_from_slice(&j.q[3..6]);
            out.extend_from_slice(&j.u[3..6]);
        }
        let f_wheel_0 = contact_force(ctx, f, &self.mass);
        let start = out.len();
        let w_0 = f.rot.tr_mul(&f.w);
        let road = road_contact(&f.rot, &w_0, &f.r_0, &f.v_0, self.radius, self.surface.as_ref());
        evaluate_contact(f, &road, -1.0, f_wheel_0, out);
        // The library's f_lat and f_long of a slipping wheel push against the slip.
        out[start + 7] = -out[start + 7];
        out[start + 8] = -out[start + 8];
        let (c, e_n) = (road.frame, road.e_n);
        let e_lat = -c.e_lat;
        let v_contact = f.v_0 + w_0.cross(&c.delta);
        let (v_long, v_lat) = (v_contact.dot(&c.e_long), v_contact.dot(&e_lat));
        let w_roll = w_0.dot(&c.e_axis);
        let v_small = match self.law {
            SlipLaw::Triple { v_small, .. } | SlipLaw::Pacejka { v_small, .. } => v_small,
        };
        let along = f.v_0.dot(&c.e_long);
        let slip_ratio = if along != 0.0 { v_long / along } else { 0.0 };
        let traction = (f_wheel_0 - e_n * f_wheel_0.dot(&e_n)).norm();
        out.extend_from_slice(&[
            w_roll,
            v_long,
            v_lat,
            (v_long * v_long + v_lat * v_lat).sqrt() + v_small,
            slip_ratio,
            traction,
        ]);
        if let SlipLaw::Triple { v_adhesion_min, v_slide_min, s_adhesion, s_slide, .. } = self.law {
            let v_roll = (self.radius * w_roll).abs();
            out.extend_from_slice(&[v_adhesion_min.max(s_adhesion * v_roll), v_slide_min.max(s_slide * v_roll)]);
        }
    }
}
