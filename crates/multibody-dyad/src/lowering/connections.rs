//! Connections through user components. A user component may declare
//! connectors (`frame_a = Frame3D()`) and connect them inside and outside;
//! the engine only knows the library's components, so connectors are
//! merged here (union-find) and each `connect` becomes a connection between
//! the library components' connectors it reaches.

use crate::reports::diagnostics::Diagnostic;
use crate::reports::source_map::SourceMap;
use crate::syntax::source::Span;
use multibody::components::ConnectorType;
use multibody::Model;
use std::collections::HashMap;

#[derive(Clone, Debug)]
enum NodeKind {
    /// A connector of an engine component; its type if the kind has it.
    Leaf(Option<ConnectorType>),
    /// A connector a user component declares.
    Declared { ty: ConnectorType, declaration: Span, owner: String },
}

#[derive(Clone, Debug)]
struct Node {
    name: String,
    kind: NodeKind,
}

#[derive(Clone, Debug)]
struct Statement {
    ends: Vec<(usize, Span)>,
}

/// The connectors met so far and the `connect` relations between them.
#[derive(Debug, Default)]
pub struct ConnectionGraph {
    nodes: Vec<Node>,
    by_name: HashMap<String, usize>,
    statements: Vec<Statement>,
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
    Declared { name: String, ty: ConnectorType, declaration: Span, owner: String },
}

impl ConnectionGraph {
    /// Registers a connector a user component declares (even if never connected).
    pub fn declare(&mut self, name: String, ty: ConnectorType, declaration: Span, owner: String) {
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
        let node = *self.by_name.get(name)?;
        self.statements.iter().flat_map(|s| s.ends.iter()).find(|(n, _)| *n == node).map(|(_, span)| *span)
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
        let n = self.nodes.len();
        let mut parent: Vec<usize> = (0..n).collect();
        fn find(parent: &mut [usize], mut i: usize) -> usize {
            while parent[i] != i {
                parent[i] = parent[parent[i]];
                i = parent[i];
            }
            i
        }
        for s in &self.statements {
            for w in s.ends.windows(2) {
                let (a, b) = (find(&mut parent, w[0].0), find(&mut parent, w[1].0));
                if a != b {
                    parent[b.max(a)] = a.min(b);
                }
            }
        }
        (0..n).map(|i| find(&mut parent, i)).collect()
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

    fn ty(&self, node: usize) -> Option<ConnectorType> {
        match self.nodes[node].kind {
            NodeKind::Leaf(ty) => ty,
            NodeKind::Declared { ty, .. } => Some(ty),
        }
    }

    /// Adds one `connect`. Checks the types of declared connectors against
    /// what they meet; the engine checks connections between its own.
    pub fn connect(&mut self, ends: Vec<(End, Span)>) -> Result<(), Diagnostic> {
        let ends: Vec<(usize, Span)> = ends.into_iter().map(|(e, s)| (self.node(e), s)).collect();
        let declared = |g: &Self, n: usize| matches!(g.nodes[n].kind, NodeKind::Declared { .. });
        for &(a, a_span) in &ends {
            for &(b, b_span) in &ends {
                let (Some(ta), Some(tb)) = (self.ty(a), self.ty(b)) else { continue };
                if !ta.connects_to(&tb) && (declared(self, a) || declared(self, b)) {
                    return Err(Diagnostic::error(format!(
                        "`{}` ({}) cannot be connected to `{}` ({})",
                        self.nodes[a].name,
                        ta.name(),
                        self.nodes[b].name,
                        tb.name()
                    ))
                    .primary(b_span, format!("a {} connector", tb.name()))
                    .secondary(a_span, format!("a {} connector", ta.name()))
                    .help("only connectors of the same type connect: frames to frames, splines to splines, flanges to flanges, signals to signals"));
                }
            }
        }
        self.statements.push(Statement { ends });
        Ok(())
    }

    /// Adds the connections between engine connectors to `model`, records
    /// where their ends were written, and warns about declared connectors
    /// that reach no component (unless equations use them: `used`).
    pub fn finish(self, model: &mut Model, map: &mut SourceMap, used: &[String]) -> Vec<Diagnostic> {
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
        // A declared connector must reach a component inside its owner;
        // otherwise connections to it from outside have no effect.
        let mut leaves_of: HashMap<usize, Vec<&str>> = HashMap::new();
        for (node, &root) in self.nodes.iter().zip(&class) {
            if matches!(node.kind, NodeKind::Leaf(_)) {
                leaves_of.entry(root).or_default().push(&node.name);
            }
        }
        let mut warnings = Vec::new();
        let mut warned: Vec<Span> = Vec::new();
        for (i, &root) in class.iter().enumerate() {
            if let NodeKind::Declared { declaration, owner, .. } = &self.nodes[i].kind {
                if used.contains(&self.nodes[i].name) {
                    continue;
                }
                let inside = match self.nodes[i].name.rsplit_once('.') {
                    Some((instance, _)) => format!("{instance}."),
                    None => String::new(),
                };
                let reaches = leaves_of.get(&root).is_some_and(|l| l.iter().any(|name| name.starts_with(&inside)));
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
