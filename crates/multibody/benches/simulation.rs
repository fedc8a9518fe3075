//! Wall time of complete simulations of reference examples (outputs on the
//! reference's grid included).

use criterion::{criterion_group, criterion_main, Criterion};
use multibody::{Model, OrientationState, SimulationOptions};

fn pendulum() -> Model {
    let mut model = Model::new("Pendulum");
    model.add("world", "World");
    model.add("rev", "Revolute").set("n", [0.0, 0.0, 1.0]);
    model.add("damper", "RotationalComponents.Damper").set("d", 0.1);
    model.add("body", "Body").set("m", 1.0).set("r_cm", [0.5, 0.0, 0.0]);
    model.connect(["world.frame_b", "rev.frame_a"]);
    model.connect(["rev.frame_b", "body.frame_a"]);
    model.connect(["damper.spline_a", "rev.support"]);
    model.connect(["damper.spline_b", "rev.axis"]);
    model
}

fn double_pendulum() -> Model {
    let mut model = Model::new("DoublePendulum");
    model.add("world", "World");
    model.add("revolute1", "Revolute");
    model.add("damper", "RotationalComponents.Damper").set("d", 0.1);
    model.add("revolute2", "Revolute");
    model.add("boxBody1", "BodyBox").set("r", [0.5, 0.0, 0.0]).set("width", 0.06);
    model.add("boxBody2", "BodyBox").set("r", [0.5, 0.0, 0.0]).set("width", 0.06);
    model.connect(["world.frame_b", "revolute1.frame_a"]);
    model.connect(["revolute1.frame_b", "boxBody1.frame_a"]);
    model.connect(["boxBody1.frame_b", "revolute2.frame_a"]);
    model.connect(["revolute2.frame_b", "boxBody2.frame_a"]);
    model.connect(["damper.spline_a", "revolute1.support"]);
    model.connect(["damper.spline_b", "revolute1.axis"]);
    model
}

fn point_gravity() -> Model {
    let mut model = Model::new("PointGravity");
    model.add("world", "World").set("point_gravity", true).set("mu", 1.0);
    for (name, r, v) in [("body1", [0.0, 0.6, 0.0], [1.0, 0.0, 0.0]), ("body2", [0.6, 0.6, 0.0], [0.6, 0.0, 0.0])] {
        model
            .add(name, "Body")
            .set("I_11", 0.1)
            .set("I_22", 0.1)
            .set("I_33", 0.1)
            .set("orientation_state", OrientationState::Quaternion)
            .initial("r_0", r)
            .initial("v_0", v);
    }
    model
}

fn simulations(c: &mut Criterion) {
    let mut group = c.benchmark_group("simulate");
    group.sample_size(10);
    for (name, model, stop, saveat) in [
        ("Pendulum", pendulum(), 5.0, 0.001),
        ("DoublePendulum", double_pendulum(), 3.0, 0.0006),
        ("PointGravity", point_gravity(), 5.0, 0.001),
    ] {
        let mechanism = model.assemble().unwrap();
        let options = SimulationOptions { stop, saveat, ..Default::default() };
        group.bench_function(name, |b| b.iter(|| mechanism.simulate(&options).unwrap()));
        let integrate_only = SimulationOptions { stop, saveat: stop, ..Default::default() };
        group.bench_function(format!("{name} (states only)"), |b| {
            b.iter(|| mechanism.simulate(&integrate_only).unwrap())
        });
    }
    group.finish();
}

criterion_group!(benches, simulations);
criterion_main!(benches);
