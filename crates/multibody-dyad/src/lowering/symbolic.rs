//! Equations' expressions as arrays of scalar engine expressions: names
//! become variables (`ctrl.x`, `body.frame_a.r_0[2]`) or constants
//! (parameters, loop indices), and vector and matrix operations
//! (`R * v`, `cross`, `resolve1`, `axes_rotations`, ...) are written out
//! element by element, so that the engine sees scalar equations only.

use crate::reports::diagnostics::{did_you_mean, Diagnostic};
use crate::semantics::eval::Val;
use crate::syntax::ast::{BinaryOp, Expr, ExprKind, Path, UnaryOp};
use crate::syntax::source::Span;
use multibody::math::expr::Node;
use multibody::math::symbolic::{self as sym, add, call, constant, div, mul, neg, sub};
use multibody::{Cmp, Expr as E, Func, Func2};
use std::sync::Arc;

/// An equation's expression written out element by element: one scalar
/// expression of the engine's tree, or an array of them (a matrix is an
/// array of rows). Arrays exist only here; the engine sees scalars.
#[derive(Clone, Debug, PartialEq)]
pub enum ArrayExpr {
    Scalar(Node),
    Array(Vec<ArrayExpr>),
}

type SResult = Result<ArrayExpr, Diagnostic>;

/// What names in an equation stand for.
pub trait Names {
    /// The value of a reference (`x`, `frame_a.r_0`, `links[2].body.phi`),
    /// `None` if the name is unknown (the caller suggests names).
    fn reference(&mut self, expr: &Expr) -> Result<Option<ArrayExpr>, Diagnostic>;
    /// Names that could have been meant, for suggestions.
    fn candidates(&self) -> Vec<String>;
}

impl ArrayExpr {
    pub fn scalar(x: f64) -> ArrayExpr {
        ArrayExpr::Scalar(constant(x))
    }

    /// The sizes of the array (`[]` for a scalar), if it is rectangular.
    pub fn shape(&self) -> Option<Vec<usize>> {
        match self {
            ArrayExpr::Scalar(_) => Some(vec![]),
            ArrayExpr::Array(items) => {
                let first = items.first().map_or(Some(vec![]), ArrayExpr::shape)?;
                if items.iter().skip(1).all(|i| i.shape().as_ref() == Some(&first)) {
                    Some(std::iter::once(items.len()).chain(first).collect())
                } else {
                    None
                }
            }
        }
    }

    pub fn describe(&self) -> String {
        match self.shape() {
            Some(s) if s.is_empty() => "a scalar".into(),
            Some(s) if s.len() == 1 => format!("a vector of {}", s[0]),
            Some(s) => format!("a {} array", s.iter().map(usize::to_string).collect::<Vec<_>>().join("x")),
            None => "an array of mixed sizes".into(),
        }
    }

    /// Every scalar, in order (row by row).
    pub fn flatten(self, out: &mut Vec<Node>) {
        match self {
            ArrayExpr::Scalar(e) => out.push(e),
            ArrayExpr::Array(items) => items.into_iter().for_each(|i| i.flatten(out)),
        }
    }

    fn as_scalar(&self) -> Option<&Node> {
        match self {
            ArrayExpr::Scalar(e) => Some(e),
            _ => None,
        }
    }

    /// The constant value, if the expression is one.
    pub fn constant(&self) -> Option<f64> {
        match self {
            ArrayExpr::Scalar(e) => e.as_const(),
            _ => None,
        }
    }

    fn map(&self, f: &dyn Fn(&Node) -> Node) -> ArrayExpr {
        match self {
            ArrayExpr::Scalar(e) => ArrayExpr::Scalar(f(e)),
            ArrayExpr::Array(items) => ArrayExpr::Array(items.iter().map(|i| i.map(f)).collect()),
        }
    }

    /// The rows of a matrix, each a list of scalars.
    fn matrix(&self) -> Option<Vec<Vec<Node>>> {
        let ArrayExpr::Array(rows) = self else { return None };
        rows.iter()
            .map(|r| match r {
                ArrayExpr::Array(items) => items.iter().map(|i| i.as_scalar().cloned()).collect(),
                ArrayExpr::Scalar(_) => None,
            })
            .collect()
    }

    fn vector(&self) -> Option<Vec<Node>> {
        match self {
            ArrayExpr::Array(items) => items.iter().map(|i| i.as_scalar().cloned()).collect(),
            ArrayExpr::Scalar(_) => None,
        }
    }

    fn from_vector(v: Vec<Node>) -> ArrayExpr {
        ArrayExpr::Array(v.into_iter().map(ArrayExpr::Scalar).collect())
    }

