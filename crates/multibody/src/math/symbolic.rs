//! Symbolic scalar expressions over numbered variables: the form in which
//! assembly solves a model's equations. Constructors fold constants and
//! drop neutral terms, so that derivatives stay small; `derivative` gives
//! the partial derivative by a variable, which closes the form of an
//! equation linear in its unknown and gives Newton its Jacobian.

use super::expr::{Cmp, Func, Func2};
use std::rc::Rc;

/// A symbolic expression; shared subtrees are reference-counted.
#[derive(Clone, Debug, PartialEq)]
pub enum Sym {
    Const(f64),
    Time,
    Var(usize),
    Neg(Rc<Sym>),
    Add(Rc<Sym>, Rc<Sym>),
    Sub(Rc<Sym>, Rc<Sym>),
    Mul(Rc<Sym>, Rc<Sym>),
    Div(Rc<Sym>, Rc<Sym>),
    Pow(Rc<Sym>, Rc<Sym>),
    Call(Func, Rc<Sym>),
    Call2(Func2, Rc<Sym>, Rc<Sym>),
    Compare(Cmp, Rc<Sym>, Rc<Sym>),
    And(Rc<Sym>, Rc<Sym>),
    Or(Rc<Sym>, Rc<Sym>),
    Not(Rc<Sym>),
    If(Rc<Sym>, Rc<Sym>, Rc<Sym>),
    /// Relations inside are evaluated as they are, without events.
    NoEvent(Rc<Sym>),
    /// The value of a variable before the current event (not a dependence
    /// on its present value).
    Pre(usize),
    /// True during the event iteration at the start.
    Initial,
    /// True at the event where the argument became true.
    Edge(Rc<Sym>),
    /// True at the event where the argument changed.
    Change(Rc<Sym>),
    /// True at the time events `start + k interval`.
    Sample(f64, f64),
}

pub type S = Rc<Sym>;

pub fn constant(x: f64) -> S {
    Rc::new(Sym::Const(x))
}

pub fn var(v: usize) -> S {
    Rc::new(Sym::Var(v))
}

impl Sym {
    pub fn as_const(&self) -> Option<f64> {
        if let Sym::Const(x) = self {
            Some(*x)
        } else {
            None
        }
    }

    /// Whether variable `v` appears in the expression.
    pub fn depends_on(&self, v: usize) -> bool {
        let mut found = false;
        self.each_var(&mut |w| found |= w == v);
        found
    }

    /// The expression's operands (up to three), in order.
    pub fn children(&self) -> [Option<&S>; 3] {
        match self {
            Sym::Const(_) | Sym::Time | Sym::Var(_) | Sym::Pre(_) | Sym::Initial | Sym::Sample(..) => [None; 3],
            Sym::Neg(a) | Sym::Call(_, a) | Sym::Not(a) | Sym::NoEvent(a) | Sym::Edge(a) | Sym::Change(a) => {
                [Some(a), None, None]
            }
            Sym::Add(a, b)
            | Sym::Sub(a, b)
            | Sym::Mul(a, b)
            | Sym::Div(a, b)
            | Sym::Pow(a, b)
            | Sym::Call2(_, a, b)
            | Sym::Compare(_, a, b)
            | Sym::And(a, b)
            | Sym::Or(a, b) => [Some(a), Some(b), None],
            Sym::If(c, a, b) => [Some(c), Some(a), Some(b)],
        }
    }

    /// The first `Some` that `f` gives on the nodes, in pre-order.
    pub fn find<T>(&self, f: &mut impl FnMut(&Sym) -> Option<T>) -> Option<T> {
        f(self).or_else(|| self.children().into_iter().flatten().find_map(|c| c.find(f)))
    }

    /// Calls `f` for every variable occurrence.
    pub fn each_var(&self, f: &mut impl FnMut(usize)) {
        self.find(&mut |node| {
            if let Sym::Var(v) = node {
                f(*v);
            }
            None::<()>
        });
    }

    /// Whether the expression mentions time.
    pub fn mentions_time(&self) -> bool {
        self.find(&mut |node| matches!(node, Sym::Time).then_some(())).is_some()
    }
}

