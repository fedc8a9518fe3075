//! The analytic derivatives of forward dynamics (`System::aba_derivatives`):
//! 1. against Pinocchio's `computeABADerivatives` on the peers' benchmark
//!    chain (golden values written by scripts/aba_derivatives_golden.py);
//! 2. against central differences (with Richardson extrapolation) of our own
//!    right-hand side on other trees: a cart-pole, a branched tree of
//!    prismatic and revolute joints with an armature, the geared chain,
//!    joints with several coordinates, and `generalized_forces` on models
//!    with springs, dampers, a world force and point gravity (a consistency
//!    check; the outside proof is Pinocchio);
//! 3. `derivatives_unsupported` names what it cannot handle.

#[path = "common/chain.rs"]
mod chain;
#[path = "common/four_bar.rs"]
mod four_bar;

use multibody::dynamics::DynamicsDerivatives;
use multibody::Mechanism;

/// Reads a list of numbers or a list of rows (flattened row-major).
fn numbers(v: &serde_json::Value) -> Vec<f64> {
    let mut out = Vec::new();
    for x in v.as_array().expect("a list") {
        match x.as_array() {
            Some(row) => out.extend(row.iter().map(|y| y.as_f64().unwrap())),
            None => out.push(x.as_f64().unwrap()),
        }
    }
    out
}

fn largest(a: &[f64]) -> f64 {
    a.iter().fold(0.0f64, |m, x| m.max(x.abs()))
}

fn worst_difference(a: &[f64], b: &[f64]) -> f64 {
    assert_eq!(a.len(), b.len());
    a.iter().zip(b).fold(0.0f64, |m, (x, y)| m.max((x - y).abs()))
}

/// The accelerations of `rhs` at `y`.
fn accelerations(mechanism: &Mechanism, y: &[f64]) -> Vec<f64> {
    let mut ws = mechanism.workspace();
    let mut dy = vec![0.0; y.len()];
    mechanism.rhs(&mut ws, 0.0, y, &mut dy).unwrap();
    dy[mechanism.states().nq..mechanism.states().nq + mechanism.states().nv].to_vec()
}

/// The derivatives at `y`, at the accelerations of `rhs` there (plus
/// `M^-1 tau` for extra joint forces `tau`).
fn derivatives_at(mechanism: &Mechanism, y: &[f64], tau: Option<&[f64]>) -> (DynamicsDerivatives, Vec<f64>) {
    let system = mechanism.system();
    assert_eq!(system.derivatives_unsupported(), None);
    let (nq, nv) = (mechanism.states().nq, mechanism.states().nv);
    let (q, u) = (&y[..nq], &y[nq..nq + nv]);
    let mut ud = accelerations(mechanism, y);
    let mut ws = mechanism.workspace();
    let mut d = system.derivatives_work();
    system.aba_derivatives(&mut ws, &mut d, q, u, &ud).unwrap();
    if let Some(tau) = tau {
        for i in 0..nv {
            ud[i] += (0..nv).map(|j| d.minv()[i * nv + j] * tau[j]).sum::<f64>();
        }
        system.aba_derivatives(&mut ws, &mut d, q, u, &ud).unwrap();
    }
    (d, ud)
}

#[test]
fn chain_derivatives_match_pinocchio() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/golden/aba_derivatives.json");
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("cannot read {}: {e}", path.display()));
    let json: serde_json::Value = serde_json::from_str(&text).unwrap();
    let tolerance = 1e-9;
    let cases = json["cases"].as_array().unwrap();
    assert!(cases.len() >= 3);
    for case in cases {
        let n = case["n"].as_u64().unwrap() as usize;
        let label = case["state"].as_str().unwrap();
        let (q, v, tau) = (numbers(&case["q"]), numbers(&case["v"]), numbers(&case["tau"]));
        let mechanism = chain::benchmark_chain(n).assemble().unwrap();
        let states = mechanism.states();
        assert_eq!((states.nq, states.nv), (n, n));
        for k in 0..n {
            assert_eq!(states.names[k], format!("j{k}.phi"));
            assert_eq!(states.names[n + k], format!("j{k}.w"));
        }
        let y: Vec<f64> = q.iter().chain(&v).copied().collect();
        let (d, ud) = derivatives_at(&mechanism, &y, Some(&tau));
        let ddq = numbers(&case["ddq"]);
        let acc = worst_difference(&ud, &ddq) / largest(&ddq);
        let mut line = format!("N = {n:3} ({label:6}): |ddq| {:.1e}", acc / tolerance);
        let mut worst = acc;
        for (name, ours) in [("ddq_dq", d.ddq_dq()), ("ddq_dv", d.ddq_dv()), ("Minv", d.minv())] {
            let theirs = numbers(&case[name]);
            let err = worst_difference(ours, &theirs) / largest(&theirs);
            line += &format!(", {name} {:.1e}", err / tolerance);
            worst = worst.max(err);
        }
        println!("{line}  (worst error / tolerance, tolerance 1e-9 of each matrix's largest entry)");
        assert!(worst < tolerance, "N = {n} ({label}): relative error {worst:e}");
    }
}
