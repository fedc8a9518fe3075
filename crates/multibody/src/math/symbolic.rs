//! The algebra of expressions, written once for the tree with names and
//! for the tree with numbered variables (the form in which assembly solves
//! a model's equations): constructors that fold constants and drop
//! neutral terms, so that derivatives stay small; partial and time
//! derivatives, which close the form of an equation linear in its unknown
//! and give Newton its Jacobian; substitution; evaluation.

use super::expr::{Cmp, Expr, Func, Func2, Node};
use std::sync::Arc;

/// A variable of the model's equations once assembly resolves its name:
/// its number among them, a type of its own so that it is never taken for
/// a register, a state index or a signal slot. Vectors and slices with one
/// entry per variable are indexed by it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct VarId(u32);

impl VarId {
    pub fn new(index: usize) -> VarId {
        VarId(u32::try_from(index).expect("fewer than 2^32 variables"))
    }

    pub fn index(self) -> usize {
        self.0 as usize
    }

    /// The variables numbered `0..n`.
    pub fn all(n: usize) -> impl Iterator<Item = VarId> {
        (0..n).map(VarId::new)
    }
}

impl<T> std::ops::Index<VarId> for [T] {
    type Output = T;
    fn index(&self, v: VarId) -> &T {
        &self[v.index()]
    }
}

impl<T> std::ops::IndexMut<VarId> for [T] {
    fn index_mut(&mut self, v: VarId) -> &mut T {
        &mut self[v.index()]
    }
}

impl<T> std::ops::Index<VarId> for Vec<T> {
    type Output = T;
    fn index(&self, v: VarId) -> &T {
        &self[v.index()]
    }
}

impl<T> std::ops::IndexMut<VarId> for Vec<T> {
    fn index_mut(&mut self, v: VarId) -> &mut T {
        &mut self[v.index()]
    }
}

/// An expression over the model's variables (after assembly resolves names).
pub type Sym = Expr<VarId>;
/// A shared expression over the model's variables.
pub type S = Node<VarId>;

pub fn constant<V>(x: f64) -> Node<V> {
    Arc::new(Expr::Const(x))
}

pub fn var<V>(v: V) -> Node<V> {
    Arc::new(Expr::Var(v))
}

impl<V: PartialEq> Expr<V> {
    /// Whether variable `v` appears in the expression.
    pub fn depends_on(&self, v: &V) -> bool {
        self.find(&mut |node| matches!(node, Expr::Var(w) if w == v).then_some(())).is_some()
    }
}

impl<V> Expr<V> {
    /// Calls `f` for every variable occurrence.
    pub fn each_var(&self, f: &mut impl FnMut(&V)) {
        self.visit(&mut |node| {
            if let Expr::Var(v) = node {
                f(v);
            }
        });
    }
}

pub fn neg<V>(a: Node<V>) -> Node<V> {
    match &*a {
        Expr::Const(x) => constant(-x),
        Expr::Neg(inner) => inner.clone(),
        _ => Arc::new(Expr::Neg(a)),
    }
}

/// `items` joined pairwise into a balanced tree (`None` when empty): a sum
/// of n terms nests log2(n) deep instead of n, so that the recursive
/// passes over it (resolution, derivatives, code) stay shallow for a node
/// where hundreds of connections meet.
pub fn balanced<T>(items: impl IntoIterator<Item = T>, join: impl Fn(T, T) -> T) -> Option<T> {
    let mut level: Vec<T> = items.into_iter().collect();
    while level.len() > 1 {
        let mut next = Vec::with_capacity(level.len().div_ceil(2));
        let mut items = level.into_iter();
        while let Some(a) = items.next() {
            next.push(match items.next() {
                Some(b) => join(a, b),
                None => a,
            });
        }
        level = next;
    }
    level.pop()
}

pub fn add<V: PartialEq>(a: Node<V>, b: Node<V>) -> Node<V> {
    match (a.as_const(), b.as_const()) {
        (Some(x), Some(y)) => constant(x + y),
        (Some(0.0), _) => b,
        (_, Some(0.0)) => a,
        _ => match &*b {
            Expr::Neg(inner) => Arc::new(Expr::Sub(a, inner.clone())),
            _ => Arc::new(Expr::Add(a, b)),
        },
    }
}

