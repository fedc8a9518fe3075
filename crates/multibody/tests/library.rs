//! The everyday library against closed forms, conservation laws and
//! equivalent formulations.

use multibody::{Error, Model, OrientationState, SimulationOptions, Solution, Value};

const G: f64 = 9.80665;

fn tight(stop: f64) -> SimulationOptions {
    SimulationOptions { stop, saveat: 0.01, abstol: 1e-10, reltol: 1e-10, ..Default::default() }
}

fn worst_difference(a: &Solution, b: &Solution, names: &[String]) -> f64 {
    names.iter().fold(0.0f64, |w, n| {
        let (x, y) = (a.get(n).unwrap_or_else(|| panic!("no {n}")), b.get(n).unwrap_or_else(|| panic!("no {n}")));
        x.iter().zip(y).fold(w, |w, (p, q)| w.max((p - q).abs()))
    })
}

fn rotation_and_position(frame: &str) -> Vec<String> {
    let mut names: Vec<String> = (1..=3).map(|i| format!("{frame}.r_0[{i}]")).collect();
    for i in 1..=3 {
        for j in 1..=3 {
            names.push(format!("{frame}.R[{i},{j}]"));
        }
    }
    names
}

fn body(model: &mut Model, name: &str) {
    model
        .add(name, "Body")
        .set("m", 1.5)
        .set("r_cm", [0.1, -0.6, 0.2])
        .set("I_11", 0.03)
        .set("I_22", 0.02)
        .set("I_33", 0.04)
        .set("I_21", 0.004);
}

/// A Universal pendulum and the same with two revolutes in series (about
/// x, then about y) move the same.
#[test]
fn universal_equals_two_revolutes_in_series() {
    let mut universal = Model::new("universal");
    universal.add("world", "World");
    universal.add("joint", "Universal").initial("phi_a", 0.5).initial("phi_b", -0.3).initial("w_a", 1.0);
    body(&mut universal, "body");
    universal.connect(["world.frame_b", "joint.frame_a"]);
    universal.connect(["joint.frame_b", "body.frame_a"]);
    let mut revolutes = Model::new("revolutes");
    revolutes.add("world", "World");
    revolutes.add("rev_a", "Revolute").set("n", [1.0, 0.0, 0.0]).initial("phi", 0.5).initial("w", 1.0);
    revolutes.add("rev_b", "Revolute").set("n", [0.0, 1.0, 0.0]).initial("phi", -0.3);
    body(&mut revolutes, "body");
    revolutes.connect(["world.frame_b", "rev_a.frame_a"]);
    revolutes.connect(["rev_a.frame_b", "rev_b.frame_a"]);
    revolutes.connect(["rev_b.frame_b", "body.frame_a"]);
    let (a, b) = (
        universal.assemble().unwrap().simulate(&tight(3.0)).unwrap(),
        revolutes.assemble().unwrap().simulate(&tight(3.0)).unwrap(),
    );
    let worst = worst_difference(&a, &b, &rotation_and_position("body.frame_a"));
    let angles = a
        .get("joint.phi_b")
        .unwrap()
        .iter()
        .zip(b.get("rev_b.phi").unwrap())
        .fold(0.0f64, |w, (x, y)| w.max((x - y).abs()));
    println!("Universal vs two revolutes: worst |r, R difference| {worst:.2e}, |phi_b - rev_b.phi| {angles:.2e} (tolerance 1e-7)");
    assert!(worst < 1e-7 && angles < 1e-7);
}

