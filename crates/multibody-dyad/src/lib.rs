//! Reads Dyad model files (`.dyad`) into [`multibody::Model`]s.
//!
//! The supported part of the language composes models: components with
//! sub-components and modifiers, parameters, `connect` and `initial`
//! relations, metadata (accepted and ignored), and analyses extending
//! `TransientAnalysis`. Everything else is reported as not supported yet,
//! pointing at it.
//!
//! ```
//! use multibody_dyad::Package;
//!
//! let mut package = Package::new();
//! package.add_source("pendulum.dyad", r#"
//! example component Pendulum
//!   world = MultibodyComponents.World()
//!   joint = MultibodyComponents.Revolute(phi(initial = 0.5))
//!   body = MultibodyComponents.Body(m = 1, r_cm = [0.5, 0, 0])
//! relations
//!   connect(world.frame_b, joint.frame_a)
//!   connect(joint.frame_b, body.frame_a)
//! end
//! analysis PendulumSim
//!   extends TransientAnalysis(stop = 1, saveat = 0.01)
//!   model = Pendulum()
//! end
//! "#).unwrap();
//! let lowered = package.lower_analysis("PendulumSim").unwrap();
//! let mechanism = lowered.assemble().unwrap();
//! let solution = mechanism.simulate(&lowered.options).unwrap();
//! assert_eq!(solution.time().last(), Some(&1.0));
//! ```

// The crate's files are grouped by stage, as data flows through them:
// syntax (text to trees), semantics (what names mean), lowering (trees to
// an engine model) and reports (diagnostics). The standard library's
// sources and studies (many runs of one package) sit beside the package.
mod lowering;
mod reports;
mod semantics;
mod syntax;

pub mod stdlib;
pub mod study;
pub mod urdf;

pub use lowering::symbolic;
pub use reports::{diagnostics, source_map};
pub use semantics::{catalog, eval};
pub use syntax::{ast, lexer, parser, source};

pub use diagnostics::{Diagnostic, Severity};
pub use lowering::analysis::Study;
pub use lowering::tunables::{Tunable, TunableKind};
pub use reports::engine_errors::engine_diagnostic;
pub use semantics::modifiers::Override;
pub use source::{FileId, Sources, Span};
pub use source_map::SourceMap;
pub use study::{BadOption, OptionOverrides, RunError, Samples, Target};

use ast::{ComponentKind, Item};
use multibody::{Mechanism, Model, SimulationOptions};

/// Model files read as one package: a file may use what another defines,
/// and every file may use the standard library ([`stdlib`]).
#[derive(Debug, Clone)]
pub struct Package {
    sources: Sources,
    files: Vec<ast::File>,
}

impl Default for Package {
    fn default() -> Self {
        let mut sources = Sources::new();
        for (name, text) in stdlib::sources() {
            sources.add(name, text);
        }
        Self { sources, files: Vec::new() }
    }
}

/// A model ready to assemble: the engine model, the simulation options,
/// and where everything came from.
#[derive(Debug, Clone)]
pub struct Lowered {
    /// The analysis's name, or the component's when there is no analysis.
    pub name: String,
    pub model: Model,
    /// The analysis's options, or the defaults.
    pub options: SimulationOptions,
    pub from_analysis: bool,
    /// What the analysis asks for: a simulation, a linear model or a steady state.
    pub study: Study,
    pub warnings: Vec<Diagnostic>,
    pub source_map: SourceMap,
    /// The values a user most likely wants to change, in the model's order:
    /// the numeric parameters of the components the model's files define
    /// (for every instance: `link1.length`) and the start values those
    /// files write (`link1.joint.phi`), as the model gets them.
    pub tunables: Vec<Tunable>,
}

impl Lowered {
    /// Assembles the model; the engine's errors point at the source.
    pub fn assemble(&self) -> Result<Mechanism, Diagnostic> {
        self.model.assemble().map_err(|e| reports::engine_errors::engine_diagnostic(&e, &self.source_map))
    }

    /// `message` with each origin `#k` it names (the equations of a
    /// message from the run) written as the equation and where it is:
    /// "`x * x = -1 - time` (model.dyad:4:3)".
    pub fn with_places(&self, sources: &Sources, message: &str) -> String {
        let mut out = String::with_capacity(message.len());
        let mut copied = 0;
        for (token, span) in self.origins_in(message) {
            out.push_str(&message[copied..token.start]);
            let text = sources.slice(span).split_whitespace().collect::<Vec<_>>().join(" ");
            out.push_str(&format!("`{text}` ({})", sources.location(span)));
            copied = token.end;
        }
        out.push_str(&message[copied..]);
        out
    }

