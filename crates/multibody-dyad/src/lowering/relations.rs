//! The relations of a component instance: `for` loops unrolled, `if` and
//! `switch` on parameters decided, and equations turned into scalar
//! equations of the model, their names resolved to the flattened variables
//! and connector quantities.

use crate::lowering::symbolic::{self, ArrayExpr, Names};
use crate::reports::diagnostics::{did_you_mean, Diagnostic};
use crate::reports::source_map::SourceMap;
use crate::semantics::connectors::Connector;
use crate::semantics::eval::{eval, Scope, Val};
use crate::semantics::scope::ParamScope;
use crate::syntax::ast::*;
use crate::syntax::source::Span;
use multibody::components::{ComponentSpec, ConnectorType};
use multibody::Expr as E;
use std::collections::HashMap;
use std::sync::Arc;

/// Loop variables in scope, innermost last.
pub type Env = Vec<(String, f64)>;

/// How many times loops may run in one component, in all.
const MAX_ITERATIONS: usize = 1_000_000;

/// A scope of parameters with loop variables over it.
pub struct WithEnv<'s, 'a, 'i> {
    pub scope: &'s mut ParamScope<'a, 'i>,
    pub env: &'s [(String, f64)],
}

impl Scope for WithEnv<'_, '_, '_> {
    fn parameter(&mut self, name: &Ident) -> Result<Option<Val>, Diagnostic> {
        if let Some((_, v)) = self.env.iter().rev().find(|(n, _)| *n == name.name) {
            return Ok(Some(Val::Number(*v)));
        }
        self.scope.parameter(name)
    }

    fn parameter_names(&self) -> Vec<String> {
        let mut names = self.scope.parameter_names();
        names.extend(self.env.iter().map(|(n, _)| n.clone()));
        names
    }

    fn is_component(&self, name: &str) -> bool {
        self.scope.is_component(name)
    }

    fn reads(&self) -> usize {
        self.scope.reads()
    }
}

/// A relation after the structure is unrolled, with its loop variables.
pub enum Flat<'r> {
    Connect {
        ends: &'r [Expr],
        env: Env,
    },
    Initial {
        lhs: &'r Expr,
        rhs: &'r Expr,
        span: Span,
        env: Env,
    },
    Guess {
        lhs: &'r Expr,
        rhs: &'r Expr,
        span: Span,
        env: Env,
    },
    Equation {
        lhs: &'r Expr,
        rhs: &'r Expr,
        span: Span,
        env: Env,
    },
    /// A `when` clause: each branch's condition and what it does.
    When {
        branches: Vec<(&'r Expr, Vec<&'r Relation>)>,
        span: Span,
        env: Env,
    },
    /// An `if` whose conditions change during the simulation.
    Conditional {
        branches: Vec<(&'r Expr, Vec<Flat<'r>>)>,
        otherwise: Option<Vec<Flat<'r>>>,
        span: Span,
        env: Env,
    },
    Assert {
        condition: &'r Expr,
        message: &'r str,
        span: Span,
        env: Env,
    },
}

/// Whether `expr` reads something that changes during the simulation:
/// time, a variable, a connector or a component (names in `runtime`).
pub fn is_runtime(expr: &Expr, runtime: &[String]) -> bool {
    match &expr.kind {
        ExprKind::Name(p) => {
            let first = &p.parts[0].name;
            first == "time" || runtime.iter().any(|r| r == first)
        }
        ExprKind::Call { callee, args } => {
            matches!(callee.last().name.as_str(), "der" | "pre" | "initial" | "sample" | "edge" | "change")
                || args.iter().any(|a| is_runtime(a, runtime))
        }
        ExprKind::Array(items) => items.iter().any(|i| is_runtime(i, runtime)),
        ExprKind::Index { base, indices } => {
            is_runtime(base, runtime) || indices.iter().any(|i| is_runtime(i, runtime))
        }
        ExprKind::Field { base, .. } => is_runtime(base, runtime),
        ExprKind::Unary { operand, .. } => is_runtime(operand, runtime),
        ExprKind::Binary { lhs, rhs, .. } => is_runtime(lhs, runtime) || is_runtime(rhs, runtime),
        ExprKind::Chain { first, rest } => {
            is_runtime(first, runtime) || rest.iter().any(|(_, e)| is_runtime(e, runtime))
        }
        ExprKind::If { condition, then, otherwise } => {
            is_runtime(condition, runtime) || is_runtime(then, runtime) || is_runtime(otherwise, runtime)
        }
        ExprKind::Range { start, step, stop } => {
            is_runtime(start, runtime)
                || step.as_ref().is_some_and(|s| is_runtime(s, runtime))
                || is_runtime(stop, runtime)
        }
        ExprKind::Number(_) | ExprKind::Bool(_) | ExprKind::Str(_) | ExprKind::Unsupported(_) => false,
    }
}

/// Unrolls `for`, and decides `if` and `switch` on parameters.
pub fn expand<'r>(
    relations: &'r [Relation],
    scope: &mut ParamScope,
    runtime: &[String],
    env: &mut Env,
) -> Result<Vec<Flat<'r>>, Diagnostic> {
    let mut out = Vec::new();
    let mut iterations = 0;
    expand_into(relations, scope, runtime, env, &mut out, &mut iterations)?;
    Ok(out)
}

