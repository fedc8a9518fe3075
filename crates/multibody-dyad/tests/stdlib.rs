//! The standard library written in Dyad (and the blocks the engine has
//! built in beside it), each against its closed form: responses of the
//! linear blocks to steps and ramps, the limited PID's anti-windup, and
//! the memoryless blocks point by point.
//!
//! Tolerances: responses in time carry the integration error, which runs
//! at abstol = reltol = 1e-10 keep below 1e-8 (we allow 1e-7); pointwise
//! blocks agree to rounding (1e-12).

use multibody::{SimulationOptions, Solution};
use multibody_dyad::Package;

fn run(blocks: &str, connections: &str, stop: f64) -> Solution {
    let text = format!("example component Test\n{blocks}\nrelations\n{connections}\nend\n");
    let mut package = Package::new();
    if let Err(d) = package.add_source("test.dyad", text) {
        panic!("{}", d.render(package.sources(), false));
    }
    let lowered = package.lower_component("Test").unwrap_or_else(|d| panic!("{}", d.render(package.sources(), false)));
    let options = SimulationOptions { stop, saveat: 0.01, abstol: 1e-10, reltol: 1e-10, ..Default::default() };
    lowered.assemble().unwrap_or_else(|d| panic!("{}", d.render(package.sources(), false))).simulate(&options).unwrap()
}

/// Worst |signal - exact(t)|, printed with the tolerance it is held to.
fn check(s: &Solution, name: &str, tolerance: f64, exact: impl Fn(f64) -> f64) {
    let column = s.get(name).unwrap_or_else(|| panic!("no column {name}"));
    let worst = column.iter().zip(s.time()).map(|(y, &t)| (y - exact(t)).abs()).fold(0.0, f64::max);
    if tolerance > 0.0 {
        println!("{name}: worst error {worst:.2e} ({:.3} of {tolerance:e})", worst / tolerance);
    } else {
        println!("{name}: worst error {worst:.2e} (exact required)");
    }
    assert!(worst <= tolerance, "{name}: {worst:e} > {tolerance:e}");
}

#[test]
fn integrator_derivative_and_lags_follow_their_responses() {
    let s = run(
        "  one = BlockComponents.Constant(k = 1)
  ramp = BlockComponents.Ramp(height = 5, duration = 5)
  integrator = BlockComponents.Integrator(k = 2, x0 = 1)
  derivative = BlockComponents.Derivative(k = 3, T = 0.2)
  lag = BlockComponents.FirstOrder(k = 2, T = 0.5)
  second = BlockComponents.SecondOrder(k = 1.5, w = 4, d = 1)
  pi = BlockComponents.PI(k = 2, T = 0.25)",
        "  connect(one.y, integrator.u, lag.u, second.u, pi.u)
  connect(ramp.y, derivative.u)",
        3.0,
    );
    check(&s, "integrator.y", 1e-7, |t| 1.0 + 2.0 * t);
    // u = t: x = t - T (1 - e^(-t/T)), y = k/T (u - x) = k (1 - e^(-t/T)).
    check(&s, "derivative.y", 1e-7, |t| 3.0 * (1.0 - (-t / 0.2).exp()));
    check(&s, "lag.y", 1e-7, |t| 2.0 * (1.0 - (-t / 0.5).exp()));
    check(&s, "second.y", 1e-7, |t| 1.5 * (1.0 - (1.0 + 4.0 * t) * (-4.0 * t).exp()));
    check(&s, "pi.y", 1e-7, |t| 2.0 * (1.0 + t / 0.25));
}

