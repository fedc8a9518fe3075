//! Modelica MultiBody reference trajectories (../shared/reference/msl),
//! rebuilt from their descriptions with the Rust API.

mod common;

use common::{assert_within_tube, Reference};
use multibody::{Model, OrientationState, SimulationOptions};

fn options_for(reference: &Reference) -> SimulationOptions {
    SimulationOptions { stop: reference.stop(), saveat: reference.interval(), ..SimulationOptions::default() }
}

/// Pendulum.md: a revolute about z with a rotational damper d = 0.1, and a
/// body m = 1 at r_cm = [0.5, 0, 0].
#[test]
fn pendulum() {
    let mut model = Model::new("Pendulum");
    model.add("world", "World");
    model.add("rev", "Revolute").set("n", [0.0, 0.0, 1.0]).set("axisflange", true);
    model.add("damper", "RotationalComponents.Damper").set("d", 0.1);
    model.add("body", "Body").set("m", 1.0).set("r_cm", [0.5, 0.0, 0.0]);
    model.connect(["world.frame_b", "rev.frame_a"]);
    model.connect(["rev.frame_b", "body.frame_a"]);
    model.connect(["damper.spline_a", "rev.support"]);
    model.connect(["damper.spline_b", "rev.axis"]);
    let reference = Reference::load("Pendulum");
    let solution = model.assemble().unwrap().simulate(&options_for(&reference)).unwrap();
    assert_within_tube(&reference, &solution, &[("rev.phi", "rev.phi"), ("rev.w", "rev.w")]);
}

/// DoublePendulum.md: two revolutes and two boxes (as Bodies with the
/// BodyBox mass and inertia from the description, and a rod to frame_b).
#[test]
fn double_pendulum() {
    let mut model = Model::new("DoublePendulum");
    model.add("world", "World");
    model.add("revolute1", "Revolute");
    model.add("damper", "RotationalComponents.Damper").set("d", 0.1);
    model.add("revolute2", "Revolute");
    for k in ["1", "2"] {
        model
            .add(format!("boxBody{k}"), "Body")
            .set("m", 13.86)
            .set("r_cm", [0.25, 0.0, 0.0])
            .set("I_11", 0.008316)
            .set("I_22", 0.292908)
            .set("I_33", 0.292908);
        model.add(format!("rod{k}"), "FixedTranslation").set("r", [0.5, 0.0, 0.0]);
        model.connect([format!("boxBody{k}.frame_a"), format!("rod{k}.frame_a")]);
    }
    model.connect(["world.frame_b", "revolute1.frame_a"]);
    model.connect(["revolute1.frame_b", "boxBody1.frame_a"]);
    model.connect(["rod1.frame_b", "revolute2.frame_a"]);
    model.connect(["revolute2.frame_b", "boxBody2.frame_a"]);
    model.connect(["damper.spline_a", "revolute1.support"]);
    model.connect(["damper.spline_b", "revolute1.axis"]);
    let reference = Reference::load("DoublePendulum");
    let solution = model.assemble().unwrap().simulate(&options_for(&reference)).unwrap();
    let pairs: Vec<(&str, &str)> =
        ["revolute1.phi", "revolute1.w", "revolute2.phi", "revolute2.w"].iter().map(|s| (*s, *s)).collect();
    assert_within_tube(&reference, &solution, &pairs);
}

/// PointGravity.md: two free bodies in a point-gravity field with mu = 1.
#[test]
fn point_gravity() {
    let mut model = Model::new("PointGravity");
    model.add("world", "World").set("point_gravity", true).set("mu", 1.0);
    for (name, r, v) in [("body1", [0.0, 0.6, 0.0], [1.0, 0.0, 0.0]), ("body2", [0.6, 0.6, 0.0], [0.6, 0.0, 0.0])] {
        model
            .add(name, "Body")
            .set("m", 1.0)
            .set("I_11", 0.1)
            .set("I_22", 0.1)
            .set("I_33", 0.1)
            .set("orientation_state", OrientationState::Quaternion)
            .initial("r_0", r)
            .initial("v_0", v);
    }
    let reference = Reference::load("PointGravity");
    let solution = model.assemble().unwrap().simulate(&options_for(&reference)).unwrap();
    let mut pairs = Vec::new();
    for b in ["body1", "body2"] {
        for i in 1..=3 {
            pairs.push((format!("{b}.frame_a.r_0[{i}]"), format!("{b}.frame_a.r_0[{i}]")));
            pairs.push((format!("{b}.v_0[{i}]"), format!("{b}.v_0[{i}]")));
            pairs.push((format!("{b}.w_a[{i}]"), format!("{b}.w_a[{i}]")));
        }
    }
    let pairs: Vec<(&str, &str)> = pairs.iter().map(|(a, b)| (a.as_str(), b.as_str())).collect();
    assert_within_tube(&reference, &solution, &pairs);
}
