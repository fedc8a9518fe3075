//! 1-D drive trains: where every 1-D node (a set of connected splines or
//! flanges) sits. A node is fixed (a joint's support, a `Fixed`, a housing),
//! or an affine function `offset + scale * q` of one 1-DOF coordinate: a
//! joint's axis, or the own coordinate of a free 1-D inertia. Rigid parts
//! (inertias) and gears carry a place from node to node, so a motor behind
//! a gear adds `ratio^2 J` to its joint instead of a state and a constraint;
//! compliant elements (springs, dampers) do not, and what they separate gets
//! coordinates of its own. A gear whose sides are already placed otherwise
//! (between two joints, or closing a loop of gears) stays a constraint.

use super::connections::Connectors;
use super::links::Tree;
use super::mechanism::{CompiledComponent, JointRef};
use crate::components::{Law1D, Part, StateNames};
use crate::math::union_find::UnionFind;
use crate::math::{RigidInertia, Transform, Vec3};
use crate::system::{Anchor, AxisElement, Coupling, FlangeRef, JointModel, Link, GROUND};
use crate::Error;

/// The states of a coordinate without inertia on a measured coupling's
/// side, by the coupling's local connector (splines, then flanges).
const SIDE_STATES: [StateNames; 8] = [
    StateNames { q: &[("spline_1.phi", 1)], u: &[("spline_1.w", 1)] },
    StateNames { q: &[("spline_2.phi", 1)], u: &[("spline_2.w", 1)] },
    StateNames { q: &[("spline_3.phi", 1)], u: &[("spline_3.w", 1)] },
    StateNames { q: &[("spline_4.phi", 1)], u: &[("spline_4.w", 1)] },
    StateNames { q: &[("flange_1.s", 1)], u: &[("flange_1.v", 1)] },
    StateNames { q: &[("flange_2.s", 1)], u: &[("flange_2.v", 1)] },
    StateNames { q: &[("flange_3.s", 1)], u: &[("flange_3.v", 1)] },
    StateNames { q: &[("flange_4.s", 1)], u: &[("flange_4.v", 1)] },
];

/// For every 1-D node, where it sits and the connector that placed it
/// (`None`: nothing places it).
pub type Places = Vec<Option<(FlangeRef, usize)>>;

/// A gear's terms: `(node, coefficient, connector)`.
type GearTerms = Vec<(usize, f64, usize)>;

/// The placed drive train: the places, the gears left as constraints, and
/// the constant forces on coordinates.
pub struct DriveTrain {
    pub places: Places,
    /// `(component, terms (node, coefficient, connector), constant,
    /// measured)` of each gear that could not be made rigid or is measured.
    pending: Vec<(usize, GearTerms, f64, bool)>,
    pub axis_forces: Vec<(usize, f64)>,
    /// `(component, centre, state names)` of each 1-D body that turns with
    /// another coordinate than its own.
    pub geared: Vec<(usize, FlangeRef, StateNames)>,
    /// The links of the nodes without mass that the forces on them hold.
    pub balance_links: Vec<usize>,
}

