//! Forward dynamics (ABA) and the full right-hand side on the peers'
//! benchmark chain (shared/bench/peers/chain_common.py), at its test state.
//! `scripts/bench.sh` runs this with the peers and prints the ratios.

use criterion::{black_box, criterion_group, criterion_main, BenchmarkId, Criterion};

#[path = "../tests/common/chain.rs"]
mod chain;

fn dynamics(c: &mut Criterion) {
    let mut aba = c.benchmark_group("aba");
    for n in [1usize, 7, 30, 100, 1000] {
        let mechanism = chain::benchmark_chain(n).assemble().unwrap();
        let y = mechanism.states().start.clone();
        let (q, u) = y.split_at(n);
        let mut ws = mechanism.workspace();
        let mut ud = vec![0.0; n];
        aba.bench_with_input(BenchmarkId::from_parameter(n), &n, |b, _| {
            b.iter(|| mechanism.forward_dynamics(&mut ws, 0.0, black_box(q), black_box(u), &mut ud).unwrap())
        });
    }
    aba.finish();
    let mut rhs = c.benchmark_group("rhs");
    for n in [1usize, 7, 30, 100, 1000] {
        let mechanism = chain::benchmark_chain(n).assemble().unwrap();
        let y = mechanism.states().start.clone();
        let mut ws = mechanism.workspace();
        let mut dy = vec![0.0; 2 * n];
        rhs.bench_with_input(BenchmarkId::from_parameter(n), &n, |b, _| {
            b.iter(|| mechanism.rhs(&mut ws, 0.0, black_box(&y), &mut dy).unwrap())
        });
    }
    rhs.finish();
    // The analytic derivatives of the forward dynamics (ddq_dq, ddq_dv,
    // Minv) at the accelerations of the test state, as Pinocchio's
    // computeABADerivatives (scripts/peers/pin_derivatives.cpp times it).
    let mut derivatives = c.benchmark_group("aba_derivatives");
    for n in [7usize, 30, 100] {
        let mechanism = chain::benchmark_chain(n).assemble().unwrap();
        let system = mechanism.system();
        let y = mechanism.states().start.clone();
        let mut ws = mechanism.workspace();
        let mut dy = vec![0.0; 2 * n];
        mechanism.rhs(&mut ws, 0.0, &y, &mut dy).unwrap();
        let (q, u) = y.split_at(n);
        let ud = dy[n..].to_vec();
        let mut d = system.derivatives_work();
        derivatives.bench_with_input(BenchmarkId::from_parameter(n), &n, |b, _| {
            b.iter(|| system.aba_derivatives(&mut ws, &mut d, black_box(q), black_box(u), black_box(&ud)).unwrap())
        });
    }
    derivatives.finish();
    // The whole linear model (A with names, exact derivatives, no outputs)
    // at the chain's test state: the target is at most 30 rhs/30.
    let mut linearize = c.benchmark_group("linearize");
    for n in [7usize, 30] {
        let mechanism = chain::benchmark_chain(n).assemble().unwrap();
        let sim = multibody::Simulator::new(&mechanism, &multibody::SimulationOptions::default()).unwrap();
        let options = multibody::LinearizeOptions { derivatives: multibody::Derivatives::Exact, ..Default::default() };
        linearize.bench_with_input(BenchmarkId::from_parameter(n), &n, |b, _| {
            b.iter(|| black_box(sim.linearize(&options).unwrap()))
        });
    }
    linearize.finish();
    // A motor inertia behind a gear on every joint: the same tree with an
    // armature on each joint, so the cost should hardly change.
    let mut drive = c.benchmark_group("drive_train");
    for (name, model) in [("plain/30", chain::benchmark_chain(30)), ("geared/30", chain::geared_chain(30))] {
        let mechanism = model.assemble().unwrap();
        let y = mechanism.states().start.clone();
        let mut ws = mechanism.workspace();
        let mut dy = vec![0.0; y.len()];
        drive.bench_function(name, |b| b.iter(|| mechanism.rhs(&mut ws, 0.0, black_box(&y), &mut dy).unwrap()));
    }
    drive.finish();
}

criterion_group!(benches, dynamics);
criterion_main!(benches);
