//! Signal connections: each signal node carries the value of its one
//! source (a block's output); inputs with no source read zero.

use super::connections::Connectors;
use crate::components::{ConnectorType, Part, SignalSource};
use crate::mechanism::CompiledComponent;
use crate::Error;

pub struct Signals {
    pub sources: Vec<SignalSource>,
    /// For every connector, its signal slot (`sources.len()` reads zero).
    pub of_connector: Vec<usize>,
    pub warnings: Vec<String>,
}

pub fn resolve(components: &[CompiledComponent], conn: &Connectors) -> Result<Signals, Error> {
    let mut sources = Vec::new();
    let mut source_of_connector = vec![usize::MAX; conn.infos.len()];
    for (ci, c) in components.iter().enumerate() {
        for part in &c.parts {
            if let Part::Source { output, signal } = part {
                source_of_connector[Connectors::id(components, ci, *output)] = sources.len();
                sources.push(signal.clone());
            }
        }
    }
    let zero = sources.len();
    let mut of_connector = vec![zero; conn.infos.len()];
    let mut warnings = Vec::new();
    for members in &conn.flange_nodes {
        if !conn.types[members[0]].is_signal() {
            continue;
        }
        let outputs: Vec<usize> =
            members.iter().copied().filter(|&c| conn.types[c] == ConnectorType::RealOutput).collect();
        let slot = match outputs.as_slice() {
            [] => {
                for &c in members {
                    warnings.push(format!(
                        "the input `{}` is not connected to a source; it reads 0",
                        conn.name(components, c)
                    ));
                }
                zero
            }
            [one] => source_of_connector[*one],
            [first, second, ..] => {
                return Err(Error::Unsupported {
                    component: components[conn.infos[*second].component].name.clone(),
                    what: format!(
                        "two outputs (`{}` and `{}`) driving one signal; connect each input to one output",
                        conn.name(components, *first),
                        conn.name(components, *second)
                    ),
                })
            }
        };
        for &c in members {
            of_connector[c] = slot;
        }
    }
    Ok(Signals { sources, of_connector, warnings })
}
