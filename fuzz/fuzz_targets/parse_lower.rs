//! Any text, read as a model file: parse, lower every definition, assemble,
//! and render every diagnostic. Nothing may panic, overflow or hang.
#![no_main]

mod front_end;

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else { return };
    front_end::each_lowered(text, |package, lowered| {
        for w in &lowered.warnings {
            let _ = w.render(package.sources(), false);
        }
        if let Err(d) = lowered.assemble() {
            let _ = d.render(package.sources(), false);
        }
    });
});
