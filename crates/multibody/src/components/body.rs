//! Body: a rigid body with mass, inertia tensor and one frame connector.
//! The shaped bodies (BodyShape, BodyBox, BodyCylinder) are the same body
//! with a second frame.

use super::orientation::{self, INITIALIZE_ORIENTATION, K, SEQUENCE, STATE_PRIORITY};
use super::shapes::{look, LocalShape, ShapeKind};
use super::spec::{concat, ComponentSpec, ConnectorSpec, ParamSpec, ParamType, VarSpec};
use super::{Component, EvalContext, ParamSet, Part, StateNames};
use crate::math::{Mat3, RigidInertia, Transform, Vec3};
use crate::system::joint::{JointModel, RotationCoordinates};
use crate::Error;

/// Parameters every body-like component shares, after the kind's own.
pub const COMMON_PARAMS: [ParamSpec; 10] = [
    orientation::orientation_state_param(
        "None",
        "Orientation states of a free body: None (from what it is connected to), Euler (phi, phid) or Quaternion (Q_hat, w_a)",
    ),
    SEQUENCE,
    STATE_PRIORITY,
    INITIALIZE_ORIENTATION,
    ParamSpec::integer("linearStatePriority", 1.0, "State priority of r_0 and v_0 (kept for compatibility)"),
    ParamSpec::boolean(
        "point_gravity",
        false,
        "Use a point-gravity field pointing towards the world origin instead of the uniform field g*n",
    ),
    K,
    ParamSpec::boolean("render", true, "Draw the body in animations"),
    ParamSpec::world("color", ParamType::Vector(4), "default_body_color", 1.0, "", "Colour (RGBA)"),
    ParamSpec::real("specular_coefficient", 1.5, "", "Reflection of light in animations"),
];

/// The inertia parameters, about the centre of mass, resolved in frame_a
/// (in the order [`ImpossibleInertia::of`] takes them).
pub const INERTIA_PARAMS: [ParamSpec; 6] = [
    ParamSpec::real("I_11", 0.001, "kg.m2", "Element (1,1) of inertia tensor"),
    ParamSpec::real("I_22", 0.001, "kg.m2", "Element (2,2) of inertia tensor"),
    ParamSpec::real("I_33", 0.001, "kg.m2", "Element (3,3) of inertia tensor"),
    ParamSpec::real("I_21", 0.0, "kg.m2", "Element (2,1) of inertia tensor"),
    ParamSpec::real("I_31", 0.0, "kg.m2", "Element (3,1) of inertia tensor"),
    ParamSpec::real("I_32", 0.0, "kg.m2", "Element (3,2) of inertia tensor"),
];

const MOTION_VARIABLES: [VarSpec; 9] = [
    VarSpec::vector("r_0", 3, "m", "Position vector from origin of world frame to origin of frame_a"),
    VarSpec::vector("v_0", 3, "m/s", "Absolute velocity of frame_a, resolved in world frame (= D(r_0))"),
    VarSpec::vector("a_0", 3, "m/s2", "Absolute acceleration of frame_a resolved in world frame (= D(v_0))"),
    VarSpec::vector("g_0", 3, "m/s2", "gravity acceleration"),
    VarSpec::vector("w_a", 3, "rad/s", "Absolute angular velocity of frame_a resolved in frame_a"),
    VarSpec::vector("z_a", 3, "rad/s2", "Absolute angular acceleration of frame_a resolved in frame_a"),
    VarSpec::vector("v_cm_0", 3, "m/s", "Absolute velocity of the center of mass, resolved in world frame"),
    VarSpec::scalar("KE", "J", "Kinetic energy of the body, translational plus rotational"),
    VarSpec::scalar(
        "PE",
        "J",
        "Potential energy of the body in a uniform gravity field, zero when the center of mass is at the world origin",
    ),
];

/// Every variable a body-like component can have.
pub static VARIABLES: [VarSpec; 17] = concat(&MOTION_VARIABLES, orientation::VARIABLES);

pub static SPEC: ComponentSpec = ComponentSpec {
    kind: "Body",
    doc: "Rigid body with mass, inertia tensor, and one frame connector. With orientation_state Euler or \
          Quaternion it owns the orientation of what it is rigidly connected to (a free body); with None \
          (the default) its orientation comes from what it is connected to.",
    params: &PARAMS,
    connectors: &[ConnectorSpec::frame("frame_a", "The body's frame")],
    variables: &VARIABLES,
    build,
    shapes,
};

