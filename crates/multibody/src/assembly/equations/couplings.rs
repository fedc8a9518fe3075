//! Equations between positions of 1-D connectors decide no unknown of
//! their own: `flange_a.phi = flange_b.phi` (an in-line part), a rod's
//! `flange_a.s = s - L/2`, `flange_b.s = s + L/2`, a gear's `phi_a = ratio *
//! phi_b`. They are constraints of the mechanism, which the drive train
//! makes rigid or keeps as constraint rows, as it does for a library gear.
//!
//! The equations that are linear in positions are grouped by the variables
//! they share (a connector's own position, a rod's centre `s`); eliminating
//! those variables leaves relations between library positions alone, which
//! become hidden couplings. The equations used to eliminate stay, and
//! compute those variables. The flows at the connectors a coupling holds
//! are then its reaction: their balance equations are checked to be those
//! of an ideal (lossless) constraint and dropped, with the loads they gave.

use super::{classify_library, problem, Connectivity, Extra, Read, Role};
use crate::components::blocks::equation::{EquationPart, COUPLING_CONNECTORS};
use crate::components::ConnectorType;
use crate::math::expr::Expr;
use crate::math::union_find::UnionFind;
use crate::model::{Equation, Equations, Flow};
use crate::{Error, Model};
use std::collections::{HashMap, HashSet};

/// `sum c_k name_k + constant`.
#[derive(Clone, Debug, Default)]
struct Linear {
    terms: Vec<(String, f64)>,
    constant: f64,
}

impl Linear {
    fn scaled(mut self, k: f64) -> Self {
        self.terms.iter_mut().for_each(|t| t.1 *= k);
        self.constant *= k;
        self
    }

    fn plus(mut self, other: Linear) -> Self {
        for (name, c) in other.terms {
            match self.terms.iter_mut().find(|t| t.0 == name) {
                Some(t) => t.1 += c,
                None => self.terms.push((name, c)),
            }
        }
        self.constant += other.constant;
        self
    }

    fn as_constant(&self) -> Option<f64> {
        self.terms.iter().all(|t| t.1 == 0.0).then_some(self.constant)
    }
}

/// `e` as a linear form of its variables, if it is one.
fn linear(e: &Expr) -> Option<Linear> {
    let constant = |x: f64| Some(Linear { terms: Vec::new(), constant: x });
    match e {
        Expr::Const(x) => constant(*x),
        Expr::Var(name) => Some(Linear { terms: vec![(name.clone(), 1.0)], constant: 0.0 }),
        Expr::Neg(a) => Some(linear(a)?.scaled(-1.0)),
        Expr::Add(a, b) => Some(linear(a)?.plus(linear(b)?)),
        Expr::Sub(a, b) => Some(linear(a)?.plus(linear(b)?.scaled(-1.0))),
        Expr::Mul(a, b) => {
            let (a, b) = (linear(a)?, linear(b)?);
            match (a.as_constant(), b.as_constant()) {
                (Some(k), _) => Some(b.scaled(k)),
                (_, Some(k)) => Some(a.scaled(k)),
                _ => None,
            }
        }
        Expr::Div(a, b) => {
            let k = linear(b)?.as_constant()?;
            (k != 0.0).then(|| linear(a).map(|a| a.scaled(1.0 / k)))?
        }
        Expr::Pow(a, b) => constant(linear(a)?.as_constant()?.powf(linear(b)?.as_constant()?)),
        Expr::Call(f, a) => constant(f.apply(linear(a)?.as_constant()?)),
        Expr::Call2(f, a, b) => constant(f.apply(linear(a)?.as_constant()?, linear(b)?.as_constant()?)),
        _ => None,
    }
}

/// Names numbered in the order first met.
#[derive(Default)]
struct Numbered {
    names: Vec<String>,
    index: HashMap<String, usize>,
}

impl Numbered {
    fn number(&mut self, name: String) -> usize {
        let next = self.names.len();
        *self.index.entry(name).or_insert_with_key(|name| {
            self.names.push(name.clone());
            next
        })
    }
}

/// A linear equation between positions: its terms on variables of the
/// equations (to eliminate) and on positions of library connectors.
struct Row {
    equation: usize,
    own: Vec<(usize, f64)>,
    positions: Vec<(usize, f64)>,
    constant: f64,
}

/// The suffix of the variable that stands for a measured coupling's
/// multiplier (`sensor (reaction)`): no name a model can write.
pub(super) const REACTION: &str = " (reaction)";