fn expand_into<'r>(
    relations: &'r [Relation],
    scope: &mut ParamScope,
    runtime: &[String],
    env: &mut Env,
    out: &mut Vec<Flat<'r>>,
    iterations: &mut usize,
) -> Result<(), Diagnostic> {
    for relation in relations {
        match relation {
            Relation::Connect { ends, .. } => out.push(Flat::Connect { ends, env: env.clone() }),
            Relation::Initial { lhs, rhs, span } => out.push(Flat::Initial { lhs, rhs, span: *span, env: env.clone() }),
            Relation::Guess { lhs, rhs, span } => out.push(Flat::Guess { lhs, rhs, span: *span, env: env.clone() }),
            Relation::Equation { lhs, rhs, span } => {
                out.push(Flat::Equation { lhs, rhs, span: *span, env: env.clone() })
            }
            Relation::Assert { condition, message, span } => {
                out.push(Flat::Assert { condition, message, span: *span, env: env.clone() })
            }
            Relation::When { branches, span } => {
                let mut flat = Vec::with_capacity(branches.len());
                for (condition, body) in branches {
                    let mut actions = Vec::with_capacity(body.len());
                    for r in body {
                        match r {
                            Relation::Equation { .. } | Relation::Reinit { .. } => actions.push(r),
                            Relation::When { span: inner, .. } => {
                                return Err(Diagnostic::error("a `when` cannot be inside another `when`")
                                    .primary(*inner, "nested `when`")
                                    .secondary(*span, "inside this `when`")
                                    .help("add a branch with `elsewhen`, or combine the conditions with `and`"))
                            }
                            other => {
                                return Err(Diagnostic::error(
                                    "a `when` holds assignments `x = value` and `reinit(x, value)` only",
                                )
                                .primary(relation_span(other), "not allowed in a `when`")
                                .help("move it out of the `when`"))
                            }
                        }
                    }
                    flat.push((condition, actions));
                }
                out.push(Flat::When { branches: flat, span: *span, env: env.clone() });
            }
            Relation::Reinit { span, .. } => {
                return Err(Diagnostic::error("`reinit` outside a `when`")
                    .primary(*span, "not inside a `when`")
                    .help("a state jumps at an event: `when h < 0` then `reinit(v, -e * pre(v))` then `end`"))
            }
            Relation::If { branches, otherwise, span } => {
                if branches.iter().any(|(c, _)| is_runtime(c, runtime)) {
                    let bodies = branches.iter().map(|(_, b)| b).chain(otherwise.iter());
                    if let Some(when) = bodies.flat_map(|b| b.iter()).find_map(first_when) {
                        let condition = branches.iter().map(|(c, _)| c).find(|c| is_runtime(c, runtime));
                        return Err(Diagnostic::error("a `when` inside an `if` on values that change")
                            .primary(when, "a `when` here")
                            .secondary(condition.map_or(*span, |c| c.span), "this condition changes")
                            .help(
                                "put the `when` outside the `if`, and its condition in the `when`: `when c and h < 0`",
                            ));
                    }
                    let mut expanded = Vec::new();
                    for (c, body) in branches {
                        let mut inner = Vec::new();
                        expand_into(body, scope, runtime, env, &mut inner, iterations)?;
                        expanded.push((c, inner));
                    }
                    let otherwise = match otherwise {
                        Some(body) => {
                            let mut inner = Vec::new();
                            expand_into(body, scope, runtime, env, &mut inner, iterations)?;
                            Some(inner)
                        }
                        None => None,
                    };
                    out.push(Flat::Conditional { branches: expanded, otherwise, span: *span, env: env.clone() });
                    continue;
                }
                let mut chosen = otherwise.as_deref();
                for (c, body) in branches {
                    if condition(c, scope, env)? {
                        chosen = Some(body);
                        break;
                    }
                }
                if let Some(body) = chosen {
                    expand_into(body, scope, runtime, env, out, iterations)?;
                }
            }
            Relation::For { var, range, body, .. } => {
                let values = range_values(range, scope, env)?;
                *iterations += values.len();
                if *iterations > MAX_ITERATIONS {
                    return Err(Diagnostic::error(format!("loops run more than {MAX_ITERATIONS} times"))
                        .primary(range.span, "too many iterations"));
                }
                for value in values {
                    env.push((var.name.clone(), value));
                    let result = expand_into(body, scope, runtime, env, out, iterations);
                    env.pop();
                    result?;
                }
            }
            Relation::Switch { subject, cases, default, span } => {
                let value = eval(subject, &mut WithEnv { scope, env })?;
                let Val::Enum(v) = &value else {
                    return Err(Diagnostic::error(format!(
                        "`switch` takes an enumeration value, but this is {}",
                        value.describe()
                    ))
                    .primary(subject.span, "not an enumeration value")
                    .help("switch on a (structural) parameter of an enumeration type, e.g. `orientation_state`"));
                };
                let case = v.rsplit('.').next().unwrap_or(v);
                let body = cases.iter().find(|(p, _)| p.last().name == case).map(|(_, b)| b).or(default.as_ref());
                match body {
                    Some(body) => expand_into(body, scope, runtime, env, out, iterations)?,
                    None => {
                        let names: Vec<String> = cases.iter().map(|(p, _)| p.last().name.clone()).collect();
                        return Err(Diagnostic::error(format!("no case of this `switch` is `{case}`"))
                            .primary(*span, "no case matches")
                            .note(format!("its cases are: {}", names.join(", ")))
                            .help("add the case, or a `default ... end`"));
                    }
                }
            }
        }
    }
    Ok(())
}

