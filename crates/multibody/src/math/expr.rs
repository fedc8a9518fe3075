//! The one expression tree of the library, from a model file's equations
//! to the compiled code: scalar expressions of time and variables
//! (`ctrl.y = -kp * (sensor.phi - ref)`), plain data. `Expr` (variables
//! by name) is what a model states; after assembly resolves the names,
//! the same tree with numbered variables, [`Sym`](super::symbolic::Sym),
//! is what the equation compiler sorts, differentiates and compiles
//! ([`symbolic`](super::symbolic) holds the algebra, written once for
//! both). Subtrees are shared (`Arc`), so copies and derivatives are cheap.
//!
//! A formula of time alone (no variables) also compiles into a
//! [`TimeFunction`], evaluated with its first two time derivatives, which
//! prescribed motion needs; evaluating it allocates nothing.

use std::ops;
use std::sync::Arc;

/// A shared subtree.
pub type Node<V = String> = Arc<Expr<V>>;

/// A scalar expression over variables `V` (names by default). Booleans are
/// numbers: a comparison gives 1 or 0, and a condition holds when it is
/// not 0.
#[derive(Clone, Debug, PartialEq)]
pub enum Expr<V = String> {
    Const(f64),
    Time,
    /// A variable: by name, a variable of the model's equations or a
    /// quantity of a library component (`body.frame_a.r_0[2]`, `rev.phi`,
    /// `sensor.phi`); by number after assembly.
    Var(V),
    /// The time derivative of an expression (gone after assembly, which
    /// gives each derivative a variable of its own).
    Der(Node<V>),
    Neg(Node<V>),
    Add(Node<V>, Node<V>),
    Sub(Node<V>, Node<V>),
    Mul(Node<V>, Node<V>),
    Div(Node<V>, Node<V>),
    Pow(Node<V>, Node<V>),
    Call(Func, Node<V>),
    Call2(Func2, Node<V>, Node<V>),
    Compare(Cmp, Node<V>, Node<V>),
    And(Node<V>, Node<V>),
    Or(Node<V>, Node<V>),
    Not(Node<V>),
    /// `if condition then a else b`.
    If(Node<V>, Node<V>, Node<V>),
    /// `noEvent(e)`: the relations inside are evaluated as they are,
    /// without events.
    NoEvent(Node<V>),
    /// `pre(x)`: the value of the variable `x` before the current event
    /// (its left limit); only in `when` clauses.
    Pre(V),
    /// `initial()`: true during the event iteration at the start.
    Initial,
    /// `edge(b)`: true at the event where `b` became true.
    Edge(Node<V>),
    /// `change(v)`: true at the event where `v` changed.
    Change(Node<V>),
    /// `sample(start, interval)`: true at the time events `start + k
    /// interval` (k = 0, 1, ...), false between them.
    Sample {
        start: f64,
        interval: f64,
    },
}

/// The name formulas of time had before equations could name variables.
pub type TimeExpr = Expr;

/// The functions of one argument an expression may call.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Func {
    Sin,
    Cos,
    Tan,
    Exp,
    Log,
    Log10,
    Sqrt,
    Abs,
    Sign,
    Asin,
    Acos,
    Atan,
    Sinh,
    Cosh,
    Tanh,
    Floor,
    Ceil,
}

/// The functions of two arguments.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Func2 {
    Atan2,
    Min,
    Max,
}

/// Comparisons; they give 1 when they hold and 0 otherwise.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Cmp {
    Lt,
    Le,
    Gt,
    Ge,
    Eq,
    Ne,
}

