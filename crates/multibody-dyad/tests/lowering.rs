//! What the supported language means: modifiers, parameters, user
//! components and their connectors, packages of several files, and the
//! analysis options.

use multibody::{Method, Value};
use multibody_dyad::{Lowered, Package};

fn package(files: &[(&str, &str)]) -> Package {
    let mut p = Package::new();
    for (name, text) in files {
        if let Err(d) = p.add_source(*name, *text) {
            panic!("{}", d.render(p.sources(), false));
        }
    }
    p
}

fn analysis(text: &str, name: &str) -> Lowered {
    let p = package(&[("test.dyad", text)]);
    p.lower_analysis(name).unwrap_or_else(|d| panic!("{}", d.render(p.sources(), false)))
}

fn component(text: &str, name: &str) -> Lowered {
    let p = package(&[("test.dyad", text)]);
    p.lower_component(name).unwrap_or_else(|d| panic!("{}", d.render(p.sources(), false)))
}

fn error(text: &str, name: &str) -> String {
    let p = package(&[("test.dyad", text)]);
    let lowered =
        if text.contains(&format!("analysis {name}")) { p.lower_analysis(name) } else { p.lower_component(name) };
    match lowered {
        Ok(l) => match l.assemble() {
            Ok(_) => panic!("expected an error"),
            Err(d) => d.render(p.sources(), false),
        },
        Err(d) => d.render(p.sources(), false),
    }
}

const PENDULUM: &str = r#"
example component Pendulum
  parameter L::Length = 0.5
  world = MultibodyComponents.World()
  joint = MultibodyComponents.Revolute(phi(initial = 0.1))
  body = MultibodyComponents.Body(r_cm = [L, 0, 0])
relations
  connect(world.frame_b, joint.frame_a)
  connect(joint.frame_b, body.frame_a)
end
"#;

fn with_analysis(extends: &str) -> String {
    format!("{PENDULUM}\nanalysis Sim\n  extends {extends}\n  model = Pendulum()\nend\n")
}

#[test]
fn analysis_options_map_to_the_engine() {
    let l = analysis(&with_analysis("TransientAnalysis(start = 1, stop = 2, abstol = 1e-8, reltol = 1e-7, saveat = 0.1, dtmax = 0.05, alg = ODEAlg.Auto())"), "Sim");
    let o = &l.options;
    assert_eq!((o.start, o.stop, o.abstol, o.reltol, o.saveat, o.dtmax), (1.0, 2.0, 1e-8, 1e-7, 0.1, 0.05));
    assert_eq!(o.method, Method::DormandPrince45);
    assert!(l.warnings.is_empty());
    assert!(l.from_analysis);
    assert_eq!(l.name, "Sim");

    let l = analysis(&with_analysis("Dyad.TransientAnalysis(stop = 1, saveat = 0.01, alg = \"RK4\")"), "Sim");
    assert_eq!(l.options.method, Method::Rk4 { dt: 0.01 });
    let l = analysis(&with_analysis("TransientAnalysis(stop = 1, dtmax = 0.002, alg = ODEAlg.RK4())"), "Sim");
    assert_eq!(l.options.method, Method::Rk4 { dt: 0.002 });
    let l = analysis(&with_analysis("TransientAnalysis(stop = 1, alg = \"auto\")"), "Sim");
    assert_eq!(l.options.method, Method::DormandPrince45);

    let l = analysis(&with_analysis("TransientAnalysis(stop = 1, alg = \"Rodas4\")"), "Sim");
    assert_eq!(l.options.method, Method::Rodas4);
    // Stiff methods that are not available give the implicit one, others the
    // default, each with a warning that says so.
    let l = analysis(&with_analysis("TransientAnalysis(stop = 1, alg = \"Rodas5P\", progress = false)"), "Sim");
    assert_eq!(l.options.method, Method::Rodas4);
    let warnings: Vec<&str> = l.warnings.iter().map(|w| w.message.as_str()).collect();
    assert!(warnings.iter().any(|w| w.contains("`Rodas5P` is not available; using Rodas4")), "{warnings:?}");
    assert!(warnings.iter().any(|w| w.contains("`progress` has no effect")), "{warnings:?}");
    let l = analysis(&with_analysis("TransientAnalysis(stop = 1, alg = ODEAlg.Tsit5())"), "Sim");
    assert_eq!(l.options.method, Method::DormandPrince45);
    let warnings: Vec<&str> = l.warnings.iter().map(|w| w.message.as_str()).collect();
    assert!(warnings.iter().any(|w| w.contains("`Tsit5` is not available")), "{warnings:?}");

    let e = error(&with_analysis("TransientAnalysis(stop = 1, alg = \"RK4\")"), "Sim");
    assert!(e.contains("RK4 takes a fixed step"), "{e}");
}

