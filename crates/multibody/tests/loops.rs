//! Kinematic loops closed without the user's help: degrees of freedom and
//! redundant equations of planar loops, constraints and energy kept over
//! long runs, an impossible loop named, and equivalent formulations of a
//! spherical pendulum.

use multibody::{Error, Model, OrientationState, SimulationOptions, Solution, Value};

#[path = "common/four_bar.rs"]
mod four_bar;
use four_bar::four_bar;

fn energy(solution: &Solution, bodies: &[&str], k: usize) -> f64 {
    bodies
        .iter()
        .map(|b| solution.get(&format!("{b}.KE")).unwrap()[k] + solution.get(&format!("{b}.PE")).unwrap()[k])
        .sum()
}

fn worst_residual(solution: &Solution) -> f64 {
    let mut worst = 0.0f64;
    for name in solution.names().iter().filter(|n| n.contains("constraint_residual")) {
        worst = solution.get(name).unwrap().iter().fold(worst, |a, r| a.max(r.abs()));
    }
    worst
}

/// A planar loop of spatial revolutes: 5 equations of which 3 repeat the
/// others (planar loops have 3 independent ones), 1 degree of freedom.
#[test]
fn planar_four_bar_has_one_degree_of_freedom_and_three_redundant_equations() {
    let mechanism = four_bar(0.0, 1.0, 3.0).assemble().unwrap();
    let loops = mechanism.loops();
    println!("four-bar: {} degree(s) of freedom; loops: {loops:?}", mechanism.degrees_of_freedom());
    assert_eq!(mechanism.degrees_of_freedom(), 1);
    assert_eq!(loops.len(), 1);
    assert_eq!((loops[0].equations, loops[0].redundant), (5, 3));
    assert_eq!(loops[0].joints.len(), 4, "the loop goes through the four revolutes: {:?}", loops[0].joints);
}

/// Over 100 s undamped, the constraint residual stays below 1e-8 and the
/// energy changes by less than 1e-6 of its scale (the projection after
/// every step keeps the loop closed; the integrator tolerance sets the
/// energy error).
#[test]
fn undamped_loop_keeps_its_constraints_and_energy_for_100_seconds() {
    let mechanism = four_bar(0.0, 1.0, 3.0).assemble().unwrap();
    let options = SimulationOptions { stop: 100.0, saveat: 0.01, abstol: 1e-10, reltol: 1e-10, ..Default::default() };
    let solution = mechanism.simulate(&options).unwrap();
    let bodies = ["crank", "coupler", "rocker"];
    let e0 = energy(&solution, &bodies, 0);
    // Relative to the energy's own scale: the kinetic energy at the start plus the potential swing.
    let ke0: f64 = bodies.iter().map(|b| solution.get(&format!("{b}.KE")).unwrap()[0]).sum();
    let scale = ke0 + 3.0 * 9.80665 * 1.5;
    let drift = (0..solution.len()).map(|k| (energy(&solution, &bodies, k) - e0).abs()).fold(0.0, f64::max) / scale;
    let residual = worst_residual(&solution);
    let turns = solution.last("j1.phi").unwrap() / std::f64::consts::TAU;
    println!("100 s undamped four-bar ({turns:.1} crank turns): worst constraint residual {residual:.2e} (limit 1e-8), energy drift {drift:.2e} relative (limit 1e-6)");
    assert!(residual < 1e-8);
    assert!(drift < 1e-6);
}

/// With a damper the energy only goes down.
#[test]
fn damped_loop_loses_energy_monotonically() {
    let solution = four_bar(0.5, 1.0, 3.0)
        .assemble()
        .unwrap()
        .simulate(&SimulationOptions { stop: 10.0, saveat: 0.01, ..Default::default() })
        .unwrap();
    let bodies = ["crank", "coupler", "rocker"];
    let rises = (1..solution.len())
        .map(|k| energy(&solution, &bodies, k) - energy(&solution, &bodies, k - 1))
        .fold(f64::NEG_INFINITY, f64::max);
    println!(
        "damped four-bar: largest energy increase between samples {rises:.2e} J; lost {:.3} J",
        energy(&solution, &bodies, 0) - energy(&solution, &bodies, solution.len() - 1)
    );
    assert!(rises < 1e-6);
}