pub fn neg(a: S) -> S {
    match &*a {
        Sym::Const(x) => constant(-x),
        Sym::Neg(inner) => inner.clone(),
        _ => Rc::new(Sym::Neg(a)),
    }
}

pub fn add(a: S, b: S) -> S {
    match (a.as_const(), b.as_const()) {
        (Some(x), Some(y)) => constant(x + y),
        (Some(0.0), _) => b,
        (_, Some(0.0)) => a,
        _ => match &*b {
            Sym::Neg(inner) => Rc::new(Sym::Sub(a, inner.clone())),
            _ => Rc::new(Sym::Add(a, b)),
        },
    }
}

pub fn sub(a: S, b: S) -> S {
    match (a.as_const(), b.as_const()) {
        (Some(x), Some(y)) => constant(x - y),
        (Some(0.0), _) => neg(b),
        (_, Some(0.0)) => a,
        _ if a == b => constant(0.0),
        _ => match &*b {
            Sym::Neg(inner) => Rc::new(Sym::Add(a, inner.clone())),
            _ => Rc::new(Sym::Sub(a, b)),
        },
    }
}

pub fn mul(a: S, b: S) -> S {
    match (a.as_const(), b.as_const()) {
        (Some(x), Some(y)) => constant(x * y),
        (Some(0.0), _) | (_, Some(0.0)) => constant(0.0),
        (Some(1.0), _) => b,
        (_, Some(1.0)) => a,
        (Some(-1.0), _) => neg(b),
        (_, Some(-1.0)) => neg(a),
        _ => Rc::new(Sym::Mul(a, b)),
    }
}

pub fn div(a: S, b: S) -> S {
    match (a.as_const(), b.as_const()) {
        (Some(x), Some(y)) if y != 0.0 => constant(x / y),
        (Some(0.0), _) => constant(0.0),
        (_, Some(1.0)) => a,
        (_, Some(-1.0)) => neg(a),
        _ => Rc::new(Sym::Div(a, b)),
    }
}

pub fn pow(a: S, b: S) -> S {
    match (a.as_const(), b.as_const()) {
        (Some(x), Some(y)) => constant(x.powf(y)),
        (_, Some(1.0)) => a,
        (_, Some(0.0)) => constant(1.0),
        _ => Rc::new(Sym::Pow(a, b)),
    }
}

pub fn call(f: Func, a: S) -> S {
    match a.as_const() {
        Some(x) => constant(f.apply(x)),
        None => Rc::new(Sym::Call(f, a)),
    }
}

pub fn call2(f: Func2, a: S, b: S) -> S {
    match (a.as_const(), b.as_const()) {
        (Some(x), Some(y)) => constant(f.apply(x, y)),
        _ => Rc::new(Sym::Call2(f, a, b)),
    }
}

pub fn compare(c: Cmp, a: S, b: S) -> S {
    match (a.as_const(), b.as_const()) {
        (Some(x), Some(y)) => constant(c.apply(x, y)),
        _ => Rc::new(Sym::Compare(c, a, b)),
    }
}

pub fn and(a: S, b: S) -> S {
    match (a.as_const(), b.as_const()) {
        (Some(0.0), _) => constant(0.0),
        (_, Some(0.0)) => constant(0.0),
        (Some(_), Some(_)) => constant(1.0),
        _ => Rc::new(Sym::And(a, b)),
    }
}

pub fn or(a: S, b: S) -> S {
    match (a.as_const(), b.as_const()) {
        (Some(x), _) if x != 0.0 => constant(1.0),
        (_, Some(y)) if y != 0.0 => constant(1.0),
        (Some(_), Some(_)) => constant(0.0),
        _ => Rc::new(Sym::Or(a, b)),
    }
}

pub fn not(a: S) -> S {
    match a.as_const() {
        Some(x) => constant(if x == 0.0 { 1.0 } else { 0.0 }),
        None => Rc::new(Sym::Not(a)),
    }
}

/// `noEvent(a)`; a constant needs none.
pub fn no_event(a: S) -> S {
    match &*a {
        Sym::Const(_) | Sym::Time | Sym::Var(_) | Sym::NoEvent(_) => a,
        _ => Rc::new(Sym::NoEvent(a)),
    }
}

