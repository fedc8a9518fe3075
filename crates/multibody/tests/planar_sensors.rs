//! PlanarMechanics prescribed motion and sensors against closed forms.
//!
//! Tolerances, as in the 3-D sensor tests: a quantity that is an algebraic
//! function of the state at the same instant (positions, velocities, and
//! accelerations from the equations of motion written out here) agrees to
//! rounding; we allow 1e-11 on values of order 1 to 10. Drives of the
//! exact levels take positions and speeds from the signals and their
//! derivatives, so they hold to rounding too (1e-9, the prescribed tests'
//! bound). Closed forms in time of integrated motion carry the integration
//! error of a run at tolerances 1e-12 (we allow 1e-8).

use multibody::{Error, Model, SimulationOptions, Solution, Value};
use std::f64::consts::{FRAC_PI_2, PI};

const G: f64 = 9.80665;
const STATE: f64 = 1e-11;
const EXACT: f64 = 1e-9;
const INTEGRATED: f64 = 1e-8;

fn options(stop: f64) -> SimulationOptions {
    SimulationOptions { stop, saveat: 0.01, abstol: 1e-12, reltol: 1e-12, ..Default::default() }
}

fn run(m: &Model, stop: f64) -> Solution {
    m.assemble().unwrap_or_else(|e| panic!("{}: {e}", m.name)).simulate(&options(stop)).unwrap()
}

fn column<'a>(s: &'a Solution, name: &str) -> &'a [f64] {
    s.get(name).unwrap_or_else(|| panic!("no column {name}"))
}

fn resolve(v: &str) -> Value {
    Value::Enum(v.into())
}

/// An angle in (-pi, pi], as the sensors give angles.
fn wrap(x: f64) -> f64 {
    let y = x.rem_euclid(2.0 * PI);
    if y > PI {
        y - 2.0 * PI
    } else {
        y
    }
}

/// A closed form: the expected value at sample `k`.
type Expected<'a> = Box<dyn Fn(usize) -> f64 + 'a>;

/// Checks every named column against its closed form, prints each worst
/// error as a fraction of `tolerance`, and fails on the first beyond it.
fn check(label: &str, s: &Solution, tolerance: f64, checks: Vec<(&str, Expected)>) {
    let mut failures = Vec::new();
    for (name, expected) in &checks {
        let got = column(s, name);
        let err = got.iter().enumerate().map(|(k, g)| (g - expected(k)).abs()).fold(0.0, f64::max);
        eprintln!("{label}: {name}: worst error {err:.1e} = {:.2} of {tolerance:.0e}", err / tolerance);
        if err.is_nan() || err >= tolerance {
            failures.push(format!("{name}: {err:e}"));
        }
    }
    assert!(failures.is_empty(), "{label}: beyond {tolerance:e}: {}", failures.join(", "));
}

/// A signal `amplitude sin(w t + phase)`.
fn sine(m: &mut Model, name: &str, amplitude: f64, w: f64, phase: f64) {
    m.add(name, "BlockComponents.Sine")
        .set("amplitude", amplitude)
        .set("frequency", w / (2.0 * PI))
        .set("phase", phase);
}

/// A signal `slope t` (a ramp that outlasts the runs).
fn ramp(m: &mut Model, name: &str, slope: f64) {
    m.add(name, "BlockComponents.Ramp").set("height", 100.0 * slope).set("duration", 100.0);
}

fn constant(m: &mut Model, name: &str, k: f64) {
    m.add(name, "BlockComponents.Constant").set("k", k);
}

/// A planar body of mass `m` and inertia `i` on `frame`.
fn body_on(m: &mut Model, frame: &str, mass: f64, inertia: f64) {
    m.add("body", "PlanarMechanics.Body").set("m", mass).set("I", inertia);
    m.connect([frame, "body.frame_a"]);
}

// ---------------------------------------------------------------------------
// Prescribed motion.

#[test]
fn prescribed_position_follows_sin_t_and_2t_and_holds_the_angle() {
    let mut m = Model::new("planar_prescribed_position");
    m.add("world", "PlanarMechanics.World");
    m.add("prescribed", "PlanarMechanics.PrescribedPosition");
    sine(&mut m, "x", 1.0, 1.0, 0.0);
    ramp(&mut m, "y", 2.0);
    m.connect(["x.y", "prescribed.r_x"]);
    m.connect(["y.y", "prescribed.r_y"]);
    let mass = 1.5;
    body_on(&mut m, "prescribed.frame_b", mass, 1.0);
    let mechanism = m.assemble().unwrap();
    assert_eq!(mechanism.degrees_of_freedom(), 0);
    let s = mechanism.simulate(&options(2.5)).unwrap();
    let t = s.time().to_vec();
    let checks: Vec<(&str, Expected)> = vec![
        ("prescribed.r[1]", Box::new(|k| t[k].sin())),
        ("prescribed.r[2]", Box::new(|k| 2.0 * t[k])),
        ("prescribed.v[1]", Box::new(|k| t[k].cos())),
        ("prescribed.v[2]", Box::new(|_| 2.0)),
        ("prescribed.a[1]", Box::new(|k| -t[k].sin())),
        ("prescribed.a[2]", Box::new(|_| 0.0)),
        ("body.r[1]", Box::new(|k| t[k].sin())),
        ("body.r[2]", Box::new(|k| 2.0 * t[k])),
        ("body.v[1]", Box::new(|k| t[k].cos())),
        ("body.a[1]", Box::new(|k| -t[k].sin())),
        ("body.frame_a.phi", Box::new(|_| 0.0)),
        ("body.w", Box::new(|_| 0.0)),
        // What holds the body on its path: m (a - g), g = [0, -9.80665].
        ("body.f[1]", Box::new(|k| -mass * t[k].sin())),
        ("body.f[2]", Box::new(|_| mass * G)),
    ];
    check("PrescribedPosition", &s, EXACT, checks);
}

