//! Equations' expressions as arrays of scalar engine expressions: names
//! become variables (`ctrl.x`, `body.frame_a.r_0[2]`) or constants
//! (parameters, loop indices), and vector and matrix operations
//! (`R * v`, `cross`, `resolve1`, `axes_rotations`, ...) are written out
//! element by element, so that the engine sees scalar equations only.

use crate::reports::diagnostics::{did_you_mean, Diagnostic};
use crate::semantics::eval::Val;
use crate::syntax::ast::{BinaryOp, Expr, ExprKind, Path, UnaryOp};
use crate::syntax::source::Span;
use multibody::{Cmp, Expr as E, Func, Func2};

/// A value of an equation's expression: a scalar, or an array of values
/// (a matrix is an array of rows).
#[derive(Clone, Debug, PartialEq)]
pub enum Sym {
    Scalar(E),
    Array(Vec<Sym>),
}

type SResult = Result<Sym, Diagnostic>;

/// What names in an equation stand for.
pub trait Names {
    /// The value of a reference (`x`, `frame_a.r_0`, `links[2].body.phi`),
    /// `None` if the name is unknown (the caller suggests names).
    fn reference(&mut self, expr: &Expr) -> Result<Option<Sym>, Diagnostic>;
    /// Names that could have been meant, for suggestions.
    fn candidates(&self) -> Vec<String>;
}

impl Sym {
    pub fn scalar(x: f64) -> Sym {
        Sym::Scalar(E::Const(x))
    }

