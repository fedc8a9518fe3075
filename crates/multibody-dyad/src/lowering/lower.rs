//! Lowering: instantiates a model's top component into a
//! [`multibody::Model`]. User components are flattened into dotted names
//! (`pend.body`, `links[2].body`); their parameters are computed and passed
//! down; library components become engine components whose parameters the
//! engine checks; variables and equations become the model's equations,
//! and connections that reach connectors with equations become equations
//! between their quantities (potentials equal, flows loading the mechanics).

use crate::lowering::analysis::{analysis_options, Study};
use crate::lowering::connections::{ConnectionGraph, End};
use crate::lowering::relations::{self, EngineShapes, Entity, Flat, RelationsOut, WithEnv};
use crate::lowering::tunables::{in_model_files, type_facts, Tunable, TunableKind};
use crate::reports::diagnostics::{did_you_mean, Diagnostic};
use crate::reports::source_map::{ComponentSite, MemberSite, Shadowing, SourceMap};
use crate::semantics::connectors::Connector;
use crate::semantics::eval::{eval, Scope, Val};
use crate::semantics::extends::{effective, Effective};
use crate::semantics::index::Index;
use crate::semantics::modifiers::{apply_overrides, eval_modifiers, merge_outer, merge_same_level, Mod, Override};
use crate::semantics::scope::ParamScope;
use crate::semantics::types;
use crate::syntax::ast::*;
use crate::syntax::source::Span;
use crate::Lowered;
use multibody::components::{lookup, registry, ComponentSpec, ConnectorType, ImpossibleInertia, INERTIA_PARAMS};
use multibody::{Model, SimulationOptions};
use std::collections::HashMap;

