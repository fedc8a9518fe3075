//! The behaviours of the PointMass seed (shared/seeds/PointMass.md).
//!
//! Expected values come from closed forms, conservation laws, forward
//! kinematics written here, finite differences of the engine's own
//! position signals, or a second formulation (a Body with zero inertia).
//!
//! Tolerances, and why:
//! - A polynomial solution (free fall) is reproduced exactly by Dormand-
//!   Prince 5(4) and its dense output: rounding only, 1e-9 of its size.
//! - Integrated solutions with `abstol = reltol = eps`: within `100 eps`
//!   of the signal's scale (each step's error is held to ~eps; a few
//!   hundred steps).
//! - Relations between outputs at one sample: rounding, 1e-12 of the scale.
//! - Finite differences (5-point stencils at h and 2h, Richardson-
//!   extrapolated) of samples accurate to `eps * scale`: 10 times the
//!   amplified sample error 1.65 eps scale / h, plus the truncation error
//!   estimated from the two step sizes (see `physics::check_derivative`).

#[path = "common/models.rs"]
mod models;
#[path = "common/physics.rs"]
mod physics;

use models::compare_runs;
use multibody::{Model, Solution};
use physics::*;
use std::f64::consts::PI;

/// An isroot point mass falls freely, in a World with a non-default
/// gravity direction and magnitude.
#[test]
fn isroot_point_mass_falls_freely() {
    let (g, n) = (3.7, [1.0, -2.0, 0.5]);
    let gravity = scale(g, normalize(n));
    let (r0, v0) = ([0.5, -1.0, 2.0], [1.0, 3.0, -0.5]);
    let mut model = Model::new("point_mass_fall");
    model.add("world", "World").set("g", g).set("n", n);
    model.add("pm", "PointMass").set("m", 0.3).set("isroot", true).initial("r_0", r0).initial("v_0", v0);
    let sol = run(&model, &options(2.0, 0.02, 1e-6, 1e-6));
    let t = sol.time();
    let exact = |k: usize| add(add(r0, scale(t[k], v0)), scale(0.5 * t[k] * t[k], gravity));
    // Exact quadratic: only rounding (|r| <= 15 m).
    worst_over(&sol, |k| dist(v3(&sol, "pm.r_0", k), exact(k))).check(
        "isroot fall: |r_0 - (r0 + v0 t + g n t^2/2)|",
        "m",
        1e-9,
    );
    worst_over(&sol, |k| dist(v3(&sol, "pm.v_0", k), add(v0, scale(t[k], gravity)))).check(
        "isroot fall: |v_0 - (v0 + g n t)|",
        "m/s",
        1e-9,
    );
    // Its acceleration is gravity; g_0 is g n (a relation at each sample).
    worst_over(&sol, |k| dist(v3(&sol, "pm.a_0", k), gravity)).check("isroot fall: |a_0 - g n|", "m/s2", 1e-12 * g);
    worst_over(&sol, |k| dist(v3(&sol, "pm.g_0", k), gravity)).check("isroot fall: |g_0 - g n|", "m/s2", 1e-12 * g);
    // Its frame keeps the world orientation; nothing holds it.
    worst_over(&sol, |k| mat_dist(&m3(&sol, "pm.frame_a.R", k), &IDENTITY)).check("isroot fall: |R - I|", "", 0.0);
    worst_over(&sol, |k| norm(v3(&sol, "pm.frame_a.f", k)) + norm(v3(&sol, "pm.frame_a.tau", k))).check(
        "isroot fall: |frame_a.f| + |frame_a.tau| (unconnected)",
        "N",
        1e-12 * g,
    );
}

