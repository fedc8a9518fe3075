//! Models with components of their own (examples/equations), run through
//! the `multibody run` command, against closed forms, conservation laws
//! and equivalent models built from library components.
//!
//! Tolerances: closed forms in time carry the integration error of runs
//! at abstol = reltol = 1e-10 (near 1e-9 here; we allow 1e-7); two models
//! of the same mechanism integrate the same equations, so they agree to
//! 1e-10; an algebraic loop is solved to rounding at each instant.

mod common;

use common::{crate_path, multibody, scratch, Table};
use multibody_reference::{pendulum_period, rk4, Signals};

/// Runs `examples/equations/FILE` (its analysis `analysis`, if given) and
/// reads the CSV.
fn run(file: &str, analysis: Option<&str>) -> Table {
    let stem = file.trim_end_matches(".dyad");
    let dir = scratch(&format!("equations-{stem}-{}", analysis.unwrap_or("default")));
    let out = dir.join("out.csv");
    let path = crate_path(&format!("../../examples/equations/{file}"));
    let mut args = vec!["run", path.as_str(), "--out", out.to_str().unwrap()];
    if let Some(a) = analysis {
        args.extend(["--analysis", a]);
    }
    let output = multibody(&dir, &args);
    assert!(output.status.success(), "multibody run {file} failed:\n{}", String::from_utf8_lossy(&output.stderr));
    Table::load(&out)
}

/// The worst `|column - exact(t)|` over the run, printed against its tolerance.
fn check(table: &Table, name: &str, tolerance: f64, exact: impl Fn(f64) -> f64) {
    let time = &table.time;
    let worst = table.column(name).iter().zip(time).map(|(y, &t)| (y - exact(t)).abs()).fold(0.0, f64::max);
    println!("{name}: worst error {worst:.2e} ({:.3} of the tolerance {tolerance:e})", worst / tolerance);
    assert!(worst <= tolerance, "{name}: {worst:e} > {tolerance:e}");
}

#[test]
fn a_pd_controller_component_gives_the_damped_oscillator() {
    let table = run("pd_controller.dyad", None);
    // The table: a solid cylinder of diameter 0.8 m, length 0.05 m and
    // density 500 kg/m3 about its axis: J = m r^2 / 2.
    let (r, length, density) = (0.4, 0.05, 500.0);
    let m = density * std::f64::consts::PI * r * r * length;
    let j = m * r * r / 2.0;
    let (kp, kd, reference) = (20.0, 3.0, 1.0);
    let w0 = (kp / j).sqrt();
    let zeta = kd / (2.0 * (kp * j).sqrt());
    assert!(zeta < 1.0, "the test assumes an underdamped loop");
    let wd = w0 * (1.0 - zeta * zeta).sqrt();
    let phi = |t: f64| reference * (1.0 - (-zeta * w0 * t).exp() * ((wd * t).cos() + zeta * w0 / wd * (wd * t).sin()));
    check(&table, "bearing.phi", 1e-7, phi);
    check(&table, "controller.error", 1e-7, |t| reference - phi(t));
}

#[test]
fn a_first_order_filter_follows_its_analytic_response() {
    let table = run("first_order_filter.dyad", None);
    // T x' = sin(w t) - x, x(0) = 0.
    let (tau, w) = (0.3, std::f64::consts::PI);
    let wt = w * tau;
    check(&table, "smoother.x", 1e-7, |t| {
        ((w * t).sin() - wt * (w * t).cos() + wt * (-t / tau).exp()) / (1.0 + wt * wt)
    });
}

#[test]
fn a_spring_in_equations_moves_like_the_library_spring() {
    let table = run("user_spring.dyad", None);
    let mut worst = 0.0f64;
    for pair in ["left_rail.s", "left_rail.v", "right_rail.s", "right_rail.v"] {
        let (a, b) = (table.column(&format!("library.{pair}")), table.column(&format!("written.{pair}")));
        worst = a.iter().zip(b).map(|(x, y)| (x - y).abs()).fold(worst, f64::max);
    }
    println!("spring in equations vs Spring: worst difference {worst:.2e} (tolerance 1e-10: {:.3})", worst / 1e-10);
    assert!(worst <= 1e-10);
    // They did move: the spring starts stretched by 0.3 m.
    assert!(table.column("library.left_rail.s").iter().any(|s| (s + 0.5).abs() > 0.05));
}