#[test]
fn prescribed_position_with_a_free_angle_lets_the_body_spin_on() {
    let mut m = Model::new("planar_prescribed_free_angle");
    m.add("world", "PlanarMechanics.World");
    m.add("prescribed", "PlanarMechanics.PrescribedPosition")
        .set("fixed_orientation", false)
        .initial("phi", 0.2)
        .initial("w", 0.5);
    sine(&mut m, "x", 0.5, 2.0, 0.0);
    constant(&mut m, "y", 1.0);
    m.connect(["x.y", "prescribed.r_x"]);
    m.connect(["y.y", "prescribed.r_y"]);
    body_on(&mut m, "prescribed.frame_b", 2.0, 0.3);
    let mechanism = m.assemble().unwrap();
    assert_eq!(mechanism.degrees_of_freedom(), 1);
    let s = mechanism.simulate(&options(2.5)).unwrap();
    let t = s.time().to_vec();
    // No torque acts about the body's centre: it turns at its start rate.
    let checks: Vec<(&str, Expected)> = vec![
        ("body.frame_a.phi", Box::new(|k| 0.2 + 0.5 * t[k])),
        ("body.w", Box::new(|_| 0.5)),
        ("body.alpha", Box::new(|_| 0.0)),
        ("body.r[1]", Box::new(|k| 0.5 * (2.0 * t[k]).sin())),
        ("body.r[2]", Box::new(|_| 1.0)),
        ("body.a[1]", Box::new(|k| -2.0 * (2.0 * t[k]).sin())),
        ("body.frame_a.tau", Box::new(|_| 0.0)),
    ];
    check("PrescribedPosition free angle", &s, INTEGRATED, checks);
}

#[test]
fn prescribed_pose_turns_at_0_3_rad_per_second() {
    let mut m = Model::new("planar_prescribed_pose");
    m.add("world", "PlanarMechanics.World");
    m.add("pose", "PlanarMechanics.PrescribedPose");
    sine(&mut m, "x", 1.0, 1.0, 0.0);
    ramp(&mut m, "y", 0.5);
    ramp(&mut m, "phi", 0.3);
    for input in ["x", "y"] {
        m.connect([format!("{input}.y"), format!("pose.r_{input}")]);
    }
    m.connect(["phi.y", "pose.phi"]);
    let (mass, inertia) = (2.0, 0.4);
    // The body's centre sits 0.5 m along the pose's x axis.
    m.add("arm", "PlanarMechanics.FixedTranslation").set("r", [0.5, 0.0]);
    m.connect(["pose.frame_b", "arm.frame_a"]);
    body_on(&mut m, "arm.frame_b", mass, inertia);
    let mechanism = m.assemble().unwrap();
    assert_eq!(mechanism.degrees_of_freedom(), 0);
    let s = mechanism.simulate(&options(3.0)).unwrap();
    let t = s.time().to_vec();
    let phi = |k: usize| 0.3 * t[k];
    let checks: Vec<(&str, Expected)> = vec![
        ("pose.r[1]", Box::new(|k| t[k].sin())),
        ("pose.r[2]", Box::new(|k| 0.5 * t[k])),
        ("pose.v[1]", Box::new(|k| t[k].cos())),
        ("pose.v[2]", Box::new(|_| 0.5)),
        ("pose.a[1]", Box::new(|k| -t[k].sin())),
        ("pose.a[2]", Box::new(|_| 0.0)),
        ("pose.frame_b.phi", Box::new(phi)),
        ("body.frame_a.phi", Box::new(phi)),
        ("body.w", Box::new(|_| 0.3)),
        ("body.alpha", Box::new(|_| 0.0)),
        // The arm's end: r + 0.5 [cos, sin], and its centripetal pull.
        ("body.r[1]", Box::new(|k| t[k].sin() + 0.5 * phi(k).cos())),
        ("body.r[2]", Box::new(|k| 0.5 * t[k] + 0.5 * phi(k).sin())),
        ("body.v[1]", Box::new(|k| t[k].cos() - 0.15 * phi(k).sin())),
        ("body.v[2]", Box::new(|k| 0.5 + 0.15 * phi(k).cos())),
        ("body.a[1]", Box::new(|k| -t[k].sin() - 0.045 * phi(k).cos())),
        ("body.a[2]", Box::new(|k| -0.045 * phi(k).sin())),
    ];
    check("PrescribedPose", &s, EXACT, checks);
}