/// Where a relation was written.
fn relation_span(r: &Relation) -> Span {
    match r {
        Relation::Connect { ends, .. } => ends[0].span,
        Relation::Initial { span, .. }
        | Relation::Guess { span, .. }
        | Relation::Equation { span, .. }
        | Relation::If { span, .. }
        | Relation::For { span, .. }
        | Relation::Switch { span, .. }
        | Relation::Assert { span, .. }
        | Relation::When { span, .. }
        | Relation::Reinit { span, .. } => *span,
    }
}

/// The span of the first `when` in `r` (nested in loops and branches too).
fn first_when(r: &Relation) -> Option<Span> {
    match r {
        Relation::When { span, .. } => Some(*span),
        Relation::If { branches, otherwise, .. } => {
            branches.iter().flat_map(|(_, b)| b).chain(otherwise.iter().flatten()).find_map(first_when)
        }
        Relation::For { body, .. } => body.iter().find_map(first_when),
        Relation::Switch { cases, default, .. } => {
            cases.iter().flat_map(|(_, b)| b).chain(default.iter().flatten()).find_map(first_when)
        }
        _ => None,
    }
}

/// A condition on parameters: true or false.
fn condition(c: &Expr, scope: &mut ParamScope, env: &[(String, f64)]) -> Result<bool, Diagnostic> {
    match eval(c, &mut WithEnv { scope, env })? {
        Val::Bool(b) => Ok(b),
        Val::Number(x) => Ok(x != 0.0),
        other => Err(Diagnostic::error(format!("a condition must be true or false, but this is {}", other.describe()))
            .primary(c.span, "not a condition")),
    }
}

/// The values a `for` runs over: a range `a:b`, `a:s:b`, or an array.
pub fn range_values(range: &Expr, scope: &mut ParamScope, env: &[(String, f64)]) -> Result<Vec<f64>, Diagnostic> {
    let number = |e: &Expr, scope: &mut ParamScope| -> Result<f64, Diagnostic> {
        match eval(e, &mut WithEnv { scope, env })? {
            Val::Number(x) => Ok(x),
            other => Err(Diagnostic::error(format!("a range takes numbers, but this is {}", other.describe()))
                .primary(e.span, "not a number")),
        }
    };
    match &range.kind {
        ExprKind::Range { start, step, stop } => {
            let (a, b) = (number(start, scope)?, number(stop, scope)?);
            let s = match step {
                Some(s) => number(s, scope)?,
                None => 1.0,
            };
            if s == 0.0 {
                return Err(Diagnostic::error("a range's step must not be 0").primary(range.span, "step 0"));
            }
            let n = ((b - a) / s + 1e-9).floor();
            if n > MAX_ITERATIONS as f64 {
                return Err(Diagnostic::error("this range is too long").primary(range.span, "too many values"));
            }
            Ok(if n < 0.0 { Vec::new() } else { (0..=n as usize).map(|k| a + k as f64 * s).collect() })
        }
        _ => match eval(range, &mut WithEnv { scope, env })? {
            Val::Array(items) => items
                .iter()
                .map(|v| match v {
                    Val::Number(x) => Ok(*x),
                    other => Err(Diagnostic::error(format!("a loop runs over numbers, not {}", other.describe()))
                        .primary(range.span, "not numbers")),
                })
                .collect(),
            other => Err(Diagnostic::error(format!("a loop runs over a range or an array, not {}", other.describe()))
                .primary(range.span, "not a range")
                .help("write `for i in 1:N`")),
        },
    }
}

/// A part of a reference: a name and the indices it carries.
pub type Segment = (Ident, Vec<usize>);

/// The parts of a reference (`links[2].body.phi`): names with the index
/// each carries, evaluated with the loop variables.
pub fn segments(
    expr: &Expr,
    scope: &mut ParamScope,
    env: &[(String, f64)],
) -> Result<Option<Vec<Segment>>, Diagnostic> {
    Ok(match &expr.kind {
        ExprKind::Name(p) => Some(p.parts.iter().map(|i| (i.clone(), Vec::new())).collect()),
        ExprKind::Field { base, name } => {
            let Some(mut parts) = segments(base, scope, env)? else { return Ok(None) };
            parts.push((name.clone(), Vec::new()));
            Some(parts)
        }
        ExprKind::Index { base, indices } => {
            let Some(mut parts) = segments(base, scope, env)? else { return Ok(None) };
            let last = parts.last_mut().expect("a name has a part");
            if !last.1.is_empty() {
                return Ok(None);
            }
            for i in indices {
                last.1.push(index_value(i, scope, env)?);
            }
            Some(parts)
        }
        _ => None,
    })
}

fn index_value(i: &Expr, scope: &mut ParamScope, env: &[(String, f64)]) -> Result<usize, Diagnostic> {
    match eval(i, &mut WithEnv { scope, env }) {
        Ok(Val::Number(k)) if k.fract() == 0.0 && k >= 1.0 => Ok(k as usize),
        Ok(Val::Number(k)) => Err(Diagnostic::error(format!("index {k} is not a whole number from 1"))
            .primary(i.span, "bad index")
            .note("indices start at 1")),
        Ok(other) => Err(Diagnostic::error(format!("an index must be a number, but this is {}", other.describe()))
            .primary(i.span, "not a number")),
        Err(_) => Err(Diagnostic::error("an index must be a constant: a number, a parameter or a loop variable")
            .primary(i.span, "changes during the simulation")),
    }
}