/// A free Body and the same Body on a FreeMotion joint from the world.
#[test]
fn free_body_equals_body_on_free_motion() {
    use multibody::math::{axes_rotations, to_q, Quat, Vec3};
    let q0 = to_q(&axes_rotations([1, 2, 3], &Vec3::new(0.3, -0.2, 0.5)), &Quat::new(1.0, 0.0, 0.0, 0.0));
    let (r0, v0, w0) = ([0.1, 0.5, -0.2], [1.0, 2.0, 0.5], [0.5, -3.0, 1.0]);
    let mut free = Model::new("free");
    free.add("world", "World");
    body(&mut free, "body");
    free.component_mut("body")
        .unwrap()
        .set("orientation_state", OrientationState::Quaternion)
        .initial("r_0", r0)
        .initial("v_0", v0)
        .initial("Q_hat", q0.as_slice())
        .initial("w_a", w0);
    let mut joint = Model::new("free_motion");
    joint.add("world", "World");
    joint
        .add("joint", "FreeMotion")
        .set("orientation_state", Value::Enum("Quaternion".into()))
        .initial("r_rel_a", r0)
        .initial("v_rel_a", v0)
        .initial("Q_hat", q0.as_slice())
        .initial("w_rel_b", w0);
    body(&mut joint, "body");
    joint.connect(["world.frame_b", "joint.frame_a"]);
    joint.connect(["joint.frame_b", "body.frame_a"]);
    let (a, b) = (
        free.assemble().unwrap().simulate(&tight(2.0)).unwrap(),
        joint.assemble().unwrap().simulate(&tight(2.0)).unwrap(),
    );
    let worst = worst_difference(&a, &b, &rotation_and_position("body.frame_a"));
    println!("free Body vs Body on FreeMotion: worst |r, R difference| {worst:.2e} (tolerance 1e-8)");
    assert!(worst < 1e-8);
}

/// Cylindrical(n = [0, 1, 0]) under gravity: s falls freely, s = -g t^2/2,
/// while phi turns at its constant start rate (no torque about the axis).
#[test]
fn cylindrical_slides_under_gravity_while_spinning() {
    let mut model = Model::new("cylindrical");
    model.add("world", "World");
    model.add("joint", "Cylindrical").set("n", [0.0, 1.0, 0.0]).initial("w", 4.0);
    body(&mut model, "body");
    model.connect(["world.frame_b", "joint.frame_a"]);
    model.connect(["joint.frame_b", "body.frame_a"]);
    let solution = model.assemble().unwrap().simulate(&tight(2.0)).unwrap();
    let (mut ws, mut wphi) = (0.0f64, 0.0f64);
    for (k, t) in solution.time().iter().enumerate() {
        ws = ws.max((solution.get("joint.s").unwrap()[k] + G * t * t / 2.0).abs());
        wphi = wphi.max((solution.get("joint.phi").unwrap()[k] - 4.0 * t).abs());
    }
    println!("Cylindrical: |s + g t^2/2| {ws:.2e} m, |phi - 4 t| {wphi:.2e} rad (tolerance 1e-8)");
    assert!(ws < 1e-8 && wphi < 1e-8);
}

/// A Planar joint (plane x-y) driven by a constant world force and torque
/// on a body with its centre of mass at frame_b: s_x = Fx t^2/(2m),
/// s_y = (Fy/m - g) t^2/2, phi = T t^2/(2 I_33).
#[test]
fn planar_joint_driven_by_a_known_force_follows_its_path() {
    let (m, i33, fx, fy, tz) = (2.0, 0.3, 3.0, 25.0, 0.6);
    let mut model = Model::new("planar");
    model.add("world", "World");
    model.add("joint", "Planar");
    model.add("body", "Body").set("m", m).set("I_33", i33);
    model.add("force", "WorldForce");
    model.add("torque", "WorldTorque");
    for (name, k) in [("fx", fx), ("fy", fy), ("fz", 0.0), ("tx", 0.0), ("ty", 0.0), ("tz", tz)] {
        model.add(name, "BlockComponents.Constant").set("k", k);
    }
    model.connect(["world.frame_b", "joint.frame_a"]);
    model.connect(["joint.frame_b", "body.frame_a", "force.frame_b", "torque.frame_b"]);
    for axis in ["x", "y", "z"] {
        model.connect([format!("f{axis}.y"), format!("force.force_{axis}")]);
        model.connect([format!("t{axis}.y"), format!("torque.torque_{axis}")]);
    }
    let solution = model.assemble().unwrap().simulate(&tight(2.0)).unwrap();
    let mut worst = 0.0f64;
    for (k, &t) in solution.time().iter().enumerate() {
        let expected = [fx / m * t * t / 2.0, (fy / m - G) * t * t / 2.0, tz / i33 * t * t / 2.0];
        for (name, e) in ["joint.s_x", "joint.s_y", "joint.phi"].iter().zip(expected) {
            worst = worst.max((solution.get(name).unwrap()[k] - e).abs());
        }
    }
    println!("Planar under a known force and torque: worst error {worst:.2e} (tolerance 1e-8)");
    assert!(worst < 1e-8);
}

