//! The model's own equations, from names to a compiled program.
//!
//! 1. [`plan`], before the components are built: every name is classified
//!    (a variable of the equations, a quantity of a library component the
//!    mechanics decides, or a signal input the equations write); formulas
//!    of time for signal inputs become source blocks (prescribed motion
//!    needs their exact derivatives); inputs the equations write and flows
//!    they give the mechanics become hidden components connected to them.
//! 2. [`compile`], once the mechanism's structure is known: the equations
//!    become symbolic residuals; aliases (`a = b`, `a = -b`) are removed;
//!    the rest are matched to their unknowns and sorted into blocks
//!    ([`sort`]); each block is solved in closed form where it is linear
//!    in its one unknown, by Newton otherwise, and compiled into register
//!    code ([`codegen`]); the blocks take their places among the signal
//!    blocks.

mod codegen;
mod couplings;
mod fold;
mod initial;
mod liveness;
mod reduce;
mod servo;
mod sort;
mod tearing;

pub(crate) use initial::{solve as initialize, Initial};

use super::axis::{self, Places};
use super::connections::Connectors;
use super::links::Tree;
use super::mechanism::CompiledComponent;
use super::signals::Signals;
use crate::components::blocks::equation::EquationPart;
use crate::components::{lookup, ComponentSpec, ConnectorType};
use crate::error::closest;
use crate::math::expr::{Expr, TimeFunction};
use crate::math::symbolic::{self as sym, Sym, VarId, S};
use crate::math::union_find::UnionFind;
use crate::model::Flow;
use crate::system::equations::{EquationProgram, FrameQuantity};
use crate::system::{EventLayout, Link, StateLayout};
use crate::{Error, Model};
use std::collections::HashMap;
use std::sync::Arc;

/// A hidden component the equations need, connected to `connector`.
pub(crate) struct Extra {
    pub name: String,
    pub part: EquationPart,
    /// For a 1-D flow: whether the connector is a spline (rotational).
    pub rotational: bool,
    /// The connectors of the extra (local names) and the model's connectors they join.
    pub joins: Vec<(&'static str, String)>,
}

/// What [`plan`] found: hidden components to add, and the equations to
/// compile once the mechanism is assembled.
pub(crate) struct Plan {
    pub extras: Vec<Extra>,
    equations: Option<Pending>,
}

/// What a name of the equations stands for.
#[derive(Clone, Debug, PartialEq)]
enum Role {
    /// A variable the model declared (a state if its derivative appears).
    Declared(usize),
    /// The time derivative of variable `of` (an unknown).
    Derivative { of: VarId },
    /// A signal input the equations write through the hidden component `extra`.
    Written { extra: String },
    /// A value the equations read.
    Read(Read),
}

#[derive(Clone, Debug, PartialEq)]
enum Read {
    /// The signal at a library connector (an output, or an input something drives).
    Signal {
        connector: String,
    },
    Frame {
        connector: String,
        quantity: FrameQuantity,
    },
    Axis {
        connector: String,
        speed: bool,
    },
    /// The acceleration of a 1-D connector: only initial equations read it.
    AxisAcceleration {
        connector: String,
    },
    /// A state of the mechanics by name (`rev.phi`), or its rate.
    State {
        name: String,
        rate: bool,
    },
    /// The multiplier of a measured coupling (the hidden component
    /// `coupling`), known once the accelerations are.
    Reaction {
        coupling: String,
    },
    /// Effort number `row` of the hidden servo `servo`: its multiplier,
    /// known once the accelerations are.
    Effort {
        servo: String,
        row: usize,
    },
}

#[derive(Clone, Debug)]
struct Var {
    name: String,
    role: Role,
}

/// The equations as symbolic residuals over numbered variables.
struct Pending {
    vars: Vec<Var>,
    residuals: Vec<S>,
    /// The origin of each residual (for messages).
    origins: Vec<String>,
    initial: Vec<S>,
    initial_origins: Vec<String>,
    /// Declared variables whose values go to hidden flow components:
    /// (variable, extra, its output connector).
    stores: Vec<(VarId, String, &'static str)>,
    declared: Vec<crate::model::Variable>,
    /// The `when` clauses.
    whens: Vec<PendingWhen>,
    /// The discrete variables (assigned in `when` clauses), by their slot.
    discrete: Vec<VarId>,
    /// Per variable: whether it has a derivative but is not a state, being
    /// fixed by an equation that index reduction differentiated.
    dummy: Vec<bool>,
}

impl Pending {
    /// The slot of variable `v` among the discrete variables, if it is one.
    fn discrete_slot(&self, v: VarId) -> Option<usize> {
        self.discrete.iter().position(|&d| d == v)
    }
}

/// A `when` clause over numbered variables.
struct PendingWhen {
    branches: Vec<(S, Vec<PendingAction>)>,
    origin: String,
}

enum PendingAction {
    /// Discrete variable number `slot` takes `value`.
    Assign { slot: usize, value: S },
    /// Variable `variable` (a state) jumps to `value`.
    Reinit { variable: VarId, value: S, origin: String },
}

/// The library connector types of the model's components, and which
/// signal connectors share a connection (by name).
struct Connectivity<'m> {
    specs: HashMap<&'m str, &'static ComponentSpec>,
    sets: UnionFind,
    index: HashMap<String, usize>,
    /// The sets a library output or a formula drives, found on first use.
    driven_sets: Option<std::collections::HashSet<usize>>,
}

impl<'m> Connectivity<'m> {
    fn new(model: &'m Model) -> Self {
        let specs = model.components.iter().filter_map(|c| Some((c.name.as_str(), lookup(&c.kind)?))).collect();
        let mut index: HashMap<String, usize> = HashMap::new();
        for c in &model.connections {
            for end in &c.ends {
                let n = index.len();
                index.entry(end.clone()).or_insert(n);
            }
        }
        let mut sets = UnionFind::new(index.len());
        for c in &model.connections {
            for w in c.ends.windows(2) {
                sets.union(index[&w[0]], index[&w[1]]);
            }
        }
        Self { specs, sets, index, driven_sets: None }
    }