fn with_index(name: &str, index: &[usize]) -> String {
    if index.is_empty() {
        name.to_string()
    } else {
        format!("{name}[{}]", index.iter().map(usize::to_string).collect::<Vec<_>>().join(","))
    }
}

/// The target of `initial a[2].b.c = ...` as names (`a[2]`, `b`, `c`),
/// or `None` when the left side is not a plain reference.
pub fn start_target(
    lhs: &Expr,
    scope: &mut ParamScope,
    env: &[(String, f64)],
) -> Result<Option<Vec<Ident>>, Diagnostic> {
    let Some(parts) = segments(lhs, scope, env)? else { return Ok(None) };
    // An index on the last part selects an element of a variable: not a whole start value.
    if parts.last().is_some_and(|(_, i)| !i.is_empty()) {
        return Ok(None);
    }
    Ok(Some(parts.into_iter().map(|(id, index)| Ident { name: with_index(&id.name, &index), span: id.span }).collect()))
}

/// A connect end as a path of names (`links[2]`, `frame_a`).
pub fn connect_path(end: &Expr, scope: &mut ParamScope, env: &[(String, f64)]) -> Result<Path, Diagnostic> {
    let Some(parts) = segments(end, scope, env)? else {
        return Err(
            Diagnostic::error("`connect` takes connectors, e.g. `joint.frame_a`").primary(end.span, "not a connector")
        );
    };
    let parts: Vec<Ident> =
        parts.into_iter().map(|(id, index)| Ident { name: with_index(&id.name, &index), span: id.span }).collect();
    Ok(Path { parts, span: end.span })
}

/// The sizes of a variable's type (`Real[3]` is `[3]`).
pub fn dims(ty: &TypeRef, scope: &mut ParamScope) -> Result<Vec<usize>, Diagnostic> {
    let mut sizes = Vec::new();
    for d in &ty.dims {
        match d {
            Dim::Size(e) => match eval(e, scope)? {
                Val::Number(n) if n >= 0.0 && n.fract() == 0.0 && n <= 1e6 => sizes.push(n as usize),
                other => {
                    return Err(Diagnostic::error(format!(
                        "a size must be a whole number, but this is {}",
                        other.describe()
                    ))
                    .primary(e.span, "not a size"))
                }
            },
            Dim::Any(span) => {
                return Err(Diagnostic::error("a variable needs a fixed size").primary(*span, "`:` is not a size here"))
            }
        }
    }
    if !matches!(ty.name.last().name.as_str(), "Real" | "Integer" | "Boolean") && ty.name.parts.len() == 1 {
        // Type aliases of Real (`Length`, `Angle`, ...) are fine; sizes may come from them too.
    }
    Ok(sizes)
}

/// The scalar names of a variable of sizes `dims`: `x`, `x[1]`, `x[1,2]`.
pub fn scalar_names(name: &str, dims: &[usize]) -> Vec<String> {
    let mut names = vec![String::new()];
    for &n in dims {
        names = names
            .iter()
            .flat_map(|prefix| (1..=n).map(move |k| format!("{prefix}{}{k}", if prefix.is_empty() { "" } else { "," })))
            .collect();
    }
    names.into_iter().map(|s| if s.is_empty() { name.to_string() } else { format!("{name}[{s}]") }).collect()
}

/// The numbers of a value, in order.
pub fn flatten_val(v: &Val, out: &mut Vec<f64>) {
    match v {
        Val::Number(x) => out.push(*x),
        Val::Bool(b) => out.push(if *b { 1.0 } else { 0.0 }),
        Val::Array(items) => items.iter().for_each(|i| flatten_val(i, out)),
        _ => {}
    }
}

/// The scalar variables named after `base` (of sizes `dims`) that the
/// 1-based `index` selects, as a value: `x[i]` of `x::Real[n]` is one
/// variable. Only the selected ones are built, so a reference costs the
/// same whatever the size of the array (a `for` over n elements stays
/// linear in n). Errors as [`select`] gives them.
fn selected_variables(
    base: &str,
    dims: &[usize],
    index: &[usize],
    span: Span,
    what: &str,
) -> Result<ArrayExpr, Diagnostic> {
    fn build(base: &str, dims: &[usize], index: &mut Vec<usize>) -> ArrayExpr {
        match dims.split_first() {
            None => ArrayExpr::Scalar(Arc::new(E::var(with_index(base, index)))),
            Some((&n, rest)) => ArrayExpr::Array(
                (1..=n)
                    .map(|k| {
                        index.push(k);
                        let s = build(base, rest, index);
                        index.pop();
                        s
                    })
                    .collect(),
            ),
        }
    }
    let mut prefix = Vec::with_capacity(dims.len());
    for (depth, &k) in index.iter().enumerate() {
        match dims.get(depth) {
            Some(&n) if (1..=n).contains(&k) => prefix.push(k),
            Some(&n) => {
                return Err(Diagnostic::error(format!("index {k} is out of range for `{what}`"))
                    .primary(span, format!("must be from 1 to {n}")))
            }
            None => {
                return Err(Diagnostic::error(format!("`{what}` is a scalar and cannot be indexed"))
                    .primary(span, "not an array"))
            }
        }
    }
    Ok(build(base, &dims[index.len()..], &mut prefix))
}

