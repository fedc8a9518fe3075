//! Linear models and steady states against closed forms: a damped pendulum
//! hanging and inverted, an upright cart-pole, a spring-mass-damper, a
//! four-bar loop against its own Lagrangian, a spinning free body; and the
//! errors of bad requests.

#[path = "common/four_bar.rs"]
mod four_bar;

use multibody::{
    Derivatives, Linearization, LinearizeError, LinearizeOptions, Model, SimulationOptions, Simulator,
    SteadyStateOptions,
};
use nalgebra::DMatrix;

const G: f64 = 9.80665;

fn options() -> SimulationOptions {
    SimulationOptions { stop: 1.0, abstol: 1e-10, reltol: 1e-10, ..Default::default() }
}

/// The worst entry of `ours - theirs`, relative to the largest of
/// `theirs`, printed and checked against `tol`.
fn check(what: &str, ours: &DMatrix<f64>, theirs: &DMatrix<f64>, tol: f64) {
    assert_eq!(ours.shape(), theirs.shape(), "{what}: shapes");
    let scale = theirs.amax().max(1e-300);
    let worst = (ours - theirs).amax() / scale;
    println!("{what}: worst relative error {worst:.2e} = {:.3} of the tolerance {tol:.0e}", worst / tol);
    assert!(worst <= tol, "{what}: {worst:e} > {tol:e}\nours {ours}\ntheirs {theirs}");
}

fn linearize(model: &Model, derivatives: Derivatives, io: (&[&str], &[&str])) -> Linearization {
    let mechanism = model.assemble().unwrap();
    let sim = Simulator::new(&mechanism, &options()).unwrap();
    let opts = LinearizeOptions {
        inputs: Some(io.0.iter().map(|s| s.to_string()).collect()),
        outputs: Some(io.1.iter().map(|s| s.to_string()).collect()),
        derivatives,
    };
    sim.linearize(&opts).unwrap_or_else(|e| panic!("{e}"))
}

/// A 1 kg body 0.5 m from a revolute about z (I_33 = 0.02 about its
/// centre), a damper d on the joint and a torque input `tau`, from `phi0`.
fn damped_pendulum(phi0: f64, d: f64) -> Model {
    let mut model = Model::new("pendulum");
    model.add("world", "World");
    model.add("tau", "Input");
    model.add("rev", "Revolute").set("n", [0.0, 0.0, 1.0]).set("axisflange", true).initial("phi", phi0);
    model.add("body", "Body").set("m", 1.0).set("r_cm", [0.5, 0.0, 0.0]).set("I_33", 0.02);
    model.add("damper", "RotationalComponents.Damper").set("d", d);
    model.add("motor", "RotationalComponents.Torque");
    model.connect(["world.frame_b", "rev.frame_a"]);
    model.connect(["rev.frame_b", "body.frame_a"]);
    model.connect(["damper.spline_a", "rev.support"]);
    model.connect(["damper.spline_b", "rev.axis"]);
    model.connect(["tau.y", "motor.tau"]);
    model.connect(["motor.spline", "rev.axis"]);
    model.connect(["motor.support", "rev.support"]);
    model
}

#[test]
fn damped_pendulum_hanging_and_inverted() {
    let (m, r, d) = (1.0, 0.5, 0.3);
    let j = m * r * r + 0.02;
    for (phi0, sign, label) in
        [(-std::f64::consts::FRAC_PI_2, -1.0, "hanging"), (std::f64::consts::FRAC_PI_2, 1.0, "inverted")]
    {
        let a = DMatrix::from_row_slice(2, 2, &[0.0, 1.0, sign * m * G * r / j, -d / j]);
        let b = DMatrix::from_row_slice(2, 1, &[0.0, 1.0 / j]);
        let c = DMatrix::from_row_slice(1, 2, &[1.0, 0.0]);
        for (derivatives, tol) in [(Derivatives::Differences, 1e-7), (Derivatives::Auto, 1e-10)] {
            let lin = linearize(&damped_pendulum(phi0, d), derivatives, (&["tau"], &["rev.phi"]));
            assert_eq!(lin.state_names, ["rev.phi", "rev.w"]);
            assert_eq!(lin.input_names, ["tau"]);
            let how = if lin.exact { "exact" } else { "differences" };
            if derivatives == Derivatives::Auto {
                let accuracy = lin.accuracy.expect("exact, with differences as the check");
                println!("pendulum {label}: exact vs differences {accuracy:.2e} (tolerance 1e-9)");
                assert!(lin.exact && accuracy < 1e-9);
            }
            check(&format!("pendulum {label}, A ({how})"), &lin.a, &a, tol);
            check(&format!("pendulum {label}, B ({how})"), &lin.b, &b, tol);
            check(&format!("pendulum {label}, C ({how})"), &lin.c, &c, tol);
            assert!(lin.d.amax() <= 1e-12, "D = {}", lin.d);
            // At rest at an equilibrium, nothing moves.
            assert!(lin.rates.iter().all(|r| r.abs() < 1e-12), "{:?}", lin.rates);
        }
    }
}

