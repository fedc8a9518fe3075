//! Modelica MultiBody reference trajectories (../shared/reference/msl),
//! rebuilt from their descriptions with the Rust API.

mod common;

use common::{as_pairs, assert_within_tube, same, vector_pairs, Reference};
use multibody::{Model, OrientationState, SimulationOptions};

fn options_for(reference: &Reference) -> SimulationOptions {
    SimulationOptions { stop: reference.stop(), saveat: reference.interval(), ..SimulationOptions::default() }
}

/// Pendulum.md: a revolute about z with a rotational damper d = 0.1, and a
/// body m = 1 at r_cm = [0.5, 0, 0].
#[test]
fn pendulum() {
    let mut model = Model::new("Pendulum");
    model.add("world", "World");
    model.add("rev", "Revolute").set("n", [0.0, 0.0, 1.0]).set("axisflange", true);
    model.add("damper", "RotationalComponents.Damper").set("d", 0.1);
    model.add("body", "Body").set("m", 1.0).set("r_cm", [0.5, 0.0, 0.0]);
    model.connect(["world.frame_b", "rev.frame_a"]);
    model.connect(["rev.frame_b", "body.frame_a"]);
    model.connect(["damper.spline_a", "rev.support"]);
    model.connect(["damper.spline_b", "rev.axis"]);
    let reference = Reference::reference("Pendulum");
    let solution = model.assemble().unwrap().simulate(&options_for(&reference)).unwrap();
    assert_within_tube(&reference, &solution, &[("rev.phi", "rev.phi"), ("rev.w", "rev.w")]);
}

/// DoublePendulum.md's joints and damper around two boxes `boxBody1`,
/// `boxBody2` that `add_boxes` adds; `end_of_box_1` is where revolute2 hangs.
fn double_pendulum(add_boxes: impl FnOnce(&mut Model), end_of_box_1: &str) -> Model {
    let mut model = Model::new("DoublePendulum");
    model.add("world", "World");
    model.add("revolute1", "Revolute");
    model.add("damper", "RotationalComponents.Damper").set("d", 0.1);
    model.add("revolute2", "Revolute");
    add_boxes(&mut model);
    model.connect(["world.frame_b", "revolute1.frame_a"]);
    model.connect(["revolute1.frame_b", "boxBody1.frame_a"]);
    model.connect([end_of_box_1, "revolute2.frame_a"]);
    model.connect(["revolute2.frame_b", "boxBody2.frame_a"]);
    model.connect(["damper.spline_a", "revolute1.support"]);
    model.connect(["damper.spline_b", "revolute1.axis"]);
    model
}

fn check_double_pendulum(model: Model) {
    let reference = Reference::reference("DoublePendulum");
    let solution = model.assemble().unwrap().simulate(&options_for(&reference)).unwrap();
    assert_within_tube(&reference, &solution, &same(&["revolute1.phi", "revolute1.w", "revolute2.phi", "revolute2.w"]));
}

/// DoublePendulum.md, the boxes as Bodies with the BodyBox mass and inertia
/// from the description, and a rod to the far end.
#[test]
fn double_pendulum_of_bodies_and_rods() {
    let bodies_and_rods = |model: &mut Model| {
        for k in ["1", "2"] {
            model
                .add(format!("boxBody{k}"), "Body")
                .set("m", 13.86)
                .set("r_cm", [0.25, 0.0, 0.0])
                .set("I_11", 0.008316)
                .set("I_22", 0.292908)
                .set("I_33", 0.292908);
            model.add(format!("rod{k}"), "FixedTranslation").set("r", [0.5, 0.0, 0.0]);
            model.connect([format!("boxBody{k}.frame_a"), format!("rod{k}.frame_a")]);
        }
    };
    check_double_pendulum(double_pendulum(bodies_and_rods, "rod1.frame_b"));
}

/// DoublePendulum.md with real BodyBoxes (width 0.06, height = width).
#[test]
fn double_pendulum_with_body_boxes() {
    let boxes = |model: &mut Model| {
        for k in ["1", "2"] {
            model.add(format!("boxBody{k}"), "BodyBox").set("r", [0.5, 0.0, 0.0]).set("width", 0.06);
        }
    };
    check_double_pendulum(double_pendulum(boxes, "boxBody1.frame_b"));
}

