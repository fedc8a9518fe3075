//! Connections through user components. A user component may declare
//! connectors (`frame_a = Frame3D()`, `p = Pin()`) and connect them inside
//! and outside; the engine only knows the library's components, so
//! connectors are merged here (union-find) and each `connect` becomes a
//! connection between the library components' connectors it reaches.
//! Connectors that reach none (pins, heat ports) become equations; their
//! flows count by the level of each `connect` ([`ConnectionGraph::flow_sets`]).

use crate::reports::diagnostics::Diagnostic;
use crate::reports::source_map::SourceMap;
use crate::semantics::connectors::Connector;
use crate::syntax::source::Span;
use multibody::components::ConnectorType;
use multibody::math::union_find::UnionFind;
use multibody::Model;
use std::collections::HashMap;

#[derive(Clone, Debug)]
enum NodeKind {
    /// A connector of an engine component; its type if the kind has it.
    Leaf(Option<ConnectorType>),
    /// A connector a user component declares.
    Declared { ty: Connector, declaration: Span, owner: String },
}

#[derive(Clone, Debug)]
struct Node {
    name: String,
    kind: NodeKind,
}

#[derive(Clone, Debug)]
struct Statement {
    ends: Vec<(usize, Span)>,
    /// The instance whose relations hold the `connect` (`""` for the model).
    within: String,
}

/// The connectors met so far and the `connect` relations between them.
#[derive(Debug, Default)]
pub struct ConnectionGraph {
    nodes: Vec<Node>,
    by_name: HashMap<String, usize>,
    statements: Vec<Statement>,
    /// Where each node was first named in a `connect`.
    first_connect: HashMap<usize, Span>,
}

/// The connection sets: which set each connector is in, and the library
/// connectors of each.
pub struct Sets {
    set_of: HashMap<String, usize>,
    library: Vec<Vec<(String, Option<ConnectorType>)>>,
}

impl Sets {
    pub fn set_of(&self, name: &str) -> Option<usize> {
        self.set_of.get(name).copied()
    }

    /// The library connectors of set `set`, with their types.
    pub fn library(&self, set: usize) -> &[(String, Option<ConnectorType>)] {
        &self.library[set]
    }
}

/// What a connect end names, resolved by the lowering.
pub enum End {
    Leaf { name: String, ty: Option<ConnectorType> },
    Declared { name: String, ty: Connector, declaration: Span, owner: String },
}

/// One set of connectors joined by the `connect`s of one level of the
/// hierarchy: a connector is in it from inside (a connector of a
/// sub-component) or from outside (a connector of the component that
/// holds the `connect`), as Modelica counts flows.
pub struct FlowSet {
    pub inside: Vec<String>,
    pub outside: Vec<String>,
}

impl ConnectionGraph {
    /// Registers a connector a user component declares (even if never connected).
    pub fn declare(&mut self, name: String, ty: Connector, declaration: Span, owner: String) {
        self.node(End::Declared { name, ty, declaration, owner });
    }

    fn node(&mut self, end: End) -> usize {
        let (name, kind) = match end {
            End::Leaf { name, ty } => (name, NodeKind::Leaf(ty)),
            End::Declared { name, ty, declaration, owner } => (name, NodeKind::Declared { ty, declaration, owner }),
        };
        if let Some(&i) = self.by_name.get(&name) {
            return i;
        }
        self.nodes.push(Node { name: name.clone(), kind });
        self.by_name.insert(name, self.nodes.len() - 1);
        self.nodes.len() - 1
    }

    /// Where the first `connect` naming the connector `name` was written.
    pub fn connect_of(&self, name: &str) -> Option<Span> {
        self.first_connect.get(self.by_name.get(name)?).copied()
    }

    /// Where the connector `name` was declared, if a user component declares it.
    pub fn declaration_of(&self, name: &str) -> Option<Span> {
        match &self.nodes[*self.by_name.get(name)?].kind {
            NodeKind::Declared { declaration, .. } => Some(*declaration),
            NodeKind::Leaf(_) => None,
        }
    }