#[test]
fn analysis_parameters_and_model_modifiers() {
    let text = format!(
        "{PENDULUM}\nanalysis Sim\n  extends TransientAnalysis(stop = T)\n  parameter T::Time = 3\n  parameter length::Length = 2\n  model = Pendulum(L = length / 2, joint(phi(initial = 0.7)))\nend\n"
    );
    let l = analysis(&text, "Sim");
    assert_eq!(l.options.stop, 3.0);
    let body = l.model.component("body").unwrap();
    assert_eq!(body.param("r_cm"), Some(&Value::Array(vec![1.0, 0.0, 0.0])));
    let joint = l.model.component("joint").unwrap();
    assert_eq!(joint.initial, vec![("phi".to_string(), Value::Number(0.7))]);
}

const ARM: &str = r#"
"An arm: a joint and a body, offered through two frames"
component Arm
  frame_a = Frame3D()
  frame_b = Frame3D()
  parameter L::Length = 1
  parameter state::OrientationState = OrientationState.None()
  joint = MultibodyComponents.Revolute(phi(initial = 0), w(guess = 0.5))
  rod = MultibodyComponents.FixedTranslation(r = [L, 0, 0])
  body = MultibodyComponents.Body(r_cm = [L / 2, 0, 0], orientation_state = state)
relations
  connect(frame_a, joint.frame_a)
  connect(joint.frame_b, rod.frame_a, body.frame_a)
  connect(rod.frame_b, frame_b)
end
"#;

#[test]
fn user_components_flatten_with_their_connectors() {
    let text = format!(
        "{ARM}\nexample component Robot\n  world = MultibodyComponents.World()\n  upper = Arm(L = 2)\n  lower = Arm(joint(phi(initial = 0.3)))\nrelations\n  connect(world.frame_b, upper.frame_a)\n  connect(upper.frame_b, lower.frame_a)\nend\n"
    );
    let l = component(&text, "Robot");
    let names: Vec<&str> = l.model.components.iter().map(|c| c.name.as_str()).collect();
    assert_eq!(names, ["world", "upper.joint", "upper.rod", "upper.body", "lower.joint", "lower.rod", "lower.body"]);
    assert_eq!(l.model.component("upper.rod").unwrap().param("r"), Some(&Value::Array(vec![2.0, 0.0, 0.0])));
    assert_eq!(l.model.component("lower.body").unwrap().param("r_cm"), Some(&Value::Array(vec![0.5, 0.0, 0.0])));
    // The outer modifier wins over the inner start value; the guess stays.
    let lower_joint = l.model.component("lower.joint").unwrap();
    assert_eq!(lower_joint.initial, vec![("phi".to_string(), Value::Number(0.3))]);
    assert_eq!(lower_joint.guess, vec![("w".to_string(), Value::Number(0.5))]);
    // Only the engine's connectors are connected: the arms' frames are resolved.
    let connections: Vec<Vec<&str>> =
        l.model.connections.iter().map(|c| c.ends.iter().map(String::as_str).collect()).collect();
    assert!(connections.contains(&vec!["world.frame_b", "upper.joint.frame_a"]), "{connections:?}");
    assert!(connections.contains(&vec!["upper.rod.frame_b", "lower.joint.frame_a"]), "{connections:?}");
    assert!(connections.iter().flatten().all(|e| !e.ends_with("frame_a") || e.matches('.').count() >= 1));
    assert!(!connections.iter().flatten().any(|e| *e == "upper.frame_a" || *e == "lower.frame_b"));
    let mechanism = l.assemble().unwrap();
    assert_eq!(mechanism.degrees_of_freedom(), 2);
}

