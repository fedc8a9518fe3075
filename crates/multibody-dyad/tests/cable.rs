//! MultibodyComponents.Cable, written in Dyad from the library's own parts,
//! against an equivalent chain written out joint by joint, and (closing a
//! loop between two mounts) against conservation of energy.
//!
//! Tolerances: the two chains integrate the same equations in the same
//! order, so they agree to rounding amplified by the integrator (1e-9 is
//! far above what we see, far below any modelling difference). Energy
//! drifts with the integration error, which at abstol = reltol = 1e-10 is
//! held to 1e-8 of m g l.

mod common;

use multibody::{SimulationOptions, Solution};
use multibody_dyad::Package;

const G: f64 = 9.80665;

fn simulate(text: &str, model: &str, stop: f64) -> Solution {
    let mut package = Package::new();
    if let Err(d) = package.add_source("cable.dyad", text.to_string()) {
        panic!("{}", d.render(package.sources(), false));
    }
    let lowered = package.lower_component(model).unwrap_or_else(|d| panic!("{}", d.render(package.sources(), false)));
    let options = SimulationOptions { stop, saveat: 0.01, abstol: 1e-10, reltol: 1e-10, ..Default::default() };
    lowered.assemble().unwrap_or_else(|d| panic!("{}", d.render(package.sources(), false))).simulate(&options).unwrap()
}

fn column<'a>(s: &'a Solution, name: &str) -> &'a [f64] {
    s.get(name).unwrap_or_else(|| panic!("no column {name}"))
}

fn vector(s: &Solution, name: &str, k: usize) -> [f64; 3] {
    [1, 2, 3].map(|i| column(s, &format!("{name}[{i}]"))[k])
}

/// The world-resolved velocity of a point `at` fixed on a body.
fn point_velocity(s: &Solution, body: &str, at: [f64; 3], k: usize) -> [f64; 3] {
    let w_a = vector(s, &format!("{body}.w_a"), k);
    // R maps world to frame_a coordinates, so w_0 = R^T w_a.
    let r = |i: usize, j: usize| column(s, &format!("{body}.frame_a.R[{i},{j}]"))[k];
    let w = [1, 2, 3].map(|j| (1..=3).map(|i| r(i, j) * w_a[i - 1]).sum::<f64>());
    let origin = vector(s, &format!("{body}.frame_a.r_0"), k);
    let lever = [0, 1, 2].map(|i| at[i] - origin[i]);
    let v = vector(s, &format!("{body}.v_0"), k);
    [
        v[0] + w[1] * lever[2] - w[2] * lever[1],
        v[1] + w[2] * lever[0] - w[0] * lever[2],
        v[2] + w[0] * lever[1] - w[1] * lever[0],
    ]
}

/// A Cable of three segments with a load, and the same chain written out
/// joint by joint.
const CABLE_AND_CHAIN: &str = "
example component WithCable
  world = MultibodyComponents.World()
  cable = MultibodyComponents.Cable(n = 3, l = 1.2, m = 0.6, dir = [1, 0, 0])
  load = MultibodyComponents.Body(m = 0.5, r_cm = [0, 0, 0])
relations
  connect(world.frame_b, cable.frame_a)
  connect(cable.frame_b, load.frame_a)
end
example component ByHand
  world = MultibodyComponents.World()
  link1 = MultibodyComponents.BodyShape(r = [0.4, 0, 0], r_cm = [0.2, 0, 0], m = 0.2, radius = 0.05)
  link2 = MultibodyComponents.BodyShape(r = [0.4, 0, 0], r_cm = [0.2, 0, 0], m = 0.2, radius = 0.05)
  link3 = MultibodyComponents.BodyShape(r = [0.4, 0, 0], r_cm = [0.2, 0, 0], m = 0.2, radius = 0.05)
  ball1 = MultibodyComponents.Spherical(orientation_state = OrientationState.Quaternion())
  ball2 = MultibodyComponents.Spherical(orientation_state = OrientationState.Quaternion())
  ball3 = MultibodyComponents.Spherical(orientation_state = OrientationState.Quaternion())
  ball4 = MultibodyComponents.Spherical(orientation_state = OrientationState.Quaternion())
  load = MultibodyComponents.Body(m = 0.5, r_cm = [0, 0, 0])
relations
  connect(world.frame_b, ball1.frame_a)
  connect(ball1.frame_b, link1.frame_a)
  connect(link1.frame_b, ball2.frame_a)
  connect(ball2.frame_b, link2.frame_a)
  connect(link2.frame_b, ball3.frame_a)
  connect(ball3.frame_b, link3.frame_a)
  connect(link3.frame_b, ball4.frame_a)
  connect(ball4.frame_b, load.frame_a)
