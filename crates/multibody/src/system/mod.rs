//! The compiled numeric model: the mechanism as the dynamics sees it.
//!
//! Plain data (`Clone`, no trait objects, no component names but those kept
//! for messages): links in topological order with their joint models, force
//! laws between frames, 1-D laws on joint coordinates, constraints on frames
//! and on coordinates, the signal sources, and the layout of the state.
//! Assembly writes it once; `dynamics` reads it with a
//! [`Workspace`](crate::dynamics::Workspace).

pub mod balance;
pub mod chart;
pub mod drive;
pub(crate) mod equations;
pub mod friction;
pub mod joint;
pub mod laws;
pub mod signals;

pub use drive::{Drive, DriveLevel, DriveMap};
pub use joint::{JointModel, JointMotion, RotationCoordinates};
pub use laws::{
    resolve_input, ConstraintKind, ForceLaw, Law1D, Resolve, RotationLock, SignalSource, SlipLaw, WheelContact,
};
pub(crate) use signals::SignalBlock;
pub use signals::SignalLaw;

use crate::math::{ArticulatedInertia, RigidInertia, Transform, Vec3};

/// Index of the ground (the world) among the links.
pub const GROUND: usize = 0;

/// A mechanism compiled for the dynamics.
#[derive(Debug, Clone)]
pub struct System {
    /// Link 0 is the ground; the others are in topological order (a parent
    /// comes before its children).
    pub(crate) links: Vec<Link>,
    /// 1-D force elements acting on joint coordinates.
    pub(crate) axis_elements: Vec<AxisElement>,
    /// The signal blocks in evaluation order (each after the blocks it
    /// reads); each writes its own slot, and the last slot (`signal_slots - 1`)
    /// always reads zero.
    pub(crate) signals: Vec<SignalBlock>,
    /// Whether a signal block reads frame poses.
    pub(crate) signals_read_frames: bool,
    /// How many signal slots there are (the last reads zero).
    pub(crate) signal_slots: usize,
    /// How many of the first blocks depend on time only (and so have
    /// derivatives a drive can use, evaluated before the kinematics).
    pub(crate) time_signals: usize,
    /// Joints whose motion signals impose.
    pub(crate) drives: Vec<Drive>,
    /// Per velocity coordinate, whether the dynamics decides it (no drive
    /// imposes it): what projection onto the constraints may move.
    pub(crate) free_coordinates: Vec<bool>,
    /// Linear relations between joint coordinates (gears), kept by
    /// constraint forces in the rows after those of `constraints`.
    pub(crate) couplings: Vec<Coupling>,
    /// The 1-D nodes without mass, held by the forces on them (each driven
    /// by a drive of level [`DriveLevel::Balance`]).
    pub(crate) balances: Vec<balance::Balance>,
    /// 1-D friction elements with modes; each has a constraint row after
    /// the couplings', used while it is locked.
    pub(crate) frictions: Vec<friction::Friction>,
    /// Force elements acting between frames.
    pub(crate) force_elements: Vec<ForceElement>,
    /// Groups of frames without mass whose position the force elements
    /// on them decide (solved in every evaluation).
    pub(crate) massless: Vec<MasslessGroup>,
    /// Constraints: cut joints of loops and constraint components.
    pub(crate) constraints: Vec<Constraint>,
    /// Constraints whose rows follow formulas of time and whose forces
    /// are signals driving 1-D sources (motions prescribed with unknown
    /// efforts).
    pub(crate) servos: Vec<Servo>,
    /// The roads wheels roll on (other than the plane y = 0).
    pub(crate) roads: Vec<crate::math::surface::Surface>,
    /// Total number of constraint rows, couplings included.
    pub(crate) constraint_rows: usize,
    /// Point masses on the lines between two frames (line forces with mass).
    pub(crate) line_masses: Vec<LineMass>,
    /// Lines whose lengths place 1-D connectors (LineForceWithMass).
    pub(crate) lines: Vec<LineSpan>,
    /// The model's own equations, compiled.
    pub(crate) equations: equations::EquationProgram,
    /// Sizes of the coordinate arrays of cut joints (outputs only).
    pub(crate) cut_nq: usize,
    pub(crate) cut_nv: usize,
    /// Masses that feel point gravity (or any field other than `uniform_gravity`).
    pub(crate) point_masses: Vec<PointGravityMass>,
    /// Constant generalised forces on 1-DOF coordinates `(v, force)`: the
    /// weight of 1-D masses on inclined paths.
    pub(crate) axis_forces: Vec<(usize, f64)>,
    /// The uniform gravity every mass feels, handled as an acceleration of the ground.
    pub(crate) uniform_gravity: Vec3,
    /// The gravity constant of point gravity.
    pub(crate) mu: f64,
    /// Where the planar components' plane sits (world to plane): their
    /// sensors and force laws work in its coordinates.
    pub(crate) plane: Transform,
    pub(crate) states: StateLayout,
    /// Degrees of freedom: velocity coordinates less independent constraints.
    pub(crate) dof: usize,
    /// What the dynamics knows of events, inputs and modes.
    pub(crate) events: EventLayout,
}

