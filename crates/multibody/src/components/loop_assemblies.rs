//! Joint assemblies that close a kinematic loop: JointRRR, JointRRP,
//! JointUSR, JointUSP, JointSSR and JointSSP.
//!
//! Modelica and the Dyad library solve their closure in closed form. Here
//! each is built from its elementary parts (revolutes, a prismatic, rods,
//! a rod of fixed length between two ball joints): the loop it closes is
//! cut and kept by the constraint solver like any other, which gives the
//! same motion (the assemblies have no mass) at the cost of a few
//! constraint rows. The branch is the one the start configuration is on.
//!
//! Connectors, in this order: frame_a, frame_b, frame_ia (not for the SS
//! kinds), frame_ib, frame_im, axis, bearing, then the internal frames.
//! The joint at frame_b is driven through axis and bearing.

use super::spec::{ComponentSpec, ConnectorSpec, ConnectorType, ParamSpec};
use super::{AxisFlanges, Component, ConstraintKind, ParamSet, Part, PrismaticBranch, RotationLock, StateNames};
use crate::math::{planar_rotation, Transform, Vec3};
use crate::system::JointModel;
use crate::Error;

const POSITIVE_BRANCH: ParamSpec = ParamSpec::boolean(
    "positive_branch",
    true,
    "Which closure the loop starts on (JointRRP: true, the slider the farther along n_b of the two places the \
     rod reaches; the other kinds keep the start configuration's)",
);
const N_A: ParamSpec = ParamSpec::vector(
    "n_a",
    &[0.0, 0.0, 1.0],
    "",
    "Axis of the revolutes at frame_a and in the middle, resolved in frame_a",
);
const R_ROD1_IA: ParamSpec =
    ParamSpec::vector("rRod1_ia", &[1.0, 0.0, 0.0], "m", "From frame_a to the middle revolute, in frame_ia");
const ROD1_LENGTH: ParamSpec = ParamSpec::real("rod1_length", 1.0, "m", "Length of the rod between the ball joints");
const HAS_MASS: ParamSpec =
    ParamSpec::boolean("has_mass", false, "Whether rod 1 carries a point mass (not supported yet)");
const ROD1_MASS: ParamSpec = ParamSpec::real("rod1_mass", 0.0, "kg", "Point mass in the middle of rod 1");
const ROD_RADIUS: ParamSpec = ParamSpec::real("rod_radius", 0.05, "m", "Radius of the rods in animations");
const ROD_COLOR: ParamSpec = ParamSpec::vector("rod_color", &[0.5, 0.0, 0.5, 1.0], "", "Colour of the rods (RGBA)");

const FRAME_A: ConnectorSpec = ConnectorSpec::frame("frame_a", "The outer side of the first joint");
const FRAME_B: ConnectorSpec = ConnectorSpec::frame("frame_b", "The outer side of the joint at frame_b");
const FRAME_IA: ConnectorSpec = ConnectorSpec::frame("frame_ia", "Fixed in rod 1 at frame_a's origin");
const FRAME_IB: ConnectorSpec = ConnectorSpec::frame("frame_ib", "Fixed in rod 2 at the joint at frame_b");
const FRAME_IM: ConnectorSpec = ConnectorSpec::frame("frame_im", "Fixed in rod 2 at the middle joint");
const REVOLUTE_AXIS: [ConnectorSpec; 2] = [
    ConnectorSpec::flange("axis", ConnectorType::Spline, "Drives the revolute at frame_b"),
    ConnectorSpec::flange("bearing", ConnectorType::Spline, "Support of that drive"),
];
const PRISMATIC_AXIS: [ConnectorSpec; 2] = [
    ConnectorSpec::flange("axis", ConnectorType::Flange, "Drives the prismatic joint at frame_b"),
    ConnectorSpec::flange("bearing", ConnectorType::Flange, "Support of that drive"),
];