/// Selects elements of `value` by 1-based `index`.
fn select(value: ArrayExpr, index: &[usize], span: Span, what: &str) -> Result<ArrayExpr, Diagnostic> {
    let mut v = value;
    for &k in index {
        v = match v {
            ArrayExpr::Array(mut items) if (1..=items.len()).contains(&k) => items.swap_remove(k - 1),
            ArrayExpr::Array(items) => {
                return Err(Diagnostic::error(format!("index {k} is out of range for `{what}`"))
                    .primary(span, format!("must be from 1 to {}", items.len())))
            }
            ArrayExpr::Scalar(_) => {
                return Err(Diagnostic::error(format!("`{what}` is a scalar and cannot be indexed"))
                    .primary(span, "not an array"))
            }
        };
    }
    Ok(v)
}

/// The declared shape of each engine connector type (its Dyad declaration).
pub type EngineShapes = Vec<(ConnectorType, Connector)>;

/// The shape of the engine's connector `ty`.
pub fn engine_shape(shapes: &EngineShapes, ty: ConnectorType) -> Connector {
    shapes
        .iter()
        .find(|(t, _)| *t == ty)
        .map(|(_, c)| c.clone())
        .expect("the standard library declares every engine connector")
}

/// What a flattened name is, for resolving names in equations.
#[derive(Clone, Debug)]
pub enum Entity {
    User,
    Library(&'static ComponentSpec),
    /// An array of components of this length (elements `name[k]`).
    Array(usize),
    /// A variable of these sizes.
    Variable(Vec<usize>),
    /// A connector a user component declares.
    Connector(Connector),
}

/// A connector that equations read.
pub struct ConnectorUse {
    pub connector: String,
    pub ty: Connector,
    /// The quantity read (`f`, `phi`); none for a signal.
    pub field: Option<String>,
    /// An input of a sub-component that the enclosing component's
    /// equations name: those equations decide it (`smoother.u = sin(time)`).
    pub set_from_outside: bool,
}

/// What the relations of one component instance give the model, for the
/// lowering to add: equations, start values, `when` clauses, and the
/// connectors they read (whose connections become equations later).
pub struct RelationsOut {
    pub equations: Vec<multibody::Equation>,
    pub initial: Vec<multibody::Equation>,
    pub whens: Vec<multibody::When>,
    /// Guesses: start values of variables the equations solve for and that
    /// no `initial` fixes.
    pub guesses: Vec<(String, f64)>,
    /// The connectors read, in the order read (a connector may recur).
    pub uses: Vec<ConnectorUse>,
    /// Where the new origins point, numbered on from `first_origin`: the
    /// source map's origins continue with these.
    pub origins: Vec<Span>,
    first_origin: usize,
}

impl RelationsOut {
    /// Nothing yet; the origins given are numbered from `first_origin`
    /// (how many the source map has).
    pub fn new(first_origin: usize) -> Self {
        Self {
            equations: Vec::new(),
            initial: Vec::new(),
            whens: Vec::new(),
            guesses: Vec::new(),
            uses: Vec::new(),
            origins: Vec::new(),
            first_origin,
        }
    }

    /// A name for `span` that engine messages carry back.
    fn origin(&mut self, span: Span) -> String {
        self.origins.push(span);
        SourceMap::origin_name(self.first_origin + self.origins.len() - 1)
    }
}

/// What equations of one component instance see, and what they give.
pub struct Context<'c, 's, 'e, 'j> {
    /// What each flattened name met so far is.
    pub entities: &'c HashMap<String, Entity>,
    /// The variables of the model's equations so far (guesses name them).
    pub variables: &'c [multibody::Variable],
    /// The shapes of the engine's connectors.
    pub engine: &'c EngineShapes,
    /// The model's inputs that the host sets (their `Input` component's value).
    pub host_inputs: &'c std::collections::HashSet<String>,
    pub prefix: &'c str,
    pub scope: &'s mut ParamScope<'e, 'j>,
    pub runtime: &'c [String],
    pub out: RelationsOut,
}

/// Names resolved for one relation (with its loop variables).
struct Resolver<'r, 'c, 's, 'e, 'j> {
    context: &'r mut Context<'c, 's, 'e, 'j>,
    env: &'r [(String, f64)],
}

