//! LineForceWithMass: 1-D translational components on its flanges make a
//! force along the line between two frames (flange_a at 0, flange_b at the
//! distance), with an optional point mass on the line.
//!
//! Expected values come from closed forms, and from the same mechanisms
//! built with the 3-D line forces (Spring with mass, Damper), never from
//! the engine's own output for the model under test.
//!
//! Tolerances: runs at `abstol = reltol = eps` keep the global error within
//! `100 eps` of the signal's scale (as in analytic.rs and line_mass.rs);
//! two models of the same equations differ by their integration errors,
//! so by the same bound.

#[path = "common/physics.rs"]
mod physics;

use multibody::{Model, OrientationState};
use physics::*;

/// A body hanging from the world's origin by a LineForceWithMass (0.5 kg at
/// its middle) with a 1-D spring (c = 40, s_rel0 = 0.2) between its
/// flanges: the closed form of SpringWithMass.md (see line_mass.rs),
/// `y(t) = y_eq + (-0.3 - y_eq) cos(w t)`, the point mass's share of the
/// cut force, and the spring's own variables reading the line.
#[test]
fn a_spring_on_the_flanges_hangs_a_body_as_the_closed_form_says() {
    let (c, s0, m, h, m_b) = (40.0, 0.2, 0.5, 0.5, 1.0);
    let mut model = Model::new("hanging");
    model.add("world", "World");
    model.add("line", "LineForceWithMass").set("m", m).set("lengthfraction", h);
    model.add("spring", "TranslationalComponents.Spring").set("c", c).set("s_rel0", s0);
    model
        .add("body", "Body")
        .set("m", m_b)
        .set("r_cm", [0.0, 0.0, 0.0])
        .set("orientation_state", OrientationState::Quaternion)
        .initial("r_0", [0.0, -0.3, 0.0])
        .initial("v_0", [0.0, 0.0, 0.0])
        .initial("w_a", [0.0, 0.0, 0.0]);
    model.connect(["world.frame_b", "line.frame_a"]);
    model.connect(["line.frame_b", "body.frame_a"]);
    model.connect(["line.flange_a", "spring.flange_a"]);
    model.connect(["line.flange_b", "spring.flange_b"]);
    let eps = 1e-10;
    let sol = run(&model, &options(5.0, 0.01, eps, eps));

    let y_eq = -s0 - (m_b + m * h) * G / c;
    let w = (c / (m_b + m * h * h)).sqrt();
    let amplitude = -0.3 - y_eq;
    let y = |t: f64| y_eq + amplitude * (w * t).cos();
    worst_over(&sol, |k| (v3(&sol, "body.frame_a.r_0", k)[1] - y(sol.time()[k])).abs()).check(
        "line with 1-D spring: |y - y(t)|",
        "m",
        100.0 * eps,
    );
    // The 1-D spring sees the line's length -y, and its force.
    worst_over(&sol, |k| (sig(&sol, "spring.s_rel")[k] + y(sol.time()[k])).abs()).check(
        "line with 1-D spring: |spring.s_rel - length|",
        "m",
        100.0 * eps,
    );
    worst_over(&sol, |k| (sig(&sol, "spring.f")[k] - c * (-y(sol.time()[k]) - s0)).abs()).check(
        "line with 1-D spring: |spring.f - c (length - s_rel0)|",
        "N",
        100.0 * eps * c,
    );
    worst_over(&sol, |k| {
        let t = sol.time()[k];
        let a = -amplitude * w * w * (w * t).cos();
        let expected = c * (-y(t) - s0) - m * h * (h * a + G);
        (sig(&sol, "body.frame_a.f[2]")[k] - expected).abs()
    })
    .check("line with 1-D spring: body.frame_a.f[2]", "N", 100.0 * eps * (c + m_b * w * w));
    worst_over(&sol, |k| (sig(&sol, "line.length")[k] + y(sol.time()[k])).abs()).check(
        "line with 1-D spring: |line.length - (-y)|",
        "m",
        100.0 * eps,
    );
}