end
";

/// A load hanging from the world on a three-segment cable, started
/// horizontal: the Cable and the same chain of Spherical joints and
/// BodyShapes move the same.
#[test]
fn a_cable_moves_as_the_chain_it_is_made_of() {
    let text = CABLE_AND_CHAIN;
    let cable = simulate(text, "WithCable", 2.0);
    let by_hand = simulate(text, "ByHand", 2.0);
    assert_eq!(cable.time().len(), by_hand.time().len());
    let mut worst = 0.0f64;
    for i in 1..=3 {
        for c in 1..=3 {
            let a = column(&cable, &format!("cable.links[{i}].frame_b.r_0[{c}]"));
            let b = column(&by_hand, &format!("link{i}.frame_b.r_0[{c}]"));
            worst = a.iter().zip(b).map(|(a, b)| (a - b).abs()).fold(worst, f64::max);
        }
    }
    let load = column(&cable, "load.r_0[2]");
    let fallen = load[0] - load.iter().copied().fold(f64::INFINITY, f64::min);
    println!(
        "cable vs chain: worst position difference {worst:.2e} m ({:.3} of 1e-9); load fell {fallen:.2} m",
        worst / 1e-9
    );
    assert!(fallen > 0.5, "the load hardly moves ({fallen} m)");
    assert!(worst <= 1e-9, "the cable and the chain differ by {worst} m");
}

/// The joint space of the Cable (its joints named by their place in the
/// array, `cable.joints[2]`, each once) has the mass matrix of the same
/// chain written out joint by joint.
#[test]
fn a_cables_joint_space_is_the_chains() {
    let text = CABLE_AND_CHAIN;
    let mut package = Package::new();
    package.add_source("cable.dyad", text.to_string()).unwrap();
    let mut spaces = Vec::new();
    for model in ["WithCable", "ByHand"] {
        let mechanism = package.lower_component(model).unwrap().assemble().unwrap();
        spaces.push(multibody::JointSpace::new(std::sync::Arc::new(mechanism)).unwrap());
    }
    let joints = spaces[0].joints().to_vec();
    assert_eq!(joints, ["cable.joints[1]", "cable.joints[2]", "cable.joints[3]", "cable.joints[4]"], "{joints:?}");
    assert_eq!(spaces[1].joints(), ["ball1", "ball2", "ball3", "ball4"]);
    let q: Vec<f64> = (0..spaces[0].coordinates().len()).map(|k| [0.9, 0.1, -0.3, 0.2][k % 4]).collect();
    let n = spaces[0].velocities().len();
    let (mut a, mut b) = (vec![0.0; n * n], vec![0.0; n * n]);
    spaces[0].mass_matrix(&q, &mut a).unwrap();
    spaces[1].mass_matrix(&q, &mut b).unwrap();
    let worst = a.iter().zip(&b).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max);
    assert!(worst < 1e-14, "the mass matrices differ by {worst}");
}

/// A cable 2 m long between the world's origin and a mount 1.5 m away,
/// closed by the cut rod: assembly bends it from its straight start until
/// the rod spans the rest; it then swings with the rod's length held and
/// its energy (the
/// segments' KE + PE, the rod's point mass) constant.
#[test]
fn a_cable_between_two_mounts_closes_and_keeps_its_energy() {
    let text = "
example component Bridge
  world = MultibodyComponents.World()
  mount = MultibodyComponents.Fixed(r = [1.5, 0, 0])
  cable = MultibodyComponents.Cable(n = 4, iscut = true, l = 2, m = 4, dir = [1, 0, 0], radius = 0.02)
relations
  connect(world.frame_b, cable.frame_a)
  connect(cable.frame_b, mount.frame_b)
end
";
    let (n, l, m) = (4, 2.0, 4.0);
    let s = simulate(text, "Bridge", 2.0);
    let m_rod = m / n as f64;
    let energy = |k: usize| {
        let segments: f64 = (1..n)
            .map(|i| column(&s, &format!("cable.links[{i}].KE"))[k] + column(&s, &format!("cable.links[{i}].PE"))[k])
            .sum();
        // The rod's mass is at its middle, between the last segment's end and the mount (still).
        let end = vector(&s, "cable.rod.frame_a.r_0", k);
        let v_end = point_velocity(&s, &format!("cable.links[{}]", n - 1), end, k);
        let v_mid = v_end.map(|v| v / 2.0);
        let y_mid = (end[1] + vector(&s, "cable.rod.frame_b.r_0", k)[1]) / 2.0;
        segments + 0.5 * m_rod * v_mid.iter().map(|v| v * v).sum::<f64>() + m_rod * G * y_mid
    };
    let e0 = energy(0);
    let scale = m * G * l;
    let mut drift = 0.0f64;
    let mut rod_length = 0.0f64;
    let mut sag = 0.0f64;
    for k in 0..s.time().len() {
        drift = drift.max((energy(k) - e0).abs() / scale);
        let (a, b) = (vector(&s, "cable.rod.frame_a.r_0", k), vector(&s, "cable.rod.frame_b.r_0", k));
        let length = ((0..3).map(|i| (b[i] - a[i]).powi(2)).sum::<f64>()).sqrt();
        rod_length = rod_length.max((length - l / n as f64).abs());
        sag = sag.max(-a[1]);
    }
    println!(
        "bridge: |E - E0| / (m g l) {drift:.2e} ({:.3} of 1e-8); rod length error {rod_length:.1e} m; sag {sag:.2} m",
        drift / 1e-8
    );
    assert!(sag > 0.2, "the cable does not swing down ({sag} m)");
    assert!(rod_length <= 1e-7, "the rod's length changes by {rod_length} m");
    assert!(drift <= 1e-8, "energy drifts by {drift} of m g l");
}