/// A cart of mass `big_m` on a prismatic along x pushed by the input
/// `force`, carrying a pole: a point mass `m` at `l` above a revolute
/// about z, upright.
fn cart_pole(big_m: f64, m: f64, l: f64) -> Model {
    let mut model = Model::new("cart_pole");
    model.add("world", "World");
    model.add("force", "Input");
    model.add("slider", "Prismatic").set("n", [1.0, 0.0, 0.0]).set("axisflange", true);
    model.add("cart", "Body").set("m", big_m);
    model.add("hinge", "Revolute").set("n", [0.0, 0.0, 1.0]);
    model.add("pole", "Body").set("m", m).set("r_cm", [0.0, l, 0.0]).set("I_11", 0.0).set("I_22", 0.0).set("I_33", 0.0);
    model.add("push", "TranslationalComponents.Force");
    model.connect(["world.frame_b", "slider.frame_a"]);
    model.connect(["slider.frame_b", "cart.frame_a", "hinge.frame_a"]);
    model.connect(["hinge.frame_b", "pole.frame_a"]);
    model.connect(["force.y", "push.f"]);
    model.connect(["push.flange", "slider.axis"]);
    model.connect(["push.support", "slider.support"]);
    model
}

#[test]
fn upright_cart_pole_has_the_closed_form_poles() {
    let (big_m, m, l) = (2.0, 0.5, 0.8);
    let unstable = ((big_m + m) * G / (big_m * l)).sqrt();
    for (derivatives, tol) in [(Derivatives::Differences, 1e-7f64), (Derivatives::Auto, 1e-10)] {
        let lin = linearize(&cart_pole(big_m, m, l), derivatives, (&["force"], &["slider.s", "hinge.phi"]));
        assert_eq!(lin.state_names, ["slider.s", "hinge.phi", "slider.v", "hinge.w"]);
        let mut poles: Vec<f64> = lin.poles().iter().map(|p| p.re).collect();
        poles.sort_by(f64::total_cmp);
        let expected = [-unstable, 0.0, 0.0, unstable];
        let worst = poles.iter().zip(expected).map(|(p, e)| (p - e).abs()).fold(0.0, f64::max) / unstable;
        let how = if lin.exact { "exact" } else { "differences" };
        println!("cart-pole poles ({how}): {poles:?}, worst relative error {worst:.2e} (tolerance {tol:.0e})");
        // A double pole at zero splits by sqrt of the error in A.
        assert!(worst <= tol.sqrt(), "{poles:?} vs {expected:?}");
        assert!(lin.poles().iter().all(|p| p.im.abs() <= tol.sqrt() * unstable));
        // The entries: the closed form of the linearized equations of motion.
        let mut a = DMatrix::zeros(4, 4);
        a[(0, 2)] = 1.0;
        a[(1, 3)] = 1.0;
        // With the pole's centre at (x - l sin(phi), l cos(phi)), Lagrange's
        // equations linearized at phi = 0: (M + m) x'' - m l phi'' = F and
        // l phi'' - x'' = g phi.
        a[(2, 1)] = m * G / big_m;
        a[(3, 1)] = (big_m + m) * G / (big_m * l);
        let b = DMatrix::from_row_slice(4, 1, &[0.0, 0.0, 1.0 / big_m, 1.0 / (big_m * l)]);
        check(&format!("cart-pole A ({how})"), &lin.a, &a, tol);
        check(&format!("cart-pole B ({how})"), &lin.b, &b, tol);
    }
}

