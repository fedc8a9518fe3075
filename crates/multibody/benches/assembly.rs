//! Assembly (model to compiled mechanism) of models with 10 to 10 000
//! components: chains of revolutes, bodies and rods.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};

#[path = "../tests/common/chain.rs"]
mod chain;

fn assembly(c: &mut Criterion) {
    let mut group = c.benchmark_group("assemble");
    group.sample_size(10);
    // A chain of n links has 3 n components (joint, body, rod) less one rod, plus the World.
    for components in [10usize, 100, 1000, 10_000] {
        let model = chain::benchmark_chain(components / 3);
        group.bench_with_input(BenchmarkId::from_parameter(components), &model, |b, model| {
            b.iter(|| model.assemble().unwrap())
        });
    }
    group.finish();
}

criterion_group!(benches, assembly);
criterion_main!(benches);
