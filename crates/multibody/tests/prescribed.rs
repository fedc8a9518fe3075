//! Prescribed motion: frames and joints that follow signals exactly,
//! whatever force it takes, against the formulas that drive them.

use multibody::{Error, Model, SimulationOptions};
use std::f64::consts::PI;

fn options(stop: f64) -> SimulationOptions {
    SimulationOptions { stop, saveat: 0.05, abstol: 1e-10, reltol: 1e-10, ..Default::default() }
}

/// A signal `amplitude sin(w t + phase) + offset` named `name`.
fn sine(model: &mut Model, name: &str, amplitude: f64, w: f64, phase: f64, offset: f64) {
    model
        .add(name, "BlockComponents.Sine")
        .set("amplitude", amplitude)
        .set("frequency", w / (2.0 * PI))
        .set("phase", phase)
        .set("offset", offset);
}

fn constant(model: &mut Model, name: &str, k: f64) {
    model.add(name, "BlockComponents.Constant").set("k", k);
}

/// A body of 1 kg with its centre at frame_a, hung on `prescribed.frame_b`.
fn body_on(model: &mut Model, prescribed: &str) {
    model.add("body", "Body").set("m", 1.0).set("r_cm", [0.0, 0.0, 0.0]);
    model.connect([format!("{prescribed}.frame_b"), "body.frame_a".into()]);
}

/// Largest difference between `name[i]` (i = 1..3) and `f(t)[i-1]` over the samples.
fn worst(solution: &multibody::Solution, name: &str, f: impl Fn(f64) -> [f64; 3]) -> f64 {
    let mut worst = 0.0f64;
    for i in 0..3 {
        let values = solution.get(&format!("{name}[{}]", i + 1)).unwrap_or_else(|| panic!("no {name}"));
        for (t, x) in solution.time().iter().zip(values) {
            worst = worst.max((x - f(*t)[i]).abs());
        }
    }
    worst
}

// The exact levels take positions and speeds from the signals and their
// derivatives, not from integration: they hold to rounding, and 1e-9 is
// the issue's bound.
const EXACT: f64 = 1e-9;

#[test]
fn prescribed_position_follows_sin_t_2t_cos_t() {
    let mut model = Model::new("prescribed_position");
    model.add("world", "World");
    model.add("prescribed", "PrescribedPosition");
    sine(&mut model, "x", 1.0, 1.0, 0.0, 0.0);
    model.add("y", "BlockComponents.Ramp").set("height", 6.0).set("duration", 3.0);
    sine(&mut model, "z", 1.0, 1.0, PI / 2.0, 0.0);
    for axis in ["x", "y", "z"] {
        model.connect([format!("{axis}.y"), format!("prescribed.r_{axis}")]);
    }
    body_on(&mut model, "prescribed");
    let mechanism = model.assemble().unwrap();
    assert_eq!(mechanism.degrees_of_freedom(), 0);
    let solution = mechanism.simulate(&options(2.5)).unwrap();
    let r = worst(&solution, "body.frame_a.r_0", |t| [t.sin(), 2.0 * t, t.cos()]);
    let v = worst(&solution, "body.v_0", |t| [t.cos(), 2.0, -t.sin()]);
    let a = worst(&solution, "body.a_0", |t| [-t.sin(), 0.0, -t.cos()]);
    let own = worst(&solution, "prescribed.r", |t| [t.sin(), 2.0 * t, t.cos()]);
    assert!(r.max(v).max(a).max(own) < EXACT, "r {r:e}, v {v:e}, a {a:e}, prescribed.r {own:e}");
    // What holds the body there is m (a - g): the cut force on the body.
    let g = 9.80665;
    let f = worst(&solution, "body.frame_a.f", |t| [-t.sin(), g, -t.cos()]);
    assert!(f < 1e-8, "cut force off by {f:e} N");
}

