//! What the standard library's Dyad-written components declare, for
//! `multibody list` and `multibody describe`: parameters with their
//! defaults as written, connectors, and variables (inherited ones
//! included).

use crate::semantics::extends::effective;
use crate::semantics::index::Index;
use crate::stdlib;
use crate::syntax::ast::{Causality, ComponentKind, Declaration, Item};

/// A component of the library written in Dyad.
pub struct Description {
    pub name: String,
    pub doc: String,
    /// Name, default as written (empty when required), type, doc.
    pub parameters: Vec<[String; 4]>,
    /// Name, connector type.
    pub connectors: Vec<[String; 2]>,
    /// Name, component kind: the parts it is made of.
    pub parts: Vec<[String; 2]>,
    /// Name, type (with sizes).
    pub variables: Vec<[String; 2]>,
}

/// Every component of the library written in Dyad that a model can use
/// (partial ones are left out), with its doc.
pub fn components() -> Vec<(String, String)> {
    let mut out = Vec::new();
    for (library, file) in stdlib::files() {
        for item in &file.items {
            if let Item::Component(c) = item {
                if c.kind != ComponentKind::Partial {
                    out.push((format!("{library}.{}", c.name.name), c.doc.clone().unwrap_or_default()));
                }
            }
        }
    }
    out
}

/// The description of the library component `name`
/// (`BlockComponents.PID`, or a longer name of it).
pub fn describe(name: &str) -> Option<Description> {
    let index = Index::new(std::iter::empty()).ok()?;
    let def = index.component(name)?;
    let library = stdlib::files()
        .iter()
        .position(|(_, f)| f.items.iter().any(|i| matches!(i, Item::Component(c) if std::ptr::eq(c, def))))?;
    let text = stdlib::sources().nth(library)?.1;
    let source = |span: crate::syntax::source::Span| text.get(span.range()).unwrap_or_default().trim().to_string();
    let merged = effective(&index, def).ok()?;
    let mut parameters = Vec::new();
    let mut connectors = Vec::new();
    let mut parts = Vec::new();
    let mut variables = Vec::new();
    for d in &merged.declarations {
        match d {
            Declaration::Parameter(p) => parameters.push([
                p.name.name.clone(),
                p.default.as_ref().map(|e| source(e.span)).unwrap_or_default(),
                source(p.ty.span),
                p.doc.clone().unwrap_or_default(),
            ]),
            Declaration::Component(c) if index.is_connector(&c.kind) => {
                connectors.push([c.name.name.clone(), c.kind.text()])
            }
            Declaration::Component(c) => parts.push([c.name.name.clone(), c.kind.text()]),
            Declaration::Variable(v) => match v.causality {
                Causality::Input => connectors.push([v.name.name.clone(), "RealInput".into()]),
                Causality::Output => connectors.push([v.name.name.clone(), "RealOutput".into()]),
                Causality::Internal => variables.push([v.name.name.clone(), source(v.ty.span)]),
            },
            Declaration::Extends(_) => {}
        }
    }
    let full = index.components().find(|(_, c)| std::ptr::eq(*c, def)).map(|(n, _)| n.to_string())?;
    Some(Description { name: full, doc: def.doc.clone().unwrap_or_default(), parameters, connectors, parts, variables })
}