impl Func {
    pub const NAMES: &'static [&'static str] = &[
        "sin", "cos", "tan", "exp", "log", "log10", "sqrt", "abs", "sign", "asin", "acos", "atan", "sinh", "cosh",
        "tanh", "floor", "ceil",
    ];

    /// The function called `name` in a model file.
    pub fn from_name(name: &str) -> Option<Func> {
        Some(match name {
            "sin" => Func::Sin,
            "cos" => Func::Cos,
            "tan" => Func::Tan,
            "exp" => Func::Exp,
            "log" => Func::Log,
            "log10" => Func::Log10,
            "sqrt" => Func::Sqrt,
            "abs" => Func::Abs,
            "sign" => Func::Sign,
            "asin" => Func::Asin,
            "acos" => Func::Acos,
            "atan" => Func::Atan,
            "sinh" => Func::Sinh,
            "cosh" => Func::Cosh,
            "tanh" => Func::Tanh,
            "floor" => Func::Floor,
            "ceil" => Func::Ceil,
            _ => return None,
        })
    }

    #[inline]
    pub fn apply(self, x: f64) -> f64 {
        match self {
            Func::Sin => x.sin(),
            Func::Cos => x.cos(),
            Func::Tan => x.tan(),
            Func::Exp => x.exp(),
            Func::Log => x.ln(),
            Func::Log10 => x.log10(),
            Func::Sqrt => x.sqrt(),
            Func::Abs => x.abs(),
            Func::Sign => {
                if x > 0.0 {
                    1.0
                } else if x < 0.0 {
                    -1.0
                } else {
                    0.0
                }
            }
            Func::Asin => x.asin(),
            Func::Acos => x.acos(),
            Func::Atan => x.atan(),
            Func::Sinh => x.sinh(),
            Func::Cosh => x.cosh(),
            Func::Tanh => x.tanh(),
            Func::Floor => x.floor(),
            Func::Ceil => x.ceil(),
        }
    }

    /// Where the function is defined, in words, when `x` is outside it.
    pub fn outside_domain(self, x: f64) -> Option<&'static str> {
        match self {
            Func::Sqrt if x < 0.0 => Some("zero or positive"),
            Func::Log | Func::Log10 if x <= 0.0 => Some("positive"),
            Func::Asin | Func::Acos if !(-1.0..=1.0).contains(&x) => Some("between -1 and 1"),
            _ => None,
        }
    }

    /// `f(x), f'(x), f''(x)`.
    pub fn derivatives(self, x: f64) -> [f64; 3] {
        match self {
            Func::Sin => [x.sin(), x.cos(), -x.sin()],
            Func::Cos => [x.cos(), -x.sin(), -x.cos()],
            Func::Tan => {
                let t = x.tan();
                let d = 1.0 + t * t;
                [t, d, 2.0 * t * d]
            }
            Func::Exp => [x.exp(); 3],
            Func::Log => [x.ln(), 1.0 / x, -1.0 / (x * x)],
            Func::Log10 => {
                let k = std::f64::consts::LN_10;
                [x.log10(), 1.0 / (x * k), -1.0 / (x * x * k)]
            }
            Func::Sqrt => {
                let s = x.sqrt();
                [s, 0.5 / s, -0.25 / (s * x)]
            }
            Func::Abs => [x.abs(), Func::Sign.apply(x), 0.0],
            Func::Sign | Func::Floor | Func::Ceil => [self.apply(x), 0.0, 0.0],
            Func::Asin => {
                let r = 1.0 - x * x;
                [x.asin(), 1.0 / r.sqrt(), x / (r * r.sqrt())]
            }
            Func::Acos => {
                let r = 1.0 - x * x;
                [x.acos(), -1.0 / r.sqrt(), -x / (r * r.sqrt())]
            }
            Func::Atan => {
                let r = 1.0 + x * x;
                [x.atan(), 1.0 / r, -2.0 * x / (r * r)]
            }
            Func::Sinh => [x.sinh(), x.cosh(), x.sinh()],
            Func::Cosh => [x.cosh(), x.sinh(), x.cosh()],
            Func::Tanh => {
                let t = x.tanh();
                let d = 1.0 - t * t;
                [t, d, -2.0 * t * d]
            }
        }
    }
}

impl Func2 {
    pub const NAMES: &'static [&'static str] = &["atan2", "min", "max"];

    pub fn from_name(name: &str) -> Option<Func2> {
        Some(match name {
            "atan2" => Func2::Atan2,
            "min" => Func2::Min,
            "max" => Func2::Max,
            _ => return None,
        })
    }

    #[inline]
    pub fn apply(self, a: f64, b: f64) -> f64 {
        match self {
            Func2::Atan2 => a.atan2(b),
            Func2::Min => a.min(b),
            Func2::Max => a.max(b),
        }
    }
}

impl Cmp {
    #[inline]
    pub fn apply(self, a: f64, b: f64) -> f64 {
        let holds = match self {
            Cmp::Lt => a < b,
            Cmp::Le => a <= b,
            Cmp::Gt => a > b,
            Cmp::Ge => a >= b,
            Cmp::Eq => a == b,
            Cmp::Ne => a != b,
        };
        if holds {
            1.0
        } else {
            0.0
        }
    }
}

fn b<V>(e: Expr<V>) -> Node<V> {
    Arc::new(e)
}

