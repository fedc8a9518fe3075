//! PlanarMechanics.OneDOFRollingWheelJoint and OneDOFSlippingWheelJoint:
//! a planar wheel on the ground line y = 0.
//!
//! The wheel's frame_a is its centre, turning with it about z. Both keep the
//! centre at `y = radius`; the rolling wheel's contact point does not slip
//! (a wheel turning clockwise, `phi_roll = -phi` growing, rolls towards
//! +x), the slipping wheel's is pushed against its slip by the library's
//! friction law times the normal force.

use super::super::spec::{concat, ComponentSpec, ConnectorType, ParamSpec, ParamType, VarSpec};
use super::super::wheel_common::{positive, wheel_shapes};
use super::super::{
    Component, ConstraintKind, EvalContext, ForceLaw, ParamSet, Part, RotationLock, SlipLaw, WheelContact,
};
use super::{RENDER, SPECULAR, Z_POSITION};
use crate::math::rotation::planar_angle;
use crate::math::{Transform, Vec3};
use crate::Error;

/// The library's slip law's parameters (no defaults).
const SLIP: [ParamSpec; 6] = [
    ParamSpec::required("vAdhesion_min", ParamType::Real, "m/s", "Least slip speed of full adhesion"),
    ParamSpec::required("vSlide_min", ParamType::Real, "m/s", "Least slip speed of full sliding"),
    ParamSpec::required("sAdhesion", ParamType::Real, "", "Adhesion slip as a fraction of the rolling speed"),
    ParamSpec::required("sSlide", ParamType::Real, "", "Sliding slip as a fraction of the rolling speed"),
    ParamSpec::required("mu_A", ParamType::Real, "", "Friction coefficient at adhesion"),
    ParamSpec::required("mu_S", ParamType::Real, "", "Friction coefficient when sliding"),
];

/// The radius, then how the wheel is drawn.
const RADIUS_AND_LOOK: [ParamSpec; 7] = [
    ParamSpec::real("radius", 0.1, "m", "Radius of the wheel"),
    ParamSpec::derived("rim_diameter", ParamType::Real, "radius / 3", "m", "Diameter of the rim drawn"),
    ParamSpec::derived("wheel_width", ParamType::Real, "radius / 4", "m", "Width of the wheel drawn"),
    Z_POSITION,
    RENDER,
    ParamSpec::vector("color", &[1.0, 0.0, 0.0, 1.0], "", "Colour (RGBA)"),
    SPECULAR,
];

const CONNECTORS: &[super::super::spec::ConnectorSpec] = &[
    super::super::spec::ConnectorSpec::frame_2d("frame_a", "The wheel's centre, turning with it"),
    super::super::spec::ConnectorSpec::internal("ground", ConnectorType::Frame),
    super::super::spec::ConnectorSpec::internal("axle_height", ConnectorType::Frame),
];

const ROLLING_VARIABLES: &[VarSpec] = &[
    VarSpec::scalar("x", "m", "x of the wheel's centre"),
    VarSpec::scalar("v", "m/s", "der(x)"),
    VarSpec::scalar("phi_roll", "rad", "Angle rolled (clockwise): x = radius phi_roll + x0"),
    VarSpec::scalar("w_roll", "rad/s", "der(phi_roll)"),
    VarSpec::scalar("f_n", "N", "Normal force of the ground on the wheel"),
    VarSpec::scalar("f_long", "N", "Force of the ground on the wheel along x"),
];

pub static ROLLING: ComponentSpec = ComponentSpec {
    kind: "PlanarMechanics.OneDOFRollingWheelJoint",
    doc: "A planar wheel of radius `radius` rolling without slipping on the ground line y = 0: frame_a (the \
          centre, turning with the wheel) stays at y = radius and x = radius phi_roll + x0, with phi_roll the \
          clockwise angle rolled. Give the wheel mass with a PlanarMechanics.Body on frame_a.",
    params: &concat::<ParamSpec, 8>(
        &RADIUS_AND_LOOK,
        &[ParamSpec::real("x0", 0.0, "m", "x of the centre where phi_roll is zero")],
    ),
    connectors: CONNECTORS,
    variables: ROLLING_VARIABLES,
    build: |p| {
        Ok(Box::new(Wheel { radius: positive(p, "radius", "the wheel's radius")?, x0: p.real("x0"), law: None }))
    },
    shapes,
};

