//! A planar force law written in equations on Frame2D connectors (reading
//! x, y and phi, writing fx, fy and tau) moves a body as the library's
//! PlanarMechanics.SpringDamper with the same constants (its damping off:
//! `der` of a connector's quantity inside a component is not supported
//! yet, for 3-D frames as for planar ones).

use multibody::{SimulationOptions, Solution};
use multibody_dyad::Package;

fn simulate(text: &str, model: &str) -> Solution {
    let mut package = Package::new();
    if let Err(d) = package.add_source("planar.dyad", text.to_string()) {
        panic!("{}", d.render(package.sources(), false));
    }
    let lowered = package.lower_component(model).unwrap_or_else(|d| panic!("{}", d.render(package.sources(), false)));
    let options = SimulationOptions { stop: 4.0, saveat: 0.01, abstol: 1e-11, reltol: 1e-11, ..Default::default() };
    lowered.assemble().unwrap_or_else(|d| panic!("{}", d.render(package.sources(), false))).simulate(&options).unwrap()
}

const MODELS: &str = "
component WrittenSpringDamper
  frame_a = Frame2D()
  frame_b = Frame2D()
  parameter c::Real = 4
  parameter k::Real = 2
relations
  frame_b.fx = c * (frame_b.x - frame_a.x)
  frame_b.fy = c * (frame_b.y - frame_a.y)
  frame_b.tau = k * (frame_b.phi - frame_a.phi)
  frame_a.fx = -frame_b.fx
  frame_a.fy = -frame_b.fy
  frame_a.tau = -frame_b.tau
end

example component Written
  world = MultibodyComponents.PlanarMechanics.World()
  anchor = MultibodyComponents.PlanarMechanics.Fixed(r = [0, 1])
  law = WrittenSpringDamper()
  body = MultibodyComponents.PlanarMechanics.Body(m = 0.5, I = 0.05, r(initial = [1, 0.5]), v(initial = [0, 0.4]), phi(initial = 0.3), w(initial = 0))
relations
  connect(anchor.frame_b, law.frame_a)
  connect(law.frame_b, body.frame_a)
end

example component Library
  world = MultibodyComponents.PlanarMechanics.World()
  anchor = MultibodyComponents.PlanarMechanics.Fixed(r = [0, 1])
  law = MultibodyComponents.PlanarMechanics.SpringDamper(c_x = 4, c_y = 4, c_phi = 2, d_x = 0, d_y = 0, d_phi = 0)
  body = MultibodyComponents.PlanarMechanics.Body(m = 0.5, I = 0.05, r(initial = [1, 0.5]), v(initial = [0, 0.4]), phi(initial = 0.3), w(initial = 0))
relations
  connect(anchor.frame_b, law.frame_a)
  connect(law.frame_b, body.frame_a)
end
";

#[test]
fn a_planar_force_law_in_equations_moves_a_body_as_the_library_spring_damper() {
    let (written, library) = (simulate(MODELS, "Written"), simulate(MODELS, "Library"));
    let mut worst = 0.0f64;
    for name in ["body.r[1]", "body.r[2]", "body.phi", "body.w"] {
        let (a, b) = (written.get(name).unwrap(), library.get(name).unwrap());
        worst = a.iter().zip(b).fold(worst, |m, (x, y)| m.max((x - y).abs()));
    }
    eprintln!("planar law in equations against SpringDamper: worst difference {worst:.1e} (tolerance 1e-8)");
    assert!(worst < 1e-8, "the written law differs from SpringDamper by {worst:e}");
    let turned = written.get("body.phi").unwrap().iter().fold(0.0f64, |m, p| m.max((p - 0.3).abs()));
    assert!(turned > 0.1, "the body should turn back from 0.3 rad");
}

