//! The closed-form cases of shared/reference/analytic/README.md that need
//! only World, Body, PointMass, FixedTranslation, FixedRotation, Fixed,
//! Revolute and Prismatic (items 1, 2, 3, 4, 6, 7 without FreeMotion, 8).
//!
//! Every expected value is computed here from a closed form, a conservation
//! law, an independent integration, or a second formulation of the same
//! physics; nothing is copied from the engine's output.
//!
//! Tolerances, and why:
//! - A polynomial solution (free fall) is reproduced exactly by Dormand-
//!   Prince 5(4) and its 4th-order dense output; only rounding remains, far
//!   below 1e-9 of the signal's size.
//! - For an integrated solution with `abstol = reltol = eps`, the error of
//!   each step is held to about `eps` (times the state's size), and the
//!   global error over the few hundred steps of these runs stays within
//!   `100 eps` of the signal's scale. We use that, `100 eps max(scale, 1)`.
//! - Algebraic relations evaluated at the same sample (cut forces from the
//!   state) only see rounding: 1e-12 of the force scale.

#[path = "common/models.rs"]
mod models;
#[path = "common/physics.rs"]
mod physics;

use models::{compare_runs, tumbling_body};
use multibody::{Model, OrientationState};
use multibody_reference::rk4;
use physics::*;
use std::f64::consts::PI;

// ------------------------------------------------------------ 1 free fall

const R0: V3 = [1.0, 2.0, -0.5];
const V0: V3 = [0.3, 4.0, -1.2];

/// `r0 + v0 t + g n t^2 / 2` with the default World (n = [0, -1, 0]).
fn free_fall_position(t: f64) -> V3 {
    add(add(R0, scale(t, V0)), scale(0.5 * t * t, [0.0, -G, 0.0]))
}
fn free_fall_velocity(t: f64) -> V3 {
    add(V0, scale(t, [0.0, -G, 0.0]))
}

/// Checks r_0, v_0 and the (constant) orientation of a free-falling
/// component over the run.
fn check_free_fall(label: &str, sol: &multibody::Solution, name: &str, r_expected: &M3, rot_tol: f64) {
    // Exact quadratic: only rounding (|r| <= 25 m over 2 s, ~1e-15 relative per step).
    let tol = 1e-9;
    let r = worst_over(sol, |k| dist(v3(sol, &format!("{name}.r_0"), k), free_fall_position(sol.time()[k])));
    r.check(&format!("{label}: |r_0 - (r0 + v0 t + g n t^2/2)|"), "m", tol);
    let v = worst_over(sol, |k| dist(v3(sol, &format!("{name}.v_0"), k), free_fall_velocity(sol.time()[k])));
    v.check(&format!("{label}: |v_0 - (v0 + g n t)|"), "m/s", tol);
    // The frame's own signal agrees with the component's variable.
    let rf = worst_over(sol, |k| dist(v3(sol, &format!("{name}.frame_a.r_0"), k), free_fall_position(sol.time()[k])));
    rf.check(&format!("{label}: |frame_a.r_0 - closed form|"), "m", tol);
    // Nothing turns it: the orientation stays the start orientation (rounding only).
    let rot = worst_over(sol, |k| mat_dist(&m3(sol, &format!("{name}.frame_a.R"), k), r_expected));
    rot.check(&format!("{label}: |frame_a.R - R(0)|"), "", rot_tol);
}

const FALL_TIME: f64 = 2.0;
const FALL_MASS: f64 = 1.5;
const FALL_I_MIN: f64 = 0.02;

/// Rounding bounds for the rotation of a free-falling body, which should
/// stay exactly zero: the dynamics works with forces whose moment arms reach
/// |r_0| <= 25 m, so a spurious angular acceleration of up to
/// eps_mach m g |r_0| / I_min can appear; over the run it adds up to
/// `w_tol` in w_a and `w_tol * T` in R.
fn rounding_of_free_fall() -> (f64, f64) {
    let w_tol = f64::EPSILON * FALL_MASS * G * 25.0 * FALL_TIME / FALL_I_MIN;
    (w_tol, w_tol * FALL_TIME + 1e-15)
}