    fn from_matrix(m: Vec<Vec<Node>>) -> ArrayExpr {
        ArrayExpr::Array(m.into_iter().map(ArrayExpr::from_vector).collect())
    }
}

/// A parameter's value as a symbolic one (numbers and booleans).
pub fn from_val(v: &Val) -> Option<ArrayExpr> {
    match v {
        Val::Number(x) => Some(ArrayExpr::scalar(*x)),
        Val::Bool(b) => Some(ArrayExpr::scalar(if *b { 1.0 } else { 0.0 })),
        Val::Array(items) => items.iter().map(from_val).collect::<Option<Vec<_>>>().map(ArrayExpr::Array),
        _ => None,
    }
}

/// Chains of sums this long or longer are added pairwise.
const LONG_CHAIN: usize = 32;

fn sum(terms: impl IntoIterator<Item = Node>) -> Node {
    sym::balanced(terms, add).unwrap_or_else(|| constant(0.0))
}

fn truth(x: bool) -> Node {
    constant(if x { 1.0 } else { 0.0 })
}

/// Evaluates an equation's expression.
pub fn eval(expr: &Expr, names: &mut dyn Names) -> SResult {
    let span = expr.span;
    match &expr.kind {
        ExprKind::Number(x) => Ok(ArrayExpr::scalar(*x)),
        ExprKind::Bool(b) => Ok(ArrayExpr::Scalar(truth(*b))),
        ExprKind::Str(_) => Err(Diagnostic::error("a string cannot be part of an equation").primary(span, "a string")),
        ExprKind::Name(path) if path.parts.len() == 1 && path.parts[0].name == "time" => {
            Ok(ArrayExpr::Scalar(Arc::new(E::Time)))
        }
        ExprKind::Name(_) | ExprKind::Index { .. } | ExprKind::Field { .. } => reference(expr, names),
        ExprKind::Array(items) => Ok(ArrayExpr::Array(items.iter().map(|i| eval(i, names)).collect::<Result<_, _>>()?)),
        ExprKind::Call { callee, args } => function(callee, args, span, names),
        ExprKind::Unary { op, operand } => {
            let v = eval(operand, names)?;
            Ok(match op {
                UnaryOp::Plus => v,
                UnaryOp::Neg => v.map(&|e| neg(e.clone())),
                UnaryOp::Not => ArrayExpr::Scalar(sym::not(scalar(&v, operand.span, "`!`")?)),
            })
        }
        ExprKind::Binary { op, lhs, rhs } => {
            let (a, b) = (eval(lhs, names)?, eval(rhs, names)?);
            binary(*op, a, b, lhs.span, rhs.span, span)
        }
        ExprKind::Chain { first, rest } => {
            let mut value = eval(first, names)?;
            let mut left = first.span;
            let operands = rest.iter().map(|(op, rhs)| Ok((*op, eval(rhs, names)?))).collect::<Result<Vec<_>, _>>()?;
            // A long sum or product of numbers is taken pairwise: a
            // balanced tree log2(n) deep, which the later passes walk
            // without a deep recursion (and which rounds no worse than
            // left to right).
            let numbers = operands.len() >= LONG_CHAIN
                && matches!(value, ArrayExpr::Scalar(_))
                && operands.iter().all(|(_, x)| matches!(x, ArrayExpr::Scalar(_)));
            let all = |ops: &[BinaryOp]| operands.iter().all(|(op, _)| ops.contains(op));
            if numbers && (all(&[BinaryOp::Add, BinaryOp::Sub]) || all(&[BinaryOp::Mul])) {
                let product = operands[0].0 == BinaryOp::Mul;
                let term = |(op, x): (BinaryOp, ArrayExpr)| match (op, x) {
                    (BinaryOp::Sub, ArrayExpr::Scalar(x)) => neg(x),
                    (_, ArrayExpr::Scalar(x)) => x,
                    _ => unreachable!("checked: numbers"),
                };
                let ArrayExpr::Scalar(first) = value else { unreachable!("checked: a number") };
                let terms = std::iter::once(first).chain(operands.into_iter().map(term));
                let joined = if product { sym::balanced(terms, mul) } else { sym::balanced(terms, add) };
                return Ok(ArrayExpr::Scalar(joined.expect("a chain has terms")));
            }
            for ((op, b), (_, rhs)) in operands.into_iter().zip(rest) {
                value = binary(op, value, b, left, rhs.span, left.to(rhs.span))?;
                left = left.to(rhs.span);
            }
            Ok(value)
        }
        ExprKind::If { condition, then, otherwise } => {
            let c = eval(condition, names)?;
            let c = scalar(&c, condition.span, "a condition")?;
            if let Some(x) = c.as_const() {
                return eval(if x != 0.0 { then } else { otherwise }, names);
            }
            let (a, b) = (eval(then, names)?, eval(otherwise, names)?);
            select(c, a, b, span)
        }
        ExprKind::Range { .. } => Err(Diagnostic::error("a range is not a value of an equation")
            .primary(span, "a range")
            .help("ranges go in `for i in 1:N` and in arrays of components; write the values out: `[1, 2, 3]`")),
        ExprKind::Unsupported(what) => {
            Err(Diagnostic::error(format!("{what} not supported yet")).primary(span, "not supported yet"))
        }
    }
}

