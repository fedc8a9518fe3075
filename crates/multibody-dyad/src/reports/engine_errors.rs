//! Errors the engine finds while assembling, pointed at the source: the
//! engine names components (and a parameter, variable or connector); the
//! source map knows where those were written.

use crate::reports::diagnostics::Diagnostic;
use crate::reports::source_map::SourceMap;
use crate::syntax::source::Span;
use multibody::Error;

/// At most this many other components get a label.
const MAX_SECONDARY: usize = 6;

/// The engine's message (first line as the title, the rest as notes) with
/// labels at the declarations, modifiers and connections it is about.
pub fn engine_diagnostic(error: &Error, map: &SourceMap) -> Diagnostic {
    if let Some(d) = shadowed_world(error, map) {
        return d;
    }
    if let Error::Equations { problem, equations, variables, fix } = error {
        return equations_diagnostic(problem, equations, variables, fix, map);
    }
    let text = error.to_string();
    let mut d = match error {
        // What is not supported is the message; what to do instead, the help.
        Error::Unsupported { component, what, fix } => {
            let d = Diagnostic::error(format!("`{component}`: {what} is not supported yet"));
            if fix.is_empty() {
                d
            } else {
                d.help(fix)
            }
        }
        _ => {
            let mut lines = text.lines();
            let mut d = Diagnostic::error(lines.next().unwrap_or("the model cannot be assembled"));
            for line in lines.filter(|l| !l.trim().is_empty()) {
                d = d.note(line.trim());
            }
            d
        }
    };
    if let Error::MissingParameter { param, .. } = error {
        d = d.help(format!("give it a value: `{param} = ...`"));
    }
    let (primary, others) = places(error, map);
    let mut used: Vec<Span> = Vec::new();
    if let Some((span, label)) = primary {
        d = d.primary(span, label);
        used.push(span);
    } else if let Some((_, header)) = &map.root {
        d = d.primary(*header, "in this model");
        used.push(*header);
    }
    for (span, label) in others.into_iter().take(MAX_SECONDARY) {
        if !used.contains(&span) {
            used.push(span);
            d = d.secondary(span, label);
        }
    }
    // Modifiers the message mentions (`orientation_state`, `isroot`, ...).
    for component in named_components(error) {
        let mut members: Vec<(&str, Span)> = map
            .members_of(&component)
            .filter(|(m, _)| text.contains(&format!("`{m}`")) || text.contains(&format!("{m} =")))
            .map(|(m, site)| (m, site.name))
            .collect();
        members.sort_by_key(|(_, span)| *span);
        for (member, span) in members {
            if !used.contains(&span) {
                used.push(span);
                d = d.secondary(span, format!("`{member}` of `{component}` is set here"));
            }
        }
    }
    // Where nested components are instantiated.
    if let Some(site) = named_components(error).first().and_then(|c| map.component(c)) {
        for (instance, span) in &site.within {
            if !used.contains(span) {
                used.push(*span);
                d = d.secondary(*span, format!("in `{instance}`, declared here"));
            }
        }
    }
    d
}

/// No World, where the model uses a component of the files named `World`:
/// that component, not the library's World, is what the model has.
fn shadowed_world(error: &Error, map: &SourceMap) -> Option<Diagnostic> {
    if !matches!(error, Error::NoWorld) {
        return None;
    }
    let shadow = map.shadowing.iter().find(|s| s.library_kind == "World")?;
    Some(
        Diagnostic::error(
            "the model has no World: the `World` it uses is the component defined in these files, which shadows the library's World",
        )
        .primary(shadow.used, "this is the files' own `World`, not the library's")
        .secondary(shadow.defined, "this definition shadows the library's World")
        .note("a component of the files named like a library component is used in its place wherever the name is written alone")
        .help("rename your component (e.g. `MyWorld`), or write `MultibodyComponents.World()` to use the library's World; to keep your component as the model's World, declare a `MultibodyComponents.World()` inside it"),
    )
}

/// The components an error names, by their full (flattened) names.
fn named_components(error: &Error) -> Vec<String> {
    match error {
        // These name connectors `component.connector`; components may contain dots.
        Error::IncompatibleConnectors { a, b, .. } => vec![component_of(a), component_of(b)],
        Error::UnknownComponent { reference, .. } => vec![component_of(reference)],
        Error::LonelyConnection(c)
        | Error::FloatingFlange { connector: c }
        | Error::UnusedConnected { connector: c, .. } => {
            vec![component_of(c)]
        }
        Error::SeveralWorlds { names } => names.clone(),
        other => other.components().into_iter().map(str::to_string).collect(),
    }
}

fn component_of(connector: &str) -> String {
    connector.rsplit_once('.').map_or(connector, |(c, _)| c).to_string()
}

type Place = (Span, String);

