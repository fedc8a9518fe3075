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
use crate::math::sparse::SparseLu;
pub use crate::math::tape::{Op, Reg};
use std::ops::Range;

/// The register that holds the time.
pub const TIME: Reg = 0;

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
    /// `x` (0) or `y` (1) of a planar frame: its origin in the plane.
    PlanarPosition(usize),
    /// `der` of a planar frame's `x` or `y`.
    PlanarVelocity(usize),
    /// A planar frame's angle about the plane's normal, in (-pi, pi].
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
        /// A torn block: the first `torn` residual ops compute the unknowns
        /// that follow from Newton's (the tearing variables); they run once
        /// more after the last step.
        torn: usize,
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
    /// A small linear block whose coefficients are numbers (a circuit of
    /// resistors and op-amps): inverted once, when compiled (row-major),
    /// so that each solve is one product.
    Constant { inverse: Vec<f64> },
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
    /// Its unknowns that index reduction computes instead of integrating
    /// (chosen once, at the start), for messages.
    pub reduced: Vec<String>,
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
    /// The code only the outputs read (the rest of a circuit's pin
    /// voltages): run after the right-hand side where outputs are recorded.
    pub output_ops: Vec<Op>,
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
    /// What the compilation found worth a warning (guesses nothing reads).
    pub notes: Vec<String>,
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
