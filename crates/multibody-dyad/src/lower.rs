//! Lowering: instantiates a model's top component into a
//! [`multibody::Model`]. User components are flattened into dotted names
//! (`pend.body`); their parameters are computed and passed down; library
//! components become engine components whose parameters the engine checks.

use crate::analysis::transient_options;
use crate::ast::*;
use crate::connections::{ConnectionGraph, End};
use crate::diagnostics::{did_you_mean, Diagnostic};
use crate::eval::{eval, Val};
use crate::modifiers::{apply_overrides, eval_modifiers, merge_outer, merge_same_level, Mod, Override};
use crate::scope::ParamScope;
use crate::source::Span;
use crate::source_map::{ComponentSite, MemberSite, Shadowing, SourceMap};
use crate::Lowered;
use multibody::components::{lookup, registry, ComponentSpec, ConnectorType};
use multibody::{Model, SimulationOptions};
use std::collections::HashMap;

/// How deeply user components may nest.
const MAX_NESTING: usize = 32;
/// How many library components one model may have.
const MAX_COMPONENTS: usize = 20_000;
/// The connector types users can declare, by the names the library gives them.
const CONNECTOR_TYPES: [ConnectorType; 5] = [
    ConnectorType::Frame,
    ConnectorType::Spline,
    ConnectorType::Flange,
    ConnectorType::RealInput,
    ConnectorType::RealOutput,
];

/// Every definition of the package, by name.
pub struct Index<'a> {
    pub components: HashMap<&'a str, &'a ComponentDef>,
    pub analyses: HashMap<&'a str, &'a AnalysisDef>,
    pub aliases: HashMap<&'a str, &'a TypeAlias>,
}

impl<'a> Index<'a> {
    /// Indexes the definitions; a name defined twice is an error.
    pub fn new(files: impl IntoIterator<Item = &'a File>) -> Result<Self, Diagnostic> {
        let mut index = Index { components: HashMap::new(), analyses: HashMap::new(), aliases: HashMap::new() };
        let mut seen: HashMap<&'a str, Span> = HashMap::new();
        for file in files {
            for item in &file.items {
                let (name, span) = match item {
                    Item::Component(c) => (&c.name, c.header),
                    Item::Analysis(a) => (&a.name, a.header),
                    Item::TypeAlias(t) => (&t.name, t.span),
                };
                if let Some(first) = seen.insert(name.name.as_str(), span) {
                    return Err(Diagnostic::error(format!("`{}` is defined twice", name.name))
                        .primary(name.span, "defined again here")
                        .secondary(first, "first defined here")
                        .help("rename one of the definitions"));
                }
                match item {
                    Item::Component(c) => index.components.insert(&c.name.name, c).map(|_| ()),
                    Item::Analysis(a) => index.analyses.insert(&a.name.name, a).map(|_| ()),
                    Item::TypeAlias(t) => index.aliases.insert(&t.name.name, t).map(|_| ()),
                };
            }
        }
        Ok(index)
    }
}