/// Places every 1-D node; free inertias become links of `tree` (with their
/// states), and reflected inertias the armature of the links they turn with.
pub fn place(components: &mut [CompiledComponent], conn: &Connectors, tree: &mut Tree) -> Result<DriveTrain, Error> {
    let mut place: Places = vec![None; conn.flange_nodes.len()];
    let node_of = |components: &[CompiledComponent], ci: usize, local: usize| {
        conn.flange_node_of[Connectors::id(components, ci, local)]
    };

    mount_rotors(components, conn, tree, &mut place)?;

    // Fixed places: joint axes and supports, Fixed parts, lone housings.
    let mut housings = vec![false; conn.infos.len()];
    let mut lines = 0;
    for (ci, c) in components.iter().enumerate() {
        let mut joint_index = 0;
        for part in &c.parts {
            let fixed = match *part {
                Part::Joint { flanges, .. } => {
                    joint_index += 1;
                    let (Some(f), JointRef::Link(k)) = (flanges, c.joints[joint_index - 1]) else { continue };
                    let link = &tree.links[k];
                    vec![(f.axis, FlangeRef::on(link.q_offset, link.v_offset)), (f.support, FlangeRef::FIXED)]
                }
                Part::Owner { .. } => {
                    joint_index += 1;
                    continue;
                }
                Part::Fixed1D { flange, at } => vec![(flange, FlangeRef::fixed(at))],
                Part::LineFlanges { flange_a, flange_b, .. } => {
                    lines += 1;
                    vec![(flange_a, FlangeRef::FIXED), (flange_b, FlangeRef::line(lines - 1))]
                }
                Part::Housing { flange } => {
                    housings[Connectors::id(components, ci, flange)] = true;
                    continue;
                }
                _ => continue,
            };
            for (local, r) in fixed {
                set(&mut place, components, conn, Connectors::id(components, ci, local), r)?;
            }
        }
    }
    for (node, members) in conn.flange_nodes.iter().enumerate() {
        if place[node].is_none() && members.iter().all(|&c| housings[c]) && !members.is_empty() {
            if conn.types[members[0]].is_signal() {
                continue;
            }
            place[node] = Some((FlangeRef::FIXED, members[0]));
        }
    }

    // Rigid bodies and gears carry places; what is left gets coordinates.
    let mut rigid = Vec::new();
    let mut gears = Vec::new();
    for (ci, c) in components.iter().enumerate() {
        for (pi, part) in c.parts.iter().enumerate() {
            match part {
                Part::Inertia1D { a, b, length, .. } => {
                    rigid.push((ci, pi, node_of(components, ci, *a), node_of(components, ci, *b), *length))
                }
                Part::Coupling { terms, constant, measured } => {
                    let terms = terms
                        .iter()
                        .map(|&(local, k)| {
                            let id = Connectors::id(components, ci, local);
                            (conn.flange_node_of[id], k, id)
                        })
                        .collect::<Vec<_>>();
                    gears.push((ci, pi, terms, *constant, *measured));
                }
                _ => {}
            }
        }
    }
    // A measured coupling's reaction is its multiplier: it stays a constraint.
    let mut gear_done: Vec<bool> = gears.iter().map(|g| g.4).collect();
    let mut balance_links = Vec::new();
    loop {
        let mut progress = false;
        for &(ci, _, a, b, length) in &rigid {
            if [place[a], place[b]].iter().flatten().any(|(r, _)| r.on_line()) {
                return Err(on_a_line(components, ci, "a 1-D mass or inertia"));
            }
            match (place[a], place[b]) {
                (Some((pa, id)), None) => place[b] = Some((pa.affine(1.0, length), id)),
                (None, Some((pb, id))) => place[a] = Some((pb.affine(1.0, -length), id)),
                (Some((pa, _)), Some((pb, _))) if !same_place(pa.affine(1.0, length), pb) => {
                    return Err(Error::Unsupported {
                        component: components[ci].name.clone(),
                        what: "a rigid 1-D part between two places that move independently (two joint axes, or a loop)"
                            .into(),
                        fix: String::new(),
                    })
                }
                _ => continue,
            }
            progress = true;
        }
        // Gears carry places from one coordinate; where no inertia is left
        // to place, a gear's side with no inertia behind it may follow two
        // (its output, on a housing that turns), with no coordinate or
        // constraint of its own (an inertia there would couple the two).
        let no_inertia_left = rigid.iter().all(|r| place[r.2].is_some() || place[r.3].is_some());
        for most in if no_inertia_left { [1, 2].as_slice() } else { &[1] } {
            for (g, (_, _, terms, constant, _)) in gears.iter().enumerate() {
                if gear_done[g] {
                    continue;
                }
                if let Some((node, r, id)) = solve_for_the_unplaced(terms, *constant, &place, *most) {
                    place[node] = Some((r, id));
                    gear_done[g] = true;
                    progress = true;
                }
            }
            if progress {
                break;
            }
        }
        if progress {
            continue;
        }
        // A free inertia: its centre becomes a coordinate of its own.
        let unplaced = |r: &Rigid, place: &Places| place[r.2].is_none() && place[r.3].is_none();
        if let Some(&r) = rigid.iter().find(|r| unplaced(r, &place) && massive(components, r)) {
            own_centre(tree, components, &mut place, r);
            continue;
        }
        // A side of a measured coupling that nothing else places: a
        // coordinate without inertia, which the constraint determines.
        let side = gears.iter().filter(|g| g.4).find_map(|(ci, pi, terms, _, _)| {
            let Part::Coupling { terms: locals, .. } = &components[*ci].parts[*pi] else { return None };
            terms.iter().zip(locals).find(|(t, _)| place[t.0].is_none()).map(|(t, l)| (*ci, *pi, t.0, t.2, l.0))
        });
        if let Some((ci, pi, node, id, local)) = side {
            let joint = JointModel::Prismatic { axis: Vec3::x() };
            let k = push_link(tree, components, (ci, pi), GROUND, Transform::IDENTITY, joint, SIDE_STATES[local]);
            place[node] = Some((FlangeRef::on(tree.links[k].q_offset, tree.links[k].v_offset), id));
            continue;
        }
        // A node without mass that the forces on it hold: the centre of a
        // massless part (`Mass(m = 0)`), or where elements alone meet.
        if let Some(&r) = rigid.iter().find(|r| unplaced(r, &place)) {
            balance_links.push(own_centre(tree, components, &mut place, r));
            continue;
        }
        let Some((ci, pi, node, id, states)) = element_end(components, conn, &place) else { break };
        let joint = JointModel::Prismatic { axis: Vec3::x() };
        let k = push_link(tree, components, (ci, pi), GROUND, Transform::IDENTITY, joint, states);
        place[node] = Some((FlangeRef::on(tree.links[k].q_offset, tree.links[k].v_offset), id));
        balance_links.push(k);
    }

    // Inertias turn with the coordinate of their place.
    let mut axis_forces = Vec::new();
    let mut geared = Vec::new();
    for &(ci, pi, a, _, length) in &rigid {
        let Part::Inertia1D { inertia, weight, states, .. } = components[ci].parts[pi] else { continue };
        let Some((r, _)) = place[a] else { continue };
        if !tree.links.iter().any(|l| l.source == (ci, pi)) {
            geared.push((ci, r.affine(1.0, length / 2.0), states));
        }
        debug_assert!(r.second.is_none(), "inertias are placed before places that follow two coordinates");
        let Some((_, v)) = r.coordinate() else { continue };
        let link = tree.links.iter_mut().find(|l| l.v_offset == v && l.joint.nv() == 1);
        let link = link.expect("1-D coordinates are those of 1-DOF links");
        link.armature += inertia * r.scale * r.scale;
        if weight != 0.0 {
            axis_forces.push((v, weight * r.scale));
        }
    }
    let pending = gears
        .into_iter()
        .zip(gear_done)
        .filter(|(g, done)| g.4 || !done)
        .map(|((ci, _, terms, constant, measured), _)| (ci, terms, constant, measured))
        .collect();
    check_moving_mounts(components, conn, tree, &housings)?;
    Ok(DriveTrain { places: place, pending, axis_forces, geared, balance_links })
}