/// `if c then a else b` element by element.
fn select(c: Node, a: ArrayExpr, b: ArrayExpr, span: Span) -> SResult {
    match (a, b) {
        (ArrayExpr::Scalar(a), ArrayExpr::Scalar(b)) => Ok(ArrayExpr::Scalar(sym::if_else(c, a, b))),
        (ArrayExpr::Array(a), ArrayExpr::Array(b)) if a.len() == b.len() => Ok(ArrayExpr::Array(
            a.into_iter().zip(b).map(|(x, y)| select(c.clone(), x, y, span)).collect::<Result<_, _>>()?,
        )),
        (a, b) => Err(Diagnostic::error(format!(
            "the two branches of a condition must have the same size, but one is {} and the other {}",
            a.describe(),
            b.describe()
        ))
        .primary(span, "branches of different sizes")),
    }
}

/// The one scalar of a value, or an error naming `what` needs one.
fn scalar(v: &ArrayExpr, span: Span, what: &str) -> Result<Node, Diagnostic> {
    v.as_scalar().cloned().ok_or_else(|| {
        Diagnostic::error(format!("{what} needs a scalar, but this is {}", v.describe())).primary(span, "not a scalar")
    })
}

fn reference(expr: &Expr, names: &mut dyn Names) -> SResult {
    if let Some(v) = names.reference(expr)? {
        return Ok(v);
    }
    let text = reference_text(expr);
    let constant = match text.as_str() {
        "pi" | "π" => Some(std::f64::consts::PI),
        "true" => Some(1.0),
        "false" => Some(0.0),
        "Inf" | "inf" => Some(f64::INFINITY),
        _ => None,
    };
    if let Some(x) = constant {
        return Ok(ArrayExpr::scalar(x));
    }
    let candidates = names.candidates();
    let mut d = Diagnostic::error(format!("unknown name `{text}`"))
        .primary(expr.span, "not a variable, connector or parameter here");
    if let Some(s) = did_you_mean(&text, candidates.iter().map(String::as_str)) {
        d = d.help(s);
    }
    Err(d)
}

/// A reference written out (`links[i].x`), for messages.
pub fn reference_text(expr: &Expr) -> String {
    match &expr.kind {
        ExprKind::Name(p) => p.text(),
        ExprKind::Index { base, .. } => format!("{}[...]", reference_text(base)),
        ExprKind::Field { base, name } => format!("{}.{}", reference_text(base), name.name),
        _ => "this expression".into(),
    }
}

fn shape_error(op: &str, a: &ArrayExpr, b: &ArrayExpr, span: Span, help: &str) -> Diagnostic {
    Diagnostic::error(format!("cannot apply `{op}` to {} and {}", a.describe(), b.describe()))
        .primary(span, "sizes do not fit")
        .help(help.to_string())
}

/// Element by element, or a scalar with every element when `broadcast`.
fn zip(a: &ArrayExpr, b: &ArrayExpr, broadcast: bool, f: &dyn Fn(Node, Node) -> Node) -> Option<ArrayExpr> {
    match (a, b) {
        (ArrayExpr::Scalar(x), ArrayExpr::Scalar(y)) => Some(ArrayExpr::Scalar(f(x.clone(), y.clone()))),
        (ArrayExpr::Array(xs), ArrayExpr::Array(ys)) if xs.len() == ys.len() => {
            Some(ArrayExpr::Array(xs.iter().zip(ys).map(|(x, y)| zip(x, y, broadcast, f)).collect::<Option<_>>()?))
        }
        (ArrayExpr::Scalar(_), ArrayExpr::Array(ys)) if broadcast => {
            Some(ArrayExpr::Array(ys.iter().map(|y| zip(a, y, broadcast, f)).collect::<Option<_>>()?))
        }
        (ArrayExpr::Array(xs), ArrayExpr::Scalar(_)) if broadcast => {
            Some(ArrayExpr::Array(xs.iter().map(|x| zip(x, b, broadcast, f)).collect::<Option<_>>()?))
        }
        _ => None,
    }
}

