//! Runs the ABA on the peers' 100-link chain in a loop, for profilers
//! (`perf record`, `valgrind --tool=callgrind`): `cargo run --release
//! --example profile_chain -- [N] [ITERATIONS]`.

#[path = "../tests/common/chain.rs"]
mod chain;

fn main() {
    let mut args = std::env::args().skip(1);
    let n: usize = args.next().and_then(|a| a.parse().ok()).unwrap_or(100);
    let iterations: usize = args.next().and_then(|a| a.parse().ok()).unwrap_or(100_000);
    let mechanism = chain::benchmark_chain(n).assemble().expect("the chain assembles");
    let y = mechanism.states().start.clone();
    let (q, u) = y.split_at(n);
    let mut ws = mechanism.workspace();
    let mut ud = vec![0.0; n];
    let mut sum = 0.0;
    for _ in 0..iterations {
        mechanism.forward_dynamics(&mut ws, 0.0, std::hint::black_box(q), u, &mut ud).expect("the chain moves");
        sum += ud[n - 1];
    }
    println!("{n} links, {iterations} evaluations, checksum {sum}");
}
