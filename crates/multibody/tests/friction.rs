//! Friction with modes against closed forms: a block sliding against
//! Coulomb friction stops at the time the deceleration gives and stays
//! stuck; a force ramp breaks a stuck block away when it passes the
//! holding force, and the block then moves as Newton's law says; a one-way
//! clutch drives its load forward only; a mass with stops stops dead at
//! them at the times its friction law gives, and Stribeck's curve stops a
//! mass at the time its integral gives.

use multibody::{Model, SimulationOptions, Simulator};
use std::f64::consts::PI;

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

/// A driving inertia `a` (J_A) and a load `b` (J_B) joined by a one-way
/// clutch (b may overrun a, never lag behind it) with sliding torque
/// `TAU_F * engaged` while b overruns. The torque on a is 1 N.m, then -1
/// from t = 1, then 2 from t = 2.5.
const J_A: f64 = 1.0;
const J_B: f64 = 2.0;
const TAU_F: f64 = 0.3;

fn one_way_drive(engaged: f64) -> Model {
    let mut model = Model::new("freewheel");
    model.add("a", "RotationalComponents.Inertia").set("J", J_A).initial("phi", 0.0).initial("w", 0.0);
    model.add("b", "RotationalComponents.Inertia").set("J", J_B).initial("phi", 0.0).initial("w", 0.0);
    model
        .add("clutch", "RotationalComponents.OneWayClutch")
        .set("fn_max", 1.0)
        .set("mu_pos", multibody::Value::Matrix(vec![vec![0.0, TAU_F]]));
    model.add("engage", "BlockComponents.Constant").set("k", engaged);
    model.add("step1", "BlockComponents.Step").set("height", -2.0).set("offset", 1.0).set("start_time", 1.0);
    model.add("step2", "BlockComponents.Step").set("height", 3.0).set("start_time", 2.5);
    model.add("torque1", "RotationalComponents.Torque");
    model.add("torque2", "RotationalComponents.Torque");
    model.connect(["a.spline_b", "clutch.spline_a"]);
    model.connect(["clutch.spline_b", "b.spline_a"]);
    model.connect(["engage.y", "clutch.f_normalized"]);
    model.connect(["step1.y", "torque1.tau"]);
    model.connect(["step2.y", "torque2.tau"]);
    model.connect(["torque1.spline", "torque2.spline", "a.spline_a"]);
    model
}

/// The speeds `(w_a, w_b)` of [`one_way_drive`] at time `t`, and the time
/// the clutch locks again.
fn one_way_speeds(engaged: f64, t: f64) -> ((f64, f64), f64) {
    let tau = TAU_F * engaged;
    // Locked together: (J_A + J_B) alpha = 1 (the clutch pushes b forward, no limit).
    let w1 = 1.0 / (J_A + J_B);
    // From t = 1 the torque -1 would need a holding torque J_B / 3 = 2/3
    // against b's overrun, beyond what the clutch holds: b slides ahead.
    let at =
        |t0: f64, w0: (f64, f64), alpha: (f64, f64), t: f64| (w0.0 + alpha.0 * (t - t0), w0.1 + alpha.1 * (t - t0));
    let alpha2 = ((-1.0 + tau) / J_A, -tau / J_B);
    let w2 = at(1.0, (w1, w1), alpha2, 2.5);
    let alpha3 = ((2.0 + tau) / J_A, -tau / J_B);
    let t_lock = 2.5 + (w2.1 - w2.0) / (alpha3.0 - alpha3.1);
    let w_lock = at(2.5, w2, alpha3, t_lock).1;
    let speeds = if t < 1.0 {
        (w1 * t, w1 * t)
    } else if t < 2.5 {
        at(1.0, (w1, w1), alpha2, t)
    } else if t < t_lock {
        at(2.5, w2, alpha3, t)
    } else {
        let w = w_lock + 2.0 / (J_A + J_B) * (t - t_lock);
        (w, w)
    };
    (speeds, t_lock)
}

