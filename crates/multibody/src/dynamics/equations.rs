//! Evaluates the model's own equations (the register machine of
//! [`crate::system::equations`]): gathers what they read from the motion,
//! then runs each block at its place among the signal blocks. Allocates
//! nothing.

use super::{DynamicsError, Workspace};
use crate::math::dense::{lu, lu_solve};
use crate::math::expr::Cmp;
use crate::math::sparse::SparseLu;
use crate::math::tape::truth;
use crate::math::{skew, Vec3};
use crate::system::equations::{
    EquationProgram, FrameQuantity, Gather, Jacobian, Op, Sample, Solve, NEWTON_ITERATIONS, NEWTON_TOLERANCE, TIME,
};
use crate::system::System;

/// What the ops of events read and write besides registers and signals:
/// the workspace's discrete part, borrowed apart from the registers.
struct Events<'w> {
    indicators: &'w mut [f64],
    discrete: &'w mut [f64],
    pre: &'w [f64],
    reinits: &'w mut Vec<(usize, f64)>,
    at_event: bool,
    initial: bool,
    samples: &'w [Sample],
}

/// Runs `ops` on the workspace's registers and signal slots.
#[inline]
fn run_ops(ops: &[Op], samples: &[Sample], ws: &mut Workspace) {
    let mut events = Events {
        indicators: &mut ws.indicators,
        discrete: &mut ws.discrete,
        pre: &ws.discrete_pre,
        reinits: &mut ws.reinits,
        at_event: ws.at_event,
        initial: ws.initial,
        samples,
    };
    run(ops, &mut ws.registers, &mut ws.signals, &mut events);
}

/// Runs `ops` on the registers and signal slots.
#[inline]
fn run(ops: &[Op], r: &mut [f64], signals: &mut [f64], ev: &mut Events) {
    for op in ops {
        if op.run_arithmetic(r) {
            continue;
        }
        match *op {
            Op::Load(d, slot) => r[d as usize] = signals[slot],
            Op::Store(slot, a) => signals[slot] = r[a as usize],
            Op::Relation { cmp, dst, a, b, indicator, slot } => {
                let (x, y) = (r[a as usize], r[b as usize]);
                // Positive where `>` and `<` hold, and where `>=` and `<=`
                // fail, so that the relation's value is the indicator's
                // sign (`g > 0`) exactly, zero included.
                ev.indicators[indicator as usize] = match cmp {
                    Cmp::Gt | Cmp::Le => x - y,
                    _ => y - x,
                };
                if ev.at_event {
                    ev.discrete[slot as usize] = cmp.apply(x, y);
                }
                r[dst as usize] = ev.discrete[slot as usize];
            }
            Op::Initial(d) => r[d as usize] = truth(ev.initial),
            Op::Sample { dst, index } => {
                r[dst as usize] = truth(ev.at_event && ev.samples[index as usize].holds_at(r[TIME as usize]))
            }
            Op::LoadPre(d, slot) => r[d as usize] = ev.pre[slot as usize],
            Op::Fire { dst, cond, slot, at_start, impulse } => {
                let fired = if ev.at_event && impulse {
                    // The slot keeps the instant it last held at: once per instant.
                    let (now, t) = (r[cond as usize] != 0.0, r[TIME as usize]);
                    if now {
                        ev.discrete[slot as usize] = t;
                    }
                    now && ev.pre[slot as usize] != t && (at_start || !ev.initial)
                } else if ev.at_event {
                    let now = r[cond as usize] != 0.0;
                    let before = ev.pre[slot as usize] != 0.0;
                    ev.discrete[slot as usize] = truth(now);
                    now && !before && (at_start || !ev.initial)
                } else {
                    false
                };
                r[dst as usize] = truth(fired);
            }
            Op::Change { dst, value, slot } => {
                let changed = if ev.at_event {
                    let now = r[value as usize];
                    ev.discrete[slot as usize] = now;
                    now != ev.pre[slot as usize] && !ev.initial
                } else {
                    false
                };
                r[dst as usize] = truth(changed);
            }
            Op::Assign { slot, src, fire } => {
                if r[fire as usize] != 0.0 {
                    ev.discrete[slot as usize] = r[src as usize];
                }
            }
            Op::Reinit { state, src, fire } => {
                if r[fire as usize] != 0.0 {
                    ev.reinits.push((state as usize, r[src as usize]));
                }
            }
            _ => unreachable!("arithmetic ran above"),
        }
    }
}

