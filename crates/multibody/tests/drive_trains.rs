//! 1-D drive trains: inertias behind gears, alone and on joints, against
//! closed forms, an equivalent 3-D model and the power balance.

use multibody::{Error, Model, SimulationOptions};

#[path = "common/chain.rs"]
mod chain;

fn tight(stop: f64) -> SimulationOptions {
    SimulationOptions { stop, saveat: 0.01, abstol: 1e-11, reltol: 1e-11, ..Default::default() }
}

/// A pendulum swinging about z under gravity, the same with a motor
/// inertia J behind a gear of ratio i on its joint, and the same with a
/// body of inertia i^2 J about the axis at the pivot instead of the motor:
/// the last two move alike (the reflected inertia), and the motor adds no
/// state.
#[test]
fn a_motor_behind_a_gear_adds_its_reflected_inertia_to_the_joint() {
    let (j, ratio) = (0.002, 7.0);
    let pendulum = |extra: &dyn Fn(&mut Model)| {
        let mut model = Model::new("pendulum");
        model.add("world", "World");
        model.add("rev", "Revolute").set("n", [0.0, 0.0, 1.0]).initial("phi", 0.4).initial("w", 0.0);
        model.add("body", "Body").set("m", 1.0).set("r_cm", [0.5, 0.0, 0.0]).set("I_33", 0.02);
        model.connect(["world.frame_b", "rev.frame_a"]);
        model.connect(["rev.frame_b", "body.frame_a"]);
        extra(&mut model);
        model.assemble().unwrap()
    };
    let geared = pendulum(&|m: &mut Model| {
        m.add("motor", "RotationalComponents.Inertia").set("J", j);
        m.add("gear", "RotationalComponents.IdealGear").set("ratio", ratio);
        m.connect(["motor.spline_b", "gear.spline_a"]);
        m.connect(["gear.spline_b", "rev.axis"]);
    });
    let reflected = pendulum(&|m: &mut Model| {
        // At the pivot, on the axis: gravity on it exerts no torque about z.
        m.add("rotor", "Body").set("m", 1.0).set("r_cm", [0.0, 0.0, 0.0]).set("I_33", ratio * ratio * j);
        m.connect(["rev.frame_b", "rotor.frame_a"]);
    });
    assert_eq!(geared.states().names, ["rev.phi", "rev.w"], "the geared motor has no state of its own");
    let (a, b) = (geared.simulate(&tight(3.0)).unwrap(), reflected.simulate(&tight(3.0)).unwrap());
    let worst = ["rev.phi", "rev.w"]
        .iter()
        .fold(0.0f64, |w, n| a.get(n).unwrap().iter().zip(b.get(n).unwrap()).fold(w, |w, (x, y)| w.max((x - y).abs())));
    assert!(worst < 1e-10, "geared and reflected differ by {worst:e}");
    // The motor turns `ratio` times the joint.
    let (motor, joint) = (a.get("motor.phi").unwrap(), a.get("rev.phi").unwrap());
    assert!(motor.iter().zip(joint).all(|(m, q)| (m - ratio * q).abs() < 1e-12));
    // And it swings: the check is not of a pendulum at rest.
    assert!(joint.iter().fold(0.0f64, |m, x| m.max(x.abs())) > 0.3);
}

/// A drive train without a World: a torque drives inertia 1, which drives
/// inertias 2 and 3 through two gears. The source's power equals the rate
/// of change of the kinetic energy at every sample, and a start speed
/// given on a geared inertia sets the one state.
#[test]
fn ideal_gears_pass_on_all_the_power_of_the_source() {
    let (j1, j2, j3, r12, r23) = (0.05, 0.8, 3.0, 4.0, 0.5);
    let mut model = Model::new("gearbox");
    model.add("sine", "BlockComponents.Sine").set("amplitude", 2.0).set("frequency", 1.5).set("offset", 0.5);
    model.add("source", "RotationalComponents.Torque");
    model.add("i1", "RotationalComponents.Inertia").set("J", j1);
    model.add("g12", "RotationalComponents.IdealGear").set("ratio", r12);
    model.add("i2", "RotationalComponents.Inertia").set("J", j2);
    model.add("g23", "RotationalComponents.IdealGear").set("ratio", r23);
    model.add("i3", "RotationalComponents.Inertia").set("J", j3).initial("w", 0.6);
    model.connect(["sine.y", "source.tau"]);
    model.connect(["source.spline", "i1.spline_a"]);
    model.connect(["i1.spline_b", "g12.spline_a"]);
    model.connect(["g12.spline_b", "i2.spline_a"]);
    model.connect(["i2.spline_b", "g23.spline_a"]);
    model.connect(["g23.spline_b", "i3.spline_a"]);
    let mechanism = model.assemble().unwrap();
    assert_eq!(mechanism.degrees_of_freedom(), 1);
    let solution = mechanism.simulate(&tight(2.0)).unwrap();
    let w3 = solution.get("i3.w").unwrap();
    assert!((w3[0] - 0.6).abs() < 1e-14, "i3.w starts at {}", w3[0]);
    let w1 = solution.get("i1.w").unwrap();
    assert!((w1[0] - 0.6 * r23 * r12).abs() < 1e-12, "i1 turns r12 r23 times as fast as i3");

    let get = |n: &str| solution.get(n).unwrap();
    let mut worst = 0.0f64;
    for k in 0..solution.len() {
        let power = get("source.tau")[k] * get("i1.w")[k];
        let ke_rate = [("i1", j1), ("i2", j2), ("i3", j3)]
            .iter()
            .map(|(n, j)| j * get(&format!("{n}.w"))[k] * get(&format!("{n}.a"))[k])
            .sum::<f64>();
        worst = worst.max((power - ke_rate).abs() / power.abs().max(ke_rate.abs()).max(1e-3));
    }
    assert!(worst < 1e-8, "power balance off by {worst:e} (relative)");
}