/// How deeply user components may nest.
const MAX_NESTING: usize = 32;
/// How many library components one model may have.
pub const MAX_COMPONENTS: usize = 20_000;
/// What a declaration's kind names.
#[derive(Clone)]
enum Kind<'a> {
    Library(&'static ComponentSpec),
    User(&'a ComponentDef),
    Connector(Connector),
}

/// A connector that equations read: its name, type and the quantities used.
type UsedConnector = (String, Connector, Vec<String>);

/// One instance of a declaration: an element of an array has its index
/// in `env`.
struct Instance<'d, 'a> {
    local: String,
    decl: &'d ComponentDecl,
    kind: Kind<'a>,
    env: relations::Env,
}

/// Modifiers by the name of what they modify.
type ModsByName = HashMap<String, Vec<Mod>>;

/// The user component instance being made: its definition, its flattened
/// name, where it is declared, and the instances it is inside.
#[derive(Clone, Copy)]
struct Level<'x, 'a> {
    def: &'a ComponentDef,
    prefix: &'x str,
    site: Span,
    within: &'x [(String, Span)],
}

/// A component's declarations, sorted.
struct Declarations<'d, 'a> {
    /// Parameters, those the initialization solves for left out.
    params: Vec<&'d ParameterDecl>,
    /// Variables, with the parameters the initialization solves for.
    variables: Vec<&'d VariableDecl>,
    /// Sub-components and connectors, with what their kinds name.
    components: Vec<(&'d ComponentDecl, Kind<'a>)>,
    /// The names of things that change during the simulation: the
    /// components and the variables.
    runtime: Vec<String>,
}

impl<'d, 'a> Declarations<'d, 'a> {
    /// The component or connector declared as `name`.
    fn component(&self, name: &str) -> Option<(&'d ComponentDecl, Kind<'a>)> {
        self.components.iter().find(|(c, _)| c.name.name == name).map(|(c, k)| (*c, k.clone()))
    }
}

pub struct Lowerer<'a, 'i> {
    index: &'i Index<'a>,
    model: Model,
    map: SourceMap,
    warnings: Vec<Diagnostic>,
    graph: ConnectionGraph,
    /// The user components being instantiated, outermost first.
    stack: Vec<&'a str>,
    /// Every flattened name met so far.
    entities: HashMap<String, Entity>,
    /// Declared connectors that equations read, with the quantities used
    /// (none for a signal), and where each is in that list.
    used: Vec<UsedConnector>,
    used_index: HashMap<String, usize>,
    /// Each definition with what it extends merged in, made once.
    effective: HashMap<*const ComponentDef, std::rc::Rc<Effective>>,
    /// The simulated component's own output signals, with their
    /// declarations and types.
    outputs: Vec<(String, Span, Connector)>,
    /// The declared shapes of the engine's connectors.
    engine: EngineShapes,
    /// Inputs of sub-components that an enclosing component's equations
    /// name: those equations decide them (`smoother.u = sin(time)`).
    set_from_outside: std::collections::HashSet<String>,
    /// What a user may want to change, as met.
    tunables: Vec<Tunable>,
    /// The inputs of the model that the host sets: equations read each as
    /// the value of its `Input` component (`u`, one column).
    host_inputs: std::collections::HashSet<String>,
    /// Parameters of sub-components given a parameter the initialization
    /// decides (`Spring(c = c)` with `parameter c(guess = 100)`), by the
    /// sub-component's name: the parameter and the variable it follows.
    bound: HashMap<String, Vec<(Ident, String)>>,
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
            entities: HashMap::new(),
            used: Vec::new(),
            used_index: HashMap::new(),
            effective: HashMap::new(),
            outputs: Vec::new(),
            engine: index.engine_shapes(),
            set_from_outside: Default::default(),
            tunables: Vec::new(),
            host_inputs: Default::default(),
            bound: HashMap::new(),
        }
    }

    fn finish(mut self, name: &str, options: SimulationOptions, study: Option<Study>) -> Result<Lowered, Diagnostic> {
        self.model_outputs();
        self.connector_equations()?;
        let used: std::collections::HashSet<&str> = self.used.iter().map(|(n, _, _)| n.as_str()).collect();
        let warnings = self.graph.finish(&mut self.model, &mut self.map, &used);
        self.warnings.extend(warnings);
        Ok(Lowered {
            name: name.to_string(),
            model: self.model,
            options,
            from_analysis: study.is_some(),
            study: study.unwrap_or_default(),
            warnings: self.warnings,
            source_map: self.map,
            tunables: self.tunables,
        })
    }

    /// Declares a variable for a connector quantity (`pd.angle`,
    /// `spring.frame_a.f[1]`), declared at `span`.
    fn connector_variable(&mut self, name: String, origin: &str, span: Span) {
        self.map.variables.insert(name.clone(), span);
        self.model.variable(name).origin = origin.to_string();
    }

    /// Notes that equations read `connector` (a quantity `field` of it).
    fn use_connector(&mut self, connector: &str, ty: &Connector, field: Option<String>) {
        let k = match self.used_index.get(connector) {
            Some(&k) => k,
            None => {
                self.used.push((connector.to_string(), ty.clone(), Vec::new()));
                self.used_index.insert(connector.to_string(), self.used.len() - 1);
                self.used.len() - 1
            }
        };
        let entry = &mut self.used[k];
        if let Some(f) = field {
            if !entry.2.contains(&f) {
                entry.2.push(f);
            }
        }
    }

    /// The model's outputs: each top-level `RealOutput` that equations set
    /// or that is connected to a source becomes a variable, a column of the
    /// results (one that nothing drives keeps its warning).
    fn model_outputs(&mut self) {
        let sets = self.graph.sets();
        for (name, _, ty) in std::mem::take(&mut self.outputs) {
            let driven = self.used_index.contains_key(&name)
                || sets
                    .set_of(&name)
                    .is_some_and(|set| sets.library(set).iter().any(|(_, t)| *t == Some(ConnectorType::RealOutput)));
            if driven {
                self.use_connector(&name, &ty, None);
                self.model.outputs.push(name);
            }
        }
    }

    /// The equations connections imply for connectors that equations read:
    /// a signal equals its source; a frame's or flange's potentials equal
    /// the engine connector's it is joined to, and its flows load that
    /// connector; connectors joined to none make a network of equations
    /// ([`Self::network_potentials`], [`Self::network_flows`]).
    fn connector_equations(&mut self) -> Result<(), Diagnostic> {
        let sets = self.graph.sets();
        let used = self.used.clone();
        // The used connectors of each set, sets in the order first used.
        let mut order: Vec<usize> = Vec::new();
        let mut by_set: HashMap<usize, Vec<&UsedConnector>> = HashMap::new();
        let mut declared_by_set: HashMap<usize, Vec<String>> = HashMap::new();
        for (name, _) in self.graph.declared() {
            if let Some(set) = sets.set_of(name) {
                declared_by_set.entry(set).or_default().push(name.to_string());
            }
        }
        for u in &used {
            let Some(set) = sets.set_of(&u.0) else { continue };
            let list = by_set.entry(set).or_insert_with(|| {
                order.push(set);
                Vec::new()
            });
            list.push(u);
        }
        // The sets of declared connectors alone: their members, type and origin.
        let mut networks: Vec<(Vec<String>, Connector, String)> = Vec::new();
        for set in order {
            let members = by_set.remove(&set).expect("each set once");
            let library = sets.library(set);
            let ty = members[0].1.clone();
            // Connection equations point at a `connect` of the first member.
            let root = self.map.root.as_ref().map(|(_, s)| *s);
            let declared = self.graph.declaration_of(&members[0].0);
            let Some(span) = self.graph.connect_of(&members[0].0).or(declared).or(root) else { continue };
            let origin = self.origin(span);
            let eq = |model: &mut Model, a: &str, b: &str| {
                model.equations.equations.push(multibody::Equation {
                    lhs: multibody::Expr::var(a),
                    rhs: multibody::Expr::var(b),
                    origin: origin.clone(),
                })
            };
            if ty.is_signal() {
                for (m, _, _) in &members {
                    self.connector_variable(m.clone(), &origin, span);
                }
                let output = library.iter().find(|(_, t)| *t == Some(ConnectorType::RealOutput));
                if let Some((source, _)) = output {
                    for (m, _, _) in &members {
                        eq(&mut self.model, m, source);
                    }
                    continue;
                }
                let rep = members
                    .iter()
                    .find(|(_, t, _)| t.is_output())
                    .or_else(|| members.iter().find(|(m, _, _)| self.set_from_outside.contains(m)))
                    .map(|m| m.0.clone());
                let Some(rep) = rep else {
                    // Inputs that nothing drives read 0, as library inputs do.
                    for (m, _, _) in &members {
                        self.warnings.push(
                            Diagnostic::warning(format!("the input `{m}` is not connected to a source; it reads 0"))
                                .primary(span, "reads 0")
                                .help("connect it to an output, or give the value with a BlockComponents.Constant"),
                        );
                        self.model.equations.equations.push(multibody::Equation {
                            lhs: multibody::Expr::var(m.as_str()),
                            rhs: multibody::Expr::Const(0.0),
                            origin: origin.clone(),
                        });
                    }
                    continue;
                };
                for (m, _, _) in members.iter().filter(|(m, _, _)| *m != rep) {
                    eq(&mut self.model, m, &rep);
                }
                if let Some((input, _)) = library.iter().find(|(_, t)| *t == Some(ConnectorType::RealInput)) {
                    eq(&mut self.model, input, &rep);
                }
                continue;
            }
            let same: Vec<&(String, Option<ConnectorType>)> =
                library.iter().filter(|(_, t)| t.is_none_or(|t| ty.meets_engine(t))).collect();
            if let Some((anchor, _)) = same.first() {
                // Joined to the mechanics: potentials are its, flows load it.
                for (m, _, quantities) in &members {
                    let flows = quantities.iter().any(|q| ty.field(q).is_some_and(|f| f.flow));
                    for field in &ty.fields {
                        let names = relations::scalar_names(&format!("{m}.{}", field.name), &field.dims);
                        if field.flow && flows {
                            for n in &names {
                                self.connector_variable(n.clone(), &origin, span);
                            }
                        } else if !field.flow && quantities.contains(&field.name) {
                            let theirs = relations::scalar_names(&format!("{anchor}.{}", field.name), &field.dims);
                            for (n, t) in names.iter().zip(&theirs) {
                                self.connector_variable(n.clone(), &origin, span);
                                eq(&mut self.model, n, t);
                            }
                        }
                    }
                    if flows {
                        let flow_names = |field: &str| relations::scalar_names(&format!("{m}.{field}"), &[3]);
                        let flow = match ty.engine {
                            Some(ConnectorType::Frame2D) => multibody::Flow::Frame2D {
                                connector: anchor.clone(),
                                force: [format!("{m}.fx"), format!("{m}.fy")],
                                torque: format!("{m}.tau"),
                            },
                            Some(ConnectorType::Frame) => {
                                let (f, t) = (flow_names("f"), flow_names("tau"));
                                multibody::Flow::Frame {
                                    connector: anchor.clone(),
                                    force: [f[0].clone(), f[1].clone(), f[2].clone()],
                                    torque: [t[0].clone(), t[1].clone(), t[2].clone()],
                                }
                            }
                            _ => {
                                let field = ty.fields.iter().find(|f| f.flow).expect("a 1-D connector has a flow");
                                multibody::Flow::Flange {
                                    connector: anchor.clone(),
                                    value: format!("{m}.{}", field.name),
                                }
                            }
                        };
                        self.model.equations.flows.push(flow);
                    }
                }
                continue;
            }
            if ty.is_frame() {
                return Err(Diagnostic::error(format!(
                    "the frame `{}` is joined to no body, joint or World: nothing moves it",
                    members[0].0
                ))
                .primary(span, "its motion comes from nothing")
                .help("connect it to a library component (a Body, a joint, the World's frame_b); equations give frames forces, not motion"));
            }
            let declared = declared_by_set.remove(&set).unwrap_or_default();
            self.network_potentials(&declared, &ty, &origin, span);
            networks.push((declared, ty, origin));
        }
        self.network_flows(&networks);
        Ok(())
    }

    /// The variables of a set of declared connectors that no engine
    /// component joins (pins, heat ports, and flanges between components
    /// written in equations), and their potentials made equal.
    fn network_potentials(&mut self, members: &[String], ty: &Connector, origin: &str, span: Span) {
        for field in &ty.fields {
            let first = relations::scalar_names(&format!("{}.{}", members[0], field.name), &field.dims);
            for m in members {
                let names = relations::scalar_names(&format!("{m}.{}", field.name), &field.dims);
                for (n, f) in names.iter().zip(&first) {
                    self.connector_variable(n.clone(), origin, span);
                    if !field.flow && n != f {
                        self.model.equations.equations.push(multibody::Equation {
                            lhs: multibody::Expr::var(n),
                            rhs: multibody::Expr::var(f),
                            origin: origin.to_string(),
                        });
                    }
                }
            }
        }
    }

    /// The flow equations of the sets of declared connectors alone
    /// (`networks`: members, type, origin), all sets at once: at each level
    /// of the hierarchy the flows into the sub-components' connectors equal
    /// what enters through the component's own (Modelica's rule: a
    /// connector connected from nowhere takes no flow).
    fn network_flows(&mut self, networks: &[(Vec<String>, Connector, String)]) {
        let mut network_of: HashMap<&str, usize> = HashMap::new();
        for (k, (members, _, _)) in networks.iter().enumerate() {
            network_of.extend(members.iter().map(|m| (m.as_str(), k)));
        }
        let names: Vec<&str> = networks.iter().flat_map(|(members, _, _)| members.iter().map(String::as_str)).collect();
        for flow_set in self.graph.flow_sets(&names) {
            if flow_set.inside.is_empty() && flow_set.outside.len() == 1 {
                // What enters from outside is decided there.
                continue;
            }
            let any = flow_set.inside.first().or(flow_set.outside.first()).expect("a set has a member");
            let (_, ty, origin) = &networks[network_of[any.as_str()]];
            for field in ty.fields.iter().filter(|f| f.flow) {
                let scalars = |m: &String| relations::scalar_names(&format!("{m}.{}", field.name), &field.dims);
                let inside: Vec<Vec<String>> = flow_set.inside.iter().map(scalars).collect();
                let outside: Vec<Vec<String>> = flow_set.outside.iter().map(scalars).collect();
                for k in 0..field.dims.iter().product::<usize>() {
                    let sum = |list: &[Vec<String>]| {
                        let terms = list.iter().map(|names| multibody::Expr::var(names[k].as_str()));
                        multibody::math::symbolic::balanced(terms, |a, b| a + b)
                    };
                    let (lhs, rhs) = match (sum(&inside), sum(&outside)) {
                        (Some(a), Some(b)) => (a, b),
                        (Some(a), None) => (a, multibody::Expr::Const(0.0)),
                        (None, Some(b)) => (b, multibody::Expr::Const(0.0)),
                        (None, None) => continue,
                    };
                    self.model.equations.equations.push(multibody::Equation { lhs, rhs, origin: origin.clone() });
                }
            }
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
        lowerer.finish(&def.name.name, SimulationOptions::default(), None)
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
        let (options, study) = analysis_options(analysis, base_modifiers, &mut lowerer.warnings)?;
        lowerer.instantiate(def, "", model_modifiers, model.span, &[])?;
        lowerer.finish(&analysis.name.name, options, Some(study))
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
        self.enter(def, site)?;
        let effective = self.effective_of(def)?;
        check_unique(effective.declarations.iter().map(Declaration::name))?;
        let bound = self.bound.get(prefix).cloned().unwrap_or_default();
        let solved = solved_parameters(&effective, &modifiers, &bound, def)?;
        let decls = self.declarations(&effective, &solved)?;

        // Modifiers from outside: parameter values, start values of
        // variables, and modifiers of sub-components.
        let mut scope = ParamScope::new(name, decls.params.clone(), decls.runtime.clone(), site, &self.index.aliases);
        let (forwarded, mut variable_mods) = sort_modifiers(def, &decls, modifiers, &mut scope)?;
        scope.resolve_all()?;
        self.parameter_tunables(prefix, &decls.params, &mut scope)?;

        // The relations with their structure unrolled: `for` loops, and
        // `if` and `switch` on parameters.
        let flats = relations::expand(&effective.relations, &mut scope, &decls.runtime, &mut Vec::new())?;
        let (subs, absent) = self.instances(prefix, &decls, &mut scope)?;
        let mut consumed = vec![false; flats.len()];
        let initial = start_modifiers(&flats, &decls, &subs, &absent, &mut scope, &mut variable_mods, &mut consumed)?;
        let surfaces = surfaces(prefix, &flats, &subs, &mut scope, &mut consumed)?;

        if prefix.is_empty() {
            // An input of the model that its own equations give (`u =
            // sin(time)`) is decided there, not by the host.
            for f in &flats {
                if let Flat::Equation { lhs, rhs, .. } = f {
                    for side in [lhs, rhs] {
                        if let Some(path) = side.as_path().filter(|p| p.parts.len() == 1) {
                            self.set_from_outside.insert(path.parts[0].name.clone());
                        }
                    }
                }
            }
        }
        let level = Level { def, prefix, site, within };
        self.subcomponents(&level, &subs, &solved, &mut scope, initial, forwarded)?;
        for (component, road) in surfaces {
            if let Some(c) = self.model.component_mut(&component) {
                c.surface(road);
            }
        }
        self.own_variables(prefix, name, &decls.variables, &solved, variable_mods, &mut scope)?;
        self.connections(&level, &flats, &subs, &absent, &mut scope)?;
        self.own_relations(prefix, &flats, &consumed, &decls, &mut scope)?;
        self.stack.pop();
        Ok(())
    }

    /// Lists the numeric scalar parameters of the model's files among the
    /// tunables, with the values `scope` has computed (final ones cannot
    /// be changed and are left out).
    fn parameter_tunables(
        &mut self,
        prefix: &str,
        params: &[&ParameterDecl],
        scope: &mut ParamScope,
    ) -> Result<(), Diagnostic> {
        for p in params {
            if p.variability == Variability::Final || !in_model_files(p.span) {
                continue;
            }
            let Some(&Val::Number(value)) = scope.value(&p.name.name) else { continue };
            let Some(facts) = type_facts(&p.ty, &self.index.aliases, scope)? else { continue };
            self.tunables.push(Tunable {
                path: flat(prefix, &p.name.name),
                kind: TunableKind::Parameter,
                value,
                unit: facts.unit,
                doc: p.doc.clone(),
                min: facts.min,
                max: facts.max,
                integer: facts.integer,
                derived: scope.derived.contains(&p.name.name),
                span: p.span,
            });
        }
        Ok(())
    }

    /// Enters the user component `def`, used at `site`: one that is
    /// partial, contains itself or nests too deeply is an error.
    fn enter(&mut self, def: &'a ComponentDef, site: Span) -> Result<(), Diagnostic> {
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
        Ok(())
    }

    /// `def` with what it extends merged in, made once per definition.
    fn effective_of(&mut self, def: &ComponentDef) -> Result<std::rc::Rc<Effective>, Diagnostic> {
        Ok(match self.effective.get(&(def as *const ComponentDef)) {
            Some(e) => e.clone(),
            None => {
                let e = std::rc::Rc::new(effective(self.index, def)?);
                self.effective.insert(def as *const ComponentDef, e.clone());
                e
            }
        })
    }

    /// The declarations of a component sorted by what they declare, the
    /// kinds of its components resolved.
    fn declarations<'d>(
        &mut self,
        effective: &'d Effective,
        solved: &'d [VariableDecl],
    ) -> Result<Declarations<'d, 'a>, Diagnostic> {
        let params: Vec<&ParameterDecl> = effective
            .declarations
            .iter()
            .filter_map(|d| if let Declaration::Parameter(p) = d { Some(p) } else { None })
            .filter(|p| !solved.iter().any(|v| v.name.name == p.name.name))
            .collect();
        let variables: Vec<&VariableDecl> = effective
            .declarations
            .iter()
            .filter_map(|d| if let Declaration::Variable(v) = d { Some(v) } else { None })
            .chain(solved)
            .collect();
        let mut decls: Vec<(&ComponentDecl, Kind<'a>)> = Vec::new();
        for d in &effective.declarations {
            if let Declaration::Component(c) = d {
                let kind = resolve_kind(self.index, &c.kind)?;
                if let (Kind::User(user), Some(spec)) = (&kind, lookup(&c.kind.text())) {
                    self.map.shadowing.push(Shadowing {
                        library_kind: spec.kind.to_string(),
                        used: c.span,
                        defined: user.name.span,
                    });
                }
                decls.push((c, kind));
            }
        }
        let runtime: Vec<String> = decls
            .iter()
            .map(|(c, _)| c.name.name.clone())
            .chain(variables.iter().map(|v| v.name.name.clone()))
            .collect();
        Ok(Declarations { params, variables, components: decls, runtime })
    }

    /// The instances of the components: arrays and conditional components
    /// resolved. Also the names of the components that are absent.
    fn instances<'d>(
        &mut self,
        prefix: &str,
        decls: &Declarations<'d, 'a>,
        scope: &mut ParamScope,
    ) -> Result<(Vec<Instance<'d, 'a>>, Vec<String>), Diagnostic> {
        let mut subs: Vec<Instance<'d, 'a>> = Vec::new();
        let mut absent: Vec<String> = Vec::new();
        for (decl, kind) in &decls.components {
            let (decl, kind) = (*decl, kind.clone());
            if let Some(condition) = &decl.condition {
                let v = eval(condition, scope)?;
                let present = match v {
                    Val::Bool(b) => b,
                    other => {
                        return Err(Diagnostic::error(format!(
                            "the condition of a component must be true or false, but this is {}",
                            other.describe()
                        ))
                        .primary(condition.span, "not a condition"))
                    }
                };
                if !present {
                    absent.push(decl.name.name.clone());
                    continue;
                }
            }
            match &decl.array {
                None => subs.push(Instance { local: decl.name.name.clone(), decl, kind, env: Vec::new() }),
                Some((var, range)) => {
                    let values = relations::range_values(range, scope, &[])?;
                    self.entities.insert(flat(prefix, &decl.name.name), Entity::Array(values.len()));
                    for (k, value) in values.into_iter().enumerate() {
                        subs.push(Instance {
                            local: format!("{}[{}]", decl.name.name, k + 1),
                            decl,
                            kind: kind.clone(),
                            env: vec![(var.name.clone(), value)],
                        });
                    }
                }
            }
        }
        Ok((subs, absent))
    }

    /// Makes the instances `subs` of the component at `level`, with the
    /// modifiers its declarations give, the start values its `initial`s
    /// give, and the modifiers `forwarded` from outside.
    fn subcomponents(
        &mut self,
        level: &Level,
        subs: &[Instance<'_, 'a>],
        solved: &[VariableDecl],
        scope: &mut ParamScope,
        mut initial: ModsByName,
        mut forwarded: ModsByName,
    ) -> Result<(), Diagnostic> {
        let Level { def, prefix, site, within } = *level;
        let name = def.name.name.as_str();
        for instance in subs {
            let child = flat(prefix, &instance.local);
            let decl = instance.decl;
            // A parameter given one the initialization decides follows it
            // as a variable; the rest are values.
            let (bound, values): (Vec<&Modifier>, Vec<&Modifier>) = decl.modifiers.iter().partition(|m| {
                // A connector has no parameters: its modifiers stay values (and are refused).
                !matches!(instance.kind, Kind::Connector(_)) && solved_source(m, solved).is_some()
            });
            let values: Vec<Modifier> = values.into_iter().cloned().collect();
            let mut kind = instance.kind.clone();
            if !bound.is_empty() {
                let sources = bound
                    .iter()
                    .filter_map(|m| Some((m.name.clone(), flat(prefix, solved_source(m, solved)?))))
                    .collect();
                if let Kind::Library(spec) = kind {
                    kind = self.equation_form(decl, spec, &bound)?;
                }
                self.bound.insert(child.clone(), sources);
            }
            let mut sub_scope = WithEnv { scope, env: &instance.env };
            let own = eval_modifiers(&values, &mut sub_scope)?;
            let own = merge_same_level(own, initial.remove(&instance.local).unwrap_or_default())?;
            let outer = forwarded.get(&decl.name.name).cloned().unwrap_or_default();
            let merged = merge_outer(outer, own)?;
            // What is given for this element wins over what is given for all.
            let merged = match forwarded.remove(&instance.local).filter(|_| decl.array.is_some()) {
                Some(element) => merge_outer(element, merged)?,
                None => merged,
            };
            match kind {
                Kind::Library(spec) => {
                    self.entities.insert(child.clone(), Entity::Library(spec));
                    self.library_component(spec, &child, decl, merged, within)?
                }
                Kind::User(sub_def) => {
                    self.entities.insert(child.clone(), Entity::User);
                    let mut inner = vec![(child.clone(), decl.span)];
                    inner.extend(within.iter().cloned());
                    let given = given_values(&merged);
                    self.instantiate(sub_def, &child, merged, decl.span, &inner)
                        .map_err(|d| within_instance(d, decl.span, &child, &given))?;
                }
                Kind::Connector(ty) => {
                    if let Some(m) = merged.first() {
                        self.warnings.push(
                            Diagnostic::warning("modifiers of connectors have no effect here and are ignored")
                                .primary(m.span, "ignored"),
                        );
                    }
                    self.entities.insert(child.clone(), Entity::Connector(ty.clone()));
                    self.graph.declare(child.clone(), ty.clone(), decl.span, name.to_string());
                    if prefix.is_empty() && ty.is_signal() && !(ty.is_input() && self.set_from_outside.contains(&child))
                    {
                        self.boundary_signal(&child, &ty, decl.span, 0.0)?;
                    }
                }
            }
        }
        if let Some((key, mods)) = forwarded.iter().find(|(k, _)| k.ends_with(']')) {
            let span = mods.first().map_or(site, |m| m.span);
            return Err(Diagnostic::error(format!("`{name}` has no component `{key}`: the index is out of range"))
                .primary(span, "no such element")
                .help("index the array from 1 to its length"));
        }
        Ok(())
    }

    /// The library's equation form of built-in component `spec` (declared
    /// `decl`), for parameters `bound` to variables: the built-in one
    /// takes constants only. `TranslationalComponents.Spring` becomes
    /// `TranslationalComponents.Acausal.Spring`, which moves the same.
    fn equation_form(
        &self,
        decl: &ComponentDecl,
        spec: &'static ComponentSpec,
        bound: &[&Modifier],
    ) -> Result<Kind<'a>, Diagnostic> {
        let written = decl.kind.text();
        let form = written.rsplit_once('.').map(|(package, name)| format!("{package}.Acausal.{name}"));
        if let Some(def) = form.as_deref().and_then(|f| self.index.component(f)) {
            return Ok(Kind::User(def));
        }
        let first = bound[0];
        Err(Diagnostic::error(format!(
            "`{}` of the built-in `{}` takes a constant, and `{}` is decided by the initialization",
            first.name.name,
            spec.kind,
            first.value.as_ref().map_or(String::new(), crate::lowering::symbolic::reference_text)
        ))
        .primary(first.span, "a parameter with only a guess")
        .help(
            "write the component in Dyad (the library's equation forms are in `*.Acausal`: Spring, Damper, \
             SpringDamper, ...), so that its parameter can follow a variable",
        ))
    }

    /// The component's own variables; `input` and `output` ones are
    /// signal connectors too. Parameters the initialization solves for
    /// are constant in time.
    fn own_variables(
        &mut self,
        prefix: &str,
        owner: &str,
        variables: &[&VariableDecl],
        solved: &[VariableDecl],
        mut variable_mods: ModsByName,
        scope: &mut ParamScope,
    ) -> Result<(), Diagnostic> {
        for v in variables {
            self.variable(prefix, owner, v, variable_mods.remove(&v.name.name).unwrap_or_default(), scope)?;
        }
        let bound = self.bound.remove(prefix).unwrap_or_default();
        for v in solved {
            // Constant in time, its start free: `der(k) = 0` and a guess;
            // or equal to the enclosing component's parameter it is given.
            let full = flat(prefix, &v.name.name);
            let origin = self.origin(v.span);
            let dims = relations::dims(&v.ty, scope)?;
            let source = bound.iter().find(|(p, _)| p.name == v.name.name).map(|(_, s)| s);
            let sources = source.map(|s| relations::scalar_names(s, &dims));
            for (k, n) in relations::scalar_names(&full, &dims).into_iter().enumerate() {
                if let Some(var) = self.model.equations.variables.iter_mut().find(|var| var.name == n) {
                    var.fixed = false;
                }
                let (lhs, rhs) = match &sources {
                    Some(sources) => (multibody::Expr::var(n), multibody::Expr::var(sources[k].clone())),
                    None => (multibody::Expr::der(multibody::Expr::var(n)), multibody::Expr::Const(0.0)),
                };
                self.model.equations.equations.push(multibody::Equation { lhs, rhs, origin: origin.clone() });
            }
        }
        Ok(())
    }

    /// The `connect`s of the component at `level` (those of absent
    /// components left out), into the connection graph.
    fn connections(
        &mut self,
        level: &Level<'_, 'a>,
        flats: &[Flat],
        subs: &[Instance],
        absent: &[String],
        scope: &mut ParamScope,
    ) -> Result<(), Diagnostic> {
        let Level { def, prefix, .. } = *level;
        let by_local: HashMap<&str, usize> = subs.iter().enumerate().map(|(k, i)| (i.local.as_str(), k)).collect();
        for flat_relation in flats {
            let Flat::Connect { ends, env } = flat_relation else { continue };
            let mut resolved = Vec::with_capacity(ends.len());
            let mut skip = false;
            for end in ends.iter() {
                let path = relations::connect_path(end, scope, env)?;
                if absent.contains(&path.parts[0].name) {
                    skip = true;
                    break;
                }
                resolved.push((self.connect_end(&path, prefix, def, subs, &by_local)?, end.span));
            }
            if !skip {
                self.graph.connect(resolved, prefix)?;
            }
        }
        Ok(())
    }

    /// The component's equations, initial equations, guesses and
    /// assertions (the relations not `consumed` already), and the
    /// equations of its variables' bindings.
    fn own_relations(
        &mut self,
        prefix: &str,
        flats: &[Flat],
        consumed: &[bool],
        decls: &Declarations,
        scope: &mut ParamScope,
    ) -> Result<(), Diagnostic> {
        let mut context = relations::Context {
            entities: &self.entities,
            variables: &self.model.equations.variables,
            engine: &self.engine,
            host_inputs: &self.host_inputs,
            prefix,
            scope,
            runtime: &decls.runtime,
            out: RelationsOut::new(self.map.origins.len()),
        };
        for (k, flat_relation) in flats.iter().enumerate() {
            if !consumed[k] {
                context.relation(flat_relation)?;
            }
        }
        for v in &decls.variables {
            if let Some(binding) = &v.binding {
                context.equation_of(
                    &Expr {
                        kind: ExprKind::Name(Path { parts: vec![v.name.clone()], span: v.name.span }),
                        span: v.name.span,
                    },
                    binding,
                    v.span,
                    &Vec::new(),
                )?;
            }
        }
        let out = context.out;
        self.add_relations(out);
        Ok(())
    }

    /// A variable of a user component: its scalars become variables of the
    /// model's equations, with their start values.
    fn variable(
        &mut self,
        prefix: &str,
        owner: &str,
        v: &VariableDecl,
        mods: Vec<Mod>,
        scope: &mut ParamScope,
    ) -> Result<(), Diagnostic> {
        let full = flat(prefix, &v.name.name);
        let dims = relations::dims(&v.ty, scope)?;
        if let Causality::Input | Causality::Output = v.causality {
            if !dims.is_empty() {
                return Err(Diagnostic::error("signal connectors that are arrays are not supported yet")
                    .primary(v.ty.span, "not supported yet")
                    .help("declare one signal per element"));
            }
            let signal =
                if v.causality == Causality::Input { ConnectorType::RealInput } else { ConnectorType::RealOutput };
            let ty = relations::engine_shape(&self.engine, signal);
            self.entities.insert(full.clone(), Entity::Connector(ty.clone()));
            self.graph.declare(full.clone(), ty.clone(), v.span, owner.to_string());
            if prefix.is_empty() && !(ty.is_input() && self.set_from_outside.contains(&full)) {
                let start = match &v.initial {
                    Some(e) => match eval(e, scope)? {
                        Val::Number(x) => x,
                        other => {
                            return Err(Diagnostic::error(format!(
                                "the start value of the signal `{full}` must be a number, not {}",
                                other.describe()
                            ))
                            .primary(e.span, "not a number"))
                        }
                    },
                    None => 0.0,
                };
                self.boundary_signal(&full, &ty, v.span, start)?;
            }
        } else {
            self.entities.insert(full.clone(), Entity::Variable(dims.clone()));
        }
        let names = relations::scalar_names(&full, &dims);
        // Start values: the declaration's `= initial v`, then modifiers;
        // with where each is written and whether it reads parameters.
        let mut start: Option<(Val, bool)> = None;
        let mut written: Option<(Span, bool)> = None;
        // The declaration's type attributes (`x::Length(guess = 1)`), then
        // its aliases': the first of each name holds.
        for attribute in types::resolve(&v.ty, &self.index.aliases)?.attributes {
            let fixed = match attribute.name.name.as_str() {
                "guess" => false,
                "initial" => true,
                "units" | "unit" | "min" | "max" | "display_units" | "nominal" => continue,
                other => {
                    return Err(Diagnostic::error(format!("`{other}` is not an attribute of a variable"))
                        .primary(attribute.name.span, "unknown attribute")
                        .help(format!(
                            "a variable's type takes `guess`, `units`, `min` and `max`: `{}::Real(guess = 1)`; \
                             a start value that holds is `initial {} = ...` among the relations",
                            v.name.name, v.name.name
                        )))
                }
            };
            if start.as_ref().is_some_and(|(_, f)| *f || !fixed) {
                continue;
            }
            let Some(e) = &attribute.value else { continue };
            let reads = scope.reads();
            start = Some((eval(e, scope)?, fixed));
            written = Some((e.span, scope.reads() != reads));
        }
        if let Some(e) = &v.initial {
            let reads = scope.reads();
            start = Some((eval(e, scope)?, true));
            written = Some((e.span, scope.reads() != reads));
        }
        for m in &mods {
            let fixed = match m.name.name.as_str() {
                "initial" => true,
                "guess" => false,
                other => return Err(unknown_attribute(other, m, &v.name.name)),
            };
            match &m.value {
                Some((Val::Missing, _)) => start = None,
                Some((value, span)) => {
                    start = Some((value.clone(), fixed));
                    written = Some((*span, m.derived));
                }
                None => {}
            }
        }
        if let (Some((Val::Number(x), true)), Some((span, derived)), Causality::Internal) =
            (&start, written, v.causality)
        {
            if in_model_files(span) {
                if let Some(facts) = type_facts(&v.ty, &self.index.aliases, scope)? {
                    self.tunables.push(Tunable {
                        path: full.clone(),
                        kind: TunableKind::Start,
                        value: *x,
                        unit: facts.unit,
                        doc: v.doc.clone(),
                        min: facts.min,
                        max: facts.max,
                        integer: false,
                        derived,
                        span: v.span,
                    });
                }
            }
        }
        let values: Vec<Option<f64>> = match &start {
            None => vec![None; names.len()],
            Some((value, _)) => {
                let mut flat_values = Vec::new();
                relations::flatten_val(value, &mut flat_values);
                if flat_values.len() != names.len() {
                    return Err(Diagnostic::error(format!(
                        "`{}` has {} values but its start value has {}",
                        v.name.name,
                        names.len(),
                        flat_values.len()
                    ))
                    .primary(v.span, "sizes differ"));
                }
                flat_values.into_iter().map(Some).collect()
            }
        };
        let origin = self.origin(v.span);
        for (n, value) in names.into_iter().zip(values) {
            self.map.variables.insert(n.clone(), v.span);
            let var = self.model.variable(n);
            var.start = value;
            var.fixed = start.as_ref().is_some_and(|(_, f)| *f);
            var.origin = origin.clone();
        }
        Ok(())
    }

    /// A signal connector of the simulated component itself: an input
    /// becomes an `Input` component of the same name, which the host sets
    /// while the model runs (its start value, if declared, until then); an
    /// output is one of the model's outputs.
    fn boundary_signal(&mut self, name: &str, ty: &Connector, span: Span, start: f64) -> Result<(), Diagnostic> {
        if ty.is_output() {
            self.outputs.push((name.to_string(), span, ty.clone()));
            return Ok(());
        }
        self.model.add(name, "Input").set("start", start);
        self.host_inputs.insert(name.to_string());
        self.map.add_component(name, ComponentSite { declaration: span, within: Vec::new() });
        // The input's signal is the library source the connector joins.
        let source = End::Leaf { name: format!("{name}.y"), ty: Some(ConnectorType::RealOutput) };
        let declared =
            End::Declared { name: name.to_string(), ty: ty.clone(), declaration: span, owner: String::new() };
        self.graph.connect(vec![(declared, span), (source, span)], "")
    }

    /// A name for `span` that engine messages carry back.
    fn origin(&mut self, span: Span) -> String {
        self.map.origins.push(span);
        SourceMap::origin_name(self.map.origins.len() - 1)
    }

    /// Adds what the relations of an instance give to the model.
    fn add_relations(&mut self, out: RelationsOut) {
        self.map.origins.extend(out.origins);
        let equations = &mut self.model.equations;
        equations.equations.extend(out.equations);
        equations.initial.extend(out.initial);
        equations.whens.extend(out.whens);
        for (name, x) in out.guesses {
            if let Some(v) = equations.variables.iter_mut().find(|v| v.name == name) {
                v.start = Some(x);
            }
        }
        for u in out.uses {
            self.use_connector(&u.connector, &u.ty, u.field);
            if u.set_from_outside {
                self.set_from_outside.insert(u.connector);
            }
        }
    }

    /// What one end of a `connect` in `def` names.
    fn connect_end(
        &self,
        end: &Path,
        prefix: &str,
        def: &'a ComponentDef,
        subs: &[Instance],
        by_local: &HashMap<&str, usize>,
    ) -> Result<End, Diagnostic> {
        let owner = def.name.name.as_str();
        let sub = |n: &str| by_local.get(n).map(|&k| (subs[k].decl, subs[k].kind.clone()));
        let first = &end.parts[0];
        let declared = |name: String, owner: String| -> Option<End> {
            match self.entities.get(&name) {
                Some(Entity::Connector(ty)) => Some(End::Declared {
                    declaration: self.graph.declaration_of(&name).unwrap_or(end.span),
                    name,
                    ty: ty.clone(),
                    owner,
                }),
                _ => None,
            }
        };
        match (end.parts.len(), sub(&first.name)) {
            (1, Some((decl, Kind::Connector(ty)))) => Ok(End::Declared {
                name: flat(prefix, &first.name),
                ty,
                declaration: decl.span,
                owner: owner.to_string(),
            }),
            (1, None) if declared(flat(prefix, &first.name), owner.to_string()).is_some() => {
                Ok(declared(flat(prefix, &first.name), owner.to_string()).expect("checked"))
            }
            (1, Some((_, kind))) => {
                let connectors = connector_names(self.index, kind);
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
                let child = flat(prefix, &first.name);
                if let Some(e) = declared(format!("{child}.{}", connector.name), d.name.name.clone()) {
                    return Ok(e);
                }
                let is_component = effective(self.index, d)
                    .map(|e| e.declarations.iter().any(|x| x.name().name == connector.name))
                    .unwrap_or(false);
                if is_component {
                    return Err(Diagnostic::error(format!(
                        "`{}` is a component inside `{}`, not one of its connectors",
                        connector.name, d.name.name
                    ))
                    .primary(connector.span, "not a connector")
                    .help(format!(
                        "declare a connector in `{}` (`frame_a = Frame3D()`), connect it to `{}` inside, and connect to it here",
                        d.name.name, connector.name
                    )));
                }
                let connectors = connector_names(self.index, Kind::User(d));
                let mut diag = Diagnostic::error(format!("`{}` has no connector `{}`", d.name.name, connector.name))
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
                if let Some((base, index)) = first.name.strip_suffix(']').and_then(|n| n.split_once('[')) {
                    if let Some(Entity::Array(n)) = self.entities.get(&flat(prefix, base)) {
                        return Err(Diagnostic::error(format!(
                            "index {index} is out of range for `{base}`, which has {n} elements"
                        ))
                        .primary(end.span, format!("must be from 1 to {n}"))
                        .help("check the range of the loop that indexes it"));
                    }
                }
                let names: Vec<&str> = subs.iter().map(|i| i.local.as_str()).collect();
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
        let mut guess_spans: Vec<(String, Span)> = Vec::new();
        for m in modifiers {
            if m.has_nested
                && spec.param(&m.name.name).is_some()
                && !spec.variables.iter().any(|v| v.name == m.name.name)
            {
                return Err(start_value_of_parameter(spec, decl, &m));
            }
            if let Some((_, span)) = &m.value {
                if spec.param(&m.name.name).is_none() && spec.variables.iter().any(|v| v.name == m.name.name) {
                    return Err(value_of_variable(spec, name, &m.name, *span));
                }
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
                        if let (Val::Number(x), "initial", true) =
                            (&value, attribute.name.name.as_str(), in_model_files(span))
                        {
                            let variable = spec.variables.iter().find(|v| v.name == m.name.name);
                            self.tunables.push(Tunable {
                                path: flat(name, &m.name.name),
                                kind: TunableKind::Start,
                                value: *x,
                                unit: variable.map(|v| v.unit.to_string()).filter(|u| !u.is_empty()),
                                doc: variable.map(|v| v.doc.to_string()).filter(|d| !d.is_empty()),
                                min: None,
                                max: None,
                                integer: false,
                                derived: attribute.derived,
                                span: decl.span,
                            });
                        }
                        if attribute.name.name == "guess" {
                            guess_spans.push((m.name.name.clone(), span));
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
        // A guess beside a start value that holds: the start keeps the value.
        for (variable, span) in guess_spans {
            if initial.iter().any(|(n, _)| *n == variable) {
                self.warnings.push(
                    Diagnostic::warning(format!(
                        "the guess of `{name}.{variable}` has no effect: its start value is given (`initial`), and \
                         the start keeps it"
                    ))
                    .primary(span, "no effect")
                    .help("give either `initial` (the start holds it) or `guess` (the start may move it), not both"),
                );
            }
        }
        if let Some(doubt) = impossible_inertia(spec, &params, &initial, &guess) {
            self.warnings.push(
                Diagnostic::warning(format!(
                    "no rigid mass distribution has the inertia of `{name}`: {}",
                    doubt.describe()
                ))
                .primary(decl.span, "no rigid body has this inertia")
                .help(
                    "a rigid body's largest principal moment is at most the sum of the other two; the model runs \
                     with the inertia as given, but check I_11 ... I_32 (about the centre of mass, resolved in \
                     frame_a)",
                ),
            );
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

/// The inertia of a library component that has one (`I_11 ... I_32`,
/// given or by default), when no rigid body can have it. One decided by
/// the initialization (a start value or a guess) is not known here.
fn impossible_inertia(
    spec: &ComponentSpec,
    params: &[(String, multibody::Value)],
    initial: &[(String, multibody::Value)],
    guess: &[(String, multibody::Value)],
) -> Option<ImpossibleInertia> {
    let mut values = [0.0; 6];
    for (value, name) in values.iter_mut().zip(INERTIA_PARAMS.map(|p| p.name)) {
        if initial.iter().chain(guess).any(|(p, _)| p == name) {
            return None;
        }
        *value = match params.iter().find(|(p, _)| p == name).map(|(_, v)| v) {
            Some(multibody::Value::Number(x)) => *x,
            Some(_) => return None,
            None => match spec.param(name)?.default {
                multibody::components::Default::Number(x) => x,
                _ => return None,
            },
        };
    }
    ImpossibleInertia::of(values)
}

/// A parameter with a guess and no value (none given here either) is
/// decided by the initialization: a variable that keeps its start. So is
/// a parameter `bound` to such a parameter of the enclosing component,
/// which it then follows.
fn solved_parameters(
    effective: &Effective,
    modifiers: &[Mod],
    bound: &[(Ident, String)],
    def: &ComponentDef,
) -> Result<Vec<VariableDecl>, Diagnostic> {
    let as_variable = |p: &ParameterDecl, initial: Option<Expr>| VariableDecl {
        doc: p.doc.clone(),
        causality: Causality::Internal,
        name: p.name.clone(),
        ty: TypeRef { attributes: Vec::new(), ..p.ty.clone() },
        binding: None,
        initial,
        span: p.span,
    };
    let params =
        || effective.declarations.iter().filter_map(|d| if let Declaration::Parameter(p) = d { Some(p) } else { None });
    let mut solved = Vec::new();
    for (name, _) in bound {
        let Some(p) = params().find(|p| p.name.name == name.name) else {
            return Err(Diagnostic::error(format!("`{}` has no parameter `{}`", def.name.name, name.name))
                .primary(name.span, "not a parameter of this component"));
        };
        solved.push(as_variable(p, None));
    }
    for p in params() {
        // A start or guess given from outside (`c(initial = 2)`, a tunable's
        // override) moves the guess; only a value makes it a parameter.
        if p.default.is_none()
            && !modifiers.iter().any(|m| m.name.name == p.name.name && m.value.is_some())
            && !bound.iter().any(|(b, _)| b.name == p.name.name)
        {
            if let Some(guess) = p.ty.attributes.iter().find(|a| a.name.name == "guess").and_then(|a| a.value.clone()) {
                solved.push(as_variable(p, Some(guess)));
            }
        }
    }
    Ok(solved)
}

/// The parameter of the enclosing component that modifier `m` gives, if
/// it is one the initialization decides (`c = c`, `c` with only a guess).
fn solved_source<'s>(m: &Modifier, solved: &'s [VariableDecl]) -> Option<&'s str> {
    let path = m.value.as_ref()?.as_path()?;
    let [only] = &path.parts[..] else { return None };
    if m.nested.is_some() {
        return None;
    }
    solved.iter().find(|v| v.name.name == only.name).map(|v| v.name.name.as_str())
}

/// Sorts the modifiers given from outside: parameter values go into
/// `scope`; the modifiers of sub-components (or of one element of an
/// array of them) and the start values of variables are returned, in
/// that order.
fn sort_modifiers(
    def: &ComponentDef,
    decls: &Declarations,
    modifiers: Vec<Mod>,
    scope: &mut ParamScope,
) -> Result<(ModsByName, ModsByName), Diagnostic> {
    let name = def.name.name.as_str();
    let Declarations { params, variables, components, .. } = decls;
    let decl_of = |n: &str| decls.component(n);
    let mut forwarded: ModsByName = HashMap::new();
    let mut variable_mods: ModsByName = HashMap::new();
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
                    if m.derived {
                        scope.derived.insert(key.to_string());
                    }
                }
                _ => {
                    return Err(Diagnostic::error(format!("`{key}` is a parameter; give it a value"))
                        .primary(m.span, "not a value")
                        .help(format!("write `{key} = ...`")))
                }
            }
        } else if variables.iter().any(|v| v.name.name == key) {
            if m.value.is_some() || !m.has_nested {
                return Err(Diagnostic::error(format!("`{key}` is a variable of `{name}`; give it a start value"))
                    .primary(m.span, "not a start value")
                    .help(format!("write `{key}(initial = ...)` or `{key}(guess = ...)`")));
            }
            variable_mods.insert(key.to_string(), m.nested);
        } else if let Some((c, kind)) = decl_of(key) {
            if matches!(kind, Kind::Connector(_)) {
                return Err(Diagnostic::error(format!("`{key}` is a connector of `{name}`; it takes no modifiers"))
                    .primary(m.span, "modifies a connector")
                    .secondary(c.span, "declared here"));
            }
            if m.value.is_some() {
                return Err(Diagnostic::error(format!("`{key}` is a component of `{name}`; it cannot be replaced"))
                    .primary(m.span, "replaces a component")
                    .help(format!("change its parameters instead: `{key}(m = 2)`")));
            }
            forwarded.insert(key.to_string(), m.nested);
        } else if key
            .strip_suffix(']')
            .and_then(|k| k.split_once('['))
            .and_then(|(base, _)| decl_of(base))
            .is_some_and(|(c, _)| c.array.is_some())
        {
            // One element of an array of components (`joints[1].Q_hat`
            // from an `initial` of the enclosing component): checked
            // against the array's range when its instances are made.
            forwarded.insert(key.to_string(), m.nested);
        } else {
            let names: Vec<&str> = params
                .iter()
                .map(|p| p.name.name.as_str())
                .chain(
                    components
                        .iter()
                        .filter(|(_, k)| !matches!(k, Kind::Connector(_)))
                        .map(|(c, _)| c.name.name.as_str()),
                )
                .chain(variables.iter().map(|v| v.name.name.as_str()))
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
    Ok((forwarded, variable_mods))
}

/// `initial a.b = v` (and `guess`) with a constant value act as
/// modifiers `a(b(initial = v))` of this level.
/// Returns them by component (`a`); those of the component's own
/// variables join `variable_mods`, where the start values given from
/// outside (an enclosing component, an override) win over them. The
/// relations taken are `consumed`.
fn start_modifiers(
    flats: &[Flat],
    decls: &Declarations,
    subs: &[Instance],
    absent: &[String],
    scope: &mut ParamScope,
    variable_mods: &mut ModsByName,
    consumed: &mut [bool],
) -> Result<ModsByName, Diagnostic> {
    let Declarations { params, variables, .. } = decls;
    let decl_of = |n: &str| decls.component(n);
    let mut initial: ModsByName = HashMap::new();
    let mut own_variables: ModsByName = HashMap::new();
    for (k, flat_relation) in flats.iter().enumerate() {
        let (lhs, rhs, span, env, attribute) = match flat_relation {
            Flat::Initial { lhs, rhs, span, env } => (*lhs, *rhs, *span, env, "initial"),
            Flat::Guess { lhs, rhs, span, env } => (*lhs, *rhs, *span, env, "guess"),
            _ => continue,
        };
        let Some(target) = relations::start_target(lhs, scope, env)? else { continue };
        let first = &target[0];
        let is_sub = subs.iter().any(|i| i.local == first.name && !matches!(i.kind, Kind::Connector(_)));
        let is_variable = target.len() == 1 && variables.iter().any(|v| v.name.name == first.name);
        if !is_sub && !is_variable {
            if target.len() >= 2 || decl_of(&first.name).is_some() || absent.contains(&first.name) {
                continue;
            }
            if params.iter().any(|p| p.name.name == first.name) {
                return Err(Diagnostic::error(format!("`initial {}` names no variable of a component", first.name))
                    .primary(lhs.span, "not a variable of a sub-component")
                    .help(format!("`{}` is a parameter: give its value in its declaration", first.name)));
            }
            continue;
        }
        let Ok(v) = eval(rhs, &mut WithEnv { scope, env }) else { continue };
        if is_sub && target.len() < 2 {
            return Err(Diagnostic::error(format!("`initial {}` names no variable of a component", first.name))
                .primary(lhs.span, "not a variable of a sub-component")
                .help(format!("name one of its variables: `initial {}.phi = ...`", first.name)));
        }
        let m = Mod::start_at(&target[if is_sub { 1 } else { 0 }..], attribute, v, rhs.span, span);
        let key = if is_sub { first.name.clone() } else { String::new() };
        if is_sub {
            let list = initial.remove(&key).unwrap_or_default();
            initial.insert(key, merge_same_level(list, vec![m])?);
        } else {
            let list = own_variables.remove(&first.name).unwrap_or_default();
            let inner = m.nested;
            own_variables.insert(first.name.clone(), merge_same_level(list, inner)?);
        }
        consumed[k] = true;
    }
    for (name, own) in own_variables {
        let outer = variable_mods.remove(&name).unwrap_or_default();
        variable_mods.insert(name, merge_outer(outer, own)?);
    }
    Ok(initial)
}

/// `wheel.surface = formula`: the road a wheel rolls on, a formula
/// of x and z rather than an equation of the model.
/// The relations taken are `consumed`.
fn surfaces(
    prefix: &str,
    flats: &[Flat],
    subs: &[Instance],
    scope: &mut ParamScope,
    consumed: &mut [bool],
) -> Result<Vec<(String, multibody::Expr)>, Diagnostic> {
    let mut surfaces = Vec::new();
    for (k, flat_relation) in flats.iter().enumerate() {
        let Flat::Equation { lhs, rhs, env, .. } = flat_relation else { continue };
        let Some(target) = relations::start_target(lhs, scope, env)? else { continue };
        let [first, part] = &target[..] else { continue };
        let is_road = |i: &Instance| {
            i.local == first.name && matches!(i.kind, Kind::Library(spec) if spec.param("surface").is_some())
        };
        if part.name == "surface" && subs.iter().any(is_road) {
            let road = crate::lowering::symbolic::road(rhs, &mut WithEnv { scope, env })?;
            surfaces.push((flat(prefix, &first.name), road));
            consumed[k] = true;
        }
    }
    Ok(surfaces)
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
    // Inside a library package, a short name is that package's component
    // (unless the files define one of that name).
    if let Some(package) = index.package_of(kind.span.file) {
        if !text.contains('.') && index.get_component(&text).is_none() {
            let full = format!("{package}.{text}");
            if let Some(def) = index.get_component(&full) {
                return Ok(Kind::User(def));
            }
            if let Some(spec) = lookup(&full) {
                return Ok(Kind::Library(spec));
            }
        }
    }
    // The files' and the library's components, then the engine's.
    if let Some(def) = index.get_component(&text) {
        return Ok(Kind::User(def));
    }
    if let (Some(def), None) = (index.component(&text), lookup(&text)) {
        return Ok(Kind::User(def));
    }
    if let Some(ty) = index.connector(&text) {
        return Ok(Kind::Connector(ty.clone()));
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
    let candidates: Vec<&str> =
        registry().iter().map(|s| s.kind).chain(index.component_names()).chain(index.connector_names()).collect();
    let mut d = Diagnostic::error(format!("unknown component kind `{text}`"))
        .primary(kind.span, "not a library component or a component of these files");
    if let Some(s) = did_you_mean(&bare, candidates.iter().copied()) {
        d = d.help(s);
    }
    Err(d.note("`multibody list` shows every library component"))
}

fn connector_names(index: &Index, kind: Kind) -> Vec<String> {
    match kind {
        Kind::Library(spec) => spec.public_connectors().map(|c| c.name.to_string()).collect(),
        Kind::User(def) => def
            .declarations
            .iter()
            .filter_map(|d| match d {
                Declaration::Component(c) if index.is_connector(&c.kind) => Some(c.name.name.clone()),
                Declaration::Variable(v) if v.causality != Causality::Internal => Some(v.name.name.clone()),
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

/// `rev(phi = 1)`: a value for a variable of a library component, which
/// the simulation computes; what the user may mean is its start value.
fn value_of_variable(spec: &ComponentSpec, component: &str, variable: &Ident, span: Span) -> Diagnostic {
    let v = &variable.name;
    Diagnostic::error(format!(
        "`{v}` of `{component}` is a variable of {}, not a parameter: the simulation computes it",
        spec.kind
    ))
    .primary(span, "a value for a variable")
    .help(format!(
        "to start it at a value, give `{v}(initial = ...)` (on the command line: --initial {component}.{v}=...)"
    ))
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

/// The values an instance's modifiers give (`n = 0` in `Cable(n = 0)`):
/// each name with the span of its modifier.
fn given_values(mods: &[Mod]) -> Vec<(String, Span)> {
    mods.iter().filter(|m| m.value.is_some()).map(|m| (m.name.name.clone(), m.span)).collect()
}

/// An error inside a definition of another file (the standard library's)
/// also points at the instance `name` the model declared at `site`, and
/// at the modifier there that gave a value the error names (`` `n` is
/// zero `` points at `n = 0`), which is what the user is to change.
fn within_instance(d: Diagnostic, site: Span, name: &str, given: &[(String, Span)]) -> Diagnostic {
    if d.labels.iter().any(|l| l.span.file == site.file) {
        return d;
    }
    let named = |parameter: &str| {
        let quoted = format!("`{parameter}`");
        d.message.contains(&quoted) || d.labels.iter().any(|l| l.primary && l.message.contains(&quoted))
    };
    match given.iter().find(|(parameter, span)| span.file == site.file && named(parameter)) {
        Some((parameter, span)) => d.secondary(*span, format!("`{parameter}` of `{name}` is given here")),
        None => d.secondary(site, format!("in `{name}`, declared here")),
    }
}
