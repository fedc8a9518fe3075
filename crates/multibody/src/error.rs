//! Errors of model validation and assembly. Each says what is wrong, names
//! the components involved (so that a front end can point at their
//! declarations) and says what to do.

use std::fmt::Write;

/// Why a model could not be validated or assembled.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum Error {
    #[error("`{component}` is of unknown kind `{kind}`.{}", suggest(suggestions, "kind"))]
    UnknownKind { component: String, kind: String, suggestions: Vec<String> },

    #[error("two components are named `{name}`; give each component its own name")]
    DuplicateName { name: String },

    #[error("{kind} has no parameter `{param}` (in `{component}`).{}{}\nIts parameters are: {}", suggest(suggestions, "parameter"), if *planar_has_it { format!(" The planar PlanarMechanics.{kind} has it: write `PlanarMechanics.{kind}`; in a model file inside a folder named PlanarMechanics, short names are the planar components.") } else { String::new() }, valid.join(", "))]
    UnknownParameter {
        component: String,
        kind: String,
        param: String,
        suggestions: Vec<String>,
        valid: Vec<String>,
        /// The planar component of the same name has the parameter: the
        /// model most likely meant it.
        planar_has_it: bool,
    },

    #[error("{kind} has no variable `{variable}` that takes a start value (in `{component}`).{}\nVariables with start values: {}", suggest(suggestions, "variable"), if valid.is_empty() { "none".to_string() } else { valid.join(", ") })]
    UnknownVariable { component: String, kind: String, variable: String, suggestions: Vec<String>, valid: Vec<String> },

    #[error("{kind} `{component}` needs a value for `{param}` ({doc}); it has no default")]
    MissingParameter { component: String, kind: String, param: String, doc: String },

    #[error("`{component}.{name}` needs {expected} numbers, but {got} were given")]
    WrongSize { component: String, name: String, expected: usize, got: usize },

    #[error("`{component}.{name}` must be {expected}, but {got} was given")]
    WrongType { component: String, name: String, expected: String, got: String },

    #[error("`{component}.{name}` = {value} is not allowed: {reason}")]
    InvalidValue { component: String, name: String, value: String, reason: String },

    #[error("`{reference}` in a connection names no component.{}", suggest(suggestions, "component"))]
    UnknownComponent { reference: String, suggestions: Vec<String> },

    #[error("{kind} has no connector `{connector}` (in `{component}`).{}\nIts connectors are: {}", suggest(suggestions, "connector"), valid.join(", "))]
    UnknownConnector {
        component: String,
        kind: String,
        connector: String,
        suggestions: Vec<String>,
        valid: Vec<String>,
    },

    #[error("`{a}` ({a_type}) cannot be connected to `{b}` ({b_type}): only connectors of the same type connect{}", if a_type.starts_with("Frame") && b_type.starts_with("Frame") { "; a planar frame joins a 3-D one through a PlanarMechanics.PlanarToMultiBody" } else { "" })]
    IncompatibleConnectors { a: String, a_type: String, b: String, b_type: String },

    #[error("a connection needs at least two connectors, `{0}` is alone")]
    LonelyConnection(String),

    #[error("the model has no World; add one component of kind World (PlanarMechanics.World for a planar model): every mechanism is positioned relative to it")]
    NoWorld,

    #[error("the model has {} Worlds ({}); keep exactly one (besides, a model may have one PlanarMechanics.World)", names.len(), names.join(", "))]
    SeveralWorlds { names: Vec<String> },

    #[error("nothing owns the orientation of the assembly of {}: it is not connected to the World and has no Body with an orientation state.\nTo fix it, either connect it to the World (through joints or fixed parts), or give it an owner: a Body with `orientation_state = OrientationState.Quaternion()` (or `OrientationState.Euler()`) rigidly attached to it.", list(components))]
    NoOrientationOwner { components: Vec<String> },

    #[error("the assembly of {} has two owners of its orientation, `{first}` and `{second}`; keep exactly one (set the other's `orientation_state` to None, or `isroot = false`)", list(group))]
    TwoOwners { first: String, second: String, group: Vec<String> },

    #[error("`{component}` has `isroot = true` but is connected (to {}); a root PointMass must be unconnected. Set `isroot = false`: its orientation then comes from what it is connected to", list(connected_to))]
    ConnectedRootPointMass { component: String, connected_to: Vec<String> },

    #[error("`{component}` has an orientation state, but joints from the World already position it (through {}); set its `orientation_state` to None", list(through))]
    OwnerPositionedByJoints { component: String, through: Vec<String> },

    #[error("the {dof} of `{joint}` has no inertia behind it: what it moves ({}) has no mass or inertia for this motion. Give a body there mass and inertia, or move the mass off the joint axis", list(moved))]
    NoInertia { joint: String, dof: String, moved: Vec<String> },

    #[error("`{component}` starts at the singular configuration of its Euler angles (sequence {sequence:?}, where the first and third axes line up); start it away from it, or use orientation_state = Quaternion")]
    EulerSingularStart { component: String, sequence: [usize; 3] },

    #[error("`{component}.{variable}` is not a state here: {reason}")]
    NotAState { component: String, variable: String, reason: String },

    #[error("`{component}.{variable}` cannot start at {value}: with the start values that hold{}, it starts at {} at best. Make one of them a guess (`guess` instead of `initial`), or change this value", if fixed.is_empty() { String::new() } else { format!(" ({})", list(fixed)) }, crate::Value::Number((reached * 1e9).round() / 1e9))]
    StartUnmet { component: String, variable: String, value: f64, reached: f64, fixed: Vec<String> },

    #[error("the kinematic loop through {} cannot close: its constraints stay violated by {residual:.3e} (m or rad) at best.{}\nCheck the lengths and axes of the loop's parts, or fix fewer start values (use `guess` instead of `initial`).", list(joints), if fixed.is_empty() { String::new() } else { format!(" The fixed start values are {}.", fixed.join(", ")) })]
    LoopCannotClose { joints: Vec<String>, residual: f64, fixed: Vec<String> },

    #[error("the start velocities of the loop through {} contradict its constraints (by {violation:.3e}).{}\nFix fewer start velocities (use `guess` instead of `initial`).", list(joints), if fixed.is_empty() { String::new() } else { format!(" The fixed start velocities are {}.", fixed.join(", ")) })]
    LoopCannotMove { joints: Vec<String>, violation: f64, fixed: Vec<String> },

    #[error("`{component}`: {what} is not supported yet{}", if fix.is_empty() { String::new() } else { format!("; {fix}") })]
    Unsupported {
        component: String,
        what: String,
        /// What to do instead (may be empty).
        fix: String,
    },

    #[error("the 1-D connector `{connector}` is not attached to a joint axis or support; connect it to a joint declared with `axisflange = true`")]
    FloatingFlange { connector: String },

    #[error("`{connector}` is connected, but {why}")]
    UnusedConnected { connector: String, why: String },

    #[error("the parts {} are joined rigidly in two ways that disagree (a closed chain of fixed parts that does not close); remove one of the connections", list(components))]
    InconsistentRigidLoop { components: Vec<String> },

    #[error("the signals of {} depend on each other at the same instant (an algebraic loop); break the loop with a block that has a state, or change the connections", list(components))]
    AlgebraicLoop { components: Vec<String> },

    #[error("{problem}{}{}", if equations.is_empty() { String::new() } else { format!("\nin: {}", equations.join("; ")) }, if fix.is_empty() { String::new() } else { format!("\n{fix}") })]
    Equations {
        problem: String,
        /// The origins of the equations concerned (as the model gave them).
        equations: Vec<String>,
        /// The variables concerned.
        variables: Vec<String>,
        /// What to do (may be empty).
        fix: String,
    },
}