impl Names for Resolver<'_, '_, '_, '_, '_> {
    fn reference(&mut self, expr: &Expr) -> Result<Option<ArrayExpr>, Diagnostic> {
        let env = self.env;
        let ctx = &mut *self.context;
        let Some(parts) = segments(expr, ctx.scope, env)? else { return Ok(None) };
        let (first, first_index) = &parts[0];
        if parts.len() == 1 {
            if let Some((_, v)) = env.iter().rev().find(|(n, _)| *n == first.name) {
                return Ok(Some(select(ArrayExpr::scalar(*v), first_index, expr.span, &first.name)?));
            }
            if !ctx.runtime.contains(&first.name) {
                if let Some(v) = ctx.scope.parameter(first)? {
                    let s = symbolic::from_val(&v).ok_or_else(|| {
                        Diagnostic::error(format!("the parameter `{}` is {}, not a number", first.name, v.describe()))
                            .primary(first.span, "not a number")
                    })?;
                    return Ok(Some(select(s, first_index, expr.span, &first.name)?));
                }
            }
        }
        let mut name =
            if ctx.prefix.is_empty() { first.name.clone() } else { format!("{}.{}", ctx.prefix, first.name) };
        let mut index = first_index.clone();
        let mut rest = &parts[1..];
        loop {
            let entity = ctx.entities.get(&name).cloned();
            let Some(entity) = entity else { return Ok(None) };
            match entity {
                Entity::Array(n) => {
                    let [k] = index[..] else {
                        return Err(Diagnostic::error(format!("`{}` is an array of components: index it once", name))
                            .primary(expr.span, "needs one index"));
                    };
                    if !(1..=n).contains(&k) {
                        return Err(Diagnostic::error(format!("index {k} is out of range for `{name}`"))
                            .primary(expr.span, format!("must be from 1 to {n}")));
                    }
                    name = format!("{name}[{k}]");
                    index.clear();
                }
                Entity::User => {
                    let Some(((next, next_index), tail)) = rest.split_first() else {
                        return Err(Diagnostic::error(format!("`{}` is a component, not a value", name))
                            .primary(expr.span, "a component")
                            .help("name one of its variables or connectors"));
                    };
                    name = format!("{name}.{}", next.name);
                    index = next_index.clone();
                    rest = tail;
                }
                Entity::Variable(dims) => {
                    if !rest.is_empty() {
                        return Err(Diagnostic::error(format!("the variable `{name}` has no fields"))
                            .primary(expr.span, "no fields"));
                    }
                    return Ok(Some(selected_variables(&name, &dims, &index, expr.span, &name)?));
                }
                Entity::Connector(ty) => return connector_quantity(ctx, &name, &ty, rest, expr.span, true).map(Some),
                Entity::Library(spec) => {
                    let Some(((member, member_index), tail)) = rest.split_first() else {
                        return Err(Diagnostic::error(format!("`{name}` is a component, not a value"))
                            .primary(expr.span, "a component")
                            .help("name one of its variables or connectors"));
                    };
                    if let Some((_, c)) = spec.connector(&member.name) {
                        let full = format!("{name}.{}", member.name);
                        if !member_index.is_empty() {
                            return Err(
                                Diagnostic::error("a connector cannot be indexed").primary(expr.span, "an index")
                            );
                        }
                        let shape = engine_shape(ctx.engine, c.ty);
                        return connector_quantity(ctx, &full, &shape, tail, expr.span, false).map(Some);
                    }
                    if let Some(v) = spec.variables.iter().find(|v| v.name == member.name) {
                        if !tail.is_empty() {
                            return Err(Diagnostic::error(format!("`{}.{}` has no fields", name, member.name))
                                .primary(expr.span, "no fields"));
                        }
                        let dims: Vec<usize> = match v.shape {
                            multibody::components::Shape::Scalar => vec![],
                            multibody::components::Shape::Vector(n) => vec![n],
                            multibody::components::Shape::Matrix(r, c) => vec![r, c],
                        };
                        let full = format!("{name}.{}", member.name);
                        return Ok(Some(selected_variables(&full, &dims, member_index, expr.span, &full)?));
                    }
                    let mut names: Vec<&str> = spec.public_connectors().map(|c| c.name).collect();
                    names.extend(spec.variables.iter().map(|v| v.name));
                    let mut d =
                        Diagnostic::error(format!("{} has no connector or variable `{}`", spec.kind, member.name))
                            .primary(member.span, "unknown name");
                    if let Some(s) = did_you_mean(&member.name, names.iter().copied()) {
                        d = d.help(s);
                    }
                    return Err(d.note(format!("its connectors and variables are: {}", names.join(", "))));
                }
            }
        }
    }

    fn candidates(&self) -> Vec<String> {
        let mut names: Vec<String> = self.context.runtime.to_vec();
        names.extend(self.context.scope.parameter_names());
        names.extend(self.env.iter().map(|(n, _)| n.clone()));
        names
    }
}

/// The value of `connector.field` (or of a signal connector itself); a
/// quantity of a connector the model declares is noted for the
/// connection equations.
fn connector_quantity(
    ctx: &mut Context<'_, '_, '_, '_>,
    connector: &str,
    ty: &Connector,
    rest: &[(Ident, Vec<usize>)],
    span: Span,
    declared: bool,
) -> Result<ArrayExpr, Diagnostic> {
    if ty.is_signal() {
        if !rest.is_empty() {
            return Err(Diagnostic::error(format!("the signal `{connector}` has no fields")).primary(span, "no fields"));
        }
        if declared && ctx.host_inputs.contains(connector) {
            return Ok(ArrayExpr::Scalar(Arc::new(E::var(format!("{connector}.y")))));
        }
        if declared {
            let owner = connector.rsplit_once('.').map_or("", |(owner, _)| owner);
            ctx.out.uses.push(ConnectorUse {
                connector: connector.to_string(),
                ty: ty.clone(),
                field: None,
                set_from_outside: ty.is_input() && owner != ctx.prefix,
            });
        }
        return Ok(ArrayExpr::Scalar(Arc::new(E::var(connector))));
    }
    let names = || ty.fields.iter().map(|f| f.name.as_str()).collect::<Vec<_>>().join(", ");
    let Some(((field, index), tail)) = rest.split_first() else {
        return Err(Diagnostic::error(format!("`{connector}` is a connector; name one of its quantities"))
            .primary(span, "a connector")
            .help(format!("its quantities are: {}", names())));
    };
    let Some(found) = ty.field(&field.name) else {
        let mut d = Diagnostic::error(format!("a {} connector has no `{}`", ty.name, field.name))
            .primary(field.span, "unknown quantity");
        if let Some(s) = did_you_mean(&field.name, ty.fields.iter().map(|f| f.name.as_str())) {
            d = d.help(s);
        }
        return Err(d.note(format!("its quantities are: {}", names())));
    };
    if !tail.is_empty() {
        return Err(Diagnostic::error(format!("`{connector}.{}` has no fields", found.name)).primary(span, "no fields"));
    }
    if declared {
        ctx.out.uses.push(ConnectorUse {
            connector: connector.to_string(),
            ty: ty.clone(),
            field: Some(found.name.clone()),
            set_from_outside: false,
        });
    }
    let full = format!("{connector}.{}", found.name);
    selected_variables(&full, &found.dims, index, span, &full)
}