#[test]
fn enumeration_parameters_pass_through_user_components() {
    let text = format!("{ARM}\nexample component Free\n  world = MultibodyComponents.World()\n  arm = Arm(state = OrientationState.Quaternion())\nend\n");
    let l = component(&text, "Free");
    let body = l.model.component("arm.body").unwrap();
    assert_eq!(body.param("orientation_state"), Some(&Value::Enum("OrientationState.Quaternion".into())));
    let e = error(&text.replace("OrientationState.Quaternion()", "RootedFrame.FrameA()"), "Free");
    assert!(e.contains("wrong type for the parameter `state`"), "{e}");
}

#[test]
fn a_package_spans_files() {
    let p = package(&[
        ("arm.dyad", ARM),
        (
            "robot.dyad",
            "example component Robot\n  world = World()\n  arm = Arm()\nrelations\n  connect(world.frame_b, arm.frame_a)\nend\nanalysis Go\n  extends TransientAnalysis(stop = 0.1)\n  model = Robot()\nend\n",
        ),
    ]);
    let l = p.lower_analysis("Go").unwrap();
    assert_eq!(l.model.components.len(), 4);
    let names: Vec<String> = p.top_components().into_iter().map(|d| d.name).collect();
    assert_eq!(names, ["Robot"]);
    let solution = l.assemble().unwrap().simulate(&l.options).unwrap();
    assert_eq!(solution.time().last(), Some(&0.1));
}

#[test]
fn start_values_missing_guesses_and_relations() {
    let text = r#"
example component Free
  world = MultibodyComponents.World()
  body = MultibodyComponents.Body(orientation_state = OrientationState.Quaternion(), r_0(initial = missing), v_0(initial = [1, 0, 0], guess = [0, 0, 0]))
relations
  initial body.w_a = [0, 0, 1]
end
"#;
    let l = component(text, "Free");
    let body = l.model.component("body").unwrap();
    assert_eq!(
        body.initial,
        vec![
            ("v_0".to_string(), Value::Array(vec![1.0, 0.0, 0.0])),
            ("w_a".to_string(), Value::Array(vec![0.0, 0.0, 1.0]))
        ]
    );
    assert_eq!(body.guess, vec![("v_0".to_string(), Value::Array(vec![0.0, 0.0, 0.0]))]);
    let e = error(&text.replace("r_0(initial = missing)", "r_00(initial = missing)"), "Free");
    assert!(e.contains("Body has no variable `r_00`") && e.contains("did you mean `r_0`?"), "{e}");
}

#[test]
fn expressions_types_and_bounds() {
    let text = r#"
type Len = Real(units = "m", min = 0)
type Vec3 = Real[3]
example component M
  parameter n::Integer = 2
  parameter L::Len = sqrt(2) ^ 2 / n
  parameter r::Vec3 = [L, -L, abs(-3)] * 2
  parameter diag::Real[2, 2] = [[1, 0], [0, 1]]
  parameter picked::Real = r[3] + diag[2, 2]
  parameter flag::Boolean = true
  parameter C₁::Real = 1
  world = MultibodyComponents.World()
  body = MultibodyComponents.Body(m = picked + C₁, r_cm = r, orientation_state = OrientationState.Quaternion())
end
"#;
    let l = component(text, "M");
    let body = l.model.component("body").unwrap();
    assert_eq!(body.param("m"), Some(&Value::Number(8.0)));
    let Some(Value::Array(r)) = body.param("r_cm") else { panic!() };
    assert!((r[0] - 2.0).abs() < 1e-15 && (r[1] + 2.0).abs() < 1e-15 && r[2] == 6.0, "{r:?}");
    let e = error(&text.replace("parameter n::Integer = 2", "parameter n::Integer = -2"), "M");
    assert!(e.contains("must be at least 0"), "{e}");
    let e = error(&text.replace("parameter n::Integer = 2", "parameter n::Integer = 2.5"), "M");
    assert!(e.contains("whole number"), "{e}");
}

#[test]
fn declared_connectors_that_reach_nothing_are_reported() {
    let text = "component Empty\n  frame_a = Frame3D()\nend\nexample component M\n  world = World()\n  e = Empty()\nrelations\n  connect(world.frame_b, e.frame_a)\nend\n";
    let l = component(text, "M");
    assert_eq!(l.warnings.len(), 1);
    assert!(l.warnings[0].message.contains("`frame_a` of `Empty` reaches no component"), "{:?}", l.warnings);
    assert!(l.model.connections.is_empty());
}