pub fn if_else(c: S, a: S, b: S) -> S {
    match c.as_const() {
        Some(x) if x != 0.0 => a,
        Some(_) => b,
        None if a == b => a,
        None => Rc::new(Sym::If(c, a, b)),
    }
}

/// The partial derivative of `e` by variable `v` (conditions and
/// piecewise-constant functions count as constant).
pub fn derivative(e: &S, v: usize) -> S {
    differentiate(e, &mut |leaf| match leaf {
        Sym::Var(w) if *w == v => Some(constant(1.0)),
        _ => None,
    })
}

/// The time derivative of `e`, where `der(v)` gives the number of the
/// variable that is the derivative of variable `v` (`None`: `v` is
/// constant between events).
pub fn time_derivative(e: &S, der: &mut impl FnMut(usize) -> Option<usize>) -> S {
    differentiate(e, &mut |leaf| match leaf {
        Sym::Time => Some(constant(1.0)),
        Sym::Var(w) => der(*w).map(var),
        _ => None,
    })
}

/// The derivative of `e` where `leaf` gives the derivative of a variable
/// or of time (`None`: zero).
fn differentiate(e: &S, leaf: &mut impl FnMut(&Sym) -> Option<S>) -> S {
    if let Sym::Time | Sym::Var(_) = &**e {
        return leaf(e).unwrap_or_else(|| constant(0.0));
    }
    let mut d = |x: &S| differentiate(x, leaf);
    match &**e {
        Sym::Const(_) | Sym::Time | Sym::Var(_) => constant(0.0),
        Sym::Neg(a) => neg(d(a)),
        Sym::Add(a, b) => add(d(a), d(b)),
        Sym::Sub(a, b) => sub(d(a), d(b)),
        Sym::Mul(a, b) => add(mul(d(a), b.clone()), mul(a.clone(), d(b))),
        Sym::Div(a, b) => {
            // (a' b - a b') / b^2 = a'/b - (a/b) b'/b
            let q = div(a.clone(), b.clone());
            sub(div(d(a), b.clone()), div(mul(q, d(b)), b.clone()))
        }
        Sym::Pow(a, b) => match b.as_const() {
            Some(p) => mul(mul(constant(p), pow(a.clone(), constant(p - 1.0))), d(a)),
            // a^b (b' ln a + b a'/a)
            None => mul(e.clone(), add(mul(d(b), call(Func::Log, a.clone())), div(mul(b.clone(), d(a)), a.clone()))),
        },
        Sym::Call(f, a) => mul(function_derivative(*f, a), d(a)),
        Sym::Call2(f, a, b) => match f {
            Func2::Min | Func2::Max => {
                let first = compare(if *f == Func2::Min { Cmp::Le } else { Cmp::Ge }, a.clone(), b.clone());
                if_else(first, d(a), d(b))
            }
            Func2::Atan2 => {
                // atan2(a, b)' = (b a' - a b') / (a^2 + b^2)
                let r = add(mul(a.clone(), a.clone()), mul(b.clone(), b.clone()));
                div(sub(mul(b.clone(), d(a)), mul(a.clone(), d(b))), r)
            }
        },
        Sym::Compare(..)
        | Sym::And(..)
        | Sym::Or(..)
        | Sym::Not(_)
        | Sym::Pre(_)
        | Sym::Initial
        | Sym::Sample(..)
        | Sym::Edge(_)
        | Sym::Change(_) => constant(0.0),
        Sym::If(c, a, b) => if_else(c.clone(), d(a), d(b)),
        Sym::NoEvent(a) => no_event(d(a)),
    }
}

