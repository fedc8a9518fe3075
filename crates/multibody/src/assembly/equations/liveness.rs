//! Moves the code that only the outputs read out of the right-hand side,
//! and drops the code nothing reads.
//!
//! A circuit's equations compute every pin's voltage and current, but the
//! dynamics needs only what reaches a state's rate, a signal, a solve or
//! an event; in the industrial robot that is a third of the code. The
//! code that computes the other variables runs where the outputs are
//! recorded (and where the start is solved), after the right-hand side,
//! in its original order. Registers are written once per evaluation
//! (fresh for every result), so the values it reads are still there then.

use crate::math::tape::{Op, Reg};
use crate::system::equations::{EquationProgram, Jacobian, Solve};
use std::ops::Range;

/// Splits `program.ops` into the code the dynamics needs and
/// `program.output_ops` (what computes the variables `vars` and the
/// outputs besides), renumbering the blocks' ranges.
pub(super) fn split_output_code(program: &mut EquationProgram, vars: &[Reg]) {
    let ops = &program.ops;
    let mut needed = vec![false; program.registers];
    let mut need = |regs: &mut dyn Iterator<Item = u32>| {
        for r in regs {
            needed[r as usize] = true;
        }
    };
    need(&mut program.rates.iter().copied());
    // Solves and `when` clauses run whole: their code stays.
    let mut whole: Vec<Range<usize>> = vec![program.when_conditions.clone(), program.when_actions.clone()];
    for block in &program.blocks {
        if let Solve::Newton { unknowns, residuals, jacobian, residual_ops, jacobian_ops, .. } = &block.solve {
            need(&mut unknowns.iter().chain(residuals).copied());
            match jacobian {
                Jacobian::Dense(regs) | Jacobian::Sparse { entries: regs, .. } => need(&mut regs.iter().copied()),
                Jacobian::Constant { .. } => {}
            }
            whole.extend([residual_ops.clone(), jacobian_ops.clone()]);
        }
    }
    let mut kept = vec![false; ops.len()];
    for range in whole {
        kept[range].fill(true);
    }
    mark(ops, &mut kept, &mut needed, true);
    let dynamics_needs = kept;
    // What the variables and outputs need besides.
    let mut wanted = dynamics_needs.clone();
    let mut needed = vec![false; program.registers];
    for &r in vars.iter().chain(program.outputs.iter().map(|(_, r)| r)) {
        if let Some(n) = needed.get_mut(r as usize) {
            *n = true;
        }
    }
    mark(ops, &mut wanted, &mut needed, false);
    if dynamics_needs.iter().all(|&k| k) {
        return;
    }
    // `before[i]`: how many kept ops precede op `i`; a range maps to the
    // kept ops inside it.
    let mut before = Vec::with_capacity(ops.len() + 1);
    let (mut dynamics, mut outputs) = (Vec::new(), Vec::new());
    for (i, &op) in ops.iter().enumerate() {
        before.push(dynamics.len());
        if dynamics_needs[i] {
            dynamics.push(op)
        } else if wanted[i] {
            outputs.push(op)
        }
    }
    before.push(dynamics.len());
    let map = |r: &mut Range<usize>| *r = before[r.start]..before[r.end];
    for block in &mut program.blocks {
        map(&mut block.before);
        map(&mut block.after);
        if let Solve::Newton { residual_ops, jacobian_ops, .. } = &mut block.solve {
            map(residual_ops);
            map(jacobian_ops);
        }
    }
    map(&mut program.when_conditions);
    map(&mut program.when_actions);
    program.ops = dynamics;
    program.output_ops = outputs;
}

/// Marks the ops that write a `needed` register (and, with `effects`,
/// those that store or watch for events), and what they read, backwards
/// from the last; again while a pass finds more (a solve's code can read
/// what a later range writes first).
fn mark(ops: &[Op], kept: &mut [bool], needed: &mut [bool], effects: bool) {
    loop {
        let mut changed = false;
        for (i, &op) in ops.iter().enumerate().rev() {
            let wanted = kept[i] || (effects && op.has_effects()) || op.dst().is_some_and(|d| needed[d as usize]);
            if wanted {
                changed |= !kept[i];
                kept[i] = true;
                for r in op.sources() {
                    changed |= !needed[r as usize];
                    needed[r as usize] = true;
                }
            }
        }
        if !changed {
            return;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::system::equations::EquationBlock;

    /// `r3 = r1 + r2` feeds the rate, `r4 = -r3` only an output: it moves,
    /// and the block's range shrinks to the op that stays.
    #[test]
    fn code_only_outputs_read_moves_after_the_dynamics() {
        let mut program = EquationProgram {
            registers: 5,
            rates: vec![3],
            ops: vec![Op::Add(3, 1, 2), Op::Neg(4, 3)],
            blocks: vec![EquationBlock {
                before: 0..2,
                solve: Solve::Explicit,
                after: 2..2,
                label: String::new(),
                reduced: vec![],
            }],
            when_conditions: 2..2,
            when_actions: 2..2,
            ..EquationProgram::default()
        };
        split_output_code(&mut program, &[4]);
        assert_eq!(program.ops, vec![Op::Add(3, 1, 2)]);
        assert_eq!(program.output_ops, vec![Op::Neg(4, 3)]);
        assert_eq!(program.blocks[0].before, 0..1);
        assert_eq!((program.when_conditions.clone(), program.when_actions.clone()), (1..1, 1..1));
    }

    /// What neither the dynamics nor a variable reads is dropped.
    #[test]
    fn code_nothing_reads_is_dropped() {
        let mut program = EquationProgram {
            registers: 5,
            rates: vec![3],
            ops: vec![Op::Add(3, 1, 2), Op::Neg(4, 3)],
            when_conditions: 2..2,
            when_actions: 2..2,
            ..EquationProgram::default()
        };
        split_output_code(&mut program, &[]);
        assert_eq!((program.ops.len(), program.output_ops.len()), (1, 0));
    }

    /// A store and what it reads stay, though no rate reads them.
    #[test]
    fn stores_and_their_inputs_stay() {
        let mut program = EquationProgram {
            registers: 3,
            ops: vec![Op::Neg(2, 1), Op::Store(0, 2)],
            when_conditions: 2..2,
            when_actions: 2..2,
            ..EquationProgram::default()
        };
        split_output_code(&mut program, &[]);
        assert_eq!(program.ops.len(), 2);
        assert!(program.output_ops.is_empty());
    }
}
