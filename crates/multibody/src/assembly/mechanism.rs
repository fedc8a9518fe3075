//! The assembled mechanism: the compiled numeric model ([`System`]) with
//! the components it came from, their connectors and frame nodes, and the
//! tree along which cut forces are computed. Immutable after assembly;
//! mutable per-evaluation data lives in a [`Workspace`].

use crate::components::{Component, ComponentSpec, Part, VarSpec, WorldSettings};
use crate::dynamics::{DynamicsError, Workspace};
use crate::math::Transform;
use crate::system::{Anchor, JointModel, RotationCoordinates, StateLayout, System, GROUND};
use std::collections::HashMap;
use std::sync::{Arc, OnceLock};

/// A model compiled for simulation.
#[derive(Debug, Clone)]
pub struct Mechanism {
    pub(crate) name: String,
    pub(crate) world: WorldSettings,
    /// What the dynamics evaluates.
    pub(crate) system: System,
    pub(crate) components: Vec<CompiledComponent>,
    /// Every connector of every component; components own consecutive runs.
    pub(crate) connectors: Vec<ConnectorInfo>,
    /// Frame nodes: sets of connected frame connectors.
    pub(crate) nodes: Vec<FrameNode>,
    /// For every connector, the signal it carries (the zero slot if none).
    pub(crate) signal_of_connector: Vec<usize>,
    /// For every connector, where it sits if it is a 1-D connector.
    pub(crate) flange_of_connector: Vec<crate::system::FlangeRef>,
    /// The kinematic loops, for reports.
    pub(crate) loops: Vec<LoopInfo>,
    pub(crate) flow_tree: FlowTree,
    pub(crate) warnings: Vec<String>,
    /// The model's outputs, by the names of their signals.
    pub(crate) outputs: Vec<String>,
    /// The names and units of the output signals, shared by every solution;
    /// named at the first use (by `outputs`), so that assembly stays cheap.
    pub(crate) signal_table: OnceLock<Arc<SignalTable>>,
}

/// The names and units of a mechanism's signals, with a lookup by name.
#[derive(Debug, Default)]
pub(crate) struct SignalTable {
    names: Vec<String>,
    units: Vec<&'static str>,
    index: HashMap<String, usize>,
    /// For a mechanism's table: the component of each column (`None` for
    /// constraint residuals), so that outputs can skip what nobody reads.
    owners: Vec<Option<usize>>,
}

impl SignalTable {
    pub(crate) fn new(names: Vec<String>, units: Vec<&'static str>) -> Self {
        debug_assert_eq!(names.len(), units.len());
        let index = names.iter().enumerate().map(|(i, n)| (n.clone(), i)).collect();
        Self { names, units, index, owners: Vec::new() }
    }

    /// A mechanism's table, with the component that owns each column.
    pub(crate) fn with_owners(names: Vec<String>, units: Vec<&'static str>, owners: Vec<Option<usize>>) -> Self {
        debug_assert_eq!(names.len(), owners.len());
        Self { owners, ..Self::new(names, units) }
    }

    /// The component that owns column `k`, if any.
    pub(crate) fn owner(&self, k: usize) -> Option<usize> {
        self.owners.get(k).copied().flatten()
    }

    pub(crate) fn names(&self) -> &[String] {
        &self.names
    }

    pub(crate) fn units(&self) -> &[&'static str] {
        &self.units
    }

    pub(crate) fn index(&self, name: &str) -> Option<usize> {
        self.index.get(name).copied()
    }
}

/// One component, built, with where its pieces went.
#[derive(Debug, Clone)]
pub(crate) struct CompiledComponent {
    pub name: String,
    pub spec: &'static ComponentSpec,
    pub component: Arc<dyn Component>,
    pub parts: Vec<Part>,
    /// Global number of its connector 0.
    pub first_connector: usize,
    /// For each `Joint`/`Owner` part, in order: where its coordinates are.
    pub joints: Vec<JointRef>,
    /// For each `Element1D` part, in order: its index in `axis_elements`.
    pub elements: Vec<usize>,
    /// For each `Friction` part, in order: its index in `frictions`.
    pub frictions: Vec<usize>,
    /// Its variables (besides frame signals), as it reports them.
    pub variables: Vec<VarSpec>,
    /// What it draws in animations.
    pub shapes: Vec<crate::components::shapes::Shape>,
    /// A piece assembly added for the model's equations: no results of its own.
    pub hidden: bool,
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
    /// A wheel's contact with the ground (not a loop of joints), and how many
    /// of its equations are on velocities only (rolling without slipping).
    pub wheel_contact: Option<usize>,
    /// A motion the model's equations prescribe (not a loop of joints): the
    /// cut is the frame, the joints are those its unknown efforts move.
    pub prescribed: bool,
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

    /// The compiled numeric model, for the dynamics functions.
    pub fn system(&self) -> &System {
        &self.system
    }

    /// Number of degrees of freedom: velocity coordinates less the
    /// independent constraint equations.
    pub fn degrees_of_freedom(&self) -> usize {
        self.system.dof
    }

    /// The kinematic loops and how they are closed.
    pub fn loops(&self) -> &[LoopInfo] {
        &self.loops
    }