pub static RRR: ComponentSpec = ComponentSpec {
    kind: "JointRRR",
    doc: "Three revolutes with parallel axes n_a joined by two massless rods: rod 1 from frame_a to the middle \
          revolute (rRod1_ia, fixed in frame_ia) and rod 2 from the revolute at frame_b (axis n_b) to it \
          (rRod2_ib, fixed in frame_ib). Closes planar loops.",
    params: &[
        POSITIVE_BRANCH,
        N_A,
        ParamSpec::vector("n_b", &[0.0, 0.0, 1.0], "", "Axis of the revolute at frame_b, resolved in frame_b"),
        R_ROD1_IA,
        ParamSpec::vector("rRod2_ib", &[-1.0, 0.0, 0.0], "m", "From frame_ib to the middle revolute, in frame_ib"),
        ParamSpec::real("phi_offset", 0.0, "rad", "Angle offset of the revolute at frame_b"),
        ParamSpec::real("phi_guess", 0.0, "rad", "Kept for compatibility: the start configuration gives the branch"),
        ROD_RADIUS,
        ROD_COLOR,
    ],
    connectors: &[
        FRAME_A,
        FRAME_B,
        FRAME_IA,
        FRAME_IB,
        FRAME_IM,
        REVOLUTE_AXIS[0],
        REVOLUTE_AXIS[1],
        ConnectorSpec::internal("rod1_tip", ConnectorType::Frame),
        ConnectorSpec::internal("base_b", ConnectorType::Frame),
    ],
    variables: &[],
    build: |p| build(p, Kind::Rrr),
    shapes: super::shapes::none,
};

pub static RRP: ComponentSpec = ComponentSpec {
    kind: "JointRRP",
    doc: "Two revolutes with parallel axes n_a and a prismatic joint along n_b (orthogonal to them) joined by \
          two massless rods: rod 1 from frame_a to the middle revolute (rRod1_ia, fixed in frame_ia), rod 2 \
          from the slider at frame_ib to it (rRod2_ib). The slider sits at s + s_offset along n_b from frame_b.",
    params: &[
        POSITIVE_BRANCH,
        N_A,
        ParamSpec::vector("n_b", &[-1.0, 0.0, 0.0], "", "Axis of the prismatic joint, resolved in frame_b"),
        R_ROD1_IA,
        ParamSpec::vector("rRod2_ib", &[-1.0, 0.0, 0.0], "m", "From frame_ib to the middle revolute, in frame_ib"),
        ParamSpec::real("s_offset", 0.0, "m", "Distance offset of the prismatic joint"),
        ParamSpec::real("s_guess", 0.0, "m", "Kept for compatibility: the start configuration gives the branch"),
        ROD_RADIUS,
        ROD_COLOR,
    ],
    connectors: &[
        FRAME_A,
        FRAME_B,
        FRAME_IA,
        FRAME_IB,
        FRAME_IM,
        PRISMATIC_AXIS[0],
        PRISMATIC_AXIS[1],
        ConnectorSpec::internal("rod1_tip", ConnectorType::Frame),
        ConnectorSpec::internal("base_b", ConnectorType::Frame),
    ],
    variables: &[],
    build: |p| build(p, Kind::Rrp),
    shapes: super::shapes::none,
};

const N1_A: ParamSpec =
    ParamSpec::vector("n1_a", &[0.0, 0.0, 1.0], "", "Axis 1 of the universal joint, resolved in frame_a");
const R_ROD1_IA_US: ParamSpec =
    ParamSpec::vector("rRod1_ia", &[1.0, 0.0, 0.0], "m", "From frame_a to the ball joint, in frame_ia (the rod frame)");

pub static USR: ComponentSpec = ComponentSpec {
    kind: "JointUSR",
    doc: "A rod from a universal joint at frame_a (axis 1 n1_a, axis 2 across it and the rod; rRod1_ia in the rod \
          frame frame_ia) to a ball joint at frame_im, and a revolute about n_b at frame_b carrying rod 2 \
          (rRod2_ib from frame_ib to frame_im).",
    params: &[
        POSITIVE_BRANCH,
        N1_A,
        ParamSpec::vector("n_b", &[0.0, 0.0, 1.0], "", "Axis of the revolute, resolved in frame_b"),
        R_ROD1_IA_US,
        ParamSpec::vector("rRod2_ib", &[1.0, 0.0, 0.0], "m", "From frame_ib to the ball joint, in frame_ib"),
        ParamSpec::real("phi_offset", 0.0, "rad", "Angle offset of the revolute"),
        ParamSpec::real("phi_guess", 0.0, "rad", "Kept for compatibility: the start configuration gives the branch"),
        ROD_RADIUS,
        ROD_COLOR,
    ],
    connectors: &[
        FRAME_A,
        FRAME_B,
        FRAME_IA,
        FRAME_IB,
        FRAME_IM,
        REVOLUTE_AXIS[0],
        REVOLUTE_AXIS[1],
        ConnectorSpec::internal("rod1_tip", ConnectorType::Frame),
        ConnectorSpec::internal("base_b", ConnectorType::Frame),
    ],
    variables: &[],
    build: |p| build(p, Kind::Usr),
    shapes: super::shapes::none,
};