/// What a declaration's kind names.
#[derive(Clone, Copy)]
enum Kind<'a> {
    Library(&'static ComponentSpec),
    User(&'a ComponentDef),
    Connector(ConnectorType),
}

pub struct Lowerer<'a, 'i> {
    index: &'i Index<'a>,
    model: Model,
    map: SourceMap,
    warnings: Vec<Diagnostic>,
    graph: ConnectionGraph,
    /// The user components being instantiated, outermost first.
    stack: Vec<&'a str>,
}

fn flat(prefix: &str, name: &str) -> String {
    if prefix.is_empty() {
        name.to_string()
    } else {
        format!("{prefix}.{name}")
    }
}

impl<'a, 'i> Lowerer<'a, 'i> {
    fn new(index: &'i Index<'a>, root: &ComponentDef) -> Self {
        let mut map = SourceMap::default();
        map.root = Some((root.name.name.clone(), root.header));
        Self {
            index,
            model: Model::new(root.name.name.clone()),
            map,
            warnings: Vec::new(),
            graph: ConnectionGraph::default(),
            stack: Vec::new(),
        }
    }

    fn finish(mut self, name: &str, options: SimulationOptions, from_analysis: bool) -> Lowered {
        let warnings = self.graph.finish(&mut self.model, &mut self.map);
        self.warnings.extend(warnings);
        Lowered {
            name: name.to_string(),
            model: self.model,
            options,
            from_analysis,
            warnings: self.warnings,
            source_map: self.map,
        }
    }

    /// Lowers a component as the whole model, with default options.
    pub fn component(
        index: &'i Index<'a>,
        def: &'a ComponentDef,
        overrides: &[Override],
    ) -> Result<Lowered, Diagnostic> {
        let mut lowerer = Lowerer::new(index, def);
        let mut modifiers = Vec::new();
        apply_overrides(&mut modifiers, overrides, def.header);
        lowerer.instantiate(def, "", modifiers, def.header, &[])?;
        Ok(lowerer.finish(&def.name.name, SimulationOptions::default(), false))
    }

    /// Lowers an analysis: its model and its options.
    pub fn analysis(
        index: &'i Index<'a>,
        analysis: &'a AnalysisDef,
        overrides: &[Override],
    ) -> Result<Lowered, Diagnostic> {
        let Some(model) = &analysis.model else {
            return Err(Diagnostic::error(format!("the analysis `{}` has no model", analysis.name.name))
                .primary(analysis.header, "no `model = ...`")
                .help("add the component to simulate: `model = MyModel()`"));
        };
        let mut scope = ParamScope::new(
            &analysis.name.name,
            analysis.parameters.iter().collect(),
            vec!["model".into()],
            analysis.header,
            &index.aliases,
        );
        check_unique(analysis.parameters.iter().map(|p| &p.name))?;
        scope.resolve_all()?;
        let base_modifiers = eval_modifiers(&analysis.base_modifiers, &mut scope)?;
        let mut model_modifiers = eval_modifiers(&model.modifiers, &mut scope)?;
        apply_overrides(&mut model_modifiers, overrides, model.span);
        let def = match resolve_kind(index, &model.kind)? {
            Kind::User(def) => def,
            _ => {
                return Err(Diagnostic::error(
                    "the model of an analysis must be a component defined in the model files",
                )
                .primary(model.kind.span, "a library component or connector")
                .help("define a component with a World and what it simulates, and use it: `model = MyModel()`"))
            }
        };
        let mut lowerer = Lowerer::new(index, def);
        let options = transient_options(analysis, base_modifiers, &mut lowerer.warnings)?;
        lowerer.instantiate(def, "", model_modifiers, model.span, &[])?;
        Ok(lowerer.finish(&analysis.name.name, options, true))
    }

    /// Instantiates user component `def` under `prefix`, with modifiers
    /// from where it is declared (`site`).
    fn instantiate(
        &mut self,
        def: &'a ComponentDef,
        prefix: &str,
        modifiers: Vec<Mod>,
        site: Span,
        within: &[(String, Span)],
    ) -> Result<(), Diagnostic> {
        let name = def.name.name.as_str();
        if def.kind == ComponentKind::Partial {
            return Err(Diagnostic::error(format!("`{name}` is a partial component and cannot be used directly"))
                .primary(site, "used here")
                .secondary(def.header, "declared `partial` here")
                .help("remove `partial` from its definition, or use a complete component"));
        }
        if let Some(start) = self.stack.iter().position(|d| *d == name) {
            let mut chain: Vec<&str> = self.stack[start..].to_vec();
            chain.push(name);
            return Err(Diagnostic::error(format!("`{name}` contains itself: {}", chain.join(" → ")))
                .primary(site, format!("this makes `{}` contain itself", self.stack[start]))
                .secondary(def.header, "defined here")
                .help("a component cannot contain itself, directly or through other components"));
        }
        if self.stack.len() >= MAX_NESTING {
            return Err(Diagnostic::error(format!("components nest more than {MAX_NESTING} levels deep"))
                .primary(site, "too deep"));
        }
        self.stack.push(name);
        check_unique(def.declarations.iter().map(Declaration::name))?;

        let params: Vec<&'a ParameterDecl> = def
            .declarations
            .iter()
            .filter_map(|d| if let Declaration::Parameter(p) = d { Some(p) } else { None })
            .collect();
        let mut subs: Vec<(&'a ComponentDecl, Kind<'a>)> = Vec::new();
        for d in &def.declarations {
            if let Declaration::Component(c) = d {
                let kind = resolve_kind(self.index, &c.kind)?;
                if let (Kind::User(user), Some(spec)) = (kind, lookup(&c.kind.text())) {
                    self.map.shadowing.push(Shadowing {
                        library_kind: spec.kind.to_string(),
                        used: c.span,
                        defined: user.name.span,
                    });
                }
                subs.push((c, kind));
            }
        }
        let sub = |n: &str| subs.iter().find(|(c, _)| c.name.name == n).map(|(c, k)| (*c, *k));

        // Modifiers from outside: parameter values, and modifiers of sub-components.
        let mut scope = ParamScope::new(
            name,
            params.clone(),
            subs.iter().map(|(c, _)| c.name.name.clone()).collect(),
            site,
            &self.index.aliases,
        );
        let mut forwarded: HashMap<String, Vec<Mod>> = HashMap::new();
        for m in modifiers {
            let key = m.name.name.as_str();
            if let Some(p) = params.iter().find(|p| p.name.name == key) {
                if p.variability == Variability::Final {
                    return Err(Diagnostic::error(format!(
                        "`{key}` is a final parameter of `{name}` and cannot be changed"
                    ))
                    .primary(m.name.span, "changes a final parameter")
                    .secondary(p.span, "declared final here"));
                }
                match (&m.value, m.has_nested) {
                    (Some(v), false) => {
                        scope.overrides.insert(key.to_string(), v.clone());
                    }
                    _ => {
                        return Err(Diagnostic::error(format!("`{key}` is a parameter; give it a value"))
                            .primary(m.span, "not a value")
                            .help(format!("write `{key} = ...`")))
                    }
                }
            } else if let Some((c, kind)) = sub(key) {
                if matches!(kind, Kind::Connector(_)) {
                    return Err(Diagnostic::error(format!(
                        "`{key}` is a connector of `{name}`; it takes no modifiers"
                    ))
                    .primary(m.span, "modifies a connector")
                    .secondary(c.span, "declared here"));
                }
                if m.value.is_some() {
                    return Err(Diagnostic::error(format!(
                        "`{key}` is a component of `{name}`; it cannot be replaced"
                    ))
                    .primary(m.span, "replaces a component")
                    .help(format!("change its parameters instead: `{key}(m = 2)`")));
                }
                forwarded.insert(key.to_string(), m.nested);
            } else {
                let names: Vec<&str> = params
                    .iter()
                    .map(|p| p.name.name.as_str())
                    .chain(
                        subs.iter()
                            .filter(|(_, k)| !matches!(k, Kind::Connector(_)))
                            .map(|(c, _)| c.name.name.as_str()),
                    )
                    .collect();
                let mut d = Diagnostic::error(format!("`{name}` has no parameter `{key}`"))
                    .primary(m.name.span, "unknown parameter")
                    .secondary(def.header, format!("`{name}` is defined here"));
                if let Some(s) = did_you_mean(key, names.iter().copied()) {
                    d = d.help(s);
                }
                let param_names: Vec<&str> = params.iter().map(|p| p.name.name.as_str()).collect();
                d = if param_names.is_empty() {
                    d.note(format!("`{name}` declares no parameters"))
                } else {
                    d.note(format!("its parameters are: {}", param_names.join(", ")))
                };
                return Err(d);
            }
        }
        scope.resolve_all()?;

        // `initial a.b = v` relations act as modifiers `a(b(initial = v))` of this level.
        let mut initial: HashMap<String, Vec<Mod>> = HashMap::new();
        for relation in &def.relations {
            let Relation::Initial { target, value, span } = relation else { continue };
            let first = &target.parts[0];
            match sub(&first.name) {
                Some((_, Kind::Library(_) | Kind::User(_))) if target.parts.len() >= 2 => {}
                found => {
                    let mut d =
                        Diagnostic::error(format!("`initial {}` names no variable of a component", target.text()))
                            .primary(target.span, "not a variable of a sub-component");
                    d = match found {
                        Some((_, Kind::Connector(_))) => d.help("connectors have no start values"),
                        Some(_) => d.help(format!("name one of its variables: `initial {}.phi = ...`", first.name)),
                        None if params.iter().any(|p| p.name.name == first.name) => {
                            d.help(format!("`{}` is a parameter: give its value in its declaration", first.name))
                        }
                        None => {
                            let names = subs.iter().map(|(c, _)| c.name.name.as_str());
                            match did_you_mean(&first.name, names) {
                                Some(s) => d.help(s),
                                None => {
                                    d.help("write `initial component.variable = value`, e.g. `initial joint.phi = 0`")
                                }
                            }
                        }
                    };
                    return Err(d);
                }
            }
            let v = eval(value, &mut scope)?;
            let m = Mod::initial_at(&target.parts[1..], v, value.span, *span);
            let list = initial.remove(&first.name).unwrap_or_default();
            initial.insert(first.name.clone(), merge_same_level(list, vec![m])?);
        }

        // `sub.input = formula`: a signal input of a library component
        // driven by a formula of time; `sub.surface = formula`: the road of
        // a wheel, a formula of x and z.
        let mut surfaces = Vec::new();
        for relation in &def.relations {
            let Relation::Equation { lhs, rhs, span } = relation else { continue };
            let first = &lhs.parts[0];
            if let (Some((_, Kind::Library(spec))), Some(part)) = (sub(&first.name), lhs.parts.get(1)) {
                if lhs.parts.len() == 2 && part.name == "surface" && spec.param("surface").is_some() {
                    let road = crate::eval::surface_formula(rhs, &mut scope)?;
                    surfaces.push((flat(prefix, &first.name), road));
                    continue;
                }
            }
            let input = match (sub(&first.name), lhs.parts.get(1)) {
                (Some((_, Kind::Library(spec))), Some(connector)) if lhs.parts.len() == 2 => spec
                    .connectors
                    .iter()
                    .find(|c| c.name == connector.name && !c.internal)
                    .filter(|c| c.ty == multibody::components::ConnectorType::RealInput)
                    .map(|_| format!("{}.{}", flat(prefix, &first.name), connector.name)),
                _ => None,
            };
            let Some(input) = input else {
                return Err(Diagnostic::error("equations are not supported here yet")
                    .primary(*span, "not a signal input given a formula of time")
                    .help("an equation may give a library component's signal input a formula of time, e.g. `prescribed.r_x = sin(time)`; for other behaviour use a library component"));
            };
            let f = crate::eval::formula(rhs, &mut scope)?;
            self.model.set_input(input, f);
        }

        for &(decl, kind) in &subs {
            let child = flat(prefix, &decl.name.name);
            let own = eval_modifiers(&decl.modifiers, &mut scope)?;
            let own = merge_same_level(own, initial.remove(&decl.name.name).unwrap_or_default())?;
            let merged = merge_outer(forwarded.remove(&decl.name.name).unwrap_or_default(), own)?;
            match kind {
                Kind::Library(spec) => self.library_component(spec, &child, decl, merged, within)?,
                Kind::User(sub_def) => {
                    let mut inner = vec![(child.clone(), decl.span)];
                    inner.extend(within.iter().cloned());
                    self.instantiate(sub_def, &child, merged, decl.span, &inner)?;
                }
                Kind::Connector(ty) => {
                    if let Some(m) = merged.first() {
                        self.warnings.push(
                            Diagnostic::warning("modifiers of connectors have no effect here and are ignored")
                                .primary(m.span, "ignored"),
                        );
                    }
                    self.graph.declare(child, ty, decl.span, name.to_string());
                }
            }
        }
        for (component, road) in surfaces {
            if let Some(c) = self.model.component_mut(&component) {
                c.surface(road);
            }
        }

        for relation in &def.relations {
            let Relation::Connect { ends, .. } = relation else { continue };
            let mut resolved = Vec::with_capacity(ends.len());
            for end in ends {
                resolved.push((self.connect_end(end, prefix, def, &subs)?, end.span));
            }
            self.graph.connect(resolved)?;
        }
        self.stack.pop();
        Ok(())
    }

    /// What one end of a `connect` in `def` names.
    fn connect_end(
        &self,
        end: &Path,
        prefix: &str,
        def: &'a ComponentDef,
        subs: &[(&'a ComponentDecl, Kind<'a>)],
    ) -> Result<End, Diagnostic> {
        let owner = def.name.name.as_str();
        let sub = |n: &str| subs.iter().find(|(c, _)| c.name.name == n).map(|(c, k)| (*c, *k));
        let first = &end.parts[0];
        match (end.parts.len(), sub(&first.name)) {
            (1, Some((decl, Kind::Connector(ty)))) => Ok(End::Declared {
                name: flat(prefix, &first.name),
                ty,
                declaration: decl.span,
                owner: owner.to_string(),
            }),
            (1, Some((_, kind))) => {
                let connectors = connector_names(kind);
                let mut d = Diagnostic::error(format!("`{}` is a component, not a connector", first.name))
                    .primary(end.span, "a component");
                if let Some(c) = connectors.first() {
                    d = d.help(format!("connect one of its connectors, e.g. `{}.{c}`", first.name));
                }
                if !connectors.is_empty() {
                    d = d.note(format!("its connectors are: {}", connectors.join(", ")));
                }
                Err(d)
            }
            (2, Some((_, Kind::Library(spec)))) => {
                let connector = &end.parts[1].name;
                Ok(End::Leaf { name: flat(prefix, &end.text()), ty: spec.connector(connector).map(|(_, c)| c.ty) })
            }
            (2, Some((_, Kind::User(d)))) => {
                let connector = &end.parts[1];
                match d.declarations.iter().find_map(|decl| match decl {
                    Declaration::Component(c) if c.name.name == connector.name => Some(c),
                    _ => None,
                }) {
                    Some(c) => match resolve_kind(self.index, &c.kind) {
                        Ok(Kind::Connector(ty)) => Ok(End::Declared {
                            name: flat(prefix, &end.text()),
                            ty,
                            declaration: c.span,
                            owner: d.name.name.clone(),
                        }),
                        _ => Err(Diagnostic::error(format!(
                            "`{}` is a component inside `{}`, not one of its connectors",
                            connector.name, d.name.name
                        ))
                        .primary(connector.span, "not a connector")
                        .help(format!(
                            "declare a connector in `{}` (`frame_a = Frame3D()`), connect it to `{}` inside, and connect to it here",
                            d.name.name, connector.name
                        ))),
                    },
                    None => {
                        let connectors = connector_names(Kind::User(d));
                        let mut diag =
                            Diagnostic::error(format!("`{}` has no connector `{}`", d.name.name, connector.name))
                                .primary(connector.span, "unknown connector")
                                .secondary(d.header, format!("`{}` is defined here", d.name.name));
                        if let Some(s) = did_you_mean(&connector.name, connectors.iter().map(String::as_str)) {
                            diag = diag.help(s);
                        }
                        diag = if connectors.is_empty() {
                            diag.note(format!(
                                "`{}` declares no connectors; declare one with `frame_a = Frame3D()` and connect it inside",
                                d.name.name
                            ))
                        } else {
                            diag.note(format!("its connectors are: {}", connectors.join(", ")))
                        };
                        Err(diag)
                    }
                }
            }
            (2, Some((_, Kind::Connector(_)))) => {
                Err(Diagnostic::error(format!("`{}` is a connector; connect it as a whole", first.name))
                    .primary(end.span, "a part of a connector")
                    .help(format!("write `{}`", first.name)))
            }
            (n, Some(_)) if n > 2 => Err(Diagnostic::error("connections reach only one level into components")
                .primary(end.span, "reaches into a component's components")
                .help(format!(
                    "declare a connector in `{}`'s component, connect it inside, and connect to `{}.<connector>` here",
                    first.name, first.name
                ))),
            _ => {
                let names: Vec<&str> = subs.iter().map(|(c, _)| c.name.name.as_str()).collect();
                let mut d = Diagnostic::error(format!("`{owner}` has no component or connector `{}`", first.name))
                    .primary(first.span, "unknown name");
                if let Some(s) = did_you_mean(&first.name, names.iter().copied()) {
                    d = d.help(s);
                }
                Err(d)
            }
        }
    }

    /// An engine component, with its parameters and start values.
    fn library_component(
        &mut self,
        spec: &'static ComponentSpec,
        name: &str,
        decl: &ComponentDecl,
        modifiers: Vec<Mod>,
        within: &[(String, Span)],
    ) -> Result<(), Diagnostic> {
        if self.model.components.len() >= MAX_COMPONENTS {
            return Err(Diagnostic::error(format!("the model has more than {MAX_COMPONENTS} components"))
                .primary(decl.span, "one too many")
                .help("check for components that contain many copies of each other"));
        }
        self.map.add_component(name, ComponentSite { declaration: decl.span, within: within.to_vec() });
        let mut params = Vec::new();
        let mut initial = Vec::new();
        let mut guess = Vec::new();
        for m in modifiers {
            if m.has_nested
                && spec.param(&m.name.name).is_some()
                && !spec.variables.iter().any(|v| v.name == m.name.name)
            {
                return Err(start_value_of_parameter(spec, decl, &m));
            }
            match (m.value, m.has_nested) {
                (Some((value, span)), false) => {
                    params.push((m.name.name.clone(), engine_value(&value, span, &m.name.name)?));
                    self.map.add_member(name, &m.name.name, MemberSite { name: m.name.span, value: Some(span) });
                }
                (None, true) => {
                    for attribute in m.nested {
                        let list = match attribute.name.name.as_str() {
                            "initial" => &mut initial,
                            "guess" => &mut guess,
                            other => return Err(unknown_attribute(other, &attribute, &m.name.name)),
                        };
                        let Some((value, span)) = attribute.value else {
                            return Err(Diagnostic::error(format!("`{}` needs a value", attribute.name.name))
                                .primary(attribute.span, "no value"));
                        };
                        if !attribute.nested.is_empty() || attribute.has_nested {
                            return Err(Diagnostic::error("attributes take a value, not modifiers")
                                .primary(attribute.span, "unexpected `(...)`"));
                        }
                        self.map.add_member(name, &m.name.name, MemberSite { name: m.name.span, value: Some(span) });
                        if value == Val::Missing {
                            // No start value; the name must still be a variable of the kind.
                            if !spec.variables.iter().any(|v| v.name == m.name.name) {
                                return Err(unknown_variable(spec, &m.name));
                            }
                            continue;
                        }
                        list.push((m.name.name.clone(), engine_value(&value, span, &m.name.name)?));
                    }
                }
                (Some(_), true) => {
                    return Err(Diagnostic::error(format!("`{}(...) = value` is not supported yet", m.name.name))
                        .primary(m.span, "not supported yet")
                        .help(format!(
                            "give a parameter value, `{} = ...`, or attributes, `{}(initial = ...)`",
                            m.name.name, m.name.name
                        )))
                }
                (None, false) => {}
            }
        }
        let instance = self.model.add(name, spec.kind);
        for (p, v) in params {
            instance.set(&p, v);
        }
        for (p, v) in initial {
            instance.initial(&p, v);
        }
        for (p, v) in guess {
            instance.guess(&p, v);
        }
        Ok(())
    }
}

fn check_unique<'b>(names: impl Iterator<Item = &'b Ident>) -> Result<(), Diagnostic> {
    let mut seen: HashMap<&str, Span> = HashMap::new();
    for n in names {
        if let Some(first) = seen.insert(&n.name, n.span) {
            return Err(Diagnostic::error(format!("`{}` is declared twice", n.name))
                .primary(n.span, "declared again here")
                .secondary(first, "first declared here")
                .help("give each declaration its own name"));
        }
    }
    Ok(())
}

