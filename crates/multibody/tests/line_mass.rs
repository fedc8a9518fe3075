//! A spring with mass (`Spring(hasmass = true, m, lengthfraction)`, Modelica's
//! Spring wrapping LineForceWithMass): the point mass sits on the line at
//! `r_a + h (r_b - r_a)`; it is no degree of freedom, and its inertia and
//! weight are shared by the two ends (shared/reference/msl/SpringWithMass.md).
//!
//! Expected values come from closed forms and conservation laws, never from
//! the engine's own output.
//!
//! Tolerances: the runs use `abstol = reltol = eps`; the error of each step
//! is held to about `eps` times the state's size, and the global error of
//! these runs (a few hundred to a few thousand steps) stays within
//! `100 eps` of the signal's scale (as in analytic.rs); conservation laws
//! get the same bound relative to the energy or momentum scale.

#[path = "common/physics.rs"]
mod physics;

use multibody::{Model, OrientationState};
use physics::*;

/// SpringWithMass.md: a body m_b = 1 hanging from the world origin on a
/// spring (c = 40, s_unstretched = 0.2) with 0.5 kg at its middle; from
/// rest at y = -0.3. With a_a = 0, `(m_b + m h^2) y'' = -(m_b + m h) g -
/// c (y + 0.2)`: y(t) = y_eq + (-0.3 - y_eq) cos(w t), with
/// y_eq = -0.2 - (m_b + m h) g / c and w = sqrt(c / (m_b + m h^2)).
#[test]
fn hanging_spring_with_mass_follows_the_closed_form() {
    let (c, s0, m, h, m_b) = (40.0, 0.2, 0.5, 0.5, 1.0);
    let mut model = Model::new("SpringWithMass");
    model.add("world", "World");
    model.add("spring", "Spring").set("c", c).set("s_unstretched", s0).set("hasmass", true).set("m", m);
    model
        .add("body", "Body")
        .set("m", m_b)
        .set("r_cm", [0.0, 0.0, 0.0])
        .set("orientation_state", OrientationState::Quaternion)
        .initial("r_0", [0.0, -0.3, 0.0])
        .initial("v_0", [0.0, 0.0, 0.0])
        .initial("w_a", [0.0, 0.0, 0.0]);
    model.connect(["world.frame_b", "spring.frame_a"]);
    model.connect(["spring.frame_b", "body.frame_a"]);
    let eps = 1e-10;
    let sol = run(&model, &options(5.0, 0.01, eps, eps));

    let y_eq = -s0 - (m_b + m * h) * G / c;
    let w = (c / (m_b + m * h * h)).sqrt();
    let amplitude = -0.3 - y_eq;
    // The description's numbers: y_eq = -0.5064578, w = 5.962848.
    assert!((y_eq + 0.5064578).abs() < 1e-7 && (w - 5.962848).abs() < 1e-6);
    let tol_y = 100.0 * eps * 1.0;
    let tol_v = 100.0 * eps * (amplitude * w).max(1.0);
    worst_over(&sol, |k| {
        let t = sol.time()[k];
        (v3(&sol, "body.frame_a.r_0", k)[1] - (y_eq + amplitude * (w * t).cos())).abs()
    })
    .check("hanging spring with mass: |y - y(t)|", "m", tol_y);
    worst_over(&sol, |k| {
        let t = sol.time()[k];
        (v3(&sol, "body.v_0", k)[1] + amplitude * w * (w * t).sin()).abs()
    })
    .check("hanging spring with mass: |v - v(t)|", "m/s", tol_v);
    // x, z and the rotation stay exactly at rest: the force passes through the CM.
    worst_over(&sol, |k| {
        let (r, v, w_a) = (v3(&sol, "body.frame_a.r_0", k), v3(&sol, "body.v_0", k), v3(&sol, "body.w_a", k));
        [r[0], r[2], v[0], v[2], w_a[0], w_a[1], w_a[2]].iter().fold(0.0f64, |a, x| a.max(x.abs()))
    })
    .check("hanging spring with mass: |x|, |z|, |v_x|, |v_z|, |w_a|", "", 1e-12);
    // The point mass's outputs: on the line at its middle.
    worst_over(&sol, |k| dist(v3(&sol, "spring.r_CM_0", k), scale(h, v3(&sol, "body.frame_a.r_0", k)))).check(
        "hanging spring with mass: |r_CM_0 - h r_body|",
        "m",
        1e-14,
    );
    // The cut force on the body at frame_a (it does not turn, so world y):
    // the spring's line force c (|y| - s0) upwards, less the point mass's
    // share m h (a_m - g) with a_m = h a, from the closed form.
    worst_over(&sol, |k| {
        let t = sol.time()[k];
        let y = y_eq + amplitude * (w * t).cos();
        let a = -amplitude * w * w * (w * t).cos();
        let from_spring = c * (-y - s0) - m * h * (h * a + G);
        (sig(&sol, "body.frame_a.f[2]")[k] - from_spring).abs()
    })
    .check("hanging spring with mass: body.frame_a.f[2]", "N", 100.0 * eps * (c + m_b * w * w));
}

