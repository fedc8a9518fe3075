//! 1-D elements on joint axes: each flange is either fixed (a joint's
//! support) or follows a joint coordinate (a joint's axis).

use super::connections::Connectors;
use super::links::Tree;
use crate::components::Part;
use crate::mechanism::{AxisElement, CompiledComponent, FlangeRef, JointRef};
use crate::Error;

/// The elements, and for each component the indices of its own.
pub fn elements(
    components: &mut [CompiledComponent],
    conn: &Connectors,
    tree: &Tree,
) -> Result<Vec<AxisElement>, Error> {
    let mut place: Vec<Option<(FlangeRef, usize)>> = vec![None; conn.flange_nodes.len()];
    for c in components.iter() {
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
                                            "a 1-D connection between `{}` and `{}` (elements between two joints, such as gears)",
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
    let mut elements = Vec::new();
    for ci in 0..components.len() {
        let mut own = Vec::new();
        for part in &components[ci].parts {
            if let Part::Element1D { a, b, law } = *part {
                let end = |local: usize| -> Result<FlangeRef, Error> {
                    let id = components[ci].first_connector + local;
                    place[conn.flange_node_of[id]]
                        .map(|(r, _)| r)
                        .ok_or_else(|| Error::FloatingFlange { connector: conn.name(components, id) })
                };
                let (a, b) = (end(a)?, end(b)?);
                own.push(elements.len());
                elements.push(AxisElement { a, b, law });
            }
        }
        components[ci].elements = own;
    }
    Ok(elements)
}