/// Resolves the kind of a declaration: a user component, a connector type,
/// or a library component from the engine's registry.
fn resolve_kind<'a>(index: &Index<'a>, kind: &Path) -> Result<Kind<'a>, Diagnostic> {
    let text = kind.text();
    if let Some(def) = index.components.get(text.as_str()) {
        return Ok(Kind::User(def));
    }
    if let Some(ty) = CONNECTOR_TYPES.iter().find(|t| t.name() == kind.last().name) {
        return Ok(Kind::Connector(*ty));
    }
    if let Some(spec) = lookup(&text) {
        return Ok(Kind::Library(spec));
    }
    if index.analyses.contains_key(text.as_str()) {
        return Err(Diagnostic::error(format!("`{text}` is an analysis, not a component"))
            .primary(kind.span, "an analysis")
            .help("analyses simulate components; use a component here"));
    }
    let bare = multibody::components::canonical_kind(&text);
    let candidates: Vec<&str> = registry()
        .iter()
        .map(|s| s.kind)
        .chain(index.components.keys().copied())
        .chain(CONNECTOR_TYPES.iter().map(|t| t.name()))
        .collect();
    let mut d = Diagnostic::error(format!("unknown component kind `{text}`"))
        .primary(kind.span, "not a library component or a component of these files");
    if let Some(s) = did_you_mean(&bare, candidates.iter().copied()) {
        d = d.help(s);
    }
    Err(d.note("`multibody list` shows every library component"))
}