/// The library's planar four-bar (examples.FourBar, as in Multibody.jl's
/// tutorial): five revolutes about z, a square of four bars of 1.5 m, two
/// of them pinned at the world origin, dampers on j1 and j2, j1 started at
/// 0.1 rad. Here j4 is a plain Revolute: no special component is needed.
#[test]
fn library_four_bar_runs_with_plain_revolutes() {
    let l = 1.5;
    let mut model = Model::new("FourBar");
    model.add("world", "World");
    model.add("j1", "Revolute").set("axisflange", true).initial("phi", 0.1);
    model.add("j2", "Revolute").set("axisflange", true);
    for j in ["j3", "j4", "j5"] {
        model.add(j, "Revolute");
    }
    for (b, r) in [("b1", [l, 0.0, 0.0]), ("b2", [0.0, l, 0.0]), ("b3", [-l, 0.0, 0.0]), ("b4", [0.0, -l, 0.0])] {
        model.add(b, "BodyShape").set("m", 1.0).set("r", r);
    }
    model.add("damper1", "RotationalComponents.Damper").set("d", 0.1);
    model.add("damper2", "RotationalComponents.Damper").set("d", 0.1);
    for (a, b) in [
        ("world.frame_b", "j1.frame_a"),
        ("j1.frame_b", "b1.frame_a"),
        ("b1.frame_b", "j2.frame_a"),
        ("j2.frame_b", "b2.frame_a"),
        ("b2.frame_b", "j3.frame_a"),
        ("j3.frame_b", "b3.frame_a"),
        ("b3.frame_b", "j4.frame_a"),
        ("j4.frame_b", "b4.frame_a"),
        ("b4.frame_b", "j5.frame_a"),
        ("j5.frame_b", "world.frame_b"),
        ("damper1.spline_a", "j1.support"),
        ("damper1.spline_b", "j1.axis"),
        ("damper2.spline_a", "j2.support"),
        ("damper2.spline_b", "j2.axis"),
    ] {
        model.connect([a, b]);
    }
    let mechanism = model.assemble().unwrap();
    println!(
        "library four-bar: {} degrees of freedom (5 joint coordinates - 3 planar constraints), loops {:?}",
        mechanism.degrees_of_freedom(),
        mechanism.loops()
    );
    assert_eq!(mechanism.degrees_of_freedom(), 2);
    assert_eq!(mechanism.loops()[0].redundant, 3);
    let solution = mechanism.simulate(&SimulationOptions { stop: 10.0, saveat: 0.01, ..Default::default() }).unwrap();
    let residual = worst_residual(&solution);
    println!("library four-bar over 10 s: worst constraint residual {residual:.2e}");
    assert!(residual < 1e-8);
}

/// A coupler (0.22 m) too short to reach the rocker (0.22 + 1.5 < 2.06 m,
/// the distance from A to C with the crank held at 0): the loop cannot close, and the
/// error names its joints.
#[test]
fn impossible_loop_is_named() {
    let err = four_bar(0.0, 0.1, 3.0).assemble().unwrap_err();
    println!("{err}");
    let Error::LoopCannotClose { joints, .. } = &err else { panic!("expected LoopCannotClose, got {err:?}") };
    for j in ["j1", "j2", "j3", "j4"] {
        assert!(joints.iter().any(|n| n == j), "{j} missing from {joints:?}");
    }
    assert!(err.to_string().contains("cannot close"));
}

/// A spherical pendulum three ways: Spherical with Euler states, with
/// quaternion states, and without states (the body owns its orientation
/// and the joint is a constraint). They must agree to integration accuracy.
#[test]
fn spherical_joint_with_euler_quaternion_or_no_states_agree() {
    use multibody::math::{axes_rotations, to_q, Quat, Vec3};
    let tilt = Vec3::new(0.4, 0.0, 0.3);
    let run = |state: &str| {
        let mut model = Model::new("spherical");
        model.add("world", "World");
        let joint = model.add("joint", "Spherical").set("orientation_state", Value::Enum(state.into()));
        let body = match state {
            "Euler" => {
                joint.initial("phi", tilt).initial("phid", [0.0, 2.0, 0.0]);
                model.add("body", "Body")
            }
            "Quaternion" => {
                let q = to_q(&axes_rotations([1, 2, 3], &tilt), &Quat::new(1.0, 0.0, 0.0, 0.0));
                joint.initial("Q_hat", q.as_slice()).initial("w_rel", w_start(&tilt));
                model.add("body", "Body")
            }
            _ => {
                let q = to_q(&axes_rotations([1, 2, 3], &tilt), &Quat::new(1.0, 0.0, 0.0, 0.0));
                let body = model.add("body", "Body").set("orientation_state", OrientationState::Quaternion);
                body.initial("Q_hat", q.as_slice()).initial("w_a", w_start(&tilt));
                body
            }
        };
        body.set("m", 2.0).set("r_cm", [0.0, -0.8, 0.0]).set("I_11", 0.05).set("I_22", 0.02).set("I_33", 0.05);
        model.connect(["world.frame_b", "joint.frame_a"]);
        model.connect(["joint.frame_b", "body.frame_a"]);
        let options = SimulationOptions { stop: 3.0, saveat: 0.01, abstol: 1e-9, reltol: 1e-9, ..Default::default() };
        model.assemble().unwrap().simulate(&options).unwrap()
    };
    // phid = [0, 2, 0] at phi = tilt is this angular velocity in the body frame.
    fn w_start(tilt: &multibody::math::Vec3) -> [f64; 3] {
        let w =
            multibody::math::axes_rotations_rate_matrix([1, 2, 3], tilt) * multibody::math::Vec3::new(0.0, 2.0, 0.0);
        [w.x, w.y, w.z]
    }
    let euler = run("Euler");
    for other in ["Quaternion", "None"] {
        let solution = run(other);
        let mut worst = 0.0f64;
        for i in 1..=3 {
            for j in 1..=3 {
                let name = format!("body.frame_a.R[{i},{j}]");
                let (a, b) = (euler.get(&name).unwrap(), solution.get(&name).unwrap());
                worst = a.iter().zip(b).fold(worst, |w, (x, y)| w.max((x - y).abs()));
            }
        }
        println!("spherical pendulum, Euler vs {other}: worst |R difference| {worst:.2e} (tolerance 1e-6)");
        assert!(worst < 1e-6);
    }
}