/// A free inertia on a spring to a wall oscillates at sqrt(c / J); a 1-D
/// mass on an incline slides with g sin(theta).
#[test]
fn free_inertias_and_masses_follow_their_closed_forms() {
    let (j, c) = (0.3, 12.0);
    let mut model = Model::new("torsion");
    model.add("wall", "RotationalComponents.Fixed");
    model.add("spring", "RotationalComponents.Spring").set("c", c);
    model.add("disc", "RotationalComponents.Inertia").set("J", j).initial("phi", 0.2).initial("w", 0.0);
    model.connect(["wall.spline", "spring.spline_a"]);
    model.connect(["spring.spline_b", "disc.spline_a"]);
    let solution = model.assemble().unwrap().simulate(&tight(2.0)).unwrap();
    let omega = (c / j).sqrt();
    let phi = solution.get("disc.phi").unwrap();
    let worst = solution.time().iter().zip(phi).fold(0.0f64, |w, (t, p)| w.max((p - 0.2 * (omega * t).cos()).abs()));
    assert!(worst < 1e-9, "torsion oscillator off by {worst:e}");

    let theta = 0.3f64;
    let mut model = Model::new("incline");
    model.add("block", "TranslationalComponents.Mass").set("m", 2.0).set("theta", theta);
    let solution = model.assemble().unwrap().simulate(&tight(1.0)).unwrap();
    // m (a + g sin theta) = 0 with the library's g = -9.80665.
    let a = solution.last("block.a").unwrap();
    assert!((a - 9.80665 * theta.sin()).abs() < 1e-12, "a = {a}");
    assert!((solution.last("block.s").unwrap() - 0.5 * 9.80665 * theta.sin()).abs() < 1e-9);
}

/// A pinion of inertia J drives a rack of mass m (IdealGearR2T, `ratio`
/// rad/m) under a constant torque: one state, the angle, accelerating at
/// `tau / (J + m / ratio^2)`, and the rack travels `phi / ratio`. The
/// translational library's name for the gear finds the same component.
#[test]
fn a_rack_and_pinion_reflects_the_rack_mass() {
    let (j, m, ratio, tau) = (0.1, 3.0, 20.0, 2.0);
    let mut model = Model::new("rack");
    model.add("motor", "RotationalComponents.ConstantTorque").set("tau_constant", tau);
    model.add("pinion", "RotationalComponents.Inertia").set("J", j).initial("phi", 0.0).initial("w", 0.0);
    model.add("gear", "TranslationalComponents.Components.IdealGearR2T").set("ratio", ratio);
    model.add("rack", "TranslationalComponents.Mass").set("m", m);
    model.connect(["motor.spline", "pinion.spline_a"]);
    model.connect(["pinion.spline_b", "gear.spline"]);
    model.connect(["gear.flange", "rack.flange_a"]);
    let mechanism = model.assemble().unwrap();
    assert_eq!(mechanism.states().names, ["pinion.phi", "pinion.w"]);
    let solution = mechanism.simulate(&tight(1.5)).unwrap();
    let alpha = tau / (j + m / (ratio * ratio));
    let (phi, s) = (solution.get("pinion.phi").unwrap(), solution.get("rack.s").unwrap());
    let worst = solution.time().iter().zip(phi).zip(s).fold(0.0f64, |w, ((t, p), s)| {
        w.max((p - 0.5 * alpha * t * t).abs()).max((s - 0.5 * alpha * t * t / ratio).abs())
    });
    assert!(worst < 1e-9, "rack and pinion off by {worst:e}");
}

