//! The one compiled form of formulas: straight-line code on registers.
//! [`Op`] is the instruction set, its arithmetic run by one interpreter,
//! that every compiled formula uses: the model's equations (whose program
//! adds moves between registers and signal slots and the instructions of
//! events) and the formulas compiled here, a formula of time with its time derivatives
//! (prescribed motion) and a road's height with its gradient and curvature.
//! Their derivatives come from the one symbolic differentiation
//! ([`super::symbolic`]), so no rule of calculus is written twice. A
//! subexpression met twice is computed once. Evaluating allocates nothing.

use super::expr::{Cmp, Expr, Func, Func2, Node};
use std::collections::HashMap;

/// A register number.
pub type Reg = u32;

/// One instruction: `dst = f(operands)` on registers (booleans are 1 and
/// 0); the model's equations' program adds moves between registers and
/// signal slots and the instructions of events, which the dynamics run
/// (formulas compiled here never hold them).
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

impl Op {
    /// Runs an arithmetic instruction on registers `r`; false (and nothing
    /// done) for the others.
    #[inline(always)]
    pub fn run_arithmetic(self, r: &mut [f64]) -> bool {
        match self {
            Op::Copy(d, a) => r[d as usize] = r[a as usize],
            Op::Neg(d, a) => r[d as usize] = -r[a as usize],
            Op::Add(d, a, b) => r[d as usize] = r[a as usize] + r[b as usize],
            Op::Sub(d, a, b) => r[d as usize] = r[a as usize] - r[b as usize],
            Op::Mul(d, a, b) => r[d as usize] = r[a as usize] * r[b as usize],
            Op::Div(d, a, b) => r[d as usize] = r[a as usize] / r[b as usize],
            Op::Pow(d, a, b) => r[d as usize] = power(r[a as usize], r[b as usize]),
            Op::Call(f, d, a) => r[d as usize] = f.apply(r[a as usize]),
            Op::Call2(f, d, a, b) => r[d as usize] = f.apply(r[a as usize], r[b as usize]),
            Op::Compare(c, d, a, b) => r[d as usize] = c.apply(r[a as usize], r[b as usize]),
            Op::And(d, a, b) => r[d as usize] = truth(r[a as usize] != 0.0 && r[b as usize] != 0.0),
            Op::Or(d, a, b) => r[d as usize] = truth(r[a as usize] != 0.0 || r[b as usize] != 0.0),
            Op::Not(d, a) => r[d as usize] = truth(r[a as usize] == 0.0),
            Op::Select(d, c, a, b) => r[d as usize] = if r[c as usize] != 0.0 { r[a as usize] } else { r[b as usize] },
            _ => return false,
        }
        true
    }

    /// The arithmetic instruction that computes node `e` into `d` from
    /// the registers `x` of its operands (in [`Expr::children`] order);
    /// `None` for a node that is not arithmetic.
    pub fn arithmetic<V>(e: &Expr<V>, d: Reg, x: [Reg; 3]) -> Option<Op> {
        Some(match e {
            Expr::Neg(_) => Op::Neg(d, x[0]),
            Expr::Not(_) => Op::Not(d, x[0]),
            Expr::Call(f, _) => Op::Call(*f, d, x[0]),
            Expr::Add(..) => Op::Add(d, x[0], x[1]),
            Expr::Sub(..) => Op::Sub(d, x[0], x[1]),
            Expr::Mul(..) => Op::Mul(d, x[0], x[1]),
            Expr::Div(..) => Op::Div(d, x[0], x[1]),
            Expr::Pow(..) => Op::Pow(d, x[0], x[1]),
            Expr::Call2(f, ..) => Op::Call2(*f, d, x[0], x[1]),
            Expr::Compare(c, ..) => Op::Compare(*c, d, x[0], x[1]),
            Expr::And(..) => Op::And(d, x[0], x[1]),
            Expr::Or(..) => Op::Or(d, x[0], x[1]),
            Expr::If(..) => Op::Select(d, x[0], x[1], x[2]),
            _ => return None,
        })
    }

    /// The register the instruction writes (a store, an assignment and a
    /// re-initialization write none).
    pub fn dst(mut self) -> Option<Reg> {
        self.dst_mut().copied()
    }

    /// The register the instruction writes, to renumber it.
    pub fn dst_mut(&mut self) -> Option<&mut Reg> {
        match self {
            Op::Copy(d, _)
            | Op::Neg(d, _)
            | Op::Add(d, ..)
            | Op::Sub(d, ..)
            | Op::Mul(d, ..)
            | Op::Div(d, ..)
            | Op::Pow(d, ..)
            | Op::Call(_, d, _)
            | Op::Call2(_, d, ..)
            | Op::Compare(_, d, ..)
            | Op::And(d, ..)
            | Op::Or(d, ..)
            | Op::Not(d, _)
            | Op::Select(d, ..)
            | Op::Load(d, _)
            | Op::Relation { dst: d, .. }
            | Op::Initial(d)
            | Op::LoadPre(d, _)
            | Op::Fire { dst: d, .. }
            | Op::Sample { dst: d, .. }
            | Op::Change { dst: d, .. } => Some(d),
            Op::Store(..) | Op::Assign { .. } | Op::Reinit { .. } => None,
        }
    }
}