fn binary(op: BinaryOp, a: ArrayExpr, b: ArrayExpr, lspan: Span, rspan: Span, span: Span) -> SResult {
    let _ = (lspan, rspan);
    let symbol = op.symbol();
    let compare = |c: Cmp| -> SResult {
        let (x, y) = (scalar(&a, lspan, &format!("`{symbol}`"))?, scalar(&b, rspan, &format!("`{symbol}`"))?);
        Ok(ArrayExpr::Scalar(sym::compare(c, x, y)))
    };
    let logic = |and: bool| -> SResult {
        let (x, y) = (scalar(&a, lspan, &format!("`{symbol}`"))?, scalar(&b, rspan, &format!("`{symbol}`"))?);
        Ok(ArrayExpr::Scalar(if and { sym::and(x, y) } else { sym::or(x, y) }))
    };
    let result = match op {
        BinaryOp::Lt => return compare(Cmp::Lt),
        BinaryOp::Le => return compare(Cmp::Le),
        BinaryOp::Gt => return compare(Cmp::Gt),
        BinaryOp::Ge => return compare(Cmp::Ge),
        BinaryOp::Eq => return compare(Cmp::Eq),
        BinaryOp::Ne => return compare(Cmp::Ne),
        BinaryOp::And => return logic(true),
        BinaryOp::Or => return logic(false),
        BinaryOp::Add => zip(&a, &b, false, &add),
        BinaryOp::Sub => zip(&a, &b, false, &sub),
        BinaryOp::ElemAdd => zip(&a, &b, true, &add),
        BinaryOp::ElemSub => zip(&a, &b, true, &sub),
        BinaryOp::ElemMul => zip(&a, &b, true, &mul),
        BinaryOp::ElemDiv => zip(&a, &b, true, &div),
        BinaryOp::ElemPow => zip(&a, &b, true, &sym::pow),
        BinaryOp::Mul => product(&a, &b),
        BinaryOp::Div => match &b {
            ArrayExpr::Scalar(_) => zip(&a, &b, true, &div),
            _ => None,
        },
        BinaryOp::Pow => match (&a, &b) {
            (ArrayExpr::Scalar(x), ArrayExpr::Scalar(y)) => Some(ArrayExpr::Scalar(sym::pow(x.clone(), y.clone()))),
            _ => None,
        },
    };
    result.ok_or_else(|| {
        let help = match op {
            BinaryOp::Add | BinaryOp::Sub => "add and subtract values of the same size; `.+` adds a scalar to each element",
            BinaryOp::Mul => "multiply by scalars, a matrix by a vector or a matrix; `.*` multiplies element by element; `dot` and `cross` multiply vectors",
            BinaryOp::Div => "divide by a scalar; `./` divides element by element",
            _ => "`^` takes scalars; `.^` works element by element",
        };
        shape_error(symbol, &a, &b, span, help)
    })
}

/// `a * b`: a scalar times anything, a matrix times a vector or a matrix.
fn product(a: &ArrayExpr, b: &ArrayExpr) -> Option<ArrayExpr> {
    match (a, b) {
        (ArrayExpr::Scalar(_), _) | (_, ArrayExpr::Scalar(_)) => zip(a, b, true, &mul),
        _ => {
            let m = a.matrix()?;
            if let Some(v) = b.vector() {
                if m.iter().any(|r| r.len() != v.len()) {
                    return None;
                }
                return Some(ArrayExpr::from_vector(
                    m.iter().map(|row| sum(row.iter().zip(&v).map(|(x, y)| mul(x.clone(), y.clone())))).collect(),
                ));
            }
            let n = b.matrix()?;
            let cols = n.first()?.len();
            if m.iter().any(|r| r.len() != n.len()) {
                return None;
            }
            Some(ArrayExpr::from_matrix(
                m.iter()
                    .map(|row| {
                        (0..cols)
                            .map(|j| sum(row.iter().zip(&n).map(|(x, nrow)| mul(x.clone(), nrow[j].clone()))))
                            .collect()
                    })
                    .collect(),
            ))
        }
    }
}

fn transpose(m: &[Vec<Node>]) -> Vec<Vec<Node>> {
    let cols = m.first().map_or(0, Vec::len);
    (0..cols).map(|j| m.iter().map(|r| r[j].clone()).collect()).collect()
}

