//! Every model file in `examples/` runs, and gives exactly (bit for bit) the
//! result of the same model built by hand with the Rust API. The Modelica
//! reference models in `examples/msl/` are checked against Modelica's own
//! results instead (crates/multibody-cli/tests/reference.rs).

use multibody::{Method, Model, OrientationState, SimulationOptions, Solution};
use multibody_dyad::{DefinitionKind, Package};
use std::path::{Path, PathBuf};

fn examples_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples")
}

/// Reads an example and runs its only analysis.
fn run_file(relative: &str) -> (Model, SimulationOptions, Solution) {
    let path = examples_dir().join(relative);
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut package = Package::new();
    if let Err(d) = package.add_source(relative, text) {
        panic!("{}", d.render(package.sources(), false));
    }
    let analyses: Vec<String> =
        package.definitions().into_iter().filter(|d| d.kind == DefinitionKind::Analysis).map(|d| d.name).collect();
    assert_eq!(analyses.len(), 1, "{relative} should have exactly one analysis");
    let lowered =
        package.lower_analysis(&analyses[0]).unwrap_or_else(|d| panic!("{}", d.render(package.sources(), false)));
    assert!(lowered.warnings.is_empty(), "{relative}: {:?}", lowered.warnings);
    let mechanism = lowered.assemble().unwrap_or_else(|d| panic!("{}", d.render(package.sources(), false)));
    let solution = mechanism.simulate(&lowered.options).unwrap();
    (lowered.model, lowered.options, solution)
}

/// Runs the file and the hand-built model and compares every signal exactly.
fn assert_same(relative: &str, expected: Model, options: SimulationOptions) {
    let (model, file_options, from_file) = run_file(relative);
    assert_eq!(file_options, options, "{relative}: simulation options");
    assert_eq!(model.name, expected.name);
    let by_hand = expected.assemble().unwrap().simulate(&options).unwrap();
    assert_eq!(from_file.names(), by_hand.names(), "{relative}: the signals differ");
    assert_eq!(from_file.time(), by_hand.time(), "{relative}: the output times differ");
    for name in by_hand.names() {
        let (a, b) = (from_file.get(name).unwrap(), by_hand.get(name).unwrap());
        let same = a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits());
        assert!(same, "{relative}: {name} differs from the hand-built model");
    }
    assert!(from_file.len() > 10, "{relative}: too few samples");
}

fn options(stop: f64, saveat: f64) -> SimulationOptions {
    SimulationOptions { stop, saveat, ..SimulationOptions::default() }
}

#[test]
fn pendulum() {
    let mut m = Model::new("Pendulum");
    m.add("world", "World");
    m.add("rev", "Revolute").set("n", [0.0, 0.0, 1.0]).initial("phi", 0.0).initial("w", 0.0);
    m.add("damper", "RotationalComponents.Damper").set("d", 0.1);
    m.add("body", "Body").set("m", 1.0).set("r_cm", [0.5, 0.0, 0.0]);
    m.connect(["world.frame_b", "rev.frame_a"]);
    m.connect(["rev.frame_b", "body.frame_a"]);
    m.connect(["damper.spline_a", "rev.support"]);
    m.connect(["damper.spline_b", "rev.axis"]);
    assert_same("pendulum.dyad", m, options(5.0, 0.01));
}

#[test]
fn double_pendulum() {
    let mut m = Model::new("DoublePendulum");
    m.add("world", "World");
    for (link, d) in [("link1", 0.1), ("link2", 0.0)] {
        m.add(format!("{link}.joint"), "Revolute").set("n", [0.0, 0.0, 1.0]).initial("phi", 0.0).initial("w", 0.0);
        m.add(format!("{link}.damper"), "RotationalComponents.Damper").set("d", d);
        m.add(format!("{link}.box"), "BodyBox").set("r", [0.5, 0.0, 0.0]).set("width", 0.06);
    }
    m.connect(["world.frame_b", "link1.joint.frame_a"]);
    for link in ["link1", "link2"] {
        m.connect([format!("{link}.joint.frame_b"), format!("{link}.box.frame_a")]);
        m.connect([format!("{link}.damper.spline_a"), format!("{link}.joint.support")]);
        m.connect([format!("{link}.damper.spline_b"), format!("{link}.joint.axis")]);
    }
    m.connect(["link1.box.frame_b", "link2.joint.frame_a"]);
    assert_same("double_pendulum.dyad", m, options(3.0, 0.006));
}

#[test]
fn free_body() {
    let mut m = Model::new("FreeBody");
    m.add("world", "World");
    m.add("body", "Body")
        .set("m", 2.0)
        .set("I_11", 0.1)
        .set("I_22", 0.2)
        .set("I_33", 0.3)
        .set("orientation_state", OrientationState::Quaternion)
        .initial("r_0", [0.0, 10.0, 0.0])
        .initial("v_0", [1.0, 5.0, 0.0])
        .initial("w_a", [0.3, 2.0, 0.1]);
    assert_same("free_body.dyad", m, options(3.0, 0.01));
}

#[test]
fn orbits() {
    let mut m = Model::new("Orbits");
    m.add("world", "World").set("point_gravity", true).set("mu", 1.0);
    let circular = (1.0f64 / 0.6).sqrt();
    for (name, r, v) in
        [("circle", [0.0, 0.6, 0.0], [circular, 0.0, 0.0]), ("ellipse", [0.6, 0.6, 0.0], [0.6, 0.0, 0.0])]
    {
        m.add(format!("{name}.body"), "Body")
            .set("m", 1.0)
            .set("I_11", 0.1)
            .set("I_22", 0.1)
            .set("I_33", 0.1)
            .set("orientation_state", OrientationState::Quaternion)
            .initial("r_0", r)
            .initial("v_0", v);
    }
    assert_same("orbits.dyad", m, options(5.0, 0.01));
}