/// Two free bodies in zero gravity joined by a spring with mass at h = 0.3,
/// spinning and tumbling: kinetic energy (the bodies' and the point mass's
/// `m |v_m|^2 / 2`, with `v_m = (1 - h) v_a + h v_b`) plus the spring's
/// energy stays constant, and so does the linear momentum, point mass
/// included.
#[test]
fn free_bodies_on_a_spring_with_mass_conserve_energy_and_momentum() {
    let (c, s0, m, h) = (30.0, 0.4, 0.7, 0.3);
    let (m1, m2) = (1.2, 0.8);
    let mut model = Model::new("free_pair");
    model.add("world", "World").set("g", 0.0);
    model
        .add("spring", "Spring")
        .set("c", c)
        .set("s_unstretched", s0)
        .set("hasmass", true)
        .set("m", m)
        .set("lengthfraction", h);
    // Frames at r_cm offsets from the CMs, so the line force turns the bodies.
    for (name, mass, r0, v0, w0, r_cm) in [
        ("body1", m1, [0.0, 0.0, 0.0], [0.1, -0.3, 0.2], [0.5, -1.0, 2.0], [0.1, -0.05, 0.02]),
        ("body2", m2, [0.6, 0.2, -0.1], [-0.4, 0.5, 0.1], [-1.5, 0.3, 0.7], [-0.05, 0.1, 0.08]),
    ] {
        model
            .add(name, "Body")
            .set("m", mass)
            .set("r_cm", r_cm)
            .set("I_11", 0.02)
            .set("I_22", 0.03)
            .set("I_33", 0.04)
            .set("I_21", 0.005)
            .set("orientation_state", OrientationState::Quaternion)
            .initial("r_0", r0)
            .initial("v_0", v0)
            .initial("w_a", w0);
    }
    model.connect(["spring.frame_a", "body1.frame_a"]);
    model.connect(["spring.frame_b", "body2.frame_a"]);
    let eps = 1e-10;
    let sol = run(&model, &options(3.0, 0.005, eps, eps));

    let point_mass_velocity = |k| add(scale(1.0 - h, v3(&sol, "body1.v_0", k)), scale(h, v3(&sol, "body2.v_0", k)));
    let energy = |k| {
        let length = norm(sub(v3(&sol, "body2.frame_a.r_0", k), v3(&sol, "body1.frame_a.r_0", k)));
        let v_m = point_mass_velocity(k);
        sig(&sol, "body1.KE")[k] + sig(&sol, "body2.KE")[k] + 0.5 * m * dot(v_m, v_m) + 0.5 * c * (length - s0).powi(2)
    };
    let momentum = |k| {
        add(
            add(scale(m1, v3(&sol, "body1.v_cm_0", k)), scale(m2, v3(&sol, "body2.v_cm_0", k))),
            scale(m, point_mass_velocity(k)),
        )
    };
    let (e0, p0) = (energy(0), momentum(0));
    // The motion really exchanges energy between the parts.
    let ke_m = |k: usize| 0.5 * m * dot(point_mass_velocity(k), point_mass_velocity(k));
    let swing = (0..sol.time().len()).map(ke_m).fold(0.0f64, f64::max)
        - (0..sol.time().len()).map(ke_m).fold(f64::INFINITY, f64::min);
    assert!(swing > 1e-3 * e0, "the point mass's energy hardly changes ({swing} of {e0})");
    worst_over(&sol, |k| (energy(k) - e0).abs() / e0).check("free pair: |E - E0| / E0", "", 100.0 * eps);
    let p_scale = m1 * norm(v3(&sol, "body1.v_cm_0", 0)) + m2 * norm(v3(&sol, "body2.v_cm_0", 0));
    worst_over(&sol, |k| dist(momentum(k), p0) / p_scale).check("free pair: |p - p0| / |p|", "", 100.0 * eps);
}