/// In a plane placed in 3-D (`r_0_3d`, `rot_3d`), equations still read a
/// planar frame's `x`, `y` and `phi` and give its `fx`, `fy` and `tau` in
/// the plane: the written law moves the body exactly as in the x-y plane.
#[test]
fn a_planar_force_law_in_equations_works_in_the_plane_wherever_the_plane_is() {
    let placed = MODELS.replace(
        "world = MultibodyComponents.PlanarMechanics.World()",
        "world = MultibodyComponents.PlanarMechanics.World(r_0_3d = [1, -2, 0.5], rot_3d = [0.7, -0.4, 1.1])",
    );
    let (flat, moved) = (simulate(MODELS, "Written"), simulate(&placed, "Written"));
    let mut worst = 0.0f64;
    for name in ["body.r[1]", "body.r[2]", "body.phi", "body.w", "law.frame_b.fx", "law.frame_b.tau"] {
        let (a, b) = (flat.get(name).unwrap(), moved.get(name).unwrap_or_else(|| panic!("no {name}")));
        worst = a.iter().zip(b).fold(worst, |m, (x, y)| m.max((x - y).abs()));
    }
    eprintln!("written planar law in a placed plane: worst difference {worst:.1e} (tolerance 1e-8)");
    assert!(worst < 1e-8, "the placed plane changes the written law's motion by {worst:e}");
}

/// The library's PlanarToMultiBodyEmbeddedTest written as a user would: a
/// planar pose prescribed by equations of time in a plane at [1, 2, 3]
/// puts the adapter's 3-D frame at [6, 4.5, 3.5] at t = 5 (its page says
/// so), turned about z by 0.3 t.
#[test]
fn planar_to_multibody_embedded_test_puts_the_3d_frame_where_its_page_says() {
    let text = "
test component EmbeddedPlane
  world = MultibodyComponents.PlanarMechanics.World(r_0_3d = [1.0, 2.0, 3.0])
  prescribed = MultibodyComponents.PlanarMechanics.PrescribedPose()
  body = MultibodyComponents.PlanarMechanics.Body(m = 1.0, I = 1.0)
  adapter = MultibodyComponents.PlanarMechanics.PlanarToMultiBody(z_position = 0.5)
  sensor = MultibodyComponents.AbsoluteAngles()
relations
  prescribed.r_x = time
  prescribed.r_y = 0.5 * time
  prescribed.phi = 0.3 * time
  connect(prescribed.frame_b, body.frame_a, adapter.frame_a)
  connect(adapter.frame_b, sensor.frame_a)
end
";
    let mut package = Package::new();
    package.add_source("embedded.dyad", text.to_string()).unwrap();
    let lowered =
        package.lower_component("EmbeddedPlane").unwrap_or_else(|d| panic!("{}", d.render(package.sources(), false)));
    let options = SimulationOptions { stop: 5.0, saveat: 0.1, ..Default::default() };
    let s = lowered
        .assemble()
        .unwrap_or_else(|d| panic!("{}", d.render(package.sources(), false)))
        .simulate(&options)
        .unwrap();
    let mut worst = 0.0f64;
    for (k, t) in s.time().iter().enumerate() {
        let expected = [1.0 + t, 2.0 + 0.5 * t, 3.5];
        for (i, e) in expected.iter().enumerate() {
            worst = worst.max((s.get(&format!("adapter.frame_b.r_0[{}]", i + 1)).unwrap()[k] - e).abs());
        }
        worst = worst.max((s.get("sensor.angles[3]").unwrap()[k] - 0.3 * t).abs());
    }
    let last = s.time().len() - 1;
    let r: Vec<f64> = (1..=3).map(|i| s.get(&format!("adapter.frame_b.r_0[{i}]")).unwrap()[last]).collect();
    eprintln!("PlanarToMultiBodyEmbeddedTest: r_0 at t = 5 is {r:?} (page: [6, 4.5, 3.5]); worst error {worst:.1e}");
    assert!(worst < 1e-9, "the embedded adapter is off by {worst:e}");
}
