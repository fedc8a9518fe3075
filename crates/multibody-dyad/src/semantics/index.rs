//! Every definition of a package by name: the components, analyses,
//! type aliases and connectors of the files and the standard library.
//! The standard library's part is made once per process; an index adds
//! the package's files over it (a lowering makes one each time: a sweep
//! lowers its model once per run).

use crate::reports::diagnostics::Diagnostic;
use crate::semantics::connectors::{Connector, ConnectorShape};
use crate::syntax::ast::*;
use crate::syntax::source::{FileId, Span};
use std::collections::HashMap;
use std::sync::{Arc, OnceLock};

/// The sub-packages of Dyad's libraries that name no component of their own.
const SUBPACKAGES: &[&str] =
    &["Continuous", "Sources", "Math", "Nonlinear", "Interfaces", "Components", "Sensors", "Analog", "Basic", "Ideal"];

/// The standard library's definitions: components by their library's
/// name (`BlockComponents.Integrator`), connectors by theirs and by their
/// short names (`Dyad.Pin`, `Pin`), and the library of each of its files.
struct Library {
    components: HashMap<String, &'static ComponentDef>,
    connectors: HashMap<String, Connector>,
    packages: HashMap<FileId, &'static str>,
}

fn library() -> &'static Library {
    static LIBRARY: OnceLock<Library> = OnceLock::new();
    LIBRARY.get_or_init(|| {
        let mut library = Library { components: HashMap::new(), connectors: HashMap::new(), packages: HashMap::new() };
        for (name, file) in crate::stdlib::files() {
            for item in &file.items {
                match item {
                    Item::Component(c) => {
                        library.components.insert(format!("{name}.{}", c.name.name), c);
                    }
                    Item::Connector(c) => {
                        let shape = ConnectorShape::of(c).unwrap_or_else(|d| {
                            panic!("the standard library's {} is wrong: {}", c.name.name, d.message)
                        });
                        let shape = Arc::new(shape);
                        library.connectors.insert(format!("{name}.{}", c.name.name), shape.clone());
                        library.connectors.insert(c.name.name.clone(), shape);
                    }
                    _ => {}
                }
            }
            if let (Some(package), Some(Item::Component(c))) = (&file.package, file.items.first()) {
                library.packages.insert(c.header.file, package.as_str());
            }
        }
        library
    })
}

/// Every definition of the package, by name: the files' over the
/// standard library's (a file's connector hides the library's of the same
/// short name).
pub struct Index<'a> {
    library: &'static Library,
    /// The files' components.
    components: HashMap<String, &'a ComponentDef>,
    pub analyses: HashMap<&'a str, &'a AnalysisDef>,
    pub aliases: HashMap<&'a str, &'a TypeAlias>,
    /// The files' connector types.
    connectors: HashMap<String, Connector>,
    /// The library package of each of the files inside one (see `File::package`).
    packages: HashMap<FileId, &'a str>,
}

impl<'a> Index<'a> {
    /// Indexes the package's files over the standard library; a name
    /// defined twice in the files is an error.
    pub fn new(files: impl IntoIterator<Item = &'a File>) -> Result<Self, Diagnostic> {
        let mut index = Index {
            library: library(),
            components: HashMap::new(),
            analyses: HashMap::new(),
            aliases: HashMap::new(),
            connectors: HashMap::new(),
            packages: HashMap::new(),
        };
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
                        index.connectors.insert(c.name.name.clone(), Arc::new(ConnectorShape::of(c)?));
                        Some(())
                    }
                };
            }
        }
        Ok(index)
    }

    /// The component of exactly this name (the files' by theirs, the
    /// library's by its library's: `BlockComponents.Integrator`).
    pub fn get_component(&self, name: &str) -> Option<&'a ComponentDef> {
        self.components.get(name).copied().or_else(|| self.library.components.get(name).copied())
    }

    /// Every component's name (for suggestions).
    pub fn component_names(&self) -> impl Iterator<Item = &str> {
        self.components.keys().chain(self.library.components.keys()).map(String::as_str)
    }

    /// Every component with its name.
    pub fn components(&self) -> impl Iterator<Item = (&str, &'a ComponentDef)> {
        let library = self.library.components.iter().map(|(n, &c)| (n.as_str(), c));
        self.components.iter().map(|(n, &c)| (n.as_str(), c)).chain(library)
    }

    /// Every connector type's name (for suggestions).
    pub fn connector_names(&self) -> impl Iterator<Item = &str> {
        self.connectors.keys().chain(self.library.connectors.keys()).map(String::as_str)
    }

    /// The library package a file is inside, if it is.
    pub fn package_of(&self, file: FileId) -> Option<&'a str> {
        self.packages.get(&file).copied().or_else(|| self.library.packages.get(&file).copied())
    }

    /// The connector type `name` (`Pin`, `Dyad.Pin`).
    pub fn connector(&self, name: &str) -> Option<&Connector> {
        self.connectors.get(name).or_else(|| self.library.connectors.get(name))
    }

    /// The declared shape of each engine connector (`Dyad.Frame3D` is
    /// the engine's Frame3D).
    pub fn engine_shapes(&self) -> Vec<(multibody::components::ConnectorType, Connector)> {
        crate::semantics::connectors::ENGINE
            .into_iter()
            .filter_map(|t| {
                let c = self.connector(&format!("Dyad.{}", t.name()))?;
                (c.engine == Some(t)).then(|| (t, c.clone()))
            })
            .collect()
    }

    /// Whether a declaration of kind `kind` is a connector.
    pub fn is_connector(&self, kind: &Path) -> bool {
        let text = kind.text();
        self.get_component(&text).is_none() && self.connector(&text).is_some()
    }

    /// The component a path names where it is written: inside a library,
    /// a short name is that library's component first.
    pub fn component_at(&self, path: &Path) -> Option<&'a ComponentDef> {
        let text = path.text();
        if let Some(package) = self.package_of(path.span.file).filter(|_| !text.contains('.')) {
            if let Some(def) = self.get_component(&format!("{package}.{text}")) {
                return Some(def);
            }
        }
        self.component(&text)
    }

    /// The component `name`, also by the library's longer names
    /// (`BlockComponents.Continuous.Integrator`).
    pub fn component(&self, name: &str) -> Option<&'a ComponentDef> {
        if let Some(c) = self.get_component(name) {
            return Some(c);
        }
        if let Some(planar) = name.strip_prefix("MultibodyComponents.").filter(|n| n.starts_with("PlanarMechanics.")) {
            return self.get_component(planar);
        }
        // Dyad's libraries file components in sub-packages
        // (`ElectricalComponents.Analog.Basic.Resistor`); ours keep them flat.
        let parts: Vec<&str> = name.split('.').collect();
        match parts.as_slice() {
            [library, middle @ .., rest] if !middle.is_empty() && middle.iter().all(|p| SUBPACKAGES.contains(p)) => {
                self.get_component(&format!("{library}.{rest}"))
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
