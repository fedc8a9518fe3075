//! Components written as the libraries write theirs: `der` of expressions
//! of connector positions (index reduction), inputs of sub-components set
//! by equations. Each is checked against a closed form or against the
//! built-in component it repeats, and prints its worst error as a fraction
//! of its tolerance.

mod common;

use common::{error_of, example, report, simulate, worst_against, worst_difference};
use multibody_dyad::Package;
use multibody_reference::{pendulum_period, rk4};

/// A rotational spring-damper as the library writes its own: `w_rel` is
/// `der` of the stretch (the component's relations, without `end`).
const LIBRARY_FORM_SPRING: &str = r#"component TorsionSpringDamper
  parameter c::Real
  parameter d::Real
  spline_a = Spline()
  spline_b = Spline()
  variable phi_rel::Angle
  variable w_rel::AngularVelocity
  variable tau::Torque
relations
  phi_rel = spline_b.phi - spline_a.phi
  w_rel = der(phi_rel)
  tau = c * phi_rel + d * w_rel
  spline_b.tau = tau
  spline_a.tau = -tau
"#;

/// A rotational spring-damper in the library's form, `w_rel = der(phi_rel)`,
/// between two inertias, beside the built-in one: the same motion.
#[test]
fn a_rotational_spring_damper_in_the_library_form_equals_the_built_in_one() {
    let solution = simulate(&format!(
        r#"
{LIBRARY_FORM_SPRING}end

example component Shafts
  written = TorsionSpringDamper(c = 300, d = 2)
  library = RotationalComponents.SpringDamper(c = 300, d = 2)
  a1 = RotationalComponents.Inertia(J = 0.5, phi(initial = 0), w(initial = 4))
  b1 = RotationalComponents.Inertia(J = 1.5, phi(initial = 0.2), w(initial = 0))
  a2 = RotationalComponents.Inertia(J = 0.5, phi(initial = 0), w(initial = 4))
  b2 = RotationalComponents.Inertia(J = 1.5, phi(initial = 0.2), w(initial = 0))
relations
  connect(a1.spline_b, written.spline_a)
  connect(written.spline_b, b1.spline_a)
  connect(a2.spline_b, library.spline_a)
  connect(library.spline_b, b2.spline_a)
end

analysis ShaftsRun
  extends TransientAnalysis(stop = 2, saveat = 0.01, abstol = 1e-10, reltol = 1e-10)
  model = Shafts()
end
"#
    ));
    let mut worst = 0.0f64;
    for (x, y) in [("a1.phi", "a2.phi"), ("a1.w", "a2.w"), ("b1.phi", "b2.phi"), ("b1.w", "b2.w")] {
        worst = worst.max(worst_difference(solution.get(x).unwrap(), solution.get(y).unwrap()));
    }
    report("rotational spring-damper, written vs built-in", worst, 1e-10);
    // The written element's own variables: its stretch and rate.
    let (phi_rel, w_rel) = (solution.get("written.phi_rel").unwrap(), solution.get("written.w_rel").unwrap());
    let (b, a) = (solution.get("b1.phi").unwrap(), solution.get("a1.phi").unwrap());
    let stretch: Vec<f64> = b.iter().zip(a).map(|(b, a)| b - a).collect();
    report("phi_rel = b.phi - a.phi", worst_difference(phi_rel, &stretch), 1e-12);
    let (wb, wa) = (solution.get("b1.w").unwrap(), solution.get("a1.w").unwrap());
    let rate: Vec<f64> = wb.iter().zip(wa).map(|(b, a)| b - a).collect();
    report("w_rel = b.w - a.w", worst_difference(w_rel, &rate), 1e-12);
}

/// A damper between two frames, `f = d der(length)` with the length an
/// expression of the frames' positions, beside the built-in line damper.
#[test]
fn a_line_damper_with_der_of_a_distance_equals_the_built_in_damper() {
    let solution = simulate(
        r#"
component LineDamper
  parameter d::Real
  frame_a = Frame3D()
  frame_b = Frame3D()
  variable length::Length
  variable rate::Velocity
  variable direction::Real[3]
relations
  length = norm(frame_b.r_0 - frame_a.r_0)
  rate = der(length)
  direction = (frame_b.r_0 - frame_a.r_0) / length
  frame_a.f = -resolve2(frame_a.R, d * rate * direction)
  frame_b.f = resolve2(frame_b.R, d * rate * direction)
  frame_a.tau = zeros(3)
  frame_b.tau = zeros(3)
end

component Cart
  rail = MultibodyComponents.Prismatic(n = [1, 0, 0], s(initial = 1.2), v(initial = 2))
  body = MultibodyComponents.Body(m = 1.5, r_cm = [0, 0, 0])
  base = Frame3D()
  tip = Frame3D()
relations
  connect(base, rail.frame_a)
  connect(rail.frame_b, body.frame_a, tip)
end

example component Dampers
  world = MultibodyComponents.World(g = 0)
  anchor = MultibodyComponents.FixedTranslation(r = [0, 0.5, 0])
  written_cart = Cart()
  library_cart = Cart()
  written = LineDamper(d = 0.7)
  library = MultibodyComponents.Damper(d = 0.7)
relations
  connect(world.frame_b, written_cart.base, library_cart.base, anchor.frame_a)
  connect(anchor.frame_b, written.frame_a, library.frame_a)
  connect(written_cart.tip, written.frame_b)
  connect(library_cart.tip, library.frame_b)
end

analysis DampersRun
  extends TransientAnalysis(stop = 3, saveat = 0.01, abstol = 1e-10, reltol = 1e-10)
  model = Dampers()
end
"#,
    );
    let mut worst = 0.0f64;
    for q in ["s", "v"] {
        let (x, y) = (format!("written_cart.rail.{q}"), format!("library_cart.rail.{q}"));
        worst = worst.max(worst_difference(solution.get(&x).unwrap(), solution.get(&y).unwrap()));
    }
    report("line damper, written vs built-in", worst, 1e-10);
    let v = solution.get("written_cart.rail.v").unwrap();
    assert!(v[0] - v[v.len() - 1] > 0.3, "the damper slowed the cart: {} -> {}", v[0], v[v.len() - 1]);
}

/// An input of a sub-component set by an equation of the model: a
/// first-order lag fed `sin(time)`, against its closed form.
#[test]
fn an_input_set_by_an_equation_drives_the_block() {
    let solution = simulate(
        r#"
example component Driven
  smoother = BlockComponents.FirstOrder(T = 0.3, k = 1)
relations
  smoother.u = sin(time)
end

analysis DrivenRun
  extends TransientAnalysis(stop = 3, saveat = 0.01, abstol = 1e-10, reltol = 1e-10)
  model = Driven()
end
"#,
    );
    // T x' = sin t - x, x(0) = 0.
    let tau = 0.3f64;
    let exact = |t: f64| (t.sin() - tau * t.cos() + tau * (-t / tau).exp()) / (1.0 + tau * tau);
    let time = solution.time();
    let x = solution.get("smoother.y").unwrap();
    let worst = time.iter().zip(x).map(|(&t, x)| (x - exact(t)).abs()).fold(0.0, f64::max);
    report("lag driven by an equation", worst, 1e-8);
    let u = solution.get("smoother.u").unwrap();
    report("smoother.u = sin(time)", time.iter().zip(u).map(|(t, u)| (u - t.sin()).abs()).fold(0.0, f64::max), 1e-15);
}

