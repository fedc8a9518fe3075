//! Stiff models: the implicit method (Rodas4) against closed forms and
//! Modelica's references, and the explicit method's warnings when a model
//! is stiff or its step errors add up beyond the tolerance.

mod common;

use common::examples::load_example;
use common::{assert_pairs_within_tube, crate_path, multibody, scratch, Table};
use multibody::{Method, SimulationOptions, Solution};
use std::path::Path;

/// The closed form of `examples/stiff_spring.dyad`: a 1 kg slider on a
/// spring-damper (c, d) to the wall, pushed by `f0 sin(2 pi t)`, from
/// s = s0 at rest. Gives (s, v) at `t`.
struct ForcedSpringDamper {
    w: f64,
    /// Steady response `a sin(wt) + b cos(wt)`.
    a: f64,
    b: f64,
    /// Decaying modes `c1 e^(l1 t) + c2 e^(l2 t)` (overdamped: real rates).
    l1: f64,
    l2: f64,
    c1: f64,
    c2: f64,
}

impl ForcedSpringDamper {
    fn new(m: f64, c: f64, d: f64, f0: f64, s0: f64) -> Self {
        let w = 2.0 * std::f64::consts::PI;
        let (k, dw) = (c - m * w * w, d * w);
        let (a, b) = (f0 * k / (k * k + dw * dw), -f0 * dw / (k * k + dw * dw));
        let root = (d * d - 4.0 * m * c).sqrt();
        let (l1, l2) = ((-d + root) / (2.0 * m), (-d - root) / (2.0 * m));
        // s(0) = s0 and v(0) = 0.
        let c1 = (-a * w - l2 * (s0 - b)) / (l1 - l2);
        Self { w, a, b, l1, l2, c1, c2: s0 - b - c1 }
    }

    fn at(&self, t: f64) -> (f64, f64) {
        let (sin, cos) = (self.w * t).sin_cos();
        let (e1, e2) = ((self.l1 * t).exp(), (self.l2 * t).exp());
        let s = self.a * sin + self.b * cos + self.c1 * e1 + self.c2 * e2;
        let v = self.w * (self.a * cos - self.b * sin) + self.l1 * self.c1 * e1 + self.l2 * self.c2 * e2;
        (s, v)
    }
}

/// The worst error of `s` and `v` against the closed form, in units of the
/// tolerance asked (`abstol + reltol |x|`).
fn worst_in_tolerances(solution: &Solution, exact: &ForcedSpringDamper, options: &SimulationOptions) -> f64 {
    let (s, v) = (solution.get("slider.s").unwrap(), solution.get("slider.v").unwrap());
    let tol = |x: f64| options.abstol + options.reltol * x.abs();
    let mut worst = 0.0f64;
    for (k, &t) in solution.time().iter().enumerate() {
        let (se, ve) = exact.at(t);
        worst = worst.max((s[k] - se).abs() / tol(se)).max((v[k] - ve).abs() / tol(ve));
    }
    worst
}

fn stiff_spring() -> (multibody::Mechanism, SimulationOptions, ForcedSpringDamper) {
    let lowered = load_example(Path::new(&crate_path("../../examples/stiff_spring.dyad")));
    assert_eq!(lowered.options.method, Method::Rodas4, "the example's analysis asks for Rodas4");
    let mechanism = lowered.assemble().unwrap();
    (mechanism, lowered.options.clone(), ForcedSpringDamper::new(1.0, 1e8, 1e5, 1e6, 0.002))
}

#[test]
fn the_implicit_method_follows_a_stiff_spring_damper_within_its_tolerance() {
    let (mechanism, options, exact) = stiff_spring();
    let ends = mechanism.simulate(&SimulationOptions { saveat: 0.0, ..options.clone() }).unwrap();
    let at_ends = worst_in_tolerances(&ends, &exact, &options);
    println!("Rodas4: {} steps, worst error at their ends {at_ends:.3} tolerances", ends.len() - 1);
    assert!(at_ends < 1.0, "the error at the step ends is {at_ends} tolerances");
    let solution = mechanism.simulate(&options).unwrap();
    let worst = worst_in_tolerances(&solution, &exact, &options);
    println!("Rodas4: worst error {worst:.3} tolerances, no warnings: {:?}", solution.warnings());
    assert!(worst < 1.0, "the error is {worst} tolerances");
    assert!(solution.warnings().is_empty(), "{:?}", solution.warnings());
}

