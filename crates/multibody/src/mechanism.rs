//! The compiled mechanism: what assembly makes of a model, immutable and
//! laid out for the dynamics. Mutable per-evaluation data lives in a
//! [`Workspace`](crate::dynamics::Workspace).

use crate::components::{Component, ComponentSpec, Law1D, Part, Resolve, SignalSource, VarSpec, WorldSettings};
use crate::dynamics::joint::JointModel;
use crate::math::{RigidInertia, Transform, Vec3};

/// Index of the ground (the world) among the links.
pub const GROUND: usize = 0;

/// A model compiled for simulation.
#[derive(Debug)]
pub struct Mechanism {
    pub(crate) name: String,
    pub(crate) world: WorldSettings,
    pub(crate) components: Vec<CompiledComponent>,
    /// Every connector of every component; components own consecutive runs.
    pub(crate) connectors: Vec<ConnectorInfo>,
    /// Frame nodes: sets of connected frame connectors.
    pub(crate) nodes: Vec<FrameNode>,
    /// Link 0 is the ground; the others are in topological order (a parent
    /// comes before its children).
    pub(crate) links: Vec<Link>,
    /// 1-D force elements acting on joint coordinates.
    pub(crate) axis_elements: Vec<AxisElement>,
    /// Signal sources; inputs read `signal values[index]`, and the index
    /// `sources.len()` is a slot that always reads zero.
    pub(crate) sources: Vec<SignalSource>,
    /// For every connector, the signal it carries (the zero slot if none).
    pub(crate) signal_of_connector: Vec<usize>,
    /// Force elements acting between frames.
    pub(crate) force_elements: Vec<ForceElement>,
    /// Groups of frames without mass whose position the force elements
    /// on them decide (solved in every evaluation).
    pub(crate) massless: Vec<MasslessGroup>,
    /// Constraints: cut joints of loops and constraint components.
    pub(crate) constraints: Vec<Constraint>,
    /// Total number of constraint rows.
    pub(crate) constraint_rows: usize,
    /// Sizes of the coordinate arrays of cut joints (outputs only).
    pub(crate) cut_nq: usize,
    pub(crate) cut_nv: usize,
    /// The kinematic loops, for reports.
    pub(crate) loops: Vec<LoopInfo>,
    /// Degrees of freedom: velocity coordinates less independent constraints.
    pub(crate) dof: usize,
    /// Masses that feel point gravity (or any field other than `uniform_gravity`).
    pub(crate) point_masses: Vec<PointGravityMass>,
    /// The uniform gravity every mass feels, handled as an acceleration of the ground.
    pub(crate) uniform_gravity: Vec3,
    pub(crate) states: StateLayout,
    pub(crate) flow_tree: FlowTree,
    pub(crate) warnings: Vec<String>,
    /// The names and units of the output signals, shared by every solution;
    /// named at the first use, so that assembly stays cheap.
    pub(crate) signal_table: std::sync::OnceLock<std::sync::Arc<crate::simulate::SignalTable>>,
}

/// One component, built, with where its pieces went.
#[derive(Debug)]
pub(crate) struct CompiledComponent {
    pub name: String,
    pub spec: &'static ComponentSpec,
    pub component: Box<dyn Component>,
    pub parts: Vec<Part>,
    /// Global number of its connector 0.
    pub first_connector: usize,
    /// For each `Joint`/`Owner` part, in order: where its coordinates are.
    pub joints: Vec<JointRef>,
    /// For each `Element1D` part, in order: its index in `axis_elements`.
    pub elements: Vec<usize>,
    /// Its variables (besides frame signals), as it reports them.
    pub variables: Vec<VarSpec>,
    /// What it draws in animations.
    pub shapes: Vec<crate::components::shapes::Shape>,
}

#[derive(Debug, Clone)]
pub(crate) struct ConnectorInfo {
    pub component: usize,
    /// Frame node of a frame connector; `usize::MAX` otherwise.
    pub node: usize,
    /// Whether it appears in a connection.
    pub connected: bool,
}

/// Where a component's joint has its coordinates.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum JointRef {
    /// A tree joint: the link it moves (its coordinates are states).
    Link(usize),
    /// A cut joint: its constraint (its coordinates are computed for outputs).
    Cut(usize),
}