#[test]
fn a_nonlinear_spring_in_equations_conserves_energy() {
    let table = run("nonlinear_spring.dyad", None);
    let (vl, vr, spring) = (table.column("left_rail.v"), table.column("right_rail.v"), table.column("spring.energy"));
    let energy: Vec<f64> = (0..vl.len()).map(|k| 0.5 * vl[k] * vl[k] + 0.5 * 2.0 * vr[k] * vr[k] + spring[k]).collect();
    let drift = energy.iter().map(|e| (e - energy[0]).abs()).fold(0.0, f64::max) / energy[0];
    println!("hardening spring: relative energy drift {drift:.2e} (tolerance 1e-8: {:.3})", drift / 1e-8);
    assert!(energy[0] > 1e-3 && drift <= 1e-8);
}

#[test]
fn an_algebraic_loop_across_two_components_gives_u_over_one_plus_k() {
    let table = run("algebraic_loop.dyad", None);
    let (u, y) = (table.column("input.y"), table.column("subtract.y"));
    let worst = u.iter().zip(y).map(|(u, y)| (y - u / 4.0).abs()).fold(0.0, f64::max);
    println!("algebraic loop: worst |y - u/(1 + k)| = {worst:.2e}");
    assert!(worst <= 1e-12 && u.last().copied() == Some(2.0));
}

/// One algebraic loop of 20,000 equations written with a `for` (issue 26:
/// 5000 such equations hung). x[1] = x[n]/2 + t and x[i] = x[i-1]/2 + 1
/// give x[n] = (2 (1 - a) + a t) / (1 - a/2) with a = 2^(1-n), so
/// x[1] = 1 + t and x[n] = 2 to rounding. Its Jacobian has two entries a
/// row: factored sparse, in time and memory about n (a dense LU needed
/// 3.2 GB and about n^2 work per evaluation here).
#[test]
fn a_long_algebraic_loop_from_a_for_is_solved_to_its_closed_form() {
    let n = 20_000;
    let table = run_text(
        "long-algebraic-loop",
        &format!(
            "example component BigLoop\n  variable x::Real[{n}]\nrelations\n  x[1] = 0.5 * x[{n}] + time\n  \
             for i in 2:{n}\n    x[i] = 0.5 * x[i - 1] + 1\n  end\nend\n"
        ),
    );
    check(&table, "x[1]", 1e-12, |t| 1.0 + t);
    check(&table, &format!("x[{n}]"), 1e-12, |_| 2.0);
}

/// A spring constant with only a guess, passed to the library's torsion
/// spring, is found at the start so that the pendulum rests at -0.4 rad:
/// `c (phi0 - phi_rel0) = -m g L cos(phi0)`.
#[test]
fn a_spring_constant_found_at_the_start_holds_the_pendulum() {
    let table = run("init_spring_constant.dyad", None);
    let (phi0, phi_rel0) = (-0.4f64, 0.1);
    let c = -9.80665 * 0.5 * phi0.cos() / (phi0 - phi_rel0);
    check(&table, "c", 1e-9 * c, |_| c);
    check(&table, "spring.c", 1e-9 * c, |_| c);
    check(&table, "joint.phi", 1e-9, |_| phi0);
}