const SLIPPING_VARIABLES: &[VarSpec] = &[
    VarSpec::scalar("x", "m", "x of the wheel's centre"),
    VarSpec::scalar("v", "m/s", "der(x)"),
    VarSpec::scalar("phi_roll", "rad", "Angle rolled (clockwise, -frame_a.phi, in (-pi, pi])"),
    VarSpec::scalar("w_roll", "rad/s", "der(phi_roll)"),
    VarSpec::scalar("v_slip_long", "m/s", "Slip speed of the contact point along x: v - radius w_roll"),
    VarSpec::scalar("f_n", "N", "Normal force of the ground on the wheel"),
    VarSpec::scalar("f_long", "N", "Friction force of the ground on the wheel along x"),
];

pub static SLIPPING: ComponentSpec = ComponentSpec {
    kind: "PlanarMechanics.OneDOFSlippingWheelJoint",
    doc: "A planar wheel of radius `radius` on the ground line y = 0 that may slip: frame_a (the centre, turning \
          with the wheel) stays at y = radius, and the ground pushes the contact point against its slip with \
          the normal force times mu = limit_S_triple(vAdhesion, vSlide, mu_A, mu_S, |v_slip| + 1e-4), \
          vAdhesion = max(vAdhesion_min, sAdhesion |radius w_roll|), vSlide likewise.",
    params: &concat::<ParamSpec, 13>(&SLIP, &RADIUS_AND_LOOK),
    connectors: CONNECTORS,
    variables: SLIPPING_VARIABLES,
    build: build_slipping,
    shapes,
};

fn build_slipping(p: &ParamSet) -> Result<Box<dyn Component>, Error> {
    Ok(Box::new(Wheel { radius: positive(p, "radius", "the wheel's radius")?, x0: 0.0, law: Some(slip_law(p)?) }))
}

/// The library's slip law from the wheel's parameters.
fn slip_law(p: &ParamSet) -> Result<SlipLaw, Error> {
    Ok(SlipLaw::Triple {
        v_adhesion_min: positive(p, "vAdhesion_min", "the adhesion speed")?,
        v_slide_min: positive(p, "vSlide_min", "the sliding speed")?,
        s_adhesion: p.non_negative("sAdhesion", true)?,
        s_slide: p.non_negative("sSlide", true)?,
        mu_a: p.non_negative("mu_A", true)?,
        mu_s: p.non_negative("mu_S", true)?,
        v_small: 1e-4,
    })
}

fn shapes(p: &ParamSet) -> Vec<super::super::shapes::LocalShape> {
    if !p.boolean("render") {
        return Vec::new();
    }
    let radius = p.real("radius");
    let width = p.real_opt("wheel_width").unwrap_or(radius / 4.0);
    wheel_shapes("frame_a", radius, width, p.color("color"), p.real("specular_coefficient"))
}

#[derive(Debug)]
struct Wheel {
    radius: f64,
    x0: f64,
    /// The slipping wheel's friction law; `None`: it rolls.
    law: Option<SlipLaw>,
}

impl Component for Wheel {
    fn parts(&self) -> Vec<Part> {
        // frame_a 0, ground 1, axle_height 2 (at the height of the axle).
        let height = Transform::translation(Vec3::new(0.0, self.radius, 0.0));
        let mut parts =
            vec![Part::Ground { frame: 1, pose: Transform::IDENTITY }, Part::Ground { frame: 2, pose: height }];
        match self.law {
            // The 3-D slipping contact keeps the rim on the ground itself.
            Some(law) => parts.push(Part::Constraint {
                a: 1,
                b: 0,
                kind: ConstraintKind::Wheel {
                    radius: self.radius,
                    contact: WheelContact::Slipping { law, road: None },
                },
            }),
            None => {
                let directions = [Vec3::y(), Vec3::zeros(), Vec3::zeros()];
                parts.extend([
                    Part::Constraint {
                        a: 2,
                        b: 0,
                        kind: ConstraintKind::Locks { rotation: RotationLock::Free, directions, count: 1 },
                    },
                    Part::Constraint {
                        a: 1,
                        b: 0,
                        kind: ConstraintKind::Wheel {
                            radius: self.radius,
                            contact: WheelContact::Vertical { lateral: false },
                        },
                    },
                ]);
            }
        }
        parts
    }

    fn variables(&self) -> Vec<VarSpec> {
        if self.law.is_some() { SLIPPING_VARIABLES } else { ROLLING_VARIABLES }.to_vec()
    }

