//! The analytic derivatives of forward dynamics (`System::aba_derivatives`):
//! 1. against Pinocchio's `computeABADerivatives` on the peers' benchmark
//!    chain (golden values written by scripts/aba_derivatives_golden.py);
//! 2. against central differences (with Richardson extrapolation) of our own
//!    right-hand side on other trees: a cart-pole, a branched tree of
//!    prismatic and revolute joints with an armature, the geared chain,
//!    joints with several coordinates, and `generalized_forces` on models
//!    with springs, dampers, a world force and point gravity (a consistency
//!    check; the outside proof is Pinocchio);
//! 3. `derivatives_unsupported` names what it cannot handle.

#[path = "common/chain.rs"]
mod chain;
#[path = "common/four_bar.rs"]
mod four_bar;

use multibody::dynamics::DynamicsDerivatives;
use multibody::{Mechanism, Model};

/// Reads a list of numbers or a list of rows (flattened row-major).
fn numbers(v: &serde_json::Value) -> Vec<f64> {
    let mut out = Vec::new();
    for x in v.as_array().expect("a list") {
        match x.as_array() {
            Some(row) => out.extend(row.iter().map(|y| y.as_f64().unwrap())),
            None => out.push(x.as_f64().unwrap()),
        }
    }
    out
}

fn largest(a: &[f64]) -> f64 {
    a.iter().fold(0.0f64, |m, x| m.max(x.abs()))
}

fn worst_difference(a: &[f64], b: &[f64]) -> f64 {
    assert_eq!(a.len(), b.len());
    a.iter().zip(b).fold(0.0f64, |m, (x, y)| m.max((x - y).abs()))
}

/// The accelerations of `rhs` at `y`.
fn accelerations(mechanism: &Mechanism, y: &[f64]) -> Vec<f64> {
    let mut ws = mechanism.workspace();
    let mut dy = vec![0.0; y.len()];
    mechanism.rhs(&mut ws, 0.0, y, &mut dy).unwrap();
    dy[mechanism.states().nq..mechanism.states().nq + mechanism.states().nv].to_vec()
}

/// The derivatives at `y`, at the accelerations of `rhs` there (plus
/// `M^-1 tau` for extra joint forces `tau`).
fn derivatives_at(mechanism: &Mechanism, y: &[f64], tau: Option<&[f64]>) -> (DynamicsDerivatives, Vec<f64>) {
    let system = mechanism.system();
    assert_eq!(system.derivatives_unsupported(), None);
    let (nq, nv) = (mechanism.states().nq, mechanism.states().nv);
    let (q, u) = (&y[..nq], &y[nq..nq + nv]);
    let mut ud = accelerations(mechanism, y);
    let mut ws = mechanism.workspace();
    let mut d = system.derivatives_work();
    system.aba_derivatives(&mut ws, &mut d, q, u, &ud).unwrap();
    if let Some(tau) = tau {
        for (i, x) in ud.iter_mut().enumerate() {
            *x += (0..nv).map(|j| d.minv()[i * nv + j] * tau[j]).sum::<f64>();
        }
        system.aba_derivatives(&mut ws, &mut d, q, u, &ud).unwrap();
    }
    (d, ud)
}

#[test]
fn chain_derivatives_match_pinocchio() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/golden/aba_derivatives.json");
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("cannot read {}: {e}", path.display()));
    let json: serde_json::Value = serde_json::from_str(&text).unwrap();
    let tolerance = 1e-9;
    let cases = json["cases"].as_array().unwrap();
    assert!(cases.len() >= 3);
    for case in cases {
        let n = case["n"].as_u64().unwrap() as usize;
        let label = case["state"].as_str().unwrap();
        let (q, v, tau) = (numbers(&case["q"]), numbers(&case["v"]), numbers(&case["tau"]));
        let mechanism = chain::benchmark_chain(n).assemble().unwrap();
        let states = mechanism.states();
        assert_eq!((states.nq, states.nv), (n, n));
        for k in 0..n {
            assert_eq!(states.names[k], format!("j{k}.phi"));
            assert_eq!(states.names[n + k], format!("j{k}.w"));
        }
        let y: Vec<f64> = q.iter().chain(&v).copied().collect();
        let (d, ud) = derivatives_at(&mechanism, &y, Some(&tau));
        let ddq = numbers(&case["ddq"]);
        let acc = worst_difference(&ud, &ddq) / largest(&ddq);
        let mut line = format!("N = {n:3} ({label:6}): |ddq| {:.1e}", acc / tolerance);
        let mut worst = acc;
        for (name, ours) in [("ddq_dq", d.ddq_dq()), ("ddq_dv", d.ddq_dv()), ("Minv", d.minv())] {
            let theirs = numbers(&case[name]);
            let err = worst_difference(ours, &theirs) / largest(&theirs);
            line += &format!(", {name} {:.1e}", err / tolerance);
            worst = worst.max(err);
        }
        println!("{line}  (worst error / tolerance, tolerance 1e-9 of each matrix's largest entry)");
        assert!(worst < tolerance, "N = {n} ({label}): relative error {worst:e}");
    }
}