/// An isroot point mass orbits in a point-gravity field (World mu = 1, a
/// circular orbit of radius 2 in the y-z plane), with point_gravity set on
/// the mass, or on the World for every mass.
#[test]
fn isroot_point_mass_orbits() {
    let (mu, radius): (f64, f64) = (1.0, 2.0);
    let speed = (mu / radius).sqrt();
    let period = 2.0 * PI * (radius.powi(3) / mu).sqrt();
    let eps = 1e-10;
    for on_world in [false, true] {
        let label = if on_world { "orbit (World point_gravity)" } else { "orbit (PointMass point_gravity)" };
        let mut model = Model::new("point_mass_orbit");
        model.add("world", "World").set("mu", mu).set("point_gravity", on_world);
        model
            .add("pm", "PointMass")
            .set("m", 0.4)
            .set("isroot", true)
            .set("point_gravity", !on_world)
            .initial("r_0", [0.0, 0.0, radius])
            .initial("v_0", [0.0, speed, 0.0]);
        let sol = run(&model, &options(period, period / 100.0, eps, eps));
        let r = |k| v3(&sol, "pm.r_0", k);
        let v = |k| v3(&sol, "pm.v_0", k);
        // Invariants: 100 eps relative.
        worst_over(&sol, |k| (norm(r(k)) - radius).abs() / radius).check(
            &format!("{label}: ||r| - r0| / r0"),
            "",
            100.0 * eps,
        );
        worst_over(&sol, |k| (norm(v(k)) - speed).abs() / speed).check(
            &format!("{label}: ||v| - v0| / v0"),
            "",
            100.0 * eps,
        );
        let energy = |k| 0.5 * dot(v(k), v(k)) - mu / norm(r(k));
        let e0 = -0.5 * speed * speed;
        worst_over(&sol, |k| (energy(k) - e0).abs() / e0.abs()).check(
            &format!("{label}: |E - E0| / |E0|"),
            "",
            100.0 * eps,
        );
        let l0 = cross([0.0, 0.0, radius], [0.0, speed, 0.0]);
        worst_over(&sol, |k| norm(sub(cross(r(k), v(k)), l0)) / norm(l0)).check(
            &format!("{label}: |r x v - L0| / |L0|"),
            "",
            100.0 * eps,
        );
        // Back at the start after one period (along-track error adds up over
        // the steps: 1000 eps).
        let last = sol.len() - 1;
        Worst { err: dist(r(last), [0.0, 0.0, radius]) / radius, t: sol.time()[last] }.check(
            &format!("{label}: |r(T) - r(0)| / r0"),
            "",
            1000.0 * eps,
        );
        // g_0 = -mu r / |r|^3, and the free mass accelerates with it (relations at each sample).
        let g_scale = mu / radius / radius;
        let field = |k| scale(-mu / norm(r(k)).powi(3), r(k));
        worst_over(&sol, |k| dist(v3(&sol, "pm.g_0", k), field(k))).check(
            &format!("{label}: |g_0 - (-mu r/|r|^3)|"),
            "m/s2",
            1e-12 * g_scale,
        );
        worst_over(&sol, |k| dist(v3(&sol, "pm.a_0", k), field(k))).check(
            &format!("{label}: |a_0 - (-mu r/|r|^3)|"),
            "m/s2",
            1e-12 * g_scale,
        );
    }
}

const ROD1: V3 = [0.5, 0.0, 0.0];
const ROD2: V3 = [0.4, 0.0, 0.1];
const AXIS1: V3 = [0.0, 0.0, 1.0];
const AXIS2: V3 = [0.0, 1.0, 1.0];
const M1: f64 = 1.1;
const M2: f64 = 0.7;

/// A 3-D double pendulum whose masses are point masses at the ends of rods
/// (`point_masses = true`) or Bodies with zero inertia and r_cm at the rod
/// ends.
fn double_pendulum(point_masses: bool) -> Model {
    let mut model = Model::new(if point_masses { "point_masses_on_rods" } else { "bodies_without_inertia" });
    model.add("world", "World");
    model.add("rev1", "Revolute").set("n", AXIS1).initial("phi", 0.5).initial("w", 0.0);
    model.add("rod1", "FixedTranslation").set("r", ROD1);
    model.add("rev2", "Revolute").set("n", AXIS2).initial("phi", -0.3).initial("w", 1.5);
    model.add("rod2", "FixedTranslation").set("r", ROD2);
    model.connect(["world.frame_b", "rev1.frame_a"]);
    model.connect(["rev1.frame_b", "rod1.frame_a"]);
    model.connect(["rod1.frame_b", "rev2.frame_a"]);
    model.connect(["rev2.frame_b", "rod2.frame_a"]);
    if point_masses {
        model.add("pm1", "PointMass").set("m", M1);
        model.add("pm2", "PointMass").set("m", M2);
        model.connect(["rod1.frame_b", "pm1.frame_a"]);
        model.connect(["rod2.frame_b", "pm2.frame_a"]);
    } else {
        for (name, m, r) in [("body1", M1, ROD1), ("body2", M2, ROD2)] {
            model.add(name, "Body").set("m", m).set("r_cm", r).set("I_11", 0.0).set("I_22", 0.0).set("I_33", 0.0);
        }
        model.connect(["rev1.frame_b", "body1.frame_a"]);
        model.connect(["rev2.frame_b", "body2.frame_a"]);
    }
    model
}

