//! The repository's example models (examples/**/*.dyad), each with the one
//! analysis it defines. Shared by the tests and the benchmarks.

use multibody_dyad::{DefinitionKind, Lowered, Package};
use std::path::{Path, PathBuf};

/// The repository's `examples` folder.
pub fn examples_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples")
}

/// Every `.dyad` file under the repository's `examples` folder, sorted.
#[allow(dead_code)]
pub fn example_files() -> Vec<PathBuf> {
    let mut files = Vec::new();
    let mut folders = vec![examples_dir()];
    while let Some(folder) = folders.pop() {
        for entry in std::fs::read_dir(&folder).expect("the examples folder is readable") {
            let path = entry.unwrap().path();
            if path.is_dir() {
                folders.push(path);
            } else if path.extension().is_some_and(|e| e == "dyad") {
                files.push(path);
            }
        }
    }
    files.sort();
    files
}

#[allow(dead_code)]
/// The file's stem, e.g. `Fourbar1` for `examples/msl/Fourbar1.dyad`.
pub fn example_name(path: &Path) -> String {
    path.file_stem().unwrap().to_string_lossy().into_owned()
}

/// Parses the file and lowers its analysis.
pub fn load_example(path: &Path) -> Lowered {
    let text = std::fs::read_to_string(path).unwrap();
    let mut package = Package::new();
    package.add_source(path.display().to_string(), text).unwrap();
    let analysis = package
        .definitions()
        .into_iter()
        .find(|d| d.kind == DefinitionKind::Analysis)
        .unwrap_or_else(|| panic!("{} defines no analysis", path.display()));
    package.lower_analysis(&analysis.name).unwrap()
}
