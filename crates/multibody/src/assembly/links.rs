//! From frame nodes to links: rigid parts merge nodes into rigid groups, and
//! joints and orientation owners connect the groups into a tree rooted at
//! the ground.

use super::connections::Connectors;
use super::mechanism::{CompiledComponent, FrameNode};
use crate::components::{ConstraintKind, Part, RotationLock, StateNames};
use crate::math::union_find::UnionFind;
use crate::math::Transform;
use crate::math::Vec3;
use crate::system::joint::JointModel;
use crate::system::{Anchor, Link, MasslessGroup, GROUND};
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
    /// Where the planar components' plane sits (world to plane).
    pub plane: Transform,
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

/// The rigid groups of the frames; a planar frame fixed to the ground is
/// fixed in the plane at `plane`.
pub fn rigid_groups(
    components: &[CompiledComponent],
    conn: &Connectors,
    plane: Transform,
) -> Result<RigidGroups, Error> {
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
                    let pose = if c.spec.is_planar() { plane.then(pose) } else { *pose };
                    edges.push(RigidEdge { from: ground_vertex, to: node(*frame), pose, component: ci })
                }
                Part::Unused { frame, use_it } => {
                    if conn.frame_nodes[node(*frame)].len() > 1 {
                        return Err(Error::UnusedConnected {
                            connector: format!("{}.{}", c.name, c.spec.connectors[*frame].name),
                            why: (*use_it).into(),
                        });
                    }
                    let pose = if c.spec.is_planar() { plane } else { Transform::IDENTITY };
                    edges.push(RigidEdge { from: ground_vertex, to: node(*frame), pose, component: ci })
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
        plane,
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
    /// 1-D elements act on its axis: it cannot be cut.
    elements: bool,
    /// The model gave it start values: better kept in the tree.
    fixed: bool,
    /// The model asks for it to be cut.
    iscut: bool,
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
    /// Used only where nothing else places the group (see `Part::Owner`).
    fallback: bool,
}

/// A relation kept by constraint forces: a joint left out of the tree (it
/// closes a loop), or a constraint component.
#[derive(Clone, Copy, Debug)]
pub struct Cut {
    pub component: usize,
    pub part: usize,
    pub a: usize,
    pub b: usize,
    pub kind: ConstraintKind,
    /// The joint, when a joint was cut (its coordinates become outputs).
    pub joint: Option<JointModel>,
}

/// The tree: links in topological order, and each frame node's place.
pub struct Tree {
    pub links: Vec<Link>,
    pub nodes: Vec<FrameNode>,
    /// State names of each link's joint (parallel to `links`, empty for ground).
    pub state_names: Vec<StateNames>,
    pub massless: Vec<MasslessGroup>,
    pub cuts: Vec<Cut>,
    /// The loop each cut joint closes, for messages.
    pub cut_loops: Vec<CutLoop>,
}

/// A joint cut to close a kinematic loop, and the tree joints of that loop.
#[derive(Clone, Debug)]
pub struct CutLoop {
    pub component: usize,
    /// The other joints of the loop (none when the cut joint's two frames
    /// are joined rigidly).
    pub others: Vec<LoopJoint>,
}

/// A joint of a kinematic loop, and what keeps it from being cut.
#[derive(Clone, Copy, Debug)]
pub struct LoopJoint {
    pub component: usize,
    /// 1-D elements act on its axis.
    pub elements: bool,
    /// The model gives it start values.
    pub fixed: bool,
}

const TRANSLATION_STATES: StateNames = StateNames { q: &[("r_0", 3)], u: &[("v_0", 3)] };

