//! From frame nodes to links: rigid parts merge nodes into rigid groups, and
//! joints and orientation owners connect the groups into a tree rooted at
//! the ground.

use super::connections::Connectors;
use super::union_find::UnionFind;
use crate::components::{Part, StateNames};
use crate::dynamics::joint::JointModel;
use crate::math::{RigidInertia, Transform};
use crate::mechanism::{CompiledComponent, FrameNode, Link, GROUND};
use crate::Error;
use std::collections::VecDeque;

/// Frame nodes merged by rigid parts, with each node's pose in its group.
pub struct RigidGroups {
    /// Group of each frame node.
    pub group_of: Vec<usize>,
    /// Group reference frame to node frame; the ground group's reference is the world.
    pub pose: Vec<Transform>,
    pub ground: usize,
    pub count: usize,
    pub warnings: Vec<String>,
}

/// Two frames related by a fixed transform: `to = pose(from)`.
struct RigidEdge {
    from: usize,
    to: usize,
    pose: Transform,
    component: usize,
}

/// Poses within a rigid group must agree to this tolerance when a rigid
/// loop reaches a node twice.
const RIGID_LOOP_TOLERANCE: f64 = 1e-9;

pub fn rigid_groups(components: &[CompiledComponent], conn: &Connectors) -> Result<RigidGroups, Error> {
    let n = conn.frame_nodes.len();
    let ground_vertex = n;
    let mut edges = Vec::new();
    for (ci, c) in components.iter().enumerate() {
        for part in &c.parts {
            let node = |local: usize| conn.node(Connectors::id(components, ci, local));
            match part {
                Part::Rigid { a, b, pose } => {
                    edges.push(RigidEdge { from: node(*a), to: node(*b), pose: *pose, component: ci })
                }
                Part::Ground { frame, pose } => {
                    edges.push(RigidEdge { from: ground_vertex, to: node(*frame), pose: *pose, component: ci })
                }
                _ => {}
            }
        }
    }
    let mut adjacency: Vec<Vec<(usize, Transform, usize)>> = vec![Vec::new(); n + 1];
    let mut sets = UnionFind::new(n + 1);
    for e in &edges {
        adjacency[e.from].push((e.to, e.pose, e.component));
        adjacency[e.to].push((e.from, e.pose.inverse(), e.component));
        sets.union(e.from, e.to);
    }
    let (class, count) = sets.classes();
    let mut pose: Vec<Option<Transform>> = vec![None; n + 1];
    let mut warnings = Vec::new();
    // Ground first so that its group's reference is the world frame.
    let roots = std::iter::once(ground_vertex).chain(0..n);
    for root in roots {
        if pose[root].is_some() {
            continue;
        }
        pose[root] = Some(Transform::IDENTITY);
        let mut queue = VecDeque::from([root]);
        while let Some(v) = queue.pop_front() {
            let pv = pose[v].expect("visited nodes have poses");
            for &(w, edge, component) in &adjacency[v] {
                let pw = pv.then(&edge);
                match pose[w] {
                    None => {
                        pose[w] = Some(pw);
                        queue.push_back(w);
                    }
                    Some(existing) => {
                        let gap = (existing.trans - pw.trans).norm() + (existing.rot - pw.rot).norm();
                        if gap > RIGID_LOOP_TOLERANCE {
                            let mut names: Vec<String> = conn
                                .frame_nodes
                                .get(w)
                                .into_iter()
                                .flatten()
                                .map(|&c| components[conn.infos[c].component].name.clone())
                                .collect();
                            names.insert(0, components[component].name.clone());
                            names.dedup();
                            return Err(Error::InconsistentRigidLoop { components: names });
                        }
                    }
                }
            }
        }
    }
    // Rigid cycles leave some cut forces undetermined; say so once.
    let cycles = edges.len() + count - (n + 1);
    if cycles > 0 {
        warnings.push(format!(
            "{cycles} closed chain(s) of fixed parts: the cut forces inside them are statically indeterminate and are reported through one path only"
        ));
    }
    let ground = class[ground_vertex];
    Ok(RigidGroups {
        group_of: class[..n].to_vec(),
        pose: pose[..n].iter().map(|p| p.expect("every node is posed")).collect(),
        ground,
        count,
        warnings,
    })
}

/// A joint between two frame nodes, as it appears in the model.
#[derive(Clone, Copy)]
struct JointEdge {
    component: usize,
    part: usize,
    a: usize,
    b: usize,
    model: JointModel,
}

/// An orientation owner, as it appears in the model.
#[derive(Clone, Copy)]
struct OwnerRef {
    component: usize,
    part: usize,
    node: usize,
    model: JointModel,
}

