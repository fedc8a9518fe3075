//! Connectors and connections: checks each `connect` and merges the
//! connected connectors into nodes.

use super::mechanism::{CompiledComponent, ConnectorInfo};
use crate::components::ConnectorType;
use crate::error::closest;
use crate::math::union_find::UnionFind;
use crate::{Error, Model};
use std::collections::HashMap;

pub struct Connectors {
    pub infos: Vec<ConnectorInfo>,
    pub types: Vec<ConnectorType>,
    /// Frame nodes, each a list of connectors.
    pub frame_nodes: Vec<Vec<usize>>,
    /// 1-D nodes (splines and flanges), each a list of connectors.
    pub flange_nodes: Vec<Vec<usize>>,
    /// For a 1-D connector, its 1-D node.
    pub flange_node_of: Vec<usize>,
}

impl Connectors {
    /// Global number of `component`'s connector `local`.
    pub fn id(components: &[CompiledComponent], component: usize, local: usize) -> usize {
        components[component].first_connector + local
    }

    pub fn node(&self, connector: usize) -> usize {
        self.infos[connector].node
    }

    /// `component.connector`, for messages.
    pub fn name(&self, components: &[CompiledComponent], connector: usize) -> String {
        let c = &components[self.infos[connector].component];
        format!("{}.{}", c.name, c.spec.connectors[connector - c.first_connector].name)
    }
}

pub fn resolve(model: &Model, components: &[CompiledComponent]) -> Result<Connectors, Error> {
    let mut infos = Vec::new();
    let mut types = Vec::new();
    for (index, c) in components.iter().enumerate() {
        for spec in c.spec.connectors {
            infos.push(ConnectorInfo { component: index, node: usize::MAX, connected: false });
            types.push(spec.ty);
        }
    }
    let by_name: HashMap<&str, usize> = components.iter().enumerate().map(|(i, c)| (c.name.as_str(), i)).collect();
    let mut sets = UnionFind::new(infos.len());
    for connection in &model.connections {
        if connection.ends.len() < 2 {
            return Err(Error::LonelyConnection(connection.ends.first().cloned().unwrap_or_default()));
        }
        let ends: Vec<usize> =
            connection.ends.iter().map(|end| find_connector(end, components, &by_name)).collect::<Result<_, _>>()?;
        for (k, &id) in ends.iter().enumerate() {
            infos[id].connected = true;
            if !types[id].connects_to(&types[ends[0]]) {
                return Err(Error::IncompatibleConnectors {
                    a: connection.ends[0].clone(),
                    a_type: types[ends[0]].name().into(),
                    b: connection.ends[k].clone(),
                    b_type: types[id].name().into(),
                });
            }
            sets.union(ends[0], id);
        }
    }
    let (class, count) = sets.classes();
    // Number frame and 1-D nodes separately, in order of first appearance.
    let mut frame_of_class = vec![usize::MAX; count];
    let mut flange_of_class = vec![usize::MAX; count];
    let mut frame_nodes: Vec<Vec<usize>> = Vec::new();
    let mut flange_nodes: Vec<Vec<usize>> = Vec::new();
    let mut flange_node_of = vec![usize::MAX; infos.len()];
    for id in 0..infos.len() {
        let k = class[id];
        if types[id].is_frame() {
            if frame_of_class[k] == usize::MAX {
                frame_of_class[k] = frame_nodes.len();
                frame_nodes.push(Vec::new());
            }
            infos[id].node = frame_of_class[k];
            frame_nodes[frame_of_class[k]].push(id);
        } else {
            if flange_of_class[k] == usize::MAX {
                flange_of_class[k] = flange_nodes.len();
                flange_nodes.push(Vec::new());
            }
            flange_node_of[id] = flange_of_class[k];
            flange_nodes[flange_of_class[k]].push(id);
        }
    }
    Ok(Connectors { infos, types, frame_nodes, flange_nodes, flange_node_of })
}

/// The connector `component.connector` (the component name may itself contain dots).
fn find_connector(end: &str, components: &[CompiledComponent], by_name: &HashMap<&str, usize>) -> Result<usize, Error> {
    let Some((component, connector)) = end.rsplit_once('.') else {
        return Err(Error::UnknownComponent {
            reference: end.into(),
            suggestions: closest(end, by_name.keys().copied()),
        });
    };
    let Some(&index) = by_name.get(component) else {
        return Err(Error::UnknownComponent {
            reference: end.into(),
            suggestions: closest(component, by_name.keys().copied()),
        });
    };
    let c = &components[index];
    let Some((local, _)) = c.spec.connector(connector) else {
        return Err(Error::UnknownConnector {
            component: component.into(),
            kind: c.spec.kind.into(),
            connector: connector.into(),
            suggestions: closest(connector, c.spec.public_connectors().map(|s| s.name)),
            valid: c.spec.public_connectors().map(|s| s.name.to_string()).collect(),
        });
    };
    Ok(c.first_connector + local)
}