/// `a^b`, as every compiled formula computes it: exact for whole exponents.
#[inline]
pub fn power(a: f64, b: f64) -> f64 {
    if b == 2.0 {
        a * a
    } else if b.fract() == 0.0 && b.abs() <= 64.0 {
        a.powi(b as i32)
    } else {
        a.powf(b)
    }
}

/// 1 for true, 0 for false.
#[inline]
pub fn truth(b: bool) -> f64 {
    if b {
        1.0
    } else {
        0.0
    }
}

/// The most registers a tape may use (they live on the stack).
pub const MAX_REGISTERS: usize = 256;

/// Compiled formulas (the roots) over inputs `Var(0)`, `Var(1)`, ...
/// Registers: `[inputs | constants | results]`.
#[derive(Clone, Debug, PartialEq)]
pub struct Tape {
    inputs: usize,
    constants: Vec<f64>,
    ops: Vec<Op>,
    roots: Vec<Reg>,
}

impl Tape {
    /// Compiles `roots` over `inputs` inputs, or says why they cannot be:
    /// too long, or a node that is not arithmetic (`der`, events); `what`
    /// names the formula in the message.
    pub fn new(roots: &[Node<usize>], inputs: usize, what: &str) -> Result<Tape, String> {
        let mut c = Compiler { inputs, constants: Vec::new(), ops: Vec::new(), by_node: HashMap::new(), what };
        let roots = roots.iter().map(|r| c.emit(r)).collect::<Result<Vec<_>, _>>()?;
        // Constants sit between the inputs and the results: renumber.
        let first_result = (inputs + c.constants.len()) as Reg;
        let at = |r: Reg| if r >= RESULT_BASE { r - RESULT_BASE + first_result } else { r };
        let ops = c.ops.iter().map(|op| remap(*op, &at)).collect();
        let tape = Tape { inputs, constants: c.constants, ops, roots: roots.into_iter().map(at).collect() };
        if tape.registers() > MAX_REGISTERS {
            return Err(format!(
                "{what} is too long: with its derivatives it needs more than {MAX_REGISTERS} numbers and operations"
            ));
        }
        Ok(tape)
    }

    fn registers(&self) -> usize {
        self.inputs + self.constants.len() + self.ops.len()
    }

    /// Every root at `inputs`, into `out` (as many as there are roots).
    pub fn eval(&self, inputs: &[f64], out: &mut [f64]) {
        let mut r = [0.0; MAX_REGISTERS];
        let k = self.inputs;
        r[..k].copy_from_slice(&inputs[..k]);
        r[k..k + self.constants.len()].copy_from_slice(&self.constants);
        for op in &self.ops {
            op.run_arithmetic(&mut r);
        }
        for (o, &root) in out.iter_mut().zip(&self.roots) {
            *o = r[root as usize];
        }
    }
}

/// Results are numbered from here while compiling (constants from the
/// inputs up), until the count of constants is known.
const RESULT_BASE: Reg = 1 << 20;

/// `op` with its registers renumbered by `at`.
fn remap(op: Op, at: &dyn Fn(Reg) -> Reg) -> Op {
    match op {
        Op::Copy(d, a) => Op::Copy(at(d), at(a)),
        Op::Neg(d, a) => Op::Neg(at(d), at(a)),
        Op::Add(d, a, b) => Op::Add(at(d), at(a), at(b)),
        Op::Sub(d, a, b) => Op::Sub(at(d), at(a), at(b)),
        Op::Mul(d, a, b) => Op::Mul(at(d), at(a), at(b)),
        Op::Div(d, a, b) => Op::Div(at(d), at(a), at(b)),
        Op::Pow(d, a, b) => Op::Pow(at(d), at(a), at(b)),
        Op::Call(f, d, a) => Op::Call(f, at(d), at(a)),
        Op::Call2(f, d, a, b) => Op::Call2(f, at(d), at(a), at(b)),
        Op::Compare(c, d, a, b) => Op::Compare(c, at(d), at(a), at(b)),
        Op::And(d, a, b) => Op::And(at(d), at(a), at(b)),
        Op::Or(d, a, b) => Op::Or(at(d), at(a), at(b)),
        Op::Not(d, a) => Op::Not(at(d), at(a)),
        Op::Select(d, c, a, b) => Op::Select(at(d), at(c), at(a), at(b)),
        other => other,
    }
}