/// A loop whose Jacobian changes with time, so its pivots are chosen
/// from the pattern when it compiles: t x[1] + x[n] = 1 and
/// x[i] = 2 x[i-1] + 1. At t = 0 the first pivot the pattern suggests,
/// t, is zero, and the pivots are chosen again from the values. The
/// closed form: x[i] + 1 = 2^(i-1) (x[1] + 1), so
/// x[1] = (2 - 2^(n-1)) / (t + 2^(n-1)) and x[n] = 1 - t x[1].
#[test]
fn a_loop_whose_first_pivot_starts_at_zero_is_solved_to_its_closed_form() {
    let n = 40;
    let table = run_text(
        "loop-with-zero-pivot",
        &format!(
            "example component ZeroPivot\n  variable x::Real[{n}]\nrelations\n  time * x[1] + x[{n}] = 1\n  \
             for i in 2:{n}\n    x[i] = 2 * x[i - 1] + 1\n  end\nend\n"
        ),
    );
    let p = 2f64.powi(n - 1);
    let x1 = move |t: f64| (2.0 - p) / (t + p);
    check(&table, "x[1]", 1e-12, x1);
    check(&table, &format!("x[{n}]"), 1e-12, move |t| 1.0 - t * x1(t));
}

/// Runs a model given as text (0.1 s, a sample each 0.05 s) and reads its table.
fn run_text(name: &str, text: &str) -> Table {
    let dir = scratch(name);
    std::fs::create_dir_all(dir.join("models")).unwrap();
    std::fs::write(dir.join("models/model.dyad"), text).unwrap();
    let output =
        multibody(&dir, &["run", "models/model.dyad", "--stop", "0.1", "--saveat", "0.05", "--out", "out.csv"]);
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    Table::load(&dir.join("out.csv"))
}

#[test]
fn a_chain_made_in_a_loop_equals_the_chain_written_out() {
    let array = run("chain.dyad", Some("ChainOfLinksRun"));
    let by_hand = run("chain.dyad", Some("ChainByHandRun"));
    assert_eq!(array.time, by_hand.time);
    for k in 1..=4 {
        for state in ["phi", "w"] {
            let (a, b) = (format!("links[{k}].joint.{state}"), format!("link{k}.joint.{state}"));
            assert_eq!(array.column(&a), by_hand.column(&b), "{a} and {b} differ");
        }
        for i in 1..=3 {
            let (a, b) = (format!("links[{k}].rod.frame_b.r_0[{i}]"), format!("link{k}.rod.frame_b.r_0[{i}]"));
            assert_eq!(array.column(&a), by_hand.column(&b), "{a} and {b} differ");
        }
    }
}

/// The library's own form of a compliant element (`v_rel = der(s_rel)` of
/// flange positions, by index reduction): the damped oscillator's closed
/// form, and the library's SpringDamper beside it.
#[test]
fn a_spring_damper_in_the_library_form_gives_the_damped_oscillator() {
    let table = run("compliant_element.dyad", None);
    // m x'' + d x' + c x = 0, x(0) = 0.1, x'(0) = 0, with m = 2, c = 40, d = 0.8.
    let (m, c, d, x0) = (2.0f64, 40.0f64, 0.8f64, 0.1f64);
    let decay = d / (2.0 * m);
    let wd = (c / m - decay * decay).sqrt();
    let x = |t: f64| (-decay * t).exp() * x0 * ((wd * t).cos() + decay / wd * (wd * t).sin());
    check(&table, "slider.s", 1e-7, x);
    check(&table, "written.s_rel", 1e-7, x);
    check(&table, "written.v_rel", 1e-6, |t| -(-decay * t).exp() * x0 * (decay * decay / wd + wd) * (wd * t).sin());
    let (a, b) = (table.column("slider.s"), table.column("twin.s"));
    let worst = a.iter().zip(b).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max);
    println!("written vs library SpringDamper: worst difference {worst:.2e} (tolerance 1e-10: {:.3})", worst / 1e-10);
    assert!(worst <= 1e-10);
}

/// Rigid parts written as equations between positions (a reduction, the
/// library-form Rod) carry the drum and the load with the rotor: one
/// degree of freedom swinging about the spring's equilibrium, in closed form.
#[test]
fn rigid_parts_written_as_position_equations_move_as_one_body() {
    let table = run("rigid_parts.dyad", None);
    // On the rotor's angle: J = 0.01 + 0.2 / 4^2 + 5 / 40^2, k = 100 / 40^2, torque 1.5.
    let (j, k, tau): (f64, f64, f64) = (0.01 + 0.2 / 16.0 + 5.0 / 1600.0, 100.0 / 1600.0, 1.5);
    let w = (k / j).sqrt();
    let phi = move |t: f64| tau / k * (1.0 - (w * t).cos());
    check(&table, "rotor.phi", 1e-7, phi);
    check(&table, "drum.phi", 1e-7, move |t| phi(t) / 4.0);
    check(&table, "load.s", 1e-7, move |t| 2.0 + phi(t) / 40.0);
    check(&table, "rope.s", 1e-7, move |t| 1.0 + phi(t) / 40.0);
}

