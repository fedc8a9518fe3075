//! The one expression tree of the library, from a model file's equations
//! to the compiled code: scalar expressions of time and variables
//! (`ctrl.y = -kp * (sensor.phi - ref)`), plain data. `Expr` (variables
//! by name) is what a model states; after assembly resolves the names,
//! the same tree over typed variable ids ([`VarId`](super::symbolic::VarId)),
//! [`Sym`](super::symbolic::Sym), is what the equation compiler sorts,
//! differentiates and compiles
//! ([`symbolic`](super::symbolic) holds the algebra, written once for
//! both). Subtrees are shared (`Arc`), so copies and derivatives are cheap.
//!
//! A formula of time alone (no variables) also compiles into a
//! [`TimeFunction`], evaluated with its first two time derivatives, which
//! prescribed motion needs.

pub use super::tape::TimeFunction;
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
        use crate::math::symbolic::{derivative, evaluate, var};
        let h = 1e-5;
        for name in Func::NAMES {
            let f = Func::from_name(name).unwrap();
            let e = std::sync::Arc::new(Expr::Call(f, var(0usize)));
            let d1 = derivative(&e, &0);
            let d2 = derivative(&d1, &0);
            let at = |e: &Expr<usize>, x: f64| evaluate(e, 0.0, &|_| x);
            for x in [0.3, 0.7] {
                assert_eq!(at(&e, x), f.apply(x), "{name}");
                let fd1 = (f.apply(x + h) - f.apply(x - h)) / (2.0 * h);
                let fd2 = (at(&d1, x + h) - at(&d1, x - h)) / (2.0 * h);
                // Truncation h^2 |f'''| / 6 reaches 1e-8 for log at 0.3.
                let close = |a: f64, b: f64| (a - b).abs() < 1e-7 * (1.0 + a.abs());
                let (d1, d2) = (at(&d1, x), at(&d2, x));
                assert!(close(d1, fd1) && close(d2, fd2), "{name} at {x}: {d1} {fd1}, {d2} {fd2}");
            }
        }
    }
}
