//! The values of a model that a user most likely wants to change, e.g. on
//! a panel of sliders: the numeric parameters of the components the
//! model's own files define, and the start values those files write. The
//! lowering records them as it computes them ([`crate::Lowered::tunables`]);
//! each is changed with an [`Override`] of its path.

use crate::reports::diagnostics::Diagnostic;
use crate::semantics::eval::{eval, Scope, Val};
use crate::semantics::modifiers::Override;
use crate::semantics::types::{self, BaseType};
use crate::syntax::ast::{TypeAlias, TypeRef};
use crate::syntax::source::Span;
use std::collections::HashMap;

/// A value of the lowered model that can be changed from outside the files:
/// lowering again with [`Tunable::set`]`(v)` among the overrides gives the
/// model with `v` in its place.
#[derive(Debug, Clone, PartialEq)]
pub struct Tunable {
    /// The dotted path an [`Override`] names: `link1.length`, `link1.joint.phi`.
    pub path: String,
    pub kind: TunableKind,
    /// The value the model gets (from a modifier, the default, or an override).
    pub value: f64,
    /// The unit of the declared type (`Length` is "m"), its `units`
    /// attribute, or for a start value of a library component, the
    /// variable's unit.
    pub unit: Option<String>,
    /// The doc string before the declaration (the library's description of
    /// a library component's variable).
    pub doc: Option<String>,
    /// The type's `min` and `max` (`Real(min = 0)`, an alias's, or the
    /// lower bound of a standard type such as `Mass`); values outside them
    /// are refused for parameters.
    pub min: Option<f64>,
    pub max: Option<f64>,
    /// Whole numbers only: an `Integer` parameter.
    pub integer: bool,
    /// The value is computed from other parameters (`= length / 2`,
    /// `Link(d = d)`): an override replaces the formula, so the value stops
    /// following them.
    pub derived: bool,
    /// The declaration of the parameter, of the variable, or of the library
    /// component whose variable it starts (`joint = Revolute(...)`); the
    /// same whatever the overrides.
    pub span: Span,
}

/// What a [`Tunable`] sets, and so which [`Override`] changes it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TunableKind {
    /// A parameter of a component of the model's files: [`Override::parameter`].
    Parameter,
    /// A start value (`phi(initial = 0)`, `initial x = 1`, a variable's
    /// `= initial 1`) written in the model's files: [`Override::initial`].
    Start,
}

impl Tunable {
    /// The override that gives this value `value`.
    pub fn set(&self, value: f64) -> Override {
        match self.kind {
            TunableKind::Parameter => Override::parameter(self.path.clone(), value),
            TunableKind::Start => Override::initial(self.path.clone(), value),
        }
    }
}

/// What a panel shows of a declared scalar numeric type.
pub(crate) struct TypeFacts {
    pub unit: Option<String>,
    pub min: Option<f64>,
    pub max: Option<f64>,
    pub integer: bool,
}

/// The unit and bounds of `ty` (its attributes and its aliases', then the
/// standard types' table), or `None` when it is not a scalar number
/// (an array, a boolean, a string, an enumeration).
pub(crate) fn type_facts(
    ty: &TypeRef,
    aliases: &HashMap<&str, &TypeAlias>,
    scope: &mut dyn Scope,
) -> Result<Option<TypeFacts>, Diagnostic> {
    let resolved = types::resolve(ty, aliases)?;
    if !resolved.dims.is_empty() || !matches!(resolved.base, BaseType::Real | BaseType::Integer) {
        return Ok(None);
    }
    let standard = types::standard_unit(resolved.name);
    let mut facts = TypeFacts { unit: None, min: None, max: None, integer: resolved.base == BaseType::Integer };
    // The declaration's own attributes come first, then its aliases': the
    // first of each name is the one that holds.
    for attribute in &resolved.attributes {
        let Some(value) = &attribute.value else { continue };
        match attribute.name.name.as_str() {
            "units" | "unit" if facts.unit.is_none() => {
                if let Val::Str(unit) = eval(value, scope)? {
                    facts.unit = Some(unit);
                }
            }
            "min" if facts.min.is_none() => {
                if let Val::Number(x) = eval(value, scope)? {
                    facts.min = Some(x);
                }
            }
            "max" if facts.max.is_none() => {
                if let Val::Number(x) = eval(value, scope)? {
                    facts.max = Some(x);
                }
            }
            _ => {}
        }
    }
    if let Some((unit, min)) = standard {
        facts.unit = facts.unit.or_else(|| Some(unit.to_string()));
        facts.min = facts.min.or(min);
    }
    Ok(Some(facts))
}

/// Whether `span` is in the model's own files, not the standard library's
/// (whose files come first in every package).
pub(crate) fn in_model_files(span: Span) -> bool {
    span.file >= crate::stdlib::sources().count()
}
