//! Folds what the compiled equations know before they run: results of
//! numbers alone, copies, and the identities of adding zero, multiplying
//! by one and negating twice. Connections give many variables that are
//! another's copy, its negation, or zero (a grounded pin's potential), and
//! solving for them adds more; written out, a third of the robot's
//! circuit code was moves like these.
//!
//! Each rewrite gives exactly the value it replaces (up to the sign of a
//! zero). A register written by the dynamics (time, gathered motion,
//! states, a solve's unknowns, reactions) or by more than one instruction
//! is left as it is.

use crate::math::tape::{Op, Reg};
use crate::system::equations::{EquationProgram, Gather, Jacobian, Solve, TIME};
use std::collections::HashMap;

/// Rewrites `program` in place; `vars` (each variable's register) follows
/// the registers that moved. Instructions whose results nobody reads any
/// more are left for [`super::liveness`] to drop.
pub(super) fn fold(program: &mut EquationProgram, vars: &mut [Reg]) {
    let n = program.registers;
    let mut writes = vec![0u32; n];
    for r in external_writes(program) {
        writes[r as usize] += 2;
    }
    for op in &program.ops {
        if let Some(d) = op.dst() {
            writes[d as usize] += 1;
        }
    }
    let mut value: Vec<Option<f64>> = vec![None; n];
    let mut by_bits = HashMap::new();
    for &(r, x) in &program.constants {
        if writes[r as usize] == 0 {
            value[r as usize] = Some(x);
            by_bits.entry(x.to_bits()).or_insert(r);
        }
    }
    let mut alias: Vec<Reg> = (0..n as Reg).collect();
    // The instruction that last wrote each register (after rewriting).
    let mut def: Vec<Option<Op>> = vec![None; n];
    for op in &mut program.ops {
        map_sources(op, |r| alias[r as usize]);
        let Some(d) = op.dst() else { continue };
        if writes[d as usize] != 1 || !is_pure(*op) {
            def[d as usize] = Some(*op);
            continue;
        }
        let rewritten = rewrite(*op, &value, &def);
        let target = match rewritten {
            Rewrite::Same(new) => {
                *op = new;
                def[d as usize] = Some(new);
                continue;
            }
            Rewrite::Alias(r) => r,
            Rewrite::Number(x) => *by_bits.entry(x.to_bits()).or_insert_with(|| {
                program.registers += 1;
                value.push(Some(x));
                alias.push(program.registers as Reg - 1);
                def.push(None);
                program.constants.push((program.registers as Reg - 1, x));
                program.registers as Reg - 1
            }),
        };
        alias[d as usize] = target;
        if let Some(x) = value[target as usize] {
            value[d as usize] = Some(x);
        }
        def[d as usize] = def[target as usize];
    }
    // Readers that run before their writer in the list (a solve's loop)
    // and everything outside the instructions that names a register.
    let resolve = |r: &mut Reg| {
        if let Some(&a) = alias.get(*r as usize) {
            *r = a;
        }
    };
    for op in &mut program.ops {
        map_sources(op, |r| alias[r as usize]);
    }
    program.rates.iter_mut().for_each(resolve);
    program.outputs.iter_mut().for_each(|(_, r)| resolve(r));
    vars.iter_mut().for_each(resolve);
    for block in &mut program.blocks {
        if let Solve::Newton { residuals, jacobian, .. } = &mut block.solve {
            residuals.iter_mut().for_each(resolve);
            match jacobian {
                Jacobian::Dense(regs) | Jacobian::Sparse { entries: regs, .. } => regs.iter_mut().for_each(resolve),
                Jacobian::Constant { .. } => {}
            }
        }
    }
}

/// What an instruction becomes.
enum Rewrite {
    /// Still an instruction (perhaps a simpler one).
    Same(Op),
    /// Its result is this register's value.
    Alias(Reg),
    /// Its result is this number.
    Number(f64),
}