/// The shaped bodies' look: `kind` from `start` along `length` (frame_a
/// coordinates), and a sphere at the centre of mass.
pub fn shaped_body_shapes(
    p: &ParamSet,
    kind: ShapeKind,
    start: Vec3,
    length: Vec3,
    width: f64,
    height: f64,
) -> Vec<LocalShape> {
    if !p.boolean("render") {
        return Vec::new();
    }
    let (color, specular) = look(p);
    let mut shape = LocalShape::in_frame(kind, "frame_a", start, length, width, height).colored(color, specular);
    // A box keeps its width along width_dir (made perpendicular to its length).
    let given_width_dir = p.spec.param("width_dir").and_then(|_| p.vec3_opt("width_dir"));
    if let (Some(dir), super::shapes::Placement::InFrame { width_dir, .. }) = (given_width_dir, &mut shape.placement) {
        let e = length.try_normalize(1e-12).unwrap_or_else(Vec3::x);
        let w = dir - e * e.dot(&dir);
        if w.norm() > 1e-10 {
            *width_dir = w.normalize();
        }
    }
    vec![shape]
}

/// A sphere at the centre of mass and a cylinder from frame_a towards it.
fn shapes(p: &ParamSet) -> Vec<LocalShape> {
    if !p.boolean("render") {
        return Vec::new();
    }
    let (color, specular) = look(p);
    let r_cm = p.vec3("r_cm");
    let radius = p.real("radius");
    let mut out = vec![LocalShape::in_frame(ShapeKind::Sphere, "frame_a", r_cm, r_cm, 2.0 * radius, 2.0 * radius)
        .colored(color, specular)];
    if r_cm.norm() > 1e-10 {
        let length = r_cm * p.real("length_fraction");
        let d = 2.0 * p.real("cylinder_radius");
        out.push(
            LocalShape::in_frame(ShapeKind::Cylinder, "frame_a", Vec3::zeros(), length, d, d).colored(color, specular),
        );
    }
    out
}

static PARAMS: [ParamSpec; 21] = concat(
    &COMMON_PARAMS,
    &concat::<ParamSpec, 11>(
        &[
            ParamSpec::real("m", 1.0, "kg", "mass"),
            ParamSpec::vector(
                "r_cm",
                &[0.0, 0.0, 0.0],
                "m",
                "Vector from frame_a to center of mass, resolved in frame_a",
            ),
        ],
        &concat::<ParamSpec, 9>(
            &INERTIA_PARAMS,
            &[
                ParamSpec::world(
                    "radius",
                    ParamType::Real,
                    "default_body_diameter",
                    0.5,
                    "m",
                    "Radius of the body in animations",
                ),
                ParamSpec::world(
                    "cylinder_radius",
                    ParamType::Real,
                    "default_body_diameter",
                    1.0 / 6.0,
                    "m",
                    "Radius of the cylinder from frame to COM in animations",
                ),
                ParamSpec::real(
                    "length_fraction",
                    1.0,
                    "",
                    "Fraction of the length of the body that is the cylinder from frame to COM in animations",
                ),
            ],
        ),
    ),
);

const QUATERNION_STATES: StateNames = StateNames { q: &[("r_0", 3), ("Q_hat", 4)], u: &[("v_0", 3), ("w_a", 3)] };
const EULER_STATES: StateNames = StateNames { q: &[("r_0", 3), ("phi", 3)], u: &[("v_0", 3), ("phid", 3)] };

/// An inertia tensor no rigid body can have: its largest principal moment
/// is more than the sum of the other two. Every mass distribution has
/// `I_3 <= I_1 + I_2` (with equality for flat bodies), so such data is a
/// mistake, but a tolerated one (Modelica's industrial robot has a link
/// with the moments 0.001, 1.16, 0.001): the model runs with it, with a
/// warning.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ImpossibleInertia {
    /// The principal moments, smallest first.
    pub moments: [f64; 3],
}