/// The model's boundary and its discrete part: the inputs the host sets,
/// the event indicators every evaluation writes (`Workspace::indicators`;
/// an event is where one changes sign), and the discrete state (modes,
/// the values of relations between events) that events change.
#[derive(Debug, Clone, Default)]
pub struct EventLayout {
    /// The inputs by number: name and value before the host sets one.
    pub inputs: Vec<(String, f64)>,
    /// What each indicator watches, for messages.
    pub indicators: Vec<String>,
    /// The discrete state at the start, before the first event iteration.
    pub discrete_start: Vec<f64>,
}

impl System {
    /// The states, with their names and start values.
    pub fn states(&self) -> &StateLayout {
        &self.states
    }

    /// Number of moving links (rigid bodies of the tree).
    pub fn link_count(&self) -> usize {
        self.links.len() - 1
    }
}

/// A relation kept by constraint forces.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Constraint {
    pub component: usize,
    pub a: Attachment,
    pub b: Attachment,
    /// The component's connectors at `a` and `b` (global numbers).
    pub connectors: (usize, usize),
    pub kind: ConstraintKind,
    /// Its first row among all constraint rows.
    pub row: usize,
    pub rows: usize,
    /// A cut joint: its model and where its output coordinates go.
    pub joint: Option<CutJoint>,
}

/// A point mass `m` on the line between the origins of two frames, at
/// `r_a + h (r_b - r_a)` (a line force with mass). It is no degree of
/// freedom: its acceleration is `(1 - h) a_a + h a_b`, so its inertia
/// couples the two ends' links (the mass matrix holds it; the
/// articulated-body recursion cannot), and its weight loads both ends.
#[derive(Debug, Clone, Copy)]
pub(crate) struct LineMass {
    pub a: Attachment,
    pub b: Attachment,
    /// The component's connectors at `a` and `b` (global numbers).
    pub connectors: (usize, usize),
    pub m: f64,
    pub h: f64,
    /// Whether it feels point gravity rather than the uniform field.
    pub point_gravity: bool,
}

impl System {
    /// Whether loads other than inertia and gravity change with the state
    /// (1-D elements, forces between frames, point gravity, signals that
    /// read the motion): where they do not, they add nothing to a
    /// linearization's state columns.
    pub(crate) fn has_state_dependent_loads(&self) -> bool {
        !(self.axis_elements.is_empty()
            && self.force_elements.is_empty()
            && self.point_masses.is_empty()
            && self.lines.is_empty()
            && self.massless.is_empty()
            && self.signals.is_empty())
    }