#[test]
fn the_explicit_method_warns_that_a_stiff_model_is_stiff_and_names_the_state() {
    let (mechanism, mut options, exact) = stiff_spring();
    options.method = Method::DormandPrince45;
    let solution = mechanism.simulate(&options).unwrap();
    let worst = worst_in_tolerances(&solution, &exact, &options);
    println!("Dormand-Prince: worst error {worst:.3} tolerances; {:?}", solution.warnings());
    assert!(worst < 1.0, "stable steps are accurate too: {worst} tolerances");
    let warning = solution.warnings().iter().find(|w| w.contains("stiff")).expect("a stiffness warning");
    assert!(warning.contains("`slider.v`") && warning.contains("ROS34PW2"), "{warning}");
}

/// The Rosenbrock-W method (its Jacobian kept over many steps) on the same
/// stiff spring-damper: within the tolerance of the closed form, at far
/// fewer evaluations than the explicit method.
#[test]
fn the_w_method_follows_a_stiff_spring_damper_within_its_tolerance() {
    let (mechanism, mut options, exact) = stiff_spring();
    options.method = Method::Ros34Pw2;
    let ends = mechanism.simulate(&SimulationOptions { saveat: 0.0, ..options.clone() }).unwrap();
    println!(
        "ROS34PW2: {} steps, worst error at their ends {:.3} tolerances",
        ends.len() - 1,
        worst_in_tolerances(&ends, &exact, &options)
    );
    let solution = mechanism.simulate(&options).unwrap();
    let worst = worst_in_tolerances(&solution, &exact, &options);
    println!("ROS34PW2: worst error {worst:.3} tolerances; {:?}", solution.warnings());
    assert!(worst < 1.0, "the error is {worst} tolerances");
    assert!(solution.warnings().is_empty(), "{:?}", solution.warnings());
}

/// Without damping nothing is stiff, but a fast oscillation runs through so
/// many steps that their errors add up: a run far off its tolerance must
/// say so. (Each step meets the tolerance; no explicit method bounds the
/// global error. The warning comes when the step errors add up to 1e4
/// tolerances: a short run can be tens of tolerances off without one.)
#[test]
fn an_undamped_fast_spring_far_off_its_tolerance_warns() {
    // The example's slider without damper or force: s = s0 cos(w t), w = 1e4 rad/s.
    let text = std::fs::read_to_string(crate_path("../../examples/stiff_spring.dyad")).unwrap();
    let undamped = text.replace("d = 1e5", "d = 0").replace("amplitude = 1e6", "amplitude = 0");
    assert_ne!(undamped, text);
    let mut package = multibody_dyad::Package::new();
    package.add_source("undamped.dyad", undamped).unwrap();
    let lowered = package.lower_analysis("StiffSpringSimulation").unwrap();
    let mechanism = lowered.assemble().unwrap();
    for stop in [0.01, 1.0] {
        let options = SimulationOptions { stop, method: Method::DormandPrince45, ..lowered.options.clone() };
        let solution = mechanism.simulate(&options).unwrap();
        let (s, v) = (solution.get("slider.s").unwrap(), solution.get("slider.v").unwrap());
        let tol = |x: f64| options.abstol + options.reltol * x.abs();
        let mut worst = 0.0f64;
        for (k, &t) in solution.time().iter().enumerate() {
            let (se, ve) = (0.002 * (1e4 * t).cos(), -20.0 * (1e4 * t).sin());
            worst = worst.max((s[k] - se).abs() / tol(se)).max((v[k] - ve).abs() / tol(ve));
        }
        let warned = solution.warnings().iter().any(|w| w.contains("add up to"));
        println!("undamped, {stop} s: worst error {worst:.1} tolerances, warned: {warned}");
        if worst > 1000.0 {
            assert!(warned, "{stop} s: {worst} tolerances off, and no warning");
        }
    }
}

/// The implicit method on ordinary (non-stiff) mechanisms: Modelica's
/// references pass with it as with the default.
#[test]
fn the_implicit_method_passes_modelica_references() {
    for (model, signals) in [
        ("DoublePendulum", &["revolute1.phi", "revolute1.w", "revolute2.phi", "revolute2.w"][..]),
        ("Fourbar1", &["j1.phi", "j1.w"][..]),
    ] {
        let dir = scratch(&format!("rodas-{model}"));
        let path = crate_path(&format!("../../examples/msl/{model}.dyad"));
        let o = multibody(&dir, &["run", &path, "--alg", "Rodas4", "--out", "rodas.csv"]);
        assert!(o.status.success(), "{model}: {}", String::from_utf8_lossy(&o.stderr));
        assert!(String::from_utf8_lossy(&o.stderr).contains("implicit Rodas4"));
        let pairs: Vec<(&str, &str)> = signals.iter().map(|s| (*s, *s)).collect();
        assert_pairs_within_tube(&Table::reference(model), &Table::load(&dir.join("rodas.csv")), &pairs);
    }
}
