//! Every example model (examples/**/*.dyad, the Modelica references among
//! them): how long it takes from file text to a compiled mechanism, and the
//! wall time of its complete simulation as its analysis asks for it
//! (outputs on the analysis's grid included).

use criterion::{criterion_group, criterion_main, Criterion};
use multibody::{Method, SimulationOptions};
use multibody_dyad::Package;

#[path = "../tests/common/examples.rs"]
mod examples;

fn compile(c: &mut Criterion) {
    let mut group = c.benchmark_group("compile");
    for path in examples::example_files() {
        let sources = examples::example_sources(&path);
        let analysis = examples::load_example(&path).name;
        group.bench_function(examples::example_name(&path), |b| {
            b.iter(|| {
                let mut package = Package::new();
                // Under their own paths, as the tests load them (added as
                // `model.dyad`, one example failed to lower: `rod.r` needs 3
                // numbers).
                for (name, text) in &sources {
                    package.add_source(name.as_str(), text.as_str()).unwrap();
                }
                package.lower_analysis(&analysis).unwrap().assemble().unwrap()
            })
        });
    }
    group.finish();
}

fn simulate(c: &mut Criterion) {
    let mut group = c.benchmark_group("simulate");
    group.sample_size(10);
    for path in examples::example_files() {
        let lowered = examples::load_example(&path);
        let mechanism = lowered.assemble().unwrap();
        group.bench_function(examples::example_name(&path), |b| {
            b.iter(|| mechanism.simulate(&lowered.options).unwrap())
        });
    }
    group.finish();
}

/// The stiff example with the implicit method its analysis asks for, and
/// with the explicit default: the case for Rodas4 (same run, same model).
fn stiff(c: &mut Criterion) {
    let path = examples::examples_dir().join("stiff_spring.dyad");
    let lowered = examples::load_example(&path);
    let mechanism = lowered.assemble().unwrap();
    let mut group = c.benchmark_group("stiff_spring");
    group.sample_size(10);
    for method in [Method::Rodas4, Method::DormandPrince45] {
        let options = SimulationOptions { method, ..lowered.options.clone() };
        group.bench_function(format!("{method:?}"), |b| b.iter(|| mechanism.simulate(&options).unwrap()));
    }
    group.finish();
}

/// A pendulum held by a PD law on its angle: the law as a component
/// written in Dyad, or built from library blocks (Feedback, Add).
fn pd_pendulum(in_dyad: bool) -> String {
    let controller = if in_dyad {
        "  controller = PD(kp = 40, kd = 6, reference = 0.5)
relations
  connect(angle.phi, controller.angle)
  connect(speed.w, controller.speed)
  connect(controller.torque, motor.tau)"
    } else {
        "  reference = BlockComponents.Constant(k = 0.5)
  error = BlockComponents.Feedback()
  law = BlockComponents.Add(k1 = 40, k2 = -6)
relations
  connect(reference.y, error.u1)
  connect(angle.phi, error.u2)
  connect(error.y, law.u1)
  connect(speed.w, law.u2)
  connect(law.y, motor.tau)"
    };
    format!(
        "component PD
  parameter kp::Real = 1
  parameter kd::Real = 0
  parameter reference::Real = 0
  angle = RealInput()
  speed = RealInput()
  torque = RealOutput()
relations
  torque = kp * (reference - angle) - kd * speed
end

example component Held
  world = MultibodyComponents.World()
  rev = MultibodyComponents.Revolute(n = [0, 0, 1], phi(initial = 0), w(initial = 0))
  body = MultibodyComponents.Body(m = 1, r_cm = [0.5, 0, 0])
  motor = RotationalComponents.Torque()
  angle = RotationalComponents.AngleSensor()
  speed = RotationalComponents.SpeedSensor()
{controller}
  connect(world.frame_b, rev.frame_a)
  connect(rev.frame_b, body.frame_a)
  connect(motor.spline, angle.spline, speed.spline, rev.axis)
  connect(motor.support, rev.support)
end
"
    )
}

/// A chain of `n` first-order lags written in Dyad (two equations each,
/// and one for each connection): about 3 n equations.
fn lag_chain(n: usize) -> String {
    format!(
        "component Lag
  parameter T::Real = 0.1
  u = RealInput()
  y = RealOutput()
  variable x::Real
relations
  der(x) = (u - x) / T
  y = x
end

example component Lags
  structural parameter N::Integer = {n}
  source = BlockComponents.Sine(amplitude = 1, frequency = 1)
  lags = [Lag(T = 0.1 + 0.001 * i) for i in 1:N]
relations
  connect(source.y, lags[1].u)
  for i in 1:N - 1
    connect(lags[i].y, lags[i + 1].u)
  end
end
"
    )
}

