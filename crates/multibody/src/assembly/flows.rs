//! The flow tree: how cut forces reach the ground. Its edges are the parts
//! that transmit force between frames (ground anchors, rigid parts, tree
//! joints); loads (masses, force elements) hang on its nodes.

use super::connections::Connectors;
use super::links::Tree;
use super::mechanism::{CompiledComponent, FlowEdge, FlowTree};
use crate::components::Part;
use std::collections::{HashSet, VecDeque};

/// An edge leaving a frame node: (the node it reaches, the connector at this end, the one at the other end).
type Edge = (usize, Option<usize>, Option<usize>);

pub fn flow_tree(components: &[CompiledComponent], conn: &Connectors, tree: &Tree) -> FlowTree {
    let n = conn.frame_nodes.len();
    let mut adjacency: Vec<Vec<Edge>> = vec![Vec::new(); n];
    let mut from_ground: Vec<(usize, Option<usize>)> = Vec::new();
    let tree_parts: HashSet<(usize, usize)> = tree.links.iter().skip(1).map(|l| l.source).collect();
    for (ci, c) in components.iter().enumerate() {
        let id = |local: usize| Connectors::id(components, ci, local);
        for (pi, part) in c.parts.iter().enumerate() {
            match *part {
                Part::Ground { frame, .. } | Part::Unused { frame, .. } => {
                    from_ground.push((conn.node(id(frame)), Some(id(frame))))
                }
                // A fallback owner that is not used does not hold its frame.
                Part::Owner { frame, fallback, .. } if !fallback || tree_parts.contains(&(ci, pi)) => {
                    from_ground.push((conn.node(id(frame)), None))
                }
                Part::Rigid { a, b, .. } => link(&mut adjacency, conn, id(a), id(b)),
                Part::Joint { a, b, .. } if tree_parts.contains(&(ci, pi)) => link(&mut adjacency, conn, id(a), id(b)),
                _ => {}
            }
        }
    }
    let mut parent: Vec<Option<FlowEdge>> = vec![None; n];
    let mut order = Vec::with_capacity(n);
    let mut queue = VecDeque::new();
    for (node, connector) in from_ground {
        if parent[node].is_none() {
            parent[node] = Some(FlowEdge { parent_node: None, parent_connector: None, child_connector: connector });
            order.push(node);
            queue.push_back(node);
        }
    }
    while let Some(v) = queue.pop_front() {
        for &(w, at_v, at_w) in &adjacency[v] {
            if parent[w].is_none() {
                parent[w] = Some(FlowEdge { parent_node: Some(v), parent_connector: at_v, child_connector: at_w });
                order.push(w);
                queue.push_back(w);
            }
        }
    }
    FlowTree { order, parent }
}

fn link(adjacency: &mut [Vec<Edge>], conn: &Connectors, a: usize, b: usize) {
    let (na, nb) = (conn.node(a), conn.node(b));
    adjacency[na].push((nb, Some(a), Some(b)));
    adjacency[nb].push((na, Some(b), Some(a)));
}