/// A rigid 1-D body between two joint axes cannot move with both; and an
/// inertia without mass needs forces to hold it.
#[test]
fn impossible_drive_trains_are_explained() {
    let mut model = Model::new("bad");
    model.add("world", "World");
    for j in ["r1", "r2"] {
        model.add(j, "Revolute");
        model.add(format!("{j}_body"), "Body").set("m", 1.0).set("r_cm", [0.5, 0.0, 0.0]);
        model.connect(["world.frame_b".to_string(), format!("{j}.frame_a")]);
        model.connect([format!("{j}.frame_b"), format!("{j}_body.frame_a")]);
    }
    model.add("shaft", "RotationalComponents.Inertia").set("J", 1.0);
    model.connect(["shaft.spline_a", "r1.axis"]);
    model.connect(["shaft.spline_b", "r2.axis"]);
    match model.assemble() {
        Err(Error::Unsupported { component, what, .. }) => {
            assert_eq!(component, "shaft");
            assert!(what.contains("move independently"), "{what}");
        }
        other => panic!("expected an error naming the shaft, got {other:?}"),
    }

    // A negative spring or damper constant would make the train gain energy.
    for (kind, name) in [
        ("RotationalComponents.Spring", "c"),
        ("RotationalComponents.Damper", "d"),
        ("TranslationalComponents.SpringDamper", "d"),
    ] {
        let mut model = Model::new("negative");
        let element = model.add("element", kind).set(name, -1.0);
        for other in ["c", "d"].into_iter().filter(|p| *p != name && kind.ends_with("SpringDamper")) {
            element.set(other, 1.0);
        }
        match model.assemble() {
            Err(Error::InvalidValue { name: n, reason, .. }) => {
                assert_eq!(n, name, "{kind}");
                assert!(reason.contains("negative"), "{reason}");
            }
            other => panic!("{kind} with {name} = -1: expected an invalid value, got {other:?}"),
        }
    }

    // An inertia without mass is a node the forces on it must hold; alone,
    // nothing does. A negative one is no inertia at all.
    let mut model = Model::new("weightless");
    model.add("disc", "RotationalComponents.Inertia").set("J", 0.0);
    match model.assemble() {
        Err(Error::Unsupported { component, what, .. }) => {
            assert_eq!(component, "disc");
            assert!(what.contains("no spring or damper on it"), "{what}");
        }
        other => panic!("expected an error naming the disc, got {other:?}"),
    }
    let mut model = Model::new("negative_inertia");
    model.add("disc", "RotationalComponents.Inertia").set("J", -1.0);
    assert!(matches!(model.assemble(), Err(Error::InvalidValue { name, .. }) if name == "J"));
}

/// The benchmark chain with a geared motor on every joint: the ABA (with
/// the motors as armatures) against the mass matrix of the composite-rigid-
/// body algorithm, whose diagonal must grow by exactly `ratio^2 J`.
#[test]
fn geared_motors_enter_the_aba_and_the_mass_matrix_alike() {
    let n = 12;
    let (plain, geared) = (chain::benchmark_chain(n).assemble().unwrap(), chain::geared_chain(n).assemble().unwrap());
    assert_eq!(geared.states().names.len(), 2 * n, "motors behind gears add no states");
    let y = geared.states().start.clone();
    let (q, u) = y.split_at(n);
    let mut ws = geared.workspace();
    let mut ud = vec![0.0; n];
    geared.forward_dynamics(&mut ws, 0.0, q, u, &mut ud).unwrap();
    let (mut m, mut f) = (vec![0.0; n * n], vec![0.0; n]);
    geared.system().mass_matrix_and_bias(&mut ws, 0.0, q, u, &mut m, &mut f).unwrap();
    let (mut m0, mut f0) = (vec![0.0; n * n], vec![0.0; n]);
    let mut ws0 = plain.workspace();
    plain.system().mass_matrix_and_bias(&mut ws0, 0.0, q, u, &mut m0, &mut f0).unwrap();
    for k in 0..n {
        let armature = 2500.0 * 2e-5 * (k + 1) as f64;
        assert!((m[k * n + k] - m0[k * n + k] - armature).abs() < 1e-12, "joint {k}");
        assert!((f[k] - f0[k]).abs() < 1e-12, "the motors add no bias force");
        let row: f64 = (0..n).map(|j| m[k * n + j] * ud[j]).sum();
        assert!((row - f[k]).abs() < 1e-10 * (1.0 + f[k].abs()), "row {k}: {row} vs {}", f[k]);
    }
}