    /// Whether accelerations come from the mass matrix (constraints, or
    /// inertia shared between links) rather than the articulated-body
    /// recursion.
    pub(crate) fn uses_mass_matrix(&self) -> bool {
        self.constraint_rows > 0 || !self.line_masses.is_empty()
    }
}

#[derive(Debug, Clone, Copy)]
pub(crate) struct CutJoint {
    pub model: JointModel,
    pub q_offset: usize,
    pub v_offset: usize,
}

/// What a frame is fixed to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Anchor {
    Link(usize),
    /// A massless group, whose orientation is the world's.
    Massless(usize),
}

/// Where a force element attaches: a node and how it is fixed.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Attachment {
    pub anchor: Anchor,
    pub pose: Transform,
}

/// A force element in the form the dynamics evaluates: its law and its
/// attachments.
#[derive(Debug, Clone, Copy)]
pub(crate) struct ForceElement {
    pub law: ForceLaw,
    /// The reaction side (None: the world).
    pub a: Option<Attachment>,
    pub b: Attachment,
    /// The element's connectors at `a` and `b` (global numbers).
    pub connectors: (Option<usize>, usize),
    /// The signal slots of its inputs (the zero slot where unused).
    pub inputs: [usize; 6],
    /// Its 1-D flanges a and b (fixed where unused).
    pub flanges: [FlangeRef; 2],
    /// A planar component's element in a plane placed away from the x-y
    /// plane: its law sees the frames in the plane's coordinates.
    pub in_plane: bool,
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
    pub articulated: ArticulatedInertia,
    pub q_offset: usize,
    pub v_offset: usize,
    /// The component and part of the joint (or owner) that moves this link.
    pub source: (usize, usize),
    /// The component whose name the states carry.
    pub states_of: usize,
    /// Whether the joint is traversed from its frame_b to its frame_a by
    /// inverting its motion (1-DOF joints flip their axis instead).
    pub inverted: bool,
    /// Inertia of 1-D parts that turn with a 1-DOF joint's coordinate
    /// (rotors behind gears, reflected as `ratio^2 J`): it adds to the
    /// joint's diagonal of the mass matrix. A free 1-D inertia is a link of
    /// its own with no rigid inertia and only this.
    pub armature: f64,
    /// Bit `k` set: a drive imposes the acceleration of velocity
    /// coordinate `k` of this joint.
    pub driven: u8,
    /// An Euler-angle joint that a simulator moved to a chart near its
    /// singular configuration: its coordinates are the chart's, and
    /// `x_tree` includes the chart's base.
    pub chart: Option<chart::EulerChart>,
}

impl Link {
    /// A link without mass yet (assembly adds it), not inverted and without
    /// armature, whose coordinates start at `(q_offset, v_offset)`.
    pub fn new(
        parent: usize,
        joint: JointModel,
        x_tree: Transform,
        (q_offset, v_offset): (usize, usize),
        source: (usize, usize),
        states_of: usize,
    ) -> Self {
        Link {
            parent,
            joint,
            x_tree,
            inertia: RigidInertia::ZERO,
            articulated: Default::default(),
            q_offset,
            v_offset,
            source,
            states_of,
            inverted: false,
            armature: 0.0,
            driven: 0,
            chart: None,
        }
    }

    /// The motion of this link's frame relative to the parent-side joint frame.
    #[inline]
    pub fn motion(&self, q: &[f64], u: &[f64], m: &mut JointMotion) {
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

/// What moves a 1-D connector.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Mover {
    /// A 1-DOF coordinate: its position and velocity index.
    State { q: usize, v: usize },
    /// The distance between the frames of line `k` (`System::lines`): a
    /// LineForceWithMass's flange_b.
    Line(usize),
}

/// Where a 1-D connector sits: at `offset + scale * x`, where `x` is what
/// moves it (a joint's axis, a free inertia's own coordinate, anything
/// rigidly geared to one, or a line's length), or fixed at `offset`; plus
/// `k * q` of a second coordinate where a gear without inertia behind it
/// follows two (its output on a housing that turns).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct FlangeRef {
    pub mover: Option<Mover>,
    pub scale: f64,
    pub offset: f64,
    /// `(position index, velocity index, k)` of the second coordinate
    /// (indices as `u32`, to keep every place small).
    pub second: Option<(u32, u32, f64)>,
}

