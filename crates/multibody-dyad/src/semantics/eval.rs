//! Values and the evaluation of constant expressions: numbers, booleans,
//! arrays, enumeration values, and references to parameters.

use crate::reports::diagnostics::{did_you_mean, Diagnostic};
use crate::syntax::ast::{BinaryOp, Expr, ExprKind, Ident, Path, UnaryOp};
use crate::syntax::source::Span;
use multibody::math::expr::{Func, Func2};

/// A value of an expression.
#[derive(Clone, Debug, PartialEq)]
pub enum Val {
    Number(f64),
    Bool(bool),
    Str(String),
    /// `OrientationState.Quaternion()`, kept as `OrientationState.Quaternion`.
    Enum(String),
    Array(Vec<Val>),
    /// `missing`: no value (`r_0(initial = missing)`).
    Missing,
}

impl Val {
    pub fn describe(&self) -> String {
        match self {
            Val::Number(_) => "a number".into(),
            Val::Bool(_) => "a boolean".into(),
            Val::Str(_) => "a string".into(),
            Val::Enum(name) => format!("the enumeration value {name}"),
            Val::Missing => "`missing`".into(),
            Val::Array(items) => match self.shape() {
                Some(dims) if dims.len() == 1 => format!("an array of {} numbers", dims[0]),
                Some(dims) => format!("a {} array", dims.iter().map(usize::to_string).collect::<Vec<_>>().join("x")),
                None if items.is_empty() => "an empty array".into(),
                None => "an array".into(),
            },
        }
    }

    /// How deeply arrays nest in the value (0 for a number).
    pub fn depth(&self) -> usize {
        match self {
            Val::Array(items) => 1 + items.iter().map(Val::depth).max().unwrap_or(0),
            _ => 0,
        }
    }

    /// How many values (numbers, ...) the value holds.
    pub fn size(&self) -> usize {
        match self {
            Val::Array(items) => items.iter().map(Val::size).sum(),
            _ => 1,
        }
    }

    /// The sizes of a rectangular array of numbers (`[]` for a number).
    pub fn shape(&self) -> Option<Vec<usize>> {
        match self {
            Val::Number(_) => Some(vec![]),
            Val::Array(items) => {
                let first = items.first()?.shape()?;
                if items.iter().skip(1).all(|i| i.shape().as_ref() == Some(&first)) {
                    Some(std::iter::once(items.len()).chain(first).collect())
                } else {
                    None
                }
            }
            _ => None,
        }
    }

    /// The engine's value: numbers, booleans, strings, vectors, matrices, enumerations.
    pub fn to_engine(&self) -> Option<multibody::Value> {
        use multibody::Value;
        match self {
            Val::Number(x) => Some(Value::Number(*x)),
            Val::Bool(b) => Some(Value::Bool(*b)),
            Val::Enum(e) => Some(Value::Enum(e.clone())),
            Val::Str(text) => Some(Value::Str(text.clone())),
            Val::Array(items) => match self.shape()?.len() {
                1 => Some(Value::Array(numbers(items)?)),
                2 => {
                    let rows = items.iter().map(|r| if let Val::Array(r) = r { numbers(r) } else { None });
                    Some(Value::Matrix(rows.collect::<Option<_>>()?))
                }
                _ => None,
            },
            Val::Missing => None,
        }
    }
}

fn numbers(items: &[Val]) -> Option<Vec<f64>> {
    items.iter().map(|v| if let Val::Number(x) = v { Some(*x) } else { None }).collect()
}

/// Where names in an expression get their values.
pub trait Scope {
    /// The value of the parameter `name`, or `None` if there is none.
    fn parameter(&mut self, name: &Ident) -> Result<Option<Val>, Diagnostic>;
    /// Every parameter name, for suggestions.
    fn parameter_names(&self) -> Vec<String>;
    /// Whether `name` is a sub-component or connector (not a value).
    fn is_component(&self, name: &str) -> bool;
    /// How many times a parameter has been read so far: a value whose
    /// evaluation changes the count is computed from parameters.
    fn reads(&self) -> usize {
        0
    }
}