#[test]
fn spring_mass() {
    let mut m = Model::new("SpringMass");
    m.add("world", "World");
    m.add("slider", "Prismatic").set("n", [0.0, -1.0, 0.0]).initial("v", 0.0).initial("s", 0.1);
    m.add("spring", "TranslationalComponents.Spring").set("c", 30.0).set("s_rel0", 0.1);
    m.add("body", "Body").set("m", 1.0);
    m.connect(["world.frame_b", "slider.frame_a"]);
    m.connect(["slider.frame_b", "body.frame_a"]);
    m.connect(["spring.flange_a", "slider.support"]);
    m.connect(["spring.flange_b", "slider.axis"]);
    assert_same("spring_mass.dyad", m, options(5.0, 0.01));
}

#[test]
fn stiff_spring() {
    let mut m = Model::new("StiffSpring");
    m.add("wall", "TranslationalComponents.Fixed");
    m.add("spring", "TranslationalComponents.SpringDamper").set("c", 1e8).set("d", 1e5);
    m.add("slider", "TranslationalComponents.Mass").set("m", 1.0).initial("s", 0.002).initial("v", 0.0);
    m.add("push", "TranslationalComponents.Force");
    m.add("force", "BlockComponents.Sine").set("amplitude", 1e6).set("frequency", 1.0);
    m.connect(["wall.flange", "spring.flange_a", "push.support"]);
    m.connect(["spring.flange_b", "slider.flange_a"]);
    m.connect(["push.flange", "slider.flange_b"]);
    m.connect(["force.y", "push.f"]);
    assert_same("stiff_spring.dyad", m, SimulationOptions { method: Method::Rodas4, ..options(2.0, 0.001) });
}

/// A file with an editor's layout metadata (inline JSON, `{^name}` links,
/// a metadata section): the metadata changes nothing.
#[test]
fn annotated_swing() {
    let mut m = Model::new("Swing");
    m.add("world", "World");
    m.add("beam", "FixedTranslation").set("r", [0.0, 2.0, 0.0]);
    m.add("pivot", "Revolute").set("n", [0.0, 0.0, 1.0]).initial("phi", -1.2).initial("w", 0.0);
    m.add("friction", "RotationalComponents.Damper").set("d", 0.4);
    m.add("seat", "BodyShape").set("r", [0.0, -1.8, 0.0]).set("r_cm", [0.0, -1.8, 0.0]).set("m", 20.0);
    m.connect(["world.frame_b", "beam.frame_a"]);
    m.connect(["beam.frame_b", "pivot.frame_a"]);
    m.connect(["pivot.frame_b", "seat.frame_a"]);
    m.connect(["friction.spline_a", "pivot.support"]);
    m.connect(["friction.spline_b", "pivot.axis"]);
    assert_same("docs/annotated_swing.dyad", m, options(8.0, 0.01));
}

#[test]
fn four_bar() {
    let mut m = Model::new("FourBar");
    m.add("world", "World");
    m.add("ground", "FixedTranslation").set("r", [2.0, 0.0, 0.0]);
    m.add("j1", "Revolute").set("axisflange", true).initial("phi", 0.0).initial("w", 5.0);
    for j in ["j2", "j3", "j4"] {
        m.add(j, "Revolute");
    }
    for (bar, r) in [("crank", [0.0, 0.5, 0.0]), ("coupler", [2.0, 1.0, 0.0]), ("rocker", [0.0, 1.5, 0.0])] {
        m.add(bar, "BodyShape").set("m", 1.0).set("r", r).set("I_11", 0.01).set("I_22", 0.01).set("I_33", 0.01);
    }
    m.add("damper", "RotationalComponents.Damper").set("d", 0.05);
    m.connect(["world.frame_b", "j1.frame_a", "ground.frame_a"]);
    for (a, b) in [
        ("j1.frame_b", "crank.frame_a"),
        ("crank.frame_b", "j2.frame_a"),
        ("j2.frame_b", "coupler.frame_a"),
        ("coupler.frame_b", "j3.frame_a"),
        ("ground.frame_b", "j4.frame_a"),
        ("j4.frame_b", "rocker.frame_a"),
        ("rocker.frame_b", "j3.frame_b"),
        ("damper.spline_a", "j1.support"),
        ("damper.spline_b", "j1.axis"),
    ] {
        m.connect([a, b]);
    }
    assert_same("four_bar.dyad", m, options(10.0, 0.01));
}

/// A pendulum whose torque is an input of the model (left at its start,
/// 0, here) and whose angle and speed are its outputs.
#[test]
fn controlled_pendulum() {
    let mut m = Model::new("ControlledPendulum");
    m.add("tau", "Input").set("start", 0.0);
    m.add("world", "World");
    m.add("rev", "Revolute").set("n", [0.0, 0.0, 1.0]).initial("phi", 0.0).initial("w", 0.0);
    m.add("body", "Body").set("m", 1.0).set("r_cm", [0.5, 0.0, 0.0]).set("I_22", 0.02).set("I_33", 0.02);
    m.add("motor", "RotationalComponents.Torque");
    m.add("angle_sensor", "RotationalComponents.AngleSensor");
    m.add("speed_sensor", "RotationalComponents.SpeedSensor");
    m.connect(["world.frame_b", "rev.frame_a"]);
    m.connect(["rev.frame_b", "body.frame_a"]);
    m.connect(["motor.spline", "angle_sensor.spline", "speed_sensor.spline", "rev.axis"]);
    m.connect(["motor.support", "rev.support"]);
    m.connect(["tau.y", "motor.tau"]);
    for (output, source) in [("angle", "angle_sensor.phi"), ("speed", "speed_sensor.w")] {
        m.variable(output);
        m.equations.equations.push(multibody::Equation {
            lhs: multibody::Expr::var(output),
            rhs: multibody::Expr::var(source),
            origin: String::new(),
        });
    }
    m.outputs = vec!["angle".into(), "speed".into()];
    let (from_file, _, _) = run_file("controlled_pendulum.dyad");
    assert_eq!(from_file.outputs, m.outputs);
    assert_eq!(from_file.components[0].kind, "Input");
    let options = SimulationOptions { stop: 5.0, saveat: 0.001, abstol: 1e-10, reltol: 1e-10, ..Default::default() };
    assert_same("controlled_pendulum.dyad", m, options);
}