#[test]
fn prescribed_velocity_and_acceleration_integrate_from_their_starts() {
    let mut m = Model::new("planar_prescribed_rates");
    m.add("world", "PlanarMechanics.World");
    m.add("velocity", "PlanarMechanics.PrescribedVelocity").set("r_start", [1.0, 2.0]);
    m.add("acceleration", "PlanarMechanics.PrescribedAcceleration")
        .set("r_start", [0.0, 1.0])
        .set("v_start", [1.0, 3.0]);
    constant(&mut m, "vx", 1.0);
    ramp(&mut m, "vy", 2.0);
    sine(&mut m, "ax", 1.0, 1.0, FRAC_PI_2);
    constant(&mut m, "ay", -2.0);
    m.connect(["vx.y", "velocity.v_x"]);
    m.connect(["vy.y", "velocity.v_y"]);
    m.connect(["ax.y", "acceleration.a_x"]);
    m.connect(["ay.y", "acceleration.a_y"]);
    m.add("b1", "PlanarMechanics.Body").set("m", 1.0).set("I", 0.1);
    m.add("b2", "PlanarMechanics.Body").set("m", 2.0).set("I", 0.1);
    m.connect(["velocity.frame_b", "b1.frame_a"]);
    m.connect(["acceleration.frame_b", "b2.frame_a"]);
    let s = run(&m, 2.0);
    let t = s.time().to_vec();
    let checks: Vec<(&str, Expected)> = vec![
        ("velocity.r[1]", Box::new(|k| 1.0 + t[k])),
        ("velocity.r[2]", Box::new(|k| 2.0 + t[k] * t[k])),
        ("velocity.v[1]", Box::new(|_| 1.0)),
        ("velocity.v[2]", Box::new(|k| 2.0 * t[k])),
        ("velocity.a[2]", Box::new(|_| 2.0)),
        ("b1.frame_a.phi", Box::new(|_| 0.0)),
        // a = [cos t, -2] from v = [1, 3] at r = [0, 1].
        ("acceleration.r[1]", Box::new(|k| t[k] + 1.0 - t[k].cos())),
        ("acceleration.r[2]", Box::new(|k| 1.0 + 3.0 * t[k] - t[k] * t[k])),
        ("acceleration.v[1]", Box::new(|k| 1.0 + t[k].sin())),
        ("acceleration.v[2]", Box::new(|k| 3.0 - 2.0 * t[k])),
        ("acceleration.a[1]", Box::new(|k| t[k].cos())),
        ("acceleration.a[2]", Box::new(|_| -2.0)),
        ("b2.frame_a.phi", Box::new(|_| 0.0)),
        ("b2.f[2]", Box::new(|_| 2.0 * (-2.0 + G))),
    ];
    check("PrescribedVelocity/Acceleration", &s, INTEGRATED, checks);
}

// ---------------------------------------------------------------------------
// Absolute sensors on a pendulum.

/// A planar pendulum: a revolute at the origin, a rod of length `l`, a body
/// of mass `mass` and inertia `inertia` (about its point) at its end,
/// starting at rest at `phi0` (0 horizontal, -pi/2 hanging).
fn pendulum(l: f64, mass: f64, inertia: f64, phi0: f64) -> Model {
    let mut m = Model::new("planar_pendulum");
    m.add("world", "PlanarMechanics.World");
    m.add("rev", "PlanarMechanics.Revolute").initial("phi", phi0).initial("w", 0.0);
    m.add("rod", "PlanarMechanics.FixedTranslation").set("r", [l, 0.0]);
    m.connect(["world.frame_b", "rev.frame_a"]);
    m.connect(["rev.frame_b", "rod.frame_a"]);
    m.add("body", "PlanarMechanics.Body").set("m", mass).set("I", inertia);
    m
}

/// Its angular acceleration from its equation of motion,
/// `(I + m l^2) phi'' = -m g l cos(phi)`.
fn pendulum_alpha(l: f64, mass: f64, inertia: f64, phi: f64) -> f64 {
    -mass * G * l * phi.cos() / (inertia + mass * l * l)
}

