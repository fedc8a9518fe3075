//! 1-D connectors on joint axes: each 1-D node is either fixed (a joint's
//! support) or follows a joint coordinate (a joint's axis). The 1-D
//! elements and the couplings (gears) between them act there.

use super::connections::Connectors;
use super::links::Tree;
use super::mechanism::{CompiledComponent, JointRef};
use crate::components::{Law1D, Part};
use crate::system::{AxisElement, Coupling, FlangeRef};
use crate::Error;

/// For every 1-D node, where it sits and the connector that placed it
/// (`None`: no joint axis or support is connected to it).
pub type Places = Vec<Option<(FlangeRef, usize)>>;

/// Where each 1-D node sits.
pub fn places(components: &[CompiledComponent], conn: &Connectors, tree: &Tree) -> Result<Places, Error> {
    let mut place: Places = vec![None; conn.flange_nodes.len()];
    for c in components {
        let mut joint_index = 0;
        for part in &c.parts {
            match part {
                Part::Joint { flanges, .. } => {
                    if let (Some(f), JointRef::Link(k)) = (flanges, c.joints[joint_index]) {
                        let link = &tree.links[k];
                        let coordinate = FlangeRef::Coordinate { q: link.q_offset, v: link.v_offset };
                        for (local, r) in [(f.axis, coordinate), (f.support, FlangeRef::Fixed)] {
                            let id = c.first_connector + local;
                            let node = conn.flange_node_of[id];
                            match place[node] {
                                Some((existing, other)) if existing != r => {
                                    return Err(Error::Unsupported {
                                        component: c.name.clone(),
                                        what: format!(
                                            "a 1-D connection between `{}` and `{}` (two joint axes joined directly; put a gear between them)",
                                            conn.name(components, id),
                                            conn.name(components, other)
                                        ),
                                    });
                                }
                                _ => place[node] = Some((r, id)),
                            }
                        }
                    }
                    joint_index += 1;
                }
                Part::Owner { .. } => joint_index += 1,
                _ => {}
            }
        }
    }
    Ok(place)
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
        .map(|&node| places.get(node).copied().flatten().map_or(FlangeRef::Fixed, |(r, _)| r))
        .collect()
}

/// The elements, and for each component the indices of its own; signal
/// inputs of driven sources become signal slots.
pub fn elements(
    components: &mut [CompiledComponent],
    conn: &Connectors,
    places: &Places,
    signal_of_connector: &[usize],
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
                    other => other,
                };
                own.push(elements.len());
                elements.push(AxisElement { a, b, law });
            }
        }
        components[ci].elements = own;
    }
    Ok(elements)
}

/// The couplings between joint coordinates, numbered from `first_row` on.
/// Only 1-DOF joints have axis flanges, so every coordinate a coupling
/// reaches has its velocity as its rate, as the constraint rows assume.
pub fn couplings(
    components: &[CompiledComponent],
    conn: &Connectors,
    places: &Places,
    first_row: usize,
) -> Result<Vec<Coupling>, Error> {
    let mut couplings = Vec::new();
    for (ci, c) in components.iter().enumerate() {
        for part in &c.parts {
            let Part::Coupling { terms } = part else { continue };
            let mut coupling = Coupling { terms: Vec::new(), row: first_row + couplings.len(), component: ci };
            for &(local, coefficient) in terms {
                let id = Connectors::id(components, ci, local);
                if !conn.infos[id].connected {
                    continue; // a housing left unconnected is fixed
                }
                if let FlangeRef::Coordinate { q, v } = flange(components, conn, places, id)? {
                    coupling.terms.push((q, v, coefficient));
                }
            }
            couplings.push(coupling);
        }
    }
    Ok(couplings)
}