/// The damped pendulum of the linear and steady-state analyses: the three
/// analyses lower to the hand-built model (the transient one simulates
/// alike) with Dyad's parameters read.
#[test]
fn linear_analysis() {
    let pendulum = |phi0: f64| {
        let mut m = Model::new("DampedPendulum");
        m.add("tau", "Input").set("start", 0.0);
        m.add("world", "World");
        m.add("rev", "Revolute")
            .set("n", [0.0, 0.0, 1.0])
            .set("axisflange", true)
            .initial("phi", phi0)
            .initial("w", 0.0);
        m.add("body", "Body").set("m", 1.0).set("r_cm", [0.5, 0.0, 0.0]).set("I_22", 0.02).set("I_33", 0.02);
        m.add("damper", "RotationalComponents.Damper").set("d", 0.3);
        m.add("motor", "RotationalComponents.Torque");
        m.add("angle_sensor", "RotationalComponents.AngleSensor");
        m.connect(["world.frame_b", "rev.frame_a"]);
        m.connect(["rev.frame_b", "body.frame_a"]);
        m.connect(["damper.spline_a", "motor.support", "rev.support"]);
        m.connect(["damper.spline_b", "motor.spline", "angle_sensor.spline", "rev.axis"]);
        m.connect(["tau.y", "motor.tau"]);
        m.variable("angle");
        m.equations.equations.push(multibody::Equation {
            lhs: multibody::Expr::var("angle"),
            rhs: multibody::Expr::var("angle_sensor.phi"),
            origin: String::new(),
        });
        m.outputs = vec!["angle".into()];
        m
    };
    let path = examples_dir().join("linear_analysis.dyad");
    let mut package = Package::new();
    package.add_source("linear_analysis.dyad", std::fs::read_to_string(path).unwrap()).unwrap();
    let lower =
        |name: &str| package.lower_analysis(name).unwrap_or_else(|d| panic!("{}", d.render(package.sources(), false)));
    let linear = lower("DampedPendulumLinear");
    assert_eq!(
        linear.study,
        multibody_dyad::Study::Linear {
            inputs: vec!["tau".into()],
            outputs: vec!["angle".into()],
            duration: Some(5.0)
        }
    );
    let rest = lower("DampedPendulumRest");
    assert_eq!(rest.study, multibody_dyad::Study::SteadyState { abstol: 1e-10, reltol: 1e-10 });
    let transient = lower("DampedPendulumSimulation");
    assert_eq!(transient.study, multibody_dyad::Study::Transient);
    let options = options(5.0, 0.01);
    for (lowered, phi0) in [(&linear, -std::f64::consts::FRAC_PI_2), (&rest, 1.0), (&transient, 1.0)] {
        assert!(lowered.warnings.is_empty(), "{:?}", lowered.warnings);
        let from_file = lowered.assemble().unwrap().simulate(&options).unwrap();
        let by_hand = pendulum(phi0).assemble().unwrap().simulate(&options).unwrap();
        assert_eq!(from_file.names(), by_hand.names());
        for name in by_hand.names() {
            let (a, b) = (from_file.get(name).unwrap(), by_hand.get(name).unwrap());
            assert!(a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits()), "{}: {name} differs", lowered.name);
        }
    }
    assert_eq!(transient.options, options);
}

#[test]
fn geared_servo() {
    let mut m = Model::new("GearedServo");
    m.add("world", "World");
    m.add("motor", "Revolute").set("n", [0.0, 1.0, 0.0]).initial("phi", 0.0).initial("w", 0.0);
    m.add("rotor", "Body").set("m", 0.5).set("r_cm", [0.0, 0.0, 0.0]).set("I_22", 0.002);
    m.add("table", "Revolute").set("n", [0.0, 1.0, 0.0]);
    m.add("load", "Body").set("m", 2.0).set("r_cm", [0.3, 0.0, 0.0]).set("I_22", 0.01).set("I_33", 0.01);
    m.add("gear", "RotationalComponents.IdealGear").set("ratio", 4.0);
    m.add("angle", "RotationalComponents.AngleSensor");
    m.add("speed", "RotationalComponents.SpeedSensor");
    m.add("setpoint", "BlockComponents.Constant").set("k", 1.0);
    m.add("error", "BlockComponents.Feedback");
    m.add("pd", "BlockComponents.Add").set("k1", 2.0).set("k2", -0.6);
    m.add("drive", "RotationalComponents.Torque");
    m.connect(["world.frame_b", "motor.frame_a", "table.frame_a"]);
    m.connect(["motor.frame_b", "rotor.frame_a"]);
    m.connect(["table.frame_b", "load.frame_a"]);
    m.connect(["gear.spline_a", "motor.axis"]);
    m.connect(["gear.spline_b", "table.axis", "angle.spline", "speed.spline"]);
    m.connect(["drive.spline", "motor.axis"]);
    m.connect(["drive.support", "motor.support"]);
    m.connect(["setpoint.y", "error.u1"]);
    m.connect(["angle.phi", "error.u2"]);
    m.connect(["error.y", "pd.u1"]);
    m.connect(["speed.w", "pd.u2"]);
    m.connect(["pd.y", "drive.tau"]);
    assert_same("geared_servo.dyad", m, options(10.0, 0.01));
}