    fn evaluate(&self, ctx: &EvalContext, out: &mut Vec<f64>) {
        let a = &ctx.frames[0];
        // The ground's push on the wheel: the opposite of the cut force on this joint.
        let on_wheel = -a.rot.tr_mul(&a.f);
        let (x, v, w_roll) = (a.r_0.x, a.v_0.x, -a.w.z);
        match self.law {
            None => out.extend([x, v, (x - self.x0) / self.radius, w_roll, on_wheel.y, on_wheel.x]),
            Some(_) => {
                out.extend([x, v, -planar_angle(&a.rot), w_roll, v - self.radius * w_roll, on_wheel.y, on_wheel.x])
            }
        }
    }
}

const SLIP_BASED_VARIABLES: &[VarSpec] = &[
    VarSpec::scalar(
        "f_long",
        "N",
        "Longitudinal force of the wheel on the ground (the ground's on the wheel is its opposite)",
    ),
    VarSpec::scalar("f_lat", "N", "Lateral force of the wheel on the ground"),
    VarSpec::scalar("w_roll", "rad/s", "Rolling speed of flange_a"),
    VarSpec::vector("e0", 2, "", "Rolling direction, world coordinates"),
];

pub static SLIP_BASED: ComponentSpec = ComponentSpec {
    kind: "PlanarMechanics.SlipBasedWheelJoint",
    doc: "A planar wheel that slips: frame_a is its steering frame (it does not turn with the wheel), flange_a its \
          rolling axis. The ground pushes frame_a against the slip of the contact (frame_a's velocity less \
          radius w_roll along r, turned with frame_a) with the normal force max(0, N + dynamicLoad) times \
          mu = limit_S_triple(vAdhesion, vSlide, mu_A, mu_S, |v_slip| + 1e-4), and brakes the flange by the \
          longitudinal force at the radius. Put the wheel's spin inertia on flange_a.",
    params: &concat::<ParamSpec, 15>(
        &[
            ParamSpec::vector("r", &[1.0, 0.0], "", "Rolling direction, resolved in frame_a"),
            ParamSpec::required("N", ParamType::Real, "N", "Base normal load"),
        ],
        &concat::<ParamSpec, 13>(&SLIP, &RADIUS_AND_LOOK),
    ),
    connectors: &[
        super::super::spec::ConnectorSpec::frame_2d("frame_a", "The wheel's steering frame"),
        super::super::spec::ConnectorSpec::flange("flange_a", ConnectorType::Spline, "The wheel's rolling axis"),
        super::super::spec::ConnectorSpec::input("dynamicLoad", "Normal load added to N"),
    ],
    variables: SLIP_BASED_VARIABLES,
    build: build_slip_based,
    shapes: super::super::shapes::none,
};

fn build_slip_based(p: &ParamSet) -> Result<Box<dyn Component>, Error> {
    let r = super::in_plane(p, "r");
    if r.norm() == 0.0 {
        return Err(p.invalid("r", "the rolling direction must not be zero"));
    }
    let radius = positive(p, "radius", "the wheel's radius")?;
    Ok(Box::new(SlipBased { radius, axis: r.normalize(), n: p.real("N"), law: slip_law(p)? }))
}

#[derive(Debug)]
struct SlipBased {
    radius: f64,
    /// Rolling direction in frame_a.
    axis: Vec3,
    n: f64,
    law: SlipLaw,
}

impl Component for SlipBased {
    fn parts(&self) -> Vec<Part> {
        // One element on the steering frame (0) and the rolling flange (1),
        // reading dynamicLoad (2).
        let law = ForceLaw::PlanarSlip { radius: self.radius, axis: self.axis, n: self.n, law: self.law };
        vec![Part::Force {
            a: None,
            b: 0,
            law,
            inputs: [Some(2), None, None, None, None, None],
            flanges: [None, Some(1)],
        }]
    }

    fn variables(&self) -> Vec<VarSpec> {
        SLIP_BASED_VARIABLES.to_vec()
    }

    fn evaluate(&self, ctx: &EvalContext, out: &mut Vec<f64>) {
        let a = &ctx.frames[0];
        let e0 = a.rot.tr_mul(&self.axis);
        let e_lat = Vec3::new(-e0.y, e0.x, 0.0);
        // The ground's force on the wheel is what the wheel's frame gets:
        // the opposite of the cut force on this component there.
        let on_wheel = -a.rot.tr_mul(&a.f);
        out.extend([-on_wheel.dot(&e0), -on_wheel.dot(&e_lat), ctx.flanges[1].v, e0.x, e0.y]);
    }
}
