//! The values a live parameter panel offers (`Lowered::tunables`): which
//! are listed, with what value, unit and bounds, and that each one set
//! back through an `Override` gives the same model, and a changed one a
//! different model.

use multibody_dyad::{Lowered, Package, Target, Tunable, TunableKind};

const DOUBLE_PENDULUM: &str = include_str!("../../../examples/double_pendulum.dyad");

fn package(text: &str) -> Package {
    let mut p = Package::new();
    if let Err(d) = p.add_source("model.dyad", text) {
        panic!("{}", d.render(p.sources(), false));
    }
    p
}

fn lower(p: &Package, target: &Target, overrides: &[multibody_dyad::Override]) -> Lowered {
    p.lower_target(target, overrides).unwrap_or_else(|d| panic!("{}", d.render(p.sources(), false)))
}

/// Path, kind, value and unit of each tunable, in order.
fn summary(tunables: &[Tunable]) -> Vec<(String, TunableKind, f64, Option<String>)> {
    tunables.iter().map(|t| (t.path.clone(), t.kind, t.value, t.unit.clone())).collect()
}

fn row(path: &str, kind: TunableKind, value: f64, unit: &str) -> (String, TunableKind, f64, Option<String>) {
    (path.to_string(), kind, value, Some(unit.to_string()))
}

/// Every tunable set to its own value gives the same model and list; set
/// to another value, a different model, where the tunable has that value.
fn round_trips(p: &Package, target: &Target) {
    let lowered = lower(p, target, &[]);
    let model = format!("{:?}", lowered.model);
    assert!(!lowered.tunables.is_empty());
    for t in &lowered.tunables {
        let same = lower(p, target, &[t.set(t.value)]);
        assert_eq!(format!("{:?}", same.model), model, "{} set to its own value", t.path);
        // The same list, but for the tunable itself: given from outside,
        // it no longer follows other parameters.
        let mut expected = lowered.tunables.clone();
        expected.iter_mut().filter(|e| e.path == t.path).for_each(|e| e.derived = false);
        assert_eq!(same.tunables, expected, "{} set to its own value", t.path);

        let changed_value = if t.integer { t.value + 1.0 } else { t.value + 0.25 };
        let changed = lower(p, target, &[t.set(changed_value)]);
        assert_ne!(format!("{:?}", changed.model), model, "{} changed", t.path);
        let listed = changed.tunables.iter().find(|c| c.path == t.path).expect("still listed");
        assert_eq!(listed.value, changed_value, "{}", t.path);
    }
}

#[test]
fn the_double_pendulum_offers_its_links_parameters_and_start_values() {
    use TunableKind::{Parameter, Start};
    let p = package(DOUBLE_PENDULUM);
    let lowered = lower(&p, &Target::Analysis("DoublePendulumSimulation".into()), &[]);
    assert_eq!(
        summary(&lowered.tunables),
        vec![
            row("link1.length", Parameter, 0.5, "m"),
            row("link1.width", Parameter, 0.06, "m"),
            row("link1.d", Parameter, 0.1, "N.m.s/rad"),
            row("link1.joint.phi", Start, 0.0, "rad"),
            row("link1.joint.w", Start, 0.0, "rad/s"),
            row("link2.length", Parameter, 0.5, "m"),
            row("link2.width", Parameter, 0.06, "m"),
            row("link2.d", Parameter, 0.0, "N.m.s/rad"),
            row("link2.joint.phi", Start, 0.0, "rad"),
            row("link2.joint.w", Start, 0.0, "rad/s"),
        ]
    );
    let length = &lowered.tunables[0];
    assert_eq!(length.doc.as_deref(), Some("Length of the box"));
    assert_eq!((length.min, length.max, length.integer, length.derived), (None, None, false, false));
    assert_eq!(p.sources().slice(length.span).trim(), "parameter length::Length = 0.5");
    let phi = &lowered.tunables[3];
    assert_eq!(phi.doc.as_deref(), Some("Relative rotation angle from frame_a to frame_b"));
    assert!(p.sources().slice(phi.span).starts_with("joint = MultibodyComponents.Revolute("));
    assert!(lowered.tunables.iter().all(|t| !t.derived));
}

#[test]
fn the_double_pendulum_round_trips_as_analysis_and_as_component() {
    let p = package(DOUBLE_PENDULUM);
    round_trips(&p, &Target::Analysis("DoublePendulumSimulation".into()));
    round_trips(&p, &Target::Component("DoublePendulum".into()));
    let analysis = lower(&p, &Target::Analysis("DoublePendulumSimulation".into()), &[]);
    let component = lower(&p, &Target::Component("DoublePendulum".into()), &[]);
    assert_eq!(analysis.tunables, component.tunables);
}