fn free_fall_body(state: OrientationState) -> (Model, M3) {
    let phi0 = [0.3, -0.2, 0.5];
    let r_start = euler_r([1, 2, 3], phi0);
    let mut model = Model::new(format!("free_fall_{state:?}"));
    model.add("world", "World");
    let body = model
        .add("body", "Body")
        .set("m", FALL_MASS)
        .set("r_cm", [0.1, 0.2, -0.3])
        .set("I_11", FALL_I_MIN)
        .set("I_22", 0.03)
        .set("I_33", 0.04)
        .set("orientation_state", state)
        .initial("r_0", R0)
        .initial("v_0", V0);
    match state {
        OrientationState::Euler => {
            body.initial("phi", phi0);
        }
        OrientationState::Quaternion => {
            body.initial("Q_hat", quat_from_r(&r_start).to_vec());
        }
        OrientationState::None => unreachable!(),
    }
    (model, r_start)
}

#[test]
fn free_fall_of_root_body_with_euler_state() {
    let (model, r_start) = free_fall_body(OrientationState::Euler);
    let sol = run(&model, &options(FALL_TIME, 0.05, 1e-6, 1e-6));
    let (w_tol, rot_tol) = rounding_of_free_fall();
    check_free_fall("free fall, Euler Body", &sol, "body", &r_start, rot_tol);
    let w = worst_over(&sol, |k| norm(v3(&sol, "body.w_a", k)));
    w.check("free fall, Euler Body: |w_a| (stays 0)", "rad/s", w_tol);
}

#[test]
fn free_fall_of_root_body_with_quaternion_state() {
    let (model, r_start) = free_fall_body(OrientationState::Quaternion);
    let sol = run(&model, &options(FALL_TIME, 0.05, 1e-6, 1e-6));
    let (w_tol, rot_tol) = rounding_of_free_fall();
    check_free_fall("free fall, Quaternion Body", &sol, "body", &r_start, rot_tol);
    let w = worst_over(&sol, |k| norm(v3(&sol, "body.w_a", k)));
    w.check("free fall, Quaternion Body: |w_a| (stays 0)", "rad/s", w_tol);
}

#[test]
fn free_fall_of_root_point_mass() {
    let mut model = Model::new("free_fall_point_mass");
    model.add("world", "World");
    model.add("pm", "PointMass").set("m", 0.7).set("isroot", true).initial("r_0", R0).initial("v_0", V0);
    let sol = run(&model, &options(FALL_TIME, 0.05, 1e-6, 1e-6));
    // A root point mass's frame has the world's orientation, exactly.
    check_free_fall("free fall, root PointMass", &sol, "pm", &IDENTITY, 0.0);
}

// -------------------------------------------------------- 2 circular orbit

/// Radius 7e6 m, speed sqrt(mu / r); in the x-y plane.
const ORBIT_R: f64 = 7e6;

/// Tolerances of the orbit runs. reltol = 1e-10 holds every state to ~1e-10
/// of its size: positions (7e6 m) to ~7e-4 m, velocities (7.5e3 m/s) to
/// ~7.5e-7 m/s. abstol is shared by metres and metres per second, so it must
/// not exceed the velocity scale 7.5e-7 m/s or it would loosen the velocity
/// control; 1e-6 is of that order and negligible for positions.
const ORBIT_ABSTOL: f64 = 1e-6;
const ORBIT_RELTOL: f64 = 1e-10;

