//! The 3-D sensors against closed forms: kinematic sensors on an undamped
//! revolute pendulum (from its own angle and rate), cut forces and torques
//! from Newton's law for the bob, power from a torque-driven turntable, and
//! a sensor in a feedback loop that holds a body at a height.
//!
//! Tolerances: a kinematic sensor is an algebraic function of the state at
//! the same instant, so it agrees with its closed form in the state to
//! rounding (values of order 1, errors of order 1e-15; we allow 1e-12).
//! Cut forces go through the accelerations of the articulated-body
//! algorithm, a few hundred flops more (1e-10 N on forces of order 10 N).
//! Closed forms in time (not in the state) carry the integration error,
//! which a run at abstol = reltol = 1e-11 keeps near 1e-9 (we allow 1e-7).

use multibody::{Model, SimulationOptions, Solution, Value};

const G: f64 = 9.80665;

fn tight(stop: f64) -> SimulationOptions {
    SimulationOptions { stop, saveat: 0.01, abstol: 1e-11, reltol: 1e-11, ..Default::default() }
}

fn column<'a>(s: &'a Solution, name: &str) -> &'a [f64] {
    s.get(name).unwrap_or_else(|| panic!("no column {name}"))
}

/// An undamped pendulum turning about the world's z axis: a massless rod of
/// length `l` along frame x, and a body of mass `m` (inertia `j` about z at
/// its centre) at the rod's end, through a CutForceAndTorque `cut`.
/// It starts at rest at `phi0` (0 is horizontal; it hangs at -pi/2).
fn pendulum(l: f64, m: f64, j: f64, phi0: f64) -> Model {
    let mut model = Model::new("pendulum");
    model.add("world", "World");
    model.add("rev", "Revolute").set("n", [0.0, 0.0, 1.0]).initial("phi", phi0).initial("w", 0.0);
    model.add("rod", "FixedTranslation").set("r", [l, 0.0, 0.0]);
    model.add("cut", "CutForceAndTorque");
    model.add("body", "Body").set("m", m).set("r_cm", [0.0, 0.0, 0.0]).set("I_11", j).set("I_22", j).set("I_33", j);
    model.connect(["world.frame_b", "rev.frame_a"]);
    model.connect(["rev.frame_b", "rod.frame_a"]);
    model.connect(["rod.frame_b", "cut.frame_a"]);
    model.connect(["cut.frame_b", "body.frame_a"]);
    model
}

/// Worst absolute difference between `got` and `expected(k)` over the run.
/// A closed form: the expected value at sample `k`.
type Expected<'a> = Box<dyn Fn(usize) -> f64 + 'a>;

fn worst(got: &[f64], expected: impl Fn(usize) -> f64) -> f64 {
    got.iter().enumerate().map(|(k, g)| (g - expected(k)).abs()).fold(0.0, f64::max)
}