fn connector_names(kind: Kind) -> Vec<String> {
    match kind {
        Kind::Library(spec) => spec.public_connectors().map(|c| c.name.to_string()).collect(),
        Kind::User(def) => def
            .declarations
            .iter()
            .filter_map(|d| match d {
                Declaration::Component(c) if CONNECTOR_TYPES.iter().any(|t| t.name() == c.kind.last().name) => {
                    Some(c.name.name.clone())
                }
                _ => None,
            })
            .collect(),
        Kind::Connector(_) => Vec::new(),
    }
}

/// The engine's form of a value, or why there is none.
fn engine_value(value: &Val, span: Span, name: &str) -> Result<multibody::Value, Diagnostic> {
    value.to_engine().ok_or_else(|| {
        let d = Diagnostic::error(format!("`{name}` cannot take {}", value.describe()));
        match value {
            Val::Missing => d
                .primary(span, "`missing` is not a value")
                .help(format!("give `{name}` a value, or leave it out for its default; `missing` only removes start values, as in `r_0(initial = missing)`")),
            Val::Str(_) => d
                .primary(span, "a string")
                .help("library parameters take numbers, booleans, arrays of numbers and enumeration values"),
            _ => d
                .primary(span, "not a number, a vector or a matrix")
                .help("arrays hold numbers, and the rows of a matrix have equal lengths: `[[1, 0], [0, 1]]`"),
        }
    })
}

