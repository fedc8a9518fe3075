//! Equations between positions of 1-D connectors, as the libraries write
//! their rigid parts (a rod, a gear, a planetary gear, a rack): each is a
//! constraint of the drive train. Checked against closed forms and against
//! the built-in parts; the Dyad-written twins of the standard library
//! (`RotationalComponents.Acausal.*`, `TranslationalComponents.Acausal.*`)
//! against the built-in elements of the same names on a chain. Each test
//! prints its worst error as a fraction of its tolerance.

mod common;

use common::{error_of, example, report, simulate, worst_difference};
use multibody::Solution;

fn column<'s>(s: &'s Solution, name: &str) -> &'s [f64] {
    s.get(name).unwrap_or_else(|| panic!("no column {name}"))
}

/// Worst |a - b| over two columns, against its tolerance.
fn compare(s: &Solution, a: &str, b: &str, tolerance: f64) {
    report(&format!("{a} vs {b}"), worst_difference(column(s, a), column(s, b)), tolerance);
}

/// Worst |signal - exact(t)|, against its tolerance.
fn check(s: &Solution, name: &str, tolerance: f64, exact: impl Fn(f64) -> f64) {
    let worst = column(s, name).iter().zip(s.time()).map(|(y, &t)| (y - exact(t)).abs()).fold(0.0, f64::max);
    report(name, worst, tolerance);
}

const RUN: &str = "extends TransientAnalysis(stop = 2, saveat = 0.01, abstol = 1e-11, reltol = 1e-11)";
const TIGHT: &str = "extends TransientAnalysis(stop = 2, saveat = 0.01, abstol = 1e-13, reltol = 1e-13)";

/// The library's Rod (its middle `s` eliminated) carries a second mass
/// rigidly: one degree of freedom, the closed-form oscillation of both
/// masses on the spring, the rod's length kept.
#[test]
fn a_rod_in_the_library_form_carries_the_mass_behind_it() {
    let s = simulate(&format!(
        "example component RodOnSpring
  wall = TranslationalComponents.Fixed()
  spring = TranslationalComponents.Spring(c = 10)
  m1 = TranslationalComponents.Mass(m = 1, s(initial = 0.5), v(initial = 0))
  rod = TranslationalComponents.Rod(L = 0.3)
  m2 = TranslationalComponents.Mass(m = 3)
relations
  connect(wall.flange, spring.flange_a)
  connect(spring.flange_b, m1.flange_a)
  connect(m1.flange_b, rod.flange_a)
  connect(rod.flange_b, m2.flange_a)
end
analysis Run
  {RUN}
  model = RodOnSpring()
end"
    ));
    let w = (10.0f64 / 4.0).sqrt();
    check(&s, "m1.s", 1e-9, |t| 0.5 * (w * t).cos());
    check(&s, "m2.s", 1e-9, |t| 0.5 * (w * t).cos() + 0.3);
    check(&s, "rod.s", 1e-9, |t| 0.5 * (w * t).cos() + 0.15);
}