impl<V> Expr<V> {
    pub fn der(e: Expr<V>) -> Self {
        Expr::Der(b(e))
    }

    pub fn call(f: Func, e: Expr<V>) -> Self {
        Expr::Call(f, b(e))
    }

    pub fn call2(f: Func2, x: Expr<V>, y: Expr<V>) -> Self {
        Expr::Call2(f, b(x), b(y))
    }

    pub fn compare(op: Cmp, x: Expr<V>, y: Expr<V>) -> Self {
        Expr::Compare(op, b(x), b(y))
    }

    pub fn if_else(condition: Expr<V>, then: Expr<V>, otherwise: Expr<V>) -> Self {
        Expr::If(b(condition), b(then), b(otherwise))
    }

    pub fn pow(self, e: Expr<V>) -> Self {
        Expr::Pow(b(self), b(e))
    }

    pub fn as_const(&self) -> Option<f64> {
        match self {
            Expr::Const(x) => Some(*x),
            _ => None,
        }
    }

    /// The nodes right below this one (up to three), in order.
    pub fn children(&self) -> [Option<&Node<V>>; 3] {
        match self {
            Expr::Const(_) | Expr::Time | Expr::Var(_) | Expr::Initial | Expr::Pre(_) | Expr::Sample { .. } => {
                [None; 3]
            }
            Expr::Der(a)
            | Expr::Neg(a)
            | Expr::Call(_, a)
            | Expr::Not(a)
            | Expr::NoEvent(a)
            | Expr::Edge(a)
            | Expr::Change(a) => [Some(a), None, None],
            Expr::Add(x, y)
            | Expr::Sub(x, y)
            | Expr::Mul(x, y)
            | Expr::Div(x, y)
            | Expr::Pow(x, y)
            | Expr::Call2(_, x, y)
            | Expr::Compare(_, x, y)
            | Expr::And(x, y)
            | Expr::Or(x, y) => [Some(x), Some(y), None],
            Expr::If(c, x, y) => [Some(c), Some(x), Some(y)],
        }
    }

    /// Calls `f` on this node and every node below it, in pre-order.
    pub fn visit<'a>(&'a self, f: &mut impl FnMut(&'a Expr<V>)) {
        f(self);
        for child in self.children().into_iter().flatten() {
            child.visit(f);
        }
    }

    /// The first `Some` that `f` gives on the nodes, in pre-order.
    pub fn find<T>(&self, f: &mut impl FnMut(&Expr<V>) -> Option<T>) -> Option<T> {
        f(self).or_else(|| self.children().into_iter().flatten().find_map(|c| c.find(f)))
    }

    /// Every variable the expression names (not under `pre`), in order of
    /// appearance (with repeats), into `out`.
    pub fn variables<'a>(&'a self, out: &mut Vec<&'a V>) {
        self.visit(&mut |e| {
            if let Expr::Var(v) = e {
                out.push(v);
            }
        });
    }

    /// Whether the expression names a variable.
    pub fn has_variables(&self) -> bool {
        self.find(&mut |e| matches!(e, Expr::Var(_)).then_some(())).is_some()
    }

    /// Whether the expression mentions time.
    pub fn mentions_time(&self) -> bool {
        self.find(&mut |e| matches!(e, Expr::Time).then_some(())).is_some()
    }
}

impl<V: Clone> Expr<V> {
    /// This node with each operand replaced by `f` of it (no folding).
    pub fn map_children(&self, mut f: impl FnMut(&Node<V>) -> Node<V>) -> Expr<V> {
        match self {
            Expr::Const(_) | Expr::Time | Expr::Var(_) | Expr::Initial | Expr::Pre(_) | Expr::Sample { .. } => {
                self.clone()
            }
            Expr::Der(a) => Expr::Der(f(a)),
            Expr::Neg(a) => Expr::Neg(f(a)),
            Expr::Call(g, a) => Expr::Call(*g, f(a)),
            Expr::Not(a) => Expr::Not(f(a)),
            Expr::NoEvent(a) => Expr::NoEvent(f(a)),
            Expr::Edge(a) => Expr::Edge(f(a)),
            Expr::Change(a) => Expr::Change(f(a)),
            Expr::Add(x, y) => Expr::Add(f(x), f(y)),
            Expr::Sub(x, y) => Expr::Sub(f(x), f(y)),
            Expr::Mul(x, y) => Expr::Mul(f(x), f(y)),
            Expr::Div(x, y) => Expr::Div(f(x), f(y)),
            Expr::Pow(x, y) => Expr::Pow(f(x), f(y)),
            Expr::Call2(g, x, y) => Expr::Call2(*g, f(x), f(y)),
            Expr::Compare(c, x, y) => Expr::Compare(*c, f(x), f(y)),
            Expr::And(x, y) => Expr::And(f(x), f(y)),
            Expr::Or(x, y) => Expr::Or(f(x), f(y)),
            Expr::If(c, x, y) => Expr::If(f(c), f(x), f(y)),
        }
    }
}