/// A rigid 1-D part: `(component, part, node a, node b, length)`.
type Rigid = (usize, usize, usize, usize, f64);

/// Whether a rigid 1-D part has inertia.
fn massive(components: &[CompiledComponent], r: &Rigid) -> bool {
    matches!(components[r.0].parts[r.1], Part::Inertia1D { inertia, .. } if inertia > 0.0)
}

/// Gives the rigid part `r`, which nothing places, a coordinate of its own
/// at its centre, and places its ends; returns the new link.
fn own_centre(tree: &mut Tree, components: &mut [CompiledComponent], place: &mut Places, r: Rigid) -> usize {
    let (ci, pi, a, b, length) = r;
    let Part::Inertia1D { states, .. } = components[ci].parts[pi] else { unreachable!("rigid parts are inertias") };
    let joint = JointModel::Prismatic { axis: Vec3::x() };
    let k = push_link(tree, components, (ci, pi), GROUND, Transform::IDENTITY, joint, states);
    let centre = FlangeRef::on(tree.links[k].q_offset, tree.links[k].v_offset);
    let id = Connectors::id(components, ci, 0);
    place[a] = Some((centre.affine(1.0, -length / 2.0), id));
    place[b] = Some((centre.affine(1.0, length / 2.0), id));
    k
}

