//! `multibody linearize`, and Dyad's LinearAnalysis and SteadyStateAnalysis
//! run by `multibody run`: the damped pendulum of
//! examples/linear_analysis.dyad against its closed form.

mod common;

use common::{code, example, multibody, scratch, stderr, stdout};

// The pendulum: J phi'' = -m g r cos(phi) - d phi' + tau, hanging at -pi/2.
const M: f64 = 1.0;
const R: f64 = 0.5;
const D: f64 = 0.3;
const G: f64 = 9.80665;
const J: f64 = M * R * R + 0.02;

fn json(path: &std::path::Path) -> serde_json::Value {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    serde_json::from_str(&text).unwrap()
}

fn matrix(v: &serde_json::Value) -> Vec<Vec<f64>> {
    v.as_array().unwrap().iter().map(|r| r.as_array().unwrap().iter().map(|x| x.as_f64().unwrap()).collect()).collect()
}

#[test]
fn a_linear_analysis_gives_the_pendulum_s_poles_and_writes_its_model() {
    let dir = scratch("linear-analysis");
    let o = multibody(
        &dir,
        &["run", &example("linear_analysis.dyad"), "--analysis", "DampedPendulumLinear", "--plot", "bode.png"],
    );
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    let out = stdout(&o);
    assert!(out.contains("coordinates (2): rev.phi, rev.w"), "{out}");
    assert!(out.contains("inputs: tau") && out.contains("outputs: angle"), "{out}");
    assert!(out.contains("DampingRatio") || out.contains("damping"), "{out}");
    let lin = json(&dir.join("DampedPendulumLinear.json"));
    let a = matrix(&lin["A"]);
    let expected = [[0.0, 1.0], [-M * G * R / J, -D / J]];
    let worst = (0..2)
        .flat_map(|i| (0..2).map(move |j| (i, j)))
        .map(|(i, j)| (a[i][j] - expected[i][j]).abs())
        .fold(0.0, f64::max);
    println!("linear analysis: worst |A - closed form| = {worst:.2e} (tolerance 1e-9)");
    assert!(worst < 1e-9, "{a:?}");
    let b = matrix(&lin["B"]);
    assert!((b[1][0] - 1.0 / J).abs() < 1e-9 / J);
    let wn = (M * G * R / J).sqrt();
    let zeta = D / (2.0 * J * wn);
    for pole in lin["poles"].as_array().unwrap() {
        let (z, w) = (pole["damping_ratio"].as_f64().unwrap(), pole["frequency_rad_s"].as_f64().unwrap());
        println!("pole: damping ratio {z} vs {zeta}, frequency {w} vs {wn}");
        assert!((z - zeta).abs() < 1e-9 && (w - wn).abs() < 1e-9 * wn);
    }
    let png = std::fs::read(dir.join("bode.png")).unwrap();
    assert_eq!(&png[1..4], b"PNG");
}

#[test]
fn a_steady_state_analysis_finds_where_the_pendulum_rests() {
    let dir = scratch("steady-analysis");
    let o = multibody(&dir, &["run", &example("linear_analysis.dyad"), "--analysis", "DampedPendulumRest"]);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    assert!(stderr(&o).contains("at a steady state"), "{}", stderr(&o));
    let lin = json(&dir.join("DampedPendulumRest.json"));
    let angle = lin["operating_point"]["outputs"]["angle"].as_f64();
    // Without outputs in a steady-state analysis, the state says where it rests.
    let state: Vec<f64> =
        lin["operating_point"]["state"].as_array().unwrap().iter().map(|x| x.as_f64().unwrap()).collect();
    let rest = -std::f64::consts::FRAC_PI_2;
    println!("steady state: phi = {} (angle output {angle:?}) vs {rest}", state[0]);
    assert!((state[0] - rest).abs() < 1e-9 && state[1].abs() < 1e-9, "{state:?}");
}

#[test]
fn linearize_along_a_simulation_and_at_a_steady_state() {
    let dir = scratch("linearize-at");
    let file = example("linear_analysis.dyad");
    let o = multibody(
        &dir,
        &["linearize", &file, "--analysis", "DampedPendulumSimulation", "--at", "t=0.5", "--out", "half.json"],
    );
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    assert!(stdout(&o).contains("not an equilibrium"), "{}", stdout(&o));
    let lin = json(&dir.join("half.json"));
    assert_eq!(lin["time"].as_f64(), Some(0.5));
    // The linear model there has A[1][0] = m g r sin(phi) / J at the angle reached.
    let phi = lin["operating_point"]["state"][0].as_f64().unwrap();
    let a10 = matrix(&lin["A"])[1][0];
    assert!((a10 - M * G * R * phi.sin() / J).abs() < 1e-8, "{a10} at phi = {phi}");
    let o = multibody(
        &dir,
        &["linearize", &file, "--analysis", "DampedPendulumSimulation", "--at", "steady", "--out", "rest.json"],
    );
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    let lin = json(&dir.join("rest.json"));
    assert!((lin["operating_point"]["state"][0].as_f64().unwrap() + std::f64::consts::FRAC_PI_2).abs() < 1e-9);
}

#[test]
fn bad_requests_say_what_to_do() {
    let dir = scratch("linearize-bad");
    let file = example("linear_analysis.dyad");
    let o = multibody(&dir, &["linearize", &file, "--analysis", "DampedPendulumLinear", "--inputs", "tao"]);
    assert_eq!(code(&o), 2, "{}", stderr(&o));
    assert!(stderr(&o).contains("did you mean `tau`"), "{}", stderr(&o));
    let o = multibody(&dir, &["linearize", &file, "--analysis", "DampedPendulumLinear", "--at", "later"]);
    assert_eq!(code(&o), 2);
    assert!(stderr(&o).contains("t=2.5"), "{}", stderr(&o));
    let o = multibody(&dir, &["linearize", &file, "--analysis", "DampedPendulumLinear", "--out", &file]);
    assert_eq!(code(&o), 2, "{}", stderr(&o));
    // No file was written over the model.
    assert!(std::fs::read_to_string(&file).unwrap().contains("LinearAnalysis"));
    // Analyses with parameters Dyad's do not have, or loop openings.
    let text = std::fs::read_to_string(&file).unwrap();
    for (change, message) in [
        ("duration = 5)", "LinearAnalysis has no parameter `durration`"),
        ("outputs = [\"angle\"]", "loop openings are not supported yet"),
    ] {
        let bad = match change {
            "duration = 5)" => text.replace(change, "durration = 5)"),
            _ => text.replace(change, "outputs = [\"angle\"], loop_openings = [\"tau\"]"),
        };
        let path = dir.join("bad.dyad");
        std::fs::write(&path, bad).unwrap();
        let o = multibody(&dir, &["run", path.to_str().unwrap(), "--analysis", "DampedPendulumLinear"]);
        assert_eq!(code(&o), 1, "{}", stderr(&o));
        assert!(stderr(&o).contains(message) && stderr(&o).contains("bad.dyad:"), "{}", stderr(&o));
    }
}