#[test]
fn kinematic_sensors_on_a_pendulum_match_its_angle_and_rate() {
    let l = 0.8;
    let mut model = pendulum(l, 1.0, 0.0, -std::f64::consts::FRAC_PI_2 + 1.2);
    model.add("angles", "AbsoluteAngles");
    model.add("angles_far", "AbsoluteAngles").set("guess_angle1", 3.0);
    model.add("pos", "RelativePosition").set("resolve_in_frame", Value::Enum("World".into()));
    model.add("pos_b", "RelativePosition").set("resolve_in_frame", Value::Enum("FrameB".into()));
    model.add("abs_pos", "AbsolutePosition").set("resolve_in_frame", Value::Enum("FrameResolve".into()));
    model.add("vel", "AbsoluteVelocity").set("resolve_in_frame", Value::Enum("World".into()));
    model.add("vel_a", "AbsoluteVelocity");
    model.add("omega", "AbsoluteAngularVelocity");
    model.add("omega_rel", "RelativeAngularVelocity").set("resolve_in_frame", Value::Enum("World".into()));
    model.add("rel_vel", "RelativeVelocity");
    model.add("rel_angles", "RelativeAngles");
    model.add("dist", "Distance");
    model
        .add("rel", "RelativeSensor")
        .set("resolve_in_frame", Value::Enum("World".into()))
        .set("get_v_rel", true)
        .set("get_w_rel", true)
        .set("get_angles", true);
    // Outputs through Gain blocks: what a feedback would read.
    for (gain, output) in
        [("g_dist", "dist.distance"), ("g_vx", "vel.v_x"), ("g_rx", "abs_pos.r_x"), ("g_ry", "abs_pos.r_y")]
    {
        model.add(gain, "BlockComponents.Gain").set("k", 1.0);
        model.connect([output.to_string(), format!("{gain}.u")]);
    }
    model.connect(["rod.frame_b", "angles.frame_a", "angles_far.frame_a", "vel.frame_a", "vel_a.frame_a"]);
    model.connect(["rod.frame_b", "omega.frame_a", "abs_pos.frame_a", "abs_pos.frame_resolve"]);
    model.connect(["world.frame_b", "pos.frame_a", "pos_b.frame_a", "omega_rel.frame_a", "dist.frame_a"]);
    model.connect(["rod.frame_b", "pos.frame_b", "pos_b.frame_b", "omega_rel.frame_b", "dist.frame_b"]);
    // Seen from the rod's own rotating frame the bob does not move.
    model.connect(["rev.frame_b", "rel_vel.frame_a", "rel_angles.frame_a"]);
    model.connect(["rod.frame_b", "rel_vel.frame_b", "rel_angles.frame_b"]);
    model.connect(["world.frame_b", "rel.frame_a"]);
    model.connect(["rod.frame_b", "rel.frame_b"]);

    let solution = model.assemble().unwrap().simulate(&tight(3.0)).unwrap();
    let phi = column(&solution, "rev.phi");
    let w = column(&solution, "rev.w");
    assert!(phi.iter().any(|p| *p < -2.0), "the pendulum swings through its lowest point");
    let (c, s) = (|k: usize| phi[k].cos(), |k: usize| phi[k].sin());
    let checks: Vec<(&str, Expected)> = vec![
        ("angles.angles[1]", Box::new(|_| 0.0)),
        ("angles.angles[2]", Box::new(|_| 0.0)),
        ("angles.angles[3]", Box::new(|k| phi[k])),
        // The other solution: (pi, pi, phi + pi) wrapped into [-pi, pi].
        ("angles_far.angles[1]", Box::new(|_| std::f64::consts::PI)),
        ("angles_far.angles[2]", Box::new(|_| std::f64::consts::PI)),
        ("angles_far.angles[3]", Box::new(|k| phi[k] + std::f64::consts::PI)),
        ("pos.r_rel[1]", Box::new(|k| l * c(k))),
        ("pos.r_rel[2]", Box::new(|k| l * s(k))),
        ("pos.r_rel[3]", Box::new(|_| 0.0)),
        ("pos_b.r_rel[1]", Box::new(|_| l)),
        ("pos_b.r_rel[2]", Box::new(|_| 0.0)),
        ("abs_pos.r[1]", Box::new(|_| l)),
        ("abs_pos.r[2]", Box::new(|_| 0.0)),
        ("g_rx.y", Box::new(|_| l)),
        ("g_ry.y", Box::new(|_| 0.0)),
        ("vel.v[1]", Box::new(|k| -l * w[k] * s(k))),
        ("vel.v[2]", Box::new(|k| l * w[k] * c(k))),
        ("g_vx.y", Box::new(|k| -l * w[k] * s(k))),
        ("vel.v0[2]", Box::new(|k| l * w[k] * c(k))),
        ("vel_a.v[1]", Box::new(|_| 0.0)),
        ("vel_a.v[2]", Box::new(|k| l * w[k])),
        ("omega.w[1]", Box::new(|_| 0.0)),
        ("omega.w[2]", Box::new(|_| 0.0)),
        ("omega.w[3]", Box::new(|k| w[k])),
        ("omega_rel.w_rel[3]", Box::new(|k| w[k])),
        ("omega_rel.R_rel[1,1]", Box::new(c)),
        ("omega_rel.R_rel[1,2]", Box::new(s)),
        ("rel_vel.v_rel[1]", Box::new(|_| 0.0)),
        ("rel_vel.v_rel[2]", Box::new(|_| 0.0)),
        ("rel_vel.r_rel_a[1]", Box::new(|_| l)),
        ("rel_angles.angles[3]", Box::new(|_| 0.0)),
        ("rel.v_rel[1]", Box::new(|k| -l * w[k] * s(k))),
        ("rel.v_rel[2]", Box::new(|k| l * w[k] * c(k))),
        ("rel.w_rel[3]", Box::new(|k| w[k])),
        ("rel.angles[3]", Box::new(|k| phi[k])),
        ("dist.distance", Box::new(|_| l)),
        ("dist.L2", Box::new(|_| l * l)),
        ("g_dist.y", Box::new(|_| l)),
    ];
    let mut report = Vec::new();
    for (name, expected) in &checks {
        let err = worst(column(&solution, name), expected);
        report.push(format!("{name}: {err:.1e}"));
        assert!(err < 1e-12, "{name}: worst error {err:e}");
    }
    println!("{}", report.join("\n"));
}