#[test]
fn a_one_way_clutch_drives_its_load_forward_only_and_catches_it_again() {
    for engaged in [0.0, 1.0] {
        let mechanism = one_way_drive(engaged).assemble().unwrap();
        let mut sim = Simulator::new(&mechanism, &options(4.0)).unwrap();
        let (_, t_lock) = one_way_speeds(engaged, 0.0);
        sim.step_until(t_lock + 0.1).unwrap();
        let (t_event, why) = sim.last_event().unwrap();
        let lock_error = (t_event - t_lock).abs();
        sim.step_until(4.0).unwrap();
        let solution = sim.solution();
        let mut worst: f64 = 0.0;
        for (k, &t) in solution.time().iter().enumerate() {
            let ((wa, wb), _) = one_way_speeds(engaged, t);
            let (ga, gb) = (solution.get("a.w").unwrap()[k], solution.get("b.w").unwrap()[k]);
            worst = worst.max((ga - wa).abs()).max((gb - wb).abs());
            // Never lagging: the relative speed stays >= 0.
            assert!(gb - ga > -1e-9, "t = {t}: b lags a by {}", ga - gb);
        }
        println!(
            "engaged {engaged}: locks again at {t_event} against {t_lock} ({lock_error:.2e}, tolerance 1e-9; {why:?}); \
             worst speed error {worst:.2e} (tolerance 1e-8)"
        );
        assert!(lock_error < 1e-9);
        assert!(worst < 1e-8);
        assert_eq!(sim.value("clutch.locked").unwrap(), 1.0);
        // Locked and driving b forward: the clutch pushes b by J_B * 2/3.
        assert!((sim.value("clutch.tau").unwrap() + J_B * 2.0 / 3.0).abs() < 1e-9);
    }
}

/// Started with its load lagging (b at -1 rad/s, a at rest), the clutch
/// is locked at once: the two sides take one speed as in a plastic
/// impact, which keeps the momentum, J_A * 0 + J_B * (-1) = (J_A + J_B) w.
/// (They were averaged at the end of the first step: w = -0.5, momentum
/// lost.) A note says so.
#[test]
fn a_one_way_clutch_started_lagging_locks_keeping_the_momentum() {
    let mut model = one_way_drive(1.0);
    model.component_mut("b").unwrap().initial("w", -1.0);
    let mechanism = model.assemble().unwrap();
    let solution = mechanism.simulate(&options(0.5)).unwrap();
    let w = -J_B / (J_A + J_B);
    // Then torque 1 on both: w + t / (J_A + J_B).
    for (k, &t) in solution.time().iter().enumerate() {
        let exact = w + t / (J_A + J_B);
        let (wa, wb) = (solution.get("a.w").unwrap()[k], solution.get("b.w").unwrap()[k]);
        assert!((wa - exact).abs() < 1e-9 && (wb - exact).abs() < 1e-9, "t = {t}: {wa}, {wb}, not {exact}");
    }
    assert!(solution.warnings().iter().any(|n| n.contains("plastic impact") && n.contains("b.w -1 ->")));
}

/// A mass with stops pushed by `push` (a Step's parameters) from rest at 0.
fn mass_with_stops(push: &[(&str, f64)], friction: &[(&str, f64)]) -> Model {
    let mut model = Model::new("stops");
    let mass = model
        .add("mass", "TranslationalComponents.MassWithStopAndFriction")
        .set("m", 2.0)
        .set("L", 0.4)
        .set("smin", -1.0)
        .set("smax", 1.0)
        .initial("s", 0.0)
        .initial("v", 0.0);
    for &(name, value) in friction {
        mass.set(name, value);
    }
    let source = model.add("push", "BlockComponents.Step");
    for &(name, value) in push {
        source.set(name, value);
    }
    model.add("force", "TranslationalComponents.Force");
    model.connect(["push.y", "force.f"]);
    model.connect(["force.flange", "mass.flange_a"]);
    model
}