impl Context<'_, '_, '_, '_> {
    fn eval(&mut self, e: &Expr, env: &[(String, f64)]) -> Result<ArrayExpr, Diagnostic> {
        let mut r = Resolver { context: self, env };
        symbolic::eval(e, &mut r)
    }

    /// The scalar residuals `lhs - rhs` of `lhs = rhs`, sizes checked.
    fn residuals(
        &mut self,
        lhs: &Expr,
        rhs: &Expr,
        span: Span,
        env: &[(String, f64)],
    ) -> Result<Vec<(E, E)>, Diagnostic> {
        let (a, b) = (self.eval(lhs, env)?, self.eval(rhs, env)?);
        let (sa, sb) = (a.shape(), b.shape());
        if sa != sb || sa.is_none() {
            let _ = span;
            return Err(Diagnostic::error(format!(
                "the two sides of this equation differ in size: {} and {}",
                a.describe(),
                b.describe()
            ))
            .primary(lhs.span, a.describe())
            .secondary(rhs.span, b.describe())
            .help("both sides of an equation have the same size; `fill(x, 3)` repeats a scalar, `.+` adds one to each element"));
        }
        let (mut xs, mut ys) = (Vec::new(), Vec::new());
        a.flatten(&mut xs);
        b.flatten(&mut ys);
        Ok(xs.into_iter().map(Arc::unwrap_or_clone).zip(ys.into_iter().map(Arc::unwrap_or_clone)).collect())
    }

    /// Adds `lhs = rhs` to the equations.
    pub fn equation_of(&mut self, lhs: &Expr, rhs: &Expr, span: Span, env: &[(String, f64)]) -> Result<(), Diagnostic> {
        let pairs = self.residuals(lhs, rhs, span, env)?;
        let origin = self.out.origin(span);
        for (l, r) in pairs {
            if !mentions_variable(&l) && !mentions_variable(&r) {
                return Err(Diagnostic::error("this equation has no variable: both sides are constants")
                    .primary(span, "nothing to solve for")
                    .help("an equation relates variables; a constant value belongs in a parameter"));
            }
            self.out.equations.push(multibody::Equation { lhs: l, rhs: r, origin: origin.clone() });
        }
        Ok(())
    }

