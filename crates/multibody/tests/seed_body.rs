//! The behaviours of the Body seed (shared/seeds/Body.md), one test each.
//!
//! Expected values come from closed forms, conservation laws, finite
//! differences of the engine's own position signals, or a second
//! formulation; never from the engine's output for the quantity checked.
//!
//! Tolerances, and why:
//! - Integrated solutions with `abstol = reltol = eps`: each step's error is
//!   held to ~eps of the state's size; over the few hundred steps of these
//!   runs the global error stays within `100 eps` of the signal's scale.
//! - Relations between outputs at one sample (no integration involved):
//!   rounding only, 1e-12 of the quantity's scale.
//! - Finite differences (5-point stencils at h and 2h, Richardson-
//!   extrapolated) of samples accurate to `eps * scale`: sample errors are
//!   amplified by at most 1.65/h; we allow 10 times that, plus the
//!   truncation error estimated from the two step sizes (see
//!   `physics::check_derivative`).

#[path = "common/models.rs"]
mod models;
#[path = "common/physics.rs"]
mod physics;

use models::{compare_runs, tumbling_body};
use multibody::{Method, Model, OrientationState};
use physics::*;
use std::f64::consts::PI;

/// The tumbling body's inertia about its centre of mass, from its
/// parameters (see `models::tumbling_body`).
const TUMBLING_I: M3 = [[0.05, 0.005, 0.0], [0.005, 0.08, 0.0], [0.0, 0.0, 0.1]];
const TUMBLING_M: f64 = 1.3;
const R_CM: V3 = [0.2, -0.1, 0.15];

/// Euler and Quaternion roots give the same motion, with gravity and an
/// offset r_cm, tumbling: every output of the body agrees.
#[test]
fn euler_and_quaternion_roots_give_the_same_motion() {
    let eps = 1e-10;
    let opts = options(2.0, 0.01, eps, eps);
    let eu = run(&tumbling_body(OrientationState::Euler, R_CM, G), &opts);
    let q = run(&tumbling_body(OrientationState::Quaternion, R_CM, G), &opts);
    let phi2_max = sig(&eu, "body.phi[2]").iter().fold(0.0f64, |a, x| a.max(x.abs()));
    println!("Euler vs Quaternion: max |phi[2]| = {phi2_max:.3} rad (singular at {:.3})", PI / 2.0);
    assert!(phi2_max < 1.3, "the Euler run must stay away from its singularity");
    let signals = [
        "body.r_0",
        "body.v_0",
        "body.a_0",
        "body.w_a",
        "body.z_a",
        "body.g_0",
        "body.v_cm_0",
        "body.KE",
        "body.PE",
        "body.frame_a.R",
        "body.frame_a.r_0",
    ];
    compare_runs("Euler vs Quaternion root", &eu, &q, &signals, eps);
}

/// n_q(t) for der(Q_hat) = Omega(w) Q_hat / 2 + k (1 - n_q) Q_hat: Omega is
/// skew-symmetric, so Q_hat' Omega Q_hat = 0 and d(n_q)/dt = 2 Q_hat . der(Q_hat)
/// = 2 k (1 - n_q) n_q, the logistic curve
/// n_q(t) = 1 / (1 + (1/n_q(0) - 1) exp(-2 k t)).
fn logistic(n0: f64, k: f64, t: f64) -> f64 {
    1.0 / (1.0 + (1.0 / n0 - 1.0) * (-2.0 * k * t).exp())
}

fn spinning_quaternion_body(q_hat0: [f64; 4], k: f64, w: V3) -> Model {
    let mut model = Model::new("quaternion_norm");
    model.add("world", "World").set("g", 0.0);
    model
        .add("body", "Body")
        .set("orientation_state", OrientationState::Quaternion)
        .set("k", k)
        .initial("Q_hat", q_hat0.to_vec())
        .initial("w_a", w);
    model
}