/// A node with no mass between a written spring and damper: its position
/// is a state of the equations, held by the balance of their forces; the
/// spring's force and the block's speed follow their closed forms.
#[test]
fn a_massless_node_between_written_elements_is_held_by_their_forces() {
    let table = run("massless_node.dyad", None);
    let decay = |t: f64| (-5.0 * t).exp();
    check(&table, "spring.f", 1e-7, move |t| 10.0 - 10.0 * decay(t) * ((5.0 * t).cos() + (5.0 * t).sin()));
    check(&table, "damper.f", 1e-7, move |t| 10.0 - 10.0 * decay(t) * ((5.0 * t).cos() + (5.0 * t).sin()));
    check(&table, "block.v", 1e-7, move |t| 2.0 * (1.0 - decay(t) * (5.0 * t).cos()));
}

/// Torque sensors of the library form in line on a driven shaft: each
/// reads the closed-form torque at its place, the multi-sensor also the
/// speed and power, and a filter written in the model integrates the torque
/// at the wall (a state fed by a reaction).
#[test]
fn in_line_sensors_read_the_torque_through_them() {
    let table = run("in_line_sensors.dyad", None);
    let pi = std::f64::consts::PI;
    let (j, c, t0, w): (f64, f64, f64, f64) = (2.0, 20.0, 2.0, pi);
    let w0 = (c / j).sqrt();
    let a = t0 / (c - j * w * w);
    let phi = move |t: f64| a * ((w * t).sin() - w / w0 * (w0 * t).sin());
    let speed = move |t: f64| a * w * ((w * t).cos() - (w0 * t).cos());
    let accel = move |t: f64| a * (-w * w * (w * t).sin() + w * w0 * (w0 * t).sin());
    let between = move |t: f64| 1.5 * accel(t) + c * phi(t);
    // A first-order filter (T = 0.1) of sin(k t) from rest.
    let filtered = |k: f64, t: f64| {
        let kt = k * 0.1;
        ((k * t).sin() - kt * (k * t).cos() + kt * (-t / 0.1).exp()) / (1.0 + kt * kt)
    };
    check(&table, "at_motor.tau", 1e-7, move |t| t0 * (w * t).sin());
    check(&table, "between.tau", 1e-7, between);
    check(&table, "between.w", 1e-7, speed);
    check(&table, "between.power", 1e-7, move |t| between(t) * speed(t));
    check(&table, "at_wall.tau", 1e-7, move |t| c * phi(t));
    check(&table, "smoother.y", 1e-7, move |t| c * a * (filtered(w, t) - w / w0 * filtered(w0, t)));
    check(&table, "second.phi", 1e-7, phi);
}

/// Start values on variables that are not states (a spring's stretch, a
/// damper's speed, an angle sensor's reading) are met by the free start
/// values: each motion follows its closed form from that start.
#[test]
fn start_values_on_variables_that_are_not_states_place_the_mechanism() {
    let table = run("start_on_non_states.dyad", None);
    let w = 40f64.sqrt();
    check(&table, "block.s", 1e-7, move |t| 0.5 + 0.3 * (w * t).cos());
    check(&table, "spring.s_rel", 1e-7, move |t| 0.5 + 0.3 * (w * t).cos());
    check(&table, "sliding.v", 1e-7, |t| 3.0 * (-t / 2.0).exp());
    check(&table, "damper.v_rel", 1e-7, |t| 3.0 * (-t / 2.0).exp());
    check(&table, "sliding.s", 1e-7, |t| 6.0 * (1.0 - (-t / 2.0).exp()));
    check(&table, "disc.phi", 1e-7, |t| 0.4 * (2.0 * t).cos());
    check(&table, "angle.phi", 1e-7, |t| 0.4 * (2.0 * t).cos());
}