/// A 1-D mass on a spring and a damper to a wall, pushed by `f`.
fn spring_mass_damper(s0: f64, v0: f64) -> Model {
    let mut model = Model::new("smd");
    model.add("f", "Input");
    model.add("wall", "TranslationalComponents.Fixed");
    model.add("spring", "TranslationalComponents.Spring").set("c", 40.0).set("s_rel0", 0.2);
    model.add("damper", "TranslationalComponents.Damper").set("d", 1.5);
    model.add("mass", "TranslationalComponents.Mass").set("m", 2.5).initial("s", s0).initial("v", v0);
    model.add("push", "TranslationalComponents.Force");
    model.connect(["wall.flange", "spring.flange_a", "damper.flange_a"]);
    model.connect(["spring.flange_b", "damper.flange_b", "mass.flange_a"]);
    model.connect(["f.y", "push.f"]);
    model.connect(["push.flange", "mass.flange_b"]);
    model
}

#[test]
fn spring_mass_damper_is_exact_at_any_point() {
    let (c, d, m) = (40.0, 1.5, 2.5);
    let a = DMatrix::from_row_slice(2, 2, &[0.0, 1.0, -c / m, -d / m]);
    let b = DMatrix::from_row_slice(2, 1, &[0.0, 1.0 / m]);
    for (s0, v0) in [(0.0, 0.0), (0.7, -3.0), (-2.0, 11.0)] {
        for derivatives in [Derivatives::Differences, Derivatives::Auto] {
            let lin = linearize(&spring_mass_damper(s0, v0), derivatives, (&["f"], &["mass.s", "mass.v"]));
            let how = if lin.exact { "exact" } else { "differences" };
            check(&format!("spring-mass-damper at s = {s0}, v = {v0}: A ({how})"), &lin.a, &a, 1e-10);
            check(&format!("spring-mass-damper at s = {s0}, v = {v0}: B ({how})"), &lin.b, &b, 1e-10);
            check(&format!("spring-mass-damper C ({how})"), &lin.c, &DMatrix::identity(2, 2), 1e-10);
        }
    }
}

/// Numbers with their first and second derivatives in one variable:
/// enough to differentiate the four-bar's geometry twice, exactly.
#[derive(Clone, Copy, Debug)]
struct Jet(f64, f64, f64);

impl Jet {
    fn constant(x: f64) -> Self {
        Jet(x, 0.0, 0.0)
    }
    fn sqrt(self) -> Self {
        let s = self.0.sqrt();
        Jet(s, self.1 / (2.0 * s), self.2 / (2.0 * s) - self.1 * self.1 / (4.0 * s * s * s))
    }
    fn sin(self) -> Self {
        let (s, c) = self.0.sin_cos();
        Jet(s, c * self.1, c * self.2 - s * self.1 * self.1)
    }
    fn cos(self) -> Self {
        let (s, c) = self.0.sin_cos();
        Jet(c, -s * self.1, -s * self.2 - c * self.1 * self.1)
    }
}
impl std::ops::Add for Jet {
    type Output = Jet;
    fn add(self, o: Jet) -> Jet {
        Jet(self.0 + o.0, self.1 + o.1, self.2 + o.2)
    }
}
impl std::ops::Sub for Jet {
    type Output = Jet;
    fn sub(self, o: Jet) -> Jet {
        Jet(self.0 - o.0, self.1 - o.1, self.2 - o.2)
    }
}
impl std::ops::Mul for Jet {
    type Output = Jet;
    fn mul(self, o: Jet) -> Jet {
        Jet(self.0 * o.0, self.1 * o.0 + self.0 * o.1, self.2 * o.0 + 2.0 * self.1 * o.1 + self.0 * o.2)
    }
}
impl std::ops::Div for Jet {
    type Output = Jet;
    fn div(self, o: Jet) -> Jet {
        let inv = Jet(1.0 / o.0, -o.1 / (o.0 * o.0), -o.2 / (o.0 * o.0) + 2.0 * o.1 * o.1 / (o.0 * o.0 * o.0));
        self * inv
    }
}

