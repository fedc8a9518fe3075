//! Every file in `bad/` is a model with a mistake. Its diagnostics (rendered
//! without colours) are compared with the snapshot in `snapshots/`: each
//! must name the place (file:line:col with a caret) and say what to do.

use multibody_dyad::diagnostics::render_all;
use multibody_dyad::{DefinitionKind, Diagnostic, Package};
use std::path::Path;

/// Reads, lowers and assembles a file like `multibody check` does, and
/// collects what it reports.
fn diagnose(path: &Path) -> (Package, Vec<Diagnostic>) {
    let text = std::fs::read_to_string(path).unwrap();
    let name = format!("bad/{}", path.file_name().unwrap().to_string_lossy());
    let mut package = Package::new();
    let mut reported = Vec::new();
    if let Err(d) = package.add_source(name, text) {
        reported.push(d);
        return (package, reported);
    }
    let analysis = package.definitions().into_iter().find(|d| d.kind == DefinitionKind::Analysis);
    let lowered = match analysis {
        Some(a) => package.lower_analysis(&a.name),
        None => {
            let top = package.top_components();
            let first = top.first().map(|d| d.name.clone()).unwrap_or_else(|| "Pendulum".into());
            package.lower_component(&first)
        }
    };
    match lowered {
        Err(d) => reported.push(d),
        Ok(l) => {
            reported.extend(l.warnings.iter().cloned());
            if let Err(d) = l.assemble() {
                reported.push(d);
            }
        }
    }
    (package, reported)
}

#[test]
fn bad_models_are_explained() {
    insta::glob!("bad/*.dyad", |path| {
        let (package, reported) = diagnose(path);
        let errors: Vec<&Diagnostic> = reported.iter().filter(|d| d.is_error()).collect();
        assert!(!errors.is_empty(), "{}: expected an error", path.display());
        for e in &errors {
            assert!(e.primary_span().is_some(), "{}: `{}` points nowhere", path.display(), e.message);
        }
        insta::assert_snapshot!(render_all(&reported, package.sources(), false));
    });
}

#[test]
fn there_are_enough_bad_models() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/bad");
    let count = std::fs::read_dir(dir)
        .unwrap()
        .filter(|e| e.as_ref().unwrap().path().extension().is_some_and(|x| x == "dyad"))
        .count();
    assert!(count >= 25, "only {count} bad models");
}