/// Library parts without mass between compliant elements (Mass(m = 0),
/// Inertia(J = 0), a spring meeting a damper): each node is held by the
/// balance of its forces, and the chains follow their closed forms, the
/// nodes' positions and accelerations included.
#[test]
fn massless_library_parts_are_held_by_the_forces_on_them() {
    let table = run("massless_library_parts.dyad", None);
    let decay = |t: f64| (-5.0 * t).exp();
    let force = move |t: f64| 10.0 - 10.0 * decay(t) * ((5.0 * t).cos() + (5.0 * t).sin());
    let speed = move |t: f64| 2.0 * (1.0 - decay(t) * (5.0 * t).cos());
    for chain in ["", "bare_"] {
        check(&table, &format!("{chain}spring.f"), 1e-7, force);
        check(&table, &format!("{chain}block.v"), 1e-7, speed);
    }
    // The node sits where the spring's force puts it: s = f / c.
    check(&table, "node.s", 1e-7, move |t| force(t) / 50.0);
    check(&table, "node.v", 1e-7, move |t| 100.0 * decay(t) * (5.0 * t).sin() / 50.0);
    check(&table, "node.a", 1e-7, move |t| 500.0 * decay(t) * ((5.0 * t).cos() - (5.0 * t).sin()) / 50.0);
    let a = 0.8 / (12.0 - 27.0);
    let phi = move |t: f64| 0.5 * (2.0 * t).cos() + a * ((3.0 * t).sin() - 1.5 * (2.0 * t).sin());
    let torque = |t: f64| 2.0 * (3.0 * t).sin();
    check(&table, "disc.phi", 1e-7, phi);
    // The massless joint between the springs: 50 x = 20 phi + torque.
    check(&table, "joint.phi", 1e-7, move |t| (20.0 * phi(t) + torque(t)) / 50.0);
    let phi_dd = move |t: f64| (-12.0 * phi(t) + 0.8 * (3.0 * t).sin()) / 3.0;
    check(&table, "joint.a", 1e-7, move |t| (20.0 * phi_dd(t) - 18.0 * (3.0 * t).sin()) / 50.0);
}

/// The DC motor on a turntable: a circuit of the electrical library turns
/// the mechanism through `RotationalEMF`. With x = [i, w], `x' = A x + b`;
/// its closed form `x = x_ss + exp(A t) (x_0 - x_ss)`.
#[test]
fn a_dc_motor_circuit_turns_the_table_as_its_linear_closed_form() {
    let table = run("dc_motor_turntable.dyad", None);
    let (r, l, k, v) = (2.0, 0.05, 0.8, 24.0);
    let (radius, length, density) = (0.4, 0.05, 500.0);
    let m = density * std::f64::consts::PI * radius * radius * length;
    let j = m * radius * radius / 2.0;
    let a = [[-r / l, -k / l], [k / j, 0.0]];
    let expm = move |t: f64| multibody_reference::expm2(a, t);
    // Steady: no current, w = V / k; start from rest.
    let w_ss = v / k;
    let current = move |t: f64| -expm(t)[0][1] * w_ss;
    let speed = move |t: f64| w_ss - expm(t)[1][1] * w_ss;
    check(&table, "coil.i", 1e-7 * v / r, current);
    check(&table, "ammeter.i", 1e-7 * v / r, current);
    check(&table, "bearing.w", 1e-7 * w_ss, speed);
    check(&table, "tachometer.w", 1e-7 * w_ss, speed);
}