/// PointGravity.md: two free bodies in a point-gravity field with mu = 1.
#[test]
fn point_gravity() {
    let mut model = Model::new("PointGravity");
    model.add("world", "World").set("point_gravity", true).set("mu", 1.0);
    for (name, r, v) in [("body1", [0.0, 0.6, 0.0], [1.0, 0.0, 0.0]), ("body2", [0.6, 0.6, 0.0], [0.6, 0.0, 0.0])] {
        model
            .add(name, "Body")
            .set("m", 1.0)
            .set("I_11", 0.1)
            .set("I_22", 0.1)
            .set("I_33", 0.1)
            .set("orientation_state", OrientationState::Quaternion)
            .initial("r_0", r)
            .initial("v_0", v);
    }
    let reference = Reference::reference("PointGravity");
    let solution = model.assemble().unwrap().simulate(&options_for(&reference)).unwrap();
    let mut pairs = vector_pairs("body1", "body1", &["frame_a.r_0", "v_0", "w_a"]);
    pairs.extend(vector_pairs("body2", "body2", &["frame_a.r_0", "v_0", "w_a"]));
    assert_within_tube(&reference, &solution, &as_pairs(&pairs));
}

/// FreeBody.md: a free BodyShape (quaternion states) hung from two
/// zero-length springs, released at angles (10, 10, 10) degrees.
#[test]
fn free_body() {
    use multibody::math::{axes_rotations, to_q, Quat, Vec3};
    let angle = 10f64.to_radians();
    let q0 = to_q(&axes_rotations([1, 2, 3], &Vec3::new(angle, angle, angle)), &Quat::new(1.0, 0.0, 0.0, 0.0));
    let mut model = Model::new("FreeBody");
    model.add("world", "World");
    model.add("bar2", "FixedTranslation").set("r", [0.8, 0.0, 0.0]);
    model.add("spring1", "Spring").set("c", 20.0);
    model.add("spring2", "Spring").set("c", 20.0);
    model
        .add("body", "BodyShape")
        .set("m", 1.0)
        .set("I_11", 1.0)
        .set("I_22", 1.0)
        .set("I_33", 1.0)
        .set("r", [0.4, 0.0, 0.0])
        .set("r_cm", [0.2, 0.0, 0.0])
        .set("orientation_state", OrientationState::Quaternion)
        .initial("r_0", [0.2, -0.5, 0.1])
        .initial("Q_hat", q0.as_slice());
    model.connect(["world.frame_b", "bar2.frame_a"]);
    model.connect(["spring1.frame_a", "world.frame_b"]);
    model.connect(["spring1.frame_b", "body.frame_a"]);
    model.connect(["spring2.frame_a", "bar2.frame_b"]);
    model.connect(["spring2.frame_b", "body.frame_b"]);
    let reference = Reference::reference("FreeBody");
    let solution = model.assemble().unwrap().simulate(&options_for(&reference)).unwrap();
    let mut pairs = vector_pairs("body.body.frame_a", "body.frame_a", &["r_0"]);
    pairs.extend(vector_pairs("body.body", "body", &["w_a"]));
    pairs.extend(vector_pairs("body", "body", &["v_0"]));
    assert_within_tube(&reference, &solution, &as_pairs(&pairs));
}

