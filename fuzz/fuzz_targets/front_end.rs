//! What both targets do first: read the text as a model file and lower
//! each of its first definitions, rendering every diagnostic on the way.

use multibody_dyad::{DefinitionKind, Lowered, Package};

/// Enough definitions to exercise several models per input, few enough to stay fast.
const MAX_DEFINITIONS: usize = 8;

/// Calls `then` with each definition of `text` that lowers.
pub fn each_lowered(text: &str, mut then: impl FnMut(&Package, Lowered)) {
    let mut package = Package::new();
    if let Err(d) = package.add_source("fuzz.dyad", text) {
        let _ = d.render(package.sources(), false);
        return;
    }
    for definition in package.definitions().into_iter().take(MAX_DEFINITIONS) {
        let lowered = match definition.kind {
            DefinitionKind::Analysis => package.lower_analysis(&definition.name),
            DefinitionKind::Component(_) => package.lower_component(&definition.name),
        };
        match lowered {
            Ok(lowered) => then(&package, lowered),
            Err(d) => {
                let _ = d.render(package.sources(), false);
            }
        }
    }
}
