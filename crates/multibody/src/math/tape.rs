//! The one compiled form of formulas: straight-line code on registers.
//! [`Op`] is the instruction set, its arithmetic run by one interpreter,
//! and [`Writer`] the one writer of code from expression trees, that every
//! compiled formula uses: the model's equations (whose program adds moves
//! between registers and signal slots and the instructions of events, as
//! the writer's [`Leaves`]) and the [`Tape`]s compiled here, a formula of
//! time with its time derivatives (prescribed motion) and a road's height
//! with its gradient and curvature. Their derivatives come from the one
//! symbolic differentiation ([`super::symbolic`]), so no rule of calculus
//! is written twice. A subexpression met twice is computed once.
//! Evaluating allocates nothing.

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

    /// The registers the instruction reads.
    pub fn sources(mut self) -> impl Iterator<Item = Reg> {
        self.sources_mut().map(|r| r.copied()).into_iter().flatten()
    }

    /// The registers the instruction reads, to renumber them.
    pub fn sources_mut(&mut self) -> [Option<&mut Reg>; 3] {
        match self {
            Op::Copy(_, a) | Op::Neg(_, a) | Op::Call(_, _, a) | Op::Not(_, a) | Op::Store(_, a) => {
                [Some(a), None, None]
            }
            Op::Add(_, a, b)
            | Op::Sub(_, a, b)
            | Op::Mul(_, a, b)
            | Op::Div(_, a, b)
            | Op::Pow(_, a, b)
            | Op::Call2(_, _, a, b)
            | Op::Compare(_, _, a, b)
            | Op::And(_, a, b)
            | Op::Or(_, a, b)
            | Op::Relation { a, b, .. } => [Some(a), Some(b), None],
            Op::Select(_, c, a, b) => [Some(c), Some(a), Some(b)],
            Op::Fire { cond: a, .. } | Op::Change { value: a, .. } => [Some(a), None, None],
            Op::Assign { src, fire, .. } | Op::Reinit { src, fire, .. } => [Some(src), Some(fire), None],
            // (`Sample` and `Fire` read the time too, which no instruction writes.)
            Op::Load(..) | Op::Initial(_) | Op::LoadPre(..) | Op::Sample { .. } => [None, None, None],
        }
    }

    /// Whether the instruction does more than write its register: it
    /// stores a signal, watches for events or acts at them.
    pub fn has_effects(self) -> bool {
        matches!(
            self,
            Op::Store(..)
                | Op::Relation { .. }
                | Op::Fire { .. }
                | Op::Change { .. }
                | Op::Assign { .. }
                | Op::Reinit { .. }
        )
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

/// Writes expression trees as instructions: a fresh register for each
/// result, each constant once (a register loaded before the code runs),
/// and each subtree shared by address once, until [`Writer::forget`]. The
/// one writer of code: the leaves, and nodes that are not arithmetic, are
/// its caller's ([`Leaves`]).
#[derive(Debug)]
pub struct Writer<V> {
    pub ops: Vec<Op>,
    /// The next free register.
    pub registers: usize,
    /// Registers with a value before the code first runs: the constants,
    /// and whatever else the caller adds (an unknown's start value).
    pub preset: Vec<(Reg, f64)>,
    by_bits: HashMap<u64, Reg>,
    /// Registers holding a subtree (by its address); `keep` holds those
    /// subtrees, so that no address is reused while they are remembered.
    memo: HashMap<*const Expr<V>, Reg>,
    keep: Vec<Node<V>>,
    /// Past this many registers the writer stops writing (and descending):
    /// [`Writer::overflowed`] then says the code is too long.
    budget: usize,
}

/// What a caller of [`Writer::write`] decides: the register of a leaf
/// (a variable, time) and the code of nodes that are not arithmetic
/// (events); `None` leaves the node to the writer.
pub trait Leaves<V> {
    fn leaf(&mut self, w: &mut Writer<V>, e: &Node<V>) -> Option<Leaf>;
}

/// Where a caller put a node.
pub enum Leaf {
    /// In a register that is not remembered for the node (a variable's
    /// register may differ between calls).
    At(Reg),
    /// In code written for it, remembered like arithmetic.
    Written(Reg),
}

impl<V> Writer<V> {
    /// A writer whose first free register is `first`.
    pub fn new(first: usize) -> Self {
        Writer {
            ops: Vec::new(),
            registers: first,
            preset: Vec::new(),
            by_bits: HashMap::new(),
            memo: HashMap::new(),
            keep: Vec::new(),
            budget: usize::MAX,
        }
    }

    /// A writer that stops past `budget` registers.
    pub fn with_budget(first: usize, budget: usize) -> Self {
        Writer { budget, ..Writer::new(first) }
    }

    /// Whether it stopped for want of registers (its code is then unusable).
    pub fn overflowed(&self) -> bool {
        self.registers > self.budget
    }

    /// A fresh register.
    pub fn register(&mut self) -> Reg {
        self.registers += 1;
        (self.registers - 1) as Reg
    }

    /// The register that holds the constant `x`.
    pub fn constant(&mut self, x: f64) -> Reg {
        if let Some(&r) = self.by_bits.get(&x.to_bits()) {
            return r;
        }
        let r = self.register();
        self.by_bits.insert(x.to_bits(), r);
        self.preset.push((r, x));
        r
    }

    /// Code that leaves the value of `e` in a register, which it returns.
    pub fn write(&mut self, e: &Node<V>, leaves: &mut impl Leaves<V>) -> Reg {
        if let Some(&r) = self.memo.get(&std::sync::Arc::as_ptr(e)) {
            return r;
        }
        if self.overflowed() {
            return 0;
        }
        let r = match leaves.leaf(self, e) {
            Some(Leaf::At(r)) => return r,
            Some(Leaf::Written(r)) => r,
            None => match &**e {
                Expr::Const(x) => return self.constant(*x),
                _ => {
                    let mut x = [0; 3];
                    for (k, child) in e.children().into_iter().enumerate() {
                        if let Some(child) = child {
                            x[k] = self.write(child, leaves);
                        }
                    }
                    let d = self.register();
                    self.ops.push(Op::arithmetic(e, d, x).expect("the leaves take every node that is not arithmetic"));
                    d
                }
            },
        };
        self.remember(e, r);
        r
    }

    /// From now on `e` is in register `r`.
    pub fn remember(&mut self, e: &Node<V>, r: Reg) {
        self.keep.push(e.clone());
        self.memo.insert(std::sync::Arc::as_ptr(e), r);
    }

    /// Forgets which registers hold which subtrees (their registers may
    /// be written again); constants stay.
    pub fn forget(&mut self) {
        self.memo.clear();
        self.keep.clear();
    }
}

/// The most registers a tape may use (they live on the stack).
pub const MAX_REGISTERS: usize = 256;

/// Compiled formulas (the roots) over inputs `Var(0)`, `Var(1)`, ...,
/// which are its first registers.
#[derive(Clone, Debug, PartialEq)]
pub struct Tape {
    inputs: usize,
    registers: usize,
    constants: Vec<(Reg, f64)>,
    ops: Vec<Op>,
    roots: Vec<Reg>,
}

/// A tape's leaves: its inputs; what it cannot hold (time, `der`,
/// events) is its first refusal, and nothing is written for it.
struct Inputs<'w> {
    what: &'w str,
    refused: Option<String>,
}

