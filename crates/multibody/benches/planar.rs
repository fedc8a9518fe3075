//! A 100-link planar chain built from PlanarMechanics components against
//! its 3-D twin (revolutes about z, rods with inertia about z): the
//! right-hand side and a short simulation, in one run.

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use multibody::SimulationOptions;

#[path = "../tests/common/chain.rs"]
mod chain;

fn planar(c: &mut Criterion) {
    let mut group = c.benchmark_group("planar");
    for (name, planar) in [("planar", true), ("3d", false)] {
        let mechanism = chain::planar_chain(100, planar).assemble().unwrap();
        let y = mechanism.states().start.clone();
        let mut ws = mechanism.workspace();
        let mut dy = vec![0.0; y.len()];
        group.bench_function(format!("rhs/{name}/100"), |b| {
            b.iter(|| mechanism.rhs(&mut ws, 0.0, black_box(&y), &mut dy).unwrap())
        });
        let options = SimulationOptions { stop: 0.05, saveat: 0.01, ..Default::default() };
        group.bench_function(format!("simulate/{name}/100"), |b| b.iter(|| mechanism.simulate(&options).unwrap()));
    }
    group.finish();
}

criterion_group!(benches, planar);
criterion_main!(benches);