/// A planar four-bar (crank 1 from the origin, coupler 1, rocker 0.5 to a
/// pivot at [1.2, 0]) whose crank is driven at 1 rad/s from 60 degrees. The
/// loop closes only while the crank tip is within 1.5 of the pivot: from
/// cos(theta) = (1 + 1.44 - 2.25) / 2.4 on it cannot. The run stops there
/// (t = acos(0.0791667) - pi / 3 = 0.4443 s), naming the loop, with what was
/// computed kept, instead of running on with the loop open.
#[test]
fn a_four_bar_driven_past_its_dead_point_stops_there_naming_the_loop() {
    let mut m = Model::new("past_dead_point");
    m.add("world", "PlanarMechanics.World");
    m.add("crank_joint", "PlanarMechanics.Revolute").initial("phi", std::f64::consts::FRAC_PI_3).initial("w", 1.0);
    for (name, length) in [("crank", 1.0), ("coupler", 1.0), ("rocker", 0.5)] {
        m.add(name, "PlanarMechanics.BodyShape").set("r", [length, 0.0]).set("m", 1.0).set("I", 0.1);
    }
    for joint in ["coupler_joint", "rocker_joint", "ground_joint"] {
        m.add(joint, "PlanarMechanics.Revolute");
    }
    m.add("base", "PlanarMechanics.Fixed").set("r", [1.2, 0.0]);
    m.add("drive", "RotationalComponents.Speed");
    m.add("mount", "RotationalComponents.Fixed");
    m.add("speed", "BlockComponents.Constant").set("k", 1.0);
    m.connect(["world.frame_b", "crank_joint.frame_a"]);
    m.connect(["crank_joint.frame_b", "crank.frame_a"]);
    m.connect(["crank.frame_b", "coupler_joint.frame_a"]);
    m.connect(["coupler_joint.frame_b", "coupler.frame_a"]);
    m.connect(["coupler.frame_b", "rocker_joint.frame_a"]);
    m.connect(["rocker_joint.frame_b", "rocker.frame_a"]);
    m.connect(["rocker.frame_b", "ground_joint.frame_a"]);
    m.connect(["ground_joint.frame_b", "base.frame_b"]);
    m.connect(["speed.y", "drive.w_ref"]);
    m.connect(["drive.spline", "crank_joint.flange_a"]);
    m.connect(["drive.support", "mount.spline"]);
    let options = SimulationOptions { stop: 1.0, saveat: 0.01, ..Default::default() };
    let stopped = m.assemble().unwrap().simulate(&options).unwrap_err();
    let dead_point = (0.19f64 / 2.4).acos() - std::f64::consts::FRAC_PI_3;
    let message = stopped.to_string();
    eprintln!("four-bar past its dead point ({dead_point:.5} s): {message}");
    assert!((stopped.time - dead_point).abs() < 1e-3, "stopped at {} instead of near {dead_point}", stopped.time);
    for expected in ["loop", "`ground_joint`", "`crank_joint`", "cannot close", "dead point"] {
        assert!(message.contains(expected), "`{expected}` missing from: {message}");
    }
    let kept = stopped.partial.time();
    assert!(kept.len() > 40 && *kept.last().unwrap() <= stopped.time, "the samples before the stop are kept");
}

