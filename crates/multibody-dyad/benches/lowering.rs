//! How lowering grows with the size of a model: from file text to a
//! compiled mechanism and one evaluation of its right-hand side, for long
//! chains of parameters, long `for` loops and one long algebraic loop
//! (issue 26: they grew quadratically or worse, and hung at 250,000
//! parameters, 50,000 elements and 5,000 equations in one loop). Linear
//! cost means the time per element stays put as the size grows by ten.

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

/// One algebraic loop of `n` equations: `x[1] = x[n]/2 + t`, `x[i] = x[i-1]/2 + 1`.
fn algebraic_loop(n: usize) -> String {
    format!(
        "example component Chain\n  variable x::Real[{n}]\nrelations\n  x[1] = 0.5 * x[{n}] + time\n  for i in 2:{n}\n    x[i] = 0.5 * x[i - 1] + 1\n  end\nend\n"
    )
}

/// An RC ladder of `n` sections from the electrical library written in
/// Dyad (a resistor and a capacitor to ground each), fed by a voltage
/// source: about 20 equations per section with the connection equations.
fn rc_ladder(n: usize) -> String {
    ladder(n, "")
}

/// The same ladder with every capacitor started at rest: `n` initial
/// equations over `n` start values, one sparse Newton system.
fn ladder_at_rest(n: usize) -> String {
    ladder(n, "    initial der(c[i].v) = 0\n")
}

fn ladder(n: usize, per_stage: &str) -> String {
    let mut text = format!(
        "example component Chain\n  source = ElectricalComponents.VoltageSource()\n  level = BlockComponents.Constant(k = 1)\n  ground = ElectricalComponents.Ground()\n  r = [ElectricalComponents.Resistor(R = 1) for i in 1:{n}]\n  c = [ElectricalComponents.Capacitor(C = 1e-3) for i in 1:{n}]\nrelations\n  connect(level.y, source.V)\n  connect(source.n, ground.g)\n  connect(source.p, r[1].p)\n"
    );
    text.push_str(&format!(
        "  for i in 1:{n}\n    connect(r[i].n, c[i].p)\n    connect(c[i].n, ground.g)\n{per_stage}  end\n"
    ));
    text.push_str(&format!("  for i in 1:{}\n    connect(r[i].n, r[i + 1].p)\n  end\nend\n", n - 1));
    text
}

fn check(text: &str) -> usize {
    let mut package = Package::new();
    package.add_source("model.dyad", text).unwrap();
    let mechanism = package.lower_component("Chain").unwrap().assemble().unwrap();
    let y = mechanism.states().start.clone();
    let mut dy = vec![0.0; y.len()];
    mechanism.rhs(&mut mechanism.workspace(), 0.0, &y, &mut dy).unwrap();
    mechanism.signals().len()
}

fn sizes(c: &mut Criterion) {
    type Model = fn(usize) -> String;
    const LARGE: [usize; 2] = [10_000, 100_000];
    // Issue 42's goal: a model of 2,000 user equations compiles in under
    // 50 ms (rc_ladder/150); started at rest, the ladder also runs the
    // initialization's Newton system.
    const LADDER: [usize; 2] = [150, 1500];
    let cases: [(&str, Model, [usize; 2]); 5] = [
        ("chained_parameters", chained_parameters, LARGE),
        ("for_loop", for_loop, LARGE),
        ("algebraic_loop", algebraic_loop, LARGE),
        ("rc_ladder", rc_ladder, LADDER),
        ("ladder_started_at_rest", ladder_at_rest, LADDER),
    ];
    for (name, model, sizes) in cases {
        let mut group = c.benchmark_group(name);
        group.sample_size(10);
        for n in sizes {
            let text = model(n);
            group.throughput(Throughput::Elements(n as u64));
            group.bench_with_input(BenchmarkId::from_parameter(n), &text, |b, text| b.iter(|| check(text)));
        }
        group.finish();
    }
}

criterion_group!(benches, sizes);
criterion_main!(benches);
