//! Motions prescribed with unknown efforts: equations that set a frame's
//! position to formulas of time (`hand.frame_a.r_0[1] = 1.2 + 0.2 *
//! cos(time)`), beside efforts that no equation decides (the torques of
//! the motors that move the joints). Each such equation fixes what the
//! mechanism already decides, and the efforts act on it only through the
//! accelerations: a problem of index 3, which Pantelides' algorithm would
//! differentiate twice. The mechanism does that differentiation exactly:
//! the prescribed positions become a servo constraint (its rows' second
//! derivatives are the constraint's `J ud + Jdot u`), whose multipliers
//! are the efforts. The equations then read the efforts after the
//! accelerations, as they read a measured coupling's reaction.

use super::{problem, Connectivity, Extra};
use crate::components::blocks::equation::{EquationPart, SERVO_ROWS};
use crate::components::ConnectorType;
use crate::math::expr::{Expr, TimeFunction};
use crate::math::union_find::UnionFind;
use crate::model::{Equation, Equations};
use crate::Error;
use std::collections::HashMap;

/// The suffix of the variable that stands for a servo's effort number `k`
/// (`hand.frame_a (servo) (effort 1)`): no name a model can write.
pub(super) const EFFORT: &str = " (effort ";

/// The local names of a servo's effort outputs.
const EFFORTS: [&str; SERVO_ROWS] = ["effort_1", "effort_2", "effort_3"];

/// A prescribed position: the frame connector, the world axis (0 = x), the
/// formula, and the equation that says so.
struct Target {
    connector: String,
    axis: usize,
    formula: TimeFunction,
    equation: usize,
}

/// The frame connector and axis of a library position `link.frame_b.r_0[2]`.
fn frame_position(name: &str, net: &Connectivity) -> Option<(String, usize)> {
    let (connector, member) = name.rsplit_once('.')?;
    let index = member.strip_prefix("r_0[")?.strip_suffix(']')?.parse::<usize>().ok()?;
    let is_frame = net.connector_type(connector) == Some(ConnectorType::Frame);
    (is_frame && (1..=3).contains(&index)).then(|| (connector.to_string(), index - 1))
}