/// `A_axis(angle)` of the library's convention (`v_frame = A v_parent`).
fn axis_rotation(axis: usize, angle: &Node) -> Vec<Vec<Node>> {
    let (c, s) = (call(Func::Cos, angle.clone()), call(Func::Sin, angle.clone()));
    let (zero, one) = (constant(0.0), constant(1.0));
    let mut m = vec![vec![zero.clone(); 3]; 3];
    let (p, q) = ((axis + 1) % 3, (axis + 2) % 3);
    m[axis][axis] = one;
    m[p][p] = c.clone();
    m[p][q] = s.clone();
    m[q][p] = neg(s);
    m[q][q] = c;
    m
}

fn matmul(a: &[Vec<Node>], b: &[Vec<Node>]) -> Vec<Vec<Node>> {
    a.iter()
        .map(|row| {
            (0..b[0].len()).map(|j| sum(row.iter().zip(b).map(|(x, br)| mul(x.clone(), br[j].clone())))).collect()
        })
        .collect()
}

/// The functions equations may call besides the engine's functions of
/// numbers (`Func`, `Func2`: one table for parameters and equations, so a
/// new function of numbers is an entry there and its derivative).
const FORMS: &[&str] = &[
    "deg2rad",
    "rad2deg",
    "clamp",
    "ifelse",
    "der",
    "pre",
    "noEvent",
    "initial",
    "sample",
    "edge",
    "change",
    "norm",
    "dot",
    "cross",
    "transpose",
    "skew",
    "resolve1",
    "resolve2",
    "sum",
    "zeros",
    "ones",
    "fill",
    "length",
    "axes_rotations",
    "from_Q",
    "identity",
    "world_default_body_diameter",
    "world_default_joint_length",
    "world_default_joint_width",
    "world_default_body_color",
    "world_default_joint_color",
    "world_default_rod_color",
];

/// Every function equations may call.
pub fn function_names() -> Vec<&'static str> {
    Func::NAMES.iter().chain(Func2::NAMES).chain(FORMS).copied().collect()
}