#[test]
fn a_mass_with_stops_slides_into_a_stop_stays_and_is_pushed_to_the_other() {
    // m dv/dt = F - F_Coulomb - F_prop v with F = 3, then -3 from t = 4; no
    // Stribeck term: v = v_inf (1 - exp(-t/tau)) with v_inf = (|F| - F_C) /
    // F_prop, tau = m / F_prop. The stops for the centre are at +-(1 - L/2).
    let (m, f, f_c, f_prop, t_rev) = (2.0, 3.0, 1.0, 0.5, 4.0);
    let model = mass_with_stops(
        &[("height", -2.0 * f), ("offset", f), ("start_time", t_rev)],
        &[("F_prop", f_prop), ("F_Coulomb", f_c), ("F_Stribeck", 0.0)],
    );
    let mechanism = model.assemble().unwrap();
    let mut sim = Simulator::new(&mechanism, &options(9.0)).unwrap();
    let (v_inf, tau, travel) = ((f - f_c) / f_prop, m / f_prop, 0.8);
    let run = |t: f64| v_inf * (t - tau * (1.0 - (-t / tau).exp()));
    // The time to travel `d` from rest: Newton on run(t) = d.
    let reach = |d: f64| {
        let mut t = (2.0 * d * m / (f - f_c)).sqrt();
        for _ in 0..50 {
            t -= (run(t) - d) / (v_inf * (1.0 - (-t / tau).exp()));
        }
        t
    };
    let t_hit = reach(travel);
    let t_back = t_rev + reach(2.0 * travel);
    let exact = |t: f64| -> (f64, f64) {
        if t < t_hit {
            (run(t), v_inf * (1.0 - (-t / tau).exp()))
        } else if t < t_rev {
            (travel, 0.0)
        } else if t < t_back {
            (travel - run(t - t_rev), -v_inf * (1.0 - (-(t - t_rev) / tau).exp()))
        } else {
            (-travel, 0.0)
        }
    };
    sim.step_until(t_hit + 0.1).unwrap();
    let hit_error = (sim.last_event().unwrap().0 - t_hit).abs();
    assert_eq!(sim.state_value("mass.v").unwrap(), 0.0, "stopped dead");
    assert_eq!(sim.state_value("mass.s").unwrap(), travel, "on the stop");
    sim.step_until(t_back + 0.1).unwrap();
    let back_error = (sim.last_event().unwrap().0 - t_back).abs();
    sim.step_until(9.0).unwrap();
    let solution = sim.solution();
    let mut worst: f64 = 0.0;
    for (k, &t) in solution.time().iter().enumerate() {
        let (s, v) = exact(t);
        let (gs, gv) = (solution.get("mass.s").unwrap()[k], solution.get("mass.v").unwrap()[k]);
        worst = worst.max((gs - s).abs()).max((gv - v).abs());
        let stopped = solution.get("mass.stopped").unwrap()[k];
        if t > t_hit + 1e-6 && t < t_rev {
            assert_eq!((gs, gv, stopped), (travel, 0.0, 1.0), "held at the right stop at t = {t}");
        }
        if t > t_back + 1e-6 {
            assert_eq!((gs, gv, stopped), (-travel, 0.0, -1.0), "held at the left stop at t = {t}");
        }
    }
    println!(
        "stops reached at {t_hit} and {t_back}: errors {hit_error:.2e}, {back_error:.2e} (tolerance 1e-9); worst state \
         error {worst:.2e} (tolerance 1e-8); {} events",
        sim.event_count()
    );
    assert!(hit_error < 1e-9 && back_error < 1e-9);
    assert!(worst < 1e-8);
    assert!(sim.event_count() < 20, "{} events", sim.event_count());
}

/// Started past a stop (centre at 5 where the stop holds it at 0.8), the
/// mass was put on the stop by the first event and its start value lost
/// without a word; a start on the stop itself is the stop's to hold.
#[test]
fn a_mass_started_past_its_stop_is_refused_and_one_on_it_is_held() {
    let mut model = mass_with_stops(&[("height", 0.0)], &[]);
    model.component_mut("mass").unwrap().initial("s", 5.0);
    let mechanism = model.assemble().unwrap();
    let e = mechanism.simulate(&options(1.0)).unwrap_err();
    assert!(e.reason.contains("the start is 4.200000 past the upper stop of mass"), "{}", e.reason);
    let mut model = mass_with_stops(&[("height", 0.0)], &[]);
    model.component_mut("mass").unwrap().initial("s", -0.8);
    let solution = model.assemble().unwrap().simulate(&options(1.0)).unwrap();
    assert_eq!(solution.get("mass.s").unwrap().last(), Some(&-0.8));
}