/// ThreeSprings.md: a free body hanging from a spring whose upper end is a
/// massless node held by two more springs (solved in every evaluation).
#[test]
fn three_springs() {
    let mut model = Model::new("ThreeSprings");
    model.add("world", "World");
    model.add("bar1", "FixedTranslation").set("r", [0.3, 0.0, 0.0]);
    model.add("bar2", "FixedTranslation").set("r", [0.0, 0.0, 0.3]);
    model.add("spring1", "Spring").set("c", 20.0).set("s_unstretched", 0.1);
    model.add("spring2", "Spring").set("c", 40.0).set("s_unstretched", 0.1);
    model.add("spring3", "Spring").set("c", 20.0).set("s_unstretched", 0.1).set("fixed_rotation_at_frame_b", true);
    model
        .add("body1", "Body")
        .set("m", 0.8)
        .set("r_cm", [0.0, -0.2, 0.0])
        .set("I_11", 0.1)
        .set("I_22", 0.1)
        .set("I_33", 0.1)
        .set("orientation_state", OrientationState::Quaternion)
        .initial("r_0", [0.5, -0.3, 0.0]);
    model.connect(["world.frame_b", "bar1.frame_a", "bar2.frame_a"]);
    model.connect(["bar1.frame_b", "spring1.frame_a"]);
    model.connect(["bar2.frame_b", "spring3.frame_a"]);
    model.connect(["spring1.frame_b", "spring3.frame_b", "spring2.frame_a"]);
    model.connect(["spring2.frame_b", "body1.frame_a"]);
    let reference = Reference::reference("ThreeSprings");
    let solution = model.assemble().unwrap().simulate(&options_for(&reference)).unwrap();
    let mut pairs = vector_pairs("body1.frame_a", "body1.frame_a", &["r_0"]);
    pairs.extend(vector_pairs("body1", "body1", &["v_0", "w_a"]));
    assert_within_tube(&reference, &solution, &as_pairs(&pairs));
}

/// SpringWithMass.md: a free body hanging on a spring (c = 40,
/// s_unstretched = 0.2) with a 0.5 kg point mass at its middle, which is no
/// degree of freedom; x, z and w_a stay exactly zero.
#[test]
fn spring_with_mass() {
    let mut model = Model::new("SpringWithMass");
    model.add("world", "World");
    model.add("spring", "Spring").set("c", 40.0).set("s_unstretched", 0.2).set("hasmass", true).set("m", 0.5);
    model
        .add("body", "Body")
        .set("m", 1.0)
        .set("r_cm", [0.0, 0.0, 0.0])
        .set("orientation_state", OrientationState::Quaternion)
        .initial("r_0", [0.0, -0.3, 0.0])
        .initial("v_0", [0.0, 0.0, 0.0])
        .initial("w_a", [0.0, 0.0, 0.0]);
    model.connect(["world.frame_b", "spring.frame_a"]);
    model.connect(["spring.frame_b", "body.frame_a"]);
    let reference = Reference::reference("SpringWithMass");
    let solution = model.assemble().unwrap().simulate(&options_for(&reference)).unwrap();
    let mut pairs = vector_pairs("body.frame_a", "body.frame_a", &["r_0"]);
    pairs.extend(vector_pairs("body", "body", &["v_0", "w_a"]));
    assert_within_tube(&reference, &solution, &as_pairs(&pairs));
}

/// ForceAndTorque.md: a cylinder on two revolutes, pushed at its tip by a
/// constant force and torque given in a frame rotated 30 degrees about z
/// (here resolved in the world, with the vectors rotated accordingly).
#[test]
fn force_and_torque() {
    let (c, s) = (30f64.to_radians().cos(), 30f64.to_radians().sin());
    let force = [-s * 1000.0, c * 1000.0, 0.0];
    let torque = [-c * 100.0 - s * 100.0, -s * 100.0 + c * 100.0, 0.0];
    let mut model = Model::new("ForceAndTorque");
    model.add("world", "World");
    model.add("fixed1", "Fixed").set("r", [0.0, -0.5, 0.0]);
    model.add("revolute1", "Revolute");
    model.add("revolute2", "Revolute").set("n", [0.0, 1.0, 0.0]);
    model.add("body", "BodyCylinder").set("r", [1.0, 0.0, 0.0]);
    model.add("fixed2", "Fixed").set("r", [1.5, 0.25, 0.0]);
    model.add("force", "Force").set("resolve_in_frame", multibody::Value::Enum("World".into()));
    model.add("torque", "Torque").set("resolve_in_frame", multibody::Value::Enum("World".into()));
    model.connect(["fixed1.frame_b", "revolute1.frame_a"]);
    model.connect(["revolute1.frame_b", "revolute2.frame_a"]);
    model.connect(["revolute2.frame_b", "body.frame_a"]);
    model.connect(["fixed2.frame_b", "force.frame_a", "torque.frame_a"]);
    model.connect(["body.frame_b", "force.frame_b", "torque.frame_b"]);
    for (i, axis) in ["x", "y", "z"].iter().enumerate() {
        model.add(format!("f{axis}"), "BlockComponents.Constant").set("k", force[i]);
        model.add(format!("t{axis}"), "BlockComponents.Constant").set("k", torque[i]);
        model.connect([format!("f{axis}.y"), format!("force.force_{axis}")]);
        model.connect([format!("t{axis}.y"), format!("torque.torque_{axis}")]);
    }
    let reference = Reference::reference("ForceAndTorque");
    let solution = model.assemble().unwrap().simulate(&options_for(&reference)).unwrap();
    let pairs: Vec<(&str, &str)> =
        ["revolute1.phi", "revolute1.w", "revolute2.phi", "revolute2.w"].iter().map(|s| (*s, *s)).collect();
    assert_within_tube(&reference, &solution, &pairs);
}