fn check_orbit(label: &str, sol: &multibody::Solution, name: &str, m: f64) {
    let v_circ = (MU / ORBIT_R).sqrt();
    let period = 2.0 * PI * (ORBIT_R.powi(3) / MU).sqrt();
    assert!((period - 5828.5).abs() < 0.1, "period {period} (README: 5828.5 s)");
    let r = |k| v3(sol, &format!("{name}.r_0"), k);
    let v = |k| v3(sol, &format!("{name}.v_0"), k);
    let energy = |k| 0.5 * m * dot(v(k), v(k)) - MU * m / norm(r(k));
    let momentum = |k| scale(m, cross(r(k), v(k)));
    let (e0, l0) = (-0.5 * m * v_circ * v_circ, [0.0, 0.0, m * ORBIT_R * v_circ]);
    // Invariants: 100 reltol relative (see the file header).
    let tol = 100.0 * ORBIT_RELTOL;
    worst_over(sol, |k| (norm(r(k)) - ORBIT_R).abs() / ORBIT_R).check(
        &format!("{label}: ||r_0| - 7e6| / 7e6"),
        "",
        tol,
    );
    worst_over(sol, |k| (norm(v(k)) - v_circ).abs() / v_circ).check(&format!("{label}: ||v_0| - v| / v"), "", tol);
    worst_over(sol, |k| (energy(k) - e0).abs() / e0.abs()).check(
        &format!("{label}: |E - E0| / |E0|, E = KE - mu m/|r|"),
        "",
        tol,
    );
    worst_over(sol, |k| norm(sub(momentum(k), l0)) / norm(l0)).check(
        &format!("{label}: |r x m v - L0| / |L0|"),
        "",
        tol,
    );
    // After one period it is back at the start. The along-track (phase)
    // error is not restored by the dynamics and adds up over the ~10^3
    // steps: allow 1000 reltol.
    let last = sol.len() - 1;
    let t_end = sol.time()[last];
    assert!((t_end - period).abs() < 1e-6 * period, "last sample at {t_end}, period {period}");
    let back = dist(r(last), [ORBIT_R, 0.0, 0.0]) / ORBIT_R;
    let w = Worst { err: back, t: t_end };
    w.check(&format!("{label}: |r_0(T) - r_0(0)| / r after one period"), "", 1000.0 * ORBIT_RELTOL);
    let w = Worst { err: dist(v(last), [0.0, v_circ, 0.0]) / v_circ, t: t_end };
    w.check(&format!("{label}: |v_0(T) - v_0(0)| / v after one period"), "", 1000.0 * ORBIT_RELTOL);
}

fn orbit_options() -> multibody::SimulationOptions {
    let period = 2.0 * PI * (ORBIT_R.powi(3) / MU).sqrt();
    options(period, period / 100.0, ORBIT_ABSTOL, ORBIT_RELTOL)
}

#[test]
fn circular_orbit_of_root_point_mass() {
    let v_circ = (MU / ORBIT_R).sqrt();
    let mut model = Model::new("orbit_point_mass");
    model.add("world", "World");
    model
        .add("sat", "PointMass")
        .set("m", 3.0)
        .set("isroot", true)
        .set("point_gravity", true)
        .initial("r_0", [ORBIT_R, 0.0, 0.0])
        .initial("v_0", [0.0, v_circ, 0.0]);
    let sol = run(&model, &orbit_options());
    check_orbit("orbit, root PointMass", &sol, "sat", 3.0);
}

#[test]
fn circular_orbit_of_root_body() {
    let v_circ = (MU / ORBIT_R).sqrt();
    let mut model = Model::new("orbit_body");
    model.add("world", "World");
    model
        .add("sat", "Body")
        .set("m", 2.5)
        .set("orientation_state", OrientationState::Quaternion)
        .set("point_gravity", true)
        .initial("r_0", [ORBIT_R, 0.0, 0.0])
        .initial("v_0", [0.0, v_circ, 0.0]);
    let sol = run(&model, &orbit_options());
    check_orbit("orbit, root Body", &sol, "sat", 2.5);
}

// ----------------------------------------------------- 3 spinning body

/// A Body spinning at w_a = e_axis with g = 0, with Quaternion state and with
/// Euler state (a sequence starting with the spin axis, so that the motion
/// stays away from the Euler singularity): frame_a.R = A_axis(t).
fn spin_model(axis: usize, state: OrientationState) -> Model {
    let mut model = Model::new(format!("spin_{axis}_{state:?}"));
    model.add("world", "World").set("g", 0.0);
    let body = model.add("body", "Body").set("orientation_state", state);
    match state {
        OrientationState::Quaternion => {
            body.initial("w_a", e(axis));
        }
        OrientationState::Euler => {
            let sequence = [axis, axis % 3 + 1, (axis + 1) % 3 + 1];
            body.set("sequence", sequence.map(|a| a as i32)).initial("phid", [1.0, 0.0, 0.0]);
        }
        OrientationState::None => unreachable!(),
    }
    model
}