#[test]
fn the_documentation_examples_parse() {
    // From the notes on the language: old-style metadata, `#` docs, `;`, empty relations.
    let text = r#"
# Linear 1D rotational spring
component Spring
  spline_a = Spline() [{
    "JuliaSim": {"placement": {"icon": {"x1": -50, "y1": 450, "x2": 50, "y2": 550}}}
  }]
  spline_b = Spline() [{
    "JuliaSim": {"placement": {"icon": {"x1": 950, "y1": 450, "x2": 1050, "y2": 550}}}
  }];
  # Spring constant
  parameter c::RotationalSpringConstant(final min = 0) = 100000
relations
metadata {"JuliaSim": {"icons": {"default": "jsml://RotationalComponents/Spring.svg"}}}
end

example component EulerBody
  world = MultibodyComponents.World()
  body = MultibodyComponents.Body(m = 1, r_cm = [0.0, 0, 0], orientation_state = OrientationState.Euler())
relations
metadata {}
end
"#;
    let l = component(text, "EulerBody");
    assert_eq!(l.assemble().unwrap().degrees_of_freedom(), 6);
    let spring = component(text, "Spring");
    assert!(spring.model.components.is_empty());
}

#[test]
fn values_cannot_grow_without_bound() {
    // Each parameter is four copies of the next: 4^12 numbers if unchecked.
    let mut text = String::from("example component M\n  world = World()\n");
    for i in 0..12 {
        let dims = vec![":"; 12 - i].join(", ");
        text.push_str(&format!("  parameter p{i}::Real[{dims}] = [p{n}, p{n}, p{n}, p{n}]\n", n = i + 1));
    }
    text.push_str("  parameter p12::Real = 1\nend\n");
    let e = error(&text, "M");
    assert!(e.contains("this array is too large"), "{e}");
}

#[test]
fn signals_pass_through_declared_inputs() {
    let text = r#"
component Pushed
  push = RealInput()
  body = Body(m = 1, orientation_state = OrientationState.Quaternion())
  force = WorldForce()
relations
  connect(body.frame_a, force.frame_b)
  connect(push, force.force_x)
end
example component M
  world = World(g = 0)
  thing = Pushed()
  strength = BlockComponents.Sources.Constant(k = 2)
relations
  connect(strength.y, thing.push)
end
"#;
    let l = component(text, "M");
    let connections: Vec<Vec<&str>> =
        l.model.connections.iter().map(|c| c.ends.iter().map(String::as_str).collect()).collect();
    assert!(connections.contains(&vec!["strength.y", "thing.force.force_x"]), "{connections:?}");
    let options = multibody::SimulationOptions { stop: 1.0, saveat: 0.5, ..Default::default() };
    let solution = l.assemble().unwrap().simulate(&options).unwrap();
    // F = 2 N on 1 kg for 1 s.
    assert!((solution.last("thing.body.v_0[1]").unwrap() - 2.0).abs() < 1e-9);
}

/// A long flat sum is one level of nesting (not one per term), and is
/// computed from the left.
#[test]
fn a_long_flat_sum_is_computed_from_the_left() {
    let terms = " + 0.5".repeat(999);
    let text = format!(
        "example component P\n  parameter m::Real = 0.5{terms}\n  parameter r::Real = 100 - 1 - 2 - 3 * 2 / 4 - 1.5\n  world = MultibodyComponents.World()\n  body = MultibodyComponents.Body(m = m, r_cm = [r, 0, 0], orientation_state = OrientationState.Quaternion())\nend\n"
    );
    let l = component(&text, "P");
    let body = l.model.components.iter().find(|c| c.name == "body").unwrap();
    let param = |name: &str| body.params.iter().find(|(n, _)| n == name).map(|(_, v)| v.clone()).unwrap();
    assert_eq!(param("m"), Value::Number(500.0));
    assert_eq!(param("r_cm"), Value::Array(vec![100.0 - 1.0 - 2.0 - 3.0 * 2.0 / 4.0 - 1.5, 0.0, 0.0]));
}