/// A long cable (200 segments, issue 26: "loop cannot close ... check the
/// lengths" although 100 closed) between mounts closer than its length
/// closes at assembly: the rod that closes it keeps one segment's length
/// and ends at the mount.
#[test]
fn a_long_cable_between_two_mounts_closes() {
    for n in [100, 200] {
        let text = format!(
            "
example component Hang
  world = MultibodyComponents.World()
  mount = MultibodyComponents.Fixed(r = [2, 0, 0])
  cable = MultibodyComponents.Cable(n = {n}, iscut = true, l = 2.4, m = 6, dir = [1, 0, 0])
relations
  connect(world.frame_b, cable.frame_a)
  connect(cable.frame_b, mount.frame_b)
end
"
        );
        let s = simulate(&text, "Hang", 1e-3);
        let (a, b) = (vector(&s, "cable.rod.frame_a.r_0", 0), vector(&s, "cable.rod.frame_b.r_0", 0));
        let length = ((0..3).map(|i| (b[i] - a[i]).powi(2)).sum::<f64>()).sqrt();
        let error = (length - 2.4 / n as f64).abs();
        println!("cable of {n}: rod length error {error:.1e} m, rod ends at {b:?}");
        assert!(error <= 1e-9, "n = {n}: the rod is {length} m long, not {}", 2.4 / n as f64);
        assert!((b[0] - 2.0).abs() < 1e-9 && b[1].abs() < 1e-9 && b[2].abs() < 1e-9, "n = {n}: the rod ends at {b:?}");
    }
}