/// How a velocity coordinate moves the positions: one position coordinate,
/// or the rotation increment about axis `axis` of the quaternion at `q`.
#[derive(Clone, Copy, Debug)]
enum Coordinate {
    Plain(usize),
    Rotation { q: usize, axis: usize },
}

/// The position coordinate of each velocity coordinate, from the state
/// names: a quaternion `X.Q_hat[1..4]` takes the next three velocity
/// coordinates as its rotation increments; every other position takes one.
fn coordinates(mechanism: &Mechanism) -> Vec<Coordinate> {
    let states = mechanism.states();
    let mut out = Vec::new();
    let mut p = 0;
    while p < states.nq {
        if states.names[p].ends_with("Q_hat[1]") {
            out.extend((0..3).map(|axis| Coordinate::Rotation { q: p, axis }));
            p += 4;
        } else {
            out.push(Coordinate::Plain(p));
            p += 1;
        }
    }
    assert_eq!(out.len(), states.nv);
    out
}

/// The state `y` moved by `eps` along velocity coordinate `j`'s position.
fn displaced(coordinates: &[Coordinate], y: &[f64], j: usize, eps: f64) -> Vec<f64> {
    use multibody::math::{from_q, planar_rotation, to_q, unit, Quat};
    let mut y = y.to_vec();
    match coordinates[j] {
        Coordinate::Plain(p) => y[p] += eps,
        Coordinate::Rotation { q, axis } => {
            let q0 = Quat::new(y[q], y[q + 1], y[q + 2], y[q + 3]);
            // The link turns by eps about its own axis: R' = A(eps) R.
            let r = planar_rotation(&unit(axis), eps) * from_q(&(q0 / q0.norm()));
            y[q..q + 4].copy_from_slice(to_q(&r, &q0).as_slice());
        }
    }
    y
}

/// Central differences of `f` at 0 with one Richardson step:
/// `(4 D(h/2) - D(h)) / 3`, accurate to O(h^4).
fn richardson(f: impl Fn(f64) -> Vec<f64>, h: f64) -> Vec<f64> {
    let central = |h: f64| -> Vec<f64> { f(h).iter().zip(f(-h)).map(|(p, m)| (p - m) / (2.0 * h)).collect() };
    let (coarse, fine) = (central(h), central(h / 2.0));
    fine.iter().zip(&coarse).map(|(f, c)| (4.0 * f - c) / 3.0).collect()
}

/// The generalised forces of `generalized_forces` at `y`.
fn forces(mechanism: &Mechanism, y: &[f64]) -> Vec<f64> {
    let (nq, nv) = (mechanism.states().nq, mechanism.states().nv);
    let mut ws = mechanism.workspace();
    let mut out = vec![0.0; nv];
    mechanism.system().generalized_forces(&mut ws, 0.0, &y[..nq], &y[nq..nq + nv], &mut out).unwrap();
    out
}

