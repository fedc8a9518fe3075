//! Assembly: turns a [`Model`] into a [`Mechanism`].
//!
//! 1. `instances`: find the World, check each component's kind and
//!    parameters, build the components.
//! 2. `connections`: check each `connect`, merge connectors into nodes.
//! 3. `links`: merge nodes joined by rigid parts into rigid groups; grow a
//!    tree of joints from the World, and from the one orientation owner of
//!    each floating group.
//! 4. masses into link inertias, point-gravity masses, 1-D elements
//!    (`axis`), states and start values (`states`).
//! 5. `checks`: every degree of freedom has inertia behind it.
//! 6. `flows`: the tree along which cut forces are computed for outputs.

mod axis;
mod checks;
mod connections;
mod flows;
mod instances;
mod links;
mod states;
mod union_find;

use crate::components::Part;
use crate::mechanism::{Mechanism, PointGravityMass, GROUND};
use crate::{Error, Model};

pub fn assemble(model: &Model) -> Result<Mechanism, Error> {
    let world = instances::world_settings(model)?;
    let mut components = instances::build(model, &world)?;
    let conn = connections::resolve(model, &components)?;
    let groups = links::rigid_groups(&components, &conn)?;
    let mut tree = links::spanning_tree(&components, &conn, &groups)?;
    for (n, node) in tree.nodes.iter_mut().enumerate() {
        node.connectors = conn.frame_nodes[n].clone();
    }
    let warnings = groups.warnings.clone();

    // Which link each component's joints and owners move.
    for (k, link) in tree.links.iter().enumerate().skip(1) {
        let (ci, pi) = link.source;
        let position =
            components[ci].parts[..pi].iter().filter(|p| matches!(p, Part::Joint { .. } | Part::Owner { .. })).count();
        let joint_links = &mut components[ci].joint_links;
        if joint_links.len() <= position {
            joint_links.resize(position + 1, usize::MAX);
        }
        joint_links[position] = k;
    }

    // Masses into link inertias.
    let uniform_gravity = world.uniform_gravity();
    let mut point_masses = Vec::new();
    for c in &components {
        for part in &c.parts {
            if let Part::Mass { frame, inertia, point_gravity } = part {
                let node = &tree.nodes[conn.node(c.first_connector + frame)];
                if node.link == GROUND {
                    continue;
                }
                let in_link = inertia.expressed_in_parent(&node.pose);
                tree.links[node.link].inertia += in_link;
                if (*point_gravity || world.point_gravity) && in_link.mass > 0.0 {
                    point_masses.push(PointGravityMass { link: node.link, mass: in_link.mass, com: in_link.com() });
                }
            }
        }
    }

    let axis_elements = axis::elements(&mut components, &conn, &tree)?;
    let states = states::layout(model, &components, &tree)?;
    checks::inertia_behind_every_joint(&components, &conn, &tree, &states.start[..states.nq])?;
    let flow_tree = flows::flow_tree(&components, &conn, &tree);

    Ok(Mechanism {
        name: model.name.clone(),
        world,
        components,
        connectors: conn.infos,
        nodes: tree.nodes,
        links: tree.links,
        axis_elements,
        point_masses,
        uniform_gravity,
        states,
        flow_tree,
        warnings,
    })
}