/// An input that nothing connects and no equation sets still reads 0,
/// with its warning.
#[test]
fn an_input_nothing_sets_still_reads_zero_with_a_warning() {
    let text = r#"
example component Idle
  smoother = BlockComponents.FirstOrder(T = 0.3, k = 1, x(initial = 1))
end

analysis IdleRun
  extends TransientAnalysis(stop = 1, saveat = 0.1)
  model = Idle()
end
"#;
    let mut package = Package::new();
    package.add_source("idle.dyad", text.to_string()).unwrap();
    let lowered = package.lower_analysis("IdleRun").unwrap();
    assert!(lowered.warnings.iter().any(|w| w.message.contains("`smoother.u` is not connected")));
    let solution = lowered.assemble().unwrap().simulate(&lowered.options).unwrap();
    let y = solution.get("smoother.y").unwrap();
    // x' = -x / T from 1.
    report("idle lag decays as exp(-t/T)", (y[y.len() - 1] - (-1.0f64 / 0.3).exp()).abs(), 1e-6);
}

/// Index reduction that would need the acceleration of the mechanism (a
/// second derivative of a position) is refused with a message naming the
/// equation.
#[test]
fn a_second_derivative_of_a_position_is_refused_clearly() {
    let message = error_of(
        r#"
component Probe
  flange = Flange()
  variable p::Length
  variable v::Velocity
  variable a::Acceleration
relations
  p = flange.s
  v = der(p)
  a = der(v)
  flange.f = 0
end

example component Probed
  mass = TranslationalComponents.Mass(m = 1, s(initial = 0), v(initial = 1))
  probe = Probe()
relations
  connect(mass.flange_a, probe.flange)
end

analysis ProbedRun
  extends TransientAnalysis(stop = 1, saveat = 0.1)
  model = Probed()
end
"#,
    );
    println!("{message}");
    assert!(message.contains("second derivative") && message.contains("acceleration"), "{message}");
    assert!(message.contains("model.dyad:"), "the message points at the model: {message}");
}

/// A drag force on a frame, `der` of the frame's own position (a model
/// that was refused before): a body falling from rest against linear drag
/// reaches the closed-form speed `-(g m / d) (1 - exp(-d t / m))`.
#[test]
fn a_drag_force_with_der_of_a_frame_position_gives_the_closed_form_fall() {
    let solution = simulate(
        r#"
component Drag
  frame_a = Frame3D()
  parameter d::Real = 0.5
relations
  # The flow is what acts on this component: the body feels its opposite.
  frame_a.f = resolve2(frame_a.R, d * der(frame_a.r_0))
  frame_a.tau = zeros(3)
end

example component Dragged
  world = MultibodyComponents.World()
  body = MultibodyComponents.Body(m = 2, r_cm = [0, 0, 0], orientation_state = OrientationState.Quaternion())
  drag = Drag(d = 0.5)
relations
  connect(body.frame_a, drag.frame_a)
end

analysis DraggedRun
  extends TransientAnalysis(stop = 3, saveat = 0.01, abstol = 1e-10, reltol = 1e-10)
  model = Dragged()
end
"#,
    );
    let (g, m, d) = (9.80665f64, 2.0f64, 0.5f64);
    let exact = |t: f64| -(g * m / d) * (1.0 - (-d * t / m).exp());
    let time = solution.time();
    let v = solution.get("body.v_0[2]").unwrap();
    let worst = time.iter().zip(v).map(|(&t, v)| (v - exact(t)).abs()).fold(0.0, f64::max);
    report("falling body with linear drag", worst, 1e-8);
}

/// A start value on a variable that index reduction computes (a spring's
/// stretch) cannot yet move the mechanism's start: it is reported at the
/// variable, never dropped.
#[test]
fn a_start_value_on_a_computed_stretch_is_reported_not_dropped() {
    let text = example("equations/compliant_element.dyad").replace(
        "written = LinearSpringDamper(c = 40, d = 0.8)",
        "written = LinearSpringDamper(c = 40, d = 0.8, s_rel(initial = 0.2))",
    );
    let message = error_of(&text);
    println!("{message}");
    assert!(message.contains("1 initial equation but 0 states free"), "{message}");
    assert!(message.contains("variable s_rel::Length"), "the message points at the variable: {message}");
}

/// A start value on a variable the equations compute, with the masses'
/// starts left free: the stretch holds at the start (the masses move apart
/// as little as they can), and the masses oscillate about each other as
/// `s_rel = 1.5 cos(w t)`, `w = sqrt(c (1/m_a + 1/m_b))`.
#[test]
fn a_start_stretch_moves_the_free_masses_at_its_ends() {
    let solution = simulate(
        r#"
component Coil
  flange_a = Flange()
  flange_b = Flange()
  parameter c::Real
  variable s_rel::Length
relations
  s_rel = flange_b.s - flange_a.s
  flange_b.f = c * s_rel
  flange_a.f = -c * s_rel
end

example component Pair
  coil = Coil(c = 12, s_rel(initial = 1.5))
  a = TranslationalComponents.Mass(m = 1)
  b = TranslationalComponents.Mass(m = 3)
relations
  connect(a.flange_b, coil.flange_a)
  connect(coil.flange_b, b.flange_a)
end

analysis PairRun
  extends TransientAnalysis(stop = 3, saveat = 0.01, abstol = 1e-10, reltol = 1e-10)
  model = Pair()
end
"#,
    );
    let w = (12.0f64 * (1.0 + 1.0 / 3.0)).sqrt();
    let worst = worst_against(&solution, "coil.s_rel", |t| 1.5 * (w * t).cos());
    report("a start stretch on two free masses, s_rel = 1.5 cos(w t)", worst, 1e-6);
    // Least change: the masses' starts move by opposite amounts.
    let (a, b) = (solution.get("a.s").unwrap()[0], solution.get("b.s").unwrap()[0]);
    report("the masses start symmetric about 0", (a + b).abs(), 1e-9);
}

/// A library spring's stretch given at the start, with both ends' start
/// values fixed otherwise: no free start value can meet it, and the message
/// says where, what it reaches, and which start values held.
#[test]
fn a_start_stretch_the_fixed_starts_cannot_meet_is_named_at_its_place() {
    let message = error_of(
        "example component Pinned
  wall = TranslationalComponents.Fixed()
  spring = TranslationalComponents.Spring(c = 40, s_rel(initial = 0.8))
  block = TranslationalComponents.Mass(m = 1, s(initial = 0.25), v(initial = 0))
relations
  connect(wall.flange, spring.flange_a)
  connect(spring.flange_b, block.flange_a)
end
analysis Run
  extends TransientAnalysis(stop = 1)
  model = Pinned()
end",
    );
    println!("{message}");
    for expected in ["`spring.s_rel` cannot start at 0.8", "starts at 0.25 at best", "`block.s`", "s_rel(initial"] {
        assert!(message.contains(expected), "`{expected}` missing from: {message}");
    }
}