/// A gear written by the user (`phi_a = ratio * phi_b` and its torque
/// balance) beside the built-in IdealGear, and the library's planetary gear
/// with its ring held: the reflected inertias give the closed-form
/// accelerations.
#[test]
fn written_gears_reflect_their_inertias() {
    let s = simulate(&format!(
        "component MyGear
  flange_a = Spline()
  flange_b = Spline()
  parameter ratio::Real = 1
relations
  flange_a.phi = ratio * flange_b.phi
  0 = ratio * flange_a.tau + flange_b.tau
end
example component Gears
  fixed = RotationalComponents.Fixed()
  k = BlockComponents.Constant(k = 2)
  src = RotationalComponents.Torque()
  j1 = RotationalComponents.Inertia(J = 1, phi(initial = 0), w(initial = 0))
  gear = MyGear(ratio = 3)
  j2 = RotationalComponents.Inertia(J = 9)
  srcb = RotationalComponents.Torque()
  j1b = RotationalComponents.Inertia(J = 1, phi(initial = 0), w(initial = 0))
  gearb = RotationalComponents.IdealGear(ratio = 3)
  j2b = RotationalComponents.Inertia(J = 9)
  srcc = RotationalComponents.Torque()
  sun = RotationalComponents.Inertia(J = 0.5, phi(initial = 0), w(initial = 0))
  planetary = RotationalComponents.Components.IdealPlanetaryGear(ratio = 2)
  carrier = RotationalComponents.Inertia(J = 2)
relations
  connect(k.y, src.tau, srcb.tau, srcc.tau)
  connect(src.support, srcb.support, srcc.support, fixed.spline, planetary.ring)
  connect(src.spline, j1.spline_a)
  connect(j1.spline_b, gear.flange_a)
  connect(gear.flange_b, j2.spline_a)
  connect(srcb.spline, j1b.spline_a)
  connect(j1b.spline_b, gearb.spline_a)
  connect(gearb.spline_b, j2b.spline_a)
  connect(srcc.spline, sun.spline_a)
  connect(sun.spline_b, planetary.sun)
  connect(planetary.carrier, carrier.spline_a)
end
analysis Run
  {RUN}
  model = Gears()
end"
    ));
    // Torque 2 on J1 + J2 / ratio^2 = 2: acceleration 1.
    check(&s, "j1.phi", 1e-9, |t| 0.5 * t * t);
    check(&s, "j2.phi", 1e-9, |t| 0.5 * t * t / 3.0);
    compare(&s, "j1.phi", "j1b.phi", 1e-10);
    compare(&s, "j2.phi", "j2b.phi", 1e-10);
    // Ring held: carrier = sun / (1 + ratio); J = 0.5 + 2 / 9 at the sun.
    let a = 2.0 / (0.5 + 2.0 / 9.0);
    check(&s, "sun.phi", 1e-9, |t| 0.5 * a * t * t);
    check(&s, "carrier.phi", 1e-9, |t| 0.5 * a * t * t / 3.0);
}

/// A chain of five bodies (`body`, its parameters) from a wall, joined by
/// `element` (a kind with its parameters); names start with `prefix`. The
/// bodies start spread out and at rest.
fn chain(prefix: &str, element: &str, body: &str, rotational: bool) -> (String, String) {
    let (a, b, wall, wall_end, p, v) = if rotational {
        ("spline_a", "spline_b", "RotationalComponents.Fixed()", "spline", "phi", "w")
    } else {
        ("flange_a", "flange_b", "TranslationalComponents.Fixed()", "flange", "s", "v")
    };
    let mut parts = format!("  {prefix}wall = {wall}\n");
    let mut links = String::new();
    for i in 1..=5 {
        let start = 0.1 * i as f64 + 0.01 * (i * i) as f64;
        parts += &format!(
            "  {prefix}e{i} = {element}\n  {prefix}b{i} = {body}, {p}(initial = {start}), {v}(initial = 0))\n"
        );
        let previous = if i == 1 { format!("{prefix}wall.{wall_end}") } else { format!("{prefix}b{}.{b}", i - 1) };
        links += &format!("  connect({previous}, {prefix}e{i}.{a})\n  connect({prefix}e{i}.{b}, {prefix}b{i}.{a})\n");
    }
    (parts, links)
}

/// A Dyad-written twin in a chain of five, beside the same chain of the
/// built-in element: every body's position agrees to 1e-10. At tolerance
/// 1e-13: a written relation (the backlash's contact) holds its value
/// until its event, as in Modelica, where the built-in law switches inside
/// the integration step that crosses it, so the two differ by the
/// integrator's error (1.9e-10 at 1e-11, 7e-12 at 1e-13).
fn twin_chain(twin: &str, builtin: &str, params: &str, rotational: bool) {
    let (body, p) = if rotational {
        ("RotationalComponents.Inertia(J = 0.3", "phi")
    } else {
        ("TranslationalComponents.Mass(m = 0.3", "s")
    };
    let (tw_parts, tw_links) = chain("t_", &format!("{twin}({params})"), body, rotational);
    let (bi_parts, bi_links) = chain("l_", &format!("{builtin}({params})"), body, rotational);
    let s = simulate(&format!(
        "example component Twins\n{tw_parts}{bi_parts}relations\n{tw_links}{bi_links}end\n\
         analysis Run\n  {TIGHT}\n  model = Twins()\nend\n"
    ));
    for i in 1..=5 {
        compare(&s, &format!("t_b{i}.{p}"), &format!("l_b{i}.{p}"), 1e-10);
    }
}