#[test]
fn absolute_sensors_on_a_pendulum_match_its_angle_and_rate() {
    let (l, mass, inertia) = (1.2, 1.0, 0.1);
    let mut m = pendulum(l, mass, inertia, -0.5);
    m.connect(["rod.frame_b", "body.frame_a"]);
    // The fixed frame_resolve: turned by 0.7 at [0.3, -0.2].
    m.add("fixed", "PlanarMechanics.Fixed").set("r", [0.3, -0.2]).set("phi", 0.7);
    let kinds = ["AbsolutePosition", "AbsoluteVelocity", "AbsoluteAcceleration"];
    for (kind, short) in kinds.iter().zip(["pos", "vel", "acc"]) {
        for frame in ["World", "FrameA", "FrameResolve"] {
            let name = format!("{short}_{frame}");
            m.add(&name, format!("PlanarMechanics.{kind}")).set("resolve_in_frame", resolve(frame));
            m.connect([format!("{name}.frame_a"), "body.frame_a".into()]);
            if frame == "FrameResolve" {
                m.connect([format!("{name}.frame_resolve"), "fixed.frame_b".into()]);
            }
        }
    }
    // A default sensor resolves in frame_a.
    m.add("pos_default", "PlanarMechanics.AbsolutePosition");
    m.connect(["pos_default.frame_a", "body.frame_a"]);
    // Outputs of positions and velocities are signals: a gain reads one.
    m.add("gain", "BlockComponents.Gain").set("k", 2.0);
    m.connect(["vel_World.v_y", "gain.u"]);
    let s = run(&m, 3.0);
    let (phi, w) = (column(&s, "rev.phi").to_vec(), column(&s, "rev.w").to_vec());
    let alpha = |k: usize| pendulum_alpha(l, mass, inertia, phi[k]);
    let (c, sn) = (|k: usize| phi[k].cos(), |k: usize| phi[k].sin());
    // World vectors of the bob: r = l e, v = l w e_t, a = l (alpha e_t - w^2 e).
    let r = |k: usize| [l * c(k), l * sn(k)];
    let v = |k: usize| [-l * w[k] * sn(k), l * w[k] * c(k)];
    let a = |k: usize| {
        let w2 = w[k] * w[k];
        [l * (-alpha(k) * sn(k) - w2 * c(k)), l * (alpha(k) * c(k) - w2 * sn(k))]
    };
    // Resolved in a frame at angle psi: R(psi)^T x.
    let turned = |x: [f64; 2], psi: f64| [psi.cos() * x[0] + psi.sin() * x[1], -psi.sin() * x[0] + psi.cos() * x[1]];
    let checks: Vec<(&str, Expected)> = vec![
        ("body.r[1]", Box::new(|k| r(k)[0])),
        ("pos_World.x", Box::new(|k| r(k)[0])),
        ("pos_World.y", Box::new(|k| r(k)[1])),
        ("pos_World.phi", Box::new(|k| phi[k])),
        ("pos_FrameA.x", Box::new(|k| turned(r(k), phi[k])[0])),
        ("pos_FrameA.y", Box::new(|k| turned(r(k), phi[k])[1])),
        ("pos_FrameA.phi", Box::new(|_| 0.0)),
        ("pos_default.x", Box::new(|_| l)),
        ("pos_default.y", Box::new(|_| 0.0)),
        // The position is the origin's, resolved in frame_resolve.
        ("pos_FrameResolve.x", Box::new(|k| turned(r(k), 0.7)[0])),
        ("pos_FrameResolve.y", Box::new(|k| turned(r(k), 0.7)[1])),
        // Angles read in (-pi, pi].
        ("pos_FrameResolve.phi", Box::new(|k| wrap(phi[k] - 0.7))),
        ("vel_World.v_x", Box::new(|k| v(k)[0])),
        ("vel_World.v_y", Box::new(|k| v(k)[1])),
        ("vel_World.w", Box::new(|k| w[k])),
        ("vel_World.px", Box::new(|k| r(k)[0])),
        ("vel_World.pphi", Box::new(|k| phi[k])),
        ("gain.y", Box::new(|k| 2.0 * v(k)[1])),
        ("vel_FrameA.v_x", Box::new(|_| 0.0)),
        ("vel_FrameA.v_y", Box::new(|k| l * w[k])),
        ("vel_FrameA.w", Box::new(|k| w[k])),
        ("vel_FrameResolve.v_x", Box::new(|k| turned(v(k), 0.7)[0])),
        ("vel_FrameResolve.v_y", Box::new(|k| turned(v(k), 0.7)[1])),
        ("acc_World.a_x", Box::new(|k| a(k)[0])),
        ("acc_World.a_y", Box::new(|k| a(k)[1])),
        ("acc_World.alpha", Box::new(alpha)),
        ("acc_World.vy", Box::new(|k| v(k)[1])),
        ("acc_World.vphi", Box::new(|k| w[k])),
        // In the bob's frame: the tangential l alpha and the centripetal -l w^2.
        ("acc_FrameA.a_x", Box::new(|k| -l * w[k] * w[k])),
        ("acc_FrameA.a_y", Box::new(|k| l * alpha(k))),
        ("acc_FrameA.alpha", Box::new(alpha)),
        ("acc_FrameResolve.a_x", Box::new(|k| turned(a(k), 0.7)[0])),
        ("acc_FrameResolve.a_y", Box::new(|k| turned(a(k), 0.7)[1])),
    ];
    check("absolute sensors", &s, STATE, checks);
    // It swings: the checks are not of a body at rest.
    let swing = column(&s, "rev.phi").iter().fold(0.0f64, |m, p| m.max((p + 0.5).abs()));
    assert!(swing > 0.5, "the pendulum hardly swings ({swing})");
}

// ---------------------------------------------------------------------------
// Relative sensors on a double pendulum.

/// The angular accelerations of a double pendulum of point bodies (masses
/// `m1`, `m2`, inertias `i1`, `i2` about them) on massless rods `l1`, `l2`,
/// from its Lagrange equations in the absolute angles `th1 = phi1` and
/// `th2 = phi1 + phi2`: returns `[phi1'', phi2'']`.
#[allow(clippy::too_many_arguments)]
fn double_pendulum_accelerations(
    (l1, l2, m1, m2, i1, i2): (f64, f64, f64, f64, f64, f64),
    phi1: f64,
    phi2: f64,
    w1: f64,
    w2: f64,
) -> [f64; 2] {
    let (th1, th2) = (phi1, phi1 + phi2);
    let (d1, d2) = (w1, w1 + w2);
    let m11 = (m1 + m2) * l1 * l1 + i1;
    let m12 = m2 * l1 * l2 * (th1 - th2).cos();
    let m22 = m2 * l2 * l2 + i2;
    let s = m2 * l1 * l2 * (th1 - th2).sin();
    let b1 = -s * d2 * d2 - (m1 + m2) * G * l1 * th1.cos();
    let b2 = s * d1 * d1 - m2 * G * l2 * th2.cos();
    let det = m11 * m22 - m12 * m12;
    let a1 = (b1 * m22 - m12 * b2) / det;
    let a2 = (m11 * b2 - m12 * b1) / det;
    [a1, a2 - a1]
}

