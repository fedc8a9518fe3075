//! Events of the model's own equations: relations watched by indicators,
//! `when` clauses with `reinit` and discrete variables, `noEvent`, each
//! checked against closed forms. Each test prints its worst error as a
//! fraction of its tolerance.

mod common;

use common::load;
use multibody::{Mechanism, SimulationOptions, Simulator};
use multibody_dyad::Package;
use std::path::Path;

fn example(relative: &str) -> (Mechanism, SimulationOptions) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples").join(relative);
    load(relative, &std::fs::read_to_string(path).unwrap())
}

#[test]
fn a_bouncing_ball_hits_the_ground_at_the_closed_form_times() {
    let (mechanism, options) = example("equations/bouncing_ball.dyad");
    let (g, e, h0) = (9.81f64, 0.8f64, 1.0f64);
    let mut sim = Simulator::new(&mechanism, &options).unwrap();
    sim.step_until(options.stop).unwrap();
    let solution = sim.solution();
    // The impacts, from the discrete variables the model keeps.
    let (count, last) = (solution.get("impacts").unwrap(), solution.get("last_impact").unwrap());
    let mut times: Vec<f64> = Vec::new();
    for (n, t) in count.iter().zip(last) {
        if *n as usize > times.len() {
            assert_eq!(*n as usize, times.len() + 1, "one impact at a time");
            times.push(*t);
        }
    }
    assert_eq!(times.len(), 10, "ten bounces before the stop");
    // Closed form: the first fall, then flights of 2 e^k v1 / g.
    let v1 = (2.0 * g * h0).sqrt();
    let mut expected = v1 / g;
    let tolerance = 1e-9;
    let mut worst = 0.0f64;
    for (k, &t) in times.iter().enumerate() {
        if k > 0 {
            expected += 2.0 * e.powi(k as i32) * v1 / g;
        }
        worst = worst.max((t - expected).abs());
    }
    // Each impact is two events: the ball goes below the ground, and
    // (just after, rising) back above it.
    println!(
        "bouncing ball: worst impact time error {worst:.2e} s = {:.2e} of {tolerance:.0e}; {} events",
        worst / tolerance,
        sim.event_count()
    );
    assert!(worst <= tolerance, "impact times off by {worst:e}");
    // Between impacts the motion is the free fall from the last one.
    let (h, time) = (solution.get("h").unwrap(), solution.time());
    let mut worst_h = 0.0f64;
    for (i, &t) in time.iter().enumerate() {
        let k = times.iter().take_while(|&&ti| ti <= t).count();
        let expected = if k == 0 {
            h0 - 0.5 * g * t * t
        } else {
            let (tk, vk) = (times[k - 1], e.powi(k as i32) * v1);
            vk * (t - tk) - 0.5 * g * (t - tk) * (t - tk)
        };
        worst_h = worst_h.max((h[i] - expected).abs());
    }
    println!("bouncing ball: worst height error {worst_h:.2e} m = {:.2e} of 1e-9", worst_h / 1e-9);
    assert!(worst_h <= 1e-9);
}

/// A mass that meets a spring which only pushes (`f = -c x` for `x < 0`),
/// arriving at speed `v0`: it moves freely to `x = 0` at `t1 = x0 / v0`,
/// half an oscillation on the spring, and leaves at `t2 = t1 + pi / w`
/// with the speed reversed. `relation` is how the force is written.
fn contact(relation: &str, abstol: f64) -> String {
    format!(
        r#"
example component Contact
  parameter m::Real = 2
  parameter c::Real = 800
  variable x::Real = initial 0.5
  variable v::Real = initial -1
  variable f::Real
relations
  der(x) = v
  m * der(v) = f
  f = {relation}
end

analysis ContactRun
  extends TransientAnalysis(stop = 1.5, saveat = 0.001, abstol = {abstol}, reltol = {abstol})
  model = Contact()
end
"#
    )
}

/// The closed form of `contact`.
fn contact_position(t: f64) -> f64 {
    let (m, c, x0, v0) = (2.0f64, 800.0f64, 0.5f64, 1.0f64);
    let w = (c / m).sqrt();
    let t1 = x0 / v0;
    let t2 = t1 + std::f64::consts::PI / w;
    if t <= t1 {
        x0 - v0 * t
    } else if t <= t2 {
        -(v0 / w) * (w * (t - t1)).sin()
    } else {
        v0 * (t - t2)
    }
}