/// 3-D sensors in feedback: a mass on a vertical rail held by a PD force
/// from an AbsolutePosition and an AbsoluteVelocity.
#[test]
fn sensors() {
    use multibody::Value;
    let world = || Value::Enum("World".into());
    let mut m = Model::new("Hover");
    m.add("world", "World");
    m.add("rail", "Prismatic").set("n", [0.0, 1.0, 0.0]).initial("s", 0.0).initial("v", 0.0);
    m.add("mass", "Body").set("m", 2.0).set("r_cm", [0.0, 0.0, 0.0]);
    m.add("position", "AbsolutePosition").set("resolve_in_frame", world());
    m.add("velocity", "AbsoluteVelocity").set("resolve_in_frame", world());
    m.add("setpoint", "BlockComponents.Constant").set("k", 1.0);
    m.add("error", "BlockComponents.Feedback");
    m.add("pd", "BlockComponents.Add").set("k1", 200.0).set("k2", -40.0);
    m.add("thrust", "WorldForce");
    m.add("zero", "BlockComponents.Constant").set("k", 0.0);
    m.connect(["world.frame_b", "rail.frame_a"]);
    m.connect(["rail.frame_b", "mass.frame_a", "position.frame_a", "velocity.frame_a", "thrust.frame_b"]);
    m.connect(["setpoint.y", "error.u1"]);
    m.connect(["position.r_y", "error.u2"]);
    m.connect(["error.y", "pd.u1"]);
    m.connect(["velocity.v_y", "pd.u2"]);
    m.connect(["pd.y", "thrust.force_y"]);
    m.connect(["zero.y", "thrust.force_x", "thrust.force_z"]);
    assert_same("sensors.dyad", m, options(2.0, 0.01));
    // It settles where the pull balances the weight: y = 1 - m g / kp.
    let (_, _, solution) = run_file("sensors.dyad");
    let y = solution.last("position.r[2]").unwrap();
    assert!((y - (1.0 - 2.0 * 9.80665 / 200.0)).abs() < 1e-4, "settled at {y}");
}

/// A new example must get a hand-built twin above (or, in `msl/`, a reference test).
/// Formulas of time in `relations` drive signal inputs: the file against
/// the same model built with `Model::set_input`, and the carried body
/// against the formulas themselves.
#[test]
fn prescribed_motion() {
    use multibody::{Func, TimeExpr as T};
    let b = std::sync::Arc::new;
    let mut m = Model::new("PrescribedMotion");
    m.add("world", "World");
    m.add("carrier", "PrescribedPosition");
    m.add("load", "Body").set("m", 2.0).set("r_cm", [0.0, 0.0, 0.0]);
    m.add("hinge", "Revolute").set("n", [0.0, 0.0, 1.0]);
    m.add("arm", "Body").set("m", 1.0).set("r_cm", [0.4, 0.0, 0.0]);
    m.add("drive", "RotationalComponents.Position").set("f_crit", 5.0);
    m.set_input("carrier.r_x", T::Call(Func::Sin, b(T::Time)));
    m.set_input("carrier.r_y", T::Mul(b(T::Const(2.0)), b(T::Time)));
    m.set_input("carrier.r_z", T::Call(Func::Cos, b(T::Time)));
    // amplitude * sin(2 pi 0.5 time): the parameter and constants fold in order.
    let angle = T::Mul(b(T::Const(2.0 * std::f64::consts::PI * 0.5)), b(T::Time));
    m.set_input("drive.phi_ref", T::Mul(b(T::Const(0.6)), b(T::Call(Func::Sin, b(angle)))));
    m.connect(["carrier.frame_b", "load.frame_a"]);
    m.connect(["world.frame_b", "hinge.frame_a"]);
    m.connect(["hinge.frame_b", "arm.frame_a"]);
    m.connect(["drive.spline", "hinge.axis"]);
    assert_same("prescribed_motion.dyad", m, options(4.0, 0.01));

    let (_, _, solution) = run_file("prescribed_motion.dyad");
    let mut worst = 0.0f64;
    for (i, f) in [f64::sin as fn(f64) -> f64, |t| 2.0 * t, f64::cos].iter().enumerate() {
        let values = solution.get(&format!("load.frame_a.r_0[{}]", i + 1)).unwrap();
        for (t, x) in solution.time().iter().zip(values) {
            worst = worst.max((x - f(*t)).abs());
        }
    }
    assert!(worst < 1e-9, "the carried body is {worst:e} m off its formula");
}

/// The small vehicle: a box on two rolling wheel sets, the rear one driven,
/// the front one steered by a formula of time.
#[test]
fn wheeled_cart() {
    use multibody::{Func, TimeExpr as T};
    let b = std::sync::Arc::new;
    let mut m = Model::new("WheeledCart");
    m.add("world", "World");
    let wheels = |m: &mut Model, name: &str| {
        m.add(name, "RollingWheelSet")
            .set("radius", 0.25)
            .set("m_wheel", 2.0)
            .set("I_axis", 0.0625)
            .set("I_long", 0.035)
            .set("track", 1.2)
            .set("width_wheel", 0.12);
    };
    wheels(&mut m, "rear");
    for state in ["x", "z", "phi", "theta1", "theta2", "der_theta1", "der_theta2"] {
        m.component_mut("rear").unwrap().initial(state, 0.0);
    }
    m.add("chassis", "BodyBox").set("r", [2.0, 0.0, 0.0]).set("width", 0.9).set("height", 0.25).set("density", 300.0);
    m.add("steering", "Revolute").set("n", [0.0, 1.0, 0.0]);
    m.add("steer", "RotationalComponents.Position").set("exact", true);
    wheels(&mut m, "front");
    m.component_mut("front").unwrap().set("iscut", true);
    m.add("throttle", "BlockComponents.Constant").set("k", -6.0);
    m.add("drive1", "RotationalComponents.Torque");
    m.add("drive2", "RotationalComponents.Torque");
    let angle = T::Mul(b(T::Const(0.5)), b(T::Time));
    m.set_input("steer.phi_ref", T::Mul(b(T::Const(0.35)), b(T::Call(Func::Sin, b(angle)))));
    for pair in [
        ["rear.frame_middle", "chassis.frame_a"],
        ["chassis.frame_b", "steering.frame_a"],
        ["steering.frame_b", "front.frame_middle"],
        ["steer.spline", "steering.axis"],
        ["steer.support", "steering.support"],
        ["drive1.spline", "rear.axis1"],
        ["drive1.support", "rear.support"],
        ["drive2.spline", "rear.axis2"],
        ["drive2.support", "rear.support"],
    ] {
        m.connect(pair);
    }
    m.connect(["throttle.y", "drive1.tau", "drive2.tau"]);
    assert_same("wheeled_cart.dyad", m, options(10.0, 0.02));

    // The rear axle does not slide sideways: its middle moves along its
    // heading (1, 0, -tan phi). Central differences over the 0.02 s samples
    // err by about (h^2 / 6) times the third derivative: 1e-4 of the speed here.
    let (_, _, s) = run_file("wheeled_cart.dyad");
    let (x, z, phi) = (s.get("rear.x").unwrap(), s.get("rear.z").unwrap(), s.get("rear.phi").unwrap());
    let mut worst = 0.0f64;
    for k in 1..x.len() - 1 {
        let (dx, dz) = (x[k + 1] - x[k - 1], z[k + 1] - z[k - 1]);
        let speed = (dx * dx + dz * dz).sqrt();
        if speed > 1e-6 {
            worst = worst.max((dx * phi[k].sin() + dz * phi[k].cos()).abs() / speed);
        }
    }
    println!("wheeled cart: sideways motion of the rear axle {worst:.1e} of its speed (tolerance 1e-3)");
    assert!(worst < 1e-3);
    assert!(*x.last().unwrap() > 5.0, "the cart drives forwards");
}