/// The four-bar of `four_bar_linkage(.., 1.0)` as a function of the crank
/// angle `theta` alone: its reduced mass `m(theta)` with `m'`, and its
/// potential's `V'` and `V''` (bars of 1 kg with their centres halfway,
/// 0.01 kg m^2 about them, gravity along -y). The geometry: crank
/// O -> A of 0.5, coupler A -> B of sqrt(5), rocker C -> B of 1.5, C at (2, 0).
fn four_bar_lagrangian(theta: f64) -> (f64, f64, f64, f64) {
    let th = Jet(theta, 1.0, 0.0);
    let zero = Jet::constant(0.0);
    let half = Jet::constant(0.5);
    let (ax, ay) = (zero - half * th.sin(), half * th.cos());
    let (cx, cy) = (Jet::constant(2.0), zero);
    let (r1, r2) = (Jet::constant(5.0f64.sqrt()), Jet::constant(1.5));
    let (dx, dy) = (cx - ax, cy - ay);
    let dist = (dx * dx + dy * dy).sqrt();
    let a = (r1 * r1 - r2 * r2 + dist * dist) / (Jet::constant(2.0) * dist);
    let h = (r1 * r1 - a * a).sqrt();
    let (ex, ey) = (dx / dist, dy / dist);
    // The branch with B above the line A -> C (B = (2, 1.5) at theta = 0).
    let (bx, by) = (ax + a * ex - h * ey, ay + a * ey + h * ex);
    let centres = [(half * ax, half * ay), (half * (ax + bx), half * (ay + by)), (half * (cx + bx), half * (cy + by))];
    let bars = [(ax, ay), (bx - ax, by - ay), (bx - cx, by - cy)];
    let (mut mass, mut mass_d, mut v_d, mut v_dd) = (0.0, 0.0, 0.0, 0.0);
    for ((x, y), (px, py)) in centres.iter().zip(bars) {
        // Kinetic energy per unit theta-rate^2, doubled: |r'|^2 + I phi'^2.
        let rate = (px * py.d() - py * px.d()) / (px * px + py * py);
        let k = x.d() * x.d() + y.d() * y.d() + Jet::constant(0.01) * rate * rate;
        mass += k.0;
        mass_d += k.1;
        v_d += G * y.1;
        v_dd += G * y.2;
    }
    assert!((bx.0 - 2.0).abs() < 1.0 && by.0 > 0.0);
    (mass, mass_d, v_d, v_dd)
}

impl Jet {
    /// The derivative as a jet (losing the last order): `(x', x'', 0)`.
    fn d(self) -> Jet {
        Jet(self.1, self.2, 0.0)
    }
}

#[test]
fn four_bar_in_its_independent_coordinate_matches_its_lagrangian() {
    let theta = 0.3;
    let mut model = four_bar::four_bar_linkage("four_bar", 1.0);
    model.component_mut("j1").unwrap().initial("phi", theta).initial("w", 0.0);
    let lin = linearize(&model, Derivatives::Auto, (&[], &[]));
    assert_eq!(lin.state_names, ["j1.phi", "j1.w"], "{:?}", lin.notes);
    assert!(!lin.exact);
    // At rest: m(theta) theta'' + m'(theta) theta'^2 / 2 + V'(theta) = 0, so
    // d(theta'')/d(theta) = -(V'' m - V' m') / m^2 and d(theta'')/d(theta') = 0.
    let (m, m_d, v_d, v_dd) = four_bar_lagrangian(theta);
    let a = DMatrix::from_row_slice(2, 2, &[0.0, 1.0, -(v_dd * m - v_d * m_d) / (m * m), 0.0]);
    check("four-bar A in j1.phi (differences)", &lin.a, &a, 1e-7);
    // The rates agree with the Lagrangian's theta'' = -V'/m too.
    let expected = -v_d / m;
    let err = (lin.rates[1] - expected).abs() / expected.abs();
    println!("four-bar theta'': {} vs {expected}, relative error {err:.2e} (tolerance 1e-9)", lin.rates[1]);
    assert!(err < 1e-9);
}