/// The force and torque the rod passes to the bob, from Newton's and
/// Euler's laws for the bob: with `e_r` along the rod and `e_t` across it,
/// `f = m (a - g)` has `f . e_r = m (g sin phi - l w^2)` and
/// `f . e_t = m (l w' + g cos phi)`, and the torque is `J w'`, where
/// `w' = -m g l cos phi / (m l^2 + J)`.
#[test]
fn cut_force_and_torque_at_a_pendulum_bob_match_newtons_law() {
    let (l, m, j) = (0.6, 2.0, 0.05);
    // The sensors in series between the rod and the bob, each passing on
    // what it receives: rod -> cut -> cut_world -> cut_neg -> force -> torque -> body.
    let mut model = Model::new("pendulum");
    model.add("world", "World");
    model.add("rev", "Revolute").set("n", [0.0, 0.0, 1.0]).initial("phi", 0.4).initial("w", 0.0);
    model.add("rod", "FixedTranslation").set("r", [l, 0.0, 0.0]);
    model.add("cut", "CutForceAndTorque");
    model.add("cut_world", "CutForceAndTorque").set("resolve_in_frame", Value::Enum("World".into()));
    model.add("cut_neg", "CutForceAndTorque").set("positive_sign", false);
    model.add("force", "CutForce");
    model.add("torque", "CutTorque");
    model.add("body", "Body").set("m", m).set("r_cm", [0.0, 0.0, 0.0]).set("I_11", j).set("I_22", j).set("I_33", j);
    model.connect(["world.frame_b", "rev.frame_a"]);
    model.connect(["rev.frame_b", "rod.frame_a"]);
    model.connect(["rod.frame_b", "cut.frame_a"]);
    model.connect(["cut.frame_b", "cut_world.frame_a"]);
    model.connect(["cut_world.frame_b", "cut_neg.frame_a"]);
    model.connect(["cut_neg.frame_b", "force.frame_a"]);
    model.connect(["force.frame_b", "torque.frame_a"]);
    model.connect(["torque.frame_b", "body.frame_a"]);

    let solution = model.assemble().unwrap().simulate(&tight(2.0)).unwrap();
    let phi = column(&solution, "rev.phi");
    let w = column(&solution, "rev.w");
    let wd = |k: usize| -m * G * l * phi[k].cos() / (m * l * l + j);
    let f_r = |k: usize| m * (G * phi[k].sin() - l * w[k] * w[k]);
    let f_t = |k: usize| m * (l * wd(k) + G * phi[k].cos());
    // In the world: f_r e_r + f_t e_t with e_r = (cos, sin), e_t = (-sin, cos).
    let f_x = |k: usize| f_r(k) * phi[k].cos() - f_t(k) * phi[k].sin();
    let f_y = |k: usize| f_r(k) * phi[k].sin() + f_t(k) * phi[k].cos();
    let checks: Vec<(&str, Expected)> = vec![
        ("cut.force[1]", Box::new(f_r)),
        ("cut.force[2]", Box::new(f_t)),
        ("cut.force[3]", Box::new(|_| 0.0)),
        ("cut.torque[1]", Box::new(|_| 0.0)),
        ("cut.torque[3]", Box::new(|k| j * wd(k))),
        ("cut_world.force[1]", Box::new(f_x)),
        ("cut_world.force[2]", Box::new(f_y)),
        ("cut_world.torque[3]", Box::new(|k| j * wd(k))),
        ("cut_neg.force[1]", Box::new(|k| -f_r(k))),
        ("cut_neg.torque[3]", Box::new(|k| -j * wd(k))),
        ("force.force[1]", Box::new(f_r)),
        ("force.force[2]", Box::new(f_t)),
        ("torque.torque[3]", Box::new(|k| j * wd(k))),
    ];
    let mut report = Vec::new();
    for (name, expected) in &checks {
        let err = worst(column(&solution, name), expected);
        report.push(format!("{name}: {err:.1e}"));
        assert!(err < 1e-10, "{name}: worst error {err:e} N");
    }
    println!("{}", report.join("\n"));
}