/// The cost of equations: one right-hand side of the PD pendulum with
/// the law in Dyad against the law from library blocks, and compiling a
/// model of about 1000 equations from its text.
fn equations(c: &mut Criterion) {
    let mut group = c.benchmark_group("equations");
    for (name, in_dyad) in [("rhs_pd_dyad", true), ("rhs_pd_blocks", false)] {
        let mut package = Package::new();
        package.add_source("held.dyad", pd_pendulum(in_dyad)).unwrap();
        let mechanism = package.lower_component("Held").unwrap().assemble().unwrap();
        let mut ws = mechanism.workspace();
        let mut y = mechanism.states().start.clone();
        y[0] = 0.3;
        y[1] = -0.7;
        let mut dy = vec![0.0; y.len()];
        group.bench_function(name, |b| {
            b.iter(|| mechanism.rhs(&mut ws, std::hint::black_box(0.1), std::hint::black_box(&y), &mut dy).unwrap())
        });
    }
    let text = lag_chain(334);
    let equations = {
        let mut package = Package::new();
        package.add_source("lags.dyad", text.as_str()).unwrap();
        package.lower_component("Lags").unwrap().model.equations.equations.len()
    };
    assert!(equations >= 1000, "the chain has {equations} equations");
    group.bench_function("compile_1000_equations", |b| {
        b.iter(|| {
            let mut package = Package::new();
            package.add_source("lags.dyad", text.as_str()).unwrap();
            package.lower_component("Lags").unwrap().assemble().unwrap()
        })
    });
    group.finish();
}

/// The PD pendulum with 100 relations on its angle that never change
/// (`rev.phi < 10 + i`): each an event indicator, or with `noEvent` the
/// same arithmetic without one. What watching idle indicators costs, per
/// right-hand side and per simulation (the target: within 1.2x).
fn idle_indicators(watched: bool) -> String {
    let relation = if watched { "rev.phi < 10 + i" } else { "noEvent(rev.phi < 10 + i)" };
    pd_pendulum(true)
        .replace(
            "  connect(world.frame_b, rev.frame_a)",
            &format!(
                "  for i in 1:100
    z[i] = if {relation} then rev.phi else 0
  end
  connect(world.frame_b, rev.frame_a)"
            ),
        )
        .replace("  controller = PD(", "  variable z::Real[100]\n  controller = PD(")
}

fn indicators(c: &mut Criterion) {
    let mut group = c.benchmark_group("equations");
    group.sample_size(20);
    for (name, watched) in [("idle_indicators_100", true), ("idle_indicators_100_noevent", false)] {
        let mut package = Package::new();
        package.add_source("idle.dyad", idle_indicators(watched)).unwrap();
        let mechanism = package.lower_component("Held").unwrap().assemble().unwrap();
        let mut ws = mechanism.workspace();
        let mut y = mechanism.states().start.clone();
        y[0] = 0.3;
        y[1] = -0.7;
        let mut dy = vec![0.0; y.len()];
        group.bench_function(format!("rhs_{name}"), |b| {
            b.iter(|| mechanism.rhs(&mut ws, std::hint::black_box(0.1), std::hint::black_box(&y), &mut dy).unwrap())
        });
        let options = SimulationOptions { stop: 2.0, saveat: 0.01, ..SimulationOptions::default() };
        group.bench_function(format!("simulate_{name}"), |b| b.iter(|| mechanism.simulate(&options).unwrap()));
    }
    group.finish();
}

/// A chain of `n` masses joined by spring-dampers, the first held by a
/// wall: the elements written in Dyad in the library's own form
/// (`v_rel = der(s_rel)`, by index reduction) or the library's built-in
/// TranslationalComponents.SpringDamper.
fn spring_damper_chain(n: usize, written: bool) -> String {
    let element = if written {
        "LibraryForm(c = 100, d = 0.5)"
    } else {
        "TranslationalComponents.SpringDamper(c = 100, d = 0.5)"
    };
    format!(
        "component LibraryForm
  parameter c::Real
  parameter d::Real
  flange_a = Flange()
  flange_b = Flange()
  variable s_rel::Length
  variable v_rel::Velocity
  variable f::Force
relations
  s_rel = flange_b.s - flange_a.s
  v_rel = der(s_rel)
  f = c * s_rel + d * v_rel
  flange_b.f = f
  flange_a.f = -f
end

example component Chain
  structural parameter N::Integer = {n}
  wall = TranslationalComponents.Fixed()
  elements = [{element} for i in 1:N]
  masses = [TranslationalComponents.Mass(m = 1, s(initial = 0.01 * i), v(initial = 0)) for i in 1:N]
relations
  connect(wall.flange, elements[1].flange_a)
  for i in 1:N
    connect(elements[i].flange_b, masses[i].flange_a)
  end
  for i in 1:N - 1
    connect(masses[i].flange_b, elements[i + 1].flange_a)
  end
end
"
    )
}

/// One right-hand side of a 100-element spring-damper chain: elements
/// written in Dyad against the built-in ones (the target: within 1.5x).
fn written_elements(c: &mut Criterion) {
    let mut group = c.benchmark_group("equations");
    for (name, written) in [("rhs_chain100_written", true), ("rhs_chain100_builtin", false)] {
        let mut package = Package::new();
        package.add_source("chain.dyad", spring_damper_chain(100, written)).unwrap();
        let mechanism = package.lower_component("Chain").unwrap().assemble().unwrap();
        let mut ws = mechanism.workspace();
        let y: Vec<f64> = mechanism.states().start.iter().enumerate().map(|(k, s)| s + 1e-3 * k as f64).collect();
        let mut dy = vec![0.0; y.len()];
        group.bench_function(name, |b| {
            b.iter(|| mechanism.rhs(&mut ws, std::hint::black_box(0.1), std::hint::black_box(&y), &mut dy).unwrap())
        });
    }
    group.finish();
}

criterion_group!(benches, compile, simulate, stiff, equations, indicators, written_elements);
criterion_main!(benches);