impl Expr {
    pub fn var(name: impl Into<String>) -> Expr {
        Expr::Var(name.into())
    }
}

impl<V> From<f64> for Expr<V> {
    fn from(x: f64) -> Self {
        Expr::Const(x)
    }
}

macro_rules! binary_operator {
    ($trait:ident, $method:ident, $variant:ident) => {
        impl<V> ops::$trait for Expr<V> {
            type Output = Expr<V>;
            fn $method(self, rhs: Expr<V>) -> Expr<V> {
                Expr::$variant(b(self), b(rhs))
            }
        }
        impl<V> ops::$trait<f64> for Expr<V> {
            type Output = Expr<V>;
            fn $method(self, rhs: f64) -> Expr<V> {
                Expr::$variant(b(self), b(Expr::Const(rhs)))
            }
        }
        impl<V> ops::$trait<Expr<V>> for f64 {
            type Output = Expr<V>;
            fn $method(self, rhs: Expr<V>) -> Expr<V> {
                Expr::$variant(b(Expr::Const(self)), b(rhs))
            }
        }
    };
}
binary_operator!(Add, add, Add);
binary_operator!(Sub, sub, Sub);
binary_operator!(Mul, mul, Mul);
binary_operator!(Div, div, Div);

impl<V> ops::Neg for Expr<V> {
    type Output = Expr<V>;
    fn neg(self) -> Expr<V> {
        Expr::Neg(b(self))
    }
}

/// One instruction of a compiled formula of time.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Op {
    Time,
    Const(f64),
    Neg,
    Not,
    Add,
    Sub,
    Mul,
    Div,
    Pow,
    Call(Func),
    Call2(Func2),
    Compare(Cmp),
    And,
    Or,
    If,
}

/// A formula of time compiled for evaluation, with the stack depth it needs.
#[derive(Clone, Debug, PartialEq)]
pub struct TimeFunction {
    ops: Vec<Op>,
    depth: usize,
}

/// Formulas deeper than this are refused (they would need a larger stack).
pub const MAX_DEPTH: usize = 32;

type Jet = [f64; 3];

impl TimeFunction {
    /// Compiles `expr`, or says why it is not a formula of time.
    pub fn new(expr: &Expr) -> Result<Self, String> {
        let mut ops = Vec::new();
        let depth = compile(expr, &mut ops)?;
        if depth > MAX_DEPTH {
            return Err(format!("the formula nests {depth} levels deep; at most {MAX_DEPTH} are supported"));
        }
        Ok(Self { ops, depth })
    }

    /// The value and its first two time derivatives at `t`.
    pub fn jet(&self, t: f64) -> [f64; 3] {
        let mut stack = [[0.0; 3]; MAX_DEPTH];
        let mut n = 0;
        for op in &self.ops {
            let jet = match *op {
                Op::Time => [t, 1.0, 0.0],
                Op::Const(c) => [c, 0.0, 0.0],
                Op::Neg => {
                    n -= 1;
                    stack[n].map(|x| -x)
                }
                Op::Not => {
                    n -= 1;
                    [if stack[n][0] == 0.0 { 1.0 } else { 0.0 }, 0.0, 0.0]
                }
                Op::Call(f) => {
                    n -= 1;
                    let [u, u1, u2] = stack[n];
                    let [g, g1, g2] = f.derivatives(u);
                    [g, g1 * u1, g2 * u1 * u1 + g1 * u2]
                }
                Op::If => {
                    n -= 3;
                    if stack[n][0] != 0.0 {
                        stack[n + 1]
                    } else {
                        stack[n + 2]
                    }
                }
                binary => {
                    n -= 2;
                    binary_jet(binary, stack[n], stack[n + 1])
                }
            };
            stack[n] = jet;
            n += 1;
        }
        debug_assert!(n == 1 && self.depth <= MAX_DEPTH);
        stack[0]
    }