/// The worst position error of a run of `text` against the closed form, and its number of events.
fn contact_error(text: &str) -> (f64, usize) {
    let (mechanism, options) = load("contact.dyad", text);
    let mut sim = Simulator::new(&mechanism, &options).unwrap();
    sim.step_until(options.stop).unwrap();
    let solution = sim.solution();
    let x = solution.get("x").unwrap();
    let worst = solution.time().iter().zip(x).map(|(&t, &x)| (x - contact_position(t)).abs()).fold(0.0, f64::max);
    (worst, sim.event_count())
}

#[test]
fn a_spring_that_only_pushes_switches_at_the_located_event() {
    let tolerance = 1e-7;
    for (written, relation) in [
        ("if x < 0 then -c * x else 0", "if x < 0 then -c * x else 0"),
        ("x > 0 ? 0 : -c * x", "x > 0 ? 0 : -c * x"),
        ("ifelse(x >= 0, 0, -c * x)", "ifelse(x >= 0, 0, -c * x)"),
    ] {
        let (worst, events) = contact_error(&contact(relation, 1e-8));
        let (stepped_over, none) = contact_error(&contact(&format!("noEvent({relation})"), 1e-8));
        println!(
            "contact `{written}`: worst error {worst:.2e} m = {:.2e} of {tolerance:.0e} with {events} events; \
             {stepped_over:.2e} m ({:.0}x) stepping over the switch with noEvent",
            worst / tolerance,
            stepped_over / worst.max(f64::MIN_POSITIVE)
        );
        assert!(worst <= tolerance, "{written}: {worst:e}");
        assert_eq!(events, 2, "{written}: the mass meets the spring and leaves it");
        assert_eq!(none, 0, "{written}: noEvent makes no events");
        assert!(stepped_over > 10.0 * worst, "{written}: locating the switch should matter");
    }
}

#[test]
fn relations_on_parameters_make_no_indicators() {
    let text = contact("if c > 0 then -c * x else 0", 1e-8);
    let (mechanism, options) = load("contact.dyad", &text);
    let mut sim = Simulator::new(&mechanism, &options).unwrap();
    sim.step_until(options.stop).unwrap();
    assert_eq!(sim.event_count(), 0);
}

/// The value of `name` at the end of the run of `text`, and the number of events.
fn final_values(text: &str, names: &[&str]) -> (Vec<f64>, usize) {
    let (mechanism, options) = load("model.dyad", text);
    let mut sim = Simulator::new(&mechanism, &options).unwrap();
    sim.step_until(options.stop).unwrap();
    let solution = sim.solution();
    (names.iter().map(|n| *solution.get(n).unwrap().last().unwrap()).collect(), sim.event_count())
}

#[test]
fn elsewhen_initial_and_change_follow_modelica() {
    let text = r#"
example component Modes
  variable x::Real = initial 0
  variable mode::Real = initial 0
  variable n::Real = initial 0
  variable changes::Real = initial 0
relations
  der(x) = 1
  when initial()
    mode = 5
  elsewhen x > 1
    mode = pre(mode) + 1
  end
  when x > 2
    n = pre(n) + 1
  elsewhen x > 2.5
    n = 100
  end
  when change(mode)
    changes = pre(changes) + 1
  end
end

analysis ModesRun
  extends TransientAnalysis(stop = 3, saveat = 0.5)
  model = Modes()
end
"#;
    let (values, events) = final_values(text, &["mode", "n", "changes"]);
    // mode: 5 at the start, 6 at x = 1; n: 1 at x = 2, then the second
    // branch at x = 2.5 (the first one's condition is still true: it does
    // not fire again); change(mode) is false at the start.
    assert_eq!(values, vec![6.0, 100.0, 1.0]);
    assert_eq!(events, 3);
}