#[test]
fn stribeck_friction_stops_a_mass_at_the_time_its_curve_gives() {
    // Sliding from v0 without a push: m dv/dt = -(F_prop v + F_C + F_S
    // exp(-fexp v)), so t_stop = integral over v from 0 to v0 of
    // m / f(v), here by Simpson's rule on 20000 panels (error ~1e-15).
    let (m, v0) = (2.0, 3.0);
    let (f_prop, f_c, f_s, fexp) = (1.0, 5.0, 10.0, 2.0);
    let mut model = Model::new("stribeck");
    model.add("mass", "TranslationalComponents.MassWithStopAndFriction").set("m", m).initial("s", 0.0).initial("v", v0);
    let mechanism = model.assemble().unwrap();
    let mut sim = Simulator::new(&mechanism, &options(3.0)).unwrap();
    sim.step_until(3.0).unwrap();
    let f = |v: f64| m / (f_prop * v + f_c + f_s * (-fexp * v).exp());
    let n = 20000;
    let h = v0 / n as f64;
    let simpson: f64 = (0..=n)
        .map(|k| {
            let w = if k == 0 || k == n {
                1.0
            } else if k % 2 == 1 {
                4.0
            } else {
                2.0
            };
            w * f(k as f64 * h)
        })
        .sum::<f64>()
        * h
        / 3.0;
    let (t_stop, _) = sim.last_event().unwrap();
    let error = (t_stop - simpson).abs();
    println!("Stribeck stop at {t_stop} against {simpson}: {error:.2e} (tolerance 1e-8)");
    assert!(error < 1e-8);
    assert_eq!(sim.value("mass.mode").unwrap(), 0.0);
    assert_eq!(sim.state_value("mass.v").unwrap(), 0.0);
}