    /// The component and the rest of a name (`link1.body` + `frame_a.r_0[1]`):
    /// the longest leading part that names a component.
    fn split<'n>(&self, name: &'n str) -> Option<(&'n str, &'n str)> {
        let mut end = name.len();
        while let Some(dot) = name[..end].rfind('.') {
            if self.specs.contains_key(&name[..dot]) {
                return Some((&name[..dot], &name[dot + 1..]));
            }
            end = dot;
        }
        None
    }

    /// The type of the library connector `component.connector`.
    fn connector_type(&self, connector: &str) -> Option<ConnectorType> {
        let (component, local) = self.split(connector)?;
        self.specs.get(component)?.connector(local).map(|(_, c)| c.ty)
    }

    /// A representative of the connection set of `connector`.
    fn set_of(&mut self, connector: &str) -> Option<usize> {
        let &i = self.index.get(connector)?;
        Some(self.sets.find(i))
    }

    /// Whether a library output (or a formula, `sources`) drives the
    /// connection set of `connector`.
    fn driven(&mut self, connector: &str, sources: &[String]) -> bool {
        let Some(set) = self.set_of(connector) else { return sources.iter().any(|s| s == connector) };
        if self.driven_sets.is_none() {
            let names: Vec<String> = self.index.keys().cloned().collect();
            let mut driven = std::collections::HashSet::new();
            for m in names {
                if self.connector_type(&m) == Some(ConnectorType::RealOutput) || sources.contains(&m) {
                    if let Some(s) = self.set_of(&m) {
                        driven.insert(s);
                    }
                }
            }
            self.driven_sets = Some(driven);
        }
        self.driven_sets.as_ref().is_some_and(|d| d.contains(&set))
    }
}

/// Splits `r_0[2]` into `("r_0", [2])`; `None` if the brackets do not parse.
fn indexed(member: &str) -> Option<(&str, Vec<usize>)> {
    match member.find('[') {
        None => Some((member, Vec::new())),
        Some(open) => {
            let inner = member[open..].strip_prefix('[')?.strip_suffix(']')?;
            let indices = inner.split(',').map(|s| s.trim().parse().ok()).collect::<Option<Vec<usize>>>()?;
            Some((&member[..open], indices))
        }
    }
}

fn problem(
    problem: impl Into<String>,
    equations: Vec<String>,
    variables: Vec<String>,
    fix: impl Into<String>,
) -> Error {
    Error::Equations { problem: problem.into(), equations, variables, fix: fix.into() }
}