/// Two wheels dropped spinning: the library's slip law on a rigid contact,
/// Pacejka's magic formula on an elastic one. Both end rolling at the speed
/// that their angular momentum about the ground line gives.
#[test]
fn slipping_wheels() {
    let mut m = Model::new("SlippingWheels");
    m.add("world", "World");
    for (name, kind, z) in [("slip", "SlippingWheel", 0.0), ("pacejka", "PacejkaSlippingWheel", 1.0)] {
        m.add(name, kind)
            .set("radius", 0.3)
            .set("m", 1.0)
            .set("I_axis", 0.06)
            .set("I_long", 0.12)
            .initial("x", 0.0)
            .initial("z", z)
            .initial("angles", vec![0.0; 3])
            .initial("v_0", vec![0.0; 3])
            .initial("der_angles", vec![0.0, 25.0, 0.0]);
    }
    m.component_mut("pacejka").unwrap().set("elastic_contact", true).set("color", [0.0, 0.0, 1.0, 1.0]);
    {
        use multibody::{Expr as S, Func};
        let b = std::sync::Arc::new;
        m.add("wavy", "SlippingWheel")
            .set("radius", 0.3)
            .set("m", 1.0)
            .set("I_axis", 0.06)
            .set("I_long", 0.12)
            .set("color", [0.0, 0.6, 0.0, 1.0])
            .initial("x", 0.0)
            .initial("z", 2.0)
            .initial("angles", vec![0.0; 3])
            .initial("v_0", vec![0.0; 3])
            .initial("der_angles", vec![0.0, 25.0, 0.0])
            .surface(S::Mul(
                b(S::Const(0.05)),
                b(S::Call(Func::Sin, b(S::Mul(b(S::Const(2.0)), b(S::Var("x".into())))))),
            ));
    }
    assert_same("slipping_wheels.dyad", m, SimulationOptions { method: Method::Rodas4, ..options(2.0, 0.01) });
    let (_, _, s) = run_file("slipping_wheels.dyad");
    // I_axis w0 / (I_axis + m R^2) = 0.06 * 25 / 0.15 = 10 rad/s. The run's
    // tolerance is 1e-6 (Dyad's default); it ends within 5e-8 of that here.
    for wheel in ["slip", "pacejka"] {
        let w = s.last(&format!("{wheel}.w_roll")).unwrap();
        let v = s.last(&format!("{wheel}.v_0[1]")).unwrap();
        println!("{wheel}: w_roll {w:.9} rad/s (closed form 10), v {v:.9} m/s (closed form -3)");
        assert!((w - 10.0).abs() < 1e-6 && (v + 3.0).abs() < 1e-6, "{wheel}: w {w}, v {v}");
    }
    // The wavy road's wheel stays on it: its centre is always the radius
    // away from the road, along the road's normal at the contact.
    let (x, y) = (s.get("wavy.x").unwrap(), s.get("wavy.y").unwrap());
    let road = |k: usize| {
        let (cx, cy) = (s.get("wavy.r_road_0[1]").unwrap()[k], s.get("wavy.r_road_0[2]").unwrap()[k]);
        ((x[k] - cx).powi(2) + (y[k] - cy).powi(2)).sqrt()
    };
    let worst = (0..x.len()).fold(0.0f64, |a, k| a.max((road(k) - 0.3).abs()));
    // The steps end on the road (projected to 1e-12), but the output grid is
    // interpolated between them at the run's tolerance, 1e-6 (Dyad's
    // default): 1e-5 m (it is 2.5e-6 m here).
    println!("wavy road: the wheel's centre is within {worst:.1e} m of the radius from the road (tolerance 1e-5)");
    assert!(worst < 1e-5, "the wavy road's wheel is {worst:e} m off its radius");
    assert!(s.get("wavy.r_road_0[2]").unwrap().iter().any(|y| y.abs() > 0.04), "the road is wavy where it ran");
}

