//! URDF robots: importing Talos (60 links, 32 moving joints, from
//! example-robot-data) into a model ready to simulate, and its forward
//! dynamics at random states, which `scripts/bench.sh` compares with
//! Pinocchio's ABA in C++ on the same file (scripts/peers/pin_urdf_aba.cpp).
//! Needs the robots of `scripts/fetch-robots.sh` (`$MULTIBODY_ROBOTS`, by
//! default target/robots); without them it says so and measures nothing.

use criterion::{criterion_group, criterion_main, Criterion};
use multibody::Mechanism;
use multibody_dyad::urdf::{self, ImportOptions};
use multibody_dyad::Package;
use std::hint::black_box;
use std::path::PathBuf;

const TALOS: &str = "talos_data/robots/talos_reduced.urdf";

fn talos() -> Option<(String, String)> {
    let folder = std::env::var_os("MULTIBODY_ROBOTS")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../target/robots"));
    let path = folder.join("example-robot-data").join(TALOS);
    match std::fs::read_to_string(&path) {
        Ok(text) => Some((path.display().to_string(), text)),
        Err(e) => {
            eprintln!("urdf benchmarks skipped: {} ({e}); scripts/fetch-robots.sh fetches it", path.display());
            None
        }
    }
}

/// From the file's text to a mechanism ready to simulate: read and check
/// the URDF, write the Dyad model, lower and assemble it.
fn import(file: &str, text: &str) -> Mechanism {
    let robot = urdf::parse(text).unwrap();
    let dyad = urdf::to_dyad(&robot, file, &ImportOptions { mimic: false, ..Default::default() });
    let mut package = Package::new();
    package.add_source(format!("{file}.dyad"), dyad).unwrap();
    let target = package.choose_target(None, None).unwrap();
    package.lower_target(&target, &[]).unwrap().assemble().unwrap()
}

fn talos_benches(c: &mut Criterion) {
    let Some((file, text)) = talos() else { return };
    c.bench_function("urdf/import_talos", |b| b.iter(|| import(black_box(&file), black_box(&text))));
    let mechanism = import(&file, &text);
    let (nq, nv) = (mechanism.states().nq, mechanism.states().nv);
    assert_eq!((nq, nv), (32, 32), "Talos's moving joints");
    // Random states in [-1, 1], as the C++ benchmark draws them.
    let mut seed = 2026_u64;
    let mut random = move || {
        seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (seed >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    };
    let states: Vec<(Vec<f64>, Vec<f64>)> =
        (0..64).map(|_| ((0..nq).map(|_| random()).collect(), (0..nv).map(|_| random()).collect())).collect();
    let mut ws = mechanism.workspace();
    let mut ddq = vec![0.0; nv];
    let mut k = 0;
    c.bench_function("urdf/forward_dynamics_talos", |b| {
        b.iter(|| {
            let (q, v) = &states[k % states.len()];
            k += 1;
            mechanism.forward_dynamics(&mut ws, 0.0, q, v, &mut ddq).unwrap();
            black_box(ddq[0])
        })
    });
}

criterion_group!(benches, talos_benches);
criterion_main!(benches);
