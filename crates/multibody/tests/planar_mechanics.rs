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

/// Without damping the bodies' KE + PE stays what it was, to 1e-9 of its
/// swing.
fn assert_energy_kept(label: &str, s: &Solution, bodies: &[&str]) {
    let total: Vec<f64> = (0..s.time().len())
        .map(|k| {
            bodies.iter().map(|b| s.get(&format!("{b}.KE")).unwrap()[k] + s.get(&format!("{b}.PE")).unwrap()[k]).sum()
        })
        .collect();
    let ke_max = bodies.iter().flat_map(|b| s.get(&format!("{b}.KE")).unwrap().iter()).fold(0.0f64, |m, x| m.max(*x));
    let drift = total.iter().fold(0.0f64, |m, e| m.max((e - total[0]).abs())) / ke_max;
    eprintln!("{label}: energy drift {drift:.1e} of the largest kinetic energy (tolerance 1e-9)");
    assert!(drift < 1e-9, "{label}: energy drifts by {drift:e}");
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

/// Kinds of the planar library and their 3-D twins.
struct Kinds {
    planar: bool,
}

impl Kinds {
    fn world(&self, m: &mut Model) {
        m.add("world", if self.planar { "PlanarMechanics.World" } else { "World" });
    }
    fn revolute(&self, m: &mut Model, name: &str) {
        if self.planar {
            m.add(name, "PlanarMechanics.Revolute");
        } else {
            m.add(name, "Revolute").set("n", [0.0, 0.0, 1.0]);
        }
    }
    fn rod(&self, m: &mut Model, name: &str, r: [f64; 2]) {
        if self.planar {
            m.add(name, "PlanarMechanics.FixedTranslation").set("r", r);
        } else {
            m.add(name, "FixedTranslation").set("r", [r[0], r[1], 0.0]);
        }
    }
    fn fixed(&self, m: &mut Model, name: &str, r: [f64; 2]) {
        if self.planar {
            m.add(name, "PlanarMechanics.Fixed").set("r", r);
        } else {
            m.add(name, "Fixed").set("r", [r[0], r[1], 0.0]);
        }
    }
    fn body(&self, m: &mut Model, name: &str, mass: f64, inertia: f64) {
        if self.planar {
            m.add(name, "PlanarMechanics.Body").set("m", mass).set("I", inertia);
        } else {
            m.add(name, "Body").set("m", mass).set("I_11", 0.0).set("I_22", 0.0).set("I_33", inertia);
        }
    }
    fn prismatic(&self, m: &mut Model, name: &str, r: [f64; 2]) {
        if self.planar {
            m.add(name, "PlanarMechanics.Prismatic").set("r", r);
        } else {
            m.add(name, "Prismatic").set("n", [r[0], r[1], 0.0]);
        }
    }
}

/// A crank (0.5 m, turning at 2 rad/s at the start) drives a slider along x
/// through a 1.5 m connecting rod; bodies on the crank's tip, the rod's
/// middle and the slider; gravity along -y.
fn slider_crank(k: &Kinds) -> Model {
    let mut m = Model::new("slider_crank");
    k.world(&mut m);
    k.revolute(&mut m, "crank");
    k.rod(&mut m, "crank_rod", [0.5, 0.0]);
    k.body(&mut m, "crank_tip", 1.0, 0.01);
    k.revolute(&mut m, "elbow");
    k.rod(&mut m, "rod_half", [0.75, 0.0]);
    k.rod(&mut m, "rod_rest", [0.75, 0.0]);
    k.body(&mut m, "rod_mass", 0.5, 0.1);
    k.revolute(&mut m, "wrist");
    k.prismatic(&mut m, "slide", [1.0, 0.0]);
    k.body(&mut m, "slider", 2.0, 0.01);
    m.connect(["world.frame_b", "crank.frame_a", "slide.frame_a"]);
    m.connect(["crank.frame_b", "crank_rod.frame_a"]);
    m.connect(["crank_rod.frame_b", "crank_tip.frame_a", "elbow.frame_a"]);
    m.connect(["elbow.frame_b", "rod_half.frame_a"]);
    m.connect(["rod_half.frame_b", "rod_mass.frame_a", "rod_rest.frame_a"]);
    m.connect(["rod_rest.frame_b", "wrist.frame_a"]);
    m.connect(["wrist.frame_b", "slider.frame_a", "slide.frame_b"]);
    m.component_mut("crank").unwrap().initial("phi", 0.0).initial("w", 2.0);
    m
}

#[test]
fn a_planar_slider_crank_moves_as_its_3d_twin() {
    let (planar, spatial) = (slider_crank(&Kinds { planar: true }), slider_crank(&Kinds { planar: false }));
    let pairs =
        [("crank.phi", "crank.phi"), ("crank.w", "crank.w"), ("slide.s", "slide.s"), ("elbow.phi", "elbow.phi")];
    let s = assert_same("slider-crank", &planar, &spatial, 3.0, &pairs);
    assert_energy_kept("slider-crank", &s, &["crank_tip", "rod_mass", "slider"]);
}

/// A four-bar: crank from the origin to A = (0, 0.5), coupler from A to
/// M = (1.1, 0.6), rocker from B = (1, 0) to M; bodies on all three.
fn four_bar(k: &Kinds) -> Model {
    let mut m = Model::new("four_bar");
    k.world(&mut m);
    k.fixed(&mut m, "b", [1.0, 0.0]);
    for (rev, rod, body, r, mass) in [
        ("j1", "crank", "crank_body", [0.0, 0.5], 1.0),
        ("j2", "coupler", "coupler_body", [1.1, 0.1], 2.0),
        ("j4", "rocker", "rocker_body", [0.1, 0.6], 1.5),
    ] {
        k.revolute(&mut m, rev);
        k.rod(&mut m, rod, r);
        k.body(&mut m, body, mass, 0.05);
        m.connect([format!("{rev}.frame_b"), format!("{rod}.frame_a")]);
        m.connect([format!("{rod}.frame_b"), format!("{body}.frame_a")]);
    }
    k.revolute(&mut m, "j3");
    m.connect(["world.frame_b", "j1.frame_a"]);
    m.connect(["crank.frame_b", "j2.frame_a"]);
    m.connect(["b.frame_b", "j4.frame_a"]);
    m.connect(["coupler.frame_b", "j3.frame_a"]);
    m.connect(["rocker.frame_b", "j3.frame_b"]);
    m.component_mut("j1").unwrap().initial("w", 3.0);
    m
}

#[test]
fn a_planar_four_bar_moves_as_its_3d_twin() {
    let (planar, spatial) = (four_bar(&Kinds { planar: true }), four_bar(&Kinds { planar: false }));
    let pairs = [("j1.phi", "j1.phi"), ("j1.w", "j1.w"), ("j4.phi", "j4.phi"), ("j2.phi", "j2.phi")];
    let s = assert_same("four-bar", &planar, &spatial, 3.0, &pairs);
    assert_energy_kept("four-bar", &s, &["crank_body", "coupler_body", "rocker_body"]);
    // The loop stays closed: the coupler's end is the rocker's.
    let gap = worst(&s, &s, &[("coupler.frame_b.x", "rocker.frame_b.x"), ("coupler.frame_b.y", "rocker.frame_b.y")]);
    assert!(gap < 1e-9, "the loop opens by {gap:e}");
}

/// A planar body with nothing holding it falls freely: its own planar
/// coordinates are its states.
#[test]
fn a_free_planar_body_falls_as_the_closed_form_says() {
    let mut m = Model::new("free_fall");
    m.add("world", "PlanarMechanics.World");
    m.add("body", "PlanarMechanics.Body")
        .set("m", 2.0)
        .set("I", 1.0)
        .initial("r", [1.0, 2.0])
        .initial("v", [0.5, 3.0])
        .initial("w", 0.7);
    let s = run(&m, 3.0);
    let g = 9.80665;
    let mut worst = 0.0f64;
    for (k, t) in s.time().iter().enumerate() {
        let expect = [1.0 + 0.5 * t, 2.0 + 3.0 * t - g * t * t / 2.0, 0.7 * t];
        let got = [s.get("body.r[1]").unwrap()[k], s.get("body.r[2]").unwrap()[k], s.get("body.phi").unwrap()[k]];
        worst = (0..3).fold(worst, |m, i| m.max((got[i] - expect[i]).abs()));
    }
    eprintln!("free fall: worst error {worst:.1e} m (tolerance 1e-9)");
    assert!(worst < 1e-9, "free fall differs by {worst:e}");
}

/// Constant signals feeding a WorldForceTorque.
fn push(m: &mut Model, at: &str, force: [f64; 3]) {
    m.add("push", "PlanarMechanics.WorldForceTorque");
    for (k, input) in ["force_x", "force_y", "torque"].iter().enumerate() {
        let name = format!("push_{input}");
        m.add(&name, "BlockComponents.Constant").set("k", force[k]);
        m.connect([format!("{name}.y"), format!("push.{input}")]);
    }
    m.connect([at.to_string(), "push.frame_b".to_string()]);
}

#[test]
fn a_body_on_a_prismatic_joint_pushed_by_a_constant_force_moves_as_f_t2_over_2m() {
    let (f, mass) = (3.0, 2.0);
    let mut m = Model::new("push");
    m.add("world", "PlanarMechanics.World").set("g", 0.0);
    m.add("slide", "PlanarMechanics.Prismatic").set("r", [3.0, 4.0]);
    m.add("body", "PlanarMechanics.Body").set("m", mass).set("I", 0.1);
    m.connect(["world.frame_b", "slide.frame_a"]);
    m.connect(["slide.frame_b", "body.frame_a"]);
    // Along the slide (3, 4)/5, plus a push across it that the joint takes.
    push(&mut m, "body.frame_a", [f * 0.6 - 4.0 * 0.8, f * 0.8 + 4.0 * 0.6, 0.0]);
    let s = run(&m, 2.0);
    let worst = s
        .time()
        .iter()
        .zip(s.get("slide.s").unwrap())
        .fold(0.0f64, |w, (t, x)| w.max((x - f * t * t / (2.0 * mass)).abs()));
    eprintln!("prismatic push: worst error {worst:.1e} m (tolerance 1e-9)");
    assert!(worst < 1e-9, "s differs from F t^2 / 2m by {worst:e}");
    // The joint's force along its axis is zero: nothing drives it.
    assert!(s.get("slide.f").unwrap().iter().all(|f| f.abs() < 1e-9));
}

#[test]
fn a_planar_spring_mass_oscillates_at_sqrt_c_over_m() {
    let (c, mass, x0) = (4.0, 1.0, 0.5);
    let mut m = Model::new("spring_mass");
    m.add("world", "PlanarMechanics.World");
    m.add("slide", "PlanarMechanics.Prismatic").set("r", [1.0, 0.0]).initial("s", x0).initial("v", 0.0);
    m.add("body", "PlanarMechanics.Body").set("m", mass).set("I", 0.1);
    m.add("spring", "PlanarMechanics.Spring").set("c_x", c).set("c_y", 7.0);
    m.connect(["world.frame_b", "slide.frame_a", "spring.frame_a"]);
    m.connect(["slide.frame_b", "body.frame_a", "spring.frame_b"]);
    let s = run(&m, 5.0);
    let omega = (c / mass).sqrt();
    let worst = s
        .time()
        .iter()
        .zip(s.get("slide.s").unwrap())
        .fold(0.0f64, |w, (t, x)| w.max((x - x0 * (omega * t).cos()).abs()));
    eprintln!("spring-mass: worst error {worst:.1e} m (tolerance 1e-9)");
    assert!(worst < 1e-9, "the spring-mass differs from x0 cos(sqrt(c/m) t) by {worst:e}");
    // The spring's force is c x along x, none along y (the body stays on y = 0).
    let (fx, x) = (s.get("spring.f_x").unwrap(), s.get("spring.s_relx").unwrap());
    assert!(fx.iter().zip(x).all(|(f, x)| (f - c * x).abs() < 1e-12));
}

/// A planar pendulum carries a 3-D body through PlanarToMultiBody, 0.25 m
/// out of the plane: it swings as the same pendulum built in 3-D, and the
/// plane takes the body's weight moment about the rod.
#[test]
fn a_planar_pendulum_drives_a_3d_body_through_planar_to_multibody() {
    let mut planar = chain(true, &[([1.0, 0.0], 1.0, 0.1)]);
    planar.add("adapter", "PlanarMechanics.PlanarToMultiBody").set("z_position", 0.25);
    planar.add("world3d", "World");
    planar.add("load", "Body").set("m", 0.5).set("r_cm", [0.1, 0.0, 0.0]).set("I_33", 0.02);
    planar.connect(["rod1.frame_b", "adapter.frame_a"]);
    planar.connect(["adapter.frame_b", "load.frame_a"]);

    let mut spatial = chain(false, &[([1.0, 0.0], 1.0, 0.1)]);
    spatial.add("lift", "FixedTranslation").set("r", [0.0, 0.0, 0.25]);
    spatial.add("load", "Body").set("m", 0.5).set("r_cm", [0.1, 0.0, 0.0]).set("I_33", 0.02);
    spatial.connect(["rod1.frame_b", "lift.frame_a"]);
    spatial.connect(["lift.frame_b", "load.frame_a"]);

    let pairs = [
        ("rev1.phi", "rev1.phi"),
        ("rev1.w", "rev1.w"),
        ("load.r_0[1]", "load.r_0[1]"),
        ("load.r_0[3]", "load.r_0[3]"),
    ];
    assert_same("planar to 3-D", &planar, &spatial, 2.0, &pairs);
    // Hanging at rest, the load's weight (0.5 g, 0.25 m out of the plane)
    // is a moment about the rod's y axis that the plane takes.
    planar.component_mut("rev1").unwrap().initial("phi", -std::f64::consts::FRAC_PI_2).initial("w", 0.0);
    let s = run(&planar, 1.0);
    let expected = 0.5 * 9.80665 * 0.25;
    let worst = s.get("adapter.tau_perp[2]").unwrap().iter().fold(0.0f64, |m, t| m.max((t.abs() - expected).abs()));
    assert!(worst < 1e-9, "the plane's moment differs from m g z by {worst:e}");
}

#[test]
fn a_planar_frame_does_not_connect_to_a_3d_frame() {
    let mut m = chain(true, &[([1.0, 0.0], 1.0, 0.1)]);
    m.add("world3d", "World");
    m.add("load", "Body").set("m", 0.5);
    m.connect(["rod1.frame_b", "load.frame_a"]);
    let message = m.assemble().unwrap_err().to_string();
    for part in ["`rod1.frame_b` (Frame2D)", "`load.frame_a` (Frame3D)", "PlanarToMultiBody"] {
        assert!(message.contains(part), "{message}");
    }
    // The 3-D Prismatic has no `r`; the message points at the planar one.
    let mut m = Model::new("m");
    m.add("world", "PlanarMechanics.World");
    m.add("slide", "Prismatic").set("r", [1.0, 0.0]);
    let message = m.assemble().unwrap_err().to_string();
    assert!(message.contains("`PlanarMechanics.Prismatic`"), "{message}");
}

#[path = "common/chain.rs"]
mod chain;

/// The benchmark's 100-link planar chain moves as its 3-D twin.
#[test]
fn a_hundred_link_planar_chain_moves_as_its_3d_twin() {
    let (planar, spatial) = (chain::planar_chain(100, true), chain::planar_chain(100, false));
    let pairs = [("j0.phi", "j0.phi"), ("j99.phi", "j99.phi"), ("j50.w", "j50.w")];
    let (a, b) = (run(&planar, 0.2), run(&spatial, 0.2));
    let d = worst(&a, &b, &pairs);
    eprintln!("100-link chain: planar and 3-D differ by {d:.1e} (tolerance 1e-9)");
    assert!(d < 1e-9, "the 100-link chains differ by {d:e}");
}

/// A wheel (a planar body on a rolling joint) pushed along x by a constant
/// force at its centre: it rolls with a = F / (m + I / r^2), the ground
/// carries its weight, and x = radius phi_roll + x0 holds.
const ROLLING: (f64, f64, f64, f64) = (0.5, 0.1, 0.01, 0.4);

/// A planar body on a rolling wheel joint, pushed along x at its centre.
fn rolling_wheel() -> Model {
    let (f, mass, inertia, radius) = ROLLING;
    let mut m = Model::new("rolling");
    m.add("world", "PlanarMechanics.World");
    m.add("wheel", "PlanarMechanics.OneDOFRollingWheelJoint").set("radius", radius).set("x0", 0.3);
    m.add("body", "PlanarMechanics.Body")
        .set("m", mass)
        .set("I", inertia)
        .initial("r", [0.3, radius])
        .initial("v", [0.0, 0.0])
        .initial("phi", 0.0)
        .initial("w", 0.0);
    m.connect(["wheel.frame_a", "body.frame_a"]);
    push(&mut m, "body.frame_a", [f, 0.0, 0.0]);
    m
}

#[test]
fn a_planar_rolling_wheel_pushed_at_its_centre_accelerates_as_the_closed_form_says() {
    let (f, mass, inertia, radius) = ROLLING;
    let s = run(&rolling_wheel(), 3.0);
    let a = f / (mass + inertia / (radius * radius));
    let (x, phi_roll) = (s.get("wheel.x").unwrap(), s.get("wheel.phi_roll").unwrap());
    let mut worst = 0.0f64;
    for (k, t) in s.time().iter().enumerate() {
        worst = worst.max((x[k] - 0.3 - a * t * t / 2.0).abs());
        // Turning clockwise while it rolls to +x: phi = -phi_roll.
        worst = worst.max((s.get("body.w").unwrap()[k] + a * t / radius).abs());
        worst = worst.max((radius * phi_roll[k] + 0.3 - x[k]).abs());
    }
    let weight = s.get("wheel.f_n").unwrap().iter().fold(0.0f64, |m, n| m.max((n - mass * 9.80665).abs()));
    let grip = mass * a - f; // the ground's push along x: m a = F + f_long
    let long = s.get("wheel.f_long").unwrap().iter().fold(0.0f64, |m, g| m.max((g - grip).abs()));
    eprintln!("rolling wheel: worst motion error {worst:.1e} (tolerance 1e-8), normal force {weight:.1e} N, grip {long:.1e} N");
    assert!(worst < 1e-8, "the rolling wheel differs from its closed form by {worst:e}");
    assert!(weight < 1e-9 && long < 1e-9, "contact forces: {weight:e}, {long:e}");
}

/// A wheel spun at 30 rad/s and set on the ground slips, and friction brings
/// it to rolling; about the contact point its angular momentum
/// I w - m r v is kept throughout (ground forces act at that point, gravity
/// on the vertical through it), so it ends rolling at w = I w0 / (I + m r^2).
const SLIPPING: (f64, f64, f64, f64) = (0.1, 0.1, 1.0, 30.0);

/// A planar wheel spun at `w0` set on the ground, where it slips.
fn slipping_wheel() -> Model {
    let (mass, inertia, radius, w0) = SLIPPING;
    let mut m = Model::new("slipping");
    m.add("world", "PlanarMechanics.World");
    m.add("wheel", "PlanarMechanics.OneDOFSlippingWheelJoint")
        .set("radius", radius)
        .set("mu_A", 0.95)
        .set("mu_S", 0.7)
        .set("sAdhesion", 0.04)
        .set("sSlide", 0.12)
        .set("vAdhesion_min", 0.05)
        .set("vSlide_min", 0.15);
    m.add("body", "PlanarMechanics.Body")
        .set("m", mass)
        .set("I", inertia)
        .initial("r", [0.0, radius])
        .initial("v", [0.0, 0.0])
        .initial("phi", 0.0)
        .initial("w", w0);
    m.connect(["wheel.frame_a", "body.frame_a"]);
    m
}

#[test]
fn a_spinning_planar_wheel_slips_until_it_rolls_keeping_its_angular_momentum_about_the_contact() {
    let (mass, inertia, radius, w0) = SLIPPING;
    let s = run(&slipping_wheel(), 6.0);
    let (v, w) = (s.get("body.v[1]").unwrap(), s.get("body.w").unwrap());
    let l0 = inertia * w0;
    let kept = v.iter().zip(w).fold(0.0f64, |m, (v, w)| m.max((inertia * w - mass * radius * v - l0).abs())) / l0;
    let last = v.len() - 1;
    let w_end = inertia * w0 / (inertia + mass * radius * radius);
    eprintln!(
        "slipping wheel: angular momentum about the contact kept to {kept:.1e} of it (tolerance 1e-8); ends at w = {:.6} (rolling: {w_end}), v + r w = {:.1e}",
        w[last],
        v[last] + radius * w[last]
    );
    assert!(kept < 1e-8, "angular momentum about the contact changes by {kept:e}");
    assert!((w[last] - w_end).abs() < 1e-3 * w_end, "ends at w = {}", w[last]);
    assert!(v[last] < 0.0, "a wheel spinning counterclockwise rolls towards -x");
}

/// Multibody.jl's test of the slip-based wheel: a 10 kg body held on a
/// slide (along y) from a pivot, its wheel (radius 0.3, rolling along x)
/// driven by 2 N.m through a 1 kg.m2 inertia, no gravity. The wheel runs in
/// circles, its lateral force saturated at mu_A N = 80 N; that test asserts
/// [f_lat, f_long] = [80, -5] at t = 15 and [80, -4.95] at t = 20 (to 1 %).
/// A body on a slide from a pivot, driven in circles by a slip-based wheel.
fn slip_based_wheel() -> Model {
    let mut m = Model::new("slip_based");
    m.add("world", "PlanarMechanics.World").set("g", 0.0);
    m.add("pivot", "PlanarMechanics.Revolute");
    m.add("slide", "PlanarMechanics.Prismatic").set("r", [0.0, 1.0]).initial("s", 1.0).initial("v", 0.0);
    m.add("body", "PlanarMechanics.Body").set("m", 10.0).set("I", 1.0);
    m.add("wheel", "PlanarMechanics.SlipBasedWheelJoint")
        .set("radius", 0.3)
        .set("r", [1.0, 0.0])
        .set("mu_A", 0.8)
        .set("mu_S", 0.4)
        .set("N", 100.0)
        .set("sAdhesion", 0.04)
        .set("sSlide", 0.12)
        .set("vAdhesion_min", 0.05)
        .set("vSlide_min", 0.15);
    m.add("engine", "RotationalComponents.ConstantTorque").set("tau_constant", 2.0);
    m.add("mount", "RotationalComponents.Fixed");
    m.add("inertia", "RotationalComponents.Inertia").set("J", 1.0).initial("phi", 0.0).initial("w", 1e-10);
    m.add("load", "BlockComponents.Constant").set("k", 0.0);
    m.component_mut("pivot").unwrap().initial("phi", 0.0).initial("w", 0.0);
    m.connect(["world.frame_b", "pivot.frame_a"]);
    m.connect(["pivot.frame_b", "slide.frame_a"]);
    m.connect(["slide.frame_b", "body.frame_a", "wheel.frame_a"]);
    m.connect(["engine.support", "mount.spline"]);
    m.connect(["engine.spline", "inertia.spline_a"]);
    m.connect(["inertia.spline_b", "wheel.flange_a"]);
    m.connect(["load.y", "wheel.dynamicLoad"]);
    m
}

#[test]
fn a_slip_based_wheel_driving_in_circles_meets_multibody_jl() {
    let options = SimulationOptions { stop: 20.0, saveat: 0.05, abstol: 1e-8, reltol: 1e-8, ..Default::default() };
    let s = slip_based_wheel().assemble().unwrap().simulate(&options).unwrap();
    let at = |name: &str, t: f64| s.get(name).unwrap()[(t / 0.05).round() as usize];
    let mut worst = 0.0f64;
    for (t, lat, long) in [(15.0, 80.0, -5.0), (20.0, 80.0, -4.95)] {
        let (f_lat, f_long) = (at("wheel.f_lat", t), at("wheel.f_long", t));
        eprintln!(
            "slip-based wheel at t = {t}: [f_lat, f_long] = [{f_lat:.4}, {f_long:.4}], Multibody.jl [{lat}, {long}]"
        );
        worst = worst.max(((f_lat - lat) / lat).abs()).max(((f_long - long) / long).abs());
    }
    eprintln!("slip-based wheel: worst relative difference {worst:.1e} (tolerance 1e-2)");
    assert!(worst < 1e-2, "the slip-based wheel differs from Multibody.jl by {worst:e}");
}

/// The plane's axes in the world for the planar World's `rot_3d`: turned
/// about x, then the new y, then the new z (columns: the plane's x, y and
/// normal in world coordinates), written here with the textbook matrices.
fn plane_axes(angles: [f64; 3]) -> multibody::math::Mat3 {
    use multibody::math::Mat3;
    let [a, b, c] = angles;
    let rx = Mat3::new(1.0, 0.0, 0.0, 0.0, a.cos(), -a.sin(), 0.0, a.sin(), a.cos());
    let ry = Mat3::new(b.cos(), 0.0, b.sin(), 0.0, 1.0, 0.0, -b.sin(), 0.0, b.cos());
    let rz = Mat3::new(c.cos(), -c.sin(), 0.0, c.sin(), c.cos(), 0.0, 0.0, 0.0, 1.0);
    rx * ry * rz
}

/// A pendulum carrying a 3-D body through PlanarToMultiBody, a puck on a
/// spring-damper pushed by a world force, and sensors, in a plane at
/// `origin` turned by `angles`.
fn mechanism_in_plane(origin: [f64; 3], angles: [f64; 3]) -> Model {
    let mut m = Model::new("in_plane");
    m.add("world", "PlanarMechanics.World").set("r_0_3d", origin).set("rot_3d", angles);
    m.add("hinge", "PlanarMechanics.Revolute").initial("phi", 0.4).initial("w", 0.0);
    m.add("rod", "PlanarMechanics.FixedTranslation").set("r", [1.0, 0.0]);
    m.add("bob", "PlanarMechanics.Body").set("m", 1.0).set("I", 0.1);
    m.add("adapter", "PlanarMechanics.PlanarToMultiBody").set("z_position", 0.3);
    m.add("load", "Body").set("m", 0.5).set("r_cm", [0.1, 0.0, 0.2]);
    m.add("anchor", "PlanarMechanics.Fixed").set("r", [0.5, 1.0]).set("phi", 0.2);
    m.add("spring", "PlanarMechanics.SpringDamper")
        .set("c_x", 4.0)
        .set("c_y", 6.0)
        .set("c_phi", 2.0)
        .set("d_x", 0.3)
        .set("d_y", 0.2)
        .set("d_phi", 0.1);
    m.add("puck", "PlanarMechanics.Body")
        .set("m", 0.5)
        .set("I", 0.05)
        .initial("r", [1.0, 0.5])
        .initial("v", [0.0, 0.4])
        .initial("phi", 0.3)
        .initial("w", 0.0);
    m.add("push", "PlanarMechanics.WorldForceTorque");
    for (name, k) in [("fx", 1.0), ("fy", 0.5), ("tz", 0.2)] {
        m.add(name, "BlockComponents.Constant").set("k", k);
    }
    m.add("where", "PlanarMechanics.AbsolutePosition").set("resolve_in_frame", multibody::Value::Enum("World".into()));
    m.add("speed", "PlanarMechanics.AbsoluteVelocity").set("resolve_in_frame", multibody::Value::Enum("World".into()));
    m.connect(["world.frame_b", "hinge.frame_a"]);
    m.connect(["hinge.frame_b", "rod.frame_a"]);
    m.connect(["rod.frame_b", "bob.frame_a", "adapter.frame_a"]);
    m.connect(["adapter.frame_b", "load.frame_a"]);
    m.connect(["anchor.frame_b", "spring.frame_a"]);
    m.connect(["spring.frame_b", "puck.frame_a", "push.frame_b", "where.frame_a", "speed.frame_a"]);
    m.connect(["fx.y", "push.force_x"]);
    m.connect(["fy.y", "push.force_y"]);
    m.connect(["tz.y", "push.torque"]);
    m
}

/// The planar World's `r_0_3d` and `rot_3d` move the plane in 3-D: every
/// planar quantity (positions, angles, forces, sensors, energies) is the
/// same as in the x-y plane, and the 3-D side of PlanarToMultiBody sits at
/// `origin + A [x, y, z_position]` turned by `A Rz(phi)`, with `A` the
/// plane's axes computed in the test.
#[test]
fn a_plane_placed_in_3d_moves_its_3d_parts_and_keeps_every_planar_quantity() {
    let (origin, angles) = ([1.0, -2.0, 0.5], [0.7, -0.4, 1.1]);
    let flat = run(&mechanism_in_plane([0.0; 3], [0.0; 3]), 3.0);
    let placed = run(&mechanism_in_plane(origin, angles), 3.0);
    let planar =
        ["hinge.", "rod.", "bob.", "anchor.", "spring.", "puck.", "push.", "where.", "speed.", "adapter.frame_a"];
    // Cut forces and torques at the 3-D frames are in frame coordinates.
    let invariant = ["adapter.fz", "adapter.tau_perp", "adapter.frame_b.f", "adapter.frame_b.tau", "load.frame_a.f"];
    let (compared, worst) =
        placement_difference(&flat, &placed, |name| planar.iter().chain(&invariant).any(|p| name.starts_with(p)));
    eprintln!("placed plane: {compared} planar columns differ from the x-y plane's by {worst:.1e} (tolerance 1e-8)");
    assert!(compared > 60, "only {compared} columns compared");
    assert!(worst < 1e-8, "planar quantities change with the plane's placement by {worst:e}");
    let moved = flat.get("puck.r[1]").unwrap().iter().fold(0.0f64, |m, x| m.max((x - 1.0).abs()));
    assert!(moved > 0.1, "the puck hardly moves");

    let axes = plane_axes(angles);
    let o = multibody::math::Vec3::from(origin);
    let mut worst = 0.0f64;
    for k in 0..flat.time().len() {
        let col = |s: &Solution, n: &str| s.get(n).unwrap()[k];
        let (x, y, phi) =
            (col(&flat, "adapter.frame_a.x"), col(&flat, "adapter.frame_a.y"), col(&flat, "adapter.frame_a.phi"));
        let r = o + axes * multibody::math::Vec3::new(x, y, 0.3);
        let turn = multibody::math::Mat3::new(phi.cos(), -phi.sin(), 0.0, phi.sin(), phi.cos(), 0.0, 0.0, 0.0, 1.0);
        let world_to_frame = (axes * turn).transpose();
        for i in 0..3 {
            worst = worst.max((col(&placed, &format!("adapter.frame_b.r_0[{}]", i + 1)) - r[i]).abs());
            for j in 0..3 {
                let got = col(&placed, &format!("adapter.frame_b.R[{},{}]", i + 1, j + 1));
                worst = worst.max((got - world_to_frame[(i, j)]).abs());
            }
        }
    }
    eprintln!("placed plane: the 3-D frame differs from the plane's placement by {worst:.1e} (tolerance 1e-8)");
    assert!(worst < 1e-8, "the 3-D side of PlanarToMultiBody is off its placed plane by {worst:e}");
}

/// How many columns `keep` selects, and their largest difference between
/// a run in the x-y plane and one in a placed plane.
fn placement_difference(flat: &Solution, placed: &Solution, keep: impl Fn(&str) -> bool) -> (usize, f64) {
    let mut compared = 0;
    let mut worst = 0.0f64;
    for name in flat.names().iter().filter(|n| keep(n)) {
        let (a, b) = (flat.get(name).unwrap(), placed.get(name).unwrap_or_else(|| panic!("no {name}")));
        worst = a.iter().zip(b).fold(worst, |m, (a, b)| m.max((a - b).abs()));
        compared += 1;
    }
    (compared, worst)
}

/// Wheels roll on the plane's ground line wherever the plane is: the
/// rolling, slipping and slip-based wheels give every column of their
/// x-y plane runs in a plane moved to [1, -2, 0.5] and turned. (The
/// slipping wheel's friction is steep near adhesion: there the two runs'
/// rounding, integrated at 1e-12, leaves 6e-9 in its accelerations.)
#[test]
fn planar_wheels_in_a_placed_plane_roll_and_slip_as_in_the_x_y_plane() {
    let options = SimulationOptions { stop: 3.0, saveat: 0.05, abstol: 1e-12, reltol: 1e-12, ..Default::default() };
    for flat in [rolling_wheel(), slipping_wheel(), slip_based_wheel()] {
        let mut placed = flat.clone();
        placed.component_mut("world").unwrap().set("r_0_3d", [1.0, -2.0, 0.5]).set("rot_3d", [0.7, -0.4, 1.1]);
        let simulate =
            |m: &Model| m.assemble().unwrap_or_else(|e| panic!("{}: {e}", m.name)).simulate(&options).unwrap();
        let (a, b) = (simulate(&flat), simulate(&placed));
        let (compared, worst) = placement_difference(&a, &b, |_| true);
        eprintln!("{} in a placed plane: {compared} columns differ by {worst:.1e} (tolerance 1e-7)", flat.name);
        assert!(worst < 1e-7, "{}: the placed plane changes the run by {worst:e}", flat.name);
    }
}

/// The library's PlanarToMultiBodyEmbeddedTest: a pose prescribed as
/// x = t, y = t / 2, phi = 0.3 t in a plane at [1, 2, 3] puts the 3-D frame
/// (z_position 0.5) at [6, 4.5, 3.5] at t = 5, as its documentation says,
/// turned about z by 1.5 rad.
#[test]
fn planar_to_multibody_embedded_in_a_plane_at_1_2_3_is_at_6_4_5_3_5_at_t_5() {
    let mut m = Model::new("PlanarToMultiBodyEmbeddedTest");
    m.add("world", "PlanarMechanics.World").set("r_0_3d", [1.0, 2.0, 3.0]);
    m.add("prescribed", "PlanarMechanics.PrescribedPose");
    m.add("body", "PlanarMechanics.Body").set("m", 1.0).set("I", 1.0);
    m.add("adapter", "PlanarMechanics.PlanarToMultiBody").set("z_position", 0.5);
    m.add("sensor", "AbsoluteAngles");
    for (name, slope, input) in [("x", 1.0, "r_x"), ("y", 0.5, "r_y"), ("turn", 0.3, "phi")] {
        m.add(name, "BlockComponents.Ramp").set("height", 100.0 * slope).set("duration", 100.0);
        m.connect([format!("{name}.y"), format!("prescribed.{input}")]);
    }
    m.connect(["prescribed.frame_b", "body.frame_a", "adapter.frame_a"]);
    m.connect(["adapter.frame_b", "sensor.frame_a"]);
    let s = run(&m, 5.0);
    let last = s.time().len() - 1;
    let at = |name: &str| s.get(name).unwrap_or_else(|| panic!("no {name}"))[last];
    let r = [at("adapter.frame_b.r_0[1]"), at("adapter.frame_b.r_0[2]"), at("adapter.frame_b.r_0[3]")];
    let angles = [at("sensor.angles[1]"), at("sensor.angles[2]"), at("sensor.angles[3]")];
    eprintln!("embedded test at t = 5: r_0 = {r:?} (documented [6, 4.5, 3.5]), angles = {angles:?}");
    let gap = (0..3).map(|i| (r[i] - [6.0, 4.5, 3.5][i]).abs()).fold(0.0f64, f64::max);
    let turn = (0..3).map(|i| (angles[i] - [0.0, 0.0, 1.5][i]).abs()).fold(0.0f64, f64::max);
    assert!(gap < 1e-9 && turn < 1e-9, "r_0 {r:?}, angles {angles:?}");
    // The planar side reads in the plane: x = t, y = t / 2.
    assert!((at("body.r[1]") - 5.0).abs() < 1e-9 && (at("body.r[2]") - 2.5).abs() < 1e-9);
}

/// A planar Prismatic with `axisflange`: a translational spring between
/// its support and axis holds a 1 kg body sliding along x, which then
/// oscillates as `s0 cos(sqrt(c / m) t)`, and the joint's force is the
/// spring's.
#[test]
fn a_planar_prismatic_driven_through_its_axis_flange_oscillates_at_sqrt_c_over_m() {
    let (c, mass, x0) = (4.0, 1.0, 0.5);
    let mut m = Model::new("flange_spring");
    m.add("world", "PlanarMechanics.World");
    m.add("slide", "PlanarMechanics.Prismatic")
        .set("r", [1.0, 0.0])
        .set("axisflange", true)
        .initial("s", x0)
        .initial("v", 0.0);
    m.add("body", "PlanarMechanics.Body").set("m", mass).set("I", 0.1);
    m.add("spring", "TranslationalComponents.Spring").set("c", c).set("s_rel0", 0.0);
    m.connect(["world.frame_b", "slide.frame_a"]);
    m.connect(["slide.frame_b", "body.frame_a"]);
    m.connect(["spring.flange_a", "slide.support"]);
    m.connect(["spring.flange_b", "slide.axis"]);
    let s = run(&m, 3.0);
    let omega = (c / mass).sqrt();
    let worst = s
        .time()
        .iter()
        .zip(s.get("slide.s").unwrap())
        .fold(0.0f64, |w, (t, x)| w.max((x - x0 * (omega * t).cos()).abs()));
    assert!(worst < 1e-9, "the spring on the flange differs from x0 cos(sqrt(c/m) t) by {worst:e}");
}

/// A plane turned by rot_3d = [pi/2, 0, 0] stands upright: its y axis is
/// the world's z, so its gravity [0, -1] points along the world's -z. A
/// 3-D World beside it must say the same: its default gravity (-y) is
/// refused with a message that points at rot_3d, and n = [0, 0, -1] runs,
/// a 3-D body hanging from the plane then falling with the planar body.
#[test]
fn a_turned_plane_and_a_3d_world_must_agree_on_gravity() {
    let model = |n_3d: Option<[f64; 3]>| {
        let mut m = Model::new("upright_plane");
        m.add("world", "PlanarMechanics.World").set("rot_3d", [std::f64::consts::FRAC_PI_2, 0.0, 0.0]);
        let world_3d = m.add("world_3d", "World");
        if let Some(n) = n_3d {
            world_3d.set("n", n);
        }
        m.add("puck", "PlanarMechanics.Body")
            .set("m", 1.0)
            .set("I", 0.1)
            .initial("r", [0.0, 0.0])
            .initial("v", [0.0, 0.0]);
        m.add("adapter", "PlanarMechanics.PlanarToMultiBody");
        m.add("ball", "Body").set("m", 0.5);
        m.connect(["puck.frame_a", "adapter.frame_a"]);
        m.connect(["adapter.frame_b", "ball.frame_a"]);
        m
    };
    let message = model(None).assemble().unwrap_err().to_string();
    for expected in ["gravity", "rot_3d", "world_3d", "must agree"] {
        assert!(message.contains(expected), "`{expected}` missing from: {message}");
    }
    let s = run(&model(Some([0.0, 0.0, -1.0])), 1.0);
    let g = 9.80665;
    let mut worst = 0.0f64;
    for (k, t) in s.time().iter().enumerate() {
        // In the plane: y falls as -g t^2 / 2; in the world: z does.
        worst = worst.max((s.get("puck.r[2]").unwrap()[k] + g * t * t / 2.0).abs());
        worst = worst.max((s.get("ball.frame_a.r_0[3]").unwrap()[k] + g * t * t / 2.0).abs());
        worst = worst.max(s.get("ball.frame_a.r_0[2]").unwrap()[k].abs());
    }
    eprintln!("upright plane: free fall off by {worst:.1e} (tolerance 1e-9)");
    assert!(worst < 1e-9, "a body in an upright plane falls off by {worst:e}");
}