impl ImpossibleInertia {
    /// Checks `[I_11, I_22, I_33, I_21, I_31, I_32]`. An excess within
    /// 1e-9 of the trace is rounding (thin rods and flat plates reach the
    /// bound exactly). An inertia that is not positive semi-definite is
    /// another error, refused where the body is built.
    pub fn of([i11, i22, i33, i21, i31, i32]: [f64; 6]) -> Option<ImpossibleInertia> {
        let inertia = Mat3::new(i11, i21, i31, i21, i22, i32, i31, i32, i33);
        if !inertia.iter().all(|x| x.is_finite()) {
            return None;
        }
        let e = inertia.symmetric_eigenvalues();
        let mut moments = [e[0], e[1], e[2]];
        moments.sort_by(f64::total_cmp);
        let trace = moments.iter().map(|x| x.abs()).sum::<f64>();
        (moments[2] - (moments[0] + moments[1]) > 1e-9 * trace).then_some(ImpossibleInertia { moments })
    }

    /// "its principal moments 0.001, 0.001 and 1.16 kg.m2 break the
    /// triangle inequality (1.16 > 0.001 + 0.001)".
    pub fn describe(&self) -> String {
        let [a, b, c] = self.moments.map(significant);
        format!("its principal moments {a}, {b} and {c} kg.m2 break the triangle inequality ({c} > {a} + {b})")
    }
}