#[test]
fn a_free_body_linearizes_in_three_rotation_coordinates() {
    let mut model = Model::new("spinning");
    model.add("world", "World").set("g", 0.0);
    model
        .add("body", "Body")
        .set("m", 2.0)
        .set("I_11", 0.1)
        .set("I_22", 0.2)
        .set("I_33", 0.3)
        .set("orientation_state", multibody::OrientationState::Quaternion)
        .initial("w_a", [0.0, 0.0, 2.0]);
    let lin = linearize(&model, Derivatives::Auto, (&[], &[]));
    // Exact derivatives along the same rotation increments as the differences beside them.
    let accuracy = lin.accuracy.expect("exact, with differences as the check");
    println!("free body: exact vs differences {accuracy:.2e} of the largest entry (tolerance 1e-9)");
    assert!(lin.exact && accuracy < 1e-9, "{:?}", lin.notes);
    assert_eq!(lin.a.nrows(), 12, "{:?}", lin.state_names);
    assert!(lin.state_names.contains(&"body.rotation[3]".to_string()), "{:?}", lin.state_names);
    // Spinning about the axis of largest inertia: Euler's equations give a
    // stable nutation at w^2 (I3 - I1)(I3 - I2) / (I1 I2) = 4 * 0.2 * 0.1 / 0.02.
    let nutation = (4.0f64 * 0.2 * 0.1 / 0.02).sqrt();
    let found = lin.poles().iter().map(|p| p.im).fold(0.0, f64::max);
    println!("free body nutation: {found} vs {nutation}");
    assert!((found - nutation).abs() < 1e-6 * nutation, "{:?}", lin.poles());
}

#[test]
fn steady_state_of_a_pendulum_under_a_torque_and_none_on_a_free_joint() {
    // Held at rest by a constant torque tau0: m g r cos(phi) = tau0.
    let (m, r, tau0) = (1.0, 0.5, 1.2);
    let mechanism = damped_pendulum(-1.0, 0.3).assemble().unwrap();
    let mut sim = Simulator::new(&mechanism, &options()).unwrap();
    sim.set_input("tau", tau0).unwrap();
    let found = sim.steady_state(&SteadyStateOptions::default()).unwrap();
    let phi = sim.state_value("rev.phi").unwrap();
    let expected = -(tau0 / (m * G * r)).acos();
    println!(
        "steady pendulum: phi = {phi} vs {expected} after {} steps, residual {:.1e}",
        found.iterations, found.residual
    );
    assert!((phi - expected).abs() < 1e-9);
    // The torque that holds it at an angle: tau free, the angle fixed.
    let mut sim = Simulator::new(&mechanism, &options()).unwrap();
    let trim = SteadyStateOptions {
        free_inputs: vec!["tau".into()],
        fixed_outputs: vec![("rev.phi".into(), -0.4)],
        ..Default::default()
    };
    let found = sim.steady_state(&trim).unwrap();
    let expected = m * G * r * (-0.4f64).cos();
    println!("trim: tau = {} vs {expected} after {} steps", found.inputs[0].1, found.iterations);
    assert!((found.inputs[0].1 - expected).abs() < 1e-9 * expected);
    assert_eq!(sim.input("tau").unwrap(), found.inputs[0].1);
    // A free inertia under a torque accelerates for ever.
    let mut model = Model::new("free");
    model.add("tau", "Input");
    model.add("motor", "RotationalComponents.Torque");
    model.add("inertia", "RotationalComponents.Inertia").set("J", 2.0);
    model.connect(["tau.y", "motor.tau"]);
    model.connect(["motor.spline", "inertia.spline_a"]);
    let mechanism = model.assemble().unwrap();
    let mut sim = Simulator::new(&mechanism, &options()).unwrap();
    sim.set_input("tau", 1.0).unwrap();
    let e = sim.steady_state(&SteadyStateOptions::default()).unwrap_err().to_string();
    println!("{e}");
    assert!(e.contains("no steady state") && e.contains("der(inertia.w) = 5.000e-1"), "{e}");
}