    /// One relation of the instance (connects were taken already).
    pub fn relation(&mut self, flat: &Flat) -> Result<(), Diagnostic> {
        match flat {
            Flat::Connect { .. } => Ok(()),
            Flat::Equation { lhs, rhs, span, env } => self.equation_of(lhs, rhs, *span, env),
            Flat::Initial { lhs, rhs, span, env } => {
                let pairs = self.residuals(lhs, rhs, *span, env)?;
                let origin = self.out.origin(*span);
                for (l, r) in pairs {
                    self.out.initial.push(multibody::Equation { lhs: l, rhs: r, origin: origin.clone() });
                }
                Ok(())
            }
            Flat::Guess { lhs, rhs, span, env } => {
                let pairs = self.residuals(lhs, rhs, *span, env)?;
                for (l, r) in pairs {
                    let (E::Var(name), E::Const(x)) = (&l, &r) else {
                        return Err(Diagnostic::error("`guess` gives a variable a constant start value")
                            .primary(*span, "not `guess variable = constant`"));
                    };
                    match self.variables.iter().find(|v| v.name == *name) {
                        Some(v) if !v.fixed => self.out.guesses.push((name.clone(), *x)),
                        Some(_) => {}
                        None => return Err(Diagnostic::error(format!(
                            "`guess` for `{name}`, which the equations do not solve for"
                        ))
                        .primary(*span, "not a variable of the equations")
                        .help(
                            "guesses of library components' states go in their declaration: `joint(phi(guess = 0.1))`",
                        )),
                    }
                }
                Ok(())
            }
            Flat::Assert { condition, message, span, env } => {
                let c = self.eval(condition, env)?;
                match c.constant() {
                    Some(x) if x != 0.0 => Ok(()),
                    Some(_) => {
                        Err(Diagnostic::error(format!("assertion failed: {message}")).primary(*span, "does not hold"))
                    }
                    None => Err(Diagnostic::error(
                        "an `assert` on values that change during the simulation is not supported yet",
                    )
                    .primary(*span, "changes during the simulation")
                    .help("assert on parameters, or watch the value in the results")),
                }
            }
            Flat::When { branches, span, env } => {
                let mut when = multibody::When { branches: Vec::new(), origin: self.out.origin(*span) };
                for (condition, body) in branches {
                    let c = self.eval(condition, env)?;
                    let ArrayExpr::Scalar(c) = c else {
                        return Err(
                            Diagnostic::error("a condition must be a scalar").primary(condition.span, "not a scalar")
                        );
                    };
                    let mut actions = Vec::new();
                    for r in body {
                        self.when_action(r, env, &mut actions)?;
                    }
                    when.branches.push((Arc::unwrap_or_clone(c), actions));
                }
                self.out.whens.push(when);
                Ok(())
            }
            Flat::Conditional { branches, otherwise, span, env } => {
                let Some(otherwise) = otherwise else {
                    return Err(Diagnostic::error("an `if` on values that change during the simulation needs an `else`")
                        .primary(*span, "no `else`")
                        .help("give the `else` branch as many equations as the others, so that every case decides the same unknowns"));
                };
                let mut cases: Vec<(Option<E>, Vec<E>)> = Vec::new();
                for (c, body) in branches {
                    let cond = self.eval(c, env)?;
                    let ArrayExpr::Scalar(cond) = cond else {
                        return Err(Diagnostic::error("a condition must be a scalar").primary(c.span, "not a scalar"));
                    };
                    cases.push((Some(Arc::unwrap_or_clone(cond)), self.branch(body)?));
                }
                cases.push((None, self.branch(otherwise)?));
                let n = cases[0].1.len();
                if let Some((_, different)) = cases.iter().find(|(_, r)| r.len() != n) {
                    return Err(Diagnostic::error(format!(
                        "the branches of this `if` have different numbers of equations ({n} and {})",
                        different.len()
                    ))
                    .primary(*span, "unequal branches")
                    .help("each branch must give the same number of scalar equations"));
                }
                let origin = self.out.origin(*span);
                for k in 0..n {
                    let mut value = cases.last().expect("otherwise").1[k].clone();
                    for (cond, residuals) in cases.iter().rev().skip(1) {
                        value = E::if_else(cond.clone().expect("a condition"), residuals[k].clone(), value);
                    }
                    self.out.equations.push(multibody::Equation {
                        lhs: value,
                        rhs: E::Const(0.0),
                        origin: origin.clone(),
                    });
                }
                Ok(())
            }
        }
    }

    /// What one relation inside a `when` does: `x = value` assigns (each
    /// element of an array), `reinit(x, value)` makes a state jump.
    fn when_action(
        &mut self,
        r: &Relation,
        env: &[(String, f64)],
        actions: &mut Vec<multibody::WhenAction>,
    ) -> Result<(), Diagnostic> {
        let (target, value, span, reinit) = match r {
            Relation::Equation { lhs, rhs, span } => (lhs, rhs, *span, false),
            Relation::Reinit { state, value, span } => (state, value, *span, true),
            _ => unreachable!("only assignments and reinit get here"),
        };
        let origin = self.out.origin(span);
        let pairs = self.residuals(target, value, span, env)?;
        for (t, v) in pairs {
            let E::Var(name) = t else {
                let what = if reinit { "`reinit` takes a state first" } else { "a `when` assigns a variable" };
                return Err(Diagnostic::error(format!("{what}, not an expression"))
                    .primary(target.span, "not a variable")
                    .help(if reinit {
                        "write `reinit(x, value)` with a state `x` (a variable whose `der` appears, or `rev.w`)"
                    } else {
                        "write `x = value` with a variable `x` on the left"
                    }));
            };
            actions.push(if reinit {
                multibody::WhenAction::Reinit { state: name, value: v, origin: origin.clone() }
            } else {
                multibody::WhenAction::Assign { variable: name, value: v, origin: origin.clone() }
            });
        }
        Ok(())
    }

    /// The residuals of a branch of a conditional `if`: equations only.
    fn branch(&mut self, body: &[Flat]) -> Result<Vec<E>, Diagnostic> {
        let mut out = Vec::new();
        for f in body {
            match f {
                Flat::Equation { lhs, rhs, span, env } => {
                    for (l, r) in self.residuals(lhs, rhs, *span, env)? {
                        out.push(l - r);
                    }
                }
                Flat::Conditional { span, .. }
                | Flat::When { span, .. }
                | Flat::Initial { span, .. }
                | Flat::Guess { span, .. }
                | Flat::Assert { span, .. } => {
                    return Err(Diagnostic::error(
                        "only equations can depend on values that change during the simulation",
                    )
                    .primary(*span, "not an equation")
                    .help("move it out of the `if`, or make the condition a parameter"))
                }
                Flat::Connect { ends, .. } => {
                    return Err(Diagnostic::error(
                        "a `connect` cannot depend on values that change during the simulation",
                    )
                    .primary(ends[0].span, "inside a changing `if`")
                    .help("make the condition a (structural) parameter"));
                }
            }
        }
        Ok(out)
    }
}

fn mentions_variable(e: &E) -> bool {
    let mut found = false;
    e.visit(&mut |n| found |= matches!(n, E::Var(_) | E::Time));
    found
}