impl FlangeRef {
    /// Fixed at 0.
    pub const FIXED: FlangeRef = FlangeRef { mover: None, scale: 0.0, offset: 0.0, second: None };

    /// Fixed at `at`.
    pub fn fixed(at: f64) -> Self {
        FlangeRef { mover: None, scale: 0.0, offset: at, second: None }
    }

    /// The coordinate itself.
    pub fn on(q: usize, v: usize) -> Self {
        FlangeRef { mover: Some(Mover::State { q, v }), scale: 1.0, offset: 0.0, second: None }
    }

    /// The length of line `k`.
    pub fn line(k: usize) -> Self {
        FlangeRef { mover: Some(Mover::Line(k)), scale: 1.0, offset: 0.0, second: None }
    }

    /// The coordinate `(q, v)` that moves it, if one coordinate alone does.
    pub fn coordinate(&self) -> Option<(usize, usize)> {
        match (self.mover, self.second) {
            (Some(Mover::State { q, v }), None) => Some((q, v)),
            _ => None,
        }
    }

    /// The coordinates that move it, `(q, v, k)`, where no line does.
    pub fn coordinates(&self) -> impl Iterator<Item = (usize, usize, f64)> {
        let first = match self.mover {
            Some(Mover::State { q, v }) => Some((q, v, self.scale)),
            _ => None,
        };
        first.into_iter().chain(self.second.map(|(q, v, k)| (q as usize, v as usize, k)))
    }

    /// Whether a line's length moves it.
    pub fn on_line(&self) -> bool {
        matches!(self.mover, Some(Mover::Line(_)))
    }

    /// The place `offset + scale * x`, where `x` is this place.
    pub fn affine(self, scale: f64, offset: f64) -> Self {
        let mover = if scale == 0.0 { None } else { self.mover };
        let second = if scale == 0.0 { None } else { self.second.map(|(q, v, k)| (q, v, k * scale)) };
        FlangeRef { mover, scale: self.scale * scale, offset: self.offset * scale + offset, second }
    }

    /// Position and speed of the flange at `(q, u)`, with the lines' lengths.
    #[inline]
    pub fn motion(&self, q: &[f64], u: &[f64], lines: &[LineState]) -> (f64, f64) {
        let (s, v) = match self.mover {
            None => (self.offset, 0.0),
            Some(Mover::State { q: i, v }) => (self.offset + self.scale * q[i], self.scale * u[v]),
            Some(Mover::Line(k)) => (self.offset + self.scale * lines[k].s, self.scale * lines[k].v),
        };
        match self.second {
            None => (s, v),
            Some(second) => with_second(second, (s, v), q, u),
        }
    }

    /// Acceleration of the flange for the velocity rates `ud` and the
    /// lines' accelerations `line_a`.
    #[inline]
    pub fn acceleration(&self, ud: &[f64], line_a: &[f64]) -> f64 {
        let a = match self.mover {
            None => 0.0,
            Some(Mover::State { v, .. }) => self.scale * ud[v],
            Some(Mover::Line(k)) => self.scale * line_a[k],
        };
        self.second.map_or(a, |(_, j, k)| a + k * ud[j as usize])
    }

    /// Adds the generalised force of `force` pushing this flange forward:
    /// to its coordinate's, or to its line's tension.
    #[inline]
    pub fn push(&self, tau: &mut [f64], lines: &mut [LineState], force: f64) {
        match self.mover {
            None => {}
            Some(Mover::State { v, .. }) => tau[v] += self.scale * force,
            Some(Mover::Line(k)) => lines[k].force += self.scale * force,
        }
        if let Some((_, j, k)) = self.second {
            tau[j as usize] += k * force;
        }
    }
}