pub static USP: ComponentSpec = ComponentSpec {
    kind: "JointUSP",
    doc: "A rod from a universal joint at frame_a (axis 1 n1_a, axis 2 across it and the rod; rRod1_ia in the rod \
          frame frame_ia) to a ball joint at frame_im, and a prismatic joint along n_b at frame_b carrying rod 2 \
          (rRod2_ib from frame_ib to frame_im); the slider sits at s + s_offset from frame_b.",
    params: &[
        POSITIVE_BRANCH,
        N1_A,
        ParamSpec::vector("n_b", &[0.0, 0.0, 1.0], "", "Axis of the prismatic joint, resolved in frame_b"),
        R_ROD1_IA_US,
        ParamSpec::vector("rRod2_ib", &[1.0, 0.0, 0.0], "m", "From frame_ib to the ball joint, in frame_ib"),
        ParamSpec::real("s_offset", 0.0, "m", "Distance offset of the prismatic joint"),
        ParamSpec::real("s_guess", 0.0, "m", "Kept for compatibility: the start configuration gives the branch"),
        ROD_RADIUS,
        ROD_COLOR,
    ],
    connectors: &[
        FRAME_A,
        FRAME_B,
        FRAME_IA,
        FRAME_IB,
        FRAME_IM,
        PRISMATIC_AXIS[0],
        PRISMATIC_AXIS[1],
        ConnectorSpec::internal("rod1_tip", ConnectorType::Frame),
        ConnectorSpec::internal("base_b", ConnectorType::Frame),
    ],
    variables: &[],
    build: |p| build(p, Kind::Usp),
    shapes: super::shapes::none,
};

/// Connectors of the two kinds with a rod between ball joints (no frame_ia).
const SS: [ConnectorSpec; 4] = [FRAME_A, FRAME_B, FRAME_IB, FRAME_IM];

pub static SSR: ComponentSpec = ComponentSpec {
    kind: "JointSSR",
    doc: "A massless rod of length rod1_length with ball joints at both ends, from frame_a to frame_im, and a \
          revolute about n_b at frame_b carrying rod 2 (rRod2_ib from frame_ib to frame_im).",
    params: &[
        POSITIVE_BRANCH,
        HAS_MASS,
        ROD1_LENGTH,
        ROD1_MASS,
        ParamSpec::vector("n_b", &[0.0, 0.0, 1.0], "", "Axis of the revolute, resolved in frame_b"),
        ParamSpec::vector("rRod2_ib", &[1.0, 0.0, 0.0], "m", "From frame_ib to the middle ball joint, in frame_ib"),
        ParamSpec::real("phi_offset", 0.0, "rad", "Angle offset of the revolute"),
        ParamSpec::real("phi_guess", 0.0, "rad", "Kept for compatibility: the start configuration gives the branch"),
        ROD_RADIUS,
        ROD_COLOR,
    ],
    connectors: &[
        SS[0],
        SS[1],
        SS[2],
        SS[3],
        REVOLUTE_AXIS[0],
        REVOLUTE_AXIS[1],
        ConnectorSpec::internal("base_b", ConnectorType::Frame),
    ],
    variables: &[],
    build: |p| build(p, Kind::Ssr),
    shapes: super::shapes::none,
};