#[test]
fn spinning_body_orientation_follows_axis_rotation() {
    // DESIGN.md's sign check first: w_a = [1, 0, 0] for pi/2 s gives
    // R = [1 0 0; 0 0 1; 0 -1 0].
    let at_quarter = run(&spin_model(1, OrientationState::Quaternion), &options(PI / 2.0, 0.0, 1e-10, 1e-10));
    let r_end = m3(&at_quarter, "body.frame_a.R", at_quarter.len() - 1);
    let w = Worst { err: mat_dist(&r_end, &[[1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, -1.0, 0.0]]), t: PI / 2.0 };
    w.check("spin about x for pi/2 s: |R - [1 0 0; 0 0 1; 0 -1 0]|", "", 1e-8);

    let eps = 1e-10;
    let tol = 100.0 * eps; // R entries are of size 1
    for axis in 1..=3 {
        let q = run(&spin_model(axis, OrientationState::Quaternion), &options(2.0 * PI, 0.05, eps, eps));
        let eu = run(&spin_model(axis, OrientationState::Euler), &options(2.0 * PI, 0.05, eps, eps));
        assert_eq!(q.time(), eu.time());
        for (label, sol) in [("Quaternion", &q), ("Euler", &eu)] {
            worst_over(sol, |k| mat_dist(&m3(sol, "body.frame_a.R", k), &a_axis(axis, sol.time()[k]))).check(
                &format!("spin about axis {axis}, {label}: |frame_a.R - A_{axis}(t)|"),
                "",
                tol,
            );
            worst_over(sol, |k| dist(v3(sol, "body.w_a", k), e(axis))).check(
                &format!("spin about axis {axis}, {label}: |w_a - e_{axis}|"),
                "rad/s",
                tol,
            );
        }
        worst_over(&q, |k| mat_dist(&m3(&q, "body.frame_a.R", k), &m3(&eu, "body.frame_a.R", k))).check(
            &format!("spin about axis {axis}: |R_quaternion - R_euler|"),
            "",
            tol,
        );
    }
}

// ------------------------------------------------ 4 torque-free symmetric top

#[test]
fn torque_free_symmetric_top() {
    let (i1, i3, a, b) = (0.1, 0.3, 1.0, 2.0);
    let inertia = [[i1, 0.0, 0.0], [0.0, i1, 0.0], [0.0, 0.0, i3]];
    let mut model = Model::new("symmetric_top");
    model.add("world", "World").set("g", 0.0);
    model
        .add("top", "Body")
        .set("m", 2.0)
        .set("I_11", i1)
        .set("I_22", i1)
        .set("I_33", i3)
        .set("orientation_state", OrientationState::Quaternion)
        .initial("Q_hat", quat_from_r(&euler_r([1, 2, 3], [0.2, -0.4, 0.1])).to_vec())
        .initial("w_a", [a, 0.0, b]);
    let eps = 1e-10;
    let sol = run(&model, &options(3.0, 0.01, eps, eps));
    // I1 w1' = (I1 - I3) w2 w3, I1 w2' = (I3 - I1) w3 w1: with w3 = b the
    // pair (w1, w2) = a (cos Wt, sin Wt), W = (I3 - I1) b / I1.
    let rate = (i3 - i1) * b / i1;
    let tol = 100.0 * eps * b; // |w| <= |[a, 0, b]| ~ b
    worst_over(&sol, |k| (v3(&sol, "top.w_a", k)[2] - b).abs()).check("symmetric top: |w_a[3] - b|", "rad/s", tol);
    worst_over(&sol, |k| {
        let t = sol.time()[k];
        dist(v3(&sol, "top.w_a", k), [a * (rate * t).cos(), a * (rate * t).sin(), b])
    })
    .check("symmetric top: |w_a - (a cos Wt, a sin Wt, b)|", "rad/s", tol);
    // World angular momentum R' I w_a and kinetic energy are constant.
    let l = |k| mat_t_vec(&m3(&sol, "top.frame_a.R", k), mat_vec(&inertia, v3(&sol, "top.w_a", k)));
    let ke = |k| 0.5 * dot(v3(&sol, "top.w_a", k), mat_vec(&inertia, v3(&sol, "top.w_a", k)));
    let (l0, ke0) = (l(0), ke(0));
    worst_over(&sol, |k| norm(sub(l(k), l0)) / norm(l0)).check("symmetric top: |R' I w - L0| / |L0|", "", 100.0 * eps);
    worst_over(&sol, |k| (ke(k) - ke0).abs() / ke0).check("symmetric top: |KE - KE0| / KE0", "", 100.0 * eps);
    // The body's own KE output is the same energy.
    worst_over(&sol, |k| (sig(&sol, "top.KE")[k] - ke0).abs() / ke0).check(
        "symmetric top: |top.KE - KE0| / KE0",
        "",
        100.0 * eps,
    );
}

