//! Nodes without mass (see [`crate::system::balance`]): the elements on
//! each, checked to be ones whose balance has a closed form, and the drives
//! that impose what the balance gives.

use super::links::Tree;
use super::mechanism::CompiledComponent;
use super::signals::Signals;
use crate::system::balance::{Balance, BalanceTerm};
use crate::system::friction::Friction;
use crate::system::{AxisElement, Coupling, Drive, DriveLevel, DriveMap, Law1D};
use crate::Error;

/// The balance of each node on `links` (links without inertia made for
/// them), and a drive per node; marks the links driven.
pub fn nodes(
    components: &[CompiledComponent],
    tree: &mut Tree,
    links: &[usize],
    elements: &[AxisElement],
    couplings: &[Coupling],
    frictions: &[Friction],
    signals: &Signals,
) -> Result<(Vec<Balance>, Vec<Drive>), Error> {
    let node_coordinates: Vec<(usize, usize)> =
        links.iter().map(|&k| (tree.links[k].q_offset, tree.links[k].v_offset)).collect();
    let mut element_owner = vec![0; elements.len()];
    for (ci, c) in components.iter().enumerate() {
        for &e in &c.elements {
            element_owner[e] = ci;
        }
    }
    let mut balances = Vec::with_capacity(links.len());
    let mut drives = Vec::with_capacity(links.len());
    for (n, (&link, &(q, v))) in links.iter().zip(&node_coordinates).enumerate() {
        let owner = tree.links[link].source.0;
        let refuse = |ci: usize, what: String, fix: &str| Error::Unsupported {
            component: components[ci].name.clone(),
            what: format!("{what} at the node without mass of `{}`", components[owner].name),
            fix: fix.into(),
        };
        let mut balance = Balance { q, v, terms: Vec::new(), stiffness: 0.0, damping: 0.0 };
        for (i, e) in elements.iter().enumerate() {
            let ci = element_owner[i];
            let ends = [(e.a, false), (e.b, true)];
            let here: Vec<_> = ends.iter().filter(|(r, _)| r.coordinates().any(|c| c.1 == v)).collect();
            let [(end, at_b)] = here.as_slice() else {
                if here.len() == 2 {
                    return Err(refuse(ci, "an element with both ends".into(), "connect its ends to different nodes"));
                }
                continue;
            };
            if end.second.is_some() {
                return Err(refuse(ci, "a place that follows two coordinates".into(), "give the node a mass"));
            }
            let other = if *at_b { e.a } else { e.b };
            if other.on_line() || other.coordinates().any(|c| node_coordinates.iter().any(|m| m.1 == c.1)) {
                return Err(refuse(
                    ci,
                    "an element from another node without mass (or from a line force's flange)".into(),
                    "give one of the nodes a mass, or join the elements into one",
                ));
            }
            let (c, d) = match e.law {
                Law1D::Spring { c, .. } => (c, 0.0),
                Law1D::Damper { d } => (0.0, d),
                Law1D::SpringDamper { c, d, .. } => (c, d),
                Law1D::Source { .. } => (0.0, 0.0),
                Law1D::Input { signal } | Law1D::Flow { signal } if signals.of_time[signal] => (0.0, 0.0),
                Law1D::Input { .. } | Law1D::Flow { .. } => {
                    return Err(refuse(
                        ci,
                        "a force that depends on the motion".into(),
                        "give the node a mass, or drive the force with sources of time",
                    ))
                }
                Law1D::Contact { .. } => {
                    return Err(refuse(ci, "a contact (gap or backlash)".into(), "give the node a mass"))
                }
            };
            let k = end.scale;
            balance.stiffness += c * k * k;
            balance.damping += d * k * k;
            balance.terms.push(BalanceTerm { element: i, at_b: *at_b, k, offset: end.offset });
        }
        if let Some(c) = couplings.iter().find(|c| c.terms.iter().any(|t| t.1 == v)) {
            return Err(refuse(c.component, "a gear held as a constraint".into(), "give the node a mass"));
        }
        if frictions.iter().any(|f| [f.a, f.b].iter().any(|r| r.coordinates().any(|c| c.1 == v))) {
            return Err(refuse(owner, "friction".into(), "give the node a mass"));
        }
        if tree.links[link].driven != 0 {
            return Err(refuse(owner, "a motion source".into(), "drive a node with mass"));
        }
        if !(balance.stiffness > 0.0 || balance.damping > 0.0) {
            return Err(Error::Unsupported {
                component: components[owner].name.clone(),
                what: "a node without mass with no spring or damper on it (forces alone leave its position \
                       undetermined)"
                    .into(),
                fix: "give the node a mass, or connect a spring or damper to it".into(),
            });
        }
        tree.links[link].driven = 1;
        let map = DriveMap::Linear { first: 0, count: 1, scale: 1.0, offset: 0.0 };
        let zero = signals.slots - 1;
        drives.push(Drive { link, level: DriveLevel::Balance { node: n }, map, slots: [zero; 7], component: owner });
        balances.push(balance);
    }
    Ok((balances, drives))
}

/// A start value the model fixes on what a node's balance decides (its
/// speed, and without damping its position) cannot hold: refused, naming it.
pub fn check_starts(
    components: &[CompiledComponent],
    tree: &Tree,
    links: &[usize],
    balances: &[Balance],
    states: &crate::system::StateLayout,
) -> Result<(), Error> {
    for (b, &link) in balances.iter().zip(links) {
        let mut decided = vec![states.nq + b.v];
        if b.damping == 0.0 {
            decided.push(b.q);
        }
        if let Some(index) = decided.into_iter().find(|&i| states.fixed[i]) {
            let component = &components[tree.links[link].states_of].name;
            let name = &states.names[index];
            return Err(Error::NotAState {
                component: component.clone(),
                variable: name.strip_prefix(&format!("{component}.")).unwrap_or(name).to_string(),
                reason: "it sits at a node without mass, where the balance of the forces on it decides it; give \
                         the start to what the elements join there, or give the node a mass"
                    .into(),
            });
        }
    }
    Ok(())
}
