//! The Simulator: a model advanced on request while the host sets its
//! inputs and reads or sets its state.

use multibody::{Model, SimulationOptions, Simulator};

/// A pendulum: a 1 kg body 0.5 m from a revolute about z, from 0.3 rad.
fn pendulum() -> Model {
    let mut model = Model::new("pendulum");
    model.add("world", "World");
    model.add("rev", "Revolute").set("n", [0.0, 0.0, 1.0]).initial("phi", 0.3);
    model.add("body", "Body").set("m", 1.0).set("r_cm", [0.5, 0.0, 0.0]);
    model.connect(["world.frame_b", "rev.frame_a"]);
    model.connect(["rev.frame_b", "body.frame_a"]);
    model
}

/// A free inertia (J = 2) turned by a torque the host sets: the input `tau`.
fn driven_inertia() -> Model {
    let mut model = Model::new("driven");
    model.add("tau", "Input");
    model.add("motor", "RotationalComponents.Torque");
    model.add("inertia", "RotationalComponents.Inertia").set("J", 2.0);
    model.connect(["tau.y", "motor.tau"]);
    model.connect(["motor.spline", "inertia.spline_a"]);
    model.outputs = vec!["inertia.w".into()];
    model
}

#[test]
fn many_small_steps_give_the_samples_of_one_run() {
    let mechanism = pendulum().assemble().unwrap();
    let options = SimulationOptions { stop: 2.0, saveat: 0.01, abstol: 1e-12, reltol: 1e-12, ..Default::default() };
    let once = mechanism.simulate(&options).unwrap();
    let mut sim = Simulator::new(&mechanism, &options).unwrap();
    // Steps of 3 ms: off the output grid, so samples fall inside steps and on their ends.
    let mut k = 0;
    while sim.time() < options.stop {
        k += 1;
        sim.step_until((k as f64 * 0.003).min(options.stop)).unwrap();
    }
    assert_eq!(sim.time(), options.stop);
    // Calls shorter than the steps cost no more steps: the integration goes
    // on past the time asked for and reads the state there on its step.
    let mut one = Simulator::new(&mechanism, &options).unwrap();
    one.step_until(options.stop).unwrap();
    let (steps, steps_once) = (sim.stats().accepted, one.stats().accepted);
    assert!(steps <= steps_once + 1, "{steps} steps in {k} calls, {steps_once} in one");
    let stepped = sim.solution();
    assert_eq!(stepped.time(), once.time(), "the same output grid");
    let mut worst = 0.0f64;
    for name in ["rev.phi", "rev.w", "body.r_0[1]", "body.r_0[2]", "body.v_0[1]"] {
        let (a, b) = (stepped.get(name).unwrap(), once.get(name).unwrap());
        for (x, y) in a.iter().zip(b) {
            worst = worst.max((x - y).abs());
        }
    }
    println!(
        "{k} calls of step_until ({steps} steps) against one simulate() ({steps_once} steps): worst difference \
         {worst:.2e} (tolerance 1e-9)"
    );
    assert!(worst < 1e-9, "worst difference {worst:e}");
}

#[test]
fn a_torque_set_by_the_host_turns_a_free_inertia_as_the_closed_form_says() {
    let mechanism = driven_inertia().assemble().unwrap();
    assert_eq!(mechanism.input_names(), ["tau"]);
    let options = SimulationOptions { stop: 2.0, saveat: 0.1, abstol: 1e-12, reltol: 1e-12, ..Default::default() };
    let mut sim = Simulator::new(&mechanism, &options).unwrap();
    let (j, tau) = (2.0, 3.0);
    sim.set_input("tau", tau).unwrap();
    assert_eq!(sim.input("tau").unwrap(), tau);
    sim.step_until(1.0).unwrap();
    // phi = tau t^2 / 2J, w = tau t / J
    let phi1 = tau / (2.0 * j);
    let w1 = tau / j;
    let err1 = (sim.state_value("inertia.phi").unwrap() - phi1).abs();
    assert!(err1 < 1e-10, "phi(1) off by {err1:e}");
    assert!((sim.value("inertia.w").unwrap() - w1).abs() < 1e-10);
    assert_eq!(sim.outputs().unwrap(), vec![("inertia.w".to_string(), sim.value("inertia.w").unwrap())]);
    // The opposite torque from t = 1: phi = phi1 + w1 (t - 1) - tau (t - 1)^2 / 2J.
    sim.set_input("tau", -tau).unwrap();
    sim.step_until(2.0).unwrap();
    let phi2 = phi1 + w1 - tau / (2.0 * j);
    let err2 = (sim.state_value("inertia.phi").unwrap() - phi2).abs();
    assert!(err2 < 1e-10, "phi(2) off by {err2:e}");
    // The recorded samples follow the same closed form.
    let solution = sim.solution();
    let phi = solution.get("inertia.phi").unwrap();
    for (&t, &x) in solution.time().iter().zip(phi) {
        let exact = if t <= 1.0 {
            tau * t * t / (2.0 * j)
        } else {
            phi1 + w1 * (t - 1.0) - tau * (t - 1.0).powi(2) / (2.0 * j)
        };
        assert!((x - exact).abs() < 1e-10, "phi({t}) = {x}, closed form {exact}");
    }
    assert_eq!(solution.get("tau").unwrap().last(), Some(&-tau));
    println!("free inertia under a host's torque: phi(1) off by {err1:.1e}, phi(2) by {err2:.1e} (tolerance 1e-10)");
}