/// The planar Cable (PlanarMechanics) with damped joints against the same
/// chain of planar revolutes, rods and rotational dampers written out.
#[test]
fn a_planar_cable_moves_as_the_chain_it_is_made_of() {
    let text = "
example component WithCable
  world = MultibodyComponents.PlanarMechanics.World()
  cable = MultibodyComponents.PlanarMechanics.Cable(n = 3, l = 1.2, m = 0.6, dir = [1, 0], hasdamping = true, d_joint = 0.05)
  load = MultibodyComponents.PlanarMechanics.Body(m = 0.5, I = 0.01)
relations
  connect(world.frame_b, cable.frame_a)
  connect(cable.frame_b, load.frame_a)
end
example component ByHand
  world = MultibodyComponents.PlanarMechanics.World()
  link1 = MultibodyComponents.PlanarMechanics.BodyShape(r = [0.4, 0], m = 0.2, I = 0.2 * 0.4 ^ 2 / 12)
  link2 = MultibodyComponents.PlanarMechanics.BodyShape(r = [0.4, 0], m = 0.2, I = 0.2 * 0.4 ^ 2 / 12)
  link3 = MultibodyComponents.PlanarMechanics.BodyShape(r = [0.4, 0], m = 0.2, I = 0.2 * 0.4 ^ 2 / 12)
  rev1 = MultibodyComponents.PlanarMechanics.Revolute()
  rev2 = MultibodyComponents.PlanarMechanics.Revolute()
  rev3 = MultibodyComponents.PlanarMechanics.Revolute()
  rev4 = MultibodyComponents.PlanarMechanics.Revolute()
  d1 = RotationalComponents.Components.Damper(d = 0.05)
  d2 = RotationalComponents.Components.Damper(d = 0.05)
  d3 = RotationalComponents.Components.Damper(d = 0.05)
  d4 = RotationalComponents.Components.Damper(d = 0.05)
  f1 = RotationalComponents.Components.Fixed()
  f2 = RotationalComponents.Components.Fixed()
  f3 = RotationalComponents.Components.Fixed()
  f4 = RotationalComponents.Components.Fixed()
  load = MultibodyComponents.PlanarMechanics.Body(m = 0.5, I = 0.01)
relations
  connect(world.frame_b, rev1.frame_a)
  connect(rev1.frame_b, link1.frame_a)
  connect(link1.frame_b, rev2.frame_a)
  connect(rev2.frame_b, link2.frame_a)
  connect(link2.frame_b, rev3.frame_a)
  connect(rev3.frame_b, link3.frame_a)
  connect(link3.frame_b, rev4.frame_a)
  connect(rev4.frame_b, load.frame_a)
  connect(d1.spline_b, rev1.flange_a)
  connect(d2.spline_b, rev2.flange_a)
  connect(d3.spline_b, rev3.flange_a)
  connect(d4.spline_b, rev4.flange_a)
  connect(d1.spline_a, f1.spline)
  connect(d2.spline_a, f2.spline)
  connect(d3.spline_a, f3.spline)
  connect(d4.spline_a, f4.spline)
end
";
    let (cable, hand) = (simulate(text, "WithCable", 2.0), simulate(text, "ByHand", 2.0));
    let mut worst = 0.0f64;
    for (a, b) in [
        ("load.r[1]", "load.r[1]"),
        ("load.r[2]", "load.r[2]"),
        ("cable.joints[2].phi", "rev2.phi"),
        ("cable.joints[4].w", "rev4.w"),
    ] {
        worst = column(&cable, a).iter().zip(column(&hand, b)).fold(worst, |m, (x, y)| m.max((x - y).abs()));
    }
    eprintln!("planar cable against the chain by hand: worst difference {worst:.1e} (tolerance 1e-9)");
    assert!(worst < 1e-9, "the planar cable and the chain differ by {worst:e}");
    assert!(column(&cable, "load.r[2]").iter().any(|y| *y < -0.5), "the load should fall");
}

/// A planar cable hanging between two mounts 1 m apart (a loop), undamped:
/// energy stays what it was.
#[test]
fn a_planar_cable_between_two_mounts_keeps_its_energy() {
    let text = "
example component Bridge
  world = MultibodyComponents.PlanarMechanics.World()
  post = MultibodyComponents.PlanarMechanics.Fixed(r = [1, 0])
  cable = MultibodyComponents.PlanarMechanics.Cable(n = 4, l = 1.4, m = 0.8, dir = [1, -1])
relations
  connect(world.frame_b, cable.frame_a)
  connect(cable.frame_b, post.frame_b)
end
";
    let s = simulate(text, "Bridge", 2.0);
    let energy: Vec<f64> = (0..s.time().len())
        .map(|k| {
            (1..=4)
                .map(|i| {
                    column(&s, &format!("cable.links[{i}].KE"))[k] + column(&s, &format!("cable.links[{i}].PE"))[k]
                })
                .sum()
        })
        .collect();
    let scale = 0.8 * G * 1.4;
    let drift = energy.iter().fold(0.0f64, |m, e| m.max((e - energy[0]).abs())) / scale;
    let gap = column(&s, "cable.links[4].frame_b.x").iter().fold(0.0f64, |m, x| m.max((x - 1.0).abs()));
    eprintln!(
        "planar cable bridge: energy drift {drift:.1e} of m g l (tolerance 1e-8), end off its mount by {gap:.1e} m"
    );
    assert!(drift < 1e-8, "energy drifts by {drift:e} of m g l");
    assert!(gap < 1e-9, "the cable's end leaves its mount by {gap:e}");
    let swing = column(&s, "cable.joints[1].w").iter().fold(0.0f64, |m, w| m.max(w.abs()));
    assert!(swing > 0.5, "the cable should swing");
}