/// The states of a node where elements alone meet, by the connector of the
/// element that names it.
fn node_states(name: &str) -> StateNames {
    const NAMES: [(&str, StateNames); 4] = [
        ("flange_a", StateNames { q: &[("flange_a.s", 1)], u: &[("flange_a.v", 1)] }),
        ("flange_b", StateNames { q: &[("flange_b.s", 1)], u: &[("flange_b.v", 1)] }),
        ("spline_a", StateNames { q: &[("spline_a.phi", 1)], u: &[("spline_a.w", 1)] }),
        ("spline_b", StateNames { q: &[("spline_b.phi", 1)], u: &[("spline_b.w", 1)] }),
    ];
    NAMES.iter().find(|n| n.0 == name).map_or(StateNames { q: &[("node.s", 1)], u: &[("node.v", 1)] }, |n| n.1)
}

/// An end of a 1-D element at a node nothing places: `(component, part,
/// node, connector, state names)`.
fn element_end(
    components: &[CompiledComponent],
    conn: &Connectors,
    place: &Places,
) -> Option<(usize, usize, usize, usize, StateNames)> {
    for (ci, c) in components.iter().enumerate() {
        for (pi, part) in c.parts.iter().enumerate() {
            let Part::Element1D { a, b, .. } = *part else { continue };
            for local in [a, b] {
                let id = Connectors::id(components, ci, local);
                let node = conn.flange_node_of[id];
                if place[node].is_none() {
                    return Some((ci, pi, node, id, node_states(c.spec.connectors[local].name)));
                }
            }
        }
    }
    None
}

/// Each rotor becomes a revolute link of its own on the body that carries
/// it, with the spin inertia `J e e'`; the carrier, which holds the rotor's
/// full inertia already, loses `J e e'`, so that the rotor adds only the
/// energy of its spin relative to the carrier. Both its flanges sit on the
/// new coordinate.
fn mount_rotors(
    components: &mut [CompiledComponent],
    conn: &Connectors,
    tree: &mut Tree,
    place: &mut Places,
) -> Result<(), Error> {
    for ci in 0..components.len() {
        for pi in 0..components[ci].parts.len() {
            let Part::Rotor1D { frame, axis, inertia, a, b, states } = components[ci].parts[pi] else { continue };
            let node = &tree.nodes[conn.node(Connectors::id(components, ci, frame))];
            let Anchor::Link(carrier) = node.anchor else {
                return Err(Error::Unsupported {
                    component: components[ci].name.clone(),
                    what: "a Rotor1D on a frame without mass of its own".into(),
                    fix: "mount it on a body".into(),
                });
            };
            let spin = RigidInertia { mass: 0.0, h: Vec3::zeros(), rot: inertia * axis * axis.transpose() };
            let pose = node.pose;
            let shaft = push_link(tree, components, (ci, pi), carrier, pose, JointModel::Revolute { axis }, states);
            tree.links[shaft].inertia = spin;
            if carrier != GROUND {
                let locked = RigidInertia { rot: -spin.rot, ..spin };
                tree.links[carrier].inertia += locked.expressed_in_parent(&pose);
            }
            let on_shaft = FlangeRef::on(tree.links[shaft].q_offset, tree.links[shaft].v_offset);
            for local in [a, b] {
                set(place, components, conn, Connectors::id(components, ci, local), on_shaft)?;
            }
        }
    }
    Ok(())
}