// --------------------------------------------------------------- 6 pendulum

#[test]
fn pendulum_matches_independent_integration_and_conserves_energy() {
    let (m, l, i33) = (1.0, 0.5, 0.01);
    let j = i33 + m * l * l;
    let mut model = Model::new("pendulum");
    model.add("world", "World");
    model.add("rev", "Revolute").set("n", [0.0, 0.0, 1.0]);
    model.add("body", "Body").set("m", m).set("r_cm", [l, 0.0, 0.0]).set("I_33", i33);
    model.connect(["world.frame_b", "rev.frame_a"]);
    model.connect(["rev.frame_b", "body.frame_a"]);
    let (stop, saveat, eps) = (3.0, 0.005, 1e-10);
    let sol = run(&model, &options(stop, saveat, eps, eps));

    // J phi'' = -m g l cos(phi), by RK4 with dt = saveat / 50 = 1e-4 s: its
    // global error ~ dt^4 |phi^(5)| T is below 1e-12 here.
    let samples = (stop / saveat).round() as usize + 1;
    let reference = rk4(|y: &[f64; 2]| [y[1], -m * G * l * y[0].cos() / j], [0.0, 0.0], saveat / 50.0, samples, 50);
    assert!(sol.len() >= samples);
    let w_max = (2.0 * m * G * l / j).sqrt(); // speed at the bottom
    worst_over(&sol, |k| if k < samples { (sig(&sol, "rev.phi")[k] - reference[k][0]).abs() } else { 0.0 }).check(
        "pendulum: |phi - phi_rk4|",
        "rad",
        100.0 * eps * PI,
    );
    worst_over(&sol, |k| if k < samples { (sig(&sol, "rev.w")[k] - reference[k][1]).abs() } else { 0.0 }).check(
        "pendulum: |w - w_rk4|",
        "rad/s",
        100.0 * eps * w_max,
    );

    // Energy: body.KE + body.PE stays at its start value 0 (at rest, CM at y = 0).
    let scale_e = m * G * l;
    worst_over(&sol, |k| (sig(&sol, "body.KE")[k] + sig(&sol, "body.PE")[k]).abs() / scale_e).check(
        "pendulum: |KE + PE - E0| / (m g l)",
        "",
        100.0 * eps,
    );

    // Started horizontal at rest it swings between 0 and -pi. The nearest
    // sample is at most saveat/2 from the turning point, where
    // phi'' = m g l / J: it lies within (m g l / J) (saveat/2)^2 / 2 of -pi.
    let phi = sig(&sol, "rev.phi");
    let (lo, hi) = phi.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &x| (a.min(x), b.max(x)));
    let tol = 100.0 * eps * PI;
    Worst { err: hi.max(0.0), t: f64::NAN }.check("pendulum: max(phi) above 0", "rad", tol);
    Worst { err: (-PI - lo).max(0.0), t: f64::NAN }.check("pendulum: min(phi) below -pi", "rad", tol);
    let sampling = 0.5 * m * G * l / j * (saveat / 2.0).powi(2);
    Worst { err: (lo + PI).abs(), t: f64::NAN }.check("pendulum: |min(phi) + pi|", "rad", sampling + tol);
}

// ------------------------------------------------------ 7 equivalent models