/// Classifies the equations' names and finds the hidden components they need.
pub(crate) fn plan(model: &Model) -> Result<Plan, Error> {
    if model.equations.is_empty() {
        return Ok(Plan { extras: Vec::new(), equations: None });
    }
    let mut net = Connectivity::new(model);
    // Equations between positions become couplings of the drive train.
    let mut eqs = model.equations.clone();
    let mut extras = couplings::extract(&mut eqs, &mut net, model)?;
    // Positions prescribed with unknown efforts become a servo constraint.
    extras.extend(servo::extract(&mut eqs, &mut net)?);
    let eqs = &eqs;
    let declared: HashMap<&str, usize> = eqs.variables.iter().enumerate().map(|(i, v)| (v.name.as_str(), i)).collect();
    if declared.len() != eqs.variables.len() {
        let mut seen = std::collections::HashSet::new();
        let twice = eqs.variables.iter().find(|v| !seen.insert(v.name.as_str())).map(|v| v.name.clone());
        return Err(problem(
            format!("the variable `{}` is declared twice", twice.unwrap_or_default()),
            vec![],
            vec![],
            "give each variable its own name",
        ));
    }
    for v in &eqs.variables {
        if net.split(&v.name).is_some_and(|(c, _)| model.component(c).is_some())
            && net.connector_type(&v.name).is_some()
        {
            return Err(problem(
                format!("the variable `{}` has the name of a library connector", v.name),
                vec![],
                vec![v.name.clone()],
                "rename the variable",
            ));
        }
    }

    // Formulas of time for signal inputs: source blocks with exact derivatives.
    let mut formulas: Vec<String> = Vec::new();
    let mut general = Vec::new();
    for e in &eqs.equations {
        if let (Expr::Var(input), false) = (&e.lhs, e.rhs.has_variables()) {
            let is_input = !declared.contains_key(input.as_str())
                && net.connector_type(input) == Some(ConnectorType::RealInput)
                && !contains_der(&e.rhs);
            if is_input && !formulas.contains(input) {
                let formula = TimeFunction::new(&e.rhs).map_err(|reason| {
                    problem(format!("the formula for `{input}`: {reason}"), vec![e.origin.clone()], vec![], "")
                })?;
                extras.push(Extra {
                    name: format!("{input} (equation)"),
                    part: EquationPart::Formula(formula),
                    rotational: false,
                    joins: vec![("y", input.clone())],
                });
                formulas.push(input.clone());
                continue;
            }
        }
        general.push(e);
    }

    let mut table = Table { vars: Vec::new(), by_name: HashMap::new() };
    for (i, v) in eqs.variables.iter().enumerate() {
        table.add(v.name.clone(), Role::Declared(i));
    }
    // At the start, a variable the equations make equal to a quantity of
    // the mechanics is that quantity: its `der` of any order reads the
    // mechanics (`initial der(der(flange.phi)) = 0` of a connector).
    let mut initial_equations = eqs.initial.clone();
    expand_initial_derivatives(&mut initial_equations, &general, &declared);
    let mut same = mechanical_aliases(&general, &declared);
    same.retain(|_, quantity| {
        let connector = quantity.rsplit_once('.').map_or("", |(c, _)| c);
        net.connector_type(connector).is_some_and(|t| !t.is_signal())
    });
    let mut written_sets: HashMap<usize, VarId> = HashMap::new();
    let mut classify = |name: &str, table: &mut Table, extras: &mut Vec<Extra>| -> Result<VarId, Error> {
        if let Some(&v) = table.by_name.get(name) {
            return Ok(v);
        }
        let role = match (name.strip_suffix(couplings::REACTION), servo::effort_of(name)) {
            (Some(coupling), _) => Some(Role::Read(Read::Reaction { coupling: coupling.to_string() })),
            (_, Some((servo, row))) => Some(Role::Read(Read::Effort { servo: servo.to_string(), row })),
            _ => classify_library(name, &mut net, &formulas, &declared, model)?,
        };
        let role = match role {
            Some(r) => r,
            None => {
                // A signal input nothing drives: the equations write it, once per connection set.
                let set = net.set_of(name);
                if let Some(v) = set.and_then(|s| written_sets.get(&s)) {
                    let v = *v;
                    table.by_name.insert(name.to_string(), v);
                    return Ok(v);
                }
                let extra = format!("{name} (equation)");
                extras.push(Extra {
                    name: extra.clone(),
                    part: EquationPart::Written,
                    rotational: false,
                    joins: vec![("y", name.to_string())],
                });
                let v = table.add(name.to_string(), Role::Written { extra });
                if let Some(s) = set {
                    written_sets.insert(s, v);
                }
                return Ok(v);
            }
        };
        Ok(table.add(name.to_string(), role))
    };

    let mut residuals = Vec::with_capacity(general.len());
    let mut origins = Vec::with_capacity(general.len());
    for e in &general {
        let lhs = to_sym(&e.lhs, &mut table, &mut classify, &mut extras, &e.origin)?;
        let rhs = to_sym(&e.rhs, &mut table, &mut classify, &mut extras, &e.origin)?;
        residuals.push(sym::sub(lhs, rhs));
        origins.push(e.origin.clone());
    }
    let mut initial = Vec::new();
    let mut initial_origins = Vec::new();
    let mut classify_initial =
        |name: &str, t: &mut Table, x: &mut Vec<Extra>| classify(same.get(name).map_or(name, String::as_str), t, x);
    for e in &initial_equations {
        let lhs = to_sym(&e.lhs, &mut table, &mut classify_initial, &mut extras, &e.origin)?;
        let rhs = to_sym(&e.rhs, &mut table, &mut classify_initial, &mut extras, &e.origin)?;
        initial.push(sym::sub(lhs, rhs));
        initial_origins.push(e.origin.clone());
    }

    // `when` clauses: the variables they assign become discrete.
    let mut discrete: Vec<VarId> = Vec::new();
    let mut whens = Vec::with_capacity(eqs.whens.len());
    for w in &eqs.whens {
        let mut branches = Vec::with_capacity(w.branches.len());
        for (condition, actions) in &w.branches {
            let condition = to_sym(condition, &mut table, &mut classify, &mut extras, &w.origin)?;
            let mut pending_actions = Vec::with_capacity(actions.len());
            for action in actions {
                pending_actions.push(match action {
                    crate::model::WhenAction::Assign { variable, value, origin } => {
                        let Some(&d) = declared.get(variable.as_str()) else {
                            return Err(problem(
                                format!("`{variable}` is assigned in a `when` but is not a variable of the equations"),
                                vec![origin.clone()],
                                vec![variable.clone()],
                                "declare it (`variable x::Real`); a `when` sets variables that hold between events, \
                                 and `reinit` sets states",
                            ));
                        };
                        let v = table.by_name[eqs.variables[d].name.as_str()];
                        let slot = match discrete.iter().position(|&x| x == v) {
                            Some(k) => k,
                            None => {
                                discrete.push(v);
                                discrete.len() - 1
                            }
                        };
                        let value = to_sym(value, &mut table, &mut classify, &mut extras, origin)?;
                        PendingAction::Assign { slot, value }
                    }
                    crate::model::WhenAction::Reinit { state, value, origin } => {
                        let variable =
                            to_sym(&Expr::Var(state.clone()), &mut table, &mut classify, &mut extras, origin)?;
                        let Sym::Var(variable) = &*variable else { unreachable!("a name is a variable") };
                        let value = to_sym(value, &mut table, &mut classify, &mut extras, origin)?;
                        PendingAction::Reinit { variable: *variable, value, origin: origin.clone() }
                    }
                });
            }
            branches.push((condition, pending_actions));
        }
        whens.push(PendingWhen { branches, origin: w.origin.clone() });
    }
    for &v in &discrete {
        if table.by_name.contains_key(&format!("der({})", table.vars[v].name)) {
            let name = table.vars[v].name.clone();
            return Err(problem(
                format!("`{name}` is assigned in a `when`, so it holds between events, but `der({name})` appears too"),
                vec![],
                vec![name],
                "a state jumps with `reinit(x, value)` inside the `when`",
            ));
        }
    }
    // `pre` outside `when` clauses: of discrete variables only.
    for (r, origin) in residuals.iter().zip(&origins) {
        if let Some(v) = pre_of_continuous(r, &discrete) {
            return Err(problem(
                format!(
                    "`pre({})` outside a `when` clause, of a variable that changes continuously",
                    table.vars[v].name
                ),
                vec![origin.clone()],
                vec![table.vars[v].name.clone()],
                "use `pre` inside `when` clauses, or of variables that a `when` assigns",
            ));
        }
    }

    // Flows: a hidden load on the connector, fed by the declared variables.
    let mut stores = Vec::new();
    for (k, flow) in eqs.flows.iter().enumerate() {
        let (connector, names, outputs, part, rotational): (&String, Vec<&String>, &[&'static str], _, _) = match flow {
            Flow::Frame { connector, force, torque } => (
                connector,
                force.iter().chain(torque.iter()).collect(),
                &["f_1", "f_2", "f_3", "tau_1", "tau_2", "tau_3"],
                EquationPart::FrameFlow,
                false,
            ),
            Flow::Frame2D { connector, force, torque } => (
                connector,
                force.iter().chain([torque]).collect(),
                &["fx", "fy", "tau"],
                EquationPart::PlanarFlow,
                false,
            ),
            Flow::Flange { connector, value } => (
                connector,
                vec![value],
                &["y"],
                EquationPart::AxisFlow,
                net.connector_type(connector) == Some(ConnectorType::Spline),
            ),
        };
        let expected = match flow {
            Flow::Frame { .. } => [ConnectorType::Frame].as_slice(),
            Flow::Frame2D { .. } => [ConnectorType::Frame2D].as_slice(),
            Flow::Flange { .. } => [ConnectorType::Spline, ConnectorType::Flange].as_slice(),
        };
        if !net.connector_type(connector).is_some_and(|t| expected.contains(&t)) {
            return Err(problem(
                format!("flows are given at `{connector}`, which is not a library connector of the right kind"),
                vec![],
                names.iter().map(|n| n.to_string()).collect(),
                "name a frame connector for forces and torques, a spline or flange for 1-D flows",
            ));
        }
        let extra = format!("{connector} (flow {k})");
        for (name, &output) in names.iter().zip(outputs) {
            let Some(&v) = declared.get(name.as_str()) else {
                return Err(problem(format!("the flow variable `{name}` is not declared"), vec![], vec![], ""));
            };
            stores.push((table.by_name[name.as_str()], extra.clone(), output));
            let _ = v;
        }
        let local = match part {
            EquationPart::FrameFlow | EquationPart::PlanarFlow => "frame",
            _ if rotational => "spline",
            _ => "flange",
        };
        extras.push(Extra { name: extra, part, rotational, joins: vec![(local, connector.clone())] });
    }

    let mut pending = Pending {
        vars: Vec::new(),
        residuals,
        origins,
        initial,
        initial_origins,
        stores,
        declared: eqs.variables.clone(),
        whens,
        discrete,
        dummy: Vec::new(),
    };
    reduce::reduce(&mut pending, &mut table)?;
    pending.vars = table.vars;
    Ok(Plan { extras, equations: Some(pending) })
}

/// In initial equations, `der` of a variable that the equations do not
/// differentiate themselves (`initial der(w_rel) = 0` of a spring written
/// with `w_rel = der(phi_rel)`) is the derivative of what defines it:
/// under a `der`, such a variable is replaced by the other side of its
/// explicit equation (`x = e`), down to states and quantities of the
/// mechanics, whose rates the start reads (accelerations included).
fn expand_initial_derivatives(
    initial: &mut [crate::Equation],
    regular: &[&crate::Equation],
    declared: &HashMap<&str, usize>,
) {
    let mut any = false;
    for e in initial.iter() {
        e.lhs.visit(&mut |n| any |= matches!(n, Expr::Der(_)));
        e.rhs.visit(&mut |n| any |= matches!(n, Expr::Der(_)));
    }
    if !any {
        return;
    }
    let mut differentiated = std::collections::HashSet::new();
    let mut definitions: HashMap<&str, &Expr> = HashMap::new();
    for e in regular {
        for side in [&e.lhs, &e.rhs] {
            side.visit(&mut |node| {
                if let Expr::Der(inner) = node {
                    if let Expr::Var(x) = &**inner {
                        differentiated.insert(x.as_str());
                    }
                }
            });
        }
        for (x, other) in [(&e.lhs, &e.rhs), (&e.rhs, &e.lhs)] {
            if let Expr::Var(x) = x {
                let mut names = Vec::new();
                other.variables(&mut names);
                if declared.contains_key(x.as_str()) && !names.contains(&x) {
                    definitions.entry(x.as_str()).or_insert(other);
                }
            }
        }
    }
    // `depth`: how many `der` enclose the node; `budget` ends a cycle of definitions.
    fn expand(
        e: &Expr,
        depth: usize,
        rules: (&HashMap<&str, &Expr>, &std::collections::HashSet<&str>),
        budget: &mut usize,
    ) -> Expr {
        let (definitions, differentiated) = rules;
        match e {
            Expr::Der(inner) => Expr::Der(Arc::new(expand(inner, depth + 1, rules, budget))),
            Expr::Var(x) if depth > 0 && (depth > 1 || !differentiated.contains(x.as_str())) => {
                match (definitions.get(x.as_str()), *budget > 0) {
                    (Some(definition), true) => {
                        *budget -= 1;
                        expand(definition, depth, rules, budget)
                    }
                    _ => e.clone(),
                }
            }
            _ => e.map_children(|c| Arc::new(expand(c, depth, rules, budget))),
        }
    }
    for e in initial {
        let mut budget = 64;
        e.lhs = expand(&e.lhs, 0, (&definitions, &differentiated), &mut budget);
        e.rhs = expand(&e.rhs, 0, (&definitions, &differentiated), &mut budget);
    }
}

/// The declared variables that equations `a = b` make equal to a quantity
/// of a library component (directly or through other such variables), with it.
fn mechanical_aliases(equations: &[&crate::Equation], declared: &HashMap<&str, usize>) -> HashMap<String, String> {
    let mut next: HashMap<&str, &str> = HashMap::new();
    for e in equations {
        if let (Expr::Var(a), Expr::Var(b)) = (&e.lhs, &e.rhs) {
            match (declared.contains_key(a.as_str()), declared.contains_key(b.as_str())) {
                (true, false) => {
                    next.insert(a.as_str(), b.as_str());
                }
                (false, true) => {
                    next.insert(b.as_str(), a.as_str());
                }
                _ => {}
            }
        }
    }
    // Chains through declared variables: `outer.phi = inner.phi = rev.phi`.
    for e in equations {
        if let (Expr::Var(a), Expr::Var(b)) = (&e.lhs, &e.rhs) {
            if declared.contains_key(a.as_str()) && declared.contains_key(b.as_str()) {
                if let (None, Some(&end)) = (next.get(a.as_str()), next.get(b.as_str())) {
                    next.insert(a.as_str(), end);
                } else if let (None, Some(&end)) = (next.get(b.as_str()), next.get(a.as_str())) {
                    next.insert(b.as_str(), end);
                }
            }
        }
    }
    next.into_iter().map(|(a, b)| (a.to_string(), b.to_string())).collect()
}

/// A variable that `pre` is taken of in `e` and that is not discrete.
fn pre_of_continuous(e: &S, discrete: &[VarId]) -> Option<VarId> {
    e.find(&mut |node| match node {
        Sym::Pre(v) if !discrete.contains(v) => Some(*v),
        _ => None,
    })
}

/// The interned variables.
struct Table {
    vars: Vec<Var>,
    by_name: HashMap<String, VarId>,
}

impl Table {
    fn add(&mut self, name: String, role: Role) -> VarId {
        let v = VarId::new(self.vars.len());
        self.vars.push(Var { name: name.clone(), role });
        self.by_name.insert(name, v);
        v
    }

    /// The variable that is the derivative of `v`, made on first use.
    fn derivative(&mut self, v: VarId, origin: &str) -> Result<VarId, Error> {
        let role = match &self.vars[v].role {
            Role::Declared(_) | Role::Derivative { .. } => Role::Derivative { of: v },
            Role::Read(Read::Frame { connector, quantity }) => Role::Read(Read::Frame {
                connector: connector.clone(),
                quantity: match *quantity {
                    FrameQuantity::Position(i) => FrameQuantity::Velocity(i),
                    FrameQuantity::Rotation(i, j) => FrameQuantity::RotationRate(i, j),
                    FrameQuantity::PlanarAngle => FrameQuantity::PlanarAngleRate,
                    FrameQuantity::PlanarPosition(i) => FrameQuantity::PlanarVelocity(i),
                    _ => return Err(second_derivative(&self.vars[v].name, origin)),
                },
            }),
            Role::Read(Read::Axis { connector, speed: false }) => {
                Role::Read(Read::Axis { connector: connector.clone(), speed: true })
            }
            Role::Read(Read::Axis { connector, speed: true }) => {
                Role::Read(Read::AxisAcceleration { connector: connector.clone() })
            }
            Role::Read(Read::State { name, rate: false }) => Role::Read(Read::State { name: name.clone(), rate: true }),
            Role::Read(Read::AxisAcceleration { .. } | Read::State { rate: true, .. }) => {
                return Err(second_derivative(&self.vars[v].name, origin))
            }
            Role::Read(Read::Reaction { .. } | Read::Effort { .. }) => {
                return Err(problem(
                    format!("`der` of `{}`, a flow measured through a rigid part, is not available", self.vars[v].name),
                    vec![origin.to_string()],
                    vec![self.vars[v].name.clone()],
                    "filter the measured flow with a state of the equations instead",
                ))
            }
            Role::Written { .. } | Role::Read(Read::Signal { .. }) => {
                return Err(problem(
                    format!(
                        "`der({})` is not available: it is a signal, whose rate nothing computes",
                        self.vars[v].name
                    ),
                    vec![origin.to_string()],
                    vec![self.vars[v].name.clone()],
                    "differentiate a variable of the equations instead, or use a BlockComponents.Derivative block",
                ))
            }
        };
        let name = format!("der({})", self.vars[v].name);
        if let Some(&d) = self.by_name.get(&name) {
            return Ok(d);
        }
        Ok(self.add(name, role))
    }
}

fn second_derivative(name: &str, origin: &str) -> Error {
    problem(
        format!("`der` of `{name}` needs accelerations, which the equations cannot read"),
        vec![origin.to_string()],
        vec![name.to_string()],
        "equations read positions and velocities of the mechanics; for a mass or inertia use Body, PointMass or \
         RotationalComponents.Inertia",
    )
}

fn contains_der(e: &Expr) -> bool {
    let mut found = false;
    e.visit(&mut |n| found |= matches!(n, Expr::Der(_)));
    found
}

/// The role of a name that is not a declared variable: a quantity of a
/// library component; `None` for a signal input that nothing drives.
fn classify_library(
    name: &str,
    net: &mut Connectivity,
    formulas: &[String],
    declared: &HashMap<&str, usize>,
    model: &Model,
) -> Result<Option<Role>, Error> {
    let unknown = || {
        let candidates = declared.keys().copied().chain(model.components.iter().map(|c| c.name.as_str()));
        problem(
            format!("`{name}` is neither a variable of the equations nor a quantity of a component{}", {
                let s = closest(name, candidates);
                if s.is_empty() {
                    String::new()
                } else {
                    format!(" (did you mean `{}`?)", s.join("`, `"))
                }
            }),
            vec![],
            vec![name.to_string()],
            "declare it as a variable, or name a connector quantity such as `body.frame_a.r_0[1]` or `sensor.phi`",
        )
    };
    let Some((component, member)) = net.split(name) else { return Err(unknown()) };
    let spec = net.specs[component];
    let (head, rest) = member.split_once('.').unwrap_or((member, ""));
    // A connector's own name may carry an index (a block's `q[2]`); else
    // the index is of the quantity (`r_0[1]`).
    let found = spec.connector(head).or_else(|| spec.connector(indexed(head).map_or(head, |(h, _)| h)));
    let Some((_, connector)) = found else {
        // Not a connector: a variable of the component (a state, say).
        return Ok(Some(Role::Read(Read::State { name: name.to_string(), rate: false })));
    };
    let connector_name = format!("{component}.{}", connector.name);
    let field = indexed(rest);
    let bad_field = |what: &str| {
        problem(
            format!("`{name}`: {what}"),
            vec![],
            vec![name.to_string()],
            match connector.ty {
                ConnectorType::Frame => "a frame's equations read `r_0[i]` and `R[i, j]` (and `der` of them)",
                ConnectorType::Frame2D => "a planar frame's equations read `x`, `y` and `phi` (and `der` of them)",
                ConnectorType::Spline => "a spline's equations read `phi` (and `der(phi)`)",
                ConnectorType::Flange => "a flange's equations read `s` (and `der(s)`)",
                _ => "a signal connector is read by its name alone",
            },
        )
    };
    let in_range = |indices: &[usize], n: usize| indices.iter().all(|&i| (1..=3).contains(&i)) && indices.len() == n;
    Ok(Some(match connector.ty {
        ConnectorType::RealOutput | ConnectorType::RealInput if rest.is_empty() => {
            if connector.ty == ConnectorType::RealInput && !net.driven(&connector_name, formulas) {
                return Ok(None);
            }
            Role::Read(Read::Signal { connector: connector_name })
        }
        ConnectorType::RealOutput | ConnectorType::RealInput => return Err(bad_field("a signal has no fields")),
        ConnectorType::Frame => match field {
            Some(("r_0", i)) if in_range(&i, 1) => {
                Role::Read(Read::Frame { connector: connector_name, quantity: FrameQuantity::Position(i[0] - 1) })
            }
            Some(("R", i)) if in_range(&i, 2) => Role::Read(Read::Frame {
                connector: connector_name,
                quantity: FrameQuantity::Rotation(i[0] - 1, i[1] - 1),
            }),
            Some(("f" | "tau", _)) => {
                return Err(problem(
                    format!("`{name}` is a flow that the mechanics decides; equations cannot read it"),
                    vec![],
                    vec![name.to_string()],
                    "measure it in the results (every connector's `f` and `tau` are there)",
                ))
            }
            _ => return Err(bad_field("not a quantity of a frame")),
        },
        ConnectorType::Frame2D => match rest {
            "x" | "y" => Role::Read(Read::Frame {
                connector: connector_name,
                quantity: FrameQuantity::PlanarPosition(usize::from(rest == "y")),
            }),
            "phi" => Role::Read(Read::Frame { connector: connector_name, quantity: FrameQuantity::PlanarAngle }),
            "fx" | "fy" | "tau" => {
                return Err(problem(
                    format!("`{name}` is a flow that the mechanics decides; equations cannot read it"),
                    vec![],
                    vec![name.to_string()],
                    "measure it in the results (every planar frame's `fx`, `fy` and `tau` are there)",
                ))
            }
            _ => return Err(bad_field("not a quantity of a planar frame")),
        },
        ConnectorType::Spline | ConnectorType::Flange => match rest {
            "phi" | "s" => Role::Read(Read::Axis { connector: connector_name, speed: false }),
            "tau" | "f" => {
                return Err(problem(
                    format!("`{name}` is a flow that the mechanics decides; equations cannot read it"),
                    vec![],
                    vec![name.to_string()],
                    "measure it with a torque or force sensor in the results",
                ))
            }
            _ => return Err(bad_field("not a quantity of a 1-D connector")),
        },
    }))
}

/// `expr` as a symbolic expression, interning its names; `der(e)` becomes
/// the time derivative of `e` over the derivatives' variables.
fn to_sym<F: FnMut(&str, &mut Table, &mut Vec<Extra>) -> Result<VarId, Error>>(
    expr: &Expr,
    table: &mut Table,
    classify: &mut F,
    extras: &mut Vec<Extra>,
    origin: &str,
) -> Result<S, Error> {
    sym::rewrite(expr, &mut |node| {
        Ok(match node {
            Expr::Var(name) => Some(sym::var(classify(name, table, extras).map_err(|e| with_origin(e, origin))?)),
            Expr::Pre(name) => {
                Some(Arc::new(Sym::Pre(classify(name, table, extras).map_err(|e| with_origin(e, origin))?)))
            }
            Expr::Der(inner) => {
                let s = to_sym(inner, table, classify, extras, origin)?;
                let mut failure = None;
                let d = sym::time_derivative(&s, &mut |&v| match table.derivative(v, origin) {
                    Ok(d) => Some(d),
                    Err(e) => {
                        failure.get_or_insert(e);
                        None
                    }
                });
                if let Some(e) = failure {
                    return Err(e);
                }
                Some(d)
            }
            _ => None,
        })
    })
}

/// The error with the equation it comes from, if it names none yet.
fn with_origin(e: Error, origin: &str) -> Error {
    match e {
        Error::Equations { problem, equations, variables, fix } if equations.is_empty() && !origin.is_empty() => {
            Error::Equations { problem, equations: vec![origin.to_string()], variables, fix }
        }
        other => other,
    }
}

/// What compiling needs from the assembly.
pub(crate) struct Context<'a> {
    pub components: &'a [CompiledComponent],
    pub conn: &'a Connectors,
    pub tree: &'a Tree,
    pub places: &'a Places,
    pub links: &'a [Link],
    /// The couplings left as constraint rows (measured ones among them).
    pub couplings: &'a [crate::system::Coupling],
    /// The constraints (a servo's among them).
    pub constraints: &'a [crate::system::Constraint],
}