/// `f'(a)` as an expression.
fn function_derivative(f: Func, a: &S) -> S {
    let a = a.clone();
    let one = || constant(1.0);
    match f {
        Func::Sin => call(Func::Cos, a),
        Func::Cos => neg(call(Func::Sin, a)),
        Func::Tan => {
            let c = call(Func::Cos, a);
            div(one(), mul(c.clone(), c))
        }
        Func::Exp => call(Func::Exp, a),
        Func::Log => div(one(), a),
        Func::Log10 => div(one(), mul(a, constant(std::f64::consts::LN_10))),
        Func::Sqrt => div(constant(0.5), call(Func::Sqrt, a)),
        Func::Abs => call(Func::Sign, a),
        Func::Sign | Func::Floor | Func::Ceil => constant(0.0),
        Func::Asin => div(one(), call(Func::Sqrt, sub(one(), mul(a.clone(), a)))),
        Func::Acos => neg(div(one(), call(Func::Sqrt, sub(one(), mul(a.clone(), a))))),
        Func::Atan => div(one(), add(one(), mul(a.clone(), a))),
        Func::Sinh => call(Func::Cosh, a),
        Func::Cosh => call(Func::Sinh, a),
        Func::Tanh => {
            let t = call(Func::Tanh, a);
            sub(one(), mul(t.clone(), t))
        }
    }
}

/// `e` with every variable `v` for which `by(v)` gives an expression
/// replaced by it.
pub fn substitute_all(e: &S, by: &dyn Fn(usize) -> Option<S>) -> S {
    let s = |x: &S| substitute_all(x, by);
    match &**e {
        Sym::Var(w) => by(*w).unwrap_or_else(|| e.clone()),
        Sym::Const(_) | Sym::Time | Sym::Pre(_) | Sym::Initial | Sym::Sample(..) => e.clone(),
        Sym::NoEvent(a) => no_event(s(a)),
        Sym::Edge(a) => Rc::new(Sym::Edge(s(a))),
        Sym::Change(a) => Rc::new(Sym::Change(s(a))),
        Sym::Neg(a) => neg(s(a)),
        Sym::Add(a, b) => add(s(a), s(b)),
        Sym::Sub(a, b) => sub(s(a), s(b)),
        Sym::Mul(a, b) => mul(s(a), s(b)),
        Sym::Div(a, b) => div(s(a), s(b)),
        Sym::Pow(a, b) => pow(s(a), s(b)),
        Sym::Call(f, a) => call(*f, s(a)),
        Sym::Call2(f, a, b) => call2(*f, s(a), s(b)),
        Sym::Compare(c, a, b) => compare(*c, s(a), s(b)),
        Sym::And(a, b) => and(s(a), s(b)),
        Sym::Or(a, b) => or(s(a), s(b)),
        Sym::Not(a) => not(s(a)),
        Sym::If(c, a, b) => if_else(s(c), s(a), s(b)),
    }
}

/// `e` with variable `v` replaced by `by`.
pub fn substitute(e: &S, v: usize, by: &S) -> S {
    if !e.depends_on(v) {
        return e.clone();
    }
    substitute_all(e, &|w| (w == v).then(|| by.clone()))
}

/// If `e` is affine in `v`, `e = slope * v + rest` with neither part
/// depending on `v`: `(slope, rest)`.
pub fn affine_in(e: &S, v: usize) -> Option<(S, S)> {
    let slope = derivative(e, v);
    if slope.depends_on(v) || has_condition_on(e, v) {
        return None;
    }
    Some((slope, substitute(e, v, &constant(0.0))))
}

/// Whether `v` appears in a condition or a piecewise function of `e`
/// (where the derivative hides it).
fn has_condition_on(e: &S, v: usize) -> bool {
    match &**e {
        Sym::Const(_) | Sym::Time | Sym::Var(_) | Sym::Pre(_) | Sym::Initial | Sym::Sample(..) => false,
        Sym::Compare(..) | Sym::And(..) | Sym::Or(..) | Sym::Not(_) | Sym::Edge(_) | Sym::Change(_) => e.depends_on(v),
        Sym::NoEvent(a) => has_condition_on(a, v),
        Sym::Call(Func::Sign | Func::Floor | Func::Ceil | Func::Abs, a) => a.depends_on(v),
        Sym::Call2(Func2::Min | Func2::Max, a, b) => a.depends_on(v) || b.depends_on(v),
        Sym::If(c, a, b) => c.depends_on(v) || has_condition_on(a, v) || has_condition_on(b, v),
        Sym::Neg(a) | Sym::Call(_, a) => has_condition_on(a, v),
        Sym::Add(a, b) | Sym::Sub(a, b) | Sym::Mul(a, b) | Sym::Div(a, b) | Sym::Pow(a, b) | Sym::Call2(_, a, b) => {
            has_condition_on(a, v) || has_condition_on(b, v)
        }
    }
}

