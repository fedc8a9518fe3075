//! Modifiers after evaluation, and how modifiers from different levels
//! combine: the outer declaration wins over the inner one, except where the
//! inner one is `final`.

use crate::reports::diagnostics::Diagnostic;
use crate::semantics::eval::{eval, Scope, Val};
use crate::syntax::ast::{self, Ident};
use crate::syntax::source::Span;

/// `name = value` and/or `name(nested...)`, with the value computed where
/// it was written.
#[derive(Clone, Debug, PartialEq)]
pub struct Mod {
    pub name: Ident,
    pub is_final: bool,
    /// The value and the span of its expression.
    pub value: Option<(Val, Span)>,
    /// Whether the value is computed from parameters (`d = d`, `k = 2 * m`).
    pub derived: bool,
    pub nested: Vec<Mod>,
    /// Whether `name(...)` was written (possibly empty).
    pub has_nested: bool,
    pub span: Span,
}

impl Mod {
    /// A start value `target(initial = value)` for `initial a.b.target = value`
    /// (or `guess`, per `attribute`): `path` is the part after the
    /// sub-component (`b`, `target`).
    pub fn start_at(path: &[Ident], attribute: &str, value: Val, value_span: Span, span: Span) -> Mod {
        let initial = Mod {
            name: Ident { name: attribute.into(), span: path.last().map_or(span, |p| p.span) },
            is_final: false,
            value: Some((value, value_span)),
            derived: false,
            nested: vec![],
            has_nested: false,
            span,
        };
        path.iter().rev().fold(initial, |inner, part| Mod {
            name: part.clone(),
            is_final: false,
            value: None,
            derived: false,
            nested: vec![inner],
            has_nested: true,
            span,
        })
    }
}

/// Evaluates a modifier list in `scope`; a name given twice is an error.
pub fn eval_modifiers(modifiers: &[ast::Modifier], scope: &mut dyn Scope) -> Result<Vec<Mod>, Diagnostic> {
    let mut out: Vec<Mod> = Vec::with_capacity(modifiers.len());
    for m in modifiers {
        if let Some(first) = out.iter().find(|o| o.name.name == m.name.name) {
            return Err(Diagnostic::error(format!("`{}` is modified twice", m.name.name))
                .primary(m.name.span, "second time")
                .secondary(first.name.span, "first time")
                .help("keep one of them"));
        }
        let reads = scope.reads();
        let value = match &m.value {
            Some(e) => Some((eval(e, scope)?, e.span)),
            None => None,
        };
        let derived = scope.reads() != reads;
        let nested = match &m.nested {
            Some(n) => eval_modifiers(n, scope)?,
            None => Vec::new(),
        };
        out.push(Mod {
            name: m.name.clone(),
            is_final: m.is_final,
            value,
            derived,
            nested,
            has_nested: m.nested.is_some(),
            span: m.span,
        });
    }
    Ok(out)
}

/// Combines modifiers written at the same level (a declaration's own and its
/// component's `initial` relations): giving one thing twice is an error.
pub fn merge_same_level(mut own: Vec<Mod>, extra: Vec<Mod>) -> Result<Vec<Mod>, Diagnostic> {
    for m in extra {
        match own.iter_mut().find(|o| o.name.name == m.name.name) {
            None => own.push(m),
            Some(o) => {
                if let (Some(_), Some(_)) = (&o.value, &m.value) {
                    let what = if m.name.name == "initial" { "the start value" } else { "this value" };
                    return Err(Diagnostic::error(format!("{what} is given twice"))
                        .primary(m.span, "given again here")
                        .secondary(o.span, "first given here")
                        .help("keep one of them"));
                }
                if o.value.is_none() {
                    o.value = m.value;
                    o.derived = m.derived;
                }
                o.has_nested |= m.has_nested;
                o.nested = merge_same_level(std::mem::take(&mut o.nested), m.nested)?;
            }
        }
    }
    Ok(own)
}

/// Applies modifiers from an enclosing declaration (`outer`) over a
/// declaration's own (`own`): the outer value wins unless the own is final.
pub fn merge_outer(outer: Vec<Mod>, mut own: Vec<Mod>) -> Result<Vec<Mod>, Diagnostic> {
    for m in outer {
        match own.iter_mut().find(|o| o.name.name == m.name.name) {
            None => own.push(m),
            Some(o) => {
                if o.is_final {
                    return Err(Diagnostic::error(format!("`{}` is final and cannot be changed", m.name.name))
                        .primary(m.span, "changes a final modifier")
                        .secondary(o.span, "declared final here")
                        .help("remove this modifier, or remove `final` where it is declared"));
                }
                if m.value.is_some() {
                    o.value = m.value;
                    o.derived = m.derived;
                    o.span = m.span;
                    o.name.span = m.name.span;
                }
                o.has_nested |= m.has_nested;
                o.nested = merge_outer(m.nested, std::mem::take(&mut o.nested))?;
            }
        }
    }
    Ok(own)
}

/// A value given from outside the model files (the command line, a sweep,
/// Python) for a parameter or a start value of the simulated model, by its
/// path: `length`, `body.m`, or with `initial` a start value, `rev.phi`.
#[derive(Clone, Debug, PartialEq)]
pub struct Override {
    pub path: String,
    pub value: Val,
    /// A start value (`rev.phi(initial = value)`) rather than a parameter.
    pub initial: bool,
}

impl Override {
    pub fn parameter(path: impl Into<String>, value: f64) -> Self {
        Self { path: path.into(), value: Val::Number(value), initial: false }
    }

    pub fn initial(path: impl Into<String>, value: f64) -> Self {
        Self { path: path.into(), value: Val::Number(value), initial: true }
    }
}

/// Applies overrides to the model's own modifiers, replacing what the files
/// give at the same place (`body.m = 2` becomes the modifier `body(m = 2)`).
/// The new modifiers point at `span`, the model's declaration.
pub fn apply_overrides(modifiers: &mut Vec<Mod>, overrides: &[Override], span: Span) {
    for o in overrides {
        let mut path: Vec<&str> = o.path.split('.').collect();
        if o.initial {
            path.push("initial");
        }
        set_at(modifiers, &path, &o.value, span);
    }
}

fn set_at(modifiers: &mut Vec<Mod>, path: &[&str], value: &Val, span: Span) {
    let Some((first, rest)) = path.split_first() else { return };
    let index = match modifiers.iter().position(|m| m.name.name == *first) {
        Some(i) => i,
        None => {
            modifiers.push(Mod {
                name: Ident { name: first.to_string(), span },
                is_final: false,
                value: None,
                derived: false,
                nested: Vec::new(),
                has_nested: false,
                span,
            });
            modifiers.len() - 1
        }
    };
    let m = &mut modifiers[index];
    if rest.is_empty() {
        m.value = Some((value.clone(), span));
        m.derived = false;
    } else {
        m.has_nested = true;
        set_at(&mut m.nested, rest, value, span);
    }
}
