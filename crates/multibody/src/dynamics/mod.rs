//! Dynamics over the compiled numeric model ([`System`]) and a mutable
//! [`Workspace`]: the articulated-body algorithm for the right-hand side of
//! the ODE (`aba`), forces between frames and massless groups (`forces`),
//! and constraints of loops and couplings (`constraints`).

mod aba;
mod balance;
pub(crate) mod chart;
mod constraints;
mod derivatives;
mod drives;
mod equations;
pub(crate) mod forces;
mod friction;
mod jacobian;
mod signals;

pub use derivatives::DynamicsDerivatives;
pub use jacobian::StateJacobian;

use crate::math::{ArticulatedInertia, Force, Mat3, Motion, Transform, Vec3};
use crate::system::System;
use nalgebra::{Matrix6, Vector6};

/// Why the dynamics could not be evaluated at a state.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum DynamicsError {
    /// The Euler angles of a link reached their singular configuration at `time`.
    EulerSingularity { link: usize, time: f64 },
    /// The articulated inertia seen by a joint is not positive definite.
    SingularInertia { link: usize },
    /// The mass matrix of a mechanism with constraints is singular; `dof`
    /// (a velocity coordinate) is the one with the least inertia.
    SingularMotion { dof: usize },
    /// A value became infinite or NaN.
    NotFinite,
    /// No position of a massless group balances the forces on it.
    MasslessWithoutBalance { group: usize },
    /// The Jacobian of a block of the model's equations is singular.
    EquationsSingular { block: usize },
    /// Newton's method did not converge on a block of the model's equations.
    EquationsDiverged { block: usize },
    /// The normal forces of slipping wheels (whose friction follows them)
    /// and the other constraint forces have no unique solution.
    ContactIndeterminate { link: usize },
    /// Projection cannot bring constraint `constraint` back: its position
    /// equations stay violated by `residual` (m or rad). The loop cannot
    /// close in the configuration the motion reached.
    LoopOpen { constraint: usize, residual: f64 },
}

/// Scratch memory of the dynamics for one mechanism: everything the
/// algorithms write, allocated once.
#[derive(Clone, Debug)]
pub struct Workspace {
    pub(crate) links: Vec<LinkWork>,
    /// For links whose joint has more than one degree of freedom.
    pub(crate) multi: Vec<MultiWork>,
    /// Per link, its index in `multi` (unused for 1-DOF joints).
    pub(crate) multi_index: Vec<usize>,
    /// Generalised forces of the 1-D elements, one per velocity coordinate.
    pub(crate) tau: Vec<f64>,
    /// The lines whose lengths place 1-D connectors, and their tensions.
    pub(crate) lines: Vec<crate::system::LineState>,
    /// Signal values at the current time; the last slot is always zero.
    pub(crate) signals: Vec<f64>,
    /// First and second time derivatives of the signals of time only.
    pub(crate) signal_rates: Vec<[f64; 2]>,
    /// The state with the driven coordinates set exactly (scratch).
    pub(crate) driven_state: Vec<f64>,
    /// Accelerations the drives impose, by velocity coordinate.
    pub(crate) imposed: Vec<f64>,
    /// Positions and velocities of the massless groups.
    pub(crate) massless_pos: Vec<Vec3>,
    pub(crate) massless_vel: Vec<Vec3>,
    // Constraint buffers: rows x nv Jacobian, nv x nv mass matrix (and its
    // factor), rows x nv rows of M^-1 J', rows x rows Schur complement.
    pub(crate) jac: Vec<f64>,
    /// Rows x nv: what a row's multiplier applies beyond `J'`: the
    /// generalised friction forces of slipping wheels per unit multiplier
    /// of their contact rows, `B - J` on a servo's rows, zero elsewhere.
    pub(crate) jac_force: Vec<f64>,
    /// Per constraint row: the value, rate and acceleration it must have
    /// (a servo's formulas of time; zero for every other row).
    pub(crate) targets: Vec<[f64; 3]>,
    pub(crate) mass: Vec<f64>,
    pub(crate) y_rows: Vec<f64>,
    pub(crate) schur: Vec<f64>,
    pub(crate) perm: Vec<usize>,
    /// Row pivots of the mass matrix's LU factors, when it is indefinite.
    pub(crate) pivots: Vec<usize>,
    pub(crate) lambda: Vec<f64>,
    pub(crate) residual: Vec<f64>,
    pub(crate) bias: Vec<f64>,
    pub(crate) work: Vec<f64>,
    pub(crate) du: Vec<f64>,
    pub(crate) composite: Vec<crate::math::RigidInertia>,
    pub(crate) bias_acc: Vec<Motion>,
    /// Registers of the model's own equations (see `system::equations`),
    /// holding their last solution (Newton's next start).
    pub(crate) registers: Vec<f64>,
    /// Newton's scratch: the Jacobian's factors, the step, LU work; and
    /// pivots.
    pub(crate) newton_factors: Vec<f64>,
    /// For each block, the sparse layout chosen again at run time when
    /// the compiled pivots did not suit the values (rare: it allocates).
    pub(crate) newton_layouts: Vec<Option<crate::math::sparse::SparseLu>>,
    pub(crate) newton_step: Vec<f64>,
    pub(crate) newton_work: Vec<f64>,
    pub(crate) newton_pivots: Vec<usize>,
    /// The values of the model's inputs, as the host set them.
    pub(crate) inputs: Vec<f64>,
    /// The event indicators of the last evaluation (see `EventLayout`).
    pub(crate) indicators: Vec<f64>,
    /// The discrete state, and its value before the current pass of an
    /// event iteration (`pre`).
    pub(crate) discrete: Vec<f64>,
    pub(crate) discrete_pre: Vec<f64>,
    /// Set during an event iteration: relations are evaluated as they are
    /// and modes may change; between events they hold.
    pub(crate) at_event: bool,
    /// Set during the first event iteration, at the start (`initial()`).
    pub(crate) initial: bool,
    /// State values that the last event pass sets (`reinit`): index, value.
    pub(crate) reinits: Vec<(usize, f64)>,
    /// What each friction element computed in the last evaluation.
    pub(crate) friction: Vec<crate::system::friction::FrictionValues>,
    /// The time of the time event the integration is heading for: sources
    /// show their values from before it there (NaN: none).
    pub(crate) left_limit_at: f64,
}