const NESTED: &str = r#"
component Link
  frame_a = Frame3D()
  frame_b = Frame3D()
  parameter length::Length = 0.5
  "Mass of the link"
  parameter m::Mass = 1
  "Half the length: it follows `length`"
  parameter half::Length = length / 2
  parameter n_marks::Integer = 3
  parameter stiffness::Real(min = 0.5, max = 10) = 2
  parameter k::Stiffness = 4
  final parameter fixed_value::Real = 1
  parameter axis::Real[3] = [0, 0, 1]
  parameter visible::Boolean = true
  parameter label::String = "link"
  joint = MultibodyComponents.Revolute(n = axis, phi(initial = 0.1 * n_marks), w(initial = 0))
  body = MultibodyComponents.Body(m = m, r_cm = [half, 0, 0])
  rod = MultibodyComponents.FixedTranslation(r = [length, 0, 0])
  damper = RotationalComponents.Components.Damper(d = stiffness / 10 + k / 100)
relations
  connect(frame_a, joint.frame_a)
  connect(joint.frame_b, body.frame_a, rod.frame_a)
  connect(rod.frame_b, frame_b)
  connect(damper.spline_a, joint.support)
  connect(damper.spline_b, joint.axis)
end

type Stiffness = Real(units = "N/m", min = 0)

component Arm
  frame_a = Frame3D()
  parameter L::Length = 0.4
  link1 = Link(length = L)
  link2 = Link(m = 2)
relations
  connect(frame_a, link1.frame_a)
  connect(link1.frame_b, link2.frame_a)
end

example component Robot
  world = MultibodyComponents.World()
  arm = Arm()
relations
  connect(world.frame_b, arm.frame_a)
end

analysis RobotRun
  extends TransientAnalysis(stop = 1)
  parameter L2::Length = 0.7
  model = Robot(arm(link2(length = L2, joint(w(initial = 1)))))
end
"#;

#[test]
fn nested_user_components_give_paths_through_both_levels() {
    use TunableKind::{Parameter, Start};
    let p = package(NESTED);
    let lowered = lower(&p, &Target::Analysis("RobotRun".into()), &[]);
    let link = |prefix: &str, length: f64, m: f64, w: f64| {
        vec![
            row(&format!("{prefix}.length"), Parameter, length, "m"),
            row(&format!("{prefix}.m"), Parameter, m, "kg"),
            row(&format!("{prefix}.half"), Parameter, length / 2.0, "m"),
            (format!("{prefix}.n_marks"), Parameter, 3.0, None),
            (format!("{prefix}.stiffness"), Parameter, 2.0, None),
            row(&format!("{prefix}.k"), Parameter, 4.0, "N/m"),
            row(&format!("{prefix}.joint.phi"), Start, 0.1 * 3.0, "rad"),
            row(&format!("{prefix}.joint.w"), Start, w, "rad/s"),
        ]
    };
    let mut expected = vec![row("arm.L", Parameter, 0.4, "m")];
    expected.extend(link("arm.link1", 0.4, 1.0, 0.0));
    expected.extend(link("arm.link2", 0.7, 2.0, 1.0));
    assert_eq!(summary(&lowered.tunables), expected);

    let get = |path: &str| lowered.tunables.iter().find(|t| t.path == path).unwrap();
    // Values computed from parameters are marked: here or in the enclosing
    // component (`Link(length = L)`) or in the analysis (`length = L2`).
    let derived: Vec<&str> = lowered.tunables.iter().filter(|t| t.derived).map(|t| t.path.as_str()).collect();
    assert_eq!(
        derived,
        [
            "arm.link1.length",
            "arm.link1.half",
            "arm.link1.joint.phi",
            "arm.link2.length",
            "arm.link2.half",
            "arm.link2.joint.phi"
        ]
    );
    assert_eq!(get("arm.link1.m").doc.as_deref(), Some("Mass of the link"));
    assert_eq!((get("arm.link1.m").min, get("arm.link1.m").max), (Some(0.0), None));
    assert_eq!((get("arm.link1.stiffness").min, get("arm.link1.stiffness").max), (Some(0.5), Some(10.0)));
    assert_eq!((get("arm.link1.k").min, get("arm.link1.k").max), (Some(0.0), None));
    assert!(get("arm.link1.n_marks").integer);
    assert!(!get("arm.link1.length").integer);

    round_trips(&p, &Target::Analysis("RobotRun".into()));
    round_trips(&p, &Target::Component("Robot".into()));
}