/// The drawing arm: its hand on the circle by equations, its torques
/// unknown (index 3). The angles are the closed-form inverse kinematics of
/// two unit links, elbow below (the torques are checked against inverse
/// dynamics in the language crate's tests).
#[test]
fn a_hand_drawing_a_circle_puts_the_joints_at_the_inverse_kinematics() {
    let table = run("prescribed_hand.dyad", None);
    let angles = |t: f64| {
        let (x, y) = (1.2 + 0.2 * t.cos(), 0.2 * t.sin());
        let elbow = -((x * x + y * y - 2.0) / 2.0).acos();
        (y.atan2(x) - elbow.sin().atan2(1.0 + elbow.cos()), elbow)
    };
    check(&table, "shoulder.phi", 1e-6, move |t| angles(t).0);
    check(&table, "elbow.phi", 1e-6, move |t| angles(t).1);
    // The motors hold the hand: the pen's frame feels no force.
    check(&table, "forearm.frame_b.f[1]", 1e-9, |_| 0.0);
    // `check` says what holds the hand: not a loop of joints.
    let path = crate_path("../../examples/equations/prescribed_hand.dyad");
    let output = multibody(&scratch("equations-prescribed-hand-check"), &["check", path.as_str()]);
    let report = String::from_utf8_lossy(&output.stdout);
    assert!(report.contains("motion prescribed by equations: forearm.frame_b (2 position coordinates"), "{report}");
    assert!(report.contains("held by the unknown efforts on elbow, shoulder") && !report.contains("kinematic loops"));
}

#[test]
fn every_model_with_equations_is_checked() {
    let source = std::fs::read_to_string(crate_path("tests/equations.rs")).unwrap();
    for entry in std::fs::read_dir(crate_path("../../examples/equations")).unwrap() {
        let name = entry.unwrap().file_name().to_string_lossy().into_owned();
        assert!(source.contains(&format!("run(\"{name}\"")), "examples/equations/{name} has no test here");
    }
}

/// The bouncing ball through the command: its discrete variables count the
/// impacts (closed form: the n-th at sqrt(2 h0/g) (1 + 2 e (1 - e^(n-1)) / (1 - e))).
#[test]
fn a_bouncing_ball_counts_its_impacts_at_the_closed_form_times() {
    let table = run("bouncing_ball.dyad", None);
    let (g, e, h0) = (9.81f64, 0.8f64, 1.0f64);
    let t1 = (2.0 * h0 / g).sqrt();
    let impact = |n: i32| t1 * (1.0 + 2.0 * e * (1.0 - e.powi(n - 1)) / (1.0 - e));
    let (impacts, last) = (table.column("impacts"), table.column("last_impact"));
    let n = *impacts.last().unwrap() as i32;
    assert!(n >= 10, "{n} impacts");
    let error = (last.last().unwrap() - impact(n)).abs();
    println!("impact {n} at {} (closed form {}): {error:.1e}", last.last().unwrap(), impact(n));
    assert!(error < 1e-8, "impact {n}: {error}");
}

/// The op-amp linear motor through the command: the amplifier's output is
/// `u = -3 sin(w t)` (w = 4 pi), the slider's speed solves
/// `v' = -a v + b sin(w t)` with a = k^2/(m R) = 12.5, b = -3 k/(m R) = -7.5
/// from rest, and the amplifier delivers `u i` with `i = (u - k v) / R`.
#[test]
fn an_op_amp_amplifier_drives_a_linear_motor_as_its_closed_form() {
    let table = run("op_amp_linear_motor.dyad", None);
    let w = 4.0 * std::f64::consts::PI;
    let (a, b) = (12.5, -7.5);
    let u = |t: f64| -3.0 * (w * t).sin();
    let v = |t: f64| {
        let d = a * a + w * w;
        b / d * (a * (w * t).sin() - w * (w * t).cos()) + b * w / d * (-a * t).exp()
    };
    check(&table, "drive.phi", 1e-9, u);
    check(&table, "slider.v", 1e-7, v);
    check(&table, "meter.power", 1e-6, |t| u(t) * (u(t) - 5.0 * v(t)) / 2.0);
}