/// A link at the end of the tree, moved by part `source` of its component,
/// on `parent` at `x_tree`: a free 1-D body or a rotor.
fn push_link(
    tree: &mut Tree,
    components: &mut [CompiledComponent],
    source: (usize, usize),
    parent: usize,
    x_tree: Transform,
    joint: JointModel,
    states: StateNames,
) -> usize {
    let (nq, nv) = tree.links.iter().skip(1).fold((0, 0), |(q, v), l| (q + l.joint.nq(), v + l.joint.nv()));
    let k = tree.links.len();
    tree.links.push(Link::new(parent, joint, x_tree, (nq, nv), source, source.0));
    tree.state_names.push(states);
    components[source.0].joints.push(JointRef::Link(k));
    k
}

/// A drive train mounted on a moving body (by a Rotor1D, Mounting1D or
/// BevelGear1D on a frame that moves) works in angles relative to that
/// body, and the torques on its shafts react on it through the rotors'
/// joints. That is exact when every shaft in it is a rotor on that body and
/// every support is mounted there; an Inertia, a Fixed, a joint's axis or a
/// support left to the world would send its reaction to the wrong body, so
/// they are refused.
fn check_moving_mounts(
    components: &[CompiledComponent],
    conn: &Connectors,
    tree: &Tree,
    housings: &[bool],
) -> Result<(), Error> {
    let n = conn.flange_nodes.len();
    let node_of = |ci: usize, local: usize| conn.flange_node_of[Connectors::id(components, ci, local)];
    let mut trains = UnionFind::new(n);
    // (node, component, what) that turn with or are fixed in the world.
    let mut worldly: Vec<(usize, usize, &str)> = Vec::new();
    // (node, component, carrier link) of the mounted parts.
    let mut mounted: Vec<(usize, usize, usize)> = Vec::new();
    let carrier = |ci: usize, frame: usize| tree.nodes[conn.node(Connectors::id(components, ci, frame))].link();
    for (ci, c) in components.iter().enumerate() {
        let mounted_here: Vec<usize> = c
            .parts
            .iter()
            .flat_map(|p| match p {
                Part::Mount1D { flanges, .. } => flanges.clone(),
                _ => Vec::new(),
            })
            .collect();
        for part in &c.parts {
            let joined: Vec<usize> = match part {
                Part::Element1D { a, b, .. } => vec![*a, *b],
                Part::Coupling { terms, .. } => terms.iter().map(|t| t.0).collect(),
                Part::Inertia1D { a, b, .. } => {
                    worldly.push((node_of(ci, *a), ci, "an Inertia (or Mass), which turns in the world,"));
                    vec![*a, *b]
                }
                Part::Rotor1D { frame, a, b, .. } => {
                    mounted.push((node_of(ci, *a), ci, carrier(ci, *frame)));
                    vec![*a, *b]
                }
                Part::Mount1D { frame, flanges } => {
                    mounted.extend(flanges.iter().map(|&f| (node_of(ci, f), ci, carrier(ci, *frame))));
                    flanges.clone()
                }
                Part::Fixed1D { flange, .. } if !mounted_here.contains(flange) => {
                    worldly.push((node_of(ci, *flange), ci, "a Fixed, which is fixed in the world,"));
                    Vec::new()
                }
                Part::Joint { flanges: Some(f), .. } => {
                    worldly.push((node_of(ci, f.axis), ci, "a joint's axis"));
                    Vec::new()
                }
                _ => Vec::new(),
            };
            for pair in joined.windows(2) {
                trains.union(node_of(ci, pair[0]), node_of(ci, pair[1]));
            }
        }
    }
    for (node, members) in conn.flange_nodes.iter().enumerate() {
        if !members.is_empty() && members.iter().all(|&c| housings[c]) {
            let ci = conn.infos[members[0]].component;
            worldly.push((node, ci, "a support left unconnected (so fixed in the world)"));
        }
    }
    let mut carrier_of_train: Vec<Option<(usize, usize)>> = vec![None; n];
    for &(node, ci, link) in &mounted {
        let t = trains.find(node);
        match carrier_of_train[t] {
            Some((other, oc)) if other != link => {
                return Err(Error::Unsupported {
                    component: components[ci].name.clone(),
                    what: format!(
                        "one drive train mounted on two bodies that move apart (here and at `{}`)",
                        components[oc].name
                    ),
                    fix: String::new(),
                })
            }
            _ => carrier_of_train[t] = Some((link, ci)),
        }
    }
    for (node, ci, what) in worldly {
        if let Some((link, mount)) = carrier_of_train[trains.find(node)] {
            if link != GROUND {
                return Err(Error::Unsupported {
                    component: components[ci].name.clone(),
                    what: format!(
                        "{what} in a drive train mounted on the moving frame of `{}`",
                        components[mount].name
                    ),
                    fix: "use Rotor1D shafts and connect every support to a Mounting1D on that frame".into(),
                });
            }
        }
    }
    Ok(())
}

