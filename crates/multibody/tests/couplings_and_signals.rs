//! Couplings of joint coordinates (an ideal gear between two revolutes) and
//! signals that depend on the state (sensors feeding a controller that
//! drives a joint), against closed forms.

use multibody::{Error, Model, SimulationOptions};

fn tight(stop: f64) -> SimulationOptions {
    SimulationOptions { stop, saveat: 0.05, abstol: 1e-11, reltol: 1e-11, ..Default::default() }
}

/// A revolute about the world's y axis, parallel to gravity, so gravity
/// exerts no torque about it, carrying a body whose inertia about the axis
/// is `i_22 + m x^2`.
fn turntable(model: &mut Model, joint: &str, body: &str, m: f64, x: f64, i_22: f64) {
    model.add(joint, "Revolute").set("n", [0.0, 1.0, 0.0]);
    model.add(body, "Body").set("m", m).set("r_cm", [x, 0.0, 0.0]).set("I_22", i_22);
    model.connect(["world.frame_b", &format!("{joint}.frame_a")]);
    model.connect([format!("{joint}.frame_b"), format!("{body}.frame_a")]);
}

/// Two turntables coupled by a gear `phi_1 = ratio phi_2`, the first driven
/// by a constant torque: one degree of freedom with the inertia
/// `J1 + J2 / ratio^2` seen from the first, so `phi_1 = tau t^2 / (2 J)`.
#[test]
fn an_ideal_gear_couples_two_revolutes_with_the_reflected_inertia() {
    let (tau, ratio) = (1.5, 2.5);
    let (j1, j2) = (0.01 + 1.0 * 0.5f64.powi(2), 0.02 + 2.0 * 0.3f64.powi(2));
    let mut model = Model::new("geared");
    model.add("world", "World");
    turntable(&mut model, "rev1", "body1", 1.0, 0.5, 0.01);
    turntable(&mut model, "rev2", "body2", 2.0, 0.3, 0.02);
    model.add("gear", "RotationalComponents.IdealGear").set("ratio", ratio);
    model.add("motor", "RotationalComponents.ConstantTorque").set("tau_constant", tau);
    model.connect(["gear.spline_a", "rev1.axis"]);
    model.connect(["gear.spline_b", "rev2.axis"]);
    model.connect(["motor.spline", "rev1.axis"]);
    model.connect(["motor.support", "rev1.support"]);
    let mechanism = model.assemble().unwrap();
    assert_eq!(mechanism.degrees_of_freedom(), 1);
    assert!(mechanism.loops().is_empty(), "a coupling is not a kinematic loop");

    let solution = mechanism.simulate(&tight(1.0)).unwrap();
    let j = j1 + j2 / (ratio * ratio);
    let (time, phi1, phi2) = (solution.time(), solution.get("rev1.phi").unwrap(), solution.get("rev2.phi").unwrap());
    let mut worst = 0.0f64;
    for k in 0..time.len() {
        let expected = tau * time[k] * time[k] / (2.0 * j);
        worst = worst.max((phi1[k] - expected).abs()).max((phi1[k] - ratio * phi2[k]).abs());
    }
    assert!(worst < 1e-9, "worst error {worst:e} rad");
    // The gear reports the angles it relates, and the torque it puts on the
    // driven joint accelerates that joint's body: tau_2 = J2 phi_2''.
    let phi_a = solution.last("gear.phi_a").unwrap();
    let phi_b = solution.last("gear.phi_b").unwrap();
    assert!((phi_a - ratio * phi_b).abs() < 1e-9);
    // Every constraint row has its named residual column, the gear's too.
    let residual = solution.get("gear.constraint_residual[1]").expect("the gear's residual is an output");
    assert!(residual.iter().all(|r| r.abs() < 1e-9));
    assert_eq!(mechanism.signals().len(), solution.names().len());
    let tau2 = solution.last("rev2.tau").unwrap();
    assert!((tau2 - j2 * tau / j / ratio).abs() < 1e-8, "rev2.tau = {tau2}");
}