#[test]
fn the_pid_weights_its_parts() {
    // Set point 1, measurement 0: P = wp, I = t / Ti, and with wd = 1 the
    // filtered derivative of the step, D = Nd e^(-t Nd / Td).
    let s = run(
        "  one = BlockComponents.Constant(k = 1)
  zero = BlockComponents.Constant(k = 0)
  pid = BlockComponents.PID(k = 2, Ti = 0.5, Td = 0.1, Nd = 10, wp = 0.8, wd = 1)
  pi_only = BlockComponents.PID(k = 2, Ti = 0.5, with_D = false)",
        "  connect(one.y, pid.u_s, pi_only.u_s)
  connect(zero.y, pid.u_m, pi_only.u_m)",
        1.0,
    );
    check(&s, "pid.y", 1e-7, |t| 2.0 * (0.8 + t / 0.5 + 10.0 * (-t * 100.0).exp()));
    check(&s, "pi_only.y", 1e-7, |t| 2.0 * (1.0 + t / 0.5));
}

#[test]
fn the_limited_pid_holds_its_limit_and_winds_back() {
    // A PI (with_D = false) on a constant error e = 1: v = k (e + xi)
    // reaches y_max at t1; from there xi' = (e + (y_max - v)/(k Ni)) / Ti
    // is linear: xi settles at y_max / k - e + Ni e (anti-windup).
    let (k, ti, ni, y_max, e) = (2.0, 0.5, 0.3, 5.0, 1.0);
    let s = run(
        "  one = BlockComponents.Constant(k = 1)
  zero = BlockComponents.Constant(k = 0)
  pid = BlockComponents.LimPID(k = 2, Ti = 0.5, Ni = 0.3, y_max = 5, with_D = false)",
        "  connect(one.y, pid.u_s)
  connect(zero.y, pid.u_m)",
        4.0,
    );
    let t1 = (y_max / k - e) * ti / e;
    let b = 1.0 / (ni * ti);
    let a = (e + (y_max - k * e) / (k * ni)) / ti;
    let xi = |t: f64| if t <= t1 { e * t / ti } else { a / b + (e * t1 / ti - a / b) * (-b * (t - t1)).exp() };
    // The kink at t1 costs the adaptive steps a little accuracy there.
    check(&s, "pid.xi", 1e-6, xi);
    check(&s, "pid.y", 1e-6, |t| (k * (e + xi(t))).min(y_max));
    assert!((xi(4.0) - (y_max / k - e + ni * e)).abs() < 1e-6);
}

#[test]
fn memoryless_blocks_agree_point_by_point() {
    let s = run(
        "  wave = BlockComponents.Sine(amplitude = 3, frequency = 0.7)
  other = BlockComponents.Constant(k = 4)
  limiter = BlockComponents.Limiter(y_max = 1.5, y_min = -0.5)
  dead = BlockComponents.DeadZone(uMax = 1, uMin = -2)
  absolute = BlockComponents.Math.Abs()
  sign = BlockComponents.Sign()
  root = BlockComponents.Sqrt()
  product = BlockComponents.Product()
  quotient = BlockComponents.Division()
  sum = BlockComponents.Add3(k1 = 1, k2 = -2, k3 = 0.5)",
        "  connect(wave.y, limiter.u, dead.u, absolute.u, sign.u, product.u1, quotient.u1, sum.u1, sum.u3)
  connect(other.y, root.u, product.u2, quotient.u2, sum.u2)",
        2.0,
    );
    let u = |t: f64| 3.0 * (2.0 * std::f64::consts::PI * 0.7 * t).sin();
    check(&s, "limiter.y", 1e-12, |t| u(t).clamp(-0.5, 1.5));
    check(&s, "dead.y", 1e-12, |t| {
        if u(t) > 1.0 {
            u(t) - 1.0
        } else if u(t) < -2.0 {
            u(t) + 2.0
        } else {
            0.0
        }
    });
    check(&s, "absolute.y", 1e-12, |t| u(t).abs());
    check(&s, "sign.y", 0.0, |t| {
        if u(t) > 0.0 {
            1.0
        } else if u(t) < 0.0 {
            -1.0
        } else {
            0.0
        }
    });
    check(&s, "root.y", 1e-12, |_| 2.0);
    check(&s, "product.y", 1e-12, |t| 4.0 * u(t));
    check(&s, "quotient.y", 1e-12, |t| u(t) / 4.0);
    check(&s, "sum.y", 1e-12, |t| 1.5 * u(t) - 8.0);
}

