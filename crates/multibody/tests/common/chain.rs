//! The peers' benchmark chain (shared/bench/peers/chain_common.py): N
//! revolutes with axes z, y, z, ...; joint k > 0 one metre along the parent
//! link's x; each link 1 kg with its centre of mass 0.5 m along x and
//! inertia diag(0.001, 1/12, 1/12); gravity (0, 0, -9.81); test state
//! q_k = 0.1 (k+1), v_k = 0.05 (k+1).

#![allow(dead_code)] // each test file uses part of it

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

/// The benchmark chain with a motor on every joint: a rotor inertia behind
/// a 50:1 gear, as in a robot arm.
pub fn geared_chain(n: usize) -> Model {
    let mut model = benchmark_chain(n);
    for k in 0..n {
        model.add(format!("m{k}"), "RotationalComponents.Inertia").set("J", 2e-5 * (k + 1) as f64);
        model.add(format!("g{k}"), "RotationalComponents.IdealGear").set("ratio", 50.0);
        model.connect([format!("m{k}.spline_b"), format!("g{k}.spline_a")]);
        model.connect([format!("g{k}.spline_b"), format!("j{k}.axis")]);
    }
    model
}

/// A chain of `n` rods hanging from revolutes about z, in the plane: built
/// from PlanarMechanics components (`planar`) or from their 3-D twins.
/// Each rod 1 m, 1 kg, inertia 1/12 about its centre; start angles 0.1 rad
/// each, at rest.
pub fn planar_chain(n: usize, planar: bool) -> Model {
    let mut model = Model::new(format!("{}{n}", if planar { "planar" } else { "spatial" }));
    model.add("world", if planar { "PlanarMechanics.World" } else { "World" });
    let mut previous = "world.frame_b".to_string();
    for k in 0..n {
        if planar {
            model.add(format!("j{k}"), "PlanarMechanics.Revolute");
            model.add(format!("b{k}"), "PlanarMechanics.BodyShape").set("r", [1.0, 0.0]).set("I", 1.0 / 12.0);
        } else {
            model.add(format!("j{k}"), "Revolute").set("n", [0.0, 0.0, 1.0]);
            model
                .add(format!("b{k}"), "BodyShape")
                .set("r", [1.0, 0.0, 0.0])
                .set("r_cm", [0.5, 0.0, 0.0])
                .set("I_11", 0.0)
                .set("I_22", 0.0)
                .set("I_33", 1.0 / 12.0);
        }
        model.component_mut(&format!("j{k}")).unwrap().initial("phi", 0.1).initial("w", 0.0);
        model.connect([previous.clone(), format!("j{k}.frame_a")]);
        model.connect([format!("j{k}.frame_b"), format!("b{k}.frame_a")]);
        previous = format!("b{k}.frame_b");
    }
    model
}