struct Compiler<'w> {
    inputs: usize,
    constants: Vec<f64>,
    ops: Vec<Op>,
    /// Shared subtrees, by address.
    by_node: HashMap<*const Expr<usize>, Reg>,
    what: &'w str,
}

impl Compiler<'_> {
    /// The register of the next instruction's result (renumbered later).
    fn next(&self) -> Reg {
        RESULT_BASE + self.ops.len() as Reg
    }

    fn emit(&mut self, e: &Node<usize>) -> Result<Reg, String> {
        let key = std::sync::Arc::as_ptr(e);
        if let Some(&r) = self.by_node.get(&key) {
            return Ok(r);
        }
        let op = match &**e {
            Expr::Var(k) => return Ok(*k as Reg),
            Expr::Const(c) => {
                let k = match self.constants.iter().position(|x| x.to_bits() == c.to_bits()) {
                    Some(k) => k,
                    None => {
                        self.constants.push(*c);
                        self.constants.len() - 1
                    }
                };
                return Ok((self.inputs + k) as Reg);
            }
            Expr::NoEvent(a) => return self.emit(a),
            Expr::Time | Expr::Der(_) => return Err(format!("{} cannot hold `time` or `der` here", self.what)),
            Expr::Pre(_) | Expr::Initial | Expr::Edge(_) | Expr::Change(_) | Expr::Sample { .. } => {
                return Err(format!(
                    "`pre`, `initial`, `edge`, `change` and `sample` belong in `when` clauses, not in {}",
                    self.what
                ))
            }
            _ => {
                let mut x = [0; 3];
                for (k, child) in e.children().into_iter().enumerate() {
                    if let Some(child) = child {
                        x[k] = self.emit(child)?;
                    }
                }
                Op::arithmetic(e, self.next(), x).expect("every other node is arithmetic")
            }
        };
        let d = self.next();
        self.ops.push(op);
        self.by_node.insert(key, d);
        if self.ops.len() > MAX_REGISTERS {
            return Err(format!(
                "{} is too long: with its derivatives it needs more than {MAX_REGISTERS} numbers and operations",
                self.what
            ));
        }
        Ok(d)
    }
}

/// `expr` over inputs numbered by `input` (`None`: not an input, which is
/// an error naming it), ready to differentiate and compile.
fn numbered(expr: &Expr, input: &dyn Fn(&Expr) -> Option<Result<usize, String>>) -> Result<Node<usize>, String> {
    super::symbolic::rewrite(expr, &mut |node| match input(node) {
        Some(k) => k.map(|k| Some(super::symbolic::var(k))),
        None => match node {
            Expr::Var(name) | Expr::Pre(name) => Err(format!("`{name}` cannot appear here")),
            _ => Ok(None),
        },
    })
}

/// A formula of time compiled with its first two time derivatives.
#[derive(Clone, Debug, PartialEq)]
pub struct TimeFunction {
    tape: Tape,
}

impl TimeFunction {
    /// Compiles `expr`, or says why it is not a formula of time.
    pub fn new(expr: &Expr) -> Result<Self, String> {
        let f = numbered(expr, &|node| match node {
            Expr::Time => Some(Ok(0)),
            Expr::Var(name) => Some(Err(format!("`{name}` is not a function of time alone"))),
            Expr::Der(_) => Some(Err("`der` of a formula of time is not supported; differentiate it by hand".into())),
            _ => None,
        })?;
        let d1 = super::symbolic::derivative(&f, &0);
        let d2 = super::symbolic::derivative(&d1, &0);
        Ok(Self { tape: Tape::new(&[f, d1, d2], 1, "a formula of time")? })
    }

    /// The value and its first two time derivatives at `t`.
    pub fn jet(&self, t: f64) -> [f64; 3] {
        let mut out = [0.0; 3];
        self.tape.eval(&[t], &mut out);
        out
    }

    /// The value at `t`.
    pub fn value(&self, t: f64) -> f64 {
        self.jet(t)[0]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::symbolic::{add, constant, mul, var};

    #[test]
    fn shared_subexpressions_are_computed_once() {
        // (x + 1) * (x + 1) and x + 1: one addition, one product.
        let s = add(var(0usize), constant(1.0));
        let t = Tape::new(&[mul(s.clone(), s.clone()), s], 1, "a test").unwrap();
        assert_eq!(t.ops.len(), 2); // x + 1, (x + 1)^2
        assert_eq!(t.constants, [1.0]);
        let mut out = [0.0; 2];
        t.eval(&[2.0], &mut out);
        assert_eq!(out, [9.0, 3.0]);
    }

    #[test]
    fn a_tape_too_long_is_refused_with_the_reason() {
        let mut e = var(0usize);
        for k in 0..MAX_REGISTERS {
            e = add(mul(e, var(0)), constant(k as f64 + 0.5));
        }
        let why = Tape::new(&[e], 1, "this formula").unwrap_err();
        assert!(why.contains("this formula is too long"), "{why}");
    }
}