/// A spring with mass between the tips of a double pendulum's two links,
/// with gravity: both ends move, on one branch of the tree. Energy (the
/// bodies' KE + PE, the point mass's kinetic and potential energy
/// `m g y_m`, the spring's energy) stays constant.
#[test]
fn spring_with_mass_inside_a_double_pendulum_conserves_energy() {
    let (c, s0, m, h) = (50.0, 0.3, 0.4, 0.6);
    let mut model = Model::new("pendulum_pair");
    model.add("world", "World");
    model.add("rev1", "Revolute").set("n", [0.0, 0.0, 1.0]).initial("phi", 0.3).initial("w", 0.0);
    model.add("rev2", "Revolute").set("n", [0.3, 0.2, 1.0]).initial("phi", -0.8).initial("w", 1.5);
    model.add("rod1", "FixedTranslation").set("r", [0.5, 0.0, 0.0]);
    model.add("rod2", "FixedTranslation").set("r", [0.4, -0.1, 0.0]);
    model.add("body1", "Body").set("m", 1.0).set("r_cm", [0.25, 0.0, 0.0]);
    model.add("body2", "Body").set("m", 0.7).set("r_cm", [0.2, 0.0, 0.05]);
    model
        .add("spring", "Spring")
        .set("c", c)
        .set("s_unstretched", s0)
        .set("hasmass", true)
        .set("m", m)
        .set("lengthfraction", h);
    model.connect(["world.frame_b", "rev1.frame_a"]);
    model.connect(["rev1.frame_b", "rod1.frame_a", "body1.frame_a"]);
    model.connect(["rod1.frame_b", "rev2.frame_a", "spring.frame_a"]);
    model.connect(["rev2.frame_b", "rod2.frame_a", "body2.frame_a"]);
    model.connect(["rod2.frame_b", "spring.frame_b"]);
    let eps = 1e-10;
    let sol = run(&model, &options(3.0, 0.005, eps, eps));

    let energy = |k| {
        let (ra, rb) = (v3(&sol, "spring.frame_a.r_0", k), v3(&sol, "spring.frame_b.r_0", k));
        let r_m = add(scale(1.0 - h, ra), scale(h, rb));
        // The ends' velocities from their links' motion: v + w x (r_end - r).
        let end_velocity = |body: &str, end: V3| {
            let w = mat_t_vec(&m3(&sol, &format!("{body}.frame_a.R"), k), v3(&sol, &format!("{body}.w_a"), k));
            let lever = sub(end, v3(&sol, &format!("{body}.frame_a.r_0"), k));
            add(v3(&sol, &format!("{body}.v_0"), k), cross(w, lever))
        };
        let v_m = add(scale(1.0 - h, end_velocity("body1", ra)), scale(h, end_velocity("body2", rb)));
        let length = norm(sub(rb, ra));
        let bodies: f64 = ["body1", "body2"]
            .iter()
            .map(|b| sig(&sol, &format!("{b}.KE"))[k] + sig(&sol, &format!("{b}.PE"))[k])
            .sum();
        bodies + 0.5 * m * dot(v_m, v_m) + m * G * r_m[1] + 0.5 * c * (length - s0).powi(2)
    };
    let e0 = energy(0);
    let scale_e = 2.0 * G; // masses ~2 kg, heights ~1 m
    worst_over(&sol, |k| (energy(k) - e0).abs() / scale_e).check("pendulum pair: |E - E0| / (m g l)", "", 100.0 * eps);
}