/// (a) A PointMass at the end of a FixedTranslation, and a Body with zero
/// inertia and the same r_cm, on a Revolute pendulum.
#[test]
fn point_mass_on_rod_equals_body_with_zero_inertia() {
    let (m, r) = (1.7, [0.7, 0.0, 0.2]);
    let axis = [0.0, 0.3, 1.0];
    let base = |name: &str| {
        let mut model = Model::new(name);
        model.add("world", "World");
        model.add("rev", "Revolute").set("n", axis).initial("phi", 0.3).initial("w", -1.0);
        model.connect(["world.frame_b", "rev.frame_a"]);
        model
    };
    let mut with_point = base("point_mass_on_rod");
    with_point.add("rod", "FixedTranslation").set("r", r);
    with_point.add("pm", "PointMass").set("m", m);
    with_point.connect(["rev.frame_b", "rod.frame_a"]);
    with_point.connect(["rod.frame_b", "pm.frame_a"]);
    let mut with_body = base("body_without_inertia");
    with_body.add("body", "Body").set("m", m).set("r_cm", r).set("I_11", 0.0).set("I_22", 0.0).set("I_33", 0.0);
    with_body.connect(["rev.frame_b", "body.frame_a"]);

    let eps = 1e-10;
    let opts = options(3.0, 0.01, eps, eps);
    let (a, b) = (run(&with_point, &opts), run(&with_body, &opts));
    assert_eq!(a.time(), b.time());
    worst_over(&a, |k| (sig(&a, "rev.phi")[k] - sig(&b, "rev.phi")[k]).abs()).check(
        "point mass vs zero-inertia body: |phi_a - phi_b|",
        "rad",
        100.0 * eps * PI,
    );
    let w_scale = sig(&a, "rev.w").iter().fold(1.0f64, |s, x| s.max(x.abs()));
    worst_over(&a, |k| (sig(&a, "rev.w")[k] - sig(&b, "rev.w")[k]).abs()).check(
        "point mass vs zero-inertia body: |w_a - w_b|",
        "rad/s",
        100.0 * eps * w_scale,
    );
    // The mass is at the same place: pm.r_0 = body.r_0 + R' r_cm.
    worst_over(&a, |k| {
        let cm = add(v3(&b, "body.r_0", k), mat_t_vec(&m3(&b, "body.frame_a.R", k), r));
        dist(v3(&a, "pm.r_0", k), cm)
    })
    .check("point mass vs zero-inertia body: |r_pm - r_cm|", "m", 100.0 * eps * norm(r) * PI);
}

/// (b) Euler and quaternion states of a free Body give the same motion.
#[test]
fn free_body_euler_and_quaternion_states_agree() {
    let eps = 1e-10;
    let opts = options(2.0, 0.01, eps, eps);
    let eu = run(&tumbling_body(OrientationState::Euler, [0.0; 3], G), &opts);
    let q = run(&tumbling_body(OrientationState::Quaternion, [0.0; 3], G), &opts);
    // Precondition: the Euler run stays away from its singularity (|phi2| = pi/2).
    let phi2_max = sig(&eu, "body.phi[2]").iter().fold(0.0f64, |a, x| a.max(x.abs()));
    println!("tumbling body: max |phi[2]| = {phi2_max:.3} rad (singular at {:.3})", PI / 2.0);
    assert!(phi2_max < 1.3);
    let signals = ["body.r_0", "body.v_0", "body.w_a", "body.frame_a.R"];
    compare_runs("tumbling body, Euler vs Quaternion", &eu, &q, &signals, eps);
}

/// The 3-D double pendulum of the rotated-world test: world.frame_b (or a
/// FixedRotation from it) -> rev1 (about z) -> body1 and rod -> rev2 (about
/// [0, 1, 1]) -> body2.
fn double_pendulum(rotation: Option<(V3, f64)>) -> Model {
    let mut model = Model::new("double_pendulum_3d");
    let base = match rotation {
        None => {
            model.add("world", "World");
            "world.frame_b"
        }
        Some((n, angle)) => {
            // Gravity rotated with the geometry: in the base frame it is [0, -1, 0].
            let rot = planar(n, angle);
            model.add("world", "World").set("n", mat_t_vec(&rot, [0.0, -1.0, 0.0]).to_vec());
            model.add("base", "FixedRotation").set("n", n).set("angle", angle);
            model.connect(["world.frame_b", "base.frame_a"]);
            "base.frame_b"
        }
    };
    model.add("rev1", "Revolute").set("n", [0.0, 0.0, 1.0]).initial("phi", 0.4).initial("w", 0.5);
    model
        .add("body1", "Body")
        .set("m", 1.2)
        .set("r_cm", [0.3, 0.05, 0.0])
        .set("I_11", 0.01)
        .set("I_22", 0.02)
        .set("I_33", 0.02);
    model.add("rod", "FixedTranslation").set("r", [0.6, 0.0, 0.1]);
    model.add("rev2", "Revolute").set("n", [0.0, 1.0, 1.0]).initial("phi", -0.7).initial("w", 1.0);
    model
        .add("body2", "Body")
        .set("m", 0.8)
        .set("r_cm", [0.4, 0.0, -0.1])
        .set("I_11", 0.005)
        .set("I_22", 0.01)
        .set("I_33", 0.012);
    model.connect([base, "rev1.frame_a"]);
    model.connect(["rev1.frame_b", "body1.frame_a", "rod.frame_a"]);
    model.connect(["rod.frame_b", "rev2.frame_a"]);
    model.connect(["rev2.frame_b", "body2.frame_a"]);
    model
}

