//! The model's own equations, compiled: a register machine. Before the
//! signal graph runs, the potentials the equations read (frame poses and
//! velocities, 1-D positions and speeds, joint coordinates) are gathered
//! into registers; then each block of equations runs at its place among
//! the signal blocks, reading signal slots and writing the signals and
//! flows it gives the mechanics; the rates of the equations' states are
//! left in registers for the right-hand side.
//!
//! Registers: `[time | constants | gathered | states | unknowns | temporaries]`.

use super::{Attachment, FlangeRef};
use crate::math::expr::{Cmp, Func, Func2};
use crate::math::sparse::SparseLu;
use std::ops::Range;

/// A register number.
pub type Reg = u32;

/// The register that holds the time.
pub const TIME: Reg = 0;

/// One instruction: `dst = f(operands)` on registers, or a move between a
/// register and a signal slot.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Op {
    Copy(Reg, Reg),
    Neg(Reg, Reg),
    Add(Reg, Reg, Reg),
    Sub(Reg, Reg, Reg),
    Mul(Reg, Reg, Reg),
    Div(Reg, Reg, Reg),
    Pow(Reg, Reg, Reg),
    Call(Func, Reg, Reg),
    Call2(Func2, Reg, Reg, Reg),
    Compare(Cmp, Reg, Reg, Reg),
    And(Reg, Reg, Reg),
    Or(Reg, Reg, Reg),
    Not(Reg, Reg),
    /// `dst = if c != 0 { a } else { b }`.
    Select(Reg, Reg, Reg, Reg),
    /// `dst = signals[slot]`.
    Load(Reg, usize),
    /// `signals[slot] = src`.
    Store(usize, Reg),
    /// A relation that makes events: between events `dst` is the value it
    /// had at the last event (`discrete[slot]`); at events it is evaluated
    /// and kept there. Either way `indicators[indicator]` is set: positive
    /// exactly where `a > b` or `a < b` holds (`a - b`, `b - a`), and where
    /// `a >= b` or `a <= b` fails (`b - a`, `a - b`), so that the value
    /// changes exactly where the indicator's sign does, at zero too.
    Relation {
        cmp: Cmp,
        dst: Reg,
        a: Reg,
        b: Reg,
        indicator: u32,
        slot: u32,
    },
    /// `dst = initial()`.
    Initial(Reg),
    /// `dst = pre(discrete[slot])`: its value before the event pass.
    LoadPre(Reg, u32),
    /// At events: whether `cond` became true (`discrete[slot]` keeps its
    /// value; at the start only with `at_start`, for `initial()`); between
    /// events false. An `impulse` condition (one with `sample`) holds only
    /// at its own instants: the slot keeps the last instant it fired at
    /// (from minus infinity), so it fires once at each.
    Fire {
        dst: Reg,
        cond: Reg,
        slot: u32,
        at_start: bool,
        impulse: bool,
    },
    /// `dst = sample(start, interval)` of the program's sample number
    /// `index`: true at events at one of its instants.
    Sample {
        dst: Reg,
        index: u32,
    },
    /// At events: whether `value` changed (`discrete[slot]` keeps it); false
    /// at the start and between events.
    Change {
        dst: Reg,
        value: Reg,
        slot: u32,
    },
    /// `discrete[slot] = src` if `fire` holds (a `when` assigns).
    Assign {
        slot: u32,
        src: Reg,
        fire: Reg,
    },
    /// `reinit` of state `y[state]` to `src` if `fire` holds.
    Reinit {
        state: u32,
        src: Reg,
        fire: Reg,
    },
}

/// A potential of the mechanics the equations read.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum FrameQuantity {
    /// `r_0[i]`: the origin in the world.
    Position(usize),
    /// `R[i, j]`: world to frame.
    Rotation(usize, usize),
    /// `der(r_0[i])`.
    Velocity(usize),
    /// `der(R[i, j])`.
    RotationRate(usize, usize),
    /// A planar frame's angle about z, in (-pi, pi].
    PlanarAngle,
    /// `der(phi)` of a planar frame: its angular velocity about z.
    PlanarAngleRate,
}

/// What is read into registers before the blocks run.
#[derive(Clone, Debug)]
pub enum Gather {
    /// Quantities of the frame at `at` (one motion computed for all).
    Frame { at: Attachment, reads: Vec<(FrameQuantity, Reg)> },
    /// The position and the speed of a 1-D connector (into the registers
    /// given; one motion computed for both).
    Flange { at: FlangeRef, position: Option<Reg>, speed: Option<Reg> },
    /// `y[index]`: a joint coordinate or rate of the mechanics.
    State { index: usize, register: Reg },
    /// A discrete variable (assigned in `when` clauses): `discrete[slot]`.
    Discrete { slot: usize, register: Reg },
}