    /// A failure of the run's first evaluation (`check`, or a run that
    /// stops where it starts) as a diagnostic: the message with its
    /// places, and the equations it names under carets.
    pub fn start_failure(&self, sources: &Sources, title: &str, message: &str) -> Diagnostic {
        let mut d = Diagnostic::error(format!("{title}{}", self.with_places(sources, message)));
        for (k, (_, span)) in self.origins_in(message).into_iter().enumerate() {
            d = if k == 0 { d.primary(span, "this equation") } else { d.secondary(span, "and this one") };
        }
        d
    }

    /// The origins `#k` that `message` names, in order: where each is in
    /// the message, and its span in the sources.
    fn origins_in(&self, message: &str) -> Vec<(std::ops::Range<usize>, Span)> {
        let mut found = Vec::new();
        let mut from = 0;
        while let Some(at) = message[from..].find('#').map(|at| from + at) {
            let digits = message[at + 1..].bytes().take_while(u8::is_ascii_digit).count();
            let token = at..at + 1 + digits;
            if let Some(span) = self.source_map.origin(&message[token.clone()]).filter(|_| digits > 0) {
                found.push((token.clone(), span));
            }
            from = token.end;
        }
        found
    }
}

/// A definition of the package, for listing.
#[derive(Debug, Clone, PartialEq)]
pub struct Definition {
    pub name: String,
    pub kind: DefinitionKind,
    pub doc: Option<String>,
    pub span: Span,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DefinitionKind {
    Component(ComponentKind),
    Analysis,
}

impl Package {
    pub fn new() -> Self {
        Self::default()
    }

    /// A package of the files given as name and text (a host that holds
    /// them in memory: the live page, an FMU). The error is every file's
    /// syntax errors as the command prints them, without colour.
    pub fn from_texts(files: &[(String, String)]) -> Result<Package, String> {
        let mut package = Package::new();
        let errors: Vec<Diagnostic> =
            files.iter().filter_map(|(name, text)| package.add_source(name.clone(), text.clone()).err()).collect();
        if errors.is_empty() {
            Ok(package)
        } else {
            Err(package.render(&errors))
        }
    }

    /// Diagnostics as the command prints them, without colour.
    pub fn render(&self, diagnostics: &[Diagnostic]) -> String {
        diagnostics.iter().map(|d| d.render(self.sources(), false)).collect::<Vec<_>>().join("\n")
    }

    /// Adds and parses a source file. The text is kept either way, so that
    /// a syntax error can be shown with it.
    pub fn add_source(&mut self, name: impl Into<String>, text: impl Into<String>) -> Result<FileId, Diagnostic> {
        let name = name.into();
        let package = library_package(&name);
        let id = self.sources.add(name, text);
        let mut file = parser::parse(id, self.sources.text(id))?;
        file.package = package;
        self.files.push(file);
        Ok(id)
    }

    /// Adds and parses a file as read from disk. Bytes that are not UTF-8
    /// are an error that points at the first of them (the file is kept,
    /// with such bytes shown as `�`, so that the error can show it).
    pub fn add_source_bytes(&mut self, name: impl Into<String>, bytes: Vec<u8>) -> Result<FileId, Diagnostic> {
        let name = name.into();
        let error = match String::from_utf8(bytes) {
            Ok(text) => return self.add_source(name, text),
            Err(e) => e,
        };
        let at = error.utf8_error().valid_up_to();
        let bytes = error.as_bytes();
        let bad = &bytes[at..(at + error.utf8_error().error_len().unwrap_or(bytes.len() - at)).min(bytes.len())];
        let hex: Vec<String> = bad.iter().map(|b| format!("0x{b:02X}")).collect();
        let utf16 = bytes.starts_with(&[0xFF, 0xFE]) || bytes.starts_with(&[0xFE, 0xFF]);
        let text = String::from_utf8_lossy(bytes).into_owned();
        let id = self.sources.add(name.clone(), text);
        // The text before the first bad byte is the same in the shown text, where `�` replaces it.
        let span = Span::new(id, at, at + '\u{fffd}'.len_utf8());
        let place = self.sources.location(span);
        let what = if bad.len() == 1 { "the byte" } else { "the bytes" };
        let d = Diagnostic::error(format!(
            "{name} is not UTF-8 text: {what} {} at {place} (byte offset {at}) cannot be read",
            hex.join(" ")
        ))
        .primary(span, "not UTF-8");
        Err(if utf16 {
            d.help("the file is UTF-16 text (it starts with a UTF-16 byte-order mark); save it as UTF-8")
        } else {
            d.help("model files are UTF-8 text: save the file as UTF-8 (it may be a binary file, or text in another encoding such as Latin-1)")
        })
    }