/// A non-unit Q_hat(0) is pulled back towards norm 1 at the rate k sets;
/// c_q = k (1 - n_q); Q = Q_hat / |Q_hat|; the orientation does not depend
/// on |Q_hat|.
#[test]
fn non_unit_quaternion_is_pulled_back_to_norm_one_at_rate_k() {
    let w = [0.5, -0.3, 0.8];
    let eps = 1e-10;
    let stop = 5.0;
    let opts = options(stop, 0.01, eps, eps);
    for q_hat0 in [[2.0, 0.0, 0.0, 0.0], [1.2, 0.3, 0.0, 0.0]] {
        let n0: f64 = q_hat0.iter().map(|x| x * x).sum();
        let norm0 = n0.sqrt();
        let unit0 = q_hat0.map(|x| x / norm0);
        // The same start orientation with a unit quaternion.
        let reference = run(&spinning_quaternion_body(unit0, 0.1, w), &opts);
        for k in [0.1, 1.0] {
            let label = format!("Q_hat(0) = {q_hat0:?}, k = {k}");
            let sol = run(&spinning_quaternion_body(q_hat0, k, w), &opts);
            let t = sol.time();
            // n_q follows the logistic curve (scale n0 = 4 at most).
            worst_over(&sol, |i| (sig(&sol, "body.n_q")[i] - logistic(n0, k, t[i])).abs()).check(
                &format!("{label}: |n_q - logistic|"),
                "",
                100.0 * eps * n0,
            );
            // (For the record: how far the closed form pulls it back in the run.)
            let n_end = logistic(n0, k, stop);
            println!("{label}: the closed form takes n_q from {n0} to {n_end:.6} by t = {stop}");
            // c_q = k (1 - n_q), with n_q from the closed form.
            worst_over(&sol, |i| (sig(&sol, "body.c_q")[i] - k * (1.0 - logistic(n0, k, t[i]))).abs()).check(
                &format!("{label}: |c_q - k (1 - n_q)|"),
                "1/s",
                100.0 * eps * n0 * k,
            );
            // Q is Q_hat normalised (rounding only).
            worst_over(&sol, |i| {
                let q_hat = v4(&sol, "body.Q_hat", i);
                let n = q_hat.iter().map(|x| x * x).sum::<f64>().sqrt();
                let q = v4(&sol, "body.Q", i);
                (0..4).map(|j| (q[j] - q_hat[j] / n).abs()).fold(0.0, f64::max)
            })
            .check(&format!("{label}: |Q - Q_hat / |Q_hat||"), "", 1e-15);
            // der(Q_hat) (the Q_hat_d output) against finite differences of Q_hat
            // on a fine grid (the logistic is fast at k = 1, n_q(0) = 4: its
            // rate 2 k (2 n_q - 1) is 14/s), with samples accurate to eps |Q_hat|.
            let h = 1e-3;
            let fine = run(&spinning_quaternion_body(q_hat0, k, w), &options(2.0, h, eps, eps));
            let qh: Vec<Vec<f64>> = (1..=4).map(|j| sig(&fine, &format!("body.Q_hat[{j}]")).to_vec()).collect();
            let qd: Vec<Vec<f64>> = (1..=4).map(|j| sig(&fine, &format!("body.Q_hat_d[{j}]")).to_vec()).collect();
            check_derivative(
                &format!("{label}: |Q_hat_d - d/dt Q_hat (finite difference)|"),
                "1/s",
                fine.time(),
                h,
                &qh,
                &qd,
                eps * norm0,
            );
            // The orientation is that of the unit start, and of the closed form
            // R(t) = planar(w, |w| t) R(0) (a spherical body keeps w constant).
            let r0 = r_from_quat(unit0);
            worst_over(&sol, |i| mat_dist(&m3(&sol, "body.frame_a.R", i), &m3(&reference, "body.frame_a.R", i))).check(
                &format!("{label}: |R - R with unit Q_hat(0)|"),
                "",
                100.0 * eps,
            );
            worst_over(&sol, |i| mat_dist(&m3(&sol, "body.frame_a.R", i), &mat_mul(&planar(w, norm(w) * t[i]), &r0)))
                .check(&format!("{label}: |R - planar(w, |w| t) R(0)|"), "", 100.0 * eps);
            // And R is the rotation of Q in the convention of DESIGN.md.
            worst_over(&sol, |i| mat_dist(&m3(&sol, "body.frame_a.R", i), &r_from_quat(v4(&sol, "body.Q", i)))).check(
                &format!("{label}: |R - R(Q)|"),
                "",
                1e-14,
            );
        }
    }
}