/// A relation kept by constraint forces.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Constraint {
    pub component: usize,
    pub a: Attachment,
    pub b: Attachment,
    /// The component's connectors at `a` and `b` (global numbers).
    pub connectors: (usize, usize),
    pub kind: crate::components::ConstraintKind,
    /// Its first row among all constraint rows.
    pub row: usize,
    pub rows: usize,
    /// A cut joint: its model and where its output coordinates go.
    pub joint: Option<CutJoint>,
}

#[derive(Debug, Clone, Copy)]
pub(crate) struct CutJoint {
    pub model: JointModel,
    pub q_offset: usize,
    pub v_offset: usize,
}

/// A closed kinematic loop, as `check` reports it.
#[derive(Debug, Clone, PartialEq)]
pub struct LoopInfo {
    /// The component whose constraint closes the loop (a cut joint or a constraint component).
    pub cut: String,
    /// The joints around the loop, the cut included.
    pub joints: Vec<String>,
    /// Constraint equations of the cut.
    pub equations: usize,
    /// How many of them repeat what the others already say.
    pub redundant: usize,
}

/// A set of connected frames, fixed in a link (or in a massless group).
#[derive(Debug, Clone)]
pub(crate) struct FrameNode {
    pub anchor: Anchor,
    /// Link (or group) frame to node frame.
    pub pose: Transform,
    /// The connectors in this node.
    pub connectors: Vec<usize>,
}

/// What a frame is fixed to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Anchor {
    Link(usize),
    /// A massless group, whose orientation is the world's.
    Massless(usize),
}

impl FrameNode {
    /// The link the node moves with (the ground for massless groups, which
    /// carry no inertia).
    pub fn link(&self) -> usize {
        match self.anchor {
            Anchor::Link(k) => k,
            Anchor::Massless(_) => GROUND,
        }
    }
}

/// Where a force element attaches: a node and how it is fixed.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Attachment {
    pub anchor: Anchor,
    pub pose: Transform,
}

/// A force element in the form the dynamics evaluates.
#[derive(Debug, Clone, Copy)]
pub(crate) struct ForceElement {
    pub load: Load,
    /// The reaction side (None: the world).
    pub a: Option<Attachment>,
    pub b: Attachment,
    /// The element's connectors at `a` and `b` (global numbers).
    pub connectors: (Option<usize>, usize),
}

/// A force law with its inputs resolved to signal slots.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Load {
    Line { c: f64, d: f64, s_unstretched: f64, s_small: f64 },
    Force { signals: [usize; 3], resolve: Resolve },
    Torque { signals: [usize; 3], resolve: Resolve },
}

/// Frames without mass held by force elements only; their orientation is
/// fixed to the world's by a line-force end.
#[derive(Debug, Clone)]
pub(crate) struct MasslessGroup {
    /// Force elements acting on the group.
    pub elements: Vec<usize>,
    /// Start guess of the group's reference position.
    pub guess: Vec3,
    /// Component names, for messages.
    pub components: Vec<String>,
}

/// A rigid body of the tree (all frames rigidly joined) and the joint that
/// moves it relative to its parent.
#[derive(Debug, Clone)]
pub(crate) struct Link {
    pub parent: usize,
    pub joint: JointModel,
    /// Parent link frame to the joint's frame on the parent side.
    pub x_tree: Transform,
    /// Mass of everything fixed to the link, in the link frame (the joint's
    /// child-side frame).
    pub inertia: RigidInertia,
    /// The same as an articulated inertia, where the ABA starts from.
    pub articulated: crate::math::ArticulatedInertia,
    pub q_offset: usize,
    pub v_offset: usize,
    /// The component and part of the joint (or owner) that moves this link.
    pub source: (usize, usize),
    /// The component whose name the states carry.
    pub states_of: usize,
    /// Whether the joint is traversed from its frame_b to its frame_a by
    /// inverting its motion (1-DOF joints flip their axis instead).
    pub inverted: bool,
}

impl Link {
    /// The motion of this link's frame relative to the parent-side joint frame.
    #[inline]
    pub fn motion(&self, q: &[f64], u: &[f64], m: &mut crate::dynamics::joint::JointMotion) {
        let (nq, nv) = (self.joint.nq(), self.joint.nv());
        self.joint.motion(&q[self.q_offset..self.q_offset + nq], &u[self.v_offset..self.v_offset + nv], m);
        if self.inverted {
            JointModel::invert(m, nv);
        }
    }