impl Error {
    /// The components this error is about, first the one to point at.
    pub fn components(&self) -> Vec<&str> {
        use Error::*;
        match self {
            UnknownKind { component, .. }
            | MissingParameter { component, .. }
            | UnknownParameter { component, .. }
            | UnknownVariable { component, .. }
            | WrongSize { component, .. }
            | WrongType { component, .. }
            | InvalidValue { component, .. }
            | UnknownConnector { component, .. }
            | ConnectedRootPointMass { component, .. }
            | OwnerPositionedByJoints { component, .. }
            | NotAState { component, .. }
            | StartUnmet { component, .. }
            | EulerSingularStart { component, .. }
            | Unsupported { component, .. } => vec![component],
            DuplicateName { name } => vec![name],
            LoopCannotClose { joints, .. } | LoopCannotMove { joints, .. } => {
                joints.iter().map(String::as_str).collect()
            }
            NoOrientationOwner { components } | InconsistentRigidLoop { components } | AlgebraicLoop { components } => {
                components.iter().map(String::as_str).collect()
            }
            TwoOwners { first, second, .. } => vec![first, second],
            NoInertia { joint, moved, .. } => {
                std::iter::once(joint.as_str()).chain(moved.iter().map(String::as_str)).collect()
            }
            IncompatibleConnectors { a, b, .. } => vec![component_of(a), component_of(b)],
            UnknownComponent { reference, .. } => vec![component_of(reference)],
            LonelyConnection(c) | FloatingFlange { connector: c } | UnusedConnected { connector: c, .. } => {
                vec![component_of(c)]
            }
            NoWorld | SeveralWorlds { .. } | Equations { .. } => vec![],
        }
    }