/// A parameter with a guess and no value is decided by the initialization
/// (Modelica's `fixed = false` parameter): the spring constant that holds a
/// pushed mass at rest at its start position, `c = F / s0`.
#[test]
fn a_parameter_with_only_a_guess_is_found_by_the_initialization() {
    let solution = simulate(
        r#"
example component Held
  parameter m::Real = 2
  parameter F::Real = 3
  parameter c::Real(guess = 1)
  variable s::Length = initial 0.2
  variable v::Velocity = initial 0
relations
  der(s) = v
  m * der(v) = F - c * s
  initial der(v) = 0
end

analysis HeldRun
  extends TransientAnalysis(stop = 2, saveat = 0.1)
  model = Held()
end
"#,
    );
    let c = solution.get("c").unwrap();
    report("c = F / s0", (c[0] - 3.0 / 0.2).abs(), 1e-9);
    let s = solution.get("s").unwrap();
    report("the mass stays at rest", s.iter().map(|s| (s - 0.2).abs()).fold(0.0, f64::max), 1e-9);
}

/// Nodes without mass whose balance has no closed form here are refused,
/// each naming the element and the node: a contact law there, forces alone
/// with nothing to hold the node, and two such nodes side by side.
#[test]
fn massless_nodes_the_balance_cannot_hold_are_refused() {
    let chain = |parts: &str, connections: &str| {
        format!(
            "example component Chain
  wall = TranslationalComponents.Fixed()
  block = TranslationalComponents.Mass(m = 1, s(initial = 0), v(initial = 0))
  node = TranslationalComponents.Mass(m = 0)
{parts}
relations
{connections}
end
analysis Run
  extends TransientAnalysis(stop = 1)
  model = Chain()
end"
        )
    };
    let cases = [
        (
            chain(
                "  gap = TranslationalComponents.ElastoGap(c = 100, d = 1)\n  spring = TranslationalComponents.Spring(c = 10)",
                "  connect(wall.flange, gap.flange_a)\n  connect(gap.flange_b, node.flange_a)\n  connect(node.flange_b, spring.flange_a)\n  connect(spring.flange_b, block.flange_a)",
            ),
            "`gap`: a contact (gap or backlash) at the node without mass of `node`",
        ),
        (
            chain(
                "  push = TranslationalComponents.Force()\n  k = BlockComponents.Constant(k = 1)\n  rod = TranslationalComponents.Rod(L = 0)",
                "  connect(k.y, push.f)\n  connect(wall.flange, push.support)\n  connect(push.flange, node.flange_a)\n  connect(block.flange_a, wall.flange)",
            ),
            "`node`: a node without mass with no spring or damper on it",
        ),
        (
            chain(
                "  s1 = TranslationalComponents.Spring(c = 10)\n  s2 = TranslationalComponents.Spring(c = 10)\n  s3 = TranslationalComponents.Spring(c = 10)\n  other = TranslationalComponents.Mass(m = 0)",
                "  connect(wall.flange, s1.flange_a)\n  connect(s1.flange_b, node.flange_a)\n  connect(node.flange_b, s2.flange_a)\n  connect(s2.flange_b, other.flange_a)\n  connect(other.flange_b, s3.flange_a)\n  connect(s3.flange_b, block.flange_a)",
            ),
            "`s2`: an element from another node without mass",
        ),
    ];
    for (text, expected) in cases {
        let message = error_of(&text);
        println!("{message}");
        assert!(message.contains(expected), "`{expected}` missing from: {message}");
    }
    // Between springs alone the balance decides the node's position: a
    // start value there cannot hold, and says so at its place.
    let text = example("equations/massless_library_parts.dyad").replace(
        "joint = RotationalComponents.Inertia(J = 0)",
        "joint = RotationalComponents.Inertia(J = 0, phi(initial = 0.3))",
    );
    let message = error_of(&text);
    println!("{message}");
    assert!(message.contains("`joint.phi` is not a state here: it sits at a node without mass"), "{message}");
    assert!(message.contains("phi(initial = 0.3)"), "{message}");
}

/// The library's partial components extended as Dyad's own files extend
/// them: a torque source on `PartialTorque` (its support held by a Fixed)
/// spins an inertia up, `phi = tau t² / 2J`, with the angles of the start
/// in degrees through `deg2rad`; a spring on `PartialCompliant` between a
/// wall and a mass oscillates as `s = s0 cos(sqrt(c/m) t)`.
#[test]
fn the_library_partial_components_can_be_extended() {
    let solution = simulate(
        r#"
component Push
  extends RotationalComponents.Interfaces.PartialTorque()
  tau = RealInput()
relations
  spline.tau = -tau
end

component Coil
  extends TranslationalComponents.PartialCompliant()
  parameter c::Real
relations
  f = c * s_rel
end

example component Spin
  parameter start_angle::Real = deg2rad(90)
  parameter angles::Real[2] = deg2rad([30, -45])
  push = Push()
  level = BlockComponents.Constant(k = 3)
  ground = RotationalComponents.Fixed()
  wheel = RotationalComponents.Inertia(J = 2, phi(initial = start_angle), w(initial = 0))
  coil = Coil(c = 50)
  wall = TranslationalComponents.Fixed()
  block = TranslationalComponents.Mass(m = 2, s(initial = 0.3), v(initial = 0))
  variable degrees::Real
relations
  connect(level.y, push.tau)
  connect(push.support, ground.spline)
  connect(push.spline, wheel.spline_a)
  connect(wall.flange, coil.flange_a)
  connect(coil.flange_b, block.flange_a)
  degrees = rad2deg(wheel.phi) + 0 * angles[1]
end

analysis SpinRun
  extends TransientAnalysis(stop = 2, saveat = 0.01, abstol = 1e-10, reltol = 1e-10)
  model = Spin()
end
"#,
    );
    let phi = solution.get("wheel.phi").unwrap();
    let worst = worst_against(&solution, "wheel.phi", |t| std::f64::consts::FRAC_PI_2 + 3.0 * t * t / 4.0);
    report("a torque source on PartialTorque, phi = pi/2 + tau t^2 / 2J", worst, 1e-8);
    let degrees = solution.get("degrees").unwrap();
    let worst = degrees.iter().zip(phi).map(|(d, p)| (d - p.to_degrees()).abs()).fold(0.0, f64::max);
    report("rad2deg of an angle", worst, 1e-10);
    let w = (50.0f64 / 2.0).sqrt();
    let worst = worst_against(&solution, "block.s", |t| 0.3 * (w * t).cos());
    report("a spring on PartialCompliant, s = s0 cos(w t)", worst, 1e-6);
    // The support takes the opposite of the spline's torque.
    let support = solution.get("push.support.tau").unwrap();
    report("the support's reaction", support.iter().map(|x| (x - 3.0).abs()).fold(0.0, f64::max), 1e-12);
}