/// The primary place and the other places of an error.
fn places(error: &Error, map: &SourceMap) -> (Option<Place>, Vec<Place>) {
    let declaration = |name: &str| map.component(name).map(|s| s.declaration);
    let declared = |name: &str, label: String| declaration(name).map(|s| (s, label));
    let end = |connector: &str, label: String| {
        map.end(connector).or_else(|| declaration(&component_of(connector))).map(|s| (s, label))
    };
    match error {
        Error::IncompatibleConnectors { a, a_type, b, b_type } => {
            let (a_label, b_label) = (format!("a {a_type} connector"), format!("a {b_type} connector"));
            match map.connection_of(a, b) {
                Some((a_span, b_span)) => (Some((b_span, b_label)), vec![(a_span, a_label)]),
                None => (end(b, b_label), end(a, a_label).into_iter().collect()),
            }
        }
        Error::UnknownConnector { component, connector, .. } => {
            let full = format!("{component}.{connector}");
            (end(&full, "unknown connector".into()), vec![])
        }
        Error::UnknownComponent { reference, .. } => (end(reference, "no such component".into()), vec![]),
        Error::LonelyConnection(c) => (end(c, "connected to nothing".into()), vec![]),
        Error::FloatingFlange { connector } => {
            (end(connector, "not attached to a joint axis or support".into()), vec![])
        }
        Error::UnusedConnected { connector, .. } => (end(connector, "connected, but not used".into()), vec![]),
        Error::NoWorld => (map.root.as_ref().map(|(_, h)| (*h, "this model has no World".into())), vec![]),
        Error::SeveralWorlds { names } => {
            let mut all: Vec<Place> = names.iter().filter_map(|n| declared(n, "a World".into())).collect();
            let first = (!all.is_empty()).then(|| all.remove(0));
            (first, all)
        }
        _ => {
            let names = named_components(error);
            let Some(first) = names.first() else { return (None, vec![]) };
            let label = primary_label(error);
            // Point at the modifier the error is about when there is one.
            let member_place = error.member().and_then(|m| map.member(first, m)).map(|site| {
                let span = match error {
                    Error::WrongSize { .. } | Error::WrongType { .. } | Error::InvalidValue { .. } => {
                        site.value.unwrap_or(site.name)
                    }
                    _ => site.name,
                };
                (span, label.clone())
            });
            let primary = member_place.or_else(|| declared(first, label));
            let others = names.iter().skip(1).filter_map(|n| declared(n, secondary_label(error, n))).collect();
            (primary, others)
        }
    }
}

fn primary_label(error: &Error) -> String {
    match error {
        Error::UnknownParameter { .. } => "unknown parameter".into(),
        Error::UnknownVariable { .. } => "unknown variable".into(),
        Error::MissingParameter { param, .. } => format!("needs `{param}`"),
        Error::WrongSize { expected, .. } => format!("needs {expected} numbers"),
        Error::WrongType { expected, .. } => format!("needs {expected}"),
        Error::InvalidValue { .. } => "not allowed".into(),
        Error::NoOrientationOwner { .. } => "nothing owns the orientation of this part".into(),
        Error::TwoOwners { .. } => "first owner".into(),
        Error::ConnectedRootPointMass { .. } => "a root point mass, but connected".into(),
        Error::OwnerPositionedByJoints { .. } => "has an orientation state".into(),
        Error::NoInertia { .. } => "no inertia behind this joint".into(),
        Error::NotAState { .. } => "not a state".into(),
        Error::StartUnmet { .. } => "cannot hold".into(),
        Error::Unsupported { .. } => "not supported yet".into(),
        Error::InconsistentRigidLoop { .. } => "part of the loop".into(),
        Error::AlgebraicLoop { .. } => "part of the algebraic loop".into(),
        Error::DuplicateName { .. } => "declared twice".into(),
        _ => "here".into(),
    }
}

fn secondary_label(error: &Error, name: &str) -> String {
    match error {
        Error::TwoOwners { .. } => "second owner".into(),
        Error::NoInertia { .. } => format!("`{name}` is moved by the joint"),
        Error::NoOrientationOwner { .. } => format!("`{name}` is in the same free part"),
        Error::InconsistentRigidLoop { .. } => "part of the loop".into(),
        Error::AlgebraicLoop { .. } => "part of the algebraic loop".into(),
        _ => format!("`{name}` is declared here"),
    }
}

/// An error of the model's equations: the equations it concerns (from
/// their origins `#k`), and the declarations of its variables.
fn equations_diagnostic(
    problem: &str,
    equations: &[String],
    variables: &[String],
    fix: &str,
    map: &SourceMap,
) -> Diagnostic {
    let mut d = Diagnostic::error(problem);
    let mut used: Vec<Span> = Vec::new();
    for (k, origin) in equations.iter().enumerate() {
        let Some(span) = map.origin(origin) else { continue };
        if used.contains(&span) || used.len() > MAX_SECONDARY {
            continue;
        }
        used.push(span);
        d = if k == 0 { d.primary(span, "this equation") } else { d.secondary(span, "and this one") };
    }
    // Variables are named by their flattened names; their declarations are
    // origins too when the lowering gave them one.
    for v in variables {
        if let Some(span) = map.variable(v) {
            if !used.contains(&span) && used.len() <= MAX_SECONDARY {
                d = if used.is_empty() {
                    d.primary(span, format!("`{v}`"))
                } else {
                    d.secondary(span, format!("`{v}`"))
                };
                used.push(span);
            }
        }
    }
    if used.is_empty() {
        if let Some((_, header)) = &map.root {
            d = d.primary(*header, "in this model");
        }
    }
    if !fix.is_empty() {
        d = d.help(fix);
    }
    d
}
