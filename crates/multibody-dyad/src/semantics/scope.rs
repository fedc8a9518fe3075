//! The parameters of one component instance (or analysis): their values,
//! from modifiers or defaults, computed on first use and type-checked.

use crate::reports::diagnostics::Diagnostic;
use crate::semantics::eval::{eval, Scope, Val};
use crate::semantics::types::{self, BaseType};
use crate::syntax::ast::{Dim, Ident, ParameterDecl, TypeAlias};
use crate::syntax::source::Span;
use std::collections::{HashMap, HashSet};

/// How deeply parameters may refer to parameters.
const MAX_CHAIN: usize = 32;

pub struct ParamScope<'a, 'i> {
    /// The component (or analysis) the parameters belong to, for messages.
    pub owner: String,
    params: Vec<&'a ParameterDecl>,
    /// Values given by modifiers: value and the span of its expression.
    pub overrides: HashMap<String, (Val, Span)>,
    /// Names of sub-components and connectors (not values).
    components: HashSet<String>,
    /// Where this instance is declared, for "needs a value" messages.
    pub site: Span,
    pub aliases: &'i HashMap<&'a str, &'a TypeAlias>,
    /// Where each parameter is in `params`, by name (the first of a name):
    /// a lookup per use, so that a model's cost stays linear in its size.
    by_name: HashMap<&'a str, usize>,
    values: HashMap<String, Option<Val>>,
    depth: usize,
    /// How many times a parameter has been read (see [`Scope::reads`]).
    reads: usize,
    /// The parameters whose value is computed from other parameters: a
    /// default that reads them, or a modifier's value that reads those of
    /// the enclosing component (named here by the modifier's sorting).
    pub derived: HashSet<String>,
}

impl<'a, 'i> ParamScope<'a, 'i> {
    pub fn new(
        owner: &str,
        params: Vec<&'a ParameterDecl>,
        components: Vec<String>,
        site: Span,
        aliases: &'i HashMap<&'a str, &'a TypeAlias>,
    ) -> Self {
        let mut by_name = HashMap::with_capacity(params.len());
        for (k, p) in params.iter().enumerate() {
            by_name.entry(p.name.name.as_str()).or_insert(k);
        }
        Self {
            owner: owner.to_string(),
            params,
            overrides: HashMap::new(),
            by_name,
            components: components.into_iter().collect(),
            site,
            aliases,
            values: HashMap::new(),
            depth: 0,
            reads: 0,
            derived: HashSet::new(),
        }
    }

    /// The value of the parameter `name` once computed.
    pub fn value(&self, name: &str) -> Option<&Val> {
        self.values.get(name).and_then(Option::as_ref)
    }

    /// Computes every parameter, so that errors in unused ones show too.
    pub fn resolve_all(&mut self) -> Result<(), Diagnostic> {
        for decl in self.params.clone() {
            self.resolve(decl, None)?;
        }
        Ok(())
    }

    fn resolve(&mut self, decl: &'a ParameterDecl, used_at: Option<Span>) -> Result<Val, Diagnostic> {
        let name = &decl.name.name;
        match self.values.get(name) {
            Some(Some(v)) => return Ok(v.clone()),
            Some(None) => {
                return Err(Diagnostic::error(format!("the parameter `{name}` depends on itself"))
                    .primary(used_at.unwrap_or(decl.name.span), "used while it is being computed")
                    .secondary(decl.span, "declared here")
                    .help("give one of the parameters in the cycle a value that does not refer back"))
            }
            None => {}
        }
        if self.depth >= MAX_CHAIN {
            return Err(Diagnostic::error("parameters refer to each other too deeply")
                .primary(used_at.unwrap_or(decl.name.span), format!("more than {MAX_CHAIN} levels")));
        }
        self.values.insert(name.clone(), None);
        self.depth += 1;
        let (value, span) = match (self.overrides.get(name).cloned(), &decl.default) {
            (Some(given), _) => given,
            (None, Some(default)) => {
                let reads = self.reads;
                let value = eval(default, self)?;
                if self.reads != reads {
                    self.derived.insert(name.clone());
                }
                (value, default.span)
            }
            (None, None) => {
                return Err(Diagnostic::error(format!("`{}` needs a value for the parameter `{name}`", self.owner))
                    .primary(self.site, format!("`{name}` is not given"))
                    .secondary(decl.span, "declared without a default")
                    .help(format!(
                        "give it a value where `{}` is used: `{}({name} = ...)`, or a default",
                        self.owner, self.owner
                    )))
            }
        };
        let value = self.check(decl, value, span)?;
        self.depth -= 1;
        self.values.insert(name.clone(), Some(value.clone()));
        Ok(value)
    }