    /// This link's joint coordinates in `q`.
    #[inline]
    pub fn q<'a>(&self, q: &'a [f64]) -> &'a [f64] {
        &q[self.q_offset..self.q_offset + self.joint.nq()]
    }
}

/// Where a 1-D flange sits: at the fixed support, or on a joint coordinate.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum FlangeRef {
    Fixed,
    /// Velocity index (= position index for 1-DOF joints' coordinates) and
    /// position index of the joint coordinate.
    Coordinate {
        q: usize,
        v: usize,
    },
}

#[derive(Debug, Clone, Copy)]
pub(crate) struct AxisElement {
    pub a: FlangeRef,
    pub b: FlangeRef,
    pub law: Law1D,
}

#[derive(Debug, Clone, Copy)]
pub(crate) struct PointGravityMass {
    pub link: usize,
    pub mass: f64,
    /// Centre of mass in the link frame.
    pub com: Vec3,
}

/// Names and start values of the states: positions first, then velocities.
#[derive(Debug, Clone, Default)]
pub struct StateLayout {
    pub nq: usize,
    pub nv: usize,
    pub names: Vec<String>,
    pub start: Vec<f64>,
    /// Which start values the model fixed (`initial`), as opposed to
    /// defaults and guesses that closing a loop may change.
    pub fixed: Vec<bool>,
}

/// How cut forces travel from the loads to the ground: a spanning tree over
/// the frame nodes whose edges are the parts that transmit force.
#[derive(Debug, Clone, Default)]
pub(crate) struct FlowTree {
    /// Nodes in an order where each comes after its parent.
    pub order: Vec<usize>,
    /// For each node, the edge to its parent (None only for unreachable nodes).
    pub parent: Vec<Option<FlowEdge>>,
}

#[derive(Debug, Clone, Copy)]
pub(crate) struct FlowEdge {
    /// Parent node, or None for the ground.
    pub parent_node: Option<usize>,
    /// The transmitting part's connector at the parent node (None at the
    /// ground, or for parts that report no flow, like orientation owners).
    pub parent_connector: Option<usize>,
    /// Its connector at the child node (None for parts that report no flow).
    pub child_connector: Option<usize>,
}

impl Mechanism {
    pub fn name(&self) -> &str {
        &self.name
    }

    /// Number of degrees of freedom: velocity coordinates less the
    /// independent constraint equations.
    pub fn degrees_of_freedom(&self) -> usize {
        self.dof
    }

    /// The kinematic loops and how they are closed.
    pub fn loops(&self) -> &[LoopInfo] {
        &self.loops
    }

    /// The states, with their names and start values.
    pub fn states(&self) -> &StateLayout {
        &self.states
    }

    /// Warnings found while assembling (nothing that stops a simulation).
    pub fn warnings(&self) -> &[String] {
        &self.warnings
    }

    pub fn world(&self) -> &WorldSettings {
        &self.world
    }

    /// The shapes every component draws, placed by frames of the solution.
    pub fn shapes(&self) -> Vec<crate::components::shapes::Shape> {
        self.components.iter().flat_map(|c| c.shapes.iter().cloned()).collect()
    }

    /// Number of moving links (rigid bodies of the tree).
    pub fn link_count(&self) -> usize {
        self.links.len() - 1
    }

    /// For each floating group, the component that owns its orientation
    /// and the components moved with it: `(owner, kind of state)`.
    pub fn orientation_owners(&self) -> Vec<(String, String)> {
        self.links
            .iter()
            .skip(1)
            .filter(|l| l.parent == GROUND && matches!(l.joint, JointModel::Free(_) | JointModel::Translation))
            .map(|l| {
                let c = &self.components[l.source.0];
                let what = match l.joint {
                    JointModel::Free(crate::dynamics::joint::RotationCoordinates::Quaternion { .. }) => {
                        "quaternion Q_hat, w_a"
                    }
                    JointModel::Free(_) => "Euler angles phi, phid",
                    _ => "position only, orientation fixed to the world",
                };
                (c.name.clone(), what.to_string())
            })
            .collect()
    }
}