/// How a block of equations is solved.
#[derive(Clone, Debug)]
pub enum Solve {
    /// Each unknown in closed form: the ops assign them in order.
    Explicit,
    /// Newton's method on `unknowns` (registers): `residual_ops` fill
    /// `residuals`, `jacobian_ops` fill `jacobian`. A linear block
    /// converges in one step.
    Newton {
        unknowns: Vec<Reg>,
        residuals: Vec<Reg>,
        jacobian: Jacobian,
        residual_ops: Range<usize>,
        jacobian_ops: Range<usize>,
        linear: bool,
    },
}

/// Where a Newton block's Jacobian is and how it is factored.
#[derive(Clone, Debug)]
pub enum Jacobian {
    /// Every entry, row-major by residual then unknown: a small block,
    /// factored with partial pivoting.
    Dense(Vec<Reg>),
    /// The entries that are not always zero, in the order `lu` analysed
    /// them: a large block with a few unknowns an equation.
    Sparse { entries: Vec<Reg>, lu: Box<SparseLu> },
}

/// A block of equations that are solved together, with the ops that
/// load its signal inputs first and store its signal outputs last.
#[derive(Clone, Debug)]
pub struct EquationBlock {
    /// Ops run before the solve (loads and what they feed).
    pub before: Range<usize>,
    pub solve: Solve,
    /// Ops run after the solve (what depends on the unknowns, and stores).
    pub after: Range<usize>,
    /// The equations of the block, for messages.
    pub label: String,
}

/// Newton's limits for a block; beyond them the evaluation fails.
pub const NEWTON_ITERATIONS: usize = 50;
pub const NEWTON_TOLERANCE: f64 = 1e-12;

/// The compiled equations.
#[derive(Clone, Debug, Default)]
pub struct EquationProgram {
    pub registers: usize,
    /// Registers that hold constants, with their values.
    pub constants: Vec<(Reg, f64)>,
    pub gathers: Vec<Gather>,
    /// The state registers start here, one per state of the equations.
    pub first_state: Reg,
    /// The register of each state's rate, in state order.
    pub rates: Vec<Reg>,
    pub ops: Vec<Op>,
    pub blocks: Vec<EquationBlock>,
    /// Where each block runs: before the signal block with this position
    /// in the evaluation order (the number of blocks runs it after them all).
    pub positions: Vec<usize>,
    /// The largest Newton block, for scratch space.
    pub largest_block: usize,
    /// The most values a block's Jacobian factors into (dense: n^2).
    pub largest_factors: usize,
    /// Every variable of the equations with its register, for outputs.
    pub outputs: Vec<(String, Reg)>,
    /// Whether a gather reads frames (the kinematics then computes world poses).
    pub reads_frames: bool,
    /// `(constraint row, register)`: the multipliers of measured couplings
    /// (in-line sensors), loaded once the accelerations are known.
    pub reactions: Vec<(usize, Reg)>,
    /// The blocks from this one on read those multipliers (or depend on
    /// them): they run after the accelerations.
    pub first_post: usize,
    /// The conditions of `when` clauses: run after every block, on every
    /// evaluation (their relations watch for events).
    pub when_conditions: Range<usize>,
    /// What `when` clauses do: run after the conditions, at events only.
    pub when_actions: Range<usize>,
    /// How many `reinit`s the `when` clauses hold (room for them).
    pub reinits: usize,
    /// The `sample(start, interval)` of the equations: time events.
    pub samples: Vec<Sample>,
}

/// The instants `start + k interval`, k = 0, 1, ...
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sample {
    pub start: f64,
    pub interval: f64,
}

impl Sample {
    /// Whether `t` is one of the instants (as [`Sample::next_after`] makes them).
    #[inline]
    pub fn holds_at(&self, t: f64) -> bool {
        let k = ((t - self.start) / self.interval).round();
        k >= 0.0 && self.start + k * self.interval == t
    }

    /// The first instant after `t`.
    pub fn next_after(&self, t: f64) -> f64 {
        if t < self.start {
            return self.start;
        }
        let mut k = ((t - self.start) / self.interval).floor() + 1.0;
        while self.start + k * self.interval <= t {
            k += 1.0;
        }
        self.start + k * self.interval
    }
}

impl EquationProgram {
    pub fn is_empty(&self) -> bool {
        self.blocks.is_empty() && self.rates.is_empty() && self.when_conditions.is_empty()
    }
}
