//! Friction with modes against closed forms: a block sliding against
//! Coulomb friction stops at the time the deceleration gives and stays
//! stuck; a force ramp breaks a stuck block away when it passes the
//! holding force, and the block then moves as Newton's law says.

use multibody::{Model, SimulationOptions, Simulator};

const M: f64 = 2.0;
/// Sliding friction (N) and the holding force's ratio to it.
const F_SLIDE: f64 = 5.0;
const PEAK: f64 = 1.2;

/// A block of mass M on a support with Coulomb friction, pushed by the
/// force `push` (a BlockComponents source of kind and parameters given).
fn block(v0: f64, push: (&str, &[(&str, f64)])) -> Model {
    let mut model = Model::new("block");
    model.add("mass", "TranslationalComponents.Mass").set("m", M).initial("s", 0.0).initial("v", v0);
    model
        .add("friction", "TranslationalComponents.SupportFriction")
        .set("f_pos", multibody::Value::Matrix(vec![vec![0.0, F_SLIDE]]))
        .set("peak", PEAK);
    let source = model.add("push", push.0);
    for &(name, value) in push.1 {
        source.set(name, value);
    }
    model.add("force", "TranslationalComponents.Force");
    model.connect(["mass.flange_b", "friction.flange_a"]);
    model.connect(["force.flange", "mass.flange_a"]);
    model.connect(["push.y", "force.f"]);
    model
}

fn options(stop: f64) -> SimulationOptions {
    SimulationOptions { stop, abstol: 1e-10, reltol: 1e-10, saveat: 0.01, ..Default::default() }
}

#[test]
fn a_sliding_block_stops_when_friction_has_taken_its_speed_and_stays() {
    // Pushed forward with 2 N against 5 N of friction: a = -3/M until it stops.
    let (v0, push) = (3.0, 2.0);
    let model = block(v0, ("BlockComponents.Constant", &[("k", push)]));
    let mechanism = model.assemble().unwrap();
    let mut sim = Simulator::new(&mechanism, &options(5.0)).unwrap();
    let a = (push - F_SLIDE) / M;
    let t_stop = -v0 / a;
    sim.step_until(t_stop - 0.1).unwrap();
    assert_eq!(sim.event_count(), 0, "no event while it slides");
    sim.step_until(5.0).unwrap();
    let (t_event, why) = sim.last_event().expect("it stops with an event");
    let error = (t_event - t_stop).abs();
    println!("stop at {t_event} against {t_stop}: {error:.2e} (tolerance 1e-9, {:.3} of it); {why:?}", error / 1e-9);
    assert!(error < 1e-9, "stopped at {t_event}, not {t_stop}");
    // Stuck from then on: the push (2 N) is below the holding force (6 N).
    // Bounded events: the stop, and the pass that locks it.
    assert!(sim.event_count() <= 2, "{} events", sim.event_count());
    let s_stop = v0 * t_stop + 0.5 * a * t_stop * t_stop;
    let solution = sim.solution();
    for (k, &t) in solution.time().iter().enumerate() {
        let (s, v) = (solution.get("mass.s").unwrap()[k], solution.get("mass.v").unwrap()[k]);
        let (s_exact, v_exact) = if t < t_stop { (v0 * t + 0.5 * a * t * t, v0 + a * t) } else { (s_stop, 0.0) };
        assert!((s - s_exact).abs() < 1e-8 && (v - v_exact).abs() < 1e-8, "t = {t}: s {s} v {v}");
        if t > t_stop {
            assert_eq!(solution.get("friction.mode").unwrap()[k], 0.0, "stuck at t = {t}");
            assert_eq!(solution.get("friction.locked").unwrap()[k], 1.0);
            // Held by exactly the push.
            assert!((solution.get("friction.f").unwrap()[k] - push).abs() < 1e-9);
        }
    }
}

#[test]
fn a_growing_push_breaks_a_stuck_block_away_at_the_holding_force() {
    // F = 2 t from rest: stuck until F = PEAK F_SLIDE = 6 N at t = 3, then
    // M a = 2 t - F_SLIDE.
    let ramp = [("height", 20.0), ("duration", 10.0)];
    let model = block(0.0, ("BlockComponents.Ramp", &ramp));
    let mechanism = model.assemble().unwrap();
    let mut sim = Simulator::new(&mechanism, &options(5.0)).unwrap();
    sim.step_until(2.9).unwrap();
    assert_eq!(sim.state_value("mass.v").unwrap(), 0.0, "held while the push is below 6 N");
    sim.step_until(3.5).unwrap();
    let (t_away, _) = sim.last_event().unwrap();
    let t_break = PEAK * F_SLIDE / 2.0;
    println!("breaks away at {t_away} against {t_break}: {:.2e}", (t_away - t_break).abs());
    assert!((t_away - t_break).abs() < 1e-9);
    sim.step_until(5.0).unwrap();
    let v = |t: f64| ((t * t - t_break * t_break) - F_SLIDE * (t - t_break)) / M;
    let error = (sim.state_value("mass.v").unwrap() - v(5.0)).abs();
    println!("speed at 5 s: error {error:.2e} (tolerance 1e-8)");
    assert!(error < 1e-8);
    assert_eq!(sim.value("friction.mode").unwrap(), 1.0, "sliding forward");
}

#[test]
fn bearing_friction_on_a_revolute_axis_stops_a_spinning_body() {
    // A body spinning about the vertical axis of a revolute (gravity along
    // the axis does no work) with 0.3 N.m of bearing friction: it stops at
    // t = J w0 / tau, having turned J w0^2 / (2 tau).
    let (j, w0, tau) = (0.4, 2.0, 0.3);
    let mut model = Model::new("spinning");
    model.add("world", "World");
    model.add("rev", "Revolute").set("n", [0.0, 1.0, 0.0]).set("axisflange", true).initial("phi", 0.0).initial("w", w0);
    model.add("body", "Body").set("m", 1.0).set("I_22", j).set("r_cm", [0.0, 0.0, 0.0]);
    model
        .add("bearing", "RotationalComponents.BearingFriction")
        .set("tau_pos", multibody::Value::Matrix(vec![vec![0.0, tau]]));
    model.connect(["world.frame_b", "rev.frame_a"]);
    model.connect(["rev.frame_b", "body.frame_a"]);
    model.connect(["bearing.spline_a", "rev.axis"]);
    model.connect(["bearing.support", "rev.support"]);
    let mechanism = model.assemble().unwrap();
    let mut sim = Simulator::new(&mechanism, &options(3.0)).unwrap();
    sim.step_until(3.0).unwrap();
    let (t_stop, _) = sim.last_event().unwrap();
    let errors =
        [(t_stop - j * w0 / tau).abs(), (sim.state_value("rev.phi").unwrap() - j * w0 * w0 / (2.0 * tau)).abs()];
    println!("stop time and angle: errors {errors:?} (tolerance 1e-9)");
    assert!(errors.iter().all(|e| *e < 1e-9), "{errors:?}");
    assert_eq!(sim.state_value("rev.w").unwrap().abs(), 0.0);
}
