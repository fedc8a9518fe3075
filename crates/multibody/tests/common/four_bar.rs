#![allow(dead_code)] // each test file that includes this uses a part of it
//! The planar four-bar that several loop tests share (include with
//! `#[path = "common/four_bar.rs"] mod four_bar;`).

use multibody::Model;

/// A planar crank-rocker of four plain revolutes `j1`..`j4` about z, with
/// no start values: ground points O = (0,0,0) and C = (2,0,0), crank OA =
/// 0.5 along y, coupler AB = (2, 1) (2.24 m), rocker CB = 1.5 along y.
/// Grashof: 0.5 + 2.24 < 2 + 1.5, so the crank turns fully and the linkage
/// never folds flat. `coupler` scales the coupler's length.
pub fn four_bar_linkage(name: &str, coupler: f64) -> Model {
    let mut model = Model::new(name);
    model.add("world", "World");
    model.add("ground", "FixedTranslation").set("r", [2.0, 0.0, 0.0]);
    for j in ["j1", "j2", "j3", "j4"] {
        model.add(j, "Revolute");
    }
    let bar = |model: &mut Model, name: &str, r: [f64; 3]| {
        model.add(name, "BodyShape").set("m", 1.0).set("r", r).set("I_11", 0.01).set("I_22", 0.01).set("I_33", 0.01);
    };
    bar(&mut model, "crank", [0.0, 0.5, 0.0]);
    bar(&mut model, "coupler", [2.0 * coupler, coupler, 0.0]);
    bar(&mut model, "rocker", [0.0, 1.5, 0.0]);
    for (a, b) in [
        ("world.frame_b", "j1.frame_a"),
        ("world.frame_b", "ground.frame_a"),
        ("j1.frame_b", "crank.frame_a"),
        ("crank.frame_b", "j2.frame_a"),
        ("j2.frame_b", "coupler.frame_a"),
        ("coupler.frame_b", "j3.frame_a"),
        ("ground.frame_b", "j4.frame_a"),
        ("j4.frame_b", "rocker.frame_a"),
        ("rocker.frame_b", "j3.frame_b"),
    ] {
        model.connect([a, b]);
    }
    model
}

/// The linkage with its crank started at `phi = 0`, `w = w0`, and a
/// rotational damper `damping` on the crank's joint `j1`.
pub fn four_bar(damping: f64, coupler: f64, w0: f64) -> Model {
    let mut model = four_bar_linkage("four_bar", coupler);
    model.component_mut("j1").expect("the crank joint").set("axisflange", true).initial("phi", 0.0).initial("w", w0);
    model.add("damper", "RotationalComponents.Damper").set("d", damping);
    model.connect(["damper.spline_a", "j1.support"]);
    model.connect(["damper.spline_b", "j1.axis"]);
    model
}