/// Places `id`'s node at `r`, or says why it cannot be (two joint axes or
/// fixed points joined directly).
fn set(
    place: &mut Places,
    components: &[CompiledComponent],
    conn: &Connectors,
    id: usize,
    r: FlangeRef,
) -> Result<(), Error> {
    let node = conn.flange_node_of[id];
    match place[node] {
        Some((existing, other)) if !same_place(existing, r) => Err(Error::Unsupported {
            component: components[conn.infos[id].component].name.clone(),
            what: format!(
                "a 1-D connection between `{}` and `{}`, which cannot move together (two joint axes or fixed points joined directly)",
                conn.name(components, id),
                conn.name(components, other)
            ),
            fix: "put a gear or a spring between them".into(),
        }),
        _ => {
            place[node] = Some((r, id));
            Ok(())
        }
    }
}

fn same_place(a: FlangeRef, b: FlangeRef) -> bool {
    let close = |x: f64, y: f64| (x - y).abs() <= 1e-12 * (1.0 + x.abs().max(y.abs()));
    let second = match (a.second, b.second) {
        (None, None) => true,
        (Some(x), Some(y)) => x.0 == y.0 && close(x.2, y.2),
        _ => false,
    };
    a.mover == b.mover && close(a.offset, b.offset) && (a.mover.is_none() || close(a.scale, b.scale)) && second
}

/// For a gear `sum c_k x_k + constant = 0` with one node unplaced and the
/// others on at most `most` coordinates (or fixed): that node's place.
fn solve_for_the_unplaced(
    terms: &[(usize, f64, usize)],
    constant: f64,
    place: &Places,
    most: usize,
) -> Option<(usize, FlangeRef, usize)> {
    let mut unplaced = None;
    let (mut offset, mut c_unplaced) = (constant, 0.0);
    // `(q, v, coefficient)` of each coordinate the placed nodes follow.
    let mut coordinates: Vec<(usize, usize, f64)> = Vec::with_capacity(2);
    for &(node, c, id) in terms {
        match place[node] {
            None => match unplaced {
                Some((n, _)) if n != node => return None,
                _ => {
                    unplaced = Some((node, id));
                    c_unplaced += c;
                }
            },
            // A line's length is no coordinate a gear could follow rigidly.
            Some((r, _)) if r.on_line() => return None,
            Some((r, _)) => {
                for (q, v, k) in r.coordinates() {
                    match coordinates.iter_mut().find(|x| x.0 == q) {
                        Some(x) => x.2 += c * k,
                        None => coordinates.push((q, v, c * k)),
                    }
                }
                offset += c * r.offset;
            }
        }
    }
    let (node, id) = unplaced?;
    coordinates.retain(|x| x.2 != 0.0);
    if c_unplaced == 0.0 || coordinates.len() > most {
        return None;
    }
    let mut r = FlangeRef::fixed(-offset / c_unplaced);
    if let Some(&(q, v, k)) = coordinates.first() {
        r = FlangeRef::on(q, v).affine(-k / c_unplaced, r.offset);
    }
    r.second = coordinates.get(1).map(|&(q, v, k)| (q as u32, v as u32, -k / c_unplaced));
    Some((node, r, id))
}

/// Where the 1-D connector `id` sits, or an error naming it.
pub fn flange(
    components: &[CompiledComponent],
    conn: &Connectors,
    places: &Places,
    id: usize,
) -> Result<FlangeRef, Error> {
    places[conn.flange_node_of[id]]
        .map(|(r, _)| r)
        .ok_or_else(|| Error::FloatingFlange { connector: conn.name(components, id) })
}