/// An input of the simulated component that its own equations give is
/// decided by them, not left to the host: a filter fed `u = sin(t)` at the
/// top level follows the driven first-order lag's closed form.
#[test]
fn a_top_level_input_given_by_an_equation_is_not_a_host_input() {
    let solution = simulate(
        r#"
example component Fed
  u = RealInput()
  lag = BlockComponents.FirstOrder(T = 0.5, k = 1)
relations
  u = sin(time)
  connect(u, lag.u)
end

analysis FedRun
  extends TransientAnalysis(stop = 4, saveat = 0.01, abstol = 1e-10, reltol = 1e-10)
  model = Fed()
end
"#,
    );
    // T y' + y = sin t, y(0) = 0.
    let t_c: f64 = 0.5;
    let exact = |t: f64| (t.sin() - t_c * t.cos() + t_c * (-t / t_c).exp()) / (1.0 + t_c * t_c);
    let worst = worst_against(&solution, "lag.y", exact);
    report("a top-level input given by an equation", worst, 1e-7);
}

/// `initial der(w_rel) = 0` of a spring-damper written in the library's
/// form (`w_rel = der(phi_rel)`, which makes `w_rel` no state) starts the
/// two inertias with equal accelerations: with 3 N.m on the second, both
/// at 3 / (0.5 + 1.5) = 1.5 rad/s2, the spring holding the first, so
/// `0.5 * 1.5 = 300 phi_rel + 2 * (0 - 4)`.
#[test]
fn a_library_form_spring_starts_with_no_relative_acceleration() {
    let solution = simulate(&format!(
        r#"
{LIBRARY_FORM_SPRING}  initial der(w_rel) = 0
end

example component Shafts
  written = TorsionSpringDamper(c = 300, d = 2)
  a1 = RotationalComponents.Inertia(J = 0.5, phi(initial = 0), w(initial = 4))
  b1 = RotationalComponents.Inertia(J = 1.5, phi(guess = 0.2), w(initial = 0))
  torque = RotationalComponents.ConstantTorque(tau_constant = 3)
relations
  connect(a1.spline_b, written.spline_a)
  connect(written.spline_b, b1.spline_a)
  connect(torque.spline, b1.spline_b)
end

analysis ShaftsRun
  extends TransientAnalysis(stop = 0.1, saveat = 0.01, abstol = 1e-10, reltol = 1e-10)
  model = Shafts()
end
"#
    ));
    let first = |name: &str| solution.get(name).unwrap()[0];
    let worst = (first("a1.a") - 1.5).abs().max((first("b1.a") - 1.5).abs());
    report("library-form spring, start accelerations against 1.5 rad/s2", worst, 1e-9);
    report("library-form spring, start stretch against 8.75 / 300", (first("b1.phi") - 8.75 / 300.0).abs(), 1e-9);
}

/// A two-link arm in the vertical plane whose hand is led around a circle
/// by equations on its frame, with the motor torques unknown: index 3
/// (the torques act on the hand only through its acceleration). The
/// angles must be the closed-form inverse kinematics and the torques the
/// closed-form inverse dynamics of two rods (mass 1 at mid-length,
/// inertia 0.001 about z) under gravity.
#[test]
fn a_hand_led_around_a_circle_by_unknown_torques_follows_inverse_kinematics_and_dynamics() {
    let solution = simulate(&prescribed_hand("stop = 2, saveat = 0.01, abstol = 1e-10, reltol = 1e-10"));
    let (l, lc, m, inertia, g) = (1.0, 0.5, 1.0, 0.001, 9.80665);
    let (cx, radius) = (1.2, 0.2);
    let (mut worst_angle, mut worst_torque, mut worst_force) = (0.0f64, 0.0f64, 0.0f64);
    for (k, &t) in solution.time().iter().enumerate() {
        // The hand's path and its two derivatives.
        let (s, c) = (t.sin(), t.cos());
        let p = [cx + radius * c, radius * s];
        let pd = [-radius * s, radius * c];
        let pdd = [-radius * c, -radius * s];
        // Inverse kinematics, elbow below the line to the hand (q2 < 0).
        let c2 = (p[0] * p[0] + p[1] * p[1] - 2.0 * l * l) / (2.0 * l * l);
        let q2 = -c2.acos();
        let q1 = p[1].atan2(p[0]) - (l * q2.sin()).atan2(l + l * q2.cos());
        // Joint rates and accelerations through the hand's Jacobian.
        let (s1, c1, s12, c12) = (q1.sin(), q1.cos(), (q1 + q2).sin(), (q1 + q2).cos());
        let jac = [[-l * s1 - l * s12, -l * s12], [l * c1 + l * c12, l * c12]];
        let solve = |b: [f64; 2]| {
            let det = jac[0][0] * jac[1][1] - jac[0][1] * jac[1][0];
            [(b[0] * jac[1][1] - jac[0][1] * b[1]) / det, (jac[0][0] * b[1] - b[0] * jac[1][0]) / det]
        };
        let qd = solve(pd);
        let w12 = qd[0] + qd[1];
        // Jdot qd: the centripetal accelerations of the two links.
        let jdot_qd = [-l * c1 * qd[0] * qd[0] - l * c12 * w12 * w12, -l * s1 * qd[0] * qd[0] - l * s12 * w12 * w12];
        let qdd = solve([pdd[0] - jdot_qd[0], pdd[1] - jdot_qd[1]]);
        // Inverse dynamics of two rods: M qdd + C + G.
        let c2 = q2.cos();
        let h = m * l * lc * q2.sin();
        let m11 = 2.0 * inertia + m * lc * lc + m * (l * l + lc * lc + 2.0 * l * lc * c2);
        let m12 = inertia + m * (lc * lc + l * lc * c2);
        let m22 = inertia + m * lc * lc;
        let tau1 = m11 * qdd[0] + m12 * qdd[1] - h * (2.0 * qd[0] * qd[1] + qd[1] * qd[1])
            + (m * lc + m * l) * g * c1
            + m * lc * g * c12;
        let tau2 = m12 * qdd[0] + m22 * qdd[1] + h * qd[0] * qd[0] + m * lc * g * c12;
        let at = |name: &str| solution.get(name).unwrap_or_else(|| panic!("no column `{name}`"))[k];
        worst_angle = worst_angle.max((at("shoulder.phi") - q1).abs()).max((at("elbow.phi") - q2).abs());
        let scale = tau1.abs().max(tau2.abs());
        worst_torque = worst_torque.max((at("tau1") - tau1).abs() / scale).max((at("tau2") - tau2).abs() / scale);
        // The motors hold the hand: no force reaches it from outside.
        worst_force = (1..=3).fold(worst_force, |w, i| w.max(at(&format!("lower.frame_b.f[{i}]")).abs()));
    }
    report("prescribed hand: angles against inverse kinematics (rad)", worst_angle, 1e-6);
    report("prescribed hand: torques against inverse dynamics (relative)", worst_torque, 1e-6);
    report("prescribed hand: force at the hand (N)", worst_force, 1e-9);
}