    /// The states, with their names and start values.
    pub fn states(&self) -> &StateLayout {
        &self.system.states
    }

    /// Warnings found while assembling (nothing that stops a simulation).
    pub fn warnings(&self) -> &[String] {
        &self.warnings
    }

    /// The model's inputs (its `Input` components, in model order), which
    /// a host sets while it runs.
    pub fn input_names(&self) -> Vec<&str> {
        self.system.events.inputs.iter().map(|(n, _)| n.as_str()).collect()
    }

    /// The model's outputs, by the names of the signals they are.
    pub fn output_names(&self) -> &[String] {
        &self.outputs
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
        self.system.link_count()
    }

    /// A workspace for evaluating this mechanism's dynamics.
    pub fn workspace(&self) -> Workspace {
        Workspace::new(&self.system)
    }

    /// The right-hand side of the ODE, `dy = f(t, y)` with `y = [q, u]`;
    /// see [`System::rhs`]. Allocates nothing.
    #[inline]
    pub fn rhs(&self, ws: &mut Workspace, t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), DynamicsError> {
        self.system.rhs(ws, t, y, dy)
    }

    /// Joint accelerations `ud` at positions `q` and velocities `u`; see
    /// [`System::forward_dynamics`].
    #[inline]
    pub fn forward_dynamics(
        &self,
        ws: &mut Workspace,
        t: f64,
        q: &[f64],
        u: &[f64],
        ud: &mut [f64],
    ) -> Result<(), DynamicsError> {
        self.system.forward_dynamics(ws, t, q, u, ud)
    }

    /// Moves `y` onto the constraints at time `t`; see [`System::project`].
    pub fn project(&self, ws: &mut Workspace, t: f64, y: &mut [f64]) -> Result<bool, DynamicsError> {
        self.system.project(ws, t, y, false)
    }

    /// Sets the coordinates that drives know exactly (prescribed positions
    /// and speeds) to their values at `t`.
    pub fn impose_drives(&self, ws: &mut Workspace, t: f64, y: &mut [f64]) {
        if !self.system.drives.is_empty() {
            self.system.impose_drives(ws, t, y);
        }
    }

    /// For each floating group, the component that owns its orientation
    /// and the components moved with it: `(owner, kind of state)`.
    pub fn orientation_owners(&self) -> Vec<(String, String)> {
        self.system
            .links
            .iter()
            .skip(1)
            .filter(|l| l.parent == GROUND && matches!(l.joint, JointModel::Free(_) | JointModel::Translation))
            .map(|l| {
                let c = &self.components[l.source.0];
                let what = match l.joint {
                    JointModel::Free(RotationCoordinates::Quaternion { .. }) => "quaternion Q_hat, w_a",
                    JointModel::Free(_) => "Euler angles phi, phid",
                    _ => "position only, orientation fixed to the world",
                };
                (c.name.clone(), what.to_string())
            })
            .collect()
    }

    /// The frame node of `frame`: a frame connector (`elbow.frame_b`), or
    /// a component, whose `frame_a` (or only frame connector) is meant.
    pub(crate) fn frame_node(&self, frame: &str) -> Result<usize, String> {
        let is_frame =
            |c: &CompiledComponent, local: usize| self.connectors[c.first_connector + local].node != usize::MAX;
        let at = |c: &CompiledComponent, local: usize| self.connectors[c.first_connector + local].node;
        if let Some(c) = self.components.iter().find(|c| !c.hidden && c.name == frame) {
            let frames: Vec<usize> = (0..c.spec.connectors.len()).filter(|&k| is_frame(c, k)).collect();
            let chosen = frames.iter().find(|&&k| c.spec.connectors[k].name == "frame_a").or(frames.first());
            return match (chosen, frames.len()) {
                (Some(&k), 1) => Ok(at(c, k)),
                (Some(&k), _) if c.spec.connectors[k].name == "frame_a" => Ok(at(c, k)),
                _ => Err(format!("`{frame}` has no frame_a: name one of its frames ({})", self.frame_names(c))),
            };
        }
        let (component, connector) = frame.rsplit_once('.').unwrap_or((frame, ""));
        let Some(c) = self.components.iter().find(|c| !c.hidden && c.name == component) else {
            let names: Vec<&str> = self.components.iter().filter(|c| !c.hidden).map(|c| c.name.as_str()).collect();
            let near = crate::error::closest(component, names.iter().copied());
            let hint = near.first().map(|n| format!("; did you mean `{n}`?")).unwrap_or_default();
            return Err(format!("no component or frame `{frame}` in the model{hint}"));
        };
        match c.spec.connectors.iter().position(|s| s.name == connector) {
            Some(k) if is_frame(c, k) => Ok(at(c, k)),
            _ => Err(format!("`{component}` has no frame `{connector}`: its frames are {}", self.frame_names(c))),
        }
    }

    fn frame_names(&self, c: &CompiledComponent) -> String {
        let names: Vec<&str> = (0..c.spec.connectors.len())
            .filter(|&k| self.connectors[c.first_connector + k].node != usize::MAX && !c.spec.connectors[k].internal)
            .map(|k| c.spec.connectors[k].name)
            .collect();
        if names.is_empty() {
            "none".into()
        } else {
            names.join(", ")
        }
    }