/// PendulumWithSpringDamper.md: a mass sliding on a prismatic joint on a
/// revolute, with a 3-D spring and damper from the pivot.
#[test]
fn pendulum_with_spring_damper() {
    let mut model = Model::new("PendulumWithSpringDamper");
    model.add("world", "World");
    model.add("bar1", "FixedTranslation").set("r", [0.3, 0.0, 0.0]);
    model.add("revolute", "Revolute");
    model.add("prismatic", "Prismatic").set("n", [1.0, 0.0, 0.0]).initial("s", 0.5);
    model.add("body1", "Body").set("m", 1.0).set("I_11", 1.0).set("I_22", 1.0).set("I_33", 1.0);
    model.add("spring1", "Spring").set("c", 20.0).set("s_unstretched", 0.2);
    model.add("damper1", "Damper").set("d", 1.0);
    model.connect(["world.frame_b", "bar1.frame_a"]);
    model.connect(["bar1.frame_b", "revolute.frame_a", "spring1.frame_a", "damper1.frame_a"]);
    model.connect(["revolute.frame_b", "prismatic.frame_a"]);
    model.connect(["prismatic.frame_b", "body1.frame_a", "spring1.frame_b", "damper1.frame_b"]);
    let reference = Reference::reference("PendulumWithSpringDamper");
    let solution = model.assemble().unwrap().simulate(&options_for(&reference)).unwrap();
    let pairs: Vec<(&str, &str)> =
        ["prismatic.s", "prismatic.v", "revolute.phi", "revolute.w"].iter().map(|s| (*s, *s)).collect();
    assert_within_tube(&reference, &solution, &pairs);
}

/// SpringMassSystem.md: the same spring-mass system twice, once with a 1-D
/// spring on the prismatic axis and once with a 3-D spring.
#[test]
fn spring_mass_system() {
    let mut model = Model::new("SpringMassSystem");
    model.add("world", "World");
    model.add("bar1", "FixedTranslation").set("r", [0.3, 0.0, 0.0]);
    model.add("bar2", "FixedTranslation").set("r", [0.3, 0.0, 0.0]);
    for p in ["p1", "p2"] {
        model.add(p, "Prismatic").set("n", [0.0, -1.0, 0.0]).initial("s", 0.1);
    }
    model.add("spring1", "TranslationalComponents.Spring").set("c", 30.0).set("s_rel0", 0.1);
    model.add("spring2", "Spring").set("c", 30.0).set("s_unstretched", 0.1);
    model.add("body1", "Body").set("m", 1.0);
    model.add("body2", "Body").set("m", 1.0);
    model.connect(["world.frame_b", "bar1.frame_a"]);
    model.connect(["bar1.frame_b", "p1.frame_a", "bar2.frame_a"]);
    model.connect(["p1.frame_b", "body1.frame_a"]);
    model.connect(["spring1.flange_a", "p1.support"]);
    model.connect(["spring1.flange_b", "p1.axis"]);
    model.connect(["bar2.frame_b", "p2.frame_a", "spring2.frame_a"]);
    model.connect(["p2.frame_b", "body2.frame_a", "spring2.frame_b"]);
    let reference = Reference::reference("SpringMassSystem");
    let solution = model.assemble().unwrap().simulate(&options_for(&reference)).unwrap();
    let pairs: Vec<(&str, &str)> = ["p1.s", "p1.v", "p2.s", "p2.v"].iter().map(|s| (*s, *s)).collect();
    assert_within_tube(&reference, &solution, &pairs);
}

