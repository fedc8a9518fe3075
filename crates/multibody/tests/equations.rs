//! The model's own equations against closed forms: a PD law on a joint, a
//! first-order filter, an algebraic loop, forces between frames written by
//! hand against the library's Spring, and the messages for systems that
//! do not match.
//!
//! Tolerances: closed forms in time carry the integration error, which runs
//! at abstol = reltol = 1e-10 keep near 1e-9 (we allow 1e-7); algebraic
//! results at one instant agree to rounding (1e-12).

use multibody::{Cmp, Error, Expr, Flow, Func, Model, SimulationOptions, Solution};

fn tight(stop: f64) -> SimulationOptions {
    SimulationOptions { stop, saveat: 0.01, abstol: 1e-10, reltol: 1e-10, ..Default::default() }
}

fn v(name: &str) -> Expr {
    Expr::var(name)
}

fn column<'a>(s: &'a Solution, name: &str) -> &'a [f64] {
    s.get(name).unwrap_or_else(|| panic!("no column {name}"))
}

fn worst(s: &Solution, name: &str, exact: impl Fn(f64) -> f64) -> f64 {
    column(s, name).iter().zip(s.time()).map(|(y, &t)| (y - exact(t)).abs()).fold(0.0, f64::max)
}

/// A turntable (inertia `j` about the world's z axis, no gravity) turned by
/// a PD law written as an equation: `J phi'' = -kp (phi - ref) - kd phi'`.
fn pd_turntable(kp: f64, kd: f64, reference: f64, j: f64) -> Model {
    let mut m = Model::new("pd");
    m.add("world", "World").set("g", 0.0);
    m.add("rev", "Revolute").set("n", [0.0, 0.0, 1.0]).initial("phi", 0.0).initial("w", 0.0);
    m.add("disc", "Body").set("m", 1.0).set("r_cm", [0.0, 0.0, 0.0]).set("I_33", j);
    m.add("motor", "RotationalComponents.Torque");
    m.connect(["world.frame_b", "rev.frame_a"]);
    m.connect(["rev.frame_b", "disc.frame_a"]);
    m.connect(["motor.spline", "rev.axis"]);
    m.connect(["motor.support", "rev.support"]);
    m.variable("ctrl.e");
    m.equation(v("ctrl.e"), reference - v("rev.phi"));
    m.equation(v("motor.tau"), kp * v("ctrl.e") - kd * Expr::der(v("rev.phi")));
    m
}

#[test]
fn a_pd_law_in_equations_gives_the_damped_oscillator() {
    let (kp, kd, reference, j) = (4.0, 0.8, 1.0, 1.0);
    let model = pd_turntable(kp, kd, reference, j);
    let s = model.assemble().unwrap().simulate(&tight(5.0)).unwrap();
    // phi = ref (1 - e^(-z w t) (cos(wd t) + z w / wd sin(wd t))), underdamped.
    let w0 = (kp / j).sqrt();
    let zeta = kd / (2.0 * (kp * j).sqrt());
    let wd = w0 * (1.0 - zeta * zeta).sqrt();
    let exact =
        |t: f64| reference * (1.0 - (-zeta * w0 * t).exp() * ((wd * t).cos() + zeta * w0 / wd * (wd * t).sin()));
    let err = worst(&s, "rev.phi", exact);
    println!("PD turntable: worst |phi - closed form| = {err:.2e} rad (tolerance 1e-7: {:.3})", err / 1e-7);
    assert!(err < 1e-7);
    let e = worst(&s, "ctrl.e", |t| reference - exact(t));
    assert!(e < 1e-7, "the error variable is in the results: {e}");
}

#[test]
fn a_first_order_filter_follows_its_analytic_response() {
    // der(x) = (u - x) / T with u = sin(w t), x(0) = 0:
    // x = (sin(w t) - w T cos(w t) + w T e^(-t/T)) / (1 + (w T)^2).
    let (tau, w) = (0.3, 2.0);
    let mut m = Model::new("filter");
    m.add("source", "BlockComponents.Sine").set("amplitude", 1.0).set("frequency", w / (2.0 * std::f64::consts::PI));
    m.variable("filter.x").start = Some(0.0);
    m.equations.variables.last_mut().unwrap().fixed = true;
    m.equation(Expr::der(v("filter.x")), (v("source.y") - v("filter.x")) / tau);
    let s = m.assemble().unwrap().simulate(&tight(3.0)).unwrap();
    let wt = w * tau;
    let exact = |t: f64| ((w * t).sin() - wt * (w * t).cos() + wt * (-t / tau).exp()) / (1.0 + wt * wt);
    let err = worst(&s, "filter.x", exact);
    println!("first-order filter: worst error {err:.2e} (tolerance 1e-7: {:.3})", err / 1e-7);
    assert!(err < 1e-7);
}