impl Leaves<usize> for Inputs<'_> {
    fn leaf(&mut self, w: &mut Writer<usize>, e: &Node<usize>) -> Option<Leaf> {
        let what = self.what;
        let refuse = |why: String, refused: &mut Option<String>| {
            refused.get_or_insert(why);
            Some(Leaf::At(0))
        };
        match &**e {
            Expr::Var(k) => Some(Leaf::At(*k as Reg)),
            Expr::NoEvent(a) => Some(Leaf::At(w.write(a, self))),
            Expr::Time | Expr::Der(_) => refuse(format!("{what} cannot hold `time` or `der` here"), &mut self.refused),
            Expr::Pre(_) | Expr::Initial | Expr::Edge(_) | Expr::Change(_) | Expr::Sample { .. } => refuse(
                format!("`pre`, `initial`, `edge`, `change` and `sample` belong in `when` clauses, not in {what}"),
                &mut self.refused,
            ),
            _ => None,
        }
    }
}

impl Tape {
    /// Compiles `roots` over `inputs` inputs, or says why they cannot be:
    /// too long, or a node that is not arithmetic (`der`, events); `what`
    /// names the formula in the message.
    pub fn new(roots: &[Node<usize>], inputs: usize, what: &str) -> Result<Tape, String> {
        let mut w = Writer::with_budget(inputs, MAX_REGISTERS);
        let mut leaves = Inputs { what, refused: None };
        let roots = roots.iter().map(|r| w.write(r, &mut leaves)).collect();
        if let Some(why) = leaves.refused {
            return Err(why);
        }
        if w.overflowed() {
            return Err(format!(
                "{what} is too long: with its derivatives it needs more than {MAX_REGISTERS} numbers and operations"
            ));
        }
        Ok(Tape { inputs, registers: w.registers, constants: w.preset, ops: w.ops, roots })
    }

    /// Every root at `inputs`, into `out` (as many as there are roots).
    pub fn eval(&self, inputs: &[f64], out: &mut [f64]) {
        let mut r = [0.0; MAX_REGISTERS];
        let r = &mut r[..self.registers];
        r[..self.inputs].copy_from_slice(&inputs[..self.inputs]);
        for &(k, x) in &self.constants {
            r[k as usize] = x;
        }
        for op in &self.ops {
            op.run_arithmetic(r);
        }
        for (o, &root) in out.iter_mut().zip(&self.roots) {
            *o = r[root as usize];
        }
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
        assert_eq!(t.constants, [(1, 1.0)]);
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