/// Where every connector sits, for outputs: 1-D connectors on a joint
/// axis follow its coordinate; every other connector reads as fixed.
pub fn of_connectors(conn: &Connectors, places: &Places) -> Vec<FlangeRef> {
    conn.flange_node_of
        .iter()
        .map(|&node| places.get(node).copied().flatten().map_or(FlangeRef::FIXED, |(r, _)| r))
        .collect()
}

/// The elements, and for each component the indices of its own; signal
/// inputs of driven sources become signal slots, and the indicators of
/// contact laws are added to `events`.
pub fn elements(
    components: &mut [CompiledComponent],
    conn: &Connectors,
    places: &Places,
    signal_of_connector: &[usize],
    events: &mut crate::system::EventLayout,
) -> Result<Vec<AxisElement>, Error> {
    let mut elements = Vec::new();
    for ci in 0..components.len() {
        let mut own = Vec::new();
        for part in &components[ci].parts {
            if let Part::Element1D { a, b, law } = *part {
                let id = |local: usize| Connectors::id(components, ci, local);
                let (a, b) = (flange(components, conn, places, id(a))?, flange(components, conn, places, id(b))?);
                let law = match law {
                    Law1D::Input { signal } => Law1D::Input { signal: signal_of_connector[id(signal)] },
                    Law1D::Flow { signal } => Law1D::Flow { signal: signal_of_connector[id(signal)] },
                    other => other,
                };
                let indicator = events.indicators.len();
                if law.indicator_count() > 0 {
                    let name = &components[ci].name;
                    events.indicators.extend([
                        format!("{name}: contact beyond the upper end of the gap"),
                        format!("{name}: contact beyond the lower end of the gap"),
                    ]);
                    debug_assert_eq!(events.indicators.len() - indicator, law.indicator_count());
                }
                own.push(elements.len());
                elements.push(AxisElement { a, b, law, indicator });
            }
        }
        components[ci].elements = own;
    }
    Ok(elements)
}

/// The gears that stay constraints, numbered from `first_row` on. Every
/// coordinate they reach is a 1-DOF one, whose rate is its velocity, as
/// the constraint rows assume.
pub fn couplings(
    components: &[CompiledComponent],
    conn: &Connectors,
    drive: &DriveTrain,
    first_row: usize,
) -> Result<Vec<Coupling>, Error> {
    let mut couplings = Vec::new();
    for (ci, terms, constant, measured) in &drive.pending {
        let mut coupling =
            Coupling { terms: Vec::new(), constant: *constant, row: first_row + couplings.len(), component: *ci };
        for &(_, c, id) in terms {
            let r = flange(components, conn, &drive.places, id)?;
            if r.on_line() {
                return Err(on_a_line(components, *ci, "a gear"));
            }
            coupling.constant += c * r.offset;
            for (q, v, k) in r.coordinates() {
                match coupling.terms.iter_mut().find(|t| t.1 == v) {
                    Some(t) => t.2 += c * k,
                    None => coupling.terms.push((q, v, c * k)),
                }
            }
        }
        let scale = terms.iter().map(|t| t.1.abs()).fold(0.0, f64::max);
        if *measured && coupling.terms.iter().all(|t| t.2.abs() <= 1e-12 * scale) {
            return Err(Error::Unsupported {
                component: components[*ci].name.clone(),
                what: "measuring the flow through a part whose two sides other rigid parts hold together too (how \
                       the flow splits between them is not determined)"
                    .into(),
                fix: "measure where the flow has one path, or put a compliant element in the loop".into(),
            });
        }
        couplings.push(coupling);
    }
    Ok(couplings)
}

/// The refusal of `what` on a LineForceWithMass's flange.
pub(crate) fn on_a_line(components: &[CompiledComponent], ci: usize, what: &str) -> Error {
    Error::Unsupported {
        component: components[ci].name.clone(),
        what: format!("{what} on the flange of a line force with mass (the line's length places that flange)"),
        fix: "connect springs, dampers, forces and sensors between its flanges; give the line its mass with `m`".into(),
    }
}