/// A double pendulum whose link tips a LineForceWithMass joins, with a
/// 1-D spring-damper on its flanges (m at 0.3 of the line): the same
/// motion as a Spring with the same point mass beside a Damper.
#[test]
fn a_spring_damper_on_the_flanges_moves_as_the_3d_spring_and_damper() {
    let (c, d, s0, m, h) = (60.0, 1.5, 0.25, 0.4, 0.3);
    let build = |flanges: bool| {
        let mut model = Model::new("pair");
        model.add("world", "World");
        model.add("rev1", "Revolute").set("n", [0.0, 0.0, 1.0]).initial("phi", 0.4).initial("w", 0.0);
        model.add("rev2", "Revolute").set("n", [0.2, 0.3, 1.0]).initial("phi", -0.9).initial("w", 2.0);
        model.add("rod1", "FixedTranslation").set("r", [0.5, 0.0, 0.0]);
        model.add("rod2", "FixedTranslation").set("r", [0.45, -0.1, 0.0]);
        model.add("body1", "Body").set("m", 1.0).set("r_cm", [0.25, 0.0, 0.0]);
        model.add("body2", "Body").set("m", 0.8).set("r_cm", [0.2, 0.0, 0.05]);
        model.connect(["world.frame_b", "rev1.frame_a"]);
        model.connect(["rev1.frame_b", "rod1.frame_a", "body1.frame_a"]);
        model.connect(["rod1.frame_b", "rev2.frame_a"]);
        model.connect(["rev2.frame_b", "rod2.frame_a", "body2.frame_a"]);
        if flanges {
            model.add("line", "LineForceWithMass").set("m", m).set("lengthfraction", h);
            model.add("sd", "TranslationalComponents.SpringDamper").set("c", c).set("d", d).set("s_rel0", s0);
            model.connect(["line.flange_a", "sd.flange_a"]);
            model.connect(["line.flange_b", "sd.flange_b"]);
            model.connect(["world.frame_b", "line.frame_a"]);
            model.connect(["rod2.frame_b", "line.frame_b"]);
        } else {
            model
                .add("spring", "Spring")
                .set("c", c)
                .set("s_unstretched", s0)
                .set("hasmass", true)
                .set("m", m)
                .set("lengthfraction", h);
            model.add("damper", "Damper").set("d", d);
            model.connect(["world.frame_b", "spring.frame_a", "damper.frame_a"]);
            model.connect(["rod2.frame_b", "spring.frame_b", "damper.frame_b"]);
        }
        model
    };
    let eps = 1e-10;
    let (with_flanges, with_3d) =
        (run(&build(true), &options(3.0, 0.01, eps, eps)), run(&build(false), &options(3.0, 0.01, eps, eps)));
    let swing = sig(&with_3d, "rev2.phi").iter().fold(0.0f64, |a, x| a.max((x + 0.9).abs()));
    assert!(swing > 0.3, "the pendulum hardly moves ({swing} rad)");
    for name in ["rev1.phi", "rev2.phi", "rev1.w", "rev2.w"] {
        let scale = sig(&with_3d, name).iter().fold(1.0f64, |a, x| a.max(x.abs()));
        worst_over(&with_flanges, |k| (sig(&with_flanges, name)[k] - sig(&with_3d, name)[k]).abs()).check(
            &format!("flanges vs 3-D line forces: {name}"),
            "",
            100.0 * eps * scale,
        );
    }
}

/// A body on a prismatic joint along x, pushed away from the world's
/// origin by a constant 1-D force on the line's flange_b (no point mass):
/// `x = x0 + F t^2 / (2 m)`; 1-D sensors between the flanges read the
/// distance and its rate.
#[test]
fn a_constant_force_on_the_flange_pushes_a_body_along_the_line() {
    let (f, m_b, x0) = (3.0, 1.5, 1.0);
    let mut model = Model::new("pushed");
    model.add("world", "World");
    model.add("slider", "Prismatic").set("n", [1.0, 0.0, 0.0]).initial("s", x0).initial("v", 0.0);
    model.add("body", "Body").set("m", m_b).set("r_cm", [0.0, 0.0, 0.0]);
    model.add("line", "LineForceWithMass").set("hasmass", false);
    model.add("push", "TranslationalComponents.ConstantForce").set("f_constant", f);
    model.add("distance", "TranslationalComponents.RelativePositionSensor");
    model.add("rate", "TranslationalComponents.RelativeVelocitySensor");
    model.connect(["world.frame_b", "slider.frame_a", "line.frame_a"]);
    model.connect(["slider.frame_b", "body.frame_a", "line.frame_b"]);
    model.connect(["line.flange_a", "push.support", "distance.flange_a", "rate.flange_a"]);
    model.connect(["line.flange_b", "push.flange", "distance.flange_b", "rate.flange_b"]);
    let eps = 1e-10;
    let sol = run(&model, &options(2.0, 0.01, eps, eps));
    let x = |t: f64| x0 + f * t * t / (2.0 * m_b);
    let tol = 100.0 * eps * x(2.0);
    worst_over(&sol, |k| (sig(&sol, "slider.s")[k] - x(sol.time()[k])).abs()).check(
        "pushed body: |s - s(t)|",
        "m",
        tol,
    );
    worst_over(&sol, |k| (sig(&sol, "distance.s_rel")[k] - x(sol.time()[k])).abs()).check(
        "pushed body: |distance sensor - s(t)|",
        "m",
        tol,
    );
    worst_over(&sol, |k| (sig(&sol, "rate.v_rel")[k] - f * sol.time()[k] / m_b).abs()).check(
        "pushed body: |rate sensor - F t / m|",
        "m/s",
        tol,
    );
}

/// What cannot ride on the line's flange is refused with the component named.
#[test]
fn a_mass_or_a_motion_source_on_the_line_flange_is_refused() {
    for (kind, connect) in [
        ("TranslationalComponents.Mass", ["line.flange_b", "part.flange_a"]),
        ("TranslationalComponents.Position", ["line.flange_b", "part.flange"]),
    ] {
        let mut model = Model::new("refused");
        model.add("world", "World");
        model.add("slider", "Prismatic").set("n", [1.0, 0.0, 0.0]).initial("s", 1.0).initial("v", 0.0);
        model.add("body", "Body").set("m", 1.0).set("r_cm", [0.0, 0.0, 0.0]);
        model.add("line", "LineForceWithMass");
        let part = model.add("part", kind);
        if kind.ends_with("Mass") {
            part.set("m", 1.0);
        }
        model.connect(["world.frame_b", "slider.frame_a", "line.frame_a"]);
        model.connect(["slider.frame_b", "body.frame_a", "line.frame_b"]);
        model.connect(connect);
        let message = match model.assemble() {
            Ok(_) => panic!("{kind} on the line's flange was accepted"),
            Err(e) => e.to_string(),
        };
        println!("{kind}: {message}");
        assert!(message.contains("line"), "{message}");
    }
}
