//! Every example model (examples/**/*.dyad, the Modelica references among
//! them): how long it takes from file text to a compiled mechanism, and the
//! wall time of its complete simulation as its analysis asks for it
//! (outputs on the analysis's grid included).

use criterion::{criterion_group, criterion_main, Criterion};
use multibody::{Method, SimulationOptions};
use multibody_dyad::Package;

#[path = "../tests/common/examples.rs"]
mod examples;

fn compile(c: &mut Criterion) {
    let mut group = c.benchmark_group("compile");
    for path in examples::example_files() {
        let text = std::fs::read_to_string(&path).unwrap();
        let analysis = examples::load_example(&path).name;
        group.bench_function(examples::example_name(&path), |b| {
            b.iter(|| {
                let mut package = Package::new();
                package.add_source("model.dyad", text.as_str()).unwrap();
                package.lower_analysis(&analysis).unwrap().assemble().unwrap()
            })
        });
    }
    group.finish();
}

fn simulate(c: &mut Criterion) {
    let mut group = c.benchmark_group("simulate");
    group.sample_size(10);
    for path in examples::example_files() {
        let lowered = examples::load_example(&path);
        let mechanism = lowered.assemble().unwrap();
        group.bench_function(examples::example_name(&path), |b| {
            b.iter(|| mechanism.simulate(&lowered.options).unwrap())
        });
    }
    group.finish();
}

/// The stiff example with the implicit method its analysis asks for, and
/// with the explicit default: the case for Rodas4 (same run, same model).
fn stiff(c: &mut Criterion) {
    let path = examples::examples_dir().join("stiff_spring.dyad");
    let lowered = examples::load_example(&path);
    let mechanism = lowered.assemble().unwrap();
    let mut group = c.benchmark_group("stiff_spring");
    group.sample_size(10);
    for method in [Method::Rodas4, Method::DormandPrince45] {
        let options = SimulationOptions { method, ..lowered.options.clone() };
        group.bench_function(format!("{method:?}"), |b| b.iter(|| mechanism.simulate(&options).unwrap()));
    }
    group.finish();
}

criterion_group!(benches, compile, simulate, stiff);
criterion_main!(benches);