/// Takes the equations of a motion prescribed with unknown efforts out of
/// `eqs` and returns the hidden servo that holds it; nothing when the
/// equations have no such pair (other mismatches are the sorting's to
/// explain).
pub(super) fn extract(eqs: &mut Equations, net: &mut Connectivity) -> Result<Vec<Extra>, Error> {
    // Most models prescribe no frame position: say so before any work.
    let mut names = Vec::new();
    for e in &eqs.equations {
        e.lhs.variables(&mut names);
        e.rhs.variables(&mut names);
    }
    if !names.iter().any(|n| n.contains(".r_0[")) {
        return Ok(Vec::new());
    }
    // Names made equal by `a = b`, in classes.
    let mut number: HashMap<String, usize> = HashMap::new();
    for n in names {
        let next = number.len();
        number.entry(n.to_string()).or_insert(next);
    }
    let mut classes = UnionFind::new(number.len());
    for e in &eqs.equations {
        if let (Expr::Var(a), Expr::Var(b)) = (&e.lhs, &e.rhs) {
            classes.union(number[a.as_str()], number[b.as_str()]);
        }
    }
    let mut members: HashMap<usize, Vec<&str>> = HashMap::new();
    for (name, &i) in &number {
        members.entry(classes.find(i)).or_default().push(name.as_str());
    }
    for list in members.values_mut() {
        list.sort_unstable();
    }
    let class_of = |name: &str, classes: &mut UnionFind| classes.find(number[name]);

    // Positions set to formulas of time.
    let mut targets = Vec::new();
    for (i, e) in eqs.equations.iter().enumerate() {
        let (x, formula) = match (&e.lhs, &e.rhs) {
            (Expr::Var(x), f) | (f, Expr::Var(x)) if !f.has_variables() => (x, f),
            _ => continue,
        };
        let class = class_of(x, &mut classes);
        let Some((connector, axis)) = members[&class].iter().find_map(|m| frame_position(m, net)) else { continue };
        let Ok(formula) = TimeFunction::new(formula) else { continue };
        targets.push(Target { connector, axis, formula, equation: i });
    }
    if targets.is_empty() {
        return Ok(Vec::new());
    }

    // Efforts: signal inputs nothing drives whose class appears in no
    // equation but the ones that make its names equal.
    let declared: std::collections::HashSet<&str> = eqs.variables.iter().map(|v| v.name.as_str()).collect();
    let mut used_elsewhere = vec![false; number.len()];
    for e in &eqs.equations {
        if matches!((&e.lhs, &e.rhs), (Expr::Var(_), Expr::Var(_))) {
            continue;
        }
        let mut names = Vec::new();
        e.lhs.variables(&mut names);
        e.rhs.variables(&mut names);
        for n in names {
            let c = class_of(n, &mut classes);
            used_elsewhere[c] = true;
        }
    }
    let mut other_uses: Vec<&String> = Vec::new();
    for w in &eqs.whens {
        for (condition, actions) in &w.branches {
            condition.variables(&mut other_uses);
            for a in actions {
                match a {
                    crate::model::WhenAction::Assign { variable, value, .. } => {
                        other_uses.push(variable);
                        value.variables(&mut other_uses);
                    }
                    crate::model::WhenAction::Reinit { value, .. } => value.variables(&mut other_uses),
                }
            }
        }
    }
    for e in &eqs.initial {
        e.lhs.variables(&mut other_uses);
        e.rhs.variables(&mut other_uses);
    }
    // A variable a flow is given by decides that flow: not an effort.
    for f in &eqs.flows {
        match f {
            crate::model::Flow::Frame { force, torque, .. } => other_uses.extend(force.iter().chain(torque)),
            crate::model::Flow::Frame2D { force, torque, .. } => {
                other_uses.extend(force.iter());
                other_uses.push(torque);
            }
            crate::model::Flow::Flange { value, .. } => other_uses.push(value),
        }
    }
    for n in other_uses {
        if let Some(&i) = number.get(n) {
            let c = classes.find(i);
            used_elsewhere[c] = true;
        }
    }
    let mut efforts: Vec<(usize, String)> = Vec::new();
    let mut roots: Vec<usize> = members.keys().copied().collect();
    roots.sort_by(|a, b| members[a].cmp(&members[b]));
    for root in roots {
        if used_elsewhere[root] {
            continue;
        }
        let list = &members[&root];
        let inputs: Vec<&str> =
            list.iter().copied().filter(|m| net.connector_type(m) == Some(ConnectorType::RealInput)).collect();
        let rest_declared = list.iter().all(|m| inputs.contains(m) || declared.contains(m));
        if let ([input], true) = (inputs.as_slice(), rest_declared) {
            if !net.driven(input, &[]) {
                efforts.push((root, input.to_string()));
            }
        }
    }
    if efforts.len() != targets.len() {
        return Ok(Vec::new());
    }

    let connector = targets[0].connector.clone();
    let origins = |ts: &[Target]| ts.iter().map(|t| eqs.equations[t.equation].origin.clone()).collect::<Vec<_>>();
    if targets.iter().any(|t| t.connector != connector) {
        return Err(problem(
            "equations prescribe the positions of more than one frame with unknown efforts, which is not solved yet",
            origins(&targets),
            Vec::new(),
            "prescribe one frame's position (up to its three coordinates), or prescribe the joints' motion",
        ));
    }
    targets.sort_by_key(|t| t.axis);
    if targets.windows(2).any(|w| w[0].axis == w[1].axis) {
        return Err(problem(
            "two equations prescribe the same coordinate of a frame's position",
            origins(&targets),
            Vec::new(),
            "remove one of them",
        ));
    }

    // The servo, joined to the frame and to the inputs it drives.
    let name = format!("{connector} (servo)");
    let mut joins = vec![("frame", connector.clone())];
    joins.extend(efforts.iter().zip(EFFORTS).map(|((_, input), local)| (local, input.clone())));
    let extra = Extra {
        name: name.clone(),
        part: EquationPart::Servo {
            axes: targets.iter().map(|t| t.axis).collect(),
            targets: targets.iter().map(|t| t.formula.clone()).collect(),
        },
        rotational: false,
        joins,
    };

    // Out: the prescribing equations and those that name the efforts;
    // in: each declared name of an effort reads it.
    let effort_roots: Vec<usize> = efforts.iter().map(|e| e.0).collect();
    let mut drop = vec![false; eqs.equations.len()];
    for t in &targets {
        drop[t.equation] = true;
    }
    for (i, e) in eqs.equations.iter().enumerate() {
        if let Expr::Var(a) = &e.lhs {
            if effort_roots.contains(&class_of(a, &mut classes)) {
                drop[i] = true;
            }
        }
    }
    let mut kept: Vec<Equation> =
        std::mem::take(&mut eqs.equations).into_iter().zip(drop).filter(|(_, d)| !d).map(|(e, _)| e).collect();
    for (k, (root, _)) in efforts.iter().enumerate() {
        for m in members[root].iter().filter(|m| declared.contains(*m)) {
            kept.push(Equation::new(Expr::var(*m), Expr::var(format!("{name}{EFFORT}{})", k + 1))));
        }
    }
    eqs.equations = kept;
    Ok(vec![extra])
}

/// The servo and effort number (from 0) that a name of [`extract`]'s stands for.
pub(super) fn effort_of(name: &str) -> Option<(&str, usize)> {
    let (servo, rest) = name.rsplit_once(EFFORT)?;
    let k = rest.strip_suffix(')')?.parse::<usize>().ok()?;
    Some((servo, k.checked_sub(1)?))
}