pub static SSP: ComponentSpec = ComponentSpec {
    kind: "JointSSP",
    doc: "A massless rod of length rod1_length with ball joints at both ends, from frame_a to frame_im, and a \
          prismatic joint along n_b at frame_b carrying rod 2 (rRod2_ib from frame_ib to frame_im); the \
          slider sits at s + s_offset from frame_b.",
    params: &[
        POSITIVE_BRANCH,
        HAS_MASS,
        ROD1_LENGTH,
        ROD1_MASS,
        ParamSpec::vector("n_b", &[0.0, 0.0, 1.0], "", "Axis of the prismatic joint, resolved in frame_b"),
        ParamSpec::vector("rRod2_ib", &[1.0, 0.0, 0.0], "m", "From frame_ib to the middle ball joint, in frame_ib"),
        ParamSpec::real("s_offset", 0.0, "m", "Distance offset of the prismatic joint"),
        ParamSpec::real("s_guess", 0.0, "m", "Kept for compatibility: the start configuration gives the branch"),
        ROD_RADIUS,
        ROD_COLOR,
    ],
    connectors: &[
        SS[0],
        SS[1],
        SS[2],
        SS[3],
        PRISMATIC_AXIS[0],
        PRISMATIC_AXIS[1],
        ConnectorSpec::internal("base_b", ConnectorType::Frame),
    ],
    variables: &[],
    build: |p| build(p, Kind::Ssp),
    shapes: super::shapes::none,
};

#[derive(Clone, Copy, Debug, PartialEq)]
enum Kind {
    Rrr,
    Rrp,
    Usr,
    Usp,
    Ssr,
    Ssp,
}

fn build(p: &ParamSet, kind: Kind) -> Result<Box<dyn Component>, Error> {
    let n_b = p.direction("n_b")?;
    let rod2 = Transform::translation(p.vec3("rRod2_ib"));
    // The joint at frame_b starts from an offset of its coordinate.
    let (joint_b, offset_b) = match kind {
        Kind::Rrr | Kind::Usr | Kind::Ssr => {
            (JointModel::Revolute { axis: n_b }, Transform::rotation(planar_rotation(&n_b, p.real("phi_offset"))))
        }
        Kind::Rrp | Kind::Usp | Kind::Ssp => {
            (JointModel::Prismatic { axis: n_b }, Transform::translation(n_b * p.real("s_offset")))
        }
    };
    let first = match kind {
        Kind::Rrr | Kind::Rrp => {
            let n_a = p.direction("n_a")?;
            let rod1 = p.vec3("rRod1_ia");
            if rod1.norm() == 0.0 {
                return Err(p.invalid("rRod1_ia", "rod 1 must have a length"));
            }
            First::Revolutes { n_a, rod1: Transform::translation(rod1) }
        }
        Kind::Usr | Kind::Usp => {
            let n1 = p.direction("n1_a")?;
            let rod1 = p.vec3("rRod1_ia");
            let across = n1.cross(&rod1);
            if across.norm() <= 1e-10 * rod1.norm() {
                return Err(p.invalid("rRod1_ia", "rod 1 must have a length and not lie along n1_a"));
            }
            First::Universal { n1, n2: across.normalize(), rod1: Transform::translation(rod1) }
        }
        Kind::Ssr | Kind::Ssp => {
            if p.boolean("has_mass") && p.real("rod1_mass") != 0.0 {
                return Err(Error::Unsupported {
                    component: p.component.into(),
                    what: "a rod 1 with mass in a joint assembly".into(),
                    fix: "leave rod1_mass at 0 and hang a PointMass between two SphericalSpherical rods instead".into(),
                });
            }
            let length = p.real("rod1_length");
            if !(length.is_finite() && length > 0.0) {
                return Err(p.invalid("rod1_length", "the rod's length must be positive"));
            }
            First::Rod { length }
        }
    };
    // JointRRP starts on the branch it is given, as the library's closed
    // form: rod 1 turns about n_a at frame_a, its length across n_a.
    let branch = match (kind, first) {
        (Kind::Rrp, First::Revolutes { n_a, rod1 }) => {
            let across = rod1.trans - n_a * n_a.dot(&rod1.trans);
            Some(PrismaticBranch {
                frame_a: 0,
                frame_b: 1,
                joint: 2,
                turn: 0,
                axis: n_b,
                offset: p.real("s_offset"),
                rod2: rod2.trans,
                normal: n_a,
                length: across.norm(),
                positive: p.boolean("positive_branch"),
            })
        }
        _ => None,
    };
    Ok(Box::new(LoopAssembly { first, joint_b, offset_b, rod2, branch }))
}