/// What the articulated-body algorithm keeps per link.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct LinkWork {
    /// Parent link frame to this link frame.
    pub x_up: Transform,
    /// Spatial velocity and acceleration, link coordinates.
    pub v: Motion,
    pub a: Motion,
    /// Velocity-product acceleration.
    pub c: Motion,
    pub ia: ArticulatedInertia,
    pub pa: Force,
    /// Motion subspace of a 1-DOF joint, and `U = IA S`, `1/D`, `u`.
    pub s: Motion,
    pub u_force: Force,
    pub d_inv: f64,
    pub u: f64,
    /// World to link rotation, and the link origin in the world.
    pub rot: Mat3,
    pub pos: Vec3,
}

/// The same for a joint with several degrees of freedom.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct MultiWork {
    pub s: [Motion; 6],
    pub u_force: [Force; 6],
    pub d_inv: Matrix6<f64>,
    pub u: Vector6<f64>,
}

impl Workspace {
    pub fn new(system: &System) -> Self {
        let n = system.links.len();
        let mut multi_index = vec![usize::MAX; n];
        let mut multi = Vec::new();
        for (k, link) in system.links.iter().enumerate().skip(1) {
            if link.joint.nv() > 1 {
                multi_index[k] = multi.len();
                multi.push(MultiWork::default());
            }
        }
        let ground = LinkWork { rot: Mat3::identity(), ..LinkWork::default() };
        let (m, nv) = (system.constraint_rows, system.states.nv);
        let full = system.uses_mass_matrix();
        let mut ws = Self {
            links: vec![ground; n],
            multi,
            multi_index,
            tau: vec![0.0; system.states.nv],
            lines: vec![Default::default(); system.lines.len()],
            signals: vec![0.0; system.signal_slots],
            signal_rates: vec![[0.0; 2]; system.signal_slots],
            driven_state: vec![
                0.0;
                if system.drives.is_empty() { 0 } else { system.states.nq + nv + system.states.nx }
            ],
            imposed: vec![0.0; if system.drives.is_empty() { 0 } else { nv }],
            massless_pos: system.massless.iter().map(|g| g.guess).collect(),
            massless_vel: vec![Vec3::zeros(); system.massless.len()],
            jac: vec![0.0; m * nv],
            jac_force: vec![0.0; m * nv],
            targets: vec![[0.0; 3]; m],
            mass: vec![0.0; if full { nv * nv } else { 0 }],
            y_rows: vec![0.0; m * nv],
            schur: vec![0.0; m * m],
            perm: vec![0; m],
            pivots: vec![0; if full { nv } else { 0 }],
            lambda: vec![0.0; m],
            residual: vec![0.0; m],
            bias: vec![0.0; m],
            work: vec![0.0; m.max(nv)],
            du: vec![0.0; nv],
            composite: vec![crate::math::RigidInertia::ZERO; n],
            bias_acc: vec![Motion::ZERO; n],
            registers: system.equation_registers(),
            newton_factors: vec![0.0; system.equations.largest_factors],
            newton_layouts: vec![None; system.equations.blocks.len()],
            newton_step: vec![0.0; system.equations.largest_block],
            newton_work: vec![0.0; system.equations.largest_block],
            newton_pivots: vec![0; system.equations.largest_block],
            inputs: system.events.inputs.iter().map(|i| i.1).collect(),
            indicators: vec![0.0; system.events.indicators.len()],
            discrete: system.events.discrete_start.clone(),
            discrete_pre: system.events.discrete_start.clone(),
            at_event: false,
            initial: false,
            reinits: Vec::with_capacity(system.states.start.len() + system.equations.reinits),
            left_limit_at: f64::NAN,
            friction: vec![Default::default(); system.frictions.len()],
        };
        // Assembly closes a servo's rows at t = 0 before any evaluation.
        system.servo_targets(&mut ws, 0.0);
        ws
    }
}