/// The functions parameter values may call: the engine's functions of
/// numbers (one table for parameters and equations: a new function is an
/// entry there) and those of arrays.
fn function_names() -> Vec<&'static str> {
    Func::NAMES.iter().chain(Func2::NAMES).chain(&["deg2rad", "rad2deg", "norm"]).copied().collect()
}

/// Arrays may nest this deep and hold this many numbers in all: parameters
/// built from parameters could otherwise grow without bound.
const MAX_ARRAY_DEPTH: usize = 16;
const MAX_ARRAY_SIZE: usize = 1_000_000;

type EResult = Result<Val, Diagnostic>;

/// Evaluates `expr` with the parameters of `scope`.
pub fn eval(expr: &Expr, scope: &mut dyn Scope) -> EResult {
    let value = match &expr.kind {
        ExprKind::Number(x) => Val::Number(*x),
        ExprKind::Bool(b) => Val::Bool(*b),
        ExprKind::Str(s) => Val::Str(s.clone()),
        ExprKind::Name(path) => name(path, scope)?,
        ExprKind::Call { callee, args } => call(callee, args, expr.span, scope)?,
        ExprKind::Array(items) => array(items, expr.span, scope)?,
        ExprKind::Index { base, indices } => index(base, indices, scope)?,
        ExprKind::Unary { op, operand } => {
            let v = eval(operand, scope)?;
            match op {
                UnaryOp::Plus => numeric(v, operand.span, "`+`")?,
                UnaryOp::Neg => map_numbers(&numeric(v, operand.span, "`-`")?, &|x| -x),
                UnaryOp::Not => Val::Bool(!truth(&v, operand.span)?),
            }
        }
        ExprKind::Binary { op, lhs, rhs } if is_logical(*op) => {
            let (a, b) = (eval(lhs, scope)?, eval(rhs, scope)?);
            logical(*op, &a, &b, lhs.span, rhs.span)?
        }
        ExprKind::Binary { op, lhs, rhs } => {
            let (a, b) = (eval(lhs, scope)?, eval(rhs, scope)?);
            binary(*op, a, b, lhs.span, rhs.span, expr.span).map_err(|d| naming_the_divisor(d, rhs))?
        }
        ExprKind::If { condition, then, otherwise } => {
            let c = eval(condition, scope)?;
            eval(if truth(&c, condition.span)? { then } else { otherwise }, scope)?
        }
        ExprKind::Field { .. } => {
            return Err(Diagnostic::error("a value of a sub-component cannot be read here")
                .primary(expr.span, "not a parameter")
                .help("only parameters can be used in parameter values; declare a parameter and pass it to both"))
        }
        ExprKind::Range { .. } => {
            return Err(Diagnostic::error("a range is not a value here")
                .primary(expr.span, "a range")
                .help("ranges go in `for i in 1:N` and in arrays of components"))
        }
        ExprKind::Chain { first, rest } => {
            let (mut value, mut span) = (eval(first, scope)?, first.span);
            for (op, rhs) in rest {
                let b = eval(rhs, scope)?;
                let whole = span.to(rhs.span);
                let result = binary(*op, value, b, span, rhs.span, whole).map_err(|d| naming_the_divisor(d, rhs))?;
                value = finite(result, whole)?;
                span = whole;
            }
            value
        }
        ExprKind::Unsupported(what) => {
            return Err(Diagnostic::error(format!("{what} not supported yet"))
                .primary(expr.span, "not supported yet")
                .help(
                "parameter values are constants built from numbers, arrays, `+ - * / ^` and functions such as `sqrt`",
            ))
        }
    };
    finite(value, expr.span)
}

/// An array literal, within the size limits.
fn array(items: &[Expr], span: Span, scope: &mut dyn Scope) -> EResult {
    let mut values = Vec::with_capacity(items.len());
    let (mut depth, mut size) = (1, 0);
    for item in items {
        let value = eval(item, scope)?;
        depth = depth.max(1 + value.depth());
        size += value.size();
        if depth > MAX_ARRAY_DEPTH || size > MAX_ARRAY_SIZE {
            return Err(Diagnostic::error("this array is too large")
                .primary(span, "too large")
                .note(format!("arrays hold at most {MAX_ARRAY_SIZE} numbers, nested at most {MAX_ARRAY_DEPTH} deep")));
        }
        values.push(value);
    }
    Ok(Val::Array(values))
}

