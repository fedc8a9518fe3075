//! Events of the model's own equations: relations watched by indicators,
//! `when` clauses with `reinit` and discrete variables, `noEvent`, each
//! checked against closed forms. Each test prints its worst error as a
//! fraction of its tolerance.

use multibody::{Mechanism, SimulationOptions, Simulator};
use multibody_dyad::{DefinitionKind, Package};
use std::path::Path;

/// The mechanism and options of the only analysis in `text`.
fn load(name: &str, text: &str) -> (Mechanism, SimulationOptions) {
    let mut package = Package::new();
    if let Err(d) = package.add_source(name, text.to_string()) {
        panic!("{}", d.render(package.sources(), false));
    }
    let analysis =
        package.definitions().into_iter().find(|d| d.kind == DefinitionKind::Analysis).expect("an analysis").name;
    let lowered =
        package.lower_analysis(&analysis).unwrap_or_else(|d| panic!("{}", d.render(package.sources(), false)));
    let mechanism = lowered.assemble().unwrap_or_else(|d| panic!("{}", d.render(package.sources(), false)));
    (mechanism, lowered.options)
}

fn example(relative: &str) -> (Mechanism, SimulationOptions) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples").join(relative);
    load(relative, &std::fs::read_to_string(path).unwrap())
}

#[test]
fn a_bouncing_ball_hits_the_ground_at_the_closed_form_times() {
    let (mechanism, options) = example("equations/bouncing_ball.dyad");
    let (g, e, h0) = (9.81f64, 0.8f64, 1.0f64);
    let mut sim = Simulator::new(&mechanism, &options).unwrap();
    sim.step_until(options.stop).unwrap();
    let solution = sim.solution();
    // The impacts, from the discrete variables the model keeps.
    let (count, last) = (solution.get("impacts").unwrap(), solution.get("last_impact").unwrap());
    let mut times: Vec<f64> = Vec::new();
    for (n, t) in count.iter().zip(last) {
        if *n as usize > times.len() {
            assert_eq!(*n as usize, times.len() + 1, "one impact at a time");
            times.push(*t);
        }
    }
    assert_eq!(times.len(), 10, "ten bounces before the stop");
    // Closed form: the first fall, then flights of 2 e^k v1 / g.
    let v1 = (2.0 * g * h0).sqrt();
    let mut expected = v1 / g;
    let tolerance = 1e-9;
    let mut worst = 0.0f64;
    for (k, &t) in times.iter().enumerate() {
        if k > 0 {
            expected += 2.0 * e.powi(k as i32) * v1 / g;
        }
        worst = worst.max((t - expected).abs());
    }
    // Each impact is two events: the ball goes below the ground, and
    // (just after, rising) back above it.
    println!(
        "bouncing ball: worst impact time error {worst:.2e} s = {:.2e} of {tolerance:.0e}; {} events",
        worst / tolerance,
        sim.event_count()
    );
    assert!(worst <= tolerance, "impact times off by {worst:e}");
    // Between impacts the motion is the free fall from the last one.
    let (h, time) = (solution.get("h").unwrap(), solution.time());
    let mut worst_h = 0.0f64;
    for (i, &t) in time.iter().enumerate() {
        let k = times.iter().take_while(|&&ti| ti <= t).count();
        let expected = if k == 0 {
            h0 - 0.5 * g * t * t
        } else {
            let (tk, vk) = (times[k - 1], e.powi(k as i32) * v1);
            vk * (t - tk) - 0.5 * g * (t - tk) * (t - tk)
        };
        worst_h = worst_h.max((h[i] - expected).abs());
    }
    println!("bouncing ball: worst height error {worst_h:.2e} m = {:.2e} of 1e-9", worst_h / 1e-9);
    assert!(worst_h <= 1e-9);
}
