//! What the tests of model files share: running the only analysis of a
//! file's text, and the first error it gives as the command prints it.

#![allow(dead_code)] // each test file uses what it needs

use multibody::{Mechanism, SimulationOptions, Solution};
use multibody_dyad::{DefinitionKind, Package};

/// The mechanism and options of the only analysis in `text` (file `name`).
pub fn load(name: &str, text: &str) -> (Mechanism, SimulationOptions) {
    let mut package = Package::new();
    if let Err(d) = package.add_source(name, text.to_string()) {
        panic!("{}", d.render(package.sources(), false));
    }
    let analysis = only_analysis(&package);
    let lowered =
        package.lower_analysis(&analysis).unwrap_or_else(|d| panic!("{}", d.render(package.sources(), false)));
    let mechanism = lowered.assemble().unwrap_or_else(|d| panic!("{}", d.render(package.sources(), false)));
    (mechanism, lowered.options)
}

/// Runs the only analysis in `text`.
pub fn simulate(text: &str) -> Solution {
    let (mechanism, options) = load("model.dyad", text);
    mechanism.simulate(&options).unwrap()
}

/// The message of the first error the model gives, as the command prints it.
pub fn error_of(text: &str) -> String {
    let mut package = Package::new();
    if let Err(d) = package.add_source("model.dyad", text.to_string()) {
        return d.render(package.sources(), false);
    }
    match package.lower_analysis(&only_analysis(&package)) {
        Err(d) => d.render(package.sources(), false),
        Ok(lowered) => match lowered.assemble() {
            Err(d) => d.render(package.sources(), false),
            Ok(_) => panic!("the model was accepted"),
        },
    }
}

fn only_analysis(package: &Package) -> String {
    package.definitions().into_iter().find(|d| d.kind == DefinitionKind::Analysis).expect("an analysis").name
}

/// The largest |a - b| over two columns.
pub fn worst_difference(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max)
}

/// The largest |column - f(t)| over the run.
pub fn worst_against(solution: &Solution, column: &str, f: impl Fn(f64) -> f64) -> f64 {
    let values = solution.get(column).unwrap_or_else(|| panic!("no column `{column}`"));
    solution.time().iter().zip(values).map(|(&t, &x)| (x - f(t)).abs()).fold(0.0, f64::max)
}

/// Prints `worst` as a fraction of `tolerance` and holds it to it.
pub fn report(what: &str, worst: f64, tolerance: f64) {
    println!("{what}: worst {worst:.2e} ({:.3} of the tolerance {tolerance:e})", worst / tolerance);
    assert!(worst <= tolerance, "{what}: {worst:e} > {tolerance:e}");
}

/// The text of a model file of the repository's `examples/` folder.
pub fn example(path: &str) -> String {
    let file = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples").join(path);
    std::fs::read_to_string(&file).unwrap_or_else(|e| panic!("{}: {e}", file.display()))
}