fn function(callee: &Path, args: &[Expr], span: Span, names: &mut dyn Names) -> SResult {
    let fname = callee.last().name.as_str();
    let qualified = callee.parts.len() > 1;
    // `Library.world_default_body_diameter()` and similar helpers.
    let bare = if qualified && fname.starts_with("world_default_") {
        fname
    } else if qualified {
        ""
    } else {
        fname
    };
    let arity = |n: usize| -> Result<(), Diagnostic> {
        if args.len() == n {
            Ok(())
        } else {
            Err(Diagnostic::error(format!(
                "`{fname}` takes {n} argument{}, but {} were given",
                if n == 1 { "" } else { "s" },
                args.len()
            ))
            .primary(span, "wrong number of arguments"))
        }
    };
    let arg = |k: usize, names: &mut dyn Names| eval(&args[k], names);
    if let Some(f) = Func::from_name(bare) {
        arity(1)?;
        return Ok(arg(0, names)?.map(&|e| call(f, e.clone())));
    }
    if let Some(f) = Func2::from_name(bare) {
        arity(2)?;
        let (a, b) = (arg(0, names)?, arg(1, names)?);
        return zip(&a, &b, true, &|x, y| sym::call2(f, x, y))
            .ok_or_else(|| shape_error(fname, &a, &b, span, "give two values of the same size"));
    }
    let vector_of = |v: &ArrayExpr, k: usize, n: Option<usize>| -> Result<Vec<Node>, Diagnostic> {
        match v.vector() {
            Some(x) if n.is_none_or(|n| x.len() == n) => Ok(x),
            _ => Err(Diagnostic::error(format!(
                "`{fname}` takes {} as argument {}, but this is {}",
                n.map_or("a vector".to_string(), |n| format!("a vector of {n}")),
                k + 1,
                v.describe()
            ))
            .primary(args[k].span, "wrong size")),
        }
    };
    let matrix_of = |v: &ArrayExpr, k: usize| -> Result<Vec<Vec<Node>>, Diagnostic> {
        v.matrix().filter(|m| m.len() == 3 && m.iter().all(|r| r.len() == 3)).ok_or_else(|| {
            Diagnostic::error(format!(
                "`{fname}` takes a 3x3 matrix as argument {}, but this is {}",
                k + 1,
                v.describe()
            ))
            .primary(args[k].span, "not a 3x3 matrix")
        })
    };
    let count = |v: &ArrayExpr, k: usize| -> Result<usize, Diagnostic> {
        match v.constant() {
            Some(n) if n >= 0.0 && n.fract() == 0.0 && n <= 1e6 => Ok(n as usize),
            _ => Err(Diagnostic::error(format!("`{fname}` takes a whole number of elements"))
                .primary(args[k].span, "not a constant whole number")),
        }
    };
    match bare {
        "deg2rad" | "rad2deg" => {
            arity(1)?;
            let k = if bare == "deg2rad" { std::f64::consts::PI / 180.0 } else { 180.0 / std::f64::consts::PI };
            Ok(arg(0, names)?.map(&|e| mul(e.clone(), constant(k))))
        }
        "noEvent" => {
            arity(1)?;
            Ok(arg(0, names)?.map(&|e| sym::no_event(e.clone())))
        }
        "initial" => {
            arity(0)?;
            Ok(ArrayExpr::Scalar(Arc::new(E::Initial)))
        }
        "sample" => {
            arity(2)?;
            let mut constant = |k: usize, what: &str| -> Result<f64, Diagnostic> {
                match arg(k, names)?.constant() {
                    Some(x) if x.is_finite() => Ok(x),
                    Some(x) => Err(Diagnostic::error(format!("the {what} of `sample` is {x}, not a finite number"))
                        .primary(args[k].span, "not finite")
                        .help("give `sample(start, interval)` finite numbers (0/0 is NaN, 1/0 infinite)")),
                    None => Err(Diagnostic::error(format!("the {what} of `sample` must be a number or a parameter"))
                        .primary(args[k].span, "changes during the simulation")
                        .help("write `sample(start, interval)` with parameters: its instants are fixed")),
                }
            };
            let (start, interval) = (constant(0, "start")?, constant(1, "interval")?);
            if interval <= 0.0 {
                return Err(Diagnostic::error(format!("the interval of `sample` must be positive, not {interval}"))
                    .primary(args[1].span, "not positive"));
            }
            Ok(ArrayExpr::Scalar(Arc::new(E::Sample { start, interval })))
        }
        "pre" => {
            arity(1)?;
            let not_a_variable = || {
                Diagnostic::error("`pre` takes a variable, not an expression")
                    .primary(args[0].span, "not a variable")
                    .help("write `pre` of each variable: `pre(x) + pre(y)`, not `pre(x + y)`")
            };
            if !matches!(args[0].kind, ExprKind::Name(_) | ExprKind::Index { .. } | ExprKind::Field { .. }) {
                return Err(not_a_variable());
            }
            let v = arg(0, names)?;
            let mut all = Vec::new();
            v.clone().flatten(&mut all);
            if !all.iter().all(|e| matches!(**e, E::Var(_))) {
                return Err(Diagnostic::error("`pre` takes a variable, and this is a parameter or a constant")
                    .primary(args[0].span, "does not change")
                    .help("a parameter is the same before an event: write it without `pre`"));
            }
            Ok(v.map(&|e| match &**e {
                E::Var(name) => Arc::new(E::Pre(name.clone())),
                _ => e.clone(),
            }))
        }
        "edge" | "change" => {
            arity(1)?;
            let v = arg(0, names)?;
            let v = scalar(&v, args[0].span, &format!("`{fname}`"))?;
            Ok(ArrayExpr::Scalar(Arc::new(if fname == "edge" { E::Edge(v) } else { E::Change(v) })))
        }
        "der" => {
            arity(1)?;
            let v = arg(0, names)?;
            let mut all = Vec::new();
            v.clone().flatten(&mut all);
            if all.iter().all(|e| e.as_const().is_some()) {
                return Err(Diagnostic::error("`der` of a constant: parameters do not change, so this is always 0")
                    .primary(args[0].span, "a parameter or a constant")
                    .help("take `der` of a variable (`variable x::Real`), or write 0"));
            }
            Ok(v.map(&|e| match e.as_const() {
                Some(_) => constant(0.0),
                None => Arc::new(E::Der(e.clone())),
            }))
        }
        "ifelse" => {
            arity(3)?;
            let c = arg(0, names)?;
            let c = scalar(&c, args[0].span, "a condition")?;
            if let Some(x) = c.as_const() {
                return arg(if x != 0.0 { 1 } else { 2 }, names);
            }
            let (a, b) = (arg(1, names)?, arg(2, names)?);
            select(c, a, b, span)
        }
        "clamp" => {
            arity(3)?;
            let (x, lo, hi) = (arg(0, names)?, arg(1, names)?, arg(2, names)?);
            let lo = scalar(&lo, args[1].span, "`clamp`")?;
            let hi = scalar(&hi, args[2].span, "`clamp`")?;
            Ok(x.map(&|e| sym::call2(Func2::Min, sym::call2(Func2::Max, e.clone(), lo.clone()), hi.clone())))
        }
        "norm" => {
            arity(1)?;
            let v = vector_of(&arg(0, names)?, 0, None)?;
            Ok(ArrayExpr::Scalar(call(Func::Sqrt, sum(v.iter().map(|x| mul(x.clone(), x.clone()))))))
        }
        "sum" => {
            arity(1)?;
            let mut all = Vec::new();
            arg(0, names)?.flatten(&mut all);
            Ok(ArrayExpr::Scalar(sum(all)))
        }
        "length" => {
            arity(1)?;
            Ok(ArrayExpr::scalar(match arg(0, names)? {
                ArrayExpr::Array(items) => items.len() as f64,
                ArrayExpr::Scalar(_) => 1.0,
            }))
        }
        "dot" => {
            arity(2)?;
            let (a, b) = (arg(0, names)?, arg(1, names)?);
            let a = vector_of(&a, 0, None)?;
            let b = vector_of(&b, 1, Some(a.len()))?;
            Ok(ArrayExpr::Scalar(sum(a.into_iter().zip(b).map(|(x, y)| mul(x, y)))))
        }
        "cross" => {
            arity(2)?;
            let (a, b) = (arg(0, names)?, arg(1, names)?);
            let (a, b) = (vector_of(&a, 0, Some(3))?, vector_of(&b, 1, Some(3))?);
            let c = |i: usize, j: usize| sub(mul(a[i].clone(), b[j].clone()), mul(a[j].clone(), b[i].clone()));
            Ok(ArrayExpr::from_vector(vec![c(1, 2), c(2, 0), c(0, 1)]))
        }
        "skew" => {
            arity(1)?;
            let a = vector_of(&arg(0, names)?, 0, Some(3))?;
            let z = || constant(0.0);
            Ok(ArrayExpr::from_matrix(vec![
                vec![z(), neg(a[2].clone()), a[1].clone()],
                vec![a[2].clone(), z(), neg(a[0].clone())],
                vec![neg(a[1].clone()), a[0].clone(), z()],
            ]))
        }
        "transpose" => {
            arity(1)?;
            let v = arg(0, names)?;
            let m = v.matrix().ok_or_else(|| {
                Diagnostic::error(format!("`transpose` takes a matrix, but this is {}", v.describe()))
                    .primary(args[0].span, "not a matrix")
            })?;
            Ok(ArrayExpr::from_matrix(transpose(&m)))
        }
        "resolve1" | "resolve2" => {
            arity(2)?;
            let (r, v) = (arg(0, names)?, arg(1, names)?);
            let r = matrix_of(&r, 0)?;
            let v = ArrayExpr::from_vector(vector_of(&v, 1, Some(3))?);
            let m = if bare == "resolve1" { transpose(&r) } else { r };
            product(&ArrayExpr::from_matrix(m), &v)
                .ok_or_else(|| shape_error(fname, &ArrayExpr::scalar(0.0), &v, span, ""))
        }
        "zeros" | "ones" => {
            let value = if bare == "zeros" { 0.0 } else { 1.0 };
            fill(value, args, span, names, &count)
        }
        "fill" => {
            if args.is_empty() {
                return Err(Diagnostic::error("`fill` takes a value and sizes").primary(span, "no arguments"));
            }
            let x = arg(0, names)?;
            let x = scalar(&x, args[0].span, "`fill`")?;
            let mut value = ArrayExpr::Scalar(x);
            for k in (1..args.len()).rev() {
                let n = count(&arg(k, names)?, k)?;
                value = ArrayExpr::Array(vec![value; n]);
            }
            Ok(value)
        }
        "identity" => {
            arity(1)?;
            let n = count(&arg(0, names)?, 0)?;
            Ok(ArrayExpr::from_matrix(
                (0..n).map(|i| (0..n).map(|j| constant(if i == j { 1.0 } else { 0.0 })).collect()).collect(),
            ))
        }
        "axes_rotations" => {
            // R = A_k(phi3) A_j(phi2) A_i(phi1) for sequence [i, j, k].
            arity(2)?;
            let (seq, angles) = (arg(0, names)?, arg(1, names)?);
            let seq: Vec<usize> = vector_of(&seq, 0, Some(3))?
                .iter()
                .map(|e| match e.as_const() {
                    Some(x) if [1.0, 2.0, 3.0].contains(&x) => Ok(x as usize - 1),
                    _ => Err(Diagnostic::error("the sequence of `axes_rotations` is three constant axes 1, 2 or 3")
                        .primary(args[0].span, "not a constant sequence")),
                })
                .collect::<Result<_, _>>()?;
            let phi = vector_of(&angles, 1, Some(3))?;
            let r = matmul(
                &matmul(&axis_rotation(seq[2], &phi[2]), &axis_rotation(seq[1], &phi[1])),
                &axis_rotation(seq[0], &phi[0]),
            );
            Ok(ArrayExpr::from_matrix(r))
        }
        "from_Q" => {
            // R = (2 p0^2 - 1) I + 2 (p p' - p0 [p]x), Q = [p0, p1, p2, p3].
            arity(1)?;
            let q = vector_of(&arg(0, names)?, 0, Some(4))?;
            let two = |e: Node| mul(constant(2.0), e);
            let diag = sub(two(mul(q[0].clone(), q[0].clone())), constant(1.0));
            let p = &q[1..];
            let skew = |i: usize, j: usize| -> Node {
                // [p]x (i, j)
                match (i, j) {
                    (0, 1) => neg(p[2].clone()),
                    (0, 2) => p[1].clone(),
                    (1, 0) => p[2].clone(),
                    (1, 2) => neg(p[0].clone()),
                    (2, 0) => neg(p[1].clone()),
                    (2, 1) => p[0].clone(),
                    _ => constant(0.0),
                }
            };
            let r = (0..3)
                .map(|i| {
                    (0..3)
                        .map(|j| {
                            let outer = two(sub(mul(p[i].clone(), p[j].clone()), mul(q[0].clone(), skew(i, j))));
                            if i == j {
                                add(diag.clone(), outer)
                            } else {
                                outer
                            }
                        })
                        .collect()
                })
                .collect();
            Ok(ArrayExpr::from_matrix(r))
        }
        helper if helper.starts_with("world_default_") => {
            arity(0)?;
            let value = crate::semantics::eval::world_default(helper).ok_or_else(|| {
                Diagnostic::error(format!("unknown function `{fname}`")).primary(callee.span, "not a World default")
            })?;
            from_val(&value).ok_or_else(|| {
                Diagnostic::error(format!("`{fname}` is not a number")).primary(callee.span, "not a number")
            })
        }
        _ => {
            let mut d = Diagnostic::error(format!("unknown function `{}`", callee.text()))
                .primary(callee.span, "not a function equations can call");
            let all = function_names();
            if let Some(s) = did_you_mean(fname, all.iter().copied()) {
                d = d.help(s);
            }
            Err(d.note(format!("the functions are: {}", all.join(", "))))
        }
    }
}