impl Plan {
    /// Compiles the equations into a program, adds their states to
    /// `states`, and puts their blocks among the signal blocks.
    pub(crate) fn compile(
        self,
        ctx: &Context,
        signals: &mut Signals,
        states: &mut StateLayout,
        events: &mut EventLayout,
    ) -> Result<(EquationProgram, Option<Initial>), Error> {
        let Some(pending) = self.equations else {
            return Ok((EquationProgram::default(), None));
        };
        let mut pending = pending;
        let reads = resolve_reads(&pending, ctx, signals, states)?;
        let sorted = sort::sort(&pending, &reads)?;
        starts_of_computed_variables(&mut pending, &sorted.states);
        let (nq, nv) = (states.nq, states.nv);
        let (mut program, registers) = codegen::generate(&pending, &reads, &sorted, ctx, signals, states, events)?;
        program.notes = idle_guesses(&pending, &sorted.states, &registers, &program);
        let free: Vec<(usize, String)> = sorted
            .states
            .iter()
            .enumerate()
            .filter(|&(k, _)| !states.fixed[nq + nv + k])
            .map(|(k, &s)| (nq + nv + k, pending.vars[s].name.clone()))
            .collect();
        let rates = reads
            .iter()
            .enumerate()
            .filter_map(|(v, source)| match source {
                Some(Source::Rate(terms)) => Some((registers[v], terms.clone())),
                _ => None,
            })
            .collect();
        let mut column = 0;
        let column_of_state: Vec<Option<usize>> = (0..sorted.states.len())
            .map(|k| {
                (!states.fixed[nq + nv + k]).then(|| {
                    column += 1;
                    column - 1
                })
            })
            .collect();
        let depends = initial::dependence(&sorted, &reads, &signals.of_time, &column_of_state, &pending.initial);
        let initial = (!pending.initial.is_empty()).then(|| Initial {
            depends,
            residuals: pending.initial,
            origins: pending.initial_origins,
            registers,
            rates,
            free: free.iter().map(|(i, _)| *i).collect(),
            free_names: free.into_iter().map(|(_, n)| n).collect(),
        });
        Ok((program, initial))
    }
}