#[test]
fn bad_requests_name_their_cause() {
    let mechanism = damped_pendulum(0.0, 0.1).assemble().unwrap();
    let sim = Simulator::new(&mechanism, &options()).unwrap();
    let with = |inputs: &[&str], outputs: &[&str], derivatives| LinearizeOptions {
        inputs: Some(inputs.iter().map(|s| s.to_string()).collect()),
        outputs: Some(outputs.iter().map(|s| s.to_string()).collect()),
        derivatives,
    };
    let e = sim.linearize(&with(&["tao"], &[], Derivatives::Auto)).unwrap_err();
    assert!(matches!(e, LinearizeError::UnknownInput { .. }));
    assert!(e.to_string().contains("did you mean `tau`"), "{e}");
    let e = sim.linearize(&with(&[], &["rev.ph"], Derivatives::Auto)).unwrap_err().to_string();
    assert!(e.contains("no variable `rev.ph`") && e.contains("rev.phi"), "{e}");
    // A loop has no exact derivatives (yet): asking for them says why.
    let mechanism = four_bar::four_bar_linkage("four_bar", 1.0).assemble().unwrap();
    let sim = Simulator::new(&mechanism, &options()).unwrap();
    let e = sim.linearize(&with(&[], &[], Derivatives::Exact)).unwrap_err().to_string();
    assert!(e.contains("exact derivatives do not apply"), "{e}");
}

/// A parallelogram four-bar (crank and rocker 1 m, coupler and ground
/// 2 m) with its crank turned to lie along the ground: every bar on one
/// line, where the loop's constraints lose rank and the crank's angle no
/// longer fixes the others. (Assembly cannot start there: the state is set
/// after it.)
#[test]
fn a_loop_at_its_change_point_is_refused_with_the_reason() {
    use std::f64::consts::FRAC_PI_2;
    let mut model = Model::new("parallelogram");
    model.add("world", "World").set("g", 0.0);
    model.add("ground", "FixedTranslation").set("r", [2.0, 0.0, 0.0]);
    model.add("j1", "Revolute").initial("phi", 1.0).initial("w", 0.0);
    for j in ["j2", "j3", "j4"] {
        model.add(j, "Revolute");
    }
    for (name, r) in [("crank", [0.0, 1.0, 0.0]), ("coupler", [2.0, 0.0, 0.0]), ("rocker", [0.0, 1.0, 0.0])] {
        model.add(name, "BodyShape").set("m", 1.0).set("r", r);
    }
    for (a, b) in [
        ("world.frame_b", "j1.frame_a"),
        ("world.frame_b", "ground.frame_a"),
        ("j1.frame_b", "crank.frame_a"),
        ("crank.frame_b", "j2.frame_a"),
        ("j2.frame_b", "coupler.frame_a"),
        ("coupler.frame_b", "j3.frame_a"),
        ("ground.frame_b", "j4.frame_a"),
        ("j4.frame_b", "rocker.frame_a"),
        ("rocker.frame_b", "j3.frame_b"),
    ] {
        model.connect([a, b]);
    }
    let mechanism = model.assemble().unwrap();
    let mut sim = Simulator::new(&mechanism, &options()).unwrap();
    assert!(sim.linearize(&LinearizeOptions::default()).is_ok(), "a regular point linearizes");
    // Crank along -x, coupler along +x, rocker along -x: all on the x axis.
    let place = |name: &str| match name {
        "j1.phi" | "j3.phi" | "j4.phi" => FRAC_PI_2,
        "j2.phi" => -FRAC_PI_2,
        _ => 0.0,
    };
    let y: Vec<f64> = sim.state_names().iter().map(|n| place(n)).collect();
    sim.set_state(&y).unwrap();
    let e = sim.linearize(&LinearizeOptions::default()).unwrap_err();
    println!("{e}");
    assert!(matches!(e, LinearizeError::SingularLoop { .. }), "{e}");
    assert!(e.to_string().contains("singular configuration of a loop"), "{e}");
}