/// A spring with mass may not end at a node that only force elements hold
/// (a massless node): that is refused with a message, not simulated wrong.
#[test]
fn spring_with_mass_at_a_massless_node_is_refused() {
    let mut model = Model::new("massless_end");
    model.add("world", "World");
    model.add("spring1", "Spring").set("c", 10.0).set("hasmass", true).set("m", 0.2);
    model.add("spring2", "Spring").set("c", 10.0).set("fixed_rotation_at_frame_b", true);
    model.add("spring3", "Spring").set("c", 10.0);
    model.add("bar", "FixedTranslation").set("r", [1.0, 0.0, 0.0]);
    model.connect(["world.frame_b", "spring1.frame_a", "bar.frame_a"]);
    model.connect(["bar.frame_b", "spring3.frame_a"]);
    model.connect(["spring1.frame_b", "spring2.frame_b", "spring3.frame_b"]);
    model.connect(["world.frame_b", "spring2.frame_a"]);
    let err = model.assemble().expect_err("a spring with mass at a massless node is refused").to_string();
    assert!(err.contains("spring1") && err.contains("with mass"), "{err}");
}

/// A ball on a SphericalSpherical rod with mass (m at the rod's middle)
/// from the world's origin, swinging in gravity: the rod's mass moves at
/// half the ball's velocity and height, so
/// `E = (m_b + m/4) v^2 / 2 + (m_b + m/2) g y + I |w|^2 / 2` is constant.
#[test]
fn a_rod_with_mass_keeps_the_energy_of_a_mass_at_its_middle() {
    let (m_rod, m_b, inertia) = (0.8, 1.5, 0.01);
    let mut model = Model::new("RodPendulum");
    model.add("world", "World");
    model.add("rod", "SphericalSpherical").set("r_0", [0.6, -0.8, 0.0]).set("has_mass", true).set("m", m_rod);
    model
        .add("ball", "Body")
        .set("m", m_b)
        .set("r_cm", [0.0, 0.0, 0.0])
        .set("I_11", inertia)
        .set("I_22", inertia)
        .set("I_33", inertia)
        .set("orientation_state", OrientationState::Quaternion)
        .initial("r_0", [0.6, -0.8, 0.0])
        .initial("v_0", [0.0, 0.0, 1.2])
        .initial("w_a", [0.3, 0.0, 0.0]);
    model.connect(["world.frame_b", "rod.frame_a"]);
    model.connect(["rod.frame_b", "ball.frame_a"]);
    let eps = 1e-10;
    let sol = run(&model, &options(4.0, 0.01, eps, eps));
    let energy = |k: usize| {
        let (r, v, w) = (v3(&sol, "ball.frame_a.r_0", k), v3(&sol, "ball.v_0", k), v3(&sol, "ball.w_a", k));
        0.5 * (m_b + m_rod / 4.0) * dot(v, v) + (m_b + m_rod / 2.0) * G * r[1] + 0.5 * inertia * dot(w, w)
    };
    let scale = (m_b + m_rod) * G;
    worst_over(&sol, |k| (energy(k) - energy(0)).abs()).check("rod with mass: energy drift", "J", 100.0 * eps * scale);
    // The rod keeps its length.
    worst_over(&sol, |k| (norm(v3(&sol, "ball.frame_a.r_0", k)) - 1.0).abs()).check("rod length", "m", 1e-8);
    // It swung: the ball left its start.
    assert!((0..sol.time().len()).any(|k| v3(&sol, "ball.frame_a.r_0", k)[2].abs() > 0.1));
}