/// With only the hand's x prescribed, the two unknown torques are one too
/// many: still a problem of higher index, named as one (not "too many
/// equations"), with the equation and the unknowns.
#[test]
fn a_hand_prescribed_along_one_axis_with_two_unknown_torques_is_named_an_index_problem() {
    let text = prescribed_hand("stop = 1").replace("  frame_a.r_0[2] = radius * sin(time)\n", "");
    let message = error_of(&text);
    println!("{message}");
    assert!(!message.contains("too many equations"), "{message}");
    for expected in
        ["higher index", "hand.frame_a.r_0[1]", "`tau1`, `tau2`", "frame_a.r_0[1] = 1.2 + radius * cos(time)"]
    {
        assert!(message.contains(expected), "`{expected}` missing from: {message}");
    }
}

/// An effort that a signal block also reads would be read before the
/// motion decides it: refused, naming the input.
#[test]
fn an_effort_read_by_a_block_is_refused_with_its_name() {
    let text = prescribed_hand("stop = 1")
        .replace("  variable tau1::Real\n", "  gain = BlockComponents.Gain(k = 2)\n  variable tau1::Real\n")
        .replace("  motor2.tau = tau2\n", "  motor2.tau = tau2\n  connect(motor1.tau, gain.u)\n");
    let message = error_of(&text);
    for expected in ["`lower.frame_b`", "`motor1.tau` is read by a signal block", "1-D sources"] {
        assert!(message.contains(expected), "`{expected}` missing from: {message}");
    }
}

/// The prescribed hand with its analysis options.
fn prescribed_hand(options: &str) -> String {
    format!(
        r#"
component Hand
  frame_a = Frame3D()
  parameter radius::Real = 0.2
relations
  frame_a.r_0[1] = 1.2 + radius * cos(time)
  frame_a.r_0[2] = radius * sin(time)
end

example component PrescribedHand
  world = MultibodyComponents.World()
  shoulder = MultibodyComponents.Revolute(n = [0, 0, 1], phi(guess = 0.3))
  upper = MultibodyComponents.BodyShape(r = [1, 0, 0], m = 1)
  elbow = MultibodyComponents.Revolute(n = [0, 0, 1], phi(guess = -0.6))
  lower = MultibodyComponents.BodyShape(r = [1, 0, 0], m = 1)
  hand = Hand()
  motor1 = RotationalComponents.Torque()
  motor2 = RotationalComponents.Torque()
  variable tau1::Real
  variable tau2::Real
relations
  connect(world.frame_b, shoulder.frame_a)
  connect(shoulder.frame_b, upper.frame_a)
  connect(upper.frame_b, elbow.frame_a)
  connect(elbow.frame_b, lower.frame_a)
  connect(lower.frame_b, hand.frame_a)
  connect(motor1.spline, shoulder.axis)
  connect(motor1.support, shoulder.support)
  connect(motor2.spline, elbow.axis)
  connect(motor2.support, elbow.support)
  motor1.tau = tau1
  motor2.tau = tau2
end

analysis Run
  extends TransientAnalysis({options})
  model = PrescribedHand()
end"#
    )
}

/// An initial equation a component writes on its own connector
/// (`initial flange.phi = phi_start`) moves the start of the inertia it is
/// connected to.
#[test]
fn an_initial_equation_on_a_components_connector_sets_the_start() {
    let solution = simulate(
        r#"
component Starter
  flange = Spline()
  parameter phi_start::Real = 0.4
relations
  initial flange.phi = phi_start
  flange.tau = 0
end

example component Started
  inertia = RotationalComponents.Inertia(J = 1, w(initial = 2))
  starter = Starter()
relations
  connect(starter.flange, inertia.spline_a)
end

analysis StartedRun
  extends TransientAnalysis(stop = 1, saveat = 0.1, abstol = 1e-10, reltol = 1e-10)
  model = Started()
end
"#,
    );
    let worst = worst_against(&solution, "inertia.phi", |t| 0.4 + 2.0 * t);
    report("initial flange.phi inside a component: phi = 0.4 + 2 t", worst, 1e-9);
}

/// A pendulum (1 kg at 0.5 m) on a revolute about z whose torsion spring
/// (constant `c`) acts between the support and the axis, started at rest
/// with no acceleration: `declaration` is added to the model, `start`
/// modifies the joint's angle.
fn pendulum_on_a_spring(declaration: &str, start: &str, c: &str) -> String {
    format!(
        r#"
example component RestStart
  {declaration}
  world = MultibodyComponents.World()
  j = MultibodyComponents.Revolute(n = [0, 0, 1], {start}, w(initial = 0))
  body = MultibodyComponents.Body(m = 1, r_cm = [0.5, 0, 0])
  spring = RotationalComponents.Spring(c = {c})
relations
  connect(world.frame_b, j.frame_a)
  connect(j.frame_b, body.frame_a)
  connect(j.support, spring.spline_a)
  connect(spring.spline_b, j.axis)
  initial der(j.w) = 0
end

analysis RestStartRun
  extends TransientAnalysis(stop = 2, saveat = 0.1, abstol = 1e-10, reltol = 1e-10)
  model = RestStart()
end
"#
    )
}

/// Start conditions on accelerations: a pendulum on a torsion spring
/// starts at rest in equilibrium (`initial der(j.w) = 0`), where the
/// spring's torque balances gravity's, `c phi = -m g L cos(phi)`; and a
/// component that starts its flange at rest with no acceleration
/// (Modelica's InitializeFlange, `initial der(der(flange.phi)) = 0`) holds a
/// spring-loaded inertia where the torque and the spring balance.
#[test]
fn a_start_at_rest_with_zero_acceleration_finds_the_equilibrium() {
    let solution = simulate(&pendulum_on_a_spring("", "phi(guess = 0.3)", "20"));
    // The root of c phi + m g L cos(phi) = 0 in [-1, 0].
    let phi = rising_root(|phi| 20.0 * phi + 9.80665 * 0.5 * phi.cos(), -1.0, 0.0);
    report("equilibrium angle from initial der(j.w) = 0", worst_against(&solution, "j.phi", |_| phi), 1e-8);

    let solution = simulate(
        r#"
component StartAtRest
  flange = Spline()
relations
  initial der(flange.phi) = 0
  initial der(der(flange.phi)) = 0
  flange.tau = 0
end

example component Loaded
  wall = RotationalComponents.Fixed()
  spring = RotationalComponents.Spring(c = 8)
  wheel = RotationalComponents.Inertia(J = 0.5)
  load = RotationalComponents.ConstantTorque(tau_constant = 2)
  start = StartAtRest()
relations
  connect(wall.spline, spring.spline_a, load.support)
  connect(spring.spline_b, wheel.spline_a, start.flange)
  connect(wheel.spline_b, load.spline)
end

analysis LoadedRun
  extends TransientAnalysis(stop = 1, saveat = 0.1, abstol = 1e-10, reltol = 1e-10)
  model = Loaded()
end
"#,
    );
    // The torque turns the wheel forward until the spring holds it: c phi = tau.
    report(
        "a flange started at rest with no acceleration sits where the torque and the spring balance",
        worst_against(&solution, "wheel.phi", |_| 2.0 / 8.0),
        1e-8,
    );
}