/// Checks the analytic derivatives at `y` against central differences of
/// `rhs`: with the forces `Q(q, u)` of the other elements (by differences
/// too), `d ud/dq = ddq_dq + M^-1 dQ/dq` and `d ud/du = ddq_dv + M^-1 dQ/du`.
/// Also `M^-1 (Q - RNEA(q, u, 0)) = ud`, and `M`, `Q - b` against the
/// mass matrix and bias of the constraint solver. Returns the worst
/// relative error.
fn check_against_differences(mechanism: &Mechanism, y: &[f64], label: &str) -> f64 {
    let (nq, nv) = (mechanism.states().nq, mechanism.states().nv);
    let system = mechanism.system();
    let coords = coordinates(mechanism);
    let (d, ud) = derivatives_at(mechanism, y, None);
    let minv = d.minv();
    let times_minv =
        |x: &[f64]| -> Vec<f64> { (0..nv).map(|i| (0..nv).map(|k| minv[i * nv + k] * x[k]).sum()).collect() };
    let h = 1e-3;
    let (mut fd_q, mut fd_v) = (vec![0.0; nv * nv], vec![0.0; nv * nv]);
    let (mut an_q, mut an_v) = (vec![0.0; nv * nv], vec![0.0; nv * nv]);
    for j in 0..nv {
        let along_q = |e: f64| displaced(&coords, y, j, e);
        let along_u = |e: f64| {
            let mut y = y.to_vec();
            y[nq + j] += e;
            y
        };
        let dud_q = richardson(|e| accelerations(mechanism, &along_q(e)), h);
        let dud_u = richardson(|e| accelerations(mechanism, &along_u(e)), h);
        let dq_q = times_minv(&richardson(|e| forces(mechanism, &along_q(e)), h));
        let dq_u = times_minv(&richardson(|e| forces(mechanism, &along_u(e)), h));
        for i in 0..nv {
            fd_q[i * nv + j] = dud_q[i];
            fd_v[i * nv + j] = dud_u[i];
            an_q[i * nv + j] = d.ddq_dq()[i * nv + j] + dq_q[i];
            an_v[i * nv + j] = d.ddq_dv()[i * nv + j] + dq_u[i];
        }
    }
    let err_q = worst_difference(&an_q, &fd_q) / largest(&fd_q).max(1e-300);
    let err_v = worst_difference(&an_v, &fd_v) / largest(&fd_v).max(1e-300);

    // M^-1 (Q - RNEA(q, u, 0)) = ud, and the constraint solver's M and Q - b.
    let mut ws = mechanism.workspace();
    let mut d0 = system.derivatives_work();
    system.aba_derivatives(&mut ws, &mut d0, &y[..nq], &y[nq..nq + nv], &vec![0.0; nv]).unwrap();
    let q_forces = forces(mechanism, y);
    let net: Vec<f64> = q_forces.iter().zip(d0.inverse_dynamics()).map(|(q, b)| q - b).collect();
    let err_acc = worst_difference(&times_minv(&net), &ud) / largest(&ud).max(1.0);
    let (mut mass, mut bias) = (vec![0.0; nv * nv], vec![0.0; nv]);
    system.mass_matrix_and_bias(&mut ws, 0.0, &y[..nq], &y[nq..nq + nv], &mut mass, &mut bias).unwrap();
    let err_mass = worst_difference(&mass, d.mass_matrix()) / largest(&mass);
    let err_bias = worst_difference(&bias, &net) / largest(&bias).max(1.0);
    // M M^-1 = 1.
    let mut err_inverse = 0.0f64;
    for i in 0..nv {
        for j in 0..nv {
            let x: f64 = (0..nv).map(|k| d.mass_matrix()[i * nv + k] * minv[k * nv + j]).sum();
            err_inverse = err_inverse.max((x - if i == j { 1.0 } else { 0.0 }).abs());
        }
    }
    println!(
        "{label:28}: vs differences: ddq_dq {err_q:.1e}, ddq_dv {err_v:.1e}; M^-1 (Q - b) vs rhs {err_acc:.1e}, \
         M {err_mass:.1e}, Q - b {err_bias:.1e}, |M M^-1 - 1| {err_inverse:.1e}"
    );
    [err_q, err_v, err_acc, err_mass, err_bias, err_inverse].into_iter().fold(0.0, f64::max)
}

/// The state of `mechanism` with the named values set (the rest from its start).
fn state_with(mechanism: &Mechanism, values: &[(&str, f64)]) -> Vec<f64> {
    let states = mechanism.states();
    let mut y = states.start.clone();
    for (name, value) in values {
        let i = states
            .names
            .iter()
            .position(|n| n == name)
            .unwrap_or_else(|| panic!("no state {name} in {:?}", states.names));
        y[i] = *value;
    }
    y
}

fn body(model: &mut Model, name: &str, m: f64, r_cm: [f64; 3]) {
    model
        .add(name, "Body")
        .set("m", m)
        .set("r_cm", r_cm)
        .set("I_11", 0.03 * m)
        .set("I_22", 0.05 * m)
        .set("I_33", 0.04 * m)
        .set("I_21", 0.004 * m)
        .set("I_31", -0.003 * m)
        .set("I_32", 0.002 * m);
}