#[test]
fn relative_sensors_on_a_double_pendulum_match_its_angles_and_rates() {
    let params = (1.0, 0.8, 1.0, 0.7, 0.05, 0.02);
    let (l1, l2, m1, m2, i1, i2) = params;
    let mut m = Model::new("planar_double_pendulum");
    m.add("world", "PlanarMechanics.World");
    m.add("rev1", "PlanarMechanics.Revolute").initial("phi", -1.2).initial("w", 0.0);
    m.add("rod1", "PlanarMechanics.FixedTranslation").set("r", [l1, 0.0]);
    m.add("body1", "PlanarMechanics.Body").set("m", m1).set("I", i1);
    m.add("rev2", "PlanarMechanics.Revolute").initial("phi", 0.4).initial("w", 0.0);
    m.add("rod2", "PlanarMechanics.FixedTranslation").set("r", [l2, 0.0]);
    m.add("body2", "PlanarMechanics.Body").set("m", m2).set("I", i2);
    m.connect(["world.frame_b", "rev1.frame_a"]);
    m.connect(["rev1.frame_b", "rod1.frame_a"]);
    m.connect(["rod1.frame_b", "body1.frame_a", "rev2.frame_a"]);
    m.connect(["rev2.frame_b", "rod2.frame_a"]);
    m.connect(["rod2.frame_b", "body2.frame_a"]);
    let kinds = ["RelativePosition", "RelativeVelocity", "RelativeAcceleration"];
    for (kind, short) in kinds.iter().zip(["pos", "vel", "acc"]) {
        for frame in ["World", "FrameA", "FrameB", "FrameResolve"] {
            let name = format!("{short}_{frame}");
            m.add(&name, format!("PlanarMechanics.{kind}")).set("resolve_in_frame", resolve(frame));
            m.connect([format!("{name}.frame_a"), "body1.frame_a".into()]);
            m.connect([format!("{name}.frame_b"), "body2.frame_a".into()]);
            if frame == "FrameResolve" {
                // Resolved in rod1's root frame: the same axes as frame_a, elsewhere.
                m.connect([format!("{name}.frame_resolve"), "rod1.frame_a".into()]);
            }
        }
    }
    // From the pivot to the outer bob, and between the bobs.
    m.add("dist", "PlanarMechanics.Distance");
    m.connect(["dist.frame_a", "world.frame_b"]);
    m.connect(["dist.frame_b", "body2.frame_a"]);
    m.add("rod_length", "PlanarMechanics.Distance");
    m.connect(["rod_length.frame_a", "body1.frame_a"]);
    m.connect(["rod_length.frame_b", "body2.frame_a"]);
    // The relative velocity resolved in frame_a, turned into frame_b's axes
    // and into the world's by the transform blocks.
    m.add("to_b", "PlanarMechanics.TransformRelativeVector").set("frame_out", resolve("FrameB"));
    m.add("to_world", "PlanarMechanics.TransformAbsoluteVector").set("frame_out", resolve("World"));
    for t in ["to_b", "to_world"] {
        for (i, o) in [("x_in", "rel_v_x"), ("y_in", "rel_v_y"), ("phi_in", "rel_w")] {
            m.connect([format!("vel_FrameA.{o}"), format!("{t}.{i}")]);
        }
        m.connect([format!("{t}.frame_a"), "body1.frame_a".into()]);
    }
    m.connect(["to_b.frame_b", "body2.frame_a"]);
    // From frame_a to frame_a: unchanged.
    m.add("same", "PlanarMechanics.TransformAbsoluteVector");
    for (i, o) in [("x_in", "rel_v_x"), ("y_in", "rel_v_y"), ("phi_in", "rel_w")] {
        m.connect([format!("vel_FrameA.{o}"), format!("same.{i}")]);
    }
    m.connect(["same.frame_a", "body1.frame_a"]);
    let s = run(&m, 3.0);
    let col = |n: &str| column(&s, n).to_vec();
    let (p1, p2, w1, w2) = (col("rev1.phi"), col("rev2.phi"), col("rev1.w"), col("rev2.w"));
    let acc = |k: usize| double_pendulum_accelerations(params, p1[k], p2[k], w1[k], w2[k]);
    let turned = |x: [f64; 2], psi: f64| [psi.cos() * x[0] + psi.sin() * x[1], -psi.sin() * x[0] + psi.cos() * x[1]];
    let turned_back = |x: [f64; 2], psi: f64| turned(x, -psi);
    // In frame_a (body1, at angle phi1) frame_b sits at l2 [cos phi2, sin phi2]:
    // its rates as frame_a sees them are those of phi2 alone.
    let r_a = |k: usize| [l2 * p2[k].cos(), l2 * p2[k].sin()];
    let v_a = |k: usize| [-l2 * w2[k] * p2[k].sin(), l2 * w2[k] * p2[k].cos()];
    let a_a = |k: usize| {
        let (a2, ww) = (acc(k)[1], w2[k] * w2[k]);
        [l2 * (-a2 * p2[k].sin() - ww * p2[k].cos()), l2 * (a2 * p2[k].cos() - ww * p2[k].sin())]
    };
    // Resolved in the world, v_a turns with frame_a: its rate there gains w1 x v.
    let a_world = |k: usize| {
        let (a, v) = (turned_back(a_a(k), p1[k]), turned_back(v_a(k), p1[k]));
        [a[0] - w1[k] * v[1], a[1] + w1[k] * v[0]]
    };
    // In frame_b's axes (angle phi1 + phi2, turning at w1 + w2).
    let a_b = |k: usize| {
        let (a, v) = (a_world(k), turned_back(v_a(k), p1[k]));
        let wb = w1[k] + w2[k];
        turned([a[0] + wb * v[1], a[1] - wb * v[0]], p1[k] + p2[k])
    };
    let checks: Vec<(&str, Expected)> = vec![
        ("pos_FrameA.rel_x", Box::new(|k| r_a(k)[0])),
        ("pos_FrameA.rel_y", Box::new(|k| r_a(k)[1])),
        ("pos_FrameA.rel_phi", Box::new(|k| p2[k])),
        ("pos_World.rel_x", Box::new(|k| turned_back(r_a(k), p1[k])[0])),
        ("pos_World.rel_y", Box::new(|k| turned_back(r_a(k), p1[k])[1])),
        ("pos_World.rel_phi", Box::new(|k| p2[k])),
        ("pos_FrameB.rel_x", Box::new(|_| l2)),
        ("pos_FrameB.rel_y", Box::new(|_| 0.0)),
        ("pos_FrameResolve.rel_x", Box::new(|k| r_a(k)[0])),
        ("pos_FrameResolve.rel_y", Box::new(|k| r_a(k)[1])),
        ("vel_FrameA.rel_v_x", Box::new(|k| v_a(k)[0])),
        ("vel_FrameA.rel_v_y", Box::new(|k| v_a(k)[1])),
        ("vel_FrameA.rel_w", Box::new(|k| w2[k])),
        ("vel_FrameA.rpx", Box::new(|k| r_a(k)[0])),
        ("vel_FrameA.rpphi", Box::new(|k| p2[k])),
        ("vel_World.rel_v_x", Box::new(|k| turned_back(v_a(k), p1[k])[0])),
        ("vel_World.rel_v_y", Box::new(|k| turned_back(v_a(k), p1[k])[1])),
        ("vel_World.rel_w", Box::new(|k| w2[k])),
        ("vel_FrameB.rel_v_x", Box::new(|_| 0.0)),
        ("vel_FrameB.rel_v_y", Box::new(|k| l2 * w2[k])),
        ("vel_FrameResolve.rel_v_x", Box::new(|k| v_a(k)[0])),
        ("vel_FrameResolve.rel_v_y", Box::new(|k| v_a(k)[1])),
        ("acc_FrameA.rel_a_x", Box::new(|k| a_a(k)[0])),
        ("acc_FrameA.rel_a_y", Box::new(|k| a_a(k)[1])),
        ("acc_FrameA.rel_alpha", Box::new(|k| acc(k)[1])),
        ("acc_World.rel_a_x", Box::new(|k| a_world(k)[0])),
        ("acc_World.rel_a_y", Box::new(|k| a_world(k)[1])),
        ("acc_World.rel_alpha", Box::new(|k| acc(k)[1])),
        ("acc_FrameB.rel_a_x", Box::new(|k| a_b(k)[0])),
        ("acc_FrameB.rel_a_y", Box::new(|k| a_b(k)[1])),
        ("acc_FrameResolve.rel_a_x", Box::new(|k| a_a(k)[0])),
        ("acc_FrameResolve.rel_a_y", Box::new(|k| a_a(k)[1])),
        ("rev2.alpha", Box::new(|k| acc(k)[1])),
        ("rev1.alpha", Box::new(|k| acc(k)[0])),
        ("dist.distance", Box::new(|k| (l1 * l1 + l2 * l2 + 2.0 * l1 * l2 * p2[k].cos()).sqrt())),
        ("dist.L2", Box::new(|k| l1 * l1 + l2 * l2 + 2.0 * l1 * l2 * p2[k].cos())),
        ("rod_length.distance", Box::new(|_| l2)),
        ("to_b.x_out", Box::new(|_| 0.0)),
        ("to_b.y_out", Box::new(|k| l2 * w2[k])),
        ("to_b.phi_out", Box::new(|k| w2[k])),
        ("same.x_out", Box::new(|k| v_a(k)[0])),
        ("same.phi_out", Box::new(|k| w2[k])),
        ("to_world.x_out", Box::new(|k| turned_back(v_a(k), p1[k])[0])),
        ("to_world.y_out", Box::new(|k| turned_back(v_a(k), p1[k])[1])),
        // The absolute transform adds frame_in's angle to the angular part.
        ("to_world.phi_out", Box::new(|k| w2[k] + p1[k])),
    ];
    check("relative sensors", &s, STATE, checks);
    let swing = p2.iter().fold(0.0f64, |m, p| m.max((p - 0.4).abs()));
    assert!(swing > 0.3, "the outer link hardly swings ({swing})");
}