/// A mass at the end of a rod equals a Body with zero inertia and the same
/// r_cm: on a 3-D double pendulum, every joint coordinate agrees over 3 s.
#[test]
fn mass_on_a_rod_equals_a_body_with_zero_inertia() {
    let eps = 1e-10;
    let opts = options(3.0, 0.01, eps, eps);
    let a = run(&double_pendulum(true), &opts);
    let b = run(&double_pendulum(false), &opts);
    compare_runs("point masses vs zero-inertia bodies", &a, &b, &["rev1.phi", "rev1.w", "rev2.phi", "rev2.w"], eps);
    // And the masses are where the bodies' centres of mass are.
    for (pm, body, r) in [("pm1", "body1", ROD1), ("pm2", "body2", ROD2)] {
        worst_over(&a, |k| {
            let cm = add(v3(&b, &format!("{body}.r_0"), k), mat_t_vec(&m3(&b, &format!("{body}.frame_a.R"), k), r));
            dist(v3(&a, &format!("{pm}.r_0"), k), cm)
        })
        .check(&format!("point masses vs zero-inertia bodies: |{pm}.r_0 - {body} CM|"), "m", 100.0 * eps);
    }
}

/// The double pendulum of point masses, simulated finely for finite
/// differences.
fn fine_double_pendulum(h: f64, eps: f64) -> Solution {
    run(&double_pendulum(true), &options(3.0, h, eps, eps))
}

/// A point mass transmits no torque: pm.frame_a.tau is zero at every sample.
/// The rod carrying it balances the point mass's force alone:
/// rod2.frame_a.f = pm2.frame_a.f and rod2.frame_a.tau = r x pm2.frame_a.f
/// (massless rod, frames of equal orientation), while at rod1.frame_b, where
/// the second joint also acts, the torque is that joint's.
#[test]
fn point_mass_transmits_no_torque() {
    let sol = fine_double_pendulum(0.01, 1e-10);
    for pm in ["pm1", "pm2"] {
        worst_over(&sol, |k| norm(v3(&sol, &format!("{pm}.frame_a.tau"), k))).check(
            &format!("{pm}.frame_a.tau (exactly zero)"),
            "N.m",
            0.0,
        );
    }
    // Force scale: m (|a| + g) with |a| <= 20 m/s^2 here.
    let f_scale = M2 * 30.0;
    let tol = 1e-12 * f_scale;
    worst_over(&sol, |k| dist(v3(&sol, "rod2.frame_a.f", k), v3(&sol, "pm2.frame_a.f", k))).check(
        "rod2.frame_a.f - pm2.frame_a.f",
        "N",
        tol,
    );
    worst_over(&sol, |k| dist(v3(&sol, "rod2.frame_a.tau", k), cross(ROD2, v3(&sol, "pm2.frame_a.f", k)))).check(
        "rod2.frame_a.tau - r x pm2.frame_a.f",
        "N.m",
        tol * norm(ROD2),
    );
    worst_over(&sol, |k| norm(v3(&sol, "rod2.frame_b.tau", k))).check(
        "rod2.frame_b.tau (only the point mass acts there)",
        "N.m",
        tol,
    );
    // At rod1.frame_b the flows of rod1, pm1 and rev2 sum to zero; pm1 adds no torque.
    worst_over(&sol, |k| norm(add(v3(&sol, "rod1.frame_b.tau", k), v3(&sol, "rev2.frame_a.tau", k)))).check(
        "rod1.frame_b.tau + rev2.frame_a.tau",
        "N.m",
        tol,
    );
    let rev2_torque = sig(&sol, "rev2.frame_a.tau[1]").iter().fold(0.0f64, |a, x| a.max(x.abs()));
    println!("max |rev2.frame_a.tau[1]| = {rev2_torque:.3} N.m (the joint does carry torque)");
    assert!(rev2_torque > 1e-3, "the second joint should carry a torque across its axis");
}

