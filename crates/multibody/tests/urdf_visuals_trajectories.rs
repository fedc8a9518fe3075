//! The URDF parts, the visual-only components and the trajectory sources,
//! in models, against closed forms.

use multibody::{Model, SimulationOptions, Solution};
use std::f64::consts::PI;

const G: f64 = 9.80665;

fn run(model: &Model, stop: f64, saveat: f64) -> Solution {
    let options = SimulationOptions { stop, saveat, abstol: 1e-11, reltol: 1e-11, ..Default::default() };
    model.assemble().unwrap_or_else(|e| panic!("{e}")).simulate(&options).unwrap_or_else(|e| panic!("{e}"))
}

/// Times at which `x` crosses zero going down, by linear interpolation.
fn downward_crossings(time: &[f64], x: &[f64]) -> Vec<f64> {
    let mut out = Vec::new();
    for k in 1..x.len() {
        if x[k - 1] > 0.0 && x[k] <= 0.0 {
            let f = x[k - 1] / (x[k - 1] - x[k]);
            out.push(time[k - 1] + f * (time[k] - time[k - 1]));
        }
    }
    out
}

/// A URDF joint whose origin transform turns frame_a by 90 degrees about x
/// (so the joint frame's y axis is the world's z, its z axis the world's
/// -y, along gravity) and moves it off the world origin.
fn urdf_pendulum(phi0: f64, with_visuals: bool) -> (Model, f64) {
    // A steel-like rod: length 0.6 m, radius 0.02 m, 2 kg, hanging along
    // the joint frame's z (down) from the pivot.
    let (m, l, rho) = (2.0, 0.6, 0.02);
    let axial = m * rho * rho / 2.0;
    let transverse = m * (3.0 * rho * rho + l * l) / 12.0;
    let mut model = Model::new("UrdfPendulum");
    model.add("world", "World");
    model
        .add("joint", "URDFRevolute")
        .set("r", [0.1, 0.2, 0.0])
        .set("n", [1.0, 0.0, 0.0])
        .set("angle", PI / 2.0)
        .set("joint_n", [0.0, 1.0, 0.0])
        .initial("phi", phi0)
        .initial("w", 0.0);
    model
        .add("link", "URDFBodyCylinder")
        .set("m", m)
        .set("r_cm", [0.0, 0.0, l / 2.0])
        .set("I_11", transverse)
        .set("I_22", transverse)
        .set("I_33", axial)
        .set("r_visual", [0.0, 0.0, l / 2.0])
        .set("length", l)
        .set("radius", rho);
    model.connect(["world.frame_b", "joint.frame_a"]);
    model.connect(["joint.frame_b", "link.frame_a"]);
    if with_visuals {
        model.add("axes", "FrameVisualizer");
        model.add("ball", "SphereVisualizer").set("radius", 0.05).set("r_shape", [0.0, 0.0, l]);
        model.add("cone", "ConeShape").set("length", 0.1).set("width", 0.05).set("height", 0.05);
        model.add("plate", "BoxVisualizer");
        model.connect(["joint.frame_b", "axes.frame_a", "ball.frame_a", "cone.frame_a"]);
        model.connect(["joint.frame_a", "plate.frame_a"]);
    }
    // About the pivot, around the joint axis (the link frame's y).
    let i_pivot = transverse + m * (l / 2.0) * (l / 2.0);
    let t0 = 2.0 * PI * (i_pivot / (m * G * l / 2.0)).sqrt();
    // The period of a pendulum of amplitude phi0: the series of the
    // complete elliptic integral, T0 (1 + phi0^2/16 + 11 phi0^4/3072 + ...);
    // the next term, 173 phi0^6 / 737280, is 2.3e-10 at phi0 = 0.1.
    let t = t0 * (1.0 + phi0 * phi0 / 16.0 + 11.0 * phi0.powi(4) / 3072.0);
    (model, t)
}