/// A place's motion with its second coordinate's added: out of the way of
/// the usual one-coordinate places.
#[cold]
#[inline(never)]
fn with_second((i, j, k): (u32, u32, f64), (s, v): (f64, f64), q: &[f64], u: &[f64]) -> (f64, f64) {
    (s + k * q[i as usize], v + k * u[j as usize])
}

/// The line between two frames' origins whose length places a
/// LineForceWithMass's flange_b (its flange_a sits at 0): what the 1-D
/// elements push on that flange acts along the line, on frame_b, and
/// oppositely on frame_a.
#[derive(Debug, Clone, Copy)]
pub(crate) struct LineSpan {
    pub a: Attachment,
    pub b: Attachment,
    /// The component's connectors at `a` and `b` (global numbers).
    pub connectors: (usize, usize),
    /// Below this distance the direction is kept from dividing by zero.
    pub s_small: f64,
}

/// A line's length `s >= s_small`, its rate, its unit direction from
/// frame_a to frame_b (world), and the force the 1-D elements push its far
/// end with (along `e`).
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct LineState {
    pub s: f64,
    pub v: f64,
    pub e: Vec3,
    pub force: f64,
}

#[derive(Debug, Clone, Copy)]
pub(crate) struct AxisElement {
    pub a: FlangeRef,
    pub b: FlangeRef,
    pub law: Law1D,
    /// Its first event indicator, if its law has any (`Law1D::indicator_count`).
    pub indicator: usize,
}

#[derive(Debug, Clone, Copy)]
pub(crate) struct PointGravityMass {
    pub link: usize,
    pub mass: f64,
    /// Centre of mass in the link frame.
    pub com: Vec3,
}

/// Names and start values of the states: positions first, then
/// velocities, then the states of the model's own equations.
#[derive(Debug, Clone, Default)]
pub struct StateLayout {
    pub nq: usize,
    pub nv: usize,
    /// States of the model's own equations, after the joints' velocities.
    pub nx: usize,
    pub names: Vec<String>,
    pub start: Vec<f64>,
    /// Which start values the model fixed (`initial`), as opposed to
    /// defaults and guesses that closing a loop may change.
    pub fixed: Vec<bool>,
}

/// A servo constraint (Blajer's term): the rows of constraint
/// `constraint` follow formulas of time, `g_i(q) = p_i(t)`, and their
/// multipliers are not forces along the rows but the values of signals
/// that drive 1-D sources (the unknown joint torques of a hand led along
/// a path): `M ud = f + B' lambda`, `J ud = p'' - Jdot u`. This is index
/// reduction done by the mechanism: the rows are differentiated twice
/// exactly (the formulas' jets and the constraint's `Jdot u`), and
/// projection after each step keeps the positions and velocities on them.
#[derive(Debug, Clone)]
pub(crate) struct Servo {
    pub constraint: usize,
    /// Per row: the prescribed value.
    pub targets: Vec<crate::math::expr::TimeFunction>,
    /// Per row: the signal slot that holds its effort (its multiplier).
    pub slots: Vec<usize>,
    /// Per row: the generalised forces of a unit effort (`nv` each): `B`.
    pub forces: Vec<f64>,
}

/// A linear relation between joint coordinates, `sum c_k q_k = 0`, on
/// coordinates whose rate is their velocity coordinate (1-DOF joints).
#[derive(Debug, Clone)]
pub(crate) struct Coupling {
    /// `(position index, velocity index, coefficient)` of each term.
    pub terms: Vec<(usize, usize, f64)>,
    /// The constant part of the relation (of terms on fixed places).
    pub constant: f64,
    /// Its row among all constraint rows.
    pub row: usize,
    /// The component that states it (for outputs and messages).
    pub component: usize,
}
