//! `extends`: a component's declarations and relations with those of the
//! components it extends merged in, the modifiers of each `extends`
//! applied.

use crate::reports::diagnostics::{did_you_mean, Diagnostic};
use crate::semantics::index::Index;
use crate::syntax::ast::*;

/// How deeply `extends` may chain.
const MAX_EXTENDS: usize = 32;

/// A component's declarations and relations with those of the components
/// it extends merged in (the base's first).
pub struct Effective {
    pub declarations: Vec<Declaration>,
    pub relations: Vec<Relation>,
}

pub fn effective(index: &Index, def: &ComponentDef) -> Result<Effective, Diagnostic> {
    merged(index, def, &mut Vec::new())
}

/// `def` merged with what it extends; `chain` holds the components being
/// merged around it, outermost first, so that a cycle is named.
fn merged<'a>(index: &Index<'a>, def: &'a ComponentDef, chain: &mut Vec<&'a str>) -> Result<Effective, Diagnostic> {
    let mut declarations = Vec::new();
    let mut relations = Vec::new();
    chain.push(&def.name.name);
    for d in &def.declarations {
        let Declaration::Extends(e) = d else { continue };
        if chain.len() > MAX_EXTENDS {
            return Err(Diagnostic::error(format!("`extends` chains more than {MAX_EXTENDS} levels deep"))
                .primary(e.span, "too deep")
                .help("check for components that extend each other"));
        }
        let Some(base) = index.component_at(&e.base) else {
            if multibody::components::lookup(&e.base.text()).is_some() {
                return Err(Diagnostic::error(format!(
                    "`{}` is built into the engine and cannot be extended",
                    e.base.text()
                ))
                .primary(e.base.span, "built in")
                .help(format!(
                    "use it as a sub-component (`part = {}(...)`) and connect to its connectors, or extend a partial component of the library (`MultibodyComponents.PartialTwoFrames`, `RotationalComponents.PartialTorque`, `ElectricalComponents.OnePort`)",
                    e.base.text()
                )));
            }
            let mut d = Diagnostic::error(format!("`{}` is not a component of these files", e.base.text()))
                .primary(e.base.span, "cannot extend it");
            if let Some(s) = did_you_mean(&e.base.text(), index.component_names()) {
                d = d.help(s);
            } else {
                d = d.help("a component extends a component of these files (`partial component Base ... end`); use a library component as a sub-component instead");
            }
            return Err(d);
        };
        if std::ptr::eq(base, def) {
            return Err(Diagnostic::error(format!("`{}` extends itself", def.name.name)).primary(e.span, "here"));
        }
        if let Some(start) = chain.iter().position(|&c| c == base.name.name) {
            let cycle: Vec<&str> = chain[start..].iter().copied().chain([base.name.name.as_str()]).collect();
            return Err(Diagnostic::error(format!(
                "`{}` extends itself through other components: {}",
                base.name.name,
                cycle.join(" → ")
            ))
            .primary(e.span, "this closes the cycle")
            .help(
                "components that extend each other have no declarations to start from: remove one of the `extends`",
            ));
        }
        let mut inherited = merged(index, base, chain)?;
        apply_extends_modifiers(&mut inherited, &e.modifiers, &e.base)?;
        declarations.extend(inherited.declarations);
        relations.extend(inherited.relations);
    }
    chain.pop();
    declarations.extend(def.declarations.iter().filter(|d| !matches!(d, Declaration::Extends(_))).cloned());
    relations.extend(def.relations.iter().cloned());
    Ok(Effective { declarations, relations })
}

/// `extends Base(k = 2, body(m = 1), x(initial = 0))`: new defaults for
/// the base's parameters, modifiers for its components and variables.
fn apply_extends_modifiers(base: &mut Effective, modifiers: &[Modifier], base_name: &Path) -> Result<(), Diagnostic> {
    for m in modifiers {
        let found = base.declarations.iter_mut().find(|d| d.name().name == m.name.name);
        match (found, &m.value, &m.nested) {
            (Some(Declaration::Parameter(p)), Some(value), None) => {
                p.default = Some(value.clone());
                if m.is_final {
                    p.variability = Variability::Final;
                }
            }
            (Some(Declaration::Component(c)), None, Some(nested)) => {
                for n in nested {
                    c.modifiers.retain(|own| own.name.name != n.name.name);
                    c.modifiers.push(n.clone());
                }
            }
            (Some(Declaration::Variable(v)), value, nested) => {
                if let Some(value) = value {
                    v.binding = Some(value.clone());
                }
                for n in nested.iter().flatten() {
                    match (n.name.name.as_str(), &n.value) {
                        ("initial" | "guess", Some(e)) => v.initial = Some(e.clone()),
                        _ => {
                            return Err(Diagnostic::error(format!(
                                "`{}` is not an attribute of a variable here",
                                n.name.name
                            ))
                            .primary(n.span, "unknown attribute")
                            .help("variables take `initial`: `x(initial = 0)`"))
                        }
                    }
                }
            }
            (Some(_), _, _) => {
                return Err(Diagnostic::error(format!("`{}` cannot be modified this way", m.name.name))
                    .primary(m.span, "not a parameter value or component modifier")
                    .help("give parameters values (`k = 2`) and components modifiers (`body(m = 2)`)"))
            }
            (None, _, _) => {
                let names: Vec<&str> = base.declarations.iter().map(|d| d.name().name.as_str()).collect();
                let mut d = Diagnostic::error(format!("`{}` has no member `{}`", base_name.text(), m.name.name))
                    .primary(m.name.span, "unknown name");
                if let Some(s) = did_you_mean(&m.name.name, names.iter().copied()) {
                    d = d.help(s);
                }
                return Err(d);
            }
        }
    }
    Ok(())
}