#[test]
fn urdf_pendulum_swings_with_the_period_of_its_cylinder() {
    let phi0 = 0.1;
    for with_visuals in [false, true] {
        let (model, period) = urdf_pendulum(phi0, with_visuals);
        let solution = run(&model, 3.0 * period + 0.1, 1e-3);
        let phi = solution.get("joint.phi").unwrap();
        let crossings = downward_crossings(solution.time(), phi);
        // phi starts at +phi0 at rest: the first downward crossing is at a
        // quarter period, the next ones one period apart.
        assert!(crossings.len() >= 3, "{crossings:?}");
        let measured = (crossings[2] - crossings[0]) / 2.0;
        let err = (measured - period).abs() / period;
        eprintln!("visuals {with_visuals}: period {measured} vs {period} (relative error {err:e})");
        // Series remainder 2.3e-10, crossing interpolation over 1 ms steps
        // (phi'' vanishes at the crossing: error ~ h^2 phi''' / phi' ~ 1e-7
        // of a step), integration at 1e-11: 1e-7 leaves a wide margin.
        assert!(err < 1e-7, "relative period error {err:e}");
        // Energy: the pivot (0.1, 0.2, 0) is fixed; the centre of mass hangs
        // l/2 below it at phi = 0; KE + PE is constant and PE at the start is
        // m g (0.2 - l/2 cos phi0).
        let ke = solution.get("link.KE").unwrap();
        let pe = solution.get("link.PE").unwrap();
        let e0 = 2.0 * G * (0.2 - 0.3 * phi0.cos());
        let worst = ke.iter().zip(pe).map(|(k, p)| (k + p - e0).abs()).fold(0.0, f64::max);
        eprintln!("visuals {with_visuals}: worst energy drift {worst:e} J of {e0}");
        assert!(worst < 1e-8, "energy drift {worst:e}");
    }
}

#[test]
fn shape_primitives_follow_their_frame_and_draw_where_told() {
    let (model, _) = urdf_pendulum(0.3, true);
    let solution = run(&model, 0.5, 0.05);
    // r and R of the cone are its frame's r_0 and transpose(R).
    let mut worst = 0.0f64;
    for i in 1..=3 {
        let a = solution.get(&format!("cone.r[{i}]")).unwrap();
        let b = solution.get(&format!("joint.frame_b.r_0[{i}]")).unwrap();
        worst = a.iter().zip(b).map(|(x, y)| (x - y).abs()).fold(worst, f64::max);
        for j in 1..=3 {
            let a = solution.get(&format!("cone.R[{i},{j}]")).unwrap();
            let b = solution.get(&format!("joint.frame_b.R[{j},{i}]")).unwrap();
            worst = a.iter().zip(b).map(|(x, y)| (x - y).abs()).fold(worst, f64::max);
        }
    }
    assert_eq!(worst, 0.0);
    // The pivot is at r = (0.1, 0.2, 0) whatever the angle.
    for (i, r) in [0.1, 0.2, 0.0].iter().enumerate() {
        let x = solution.get(&format!("joint.frame_b.r_0[{}]", i + 1)).unwrap();
        assert!(x.iter().all(|x| (x - r).abs() < 1e-12), "pivot moved: {x:?}");
    }
    // Shapes: three axes, a sphere at the rod's tip, a cone, a box, the
    // joint's cylinder and the link's cylinder centred on r_visual.
    let shapes = model.assemble().unwrap().shapes();
    let of = |c: &str| shapes.iter().filter(|s| s.component == c).count();
    assert_eq!([of("axes"), of("ball"), of("cone"), of("plate"), of("joint"), of("link")], [3, 1, 1, 1, 1, 1]);
    let link = shapes.iter().find(|s| s.component == "link").unwrap();
    match &link.placement {
        multibody::components::shapes::Placement::InFrame { frame, origin, length, .. } => {
            assert_eq!(frame, "link.frame_a");
            assert!((origin - multibody::math::Vec3::zeros()).norm() < 1e-15, "{origin}");
            assert!((length - multibody::math::Vec3::new(0.0, 0.0, 0.6)).norm() < 1e-15, "{length}");
        }
        other => panic!("{other:?}"),
    }
    assert!((link.width - 0.04).abs() < 1e-15);
}

#[test]
fn urdf_prismatic_falls_freely_along_its_axis() {
    // The joint frame is turned 90 degrees about x, so its z axis is the
    // world's -y: a slider along it falls freely, s = g t^2 / 2.
    let mut model = Model::new("UrdfSlider");
    model.add("world", "World");
    model
        .add("slider", "URDFPrismatic")
        .set("r", [0.0, 1.0, 0.0])
        .set("n", [1.0, 0.0, 0.0])
        .set("angle", PI / 2.0)
        .set("joint_n", [0.0, 0.0, 1.0])
        .initial("s", 0.0)
        .initial("v", 0.0);
    model.add("block", "URDFBodyBox").set("m", 3.0).set("length", 0.1).set("width", 0.1).set("height", 0.1);
    model.connect(["world.frame_b", "slider.frame_a"]);
    model.connect(["slider.frame_b", "block.frame_a"]);
    let solution = run(&model, 1.0, 0.05);
    let s = solution.get("slider.s").unwrap();
    let y = solution.get("block.r_0[2]").unwrap();
    for ((t, s), y) in solution.time().iter().zip(s).zip(y) {
        let expected = G * t * t / 2.0;
        // A polynomial of degree 2: the integrator is exact up to rounding.
        assert!((s - expected).abs() < 1e-9, "s({t}) = {s}, not {expected}");
        assert!((y - (1.0 - expected)).abs() < 1e-9, "y({t}) = {y}");
    }
}