/// A turntable about the vertical (gravity exerts no torque about it)
/// driven by a constant torque `tau`: the power through the rod's end into
/// the body is everything the torque puts in, `tau w`, with
/// `w = tau t / J` and `J = I_22 + m x^2`; both `f . v` and `tau . w` terms
/// of the sensor contribute, the body sitting off the axis.
#[test]
fn power_into_a_driven_turntable_is_torque_times_speed() {
    let (tau, m, x, i22) = (0.8, 1.5, 0.4, 0.02);
    let mut model = Model::new("turntable");
    model.add("world", "World");
    model.add("rev", "Revolute").set("n", [0.0, 1.0, 0.0]).initial("phi", 0.0).initial("w", 0.0);
    model.add("rod", "FixedTranslation").set("r", [x, 0.0, 0.0]);
    model.add("power", "Power");
    model.add("body", "Body").set("m", m).set("r_cm", [0.0, 0.0, 0.0]).set("I_22", i22);
    model.add("motor", "RotationalComponents.ConstantTorque").set("tau_constant", tau);
    model.connect(["world.frame_b", "rev.frame_a"]);
    model.connect(["rev.frame_b", "rod.frame_a"]);
    model.connect(["rod.frame_b", "power.frame_a"]);
    model.connect(["power.frame_b", "body.frame_a"]);
    model.connect(["motor.spline", "rev.axis"]);
    model.connect(["motor.support", "rev.support"]);
    let solution = model.assemble().unwrap().simulate(&tight(2.0)).unwrap();
    let t = solution.time();
    let j = i22 + m * x * x;
    let err = worst(column(&solution, "power.power"), |k| tau * tau * t[k] / j);
    println!("power: worst error {err:.1e} W");
    assert!(err < 1e-7, "power: worst error {err:e} W");
    // The same from the joint's own rate: tau w at every sample.
    let w = column(&solution, "rev.w");
    let err = worst(column(&solution, "power.power"), |k| tau * w[k]);
    assert!(err < 1e-10, "power vs tau w: worst error {err:e} W");
}