#[test]
fn cart_pole_matches_differences() {
    let mut model = Model::new("cart_pole");
    model.add("world", "World");
    model.add("rail", "Prismatic").set("n", [1.0, 0.0, 0.0]);
    model.add("cart", "Body").set("m", 2.0);
    model.add("hinge", "Revolute").set("n", [0.0, 0.0, 1.0]);
    model.add("pole", "Body").set("m", 0.4).set("r_cm", [0.0, 0.6, 0.0]).set("I_33", 0.02);
    model.connect(["world.frame_b", "rail.frame_a"]);
    model.connect(["rail.frame_b", "cart.frame_a", "hinge.frame_a"]);
    model.connect(["hinge.frame_b", "pole.frame_a"]);
    let mechanism = model.assemble().unwrap();
    let y = state_with(&mechanism, &[("rail.s", 0.3), ("hinge.phi", 0.7), ("rail.v", -0.4), ("hinge.w", 1.1)]);
    assert!(check_against_differences(&mechanism, &y, "cart-pole") < 1e-8);
}

/// A branched tree of revolute and prismatic joints on skew axes, with
/// bodies off their axes and full inertia tensors, and a motor inertia
/// behind a gear on one joint (an armature).
fn branched_tree() -> Model {
    let mut model = Model::new("branched");
    model.add("world", "World");
    let joints: [(&str, &str, [f64; 3], &str); 6] = [
        ("j1", "Revolute", [0.0, 0.0, 1.0], "world.frame_b"),
        ("j2", "Prismatic", [0.6, 0.8, 0.0], "t1.frame_b"),
        ("j3", "Revolute", [1.0, 0.0, 0.0], "t2.frame_b"),
        ("j4", "Revolute", [0.0, 0.6, 0.8], "t1.frame_b"),
        ("j5", "Prismatic", [0.0, 0.0, 1.0], "t4.frame_b"),
        ("j6", "Revolute", [0.48, 0.6, 0.64], "t3.frame_b"),
    ];
    for (k, (name, kind, n, from)) in joints.iter().enumerate() {
        model.add(*name, *kind).set("n", *n);
        model.connect([from.to_string(), format!("{name}.frame_a")]);
        let b = format!("b{}", k + 1);
        body(&mut model, &b, 0.5 + 0.3 * k as f64, [0.2, -0.1 * k as f64, 0.15]);
        let t = format!("t{}", k + 1);
        model.add(&t, "FixedTranslation").set("r", [0.4, 0.1 * k as f64, -0.2]);
        model.connect([format!("{name}.frame_b"), format!("{b}.frame_a"), format!("{t}.frame_a")]);
    }
    model.add("motor", "RotationalComponents.Inertia").set("J", 2e-4);
    model.add("gear", "RotationalComponents.IdealGear").set("ratio", 30.0);
    model.connect(["motor.spline_b", "gear.spline_a"]);
    model.connect(["gear.spline_b", "j3.axis"]);
    model
}

#[test]
fn branched_tree_with_prismatic_joints_and_armature_matches_differences() {
    let mechanism = branched_tree().assemble().unwrap();
    let mut values = Vec::new();
    let names = ["j1", "j2", "j3", "j4", "j5", "j6"];
    for (k, name) in names.iter().enumerate() {
        let (p, v) = if k == 1 || k == 4 { ("s", "v") } else { ("phi", "w") };
        values.push((format!("{name}.{p}"), 0.3 + 0.45 * k as f64));
        values.push((format!("{name}.{v}"), 0.8 - 0.35 * k as f64));
    }
    let values: Vec<(&str, f64)> = values.iter().map(|(n, v)| (n.as_str(), *v)).collect();
    let y = state_with(&mechanism, &values);
    assert!(check_against_differences(&mechanism, &y, "branched tree with armature") < 1e-8);
    // The geared benchmark chain: an armature on every joint.
    let mechanism = chain::geared_chain(6).assemble().unwrap();
    let y = mechanism.states().start.clone();
    assert!(check_against_differences(&mechanism, &y, "geared chain (6)") < 1e-8);
}