fn finite(value: Val, span: Span) -> EResult {
    fn all_finite(v: &Val) -> bool {
        match v {
            Val::Number(x) => x.is_finite(),
            Val::Array(items) => items.iter().all(all_finite),
            _ => true,
        }
    }
    if all_finite(&value) {
        Ok(value)
    } else {
        Err(Diagnostic::error("this expression does not give a finite number")
            .primary(span, "infinite or not a number")
            .help("check for overflow, or functions outside their domain (`sqrt` of a negative number, `log` of 0)"))
    }
}

fn name(path: &Path, scope: &mut dyn Scope) -> EResult {
    let first = &path.parts[0];
    if path.parts.len() == 1 {
        if let Some(v) = scope.parameter(first)? {
            return Ok(v);
        }
        return match first.name.as_str() {
            "pi" | "π" => Ok(Val::Number(std::f64::consts::PI)),
            "missing" => Ok(Val::Missing),
            "time" => Err(Diagnostic::error("`time` cannot be used here")
                .primary(first.span, "varies during the simulation")
                .help("parameter values and start values are constants")),
            _ if scope.is_component(&first.name) => Err(Diagnostic::error(format!(
                "`{}` is not a constant: it is a component, a connector or a variable",
                first.name
            ))
            .primary(first.span, "not a constant")
            .help("parameter values and start values are computed from parameters")
            .note(
                "a parameter with only a guess is a variable that the initialization decides: it can be used in \
                 equations, and passed on by name to a component's parameter (`c = c`), not in a formula there",
            )),
            _ => {
                let names = scope.parameter_names();
                let mut d = Diagnostic::error(format!("unknown name `{}`", first.name))
                    .primary(first.span, "not a parameter of this component");
                if let Some(s) = did_you_mean(&first.name, names.iter().map(String::as_str).chain(["pi"])) {
                    d = d.help(s);
                }
                d = if names.is_empty() {
                    d.note("this component declares no parameters; declare one with `parameter name::Real = value`")
                } else {
                    d.note(format!("the parameters here are: {}", names.join(", ")))
                };
                Err(d)
            }
        };
    }
    if scope.parameter(first)?.is_some() {
        return Err(Diagnostic::error(format!("the parameter `{}` has no fields", first.name))
            .primary(path.span, "not a value")
            .help(format!("use `{}` itself, or index it: `{}[1]`", first.name, first.name)));
    }
    if scope.is_component(&first.name) {
        return Err(Diagnostic::error(format!("`{}` is a value of a sub-component", path.text()))
            .primary(path.span, "cannot be read here")
            .help(
                "only parameters of this component can be used in expressions; declare a parameter and pass it to both",
            ));
    }
    Ok(enum_value(path))
}

/// `MultibodyComponents.OrientationState.Quaternion` -> `OrientationState.Quaternion`.
fn enum_value(path: &Path) -> Val {
    let n = path.parts.len();
    Val::Enum(path.parts[n.saturating_sub(2)..].iter().map(|p| p.name.as_str()).collect::<Vec<_>>().join("."))
}

/// The value of a World default by its helper's name
/// (`world_default_joint_color`), from the World's defaults.
pub fn world_default(helper: &str) -> Option<Val> {
    let name = helper.strip_prefix("world_")?;
    let world = multibody::components::world::WorldSettings::default();
    match world.scaled(name, 1.0) {
        multibody::Value::Number(x) if multibody::components::world::SPEC.param(name).is_some() => Some(Val::Number(x)),
        multibody::Value::Array(v) => Some(Val::Array(v.into_iter().map(Val::Number).collect())),
        multibody::Value::Bool(b) => Some(Val::Bool(b)),
        _ => None,
    }
}