/// `wheel.surface = formula`: a slipping wheel's road, a formula of the
/// world's x and z (parameters fold into constants).
#[test]
fn a_road_is_a_formula_of_x_and_z() {
    use multibody::Expr as S;
    let text = "component Road\n  parameter k::Real = 0.5\n  world = MultibodyComponents.World()\n  wheel = MultibodyComponents.SlippingWheel()\nrelations\n  wheel.surface = 0.1 * sin(k * x) - z / 4\nend\n";
    let lowered = component(text, "Road");
    let wheel = lowered.model.components.iter().find(|c| c.name == "wheel").unwrap();
    let b = std::sync::Arc::new;
    let expected = S::Sub(
        b(S::Mul(
            b(S::Const(0.1)),
            b(S::Call(multibody::Func::Sin, b(S::Mul(b(S::Const(0.5)), b(S::Var("x".into())))))),
        )),
        b(S::Div(b(S::Var("z".into())), b(S::Const(4.0)))),
    );
    assert_eq!(wheel.surface.as_ref(), Some(&expected));
    // The road's functions are those of formulas of time.
    let bad = text.replace("sin(k * x)", "max(k, x)");
    let message = error(&bad, "Road");
    println!("{message}");
    assert!(message.contains("max") && message.contains("road"), "{message}");
    // A wheel told to roll on a road it was not given.
    let missing = "component Missing\n  world = MultibodyComponents.World()\n  wheel = MultibodyComponents.SlippingWheel(surface = true)\nend\n";
    let message = error(missing, "Missing");
    println!("{message}");
    assert!(message.contains("wheel.surface = "), "{message}");
}

/// `parameter p_k = p_(k-1) + 1`, 250,000 times: each use of a parameter
/// is found by name in constant time (it was a scan of every parameter,
/// quadratic in all: the model hung). The chain adds up. The time it takes
/// is measured by `benches/lowering.rs`, not here.
#[test]
fn a_quarter_million_chained_parameters_lower() {
    let n = 250_000;
    let mut text = String::from("example component Chain\n  world = World()\n  parameter p_0::Real = 0\n");
    for k in 1..n {
        text.push_str(&format!("  parameter p_{k}::Real = p_{} + 1\n", k - 1));
    }
    text.push_str(&format!("relations\n  assert(p_{} == {}, \"the chain adds up\")\nend\n", n - 1, n - 1));
    component(&text, "Chain");
    let wrong = text.replace(&format!("== {}", n - 1), &format!("== {n}"));
    assert!(error(&wrong, "Chain").contains("the chain adds up"));
}

/// A `for` over the 50,000 elements of a variable: `x[i]` names one
/// variable (it built the whole array of `x` at every use, quadratic in
/// all: 10,000 elements took 10 s). Every element is an equation of its own.
#[test]
fn a_for_over_fifty_thousand_elements_lowers() {
    let n = 50_000;
    let text = format!(
        "example component Loop\n  world = World()\n  parameter n::Integer = {n}\n  variable x::Real[n]\nrelations\n  for i in 1:n\n    x[i] = i * time\n  end\nend\n"
    );
    let mechanism = component(&text, "Loop").assemble().unwrap();
    let names: Vec<String> = mechanism.signals().into_iter().map(|s| s.name).collect();
    assert!(names.iter().any(|s| s == "x[1]") && names.iter().any(|s| s == &format!("x[{n}]")), "{:?}", &names[..5]);
    // Out of range is still caught where it is written.
    let e = error(&text.replace("x[i] = i", "x[i + 1] = i"), "Loop");
    assert!(e.contains("index 50001 is out of range for `x`") && e.contains("must be from 1 to 50000"), "{e}");
}