/// The two-link arm of URDF parts, with visual-only components.
#[test]
fn urdf_arm() {
    let mut m = Model::new("UrdfArm");
    m.add("world", "World");
    m.add("shoulder", "URDFRevolute")
        .set("r", [0.0, 1.0, 0.0])
        .set("n", [1.0, 0.0, 0.0])
        .set("angle", -std::f64::consts::PI / 2.0)
        .set("joint_n", [0.0, 1.0, 0.0])
        .initial("phi", 0.8)
        .initial("w", 0.0);
    m.add("upper", "URDFBodyCylinder")
        .set("m", 2.0)
        .set("r_cm", [0.0, 0.0, -0.25])
        .set("I_11", 0.042117)
        .set("I_22", 0.042117)
        .set("I_33", 0.0009)
        .set("r_visual", [0.0, 0.0, -0.25])
        .set("length", 0.5)
        .set("radius", 0.03);
    m.add("elbow", "URDFRevolute")
        .set("r", [0.0, 0.0, -0.5])
        .set("joint_n", [0.0, 1.0, 0.0])
        .initial("phi", 0.0)
        .initial("w", 0.0);
    m.add("fore", "URDFBodyBox")
        .set("m", 1.0)
        .set("r_cm", [0.0, 0.0, -0.2])
        .set("I_11", 0.013542)
        .set("I_22", 0.013542)
        .set("I_33", 0.00041667)
        .set("r_visual", [0.0, 0.0, -0.2])
        .set("length_direction", [0.0, 0.0, 1.0])
        .set("width_direction", [1.0, 0.0, 0.0])
        .set("length", 0.4)
        .set("width", 0.05)
        .set("height", 0.05);
    m.add("damper", "RotationalComponents.Damper").set("d", 0.05);
    m.add("hand", "SphereVisualizer").set("radius", 0.04).set("r_shape", [0.0, 0.0, -0.4]);
    m.add("axes", "FrameVisualizer").set("axis_length", 0.2);
    m.connect(["world.frame_b", "shoulder.frame_a"]);
    m.connect(["shoulder.frame_b", "upper.frame_a", "elbow.frame_a"]);
    m.connect(["elbow.frame_b", "fore.frame_a", "hand.frame_a", "axes.frame_a"]);
    m.connect(["damper.spline_a", "elbow.support"]);
    m.connect(["damper.spline_b", "elbow.axis"]);
    assert_same("urdf_arm.dyad", m, options(4.0, 0.01));
}

/// The cable written in Dyad against its parts added one by one: five
/// segments on ball joints and the rod that closes the loop at the post.
#[test]
fn cable_bridge() {
    let (n, l, mass) = (6, 2.4, 6.0);
    let segment = [l / n as f64, 0.0, 0.0];
    let mut m = Model::new("CableBridge");
    m.add("world", "World");
    m.add("post", "Fixed").set("r", [2.0, 0.0, 0.0]);
    for i in 1..n {
        m.add(format!("cable.links[{i}]"), "BodyShape")
            .set("r", segment)
            .set("r_cm", segment.map(|x| x / 2.0))
            .set("m", mass / n as f64)
            .set("radius", 0.03);
    }
    for i in 1..n {
        m.add(format!("cable.joints[{i}]"), "Spherical").set("orientation_state", OrientationState::Quaternion);
    }
    m.add("cable.rod", "SphericalSpherical").set("r_0", segment).set("has_mass", true).set("m", mass / n as f64);
    m.connect(["world.frame_b", "cable.joints[1].frame_a"]);
    for i in 1..n {
        m.connect([format!("cable.joints[{i}].frame_b"), format!("cable.links[{i}].frame_a")]);
    }
    for i in 1..n - 1 {
        m.connect([format!("cable.links[{i}].frame_b"), format!("cable.joints[{}].frame_a", i + 1)]);
    }
    m.connect([format!("cable.links[{}].frame_b", n - 1), "cable.rod.frame_a".into()]);
    m.connect(["cable.rod.frame_b", "post.frame_b"]);
    assert_same("cable_bridge.dyad", m, options(3.0, 0.01));
}

#[test]
fn planar_slider_crank() {
    let mut m = Model::new("SliderCrank");
    m.add("world", "PlanarMechanics.World");
    for (name, l, mass) in [("crank", 0.5, 1.0), ("rod", 1.5, 0.5)] {
        m.add(format!("{name}.joint"), "PlanarMechanics.Revolute");
        m.add(format!("{name}.rod"), "PlanarMechanics.BodyShape")
            .set("r", [l, 0.0])
            .set("m", mass)
            .set("I", mass * l * l / 12.0);
    }
    m.add("wrist", "PlanarMechanics.Revolute");
    m.add("slide", "PlanarMechanics.Prismatic").set("r", [1.0, 0.0]);
    m.add("slider", "PlanarMechanics.Body").set("m", 2.0).set("I", 0.01);
    m.add("damper", "RotationalComponents.Damper").set("d", 0.05);
    m.add("mount", "RotationalComponents.Fixed");
    m.component_mut("crank.joint").unwrap().initial("phi", 0.0).initial("w", 2.0);
    m.connect(["world.frame_b", "crank.joint.frame_a", "slide.frame_a"]);
    m.connect(["crank.rod.frame_b", "rod.joint.frame_a"]);
    m.connect(["rod.rod.frame_b", "wrist.frame_a"]);
    m.connect(["wrist.frame_b", "slide.frame_b", "slider.frame_a"]);
    m.connect(["damper.spline_a", "mount.spline"]);
    m.connect(["damper.spline_b", "crank.joint.flange_a"]);
    for name in ["crank", "rod"] {
        m.connect([format!("{name}.joint.frame_b"), format!("{name}.rod.frame_a")]);
    }
    assert_same("PlanarMechanics/slider_crank.dyad", m, options(4.0, 0.01));
}