    /// Checks a value against the declared type, size, `min` and `max`.
    fn check(&mut self, decl: &'a ParameterDecl, value: Val, span: Span) -> Result<Val, Diagnostic> {
        let ty = types::resolve(&decl.ty, self.aliases)?;
        let declared = decl.ty.name.text();
        let type_error = |reason: String| {
            Diagnostic::error(format!("wrong type for the parameter `{}`", decl.name.name))
                .primary(span, reason)
                .secondary(decl.ty.span, format!("declared `{declared}` here"))
        };
        if value == Val::Missing {
            return Err(type_error("`missing` is not a value".into())
                .help("`missing` only removes a start value: `r_0(initial = missing)`"));
        }
        if ty.dims.is_empty() {
            let checked = types::check_scalar(ty.base, &value).map_err(type_error)?;
            self.check_bounds(decl, &checked, span, &ty.attributes)?;
            return Ok(checked);
        }
        if !matches!(ty.base, BaseType::Real | BaseType::Integer) {
            return Err(Diagnostic::error("arrays of booleans, strings or enumerations are not supported yet")
                .primary(decl.ty.span, "not supported yet"));
        }
        let mut sizes = Vec::new();
        for dim in ty.dims {
            sizes.push(match dim {
                Dim::Any(_) => None,
                Dim::Size(e) => match eval(e, self)? {
                    Val::Number(n) if n >= 0.0 && n.fract() == 0.0 && n <= 1e6 => Some(n as usize),
                    other => {
                        return Err(Diagnostic::error("an array size must be a whole number")
                            .primary(e.span, format!("this is {}", other.describe())))
                    }
                },
            });
        }
        let shape = value.shape();
        let fits = shape.as_ref().is_some_and(|s| {
            s.len() == sizes.len() && s.iter().zip(&sizes).all(|(got, want)| !matches!(want, Some(w) if w != got))
        });
        let whole = |v: &Val| -> bool {
            fn all(v: &Val, f: &dyn Fn(f64) -> bool) -> bool {
                match v {
                    Val::Number(x) => f(*x),
                    Val::Array(items) => items.iter().all(|i| all(i, f)),
                    _ => false,
                }
            }
            all(v, &|x| x.fract() == 0.0)
        };
        if !fits {
            let want: Vec<String> = sizes.iter().map(|s| s.map_or(":".into(), |n| n.to_string())).collect();
            return Err(Diagnostic::error(format!("wrong array size for the parameter `{}`", decl.name.name))
                .primary(span, format!("this is {}", value.describe()))
                .secondary(decl.ty.span, format!("declared `{declared}[{}]` here", want.join(", ")))
                .help(format!("give an array of size [{}]", want.join(", "))));
        }
        if ty.base == BaseType::Integer && !whole(&value) {
            return Err(type_error("the elements must be whole numbers".into()));
        }
        Ok(value)
    }

    fn check_bounds(
        &mut self,
        decl: &ParameterDecl,
        value: &Val,
        span: Span,
        attributes: &[&'a crate::syntax::ast::Modifier],
    ) -> Result<(), Diagnostic> {
        for attr in attributes {
            let name = attr.name.name.as_str();
            match name {
                "units" | "unit" | "displayUnit" | "quantity" | "description" => {}
                "min" | "max" => {
                    let Some(bound_expr) = &attr.value else { continue };
                    let (Val::Number(bound), Val::Number(x)) = (eval(bound_expr, self)?, value) else {
                        continue;
                    };
                    let ok = if name == "min" { *x >= bound } else { *x <= bound };
                    if !ok {
                        let relation = if name == "min" { "at least" } else { "at most" };
                        return Err(Diagnostic::error(format!(
                            "the parameter `{}` must be {relation} {bound}, but it is {x}",
                            decl.name.name
                        ))
                        .primary(span, format!("{name} = {bound}"))
                        .secondary(attr.span, "the bound"));
                    }
                }
                _ => {
                    return Err(Diagnostic::error(format!("the type attribute `{name}` is not supported yet"))
                        .primary(attr.name.span, "not supported yet")
                        .help("types take `units`, `min` and `max` here"))
                }
            }
        }
        Ok(())
    }
}

impl Scope for ParamScope<'_, '_> {
    fn parameter(&mut self, name: &Ident) -> Result<Option<Val>, Diagnostic> {
        let Some(decl) = self.by_name.get(name.name.as_str()).map(|&k| self.params[k]) else {
            return Ok(None);
        };
        self.reads += 1;
        self.resolve(decl, Some(name.span)).map(Some)
    }

    fn reads(&self) -> usize {
        self.reads
    }

    fn parameter_names(&self) -> Vec<String> {
        self.params.iter().map(|p| p.name.name.clone()).collect()
    }

    fn is_component(&self, name: &str) -> bool {
        self.components.contains(name)
    }
}