    /// The classes of connected connectors.
    fn classes(&self) -> Vec<usize> {
        let mut sets = UnionFind::new(self.nodes.len());
        for s in &self.statements {
            for w in s.ends.windows(2) {
                sets.union(w[0].0, w[1].0);
            }
        }
        (0..self.nodes.len()).map(|i| sets.find(i)).collect()
    }

    /// The connection sets, numbered by their first connector.
    pub fn sets(&self) -> Sets {
        let class = self.classes();
        let mut number: HashMap<usize, usize> = HashMap::new();
        let mut library: Vec<Vec<(String, Option<ConnectorType>)>> = Vec::new();
        let mut set_of = HashMap::new();
        for (i, node) in self.nodes.iter().enumerate() {
            let k = *number.entry(class[i]).or_insert_with(|| {
                library.push(Vec::new());
                library.len() - 1
            });
            set_of.insert(node.name.clone(), k);
            if let NodeKind::Leaf(ty) = node.kind {
                library[k].push((node.name.clone(), ty));
            }
        }
        Sets { set_of, library }
    }

    /// The name of a node's connector type, if known.
    fn type_name(&self, node: usize) -> Option<&str> {
        match &self.nodes[node].kind {
            NodeKind::Leaf(ty) => ty.map(|t| t.name()),
            NodeKind::Declared { ty, .. } => Some(ty.name.as_str()),
        }
    }

    /// Whether the connectors of nodes `a` and `b` may be connected; the
    /// engine checks connections between its own.
    fn compatible(&self, a: usize, b: usize) -> bool {
        match (&self.nodes[a].kind, &self.nodes[b].kind) {
            (NodeKind::Declared { ty: ta, .. }, NodeKind::Declared { ty: tb, .. }) => ta.connects_to(tb),
            (NodeKind::Declared { ty, .. }, NodeKind::Leaf(Some(leaf)))
            | (NodeKind::Leaf(Some(leaf)), NodeKind::Declared { ty, .. }) => ty.meets_engine(*leaf),
            _ => true,
        }
    }

    /// Adds one `connect`, written in the relations of the instance
    /// `within`. Checks the types of declared connectors against what
    /// they meet.
    pub fn connect(&mut self, ends: Vec<(End, Span)>, within: &str) -> Result<(), Diagnostic> {
        let ends: Vec<(usize, Span)> = ends.into_iter().map(|(e, s)| (self.node(e), s)).collect();
        for &(a, a_span) in &ends {
            for &(b, b_span) in &ends {
                if self.compatible(a, b) {
                    continue;
                }
                let (ta, tb) = (self.type_name(a).unwrap_or("?"), self.type_name(b).unwrap_or("?"));
                return Err(Diagnostic::error(format!(
                    "`{}` ({ta}) cannot be connected to `{}` ({tb})",
                    self.nodes[a].name, self.nodes[b].name,
                ))
                .primary(b_span, format!("a {tb} connector"))
                .secondary(a_span, format!("a {ta} connector"))
                .help("only connectors of the same type connect (pins to pins, frames to frames, splines to splines), and signals to signals"));
            }
        }
        for &(node, span) in &ends {
            self.first_connect.entry(node).or_insert(span);
        }
        self.statements.push(Statement { ends, within: within.to_string() });
        Ok(())
    }

    /// The connectors a user component declares, by name, with their types.
    pub fn declared(&self) -> impl Iterator<Item = (&str, &Connector)> {
        self.nodes.iter().filter_map(|n| match &n.kind {
            NodeKind::Declared { ty, .. } => Some((n.name.as_str(), ty)),
            NodeKind::Leaf(_) => None,
        })
    }