/// The tree: links in topological order, and each frame node's place.
pub struct Tree {
    pub links: Vec<Link>,
    pub nodes: Vec<FrameNode>,
    /// State names of each link's joint (parallel to `links`, empty for ground).
    pub state_names: Vec<StateNames>,
}

pub fn spanning_tree(components: &[CompiledComponent], conn: &Connectors, groups: &RigidGroups) -> Result<Tree, Error> {
    let node = |ci: usize, local: usize| conn.node(Connectors::id(components, ci, local));
    let mut joints = Vec::new();
    let mut owners = Vec::new();
    for (ci, c) in components.iter().enumerate() {
        for (pi, part) in c.parts.iter().enumerate() {
            match *part {
                Part::Joint { a, b, model, .. } => {
                    joints.push(JointEdge { component: ci, part: pi, a: node(ci, a), b: node(ci, b), model })
                }
                Part::Owner { frame, model, .. } => {
                    owners.push(OwnerRef { component: ci, part: pi, node: node(ci, frame), model })
                }
                _ => {}
            }
        }
    }
    let group = |node: usize| groups.group_of[node];
    let mut incident: Vec<Vec<usize>> = vec![Vec::new(); groups.count];
    for (k, j) in joints.iter().enumerate() {
        incident[group(j.a)].push(k);
        if group(j.b) != group(j.a) {
            incident[group(j.b)].push(k);
        }
    }

    // Each group becomes a link; `link_of[group]` once visited.
    let mut link_of = vec![usize::MAX; groups.count];
    let mut reached_by: Vec<Option<usize>> = vec![None; groups.count];
    let mut used = vec![false; joints.len()];
    let mut order: Vec<(usize, Parent)> = Vec::new();
    link_of[groups.ground] = GROUND;

    let grow = |start: usize,
                link_of: &mut Vec<usize>,
                order: &mut Vec<(usize, Parent)>,
                used: &mut Vec<bool>,
                reached_by: &mut Vec<Option<usize>>|
     -> Result<(), Error> {
        let mut queue = VecDeque::from([start]);
        while let Some(g) = queue.pop_front() {
            for &k in &incident[g] {
                if used[k] {
                    continue;
                }
                used[k] = true;
                let j = joints[k];
                let reversed = group(j.b) == g && group(j.a) != g;
                let other = if reversed { group(j.a) } else { group(j.b) };
                if link_of[other] != usize::MAX {
                    return Err(Error::Unsupported {
                        component: components[j.component].name.clone(),
                        what: "a kinematic loop (this joint closes a loop of joints)".into(),
                    });
                }
                link_of[other] = order.len() + 1;
                reached_by[other] = Some(k);
                order.push((other, Parent::Joint { edge: k, reversed }));
                queue.push_back(other);
            }
        }
        Ok(())
    };

    grow(groups.ground, &mut link_of, &mut order, &mut used, &mut reached_by)?;

    for o in &owners {
        if link_of[group(o.node)] != usize::MAX {
            // Walk back to the ground to name the joints that position it.
            let mut through = Vec::new();
            let mut g = group(o.node);
            while let Some(k) = reached_by[g] {
                through.push(components[joints[k].component].name.clone());
                let j = joints[k];
                g = if group(j.a) == g { group(j.b) } else { group(j.a) };
            }
            through.reverse();
            if through.is_empty() {
                through.push(components_at_group(components, conn, groups, group(o.node)).join(", "));
            }
            return Err(Error::OwnerPositionedByJoints { component: components[o.component].name.clone(), through });
        }
    }

    for o in &owners {
        if let JointModel::Translation = o.model {
            let others: Vec<String> = conn.frame_nodes[o.node]
                .iter()
                .filter(|&&c| conn.infos[c].component != o.component)
                .map(|&c| components[conn.infos[c].component].name.clone())
                .collect();
            if !others.is_empty() || groups_with_other_nodes(groups, o.node) {
                return Err(Error::ConnectedRootPointMass {
                    component: components[o.component].name.clone(),
                    connected_to: others,
                });
            }
        }
    }

    // Floating clusters: groups not reached from the ground, joined by joints.
    for start in 0..groups.count {
        if link_of[start] != usize::MAX {
            continue;
        }
        let cluster = cluster_of(start, &incident, &joints, &group);
        let cluster_owners: Vec<&OwnerRef> = owners.iter().filter(|o| cluster.contains(&group(o.node))).collect();
        match cluster_owners.as_slice() {
            [] => {
                let mut names = Vec::new();
                for &g in &cluster {
                    for n in components_at_group(components, conn, groups, g) {
                        if !names.contains(&n) {
                            names.push(n);
                        }
                    }
                }
                return Err(Error::NoOrientationOwner { components: names });
            }
            [owner] => {
                let g = group(owner.node);
                link_of[g] = order.len() + 1;
                order.push((g, Parent::Owner(**owner)));
                grow(g, &mut link_of, &mut order, &mut used, &mut reached_by)?;
            }
            [first, second, ..] => {
                let mut group_names = Vec::new();
                for &g in &cluster {
                    group_names.extend(components_at_group(components, conn, groups, g));
                }
                group_names.dedup();
                return Err(Error::TwoOwners {
                    first: components[first.component].name.clone(),
                    second: components[second.component].name.clone(),
                    group: group_names,
                });
            }
        }
    }

    build_links(components, groups, &joints, &order, &link_of)
}