#[test]
fn set_state_and_reset() {
    let mechanism = driven_inertia().assemble().unwrap();
    let options = SimulationOptions { stop: 1.0, saveat: 0.1, abstol: 1e-12, reltol: 1e-12, ..Default::default() };
    let mut sim = Simulator::new(&mechanism, &options).unwrap();
    assert_eq!(sim.state_names(), ["inertia.phi", "inertia.w"]);
    // Spinning at 2 rad/s from phi = 1, no torque: phi = 1 + 2 t.
    sim.set_state(&[1.0, 2.0]).unwrap();
    sim.step_until(0.5).unwrap();
    assert!((sim.state()[0] - 2.0).abs() < 1e-12, "{:?}", sim.state());
    sim.set_state_value("inertia.w", 0.0).unwrap();
    sim.step_until(1.0).unwrap();
    assert!((sim.state()[0] - 2.0).abs() < 1e-12 && sim.state()[1] == 0.0, "{:?}", sim.state());
    sim.set_input("tau", 5.0).unwrap();
    sim.step_until(1.5).unwrap();
    assert!(sim.state()[1] > 0.0);
    // Back to the start: time, state, inputs; no samples.
    sim.reset().unwrap();
    assert_eq!(sim.time(), 0.0);
    assert_eq!(sim.state(), [0.0, 0.0]);
    assert_eq!(sim.input("tau").unwrap(), 0.0);
    assert!(sim.solution().is_empty());
    sim.step_until(1.0).unwrap();
    assert_eq!(sim.state(), [0.0, 0.0], "no torque after the reset");
    assert_eq!(sim.solution().len(), 11);
}

/// Asked for an earlier time, the simulator says it steps forward only
/// (it did nothing without a word, and a host went on as if it stood
/// there), and stays where it was.
#[test]
fn stepping_back_is_refused_and_the_simulator_stays() {
    let mechanism = driven_inertia().assemble().unwrap();
    let options = SimulationOptions { stop: 1.0, saveat: 0.1, ..Default::default() };
    let mut sim = Simulator::new(&mechanism, &options).unwrap();
    sim.set_state(&[0.0, 2.0]).unwrap();
    sim.step_until(0.5).unwrap();
    let (state, samples) = (sim.state().to_vec(), sim.solution().len());
    let e = sim.step_until(0.2).unwrap_err();
    assert!(e.reason.contains("stands at t = 0.5") && e.reason.contains("forward only"), "{}", e.reason);
    assert_eq!((sim.time(), sim.state(), sim.solution().len()), (0.5, &state[..], samples));
    // The same time again is no step at all, and no error.
    sim.step_until(0.5).unwrap();
}

#[test]
fn bad_names_say_what_was_meant() {
    let mechanism = driven_inertia().assemble().unwrap();
    let mut sim = Simulator::new(&mechanism, &SimulationOptions::until(1.0)).unwrap();
    let e = sim.set_input("tua", 1.0).unwrap_err();
    assert!(e.contains("did you mean `tau`") && e.contains("its inputs: tau"), "{e}");
    let e = sim.set_input("tau", f64::NAN).unwrap_err();
    assert!(e.contains("must be finite"), "{e}");
    let e = sim.state_value("inertia.ph").unwrap_err();
    assert!(e.contains("did you mean `inertia.phi`"), "{e}");
    let e = sim.set_state_value("inertia.v", 1.0).unwrap_err();
    assert!(e.contains("did you mean `inertia.w`"), "{e}");
    let e = sim.value("inertia.phl").unwrap_err();
    assert!(e.contains("did you mean `inertia.phi`"), "{e}");
    let e = sim.set_state(&[1.0]).unwrap_err();
    assert!(e.contains("2 values"), "{e}");
    let e = sim.step_until(f64::NAN).unwrap_err();
    assert!(e.reason.contains("cannot step until"), "{}", e.reason);
    // A model without inputs says how to make one.
    let pendulum = pendulum().assemble().unwrap();
    let mut sim = Simulator::new(&pendulum, &SimulationOptions::until(1.0)).unwrap();
    let e = sim.set_input("tau", 1.0).unwrap_err();
    assert!(e.contains("has no inputs") && e.contains("RealInput"), "{e}");
    println!("{e}");
}