#[test]
fn an_algebraic_loop_across_two_components_is_solved() {
    // a.y = u - k * b.y and b.y = a.y: y = u / (1 + k), for a signal u of time.
    let k = 3.0;
    let mut m = Model::new("loop");
    m.add("source", "BlockComponents.Ramp").set("height", 2.0).set("duration", 1.0);
    m.variable("a.y");
    m.variable("b.y");
    m.equation(v("a.y"), v("source.y") - k * v("b.y"));
    m.equation(v("b.y"), v("a.y"));
    let s = m.assemble().unwrap().simulate(&tight(1.0)).unwrap();
    let err = column(&s, "a.y")
        .iter()
        .zip(column(&s, "source.y"))
        .map(|(y, u)| (y - u / (1.0 + k)).abs())
        .fold(0.0, f64::max);
    println!("algebraic loop: worst |y - u/(1+k)| = {err:.2e}");
    assert!(err < 1e-12);
}

#[test]
fn a_nonlinear_algebraic_equation_is_solved_by_newton() {
    // x^3 + x = u(t): Newton from the last solution, to rounding.
    let mut m = Model::new("cubic");
    m.add("source", "BlockComponents.Ramp").set("height", 10.0).set("duration", 1.0);
    m.variable("c.x");
    m.equation(v("c.x").pow(Expr::Const(3.0)) + v("c.x"), v("source.y"));
    let s = m.assemble().unwrap().simulate(&tight(1.0)).unwrap();
    for (x, u) in column(&s, "c.x").iter().zip(column(&s, "source.y")) {
        assert!((x * x * x + x - u).abs() < 1e-10, "x = {x}, u = {u}");
    }
}

/// Two bodies on prismatic joints along x, joined by a spring: once the
/// library's Spring, once a spring written with equations on the flows of
/// the frames.
fn two_sliders(hand_written: bool, c: f64, nonlinear: bool) -> Model {
    let mut m = Model::new("sliders");
    m.add("world", "World").set("g", 0.0);
    for (name, x0) in [("left", -0.5), ("right", 0.8)] {
        m.add(format!("{name}_rail"), "Prismatic").set("n", [1.0, 0.0, 0.0]).initial("s", x0).initial("v", 0.0);
        m.add(name, "Body").set("m", if name == "left" { 1.0 } else { 2.0 }).set("r_cm", [0.0, 0.0, 0.0]);
        m.connect(["world.frame_b".to_string(), format!("{name}_rail.frame_a")]);
        m.connect([format!("{name}_rail.frame_b"), format!("{name}.frame_a")]);
    }
    if !hand_written {
        m.add("spring", "Spring").set("c", c).set("s_unstretched", 1.0);
        m.connect(["left.frame_a", "spring.frame_a"]);
        m.connect(["right.frame_a", "spring.frame_b"]);
        return m;
    }
    // The frames stay parallel to the world: the force along x is the
    // tension c (s - 1) (or c (s - 1)^3), pulling the ends together.
    for name in ["f_a", "f_b"] {
        for k in 1..=3 {
            m.variable(format!("spring.{name}[{k}]"));
        }
    }
    for k in 1..=3 {
        m.variable(format!("spring.tau[{k}]"));
    }
    m.variable("spring.s");
    let ra = |i: usize| v(&format!("left.frame_a.r_0[{i}]"));
    let rb = |i: usize| v(&format!("right.frame_a.r_0[{i}]"));
    m.equation(v("spring.s"), rb(1) - ra(1));
    let stretch = v("spring.s") - 1.0;
    let tension = if nonlinear { c * stretch.clone() * stretch.clone() * stretch } else { c * stretch };
    // On the spring at frame_a the world pulls toward b: f_a = +tension x;
    // at frame_b, -tension x.
    m.equation(v("spring.f_a[1]"), -tension.clone());
    m.equation(v("spring.f_b[1]"), tension);
    for k in 2..=3 {
        m.equation(v(&format!("spring.f_a[{k}]")), Expr::Const(0.0));
        m.equation(v(&format!("spring.f_b[{k}]")), Expr::Const(0.0));
    }
    for k in 1..=3 {
        m.equation(v(&format!("spring.tau[{k}]")), Expr::Const(0.0));
    }
    let names = |p: &str| [1, 2, 3].map(|k| format!("spring.{p}[{k}]"));
    m.equations.flows.push(Flow::Frame { connector: "left.frame_a".into(), force: names("f_a"), torque: names("tau") });
    m.equations.flows.push(Flow::Frame {
        connector: "right.frame_a".into(),
        force: names("f_b"),
        torque: names("tau"),
    });
    m
}

#[test]
fn a_spring_written_with_equations_matches_the_library_spring() {
    let library = two_sliders(false, 30.0, false).assemble().unwrap().simulate(&tight(3.0)).unwrap();
    let written = two_sliders(true, 30.0, false).assemble().unwrap().simulate(&tight(3.0)).unwrap();
    let mut err = 0.0f64;
    for name in ["left_rail.s", "right_rail.s", "left_rail.v", "right_rail.v"] {
        for (a, b) in column(&library, name).iter().zip(column(&written, name)) {
            err = err.max((a - b).abs());
        }
    }
    println!("spring in equations vs Spring: worst difference {err:.2e} (tolerance 1e-10: {:.3})", err / 1e-10);
    assert!(err < 1e-10);
}