pub fn sub<V: PartialEq>(a: Node<V>, b: Node<V>) -> Node<V> {
    match (a.as_const(), b.as_const()) {
        (Some(x), Some(y)) => constant(x - y),
        (Some(0.0), _) => neg(b),
        (_, Some(0.0)) => a,
        _ if a == b => constant(0.0),
        _ => match &*b {
            Expr::Neg(inner) => Arc::new(Expr::Add(a, inner.clone())),
            _ => Arc::new(Expr::Sub(a, b)),
        },
    }
}

pub fn mul<V>(a: Node<V>, b: Node<V>) -> Node<V> {
    match (a.as_const(), b.as_const()) {
        (Some(x), Some(y)) => constant(x * y),
        (Some(0.0), _) | (_, Some(0.0)) => constant(0.0),
        (Some(1.0), _) => b,
        (_, Some(1.0)) => a,
        (Some(-1.0), _) => neg(b),
        (_, Some(-1.0)) => neg(a),
        _ => Arc::new(Expr::Mul(a, b)),
    }
}

pub fn div<V>(a: Node<V>, b: Node<V>) -> Node<V> {
    match (a.as_const(), b.as_const()) {
        // Constants divide as numbers do: 0/0 is NaN, which later checks name.
        (Some(x), Some(y)) => constant(x / y),
        (Some(0.0), _) => constant(0.0),
        (_, Some(1.0)) => a,
        (_, Some(-1.0)) => neg(a),
        _ => Arc::new(Expr::Div(a, b)),
    }
}

pub fn pow<V>(a: Node<V>, b: Node<V>) -> Node<V> {
    match (a.as_const(), b.as_const()) {
        (Some(x), Some(y)) => constant(x.powf(y)),
        (_, Some(1.0)) => a,
        (_, Some(0.0)) => constant(1.0),
        _ => Arc::new(Expr::Pow(a, b)),
    }
}

pub fn call<V>(f: Func, a: Node<V>) -> Node<V> {
    match a.as_const() {
        Some(x) => constant(f.apply(x)),
        None => Arc::new(Expr::Call(f, a)),
    }
}

pub fn call2<V>(f: Func2, a: Node<V>, b: Node<V>) -> Node<V> {
    match (a.as_const(), b.as_const()) {
        (Some(x), Some(y)) => constant(f.apply(x, y)),
        _ => Arc::new(Expr::Call2(f, a, b)),
    }
}

pub fn compare<V>(c: Cmp, a: Node<V>, b: Node<V>) -> Node<V> {
    match (a.as_const(), b.as_const()) {
        (Some(x), Some(y)) => constant(c.apply(x, y)),
        _ => Arc::new(Expr::Compare(c, a, b)),
    }
}

pub fn and<V>(a: Node<V>, b: Node<V>) -> Node<V> {
    match (a.as_const(), b.as_const()) {
        (Some(0.0), _) => constant(0.0),
        (_, Some(0.0)) => constant(0.0),
        (Some(_), Some(_)) => constant(1.0),
        _ => Arc::new(Expr::And(a, b)),
    }
}

pub fn or<V>(a: Node<V>, b: Node<V>) -> Node<V> {
    match (a.as_const(), b.as_const()) {
        (Some(x), _) if x != 0.0 => constant(1.0),
        (_, Some(y)) if y != 0.0 => constant(1.0),
        (Some(_), Some(_)) => constant(0.0),
        _ => Arc::new(Expr::Or(a, b)),
    }
}

pub fn not<V>(a: Node<V>) -> Node<V> {
    match a.as_const() {
        Some(x) => constant(if x == 0.0 { 1.0 } else { 0.0 }),
        None => Arc::new(Expr::Not(a)),
    }
}

/// `noEvent(a)`; a constant needs none.
pub fn no_event<V>(a: Node<V>) -> Node<V> {
    match &*a {
        Expr::Const(_) | Expr::Time | Expr::Var(_) | Expr::NoEvent(_) => a,
        _ => Arc::new(Expr::NoEvent(a)),
    }
}