/// Guesses that nothing reads: on a variable the equations compute
/// directly (no Newton solve has it among its unknowns; not a state), with
/// no index reduction in the model (whose choice reads the start values).
fn idle_guesses(
    pending: &Pending,
    states: &[VarId],
    registers: &[crate::system::equations::Reg],
    program: &EquationProgram,
) -> Vec<String> {
    if pending.dummy.iter().any(|&d| d) || program.blocks.iter().any(|b| !b.reduced.is_empty()) {
        return Vec::new();
    }
    let iterated = |r: crate::system::equations::Reg| {
        program.blocks.iter().any(
            |b| matches!(&b.solve, crate::system::equations::Solve::Newton { unknowns, .. } if unknowns.contains(&r)),
        )
    };
    let mut notes = Vec::new();
    for v in VarId::all(pending.vars.len()) {
        let Role::Declared(d) = pending.vars[v].role else { continue };
        let declared = &pending.declared[d];
        if declared.start.is_none() || declared.fixed || states.contains(&v) || pending.discrete_slot(v).is_some() {
            continue;
        }
        if !iterated(registers[v]) {
            notes.push(format!(
                "the guess of `{}` has no effect: the equations compute it directly (no equation is solved for it \
                 by iteration, and it is not a state); give a start value that holds (`initial`) to fix it at the \
                 start, or leave the guess out",
                declared.name
            ));
        }
    }
    notes
}