    /// The files added to the package (not the standard library's), as
    /// name and text: what another process needs to read the same package
    /// (the live page's engine).
    pub fn user_files(&self) -> Vec<(String, String)> {
        let library = stdlib::sources().count();
        (library..self.sources.len())
            .map(|f| (self.sources.name(f).to_string(), self.sources.text(f).to_string()))
            .collect()
    }

    pub fn sources(&self) -> &Sources {
        &self.sources
    }

    /// Every component and analysis, in file order.
    pub fn definitions(&self) -> Vec<Definition> {
        let mut out = Vec::new();
        for item in self.files.iter().flat_map(|f| &f.items) {
            match item {
                Item::Component(c) => out.push(Definition {
                    name: c.name.name.clone(),
                    kind: DefinitionKind::Component(c.kind),
                    doc: c.doc.clone(),
                    span: c.header,
                }),
                Item::Analysis(a) => out.push(Definition {
                    name: a.name.name.clone(),
                    kind: DefinitionKind::Analysis,
                    doc: a.doc.clone(),
                    span: a.header,
                }),
                Item::TypeAlias(_) | Item::Connector(_) => {}
            }
        }
        out
    }

    /// Components that no other component uses and that are not partial:
    /// the candidates to simulate on their own (an analysis's model is one).
    pub fn top_components(&self) -> Vec<Definition> {
        let used: Vec<String> = self
            .files
            .iter()
            .flat_map(|f| &f.items)
            .flat_map(|item| match item {
                Item::Component(c) => c
                    .declarations
                    .iter()
                    .filter_map(|d| match d {
                        ast::Declaration::Component(c) => Some(c.kind.text()),
                        _ => None,
                    })
                    .collect(),
                Item::Analysis(_) | Item::TypeAlias(_) | Item::Connector(_) => Vec::new(),
            })
            .collect();
        self.definitions()
            .into_iter()
            .filter(|d| matches!(d.kind, DefinitionKind::Component(k) if k != ComponentKind::Partial))
            .filter(|d| !used.contains(&d.name))
            .collect()
    }

    /// Lowers the analysis `name`: its model and simulation options.
    pub fn lower_analysis(&self, name: &str) -> Result<Lowered, Diagnostic> {
        self.lower_analysis_with(name, &[])
    }

    /// Lowers the analysis `name` with parameters or start values of its
    /// model given from outside the files (they win over the files').
    pub fn lower_analysis_with(&self, name: &str, overrides: &[Override]) -> Result<Lowered, Diagnostic> {
        let index = semantics::index::Index::new(&self.files)?;
        let analysis = index.analyses.get(name).copied().ok_or_else(|| self.not_found(name, "analysis"))?;
        lowering::lower::Lowerer::analysis(&index, analysis, overrides)
    }

    /// Lowers the component `name` as a whole model, with default options.
    pub fn lower_component(&self, name: &str) -> Result<Lowered, Diagnostic> {
        self.lower_component_with(name, &[])
    }

    /// Lowers the component `name` with parameters or start values given
    /// from outside the files.
    pub fn lower_component_with(&self, name: &str, overrides: &[Override]) -> Result<Lowered, Diagnostic> {
        let index = semantics::index::Index::new(&self.files)?;
        let def = index.get_component(name).ok_or_else(|| self.not_found(name, "component"))?;
        lowering::lower::Lowerer::component(&index, def, overrides)
    }

    fn not_found(&self, name: &str, what: &str) -> Diagnostic {
        let names: Vec<String> = self
            .definitions()
            .into_iter()
            .filter(|d| (what == "analysis") == (d.kind == DefinitionKind::Analysis))
            .map(|d| d.name)
            .collect();
        let mut d = Diagnostic::error(format!("there is no {what} `{name}`"));
        if let Some(s) = diagnostics::did_you_mean(name, names.iter().map(String::as_str)) {
            d = d.help(s);
        }
        if names.is_empty() {
            d.note(format!("the files define no {what}"))
        } else {
            d.note(format!("the files define: {}", names.join(", ")))
        }
    }
}

/// The library package a file at `path` is inside, as Dyad's folders make
/// packages: a file in a folder named `PlanarMechanics` is in the planar
/// package, whose components its short names then mean.
fn library_package(path: &str) -> Option<String> {
    let parent = std::path::Path::new(path).parent()?.file_name()?.to_str()?;
    (parent == "PlanarMechanics").then(|| parent.to_string())
}