pub fn if_else<V: PartialEq>(c: Node<V>, a: Node<V>, b: Node<V>) -> Node<V> {
    match c.as_const() {
        Some(x) if x != 0.0 => a,
        Some(_) => b,
        None if a == b => a,
        None => Arc::new(Expr::If(c, a, b)),
    }
}

/// The partial derivative of `e` by variable `v` (conditions and
/// piecewise-constant functions count as constant).
pub fn derivative<V: Clone + PartialEq>(e: &Node<V>, v: &V) -> Node<V> {
    differentiate(e, &mut |leaf| match leaf {
        Expr::Var(w) if w == v => Some(constant(1.0)),
        _ => None,
    })
}

/// The time derivative of `e`, where `der(v)` gives the variable that is
/// the derivative of variable `v` (`None`: `v` is constant between events).
pub fn time_derivative<V: Clone + PartialEq>(e: &Node<V>, der: &mut impl FnMut(&V) -> Option<V>) -> Node<V> {
    differentiate(e, &mut |leaf| match leaf {
        Expr::Time => Some(constant(1.0)),
        Expr::Var(w) => der(w).map(var),
        _ => None,
    })
}

/// The derivative of `e` where `leaf` gives the derivative of a variable,
/// of time or of a `der` (`None`: zero).
fn differentiate<V: Clone + PartialEq>(e: &Node<V>, leaf: &mut impl FnMut(&Expr<V>) -> Option<Node<V>>) -> Node<V> {
    if let Expr::Time | Expr::Var(_) | Expr::Der(_) = &**e {
        return leaf(e).unwrap_or_else(|| constant(0.0));
    }
    let mut d = |x: &Node<V>| differentiate(x, leaf);
    match &**e {
        Expr::Const(_) | Expr::Time | Expr::Var(_) | Expr::Der(_) => constant(0.0),
        Expr::Neg(a) => neg(d(a)),
        Expr::Add(a, b) => add(d(a), d(b)),
        Expr::Sub(a, b) => sub(d(a), d(b)),
        Expr::Mul(a, b) => add(mul(d(a), b.clone()), mul(a.clone(), d(b))),
        Expr::Div(a, b) => {
            // (a' b - a b') / b^2 = a'/b - (a/b) b'/b
            let q = div(a.clone(), b.clone());
            sub(div(d(a), b.clone()), div(mul(q, d(b)), b.clone()))
        }
        Expr::Pow(a, b) => match b.as_const() {
            Some(p) => mul(mul(constant(p), pow(a.clone(), constant(p - 1.0))), d(a)),
            // a^b (b' ln a + b a'/a)
            None => mul(e.clone(), add(mul(d(b), call(Func::Log, a.clone())), div(mul(b.clone(), d(a)), a.clone()))),
        },
        Expr::Call(f, a) => mul(function_derivative(*f, a), d(a)),
        Expr::Call2(f, a, b) => match f {
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
        Expr::Compare(..)
        | Expr::And(..)
        | Expr::Or(..)
        | Expr::Not(_)
        | Expr::Pre(_)
        | Expr::Initial
        | Expr::Sample { .. }
        | Expr::Edge(_)
        | Expr::Change(_) => constant(0.0),
        Expr::If(c, a, b) => if_else(c.clone(), d(a), d(b)),
        Expr::NoEvent(a) => no_event(d(a)),
    }
}

/// `f'(a)` as an expression: the one place a function's derivative is
/// written (with [`Func::derivatives`] for numbers).
fn function_derivative<V: PartialEq>(f: Func, a: &Node<V>) -> Node<V> {
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

/// `e` rebuilt bottom-up through the folding constructors, possibly over
/// other variables: `leaf` is asked first at every node and gives its
/// replacement, or `None` to rebuild the node from its rebuilt operands.
/// It must answer for every variable and `pre` (the only nodes that hold
/// a `V`). Substitution, name resolution and rewriting of derivatives are
/// this one walk.
pub fn rewrite<V, W: PartialEq, E>(
    e: &Expr<V>,
    leaf: &mut impl FnMut(&Expr<V>) -> Result<Option<Node<W>>, E>,
) -> Result<Node<W>, E> {
    if let Some(replacement) = leaf(e)? {
        return Ok(replacement);
    }
    let mut r = |x: &Node<V>| rewrite(x, leaf);
    Ok(match e {
        Expr::Var(_) | Expr::Pre(_) => unreachable!("`rewrite` needs a replacement for every variable"),
        Expr::Const(x) => constant(*x),
        Expr::Time => Arc::new(Expr::Time),
        Expr::Initial => Arc::new(Expr::Initial),
        &Expr::Sample { start, interval } => Arc::new(Expr::Sample { start, interval }),
        Expr::Der(a) => Arc::new(Expr::Der(r(a)?)),
        Expr::Edge(a) => Arc::new(Expr::Edge(r(a)?)),
        Expr::Change(a) => Arc::new(Expr::Change(r(a)?)),
        Expr::NoEvent(a) => no_event(r(a)?),
        Expr::Neg(a) => neg(r(a)?),
        Expr::Add(a, b) => add(r(a)?, r(b)?),
        Expr::Sub(a, b) => sub(r(a)?, r(b)?),
        Expr::Mul(a, b) => mul(r(a)?, r(b)?),
        Expr::Div(a, b) => div(r(a)?, r(b)?),
        Expr::Pow(a, b) => pow(r(a)?, r(b)?),
        Expr::Call(f, a) => call(*f, r(a)?),
        Expr::Call2(f, a, b) => call2(*f, r(a)?, r(b)?),
        Expr::Compare(c, a, b) => compare(*c, r(a)?, r(b)?),
        Expr::And(a, b) => and(r(a)?, r(b)?),
        Expr::Or(a, b) => or(r(a)?, r(b)?),
        Expr::Not(a) => not(r(a)?),
        Expr::If(c, a, b) => if_else(r(c)?, r(a)?, r(b)?),
    })
}

/// `e` with every variable `v` for which `by(v)` gives an expression
/// replaced by it.
pub fn substitute_all<V: Clone + PartialEq>(e: &Node<V>, by: &dyn Fn(&V) -> Option<Node<V>>) -> Node<V> {
    let done: Result<_, std::convert::Infallible> = rewrite(e, &mut |node| {
        Ok(match node {
            Expr::Var(w) => Some(by(w).unwrap_or_else(|| var(w.clone()))),
            Expr::Pre(_) => Some(Arc::new(node.clone())),
            _ => None,
        })
    });
    let Ok(e) = done;
    e
}

/// `e` with variable `v` replaced by `by`.
pub fn substitute<V: Clone + PartialEq>(e: &Node<V>, v: &V, by: &Node<V>) -> Node<V> {
    if !e.depends_on(v) {
        return e.clone();
    }
    substitute_all(e, &|w| (w == v).then(|| by.clone()))
}

/// If `e` is affine in `v`, `e = slope * v + rest` with neither part
/// depending on `v`: `(slope, rest)`.
pub fn affine_in<V: Clone + PartialEq>(e: &Node<V>, v: &V) -> Option<(Node<V>, Node<V>)> {
    let slope = derivative(e, v);
    if slope.depends_on(v) || has_condition_on(e, v) {
        return None;
    }
    Some((slope, substitute(e, v, &constant(0.0))))
}

/// Whether `v` appears in a condition or a piecewise function of `e`
/// (where the derivative hides it).
fn has_condition_on<V: PartialEq>(e: &Expr<V>, v: &V) -> bool {
    match e {
        Expr::Const(_) | Expr::Time | Expr::Var(_) | Expr::Pre(_) | Expr::Initial | Expr::Sample { .. } => false,
        Expr::Compare(..) | Expr::And(..) | Expr::Or(..) | Expr::Not(_) | Expr::Edge(_) | Expr::Change(_) => {
            e.depends_on(v)
        }
        Expr::NoEvent(a) | Expr::Der(a) => has_condition_on(a, v),
        Expr::Call(Func::Sign | Func::Floor | Func::Ceil | Func::Abs, a) => a.depends_on(v),
        Expr::Call2(Func2::Min | Func2::Max, a, b) => a.depends_on(v) || b.depends_on(v),
        Expr::If(c, a, b) => c.depends_on(v) || has_condition_on(a, v) || has_condition_on(b, v),
        Expr::Neg(a) | Expr::Call(_, a) => has_condition_on(a, v),
        Expr::Add(a, b)
        | Expr::Sub(a, b)
        | Expr::Mul(a, b)
        | Expr::Div(a, b)
        | Expr::Pow(a, b)
        | Expr::Call2(_, a, b) => has_condition_on(a, v) || has_condition_on(b, v),
    }
}

/// Evaluates `e` with the variables' values: the one interpreter of the
/// tree (start values, guesses, parameters' formulas, tests). Outside
/// events: `pre(x)` is `x`, no edge, no change; `der` is not a value here
/// (0).
pub fn evaluate<V>(e: &Expr<V>, t: f64, vars: &dyn Fn(&V) -> f64) -> f64 {
    let ev = |x: &Node<V>| evaluate(x, t, vars);
    let truth = |x: f64| x != 0.0;
    match e {
        Expr::Const(x) => *x,
        Expr::Time => t,
        Expr::Var(v) | Expr::Pre(v) => vars(v),
        Expr::Initial | Expr::Edge(_) | Expr::Change(_) | Expr::Sample { .. } | Expr::Der(_) => 0.0,
        Expr::NoEvent(a) => ev(a),
        Expr::Neg(a) => -ev(a),
        Expr::Add(a, b) => ev(a) + ev(b),
        Expr::Sub(a, b) => ev(a) - ev(b),
        Expr::Mul(a, b) => ev(a) * ev(b),
        Expr::Div(a, b) => ev(a) / ev(b),
        Expr::Pow(a, b) => ev(a).powf(ev(b)),
        Expr::Call(f, a) => f.apply(ev(a)),
        Expr::Call2(f, a, b) => f.apply(ev(a), ev(b)),
        Expr::Compare(c, a, b) => c.apply(ev(a), ev(b)),
        Expr::And(a, b) => (truth(ev(a)) && truth(ev(b))) as u8 as f64,
        Expr::Or(a, b) => (truth(ev(a)) || truth(ev(b))) as u8 as f64,
        Expr::Not(a) => (!truth(ev(a))) as u8 as f64,
        Expr::If(c, a, b) => {
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
        let at = |p: [f64; 2]| move |v: &usize| p[*v];
        let h = 1e-6;
        for p in [[0.3, 0.9], [1.2, -0.4]] {
            for v in 0..2 {
                let mut lo = p;
                let mut hi = p;
                lo[v] -= h;
                hi[v] += h;
                let fd = (evaluate(&f, 0.0, &at(hi)) - evaluate(&f, 0.0, &at(lo))) / (2.0 * h);
                let exact = evaluate(&derivative(&f, &v), 0.0, &at(p));
                assert!((fd - exact).abs() < 1e-7 * (1.0 + exact.abs()), "d/d{v} at {p:?}: {exact} vs {fd}");
            }
        }
    }

    #[test]
    fn affine_parts_are_found_and_conditions_are_not_affine() {
        // 3 x + y sin(y) - 2 = 0 is affine in x with slope 3.
        let (x, y) = (var(0), var(1));
        let e = sub(add(mul(constant(3.0), x.clone()), mul(y.clone(), call(Func::Sin, y.clone()))), constant(2.0));
        let (slope, rest) = affine_in(&e, &0).unwrap();
        assert_eq!(slope.as_const(), Some(3.0));
        assert!(!rest.depends_on(&0));
        assert!(affine_in(&e, &1).is_none());
        let piecewise = if_else(compare(Cmp::Gt, x.clone(), constant(0.0)), x.clone(), neg(x.clone()));
        assert!(affine_in(&piecewise, &0).is_none());
        // x / y is affine in x, not in y.
        assert!(affine_in(&div(x.clone(), y.clone()), &0).is_some());
        assert!(affine_in(&div(x, y), &1).is_none());
    }
}
