//! Work-precision of the adaptive integrator on the Pendulum and
//! DoublePendulum references: for reltol = abstol = 1e-3 ... 1e-11, the
//! error of the final state against a converged solution, and the wall time
//! of `Mechanism::simulate`. `scripts/work_precision.py` sets these against
//! MuJoCo's RK4; `scripts/bench.sh` runs both.
//!
//! `cargo run --release -p multibody-cli --example work_precision [-- --quick]`
//! prints JSON on stdout (progress on stderr):
//! `{"models": [{"name", "stop", "signals", "truth", "truth_check",
//! "adaptive": [{tol, error, seconds, steps, repetitions}], "rk4": [...]}]}`.
//!
//! What is timed: `simulate` with `saveat = stop`, so that only the states
//! are integrated and the outputs are computed at the start and the end
//! alone (no dense-output sampling on a grid). Times are medians of many
//! repetitions measured with `std::time::Instant`; one repetition includes
//! the setup of `simulate` (workspaces, the output table), as a user pays it.
//!
//! `steps` is the number of accepted steps (counted through the progress
//! callback of `simulate_from`, in a separate untimed run): `simulate` does
//! not return the integrator's evaluation count; Dormand-Prince 5(4) with
//! FSAL spends 6 right-hand-side evaluations per attempted step.
//!
//! The truth is the same integrator at reltol = abstol = 1e-14, checked
//! against 1e-13 and 1e-12 and against the fixed-step RK4 at dt = 1e-5
//! (`truth_check`): it agrees with the RK4 to a few 1e-12 and differs from
//! 1e-13 by about 1e-11 (the error of that run), far below the smallest
//! errors measured here (about 1e-10).
//!
//! `rk4` holds the engine's own fixed-step RK4 at a few steps, for the same
//! steps as MuJoCo's: the same method on the same ODE, so its final state
//! must agree with MuJoCo's to rounding (a check that the models are the
//! same) and its time per step compares the cost of one RK4 step.

use multibody::{Mechanism, Method, SimulationOptions};
use serde_json::{json, Value};
use std::time::Instant;

#[path = "../tests/common/examples.rs"]
mod examples;

/// The reference model of `examples/msl/NAME.dyad`, assembled.
fn reference_model(name: &str) -> Mechanism {
    let path = examples::examples_dir().join(format!("msl/{name}.dyad"));
    examples::load_example(&path).assemble().expect("the reference model assembles")
}

struct Case {
    name: &'static str,
    mechanism: Mechanism,
    stop: f64,
    /// Joint angles, then joint rates.
    signals: Vec<&'static str>,
}

fn options(stop: f64, tol: f64, method: Method) -> SimulationOptions {
    SimulationOptions { stop, saveat: stop, abstol: tol, reltol: tol, method, ..SimulationOptions::default() }
}

fn final_state(case: &Case, options: &SimulationOptions) -> Vec<f64> {
    let solution = case.mechanism.simulate(options).expect("the reference simulates");
    let t = *solution.time().last().unwrap();
    assert!((t - case.stop).abs() < 1e-12, "{}: the last output is at {t}, not {}", case.name, case.stop);
    case.signals.iter().map(|s| solution.last(s).unwrap_or_else(|| panic!("no signal {s}"))).collect()
}

fn max_diff(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max)
}

/// Median wall time of `simulate(options)` in seconds, over repetitions
/// that take about `budget` seconds in all (at least `min_reps`).
fn time_simulate(case: &Case, options: &SimulationOptions, budget: f64, min_reps: usize) -> (f64, usize) {
    // Warm-up, and a first estimate of one run.
    let start = Instant::now();
    std::hint::black_box(case.mechanism.simulate(std::hint::black_box(options)).unwrap());
    let once = start.elapsed().as_secs_f64();
    let reps = ((budget / once.max(1e-9)) as usize).clamp(min_reps, 20_000);
    let mut times = Vec::with_capacity(reps);
    for _ in 0..reps {
        let start = Instant::now();
        std::hint::black_box(case.mechanism.simulate(std::hint::black_box(options)).unwrap());
        times.push(start.elapsed().as_secs_f64());
    }
    times.sort_by(|a, b| a.partial_cmp(b).unwrap());
    let mid = times.len() / 2;
    let median = if times.len() % 2 == 1 { times[mid] } else { 0.5 * (times[mid - 1] + times[mid]) };
    (median, reps)
}