#[test]
fn the_rotational_twins_move_as_the_built_in_elements() {
    twin_chain("RotationalComponents.Acausal.Spring", "RotationalComponents.Spring", "c = 40", true);
    twin_chain("RotationalComponents.Acausal.Damper", "RotationalComponents.Damper", "d = 0.7", true);
    twin_chain(
        "RotationalComponents.Acausal.SpringDamper",
        "RotationalComponents.SpringDamper",
        "c = 40, d = 0.7, phi_rel0 = 0.02",
        true,
    );
    twin_chain(
        "RotationalComponents.Acausal.ElastoBacklash",
        "RotationalComponents.ElastoBacklash",
        "c = 40, d = 0.7, b = 0.05",
        true,
    );
}

#[test]
fn the_translational_twins_move_as_the_built_in_elements() {
    twin_chain(
        "TranslationalComponents.Acausal.Spring",
        "TranslationalComponents.Spring",
        "c = 40, s_rel0 = 0.05",
        false,
    );
    twin_chain("TranslationalComponents.Acausal.Damper", "TranslationalComponents.Damper", "d = 0.7", false);
    twin_chain(
        "TranslationalComponents.Acausal.SpringDamper",
        "TranslationalComponents.SpringDamper",
        "c = 40, d = 0.7",
        false,
    );
}

/// Two inertias and a written part between them, run as an analysis.
fn between_inertias(part: &str) -> String {
    format!(
        "{part}
example component Between
  j1 = RotationalComponents.Inertia(J = 1, phi(initial = 0), w(initial = 1))
  part = Part()
  j2 = RotationalComponents.Inertia(J = 2)
relations
  connect(j1.spline_b, part.flange_a)
  connect(part.flange_b, j2.spline_a)
end
analysis Run
  {RUN}
  model = Between()
end"
    )
}

/// The message for a written `Part` between two inertias, holding each
/// of `expected` (the cause, and the equation under its caret).
fn assert_refused(part: &str, expected: &[&str]) {
    let message = error_of(&between_inertias(part));
    println!("{message}");
    for e in expected {
        assert!(message.contains(e), "`{e}` missing from: {message}");
    }
}

#[test]
fn flows_that_would_do_work_are_refused() {
    assert_refused(
        "component Part
  flange_a = Spline()
  flange_b = Spline()
relations
  flange_a.phi = 2 * flange_b.phi
  flange_a.tau + flange_b.tau = 0
end",
        &["not those of an ideal constraint", "flange_a.tau + flange_b.tau = 0"],
    );
}

/// Force sensors of the library form in line on a chain of masses and
/// springs (at the wall, between two masses, between a spring and the last
/// mass), side by side with the same chain without them: the motion is the
/// same, and each reading is the force the built-in elements give there.
#[test]
fn force_sensors_in_line_read_the_forces_of_the_chain_without_them() {
    let s = simulate(&format!(
        "example component Sensed
  wall = TranslationalComponents.Fixed()
  at_wall = TranslationalComponents.ForceSensor()
  spring1 = TranslationalComponents.Spring(c = 40)
  m1 = TranslationalComponents.Mass(m = 1, s(initial = 0.3), v(initial = 0))
  middle = TranslationalComponents.MultiSensor()
  m2 = TranslationalComponents.Mass(m = 2)
  spring2 = TranslationalComponents.Spring(c = 25, s_rel0 = 0.5)
  at_end = TranslationalComponents.PowerSensor()
  m3 = TranslationalComponents.Mass(m = 0.5, s(initial = 1), v(initial = 0.5))
  twin_wall = TranslationalComponents.Fixed()
  twin_spring1 = TranslationalComponents.Spring(c = 40)
  twin_m1 = TranslationalComponents.Mass(m = 1, s(initial = 0.3), v(initial = 0))
  twin_m2 = TranslationalComponents.Mass(m = 2)
  twin_spring2 = TranslationalComponents.Spring(c = 25, s_rel0 = 0.5)
  twin_m3 = TranslationalComponents.Mass(m = 0.5, s(initial = 1), v(initial = 0.5))
relations
  connect(wall.flange, at_wall.flange_a)
  connect(at_wall.flange_b, spring1.flange_a)
  connect(spring1.flange_b, m1.flange_a)
  connect(m1.flange_b, middle.flange_a)
  connect(middle.flange_b, m2.flange_a)
  connect(m2.flange_b, spring2.flange_a)
  connect(spring2.flange_b, at_end.flange_a)
  connect(at_end.flange_b, m3.flange_a)
  connect(twin_wall.flange, twin_spring1.flange_a)
  connect(twin_spring1.flange_b, twin_m1.flange_a)
  connect(twin_m1.flange_b, twin_m2.flange_a)
  connect(twin_m2.flange_b, twin_spring2.flange_a)
  connect(twin_spring2.flange_b, twin_m3.flange_a)
end
analysis Run
  {TIGHT}
  model = Sensed()
end"
    ));
    for mass in ["m1", "m2", "m3"] {
        compare(&s, &format!("{mass}.s"), &format!("twin_{mass}.s"), 1e-10);
    }
    let twin = |name: &str| column(&s, name).to_vec();
    let (f1, f2, a2, a3, v3) =
        (twin("twin_spring1.f"), twin("twin_spring2.f"), twin("twin_m2.a"), twin("twin_m3.a"), twin("twin_m3.v"));
    let exact = |name: &str, value: &dyn Fn(usize) -> f64| {
        let worst = column(&s, name).iter().enumerate().map(|(i, y)| (y - value(i)).abs()).fold(0.0, f64::max);
        report(name, worst, 1e-9);
    };
    // The wall holds the first spring; the middle sensor pushes the second
    // mass against the second spring; the last one alone moves the end mass.
    exact("at_wall.f", &|i| -f1[i]);
    exact("middle.f", &|i| 2.0 * a2[i] - f2[i]);
    exact("middle.v", &|i| column(&s, "twin_m2.v")[i]);
    exact("at_end.power", &|i| 0.5 * a3[i] * v3[i]);
}