/// A free body on a Spring from the world origin: the vertical position
/// oscillates about -(s0 + m g / c) with angular frequency sqrt(c / m).
#[test]
fn body_on_a_spring_oscillates_at_sqrt_c_over_m() {
    let (m, c, s0, y0) = (0.8, 50.0, 0.3, -0.2);
    let mut model = Model::new("spring");
    model.add("world", "World");
    model.add("spring", "Spring").set("c", c).set("s_unstretched", s0);
    model
        .add("body", "Body")
        .set("m", m)
        .set("orientation_state", OrientationState::Quaternion)
        .initial("r_0", [0.0, y0, 0.0]);
    model.connect(["world.frame_b", "spring.frame_a"]);
    model.connect(["spring.frame_b", "body.frame_a"]);
    let solution = model.assemble().unwrap().simulate(&tight(5.0)).unwrap();
    let (centre, omega) = (-(s0 + m * G / c), (c / m).sqrt());
    let mut worst = 0.0f64;
    for (k, &t) in solution.time().iter().enumerate() {
        let expected = centre + (y0 - centre) * (omega * t).cos();
        worst = worst.max((solution.get("body.r_0[2]").unwrap()[k] - expected).abs());
    }
    println!("body on a spring: worst |y - closed form| {worst:.2e} m (tolerance 1e-8)");
    assert!(worst < 1e-8);
}

/// Two point masses held only by springs with fixed-rotation ends (the
/// PointMass seed): they simulate and keep their energy; without the flags
/// the assembly has no owner of its orientation.
#[test]
fn point_masses_held_by_springs_with_fixed_rotation_ends() {
    let build = |fixed: bool| {
        let mut model = Model::new("springs");
        model.add("world", "World");
        model.add("anchor", "FixedTranslation").set("r", [1.0, 0.0, 0.0]);
        model.add("pm1", "PointMass").set("m", 1.0);
        model.add("pm2", "PointMass").set("m", 0.5);
        model.add("spring1", "Spring").set("c", 40.0).set("s_unstretched", 0.5).set("fixed_rotation_at_frame_b", fixed);
        model.add("spring2", "Spring").set("c", 30.0).set("s_unstretched", 0.5).set("fixed_rotation_at_frame_b", fixed);
        model.add("spring3", "Spring").set("c", 20.0).set("s_unstretched", 0.8);
        model.connect(["world.frame_b", "spring1.frame_a", "anchor.frame_a"]);
        model.connect(["spring1.frame_b", "pm1.frame_a", "spring2.frame_a"]);
        model.connect(["spring2.frame_b", "pm2.frame_a", "spring3.frame_b"]);
        model.connect(["anchor.frame_b", "spring3.frame_a"]);
        model
    };
    let err = build(false).assemble().unwrap_err();
    println!("without fixed rotations: {err}");
    assert!(matches!(err, Error::NoOrientationOwner { .. }));
    let mut model = build(true);
    model.component_mut("pm1").unwrap().initial("r_0", [0.2, -0.6, 0.1]);
    model.component_mut("pm2").unwrap().initial("r_0", [0.7, -1.0, -0.1]).initial("v_0", [0.0, 0.0, 0.5]);
    let mechanism = model.assemble().unwrap();
    println!("states: {:?}", mechanism.states().names);
    let solution = mechanism.simulate(&tight(5.0)).unwrap();
    let energy = |k: usize| {
        let mut e = 0.0;
        for (pm, m) in [("pm1", 1.0), ("pm2", 0.5)] {
            let v: f64 = (1..=3).map(|i| solution.get(&format!("{pm}.v_0[{i}]")).unwrap()[k].powi(2)).sum();
            e += 0.5 * m * v + m * G * solution.get(&format!("{pm}.r_0[2]")).unwrap()[k];
        }
        for (spring, c, s0) in [("spring1", 40.0, 0.5), ("spring2", 30.0, 0.5), ("spring3", 20.0, 0.8)] {
            let l = solution.get(&format!("{spring}.length")).unwrap()[k];
            e += 0.5 * c * (l - s0) * (l - s0);
        }
        e
    };
    let drift = (0..solution.len()).map(|k| (energy(k) - energy(0)).abs()).fold(0.0, f64::max);
    println!("point masses on springs: energy drift {drift:.2e} J (tolerance 1e-7)");
    assert!(drift < 1e-7);
}