// ---------------------------------------------------------------------------
// Cut force, cut torque and power.

/// A pendulum with its bob behind the cut sensors, in series:
/// rod -> force (FrameA) -> force_world -> force_neg (FrameB, negative) ->
/// torque -> bob.
fn cut_pendulum(l: f64, mass: f64, inertia: f64, phi0: f64) -> Solution {
    let mut m = pendulum(l, mass, inertia, phi0);
    m.add("force", "PlanarMechanics.CutForce");
    m.add("force_world", "PlanarMechanics.CutForce").set("resolve_in_frame", resolve("World"));
    m.add("force_neg", "PlanarMechanics.CutForce")
        .set("resolve_in_frame", resolve("FrameB"))
        .set("positive_sign", false);
    m.add("torque", "PlanarMechanics.CutTorque");
    m.connect(["rod.frame_b", "force.frame_a"]);
    m.connect(["force.frame_b", "force_world.frame_a"]);
    m.connect(["force_world.frame_b", "force_neg.frame_a"]);
    m.connect(["force_neg.frame_b", "torque.frame_a"]);
    m.connect(["torque.frame_b", "body.frame_a"]);
    run(&m, 2.0)
}

#[test]
fn cut_force_holds_a_hanging_bob_with_m_g() {
    let (l, mass) = (0.9, 3.0);
    let s = cut_pendulum(l, mass, 0.2, -FRAC_PI_2);
    // At rest hanging: the rod pulls the sensor up with m g; frame_a points down.
    let checks: Vec<(&str, Expected)> = vec![
        ("rev.phi", Box::new(|_| -FRAC_PI_2)),
        ("force_world.force_x", Box::new(|_| 0.0)),
        ("force_world.force_y", Box::new(|_| mass * G)),
        ("force.force_x", Box::new(|_| -mass * G)),
        ("force.force_y", Box::new(|_| 0.0)),
        ("force.f0y", Box::new(|_| mass * G)),
        ("force.phi_resolve", Box::new(|_| -FRAC_PI_2)),
        ("force_neg.force_x", Box::new(|_| mass * G)),
        ("torque.torque", Box::new(|_| 0.0)),
    ];
    check("hanging CutForce", &s, 1e-10, checks);
}

