//! From frame nodes to links: rigid parts merge nodes into rigid groups, and
//! joints and orientation owners connect the groups into a tree rooted at
//! the ground.

use super::connections::Connectors;
use super::union_find::UnionFind;
use crate::components::{Part, StateNames};
use crate::dynamics::joint::JointModel;
use crate::math::Vec3;
use crate::math::{RigidInertia, Transform};
use crate::mechanism::{Anchor, CompiledComponent, FrameNode, Link, MasslessGroup, GROUND};
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
    /// A line-force end with a fixed rotation, rather than a body's states.
    line_end: bool,
}

/// The tree: links in topological order, and each frame node's place.
pub struct Tree {
    pub links: Vec<Link>,
    pub nodes: Vec<FrameNode>,
    /// State names of each link's joint (parallel to `links`, empty for ground).
    pub state_names: Vec<StateNames>,
    pub massless: Vec<MasslessGroup>,
}

const TRANSLATION_STATES: StateNames = StateNames { q: &[("r_0", 3)], u: &[("v_0", 3)] };

pub fn spanning_tree(components: &[CompiledComponent], conn: &Connectors, groups: &RigidGroups) -> Result<Tree, Error> {
    let node = |ci: usize, local: usize| conn.node(Connectors::id(components, ci, local));
    let mut joints = Vec::new();
    let mut owners = Vec::new();
    // Mass and inertia of each rigid group, and its first massive component.
    let mut group_inertia = vec![0.0f64; groups.count];
    let mut group_first_mass: Vec<Option<usize>> = vec![None; groups.count];
    for (ci, c) in components.iter().enumerate() {
        for (pi, part) in c.parts.iter().enumerate() {
            match *part {
                Part::Joint { a, b, model, .. } => {
                    joints.push(JointEdge { component: ci, part: pi, a: node(ci, a), b: node(ci, b), model })
                }
                Part::Owner { frame, model, .. } => {
                    owners.push(OwnerRef { component: ci, part: pi, node: node(ci, frame), model, line_end: false })
                }
                Part::FixedRotationEnd { frame } => owners.push(OwnerRef {
                    component: ci,
                    part: pi,
                    node: node(ci, frame),
                    model: JointModel::Translation,
                    line_end: true,
                }),
                Part::Mass { frame, inertia, .. } => {
                    let g = groups.group_of[node(ci, frame)];
                    let amount = inertia.mass + inertia.rot.trace();
                    if amount > 0.0 {
                        group_inertia[g] += amount;
                        group_first_mass[g].get_or_insert(ci);
                    }
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

    // Each group becomes a link (or a massless group); `link_of[group]` once placed.
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
                through = components_at_group(components, conn, groups, group(o.node));
            }
            return Err(Error::OwnerPositionedByJoints { component: components[o.component].name.clone(), through });
        }
        if let (JointModel::Translation, false) = (o.model, o.line_end) {
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
    let mut massless_of_group: Vec<Option<usize>> = vec![None; groups.count];
    let mut massless = Vec::new();
    for start in 0..groups.count {
        if link_of[start] != usize::MAX || massless_of_group[start].is_some() {
            continue;
        }
        let cluster = cluster_of(start, &incident, &joints, &group);
        let names = || {
            let mut names: Vec<String> = Vec::new();
            for &g in &cluster {
                for n in components_at_group(components, conn, groups, g) {
                    if !names.contains(&n) {
                        names.push(n);
                    }
                }
            }
            names
        };
        let cluster_owners: Vec<&OwnerRef> = owners.iter().filter(|o| cluster.contains(&group(o.node))).collect();
        match cluster_owners.as_slice() {
            [] => return Err(Error::NoOrientationOwner { components: names() }),
            [owner] => {
                let g = group(owner.node);
                if owner.line_end && cluster.len() == 1 && group_inertia[g] == 0.0 {
                    // Frames without mass that only force elements hold: solved, not integrated.
                    massless_of_group[g] = Some(massless.len());
                    massless.push(MasslessGroup { elements: Vec::new(), guess: Vec3::zeros(), components: names() });
                    continue;
                }
                let states_of =
                    if owner.line_end { group_first_mass[g].unwrap_or(owner.component) } else { owner.component };
                link_of[g] = order.len() + 1;
                order.push((g, Parent::Owner(**owner, states_of)));
                grow(g, &mut link_of, &mut order, &mut used, &mut reached_by)?;
            }
            [first, second, ..] => {
                return Err(Error::TwoOwners {
                    first: components[first.component].name.clone(),
                    second: components[second.component].name.clone(),
                    group: names(),
                });
            }
        }
    }

    build_links(components, groups, &joints, &order, &link_of, &massless_of_group, massless)
}

#[derive(Clone, Copy)]
enum Parent {
    Joint {
        edge: usize,
        reversed: bool,
    },
    /// An owner, and the component whose name its states carry.
    Owner(OwnerRef, usize),
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
    massless_of_group: &[Option<usize>],
    massless: Vec<MasslessGroup>,
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
            Parent::Owner(o, _) => o.node,
        };
    }
    // A massless group's frame is its first node.
    let mut massless_reference = vec![usize::MAX; massless.len()];
    for (n, &g) in groups.group_of.iter().enumerate() {
        if let Some(m) = massless_of_group[g] {
            if massless_reference[m] == usize::MAX {
                massless_reference[m] = n;
            }
        }
    }
    // Each node's pose in its link (or massless group) frame.
    let nodes: Vec<FrameNode> = (0..groups.group_of.len())
        .map(|n| {
            let g = groups.group_of[n];
            let (anchor, reference) = match massless_of_group[g] {
                Some(m) => (Anchor::Massless(m), Some(massless_reference[m])),
                None if link_of[g] == GROUND => (Anchor::Link(GROUND), None),
                None => (Anchor::Link(link_of[g]), Some(frame_node[link_of[g]])),
            };
            let pose = match reference {
                None => groups.pose[n],
                Some(r) => groups.pose[r].inverse().then(&groups.pose[n]),
            };
            FrameNode { anchor, pose, connectors: Vec::new() }
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
        states_of: usize::MAX,
        inverted: false,
    }];
    let mut state_names = vec![StateNames { q: &[], u: &[] }];
    let (mut nq, mut nv) = (0, 0);
    for (_, parent) in order {
        let (parent_link, x_tree, joint, source, states_of, inverted) = match *parent {
            Parent::Joint { edge, reversed } => {
                let j = joints[edge];
                let parent_node = if reversed { j.b } else { j.a };
                // Backwards, a 1-DOF joint flips its axis; others invert their motion.
                let (model, inverted) = match (reversed, j.model.reversed()) {
                    (false, _) => (j.model, false),
                    (true, Some(flipped)) => (flipped, false),
                    (true, None) => (j.model, true),
                };
                (
                    nodes[parent_node].link(),
                    nodes[parent_node].pose,
                    model,
                    (j.component, j.part),
                    j.component,
                    inverted,
                )
            }
            Parent::Owner(o, states_of) => {
                (GROUND, Transform::IDENTITY, o.model, (o.component, o.part), states_of, false)
            }
        };
        let names = match &components[source.0].parts[source.1] {
            Part::Joint { states, .. } | Part::Owner { states, .. } => *states,
            _ => TRANSLATION_STATES,
        };
        links.push(Link {
            parent: parent_link,
            joint,
            x_tree,
            inertia: RigidInertia::ZERO,
            q_offset: nq,
            v_offset: nv,
            source,
            states_of,
            inverted,
        });
        state_names.push(names);
        nq += joint.nq();
        nv += joint.nv();
    }
    Ok(Tree { links, nodes, state_names, massless })
}