/// Whether a value counts as true: a boolean, or a number other than 0.
fn truth(v: &Val, span: Span) -> Result<bool, Diagnostic> {
    match v {
        Val::Bool(b) => Ok(*b),
        Val::Number(x) => Ok(*x != 0.0),
        other => Err(Diagnostic::error(format!("a condition must be true or false, but this is {}", other.describe()))
            .primary(span, "not a condition")),
    }
}

fn is_logical(op: BinaryOp) -> bool {
    matches!(
        op,
        BinaryOp::Lt
            | BinaryOp::Le
            | BinaryOp::Gt
            | BinaryOp::Ge
            | BinaryOp::Eq
            | BinaryOp::Ne
            | BinaryOp::And
            | BinaryOp::Or
    )
}

/// Comparisons and `and`/`or`; enumeration values compare by their case.
fn logical(op: BinaryOp, a: &Val, b: &Val, lspan: Span, rspan: Span) -> EResult {
    let case = |v: &Val| match v {
        Val::Enum(e) => Some(e.rsplit('.').next().unwrap_or(e).to_string()),
        _ => None,
    };
    Ok(Val::Bool(match op {
        BinaryOp::And => truth(a, lspan)? && truth(b, rspan)?,
        BinaryOp::Or => truth(a, lspan)? || truth(b, rspan)?,
        BinaryOp::Eq | BinaryOp::Ne if case(a).is_some() || case(b).is_some() => {
            (case(a) == case(b)) == (op == BinaryOp::Eq)
        }
        BinaryOp::Eq | BinaryOp::Ne if matches!((a, b), (Val::Bool(_), Val::Bool(_))) => {
            (a == b) == (op == BinaryOp::Eq)
        }
        _ => {
            let number = |v: &Val, span: Span| match v {
                Val::Number(x) => Ok(*x),
                other => Err(Diagnostic::error(format!(
                    "`{}` compares numbers, but this is {}",
                    op.symbol(),
                    other.describe()
                ))
                .primary(span, "not a number")),
            };
            let (x, y) = (number(a, lspan)?, number(b, rspan)?);
            match op {
                BinaryOp::Lt => x < y,
                BinaryOp::Le => x <= y,
                BinaryOp::Gt => x > y,
                BinaryOp::Ge => x >= y,
                BinaryOp::Eq => x == y,
                _ => x != y,
            }
        }
    }))
}