    /// The sets of Modelica's flow rule over the connectors `members`
    /// (declared connectors, joined to no engine connector): the
    /// `connect`s of one level join a connector's outside side (in the
    /// component that declares it) or its inside side (in the component
    /// around); each side of each connector is in exactly one set, alone
    /// if nothing joins it.
    pub fn flow_sets(&self, members: &[&str]) -> Vec<FlowSet> {
        // Element 2k is member k from inside, 2k + 1 from outside.
        let position: HashMap<&str, usize> = members.iter().enumerate().map(|(k, m)| (*m, k)).collect();
        let mut sets = UnionFind::new(2 * members.len());
        for s in &self.statements {
            let mut first: Option<usize> = None;
            for &(node, _) in &s.ends {
                let name = self.nodes[node].name.as_str();
                let Some(&k) = position.get(name) else { continue };
                let parent = name.rsplit_once('.').map_or("", |(parent, _)| parent);
                let element = 2 * k + usize::from(parent == s.within);
                match first {
                    None => first = Some(element),
                    Some(f) => sets.union(f, element),
                }
            }
        }
        let mut out: Vec<FlowSet> = Vec::new();
        let mut number: HashMap<usize, usize> = HashMap::new();
        for element in 0..2 * members.len() {
            let root = sets.find(element);
            let k = *number.entry(root).or_insert_with(|| {
                out.push(FlowSet { inside: Vec::new(), outside: Vec::new() });
                out.len() - 1
            });
            let name = members[element / 2].to_string();
            if element % 2 == 0 {
                out[k].inside.push(name);
            } else {
                out[k].outside.push(name);
            }
        }
        out
    }

    /// Adds the connections between engine connectors to `model`, records
    /// where their ends were written, and warns about declared connectors
    /// that reach no component (unless equations use them: `used`).
    pub fn finish(
        self,
        model: &mut Model,
        map: &mut SourceMap,
        used: &std::collections::HashSet<&str>,
    ) -> Vec<Diagnostic> {
        let class = self.classes();
        // Each class is represented by its first engine connector.
        let mut representative: HashMap<usize, usize> = HashMap::new();
        for (i, node) in self.nodes.iter().enumerate() {
            if matches!(node.kind, NodeKind::Leaf(_)) {
                representative.entry(class[i]).or_insert(i);
            }
        }
        for s in &self.statements {
            let mut ends: Vec<usize> = Vec::new();
            let mut written: Vec<(String, Span)> = Vec::new();
            for &(node, span) in &s.ends {
                let leaf = match self.nodes[node].kind {
                    NodeKind::Leaf(_) => Some(node),
                    NodeKind::Declared { .. } => representative.get(&class[node]).copied(),
                };
                if let Some(leaf) = leaf {
                    map.add_end(&self.nodes[leaf].name, span);
                    if !ends.contains(&leaf) {
                        ends.push(leaf);
                        written.push((self.nodes[leaf].name.clone(), span));
                    }
                }
            }
            if ends.len() >= 2 {
                model.connect(ends.iter().map(|&i| self.nodes[i].name.clone()));
                map.add_connection(written);
            }
        }
        // A declared connector must reach something inside its owner (a
        // component's connector, or one that a component written in Dyad
        // declares); otherwise connections to it have no effect. Per class,
        // how many connectors lie inside each instance.
        let mut inside_count: HashMap<(usize, &str), usize> = HashMap::new();
        for (node, &root) in self.nodes.iter().zip(&class) {
            *inside_count.entry((root, "")).or_default() += 1;
            for (k, _) in node.name.match_indices('.') {
                *inside_count.entry((root, &node.name[..k])).or_default() += 1;
            }
        }
        let mut warnings = Vec::new();
        let mut warned: Vec<Span> = Vec::new();
        for (i, &root) in class.iter().enumerate() {
            if let NodeKind::Declared { declaration, owner, .. } = &self.nodes[i].kind {
                if used.contains(self.nodes[i].name.as_str()) {
                    continue;
                }
                let instance = self.nodes[i].name.rsplit_once('.').map_or("", |(instance, _)| instance);
                // Itself, and at least one more.
                let reaches = inside_count.get(&(root, instance)).is_some_and(|&n| n > 1);
                if !reaches && !warned.contains(declaration) {
                    warned.push(*declaration);
                    let local = self.nodes[i].name.rsplit('.').next().unwrap_or_default();
                    warnings.push(
                        Diagnostic::warning(format!("the connector `{local}` of `{owner}` reaches no component"))
                            .primary(*declaration, "connects to nothing inside")
                            .help(format!(
                                "connect it inside `{owner}`, e.g. `connect({local}, body.frame_a)`; until then, connections to it have no effect"
                            )),
                    );
                }
            }
        }
        warnings
    }
}