/// `initial body.m = 3` or `m(initial = 3)`, where `m` is a parameter of a
/// library component: it has a value, not a start value.
fn start_value_of_parameter(spec: &ComponentSpec, decl: &ComponentDecl, m: &Mod) -> Diagnostic {
    let (param, instance) = (&m.name.name, &decl.name.name);
    let attribute = m.nested.first();
    let what = match attribute.map(|a| a.name.name.as_str()) {
        Some("guess") => "a guess",
        _ => "a start value",
    };
    let mut d = Diagnostic::error(format!(
        "`{param}` is a parameter of {}, not a state: it takes a value, not {what}",
        spec.kind
    ))
    .primary(attribute.map_or(m.span, |a| a.span), format!("{what} for the parameter `{instance}.{param}`"));
    if let Some((_, span)) = &m.value {
        d = d.secondary(*span, "its value is given here");
    }
    let value = attribute
        .and_then(|a| a.value.as_ref())
        .and_then(|(v, _)| v.to_engine())
        .map_or_else(|| "...".to_string(), |v| v.to_string());
    d = d.help(format!("to set the parameter, give its value in the declaration of `{instance}`: `{param} = {value}`"));
    let states: Vec<&str> = spec.variables.iter().map(|v| v.name).collect();
    if !states.is_empty() {
        d = d.note(format!("the variables of {} are: {}", spec.kind, states.join(", ")));
    }
    d
}

fn unknown_attribute(attribute: &str, m: &Mod, variable: &str) -> Diagnostic {
    let d = Diagnostic::error(format!("`{attribute}` is not an attribute of a variable here"))
        .primary(m.name.span, "unknown attribute");
    match attribute {
        "start" | "fixed" => d.help(format!(
            "write `{variable}(initial = value)` for a start value that holds, or `{variable}(guess = value)` for a guess"
        )),
        _ => d.help(format!("variables take `initial` and `guess`: `{variable}(initial = 0)`")),
    }
}

fn unknown_variable(spec: &ComponentSpec, name: &Ident) -> Diagnostic {
    let names: Vec<&str> = spec.variables.iter().map(|v| v.name).collect();
    let mut d = Diagnostic::error(format!("{} has no variable `{}`", spec.kind, name.name))
        .primary(name.span, "unknown variable");
    if let Some(s) = did_you_mean(&name.name, names.iter().copied()) {
        d = d.help(s);
    }
    d.note(format!("its variables are: {}", names.join(", ")))
}