/// `x` to 6 significant digits, without trailing zeros.
fn significant(x: f64) -> String {
    if x == 0.0 || !x.is_finite() {
        return format!("{x}");
    }
    let magnitude = x.abs().log10().floor() as i32;
    if !(-5..=6).contains(&magnitude) {
        return format!("{x:.5e}");
    }
    let decimals = (5 - magnitude).max(0) as usize;
    let s = format!("{x:.decimals$}");
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

/// Mass, centre of mass and inertia about the centre of mass (resolved in frame_a).
#[derive(Clone, Copy, Debug)]
pub struct MassProperties {
    pub m: f64,
    pub r_cm: Vec3,
    pub inertia: Mat3,
}

impl MassProperties {
    /// `m`, `r_cm` and `I_11 ... I_32` of a component, checked: the mass must
    /// not be negative and the inertia must be positive semi-definite.
    pub fn from_params(p: &ParamSet, r_cm: Vec3) -> Result<Self, Error> {
        let m = p.non_negative("m", true)?;
        let (i11, i22, i33) = (p.real("I_11"), p.real("I_22"), p.real("I_33"));
        let (i21, i31, i32) = (p.real("I_21"), p.real("I_31"), p.real("I_32"));
        let inertia = Mat3::new(i11, i21, i31, i21, i22, i32, i31, i32, i33);
        let eigen = inertia.symmetric_eigenvalues();
        let scale = eigen.iter().fold(0.0f64, |a, x| a.max(x.abs()));
        if eigen.iter().any(|&e| e < -1e-12 * scale.max(f64::MIN_POSITIVE)) {
            return Err(p.invalid(
                "I_11",
                format!(
                    "the inertia tensor [I_11 I_21 I_31; I_21 I_22 I_32; I_31 I_32 I_33] must be positive semi-definite, but its principal moments are {:.4}, {:.4}, {:.4}",
                    eigen[0], eigen[1], eigen[2]
                ),
            ));
        }
        // A centre of mass far out makes the inertia about frame_a overflow,
        // which would read as a body without mass.
        if !(m * r_cm.norm_squared() + scale).is_finite() {
            return Err(p.invalid(
                "r_cm",
                format!(
                    "the inertia about frame_a overflows (m |r_cm|^2 = {:e}); give r_cm and m in metres and \
                     kilograms within a physical range",
                    m * r_cm.norm_squared()
                ),
            ));
        }
        Ok(Self { m, r_cm, inertia })
    }
}

/// A rigid body, optionally free, optionally with a second frame at `r`.
#[derive(Debug)]
pub struct RigidBody {
    pub mass: MassProperties,
    pub point_gravity: bool,
    pub rotation: Option<RotationCoordinates>,
    /// frame_b's position in frame_a (shaped bodies).
    pub frame_b: Option<Vec3>,
}

impl RigidBody {
    /// The body-like component of validated parameters (`COMMON_PARAMS` among them).
    pub fn new(p: &ParamSet, mass: MassProperties, frame_b: Option<Vec3>) -> Result<Self, Error> {
        Ok(Self { mass, point_gravity: p.boolean("point_gravity"), rotation: orientation::coordinates(p)?, frame_b })
    }
}

fn build(p: &ParamSet) -> Result<Box<dyn Component>, Error> {
    let mass = MassProperties::from_params(p, p.vec3("r_cm"))?;
    Ok(Box::new(RigidBody::new(p, mass, None)?))
}

impl Component for RigidBody {
    fn parts(&self) -> Vec<Part> {
        let MassProperties { m, r_cm, inertia } = self.mass;
        let mut parts = vec![Part::Mass {
            frame: 0,
            inertia: RigidInertia::from_com(m, r_cm, inertia),
            point_gravity: self.point_gravity,
        }];
        if let Some(rot) = self.rotation {
            let states = match rot {
                RotationCoordinates::Quaternion { .. } => QUATERNION_STATES,
                RotationCoordinates::Euler { .. } => EULER_STATES,
            };
            parts.push(Part::Owner { frame: 0, model: JointModel::Free(rot), states, fallback: false });
        }
        if let Some(r) = self.frame_b {
            parts.push(Part::Rigid { a: 0, b: 1, pose: Transform::translation(r) });
        }
        parts
    }

    fn variables(&self) -> Vec<VarSpec> {
        MOTION_VARIABLES.iter().copied().chain(orientation::variables(self.rotation)).collect()
    }

    fn evaluate(&self, ctx: &EvalContext, out: &mut Vec<f64>) {
        let frame = &ctx.frames[0];
        let MassProperties { m, r_cm, inertia } = self.mass;
        let r_cm_0 = frame.rot.tr_mul(&r_cm);
        let g_0 = ctx.world.gravity(&(frame.r_0 + r_cm_0), self.point_gravity);
        let v_cm_0 = frame.v_0 + frame.rot.tr_mul(&frame.w.cross(&r_cm));
        let ke = 0.5 * m * v_cm_0.norm_squared() + 0.5 * frame.w.dot(&(inertia * frame.w));
        let pe = -m * g_0.dot(&(frame.r_0 + r_cm_0));
        for v in [frame.r_0, frame.v_0, frame.a_0, g_0, frame.w, frame.z, v_cm_0] {
            out.extend_from_slice(v.as_slice());
        }
        out.extend([ke, pe]);
        if let Some(rot) = self.rotation {
            orientation::evaluate(rot, &ctx.joints[0], 3, 3, out);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::ImpossibleInertia;

    #[test]
    fn impossible_inertias_are_told_from_flat_and_thin_bodies() {
        // Modelica's industrial robot: the moments 0.001, 1.16, 0.001.
        let robot = ImpossibleInertia::of([0.001, 1.16, 0.001, 0.0, 0.0, 0.0]).unwrap();
        assert_eq!(robot.moments, [0.001, 0.001, 1.16]);
        assert_eq!(
            robot.describe(),
            "its principal moments 0.001, 0.001 and 1.16 kg.m2 break the triangle inequality (1.16 > 0.001 + 0.001)"
        );
        // A thin rod (0, I, I) and a flat plate (a, b, a + b) reach the bound.
        assert_eq!(ImpossibleInertia::of([0.0, 0.5, 0.5, 0.0, 0.0, 0.0]), None);
        assert_eq!(ImpossibleInertia::of([1.0, 2.0, 3.0, 0.0, 0.0, 0.0]), None);
        // The plate turned about z by 30 degrees (rounding in every element).
        let (c, s) = (30f64.to_radians().cos(), 30f64.to_radians().sin());
        let (xx, yy, xy) = (c * c + 2.0 * s * s, s * s + 2.0 * c * c, (1.0 - 2.0) * c * s);
        assert_eq!(ImpossibleInertia::of([xx, yy, 3.0, xy, 0.0, 0.0]), None);
        // Off-diagonal elements can break it too.
        assert!(ImpossibleInertia::of([1.0, 1.0, 1.0, 0.9, 0.0, 0.0]).is_some());
        assert_eq!(ImpossibleInertia::of([0.0; 6]), None);
    }
}
