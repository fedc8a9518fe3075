//! Formulas of a few inputs compiled into straight-line code: each
//! instruction's result is its own register, and a subexpression met twice
//! (derivatives share much with their formula) is computed once. Formulas
//! of time with their time derivatives (prescribed motion) and a road's
//! height with its gradient and curvature are compiled here; their
//! derivatives come from the one symbolic differentiation
//! ([`super::symbolic`]), so no rule of calculus is written twice.
//! Evaluating allocates nothing.

use super::expr::{Cmp, Expr, Func, Func2, Node};
use std::collections::HashMap;

/// The most instructions a tape may hold (its registers live on the stack).
pub const MAX_OPS: usize = 256;

type Reg = u16;

/// One instruction; its operands are earlier results.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Op {
    Input(Reg),
    Const(f64),
    Neg(Reg),
    Add(Reg, Reg),
    Sub(Reg, Reg),
    Mul(Reg, Reg),
    Div(Reg, Reg),
    Pow(Reg, Reg),
    Call(Func, Reg),
    Call2(Func2, Reg, Reg),
    Compare(Cmp, Reg, Reg),
    And(Reg, Reg),
    Or(Reg, Reg),
    Not(Reg),
    Select(Reg, Reg, Reg),
}

/// Compiled formulas (the roots) over inputs `Var(0)`, `Var(1)`, ...
#[derive(Clone, Debug, PartialEq)]
pub struct Tape {
    ops: Vec<Op>,
    roots: Vec<Reg>,
}

/// `a^b`, as the model's equations compute it: exact for whole exponents.
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

#[inline]
fn truth(b: bool) -> f64 {
    if b {
        1.0
    } else {
        0.0
    }
}

impl Tape {
    /// Compiles `roots`, or says why they cannot be: too long, or a node
    /// that is not arithmetic (`der`, events), named by `what`.
    pub fn new(roots: &[Node<usize>], what: &str) -> Result<Tape, String> {
        let mut c = Compiler { ops: Vec::new(), by_node: HashMap::new(), by_op: HashMap::new(), what };
        let roots = roots.iter().map(|r| c.emit(r)).collect::<Result<_, _>>()?;
        Ok(Tape { ops: c.ops, roots })
    }

    /// Every root at `inputs`, into `out` (as many as there are roots).
    pub fn eval(&self, inputs: &[f64], out: &mut [f64]) {
        let mut r = [0.0; MAX_OPS];
        for (i, op) in self.ops.iter().enumerate() {
            let g = |k: Reg| r[k as usize];
            r[i] = match *op {
                Op::Input(k) => inputs[k as usize],
                Op::Const(c) => c,
                Op::Neg(a) => -g(a),
                Op::Add(a, b) => g(a) + g(b),
                Op::Sub(a, b) => g(a) - g(b),
                Op::Mul(a, b) => g(a) * g(b),
                Op::Div(a, b) => g(a) / g(b),
                Op::Pow(a, b) => power(g(a), g(b)),
                Op::Call(f, a) => f.apply(g(a)),
                Op::Call2(f, a, b) => f.apply(g(a), g(b)),
                Op::Compare(c, a, b) => c.apply(g(a), g(b)),
                Op::And(a, b) => truth(g(a) != 0.0 && g(b) != 0.0),
                Op::Or(a, b) => truth(g(a) != 0.0 || g(b) != 0.0),
                Op::Not(a) => truth(g(a) == 0.0),
                Op::Select(c, a, b) => {
                    if g(c) != 0.0 {
                        g(a)
                    } else {
                        g(b)
                    }
                }
            };
        }
        for (o, &root) in out.iter_mut().zip(&self.roots) {
            *o = r[root as usize];
        }
    }
}

struct Compiler<'w> {
    ops: Vec<Op>,
    /// Shared subtrees, by address.
    by_node: HashMap<*const Expr<usize>, Reg>,
    /// Equal instructions, by their bits.
    by_op: HashMap<String, Reg>,
    what: &'w str,
}

impl Compiler<'_> {
    fn emit(&mut self, e: &Node<usize>) -> Result<Reg, String> {
        let key = std::sync::Arc::as_ptr(e);
        if let Some(&r) = self.by_node.get(&key) {
            return Ok(r);
        }
        let op = match &**e {
            Expr::Var(k) => Op::Input(*k as Reg),
            Expr::Const(c) => Op::Const(*c),
            Expr::Neg(a) => Op::Neg(self.emit(a)?),
            Expr::Add(a, b) => Op::Add(self.emit(a)?, self.emit(b)?),
            Expr::Sub(a, b) => Op::Sub(self.emit(a)?, self.emit(b)?),
            Expr::Mul(a, b) => Op::Mul(self.emit(a)?, self.emit(b)?),
            Expr::Div(a, b) => Op::Div(self.emit(a)?, self.emit(b)?),
            Expr::Pow(a, b) => Op::Pow(self.emit(a)?, self.emit(b)?),
            Expr::Call(f, a) => Op::Call(*f, self.emit(a)?),
            Expr::Call2(f, a, b) => Op::Call2(*f, self.emit(a)?, self.emit(b)?),
            Expr::Compare(c, a, b) => Op::Compare(*c, self.emit(a)?, self.emit(b)?),
            Expr::And(a, b) => Op::And(self.emit(a)?, self.emit(b)?),
            Expr::Or(a, b) => Op::Or(self.emit(a)?, self.emit(b)?),
            Expr::Not(a) => Op::Not(self.emit(a)?),
            Expr::If(c, a, b) => Op::Select(self.emit(c)?, self.emit(a)?, self.emit(b)?),
            Expr::NoEvent(a) => return self.emit(a),
            Expr::Time | Expr::Der(_) => return Err(format!("{} cannot hold `time` or `der` here", self.what)),
            Expr::Pre(_) | Expr::Initial | Expr::Edge(_) | Expr::Change(_) | Expr::Sample { .. } => {
                return Err(format!(
                    "`pre`, `initial`, `edge`, `change` and `sample` belong in `when` clauses, not in {}",
                    self.what
                ))
            }
        };
        let bits = format!("{op:?}");
        let r = match self.by_op.get(&bits) {
            Some(&r) => r,
            None => {
                if self.ops.len() == MAX_OPS {
                    return Err(format!(
                        "{} is too long: with its derivatives it needs more than {MAX_OPS} operations",
                        self.what
                    ));
                }
                self.ops.push(op);
                let r = (self.ops.len() - 1) as Reg;
                self.by_op.insert(bits, r);
                r
            }
        };
        self.by_node.insert(key, r);
        Ok(r)
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
        Ok(Self { tape: Tape::new(&[f, d1, d2], "a formula of time")? })
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
        let t = Tape::new(&[mul(s.clone(), s.clone()), s], "a test").unwrap();
        assert_eq!(t.ops.len(), 4); // x, 1, x + 1, (x + 1)^2
        let mut out = [0.0; 2];
        t.eval(&[2.0], &mut out);
        assert_eq!(out, [9.0, 3.0]);
    }

    #[test]
    fn a_tape_too_long_is_refused_with_the_reason() {
        let mut e = var(0usize);
        for k in 0..MAX_OPS {
            e = add(mul(e, var(0)), constant(k as f64 + 0.5));
        }
        let why = Tape::new(&[e], "this formula").unwrap_err();
        assert!(why.contains("this formula is too long"), "{why}");
    }
}
