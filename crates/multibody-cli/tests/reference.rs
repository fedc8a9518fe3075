//! The Modelica reference examples (shared/reference/msl), written as .dyad
//! files in tests/models and run through the `multibody run` command; its
//! CSV must stay within the reference's tube.

mod common;

use common::{assert_within_tube, crate_path, multibody, scratch, Table};

/// Runs `tests/models/NAME.dyad` and compares the CSV with the reference.
fn check(name: &str, signals: &[&str]) {
    let reference = Table::reference(name);
    let dir = scratch(&format!("reference-{name}"));
    let out = dir.join(format!("{name}.csv"));
    let model = crate_path(&format!("tests/models/{name}.dyad"));
    let output = multibody(&dir, &["run", &model, "--out", out.to_str().unwrap()]);
    assert!(output.status.success(), "multibody run failed:\n{}", String::from_utf8_lossy(&output.stderr));
    let ours = Table::load(&out);
    assert_within_tube(&reference, &ours, signals);
}

#[test]
fn pendulum() {
    check("Pendulum", &["rev.phi", "rev.w"]);
}

#[test]
fn double_pendulum() {
    check("DoublePendulum", &["revolute1.phi", "revolute1.w", "revolute2.phi", "revolute2.w"]);
}

#[test]
fn point_gravity() {
    let mut signals = Vec::new();
    for body in ["body1", "body2"] {
        for i in 1..=3 {
            signals.push(format!("{body}.frame_a.r_0[{i}]"));
            signals.push(format!("{body}.v_0[{i}]"));
            signals.push(format!("{body}.w_a[{i}]"));
        }
    }
    let signals: Vec<&str> = signals.iter().map(String::as_str).collect();
    check("PointGravity", &signals);
}