impl System {
    /// Fills the registers the equations read from time, the state and the
    /// motion of the last kinematics pass.
    pub(crate) fn gather_equation_inputs(&self, ws: &mut Workspace, t: f64, q: &[f64], u: &[f64]) {
        let program = &self.equations;
        let r = &mut ws.registers;
        r[TIME as usize] = t;
        for gather in &program.gathers {
            match gather {
                Gather::Frame { at, reads } => {
                    let p = self.point_state(ws, at);
                    // Angular velocity in frame coordinates: der(R) = -[w] R.
                    let w = match at.anchor {
                        crate::system::Anchor::Link(k) => p.rot * ws.links[k].rot.tr_mul(&ws.links[k].v.ang),
                        crate::system::Anchor::Massless(_) => Vec3::zeros(),
                    };
                    let rate = -skew(&w) * p.rot;
                    let plane = &self.plane;
                    for &(quantity, reg) in reads {
                        ws.registers[reg as usize] = match quantity {
                            FrameQuantity::Position(i) => p.r[i],
                            FrameQuantity::Rotation(i, j) => p.rot[(i, j)],
                            FrameQuantity::Velocity(i) => p.v[i],
                            FrameQuantity::RotationRate(i, j) => rate[(i, j)],
                            FrameQuantity::PlanarPosition(i) => plane.apply_point(&p.r)[i],
                            FrameQuantity::PlanarVelocity(i) => (plane.rot * p.v)[i],
                            FrameQuantity::PlanarAngle => {
                                crate::math::rotation::planar_angle(&(p.rot * plane.rot.transpose()))
                            }
                            FrameQuantity::PlanarAngleRate => w.z,
                        };
                    }
                }
                Gather::Flange { at, position, speed } => {
                    let (s, v) = at.motion(q, u, &ws.lines);
                    for (register, value) in [(position, s), (speed, v)] {
                        if let Some(r) = register {
                            ws.registers[*r as usize] = value;
                        }
                    }
                }
                Gather::State { index, register } => {
                    let nq = q.len();
                    ws.registers[*register as usize] = if *index < nq { q[*index] } else { u[*index - nq] };
                }
                Gather::Discrete { slot, register } => ws.registers[*register as usize] = ws.discrete[*slot],
            }
        }
    }

    /// Runs equation block `b`: its loads, its solve, its stores.
    pub(crate) fn run_equation_block(&self, ws: &mut Workspace, b: usize) -> Result<(), DynamicsError> {
        let program: &EquationProgram = &self.equations;
        let block = &program.blocks[b];
        run_ops(&program.ops[block.before.clone()], &program.samples, ws);
        if let Solve::Newton { unknowns, residuals, jacobian, residual_ops, jacobian_ops, linear, torn } = &block.solve
        {
            let n = unknowns.len();
            let mut converged = false;
            for iteration in 0..NEWTON_ITERATIONS {
                run_ops(&program.ops[residual_ops.clone()], &program.samples, ws);
                run_ops(&program.ops[jacobian_ops.clone()], &program.samples, ws);
                for (s, &reg) in ws.newton_step.iter_mut().zip(residuals) {
                    *s = -ws.registers[reg as usize];
                }
                if !newton_step(jacobian, b, n, ws) {
                    return Err(DynamicsError::EquationsSingular { block: b });
                }
                let step = &ws.newton_step[..n];
                let mut largest = 0.0f64;
                for (&reg, &dx) in unknowns.iter().zip(step.iter()) {
                    let x = &mut ws.registers[reg as usize];
                    *x += dx;
                    largest = largest.max(dx.abs() / (1.0 + x.abs()));
                }
                if !largest.is_finite() {
                    return Err(DynamicsError::NotFinite);
                }
                if *linear || largest <= NEWTON_TOLERANCE || (iteration > 0 && largest <= 1e3 * f64::EPSILON) {
                    converged = true;
                    break;
                }
            }
            if !converged {
                return Err(DynamicsError::EquationsDiverged { block: b });
            }
            // The torn unknowns from the tearing variables' last values.
            let torn = residual_ops.start..residual_ops.start + torn;
            run_ops(&program.ops[torn], &program.samples, ws);
        }
        run_ops(&program.ops[block.after.clone()], &program.samples, ws);
        Ok(())
    }