fn call(callee: &Path, args: &[Expr], span: Span, scope: &mut dyn Scope) -> EResult {
    let fname = callee.last().name.as_str();
    if fname.starts_with("world_default_") && args.is_empty() {
        if let Some(v) = world_default(fname) {
            return Ok(v);
        }
    }
    if fname == "ifelse" && callee.parts.len() == 1 && args.len() == 3 {
        let c = eval(&args[0], scope)?;
        return eval(&args[if truth(&c, args[0].span)? { 1 } else { 2 }], scope);
    }
    if callee.parts.len() > 1 {
        // An enumeration value: `OrientationState.Quaternion()`.
        if !args.is_empty() {
            return Err(unsupported_call(callee, span, "enumeration values with fields are"));
        }
        return name(callee, scope);
    }
    let fname = callee.parts[0].name.as_str();
    let (one, two) = (Func::from_name(fname), Func2::from_name(fname));
    let arity = match (one, two, fname) {
        (Some(_), ..) | (_, _, "deg2rad" | "rad2deg" | "norm") => 1,
        (_, Some(_), _) => 2,
        _ => {
            let all = function_names();
            let mut d =
                Diagnostic::error(format!("unknown function `{fname}`")).primary(callee.span, "not a known function");
            if let Some(s) = did_you_mean(fname, all.iter().copied()) {
                d = d.help(s);
            }
            return Err(d.note(format!("the functions are: {}", all.join(", "))));
        }
    };
    if args.len() != arity {
        return Err(Diagnostic::error(format!(
            "`{fname}` takes {arity} argument{}, but {} were given",
            if arity == 1 { "" } else { "s" },
            args.len()
        ))
        .primary(span, "wrong number of arguments"));
    }
    let values: Vec<Val> = args.iter().map(|a| eval(a, scope)).collect::<Result<_, _>>()?;
    if fname == "norm" {
        return match &values[0] {
            Val::Array(items) if items.iter().all(|v| matches!(v, Val::Number(_))) && !items.is_empty() => {
                Ok(Val::Number(numbers(items).unwrap_or_default().iter().map(|x| x * x).sum::<f64>().sqrt()))
            }
            other => Err(wrong_argument(fname, "a vector of numbers", other, args[0].span)),
        };
    }
    if let ("deg2rad" | "rad2deg", Val::Array(_)) = (fname, &values[0]) {
        // Angles convert element by element: `deg2rad([90, 45])`.
        let k = if fname == "deg2rad" { std::f64::consts::PI / 180.0 } else { 180.0 / std::f64::consts::PI };
        fn scale(v: &Val, k: f64) -> Option<Val> {
            match v {
                Val::Number(x) => Some(Val::Number(x * k)),
                Val::Array(items) => items.iter().map(|i| scale(i, k)).collect::<Option<_>>().map(Val::Array),
                _ => None,
            }
        }
        return scale(&values[0], k).ok_or_else(|| wrong_argument(fname, "numbers", &values[0], args[0].span));
    }
    let mut xs = Vec::with_capacity(values.len());
    for (v, a) in values.iter().zip(args) {
        match v {
            Val::Number(x) => xs.push(*x),
            other => return Err(wrong_argument(fname, "a number", other, a.span)),
        }
    }
    let x = xs[0];
    let y = match (one, two) {
        (Some(f), _) => {
            if let Some(what) = f.outside_domain(x) {
                return Err(Diagnostic::error(format!("`{fname}` of {x} is not defined"))
                    .primary(span, format!("the argument must be {what}")));
            }
            f.apply(x)
        }
        (_, Some(f)) => f.apply(x, xs[1]),
        _ if fname == "deg2rad" => x.to_radians(),
        _ => x.to_degrees(),
    };
    Ok(Val::Number(y))
}

fn unsupported_call(callee: &Path, span: Span, what: &str) -> Diagnostic {
    Diagnostic::error(format!("{what} not supported yet")).primary(span, format!("`{}(...)`", callee.text()))
}

fn wrong_argument(fname: &str, expected: &str, got: &Val, span: Span) -> Diagnostic {
    Diagnostic::error(format!("`{fname}` takes {expected}, but this is {}", got.describe()))
        .primary(span, format!("expected {expected}"))
}

fn index(base: &Expr, indices: &[Expr], scope: &mut dyn Scope) -> EResult {
    let mut value = eval(base, scope)?;
    for i in indices {
        let Val::Array(items) = value else {
            return Err(Diagnostic::error(format!("only arrays can be indexed, but this is {}", value.describe()))
                .primary(base.span, "not an array"));
        };
        let k = match eval(i, scope)? {
            Val::Number(k) if k.fract() == 0.0 && k >= 1.0 && (k as usize) <= items.len() => k as usize,
            Val::Number(k) => {
                return Err(Diagnostic::error(format!("index {k} is out of range"))
                    .primary(i.span, format!("must be a whole number from 1 to {}", items.len()))
                    .note("indices start at 1"))
            }
            other => {
                return Err(Diagnostic::error(format!("an index must be a number, but this is {}", other.describe()))
                    .primary(i.span, "not a number"))
            }
        };
        value = items.into_iter().nth(k - 1).unwrap_or(Val::Missing);
    }
    Ok(value)
}

/// Numbers and arrays of numbers pass; anything else is an error.
fn numeric(v: Val, span: Span, op: &str) -> EResult {
    if v.shape().is_some() {
        Ok(v)
    } else {
        Err(Diagnostic::error(format!("{op} needs numbers, but this is {}", v.describe()))
            .primary(span, "not a number"))
    }
}

fn map_numbers(v: &Val, f: &dyn Fn(f64) -> f64) -> Val {
    match v {
        Val::Number(x) => Val::Number(f(*x)),
        Val::Array(items) => Val::Array(items.iter().map(|i| map_numbers(i, f)).collect()),
        other => other.clone(),
    }
}