/// A component whose output comes from a block written in Dyad (the PI
/// inside it), connected to a library block, reaches that PI: no warning
/// that it reaches nothing, and the controller acts (a PI on a first-order plant settles at the set
/// point).
#[test]
fn an_output_from_a_block_written_in_dyad_is_connected() {
    let text = r#"
component Controller
  u = RealInput()
  y = RealOutput()
  pi = BlockComponents.PI(k = 2, T = 0.5)
relations
  connect(u, pi.u)
  connect(pi.y, y)
end

example component Loop
  ctrl = Controller()
  gain = BlockComponents.Gain(k = 1)
  variable x::Real = initial 0
relations
  connect(ctrl.y, gain.u)
  ctrl.u = 1 - x
  der(x) = gain.y - x
end

analysis LoopRun
  extends TransientAnalysis(stop = 20, saveat = 0.1)
  model = Loop()
end
"#;
    let mut package = Package::new();
    package.add_source("model.dyad", text.to_string()).unwrap();
    let lowered = package.lower_analysis("LoopRun").unwrap();
    let messages: Vec<&str> = lowered.warnings.iter().map(|w| w.message.as_str()).collect();
    assert!(messages.is_empty(), "{messages:?}");
    let solution = simulate(text);
    let x = solution.get("x").unwrap();
    report("the PI loop settles at the set point", (x.last().unwrap() - 1.0).abs(), 1e-4);
}

/// A parameter with only a guess passed on to a component's parameter
/// (Modelica's InitSpringConstant): the torsion spring of a pendulum gets
/// the spring constant that holds the pendulum at rest at its start angle,
/// `c phi0 = -m g L cos(phi0)`, found by the initialization from `initial
/// der(j.w) = 0`; the built-in spring is replaced by the library's
/// equation form of it, whose `c` follows the parameter.
#[test]
fn a_guess_only_parameter_passed_to_a_spring_is_the_one_that_holds_the_pendulum() {
    let solution = simulate(&pendulum_on_a_spring("parameter c::Real(guess = 1)", "phi(initial = -0.4)", "c"));
    let exact = -9.80665 * 0.5 * (-0.4f64).cos() / -0.4;
    let c = solution.get("c").unwrap();
    report("c = -m g L cos(phi0) / phi0", (c[0] - exact).abs() / exact, 1e-9);
    let spring_c = solution.get("spring.c").unwrap();
    report("the spring's c follows it", spring_c.iter().map(|x| (x - exact).abs()).fold(0.0, f64::max), 1e-9);
    report("the pendulum stays at rest", worst_against(&solution, "j.phi", |_| -0.4), 1e-8);
}

/// A built-in component with no equation form cannot take a parameter
/// the initialization decides: the message says so at the place.
#[test]
fn a_guess_only_parameter_passed_to_a_built_in_without_equations_is_refused_clearly() {
    let message = error_of(
        r#"
example component GuessedMass
  parameter m::Real(guess = 1)
  world = MultibodyComponents.World()
  body = MultibodyComponents.Body(m = m)
relations
  connect(world.frame_b, body.frame_a)
end

analysis GuessedMassRun
  extends TransientAnalysis(stop = 1)
  model = GuessedMass()
end
"#,
    );
    println!("{message}");
    assert!(message.contains("`m` of the built-in `Body` takes a constant"), "{message}");
    assert!(message.contains("body = MultibodyComponents.Body(m = m)"), "{message}");
}

/// An algebraic loop of four unknowns, one of them nonlinear, is torn:
/// three follow in closed form from the fourth, which Newton's method
/// finds from `w^3 + 6 w + 3 sin(t) - 7 = 0` (the loop written out); each
/// saved `w` is that cubic's one real root, found here by bisection.
#[test]
fn a_nonlinear_algebraic_loop_is_solved_through_its_tearing_variable() {
    let solution = simulate(
        r#"
example component Loop
  variable w::Real(guess = 1)
  variable x::Real
  variable y::Real
  variable z::Real
  variable s::Real = initial 0
relations
  x = 2 * w + 1
  y = x + sin(time)
  z = 3 * y
  w ^ 3 + z = 10
  der(s) = w
end

analysis LoopRun
  extends TransientAnalysis(stop = 3, saveat = 0.1, abstol = 1e-10, reltol = 1e-10)
  model = Loop()
end
"#,
    );
    // w^3 + 6 w + 3 sin(t) - 7 rises in w: one real root in [-3, 3].
    let root = |t: f64| rising_root(|w| w * w * w + 6.0 * w + 3.0 * t.sin() - 7.0, -3.0, 3.0);
    report("w is the cubic's root", worst_against(&solution, "w", root), 1e-10);
    report("z follows it", worst_against(&solution, "z", |t| 3.0 * (2.0 * root(t) + 1.0 + t.sin())), 1e-9);
}