/// A gear between a joint and a fixed housing locks the joint.
#[test]
fn a_gear_whose_other_side_is_fixed_holds_its_joint() {
    let mut model = Model::new("locked");
    model.add("world", "World");
    turntable(&mut model, "rev", "body", 1.0, 0.5, 0.01);
    model.add("gear", "RotationalComponents.IdealGear").set("ratio", 3.0);
    model.add("fixed", "RotationalComponents.ConstantTorque").set("tau_constant", 2.0);
    model.connect(["gear.spline_a", "rev.axis"]);
    model.connect(["gear.spline_b", "gear.support", "rev.support"]);
    model.connect(["fixed.spline", "rev.axis"]);
    model.connect(["fixed.support", "rev.support"]);
    let mechanism = model.assemble().unwrap();
    assert_eq!(mechanism.degrees_of_freedom(), 0);
    let solution = mechanism.simulate(&tight(0.5)).unwrap();
    assert!(solution.get("rev.phi").unwrap().iter().all(|p| p.abs() < 1e-12));
    // The gear holds the driving torque.
    assert!((solution.last("rev.tau").unwrap()).abs() < 1e-9);
}

/// A PD controller built from sensors and blocks: `tau = -kp phi - kd w`
/// on an inertia J gives the damped oscillator
/// `phi = e^(-zeta wn t) (cos wd t + zeta wn / wd sin wd t)` from `phi(0) = 1`.
#[test]
fn sensors_feed_a_pd_controller_that_drives_the_joint() {
    let (kp, kd) = (4.0, 0.4);
    let j = 0.01 + 1.0 * 0.25;
    let mut model = Model::new("pd");
    model.add("world", "World");
    turntable(&mut model, "rev", "body", 1.0, 0.5, 0.01);
    model.component_mut("rev").unwrap().initial("phi", 1.0).initial("w", 0.0);
    // Declared before the blocks it reads: the evaluation order is found, not given.
    model.add("sum", "BlockComponents.Add").set("k1", -kp).set("k2", -kd);
    model.add("angle", "RotationalComponents.AngleSensor");
    model.add("speed", "RotationalComponents.SpeedSensor");
    model.add("motor", "RotationalComponents.Sources.Torque");
    model.connect(["angle.spline", "speed.spline", "motor.spline", "rev.axis"]);
    model.connect(["motor.support", "rev.support"]);
    model.connect(["angle.phi", "sum.u1"]);
    model.connect(["speed.w", "sum.u2"]);
    model.connect(["sum.y", "motor.tau"]);
    let mechanism = model.assemble().unwrap();

    let solution = mechanism.simulate(&tight(5.0)).unwrap();
    let wn = (kp / j).sqrt();
    let zeta = kd / (2.0 * (kp * j).sqrt());
    let wd = wn * (1.0 - zeta * zeta).sqrt();
    let phi = solution.get("rev.phi").unwrap();
    let mut worst = 0.0f64;
    for (k, &t) in solution.time().iter().enumerate() {
        let expected = (-zeta * wn * t).exp() * ((wd * t).cos() + zeta * wn / wd * (wd * t).sin());
        worst = worst.max((phi[k] - expected).abs());
    }
    assert!(worst < 1e-8, "worst error {worst:e} rad");
    // The blocks report what they computed.
    let (y, angle, speed) =
        (solution.last("sum.y").unwrap(), solution.last("angle.phi").unwrap(), solution.last("speed.w").unwrap());
    assert_eq!(y, -kp * angle - kd * speed);
    assert_eq!(solution.last("motor.tau").unwrap(), y);
}

/// Two gains feeding each other at the same instant: an algebraic loop,
/// reported with the blocks in it.
#[test]
fn a_loop_of_gains_is_an_algebraic_loop() {
    let mut model = Model::new("loop");
    model.add("world", "World");
    model.add("g1", "BlockComponents.Gain").set("k", 2.0);
    model.add("g2", "BlockComponents.Gain").set("k", 0.5);
    model.add("g3", "BlockComponents.Gain").set("k", 1.0);
    model.connect(["g1.y", "g2.u"]);
    model.connect(["g2.y", "g1.u", "g3.u"]);
    match model.assemble() {
        Err(Error::AlgebraicLoop { components }) => {
            let mut components = components;
            components.sort();
            assert_eq!(components, ["g1", "g2"]);
        }
        other => panic!("expected an algebraic loop, got {other:?}"),
    }
}