#[test]
fn prescribed_pose_turns_about_z_at_one_radian_per_second() {
    let mut model = Model::new("prescribed_pose");
    model.add("world", "World");
    model.add("pose", "PrescribedPose");
    sine(&mut model, "x", 0.5, 1.0, 0.0, 0.0);
    constant(&mut model, "one", 1.0);
    // The quaternion of a turn by t about z: [cos(t/2), 0, 0, sin(t/2)].
    sine(&mut model, "qw", 1.0, 0.5, PI / 2.0, 0.0);
    sine(&mut model, "qz", 1.0, 0.5, 0.0, 0.0);
    constant(&mut model, "zero", 0.0);
    model.connect(["x.y", "pose.r_x"]);
    model.connect(["one.y", "pose.r_y"]);
    model.connect(["zero.y", "pose.r_z", "pose.q_x", "pose.q_y"]);
    model.connect(["qw.y", "pose.q_w"]);
    model.connect(["qz.y", "pose.q_z"]);
    body_on(&mut model, "pose");
    let solution = model.assemble().unwrap().simulate(&options(3.0)).unwrap();
    let w = worst(&solution, "body.w_a", |_| [0.0, 0.0, 1.0]);
    let z = worst(&solution, "body.z_a", |_| [0.0, 0.0, 0.0]);
    let r = worst(&solution, "body.frame_a.r_0", |t| [0.5 * t.sin(), 1.0, 0.0]);
    // R = A_z(t): rows [c s 0], [-s c 0], [0 0 1].
    let mut rot = 0.0f64;
    for (k, &t) in solution.time().iter().enumerate() {
        let (c, s) = (t.cos(), t.sin());
        let expected = [c, s, 0.0, -s, c, 0.0, 0.0, 0.0, 1.0];
        for (i, e) in expected.iter().enumerate() {
            let name = format!("body.frame_a.R[{},{}]", i / 3 + 1, i % 3 + 1);
            rot = rot.max((solution.get(&name).unwrap_or_else(|| panic!("no {name}"))[k] - e).abs());
        }
    }
    assert!(w.max(z).max(r).max(rot) < EXACT, "w {w:e}, z {z:e}, r {r:e}, R {rot:e}");
}

#[test]
fn prescribed_velocity_and_acceleration_integrate_from_their_start() {
    let mut model = Model::new("prescribed_rates");
    model.add("world", "World");
    model.add("velocity", "PrescribedVelocity").set("r_start", [1.0, 0.0, 0.0]);
    model.add("acceleration", "PrescribedAcceleration").set("v_start", [1.0, 0.0, 0.0]);
    for (name, k) in [("v1", 1.0), ("v2", 2.0), ("v3", 0.5), ("a1", 0.0), ("a2", 2.0), ("a3", -1.0)] {
        constant(&mut model, name, k);
    }
    for (i, axis) in ["x", "y", "z"].iter().enumerate() {
        model.connect([format!("v{}.y", i + 1), format!("velocity.v_{axis}")]);
        model.connect([format!("a{}.y", i + 1), format!("acceleration.a_{axis}")]);
    }
    model.add("b1", "Body").set("m", 1.0);
    model.add("b2", "Body").set("m", 2.0);
    model.connect(["velocity.frame_b", "b1.frame_a"]);
    model.connect(["acceleration.frame_b", "b2.frame_a"]);
    let solution = model.assemble().unwrap().simulate(&options(2.0)).unwrap();
    // Integrated states: polynomials of degree <= 2 are integrated exactly
    // by the Runge-Kutta formulas, so rounding is all that is left.
    let r1 = worst(&solution, "b1.frame_a.r_0", |t| [1.0 + t, 2.0 * t, 0.5 * t]);
    let r2 = worst(&solution, "b2.frame_a.r_0", |t| [t, t * t, -0.5 * t * t]);
    let v2 = worst(&solution, "b2.v_0", |t| [1.0, 2.0 * t, -t]);
    assert!(r1.max(r2).max(v2) < EXACT, "r1 {r1:e}, r2 {r2:e}, v2 {v2:e}");
}