#[test]
fn reinit_of_a_state_of_the_mechanics() {
    // A pendulum falling from the horizontal bounces elastically off a stop
    // at -0.5 rad: it swings back up to the horizontal (energy is kept).
    let text = r#"
example component Stop
  world = MultibodyComponents.World()
  rev = MultibodyComponents.Revolute(n = [0, 0, 1], phi(initial = 0), w(initial = 0))
  body = MultibodyComponents.Body(m = 1, r_cm = [0.5, 0, 0])
relations
  connect(world.frame_b, rev.frame_a)
  connect(rev.frame_b, body.frame_a)
  when rev.phi < -0.5
    reinit(rev.w, -pre(rev.w))
  end
end

analysis StopRun
  extends TransientAnalysis(stop = 1.5, saveat = 0.001, abstol = 1e-10, reltol = 1e-10)
  model = Stop()
end
"#;
    let (mechanism, options) = load("stop.dyad", text);
    let mut sim = Simulator::new(&mechanism, &options).unwrap();
    sim.step_until(options.stop).unwrap();
    let phi = sim.solution().get("rev.phi").unwrap();
    let lowest = phi.iter().copied().fold(f64::INFINITY, f64::min);
    let highest_after = phi[phi.len() / 2..].iter().copied().fold(f64::NEG_INFINITY, f64::max);
    // Never above the horizontal, and back to it (to what the 1 ms grid
    // shows of the turning point: 0.5 (g / r) (0.5 ms)^2 = 2.5e-6 rad).
    let tolerance = 1e-8;
    let (through, above) = ((-0.5 - lowest).max(0.0), highest_after.max(0.0));
    println!(
        "pendulum on a stop: through the stop by {through:.2e} rad = {:.2e} of {tolerance:.0e}, above the start by \
         {above:.2e} rad = {:.2e} of {tolerance:.0e}; back up to {highest_after:.2e}; {} events",
        through / tolerance,
        above / tolerance,
        sim.event_count()
    );
    assert!(through <= tolerance, "it goes through the stop: {lowest}");
    assert!(above <= tolerance && highest_after >= -1e-5, "it swings back up to {highest_after}");
    assert!(sim.event_count() >= 2);
}

/// Past the time at which its bounces pile up (t = 4.06 s for e = 0.8), the
/// ball's events come closer and closer: the run stops with a message that
/// names the indicator, keeping what it computed, instead of hanging.
#[test]
fn bounces_that_pile_up_stop_the_run_with_a_clear_message() {
    let (mechanism, mut options) = example("equations/bouncing_ball.dyad");
    options.stop = 6.0;
    let (g, e, h0) = (9.81f64, 0.8f64, 1.0f64);
    let t_first = (2.0 * h0 / g).sqrt();
    let t_zeno = t_first + 2.0 * e * (g * t_first) / (g * (1.0 - e));
    let error = mechanism.simulate(&options).expect_err("the events pile up");
    println!("{error}");
    assert!(error.reason.contains("pile up") && error.reason.contains("relation"), "{}", error.reason);
    assert!((error.time - t_zeno).abs() < 1e-3, "stopped at {} (bounces pile up at {t_zeno})", error.time);
    assert!(error.partial.time().last().is_some_and(|&t| t > 4.0), "the samples before are kept");
}

/// A torque that is +1 while `sin(2 pi 1000 t) > 0` and -1 otherwise, on
/// a unit inertia: the speed is a triangle wave that is 0 at every whole
/// millisecond, the angle gains 2.5e-7 rad per period (exactly 5e-4 after
/// 2 s). Between events the relation holds its value, so nothing in the
/// derivatives bounds the steps: they grew past whole periods, their ends
/// agreed, and the run ended at w = 0.987 without a word. The stages that
/// saw the other sign now find the crossings, and the steps are held short.
#[test]
fn a_relation_that_swings_faster_than_the_steps_is_followed() {
    let (mechanism, options) = load(
        "square.dyad",
        r#"
example component SquareTorque
  inertia = RotationalComponents.Inertia(J = 1)
  torque = RotationalComponents.Sources.Torque()
  u = RealOutput()
relations
  u = if sin(2 * pi * 1000 * time) > 0 then 1 else -1
  connect(u, torque.tau)
  connect(torque.spline, inertia.spline_a)
end
analysis SquareRun
  extends TransientAnalysis(stop = 2, saveat = 0.1)
  model = SquareTorque()
end
"#,
    );
    let solution = mechanism.simulate(&options).unwrap();
    let (w, phi) = (solution.get("inertia.w").unwrap(), solution.get("inertia.phi").unwrap());
    // Every 0.1 s is a whole number of periods: w = 0, phi = 2.5e-7 per period.
    for (&t, (&w, &phi)) in solution.time().iter().zip(w.iter().zip(phi)) {
        let periods = (t * 1000.0).round();
        assert!(w.abs() < 1e-9, "w = {w} at t = {t} (0 at whole periods)");
        assert!((phi - 2.5e-7 * periods).abs() < 1e-9, "phi = {phi} at t = {t}, {} expected", 2.5e-7 * periods);
    }
    assert!(
        solution.warnings().iter().any(|w| w.contains("changed sign and back within one step")),
        "the run says why its steps are short: {:?}",
        solution.warnings()
    );
}

