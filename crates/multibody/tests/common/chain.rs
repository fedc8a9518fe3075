//! The peers' benchmark chain (shared/bench/peers/chain_common.py): N
//! revolutes with axes z, y, z, ...; joint k > 0 one metre along the parent
//! link's x; each link 1 kg with its centre of mass 0.5 m along x and
//! inertia diag(0.001, 1/12, 1/12); gravity (0, 0, -9.81); test state
//! q_k = 0.1 (k+1), v_k = 0.05 (k+1).

use multibody::Model;

pub fn benchmark_chain(n: usize) -> Model {
    let mut model = Model::new(format!("chain{n}"));
    model.add("world", "World").set("g", 9.81).set("n", [0.0, 0.0, -1.0]);
    let mut previous = "world.frame_b".to_string();
    for k in 0..n {
        let axis = if k % 2 == 0 { [0.0, 0.0, 1.0] } else { [0.0, 1.0, 0.0] };
        let q = 0.1 * (k + 1) as f64;
        let v = 0.05 * (k + 1) as f64;
        model.add(format!("j{k}"), "Revolute").set("n", axis).initial("phi", q).initial("w", v);
        model
            .add(format!("b{k}"), "Body")
            .set("m", 1.0)
            .set("r_cm", [0.5, 0.0, 0.0])
            .set("I_11", 1e-3)
            .set("I_22", 1.0 / 12.0)
            .set("I_33", 1.0 / 12.0);
        model.connect([previous.clone(), format!("j{k}.frame_a")]);
        model.connect([format!("j{k}.frame_b"), format!("b{k}.frame_a")]);
        if k + 1 < n {
            model.add(format!("l{k}"), "FixedTranslation").set("r", [1.0, 0.0, 0.0]);
            model.connect([format!("j{k}.frame_b"), format!("l{k}.frame_a")]);
            previous = format!("l{k}.frame_b");
        }
    }
    model
}