/// A start value given (`initial`) to a variable the equations compute is
/// an initial equation, `v = start`: it holds at the start by moving the
/// start values left free, and is never dropped. (States take theirs
/// directly; variables index reduction made dummies have theirs already;
/// discrete variables start at theirs.)
fn starts_of_computed_variables(pending: &mut Pending, states: &[VarId]) {
    let mut is_state = vec![false; pending.vars.len()];
    for &s in states {
        is_state[s] = true;
    }
    for (v, &state) in VarId::all(is_state.len()).zip(&is_state) {
        let Role::Declared(d) = pending.vars[v].role else { continue };
        let declared = &pending.declared[d];
        let (Some(start), true) = (declared.start, declared.fixed) else { continue };
        if state || pending.dummy[v] || pending.discrete_slot(v).is_some() {
            continue;
        }
        let origin = if declared.origin.is_empty() { pending.vars[v].name.clone() } else { declared.origin.clone() };
        pending.initial.push(sym::sub(sym::var(v), sym::constant(start)));
        pending.initial_origins.push(origin);
    }
}

/// Where each read comes from, once the mechanism is assembled.
#[derive(Clone, Debug)]
enum Source {
    Slot(usize),
    Frame {
        node: usize,
        quantity: FrameQuantity,
    },
    Axis {
        flange: crate::system::FlangeRef,
        speed: bool,
    },
    /// An index into the state `y` (coordinates then rates).
    State(usize),
    /// A sum of rates of states, `sum c dy[i]`, known once the
    /// accelerations are: only initial equations read it (`initial
    /// der(joint.w) = 0`).
    Rate(Vec<(usize, f64)>),
    /// A discrete variable, by its number among them.
    Discrete(usize),
    /// The multiplier of a constraint row, after the accelerations.
    Reaction(usize),
}

