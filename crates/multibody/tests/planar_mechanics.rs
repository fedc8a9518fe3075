//! PlanarMechanics against the same mechanisms built from 3-D components
//! (revolutes about z, prismatics in the plane, bodies with inertia about
//! z), against closed forms, and against conservation of energy.

use multibody::{Model, SimulationOptions, Solution};

fn options(stop: f64) -> SimulationOptions {
    SimulationOptions { stop, saveat: 0.01, abstol: 1e-12, reltol: 1e-12, ..Default::default() }
}

fn run(m: &Model, stop: f64) -> Solution {
    m.assemble().unwrap_or_else(|e| panic!("{}: {e}", m.name)).simulate(&options(stop)).unwrap()
}

/// Largest difference between `a`'s and `b`'s named signals.
fn worst(a: &Solution, b: &Solution, pairs: &[(&str, &str)]) -> f64 {
    let mut worst = 0.0f64;
    for (x, y) in pairs {
        let (p, q) = (a.get(x).unwrap_or_else(|| panic!("no {x}")), b.get(y).unwrap_or_else(|| panic!("no {y}")));
        worst = p.iter().zip(q).fold(worst, |m, (p, q)| m.max((p - q).abs()));
    }
    worst
}

fn assert_same(label: &str, planar: &Model, spatial: &Model, stop: f64, pairs: &[(&str, &str)]) -> Solution {
    let (a, b) = (run(planar, stop), run(spatial, stop));
    let d = worst(&a, &b, pairs);
    eprintln!("{label}: planar and 3-D differ by {d:.1e} (tolerance 1e-9)");
    assert!(d < 1e-9, "{label}: planar and 3-D differ by {d:e}");
    let moved = a.get(pairs[0].0).unwrap().iter().fold(0.0f64, |m, x| m.max(x.abs()));
    assert!(moved > 0.1, "{label}: {} hardly moves", pairs[0].0);
    a
}

/// A planar link: a revolute then a rod `r` then a body at its end.
fn planar_link(m: &mut Model, k: usize, from: &str, r: [f64; 2], mass: f64, inertia: f64) -> String {
    m.add(format!("rev{k}"), "PlanarMechanics.Revolute");
    m.add(format!("rod{k}"), "PlanarMechanics.FixedTranslation").set("r", r);
    m.add(format!("body{k}"), "PlanarMechanics.Body").set("m", mass).set("I", inertia);
    m.connect([from.to_string(), format!("rev{k}.frame_a")]);
    m.connect([format!("rev{k}.frame_b"), format!("rod{k}.frame_a")]);
    m.connect([format!("rod{k}.frame_b"), format!("body{k}.frame_a")]);
    format!("rod{k}.frame_b")
}

fn spatial_link(m: &mut Model, k: usize, from: &str, r: [f64; 2], mass: f64, inertia: f64) -> String {
    m.add(format!("rev{k}"), "Revolute").set("n", [0.0, 0.0, 1.0]);
    m.add(format!("rod{k}"), "FixedTranslation").set("r", [r[0], r[1], 0.0]);
    m.add(format!("body{k}"), "Body").set("m", mass).set("I_11", 0.0).set("I_22", 0.0).set("I_33", inertia);
    m.connect([from.to_string(), format!("rev{k}.frame_a")]);
    m.connect([format!("rev{k}.frame_b"), format!("rod{k}.frame_a")]);
    m.connect([format!("rod{k}.frame_b"), format!("body{k}.frame_a")]);
    format!("rod{k}.frame_b")
}

fn chain(planar: bool, links: &[([f64; 2], f64, f64)]) -> Model {
    let mut m = Model::new(if planar { "planar_chain" } else { "spatial_chain" });
    m.add("world", if planar { "PlanarMechanics.World" } else { "World" });
    let mut from = "world.frame_b".to_string();
    for (k, (r, mass, inertia)) in links.iter().enumerate() {
        from = if planar {
            planar_link(&mut m, k + 1, &from, *r, *mass, *inertia)
        } else {
            spatial_link(&mut m, k + 1, &from, *r, *mass, *inertia)
        };
    }
    m
}

#[test]
fn a_planar_pendulum_moves_as_its_3d_twin_and_as_multibody_jl_says() {
    let links = [([1.0, 0.0], 1.0, 0.1)];
    let pairs = [
        ("rev1.phi", "rev1.phi"),
        ("rev1.w", "rev1.w"),
        ("body1.r[1]", "body1.r_0[1]"),
        ("body1.r[2]", "body1.r_0[2]"),
    ];
    let s = assert_same("pendulum", &chain(true, &links), &chain(false, &links), 3.0, &pairs);
    // Its equation of motion, (I + m l^2) phi'' = -m g l cos(phi), integrated
    // here by RK4; Multibody.jl's test asserts -2.881383661312169 to 1e-2.
    let at = |t: f64| (t / 0.01).round() as usize;
    let phi = s.get("rod1.frame_a.phi").unwrap()[at(1.0)];
    let expected = pendulum_angle(9.80665 / 1.1, 1.0);
    eprintln!("pendulum: phi(1) = {phi:.12}, its equation {expected:.12}, Multibody.jl -2.881383661312169");
    assert!((phi - expected).abs() < 1e-9, "phi(1) = {phi}, expected {expected}");
    assert!((phi + 2.881383661312169).abs() < 1e-2);
    // The body's planar frame reads as the library's variables.
    let (x, y) = (s.get("body1.frame_a.x").unwrap(), s.get("body1.r[1]").unwrap());
    assert_eq!(x, y);
}

/// `phi(t)` of `phi'' = -k cos(phi)` from rest at 0, by RK4 with steps of 1e-5.
fn pendulum_angle(k: f64, t: f64) -> f64 {
    let f = |p: f64, w: f64| (w, -k * p.cos());
    let (mut p, mut w, h) = (0.0f64, 0.0f64, 1e-5);
    for _ in 0..(t / h).round() as usize {
        let k1 = f(p, w);
        let k2 = f(p + h / 2.0 * k1.0, w + h / 2.0 * k1.1);
        let k3 = f(p + h / 2.0 * k2.0, w + h / 2.0 * k2.1);
        let k4 = f(p + h * k3.0, w + h * k3.1);
        p += h / 6.0 * (k1.0 + 2.0 * k2.0 + 2.0 * k3.0 + k4.0);
        w += h / 6.0 * (k1.1 + 2.0 * k2.1 + 2.0 * k3.1 + k4.1);
    }
    p
}

#[test]
fn a_planar_double_pendulum_moves_as_its_3d_twin() {
    let links = [([1.0, 0.5], 1.0, 0.1), ([0.7, -0.2], 0.5, 0.05)];
    let pairs =
        [("rev2.phi", "rev2.phi"), ("rev1.phi", "rev1.phi"), ("rev2.w", "rev2.w"), ("body2.r[1]", "body2.r_0[1]")];
    assert_same("double pendulum", &chain(true, &links), &chain(false, &links), 3.0, &pairs);
}