/// The issue's "a sensor drives a force": a body on a vertical prismatic
/// joint, held by a PD force from an AbsolutePosition and an
/// AbsoluteVelocity sensor through blocks into a WorldForce:
/// `f = k_p (y_ref - y) - k_d v`. The motion is the critically damped
/// `y = y_eq + (y0 - y_eq)(1 + wn t) exp(-wn t)` about
/// `y_eq = y_ref - m g / k_p`, with `wn = sqrt(k_p / m)`, `k_d = 2 m wn`.
#[test]
fn a_position_sensor_in_a_pd_loop_holds_a_body_where_the_closed_form_says() {
    let (m, kp, y_ref): (f64, f64, f64) = (2.0, 200.0, 1.0);
    let wn = (kp / m).sqrt();
    let kd = 2.0 * m * wn;
    let mut model = Model::new("hover");
    model.add("world", "World");
    model.add("slider", "Prismatic").set("n", [0.0, 1.0, 0.0]).initial("s", 0.0).initial("v", 0.0);
    model.add("body", "Body").set("m", m).set("r_cm", [0.0, 0.0, 0.0]);
    model.add("height", "AbsolutePosition").set("resolve_in_frame", Value::Enum("World".into()));
    model.add("speed", "AbsoluteVelocity").set("resolve_in_frame", Value::Enum("World".into()));
    model.add("setpoint", "BlockComponents.Constant").set("k", y_ref);
    model.add("error", "BlockComponents.Feedback");
    model.add("pd", "BlockComponents.Add").set("k1", kp).set("k2", -kd);
    model.add("thrust", "WorldForce");
    model.connect(["world.frame_b", "slider.frame_a"]);
    model.connect(["slider.frame_b", "body.frame_a", "height.frame_a", "speed.frame_a", "thrust.frame_b"]);
    model.connect(["setpoint.y", "error.u1"]);
    model.connect(["height.r_y", "error.u2"]);
    model.connect(["error.y", "pd.u1"]);
    model.connect(["speed.v_y", "pd.u2"]);
    model.connect(["pd.y", "thrust.force_y"]);
    let mechanism = model.assemble().unwrap();
    let solution = mechanism.simulate(&tight(4.0)).unwrap();
    let y_eq = y_ref - m * G / kp;
    let t = solution.time();
    let expected = |k: usize| y_eq - y_eq * (1.0 + wn * t[k]) * (-wn * t[k]).exp();
    let err = worst(column(&solution, "slider.s"), expected);
    println!("height: worst error {err:.1e} m; final {} vs {y_eq}", solution.last("slider.s").unwrap());
    assert!(err < 1e-7, "height: worst error {err:e} m");
    assert!((solution.last("height.r[2]").unwrap() - y_eq).abs() < 1e-7);
}

/// Cut forces, accelerations and switched-off outputs cannot feed the
/// model: assembly says which output and why, instead of feeding NaN or 0.
#[test]
fn reading_a_cut_force_or_a_switched_off_output_is_a_clear_error() {
    let mut model = pendulum(0.5, 1.0, 0.01, 0.0);
    model.add("push", "WorldForce");
    model.connect(["body.frame_a", "push.frame_b"]);
    model.connect(["cut.force_y", "push.force_x"]);
    let err = model.assemble().unwrap_err().to_string();
    assert!(err.contains("cut.force_y") && err.contains("push.force_x") && err.contains("cut forces"), "{err}");

    let mut model = pendulum(0.5, 1.0, 0.01, 0.0);
    model.add("abs", "AbsoluteSensor").set("get_a", true);
    model.add("gain", "BlockComponents.Gain");
    model.connect(["body.frame_a", "abs.frame_a"]);
    model.connect(["abs.a_x", "gain.u"]);
    let err = model.assemble().unwrap_err().to_string();
    assert!(err.contains("abs.a_x") && err.contains("accelerations"), "{err}");

    let mut model = pendulum(0.5, 1.0, 0.01, 0.0);
    model.add("abs", "AbsoluteSensor");
    model.add("gain", "BlockComponents.Gain");
    model.connect(["body.frame_a", "abs.frame_a"]);
    model.connect(["abs.r_x", "gain.u"]);
    let err = model.assemble().unwrap_err().to_string();
    assert!(err.contains("abs.r_x") && err.contains("get_r = false"), "{err}");

    // Unread, the same outputs are fine, and recorded.
    let mut model = pendulum(0.5, 1.0, 0.01, 0.0);
    model.add("abs", "AbsoluteSensor").set("get_a", true).set("get_r", true);
    model.connect(["body.frame_a", "abs.frame_a"]);
    let solution = model.assemble().unwrap().simulate(&tight(0.5)).unwrap();
    assert!(solution.get("abs.a[1]").is_some() && solution.get("abs.r[1]").is_some());
    assert!(solution.get("abs.v[1]").is_none(), "switched-off groups are not recorded");
}