/// Evaluates `e` with the variables' values (for tests and start values).
pub fn evaluate(e: &Sym, t: f64, vars: &dyn Fn(usize) -> f64) -> f64 {
    let ev = |x: &S| evaluate(x, t, vars);
    let truth = |x: f64| x != 0.0;
    match e {
        Sym::Const(x) => *x,
        Sym::Time => t,
        Sym::Var(v) => vars(*v),
        // Outside events: the value as it is, no edge, no change.
        Sym::Pre(v) => vars(*v),
        Sym::Initial | Sym::Edge(_) | Sym::Change(_) | Sym::Sample(..) => 0.0,
        Sym::NoEvent(a) => ev(a),
        Sym::Neg(a) => -ev(a),
        Sym::Add(a, b) => ev(a) + ev(b),
        Sym::Sub(a, b) => ev(a) - ev(b),
        Sym::Mul(a, b) => ev(a) * ev(b),
        Sym::Div(a, b) => ev(a) / ev(b),
        Sym::Pow(a, b) => ev(a).powf(ev(b)),
        Sym::Call(f, a) => f.apply(ev(a)),
        Sym::Call2(f, a, b) => f.apply(ev(a), ev(b)),
        Sym::Compare(c, a, b) => c.apply(ev(a), ev(b)),
        Sym::And(a, b) => (truth(ev(a)) && truth(ev(b))) as u8 as f64,
        Sym::Or(a, b) => (truth(ev(a)) || truth(ev(b))) as u8 as f64,
        Sym::Not(a) => (!truth(ev(a))) as u8 as f64,
        Sym::If(c, a, b) => {
            if truth(ev(c)) {
                ev(a)
            } else {
                ev(b)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn derivatives_match_finite_differences() {
        // f(x, y) = sin(x y) + x^3 / (1 + y^2) + atan2(x, y) + exp(x)^y + max(x, y)
        let (x, y) = (var(0), var(1));
        let f = add(
            add(
                add(
                    call(Func::Sin, mul(x.clone(), y.clone())),
                    div(pow(x.clone(), constant(3.0)), add(constant(1.0), mul(y.clone(), y.clone()))),
                ),
                add(call2(Func2::Atan2, x.clone(), y.clone()), pow(call(Func::Exp, x.clone()), y.clone())),
            ),
            call2(Func2::Max, x.clone(), y.clone()),
        );
        let at = |p: [f64; 2]| move |v: usize| p[v];
        let h = 1e-6;
        for p in [[0.3, 0.9], [1.2, -0.4]] {
            for v in 0..2 {
                let mut lo = p;
                let mut hi = p;
                lo[v] -= h;
                hi[v] += h;
                let fd = (evaluate(&f, 0.0, &at(hi)) - evaluate(&f, 0.0, &at(lo))) / (2.0 * h);
                let exact = evaluate(&derivative(&f, v), 0.0, &at(p));
                assert!((fd - exact).abs() < 1e-7 * (1.0 + exact.abs()), "d/d{v} at {p:?}: {exact} vs {fd}");
            }
        }
    }

    #[test]
    fn affine_parts_are_found_and_conditions_are_not_affine() {
        // 3 x + y sin(y) - 2 = 0 is affine in x with slope 3.
        let (x, y) = (var(0), var(1));
        let e = sub(add(mul(constant(3.0), x.clone()), mul(y.clone(), call(Func::Sin, y.clone()))), constant(2.0));
        let (slope, rest) = affine_in(&e, 0).unwrap();
        assert_eq!(slope.as_const(), Some(3.0));
        assert!(!rest.depends_on(0));
        assert!(affine_in(&e, 1).is_none());
        let piecewise = if_else(compare(Cmp::Gt, x.clone(), constant(0.0)), x.clone(), neg(x.clone()));
        assert!(affine_in(&piecewise, 0).is_none());
        // x / y is affine in x, not in y.
        assert!(affine_in(&div(x.clone(), y.clone()), 0).is_some());
        assert!(affine_in(&div(x, y), 1).is_none());
    }
}