#[derive(Clone, Copy)]
enum Parent {
    Joint { edge: usize, reversed: bool },
    Owner(OwnerRef),
}

/// Whether the node shares its rigid group with other nodes.
fn groups_with_other_nodes(groups: &RigidGroups, node: usize) -> bool {
    groups.group_of.iter().enumerate().any(|(n, &g)| n != node && g == groups.group_of[node])
}

/// Groups reachable from `start` through joints.
fn cluster_of(
    start: usize,
    incident: &[Vec<usize>],
    joints: &[JointEdge],
    group: &dyn Fn(usize) -> usize,
) -> Vec<usize> {
    let mut cluster = vec![start];
    let mut k = 0;
    while k < cluster.len() {
        for &e in &incident[cluster[k]] {
            for g in [group(joints[e].a), group(joints[e].b)] {
                if !cluster.contains(&g) {
                    cluster.push(g);
                }
            }
        }
        k += 1;
    }
    cluster
}

/// The names of the components with a frame in group `g`.
fn components_at_group(
    components: &[CompiledComponent],
    conn: &Connectors,
    groups: &RigidGroups,
    g: usize,
) -> Vec<String> {
    let mut names: Vec<String> = Vec::new();
    for (n, &gn) in groups.group_of.iter().enumerate() {
        if gn == g {
            for &c in &conn.frame_nodes[n] {
                let name = &components[conn.infos[c].component].name;
                if !names.contains(name) {
                    names.push(name.clone());
                }
            }
        }
    }
    names
}

fn build_links(
    components: &[CompiledComponent],
    groups: &RigidGroups,
    joints: &[JointEdge],
    order: &[(usize, Parent)],
    link_of: &[usize],
) -> Result<Tree, Error> {
    // The frame node that each link's frame sits at.
    let mut frame_node = vec![usize::MAX; order.len() + 1];
    for (k, (_, parent)) in order.iter().enumerate() {
        frame_node[k + 1] = match *parent {
            Parent::Joint { edge, reversed } => {
                if reversed {
                    joints[edge].a
                } else {
                    joints[edge].b
                }
            }
            Parent::Owner(o) => o.node,
        };
    }
    // Each node's pose in its link frame.
    let nodes: Vec<FrameNode> = (0..groups.group_of.len())
        .map(|n| {
            let link = link_of[groups.group_of[n]];
            let pose = if link == GROUND {
                groups.pose[n]
            } else {
                groups.pose[frame_node[link]].inverse().then(&groups.pose[n])
            };
            FrameNode { link, pose, connectors: Vec::new() }
        })
        .collect();

    let mut links = vec![Link {
        parent: GROUND,
        joint: JointModel::Translation,
        x_tree: Transform::IDENTITY,
        inertia: RigidInertia::ZERO,
        q_offset: 0,
        v_offset: 0,
        source: (usize::MAX, usize::MAX),
        reversed: false,
    }];
    let mut state_names = vec![StateNames { q: &[], u: &[] }];
    let (mut nq, mut nv) = (0, 0);
    for (_, parent) in order {
        let (parent_link, x_tree, joint, source, reversed) = match *parent {
            Parent::Joint { edge, reversed } => {
                let j = joints[edge];
                let parent_node = if reversed { j.b } else { j.a };
                let model = if reversed {
                    j.model.reversed().ok_or_else(|| Error::Unsupported {
                        component: components[j.component].name.clone(),
                        what: "this joint placed with its frame_b towards the World (connect its frame_a towards the World instead)".into(),
                    })?
                } else {
                    j.model
                };
                (nodes[parent_node].link, nodes[parent_node].pose, model, (j.component, j.part), reversed)
            }
            Parent::Owner(o) => (GROUND, Transform::IDENTITY, o.model, (o.component, o.part), false),
        };
        let names = match &components[source.0].parts[source.1] {
            Part::Joint { states, .. } | Part::Owner { states, .. } => *states,
            _ => unreachable!("links are moved by joints or owners"),
        };
        links.push(Link {
            parent: parent_link,
            joint,
            x_tree,
            inertia: RigidInertia::ZERO,
            q_offset: nq,
            v_offset: nv,
            source,
            reversed,
        });
        state_names.push(names);
        nq += joint.nq();
        nv += joint.nv();
    }
    Ok(Tree { links, nodes, state_names })
}