    /// The value at `t`.
    pub fn value(&self, t: f64) -> f64 {
        self.jet(t)[0]
    }
}

/// Postfix code of `expr` into `ops`; returns the stack depth it needs.
fn compile(expr: &Expr, ops: &mut Vec<Op>) -> Result<usize, String> {
    let binary = |x: &Expr, y: &Expr, op: Op, ops: &mut Vec<Op>| -> Result<usize, String> {
        let dx = compile(x, ops)?;
        let dy = compile(y, ops)?;
        ops.push(op);
        Ok(dx.max(dy + 1))
    };
    Ok(match expr {
        Expr::Time => {
            ops.push(Op::Time);
            1
        }
        Expr::Const(c) => {
            ops.push(Op::Const(*c));
            1
        }
        Expr::Var(name) => return Err(format!("`{name}` is not a function of time alone")),
        Expr::Der(_) => return Err("`der` of a formula of time is not supported; differentiate it by hand".into()),
        Expr::NoEvent(a) => compile(a, ops)?,
        Expr::Pre(_) | Expr::Initial | Expr::Edge(_) | Expr::Change(_) | Expr::Sample { .. } => {
            return Err("`pre`, `initial`, `edge`, `change` and `sample` belong in `when` clauses, not in a formula \
                        of time"
                .into())
        }
        Expr::Neg(a) | Expr::Not(a) | Expr::Call(_, a) => {
            let d = compile(a, ops)?;
            ops.push(match expr {
                Expr::Neg(_) => Op::Neg,
                Expr::Not(_) => Op::Not,
                Expr::Call(f, _) => Op::Call(*f),
                _ => unreachable!(),
            });
            d
        }
        Expr::Add(x, y) => binary(x, y, Op::Add, ops)?,
        Expr::Sub(x, y) => binary(x, y, Op::Sub, ops)?,
        Expr::Mul(x, y) => binary(x, y, Op::Mul, ops)?,
        Expr::Div(x, y) => binary(x, y, Op::Div, ops)?,
        Expr::Pow(x, y) => binary(x, y, Op::Pow, ops)?,
        Expr::Call2(f, x, y) => binary(x, y, Op::Call2(*f), ops)?,
        Expr::Compare(c, x, y) => binary(x, y, Op::Compare(*c), ops)?,
        Expr::And(x, y) => binary(x, y, Op::And, ops)?,
        Expr::Or(x, y) => binary(x, y, Op::Or, ops)?,
        Expr::If(c, x, y) => {
            let dc = compile(c, ops)?;
            let dx = compile(x, ops)?;
            let dy = compile(y, ops)?;
            ops.push(Op::If);
            dc.max(dx + 1).max(dy + 2)
        }
    })
}

