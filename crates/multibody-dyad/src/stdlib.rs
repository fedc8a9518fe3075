//! The components of the standard library written in Dyad, shipped with
//! the command: parsed once, and part of every package under their
//! library's name (`BlockComponents.Integrator`). Their files come first in
//! every package's sources, so that their spans render in messages.

use crate::ast::File;
use crate::parser::parse;
use std::sync::OnceLock;

/// Each library: its name, the file's name in messages, and its text.
const LIBRARIES: &[(&str, &str, &str)] = &[
    ("Dyad", "<stdlib>/Dyad.dyad", include_str!("../stdlib/Dyad.dyad")),
    ("BlockComponents", "<stdlib>/BlockComponents.dyad", include_str!("../stdlib/BlockComponents.dyad")),
    ("ElectricalComponents", "<stdlib>/ElectricalComponents.dyad", include_str!("../stdlib/ElectricalComponents.dyad")),
    ("ThermalComponents", "<stdlib>/ThermalComponents.dyad", include_str!("../stdlib/ThermalComponents.dyad")),
    ("MultibodyComponents", "<stdlib>/MultibodyComponents.dyad", include_str!("../stdlib/MultibodyComponents.dyad")),
    ("PlanarMechanics", "<stdlib>/PlanarMechanics.dyad", include_str!("../stdlib/PlanarMechanics.dyad")),
    ("RotationalComponents", "<stdlib>/RotationalComponents.dyad", include_str!("../stdlib/RotationalComponents.dyad")),
    (
        "TranslationalComponents",
        "<stdlib>/TranslationalComponents.dyad",
        include_str!("../stdlib/TranslationalComponents.dyad"),
    ),
    (
        "RotationalComponents.Acausal",
        "<stdlib>/Acausal/RotationalComponents.dyad",
        include_str!("../stdlib/Acausal/RotationalComponents.dyad"),
    ),
    (
        "TranslationalComponents.Acausal",
        "<stdlib>/Acausal/TranslationalComponents.dyad",
        include_str!("../stdlib/Acausal/TranslationalComponents.dyad"),
    ),
];

/// The libraries' names, file names and texts, in file order.
pub fn sources() -> impl Iterator<Item = (&'static str, &'static str)> {
    LIBRARIES.iter().map(|(_, name, text)| (*name, *text))
}

/// The parsed libraries with their names; file `k` has id `k`.
pub fn files() -> &'static [(&'static str, File)] {
    static FILES: OnceLock<Vec<(&'static str, File)>> = OnceLock::new();
    FILES.get_or_init(|| {
        LIBRARIES
            .iter()
            .enumerate()
            .map(|(id, (library, _, text))| {
                let mut file = parse(id, text)
                    .unwrap_or_else(|d| panic!("the standard library {library} does not parse: {}", d.message));
                // Short names inside a library are its components first.
                file.package = (*library != "Dyad").then(|| library.to_string());
                (*library, file)
            })
            .collect()
    })
}

#[cfg(test)]
mod tests {
    #[test]
    fn the_libraries_parse() {
        assert!(!super::files().is_empty());
    }
}