    /// The blocks that read the multipliers of measured couplings (the
    /// flows through in-line sensors), once the accelerations gave them.
    pub(crate) fn run_blocks_after_accelerations(&self, ws: &mut Workspace) -> Result<(), DynamicsError> {
        let program = &self.equations;
        for &(row, register) in &program.reactions {
            ws.registers[register as usize] = ws.lambda[row];
        }
        for b in program.first_post..program.blocks.len() {
            self.run_equation_block(ws, b)?;
        }
        Ok(())
    }

    /// The `when` clauses, after every block: their conditions (which
    /// watch for events), and at events what they do.
    pub(crate) fn run_when_clauses(&self, ws: &mut Workspace) {
        let program: &EquationProgram = &self.equations;
        run_ops(&program.ops[program.when_conditions.clone()], &program.samples, ws);
        if ws.at_event {
            run_ops(&program.ops[program.when_actions.clone()], &program.samples, ws);
        }
    }

    /// The code only the outputs read, after the right-hand side.
    pub(crate) fn run_output_equations(&self, ws: &mut Workspace) {
        run_ops(&self.equations.output_ops, &self.equations.samples, ws);
    }

    /// Copies the equations' states from `x` into their registers.
    #[inline]
    pub(crate) fn load_equation_states(&self, ws: &mut Workspace, x: &[f64]) {
        let first = self.equations.first_state as usize;
        ws.registers[first..first + x.len()].copy_from_slice(x);
    }

    /// The rates of the equations' states, after the blocks ran, into `dx`.
    #[inline]
    pub(crate) fn equation_rates(&self, ws: &Workspace, dx: &mut [f64]) {
        for (d, &reg) in dx.iter_mut().zip(&self.equations.rates) {
            *d = ws.registers[reg as usize];
        }
    }
}

/// Solves `J dx = newton_step` for the Newton step of block `b`, in
/// place, with the Jacobian's values in the registers. False when `J` is
/// singular.
fn newton_step(jacobian: &Jacobian, b: usize, n: usize, ws: &mut Workspace) -> bool {
    let registers = &ws.registers;
    match jacobian {
        Jacobian::Dense(regs) => {
            let matrix = &mut ws.newton_factors[..n * n];
            for (m, &reg) in matrix.iter_mut().zip(regs) {
                *m = registers[reg as usize];
            }
            if !lu(matrix, n, &mut ws.newton_pivots[..n]) {
                return false;
            }
            lu_solve(matrix, n, &ws.newton_pivots[..n], &mut ws.newton_step[..n], &mut ws.newton_work[..n]);
            true
        }
        Jacobian::Constant { inverse } => {
            let (step, work) = (&mut ws.newton_step[..n], &mut ws.newton_work[..n]);
            work.copy_from_slice(step);
            for (s, row) in step.iter_mut().zip(inverse.chunks_exact(n)) {
                *s = row.iter().zip(work.iter()).map(|(a, b)| a * b).sum();
            }
            true
        }
        Jacobian::Sparse { entries, lu: compiled } => {
            let values = || entries.iter().map(|&reg| registers[reg as usize]);
            let layout = ws.newton_layouts[b].as_ref().unwrap_or(compiled);
            let factors = &mut ws.newton_factors[..layout.stored()];
            layout.load(values(), factors);
            if !layout.factor(factors) {
                // The pivots do not suit these values: choose them again
                // from the values, and keep that choice.
                let now: Vec<f64> = values().collect();
                let Some(chosen) = SparseLu::analyse(n, compiled.pattern(), Some(&now)) else {
                    return false;
                };
                if ws.newton_factors.len() < chosen.stored() {
                    ws.newton_factors.resize(chosen.stored(), 0.0);
                }
                let factors = &mut ws.newton_factors[..chosen.stored()];
                chosen.load(now.iter().copied(), factors);
                if !chosen.factor(factors) {
                    return false;
                }
                ws.newton_layouts[b] = Some(chosen);
            }
            let layout = ws.newton_layouts[b].as_ref().unwrap_or(compiled);
            layout.solve(&ws.newton_factors[..layout.stored()], &mut ws.newton_step[..n], &mut ws.newton_work[..n]);
            true
        }
    }
}