/// Matrices by rows, `[a, b; c, d]`, mean the array of rows; `[a; b]` a
/// vector; rows of different lengths are an error at the row.
#[test]
fn matrices_written_by_rows() {
    let by_rows = r#"
example component Rows
  parameter A::Real[2, 2] = [1, 2; 3, 4]
  parameter v::Real[2] = [5; 6]
  world = MultibodyComponents.World()
  body = MultibodyComponents.Body(m = 1, r_cm = [A[2, 1], A[1, 2], v[2]], I_11 = v[1])
end
"#;
    let of_arrays = by_rows.replace("[1, 2; 3, 4]", "[[1, 2], [3, 4]]").replace("[5; 6]", "[5, 6]");
    let (a, b) = (component(by_rows, "Rows"), component(&of_arrays, "Rows"));
    assert_eq!(a.model.components, b.model.components);
    let body = a.model.components.iter().find(|c| c.name == "body").unwrap();
    let r_cm = body.params.iter().find(|(n, _)| n == "r_cm").map(|(_, v)| v);
    assert_eq!(r_cm, Some(&Value::Array(vec![3.0, 2.0, 6.0])));
    let mut p = Package::new();
    let message = p.add_source("rows.dyad", by_rows.replace("[1, 2; 3, 4]", "[1, 2; 3]")).unwrap_err();
    let message = message.render(p.sources(), false);
    assert!(message.contains("the rows of this matrix differ in length: 2 and 1"), "{message}");
    assert!(message.contains("rows.dyad:3:"), "{message}");
}

/// A start value given from outside a component (an enclosing
/// component's modifier, an override) wins over the component's own
/// `initial x = v`, as it does over `variable x::Real = initial v`; two
/// given in the same component are still an error.
#[test]
fn start_values_from_outside_win_over_initial_relations() {
    let text = r#"
component Decay
  variable z::Real
relations
  initial z = 3
  der(z) = -z
end

example component Two
  a = Decay()
  b = Decay(z(initial = 5))
end
"#;
    let start = |l: &Lowered, name: &str| {
        let v = l.model.equations.variables.iter().find(|v| v.name == name).unwrap();
        (v.start, v.fixed)
    };
    let lowered = component(text, "Two");
    assert_eq!((start(&lowered, "a.z"), start(&lowered, "b.z")), ((Some(3.0), true), (Some(5.0), true)));
    let p = package(&[("test.dyad", text)]);
    let overridden = p
        .lower_component_with("Two", &[multibody_dyad::Override::initial("a.z", 7.0)])
        .unwrap_or_else(|d| panic!("{}", d.render(p.sources(), false)));
    assert_eq!(start(&overridden, "a.z"), (Some(7.0), true));
    let twice = error(&text.replace("  der(z) = -z", "  initial z = 4\n  der(z) = -z"), "Two");
    assert!(twice.contains("the start value is given twice"), "{twice}");
}

/// Parameters and equations call the same functions of numbers (one
/// table): a parameter may use every function an equation may, and gets
/// the same value.
#[test]
fn parameters_call_the_functions_equations_call() {
    let lowered = component(
        r#"
component Functions
  parameter a::Real = log10(1000) + sinh(0.5) + sign(-2) + floor(2.7) + ceil(0.2) + tanh(0.3)
  variable x::Real
  variable y::Real
relations
  x = a
  y = log10(1000) + sinh(0.5) + sign(-2) + floor(2.7) + ceil(0.2) + tanh(0.3)
end"#,
        "Functions",
    );
    let expected = 3.0 + 0.5f64.sinh() - 1.0 + 2.0 + 1.0 + 0.3f64.tanh();
    let mechanism = lowered.assemble().unwrap();
    let options = multibody::SimulationOptions { stop: 0.1, saveat: 0.1, ..Default::default() };
    let solution = mechanism.simulate(&options).unwrap();
    for name in ["x", "y"] {
        let value = solution.get(name).unwrap()[0];
        assert!((value - expected).abs() < 1e-14, "{name} = {value}, expected {expected}");
    }
    // Outside its domain a function of a parameter is an error at its place.
    let message =
        error("component Bad\n  parameter a::Real = log10(-1)\n  variable x::Real\nrelations\n  x = a\nend", "Bad");
    assert!(message.contains("`log10` of -1 is not defined") && message.contains("positive"), "{message}");
}