/// KE and PE: on a pendulum, KE = (I_33 + m l^2) w^2 / 2 and PE = m g y_cm
/// with y_cm = l sin(phi); on a free tumbling body in gravity, KE + PE is
/// conserved and PE = m g y_cm with the centre of mass r_0 + R' r_cm.
#[test]
fn kinetic_and_potential_energy() {
    let (m, l, i33) = (1.4, 0.6, 0.02);
    let mut model = Model::new("pendulum_energy");
    model.add("world", "World");
    model.add("rev", "Revolute").set("n", [0.0, 0.0, 1.0]).initial("phi", 0.3).initial("w", 2.0);
    model
        .add("body", "Body")
        .set("m", m)
        .set("r_cm", [l, 0.0, 0.0])
        .set("I_11", 0.01)
        .set("I_22", 0.015)
        .set("I_33", i33)
        .set("I_31", 0.003)
        .set("I_32", -0.002);
    model.connect(["world.frame_b", "rev.frame_a"]);
    model.connect(["rev.frame_b", "body.frame_a"]);
    let eps = 1e-10;
    let sol = run(&model, &options(3.0, 0.01, eps, eps));
    let (phi, w) = (sig(&sol, "rev.phi"), sig(&sol, "rev.w"));
    let e_scale = m * G * l + 0.5 * (i33 + m * l * l) * 4.0;
    worst_over(&sol, |k| (sig(&sol, "body.KE")[k] - 0.5 * (i33 + m * l * l) * w[k] * w[k]).abs()).check(
        "pendulum: |KE - (I_33 + m l^2) w^2 / 2|",
        "J",
        1e-12 * e_scale,
    );
    worst_over(&sol, |k| (sig(&sol, "body.PE")[k] - m * G * l * phi[k].sin()).abs()).check(
        "pendulum: |PE - m g l sin(phi)|",
        "J",
        1e-12 * e_scale,
    );
    let e0 = sig(&sol, "body.KE")[0] + sig(&sol, "body.PE")[0];
    worst_over(&sol, |k| (sig(&sol, "body.KE")[k] + sig(&sol, "body.PE")[k] - e0).abs()).check(
        "pendulum: |KE + PE - E(0)|",
        "J",
        100.0 * eps * e_scale,
    );

    let free = run(&tumbling_body(OrientationState::Quaternion, R_CM, G), &options(2.0, 0.01, eps, eps));
    let cm = |k| add(v3(&free, "body.r_0", k), mat_t_vec(&m3(&free, "body.frame_a.R", k), R_CM));
    let scale_free = TUMBLING_M * G * 5.0;
    worst_over(&free, |k| (sig(&free, "body.PE")[k] - TUMBLING_M * G * cm(k)[1]).abs()).check(
        "free body: |PE - m g y_cm|",
        "J",
        1e-12 * scale_free,
    );
    let total = |k: usize| sig(&free, "body.KE")[k] + sig(&free, "body.PE")[k];
    worst_over(&free, |k| (total(k) - total(0)).abs()).check(
        "free body: |KE + PE - E(0)|",
        "J",
        100.0 * eps * scale_free,
    );
}

/// A free quaternion Body with an offset centre of mass in a point-gravity
/// field (World mu = 1, positions ~1 m so that the field varies strongly
/// across the body).
fn point_gravity_body(w0: V3, v0: V3) -> Model {
    let mut model = Model::new("point_gravity_body");
    model.add("world", "World").set("mu", 1.0);
    model
        .add("body", "Body")
        .set("m", 2.0)
        .set("r_cm", R_CM)
        .set("I_11", 0.05)
        .set("I_22", 0.08)
        .set("I_33", 0.1)
        .set("I_21", 0.005)
        .set("point_gravity", true)
        .set("orientation_state", OrientationState::Quaternion)
        .initial("Q_hat", quat_from_r(&euler_r([1, 2, 3], [0.4, -0.2, 0.7])).to_vec())
        .initial("r_0", [0.8, 0.6, 0.1])
        .initial("v_0", v0)
        .initial("w_a", w0);
    model
}

/// `-mu r / |r|^3` with mu = 1.
fn field(r: V3) -> V3 {
    scale(-1.0 / norm(r).powi(3), r)
}