#[test]
fn cut_force_and_torque_on_a_swinging_bob_match_newtons_law() {
    let (l, mass, inertia) = (0.9, 3.0, 0.2);
    let s = cut_pendulum(l, mass, inertia, 0.3);
    let (phi, w) = (column(&s, "rev.phi").to_vec(), column(&s, "rev.w").to_vec());
    let alpha = |k: usize| pendulum_alpha(l, mass, inertia, phi[k]);
    // What passes to the bob: m (a - g) in the world; along the rod and across it
    // in frame_a: m (-l w^2 + g sin phi) and m (l alpha + g cos phi).
    let along = |k: usize| mass * (-l * w[k] * w[k] + G * phi[k].sin());
    let across = |k: usize| mass * (l * alpha(k) + G * phi[k].cos());
    let world = |k: usize| {
        let (c, sn) = (phi[k].cos(), phi[k].sin());
        [c * along(k) - sn * across(k), sn * along(k) + c * across(k)]
    };
    let checks: Vec<(&str, Expected)> = vec![
        ("force.force_x", Box::new(along)),
        ("force.force_y", Box::new(across)),
        ("force_world.force_x", Box::new(|k| world(k)[0])),
        ("force_world.force_y", Box::new(|k| world(k)[1])),
        ("force_world.f0x", Box::new(|k| world(k)[0])),
        ("force_neg.force_x", Box::new(|k| -along(k))),
        ("force_neg.force_y", Box::new(|k| -across(k))),
        ("force_neg.f0y", Box::new(|k| -world(k)[1])),
        ("torque.torque", Box::new(|k| inertia * alpha(k))),
    ];
    check("swinging CutForce", &s, 1e-10, checks);
}

/// A free body pushed by a constant force and torque from WorldForceTorque
/// through a Power sensor: everything they put in is `F v_x + T w` with
/// `v_x = F t / m` and `w = T t / I` (gravity acts on the body directly,
/// not through the sensor): `(F^2 / m + T^2 / I) t`, the rate of the
/// kinetic energy of the pushed motions.
#[test]
fn power_into_a_pushed_body_is_force_times_speed() {
    let (f, torque, mass, inertia) = (2.0, 0.5, 4.0, 0.25);
    let mut m = Model::new("planar_power");
    m.add("world", "PlanarMechanics.World");
    m.add("push", "PlanarMechanics.WorldForceTorque");
    constant(&mut m, "f", f);
    constant(&mut m, "t", torque);
    m.connect(["f.y", "push.force_x"]);
    m.connect(["t.y", "push.torque"]);
    m.add("power", "PlanarMechanics.Power");
    m.connect(["push.frame_b", "power.frame_a"]);
    m.add("body", "PlanarMechanics.Body")
        .set("m", mass)
        .set("I", inertia)
        .initial("r", [0.0, 0.0])
        .initial("v", [0.0, 0.0])
        .initial("phi", 0.0)
        .initial("w", 0.0);
    m.connect(["power.frame_b", "body.frame_a"]);
    let s = run(&m, 2.0);
    let t = s.time().to_vec();
    let (vx, w, ke) = (column(&s, "body.v[1]").to_vec(), column(&s, "body.w").to_vec(), column(&s, "body.KE").to_vec());
    let checks: Vec<(&str, Expected)> = vec![
        ("power.power", Box::new(|k| (f * f / mass + torque * torque / inertia) * t[k])),
        ("body.v[2]", Box::new(|k| -G * t[k])),
    ];
    check("Power in time", &s, INTEGRATED, checks);
    let checks: Vec<(&str, Expected)> = vec![("power.power", Box::new(|k| f * vx[k] + torque * w[k]))];
    check("Power from the state", &s, STATE, checks);
    // d(KE)/dt by central differences (exact for the quadratic KE of these
    // constant accelerations), less gravity's m g^2 t, is the power.
    let (n, dt) = (t.len(), t[1] - t[0]);
    let power = column(&s, "power.power");
    let mut worst = 0.0f64;
    for k in 1..n - 1 {
        let rate = (ke[k + 1] - ke[k - 1]) / (2.0 * dt) - mass * G * G * t[k];
        worst = worst.max((rate - power[k]).abs());
    }
    eprintln!("Power and kinetic energy: worst error {worst:.1e} = {:.2} of 1e-7", worst / 1e-7);
    assert!(worst < 1e-7, "d(KE)/dt - m g^2 t differs from the power by {worst:e} W");
}

