//! What the live page does on each change, natively: lower and assemble the
//! model with the new value, simulate, and make the scene the view draws.
//! The page's own time (WebAssembly in Chromium) is measured by the live
//! page test; this is the same work without the browser.

use criterion::{criterion_group, criterion_main, Criterion};
use multibody_web::{Session, Values};
use std::path::PathBuf;

fn rerun(c: &mut Criterion) {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../examples/double_pendulum.dyad");
    let files = [("examples/double_pendulum.dyad".to_string(), std::fs::read_to_string(path).unwrap())];
    let session = Session::load(&files, None, None, Vec::new()).unwrap();
    let values = Values { params: vec!["link2.length=0.7".into()], initials: Vec::new(), stop: Some("5".into()) };
    c.bench_function("live/double_pendulum_5s", |b| b.iter(|| session.run(&values).unwrap()));
}

criterion_group!(benches, rerun);
criterion_main!(benches);