#[test]
fn overriding_a_derived_value_cuts_its_link() {
    let p = package(NESTED);
    let target = Target::Component("Robot".into());
    let lowered = lower(&p, &target, &[multibody_dyad::Override::parameter("arm.link1.length", 0.9)]);
    let get = |path: &str| lowered.tunables.iter().find(|t| t.path == path).unwrap();
    assert_eq!((get("arm.L").value, get("arm.link1.length").value), (0.4, 0.9));
    assert!(!get("arm.link1.length").derived);
    assert_eq!(get("arm.link1.half").value, 0.45);
}

#[test]
fn start_values_of_the_models_own_equations_are_listed() {
    use TunableKind::{Parameter, Start};
    let p = package(
        r#"
component Decay
  parameter T::Time = 0.5
  parameter x0::Real = 1
  "Decays with time constant T"
  variable x::Real = initial x0
  variable v::Velocity = initial 0.2
  variable z::Real
  variable g::Real
  variable arr::Real[2] = initial [1, 2]
relations
  initial z = 3
  guess g = 1
  der(x) = -x / T
  der(v) = -v
  der(z) = -z
  g = 2 * z
  der(arr[1]) = -arr[1]
  der(arr[2]) = -arr[2]
end

example component Two
  a = Decay()
  b = Decay(x0 = 2, v(initial = 0.5))
end
"#,
    );
    let target = Target::Component("Two".into());
    let lowered = lower(&p, &target, &[]);
    let mut expected = Vec::new();
    for (prefix, x0, v) in [("a", 1.0, 0.2), ("b", 2.0, 0.5)] {
        expected.extend([
            row(&format!("{prefix}.T"), Parameter, 0.5, "s"),
            (format!("{prefix}.x0"), Parameter, x0, None),
            (format!("{prefix}.x"), Start, x0, None),
            row(&format!("{prefix}.v"), Start, v, "m/s"),
            (format!("{prefix}.z"), Start, 3.0, None),
        ]);
    }
    assert_eq!(summary(&lowered.tunables), expected);
    let x = lowered.tunables.iter().find(|t| t.path == "a.x").unwrap();
    assert!(x.derived);
    assert_eq!(x.doc.as_deref(), Some("Decays with time constant T"));
    round_trips(&p, &target);
}

#[test]
fn the_standard_librarys_components_offer_nothing_of_their_own() {
    // A PID written in Dyad in the standard library: its parameters and
    // inner start values are not the model's; what the files give it is
    // a library component's parameter, not listed either.
    let p = package(
        r#"
example component Loop
  parameter gain::Real = 2
  source = BlockComponents.Constant(k = 1)
  pid = BlockComponents.PID(k = gain)
relations
  connect(source.y, pid.u_s)
  connect(pid.y, pid.u_m)
end
"#,
    );
    let lowered = lower(&p, &Target::Component("Loop".into()), &[]);
    assert_eq!(summary(&lowered.tunables), vec![("gain".to_string(), TunableKind::Parameter, 2.0, None)]);
}

/// Every example's tunables set back to their own values give the same
/// model; changed (by 10 %, or by one for whole numbers), the model still
/// lowers.
#[test]
fn every_examples_tunables_round_trip() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples");
    let mut files = Vec::new();
    let mut stack = vec![dir.clone()];
    while let Some(d) = stack.pop() {
        for entry in std::fs::read_dir(&d).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                stack.push(path);
            } else if path.extension().is_some_and(|e| e == "dyad") {
                files.push(path);
            }
        }
    }
    files.sort();
    let mut listed = 0;
    for path in files {
        let relative = path.strip_prefix(&dir).unwrap().display().to_string();
        let mut p = Package::new();
        p.add_source(relative.clone(), std::fs::read_to_string(&path).unwrap()).unwrap();
        for analysis in p.definitions().into_iter().filter(|d| d.kind == multibody_dyad::DefinitionKind::Analysis) {
            let target = Target::Analysis(analysis.name.clone());
            let Ok(lowered) = p.lower_target(&target, &[]) else { continue };
            let model = format!("{:?}", lowered.model);
            for t in &lowered.tunables {
                listed += 1;
                let same = p
                    .lower_target(&target, &[t.set(t.value)])
                    .unwrap_or_else(|d| panic!("{relative}: {}: {}", t.path, d.render(p.sources(), false)));
                assert_eq!(format!("{:?}", same.model), model, "{relative}: {}", t.path);
                let changed = if t.integer { t.value + 1.0 } else { t.value * 1.1 + 0.01 };
                if let (Err(d), None) = (p.lower_target(&target, &[t.set(changed)]), t.max) {
                    panic!("{relative}: {} = {changed}: {}", t.path, d.render(p.sources(), false));
                }
            }
        }
    }
    assert!(listed > 20, "{listed}");
}