/// Sensor outputs feed back: a free planar body held by a PD force from an
/// AbsolutePosition and an AbsoluteVelocity (both resolved in frame_resolve,
/// here the world's origin turned by a quarter turn, so that their x is the
/// world's y) through blocks into a
/// WorldForceTorque: `f_y = k_p (y_ref - y) - k_d v_y`. The motion is the
/// critically damped `y = y_eq + (y0 - y_eq)(1 + wn t) exp(-wn t)` about
/// `y_eq = y_ref - m g / k_p`, with `wn = sqrt(k_p / m)`, `k_d = 2 m wn`.
#[test]
fn planar_sensors_in_a_pd_loop_hold_a_body_where_the_closed_form_says() {
    let (mass, kp, y_ref): (f64, f64, f64) = (2.0, 200.0, 1.0);
    let wn = (kp / mass).sqrt();
    let kd = 2.0 * mass * wn;
    let mut m = Model::new("planar_hover");
    m.add("world", "PlanarMechanics.World");
    m.add("body", "PlanarMechanics.Body")
        .set("m", mass)
        .set("I", 0.1)
        .initial("r", [0.0, 0.0])
        .initial("v", [0.0, 0.0])
        .initial("phi", 0.0)
        .initial("w", 0.0);
    m.add("turned", "PlanarMechanics.Fixed").set("phi", FRAC_PI_2);
    m.add("height", "PlanarMechanics.AbsolutePosition").set("resolve_in_frame", resolve("FrameResolve"));
    m.add("speed", "PlanarMechanics.AbsoluteVelocity").set("resolve_in_frame", resolve("FrameResolve"));
    m.add("thrust", "PlanarMechanics.WorldForceTorque");
    constant(&mut m, "setpoint", y_ref);
    m.add("error", "BlockComponents.Feedback");
    m.add("pd", "BlockComponents.Add").set("k1", kp).set("k2", -kd);
    m.connect(["body.frame_a", "height.frame_a", "speed.frame_a", "thrust.frame_b"]);
    m.connect(["turned.frame_b", "height.frame_resolve", "speed.frame_resolve"]);
    // In the turned frame, the world's y is x.
    m.connect(["setpoint.y", "error.u1"]);
    m.connect(["height.x", "error.u2"]);
    m.connect(["error.y", "pd.u1"]);
    m.connect(["speed.v_x", "pd.u2"]);
    m.connect(["pd.y", "thrust.force_y"]);
    let s = run(&m, 4.0);
    let y_eq = y_ref - mass * G / kp;
    let t = s.time().to_vec();
    let checks: Vec<(&str, Expected)> = vec![
        ("body.r[2]", Box::new(|k| y_eq - y_eq * (1.0 + wn * t[k]) * (-wn * t[k]).exp())),
        ("body.r[1]", Box::new(|_| 0.0)),
        ("height.y", Box::new(|_| 0.0)),
    ];
    check("PD loop", &s, 1e-7, checks);
}

// ---------------------------------------------------------------------------
// What the signal graph cannot read.

#[test]
fn reading_a_planar_acceleration_or_cut_force_is_a_clear_error() {
    for (kind, output) in [
        ("AbsoluteAcceleration", "a_x"),
        ("RelativeAcceleration", "rel_alpha"),
        ("CutForce", "force_y"),
        ("CutTorque", "torque"),
        ("Power", "power"),
    ] {
        let mut m = pendulum(1.0, 1.0, 0.1, 0.0);
        m.add("sensor", format!("PlanarMechanics.{kind}"));
        if kind.starts_with("Absolute") {
            m.connect(["rod.frame_b", "body.frame_a", "sensor.frame_a"]);
        } else {
            m.connect(["rod.frame_b", "sensor.frame_a"]);
            m.connect(["sensor.frame_b", "body.frame_a"]);
        }
        m.add("gain", "BlockComponents.Gain");
        m.connect([format!("sensor.{output}"), "gain.u".into()]);
        let err = m.assemble().unwrap_err();
        let text = err.to_string();
        assert!(matches!(err, Error::Unsupported { .. }), "{kind}: {text}");
        assert!(text.contains(output) && text.contains("recorded in the results"), "{kind}: {text}");
    }
}