#[test]
fn sources_of_time_follow_their_formulas() {
    let s = run(
        "  cosine = BlockComponents.Cosine(amplitude = 2, frequency = 0.5, phase = 0.3, offset = 1, start_time = 0.2)
  decaying = BlockComponents.ExpSine(amplitude = 1.5, damping = 0.8, frequency = 1, phase = 0.1)
  pulse = BlockComponents.Pulse(amplitude = 3, duty_cycle = 0.25, period = 2, offset = -1, start_time = 0.5)
  square = BlockComponents.Square(amplitude = 2, frequency = 1.5, offset = 0.5)",
        "",
        2.0,
    );
    let tau = std::f64::consts::TAU;
    check(&s, "cosine.y", 1e-12, |t| {
        1.0 + 2.0 * if t >= 0.2 { (tau * 0.5 * (t - 0.2) + 0.3).cos() } else { 0.3f64.cos() }
    });
    check(&s, "decaying.y", 1e-12, |t| 1.5 * (-0.8 * t).exp() * (tau * t + 0.1).sin());
    check(&s, "pulse.y", 0.0, |t| if t > 0.5 && t <= 1.0 { 3.0 } else { -1.0 });
    // High for the first half of each period, low for the second; a
    // sample at a switch holds the value it switches from (the left limit).
    check(&s, "square.y", 0.0, |t| {
        let x = 1.5 * t;
        if t <= 0.0 {
            0.5
        } else if x - (x.ceil() - 1.0) <= 0.5 {
            2.5
        } else {
            -1.5
        }
    });
}

/// A 1 kHz square-wave torque of 1 N.m on an inertia of 0.1 for 1 s: each
/// switch is a time event, so the speed is the exact triangle wave in
/// [0, 0.005] and the angle gains 2.5e-6 per period. Stepping across the
/// switches used to end this run at w = -0.14 with no warning.
#[test]
fn a_fast_square_wave_switches_exactly_where_it_jumps() {
    let s = run(
        "  fixed = RotationalComponents.Fixed()
  wave = BlockComponents.Square(amplitude = 1, frequency = 1000)
  motor = RotationalComponents.Torque()
  disc = RotationalComponents.Inertia(J = 0.1, phi(initial = 0), w(initial = 0))",
        "  connect(wave.y, motor.tau)
  connect(motor.support, fixed.spline)
  connect(motor.spline, disc.spline_a)",
        1.0,
    );
    // Within each period T: up at 10 rad/s2 for T/2, then down.
    let period = 1e-3;
    let speed = move |t: f64| {
        let x = t / period - (t / period).floor();
        10.0 * period * if x < 0.5 { x } else { 1.0 - x }
    };
    check(&s, "disc.w", 1e-11, speed);
    check(&s, "disc.phi", 1e-11, |t| {
        let whole = (t / period).floor();
        let x = t / period - whole;
        let within = if x < 0.5 { x * x / 2.0 } else { 0.25 - (1.0 - x) * (1.0 - x) / 2.0 };
        10.0 * period * period * (whole * 0.25 + within)
    });
}

