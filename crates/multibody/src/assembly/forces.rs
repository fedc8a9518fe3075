//! Force elements, with their inputs resolved to signal slots, their ends
//! to the links (or massless groups) they act on, and their flanges placed.

use super::axis::{self, Places};
use super::connections::Connectors;
use super::links::Tree;
use super::mechanism::CompiledComponent;
use crate::components::{ForceLaw, Part};
use crate::math::Transform;
use crate::system::{Anchor, Attachment, FlangeRef, ForceElement};
use crate::Error;

pub fn elements(
    components: &[CompiledComponent],
    conn: &Connectors,
    tree: &mut Tree,
    places: &Places,
    signal_of_connector: &[usize],
    zero_slot: usize,
    plane: &Transform,
) -> Result<Vec<ForceElement>, Error> {
    let mut elements = Vec::new();
    for (ci, c) in components.iter().enumerate() {
        for part in &c.parts {
            let Part::Force { a, b, law, inputs, flanges } = *part else { continue };
            let id = |local: usize| Connectors::id(components, ci, local);
            let attach = |local: usize| {
                let node = conn.node(id(local));
                Attachment { anchor: tree.nodes[node].anchor, pose: tree.nodes[node].pose }
            };
            let law = match law {
                ForceLaw::Tyre { radius, law, c_z, d_z, road } => {
                    ForceLaw::Tyre { radius, law, c_z, d_z, road: road.map(|r| super::road_base(components, ci) + r) }
                }
                other => other,
            };
            let mut flange_refs = [FlangeRef::FIXED; 2];
            for (r, f) in flange_refs.iter_mut().zip(flanges) {
                if let Some(local) = f {
                    *r = axis::flange(components, conn, places, id(local))?;
                }
            }
            let element = ForceElement {
                law,
                a: a.map(attach),
                b: attach(b),
                connectors: (a.map(id), id(b)),
                inputs: inputs.map(|i| i.map_or(zero_slot, |i| signal_of_connector[id(i)])),
                flanges: flange_refs,
                in_plane: super::links::in_placed_plane(c, plane),
            };
            for end in element.a.iter().chain([&element.b]) {
                if let Anchor::Massless(m) = end.anchor {
                    if let ForceLaw::PlanarAxes { .. } = law {
                        return Err(Error::Unsupported {
                            component: c.name.clone(),
                            what: "a planar spring or damper on frames without mass".into(),
                            fix: "add mass there (a PlanarMechanics.Body)".into(),
                        });
                    }
                    if let ForceLaw::Line { d, .. } = law {
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
