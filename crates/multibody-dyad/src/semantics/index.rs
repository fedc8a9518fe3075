//! Every definition of a package by name: the components, analyses and
//! type aliases of the files and the standard library, and the connector
//! types users can declare.

use crate::reports::diagnostics::Diagnostic;
use crate::syntax::ast::*;
use crate::syntax::source::Span;
use multibody::components::ConnectorType;
use std::collections::HashMap;

/// The connector types users can declare, by the names the library gives them.
pub const CONNECTOR_TYPES: [ConnectorType; 6] = [
    ConnectorType::Frame,
    ConnectorType::Frame2D,
    ConnectorType::Spline,
    ConnectorType::Flange,
    ConnectorType::RealInput,
    ConnectorType::RealOutput,
];

/// Every definition of the package, by name (the standard library's with
/// their library's name first: `BlockComponents.Integrator`).
pub struct Index<'a> {
    pub components: HashMap<String, &'a ComponentDef>,
    pub analyses: HashMap<&'a str, &'a AnalysisDef>,
    pub aliases: HashMap<&'a str, &'a TypeAlias>,
    /// The library package of each file inside one (see `File::package`).
    pub packages: HashMap<crate::syntax::source::FileId, &'a str>,
}

impl<'a> Index<'a> {
    /// Indexes the standard library and the package's files; a name
    /// defined twice in the files is an error.
    pub fn new(
        libraries: &'a [(&'static str, File)],
        files: impl IntoIterator<Item = &'a File>,
    ) -> Result<Self, Diagnostic> {
        let mut index = Index {
            components: HashMap::new(),
            analyses: HashMap::new(),
            aliases: HashMap::new(),
            packages: HashMap::new(),
        };
        for (library, file) in libraries {
            for item in &file.items {
                if let Item::Component(c) = item {
                    index.components.insert(format!("{library}.{}", c.name.name), c);
                }
            }
        }
        for (_, file) in libraries {
            if let (Some(package), Some(Item::Component(c))) = (&file.package, file.items.first()) {
                index.packages.insert(c.header.file, package.as_str());
            }
        }
        let mut seen: HashMap<&'a str, Span> = HashMap::new();
        for file in files {
            for item in &file.items {
                let (name, span) = match item {
                    Item::Component(c) => (&c.name, c.header),
                    Item::Analysis(a) => (&a.name, a.header),
                    Item::TypeAlias(t) => (&t.name, t.span),
                };
                if let Some(package) = &file.package {
                    index.packages.insert(span.file, package.as_str());
                }
                if let Some(first) = seen.insert(name.name.as_str(), span) {
                    return Err(Diagnostic::error(format!("`{}` is defined twice", name.name))
                        .primary(name.span, "defined again here")
                        .secondary(first, "first defined here")
                        .help("rename one of the definitions"));
                }
                match item {
                    Item::Component(c) => index.components.insert(c.name.name.clone(), c).map(|_| ()),
                    Item::Analysis(a) => index.analyses.insert(&a.name.name, a).map(|_| ()),
                    Item::TypeAlias(t) => index.aliases.insert(&t.name.name, t).map(|_| ()),
                };
            }
        }
        Ok(index)
    }

    /// The component `name`, also by the library's longer names
    /// (`BlockComponents.Continuous.Integrator`).
    pub fn component(&self, name: &str) -> Option<&'a ComponentDef> {
        if let Some(c) = self.components.get(name) {
            return Some(c);
        }
        if let Some(planar) = name.strip_prefix("MultibodyComponents.").filter(|n| n.starts_with("PlanarMechanics.")) {
            return self.components.get(planar).copied();
        }
        let parts: Vec<&str> = name.split('.').collect();
        match parts.as_slice() {
            [library, "Continuous" | "Sources" | "Math" | "Nonlinear" | "Interfaces" | "Components" | "Sensors", rest] => {
                self.components.get(&format!("{library}.{rest}")).copied()
            }
            _ => None,
        }
    }
}