#[test]
fn bad_stops_and_contact_parameters_name_the_component_and_parameter() {
    // The kind, its parameters, and the parameter the message must name.
    type Case = (&'static str, &'static [(&'static str, f64)], &'static str);
    let cases: [Case; 4] = [
        ("TranslationalComponents.MassWithStopAndFriction", &[("m", 1.0), ("smin", 1.0), ("smax", -1.0)], "smax"),
        ("TranslationalComponents.ElastoGap", &[("c", -1.0), ("d", 0.0)], "c"),
        ("RotationalComponents.ElastoBacklash", &[("c", 1.0), ("d", 0.0), ("b", -0.1)], "b"),
        ("RotationalComponents.ElastoBacklash", &[("c", 0.0), ("d", 0.0), ("b", 0.1)], "c"),
    ];
    for (kind, params, bad) in cases {
        let mut model = Model::new("bad");
        let c = model.add("part", kind);
        for &(name, value) in params {
            c.set(name, value);
        }
        let Err(error) = model.assemble() else { panic!("{kind} with {params:?} was accepted") };
        let message = error.to_string();
        println!("{kind}: {message}");
        assert!(message.contains(&format!("`part.{bad}`")), "{message}");
    }
}

#[test]
fn support_friction_on_a_prismatic_axis_stops_a_sliding_body_and_a_ramp_holds_it() {
    // A body sliding along a horizontal prismatic (gravity across the axis
    // does no work) with 3 N of support friction stops at t = m v0 / F
    // after m v0^2 / (2 F). Tilted 30 degrees, its weight along the axis
    // (m g / 2) is held while below the holding force, else it slides down
    // at g / 2 - F / m.
    let (m, v0, f) = (1.5, 2.0, 3.0);
    let slide = |axis: [f64; 3], v0: f64, f_pos: f64| {
        let mut model = Model::new("slider");
        model.add("world", "World");
        model.add("joint", "Prismatic").set("n", axis).set("axisflange", true).initial("s", 0.0).initial("v", v0);
        model.add("body", "Body").set("m", m).set("r_cm", [0.0, 0.0, 0.0]);
        model
            .add("friction", "TranslationalComponents.SupportFriction")
            .set("f_pos", multibody::Value::Matrix(vec![vec![0.0, f_pos]]))
            .set("peak", 1.1);
        model.connect(["world.frame_b", "joint.frame_a"]);
        model.connect(["joint.frame_b", "body.frame_a"]);
        model.connect(["friction.flange_a", "joint.axis"]);
        model.connect(["friction.support", "joint.support"]);
        model.assemble().unwrap()
    };
    let mechanism = slide([1.0, 0.0, 0.0], v0, f);
    let mut sim = Simulator::new(&mechanism, &options(2.0)).unwrap();
    sim.step_until(2.0).unwrap();
    let (t_stop, _) = sim.last_event().unwrap();
    let errors = [(t_stop - m * v0 / f).abs(), (sim.state_value("joint.s").unwrap() - m * v0 * v0 / (2.0 * f)).abs()];
    println!("prismatic: stop time and distance errors {errors:?} (tolerance 1e-9)");
    assert!(errors.iter().all(|e| *e < 1e-9), "{errors:?}");
    assert_eq!(sim.state_value("joint.v").unwrap(), 0.0);

    // On a 30 degree incline, from rest: weight along the axis m g / 2.
    let g = 9.80665;
    let incline = [3f64.sqrt() / 2.0, 0.5, 0.0];
    let weight = m * g / 2.0;
    let held = slide(incline, 0.0, weight / 1.05); // holds up to 1.1 / 1.05 of the weight
    let mut sim = Simulator::new(&held, &options(1.0)).unwrap();
    sim.step_until(1.0).unwrap();
    assert_eq!(sim.state_value("joint.s").unwrap(), 0.0, "held on the incline");
    assert!((sim.value("friction.f").unwrap() + weight).abs() < 1e-9, "holding the weight");
    let sliding = slide(incline, 0.0, weight / 2.0);
    let mut sim = Simulator::new(&sliding, &options(1.0)).unwrap();
    sim.step_until(1.0).unwrap();
    let a = -(weight - weight / 2.0) / m;
    let error = (sim.state_value("joint.s").unwrap() - a / 2.0).abs();
    println!(
        "prismatic on an incline: slid {} against {}: {error:.2e} (tolerance 1e-9)",
        sim.state_value("joint.s").unwrap(),
        a / 2.0
    );
    assert!(error < 1e-9);
}

#[test]
fn a_swinging_push_breaks_a_stuck_block_away_within_a_long_quiet_stretch() {
    // F = 30 sin(pi t) against 15 N: stuck (the states do not move, so
    // nothing in them bounds the steps) until F = 15 N at t = 1/6, then
    // M v' = F - 15 N: v = (30 / pi)(cos(pi / 6) - cos(pi t)) / M - 15 (t - 1/6) / M.
    let mut model = block(0.0, ("BlockComponents.Sine", &[("amplitude", 30.0), ("frequency", 0.5)]));
    let friction = model.component_mut("friction").unwrap();
    friction.set("f_pos", multibody::Value::Matrix(vec![vec![0.0, 15.0]])).set("peak", 1.0);
    let mechanism = model.assemble().unwrap();
    let mut sim =
        Simulator::new(&mechanism, &SimulationOptions { stop: 0.5, saveat: 0.1, ..Default::default() }).unwrap();
    sim.step_until(0.5).unwrap();
    let t_break = 1.0 / 6.0;
    let break_error = (sim.last_event().unwrap().0 - t_break).abs();
    let v = (30.0 / PI) * ((PI / 6.0).cos() - (PI * 0.5).cos()) / M - 15.0 * (0.5 - t_break) / M;
    let error = (sim.state_value("mass.v").unwrap() - v).abs();
    println!("v {} mode {}", sim.state_value("mass.v").unwrap(), sim.value("friction.mode").unwrap());
    println!("breaks away at 1/6 s: error {break_error:.2e} (tolerance 1e-8); speed at 0.5 s: error {error:.2e} (tolerance 1e-6)");
    assert!(break_error < 1e-8 && error < 1e-6);
}