/// Point gravity acts at the centre of mass: g_0 is the field at the CM,
/// the CM accelerates with it, and it exerts no torque about the CM.
#[test]
fn point_gravity_acts_at_the_centre_of_mass() {
    let inertia = [[0.05, 0.005, 0.0], [0.005, 0.08, 0.0], [0.0, 0.0, 0.1]];
    let check = |label: &str, sol: &multibody::Solution, samples: usize| {
        let cm = |k| add(v3(sol, "body.r_0", k), mat_t_vec(&m3(sol, "body.frame_a.R", k), R_CM));
        // |g| ~ 1 m/s^2 here; relations at one sample: rounding only.
        let tol = 1e-12 * 10.0;
        let mut g_err = Worst::default();
        let mut a_err = Worst::default();
        let mut euler_err = Worst::default();
        for k in 0..samples {
            let t = sol.time()[k];
            let g_cm = field(cm(k));
            g_err.update(dist(v3(sol, "body.g_0", k), g_cm), t);
            // a_cm = a_0 + R' (z x r_cm + w x (w x r_cm))
            let (w, z) = (v3(sol, "body.w_a", k), v3(sol, "body.z_a", k));
            let rel = add(cross(z, R_CM), cross(w, cross(w, R_CM)));
            let a_cm = add(v3(sol, "body.a_0", k), mat_t_vec(&m3(sol, "body.frame_a.R", k), rel));
            a_err.update(dist(a_cm, g_cm), t);
            // No torque about the CM: I z + w x I w = 0.
            euler_err.update(norm(add(mat_vec(&inertia, z), cross(w, mat_vec(&inertia, w)))), t);
        }
        g_err.check(&format!("{label}: |g_0 - (-mu r_cm0 / |r_cm0|^3)| at the CM"), "m/s2", tol);
        a_err.check(&format!("{label}: |a_cm - g(r_cm0)|"), "m/s2", tol);
        euler_err.check(&format!("{label}: |I z_a + w x I w| (no torque about the CM)"), "N.m", tol * 0.1);
    };
    // From rest, at t = 0.
    let at_rest = run(&point_gravity_body([0.0; 3], [0.0; 3]), &options(0.1, 0.1, 1e-10, 1e-10));
    check("point gravity, from rest at t = 0", &at_rest, 1);
    let z0 = norm(v3(&at_rest, "body.z_a", 0));
    Worst { err: z0, t: 0.0 }.check("point gravity, from rest: |z_a(0)|", "rad/s2", 1e-12);
    // Moving and tumbling, along the whole run.
    let moving = run(&point_gravity_body([0.3, -0.5, 0.8], [-0.5, 0.9, 0.2]), &options(2.0, 0.01, 1e-10, 1e-10));
    check("point gravity, tumbling", &moving, moving.len());
}