impl Workspace {
    /// The constraint Jacobian (rows x nv, row-major) of the last
    /// evaluation with constraints.
    pub fn constraint_jacobian(&self) -> &[f64] {
        &self.jac
    }

    /// The constraint multipliers of the last evaluation: the generalised
    /// constraint forces are `J' lambda`.
    pub fn multipliers(&self) -> &[f64] {
        &self.lambda
    }

    /// The velocity-product terms `Jdot u` of the last evaluation with
    /// constraints: the accelerations keep `J ud = -Jdot u`.
    pub fn constraint_velocity_product(&self) -> &[f64] {
        &self.bias
    }
}

impl System {
    /// The right-hand side of the ODE: `dy = f(t, y)` with
    /// `y = [q, u]`. Allocates nothing.
    pub fn rhs(&self, ws: &mut Workspace, t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), DynamicsError> {
        if self.drives.is_empty() {
            return self.rhs_at(ws, t, y, dy);
        }
        let mut exact = std::mem::take(&mut ws.driven_state);
        exact.copy_from_slice(y);
        self.impose_drives(ws, t, &mut exact);
        let result = self.rhs_at(ws, t, &exact, dy);
        ws.driven_state = exact;
        result
    }

    /// [`System::rhs`] at a state whose driven coordinates are exact.
    fn rhs_at(&self, ws: &mut Workspace, t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), DynamicsError> {
        let (nq, nv) = (self.states.nq, self.states.nv);
        let (y, x) = y.split_at(nq + nv);
        let (dy, dx) = dy.split_at_mut(nq + nv);
        if !x.is_empty() {
            self.load_equation_states(ws, x);
        }
        let (q, u) = y.split_at(nq);
        let (qd, ud) = dy.split_at_mut(nq);
        for link in &self.links[1..] {
            let (qo, vo) = (link.q_offset, link.v_offset);
            link.joint.qdot(
                &q[qo..qo + link.joint.nq()],
                &u[vo..vo + link.joint.nv()],
                &mut qd[qo..qo + link.joint.nq()],
            );
        }
        self.forward_dynamics(ws, t, q, u, ud).map_err(|e| match e {
            DynamicsError::EulerSingularity { link, .. } => DynamicsError::EulerSingularity { link, time: t },
            other => other,
        })?;
        if !self.balances.is_empty() {
            self.balance_accelerations(ws, q, u, ud);
        }
        if self.equations.first_post < self.equations.blocks.len() {
            self.run_blocks_after_accelerations(ws)?;
        }
        self.equation_rates(ws, dx);
        Ok(())
    }

    /// The equations' registers with their constants and the states' start values.
    fn equation_registers(&self) -> Vec<f64> {
        let program = &self.equations;
        let mut r = vec![0.0; program.registers];
        for &(reg, value) in &program.constants {
            r[reg as usize] = value;
        }
        let first = program.first_state as usize;
        let start = &self.states.start[self.states.nq + self.states.nv..];
        r[first..first + start.len()].copy_from_slice(start);
        r
    }
}