/// Applies `f` elementwise to two values of the same shape, or a number and an array.
fn zip_numbers(a: &Val, b: &Val, broadcast: bool, f: &dyn Fn(f64, f64) -> f64) -> Option<Val> {
    match (a, b) {
        (Val::Number(x), Val::Number(y)) => Some(Val::Number(f(*x, *y))),
        (Val::Array(xs), Val::Array(ys)) if xs.len() == ys.len() => {
            Some(Val::Array(xs.iter().zip(ys).map(|(x, y)| zip_numbers(x, y, broadcast, f)).collect::<Option<_>>()?))
        }
        (Val::Number(_), Val::Array(ys)) if broadcast => {
            Some(Val::Array(ys.iter().map(|y| zip_numbers(a, y, broadcast, f)).collect::<Option<_>>()?))
        }
        (Val::Array(xs), Val::Number(_)) if broadcast => {
            Some(Val::Array(xs.iter().map(|x| zip_numbers(x, b, broadcast, f)).collect::<Option<_>>()?))
        }
        _ => None,
    }
}

/// A division by a parameter that is zero names it (`` `n` is zero ``), so
/// that the place where its value was given can be shown too (see the
/// lowering's `within_instance`).
fn naming_the_divisor(mut d: Diagnostic, divisor: &Expr) -> Diagnostic {
    if let (ExprKind::Name(path), Some(label)) = (&divisor.kind, d.labels.iter_mut().find(|l| l.primary)) {
        if let [name] = path.parts.as_slice() {
            if label.message == "this is zero" {
                label.message = format!("`{}` is zero", name.name);
            }
        }
    }
    d
}