/// v_cm_0 against a finite difference of the CM position r_0 + R' r_cm
/// computed from the solution; likewise v_0, a_0 and z_a against
/// differences of r_0, v_0 and w_a, w_a against dR/dt = -[w]x R, and KE
/// from the differenced CM velocity.
#[test]
fn velocities_and_accelerations_match_finite_differences() {
    let eps = 1e-12;
    let h = 1e-3;
    let sol = run(&tumbling_body(OrientationState::Quaternion, R_CM, G), &options(1.0, h, eps, eps));
    let t = sol.time();
    let n = sol.len();
    let rot: Vec<M3> = (0..n).map(|k| m3(&sol, "body.frame_a.R", k)).collect();
    let cm: Vec<V3> = (0..n).map(|k| add(v3(&sol, "body.r_0", k), mat_t_vec(&rot[k], R_CM))).collect();
    let columns =
        |name: &str| -> Vec<Vec<f64>> { (1..=3).map(|j| sig(&sol, &format!("{name}[{j}]")).to_vec()).collect() };
    let cm_columns: Vec<Vec<f64>> = (0..3).map(|j| cm.iter().map(|c| c[j]).collect()).collect();
    // Sample errors: eps times the scale (positions and velocities within 20, rates within 1).
    check_derivative("v_cm_0 vs d/dt (r_0 + R' r_cm)", "m/s", t, h, &cm_columns, &columns("body.v_cm_0"), eps * 20.0);
    check_derivative("v_0 vs d/dt r_0", "m/s", t, h, &columns("body.r_0"), &columns("body.v_0"), eps * 20.0);
    check_derivative("a_0 vs d/dt v_0", "m/s2", t, h, &columns("body.v_0"), &columns("body.a_0"), eps * 20.0);
    // w_a is resolved in frame_a, and so is z_a = der(w_a).
    check_derivative("z_a vs d/dt w_a", "rad/s2", t, h, &columns("body.w_a"), &columns("body.z_a"), eps);
    // w_a against the rotation: dR/dt = -[w]x R, so [w]x = -dR/dt R'.
    let r_columns: Vec<Vec<f64>> = (0..9).map(|e| rot.iter().map(|r| r[e / 3][e % 3]).collect()).collect();
    let mut worst = Worst::default();
    let mut truncation = 0.0f64;
    for i in uniform_rows(t, h) {
        let mut rdot = [[0.0; 3]; 3];
        for e in 0..9 {
            let (d, trunc) = fd_richardson(&r_columns[e], h, i);
            rdot[e / 3][e % 3] = d;
            truncation = truncation.max(trunc);
        }
        worst.update(dist(w_from_rdot(&rot[i], &rdot), v3(&sol, "body.w_a", i)), t[i]);
    }
    // w = -dR/dt R' sums three products of entries of size 1.
    worst.check("w_a vs -dR/dt R' (finite difference)", "rad/s", 3.0 * (10.0 * FD_NOISE_GAIN * eps / h + truncation));
    // KE = m |v_cm|^2 / 2 + w . I w / 2 with the differenced v_cm and the
    // inertia built here from the parameters (I_21 included).
    let mut worst = Worst::default();
    let mut truncation = 0.0f64;
    for i in uniform_rows(t, h) {
        let mut v_cm = [0.0; 3];
        for j in 0..3 {
            let (d, trunc) = fd_richardson(&cm_columns[j], h, i);
            v_cm[j] = d;
            truncation = truncation.max(trunc);
        }
        let wv = v3(&sol, "body.w_a", i);
        let ke = 0.5 * TUMBLING_M * dot(v_cm, v_cm) + 0.5 * dot(wv, mat_vec(&TUMBLING_I, wv));
        worst.update((sig(&sol, "body.KE")[i] - ke).abs(), t[i]);
    }
    // |dKE| <= m |v| |dv| with |v| <= 20 m/s and |dv| <= sqrt(3) times the per-component error.
    let dv = 10.0 * FD_NOISE_GAIN * eps * 20.0 / h + truncation;
    worst.check("KE vs m |v_cm|^2/2 + w.Iw/2 (finite-difference v_cm)", "J", TUMBLING_M * 20.0 * 3f64.sqrt() * dv);
}

/// A free Euler body (sequence [1, 2, 3], spherical inertia, g = 0)
/// spinning at the constant w from the identity.
fn euler_spinner(w: V3, phi0: V3) -> Model {
    let mut model = Model::new("euler_singularity");
    model.add("world", "World").set("g", 0.0);
    // At phi = 0 the rates are the angular velocity (w = J(0) phid, J(0) = I).
    model
        .add("tumbler", "Body")
        .set("orientation_state", OrientationState::Euler)
        .set("sequence", [1, 2, 3])
        .initial("phi", phi0)
        .initial("phid", w);
    model
}