/// A four-bar of spatial revolutes about z in the x-y plane: a crank from
/// the origin (joint j1 to the World), a coupler, and a rocker from the
/// ground pivot at `[ground, 0, 0]` (joint j4), closing at j3; each bar a
/// 1 kg BodyShape of the given length along its x.
fn spatial_four_bar(name: &str, [crank, coupler, rocker, ground]: [f64; 4]) -> Model {
    let mut m = Model::new(name);
    m.add("world", "World");
    m.add("ground", "FixedTranslation").set("r", [ground, 0.0, 0.0]);
    for j in ["j1", "j2", "j3", "j4"] {
        m.add(j, "Revolute");
    }
    for (name, length) in [("crank", crank), ("coupler", coupler), ("rocker", rocker)] {
        m.add(name, "BodyShape")
            .set("r", [length, 0.0, 0.0])
            .set("m", 1.0)
            .set("I_11", 0.01)
            .set("I_22", 0.01)
            .set("I_33", 0.01);
    }
    m.connect(["world.frame_b", "j1.frame_a", "ground.frame_a"]);
    m.connect(["j1.frame_b", "crank.frame_a"]);
    m.connect(["crank.frame_b", "j2.frame_a"]);
    m.connect(["j2.frame_b", "coupler.frame_a"]);
    m.connect(["coupler.frame_b", "j3.frame_a"]);
    m.connect(["ground.frame_b", "j4.frame_a"]);
    m.connect(["j4.frame_b", "rocker.frame_a"]);
    m.connect(["rocker.frame_b", "j3.frame_b"]);
    m
}

/// The four-bar above built of spatial joints about z (a planar loop of
/// spatial joints: 3 of its 5 cut equations repeat the others). Here the
/// loop stays closed up to the dead point and the speeds it asks for grow
/// without bound, so the steps collapse there instead of the projection
/// failing: the stop must still name the loop and say why, not only that
/// the step size fell.
#[test]
fn a_spatial_four_bar_driven_to_its_dead_point_names_the_loop_where_the_steps_collapse() {
    let mut m = spatial_four_bar("spatial_dead_point", [1.0, 1.0, 0.5, 1.2]);
    m.component_mut("j1").unwrap().initial("phi", std::f64::consts::FRAC_PI_3);
    m.add("drive", "RotationalComponents.Speed").set("exact", true);
    m.add("speed", "BlockComponents.Constant").set("k", 1.0);
    m.connect(["speed.y", "drive.w_ref"]);
    m.connect(["drive.spline", "j1.axis"]);
    m.connect(["drive.support", "j1.support"]);
    let options = SimulationOptions { stop: 1.0, saveat: 0.01, ..Default::default() };
    let stopped = m.assemble().unwrap().simulate(&options).unwrap_err();
    let message = stopped.to_string();
    // The crank reaches the dead point when its tip is 1.5 from the pivot.
    let dead_point = (0.19f64 / 2.4).acos() - std::f64::consts::FRAC_PI_3;
    eprintln!("spatial four-bar at its dead point ({dead_point:.6} s): {message}");
    assert!((stopped.time - dead_point).abs() < 1e-3, "stopped at {}, not at {dead_point}", stopped.time);
    for expected in ["loop", "`j1`", "`j4`", "singular configuration", "dead point"] {
        assert!(message.contains(expected), "`{expected}` missing from: {message}");
    }
}

/// A parallelogram four-bar (crank and rocker 1, coupler and ground 2)
/// started at its change point, all bars on one line: there the loop's
/// constraints lose a rank, and the start counted 2 degrees of freedom
/// without a word (linearizing there gave a 4-state model). The assembly
/// now says the start is a singular configuration, naming the loop; a step
/// away from it, nothing is said.
#[test]
fn a_loop_started_at_its_change_point_is_said_to_be_singular() {
    let parallelogram = |phi: f64| {
        let mut m = spatial_four_bar("parallelogram", [1.0, 2.0, 1.0, 2.0]);
        m.component_mut("world").unwrap().set("g", 0.0);
        m.component_mut("j1").unwrap().initial("phi", phi).initial("w", 1.0);
        m.assemble().unwrap()
    };
    let at = parallelogram(0.0);
    let said: Vec<&String> = at.warnings().iter().filter(|w| w.contains("singular configuration")).collect();
    assert_eq!(said.len(), 1, "{:?}", at.warnings());
    assert!(
        said[0].contains("the loop closed at") && said[0].contains("`j1`") && said[0].contains("change point"),
        "{}",
        said[0]
    );
    let away = parallelogram(0.3);
    assert_eq!(away.degrees_of_freedom(), 1);
    assert!(away.warnings().iter().all(|w| !w.contains("singular configuration")), "{:?}", away.warnings());
}