/// A pendulum whose revolute a Position source turns: the angle is the
/// signal's, exactly, and not a spring's approximation of it.
#[test]
fn a_position_source_on_a_revolute_makes_it_rheonomic() {
    let mut model = Model::new("driven_pendulum");
    model.add("world", "World");
    model.add("rev", "Revolute");
    model.add("body", "Body").set("m", 2.0).set("r_cm", [0.5, 0.0, 0.0]);
    model.add("drive", "RotationalComponents.Position").set("exact", true);
    sine(&mut model, "reference", 0.8, 3.0, 0.2, 0.1);
    model.connect(["world.frame_b", "rev.frame_a"]);
    model.connect(["rev.frame_b", "body.frame_a"]);
    model.connect(["drive.spline", "rev.axis"]);
    model.connect(["drive.support", "rev.support"]);
    model.connect(["reference.y", "drive.phi_ref"]);
    let mechanism = model.assemble().unwrap();
    assert_eq!(mechanism.degrees_of_freedom(), 0);
    let solution = mechanism.simulate(&options(2.0)).unwrap();
    let (time, phi, w) = (solution.time(), solution.get("rev.phi").unwrap(), solution.get("rev.w").unwrap());
    let a = solution.get("drive.a").unwrap();
    let mut worst = 0.0f64;
    for k in 0..time.len() {
        let x = 3.0 * time[k] + 0.2;
        worst = worst
            .max((phi[k] - (0.1 + 0.8 * x.sin())).abs())
            .max((w[k] - 2.4 * x.cos()).abs())
            .max((a[k] + 7.2 * x.sin()).abs());
    }
    assert!(worst < EXACT, "worst error {worst:e}");
}

/// The inexact source follows its reference through the filter
/// `x'' = ((r - x) w_c - af x') w_c / bf`: for a step of height h from
/// rest the response is that of a damped oscillator with
/// `w0 = w_c / sqrt(bf)` and `zeta = af / (2 sqrt(bf))`.
#[test]
fn an_inexact_position_source_follows_its_filter() {
    let (f_crit, h) = (2.0, 0.5);
    let mut model = Model::new("filtered");
    model.add("world", "World");
    model.add("rev", "Revolute").set("n", [0.0, 1.0, 0.0]);
    model.add("body", "Body").set("m", 1.0).set("r_cm", [0.3, 0.0, 0.0]);
    model.add("drive", "RotationalComponents.Position").set("f_crit", f_crit);
    constant(&mut model, "reference", h);
    model.connect(["world.frame_b", "rev.frame_a"]);
    model.connect(["rev.frame_b", "body.frame_a"]);
    model.connect(["drive.spline", "rev.axis"]);
    model.connect(["reference.y", "drive.phi_ref"]);
    let solution = model.assemble().unwrap().simulate(&options(1.0)).unwrap();
    let (af, bf) = (1.3617f64, 0.6180f64);
    let w0 = 2.0 * PI * f_crit / bf.sqrt();
    let zeta = af / (2.0 * bf.sqrt());
    let wd = w0 * (1.0 - zeta * zeta).sqrt();
    let mut worst = 0.0f64;
    for (t, phi) in solution.time().iter().zip(solution.get("rev.phi").unwrap()) {
        let decay = (-zeta * w0 * t).exp();
        let expected = h * (1.0 - decay * ((wd * t).cos() + zeta * w0 / wd * (wd * t).sin()));
        worst = worst.max((phi - expected).abs());
    }
    // Integrated with tolerances of 1e-10.
    assert!(worst < 1e-8, "worst error {worst:e} rad");
}

#[test]
fn a_prescribed_position_fed_by_the_motion_is_refused() {
    let mut model = Model::new("feedback");
    model.add("world", "World");
    model.add("prescribed", "PrescribedPosition");
    model.add("sensor", "RotationalComponents.AngleSensor");
    model.add("rev", "Revolute");
    model.add("body", "Body").set("m", 1.0).set("r_cm", [0.5, 0.0, 0.0]);
    model.connect(["world.frame_b", "rev.frame_a"]);
    model.connect(["rev.frame_b", "body.frame_a"]);
    model.connect(["sensor.spline", "rev.axis"]);
    model.connect(["sensor.phi", "prescribed.r_x"]);
    model.add("b2", "Body").set("m", 1.0);
    model.connect(["prescribed.frame_b", "b2.frame_a"]);
    let err = model.assemble().unwrap_err();
    let text = err.to_string();
    assert!(matches!(err, Error::Unsupported { .. }), "{text}");
    assert!(text.contains("prescribed") && text.contains("r_x") && text.contains("sources of time"), "{text}");
}