/// BodyBox and BodyCylinder mass properties against hand calculations (the
/// Modelica formulas), through their dynamics: each swings on a spherical
/// joint exactly like a Body given the hand-calculated m, r_cm and I.
#[test]
fn shaped_body_masses_and_inertias_match_hand_calculations() {
    use std::f64::consts::PI;
    let swing = |shaped: &dyn Fn(&mut Model)| {
        let mut model = Model::new("swing");
        model.add("world", "World");
        model.add("joint", "Spherical").initial("phid", [1.0, -0.5, 2.0]);
        shaped(&mut model);
        model.connect(["world.frame_b", "joint.frame_a"]);
        model.connect(["joint.frame_b", "body.frame_a"]);
        model.assemble().unwrap().simulate(&tight(1.5)).unwrap()
    };
    let hand_body = |m: f64, r_cm: [f64; 3], i: [[f64; 3]; 3]| {
        move |model: &mut Model| {
            model
                .add("body", "Body")
                .set("m", m)
                .set("r_cm", r_cm)
                .set("I_11", i[0][0])
                .set("I_22", i[1][1])
                .set("I_33", i[2][2])
                .set("I_21", i[1][0])
                .set("I_31", i[2][0])
                .set("I_32", i[2][1]);
        }
    };
    let names = rotation_and_position("body.frame_a");

    // A hollow box along x: L = 0.5, w = 0.1, h = 0.06, inner 0.06 x 0.02.
    let (l, w, h, wi, hi, rho) = (0.5, 0.1, 0.06, 0.06, 0.02, 7700.0);
    let (mo, mi) = (rho * l * w * h, rho * l * wi * hi);
    let i_box = [
        [(mo * (w * w + h * h) - mi * (wi * wi + hi * hi)) / 12.0, 0.0, 0.0],
        [0.0, (mo * (l * l + h * h) - mi * (l * l + hi * hi)) / 12.0, 0.0],
        [0.0, 0.0, (mo * (l * l + w * w) - mi * (l * l + wi * wi)) / 12.0],
    ];
    let boxed = swing(&|m: &mut Model| {
        m.add("body", "BodyBox")
            .set("r", [l, 0.0, 0.0])
            .set("width", w)
            .set("height", h)
            .set("inner_width", wi)
            .set("inner_height", hi);
    });
    let by_hand = swing(&hand_body(mo - mi, [l / 2.0, 0.0, 0.0], i_box));
    let worst = worst_difference(&boxed, &by_hand, &names);
    println!("hollow BodyBox (m = {:.4} kg) vs hand calculation: {worst:.2e}", mo - mi);
    assert!(worst < 1e-9);

    // A hollow cylinder along a skewed axis e: I = I_perp (E - e e') + I_axis e e'.
    let r: [f64; 3] = [0.3, 0.4, -0.2];
    let length = (r[0] * r[0] + r[1] * r[1] + r[2] * r[2]).sqrt();
    let (ro, ri) = (0.04, 0.03);
    let (mo, mi) = (rho * PI * length * ro * ro, rho * PI * length * ri * ri);
    let i_axis = (mo * ro * ro - mi * ri * ri) / 2.0;
    let i_perp = (mo * (length * length + 3.0 * ro * ro) - mi * (length * length + 3.0 * ri * ri)) / 12.0;
    let e = r.map(|x| x / length);
    let mut i_cyl = [[0.0; 3]; 3];
    for a in 0..3 {
        for b in 0..3 {
            i_cyl[a][b] = i_perp * (if a == b { 1.0 } else { 0.0 } - e[a] * e[b]) + i_axis * e[a] * e[b];
        }
    }
    let cylinder = swing(&|m: &mut Model| {
        m.add("body", "BodyCylinder").set("r", r).set("diameter", 2.0 * ro).set("inner_diameter", 2.0 * ri);
    });
    let by_hand = swing(&hand_body(mo - mi, r.map(|x| x / 2.0), i_cyl));
    let worst = worst_difference(&cylinder, &by_hand, &names);
    println!("hollow BodyCylinder on a skewed axis (m = {:.4} kg) vs hand calculation: {worst:.2e}", mo - mi);
    assert!(worst < 1e-9);
}