/// The MultiSensor that holds ElasticBearing's housing to its stiff
/// spring-damper reads the torque the built-in spring-damper gives, the
/// housing's speed, and their product.
#[test]
fn the_elastic_bearing_sensor_reads_the_spring_damper() {
    let text = example("msl/ElasticBearing.dyad");
    let s = simulate(&text);
    let spring_damper = column(&s, "springDamper.tau");
    let scale = spring_damper.iter().fold(0.0f64, |a, x| a.max(x.abs()));
    let negated: Vec<f64> = spring_damper.iter().map(|x| -x).collect();
    report(
        "multiSensor.tau vs -springDamper.tau",
        worst_difference(column(&s, "multiSensor.tau"), &negated),
        1e-12 * scale,
    );
    compare(&s, "multiSensor.w", "housing.w", 1e-12);
    let power: Vec<f64> = negated.iter().zip(column(&s, "housing.w")).map(|(t, w)| t * w).collect();
    report("multiSensor.power", worst_difference(column(&s, "multiSensor.power"), &power), 1e-12 * scale);
}

/// A measured torque fed back into the drive would act on the motion that
/// decides it: refused, naming what it would feed.
#[test]
fn a_measured_flow_cannot_drive_the_motion() {
    let message = error_of(&format!(
        "example component Feedback
  fixed = RotationalComponents.Fixed()
  motor = RotationalComponents.Torque()
  sensor = RotationalComponents.TorqueSensor()
  gain = BlockComponents.Gain(k = -1)
  j = RotationalComponents.Inertia(J = 0.5, phi(initial = 0), w(initial = 1))
relations
  connect(sensor.tau, gain.u)
  connect(gain.y, motor.tau)
  connect(motor.support, fixed.spline)
  connect(motor.spline, sensor.spline_a)
  connect(sensor.spline_b, j.spline_a)
end
analysis Run
  {RUN}
  model = Feedback()
end"
    ));
    println!("{message}");
    for expected in ["gives `gain` a value from a flow measured through a rigid part", "tau = spline_a.tau"] {
        assert!(message.contains(expected), "`{expected}` missing from: {message}");
    }
}

/// A sensor whose two sides an inertia also joins measures nothing
/// determined: refused.
#[test]
fn a_flow_with_two_rigid_paths_is_refused() {
    let message = error_of(&format!(
        "example component Loop
  j = RotationalComponents.Inertia(J = 0.5, phi(initial = 0), w(initial = 1))
  sensor = RotationalComponents.TorqueSensor()
relations
  connect(j.spline_b, sensor.spline_a)
  connect(sensor.spline_b, j.spline_a)
end
analysis Run
  {RUN}
  model = Loop()
end"
    ));
    println!("{message}");
    assert!(message.contains("other rigid parts hold together too"), "{message}");
}