/// A chain with a damper on one axis, a spring from a body to the world, a
/// world force and a body in point gravity: `generalized_forces` carries
/// them, and the derivatives with `M^-1 dQ` added match the differences of
/// `rhs`, which sees all of them.
#[test]
fn generalized_forces_of_springs_dampers_and_point_gravity_match_differences() {
    let mut model = Model::new("loaded");
    model.add("world", "World").set("mu", 3.0);
    model.add("j1", "Revolute").set("n", [0.0, 0.0, 1.0]);
    body(&mut model, "b1", 1.2, [0.3, 0.1, 0.0]);
    model.add("t1", "FixedTranslation").set("r", [0.8, 0.0, 0.1]);
    model.add("j2", "Revolute").set("n", [0.0, 1.0, 0.0]).set("axisflange", true);
    body(&mut model, "b2", 0.9, [0.25, 0.0, -0.1]);
    model.component_mut("b2").unwrap().set("point_gravity", true);
    model.add("t2", "FixedTranslation").set("r", [0.6, -0.2, 0.0]);
    model.add("j3", "Prismatic").set("n", [1.0, 0.0, 0.0]);
    body(&mut model, "b3", 0.7, [0.1, 0.1, 0.1]);
    model.add("damper", "RotationalComponents.Damper").set("d", 0.7);
    model.add("spring", "Spring").set("c", 20.0).set("s_unstretched", 0.5);
    model.add("push", "WorldForce");
    for (name, k) in [("fx", 1.5), ("fy", -0.5), ("fz", 2.0)] {
        model.add(name, "BlockComponents.Constant").set("k", k);
    }
    for axis in ["x", "y", "z"] {
        model.connect([format!("f{axis}.y"), format!("push.force_{axis}")]);
    }
    model.connect(["world.frame_b", "j1.frame_a"]);
    model.connect(["j1.frame_b", "b1.frame_a", "t1.frame_a", "push.frame_b"]);
    model.connect(["t1.frame_b", "j2.frame_a"]);
    model.connect(["j2.frame_b", "b2.frame_a", "t2.frame_a"]);
    model.connect(["t2.frame_b", "j3.frame_a"]);
    model.connect(["j3.frame_b", "b3.frame_a", "spring.frame_b"]);
    model.connect(["world.frame_b", "spring.frame_a"]);
    model.connect(["damper.spline_a", "j2.support"]);
    model.connect(["damper.spline_b", "j2.axis"]);
    let mechanism = model.assemble().unwrap();
    let y = state_with(
        &mechanism,
        &[("j1.phi", 0.4), ("j2.phi", -0.8), ("j3.s", 0.3), ("j1.w", 0.9), ("j2.w", -1.3), ("j3.v", 0.6)],
    );
    // The forces are there: Q is not zero.
    assert!(largest(&forces(&mechanism, &y)) > 0.1);
    assert!(check_against_differences(&mechanism, &y, "springs, dampers, gravity") < 1e-8);
}

/// Joints with several coordinates: Planar and Cylindrical in series, a
/// spherical joint with a quaternion, a free body with a quaternion (a root
/// of its own, held by a spring), a free point mass in point gravity
/// (three translations), and a cylindrical joint mounted backwards. Rotation columns of `ddq_dq` are along the
/// rotation increments.
#[test]
fn joints_with_several_coordinates_match_differences() {
    use multibody::OrientationState;
    let mut model = Model::new("multi");
    model.add("world", "World").set("mu", 3.0);
    model.add("plane", "Planar").set("n", [0.0, 0.0, 1.0]).set("n_x", [1.0, 0.0, 0.0]);
    body(&mut model, "a", 1.1, [0.2, 0.1, 0.05]);
    model.add("ta", "FixedTranslation").set("r", [0.5, 0.0, 0.0]);
    model.add("cyl", "Cylindrical").set("n", [0.0, 0.6, 0.8]);
    body(&mut model, "b", 0.8, [0.1, -0.2, 0.3]);
    model.add("ball", "Spherical").set("orientation_state", OrientationState::Quaternion);
    body(&mut model, "c", 0.6, [0.4, 0.1, -0.1]);
    model.add("tc", "FixedTranslation").set("r", [0.3, 0.2, 0.0]);
    model.add("hinge", "Revolute").set("n", [0.0, 1.0, 0.0]);
    body(&mut model, "e", 0.5, [0.2, 0.0, 0.1]);
    body(&mut model, "free", 0.9, [0.1, 0.05, -0.1]);
    model.component_mut("free").unwrap().set("orientation_state", OrientationState::Quaternion);
    model.add("spring", "Spring").set("c", 15.0).set("s_unstretched", 0.3);
    // A free point mass is a root of three translations; point gravity
    // makes its forces depend on its position.
    model.add("point", "PointMass").set("m", 0.4).set("isroot", true).set("point_gravity", true);
    // A cylindrical joint mounted the other way round (its axis is fixed in
    // both frames, so that is supported).
    model.add("back", "Cylindrical").set("n", [0.6, 0.0, 0.8]);
    body(&mut model, "f", 0.7, [0.0, 0.2, 0.1]);
    model.add("tf", "FixedTranslation").set("r", [0.2, 0.3, 0.0]);
    model.connect(["world.frame_b", "tf.frame_a"]);
    model.connect(["tf.frame_b", "back.frame_b"]);
    model.connect(["back.frame_a", "f.frame_a"]);
    model.connect(["world.frame_b", "plane.frame_a", "ball.frame_a"]);
    model.connect(["plane.frame_b", "a.frame_a", "ta.frame_a"]);
    model.connect(["ta.frame_b", "cyl.frame_a"]);
    model.connect(["cyl.frame_b", "b.frame_a", "spring.frame_a"]);
    model.connect(["ball.frame_b", "c.frame_a", "tc.frame_a"]);
    model.connect(["tc.frame_b", "hinge.frame_a"]);
    model.connect(["hinge.frame_b", "e.frame_a"]);
    model.connect(["spring.frame_b", "free.frame_a"]);
    let mechanism = model.assemble().unwrap();
    let system = mechanism.system();
    assert_eq!(system.derivatives_unsupported(), None);
    // A state away from every special configuration.
    let states = mechanism.states();
    let mut y = states.start.clone();
    let quaternions = |y: &mut Vec<f64>| {
        for (i, name) in states.names.iter().enumerate() {
            if name.ends_with("Q_hat[1]") {
                let q = multibody::math::Quat::new(0.8, 0.3, -0.4, 0.2).normalize();
                y[i..i + 4].copy_from_slice(q.as_slice());
            }
        }
    };
    for (i, name) in states.names.iter().enumerate() {
        if !name.contains("Q_hat") {
            y[i] = 0.3 * ((i as f64) * 1.7).sin() + 0.1;
        }
    }
    quaternions(&mut y);
    assert!(check_against_differences(&mechanism, &y, "several coordinates") < 1e-8);
}

