//! Where each part of a lowered model came from, so that errors the engine
//! finds (by component name) point at the source.

use crate::syntax::source::Span;
use std::collections::HashMap;

/// The declaration of one engine component of the flattened model.
#[derive(Clone, Debug, PartialEq)]
pub struct ComponentSite {
    /// The whole declaration `name = Kind(...)`.
    pub declaration: Span,
    /// The enclosing instances, innermost first: (`pend`, its declaration).
    pub within: Vec<(String, Span)>,
}

/// A modifier or start value of one component.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MemberSite {
    pub name: Span,
    pub value: Option<Span>,
}

/// A component of the files used where its name is also a library
/// component's (`world = World()` with a `component World` in the files).
#[derive(Clone, Debug, PartialEq)]
pub struct Shadowing {
    /// The library kind it shadows (`World`).
    pub library_kind: String,
    /// The declaration that uses the user component.
    pub used: Span,
    /// The name in the user component's definition.
    pub defined: Span,
}

#[derive(Clone, Debug, Default, PartialEq)]
pub struct SourceMap {
    /// The model's top component: its name and the header of its definition.
    pub root: Option<(String, Span)>,
    components: HashMap<String, ComponentSite>,
    members: HashMap<(String, String), MemberSite>,
    /// Connection ends (`pend.body.frame_a`) to the places that connect them.
    ends: HashMap<String, Vec<Span>>,
    /// The engine's connections, each end with where it was written.
    connections: Vec<Vec<(String, Span)>>,
    /// Uses of user components named like library components.
    pub shadowing: Vec<Shadowing>,
    /// Where the model's equations and variables were written: the origin
    /// `#k` of an equation or variable is `origins[k]`.
    pub origins: Vec<Span>,
    /// The declaration of each variable of the equations, by its name.
    pub variables: HashMap<String, Span>,
}

impl SourceMap {
    pub fn add_component(&mut self, name: &str, site: ComponentSite) {
        self.components.insert(name.to_string(), site);
    }

    pub fn add_member(&mut self, component: &str, member: &str, site: MemberSite) {
        self.members.insert((component.to_string(), member.to_string()), site);
    }

    pub fn add_end(&mut self, end: &str, span: Span) {
        let spans = self.ends.entry(end.to_string()).or_default();
        if !spans.contains(&span) {
            spans.push(span);
        }
    }

    pub fn add_connection(&mut self, ends: Vec<(String, Span)>) {
        self.connections.push(ends);
    }

    /// Where `a` and `b` were written in the connection that joins them.
    pub fn connection_of(&self, a: &str, b: &str) -> Option<(Span, Span)> {
        self.connections.iter().find_map(|ends| {
            let find = |name: &str| ends.iter().find(|(n, _)| n == name).map(|(_, s)| *s);
            Some((find(a)?, find(b)?))
        })
    }

    /// Where the variable `name` of the equations was declared.
    pub fn variable(&self, name: &str) -> Option<Span> {
        self.variables.get(name).copied()
    }

    /// The name of the origin `origins[k]`, `#k`, that equations and
    /// variables carry.
    pub fn origin_name(k: usize) -> String {
        format!("#{k}")
    }

    /// The span of an origin `#k` the lowering gave an equation or variable.
    pub fn origin(&self, origin: &str) -> Option<Span> {
        origin.strip_prefix('#')?.parse::<usize>().ok().and_then(|k| self.origins.get(k).copied())
    }

    pub fn component(&self, name: &str) -> Option<&ComponentSite> {
        self.components.get(name)
    }

    pub fn member(&self, component: &str, member: &str) -> Option<&MemberSite> {
        self.members.get(&(component.to_string(), member.to_string()))
    }

    /// The members set on a component, by name.
    pub fn members_of<'a>(&'a self, component: &'a str) -> impl Iterator<Item = (&'a str, &'a MemberSite)> + 'a {
        self.members.iter().filter(move |((c, _), _)| c == component).map(|((_, m), site)| (m.as_str(), site))
    }

    pub fn end(&self, end: &str) -> Option<Span> {
        self.ends.get(end).and_then(|s| s.first().copied())
    }
}