#[test]
fn planar_springs() {
    let mut m = Model::new("Springs");
    m.add("world", "PlanarMechanics.World");
    m.add("anchor", "PlanarMechanics.Fixed").set("r", [-1.0, 0.0]);
    m.add("spring_damper", "PlanarMechanics.SpringDamper")
        .set("c_x", 5.0)
        .set("c_y", 5.0)
        .set("c_phi", 0.0)
        .set("d_x", 1.0)
        .set("d_y", 1.0)
        .set("d_phi", 0.0);
    m.add("body", "PlanarMechanics.Body")
        .set("m", 0.5)
        .set("I", 0.1)
        .initial("r", [1.0, 1.0])
        .initial("v", [0.0, 0.0])
        .initial("phi", 0.0)
        .initial("w", 0.0);
    m.add("slide", "PlanarMechanics.Prismatic").set("r", [0.0, 1.0]).initial("s", 0.5).initial("v", 0.0);
    m.add("slider", "PlanarMechanics.Body").set("m", 1.0).set("I", 0.1);
    m.add("spring", "PlanarMechanics.Spring").set("c_x", 1.0).set("c_y", 10.0).set("s_rely0", -0.5).set("c_phi", 0.0);
    m.add("damper", "PlanarMechanics.Damper").set("d", 1.0);
    m.connect(["anchor.frame_b", "spring_damper.frame_a"]);
    m.connect(["spring_damper.frame_b", "body.frame_a"]);
    m.connect(["world.frame_b", "slide.frame_a", "spring.frame_a", "damper.frame_a"]);
    m.connect(["slide.frame_b", "slider.frame_a", "spring.frame_b", "damper.frame_b"]);
    assert_same("PlanarMechanics/springs.dyad", m, options(10.0, 0.02));
}

#[test]
fn planar_rolling_wheel() {
    let mut m = Model::new("RollingWheel");
    m.add("world", "PlanarMechanics.World");
    m.add("wheel", "PlanarMechanics.OneDOFRollingWheelJoint").set("radius", 0.3);
    m.add("hub", "PlanarMechanics.Body")
        .set("m", 2.0)
        .set("I", 0.09)
        .initial("r", [0.0, 0.3])
        .initial("v", [0.6, 0.0])
        .initial("phi", 0.0)
        .initial("w", -2.0);
    m.add("push", "PlanarMechanics.WorldForceTorque");
    m.add("force", "BlockComponents.Constant").set("k", 1.0);
    m.add("zero", "BlockComponents.Constant").set("k", 0.0);
    m.add("adapter", "PlanarMechanics.PlanarToMultiBody").set("z_position", 0.2);
    m.add("flag", "BodyBox").set("r", [0.0, 0.25, 0.0]).set("width", 0.04).set("height", 0.04);
    m.add("axes", "PlanarMechanics.FrameVisualizer2D");
    m.connect(["wheel.frame_a", "hub.frame_a", "push.frame_b", "adapter.frame_a", "axes.frame_a"]);
    m.connect(["force.y", "push.force_x"]);
    m.connect(["zero.y", "push.force_y", "push.torque"]);
    m.connect(["adapter.frame_b", "flag.frame_a"]);
    assert_same("PlanarMechanics/rolling_wheel.dyad", m, options(4.0, 0.01));
}

#[test]
fn planar_measured_pendulum() {
    let mut m = Model::new("MeasuredPendulum");
    m.add("world", "PlanarMechanics.World");
    m.add("shaker", "BlockComponents.Sine").set("amplitude", 0.2).set("frequency", 0.5);
    m.add("height", "BlockComponents.Constant").set("k", 1.0);
    m.add("support", "PlanarMechanics.PrescribedPosition");
    m.add("hinge", "PlanarMechanics.Revolute").initial("phi", -1.2).initial("w", 0.0);
    m.add("rod", "PlanarMechanics.FixedTranslation").set("r", [1.0, 0.0]);
    m.add("pull", "PlanarMechanics.CutForce").set("resolve_in_frame", multibody::Value::Enum("World".into()));
    m.add("power", "PlanarMechanics.Power");
    m.add("bob", "PlanarMechanics.Body").set("m", 1.0).set("I", 0.01);
    m.add("position", "PlanarMechanics.AbsolutePosition")
        .set("resolve_in_frame", multibody::Value::Enum("World".into()));
    m.add("speed", "PlanarMechanics.RelativeVelocity");
    m.add("distance", "PlanarMechanics.Distance");
    m.connect(["shaker.y", "support.r_x"]);
    m.connect(["height.y", "support.r_y"]);
    m.connect(["support.frame_b", "hinge.frame_a", "speed.frame_a", "distance.frame_a"]);
    m.connect(["hinge.frame_b", "rod.frame_a"]);
    m.connect(["rod.frame_b", "pull.frame_a"]);
    m.connect(["pull.frame_b", "power.frame_a"]);
    m.connect(["power.frame_b", "bob.frame_a", "position.frame_a", "speed.frame_b", "distance.frame_b"]);
    assert_same("PlanarMechanics/measured_pendulum.dyad", m, options(5.0, 0.01));
}

#[test]
fn one_way_clutch() {
    let mut m = Model::new("OneWayClutchDrive");
    m.add("motor", "RotationalComponents.Inertia").set("J", 1.0).initial("phi", 0.0).initial("w", 0.0);
    m.add("load", "RotationalComponents.Inertia").set("J", 2.0).initial("phi", 0.0).initial("w", 0.0);
    m.add("clutch", "RotationalComponents.OneWayClutch")
        .set("fn_max", 10.0)
        .set("mu_pos", multibody::Value::Matrix(vec![vec![0.0, 0.3]]));
    m.add("drive", "RotationalComponents.Torque");
    m.add("brake", "RotationalComponents.ConstantTorque").set("tau_constant", -0.5);
    m.add("swing", "BlockComponents.Sine").set("amplitude", 10.0).set("frequency", 0.5);
    m.add("press", "BlockComponents.Step").set("height", 1.0).set("start_time", 2.0);
    m.connect(["swing.y", "drive.tau"]);
    m.connect(["drive.spline", "motor.spline_a"]);
    m.connect(["motor.spline_b", "clutch.spline_a"]);
    m.connect(["clutch.spline_b", "load.spline_a"]);
    m.connect(["brake.spline", "load.spline_b"]);
    m.connect(["press.y", "clutch.f_normalized"]);
    assert_same("one_way_clutch.dyad", m, options(6.0, 0.01));
}