/// PointMass variables: r_0 from forward kinematics written here, v_0 and
/// a_0 against finite differences of r_0 and v_0, g_0 = g n, and the force
/// on it m R (a_0 - g_0) with the differenced acceleration.
#[test]
fn point_mass_variables_are_right() {
    let (h, eps) = (1e-3, 1e-12);
    let sol = fine_double_pendulum(h, eps);
    let t = sol.time();
    let n = sol.len();
    let (phi1, phi2) = (sig(&sol, "rev1.phi"), sig(&sol, "rev2.phi"));
    // Forward kinematics: world -> rev1.frame_b is planar(n1, phi1); the rods
    // do not turn; rev2.frame_b is planar(n2, phi2) after that.
    let r1 = |k: usize| planar(AXIS1, phi1[k]);
    let r2 = |k: usize| mat_mul(&planar(AXIS2, phi2[k]), &r1(k));
    let p1 = |k: usize| mat_t_vec(&r1(k), ROD1);
    let p2 = |k: usize| add(p1(k), mat_t_vec(&r2(k), ROD2));
    worst_over(&sol, |k| dist(v3(&sol, "pm1.r_0", k), p1(k))).check("pm1.r_0 vs forward kinematics", "m", 1e-14);
    worst_over(&sol, |k| dist(v3(&sol, "pm2.r_0", k), p2(k))).check("pm2.r_0 vs forward kinematics", "m", 1e-14);
    worst_over(&sol, |k| mat_dist(&m3(&sol, "pm2.frame_a.R", k), &r2(k))).check(
        "pm2.frame_a.R vs forward kinematics",
        "",
        1e-14,
    );

    // Sample errors: eps times the scale (positions ~1 m, velocities < 10 m/s).
    let gravity = [0.0, -G, 0.0];
    for (pm, m) in [("pm1", M1), ("pm2", M2)] {
        let col = |name: &str| -> Vec<Vec<f64>> {
            (1..=3).map(|j| sig(&sol, &format!("{pm}.{name}[{j}]")).to_vec()).collect()
        };
        let (r, v, a) = (col("r_0"), col("v_0"), col("a_0"));
        check_derivative(&format!("{pm}.v_0 vs d/dt r_0"), "m/s", t, h, &r, &v, eps * 1.0);
        check_derivative(&format!("{pm}.a_0 vs d/dt v_0"), "m/s2", t, h, &v, &a, eps * 10.0);
        // frame_a.f = m R (a_0 - g_0), with the differenced acceleration.
        let (mut wf, mut wg) = (Worst::default(), Worst::default());
        let mut truncation = 0.0f64;
        for i in uniform_rows(t, h) {
            let mut fd_a = [0.0; 3];
            for j in 0..3 {
                let (d, trunc) = fd_richardson(&v[j], h, i);
                fd_a[j] = d;
                truncation = truncation.max(trunc);
            }
            let rot = m3(&sol, &format!("{pm}.frame_a.R"), i);
            let f = scale(m, mat_vec(&rot, sub(fd_a, gravity)));
            wf.update(dist(v3(&sol, &format!("{pm}.frame_a.f"), i), f), t[i]);
            wg.update(dist(v3(&sol, &format!("{pm}.g_0"), i), gravity), t[i]);
        }
        // Rotating a vector mixes its three components.
        let f_tol = m * 3.0 * (10.0 * FD_NOISE_GAIN * eps * 10.0 / h + truncation);
        wf.check(&format!("{pm}.frame_a.f vs m R (d/dt v_0 - g)"), "N", f_tol);
        wg.check(&format!("{pm}.g_0 vs g n"), "m/s2", 0.0);
    }
    assert!(n > 100);
}