fn rewrite(op: Op, value: &[Option<f64>], def: &[Option<Op>]) -> Rewrite {
    let is = |r: Reg, x: f64| value[r as usize] == Some(x) || (x == 0.0 && value[r as usize] == Some(-x));
    let negated = |r: Reg| match def[r as usize] {
        Some(Op::Neg(_, x)) => Some(x),
        _ => None,
    };
    if op.sources().all(|r| value[r as usize].is_some()) {
        // Runs the instruction on a scratch copy of the registers it reads.
        let mut scratch = [0.0; 4];
        let mut local = op;
        let mut k = 0;
        map_sources(&mut local, |r| {
            k += 1;
            scratch[k] = value[r as usize].unwrap_or(0.0);
            k as Reg
        });
        set_dst(&mut local, 0);
        if local.run_arithmetic(&mut scratch) {
            return Rewrite::Number(scratch[0]);
        }
    }
    match op {
        Op::Copy(_, a) => Rewrite::Alias(a),
        Op::Add(_, a, b) if is(b, 0.0) => Rewrite::Alias(a),
        Op::Add(_, a, b) if is(a, 0.0) => Rewrite::Alias(b),
        Op::Add(d, a, b) => match (negated(a), negated(b)) {
            (_, Some(x)) => Rewrite::Same(Op::Sub(d, a, x)),
            (Some(x), _) => Rewrite::Same(Op::Sub(d, b, x)),
            _ => Rewrite::Same(op),
        },
        Op::Sub(_, a, b) if is(b, 0.0) => Rewrite::Alias(a),
        Op::Sub(d, a, b) if is(a, 0.0) => rewrite(Op::Neg(d, b), value, def),
        Op::Sub(d, a, b) => match negated(b) {
            Some(x) => Rewrite::Same(Op::Add(d, a, x)),
            None => Rewrite::Same(op),
        },
        Op::Mul(_, a, b) if is(b, 1.0) => Rewrite::Alias(a),
        Op::Mul(_, a, b) if is(a, 1.0) => Rewrite::Alias(b),
        Op::Mul(d, a, b) if is(b, -1.0) => rewrite(Op::Neg(d, a), value, def),
        Op::Mul(d, a, b) if is(a, -1.0) => rewrite(Op::Neg(d, b), value, def),
        Op::Div(_, a, b) if is(b, 1.0) => Rewrite::Alias(a),
        Op::Div(d, a, b) if is(b, -1.0) => rewrite(Op::Neg(d, a), value, def),
        Op::Neg(d, a) => match def[a as usize] {
            Some(Op::Neg(_, x)) => Rewrite::Alias(x),
            // -(x - y) = y - x: one instruction, and the difference may go.
            Some(Op::Sub(_, x, y)) => Rewrite::Same(Op::Sub(d, y, x)),
            _ => Rewrite::Same(op),
        },
        _ => Rewrite::Same(op),
    }
}

/// Arithmetic, with nothing but its register as a result.
fn is_pure(op: Op) -> bool {
    !op.has_effects()
        && !matches!(op, Op::Load(..) | Op::Initial(_) | Op::LoadPre(..) | Op::Sample { .. } | Op::Fire { .. })
}

/// The registers something other than an instruction writes.
fn external_writes(program: &EquationProgram) -> Vec<Reg> {
    let mut regs = vec![TIME];
    let first = program.first_state;
    regs.extend(first..first + program.rates.len() as Reg);
    regs.extend(program.reactions.iter().map(|&(_, r)| r));
    for gather in &program.gathers {
        match gather {
            Gather::Frame { reads, .. } => regs.extend(reads.iter().map(|&(_, r)| r)),
            Gather::Flange { position, speed, .. } => regs.extend(position.iter().chain(speed)),
            Gather::State { register, .. } | Gather::Discrete { register, .. } => regs.push(*register),
        }
    }
    for block in &program.blocks {
        if let Solve::Newton { unknowns, .. } = &block.solve {
            regs.extend(unknowns);
        }
    }
    regs
}

/// Applies `f` to each register the instruction reads.
fn map_sources(op: &mut Op, mut f: impl FnMut(Reg) -> Reg) {
    for r in op.sources_mut().into_iter().flatten() {
        *r = f(*r);
    }
}

fn set_dst(op: &mut Op, d: Reg) {
    if let Some(r) = op.dst_mut() {
        *r = d;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn program(ops: Vec<Op>, constants: Vec<(Reg, f64)>, registers: usize, rates: Vec<Reg>) -> EquationProgram {
        EquationProgram { registers, constants, ops, rates, first_state: 1, ..EquationProgram::default() }
    }

    /// r3 = r1 + 0 (r2 = -0, a grounded pin), r4 = -r3, r5 = -r4: r5 is r1.
    #[test]
    fn zeros_copies_and_double_negations_fold_to_the_value_they_pass_on() {
        let ops = vec![Op::Add(3, 1, 2), Op::Neg(4, 3), Op::Neg(5, 4), Op::Mul(6, 5, 5)];
        // r1 is the state (first_state 1; one rate read from r6).
        let mut p = program(ops, vec![(2, -0.0)], 7, vec![6]);
        let mut vars = vec![3, 4, 5];
        fold(&mut p, &mut vars);
        assert_eq!(vars, vec![1, 4, 1]);
        assert_eq!(p.ops[3], Op::Mul(6, 1, 1));
    }

    /// Numbers alone give a number, held in a register of constants.
    #[test]
    fn numbers_alone_fold_to_a_constant() {
        let ops = vec![Op::Mul(4, 2, 3), Op::Add(5, 1, 4)];
        let mut p = program(ops, vec![(2, 3.0), (3, 0.5)], 6, vec![5]);
        let mut vars = vec![4];
        fold(&mut p, &mut vars);
        assert_eq!(p.constants.iter().find(|c| c.0 == vars[0]).map(|c| c.1), Some(1.5));
        assert_eq!(p.ops[1], Op::Add(5, 1, vars[0]));
    }

    /// `a + (-b)` becomes `a - b`; `-(a - b)` becomes `b - a`.
    #[test]
    fn negations_fold_into_sums_and_differences() {
        let ops = vec![Op::Neg(3, 2), Op::Add(4, 1, 3), Op::Sub(5, 1, 2), Op::Neg(6, 5)];
        let mut p = program(ops, vec![], 7, vec![4]);
        p.gathers = vec![Gather::State { index: 0, register: 2 }];
        fold(&mut p, &mut []);
        assert_eq!(p.ops[1], Op::Sub(4, 1, 2));
        assert_eq!(p.ops[3], Op::Sub(6, 2, 1));
    }
}