#[test]
fn unsupported_systems_say_why() {
    let four_bar = four_bar::four_bar(0.1, 1.0, 1.0).assemble().unwrap();
    let why = four_bar.system().derivatives_unsupported().expect("a loop is not supported");
    println!("four-bar: {why}");
    assert!(why.contains("constraint") && why.contains("loop"), "{why}");

    let mut driven = Model::new("driven");
    driven.add("world", "World");
    driven.add("rev", "Revolute");
    driven.add("body", "Body").set("m", 2.0).set("r_cm", [0.5, 0.0, 0.0]);
    driven.add("drive", "RotationalComponents.Position").set("exact", true);
    driven.add("reference", "BlockComponents.Constant").set("k", 0.3);
    driven.connect(["world.frame_b", "rev.frame_a"]);
    driven.connect(["rev.frame_b", "body.frame_a"]);
    driven.connect(["drive.spline", "rev.axis"]);
    driven.connect(["drive.support", "rev.support"]);
    driven.connect(["reference.y", "drive.phi_ref"]);
    let why = driven.assemble().unwrap().system().derivatives_unsupported().expect("a drive is not supported");
    println!("drive: {why}");
    assert!(why.contains("drive"), "{why}");

    let mut euler = Model::new("euler");
    euler.add("world", "World");
    body(&mut euler, "free", 1.0, [0.1, 0.0, 0.0]);
    euler.component_mut("free").unwrap().set("orientation_state", multibody::OrientationState::Euler);
    let why = euler.assemble().unwrap().system().derivatives_unsupported().expect("Euler angles are not supported");
    println!("Euler angles: {why}");
    assert!(why.contains("Euler") && why.contains("`free`"), "{why}");

    // A joint with several coordinates mounted the other way round: its
    // parent-fixed and child-fixed columns trade places.
    let mut reversed = Model::new("reversed");
    reversed.add("world", "World");
    reversed.add("plane", "Planar").set("n", [0.0, 1.0, 0.0]).set("n_x", [1.0, 0.0, 0.0]);
    body(&mut reversed, "b", 1.0, [0.1, 0.0, 0.0]);
    reversed.connect(["world.frame_b", "plane.frame_b"]);
    reversed.connect(["plane.frame_a", "b.frame_a"]);
    let why =
        reversed.assemble().unwrap().system().derivatives_unsupported().expect("an inverted joint is not supported");
    println!("inverted joint: {why}");
    assert!(why.contains("`plane`") && why.contains("frame_b"), "{why}");
}
