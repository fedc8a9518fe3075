//! The repository's example models (examples/**/*.dyad), each with the one
//! analysis it defines. Shared by the tests and the benchmarks.

use multibody_dyad::{DefinitionKind, Lowered, Package};
use std::path::{Path, PathBuf};

/// The repository's `examples` folder.
pub fn examples_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples")
}

/// Whether a model file defines an analysis (else it is a library of
/// components for the files beside it, as `examples/robot/RobotAxis.dyad`).
fn defines_analysis(text: &str) -> bool {
    text.lines().any(|line| line.starts_with("analysis "))
}

/// The library files beside `path`: the `.dyad` files of its folder that
/// define no analysis, which the examples there use.
fn libraries_beside(path: &Path) -> Vec<PathBuf> {
    let folder = path.parent().expect("a file is in a folder");
    let mut out: Vec<PathBuf> = std::fs::read_dir(folder)
        .expect("the folder is readable")
        .map(|e| e.unwrap().path())
        .filter(|p| p != path && p.extension().is_some_and(|e| e == "dyad"))
        .filter(|p| !defines_analysis(&std::fs::read_to_string(p).unwrap()))
        .collect();
    out.sort();
    out
}

/// Every `.dyad` file under the repository's `examples` folder that
/// defines an analysis, sorted.
#[allow(dead_code)]
pub fn example_files() -> Vec<PathBuf> {
    let mut files = Vec::new();
    let mut folders = vec![examples_dir()];
    while let Some(folder) = folders.pop() {
        for entry in std::fs::read_dir(&folder).expect("the examples folder is readable") {
            let path = entry.unwrap().path();
            if path.is_dir() {
                folders.push(path);
            } else if path.extension().is_some_and(|e| e == "dyad")
                && defines_analysis(&std::fs::read_to_string(&path).unwrap())
            {
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

/// The sources an example needs: the library files beside it, then the
/// file itself, each as (path, text).
pub fn example_sources(path: &Path) -> Vec<(String, String)> {
    libraries_beside(path)
        .into_iter()
        .chain([path.to_path_buf()])
        .map(|p| (p.display().to_string(), std::fs::read_to_string(&p).unwrap()))
        .collect()
}

/// Parses the file, with the library files beside it, and lowers its analysis.
pub fn load_example(path: &Path) -> Lowered {
    let mut package = Package::new();
    for (name, text) in example_sources(path) {
        package.add_source(name, text).unwrap();
    }
    let analysis = package
        .definitions()
        .into_iter()
        .find(|d| d.kind == DefinitionKind::Analysis)
        .unwrap_or_else(|| panic!("{} defines no analysis", path.display()));
    package.lower_analysis(&analysis.name).unwrap()
}