fn binary(op: BinaryOp, a: Val, b: Val, lspan: Span, rspan: Span, span: Span) -> EResult {
    let symbol = op.symbol();
    let a = numeric(a, lspan, &format!("`{symbol}`"))?;
    let b = numeric(b, rspan, &format!("`{symbol}`"))?;
    let is_zero = |v: &Val| -> bool {
        match v {
            Val::Number(x) => *x == 0.0,
            Val::Array(items) => items.iter().any(|i| matches!(i, Val::Number(x) if *x == 0.0)),
            _ => false,
        }
    };
    if matches!(op, BinaryOp::Div | BinaryOp::ElemDiv) && is_zero(&b) {
        return Err(Diagnostic::error("division by zero")
            .primary(rspan, "this is zero")
            .help("check the parameter values; a divisor must not be 0"));
    }
    let scalar_or_array = matches!((&a, &b), (Val::Number(_), _) | (_, Val::Number(_)));
    let result = match op {
        BinaryOp::Add | BinaryOp::Sub if !scalar_or_array || matches!((&a, &b), (Val::Number(_), Val::Number(_))) => {
            let f: &dyn Fn(f64, f64) -> f64 = if op == BinaryOp::Add { &|x, y| x + y } else { &|x, y| x - y };
            zip_numbers(&a, &b, false, f)
        }
        BinaryOp::Mul if scalar_or_array => zip_numbers(&a, &b, true, &|x, y| x * y),
        BinaryOp::Div if matches!(b, Val::Number(_)) => zip_numbers(&a, &b, true, &|x, y| x / y),
        BinaryOp::Pow if matches!((&a, &b), (Val::Number(_), Val::Number(_))) => {
            zip_numbers(&a, &b, false, &|x, y| x.powf(y))
        }
        BinaryOp::ElemAdd => zip_numbers(&a, &b, true, &|x, y| x + y),
        BinaryOp::ElemSub => zip_numbers(&a, &b, true, &|x, y| x - y),
        BinaryOp::ElemMul => zip_numbers(&a, &b, true, &|x, y| x * y),
        BinaryOp::ElemDiv => zip_numbers(&a, &b, true, &|x, y| x / y),
        BinaryOp::ElemPow => zip_numbers(&a, &b, true, &|x, y| x.powf(y)),
        // Comparisons and logic are evaluated by `logical`.
        _ => None,
    };
    result.ok_or_else(|| {
        let hint = match op {
            BinaryOp::Add | BinaryOp::Sub => {
                "add and subtract arrays of the same size; use `.+`/`.-` to add a number to every element"
            }
            BinaryOp::Mul => "multiply arrays by numbers; use `.*` to multiply arrays element by element",
            BinaryOp::Div => "divide arrays by numbers; use `./` to divide element by element",
            BinaryOp::Pow => "`^` takes numbers; use `.^` element by element",
            _ => "element-wise operators take arrays of the same size, or a number and an array",
        };
        Diagnostic::error(format!("cannot apply `{symbol}` to {} and {}", a.describe(), b.describe()))
            .primary(span, "sizes or kinds do not fit")
            .help(hint)
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::syntax::parser::parse;

    struct Params(Vec<(String, Val)>);
    impl Scope for Params {
        fn parameter(&mut self, name: &Ident) -> Result<Option<Val>, Diagnostic> {
            Ok(self.0.iter().find(|(n, _)| *n == name.name).map(|(_, v)| v.clone()))
        }
        fn parameter_names(&self) -> Vec<String> {
            self.0.iter().map(|(n, _)| n.clone()).collect()
        }
        fn is_component(&self, name: &str) -> bool {
            name == "world"
        }
    }

    fn value(text: &str) -> EResult {
        let source = format!("component A\n parameter x::Real = {text}\nend");
        let file = parse(0, &source)?;
        let crate::syntax::ast::Item::Component(c) = &file.items[0] else { unreachable!() };
        let crate::syntax::ast::Declaration::Parameter(p) = &c.declarations[0] else { unreachable!() };
        eval(p.default.as_ref().unwrap(), &mut Params(vec![("L".into(), Val::Number(2.0))]))
    }

    #[test]
    fn arithmetic_arrays_and_functions() {
        assert_eq!(value("1 + 2 * 3 ^ 2").unwrap(), Val::Number(19.0));
        assert_eq!(value("-2^2").unwrap(), Val::Number(-4.0));
        assert_eq!(value("2^-1").unwrap(), Val::Number(0.5));
        assert_eq!(value("L * [1, 0, 0] / 2").unwrap(), value("[1, 0, 0]").unwrap());
        assert_eq!(value("sqrt(4) + norm([3, 4])").unwrap(), Val::Number(7.0));
        assert!(value("[[1, 2], [3, 4]][2, 1]").is_err()); // literals are not indexed
        assert_eq!(value("cos(pi)").unwrap(), Val::Number(-1.0));
        assert_eq!(value("OrientationState.Quaternion()").unwrap(), Val::Enum("OrientationState.Quaternion".into()));
        assert_eq!(value("MultibodyComponents.RootedFrame.FrameA()").unwrap(), Val::Enum("RootedFrame.FrameA".into()));
    }

    #[test]
    fn errors_point_at_the_cause() {
        assert!(value("1 / (L - 2)").unwrap_err().message.contains("division by zero"));
        assert!(value("Lx").unwrap_err().help[0].contains("`L`"));
        assert!(value("sqrt(-1)").unwrap_err().message.contains("not defined"));
        assert!(value("1e300 * 1e300").unwrap_err().message.contains("finite"));
        assert!(value("[1, 2] + [1, 2, 3]").is_err());
        assert!(value("world.g").is_err());
        assert!(value("1 < [1]").unwrap_err().message.contains("compares numbers"));
    }

    #[test]
    fn conditions_and_logic_on_parameters() {
        assert_eq!(value("if L > 1 then 1 else 2").unwrap(), Val::Number(1.0));
        assert_eq!(value("L == 2 and !(L < 0) ? 3 : 4").unwrap(), Val::Number(3.0));
        assert_eq!(value("ifelse(L != 2 || false, 5, 6)").unwrap(), Val::Number(6.0));
        assert_eq!(value("OrientationState.Euler() == OrientationState.Euler").unwrap(), Val::Bool(true));
        assert_eq!(value("world_default_joint_length()").unwrap(), Val::Number(0.1));
    }
}