/// Angles of a frame turned by three fixed rotations about coordinate axes
/// are those rotations, for a Cardan and for a proper Euler sequence
/// (`R = A_k(phi3) A_j(phi2) A_i(phi1)`), absolute and relative.
#[test]
fn angle_sensors_recover_the_rotations_of_a_fixed_chain() {
    for (sequence, angles) in [([3.0, 2.0, 1.0], [0.3, -0.4, 0.5]), ([3.0, 1.0, 3.0], [0.3, 0.7, -0.2])] {
        let mut model = Model::new("turned");
        model.add("world", "World");
        let axis = |a: f64| {
            let mut n = [0.0; 3];
            n[a as usize - 1] = 1.0;
            n
        };
        let mut previous = "world.frame_b".to_string();
        for (k, (&a, &angle)) in sequence.iter().zip(&angles).enumerate() {
            let name = format!("turn{k}");
            model.add(&name, "FixedRotation").set("n", axis(a)).set("angle", angle);
            model.connect([previous.clone(), format!("{name}.frame_a")]);
            previous = format!("{name}.frame_b");
        }
        model.add("angles", "AbsoluteAngles").set("sequence", sequence.to_vec());
        model.add("rel", "RelativeAngles").set("sequence", sequence.to_vec());
        model.connect([previous.clone(), "angles.frame_a".into()]);
        model.connect(["turn0.frame_a".to_string(), "rel.frame_a".into()]);
        model.connect([previous, "rel.frame_b".into()]);
        let solution = model.assemble().unwrap().simulate(&tight(0.1)).unwrap();
        for (i, expected) in angles.iter().enumerate() {
            for sensor in ["angles", "rel"] {
                let got = solution.last(&format!("{sensor}.angles[{}]", i + 1)).unwrap();
                assert!((got - expected).abs() < 1e-12, "{sequence:?} {sensor}.angles[{}] = {got}", i + 1);
            }
        }
    }
}

/// A relative sensor whose frame_resolve is connected while its
/// resolve_in_frame names another frame grounded what it was connected to:
/// a pendulum's body, which then could not move ("`rev.phi` is not a state
/// here"). Connecting it is now refused with what to do; resolving in it,
/// the pendulum swings as without the sensor.
#[test]
fn a_sensor_frame_resolve_it_does_not_use_cannot_be_connected() {
    let pendulum = |resolve: Option<&str>| {
        let mut m = Model::new("resolved");
        m.add("world", "World");
        m.add("rev", "Revolute").set("n", [0.0, 0.0, 1.0]).initial("phi", 0.5).initial("w", 0.0);
        m.add("body", "Body").set("m", 1.0).set("r_cm", [0.5, 0.0, 0.0]);
        let sensor = m.add("sensor", "RelativeVelocity");
        if let Some(frame) = resolve {
            sensor.set("resolve_in_frame", Value::Enum(frame.into()));
        }
        m.connect(["world.frame_b", "rev.frame_a", "sensor.frame_a"]);
        m.connect(["rev.frame_b", "body.frame_a", "sensor.frame_b", "sensor.frame_resolve"]);
        m.assemble().map_err(|e| e.to_string())
    };
    let refused = pendulum(None).unwrap_err();
    assert!(
        refused.contains("`sensor.frame_resolve`")
            && refused.contains("resolve_in_frame = ResolveInFrame.FrameResolve"),
        "{refused}"
    );
    let options = SimulationOptions { stop: 0.5, saveat: 0.05, ..Default::default() };
    let resolved = pendulum(Some("FrameResolve")).unwrap().simulate(&options).unwrap();
    // The same pendulum without the sensor.
    let mut bare = Model::new("bare");
    bare.add("world", "World");
    bare.add("rev", "Revolute").set("n", [0.0, 0.0, 1.0]).initial("phi", 0.5).initial("w", 0.0);
    bare.add("body", "Body").set("m", 1.0).set("r_cm", [0.5, 0.0, 0.0]);
    bare.connect(["world.frame_b", "rev.frame_a"]);
    bare.connect(["rev.frame_b", "body.frame_a"]);
    let bare = bare.assemble().unwrap().simulate(&options).unwrap();
    let worst = resolved
        .get("rev.phi")
        .unwrap()
        .iter()
        .zip(bare.get("rev.phi").unwrap())
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    assert!(worst < 1e-12, "the sensor changed the motion by {worst}");
    // The relative velocity resolved in the body's own frame: the body's
    // origin turns with it about the hinge at the same place, so it is zero.
    assert!(resolved.get("sensor.v_rel[1]").unwrap().iter().all(|v| v.abs() < 1e-9));
}