/// The Euler singularity: a free Euler body (sequence [1, 2, 3]) turning so
/// that phi[2] reaches pi/2 keeps running: near the singular configuration
/// it moves to an internal chart, says so once in the solution's warnings
/// (naming the body), and its orientation keeps matching the closed form
/// after the crossing, while its reported `phi`, `phid` stay the library's
/// angles of that orientation and their rates.
///
/// With w constant (spherical body) R(t) = planar(n, |w| t), n = w/|w|, and
/// sin(phi2) = R[3,1] = (1 - cos(|w| t)) n1 n3 + sin(|w| t) n2:
/// - about y (n = e2): phi2 = |w| t passes pi/2 at t = pi / (2 |w|) (the
///   middle angle goes through the singular value at a bounded rate);
/// - about (x + z)/sqrt(2): R[3,1] = (1 - cos(|w| t))/2 touches 1 at
///   t = pi / |w| (the angles' rates grow without bound there).
///
/// Tolerance: abstol = reltol = 1e-10 over 5 s, about 1e-9 in R (the
/// `100 eps` of the header); the issue asks for 1e-8 after the crossing.
#[test]
fn euler_body_runs_through_its_singularity_matching_the_closed_form() {
    let speed = 1.3;
    for method in [None, Some(Method::Rk4 { dt: 0.01 })] {
        for (label, n, t_singular) in [
            ("spin about y", [0.0, 1.0, 0.0], PI / (2.0 * speed)),
            ("spin about (x+z)/sqrt 2", normalize([1.0, 0.0, 1.0]), PI / speed),
        ] {
            let label = format!("{label}{}", if method.is_some() { ", RK4" } else { "" });
            let mechanism = euler_spinner(scale(speed, n), [0.0; 3]).assemble().unwrap();
            let mut opts = options(5.0, 0.01, 1e-10, 1e-10);
            if let Some(method) = method {
                opts.method = method;
            }
            let sol = mechanism.simulate(&opts).unwrap_or_else(|e| panic!("{label}: {e}"));
            assert_eq!(*sol.time().last().unwrap(), 5.0, "{label}: the run reaches its stop");
            let notes: Vec<&String> = sol.warnings().iter().filter(|w| w.contains("singular")).collect();
            println!("{label}: {notes:?}");
            assert_eq!(notes.len(), 1, "{label}: one note: {:?}", sol.warnings());
            assert!(notes[0].contains("`tumbler`") && notes[0].contains("chart"), "{}", notes[0]);
            // The note comes before the singular configuration (the band is 0.1 rad of phi[2]).
            let t_note: f64 = notes[0].split("t = ").nth(1).unwrap().split(' ').next().unwrap().parse().unwrap();
            assert!(t_note < t_singular && t_note > t_singular - 0.5, "{label}: note at {t_note}");
            let time = sol.time();
            let mut after = Worst::default();
            let mut angles = Worst::default();
            let mut rates = Worst::default();
            for (k, &t) in time.iter().enumerate() {
                let r = m3(&sol, "tumbler.frame_a.R", k);
                let err = mat_dist(&r, &planar(n, speed * t));
                if t > t_singular {
                    after.update(err, t);
                }
                // The reported angles are the library's angles of R, their rates those of w.
                let (phi, phid) = (v3(&sol, "tumbler.phi", k), v3(&sol, "tumbler.phid", k));
                angles.update(mat_dist(&euler_r([1, 2, 3], phi), &r), t);
                if phi[1].cos().abs() > 1e-3 {
                    rates.update(dist(euler_w([1, 2, 3], phi, phid), v3(&sol, "tumbler.w_a", k)), t);
                }
            }
            after.check(&format!("{label}: |R - planar(n, |w| t)| after the crossing"), "", 1e-8);
            angles.check(&format!("{label}: |R(phi) - R|"), "", 1e-12);
            rates.check(&format!("{label}: |w(phi, phid) - w_a|"), "rad/s", 1e-8);
        }
    }
}

/// A spinning Euler body thrown in gravity: across the chart switch (its
/// frame_a turned, its position and velocity states resolved there) its
/// position and velocity stay the parabola's, r_0 = v0 t + g n t^2 / 2.
#[test]
fn a_thrown_euler_body_keeps_its_parabola_across_the_singularity() {
    let (speed, v0, g) = (1.3, [1.0, 2.0, 0.5], 9.80665);
    let mut model = Model::new("thrown");
    model.add("world", "World");
    model
        .add("tumbler", "Body")
        .set("orientation_state", OrientationState::Euler)
        .set("sequence", [1, 2, 3])
        .initial("phi", [0.0; 3])
        .initial("phid", [0.0, speed, 0.0])
        .initial("v_0", v0);
    let sol = model.assemble().unwrap().simulate(&options(3.0, 0.01, 1e-10, 1e-10)).unwrap();
    assert_eq!(sol.warnings().iter().filter(|w| w.contains("singular")).count(), 1, "{:?}", sol.warnings());
    let (mut position, mut velocity, mut turn) = (Worst::default(), Worst::default(), Worst::default());
    for (k, &t) in sol.time().iter().enumerate() {
        let r = add(scale(t, v0), [0.0, -0.5 * g * t * t, 0.0]);
        let v = add(v0, [0.0, -g * t, 0.0]);
        position.update(dist(v3(&sol, "tumbler.r_0", k), r), t);
        velocity.update(dist(v3(&sol, "tumbler.v_0", k), v), t);
        turn.update(mat_dist(&m3(&sol, "tumbler.frame_a.R", k), &planar([0.0, 1.0, 0.0], speed * t)), t);
    }
    position.check("thrown: |r_0 - parabola|", "m", 1e-8);
    velocity.check("thrown: |v_0 - parabola'|", "m/s", 1e-8);
    turn.check("thrown: |R - planar(y, |w| t)|", "", 1e-8);
}