/// The benchmark chain of `n` links with a stiff spring-damper on every
/// joint: a stiff tree, for the implicit method.
fn stiff_chain(n: usize) -> Model {
    let mut model = Model::new("stiff_chain");
    model.add("world", "World");
    let mut previous = "world.frame_b".to_string();
    for k in 0..n {
        let axis = if k % 2 == 0 { [0.0, 0.0, 1.0] } else { [0.0, 1.0, 0.0] };
        model
            .add(format!("j{k}"), "Revolute")
            .set("n", axis)
            .set("axisflange", true)
            .initial("phi", 0.1 * (k + 1) as f64);
        model.add(format!("b{k}"), "Body").set("m", 1.0).set("r_cm", [0.5, 0.0, 0.0]);
        model.add(format!("s{k}"), "RotationalComponents.SpringDamper").set("c", 1e4).set("d", 5.0);
        model.connect([previous.clone(), format!("j{k}.frame_a")]);
        model.connect([format!("j{k}.frame_b"), format!("b{k}.frame_a")]);
        model.connect([format!("s{k}.spline_a"), format!("j{k}.support")]);
        model.connect([format!("s{k}.spline_b"), format!("j{k}.axis")]);
        model.add(format!("l{k}"), "FixedTranslation").set("r", [1.0, 0.0, 0.0]);
        model.connect([format!("j{k}.frame_b"), format!("l{k}.frame_a")]);
        previous = format!("l{k}.frame_b");
    }
    model
}

/// Rodas4 takes the tree's analytic Jacobian (rigid-body part exact, the
/// springs' and dampers' part by differences) instead of differences of
/// the whole right-hand side: the Jacobian agrees with central differences
/// of the right-hand side, and the run with the explicit method's.
#[test]
fn rodas_uses_the_analytic_jacobian_of_a_tree() {
    let n = 6;
    let mechanism = stiff_chain(n).assemble().unwrap();
    let system = mechanism.system();
    let mut work = system.state_jacobian_work().expect("a tree of revolutes has it");
    let mut ws = mechanism.workspace();
    let mut y = mechanism.states().start.clone();
    for (k, x) in y.iter_mut().enumerate().skip(n) {
        *x = 0.3 * (k as f64 - 7.5);
    }
    let dim = y.len();
    let mut jac = vec![0.0; dim * dim];
    system.state_jacobian(&mut ws, &mut work, 0.0, &y, &mut jac).unwrap();
    let (mut plus, mut minus) = (vec![0.0; dim], vec![0.0; dim]);
    let mut worst: f64 = 0.0;
    let largest = jac.iter().fold(0.0f64, |a, x| a.max(x.abs()));
    for j in 0..dim {
        let h = 1e-5;
        let mut yp = y.clone();
        yp[j] += h;
        mechanism.rhs(&mut ws, 0.0, &yp, &mut plus).unwrap();
        yp[j] -= 2.0 * h;
        mechanism.rhs(&mut ws, 0.0, &yp, &mut minus).unwrap();
        for i in 0..dim {
            worst = worst.max(((plus[i] - minus[i]) / (2.0 * h) - jac[i * dim + j]).abs() / largest);
        }
    }
    println!("stiff chain: analytic Jacobian vs central differences {worst:.2e} of the largest entry (tolerance 1e-7)");
    assert!(worst < 1e-7);
    let options = |method| SimulationOptions {
        stop: 0.5,
        saveat: 0.05,
        abstol: 1e-9,
        reltol: 1e-9,
        method,
        ..Default::default()
    };
    let implicit = mechanism.simulate(&options(multibody::Method::Rodas4)).unwrap();
    let explicit = mechanism.simulate(&options(multibody::Method::DormandPrince45)).unwrap();
    let mut far: f64 = 0.0;
    for k in 0..n {
        let name = format!("j{k}.phi");
        far = far.max((implicit.last(&name).unwrap() - explicit.last(&name).unwrap()).abs());
    }
    println!(
        "stiff chain: Rodas4 with the analytic Jacobian vs Dormand-Prince at 1e-9: {far:.2e} rad (tolerance 1e-6)"
    );
    assert!(far < 1e-6);
}