/// Events are watched before the accelerations, so a `when` on a measured
/// torque is refused with its clause under the caret.
#[test]
fn a_when_on_a_measured_flow_is_refused() {
    assert_refused(
        "component Part
  flange_a = Spline()
  flange_b = Spline()
  variable tau::Torque
  variable hits::Real = initial 0
relations
  flange_a.phi = flange_b.phi
  flange_a.tau + flange_b.tau = 0
  tau = flange_a.tau
  when tau > 1
    hits = pre(hits) + 1
  end
end",
        &["this `when` reads", "depends on a flow measured through a rigid part"],
    );
}

#[test]
fn position_equations_that_contradict_each_other_are_refused() {
    assert_refused(
        "component Part
  flange_a = Spline()
  flange_b = Spline()
relations
  flange_b.phi - flange_a.phi = 1
  flange_a.phi - flange_b.phi = 1
end",
        &["contradict each other"],
    );
}

/// A pinion driven by a torque moves a rack on a spring through the written
/// rack and through the built-in one: the same motion to 1e-10.
#[test]
fn the_rack_twin_moves_as_the_built_in_rack() {
    let s = simulate(&format!(
        "example component Racks
  k = BlockComponents.Sine(amplitude = 3, frequency = 0.7)
  rfix = RotationalComponents.Fixed()
  tfix = TranslationalComponents.Fixed()
  src_w = RotationalComponents.Torque()
  pinion_w = RotationalComponents.Inertia(J = 0.02, phi(initial = 0), w(initial = 0))
  rack_w = RotationalComponents.Acausal.IdealGearR2T(ratio = 20)
  mass_w = TranslationalComponents.Mass(m = 4)
  spring_w = TranslationalComponents.Spring(c = 300)
  src_b = RotationalComponents.Torque()
  pinion_b = RotationalComponents.Inertia(J = 0.02, phi(initial = 0), w(initial = 0))
  rack_b = RotationalComponents.IdealGearR2T(ratio = 20)
  mass_b = TranslationalComponents.Mass(m = 4)
  spring_b = TranslationalComponents.Spring(c = 300)
relations
  connect(k.y, src_w.tau, src_b.tau)
  connect(rfix.spline, src_w.support, src_b.support)
  connect(src_w.spline, pinion_w.spline_a)
  connect(pinion_w.spline_b, rack_w.spline)
  connect(rack_w.flange, mass_w.flange_a)
  connect(mass_w.flange_b, spring_w.flange_a)
  connect(spring_w.flange_b, tfix.flange)
  connect(src_b.spline, pinion_b.spline_a)
  connect(pinion_b.spline_b, rack_b.spline)
  connect(rack_b.flange, mass_b.flange_a)
  connect(mass_b.flange_b, spring_b.flange_a)
  connect(spring_b.flange_b, tfix.flange)
end
analysis Run
  {RUN}
  model = Racks()
end"
    ));
    compare(&s, "pinion_w.phi", "pinion_b.phi", 1e-10);
    compare(&s, "mass_w.s", "mass_b.s", 1e-10);
}

/// An equation between two joints' axis angles couples the joints: two
/// pendulums held to one angle move as the single pendulum that carries
/// both bodies.
#[test]
fn an_equation_between_joint_axes_couples_the_joints() {
    let s = simulate(&format!(
        "example component Coupled
  world = MultibodyComponents.World()
  rev1 = MultibodyComponents.Revolute(axisflange = true, phi(initial = 0.3), w(initial = 0))
  body1 = MultibodyComponents.Body(m = 1, r_cm = [0.5, 0, 0])
  rev2 = MultibodyComponents.Revolute(axisflange = true)
  body2 = MultibodyComponents.Body(m = 2, r_cm = [0.3, 0.1, 0])
  single = MultibodyComponents.Revolute(phi(initial = 0.3), w(initial = 0))
  both1 = MultibodyComponents.Body(m = 1, r_cm = [0.5, 0, 0])
  both2 = MultibodyComponents.Body(m = 2, r_cm = [0.3, 0.1, 0])
relations
  connect(world.frame_b, rev1.frame_a, rev2.frame_a, single.frame_a)
  connect(rev1.frame_b, body1.frame_a)
  connect(rev2.frame_b, body2.frame_a)
  connect(single.frame_b, both1.frame_a, both2.frame_a)
  rev1.axis.phi = rev2.axis.phi
end
analysis Run
  {RUN}
  model = Coupled()
end"
    ));
    compare(&s, "rev1.phi", "single.phi", 1e-9);
    compare(&s, "rev2.phi", "single.phi", 1e-9);
}