/// What joins frame_a to the middle joint.
#[derive(Clone, Copy, Debug)]
enum First {
    /// A revolute about `n_a` at frame_a, rod 1 to a revolute about `n_a` at the middle.
    Revolutes { n_a: Vec3, rod1: Transform },
    /// A universal joint (`n1` in frame_a, `n2` in the rod frame) and rod 1
    /// to a ball joint at the middle.
    Universal { n1: Vec3, n2: Vec3, rod1: Transform },
    /// A massless rod of `length` with ball joints at both ends.
    Rod { length: f64 },
}

#[derive(Debug)]
struct LoopAssembly {
    first: First,
    joint_b: JointModel,
    offset_b: Transform,
    rod2: Transform,
    branch: Option<PrismaticBranch>,
}

impl Component for LoopAssembly {
    fn prismatic_branch(&self) -> Option<PrismaticBranch> {
        self.branch
    }

    fn parts(&self) -> Vec<Part> {
        let states_b = match self.joint_b {
            JointModel::Prismatic { .. } => StateNames { q: &[("s", 1)], u: &[("v", 1)] },
            _ => StateNames { q: &[("phi", 1)], u: &[("w", 1)] },
        };
        let joint = |a, b, model, states, flanges| Part::Joint { a, b, model, states, flanges, iscut: false };
        match self.first {
            First::Revolutes { n_a, rod1 } => {
                // frame_a 0, frame_b 1, frame_ia 2, frame_ib 3, frame_im 4, axis 5, bearing 6, rod1_tip 7, base_b 8.
                let revolute = JointModel::Revolute { axis: n_a };
                // With a branch to start on, the slider stays in the tree
                // (its coordinate is a state the branch sets): the middle
                // revolute closes the loop.
                let middle = Part::Joint {
                    a: 7,
                    b: 4,
                    model: revolute,
                    states: StateNames { q: &[("phi_m", 1)], u: &[("w_m", 1)] },
                    flanges: None,
                    iscut: self.branch.is_some(),
                };
                vec![
                    joint(0, 2, revolute, StateNames { q: &[("phi_a", 1)], u: &[("w_a", 1)] }, None),
                    Part::Rigid { a: 2, b: 7, pose: rod1 },
                    middle,
                    Part::Rigid { a: 1, b: 8, pose: self.offset_b },
                    joint(8, 3, self.joint_b, states_b, Some(AxisFlanges { axis: 5, support: 6 })),
                    Part::Rigid { a: 3, b: 4, pose: self.rod2 },
                ]
            }
            First::Universal { n1, n2, rod1 } => {
                // frame_a 0, frame_b 1, frame_ia 2, frame_ib 3, frame_im 4, axis 5, bearing 6, rod1_tip 7, base_b 8.
                let ball = ConstraintKind::locking_axes(RotationLock::Free, [true; 3]);
                vec![
                    joint(
                        0,
                        2,
                        JointModel::Universal { n_a: n1, n_b: n2 },
                        StateNames { q: &[("phi_a", 1), ("phi_ia", 1)], u: &[("w_a", 1), ("w_ia", 1)] },
                        None,
                    ),
                    Part::Rigid { a: 2, b: 7, pose: rod1 },
                    Part::Constraint { a: 7, b: 4, kind: ball },
                    Part::Rigid { a: 1, b: 8, pose: self.offset_b },
                    joint(8, 3, self.joint_b, states_b, Some(AxisFlanges { axis: 5, support: 6 })),
                    Part::Rigid { a: 3, b: 4, pose: self.rod2 },
                ]
            }
            First::Rod { length } => {
                // frame_a 0, frame_b 1, frame_ib 2, frame_im 3, axis 4, bearing 5, base_b 6.
                vec![
                    Part::Constraint { a: 0, b: 3, kind: ConstraintKind::Distance { length } },
                    Part::Rigid { a: 1, b: 6, pose: self.offset_b },
                    joint(6, 2, self.joint_b, states_b, Some(AxisFlanges { axis: 4, support: 5 })),
                    Part::Rigid { a: 2, b: 3, pose: self.rod2 },
                ]
            }
        }
    }
}
