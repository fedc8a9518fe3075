//! How lowering grows with the size of a model: from file text to a
//! compiled mechanism for long chains of parameters and long `for` loops
//! (issue 26: both grew quadratically and hung at 250,000 parameters and
//! 50,000 elements). Linear cost means the time per element stays put as
//! the size grows by ten.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use multibody_dyad::Package;

/// `parameter p_k::Real = p_(k-1) + 1`, `n` of them.
fn chained_parameters(n: usize) -> String {
    let mut text = String::from("example component Chain\n  world = World()\n  parameter p_0::Real = 0\n");
    for k in 1..n {
        text.push_str(&format!("  parameter p_{k}::Real = p_{} + 1\n", k - 1));
    }
    text.push_str("end\n");
    text
}

/// `for i in 1:n  x[i] = i * time  end` over a variable of `n` elements.
fn for_loop(n: usize) -> String {
    format!(
        "example component Chain\n  world = World()\n  parameter n::Integer = {n}\n  variable x::Real[n]\nrelations\n  for i in 1:n\n    x[i] = i * time\n  end\nend\n"
    )
}

fn check(text: &str) -> usize {
    let mut package = Package::new();
    package.add_source("model.dyad", text).unwrap();
    package.lower_component("Chain").unwrap().assemble().unwrap().signals().len()
}

fn sizes(c: &mut Criterion) {
    type Model = fn(usize) -> String;
    let cases: [(&str, Model); 2] = [("chained_parameters", chained_parameters), ("for_loop", for_loop)];
    for (name, model) in cases {
        let mut group = c.benchmark_group(name);
        group.sample_size(10);
        for n in [10_000, 100_000] {
            let text = model(n);
            group.throughput(Throughput::Elements(n as u64));
            group.bench_with_input(BenchmarkId::from_parameter(n), &text, |b, text| b.iter(|| check(text)));
        }
        group.finish();
    }
}

criterion_group!(benches, sizes);
criterion_main!(benches);