#[test]
fn a_nonlinear_spring_in_equations_conserves_energy() {
    let c = 50.0;
    let s = two_sliders(true, c, true).assemble().unwrap().simulate(&tight(5.0)).unwrap();
    let energy: Vec<f64> = (0..s.time().len())
        .map(|k| {
            let (vl, vr) = (column(&s, "left_rail.v")[k], column(&s, "right_rail.v")[k]);
            let stretch = column(&s, "spring.s")[k] - 1.0;
            0.5 * vl * vl + 0.5 * 2.0 * vr * vr + c * stretch.powi(4) / 4.0
        })
        .collect();
    let drift = energy.iter().map(|e| (e - energy[0]).abs()).fold(0.0, f64::max) / energy[0];
    println!("nonlinear spring in equations: relative energy drift {drift:.2e} (tolerance 1e-8: {:.3})", drift / 1e-8);
    assert!(energy[0] > 0.1 && drift < 1e-8);
}

#[test]
fn conditions_and_functions_work_in_equations() {
    // A saturated signal: y = min(max(u, -1), 1) written with `if`.
    let mut m = Model::new("limit");
    m.add("source", "BlockComponents.Sine").set("amplitude", 3.0).set("frequency", 0.5);
    m.variable("lim.y");
    let u = || v("source.y");
    m.equation(
        v("lim.y"),
        Expr::if_else(
            Expr::compare(Cmp::Gt, u(), 1.0.into()),
            1.0.into(),
            Expr::if_else(Expr::compare(Cmp::Lt, u(), (-1.0).into()), (-1.0).into(), u()),
        ),
    );
    m.variable("lim.a");
    m.equation(v("lim.a"), Expr::call(Func::Abs, u()));
    let s = m.assemble().unwrap().simulate(&tight(2.0)).unwrap();
    for ((y, a), u) in column(&s, "lim.y").iter().zip(column(&s, "lim.a")).zip(column(&s, "source.y")) {
        assert_eq!(*y, u.clamp(-1.0, 1.0));
        assert_eq!(*a, u.abs());
    }
}

#[test]
fn initial_equations_start_in_steady_state() {
    // der(x) = (u - x) / T with u = 2 and `initial der(x) = 0`: x starts
    // and stays at 2; a second state starts where `initial y = 2 x` puts it.
    let mut m = Model::new("steady");
    m.add("source", "BlockComponents.Constant").set("k", 2.0);
    m.variable("f.x").start = Some(0.3);
    m.variable("f.y");
    m.equation(Expr::der(v("f.x")), (v("source.y") - v("f.x")) / 0.5);
    m.equation(Expr::der(v("f.y")), Expr::Const(0.0));
    m.equations.initial.push(multibody::Equation::new(Expr::der(v("f.x")), Expr::Const(0.0)));
    m.equations.initial.push(multibody::Equation::new(v("f.y"), 2.0 * v("f.x")));
    let s = m.assemble().unwrap().simulate(&tight(1.0)).unwrap();
    for (x, y) in column(&s, "f.x").iter().zip(column(&s, "f.y")) {
        assert!((x - 2.0).abs() < 1e-9 && (y - 4.0).abs() < 1e-9, "x = {x}, y = {y}");
    }
    // Fixing x leaves nothing to satisfy `der(x) = 0`.
    m.equations.variables[0].fixed = true;
    assert!(message(&m).contains("initial equation"), "{}", message(&m));
}

fn message(m: &Model) -> String {
    match m.assemble() {
        Err(e @ Error::Equations { .. }) => e.to_string(),
        Err(other) => panic!("another error: {other}"),
        Ok(_) => panic!("assembled"),
    }
}

#[test]
fn systems_that_do_not_match_are_named() {
    let mut m = Model::new("under");
    m.variable("a.x");
    m.variable("a.y");
    m.equation(v("a.x"), v("a.y") + 1.0);
    let text = message(&m);
    assert!(text.contains("too few equations") && text.contains("a.y") || text.contains("a.x"), "{text}");

    let mut m = Model::new("over");
    m.variable("a.x");
    m.equation(v("a.x"), Expr::Const(1.0));
    m.equation(v("a.x"), Expr::Const(2.0));
    assert!(message(&m).contains("too many equations"), "{}", message(&m));

    let mut m = pd_turntable(1.0, 1.0, 0.0, 1.0);
    m.equation(v("rev.phi"), Expr::Time);
    let text = message(&m);
    assert!(text.contains("constrains the motion") && text.contains("Position"), "{text}");

    let mut m = pd_turntable(1.0, 1.0, 0.0, 1.0);
    m.equation(v("ctrl.e"), Expr::der(Expr::der(v("rev.phi"))));
    assert!(message(&m).contains("accelerations"), "{}", message(&m));

    let mut m = pd_turntable(1.0, 1.0, 0.0, 1.0);
    m.equation(v("ctrl.e"), v("rev.frame_a.f[1]"));
    assert!(message(&m).contains("flow"), "{}", message(&m));

    let mut m = Model::new("unknown");
    m.variable("a.x");
    m.equation(v("a.x"), v("a.xx"));
    assert!(message(&m).contains("did you mean `a.x`"), "{}", message(&m));
}
