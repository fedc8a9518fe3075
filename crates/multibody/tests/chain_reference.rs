//! Forward dynamics of the peers' benchmark chain against Pinocchio's ABA
//! (which agrees with MuJoCo to 1e-13): ../shared/reference/chain_reference_ddq.json.

#[path = "common/chain.rs"]
mod chain;
mod common;

#[test]
fn accelerations_match_pinocchio_and_mujoco() {
    let path = common::reference_dir().join("chain_reference_ddq.json");
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("cannot read {}: {e}", path.display()));
    let json: serde_json::Value = serde_json::from_str(&text).unwrap();
    for n in [1usize, 7, 30, 100] {
        let case = &json["chains"][n.to_string()];
        let vec_of =
            |key: &str| -> Vec<f64> { case[key].as_array().unwrap().iter().map(|x| x.as_f64().unwrap()).collect() };
        let (q, v, ddq) = (vec_of("q"), vec_of("v"), vec_of("ddq"));
        let mechanism = chain::benchmark_chain(n).assemble().unwrap();
        let states = mechanism.states();
        // The model's start values are the reference state (to rounding);
        // evaluate at the reference's own numbers.
        assert_eq!(states.nq, n);
        let y: Vec<f64> = q.iter().chain(&v).copied().collect();
        for (ours, theirs) in states.start.iter().zip(&y) {
            assert!((ours - theirs).abs() <= 1e-14 * theirs.abs());
        }
        let mut ws = mechanism.workspace();
        let mut dy = vec![0.0; 2 * n];
        mechanism.rhs(&mut ws, 0.0, &y, &mut dy).unwrap();
        let scale = ddq.iter().fold(1.0f64, |a, x| a.max(x.abs()));
        let worst = (0..n).map(|k| (dy[n + k] - ddq[k]).abs() / scale).fold(0.0, f64::max);
        println!("N = {n:3}: worst |ddq - pinocchio| / max|ddq| = {worst:.2e} (limit 1e-9)");
        assert!(worst < 1e-9, "N = {n}: relative error {worst:e}");
    }
}