/// The bang-coast-bang move of 0 -> `d` from `t0`, written out: position.
fn ptp_closed_form(t: f64, t0: f64, d: f64, v: f64, a: f64) -> f64 {
    let ta = v / a;
    let te = d / v + ta;
    let tau = t - t0;
    if tau <= 0.0 {
        0.0
    } else if tau < ta {
        a * tau * tau / 2.0
    } else if tau < te - ta {
        a * ta * ta / 2.0 + v * (tau - ta)
    } else if tau < te {
        d - a * (te - tau) * (te - tau) / 2.0
    } else {
        d
    }
}

#[test]
fn a_ptp_acceleration_integrates_to_its_position() {
    // BlockComponents.KinematicPTP's qdd drives a joint's acceleration; the
    // joint angle, integrated twice by the solver, must follow the written
    // out closed form (and the block's own q).
    let (d, v, a, t0) = (2.0, 1.0, 2.0, 0.3);
    let mut model = Model::new("PtpDrive");
    model.add("world", "World");
    model.add("rev", "Revolute").set("n", [0.0, 0.0, 1.0]);
    model.add("body", "Body").set("m", 1.0).set("r_cm", [0.5, 0.0, 0.0]);
    model
        .add("ptp", "BlockComponents.KinematicPTP")
        .set("q0", [0.0])
        .set("q1", [d])
        .set("qd_max", [v])
        .set("qdd_max", [a])
        .set("startTime", t0);
    model.add("drive", "RotationalComponents.Accelerate");
    model.connect(["world.frame_b", "rev.frame_a"]);
    model.connect(["rev.frame_b", "body.frame_a"]);
    model.connect(["drive.spline", "rev.axis"]);
    model.connect(["ptp.qdd", "drive.a_ref"]);
    let solution = run(&model, 3.0, 0.01);
    let phi = solution.get("rev.phi").unwrap();
    let q = solution.get("ptp.q[1]").unwrap();
    let moving = solution.get("ptp.moving").unwrap();
    let end = solution.get("ptp.endTime").unwrap();
    let te = t0 + d / v + v / a;
    let mut worst = 0.0f64;
    for (k, t) in solution.time().iter().enumerate() {
        let expected = ptp_closed_form(*t, t0, d, v, a);
        worst = worst.max((phi[k] - expected).abs());
        assert!((q[k] - expected).abs() < 1e-12, "q({t}) = {}, not {expected}", q[k]);
        assert_eq!(moving[k], if *t >= t0 && *t < te { 1.0 } else { 0.0 }, "moving at {t}");
        assert!((end[k] - te).abs() < 1e-14);
    }
    eprintln!("integrated PTP angle: worst error {worst:e}");
    // The integrator steps over the acceleration jumps with tolerance 1e-11.
    assert!(worst < 1e-7, "the integrated angle is {worst:e} rad off");
}

#[test]
fn trajectory_outputs_are_named_like_the_library() {
    let mut model = Model::new("Sources");
    model.add("world", "World");
    model.add("k5", "Kinematic5").set("tf", 2.0).set("q1", [3.0]);
    model.add("jerk", "KinematicPTPBoundedJerk").set("q1", [0.5]);
    model.add("ptp", "KinematicPTP").set("q0", [1.0]).set("q1", [-1.0]);
    // Something to integrate.
    model.add("rev", "Revolute").set("n", [0.0, 0.0, 1.0]);
    model.add("body", "Body").set("m", 1.0).set("r_cm", [0.5, 0.0, 0.0]);
    model.connect(["world.frame_b", "rev.frame_a"]);
    model.connect(["rev.frame_b", "body.frame_a"]);
    let solution = run(&model, 3.0, 0.25);
    let (k5, ptp) = (solution.get("k5.q[1]").unwrap(), solution.get("ptp.q[1]").unwrap());
    for ((t, k), q) in solution.time().iter().zip(k5).zip(ptp) {
        let s = (t / 2.0).min(1.0);
        let expected = 3.0 * (10.0 * s.powi(3) - 15.0 * s.powi(4) + 6.0 * s.powi(5));
        assert!((k - expected).abs() < 1e-12, "k5.q[1]({t}) = {k}, not {expected}");
        // 1 -> -1 with v = a = 1: a triangle? d = 2 >= v^2/a = 1: trapezoid of 3 s.
        let expected = 1.0 - ptp_closed_form(*t, 0.0, 2.0, 1.0, 1.0);
        assert!((q - expected).abs() < 1e-12, "ptp.q[1]({t}) = {q}, not {expected}");
    }
    for name in ["jerk.q[1]", "jerk.qd[1]", "jerk.qdd[1]", "jerk.qddd[1]", "k5.qd[1]", "k5.qdd[1]"] {
        assert!(solution.get(name).is_some(), "no {name}");
    }
    let q = solution.get("jerk.q[1]").unwrap();
    assert_eq!((q[0], *q.last().unwrap()), (0.0, 0.5));
    // More than one axis of a polynomial block is refused with a reason.
    let mut model = Model::new("TwoAxes");
    model.add("world", "World");
    model.add("k5", "Kinematic5").set("nout", 2.0);
    let err = model.assemble().unwrap_err().to_string();
    assert!(err.contains("nout"), "{err}");
}