/// The global connector number of `component.connector`.
fn connector_id(ctx: &Context, name: &str) -> Option<usize> {
    let (component, local) = name.rsplit_once('.')?;
    let ci = ctx.components.iter().position(|c| c.name == component)?;
    let c = &ctx.components[ci];
    let (k, _) = c.spec.connector(local)?;
    Some(c.first_connector + k)
}

fn resolve_reads(
    pending: &Pending,
    ctx: &Context,
    signals: &Signals,
    states: &StateLayout,
) -> Result<Vec<Option<Source>>, Error> {
    let mut out = Vec::with_capacity(pending.vars.len());
    for (v, var) in VarId::all(pending.vars.len()).zip(&pending.vars) {
        if let Some(slot) = pending.discrete_slot(v) {
            out.push(Some(Source::Discrete(slot)));
            continue;
        }
        let Role::Read(read) = &var.role else {
            out.push(None);
            continue;
        };
        let missing = || problem(format!("`{}` names no connector", var.name), vec![], vec![var.name.clone()], "");
        out.push(Some(match read {
            Read::Signal { connector } => {
                Source::Slot(signals.of_connector[connector_id(ctx, connector).ok_or_else(missing)?])
            }
            Read::Frame { connector, quantity } => {
                let id = connector_id(ctx, connector).ok_or_else(missing)?;
                Source::Frame { node: ctx.conn.node(id), quantity: *quantity }
            }
            Read::Axis { connector, speed } => {
                let id = connector_id(ctx, connector).ok_or_else(missing)?;
                Source::Axis { flange: axis::flange(ctx.components, ctx.conn, ctx.places, id)?, speed: *speed }
            }
            Read::AxisAcceleration { connector } => {
                let id = connector_id(ctx, connector).ok_or_else(missing)?;
                let at = axis::flange(ctx.components, ctx.conn, ctx.places, id)?;
                let refused = || second_derivative(&var.name, "");
                if let Some(origin) = used_outside_initial(pending, v) {
                    return Err(with_origin(refused(), &origin));
                }
                let nq = states.nq;
                let mut terms = match at.mover {
                    None => Vec::new(),
                    Some(crate::system::Mover::State { v: k, .. }) => vec![(nq + k, at.scale)],
                    Some(crate::system::Mover::Line(_)) => return Err(refused()),
                };
                if let Some((_, k, c)) = at.second {
                    terms.push((nq + k as usize, c));
                }
                Source::Rate(terms)
            }
            Read::State { name, rate } => match state_index(name, *rate, ctx, states) {
                Ok(i) => Source::State(i),
                Err(e) => {
                    // A velocity's rate, an acceleration: the start may
                    // ask for it; the equations cannot read it.
                    let velocity = states.names[states.nq..states.nq + states.nv].iter().position(|n| n == name);
                    match (velocity, used_outside_initial(pending, v)) {
                        (Some(k), None) if *rate => Source::Rate(vec![(states.nq + k, 1.0)]),
                        (_, Some(origin)) => return Err(with_origin(e, &origin)),
                        _ => return Err(e),
                    }
                }
            },
            Read::Reaction { coupling } => {
                let ci = ctx.components.iter().position(|c| &c.name == coupling);
                let row = ctx.couplings.iter().find(|c| Some(c.component) == ci).map(|c| c.row);
                Source::Reaction(row.expect("a measured coupling stays a constraint row"))
            }
            Read::Effort { servo, row } => {
                let ci = ctx.components.iter().position(|c| &c.name == servo);
                let constraint = ctx.constraints.iter().find(|c| Some(c.component) == ci);
                Source::Reaction(constraint.expect("a servo holds a constraint").row + row)
            }
        }));
    }
    Ok(out)
}