/// A motion sensor in the model does not make a source of time look like
/// feedback: signal slots are numbered in the order of the parts, and the
/// check once compared a slot with the count of blocks of time. The sensor
/// comes first here so that its slot is 0 and the source's 1.
#[test]
fn a_position_source_beside_a_motion_sensor_is_accepted() {
    let mut model = Model::new("driven_and_measured");
    model.add("world", "World");
    model.add("sensor", "RotationalComponents.AngleSensor");
    model.add("rev", "Revolute");
    model.add("body", "Body").set("m", 2.0).set("r_cm", [0.5, 0.0, 0.0]);
    model.add("drive", "RotationalComponents.Position").set("exact", true);
    sine(&mut model, "reference", 0.8, 3.0, 0.2, 0.1);
    model.connect(["world.frame_b", "rev.frame_a"]);
    model.connect(["rev.frame_b", "body.frame_a"]);
    model.connect(["drive.spline", "rev.axis"]);
    model.connect(["drive.support", "rev.support"]);
    model.connect(["sensor.spline", "rev.axis"]);
    model.connect(["reference.y", "drive.phi_ref"]);
    let mechanism = model.assemble().unwrap();
    assert_eq!(mechanism.degrees_of_freedom(), 0);
    let solution = mechanism.simulate(&options(1.0)).unwrap();
    let (time, phi) = (solution.time(), solution.get("sensor.phi").unwrap());
    let mut worst = 0.0f64;
    for k in 0..time.len() {
        worst = worst.max((phi[k] - (0.1 + 0.8 * (3.0 * time[k] + 0.2).sin())).abs());
    }
    assert!(worst < EXACT, "worst error {worst:e}");
}

/// The inexact source's filter integrates the angle and speed it imposes,
/// so they are states and take start values on the source itself. From
/// `phi(0) = 0.1`, `w(0) = 1.5` towards a constant reference h the error
/// `e = phi - h` of the filter `e'' + 2 zeta w0 e' + w0^2 e = 0`
/// (`w0 = w_c / sqrt(bf)`, `zeta = af / (2 sqrt(bf))`) is
/// `exp(-zeta w0 t) (A cos(wd t) + B sin(wd t))`, `A = e(0)`,
/// `B = (e'(0) + zeta w0 A) / wd`.
#[test]
fn an_inexact_position_source_takes_start_values_of_its_filter() {
    let (f_crit, h, phi0, w0_start) = (2.0, 0.5, 0.1, 1.5);
    let mut model = Model::new("filtered_start");
    model.add("world", "World");
    model.add("rev", "Revolute").set("n", [0.0, 1.0, 0.0]);
    model.add("body", "Body").set("m", 1.0).set("r_cm", [0.3, 0.0, 0.0]);
    model
        .add("drive", "RotationalComponents.Position")
        .set("f_crit", f_crit)
        .initial("phi", phi0)
        .initial("w", w0_start);
    constant(&mut model, "reference", h);
    model.connect(["world.frame_b", "rev.frame_a"]);
    model.connect(["rev.frame_b", "body.frame_a"]);
    model.connect(["drive.spline", "rev.axis"]);
    model.connect(["drive.support", "rev.support"]);
    model.connect(["reference.y", "drive.phi_ref"]);
    let solution = model.assemble().unwrap().simulate(&options(1.0)).unwrap();
    let (af, bf) = (1.3617f64, 0.6180f64);
    let w0 = 2.0 * PI * f_crit / bf.sqrt();
    let zeta = af / (2.0 * bf.sqrt());
    let wd = w0 * (1.0 - zeta * zeta).sqrt();
    let a = phi0 - h;
    let b = (w0_start + zeta * w0 * a) / wd;
    let (time, phi, w) = (solution.time(), solution.get("rev.phi").unwrap(), solution.get("drive.w").unwrap());
    let mut worst = 0.0f64;
    for k in 0..time.len() {
        let t = time[k];
        let decay = (-zeta * w0 * t).exp();
        let e = decay * (a * (wd * t).cos() + b * (wd * t).sin());
        let de = -zeta * w0 * e + decay * wd * (-a * (wd * t).sin() + b * (wd * t).cos());
        worst = worst.max((phi[k] - (h + e)).abs()).max((w[k] - de).abs() / w0);
    }
    assert!((phi[0] - phi0).abs() < 1e-12 && (w[0] - w0_start).abs() < 1e-12, "start {} {}", phi[0], w[0]);
    assert!(worst < 1e-8, "worst error {worst:e}");
}