/// Several axes of a point-to-point block move on one trapezoidal profile
/// `s(t)` from 0 to 1 and end together (Modelica's KinematicPTP2, the
/// library's phase-synchronised trajectory): `q[i] = q0[i] + dq[i] s(t)`,
/// `s` the fastest profile with speed at most `min qd_max[i] / |dq[i]|`
/// and acceleration at most `min qdd_max[i] / |dq[i]|`. Here axis 1 (0 to
/// 2, qd_max 1) bounds the speed of s at 0.5 and axis 2 (1 to 0, qdd_max
/// 0.5) its acceleration at 0.5: s accelerates for 1 s, coasts for 1 s and
/// brakes for 1 s, from startTime 0.2 to 3.2.
#[test]
fn ptp_axes_share_one_profile_and_end_together() {
    let (q0, q1, t0) = ([0.0, 1.0], [2.0, 0.0], 0.2);
    for kind in ["KinematicPTP", "BlockComponents.KinematicPTP"] {
        let mut model = Model::new("TwoAxes");
        model.add("world", "World");
        let ptp = model
            .add("ptp", kind)
            .set("nout", 2.0)
            .set("q0", q0.to_vec())
            .set("q1", q1.to_vec())
            .set("qd_max", vec![1.0, 1.0])
            .set("qdd_max", vec![2.0, 0.5]);
        let start = if kind == "KinematicPTP" { 0.0 } else { t0 };
        if start != 0.0 {
            ptp.set("startTime", start);
        }
        // The second axis's acceleration drives a joint: it integrates to the same closed form.
        model.add("rev", "Revolute").set("n", [0.0, 0.0, 1.0]).initial("phi", q0[1]);
        model.add("body", "Body").set("m", 1.0).set("r_cm", [0.5, 0.0, 0.0]);
        model.add("drive", "RotationalComponents.Accelerate");
        model.connect(["world.frame_b", "rev.frame_a"]);
        model.connect(["rev.frame_b", "body.frame_a"]);
        model.connect(["drive.spline", "rev.axis"]);
        model.connect(["ptp.qdd[2]", "drive.a_ref"]);
        let solution = run(&model, 4.0, 0.01);
        let phi = solution.get("rev.phi").unwrap();
        let mut worst = 0.0f64;
        for (k, t) in solution.time().iter().enumerate() {
            let s = ptp_closed_form(*t, start, 1.0, 0.5, 0.5);
            for i in 0..2 {
                let q = solution.get(&format!("ptp.q[{}]", i + 1)).unwrap()[k];
                let expected = q0[i] + (q1[i] - q0[i]) * s;
                assert!((q - expected).abs() < 1e-12, "{kind}: q[{}]({t}) = {q}, not {expected}", i + 1);
            }
            worst = worst.max((phi[k] - (q0[1] + (q1[1] - q0[1]) * s)).abs());
        }
        // Both at their ends from 3 s after the start on, and not before.
        let end = start + 3.0;
        for (i, target) in q1.iter().enumerate() {
            let q = solution.get(&format!("ptp.q[{}]", i + 1)).unwrap();
            let qd = solution.get(&format!("ptp.qd[{}]", i + 1)).unwrap();
            for (k, t) in solution.time().iter().enumerate() {
                if *t >= end {
                    assert!((q[k] - target).abs() < 1e-12 && qd[k] == 0.0, "{kind}: axis {} at {t}", i + 1);
                } else if *t > start {
                    assert!(qd[k] != 0.0, "{kind}: axis {} rests at {t}", i + 1);
                }
            }
        }
        // The peaks: axis 1 at its speed limit (2 * 0.5), axis 2 at its acceleration limit (1 * 0.5).
        let peak = |name: &str| solution.get(name).unwrap().iter().fold(0.0f64, |m, x| m.max(x.abs()));
        assert!((peak("ptp.qd[1]") - 1.0).abs() < 1e-12 && (peak("ptp.qdd[2]") - 0.5).abs() < 1e-12);
        eprintln!("{kind}: the joint driven by qdd[2] is off the closed form by {worst:.1e} rad");
        assert!(worst < 1e-7, "{kind}: the integrated angle is {worst:e} rad off");
    }
}