/// An equation of 20,000 terms (generated models write such sums) ran the
/// command out of stack and aborted it: long sums and products are now
/// taken pairwise. `x = time + time + ...` is `20000 t`, and the product
/// of 4,000 factors `(1 + time / 4000)` is `(1 + t / 4000)^4000`.
#[test]
fn equations_of_thousands_of_terms_run() {
    let sum = vec!["time"; 20_000].join(" + ");
    let product = vec!["(1 + time / 4000)"; 4_000].join(" * ");
    let text = format!(
        "example component Long\n  variable x::Real\n  variable y::Real\nrelations\n  x = {sum}\n  y = {product}\nend\n"
    );
    let options = multibody::SimulationOptions { stop: 0.5, saveat: 0.1, ..Default::default() };
    let s = component(&text, "Long").assemble().unwrap().simulate(&options).unwrap();
    let mut worst = 0.0f64;
    for (k, t) in s.time().iter().enumerate() {
        worst = worst.max((s.get("x").unwrap()[k] - 20_000.0 * t).abs() / (1.0 + 20_000.0 * t));
        let y = (1.0 + t / 4000.0f64).powi(4000);
        worst = worst.max((s.get("y").unwrap()[k] - y).abs() / y);
    }
    assert!(worst < 1e-12, "long sums and products are off by {worst:e} (relative)");
}

/// An inertia no rigid body can have (a principal moment above the sum of
/// the other two) is taken as given, with a warning at the body that names
/// it and its moments; flat plates and thin rods reach the bound and are
/// not warned about. Modelica's industrial robot has such a link
/// (0.001, 1.16, 0.001), so it is not refused.
#[test]
fn an_inertia_no_rigid_body_has_is_warned_about_at_the_body() {
    let text = r#"
component Holder
  parameter I::Real = 2
  frame_a = Frame3D()
  shaft = MultibodyComponents.BodyShape(r = [0.5, 0, 0], m = 1, I_11 = I, I_22 = 0, I_33 = 0)
relations
  connect(frame_a, shaft.frame_a)
end

example component Arm
  world = MultibodyComponents.World()
  joint = MultibodyComponents.Revolute(n = [0, 0, 1], phi(initial = 0.1))
  link = MultibodyComponents.Body(m = 1, r_cm = [0.5, 0, 0], I_11 = 0.001, I_22 = 1.16, I_33 = 0.001)
  joint2 = MultibodyComponents.Revolute(n = [0, 0, 1])
  rod = MultibodyComponents.Body(m = 1, r_cm = [0.5, 0, 0], I_11 = 0, I_22 = 0.02, I_33 = 0.02)
  plate = MultibodyComponents.Body(m = 1, I_11 = 0.1, I_22 = 0.2, I_33 = 0.3)
  turned = MultibodyComponents.Body(m = 1, I_11 = 1, I_22 = 1, I_33 = 1, I_21 = 0.9)
  held = Holder()
relations
  connect(world.frame_b, joint.frame_a)
  connect(joint.frame_b, link.frame_a, joint2.frame_a, plate.frame_a, turned.frame_a, held.frame_a)
  connect(joint2.frame_b, rod.frame_a)
end
"#;
    let p = package(&[("arm.dyad", text)]);
    let l = p.lower_component("Arm").unwrap_or_else(|d| panic!("{}", d.render(p.sources(), false)));
    let rendered: Vec<String> = l.warnings.iter().map(|w| w.render(p.sources(), false)).collect();
    assert_eq!(rendered.len(), 3, "{rendered:#?}");
    let link = &rendered[0];
    assert!(
        link.starts_with(
            "warning: no rigid mass distribution has the inertia of `link`: its principal moments 0.001, 0.001 and \
             1.16 kg.m2 break the triangle inequality (1.16 > 0.001 + 0.001)"
        ),
        "{link}"
    );
    assert!(link.contains("arm.dyad:13:3"), "{link}");
    assert!(link.contains("the model runs with the inertia as given"), "{link}");
    assert!(rendered[1].contains("of `turned`: its principal moments 0.1, 1 and 1.9 kg.m2"), "{}", rendered[1]);
    // Inside a user component: the instance's name, at the declaration.
    assert!(rendered[2].contains("of `held.shaft`: its principal moments 0, 0 and 2 kg.m2"), "{}", rendered[2]);
    assert!(rendered[2].contains("arm.dyad:5:3"), "{}", rendered[2]);
    // Taken as given: the model assembles and runs.
    let mechanism = l.assemble().unwrap_or_else(|d| panic!("{}", d.render(p.sources(), false)));
    let options = multibody::SimulationOptions { stop: 0.1, saveat: 0.05, ..Default::default() };
    mechanism.simulate(&options).unwrap();
}