/// (c) The same model with the whole world rotated: joint coordinates are
/// equal, positions rotate.
#[test]
fn rotating_the_whole_world_rotates_positions_and_keeps_joint_coordinates() {
    let (n, angle) = ([1.0, 2.0, 3.0], 0.7);
    let rot = planar(n, angle); // world -> base frame
    let eps = 1e-10;
    let opts = options(3.0, 0.01, eps, eps);
    let plain = run(&double_pendulum(None), &opts);
    let turned = run(&double_pendulum(Some((n, angle))), &opts);
    assert_eq!(plain.time(), turned.time());
    let w_scale = ["rev1.w", "rev2.w"].iter().flat_map(|s| sig(&plain, s).iter()).fold(1.0f64, |a, x| a.max(x.abs()));
    for (name, unit, scale_) in
        [("rev1.phi", "rad", PI), ("rev2.phi", "rad", PI), ("rev1.w", "rad/s", w_scale), ("rev2.w", "rad/s", w_scale)]
    {
        worst_over(&plain, |k| (sig(&plain, name)[k] - sig(&turned, name)[k]).abs()).check(
            &format!("rotated world: |{name} - {name}_rotated|"),
            unit,
            100.0 * eps * scale_,
        );
    }
    for body in ["body1", "body2"] {
        // r_rotated = R' r (positions about the world origin, where the base sits).
        worst_over(&plain, |k| {
            dist(
                v3(&turned, &format!("{body}.frame_a.r_0"), k),
                mat_t_vec(&rot, v3(&plain, &format!("{body}.frame_a.r_0"), k)),
            )
        })
        .check(&format!("rotated world: |{body}.r_0_rotated - R' {body}.r_0|"), "m", 100.0 * eps * 2.0);
        // world -> body = (base -> body)(world -> base).
        worst_over(&plain, |k| {
            mat_dist(
                &m3(&turned, &format!("{body}.frame_a.R"), k),
                &mat_mul(&m3(&plain, &format!("{body}.frame_a.R"), k), &rot),
            )
        })
        .check(&format!("rotated world: |{body}.R_rotated - {body}.R R_base|"), "", 100.0 * eps);
    }
}

// ---------------------------------------------------------- 8 cut forces

/// A Body (r_cm = 0) at the end of a rod, hanging straight down from a
/// Revolute at rest: its connection holds it with m g upwards.
#[test]
fn cut_forces_of_a_body_hanging_at_rest() {
    let (m, l) = (2.3, 0.8);
    let mut model = Model::new("hanging_body");
    model.add("world", "World");
    // The rod lies along frame_b's x axis; phi = -pi/2 turns it straight down.
    model.add("rev", "Revolute").set("n", [0.0, 0.0, 1.0]).initial("phi", -PI / 2.0);
    model.add("rod", "FixedTranslation").set("r", [l, 0.0, 0.0]);
    model.add("body", "Body").set("m", m).set("I_11", 0.01).set("I_22", 0.02).set("I_33", 0.03);
    model.connect(["world.frame_b", "rev.frame_a"]);
    model.connect(["rev.frame_b", "rod.frame_a"]);
    model.connect(["rod.frame_b", "body.frame_a"]);
    let sol = run(&model, &options(1.0, 0.05, 1e-10, 1e-10));

    let r_body = a_z(-PI / 2.0);
    let g0 = [0.0, -G, 0.0];
    let f_expected = scale(-m, mat_vec(&r_body, g0)); // -m R g_0: m g upwards, in frame_a
    let tol = 1e-12 * m * G;
    // It stays at rest where it hangs.
    worst_over(&sol, |k| (sig(&sol, "rev.phi")[k] + PI / 2.0).abs()).check("hanging body: |phi + pi/2|", "rad", 1e-12);
    worst_over(&sol, |k| dist(v3(&sol, "body.r_0", k), [0.0, -l, 0.0])).check(
        "hanging body: |r_0 - [0, -l, 0]|",
        "m",
        1e-12,
    );
    worst_over(&sol, |k| dist(v3(&sol, "body.frame_a.f", k), f_expected)).check(
        "hanging body: |body.frame_a.f - (-m R g_0)|",
        "N",
        tol,
    );
    worst_over(&sol, |k| norm(v3(&sol, "body.frame_a.tau", k))).check("hanging body: |body.frame_a.tau|", "N.m", tol);
    // The joint's frame_b has body's orientation (the rod does not turn):
    // the force on it is the opposite; along the rod there is no torque.
    worst_over(&sol, |k| dist(v3(&sol, "rev.frame_b.f", k), scale(-1.0, f_expected))).check(
        "hanging body: |rev.frame_b.f + body.frame_a.f_expected|",
        "N",
        tol,
    );
    worst_over(&sol, |k| norm(v3(&sol, "rev.frame_b.tau", k))).check("hanging body: |rev.frame_b.tau|", "N.m", tol * l);
    // The world holds the joint up: rev.frame_a.f (world orientation) = m g up.
    worst_over(&sol, |k| dist(v3(&sol, "rev.frame_a.f", k), [0.0, m * G, 0.0])).check(
        "hanging body: |rev.frame_a.f - [0, m g, 0]|",
        "N",
        tol,
    );
}