    /// The sizes of the array (`[]` for a scalar), if it is rectangular.
    pub fn shape(&self) -> Option<Vec<usize>> {
        match self {
            Sym::Scalar(_) => Some(vec![]),
            Sym::Array(items) => {
                let first = items.first().map_or(Some(vec![]), Sym::shape)?;
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
    pub fn flatten(self, out: &mut Vec<E>) {
        match self {
            Sym::Scalar(e) => out.push(e),
            Sym::Array(items) => items.into_iter().for_each(|i| i.flatten(out)),
        }
    }

    fn as_scalar(&self) -> Option<&E> {
        match self {
            Sym::Scalar(e) => Some(e),
            _ => None,
        }
    }

    /// The constant value, if the expression is one.
    pub fn constant(&self) -> Option<f64> {
        match self {
            Sym::Scalar(E::Const(x)) => Some(*x),
            _ => None,
        }
    }

    fn map(&self, f: &dyn Fn(&E) -> E) -> Sym {
        match self {
            Sym::Scalar(e) => Sym::Scalar(f(e)),
            Sym::Array(items) => Sym::Array(items.iter().map(|i| i.map(f)).collect()),
        }
    }

    /// The rows of a matrix, each a list of scalars.
    fn matrix(&self) -> Option<Vec<Vec<E>>> {
        let Sym::Array(rows) = self else { return None };
        rows.iter()
            .map(|r| match r {
                Sym::Array(items) => items.iter().map(|i| i.as_scalar().cloned()).collect(),
                Sym::Scalar(_) => None,
            })
            .collect()
    }

    fn vector(&self) -> Option<Vec<E>> {
        match self {
            Sym::Array(items) => items.iter().map(|i| i.as_scalar().cloned()).collect(),
            Sym::Scalar(_) => None,
        }
    }

    fn from_vector(v: Vec<E>) -> Sym {
        Sym::Array(v.into_iter().map(Sym::Scalar).collect())
    }

    fn from_matrix(m: Vec<Vec<E>>) -> Sym {
        Sym::Array(m.into_iter().map(Sym::from_vector).collect())
    }
}

/// A parameter's value as a symbolic one (numbers and booleans).
pub fn from_val(v: &Val) -> Option<Sym> {
    match v {
        Val::Number(x) => Some(Sym::scalar(*x)),
        Val::Bool(b) => Some(Sym::scalar(if *b { 1.0 } else { 0.0 })),
        Val::Array(items) => items.iter().map(from_val).collect::<Option<Vec<_>>>().map(Sym::Array),
        _ => None,
    }
}

// Constant folding keeps equations of constants constant.
fn fold2(a: E, b: E, f: fn(f64, f64) -> f64, make: fn(Box<E>, Box<E>) -> E) -> E {
    match (&a, &b) {
        (E::Const(x), E::Const(y)) => E::Const(f(*x, *y)),
        _ => make(Box::new(a), Box::new(b)),
    }
}

fn add(a: E, b: E) -> E {
    match (&a, &b) {
        (E::Const(x), _) if *x == 0.0 => b,
        (_, E::Const(y)) if *y == 0.0 => a,
        _ => fold2(a, b, |x, y| x + y, E::Add),
    }
}

fn sub(a: E, b: E) -> E {
    match &b {
        E::Const(y) if *y == 0.0 => a,
        _ => fold2(a, b, |x, y| x - y, E::Sub),
    }
}

fn mul(a: E, b: E) -> E {
    match (&a, &b) {
        (E::Const(x), _) | (_, E::Const(x)) if *x == 0.0 => E::Const(0.0),
        (E::Const(x), _) if *x == 1.0 => b,
        (_, E::Const(y)) if *y == 1.0 => a,
        _ => fold2(a, b, |x, y| x * y, E::Mul),
    }
}

fn div(a: E, b: E) -> E {
    match &b {
        E::Const(y) if *y == 1.0 => a,
        _ => fold2(a, b, |x, y| x / y, E::Div),
    }
}

fn neg(a: E) -> E {
    match a {
        E::Const(x) => E::Const(-x),
        E::Neg(inner) => *inner,
        other => E::Neg(Box::new(other)),
    }
}

fn call(f: Func, a: E) -> E {
    match a {
        E::Const(x) => E::Const(f.apply(x)),
        other => E::Call(f, Box::new(other)),
    }
}

fn sum(terms: impl IntoIterator<Item = E>) -> E {
    terms.into_iter().fold(E::Const(0.0), add)
}

fn truth(x: bool) -> E {
    E::Const(if x { 1.0 } else { 0.0 })
}

/// Evaluates an equation's expression.
pub fn eval(expr: &Expr, names: &mut dyn Names) -> SResult {
    let span = expr.span;
    match &expr.kind {
        ExprKind::Number(x) => Ok(Sym::scalar(*x)),
        ExprKind::Bool(b) => Ok(Sym::Scalar(truth(*b))),
        ExprKind::Str(_) => Err(Diagnostic::error("a string cannot be part of an equation").primary(span, "a string")),
        ExprKind::Name(path) if path.parts.len() == 1 && path.parts[0].name == "time" => Ok(Sym::Scalar(E::Time)),
        ExprKind::Name(_) | ExprKind::Index { .. } | ExprKind::Field { .. } => reference(expr, names),
        ExprKind::Array(items) => Ok(Sym::Array(items.iter().map(|i| eval(i, names)).collect::<Result<_, _>>()?)),
        ExprKind::Call { callee, args } => function(callee, args, span, names),
        ExprKind::Unary { op, operand } => {
            let v = eval(operand, names)?;
            Ok(match op {
                UnaryOp::Plus => v,
                UnaryOp::Neg => v.map(&|e| neg(e.clone())),
                UnaryOp::Not => Sym::Scalar(scalar(&v, operand.span, "`!`").map(|e| match e {
                    E::Const(x) => truth(x == 0.0),
                    other => E::Not(Box::new(other)),
                })?),
            })
        }
        ExprKind::Binary { op, lhs, rhs } => {
            let (a, b) = (eval(lhs, names)?, eval(rhs, names)?);
            binary(*op, a, b, lhs.span, rhs.span, span)
        }
        ExprKind::Chain { first, rest } => {
            let mut value = eval(first, names)?;
            let mut left = first.span;
            for (op, rhs) in rest {
                let b = eval(rhs, names)?;
                value = binary(*op, value, b, left, rhs.span, left.to(rhs.span))?;
                left = left.to(rhs.span);
            }
            Ok(value)
        }
        ExprKind::If { condition, then, otherwise } => {
            let c = eval(condition, names)?;
            let c = scalar(&c, condition.span, "a condition")?;
            if let E::Const(x) = c {
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
fn select(c: E, a: Sym, b: Sym, span: Span) -> SResult {
    match (a, b) {
        (Sym::Scalar(a), Sym::Scalar(b)) => Ok(Sym::Scalar(E::if_else(c, a, b))),
        (Sym::Array(a), Sym::Array(b)) if a.len() == b.len() => {
            Ok(Sym::Array(a.into_iter().zip(b).map(|(x, y)| select(c.clone(), x, y, span)).collect::<Result<_, _>>()?))
        }
        (a, b) => Err(Diagnostic::error(format!(
            "the two branches of a condition must have the same size, but one is {} and the other {}",
            a.describe(),
            b.describe()
        ))
        .primary(span, "branches of different sizes")),
    }
}

/// The one scalar of a value, or an error naming `what` needs one.
fn scalar(v: &Sym, span: Span, what: &str) -> Result<E, Diagnostic> {
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
        return Ok(Sym::scalar(x));
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

fn shape_error(op: &str, a: &Sym, b: &Sym, span: Span, help: &str) -> Diagnostic {
    Diagnostic::error(format!("cannot apply `{op}` to {} and {}", a.describe(), b.describe()))
        .primary(span, "sizes do not fit")
        .help(help.to_string())
}

/// Element by element, or a scalar with every element when `broadcast`.
fn zip(a: &Sym, b: &Sym, broadcast: bool, f: &dyn Fn(E, E) -> E) -> Option<Sym> {
    match (a, b) {
        (Sym::Scalar(x), Sym::Scalar(y)) => Some(Sym::Scalar(f(x.clone(), y.clone()))),
        (Sym::Array(xs), Sym::Array(ys)) if xs.len() == ys.len() => {
            Some(Sym::Array(xs.iter().zip(ys).map(|(x, y)| zip(x, y, broadcast, f)).collect::<Option<_>>()?))
        }
        (Sym::Scalar(_), Sym::Array(ys)) if broadcast => {
            Some(Sym::Array(ys.iter().map(|y| zip(a, y, broadcast, f)).collect::<Option<_>>()?))
        }
        (Sym::Array(xs), Sym::Scalar(_)) if broadcast => {
            Some(Sym::Array(xs.iter().map(|x| zip(x, b, broadcast, f)).collect::<Option<_>>()?))
        }
        _ => None,
    }
}

fn binary(op: BinaryOp, a: Sym, b: Sym, lspan: Span, rspan: Span, span: Span) -> SResult {
    let _ = (lspan, rspan);
    let symbol = op.symbol();
    let compare = |c: Cmp| -> SResult {
        let (x, y) = (scalar(&a, lspan, &format!("`{symbol}`"))?, scalar(&b, rspan, &format!("`{symbol}`"))?);
        Ok(Sym::Scalar(match (&x, &y) {
            (E::Const(p), E::Const(q)) => E::Const(c.apply(*p, *q)),
            _ => E::compare(c, x, y),
        }))
    };
    let logic = |and: bool| -> SResult {
        let (x, y) = (scalar(&a, lspan, &format!("`{symbol}`"))?, scalar(&b, rspan, &format!("`{symbol}`"))?);
        Ok(Sym::Scalar(match (&x, &y) {
            (E::Const(p), E::Const(q)) => truth(if and { *p != 0.0 && *q != 0.0 } else { *p != 0.0 || *q != 0.0 }),
            _ if and => E::And(Box::new(x), Box::new(y)),
            _ => E::Or(Box::new(x), Box::new(y)),
        }))
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
        BinaryOp::ElemPow => zip(&a, &b, true, &|x, y| fold2(x, y, f64::powf, E::Pow)),
        BinaryOp::Mul => product(&a, &b),
        BinaryOp::Div => match &b {
            Sym::Scalar(_) => zip(&a, &b, true, &div),
            _ => None,
        },
        BinaryOp::Pow => match (&a, &b) {
            (Sym::Scalar(x), Sym::Scalar(y)) => Some(Sym::Scalar(fold2(x.clone(), y.clone(), f64::powf, E::Pow))),
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
fn product(a: &Sym, b: &Sym) -> Option<Sym> {
    match (a, b) {
        (Sym::Scalar(_), _) | (_, Sym::Scalar(_)) => zip(a, b, true, &mul),
        _ => {
            let m = a.matrix()?;
            if let Some(v) = b.vector() {
                if m.iter().any(|r| r.len() != v.len()) {
                    return None;
                }
                return Some(Sym::from_vector(
                    m.iter().map(|row| sum(row.iter().zip(&v).map(|(x, y)| mul(x.clone(), y.clone())))).collect(),
                ));
            }
            let n = b.matrix()?;
            let cols = n.first()?.len();
            if m.iter().any(|r| r.len() != n.len()) {
                return None;
            }
            Some(Sym::from_matrix(
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

fn transpose(m: &[Vec<E>]) -> Vec<Vec<E>> {
    let cols = m.first().map_or(0, Vec::len);
    (0..cols).map(|j| m.iter().map(|r| r[j].clone()).collect()).collect()
}

/// `A_axis(angle)` of the library's convention (`v_frame = A v_parent`).
fn axis_rotation(axis: usize, angle: &E) -> Vec<Vec<E>> {
    let (c, s) = (call(Func::Cos, angle.clone()), call(Func::Sin, angle.clone()));
    let (zero, one) = (E::Const(0.0), E::Const(1.0));
    let mut m = vec![vec![zero.clone(); 3]; 3];
    let (p, q) = ((axis + 1) % 3, (axis + 2) % 3);
    m[axis][axis] = one;
    m[p][p] = c.clone();
    m[p][q] = s.clone();
    m[q][p] = neg(s);
    m[q][q] = c;
    m
}

fn matmul(a: &[Vec<E>], b: &[Vec<E>]) -> Vec<Vec<E>> {
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
        return zip(&a, &b, true, &|x, y| match (&x, &y) {
            (E::Const(p), E::Const(q)) => E::Const(f.apply(*p, *q)),
            _ => E::call2(f, x, y),
        })
        .ok_or_else(|| shape_error(fname, &a, &b, span, "give two values of the same size"));
    }
    let vector_of = |v: &Sym, k: usize, n: Option<usize>| -> Result<Vec<E>, Diagnostic> {
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
    let matrix_of = |v: &Sym, k: usize| -> Result<Vec<Vec<E>>, Diagnostic> {
        v.matrix().filter(|m| m.len() == 3 && m.iter().all(|r| r.len() == 3)).ok_or_else(|| {
            Diagnostic::error(format!(
                "`{fname}` takes a 3x3 matrix as argument {}, but this is {}",
                k + 1,
                v.describe()
            ))
            .primary(args[k].span, "not a 3x3 matrix")
        })
    };
    let count = |v: &Sym, k: usize| -> Result<usize, Diagnostic> {
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
            Ok(arg(0, names)?.map(&|e| mul(e.clone(), E::Const(k))))
        }
        "noEvent" => {
            arity(1)?;
            Ok(arg(0, names)?.map(&|e| match e {
                E::Const(_) => e.clone(),
                other => E::NoEvent(Box::new(other.clone())),
            }))
        }
        "initial" => {
            arity(0)?;
            Ok(Sym::Scalar(E::Initial))
        }
        "sample" => {
            arity(2)?;
            let mut constant = |k: usize, what: &str| -> Result<f64, Diagnostic> {
                match arg(k, names)? {
                    Sym::Scalar(E::Const(x)) if x.is_finite() => Ok(x),
                    _ => Err(Diagnostic::error(format!("the {what} of `sample` must be a number or a parameter"))
                        .primary(args[k].span, "changes during the simulation")
                        .help("write `sample(start, interval)` with parameters: its instants are fixed")),
                }
            };
            let (start, interval) = (constant(0, "start")?, constant(1, "interval")?);
            if interval <= 0.0 {
                return Err(Diagnostic::error(format!("the interval of `sample` must be positive, not {interval}"))
                    .primary(args[1].span, "not positive"));
            }
            Ok(Sym::Scalar(E::Sample { start, interval }))
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
            if !all.iter().all(|e| matches!(e, E::Var(_))) {
                return Err(Diagnostic::error("`pre` takes a variable, and this is a parameter or a constant")
                    .primary(args[0].span, "does not change")
                    .help("a parameter is the same before an event: write it without `pre`"));
            }
            Ok(v.map(&|e| match e {
                E::Var(name) => E::Pre(name.clone()),
                other => other.clone(),
            }))
        }
        "edge" | "change" => {
            arity(1)?;
            let v = arg(0, names)?;
            let v = scalar(&v, args[0].span, &format!("`{fname}`"))?;
            Ok(Sym::Scalar(if fname == "edge" { E::Edge(Box::new(v)) } else { E::Change(Box::new(v)) }))
        }
        "der" => {
            arity(1)?;
            let v = arg(0, names)?;
            let mut all = Vec::new();
            v.clone().flatten(&mut all);
            if all.iter().all(|e| matches!(e, E::Const(_))) {
                return Err(Diagnostic::error("`der` of a constant: parameters do not change, so this is always 0")
                    .primary(args[0].span, "a parameter or a constant")
                    .help("take `der` of a variable (`variable x::Real`), or write 0"));
            }
            Ok(v.map(&|e| match e {
                E::Const(_) => E::Const(0.0),
                other => E::der(other.clone()),
            }))
        }
        "ifelse" => {
            arity(3)?;
            let c = arg(0, names)?;
            let c = scalar(&c, args[0].span, "a condition")?;
            if let E::Const(x) = c {
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
            Ok(x.map(&|e| E::call2(Func2::Min, E::call2(Func2::Max, e.clone(), lo.clone()), hi.clone())))
        }
        "norm" => {
            arity(1)?;
            let v = vector_of(&arg(0, names)?, 0, None)?;
            Ok(Sym::Scalar(call(Func::Sqrt, sum(v.iter().map(|x| mul(x.clone(), x.clone()))))))
        }
        "sum" => {
            arity(1)?;
            let mut all = Vec::new();
            arg(0, names)?.flatten(&mut all);
            Ok(Sym::Scalar(sum(all)))
        }
        "length" => {
            arity(1)?;
            Ok(Sym::scalar(match arg(0, names)? {
                Sym::Array(items) => items.len() as f64,
                Sym::Scalar(_) => 1.0,
            }))
        }
        "dot" => {
            arity(2)?;
            let (a, b) = (arg(0, names)?, arg(1, names)?);
            let a = vector_of(&a, 0, None)?;
            let b = vector_of(&b, 1, Some(a.len()))?;
            Ok(Sym::Scalar(sum(a.into_iter().zip(b).map(|(x, y)| mul(x, y)))))
        }
        "cross" => {
            arity(2)?;
            let (a, b) = (arg(0, names)?, arg(1, names)?);
            let (a, b) = (vector_of(&a, 0, Some(3))?, vector_of(&b, 1, Some(3))?);
            let c = |i: usize, j: usize| sub(mul(a[i].clone(), b[j].clone()), mul(a[j].clone(), b[i].clone()));
            Ok(Sym::from_vector(vec![c(1, 2), c(2, 0), c(0, 1)]))
        }
        "skew" => {
            arity(1)?;
            let a = vector_of(&arg(0, names)?, 0, Some(3))?;
            let z = || E::Const(0.0);
            Ok(Sym::from_matrix(vec![
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
            Ok(Sym::from_matrix(transpose(&m)))
        }
        "resolve1" | "resolve2" => {
            arity(2)?;
            let (r, v) = (arg(0, names)?, arg(1, names)?);
            let r = matrix_of(&r, 0)?;
            let v = Sym::from_vector(vector_of(&v, 1, Some(3))?);
            let m = if bare == "resolve1" { transpose(&r) } else { r };
            product(&Sym::from_matrix(m), &v)
                .ok_or_else(|| shape_error(fname, &Sym::Scalar(E::Const(0.0)), &v, span, ""))
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
            let mut value = Sym::Scalar(x);
            for k in (1..args.len()).rev() {
                let n = count(&arg(k, names)?, k)?;
                value = Sym::Array(vec![value; n]);
            }
            Ok(value)
        }
        "identity" => {
            arity(1)?;
            let n = count(&arg(0, names)?, 0)?;
            Ok(Sym::from_matrix(
                (0..n).map(|i| (0..n).map(|j| E::Const(if i == j { 1.0 } else { 0.0 })).collect()).collect(),
            ))
        }
        "axes_rotations" => {
            // R = A_k(phi3) A_j(phi2) A_i(phi1) for sequence [i, j, k].
            arity(2)?;
            let (seq, angles) = (arg(0, names)?, arg(1, names)?);
            let seq: Vec<usize> = vector_of(&seq, 0, Some(3))?
                .iter()
                .map(|e| match e {
                    E::Const(x) if [1.0, 2.0, 3.0].contains(x) => Ok(*x as usize - 1),
                    _ => Err(Diagnostic::error("the sequence of `axes_rotations` is three constant axes 1, 2 or 3")
                        .primary(args[0].span, "not a constant sequence")),
                })
                .collect::<Result<_, _>>()?;
            let phi = vector_of(&angles, 1, Some(3))?;
            let r = matmul(
                &matmul(&axis_rotation(seq[2], &phi[2]), &axis_rotation(seq[1], &phi[1])),
                &axis_rotation(seq[0], &phi[0]),
            );
            Ok(Sym::from_matrix(r))
        }
        "from_Q" => {
            // R = (2 p0^2 - 1) I + 2 (p p' - p0 [p]x), Q = [p0, p1, p2, p3].
            arity(1)?;
            let q = vector_of(&arg(0, names)?, 0, Some(4))?;
            let two = |e: E| mul(E::Const(2.0), e);
            let diag = sub(two(mul(q[0].clone(), q[0].clone())), E::Const(1.0));
            let p = &q[1..];
            let skew = |i: usize, j: usize| -> E {
                // [p]x (i, j)
                match (i, j) {
                    (0, 1) => neg(p[2].clone()),
                    (0, 2) => p[1].clone(),
                    (1, 0) => p[2].clone(),
                    (1, 2) => neg(p[0].clone()),
                    (2, 0) => neg(p[1].clone()),
                    (2, 1) => p[0].clone(),
                    _ => E::Const(0.0),
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
            Ok(Sym::from_matrix(r))
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
    count: &dyn Fn(&Sym, usize) -> Result<usize, Diagnostic>,
) -> SResult {
    if args.is_empty() {
        return Err(Diagnostic::error("give the size: `zeros(3)`").primary(span, "no size"));
    }
    let mut out = Sym::scalar(value);
    for k in (0..args.len()).rev() {
        let n = count(&eval(&args[k], names)?, k)?;
        out = Sym::Array(vec![out; n]);
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
        fn reference(&mut self, expr: &Expr) -> Result<Option<Sym>, Diagnostic> {
            if let ExprKind::Name(path) = &expr.kind {
                if let [only] = &path.parts[..] {
                    if only.name == "x" || only.name == "z" {
                        return Ok(Some(Sym::Scalar(E::Var(only.name.clone()))));
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
    Ok(height)
}