#[test]
fn elasto_backlash() {
    let mut m = Model::new("GearRattle");
    m.add("motor", "RotationalComponents.Inertia").set("J", 1.0).initial("phi", 0.0).initial("w", 0.0);
    m.add("load", "RotationalComponents.Inertia").set("J", 0.5).initial("phi", 0.0).initial("w", 0.0);
    m.add("backlash", "RotationalComponents.ElastoBacklash").set("c", 200.0).set("d", 2.0).set("b", 0.1);
    m.add("drive", "RotationalComponents.Torque");
    m.add("swing", "BlockComponents.Sine").set("amplitude", 5.0).set("frequency", 1.0);
    m.connect(["swing.y", "drive.tau"]);
    m.connect(["drive.spline", "motor.spline_a"]);
    m.connect(["motor.spline_b", "backlash.spline_a"]);
    m.connect(["backlash.spline_b", "load.spline_a"]);
    assert_same("elasto_backlash.dyad", m, options(3.0, 0.005));
}

#[test]
fn elasto_gap() {
    let mut m = Model::new("DroppedMass");
    m.add("mass", "TranslationalComponents.Mass")
        .set("m", 1.0)
        .set("theta", -std::f64::consts::FRAC_PI_2)
        .initial("s", 1.0)
        .initial("v", 0.0);
    m.add("stop", "TranslationalComponents.ElastoGap").set("c", 10000.0).set("d", 20.0);
    m.add("ground", "TranslationalComponents.Fixed");
    m.connect(["ground.flange", "stop.flange_a"]);
    m.connect(["stop.flange_b", "mass.flange_a"]);
    assert_same("elasto_gap.dyad", m, options(3.0, 0.002));
}

#[test]
fn mass_with_stops() {
    let mut m = Model::new("StopsAndFriction");
    m.add("block", "TranslationalComponents.MassWithStopAndFriction")
        .set("m", 1.0)
        .set("L", 0.2)
        .set("smin", -1.0)
        .set("smax", 1.0)
        .initial("s", 0.0)
        .initial("v", 0.0);
    m.add("push", "TranslationalComponents.Force");
    m.add("swing", "BlockComponents.Sine").set("amplitude", 30.0).set("frequency", 0.5);
    m.connect(["swing.y", "push.f"]);
    m.connect(["push.flange", "block.flange_a"]);
    assert_same("mass_with_stops.dyad", m, options(6.0, 0.01));
}

#[test]
fn mesh_pendulum() {
    let mut m = Model::new("MeshPendulum");
    m.add("world", "World");
    m.add("rev", "Revolute").set("n", [0.0, 0.0, 1.0]).initial("phi", 0.6).initial("w", 0.0);
    m.add("rod", "FixedTranslation").set("r", [0.0, -0.5, 0.0]);
    m.add("body", "Body").set("m", 1.0).set("r_cm", [0.0, 0.0, 0.0]).set("render", false);
    m.add("bob", "ShapefileVisualizer")
        .set("shapefile", "meshes/bob.obj")
        .set("color", [0.95, 0.55, 0.1, 1.0])
        .set("shape_scale", 1.5);
    m.connect(["world.frame_b", "rev.frame_a"]);
    m.connect(["rev.frame_b", "rod.frame_a"]);
    m.connect(["rod.frame_b", "body.frame_a", "bob.frame_a"]);
    // The string parameter reaches the shape as written.
    let (from_file, _, _) = run_file("mesh_pendulum.dyad");
    let shapes = from_file.assemble().unwrap().shapes();
    assert_eq!(shapes, m.clone().assemble().unwrap().shapes());
    let mesh = shapes.iter().find(|s| s.component == "bob").expect("bob draws a shape");
    let multibody::components::shapes::ShapeKind::Mesh { path, scale, .. } = &mesh.kind else {
        panic!("bob draws {:?}", mesh.kind)
    };
    assert_eq!((path.as_str(), *scale), ("meshes/bob.obj", 1.5));
    assert_same("mesh_pendulum.dyad", m, options(3.0, 0.01));
}

#[test]
fn every_example_is_checked() {
    let checked = [
        "pendulum.dyad",
        "double_pendulum.dyad",
        "free_body.dyad",
        "orbits.dyad",
        "spring_mass.dyad",
        "four_bar.dyad",
        "geared_servo.dyad",
        "controlled_pendulum.dyad",
        "linear_analysis.dyad",
        "stiff_spring.dyad",
        "prescribed_motion.dyad",
        "sensors.dyad",
        "urdf_arm.dyad",
        "cable_bridge.dyad",
        "wheeled_cart.dyad",
        "slipping_wheels.dyad",
        "one_way_clutch.dyad",
        "elasto_backlash.dyad",
        "elasto_gap.dyad",
        "mass_with_stops.dyad",
        "mesh_pendulum.dyad",
        "docs/annotated_swing.dyad",
        "PlanarMechanics/slider_crank.dyad",
        "PlanarMechanics/springs.dyad",
        "PlanarMechanics/rolling_wheel.dyad",
        "PlanarMechanics/measured_pendulum.dyad",
    ];
    let mut found = Vec::new();
    let mut dirs = vec![examples_dir()];
    while let Some(dir) = dirs.pop() {
        for entry in std::fs::read_dir(&dir).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                // The Modelica references, the models with equations and
                // the robot have their checks in the command's tests.
                if !["msl", "equations", "robot"].iter().any(|d| path.ends_with(d)) {
                    dirs.push(path);
                }
            } else if path.extension().is_some_and(|e| e == "dyad") {
                let relative = path.strip_prefix(examples_dir()).unwrap().to_string_lossy().replace('\\', "/");
                found.push(relative);
            }
        }
    }
    for file in &found {
        assert!(checked.contains(&file.as_str()), "examples/{file} has no hand-built twin in tests/examples.rs");
    }
    assert_eq!(found.len(), checked.len(), "an example listed here is missing: {found:?}");
}
