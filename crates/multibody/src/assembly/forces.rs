//! Force elements between frames, with their inputs resolved to signal
//! slots and their ends to the links (or massless groups) they act on.

use super::connections::Connectors;
use super::links::Tree;
use super::mechanism::CompiledComponent;
use crate::components::{ForceLaw, Part};
use crate::system::{Anchor, Attachment, ForceElement, Load};
use crate::Error;

pub fn elements(
    components: &[CompiledComponent],
    conn: &Connectors,
    tree: &mut Tree,
    signal_of_connector: &[usize],
) -> Result<Vec<ForceElement>, Error> {
    let mut elements = Vec::new();
    for (ci, c) in components.iter().enumerate() {
        for part in &c.parts {
            let Part::Force { a, b, law } = *part else { continue };
            let attach = |local: usize| {
                let node = conn.node(Connectors::id(components, ci, local));
                Attachment { anchor: tree.nodes[node].anchor, pose: tree.nodes[node].pose }
            };
            let slots = |inputs: [usize; 3]| inputs.map(|i| signal_of_connector[Connectors::id(components, ci, i)]);
            let load = match law {
                ForceLaw::Line { c, d, s_unstretched, s_small } => Load::Line { c, d, s_unstretched, s_small },
                ForceLaw::Force { inputs, resolve } => Load::Force { signals: slots(inputs), resolve },
                ForceLaw::Torque { inputs, resolve } => Load::Torque { signals: slots(inputs), resolve },
                ForceLaw::Flow { inputs, world } => Load::Flow {
                    signals: inputs.map(|i| signal_of_connector[Connectors::id(components, ci, i)]),
                    world,
                },
                ForceLaw::PlanarAxes { c, d, rel0 } => Load::PlanarAxes { c, d, rel0 },
                ForceLaw::Tyre { radius, law, c_z, d_z, road } => {
                    Load::Tyre { radius, law, c_z, d_z, road: road.map(|r| super::road_base(components, ci) + r) }
                }
            };
            let id = |local: usize| Connectors::id(components, ci, local);
            let element = ForceElement { load, a: a.map(attach), b: attach(b), connectors: (a.map(id), id(b)) };
            for end in element.a.iter().chain([&element.b]) {
                if let Anchor::Massless(m) = end.anchor {
                    if let Load::PlanarAxes { .. } = load {
                        return Err(Error::Unsupported {
                            component: c.name.clone(),
                            what: "a planar spring or damper on frames without mass".into(),
                            fix: "add mass there (a PlanarMechanics.Body)".into(),
                        });
                    }
                    if let Load::Line { d, .. } = load {
                        if d != 0.0 {
                            return Err(Error::Unsupported {
                                component: c.name.clone(),
                                what: "a damper on frames without mass (their velocity would be undetermined)".into(),
                                fix: "add mass there".into(),
                            });
                        }
                    }
                    tree.massless[m].elements.push(elements.len());
                }
            }
            elements.push(element);
        }
    }
    Ok(elements)
}