fn accepted_steps(case: &Case, options: &SimulationOptions) -> usize {
    let mut steps = 0usize;
    let mut count = |_t: f64| {
        steps += 1;
        Ok(())
    };
    case.mechanism.simulate_from(&case.mechanism.states().start, options, Some(&mut count)).unwrap();
    steps
}

fn main() {
    let quick = std::env::args().any(|a| a == "--quick");
    let budget = if quick { 0.05 } else { 0.4 };
    let min_reps = if quick { 3 } else { 11 };
    let cases = [
        Case { name: "Pendulum", mechanism: reference_model("Pendulum"), stop: 5.0, signals: vec!["rev.phi", "rev.w"] },
        Case {
            name: "DoublePendulum",
            mechanism: reference_model("DoublePendulum"),
            stop: 3.0,
            signals: vec!["revolute1.phi", "revolute2.phi", "revolute1.w", "revolute2.w"],
        },
    ];
    let dp = Method::DormandPrince45;
    let mut models = Vec::new();
    for case in &cases {
        eprintln!("work_precision: {} (t = {} s)", case.name, case.stop);
        // The converged solution (tol 1e-14), and how well it is converged:
        // against the next looser tolerances, and against the fixed-step RK4
        // at dt = 1e-5 (a different method, whose own error there is about
        // 1e-13: it changes by ~1e-12 from dt = 2e-5).
        let truth_tol = 1e-14;
        let truth = final_state(case, &options(case.stop, truth_tol, dp));
        let tol13 = final_state(case, &options(case.stop, 1e-13, dp));
        let tol12 = final_state(case, &options(case.stop, 1e-12, dp));
        let rk4_dt = 1e-5;
        let rk4 = final_state(case, &options(case.stop, 1e-6, Method::Rk4 { dt: rk4_dt }));
        let truth_check = json!({
            "tol": truth_tol,
            "vs_tol_1e-13": max_diff(&truth, &tol13),
            "vs_tol_1e-12": max_diff(&truth, &tol12),
            "vs_rk4_dt": rk4_dt,
            "vs_rk4": max_diff(&truth, &rk4),
        });
        eprintln!(
            "  truth {truth:?}: |tol 1e-14 - tol 1e-13| = {:.2e}, |tol 1e-14 - RK4 dt 1e-5| = {:.2e}",
            max_diff(&truth, &tol13),
            max_diff(&truth, &rk4)
        );
        let mut adaptive = Vec::new();
        for k in 3..=11 {
            let tol = 10f64.powi(-k);
            let opts = options(case.stop, tol, dp);
            let error = max_diff(&final_state(case, &opts), &truth);
            let (seconds, reps) = time_simulate(case, &opts, budget, min_reps);
            let steps = accepted_steps(case, &opts);
            eprintln!("  tol {tol:.0e}: error {error:.2e}, {:.1} us, {steps} steps", seconds * 1e6);
            adaptive.push(json!({"tol": tol, "error": error, "seconds": seconds, "steps": steps, "repetitions": reps}));
        }
        let mut fixed = Vec::new();
        for dt in [1e-2, 1e-3, 1e-4] {
            let opts = options(case.stop, 1e-6, Method::Rk4 { dt });
            let state = final_state(case, &opts);
            let error = max_diff(&state, &truth);
            let (seconds, reps) = time_simulate(case, &opts, budget, min_reps.min(5));
            let steps = (case.stop / dt).round() as usize;
            eprintln!("  rk4 dt {dt:.0e}: error {error:.2e}, {:.1} us", seconds * 1e6);
            fixed.push(json!({"dt": dt, "state": state, "error": error, "seconds": seconds, "steps": steps, "repetitions": reps}));
        }
        models.push(json!({
            "name": case.name,
            "stop": case.stop,
            "signals": case.signals,
            "truth": truth,
            "truth_check": truth_check,
            "adaptive": adaptive,
            "rk4": fixed,
        }));
    }
    let out: Value = json!({
        "method": "DormandPrince45 (adaptive), reltol = abstol = tol; simulate() with saveat = stop",
        "models": models,
    });
    println!("{}", serde_json::to_string_pretty(&out).unwrap());
}