fn fill(
    value: f64,
    args: &[Expr],
    span: Span,
    names: &mut dyn Names,
    count: &dyn Fn(&ArrayExpr, usize) -> Result<usize, Diagnostic>,
) -> SResult {
    if args.is_empty() {
        return Err(Diagnostic::error("give the size: `zeros(3)`").primary(span, "no size"));
    }
    let mut out = ArrayExpr::scalar(value);
    for k in (0..args.len()).rev() {
        let n = count(&eval(&args[k], names)?, k)?;
        out = ArrayExpr::Array(vec![out; n]);
    }
    Ok(out)
}

/// A road's height for `wheel.surface = ...`: an expression in the
/// world's `x` and `z`, with the component's parameters as numbers.
pub fn road(expr: &Expr, scope: &mut dyn crate::semantics::eval::Scope) -> Result<E, Diagnostic> {
    struct Road<'s> {
        scope: &'s mut dyn crate::semantics::eval::Scope,
    }
    impl Names for Road<'_> {
        fn reference(&mut self, expr: &Expr) -> Result<Option<ArrayExpr>, Diagnostic> {
            if let ExprKind::Name(path) = &expr.kind {
                if let [only] = &path.parts[..] {
                    if only.name == "x" || only.name == "z" {
                        return Ok(Some(ArrayExpr::Scalar(sym::var(only.name.clone()))));
                    }
                    if let Some(v) = self.scope.parameter(only)? {
                        return Ok(from_val(&v));
                    }
                }
            }
            Ok(None)
        }
        fn candidates(&self) -> Vec<String> {
            let mut names = self.scope.parameter_names();
            names.extend(["x".to_string(), "z".to_string()]);
            names
        }
    }
    let value = eval(expr, &mut Road { scope })?;
    let height = value.as_scalar().cloned().ok_or_else(|| {
        Diagnostic::error(format!("a road's height is one number at each (x, z), not {}", value.describe()))
            .primary(expr.span, "not a scalar")
    })?;
    multibody::math::surface::Surface::new(&height).map_err(|why| {
        Diagnostic::error("this formula cannot be a road's height")
            .primary(expr.span, why)
            .help("write the height as a formula of x and z, e.g. `wheel.surface = 0.1 * sin(x)`")
    })?;
    Ok(Arc::unwrap_or_clone(height))
}
