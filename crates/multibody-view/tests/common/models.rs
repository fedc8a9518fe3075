//! Models the view tests and the demo draw, built with the Rust API.
#![allow(dead_code)]

use multibody::{Mechanism, Model, SimulationOptions, Solution};

/// A pendulum: a revolute about z and a body of 1 kg at 0.5 m, released
/// horizontally.
pub fn pendulum() -> Mechanism {
    let mut model = Model::new("Pendulum");
    model.add("world", "World");
    model.add("rev", "Revolute").set("n", [0.0, 0.0, 1.0]);
    model.add("body", "Body").set("m", 1.0).set("r_cm", [0.5, 0.0, 0.0]);
    model.connect(["world.frame_b", "rev.frame_a"]);
    model.connect(["rev.frame_b", "body.frame_a"]);
    model.assemble().expect("the pendulum assembles")
}

/// Modelica's DoublePendulum with BodyBoxes (0.5 m long, 0.06 m wide) and a
/// damped first joint: the repository's examples/msl/DoublePendulum.dyad.
pub fn double_pendulum() -> Mechanism {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/msl/DoublePendulum.dyad");
    let mut package = multibody_dyad::Package::new();
    package.add_source(path.display().to_string(), std::fs::read_to_string(&path).unwrap()).unwrap();
    let lowered = package.lower_component("DoublePendulum").expect("the example lowers");
    lowered.assemble().expect("the double pendulum assembles")
}

/// A double pendulum of two Bodies on rods, the second body pure magenta
/// (drawn only with `render_second`); everything else is blue-grey.
pub fn magenta_double_pendulum(render_second: bool) -> Mechanism {
    let grey = [0.35, 0.45, 0.6, 1.0];
    let mut model = Model::new("MagentaDoublePendulum");
    model.add("world", "World").set("render", false);
    for k in ["1", "2"] {
        model.add(format!("rev{k}"), "Revolute").set("n", [0.0, 0.0, 1.0]).set("color", grey);
        model.add(format!("rod{k}"), "FixedTranslation").set("r", [0.5, 0.0, 0.0]).set("color", grey);
    }
    model.add("body1", "Body").set("m", 1.0).set("r_cm", [0.5, 0.0, 0.0]).set("color", grey);
    model
        .add("body2", "Body")
        .set("m", 1.0)
        .set("r_cm", [0.5, 0.0, 0.0])
        .set("radius", 0.1)
        .set("color", [1.0, 0.0, 1.0, 1.0])
        .set("render", render_second);
    model.connect(["world.frame_b", "rev1.frame_a"]);
    model.connect(["rev1.frame_b", "body1.frame_a", "rod1.frame_a"]);
    model.connect(["rod1.frame_b", "rev2.frame_a"]);
    model.connect(["rev2.frame_b", "body2.frame_a", "rod2.frame_a"]);
    model.assemble().expect("the magenta double pendulum assembles")
}

/// A chain of `n` revolutes about z, each with a Body (at the middle of its
/// link) and a 0.05 m rod to the next joint.
pub fn chain(n: usize) -> Mechanism {
    let mut model = Model::new("Chain");
    model.add("world", "World");
    let mut previous = "world.frame_b".to_string();
    for k in 1..=n {
        model.add(format!("rev{k}"), "Revolute").set("n", [0.0, 0.0, 1.0]);
        model.add(format!("body{k}"), "Body").set("m", 0.1).set("r_cm", [0.025, 0.0, 0.0]).set("radius", 0.015);
        model.add(format!("rod{k}"), "FixedTranslation").set("r", [0.05, 0.0, 0.0]);
        model.connect([previous.clone(), format!("rev{k}.frame_a")]);
        model.connect([format!("rev{k}.frame_b"), format!("body{k}.frame_a"), format!("rod{k}.frame_a")]);
        previous = format!("rod{k}.frame_b");
    }
    model.assemble().expect("the chain assembles")
}

/// A free body on a spring below the world origin, pushed sideways by a
/// constant world force (a helix and a force arrow to draw).
pub fn spring_mass() -> Mechanism {
    let mut model = Model::new("SpringMass");
    model.add("world", "World");
    model.add("spring", "Spring").set("c", 40.0).set("s_unstretched", 0.3);
    model
        .add("body", "Body")
        .set("m", 1.0)
        .set("I_11", 0.01)
        .set("I_22", 0.01)
        .set("I_33", 0.01)
        .set("orientation_state", multibody::OrientationState::Quaternion)
        .initial("r_0", [0.2, -0.6, 0.1]);
    model.add("push", "WorldForce").set("scale", 0.1);
    model.connect(["world.frame_b", "spring.frame_a"]);
    model.connect(["spring.frame_b", "body.frame_a", "push.frame_b"]);
    for (axis, k) in [("x", 3.0), ("y", 0.0), ("z", 0.0)] {
        model.add(format!("f{axis}"), "BlockComponents.Constant").set("k", k);
        model.connect([format!("f{axis}.y"), format!("push.force_{axis}")]);
    }
    model.assemble().expect("the spring-mass model assembles")
}

pub fn simulate(mechanism: &Mechanism, stop: f64) -> Solution {
    mechanism.simulate(&SimulationOptions { stop, saveat: 0.01, ..Default::default() }).expect("the model simulates")
}