#[test]
fn relative_sensors_read_the_difference_of_two_flanges() {
    // Two inertias driven apart by opposite constant torques of 1 N.m:
    // phi_b - phi_a = t^2 (J = 1 each), w_b - w_a = 2 t.
    let s = run(
        "  a = RotationalComponents.Inertia(J = 1)
  b = RotationalComponents.Inertia(J = 1)
  push_a = RotationalComponents.ConstantTorque(tau_constant = -1)
  push_b = RotationalComponents.ConstantTorque(tau_constant = 1)
  angle = RotationalComponents.RelAngleSensor()
  speed = RotationalComponents.RelativeVelocitySensor()",
        "  connect(push_a.spline, a.spline_a)
  connect(push_b.spline, b.spline_a)
  connect(a.spline_b, angle.spline_a, speed.spline_a)
  connect(b.spline_b, angle.spline_b, speed.spline_b)",
        1.0,
    );
    check(&s, "angle.phi_rel", 1e-7, |t| t * t);
    check(&s, "speed.w_rel", 1e-7, |t| 2.0 * t);
}

/// BlockComponents.Pulse is the library's single pulse: `amplitude` while
/// `start_time < t <= start_time + duty_cycle * period`, `offset` before
/// and after, once (not a train). Its integral is then
/// `offset t + (amplitude - offset) * overlap(t)`, the pulse's part of
/// `[0, t]`: 0.75 * 0.5 = 0.375 after a pulse of width 0.375 from 0.5 s.
#[test]
fn a_pulse_is_one_pulse_and_its_integral_is_its_area() {
    let s = run(
        "  pulse = BlockComponents.Pulse(amplitude = 2, duty_cycle = 0.25, period = 1.5, offset = -0.5, start_time = 0.5)
  area = BlockComponents.Integrator()",
        "  connect(pulse.y, area.u)",
        4.0,
    );
    let (from, to) = (0.5, 0.5 + 0.25 * 1.5);
    check(&s, "pulse.y", 0.0, |t| if t > from && t <= to { 2.0 } else { -0.5 });
    let overlap = |t: f64| (t.min(to) - from).max(0.0);
    check(&s, "area.y", 1e-9, |t| -0.5 * t + 2.5 * overlap(t));
    // Not periodic: a period later it stays at the offset.
    let y = s.get("pulse.y").unwrap();
    assert!(s.time().iter().zip(y).filter(|(t, _)| **t > to).all(|(_, y)| *y == -0.5));
}

/// The library's Pulse has no default amplitude or duty cycle: a pulse
/// without them is refused, naming the missing one.
#[test]
fn a_pulse_needs_its_amplitude_and_duty_cycle() {
    for (given, missing) in [("duty_cycle = 0.5, period = 1", "amplitude"), ("amplitude = 1, period = 1", "duty_cycle")]
    {
        let text = format!(
            "example component Test\n  pulse = BlockComponents.Pulse({given})\n  area = BlockComponents.Integrator()\nrelations\n  connect(pulse.y, area.u)\nend\n"
        );
        let mut package = Package::new();
        package.add_source("test.dyad", text).unwrap();
        let message = match package.lower_component("Test").and_then(|l| l.assemble()) {
            Ok(_) => panic!("a Pulse({given}) was accepted"),
            Err(d) => d.render(package.sources(), false),
        };
        assert!(message.contains(missing), "{message}");
    }
}

/// A Position source set by a formula of `time` beside an angle sensor on
/// the same axis: the formula is a source of time (not feedback through
/// the sensor), and the axis follows it, `phi = 0.5 t`, `w = 0.5`.
#[test]
fn a_position_source_set_from_time_beside_a_sensor_follows_time() {
    let s = run(
        "  world = World()
  rev = Revolute(n = [0, 0, 1])
  body = Body(m = 1, r_cm = [0.5, 0, 0])
  drive = RotationalComponents.Position(exact = true)
  sensor = RotationalComponents.AngleSensor()",
        "  drive.phi_ref = 0.5 * time
  connect(world.frame_b, rev.frame_a)
  connect(rev.frame_b, body.frame_a)
  connect(drive.spline, rev.axis, sensor.spline)
  connect(drive.support, rev.support)",
        1.0,
    );
    check(&s, "sensor.phi", 1e-12, |t| 0.5 * t);
    check(&s, "rev.w", 1e-12, |_| 0.5);
}
