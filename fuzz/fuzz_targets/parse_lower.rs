//! Any text, read as a model file: parse, lower every definition, assemble,
//! and render every diagnostic. Nothing may panic, overflow or hang.
#![no_main]

use libfuzzer_sys::fuzz_target;
use multibody_dyad::{DefinitionKind, Package};

/// Enough definitions to exercise several models per input, few enough to stay fast.
const MAX_DEFINITIONS: usize = 8;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else { return };
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
            Err(d) => {
                let _ = d.render(package.sources(), false);
            }
            Ok(lowered) => {
                for w in &lowered.warnings {
                    let _ = w.render(package.sources(), false);
                }
                if let Err(d) = lowered.assemble() {
                    let _ = d.render(package.sources(), false);
                }
            }
        }
    }
});
