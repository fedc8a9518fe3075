//! Body: a rigid body with mass, inertia tensor and one frame connector.

use super::spec::{ComponentSpec, ConnectorSpec, ParamSpec, ParamType, VarSpec};
use super::{Component, EvalContext, ParamSet, Part, StateNames};
use crate::dynamics::joint::{JointModel, RotationCoordinates};
use crate::math::{Mat3, RigidInertia, Vec3};
use crate::model::OrientationState;
use crate::Error;

pub static SPEC: ComponentSpec = ComponentSpec {
    kind: "Body",
    doc: "Rigid body with mass, inertia tensor, and one frame connector. With orientation_state Euler or \
          Quaternion it owns the orientation of what it is rigidly connected to (a free body); with None \
          (the default) its orientation comes from what it is connected to.",
    params: &[
        ParamSpec {
            name: "orientation_state",
            ty: ParamType::Enum("OrientationState", OrientationState::VARIANTS),
            default: super::Default::Enum("None"),
            unit: "",
            doc: "Orientation states of a free body: None, Euler (phi, phid) or Quaternion (Q_hat, w_a)",
        },
        ParamSpec {
            name: "sequence",
            ty: ParamType::IntVector(3),
            default: super::Default::Vector(&[1.0, 2.0, 3.0]),
            unit: "",
            doc: "Euler angle sequence used when orientation_state = Euler",
        },
        ParamSpec::integer("statePriority", 10.0, "State priority of the rotational states (kept for compatibility; states are chosen structurally)"),
        ParamSpec::boolean("initialize_orientation", true, "Give the orientation states their start values"),
        ParamSpec::integer("linearStatePriority", 1.0, "State priority of r_0 and v_0 (kept for compatibility)"),
        ParamSpec::boolean(
            "point_gravity",
            false,
            "Use a point-gravity field pointing towards the world origin instead of the uniform field g*n",
        ),
        ParamSpec::real("k", 0.1, "1/s", "Gain that pulls |Q_hat| back towards 1 (quaternion state)"),
        ParamSpec::boolean("render", true, "Draw the body in animations"),
        ParamSpec::world("color", ParamType::Vector(4), "default_body_color", 1.0, "", "Colour (RGBA)"),
        ParamSpec::real("specular_coefficient", 1.5, "", "Reflection of light in animations"),
        ParamSpec::real("m", 1.0, "kg", "mass"),
        ParamSpec::vector("r_cm", &[0.0, 0.0, 0.0], "m", "Vector from frame_a to center of mass, resolved in frame_a"),
        ParamSpec::real("I_11", 0.001, "kg.m2", "Element (1,1) of inertia tensor"),
        ParamSpec::real("I_22", 0.001, "kg.m2", "Element (2,2) of inertia tensor"),
        ParamSpec::real("I_33", 0.001, "kg.m2", "Element (3,3) of inertia tensor"),
        ParamSpec::real("I_21", 0.0, "kg.m2", "Element (2,1) of inertia tensor"),
        ParamSpec::real("I_31", 0.0, "kg.m2", "Element (3,1) of inertia tensor"),
        ParamSpec::real("I_32", 0.0, "kg.m2", "Element (3,2) of inertia tensor"),
        ParamSpec::world("radius", ParamType::Real, "default_body_diameter", 0.5, "m", "Radius of the body in animations"),
        ParamSpec::world(
            "cylinder_radius",
            ParamType::Real,
            "default_body_diameter",
            1.0 / 6.0,
            "m",
            "Radius of the cylinder from frame to COM in animations",
        ),
        ParamSpec::real("length_fraction", 1.0, "", "Fraction of the length of the body that is the cylinder from frame to COM in animations"),
    ],
    connectors: &[ConnectorSpec::frame("frame_a", "The body's frame")],
    variables: &[
        VarSpec::vector("r_0", 3, "m", "Position vector from origin of world frame to origin of frame_a"),
        VarSpec::vector("v_0", 3, "m/s", "Absolute velocity of frame_a, resolved in world frame (= D(r_0))"),
        VarSpec::vector("a_0", 3, "m/s2", "Absolute acceleration of frame_a resolved in world frame (= D(v_0))"),
        VarSpec::vector("g_0", 3, "m/s2", "gravity acceleration"),
        VarSpec::vector("w_a", 3, "rad/s", "Absolute angular velocity of frame_a resolved in frame_a"),
        VarSpec::vector("z_a", 3, "rad/s2", "Absolute angular acceleration of frame_a resolved in frame_a"),
        VarSpec::vector("v_cm_0", 3, "m/s", "Absolute velocity of the center of mass, resolved in world frame"),
        VarSpec::scalar("KE", "J", "Kinetic energy of the body, translational plus rotational"),
        VarSpec::scalar("PE", "J", "Potential energy of the body in a uniform gravity field, zero when the center of mass is at the world origin"),
        VarSpec::vector("Q", 4, "", "Unit quaternion with [w,i,j,k] (orientation_state = Quaternion)"),
        VarSpec::vector("Q_hat", 4, "", "Non-unit quaternion with [w,i,j,k] (orientation_state = Quaternion)"),
        VarSpec::vector("Q_hat_d", 4, "1/s", "der(Q_hat) (orientation_state = Quaternion)"),
        VarSpec::scalar("n_q", "", "|Q_hat|^2 (orientation_state = Quaternion)"),
        VarSpec::scalar("c_q", "1/s", "k (1 - n_q) (orientation_state = Quaternion)"),
        VarSpec::vector("phi", 3, "rad", "Euler angles (orientation_state = Euler)"),
        VarSpec::vector("phid", 3, "rad/s", "der(phi) (orientation_state = Euler)"),
        VarSpec::vector("phidd", 3, "rad/s2", "der(phid) (orientation_state = Euler)"),
    ],
    build,
};