/// The AccelerationSensors record a connector's acceleration: a 2 kg.m2
/// inertia under 3 N.m turns up at 1.5 rad/s2; a 0.5 kg mass on a 8 N/m
/// spring started 0.1 m out accelerates as `-0.1 w^2 cos(w t)`, w = 4.
/// Their output cannot be read (it is known only after the motion).
#[test]
fn acceleration_sensors_record_the_closed_form_accelerations() {
    let mut m = Model::new("accelerations");
    m.add("wheel", "RotationalComponents.Inertia").set("J", 2.0).initial("phi", 0.0).initial("w", 0.0);
    m.add("motor", "RotationalComponents.ConstantTorque").set("tau_constant", 3.0);
    m.add("spin", "RotationalComponents.AccelerationSensor");
    m.connect(["motor.spline", "wheel.spline_a"]);
    m.connect(["wheel.spline_b", "spin.spline"]);
    m.add("slider", "TranslationalComponents.Mass").set("m", 0.5).initial("s", 0.1).initial("v", 0.0);
    m.add("spring", "TranslationalComponents.Spring").set("c", 8.0);
    m.add("wall", "TranslationalComponents.Fixed");
    m.add("push", "TranslationalComponents.AccelerationSensor");
    m.connect(["wall.flange", "spring.flange_a"]);
    m.connect(["spring.flange_b", "slider.flange_a"]);
    m.connect(["slider.flange_b", "push.flange"]);
    let s = m.assemble().unwrap().simulate(&tight(2.0)).unwrap();
    let mut worst = 0.0f64;
    for (k, t) in s.time().iter().enumerate() {
        worst = worst.max((s.get("spin.a").unwrap()[k] - 1.5).abs());
        worst = worst.max((s.get("push.a").unwrap()[k] + 0.1 * 16.0 * (4.0 * t).cos()).abs());
    }
    eprintln!("acceleration sensors: worst {worst:.1e} (tolerance 1e-8)");
    assert!(worst < 1e-8, "recorded accelerations are off by {worst:e}");

    let mut reads = m.clone();
    reads.add("gain", "BlockComponents.Gain").set("k", 1.0);
    reads.connect(["spin.a", "gain.u"]);
    let message = reads.assemble().unwrap_err().to_string();
    assert!(message.contains("accelerations"), "{message}");
}

/// The torque a joint reports is what its axis delivers to the joint: a
/// constant torque on a motor inertia J behind a gear of ratio i turns a
/// disc of inertia I about the joint's axis with `a = i tau / (I + i^2 J)`,
/// and the joint gets `I a` of it (the rest accelerates the motor, whose
/// reflected inertia the joint's coordinate carries). Closed form, and the
/// disc's kinetic energy equals the work of the reported torque.
#[test]
fn a_joint_behind_a_geared_motor_reports_the_torque_its_axis_delivers() {
    let (j, ratio, disc, torque) = (0.002, 7.0, 0.3, 1.5);
    let mut model = Model::new("geared disc");
    model.add("world", "World").set("g", 0.0);
    model.add("rev", "Revolute").set("n", [0.0, 0.0, 1.0]).initial("phi", 0.0).initial("w", 0.0);
    model.add("body", "Body").set("m", 1.0).set("r_cm", [0.0, 0.0, 0.0]).set("I_33", disc);
    model.add("motor", "RotationalComponents.Inertia").set("J", j);
    model.add("gear", "RotationalComponents.IdealGear").set("ratio", ratio);
    model.add("drive", "RotationalComponents.ConstantTorque").set("tau_constant", torque);
    model.connect(["world.frame_b", "rev.frame_a"]);
    model.connect(["rev.frame_b", "body.frame_a"]);
    model.connect(["drive.spline", "motor.spline_a"]);
    model.connect(["motor.spline_b", "gear.spline_a"]);
    model.connect(["gear.spline_b", "rev.axis"]);
    let solution = model.assemble().unwrap().simulate(&tight(1.0)).unwrap();
    let a = ratio * torque / (disc + ratio * ratio * j);
    let worst = |name: &str, f: &dyn Fn(f64) -> f64| {
        solution.time().iter().zip(solution.get(name).unwrap()).fold(0.0f64, |m, (&t, &x)| m.max((x - f(t)).abs()))
    };
    assert!(worst("rev.w", &|t| a * t) < 1e-9, "the joint accelerates at {a}");
    let delivered = worst("rev.tau", &|_| disc * a);
    println!("reported joint torque against I a = {:.4}: worst {delivered:.2e}", disc * a);
    assert!(delivered < 1e-9, "the joint reports the torque its axis delivers: worst {delivered:e}");
}