/// Takes the equations that relate positions of 1-D connectors alone out of
/// `eqs` (with the flows and balance equations of the connectors they
/// hold) and returns the hidden couplings that replace them. Where other
/// equations read a held flow (an in-line sensor), the coupling is
/// measured: the flow becomes `-c * reaction`, read from its multiplier
/// after the accelerations.
pub(super) fn extract(eqs: &mut Equations, net: &mut Connectivity, model: &Model) -> Result<Vec<Extra>, Error> {
    let declared: HashSet<&str> = eqs.variables.iter().map(|v| v.name.as_str()).collect();
    let assigned: HashSet<&str> = eqs
        .whens
        .iter()
        .flat_map(|w| w.branches.iter().flat_map(|b| b.1.iter()))
        .filter_map(|a| match a {
            crate::model::WhenAction::Assign { variable, .. } => Some(variable.as_str()),
            _ => None,
        })
        .collect();
    let no_declared = HashMap::new();

    // The rows, over numbered own variables and library positions.
    let (mut own, mut positions) = (Numbered::default(), Numbered::default());
    let mut rows = Vec::new();
    'equations: for (i, e) in eqs.equations.iter().enumerate() {
        let Some(form) = linear(&(e.lhs.clone() - e.rhs.clone())) else { continue };
        let mut row = Row { equation: i, own: Vec::new(), positions: Vec::new(), constant: form.constant };
        for (name, c) in form.terms.into_iter().filter(|t| t.1 != 0.0) {
            if declared.contains(name.as_str()) {
                if assigned.contains(name.as_str()) {
                    continue 'equations;
                }
                row.own.push((own.number(name), c));
            } else if let Ok(Some(Role::Read(Read::Axis { speed: false, .. }))) =
                classify_library(&name, net, &[], &no_declared, model)
            {
                row.positions.push((positions.number(name), c));
            } else {
                continue 'equations;
            }
        }
        if !row.positions.is_empty() || !row.own.is_empty() {
            rows.push(row);
        }
    }
    if rows.iter().all(|r| r.positions.is_empty()) {
        return Ok(Vec::new());
    }

    // Groups of rows that share own variables.
    let mut groups = UnionFind::new(rows.len() + own.names.len());
    for (r, row) in rows.iter().enumerate() {
        for &(k, _) in &row.own {
            groups.union(r, rows.len() + k);
        }
    }
    let mut members: HashMap<usize, Vec<usize>> = HashMap::new();
    let mut order = Vec::new();
    for r in 0..rows.len() {
        let g = groups.find(r);
        members.entry(g).or_insert_with(|| {
            order.push(g);
            Vec::new()
        });
        members.get_mut(&g).expect("just made").push(r);
    }

    // What each connector's position variable is: `m.phi` of a connector
    // `m` whose flow loads a library connector.
    let flow_of: HashMap<String, (usize, String, String)> = eqs
        .flows
        .iter()
        .enumerate()
        .filter_map(|(f, flow)| match flow {
            Flow::Flange { connector, value } => {
                let (m, field) = value.rsplit_once('.')?;
                let potential = if field == "tau" { "phi" } else { "s" };
                Some((format!("{m}.{potential}"), (f, value.clone(), connector.clone())))
            }
            _ => None,
        })
        .collect();

    let mut extras = Vec::new();
    let mut drop_equations: HashSet<usize> = HashSet::new();
    let mut drop_flows: HashSet<usize> = HashSet::new();
    let mut drop_variables: HashSet<String> = HashSet::new();
    let mut measured_flows = Vec::new();
    for g in order {
        let group = &members[&g];
        // Only groups that reach positions can hold them; elimination is
        // dense, so a large algebraic system of the equations is left to the
        // general solver (an element's group has a handful of rows).
        if group.iter().all(|&r| rows[r].positions.is_empty()) || group.len() > MAX_GROUP {
            continue;
        }
        let mut own_here: Vec<usize> = group.iter().flat_map(|&r| rows[r].own.iter().map(|t| t.0)).collect();
        own_here.sort_unstable();
        own_here.dedup();
        let (constraints, replaced) = eliminate(group, &own_here, &rows, positions.names.len(), &eqs.equations)?;
        drop_equations.extend(replaced);
        if constraints.is_empty() {
            continue;
        }

        // The flows of the connectors held: the constraints' reaction.
        let mut held: Vec<(String, usize)> = Vec::new(); // (flow variable, position it loads)
        for &k in &own_here {
            if let Some((f, value, connector)) = flow_of.get(&own.names[k]) {
                let field = if net.connector_type(connector) == Some(ConnectorType::Spline) { "phi" } else { "s" };
                let Some(&p) = positions.index.get(&format!("{connector}.{field}")) else { continue };
                drop_flows.insert(*f);
                held.push((value.clone(), p));
            }
        }
        let held_names: HashSet<&str> = held.iter().map(|h| h.0.as_str()).collect();
        let mut reader = None;
        for (i, e) in eqs.equations.iter().enumerate() {
            let mut names = Vec::new();
            e.lhs.variables(&mut names);
            e.rhs.variables(&mut names);
            if !names.iter().any(|n| held_names.contains(n.as_str())) {
                continue;
            }
            let balance = linear(&(e.lhs.clone() - e.rhs.clone()))
                .filter(|f| f.terms.iter().all(|t| held_names.contains(t.0.as_str())) && f.constant == 0.0);
            let Some(balance) = balance else {
                reader.get_or_insert_with(|| e.origin.clone());
                continue;
            };
            for reaction in &constraints {
                let work: f64 = balance
                    .terms
                    .iter()
                    .map(|(name, c)| c * held.iter().find(|h| &h.0 == name).map_or(0.0, |h| reaction[h.1]))
                    .sum();
                let scale: f64 = balance.terms.iter().map(|t| t.1.abs()).sum::<f64>()
                    * reaction.iter().map(|c| c.abs()).fold(0.0, f64::max);
                if work.abs() > 1e-9 * scale {
                    return Err(problem(
                        "the flows of this equation are not those of an ideal constraint between the positions \
                         its connectors are held at: they would do work",
                        vec![e.origin.clone()],
                        held.iter().map(|h| h.0.clone()).collect(),
                        "an equation between positions transmits flows without loss (for `phi_a = ratio * phi_b`: \
                         `ratio * flange_a.tau + flange_b.tau = 0`); model losses with a damper or friction beside it",
                    ));
                }
            }
            drop_equations.insert(i);
        }
        let measured = reader.is_some();
        if !measured {
            drop_variables.extend(held.iter().map(|h| h.0.clone()));
        }

        let prefix = common_prefix(group.iter().flat_map(|&r| rows[r].own.iter().map(|t| own.names[t.0].as_str())));
        for (n, reaction) in constraints.iter().enumerate() {
            let mut terms = Vec::new();
            let mut joins = Vec::new();
            let (mut splines, mut flanges) = (0, 0);
            for (p, &c) in reaction[..positions.names.len()].iter().enumerate().filter(|(_, c)| **c != 0.0) {
                let (connector, _) = positions.names[p].rsplit_once('.').expect("a connector's position");
                let spline = net.connector_type(connector) == Some(ConnectorType::Spline);
                let count = if spline { &mut splines } else { &mut flanges };
                *count += 1;
                if *count > COUPLING_CONNECTORS {
                    return Err(problem(
                        format!("an equation between positions holds more than {COUPLING_CONNECTORS} connectors of one kind"),
                        group.iter().map(|&r| eqs.equations[rows[r].equation].origin.clone()).collect(),
                        vec![],
                        "split the relation with intermediate connectors",
                    ));
                }
                let (local, name) = if spline {
                    (*count - 1, SPLINES[*count - 1])
                } else {
                    (COUPLING_CONNECTORS + *count - 1, FLANGES[*count - 1])
                };
                terms.push((local, c));
                joins.push((name, connector.to_string()));
            }
            let base = if prefix.is_empty() { "equations".to_string() } else { prefix.clone() };
            let mut name = if n == 0 { base.clone() } else { format!("{base}.constraint{}", n + 1) };
            while model.component(&name).is_some() || extras.iter().any(|e: &Extra| e.name == name) {
                name.push('\'');
            }
            let constant = *reaction.last().expect("the constant is last");
            let part = EquationPart::Coupling { terms, constant, measured };
            extras.push(Extra { name, part, rotational: false, joins });
        }
        // Each held flow is what the constraints apply at its connector,
        // turned round: `flow = -sum_n c_n reaction_n`.
        if let Some(origin) = reader {
            let couplings = &extras[extras.len() - constraints.len()..];
            for (flow, p) in &held {
                let mut value = Expr::Const(0.0);
                for (reaction, coupling) in constraints.iter().zip(couplings) {
                    if reaction[*p] != 0.0 {
                        let multiplier = Expr::Var(format!("{}{REACTION}", coupling.name));
                        value = value + -reaction[*p] * multiplier;
                    }
                }
                measured_flows.push(Equation { lhs: Expr::Var(flow.clone()), rhs: value, origin: origin.clone() });
            }
        }
    }

    // Out of the equations: what the couplings now hold.
    let mut i = 0;
    eqs.equations.retain(|_| {
        i += 1;
        !drop_equations.contains(&(i - 1))
    });
    let mut f = 0;
    eqs.flows.retain(|_| {
        f += 1;
        !drop_flows.contains(&(f - 1))
    });
    eqs.variables.retain(|v| !drop_variables.contains(&v.name));
    eqs.equations.extend(measured_flows);
    Ok(extras)
}