/// The origin of an equation or `when` clause that reads variable `v`,
/// if any does (besides the initial equations).
fn used_outside_initial(pending: &Pending, v: VarId) -> Option<String> {
    if let Some(k) = pending.residuals.iter().position(|r| r.depends_on(&v)) {
        return Some(pending.origins[k].clone());
    }
    let reads = |w: &&PendingWhen| {
        w.branches.iter().any(|(c, actions)| {
            c.depends_on(&v)
                || actions.iter().any(|a| match a {
                    PendingAction::Assign { value, .. } | PendingAction::Reinit { value, .. } => value.depends_on(&v),
                })
        })
    };
    pending.whens.iter().find(reads).map(|w| w.origin.clone())
}

/// The index in `y` of the state `name` (or of its rate).
fn state_index(name: &str, rate: bool, ctx: &Context, states: &StateLayout) -> Result<usize, Error> {
    let (nq, nv) = (states.nq, states.nv);
    let Some(i) = states.names[..nq + nv].iter().position(|n| n == name) else {
        let candidates = states.names[..nq + nv].iter().map(String::as_str);
        let s = closest(name, candidates);
        return Err(problem(
            format!(
                "`{name}` is not a quantity the equations can read{}",
                if s.is_empty() { String::new() } else { format!(" (did you mean `{}`?)", s.join("`, `")) }
            ),
            vec![],
            vec![name.to_string()],
            "equations read the states of joints and bodies (`rev.phi`, `rev.w`), signal connectors, and the \
             positions of frames and 1-D connectors; other variables are in the results, or measure them with a \
             sensor",
        ));
    };
    if !rate {
        return Ok(i);
    }
    // der of a coordinate of a one-coordinate joint is its rate.
    let link = ctx.links.iter().skip(1).find(|l| l.q_offset == i && i < nq && l.joint.nq() == 1 && l.joint.nv() == 1);
    match link {
        Some(l) => Ok(nq + l.v_offset),
        None => Err(second_derivative(name, "")),
    }
}