/// The jet of `a op b`.
fn binary_jet(op: Op, a: Jet, b: Jet) -> Jet {
    let flat = |x: f64| [x, 0.0, 0.0];
    match op {
        Op::Add => [a[0] + b[0], a[1] + b[1], a[2] + b[2]],
        Op::Sub => [a[0] - b[0], a[1] - b[1], a[2] - b[2]],
        Op::Mul => [a[0] * b[0], a[1] * b[0] + a[0] * b[1], a[2] * b[0] + 2.0 * a[1] * b[1] + a[0] * b[2]],
        Op::Div => {
            let y = a[0] / b[0];
            let y1 = (a[1] - y * b[1]) / b[0];
            [y, y1, (a[2] - 2.0 * y1 * b[1] - y * b[2]) / b[0]]
        }
        Op::Pow if b[1] == 0.0 && b[2] == 0.0 => {
            // A constant exponent: defined for negative bases too.
            let p = b[0];
            let y = a[0].powf(p);
            let d1 = if p == 0.0 { 0.0 } else { p * a[0].powf(p - 1.0) };
            let d2 = if p == 0.0 || p == 1.0 { 0.0 } else { p * (p - 1.0) * a[0].powf(p - 2.0) };
            [y, d1 * a[1], d2 * a[1] * a[1] + d1 * a[2]]
        }
        Op::Pow => {
            // a^b = exp(b ln a).
            let [l, l1, l2] = Func::Log.derivatives(a[0]);
            let ln = [l, l1 * a[1], l2 * a[1] * a[1] + l1 * a[2]];
            let e = binary_jet(Op::Mul, b, ln);
            let y = e[0].exp();
            [y, y * e[1], y * (e[2] + e[1] * e[1])]
        }
        Op::Call2(Func2::Min) => {
            if a[0] <= b[0] {
                a
            } else {
                b
            }
        }
        Op::Call2(Func2::Max) => {
            if a[0] >= b[0] {
                a
            } else {
                b
            }
        }
        Op::Call2(Func2::Atan2) => {
            // atan2(y = a, x = b): d = (x y' - y x') / r with r = x^2 + y^2.
            let r = a[0] * a[0] + b[0] * b[0];
            let num = b[0] * a[1] - a[0] * b[1];
            let num1 = b[0] * a[2] - a[0] * b[2];
            let r1 = 2.0 * (a[0] * a[1] + b[0] * b[1]);
            [a[0].atan2(b[0]), num / r, (num1 * r - num * r1) / (r * r)]
        }
        Op::Compare(c) => flat(c.apply(a[0], b[0])),
        Op::And => flat(if a[0] != 0.0 && b[0] != 0.0 { 1.0 } else { 0.0 }),
        Op::Or => flat(if a[0] != 0.0 || b[0] != 0.0 { 1.0 } else { 0.0 }),
        _ => unreachable!("not a binary operation"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn jets_are_the_derivatives_of_the_formula() {
        use Expr::*;
        let t = || Time;
        let c = Const;
        // 2 sin(3 t) + t^2 / (1 + t) - exp(-t) cos(t) + t^1.5 + (1 + t)^t + atan2(t, 2 - t)
        let formula = 2.0 * Expr::call(Func::Sin, 3.0 * t()) + t().pow(c(2.0)) / (1.0 + t())
            - Expr::call(Func::Exp, -t()) * Expr::call(Func::Cos, t())
            + t().pow(c(1.5))
            + (1.0 + t()).pow(t())
            + Expr::call2(Func2::Atan2, t(), 2.0 - t());
        let f = TimeFunction::new(&formula).unwrap();
        let exact = |t: f64| {
            2.0 * (3.0 * t).sin() + t * t / (1.0 + t) - (-t).exp() * t.cos()
                + t.powf(1.5)
                + (1.0 + t).powf(t)
                + t.atan2(2.0 - t)
        };
        // Central differences of step 1e-4: truncation ~1e-8 |f'''|, rounding ~1e-16/h^2.
        let h = 1e-4;
        for t in [0.3, 1.1, 2.7] {
            let [y, d1, d2] = f.jet(t);
            assert!((y - exact(t)).abs() < 1e-13);
            let fd1 = (exact(t + h) - exact(t - h)) / (2.0 * h);
            let fd2 = (exact(t + h) - 2.0 * exact(t) + exact(t - h)) / (h * h);
            assert!((d1 - fd1).abs() < 1e-6, "t = {t}: {d1} vs {fd1}");
            assert!((d2 - fd2).abs() < 1e-5, "t = {t}: {d2} vs {fd2}");
        }
    }

    #[test]
    fn conditions_pick_the_branch_and_its_derivatives() {
        let t = || Expr::Time;
        let f = Expr::if_else(Expr::compare(Cmp::Lt, t(), 1.0.into()), t() * t(), 3.0 * t());
        let f = TimeFunction::new(&f).unwrap();
        assert_eq!(f.jet(0.5), [0.25, 1.0, 2.0]);
        assert_eq!(f.jet(2.0), [6.0, 3.0, 0.0]);
        assert!(TimeFunction::new(&Expr::var("x")).is_err());
    }

    #[test]
    fn every_function_differentiates_correctly() {
        let h = 1e-5;
        for name in Func::NAMES {
            let f = Func::from_name(name).unwrap();
            for x in [0.3, 0.7] {
                let value = |x: f64| f.derivatives(x)[0];
                let [y, d1, d2] = f.derivatives(x);
                assert_eq!(y, f.apply(x), "{name}");
                let fd1 = (value(x + h) - value(x - h)) / (2.0 * h);
                let fd2 = (f.derivatives(x + h)[1] - f.derivatives(x - h)[1]) / (2.0 * h);
                // Truncation h^2 |f''''| / 6 reaches 1e-8 for log at 0.3.
                let close = |a: f64, b: f64| (a - b).abs() < 1e-7 * (1.0 + a.abs());
                assert!(close(d1, fd1) && close(d2, fd2), "{name} at {x}: {d1} {fd1}, {d2} {fd2}");
            }
        }
    }
}