/// The Cartesian pendulum (index 3): after two of its periods (computed
/// here from the complete elliptic integral by the arithmetic-geometric
/// mean) the bob is back where it started, at rest, and the rod's length
/// held all along.
#[test]
fn a_pendulum_in_cartesian_coordinates_returns_after_its_elliptic_period() {
    let table = run("cartesian_pendulum.dyad", None);
    let (length, g, theta0) = (0.8f64, 9.81f64, 30f64.to_radians());
    let period = pendulum_period(length, g, theta0);
    let time = table.times();
    let last = time.len() - 1;
    // The file stops at two periods rounded to 1e-6 s, where the bob moves 1.5e-6 m at most.
    assert!(
        (time[last] - 2.0 * period).abs() < 1e-6,
        "the run ends at two periods: {} vs {}",
        time[last],
        2.0 * period
    );
    let (x, y) = (table.column("x"), table.column("y"));
    assert!((x[last] - length * theta0.sin()).abs() < 2e-6, "x = {} after two periods", x[last]);
    // At rest there; g sin(theta0) over 1e-6 s is 5e-6 m/s.
    assert!(table.column("vx")[last].abs() < 1e-5, "vx = {} after two periods", table.column("vx")[last]);
    let worst = x.iter().zip(y).map(|(x, y)| (x * x + y * y - length * length).abs()).fold(0.0, f64::max);
    assert!(worst < 1e-9, "the rod's length holds: {worst}");
}

/// Dyad's DC-motor tutorial model: a motor component (R, L, k, J, f) held
/// at 1 rad/s by a limited PID controller, a load torque of -0.3 N m from
/// 3 s. Reference, integrated here by classical Runge-Kutta at 1e-5 s: the
/// loop's four equations as the parts state them, the armature
/// `L i' = u - R i - k w`, the rotor `J w' = k i - f w + tau_load`, the
/// controller's integrator `xi' = (e + (y - v) / (k Ni)) / Ti` and its
/// derivative filter `xd' = (-w - xd) Nd / Td`, with `v = k (e + xi + D)`,
/// `D = Nd (-w - xd)`, `e = 1 - w`, `y = v` limited to +-5.
#[test]
fn the_tutorial_dc_motor_holds_its_speed_as_its_loop_equations() {
    let table = run("dc_motor_speed_control.dyad", None);
    let (r, l, k_m, j, f) = (0.5, 4.5e-3, 0.5, 0.02, 0.01);
    let (k, ti, td, nd, ni) = (0.5, 0.1, 1e5, 10.0, 0.9);
    let rates = |load: f64, s: &[f64; 4]| {
        let [i, w, xi, xd] = *s;
        let e = 1.0 - w;
        let d = nd * (-w - xd);
        let v = k * (e + xi + d);
        let u = v.clamp(-5.0, 5.0);
        [(u - r * i - k_m * w) / l, (k_m * i - f * w + load) / j, (e + (u - v) / (k * ni)) / ti, (-w - xd) * nd / td]
    };
    // Sample interval by sample interval (0.01 s, RK4 at 1e-5 s), the load on from the one that starts at 3 s.
    let time = table.times().to_vec();
    let (w_ours, i_ours) = (table.column("motor.inertia.w"), table.column("motor.L1.i"));
    let (mut worst_w, mut worst_i) = (0.0f64, 0.0f64);
    let mut s = [0.0; 4];
    for n in 0..time.len() {
        if n > 0 {
            let load = if time[n - 1] >= 3.0 - 1e-12 { -0.3 } else { 0.0 };
            let every = ((time[n] - time[n - 1]) / 1e-5).round() as usize;
            s = rk4(|s| rates(load, s), s, (time[n] - time[n - 1]) / every as f64, 2, every)[1];
        }
        worst_w = worst_w.max((w_ours[n] - s[1]).abs());
        worst_i = worst_i.max((i_ours[n] - s[0]).abs());
    }
    println!("speed: worst {worst_w:.2e} rad/s (tolerance 1e-8); current: worst {worst_i:.2e} A (tolerance 1e-7)");
    assert!(worst_w < 1e-8 && worst_i < 1e-7);
    // It runs up towards 1 rad/s, sags under the load, and comes back.
    let at = |t0: f64| w_ours[time.iter().position(|&x| (x - t0).abs() < 1e-9).unwrap()];
    assert!(at(3.0) > 0.9 && at(3.5) < at(3.0) && at(6.0) > 0.98, "{} {} {}", at(3.0), at(3.5), at(6.0));
}