const QUATERNION_STATES: StateNames = StateNames { q: &[("r_0", 3), ("Q_hat", 4)], u: &[("v_0", 3), ("w_a", 3)] };
const EULER_STATES: StateNames = StateNames { q: &[("r_0", 3), ("phi", 3)], u: &[("v_0", 3), ("phid", 3)] };

/// The mass properties shared by the body-like components.
#[derive(Clone, Copy, Debug)]
pub struct MassProperties {
    pub m: f64,
    pub r_cm: Vec3,
    /// Inertia about the centre of mass, resolved in frame_a.
    pub inertia: Mat3,
}

impl MassProperties {
    /// `m`, `r_cm` and `I_11 ... I_32` of a component, checked: the mass must
    /// not be negative and the inertia must be positive semi-definite.
    pub fn from_params(p: &ParamSet) -> Result<Self, Error> {
        let m = p.non_negative("m", true)?;
        let (i11, i22, i33) = (p.real("I_11"), p.real("I_22"), p.real("I_33"));
        let (i21, i31, i32) = (p.real("I_21"), p.real("I_31"), p.real("I_32"));
        let inertia = Mat3::new(i11, i21, i31, i21, i22, i32, i31, i32, i33);
        check_inertia(p, &inertia)?;
        Ok(Self { m, r_cm: p.vec3("r_cm"), inertia })
    }

    pub fn rigid_inertia(&self) -> RigidInertia {
        RigidInertia::from_com(self.m, self.r_cm, self.inertia)
    }
}

/// An inertia tensor must be positive semi-definite.
pub fn check_inertia(p: &ParamSet, inertia: &Mat3) -> Result<(), Error> {
    let eigen = inertia.symmetric_eigenvalues();
    let scale = eigen.iter().fold(0.0f64, |a, x| a.max(x.abs()));
    if eigen.iter().any(|&e| e < -1e-12 * scale.max(1e-300)) {
        return Err(p.invalid("I_11", format!(
            "the inertia tensor [I_11 I_21 I_31; I_21 I_22 I_32; I_31 I_32 I_33] must be positive semi-definite, but its principal moments are {:.4}, {:.4}, {:.4}",
            eigen[0], eigen[1], eigen[2]
        )));
    }
    Ok(())
}

/// The states and joint model a free body's `orientation_state` asks for.
pub fn owner_of(p: &ParamSet) -> Result<Option<(JointModel, StateNames)>, Error> {
    Ok(match p.variant("orientation_state") {
        "Quaternion" => Some((JointModel::Free(RotationCoordinates::Quaternion { k: p.real("k") }), QUATERNION_STATES)),
        "Euler" => {
            Some((JointModel::Free(RotationCoordinates::Euler { sequence: p.sequence("sequence")? }), EULER_STATES))
        }
        _ => None,
    })
}

#[derive(Debug)]
struct Body {
    mass: MassProperties,
    point_gravity: bool,
    owner: Option<(JointModel, StateNames)>,
}

fn build(p: &ParamSet) -> Result<Box<dyn Component>, Error> {
    Ok(Box::new(Body {
        mass: MassProperties::from_params(p)?,
        point_gravity: p.boolean("point_gravity"),
        owner: owner_of(p)?,
    }))
}

impl Component for Body {
    fn parts(&self) -> Vec<Part> {
        let mut parts =
            vec![Part::Mass { frame: 0, inertia: self.mass.rigid_inertia(), point_gravity: self.point_gravity }];
        if let Some((model, states)) = self.owner {
            parts.push(Part::Owner { frame: 0, model, states });
        }
        parts
    }

    fn variables(&self) -> Vec<VarSpec> {
        let wanted: &[&str] = match self.owner {
            Some((JointModel::Free(RotationCoordinates::Quaternion { .. }), _)) => {
                &["Q", "Q_hat", "Q_hat_d", "n_q", "c_q"]
            }
            Some((JointModel::Free(RotationCoordinates::Euler { .. }), _)) => &["phi", "phid", "phidd"],
            _ => &[],
        };
        let common = ["r_0", "v_0", "a_0", "g_0", "w_a", "z_a", "v_cm_0", "KE", "PE"];
        SPEC.variables.iter().filter(|v| common.contains(&v.name) || wanted.contains(&v.name)).copied().collect()
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
        if let Some((JointModel::Free(rot), _)) = self.owner {
            let joint = &ctx.joints[0];
            match rot {
                RotationCoordinates::Quaternion { k } => {
                    let q_hat = &joint.q[3..7];
                    let n_q: f64 = q_hat.iter().map(|x| x * x).sum();
                    out.extend(q_hat.iter().map(|x| x / n_q.sqrt()));
                    out.extend_from_slice(q_hat);
                    out.extend_from_slice(&joint.qdot[3..7]);
                    out.extend([n_q, k * (1.0 - n_q)]);
                }
                RotationCoordinates::Euler { .. } => {
                    out.extend_from_slice(&joint.q[3..6]);
                    out.extend_from_slice(&joint.u[3..6]);
                    out.extend_from_slice(&joint.udot[3..6]);
                }
            }
        }
    }
}