/// The tree of `groups`; `fixed[c]` says whether component `c` has start
/// values that hold (its joints are better kept in the tree).
pub fn spanning_tree(
    components: &[CompiledComponent],
    conn: &Connectors,
    groups: &RigidGroups,
    fixed: &[bool],
) -> Result<Tree, Error> {
    let node = |ci: usize, local: usize| conn.node(Connectors::id(components, ci, local));
    let mut joints = Vec::new();
    let mut owners = Vec::new();
    let mut cuts = Vec::new();
    // Mass and inertia of each rigid group, and its first massive component.
    let mut group_inertia = vec![0.0f64; groups.count];
    let mut group_first_mass: Vec<Option<usize>> = vec![None; groups.count];
    for (ci, c) in components.iter().enumerate() {
        for (pi, part) in c.parts.iter().enumerate() {
            match *part {
                Part::Joint { a, b, model, flanges, iscut, .. } => {
                    let elements =
                        flanges.is_some_and(|f| conn.infos[Connectors::id(components, ci, f.axis)].connected);
                    let (a, b, fixed) = (node(ci, a), node(ci, b), fixed[ci]);
                    joints.push(JointEdge { component: ci, part: pi, a, b, model, elements, fixed, iscut })
                }
                Part::Constraint { a, b, kind } => {
                    cuts.push(Cut { component: ci, part: pi, a: node(ci, a), b: node(ci, b), kind, joint: None })
                }
                Part::Owner { frame, model, fallback, .. } => owners.push(OwnerRef {
                    component: ci,
                    part: pi,
                    node: node(ci, frame),
                    model,
                    line_end: false,
                    fallback,
                }),
                Part::FixedRotationEnd { frame } => owners.push(OwnerRef {
                    component: ci,
                    part: pi,
                    node: node(ci, frame),
                    model: JointModel::Translation,
                    line_end: true,
                    fallback: false,
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

    // Groups joined by joints (whatever the tree): the ground's cluster,
    // and floating clusters that need one owner each.
    let mut joined = UnionFind::new(groups.count);
    for j in &joints {
        joined.union(group(j.a), group(j.b));
    }
    let ground_cluster = joined.find(groups.ground);
    for o in owners.iter().filter(|o| !o.fallback) {
        // A root PointMass has no orientation to share; a prescribed
        // position keeps its frame's orientation the world's.
        let prescribed = components[o.component].parts.iter().any(|p| matches!(p, Part::Drive { .. }));
        if let (JointModel::Translation, false, false) = (o.model, o.line_end, prescribed) {
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
        if joined.find(group(o.node)) == ground_cluster {
            let through = joint_path(&joints, &group, groups.ground, group(o.node))
                .into_iter()
                .map(|k| components[joints[k].component].name.clone())
                .collect::<Vec<_>>();
            let through =
                if through.is_empty() { components_at_group(components, conn, groups, group(o.node)) } else { through };
            return Err(Error::OwnerPositionedByJoints { component: components[o.component].name.clone(), through });
        }
    }

    // One owner per floating cluster; massless clusters held by force elements.
    let mut root_of_cluster: Vec<Option<(OwnerRef, usize)>> = vec![None; groups.count];
    let mut massless_of_group: Vec<Option<usize>> = vec![None; groups.count];
    let mut massless = Vec::new();
    let mut seen = vec![false; groups.count];
    for start in 0..groups.count {
        let cluster_id = joined.find(start);
        if cluster_id == ground_cluster || seen[cluster_id] {
            continue;
        }
        seen[cluster_id] = true;
        let cluster: Vec<usize> = (0..groups.count).filter(|&g| joined.find(g) == cluster_id).collect();
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
        let here: Vec<&OwnerRef> = owners.iter().filter(|o| joined.find(group(o.node)) == cluster_id).collect();
        let mut cluster_owners: Vec<&OwnerRef> = here.iter().copied().filter(|o| !o.fallback).collect();
        if cluster_owners.is_empty() {
            cluster_owners.extend(here.first());
        }
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
                root_of_cluster[cluster_id] = Some((**owner, states_of));
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

    // The tree keeps the joints with elements on their axis (they cannot be
    // cut), then those with start values, then the ones with the fewest
    // degrees of freedom: each loop is cut at the joint whose cut leaves the
    // fewest constraint equations, `iscut` joints first.
    let mut by_priority: Vec<usize> = (0..joints.len()).collect();
    by_priority.sort_by_key(|&k| {
        let j = &joints[k];
        (
            if j.elements {
                0
            } else if j.fixed && !j.iscut {
                1
            } else if j.iscut {
                3
            } else {
                2
            },
            j.model.nv(),
        )
    });
    let mut in_tree = vec![false; joints.len()];
    let mut cut_joints = Vec::new();
    let mut spanning = UnionFind::new(groups.count);
    for k in by_priority {
        let j = &joints[k];
        if spanning.find(group(j.a)) != spanning.find(group(j.b)) {
            spanning.union(group(j.a), group(j.b));
            in_tree[k] = true;
        } else {
            cut_joints.push(k);
            cuts.push(Cut {
                component: j.component,
                part: j.part,
                a: j.a,
                b: j.b,
                kind: if components[j.component].spec.is_planar() {
                    planar_constraint_of_joint(&j.model)
                } else {
                    constraint_of_joint(&j.model)
                },
                joint: Some(j.model),
            });
        }
    }
    let cut_loops = loops_of_cuts(&joints, &in_tree, &cut_joints, &group, groups.count);
    for (l, &k) in cut_loops.iter().zip(&cut_joints) {
        if joints[k].elements {
            return Err(cut_with_elements(components, l));
        }
    }
    for c in &cuts {
        for n in [c.a, c.b] {
            if massless_of_group[group(n)].is_some() {
                return Err(Error::Unsupported {
                    component: components[c.component].name.clone(),
                    what: "a constraint on frames without mass".into(),
                    fix: "give them mass".into(),
                });
            }
        }
    }

    // Topological order: from the ground, then from each floating cluster's owner.
    let mut incident: Vec<Vec<usize>> = vec![Vec::new(); groups.count];
    for (k, j) in joints.iter().enumerate().filter(|(k, _)| in_tree[*k]) {
        incident[group(j.a)].push(k);
        incident[group(j.b)].push(k);
    }
    let mut link_of = vec![usize::MAX; groups.count];
    let mut order: Vec<(usize, Parent)> = Vec::new();
    link_of[groups.ground] = GROUND;
    let grow = |start: usize, link_of: &mut Vec<usize>, order: &mut Vec<(usize, Parent)>| {
        let mut queue = VecDeque::from([start]);
        while let Some(g) = queue.pop_front() {
            for &k in &incident[g] {
                let j = joints[k];
                let reversed = group(j.b) == g;
                let other = if reversed { group(j.a) } else { group(j.b) };
                if link_of[other] == usize::MAX {
                    link_of[other] = order.len() + 1;
                    order.push((other, Parent::Joint { edge: k, reversed }));
                    queue.push_back(other);
                }
            }
        }
    };
    grow(groups.ground, &mut link_of, &mut order);
    for g in 0..groups.count {
        if let Some((owner, states_of)) = root_of_cluster[joined.find(g)] {
            let root = group(owner.node);
            if link_of[root] == usize::MAX {
                link_of[root] = order.len() + 1;
                order.push((root, Parent::Owner(owner, states_of)));
                grow(root, &mut link_of, &mut order);
            }
        }
    }

    let mut tree = build_links(components, groups, &joints, &order, &link_of, &massless_of_group, massless)?;
    tree.cuts = cuts;
    tree.cut_loops = cut_loops;
    Ok(tree)
}

/// The loop each cut joint closes: the tree joints between its two groups.
fn loops_of_cuts(
    joints: &[JointEdge],
    in_tree: &[bool],
    cut_joints: &[usize],
    group: &dyn Fn(usize) -> usize,
    group_count: usize,
) -> Vec<CutLoop> {
    if cut_joints.is_empty() {
        return Vec::new();
    }
    let mut incident: Vec<Vec<usize>> = vec![Vec::new(); group_count];
    for (k, j) in joints.iter().enumerate().filter(|(k, _)| in_tree[*k]) {
        incident[group(j.a)].push(k);
        incident[group(j.b)].push(k);
    }
    let mut came_by = vec![usize::MAX; group_count];
    let mut seen = vec![false; group_count];
    cut_joints
        .iter()
        .map(|&cut| {
            let (from, to) = (group(joints[cut].a), group(joints[cut].b));
            // Breadth-first through the tree from one end to the other.
            let mut visited = vec![from];
            seen[from] = true;
            let mut queue = VecDeque::from([from]);
            while let Some(g) = queue.pop_front() {
                if g == to {
                    break;
                }
                for &k in &incident[g] {
                    let other = if group(joints[k].a) == g { group(joints[k].b) } else { group(joints[k].a) };
                    if !seen[other] {
                        seen[other] = true;
                        came_by[other] = k;
                        visited.push(other);
                        queue.push_back(other);
                    }
                }
            }
            let mut others = Vec::new();
            let mut g = to;
            while g != from && seen[to] {
                let k = came_by[g];
                let j = &joints[k];
                others.push(LoopJoint { component: j.component, elements: j.elements, fixed: j.fixed });
                g = if group(j.a) == g { group(j.b) } else { group(j.a) };
            }
            others.reverse();
            for v in visited {
                seen[v] = false;
            }
            CutLoop { component: joints[cut].component, others }
        })
        .collect()
}

/// A joint with 1-D elements on its axis that must be cut: every other joint
/// of its loop has elements too, or its frames are joined rigidly.
fn cut_with_elements(components: &[CompiledComponent], l: &CutLoop) -> Error {
    let name = components[l.component].name.clone();
    if l.others.is_empty() {
        return Error::Unsupported {
            component: name.clone(),
            what: format!("a joint with 1-D elements on its axis whose two frames are already joined rigidly (`{name}` closes a kinematic loop by itself and cannot move)"),
            fix: format!("remove `{name}`, or the rigid connection between its frames"),
        };
    }
    let mut all: Vec<String> = l.others.iter().map(|j| components[j.component].name.clone()).collect();
    all.push(name.clone());
    Error::Unsupported {
        component: name.clone(),
        what: format!(
            "a kinematic loop in which every joint has 1-D elements on its axis ({})",
            crate::error::list(&all)
        ),
        fix: format!(
            "one joint of a loop is cut to close it (its coordinates follow from the others), and a cut joint cannot carry 1-D elements. Remove the 1-D elements from one joint of the loop (`{name}`, for example), so that it can be cut"
        ),
    }
}

/// The constraint that a joint's relation becomes when it is cut.
fn constraint_of_joint(model: &JointModel) -> ConstraintKind {
    let all = [true; 3];
    let perpendicular = |n: Vec3| {
        let e1 = crate::math::width_direction(&n);
        [e1, n.cross(&e1), Vec3::zeros()]
    };
    match *model {
        JointModel::Revolute { axis } => ConstraintKind::locking_axes(RotationLock::AllBut(axis), all),
        JointModel::Prismatic { axis } => {
            ConstraintKind::Locks { rotation: RotationLock::All, directions: perpendicular(axis), count: 2 }
        }
        JointModel::Spherical(_) => ConstraintKind::locking_axes(RotationLock::Free, all),
        JointModel::Universal { n_a, n_b } => ConstraintKind::locking_axes(RotationLock::Universal { n_a, n_b }, all),
        JointModel::Cylindrical { axis } => {
            ConstraintKind::Locks { rotation: RotationLock::AllBut(axis), directions: perpendicular(axis), count: 2 }
        }
        JointModel::Planar { n, .. } => ConstraintKind::Locks {
            rotation: RotationLock::AllBut(n),
            directions: [n, Vec3::zeros(), Vec3::zeros()],
            count: 1,
        },
        JointModel::Free(_) => ConstraintKind::locking_axes(RotationLock::Free, [false; 3]),
        JointModel::Translation => ConstraintKind::locking_axes(RotationLock::All, [false; 3]),
    }
}

/// Whether a component is planar in a plane other than the world's x-y
/// plane: its sensors and force laws then see its frames in the plane's
/// coordinates (in the x-y plane those are the world's already).
pub(crate) fn in_placed_plane(c: &CompiledComponent, plane: &Transform) -> bool {
    *plane != Transform::IDENTITY && c.spec.is_planar()
}

/// The constraint a cut planar joint leaves: only its rows in the plane,
/// since the rest of the planar mechanism keeps the others (a 3-D cut would
/// add three redundant rows).
fn planar_constraint_of_joint(model: &JointModel) -> ConstraintKind {
    match *model {
        // In-plane translations (frame_a's x and y).
        JointModel::Revolute { .. } => ConstraintKind::Locks {
            rotation: RotationLock::Free,
            directions: [Vec3::x(), Vec3::y(), Vec3::zeros()],
            count: 2,
        },
        // The in-plane translation across the axis, and the turn about z.
        JointModel::Prismatic { axis } => ConstraintKind::Locks {
            rotation: RotationLock::Axes([false, false, true]),
            directions: [Vec3::z().cross(&axis), Vec3::zeros(), Vec3::zeros()],
            count: 1,
        },
        _ => constraint_of_joint(model),
    }
}

/// The joints on a path between two groups (breadth-first over all joints).
fn joint_path(joints: &[JointEdge], group: &dyn Fn(usize) -> usize, from: usize, to: usize) -> Vec<usize> {
    let mut came_by: std::collections::HashMap<usize, usize> = std::collections::HashMap::new();
    let mut queue = VecDeque::from([from]);
    let mut visited = std::collections::HashSet::from([from]);
    while let Some(g) = queue.pop_front() {
        if g == to {
            break;
        }
        for (k, j) in joints.iter().enumerate() {
            let (ga, gb) = (group(j.a), group(j.b));
            let other = if ga == g {
                gb
            } else if gb == g {
                ga
            } else {
                continue;
            };
            if visited.insert(other) {
                came_by.insert(other, k);
                queue.push_back(other);
            }
        }
    }
    let mut path = Vec::new();
    let mut g = to;
    while let Some(&k) = came_by.get(&g) {
        path.push(k);
        g = if group(joints[k].a) == g { group(joints[k].b) } else { group(joints[k].a) };
    }
    path.reverse();
    path
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

    let ground =
        Link::new(GROUND, JointModel::Translation, Transform::IDENTITY, (0, 0), (usize::MAX, usize::MAX), usize::MAX);
    let mut links = vec![ground];
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
                // A planar body free in the plane moves from the plane's origin.
                let x_tree = if components[o.component].spec.is_planar() { groups.plane } else { Transform::IDENTITY };
                (GROUND, x_tree, o.model, (o.component, o.part), states_of, false)
            }
        };
        let names = match &components[source.0].parts[source.1] {
            Part::Joint { states, .. } | Part::Owner { states, .. } => *states,
            _ => TRANSLATION_STATES,
        };
        links.push(Link { inverted, ..Link::new(parent_link, joint, x_tree, (nq, nv), source, states_of) });
        state_names.push(names);
        nq += joint.nq();
        nv += joint.nv();
    }
    Ok(Tree { links, nodes, state_names, massless, cuts: Vec::new(), cut_loops: Vec::new() })
}