/// A torque-free asymmetric Euler body (sequence [1, 2, 3]) turning mostly
/// about its intermediate axis tumbles, and its orientation passes near
/// the singular configuration of the angles: across it, the kinetic energy
/// and the angular momentum in the world stay what they were at the start.
#[test]
fn torque_free_tumbler_conserves_energy_and_momentum_across_the_singularity() {
    let inertia: M3 = [[1.0, 0.0, 0.0], [0.0, 2.0, 0.0], [0.0, 0.0, 3.0]];
    let mut model = Model::new("tumbler");
    model.add("world", "World").set("g", 0.0);
    let phi0 = [0.1, 1.2, -0.3];
    let w0 = [0.05, 1.5, 0.1];
    // The rates of w0 at phi0: solve w0 = J(phi0) phid by Cramer's rule on the columns of J.
    let cols = [euler_w([1, 2, 3], phi0, [1.0, 0.0, 0.0]), euler_w([1, 2, 3], phi0, [0.0, 1.0, 0.0]), e(3)];
    let det = dot(cols[0], cross(cols[1], cols[2]));
    let phid0 = [
        dot(w0, cross(cols[1], cols[2])) / det,
        dot(cols[0], cross(w0, cols[2])) / det,
        dot(cols[0], cross(cols[1], w0)) / det,
    ];
    model
        .add("body", "Body")
        .set("orientation_state", OrientationState::Euler)
        .set("sequence", [1, 2, 3])
        .set("I_11", inertia[0][0])
        .set("I_22", inertia[1][1])
        .set("I_33", inertia[2][2])
        .initial("phi", phi0)
        .initial("phid", phid0);
    let sol = model.assemble().unwrap().simulate(&options(20.0, 0.01, 1e-10, 1e-10)).unwrap();
    let notes: Vec<&String> = sol.warnings().iter().filter(|w| w.contains("singular")).collect();
    println!("{notes:?}");
    assert_eq!(notes.len(), 1, "one note, however often it passes: {:?}", sol.warnings());
    let momentum = |k: usize| mat_t_vec(&m3(&sol, "body.frame_a.R", k), mat_vec(&inertia, v3(&sol, "body.w_a", k)));
    let energy = |k: usize| 0.5 * dot(v3(&sol, "body.w_a", k), mat_vec(&inertia, v3(&sol, "body.w_a", k)));
    let (l0, e0) = (momentum(0), energy(0));
    let (mut dl, mut de) = (Worst::default(), Worst::default());
    let mut nearest = f64::INFINITY;
    for k in 0..sol.len() {
        dl.update(dist(momentum(k), l0), sol.time()[k]);
        de.update((energy(k) - e0).abs(), sol.time()[k]);
        nearest = nearest.min(v3(&sol, "body.phi", k)[1].cos().abs());
    }
    println!("|cos phi[2]| down to {nearest:.2e}; |L| = {:.3}, KE = {e0:.3}", norm(l0));
    assert!(nearest < 0.1, "the motion passes within the band of the singularity");
    dl.check("|L_world - L_world(0)|", "N.m.s", 1e-8 * norm(l0).max(1.0));
    de.check("|KE - KE(0)|", "J", 1e-8 * e0.max(1.0));
}

/// An Euler body started at its singular configuration (phi[2] = pi/2 for
/// the sequence [1, 2, 3]) cannot be simulated: the error (from assembly
/// or at t = 0) names the body, says it is the Euler singularity, and says
/// to use quaternions.
#[test]
fn euler_body_started_at_its_singularity_is_refused_with_its_name() {
    let model = euler_spinner([0.3, 0.0, 0.2], [0.1, PI / 2.0, -0.2]);
    let message = match model.assemble() {
        Err(e) => format!("assembly: {e}"),
        Ok(mechanism) => {
            let err = mechanism.simulate(&options(1.0, 0.01, 1e-8, 1e-8)).expect_err("the start is singular");
            assert_eq!(err.time, 0.0);
            format!("simulation: {err}")
        }
    };
    println!("Euler body started at the singularity: {message}");
    assert!(message.contains("`tumbler`"), "the message names the body: {message}");
    assert!(message.contains("Euler") && message.contains("singular"), "the message names the cause: {message}");
    assert!(message.contains("Quaternion"), "the message says how to fix it: {message}");
}