/// `sample(start, interval)` in a `when`: a zero-order hold of `sin(time)`
/// at 0.1, 0.35, 0.6, 0.85 s, fired once at each instant (time events), and
/// the integral of the held value against its closed form.
#[test]
fn sample_holds_a_signal_at_its_instants() {
    let (mechanism, options) = load(
        "sample.dyad",
        r#"
example component Held
  variable u::Real = initial 0
  variable ticks::Real = initial 0
  variable last::Real = initial -1
  variable x::Real = initial 0
relations
  der(x) = u
  when sample(0.1, 0.25)
    u = sin(time)
    ticks = pre(ticks) + 1
    last = time
  end
end
analysis HeldRun
  extends TransientAnalysis(stop = 1, saveat = 0.01, abstol = 1e-10, reltol = 1e-10)
  model = Held()
end
"#,
    );
    let mut sim = Simulator::new(&mechanism, &options).unwrap();
    sim.step_until(1.0).unwrap();
    let instants = [0.1f64, 0.35, 0.6, 0.85];
    assert_eq!(sim.value("ticks"), Ok(4.0), "one firing per instant");
    assert_eq!(sim.value("last"), Ok(0.85), "the last instant, exactly");
    assert_eq!(sim.value("u"), Ok(0.85f64.sin()));
    // x(1) = sum of sin(t_k) times how long each value is held.
    let exact: f64 = instants.iter().zip([0.35, 0.6, 0.85, 1.0]).map(|(t, end)| t.sin() * (end - *t)).sum();
    let error = (sim.value("x").unwrap() - exact).abs();
    println!("sampled hold: x(1) error {error:.2e} (tolerance 1e-9: {:.3})", error / 1e-9);
    assert!(error <= 1e-9);
    // Between instants the held value does not move.
    let solution = sim.solution();
    let (time, u) = (solution.time(), solution.get("u").unwrap());
    for (t, u) in time.iter().zip(u) {
        let held = instants.iter().rev().find(|&&s| s < *t - 1e-12).map_or(0.0, |s| s.sin());
        assert!(
            (u - held).abs() < 1e-15 || instants.iter().any(|s| (s - t).abs() < 1e-12),
            "u({t}) = {u}, held {held}"
        );
    }
}

/// `sample` needs fixed instants: an interval that is not positive, not
/// finite (0/0), or that changes, is an error at its argument.
#[test]
fn sample_with_a_bad_interval_is_refused() {
    for (interval, expected) in [
        ("0", "must be positive"),
        ("x", "must be a number or a parameter"),
        ("0 / 0", "the interval of `sample` is NaN, not a finite number"),
    ] {
        let text = format!(
            "example component Bad\n  variable x::Real = initial 0\n  variable n::Real = initial 0\nrelations\n  der(x) = 1\n  when sample(0, {interval})\n    n = pre(n) + 1\n  end\nend\n"
        );
        let mut package = Package::new();
        package.add_source("bad.dyad", text).unwrap();
        let message = match package.lower_component("Bad") {
            Err(d) => d.render(package.sources(), false),
            Ok(_) => panic!("accepted"),
        };
        assert!(message.contains(expected) && message.contains("bad.dyad:6:"), "{message}");
    }
}

/// Events that pile up said "a source's switching time" or "a bounce" for
/// what a user wrote wrong: a `sample` whose interval the time cannot tell
/// apart now names it, and a `reinit` to NaN is named as such at once.
#[test]
fn a_sample_too_fine_and_a_reinit_to_nan_are_named() {
    let run = |body: &str| {
        let text = format!(
            "example component Ev\n  variable x::Real = initial 0\n  variable n::Real = initial 0\nrelations\n  \
             der(x) = 1\n{body}\nend\n\nanalysis EvRun\n  extends TransientAnalysis(stop = 2, saveat = 0.1)\n  model = Ev()\nend\n"
        );
        let (mechanism, options) = load("ev.dyad", &text);
        mechanism.simulate(&options).unwrap_err()
    };
    let stopped = run("  when sample(0, 1e-300)\n    n = pre(n) + 1\n  end");
    let message = stopped.to_string();
    assert!(message.contains("at `sample(0, 1e-300)`: its instants come every 1e-300 s"), "{message}");
    let stopped = run("  when x > 1\n    reinit(x, 0 / 0)\n    n = 1\n  end");
    let message = stopped.to_string();
    assert!(message.contains("a `reinit` of `x`") && message.contains("gives it NaN"), "{message}");
    assert!((stopped.time - 1.0).abs() < 1e-9, "stopped at {}", stopped.time);
}