/// The largest group of linear equations searched for relations between positions.
const MAX_GROUP: usize = 400;

const SPLINES: [&str; COUPLING_CONNECTORS] = ["spline_1", "spline_2", "spline_3", "spline_4"];
const FLANGES: [&str; COUPLING_CONNECTORS] = ["flange_1", "flange_2", "flange_3", "flange_4"];

/// The longest dotted prefix shared by the names (`sensor` for
/// `sensor.flange_a.phi` and `sensor.flange_b.phi`).
fn common_prefix<'a>(names: impl Iterator<Item = &'a str>) -> String {
    let mut prefix: Option<Vec<&str>> = None;
    for name in names {
        let parts: Vec<&str> = name.split('.').collect();
        let parts = &parts[..parts.len().saturating_sub(1)];
        prefix = Some(match prefix {
            None => parts.to_vec(),
            Some(p) => p.iter().zip(parts).take_while(|(a, b)| a == b).map(|(a, _)| *a).collect(),
        });
    }
    let mut p = prefix.unwrap_or_default();
    // `sensor.flange_a` alone: the component, not its connector.
    if p.len() > 1 {
        p.pop();
    }
    p.join(".")
}

/// Eliminates the own variables of a group of rows: the rows that pivot
/// on them stay (they compute those variables); the others, reduced, are
/// relations between positions alone. Returns those relations, independent
/// ones only (coefficients by position, then the constant), and the
/// equations they replace.
fn eliminate(
    group: &[usize],
    own: &[usize],
    rows: &[Row],
    positions: usize,
    equations: &[crate::model::Equation],
) -> Result<(Vec<Vec<f64>>, Vec<usize>), Error> {
    let width = own.len() + positions + 1;
    let mut m: Vec<Vec<f64>> = group
        .iter()
        .map(|&r| {
            let mut line = vec![0.0; width];
            for &(k, c) in &rows[r].own {
                line[own.iter().position(|&o| o == k).expect("own of the group")] += c;
            }
            for &(p, c) in &rows[r].positions {
                line[own.len() + p] += c;
            }
            line[width - 1] = rows[r].constant;
            line
        })
        .collect();
    let tiny = 1e-10 * m.iter().flatten().fold(0.0, |a: f64, c| a.max(c.abs()));
    // Forward elimination: own columns first, then positions.
    let mut pivoted = vec![false; m.len()];
    let mut pivot_on_own = vec![false; m.len()];
    for col in 0..width - 1 {
        let best = (0..m.len())
            .filter(|&r| !pivoted[r] && m[r][col].abs() > tiny)
            .max_by(|&a, &b| m[a][col].abs().total_cmp(&m[b][col].abs()));
        let Some(p) = best else { continue };
        pivoted[p] = true;
        pivot_on_own[p] = col < own.len();
        let pivot = m[p].clone();
        for r in (0..m.len()).filter(|&r| !pivoted[r]) {
            let k = m[r][col] / pivot[col];
            if k != 0.0 {
                m[r].iter_mut().zip(&pivot).for_each(|(x, y)| *x -= k * y);
                m[r][col] = 0.0;
            }
        }
    }
    let mut constraints = Vec::new();
    let mut replaced = Vec::new();
    for (r, line) in m.into_iter().enumerate() {
        if pivot_on_own[r] {
            continue;
        }
        replaced.push(rows[group[r]].equation);
        if pivoted[r] {
            constraints.push(line[own.len()..].to_vec());
        } else if line[width - 1].abs() > tiny {
            return Err(problem(
                "these equations between positions contradict each other",
                group.iter().map(|&g| equations[rows[g].equation].origin.clone()).collect(),
                vec![],
                "remove the equation that repeats a relation with another value",
            ));
        }
    }
    Ok((constraints, replaced))
}