/// The root of `f`, rising through zero in `[lo, hi]`, by bisection to
/// rounding: a reference the code under test does not compute.
fn rising_root(f: impl Fn(f64) -> f64, mut lo: f64, mut hi: f64) -> f64 {
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if f(mid) > 0.0 {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    lo
}

/// A pendulum written in Cartesian coordinates, `x^2 + y^2 = L^2` with
/// the rod's pull `lambda` unknown, is an index-3 system: the constraint
/// is differentiated twice and two of the four coordinates stop being
/// states. Reference, computed here: the same pendulum as the angle
/// equation `theta'' = -(g/L) sin(theta)`, integrated by classical
/// Runge-Kutta at 1e-4 s, and the pull `m (g cos(theta) + L theta'^2) / L`;
/// and the period `4 K(sin(theta0/2)) sqrt(L/g)`, K by the
/// arithmetic-geometric mean, after which the bob is back where it started.
#[test]
fn a_pendulum_in_cartesian_coordinates_runs_through_index_reduction_of_order_three() {
    let (m, length, g): (f64, f64, f64) = (1.5, 0.8, 9.81);
    let theta0: f64 = 0.7;
    let period = pendulum_period(length, g, theta0);
    let text = format!(
        r#"
example component CartesianPendulum
  parameter m::Mass = {m}
  parameter L::Length = {length}
  parameter g::Real = {g}
  variable x::Length
  variable y::Length(guess = -0.7)
  variable vx::Velocity
  variable vy::Velocity
  variable lambda::Real
relations
  initial x = L * sin({theta0})
  initial vx = 0
  der(x) = vx
  der(y) = vy
  m * der(vx) = -lambda * x
  m * der(vy) = -lambda * y - m * g
  x^2 + y^2 = L^2
end

analysis CartesianPendulumRun
  extends TransientAnalysis(stop = {period}, saveat = {step}, abstol = 1e-11, reltol = 1e-11)
  model = CartesianPendulum()
end
"#,
        step = period / 200.0
    );
    let solution = simulate(&text);
    // theta'' = -(g/L) sin(theta) from (theta0, 0), by RK4 at about 1e-4 s, on the saved grid.
    let every = ((period / 200.0) / 1e-4).ceil() as usize;
    let angles = rk4(|s| [s[1], -(g / length) * s[0].sin()], [theta0, 0.0], period / 200.0 / every as f64, 201, every);
    let worst = |name: &str, exact: &dyn Fn(&[f64; 2]) -> f64| {
        let column = solution.get(name).unwrap();
        assert_eq!(column.len(), angles.len(), "the saved grid");
        column.iter().zip(&angles).map(|(x, s)| (x - exact(s)).abs()).fold(0.0, f64::max)
    };
    report("x = L sin(theta)", worst("x", &|s| length * s[0].sin()), 1e-9);
    report("y = -L cos(theta)", worst("y", &|s| -length * s[0].cos()), 1e-9);
    report("vx = L cos(theta) theta'", worst("vx", &|s| length * s[0].cos() * s[1]), 1e-8);
    report(
        "lambda = m (g cos(theta) + L theta'^2) / L",
        worst("lambda", &|s| m * (g * s[0].cos() + length * s[1] * s[1]) / length),
        1e-6,
    );
    let x = solution.get("x").unwrap();
    report("back at the start after the elliptic period", (x[x.len() - 1] - length * theta0.sin()).abs(), 1e-9);
    let (xs, ys) = (solution.get("x").unwrap(), solution.get("y").unwrap());
    let drift = xs.iter().zip(ys).map(|(x, y)| (x * x + y * y - length * length).abs()).fold(0.0, f64::max);
    report("the constraint holds", drift, 1e-9);
}

/// `der(der(x))` written directly: the derivative `der(x)` is a state of
/// its own, free at the start unless an initial equation fixes it.
/// Closed form: `x = cos(w t) + (v0 / w) sin(w t)`.
#[test]
fn a_second_derivative_written_directly_is_integrated() {
    let solution = simulate(
        r#"
example component Oscillator
  parameter w::Real = 3
  variable x::Real
relations
  initial x = 1
  initial der(x) = 0.6
  der(der(x)) = -w^2 * x
end

analysis OscillatorRun
  extends TransientAnalysis(stop = 4, saveat = 0.05, abstol = 1e-11, reltol = 1e-11)
  model = Oscillator()
end
"#,
    );
    report(
        "x = cos(3t) + 0.2 sin(3t)",
        worst_against(&solution, "x", |t| (3.0 * t).cos() + 0.2 * (3.0 * t).sin()),
        1e-8,
    );
}

/// A variable's type attributes: `guess` picks the root Newton's method
/// finds (`x^2 = 0.36` from -0.5 and from 0.5), and an attribute variables
/// do not have is refused where it is written.
#[test]
fn a_variables_guess_attribute_is_used_and_unknown_attributes_are_refused() {
    for guess in [-0.5f64, 0.5] {
        let solution = simulate(&format!(
            r#"
example component Root
  variable x::Real(guess = {guess})
relations
  x^2 = 0.36
end

analysis RootRun
  extends TransientAnalysis(stop = 1, saveat = 0.5)
  model = Root()
end
"#
        ));
        report("the root near the guess", worst_against(&solution, "x", |_| 0.6 * guess.signum()), 1e-12);
    }
    let message = error_of(
        r#"
example component Odd
  variable x::Real(start = 3)
relations
  der(x) = -x
end

analysis OddRun
  extends TransientAnalysis(stop = 1)
  model = Odd()
end
"#,
    );
    println!("{message}");
    assert!(message.contains("`start` is not an attribute of a variable"), "{message}");
    assert!(message.contains("model.dyad:3:20"), "{message}");
    assert!(message.contains("initial x = "), "{message}");
}

/// Two Cartesian pendulums hung one from the other: two coupled
/// constraints of index 3 (four coordinates computed, four integrated).
/// Reference, computed here: the double pendulum's Lagrange equations in
/// its two angles, integrated by classical Runge-Kutta at 1e-4 s.
#[test]
fn a_double_pendulum_in_cartesian_coordinates_follows_its_lagrange_equations() {
    let (m1, m2, l1, l2, g): (f64, f64, f64, f64, f64) = (1.0, 0.7, 1.0, 0.6, 9.81);
    let (theta1, theta2): (f64, f64) = (0.5, -0.3);
    let solution = simulate(&format!(
        r#"
example component CartesianDoublePendulum
  parameter m1::Mass = {m1}
  parameter m2::Mass = {m2}
  parameter L1::Length = {l1}
  parameter L2::Length = {l2}
  parameter g::Real = {g}
  variable x1::Length
  variable y1::Length(guess = -0.9)
  variable x2::Length
  variable y2::Length(guess = -1.4)
  variable vx1::Velocity
  variable vy1::Velocity
  variable vx2::Velocity
  variable vy2::Velocity
  variable pull1::Real
  variable pull2::Real
relations
  initial x1 = L1 * sin({theta1})
  initial x2 = L1 * sin({theta1}) + L2 * sin({theta2})
  initial vx1 = 0
  initial vx2 = 0
  der(x1) = vx1
  der(y1) = vy1
  der(x2) = vx2
  der(y2) = vy2
  m1 * der(vx1) = -pull1 * x1 + pull2 * (x2 - x1)
  m1 * der(vy1) = -pull1 * y1 + pull2 * (y2 - y1) - m1 * g
  m2 * der(vx2) = -pull2 * (x2 - x1)
  m2 * der(vy2) = -pull2 * (y2 - y1) - m2 * g
  x1^2 + y1^2 = L1^2
  (x2 - x1)^2 + (y2 - y1)^2 = L2^2
end

analysis CartesianDoublePendulumRun
  extends TransientAnalysis(stop = 2, saveat = 0.02, abstol = 1e-11, reltol = 1e-11)
  model = CartesianDoublePendulum()
end
"#
    ));
    let rates = |s: &[f64; 4]| {
        let [t1, t2, w1, w2] = *s;
        let d = t1 - t2;
        let den = 2.0 * m1 + m2 - m2 * (2.0 * d).cos();
        let a1 = (-g * (2.0 * m1 + m2) * t1.sin()
            - m2 * g * (t1 - 2.0 * t2).sin()
            - 2.0 * d.sin() * m2 * (w2 * w2 * l2 + w1 * w1 * l1 * d.cos()))
            / (l1 * den);
        let a2 = 2.0 * d.sin() * (w1 * w1 * l1 * (m1 + m2) + g * (m1 + m2) * t1.cos() + w2 * w2 * l2 * m2 * d.cos())
            / (l2 * den);
        [w1, w2, a1, a2]
    };
    // The solution's grid: every 0.02 s to 2 s, RK4 at 1e-4 s.
    let angles = rk4(rates, [theta1, theta2, 0.0, 0.0], 1e-4, 101, 200);
    let worst = |name: &str, exact: &dyn Fn(&[f64; 4]) -> f64| {
        let column = solution.get(name).unwrap();
        assert_eq!(column.len(), angles.len(), "the saved grid");
        column.iter().zip(&angles).map(|(x, s)| (x - exact(s)).abs()).fold(0.0, f64::max)
    };
    report("upper bob x1 = L1 sin(theta1)", worst("x1", &|s| l1 * s[0].sin()), 1e-9);
    report("lower bob x2", worst("x2", &|s| l1 * s[0].sin() + l2 * s[1].sin()), 1e-9);
    report("lower bob y2", worst("y2", &|s| -l1 * s[0].cos() - l2 * s[1].cos()), 1e-9);
}

/// The coordinates index reduction computes are chosen once, at the
/// start: a Cartesian pendulum started near the horizontal computes `x`
/// from the rod, which stops fixing `x` at the bottom. The run stops there
/// with a message that says so, keeping what it computed.
#[test]
fn a_state_choice_that_stops_suiting_the_motion_is_named() {
    let text = r#"
example component WideSwing
  variable x::Real
  variable y::Real(guess = -0.31)
  variable vx::Real
  variable vy::Real
  variable pull::Real
relations
  initial x = 0.95
  initial vx = 0
  der(x) = vx
  der(y) = vy
  der(vx) = -pull * x
  der(vy) = -pull * y - 9.81
  x^2 + y^2 = 1
end

analysis WideSwingRun
  extends TransientAnalysis(stop = 2, saveat = 0.01)
  model = WideSwing()
end
"#;
    let (mechanism, options) = common::load("model.dyad", text);
    let failure = mechanism.simulate(&options).expect_err("the choice stops suiting the motion");
    let message = &failure.reason;
    println!("stopped at t = {}: {message}", failure.time);
    assert!(message.contains("no longer determine `x`") && message.contains("chose, at the start"), "{message}");
    // Near the bottom, a quarter of the swing's period; the samples before it are kept.
    assert!(failure.time > 0.4 && failure.time < 0.7, "{}", failure.time);
    assert!(failure.partial.time().len() > 40);
}

/// An initial equation that the mechanism's start must meet inside a
/// closed loop: a filter `0.2 x' = w1 - x` started at rest at `x = 2`
/// needs the crank of a four-bar turning at 2 rad/s, and the loop's other
/// joints must follow. Reference, from the linkage's geometry at the
/// start (O = 0, A = (0, 0.5), B = (2, 1.5), C = (2, 0)): the coupler
/// does not turn and the rocker turns at 2 * 0.5 / 1.5 rad/s.
#[test]
fn an_initial_equation_moves_the_start_of_a_closed_loop_keeping_it_closed() {
    let solution = simulate(
        r#"
example component FourBarStart
  world = MultibodyComponents.World()
  ground = MultibodyComponents.FixedTranslation(r = [2, 0, 0])
  j1 = MultibodyComponents.Revolute(axisflange = true, phi(initial = 0), w(guess = 0))
  j2 = MultibodyComponents.Revolute()
  j3 = MultibodyComponents.Revolute()
  j4 = MultibodyComponents.Revolute()
  crank = MultibodyComponents.BodyShape(m = 1, r = [0, 0.5, 0], I_11 = 0.01, I_22 = 0.01, I_33 = 0.01)
  coupler = MultibodyComponents.BodyShape(m = 1, r = [2, 1, 0], I_11 = 0.01, I_22 = 0.01, I_33 = 0.01)
  rocker = MultibodyComponents.BodyShape(m = 1, r = [0, 1.5, 0], I_11 = 0.01, I_22 = 0.01, I_33 = 0.01)
  variable x::Real = initial 2
relations
  connect(world.frame_b, j1.frame_a, ground.frame_a)
  connect(j1.frame_b, crank.frame_a)
  connect(crank.frame_b, j2.frame_a)
  connect(j2.frame_b, coupler.frame_a)
  connect(coupler.frame_b, j3.frame_a)
  connect(ground.frame_b, j4.frame_a)
  connect(j4.frame_b, rocker.frame_a)
  connect(rocker.frame_b, j3.frame_b)
  0.2 * der(x) = der(j1.axis.phi) - x
  initial der(x) = 0
end

analysis FourBarStartRun
  extends TransientAnalysis(stop = 0.1, saveat = 0.05)
  model = FourBarStart()
end
"#,
    );
    let start = |name: &str| solution.get(name).unwrap()[0];
    report("the crank starts at 2 rad/s", (start("j1.w") - 2.0).abs(), 1e-9);
    report("the coupler does not turn", (start("j2.w") + start("j1.w")).abs(), 1e-9);
    report("the rocker turns at 2/3 rad/s", (start("j4.w") - 2.0 / 3.0).abs(), 1e-9);
    report("the filter starts at rest", (start("x") - 2.0).abs(), 1e-12);
}

/// A library block's outputs named with an index (`q[2]` of a
/// point-to-point block driving two axes) reach a component written in
/// Dyad as they reach the library's own blocks: each axis its own (the
/// second axis used to read the first's). Reference: the synchronized
/// profile from 0 to [1, 3] with unit limits, `s(t) = t^2 / 6` while
/// accelerating (the slower axis sets the pace: its speed limit 1 gives
/// `s' <= 1/3`, its acceleration limit `s'' <= 1/3`).
#[test]
fn indexed_outputs_of_a_library_block_reach_components_written_in_dyad() {
    let solution = simulate(
        r#"
component Twice
  u = RealInput()
  y = RealOutput()
relations
  y = 2 * u
end

example component TwoAxes
  path = BlockComponents.KinematicPTP(nout = 2, q0 = [0, 0], q1 = [1, 3], qd_max = [1, 1], qdd_max = [1, 1])
  first = Twice()
  second = Twice()
relations
  connect(path.q[1], first.u)
  connect(path.q[2], second.u)
end

analysis TwoAxesRun
  extends TransientAnalysis(stop = 1, saveat = 0.1)
  model = TwoAxes()
end
"#,
    );
    report("the first axis's output", worst_against(&solution, "first.y", |t| 2.0 * t * t / 6.0), 1e-12);
    report("the second axis's output", worst_against(&solution, "second.y", |t| 2.0 * 3.0 * t * t / 6.0), 1e-12);
}