/// Fourbar1.md: a spatial four-bar of elementary joints, one loop closed
/// automatically (the cut is chosen by the engine).
#[test]
fn fourbar1() {
    let mut model = Model::new("Fourbar1");
    model.add("world", "World");
    model.add("j1", "Revolute").set("n", [1.0, 0.0, 0.0]).initial("phi", 0.0).initial("w", 5.235987755982989);
    model.add("j2", "Prismatic").set("n", [1.0, 0.0, 0.0]).guess("s", -0.2);
    model.add("b0", "FixedTranslation").set("r", [1.2, 0.0, 0.0]);
    model.add("b1", "BodyCylinder").set("r", [0.0, 0.5, 0.1]).set("diameter", 0.05);
    model.add("b2", "BodyCylinder").set("r", [0.0, 0.2, 0.0]).set("diameter", 0.05);
    model.add("b3", "BodyCylinder").set("r", [-1.0, 0.3, 0.1]).set("diameter", 0.05);
    for (name, n) in [
        ("rev", [0.0, 1.0, 0.0]),
        ("rev1", [0.0, 0.0, 1.0]),
        ("j3", [1.0, 0.0, 0.0]),
        ("j4", [0.0, 1.0, 0.0]),
        ("j5", [0.0, 0.0, 1.0]),
    ] {
        model.add(name, "Revolute").set("n", n);
    }
    for (a, b) in [
        ("world.frame_b", "j1.frame_a"),
        ("j1.frame_b", "b1.frame_a"),
        ("b1.frame_b", "j3.frame_a"),
        ("j3.frame_b", "j4.frame_a"),
        ("j4.frame_b", "j5.frame_a"),
        ("j5.frame_b", "b3.frame_b"),
        ("world.frame_b", "b0.frame_a"),
        ("b0.frame_b", "j2.frame_a"),
        ("j2.frame_b", "b2.frame_a"),
        ("b2.frame_b", "rev.frame_a"),
        ("rev.frame_b", "rev1.frame_a"),
        ("rev1.frame_b", "b3.frame_a"),
    ] {
        model.connect([a, b]);
    }
    let mechanism = model.assemble().unwrap();
    assert_eq!(mechanism.degrees_of_freedom(), 1);
    for l in mechanism.loops() {
        println!("loop cut at {}: {:?}, {} equations, {} redundant", l.cut, l.joints, l.equations, l.redundant);
    }
    let reference = Reference::reference("Fourbar1");
    let solution = mechanism.simulate(&options_for(&reference)).unwrap();
    assert_within_tube(&reference, &solution, &[("j1.phi", "j1.phi"), ("j1.w", "j1.w")]);
}

/// The shared environment of the Constraints examples: a frame F rotated
/// by the sequence {1,2,3} with angles {10,55,68} degrees at (0.2,-0.3,0.2),
/// and an anchor A at (0.8, 0, 0.3).
fn constraint_environment(model: &mut Model) {
    use multibody::math::{axes_rotations, rotation_vector, Vec3};
    let angles = Vec3::new(10f64.to_radians(), 55f64.to_radians(), 68f64.to_radians());
    let rot = axes_rotations([1, 2, 3], &angles);
    let axis_angle = rotation_vector(&rot);
    model.add("world", "World");
    model
        .add("fixedRotation", "FixedRotation")
        .set("r", [0.2, -0.3, 0.2])
        .set("n", axis_angle.normalize())
        .set("angle", axis_angle.norm());
    model.add("fixedTranslation", "FixedTranslation").set("r", [0.8, 0.0, 0.3]);
    model.connect(["world.frame_b", "fixedRotation.frame_a", "fixedTranslation.frame_a"]);
}

