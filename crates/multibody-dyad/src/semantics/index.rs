//! Every definition of a package by name: the components, analyses,
//! type aliases and connectors of the files and the standard library.

use crate::reports::diagnostics::Diagnostic;
use crate::semantics::connectors::{Connector, ConnectorShape};
use crate::syntax::ast::*;
use crate::syntax::source::Span;
use std::collections::HashMap;
use std::rc::Rc;

/// The sub-packages of Dyad's libraries that name no component of their own.
const SUBPACKAGES: &[&str] =
    &["Continuous", "Sources", "Math", "Nonlinear", "Interfaces", "Components", "Sensors", "Analog", "Basic", "Ideal"];

/// Every definition of the package, by name (the standard library's with
/// their library's name first: `BlockComponents.Integrator`).
pub struct Index<'a> {
    pub components: HashMap<String, &'a ComponentDef>,
    pub analyses: HashMap<&'a str, &'a AnalysisDef>,
    pub aliases: HashMap<&'a str, &'a TypeAlias>,
    /// The connector types: the standard library's by their short names
    /// and with their library's (`Pin`, `Dyad.Pin`), the files' by theirs
    /// (a file's connector hides the library's of the same name).
    pub connectors: HashMap<String, Connector>,
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
            connectors: HashMap::new(),
            packages: HashMap::new(),
        };
        for (library, file) in libraries {
            for item in &file.items {
                match item {
                    Item::Component(c) => {
                        index.components.insert(format!("{library}.{}", c.name.name), c);
                    }
                    Item::Connector(c) => {
                        let shape = Rc::new(ConnectorShape::of(c)?);
                        index.connectors.insert(format!("{library}.{}", c.name.name), shape.clone());
                        index.connectors.insert(c.name.name.clone(), shape);
                    }
                    _ => {}
                }
            }
        }
        for (_, file) in libraries {
            if let (Some(package), Some(Item::Component(c))) = (&file.package, file.items.first()) {
                index.packages.insert(c.header.file, package.as_str());
            }
        }
        let mut seen: HashMap<&'a str, Span> = HashMap::new();
        let files_read: Vec<&'a File> = files.into_iter().collect();
        for &file in &files_read {
            for item in &file.items {
                let (name, span) = match item {
                    Item::Component(c) => (&c.name, c.header),
                    Item::Analysis(a) => (&a.name, a.header),
                    Item::TypeAlias(t) => (&t.name, t.span),
                    Item::Connector(c) => (&c.name, c.header),
                };
                if let Some(package) = &file.package {
                    index.packages.insert(span.file, package.as_str());
                }
                if let Some(first) = seen.insert(name.name.as_str(), span) {
                    return Err(defined_again(&name.name, first, name.span, &files_read));
                }
                match item {
                    Item::Component(c) => index.components.insert(c.name.name.clone(), c).map(|_| ()),
                    Item::Analysis(a) => index.analyses.insert(&a.name.name, a).map(|_| ()),
                    Item::TypeAlias(t) => index.aliases.insert(&t.name.name, t).map(|_| ()),
                    Item::Connector(c) => {
                        index.connectors.insert(c.name.name.clone(), Rc::new(ConnectorShape::of(c)?));
                        Some(())
                    }
                };
            }
        }
        Ok(index)
    }

    /// The connector type `name` (`Pin`, `Dyad.Pin`).
    pub fn connector(&self, name: &str) -> Option<&Connector> {
        self.connectors.get(name)
    }

    /// The declared shape of each engine connector (`Dyad.Frame3D` is
    /// the engine's Frame3D).
    pub fn engine_shapes(&self) -> Vec<(multibody::components::ConnectorType, Connector)> {
        crate::semantics::connectors::ENGINE
            .into_iter()
            .filter_map(|t| {
                let c = self.connectors.get(&format!("Dyad.{}", t.name()))?;
                (c.engine == Some(t)).then(|| (t, c.clone()))
            })
            .collect()
    }

    /// Whether a declaration of kind `kind` is a connector.
    pub fn is_connector(&self, kind: &Path) -> bool {
        !self.components.contains_key(&kind.text()) && self.connectors.contains_key(&kind.text())
    }

    /// The component a path names where it is written: inside a library,
    /// a short name is that library's component first.
    pub fn component_at(&self, path: &Path) -> Option<&'a ComponentDef> {
        let text = path.text();
        if let Some(package) = self.packages.get(&path.span.file).filter(|_| !text.contains('.')) {
            if let Some(def) = self.components.get(&format!("{package}.{text}")) {
                return Some(def);
            }
        }
        self.component(&text)
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
        // Dyad's libraries file components in sub-packages
        // (`ElectricalComponents.Analog.Basic.Resistor`); ours keep them flat.
        let parts: Vec<&str> = name.split('.').collect();
        match parts.as_slice() {
            [library, middle @ .., rest] if !middle.is_empty() && middle.iter().all(|p| SUBPACKAGES.contains(p)) => {
                self.components.get(&format!("{library}.{rest}")).copied()
            }
            _ => None,
        }
    }
}

/// The error of a name defined again (at `again`) after
/// `first`: with how many definitions it has in all the files read, the
/// next few of them shown, and how to choose when they are in several
/// files (1000 files each defining `C` named only the first two).
fn defined_again(name: &str, first: Span, again: Span, files: &[&File]) -> Diagnostic {
    const SHOWN: usize = 2;
    let places: Vec<Span> = files
        .iter()
        .flat_map(|f| &f.items)
        .map(|item| match item {
            Item::Component(c) => &c.name,
            Item::Analysis(a) => &a.name,
            Item::TypeAlias(t) => &t.name,
            Item::Connector(c) => &c.name,
        })
        .filter(|n| n.name == name)
        .map(|n| n.span)
        .collect();
    let one_file = places.iter().all(|p| p.file == again.file);
    let mut d = Diagnostic::error(if places.len() == 2 {
        format!("`{name}` is defined twice")
    } else {
        format!("`{name}` is defined {} times", places.len())
    })
    .primary(again, "defined again here")
    .secondary(first, "first defined here");
    let later: Vec<&Span> = places.iter().skip_while(|&&p| p != again).skip(1).collect();
    for span in later.iter().take(SHOWN) {
        d = d.secondary(**span, "and here");
    }
    if later.len() > SHOWN {
        d = d.note(format!("and {} more", later.len() - SHOWN));
    }
    if one_file {
        d.help("rename one of the definitions")
    } else {
        d.help(format!(
            "a name is defined once among the files read: give only the file that defines the `{name}` you mean, \
             or rename the others"
        ))
    }
}