/// A start value on one joint of a cable (`initial cable.joints[1].Q_hat =
/// ...`, bending it at the start) reaches that joint: the cable moves as the
/// chain with the same start on its first ball joint; an index past the
/// cable's joints is an error at the start value.
#[test]
fn a_start_value_on_one_joint_of_a_cable_bends_it() {
    // A turn of 0.6 rad about z: Q = [cos 0.3, 0, 0, sin 0.3].
    let (c, s) = (0.3f64.cos(), 0.3f64.sin());
    let text = format!(
        "
example component Bent
  world = MultibodyComponents.World()
  cable = MultibodyComponents.Cable(n = 2, l = 0.8, m = 0.4, dir = [1, 0, 0])
  load = MultibodyComponents.Body(m = 0.5, r_cm = [0, 0, 0])
relations
  connect(world.frame_b, cable.frame_a)
  connect(cable.frame_b, load.frame_a)
  initial cable.joints[1].Q_hat = [{c}, 0, 0, {s}]
end
example component ByHand
  world = MultibodyComponents.World()
  link1 = MultibodyComponents.BodyShape(r = [0.4, 0, 0], r_cm = [0.2, 0, 0], m = 0.2, radius = 0.05)
  link2 = MultibodyComponents.BodyShape(r = [0.4, 0, 0], r_cm = [0.2, 0, 0], m = 0.2, radius = 0.05)
  ball1 = MultibodyComponents.Spherical(orientation_state = OrientationState.Quaternion(), Q_hat(initial = [{c}, 0, 0, {s}]))
  ball2 = MultibodyComponents.Spherical(orientation_state = OrientationState.Quaternion())
  ball3 = MultibodyComponents.Spherical(orientation_state = OrientationState.Quaternion())
  load = MultibodyComponents.Body(m = 0.5, r_cm = [0, 0, 0])
relations
  connect(world.frame_b, ball1.frame_a)
  connect(ball1.frame_b, link1.frame_a)
  connect(link1.frame_b, ball2.frame_a)
  connect(ball2.frame_b, link2.frame_a)
  connect(link2.frame_b, ball3.frame_a)
  connect(ball3.frame_b, load.frame_a)
end
"
    );
    let cable = simulate(&text, "Bent", 1.0);
    let by_hand = simulate(&text, "ByHand", 1.0);
    let mut worst = 0.0f64;
    for i in 1..=2 {
        for k in 1..=3 {
            let a = column(&cable, &format!("cable.links[{i}].frame_b.r_0[{k}]"));
            let b = column(&by_hand, &format!("link{i}.frame_b.r_0[{k}]"));
            worst = a.iter().zip(b).map(|(a, b)| (a - b).abs()).fold(worst, f64::max);
        }
    }
    // Bent at the start: the first link points 0.6 rad above x.
    let tip = column(&cable, "cable.links[1].frame_b.r_0[2]")[0];
    println!("bent cable vs chain: worst {worst:.2e} m ({:.3} of 1e-9); first tip at y = {tip:.4}", worst / 1e-9);
    assert!((tip - 0.4 * 0.6f64.sin()).abs() < 1e-12, "the first joint is not bent: y = {tip}");
    assert!(worst <= 1e-9);

    let mut package = multibody_dyad::Package::new();
    package.add_source("bent.dyad", text.replace("cable.joints[1].Q_hat", "cable.joints[7].Q_hat")).unwrap();
    let message = package.lower_component("Bent").map(|_| ()).unwrap_err().render(package.sources(), false);
    assert!(message.contains("`joints[7]`") && message.contains("out of range"), "{message}");
}

/// `Cable(n = 0)` divides by zero inside the standard library's Cable: the
/// message points there and, since the user did not write that file, at
/// the value the model gave that is zero, `n = 0` (it used to show the
/// library alone, then the whole declaration). A zero that no modifier
/// names (`norm(dir)` of `dir = [0, 0, 0]`) points at the declaration.
#[test]
fn an_error_inside_the_library_cable_points_at_the_users_cable() {
    let model = |modifiers: &str| {
        format!(
            "example component Hanging
  world = World()
  cable = MultibodyComponents.Cable({modifiers})
relations
  connect(world.frame_b, cable.frame_a)
end
analysis Run
  extends TransientAnalysis(stop = 1)
  model = Hanging()
end"
        )
    };
    let message = common::error_of(&model("n = 0"));
    for expected in [
        "division by zero",
        "<stdlib>/MultibodyComponents.dyad",
        "`n` is zero",
        "model.dyad:3:37",
        "`n` of `cable` is given here",
    ] {
        assert!(message.contains(expected), "`{expected}` missing from: {message}");
    }
    let message = common::error_of(&model("dir = [0, 0, 0]"));
    for expected in ["division by zero", "this is zero", "model.dyad:3:3", "in `cable`, declared here"] {
        assert!(message.contains(expected), "`{expected}` missing from: {message}");
    }
}