fn constraint_body(model: &mut Model, name: &str, free: bool) {
    let body = model
        .add(name, "BodyShape")
        .set("m", 1.0)
        .set("I_11", 1.0)
        .set("I_22", 1.0)
        .set("I_33", 1.0)
        .set("r", [0.4, 0.0, 0.0])
        .set("r_cm", [0.2, 0.0, 0.0]);
    if free {
        body.set("orientation_state", OrientationState::Quaternion);
    }
    let spring = format!("springOf{}", &name[6..]);
    model.add(&spring, "Spring").set("c", 20.0);
    model.connect([format!("{spring}.frame_a"), "fixedTranslation.frame_b".into()]);
    model.connect([format!("{spring}.frame_b"), format!("{name}.frame_b")]);
}

/// RevoluteConstraint.md: a body on a revolute, and the same free body tied
/// by a RevoluteConstraint; both must move the same.
#[test]
fn revolute_constraint() {
    use multibody::math::{axes_rotations, to_q, Quat, Vec3};
    let mut model = Model::new("RevoluteConstraint");
    constraint_environment(&mut model);
    model.add("joint", "Revolute").set("n", [0.0, 1.0, 0.0]).initial("phi", 0.0).initial("w", 0.0);
    constraint_body(&mut model, "bodyOfJoint", false);
    model.connect(["fixedRotation.frame_b", "joint.frame_a"]);
    model.connect(["joint.frame_b", "bodyOfJoint.frame_a"]);
    model.add("constraint", "RevoluteConstraint").set("n", [0.0, 1.0, 0.0]);
    constraint_body(&mut model, "bodyOfConstraint", true);
    // The free body starts in frame F at rest (FreeMotionScalarInit in the reference).
    let rot = axes_rotations([1, 2, 3], &Vec3::new(10f64.to_radians(), 55f64.to_radians(), 68f64.to_radians()));
    let q0 = to_q(&rot, &Quat::new(1.0, 0.0, 0.0, 0.0));
    model
        .component_mut("bodyOfConstraint")
        .unwrap()
        .initial("Q_hat", q0.as_slice())
        .initial("w_a", [0.0; 3])
        .guess("r_0", [0.2, -0.5, 0.1]);
    model.connect(["fixedRotation.frame_b", "constraint.frame_a"]);
    model.connect(["constraint.frame_b", "bodyOfConstraint.frame_a"]);
    let mechanism = model.assemble().unwrap();
    assert_eq!(mechanism.degrees_of_freedom(), 2);
    let reference = Reference::reference("RevoluteConstraint");
    let solution = mechanism.simulate(&options_for(&reference)).unwrap();
    let mut pairs = vector_pairs("bodyOfConstraint.body", "bodyOfConstraint", &["w_a"]);
    pairs.push(("bodyOfJoint.body.w_a[2]".into(), "bodyOfJoint.w_a[2]".into()));
    pairs.push(("joint.phi".into(), "joint.phi".into()));
    assert_within_tube(&reference, &solution, &as_pairs(&pairs));
}

/// SphericalConstraint.md: a free body tied by a SphericalConstraint to the
/// rotated frame F: a spherical pendulum pulled by a spring.
#[test]
fn spherical_constraint() {
    use multibody::math::{axes_rotations, to_q, Quat, Vec3};
    let mut model = Model::new("SphericalConstraint");
    constraint_environment(&mut model);
    model.add("constraint", "SphericalConstraint");
    constraint_body(&mut model, "bodyOfConstraint", true);
    let rot = axes_rotations([1, 2, 3], &Vec3::new(10f64.to_radians(), 55f64.to_radians(), 68f64.to_radians()));
    let q0 = to_q(&rot, &Quat::new(1.0, 0.0, 0.0, 0.0));
    model.component_mut("bodyOfConstraint").unwrap().initial("Q_hat", q0.as_slice()).initial("w_a", [0.0; 3]);
    model.connect(["fixedRotation.frame_b", "constraint.frame_a"]);
    model.connect(["constraint.frame_b", "bodyOfConstraint.frame_a"]);
    let mechanism = model.assemble().unwrap();
    assert_eq!(mechanism.degrees_of_freedom(), 3);
    let reference = Reference::reference("SphericalConstraint");
    let solution = mechanism.simulate(&options_for(&reference)).unwrap();
    let pairs = vector_pairs("bodyOfConstraint.body", "bodyOfConstraint", &["w_a"]);
    assert_within_tube(&reference, &solution, &as_pairs(&pairs));
}