    /// The component that owns link `link`; none for the ground.
    pub(crate) fn owner_of_link(&self, link: usize) -> Option<&str> {
        let source = self.system.links.get(link)?.source.0;
        self.components.get(source).map(|c| c.name.as_str())
    }

    /// The name of velocity coordinate `dof` (`housing.w`).
    pub(crate) fn velocity_name(&self, dof: usize) -> &str {
        self.system.states.names.get(self.system.states.nq + dof).map_or("?", String::as_str)
    }

    /// A constraint in words: the loop it closes and the joints around it,
    /// the motion prescribed there, or the wheel's contact.
    pub(crate) fn loop_name(&self, constraint: usize) -> String {
        let cut = &self.components[self.system.constraints[constraint].component].name;
        let info = self.loops.get(constraint);
        let joints = info.map(|l| l.joints.iter().map(|j| format!("`{j}`")).collect::<Vec<_>>().join(", "));
        match info {
            Some(l) if l.prescribed => format!("the motion the equations prescribe at `{cut}`"),
            Some(l) if l.wheel_contact.is_some() => format!("the contact of the wheel `{cut}`"),
            _ => format!("the loop closed at `{cut}` (through {})", joints.unwrap_or_default()),
        }
    }

    /// Explains a dynamics error in the model's terms.
    pub fn describe(&self, error: &DynamicsError) -> String {
        let name = |link: usize| self.owner_of_link(link).unwrap_or("a 1-D part").to_string();
        match *error {
            DynamicsError::EulerSingularity { link, .. } => {
                let seq = match self.system.links[link].joint.rotation_coordinates() {
                    Some((_, RotationCoordinates::Euler { sequence })) => sequence,
                    _ => [1, 2, 3],
                };
                format!(
                    "the Euler angles of `{}` (sequence {:?}) reached their singular configuration, where the first and \
                     third axes line up. Use `orientation_state = OrientationState.Quaternion()` for this body, or an Euler sequence whose \
                     singularity the motion does not reach",
                    name(link),
                    seq
                )
            }
            DynamicsError::SingularInertia { link } => format!(
                "the inertia moved by `{}` became singular: a degree of freedom lost all inertia behind it",
                name(link)
            ),
            DynamicsError::SingularMotion { dof } => format!(
                "the motion `{}` has no inertia behind it: with the constraints, nothing it moves has mass or \
                 inertia (an inertia with J = 0 that only a constraint holds, or a body without mass)",
                self.velocity_name(dof)
            ),
            DynamicsError::NotFinite => "a value became infinite or NaN (the motion blew up)".into(),
            DynamicsError::LoopOpen { constraint, residual } => {
                let what = self.loop_name(constraint);
                format!(
                    "{what} cannot close: its equations stay violated by {residual:.3e} (m or rad) after \
                     projection. The motion reached a configuration it cannot take, such as a crank driven past \
                     the dead point of its linkage or a target out of reach; change what drives it, or the \
                     lengths"
                )
            }
            DynamicsError::ContactIndeterminate { link } => format!(
                "the normal forces of the slipping wheels and the other constraint forces near `{}` have no unique \
                 solution (rigid contacts with friction on constraints that repeat each other); give the wheels \
                 elastic_contact = true, or remove the repeated constraint",
                name(link)
            ),
            DynamicsError::MasslessWithoutBalance { group } => format!(
                "no position of the frames without mass between {} balances the forces on them (springs that cannot hold them, or pulled apart without limit); give them mass or change the springs",
                self.system.massless[group].components.iter().map(|c| format!("`{c}`")).collect::<Vec<_>>().join(", ")
            ),
            DynamicsError::EquationsSingular { block } | DynamicsError::EquationsDiverged { block } => {
                let block = &self.system.equations.blocks[block];
                if !block.reduced.is_empty() {
                    let names = block.reduced.iter().map(|n| format!("`{n}`")).collect::<Vec<_>>().join(", ");
                    return format!(
                        "the equations {} no longer determine {names} here: index reduction chose, at the start, to \
                         compute {names} from them and integrate the other variables, and along the motion the \
                         equations lost their hold on {names} (their derivative with respect to it vanished). The \
                         choice is made once and not changed while the model runs; start the model where the other \
                         choice suits (give start values or guesses at which the equations depend more on the \
                         variables to integrate), or write the model in coordinates the equations fix throughout \
                         (an angle instead of two positions)",
                        block.label
                    );
                }
                if matches!(error, DynamicsError::EquationsSingular { .. }) {
                    format!(
                        "the equations {} have a singular Jacobian here: they do not determine their unknowns at \
                         this state (no solution near it, or their derivative vanishes there); give their variables \
                         start values (`guess`) near a solution, or reformulate them",
                        block.label
                    )
                } else {
                    format!(
                        "Newton's method found no solution of the equations {} here (no solution near the last one, \
                         or a discontinuity); give their variables better start values, or reformulate them",
                        block.label
                    )
                }
            }
        }
    }
}