    /// The parameter or variable this error is about, if any.
    pub fn member(&self) -> Option<&str> {
        use Error::*;
        match self {
            UnknownParameter { param, .. } | MissingParameter { param, .. } => Some(param),
            UnknownVariable { variable, .. } | NotAState { variable, .. } | StartUnmet { variable, .. } => {
                Some(variable)
            }
            WrongSize { name, .. } | WrongType { name, .. } | InvalidValue { name, .. } => Some(name),
            UnknownConnector { connector, .. } => Some(connector),
            _ => None,
        }
    }
}

/// The component of `component.connector` (component names may contain dots).
fn component_of(reference: &str) -> &str {
    reference.rsplit_once('.').map_or(reference, |(component, _)| component)
}

/// "`a`, `b` and `c`" (long lists are cut: "... and 4 more").
pub(crate) fn list(names: &[String]) -> String {
    join(names, "and")
}

/// "`a`, `b` or `c`".
pub(crate) fn list_or(names: &[String]) -> String {
    join(names, "or")
}

fn join(names: &[String], conjunction: &str) -> String {
    let quoted: Vec<String> = names.iter().map(|n| format!("`{n}`")).collect();
    match quoted.len() {
        0 => "no components".into(),
        1 => quoted[0].clone(),
        n if n <= 8 => format!("{} {conjunction} {}", quoted[..n - 1].join(", "), quoted[n - 1]),
        n => format!("{} {conjunction} {} more", quoted[..6].join(", "), n - 6),
    }
}

fn suggest(suggestions: &[String], what: &str) -> String {
    let mut s = String::new();
    match suggestions {
        [] => {}
        [one] => {
            let _ = write!(s, " Did you mean `{one}`?");
        }
        many => {
            let _ = write!(s, " Did you mean one of these {what}s: {}?", list(many));
        }
    }
    s
}

/// The names closest to `wanted` among `candidates` (by edit distance, and
/// ignoring case), best first.
pub fn closest<'a>(wanted: &str, candidates: impl IntoIterator<Item = &'a str>) -> Vec<String> {
    let wanted_lower = wanted.to_lowercase();
    let mut scored: Vec<(usize, &str)> = candidates
        .into_iter()
        .map(|c| {
            let lower = c.to_lowercase();
            let d = if lower == wanted_lower { 0 } else { edit_distance(&wanted_lower, &lower) };
            (d, c)
        })
        .collect();
    scored.sort();
    scored.dedup_by(|a, b| a.1 == b.1);
    let limit = (wanted.chars().count() / 3).clamp(1, 3);
    let best: Vec<String> = scored.iter().filter(|(d, _)| *d <= limit).take(3).map(|(_, c)| c.to_string()).collect();
    if best.is_empty() {
        // A prefix or suffix match helps with `Components.`-style prefixes.
        scored
            .iter()
            .filter(|(_, c)| {
                let c = c.to_lowercase();
                c.ends_with(&wanted_lower) || wanted_lower.ends_with(&c)
            })
            .take(3)
            .map(|(_, c)| c.to_string())
            .collect()
    } else {
        best
    }
}

/// Optimal-string-alignment distance: insertions, deletions, substitutions
/// and swaps of neighbours each count one.
fn edit_distance(a: &str, b: &str) -> usize {
    let a: Vec<char> = a.chars().collect();
    let b: Vec<char> = b.chars().collect();
    let mut d = vec![vec![0usize; b.len() + 1]; a.len() + 1];
    for (i, row) in d.iter_mut().enumerate() {
        row[0] = i;
    }
    for (j, x) in d[0].iter_mut().enumerate() {
        *x = j;
    }
    for i in 1..=a.len() {
        for j in 1..=b.len() {
            let cost = usize::from(a[i - 1] != b[j - 1]);
            d[i][j] = (d[i - 1][j] + 1).min(d[i][j - 1] + 1).min(d[i - 1][j - 1] + cost);
            if i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1] {
                d[i][j] = d[i][j].min(d[i - 2][j - 2] + 1);
            }
        }
    }
    d[a.len()][b.len()]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn suggestions_find_typos() {
        assert_eq!(closest("r_mc", ["r_cm", "m", "I_11"]), vec!["r_cm"]);
        assert_eq!(closest("Revolut", ["Revolute", "Prismatic"]), vec!["Revolute"]);
        assert!(closest("zzzz", ["Revolute", "Prismatic"]).is_empty());
    }
}