/// A Body on a vertical Prismatic held by a spring at its equilibrium.
#[test]
fn cut_forces_of_a_body_held_by_a_spring_on_a_prismatic() {
    let (m, c, s0) = (2.0, 200.0, 0.5);
    let r_cm = [0.1, 0.0, 0.0];
    // -c (s - s0) - m g = 0
    let s_eq = s0 - m * G / c;
    let mut model = Model::new("spring_prismatic");
    model.add("world", "World");
    model.add("slider", "Prismatic").set("n", [0.0, 1.0, 0.0]).set("axisflange", true).initial("s", s_eq);
    model.add("spring", "TranslationalComponents.Spring").set("c", c).set("s_rel0", s0);
    model.add("body", "Body").set("m", m).set("r_cm", r_cm);
    model.connect(["world.frame_b", "slider.frame_a"]);
    model.connect(["slider.frame_b", "body.frame_a"]);
    model.connect(["spring.flange_a", "slider.support"]);
    model.connect(["spring.flange_b", "slider.axis"]);
    let sol = run(&model, &options(1.0, 0.05, 1e-10, 1e-10));

    let tol = 1e-12 * m * G;
    // At rest at the equilibrium (the residual force is rounding, ~1e-15 N).
    worst_over(&sol, |k| (sig(&sol, "slider.s")[k] - s_eq).abs()).check("spring on prismatic: |s - s_eq|", "m", 1e-12);
    // frame_a keeps the world orientation: -m R g_0 = [0, m g, 0]; the
    // torque holds the offset centre of mass: r_cm x f.
    let f_expected = [0.0, m * G, 0.0];
    worst_over(&sol, |k| dist(v3(&sol, "body.frame_a.f", k), f_expected)).check(
        "spring on prismatic: |body.frame_a.f - [0, m g, 0]|",
        "N",
        tol,
    );
    worst_over(&sol, |k| dist(v3(&sol, "body.frame_a.tau", k), cross(r_cm, f_expected))).check(
        "spring on prismatic: |body.frame_a.tau - r_cm x f|",
        "N.m",
        tol,
    );
    worst_over(&sol, |k| dist(v3(&sol, "slider.frame_b.f", k), scale(-1.0, f_expected))).check(
        "spring on prismatic: |slider.frame_b.f + [0, m g, 0]|",
        "N",
        tol,
    );
    // The spring carries the weight: its force c (s - s0) = -m g, and the
    // joint's drive force from it is +m g along n.
    worst_over(&sol, |k| (sig(&sol, "spring.f")[k] + m * G).abs()).check(
        "spring on prismatic: |spring.f + m g|",
        "N",
        tol,
    );
    worst_over(&sol, |k| (sig(&sol, "slider.f")[k] - m * G).abs()).check(
        "spring on prismatic: |slider.f - m g|",
        "N",
        tol,
    );
}
