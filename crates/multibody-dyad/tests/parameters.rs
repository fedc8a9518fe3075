//! Every parameter of every library component has an effect, or the model
//! says why it has none (issue 45: no parameter is dropped without a word).
//!
//! The walk takes each component kind of the library where an example
//! uses it (else in a small host model made for it), gives each of its
//! parameters in turn another value, assembles the model again and
//! compares the compiled mechanism in full: its dynamics, outputs and the
//! shapes of its animation. A change must show there, or be refused, or a
//! warning must say the parameter has no effect (and then it must indeed
//! have none).

use multibody::components::spec::{ComponentSpec, ConnectorType, Default as Given, ParamType};
use multibody::components::{lookup, registry};
use multibody::{Model, Value};
use multibody_dyad::{DefinitionKind, Package};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

fn dyad_files(dir: &Path, out: &mut Vec<PathBuf>) {
    let mut entries: Vec<PathBuf> = std::fs::read_dir(dir).unwrap().map(|e| e.unwrap().path()).collect();
    entries.sort();
    for path in entries {
        if path.is_dir() {
            dyad_files(&path, out);
        } else if path.extension().is_some_and(|e| e == "dyad") {
            out.push(path);
        }
    }
}

/// What assembling a model gives: the compiled mechanism in full (as its
/// debug text, without its warnings and the World's table of its own
/// parameters, which are compared apart), or the error; and the warnings.
#[derive(Debug, PartialEq)]
struct Outcome {
    compiled: Result<String, String>,
    warnings: Vec<String>,
}

fn assemble(model: &Model) -> Outcome {
    match model.assemble() {
        Ok(mechanism) => {
            let mut compiled = format!("{mechanism:?}");
            if let (Some(start), Some(end)) = (compiled.rfind("warnings: ["), compiled.rfind("], outputs: ")) {
                compiled.replace_range(start..end, "");
            }
            // The World's table of its parameters, which other components'
            // defaults read: what they read shows where they use it.
            if let Some(start) = compiled.find("values: [(\"") {
                let mut depth = 0;
                let end = compiled[start..]
                    .char_indices()
                    .find(|&(_, c)| {
                        depth += match c {
                            '[' => 1,
                            ']' => -1,
                            _ => 0,
                        };
                        c == ']' && depth == 0
                    })
                    .map_or(compiled.len(), |(k, _)| start + k + 1);
                compiled.replace_range(start..end, "");
            }
            Outcome { compiled: Ok(compiled), warnings: mechanism.warnings().to_vec() }
        }
        Err(e) => Outcome { compiled: Err(e.to_string()), warnings: vec![] },
    }
}

/// Another value of the parameter's type, near `current` (or the default):
/// a number a tenth smaller, a vector turned (an axis is normalized), a
/// flag flipped.
fn changed(ty: &ParamType, current: Option<&Value>, default: &Given) -> Option<Value> {
    // Down rather than up: a bound above what is reached does nothing.
    let number = |x: f64| if x == 0.0 { 0.05 } else { x * 0.9 };
    // Each entry moved by another amount: the direction changes whatever
    // it was, and also across any other axis the component projects it on.
    // (One number per axis, as a point-to-point path's limits: smaller.)
    let turned = |v: &[f64]| match v {
        [x] => vec![number(*x)],
        _ => v.iter().enumerate().map(|(k, x)| x + 0.1 * (k + 1) as f64).collect::<Vec<f64>>(),
    };
    let integer = matches!(ty, ParamType::Integer);
    Some(match (ty, current, default) {
        (ParamType::Bool, Some(Value::Bool(b)), _) | (ParamType::Bool, None, Given::Bool(b)) => Value::Bool(!b),
        (ParamType::Real | ParamType::Integer, Some(Value::Number(x)), _)
        | (ParamType::Real | ParamType::Integer, None, Given::Number(x)) => {
            Value::Number(if integer { x + 1.0 } else { number(*x) })
        }
        // A default the World or the component computes: a value unlike it.
        (ParamType::Real, None, _) => Value::Number(0.0123),
        (ParamType::Vector(_), Some(Value::Array(v)), _) => Value::Array(turned(v)),
        (ParamType::Vector(_), None, Given::Vector(v)) => Value::Array(turned(v)),
        (ParamType::Vector(n), None, _) => Value::Array((0..*n).map(|k| 0.3 + 0.2 * k as f64).collect()),
        (ParamType::Enum(_, variants), current, default) => {
            let now = match (current, default) {
                (Some(Value::Enum(v)), _) => v.clone(),
                (_, Given::Enum(v)) => v.to_string(),
                _ => String::new(),
            };
            // (A model may write `ResolveInFrame.World` for `World`.)
            let tail = |v: &str| v.rsplit('.').next().unwrap_or(v).to_ascii_lowercase();
            Value::Enum(variants.iter().find(|v| tail(v) != tail(&now))?.to_string())
        }
        (ParamType::Matrix(_), Some(Value::Matrix(rows)), _) => {
            let mut rows = rows.clone();
            let last = rows.last_mut()?.last_mut()?;
            *last = number(*last);
            Value::Matrix(rows)
        }
        _ => return None,
    })
}

#[derive(Default)]
struct Walk {
    /// (kind, parameter) -> where it was walked.
    walked: BTreeMap<(String, String), String>,
    /// Changed without a trace and without a word.
    silent: Vec<String>,
    /// Said to have no effect, yet the compiled model changed.
    wrong: Vec<String>,
}

impl Walk {
    /// Walks the parameters of the components of `model` whose kinds were
    /// not walked yet.
    fn model(&mut self, model: &Model, origin: &str) {
        let base = assemble(model);
        if base.compiled.is_err() {
            return;
        }
        for (index, component) in model.components.iter().enumerate() {
            let Some(spec) = lookup(&component.kind) else { continue };
            for param in spec.params {
                // `axisflange = true` is how Dyad asks for a joint's axis
                // flanges; here they are always there, so the flag changes
                // nothing, and saying so at every driven joint would be noise
                // about a model written right.
                if param.name == "axisflange" {
                    continue;
                }
                let key = (spec.kind.to_string(), param.name.to_string());
                if self.walked.contains_key(&key) {
                    continue;
                }
                let current = component.params.iter().find(|(n, _)| n == param.name).map(|(_, v)| v);
                let Some(value) = changed(&param.ty, current, &param.default) else { continue };
                let mut changed_model = model.clone();
                changed_model.components[index].set(param.name, value.clone());
                let outcome = assemble(&changed_model);
                let what = format!("{}.{} = {value} at {} in {origin}", spec.kind, param.name, component.name);
                let said = format!("`{}.{}` has no effect", component.name, param.name);
                let says = |o: &Outcome| o.warnings.iter().any(|w| w.starts_with(&said));
                // A model the change makes impossible is refused: an effect.
                let changes = outcome.compiled != base.compiled;
                // `render = false` asks for nothing drawn: a component that
                // draws nothing meets it without a word.
                if param.name == "render" && value == Value::Bool(false) && !changes {
                    self.walked.insert(key, what);
                    continue;
                }
                if !changes && !says(&base) && !says(&outcome) {
                    self.silent.push(what.clone());
                }
                if changes && says(&outcome) {
                    self.wrong.push(what.clone());
                }
                self.walked.insert(key, what);
            }
        }
    }
}

/// How a host model holds its component's frames.
#[derive(Clone, Copy)]
struct Host {
    /// The first frame on the World.
    grounded: bool,
    /// The other frames on free bodies (else on bodies without states).
    owners: bool,
    /// Every frame fixed in the World at one place, and no 1-D flange
    /// connected (sensors between frames, a line's own flanges).
    all_fixed: bool,
    /// frame_a on the World and frame_b fixed this far from it along x,
    /// the others on bodies: an assembly that closes a loop between the two.
    apart: Option<f64>,
}

/// A model holding one component of `spec` (required parameters given):
/// its first frame on the World (when `grounded`) and its other frames on
/// bodies (free ones when `owners`), or all fixed; its supports fixed, its other flanges on an inertia or a
/// mass, its inputs on constants.
fn host(spec: &ComponentSpec, how: Host) -> Model {
    let Host { grounded, owners, all_fixed, apart } = how;
    let planar = spec.is_planar();
    let mut m = Model::new(format!("Host{}", spec.kind.replace('.', "")));
    m.add("world", if planar { "PlanarMechanics.World" } else { "World" });
    let it = m.add("it", spec.kind);
    for p in spec.params.iter().filter(|p| matches!(p.default, Given::Required)) {
        let value = match p.ty {
            ParamType::Vector(n) => Value::Array((0..n).map(|k| if k == 0 { 1.0 } else { 0.0 }).collect()),
            ParamType::Matrix(n) => {
                Value::Matrix(vec![(0..n).map(|k| k as f64).collect(), (0..n).map(|k| 1.0 + k as f64).collect()])
            }
            ParamType::Bool => Value::Bool(true),
            _ => Value::Number(1.0),
        };
        it.set(p.name, value);
    }
    let mut ground = grounded;
    for (k, c) in spec.public_connectors().enumerate() {
        let end = format!("it.{}", c.name);
        let other = format!("end{k}");
        let support = c.name.contains("support") || c.name.contains("bearing") || c.name.contains("housing");
        match c.ty {
            // (A sensor's frame_resolve is connected only to resolve in it.)
            ConnectorType::Frame | ConnectorType::Frame2D if c.name == "frame_resolve" => {}
            ConnectorType::Frame | ConnectorType::Frame2D if all_fixed => {
                let planar = c.ty == ConnectorType::Frame2D;
                m.add(&other, if planar { "PlanarMechanics.FixedTranslation" } else { "FixedTranslation" }).set(
                    "r",
                    if planar {
                        Value::Array(vec![0.3 * k as f64, 0.1])
                    } else {
                        Value::Array(vec![0.3 * k as f64, 0.1, 0.0])
                    },
                );
                m.connect(["world.frame_b".to_string(), format!("{other}.frame_a")]);
                m.connect([format!("{other}.frame_b"), end]);
            }
            ConnectorType::Spline | ConnectorType::Flange if all_fixed => {}
            ConnectorType::Frame if apart.is_some() && c.name == "frame_b" => {
                m.add(&other, "FixedTranslation").set("r", [apart.unwrap_or(0.0), 0.0, 0.0]);
                m.connect(["world.frame_b".to_string(), format!("{other}.frame_a")]);
                m.connect([format!("{other}.frame_b"), end]);
            }
            ConnectorType::Frame | ConnectorType::Frame2D if ground => {
                ground = false;
                m.connect(["world.frame_b".to_string(), end]);
            }
            ConnectorType::Frame => {
                let body = m.add(&other, "Body");
                body.set("m", 1.0).set("r_cm", [0.1, 0.0, 0.0]).set("I_11", 0.01).set("I_22", 0.01).set("I_33", 0.01);
                if owners {
                    body.set("orientation_state", multibody::OrientationState::Quaternion);
                }
                m.connect([format!("{other}.frame_a"), end]);
            }
            ConnectorType::Frame2D => {
                m.add(&other, "PlanarMechanics.Body").set("m", 1.0).set("I", 0.1);
                m.connect([format!("{other}.frame_a"), end]);
            }
            ConnectorType::Spline | ConnectorType::Flange => {
                // A support on a fixed point, another flange on a mass.
                let (kind, port, mass) = match (c.ty == ConnectorType::Spline, support) {
                    (true, true) => ("RotationalComponents.Fixed", "spline", None),
                    (true, false) => ("RotationalComponents.Inertia", "spline_a", Some("J")),
                    (false, true) => ("TranslationalComponents.Fixed", "flange", None),
                    (false, false) => ("TranslationalComponents.Mass", "flange_a", Some("m")),
                };
                let part = m.add(&other, kind);
                if let Some(mass) = mass {
                    part.set(mass, 1.0);
                }
                m.connect([format!("{other}.{port}"), end]);
            }
            ConnectorType::RealInput => {
                m.add(&other, "BlockComponents.Constant").set("k", 0.5);
                m.connect([format!("{other}.y"), end]);
            }
            ConnectorType::RealOutput => {}
        }
    }
    m
}

#[test]
fn every_parameter_of_every_component_has_an_effect_or_is_said_to_have_none() {
    let mut walk = Walk::default();
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples");
    let mut files = Vec::new();
    dyad_files(&root, &mut files);
    for path in files {
        let text = std::fs::read_to_string(&path).unwrap();
        let mut package = Package::new();
        let name = path.strip_prefix(&root).unwrap_or(&path).display().to_string();
        if package.add_source(name.clone(), text).is_err() {
            continue;
        }
        let analyses: Vec<String> =
            package.definitions().into_iter().filter(|d| d.kind == DefinitionKind::Analysis).map(|d| d.name).collect();
        let lowered: Vec<_> = if analyses.is_empty() {
            package.top_components().into_iter().filter_map(|d| package.lower_component(&d.name).ok()).collect()
        } else {
            analyses.iter().filter_map(|a| package.lower_analysis(a).ok()).collect()
        };
        for l in lowered {
            walk.model(&l.model, &format!("examples/{name}"));
        }
    }
    let mut unhosted = Vec::new();
    for spec in registry() {
        if walk.walked.keys().any(|(k, _)| k == spec.kind) {
            continue;
        }
        let hosts = [
            (true, false, false, None),
            (true, true, false, None),
            (false, true, false, None),
            (false, false, false, None),
            (false, false, true, None),
            (true, false, false, Some(1.5)),
            (true, false, false, Some(-1.5)),
        ]
        .map(|(grounded, owners, all_fixed, apart)| host(spec, Host { grounded, owners, all_fixed, apart }));
        match hosts.iter().find(|m| m.assemble().is_ok()) {
            Some(model) => walk.model(model, "a host model"),
            None => unhosted.push(format!("{} ({})", spec.kind, hosts[5].assemble().unwrap_err())),
        }
    }
    let kinds: std::collections::BTreeSet<&str> = walk.walked.keys().map(|(k, _)| k.as_str()).collect();
    println!("walked {} parameters of {} of the library's {} kinds", walk.walked.len(), kinds.len(), registry().len());
    println!("kinds no model here holds ({}):", unhosted.len());
    for u in &unhosted {
        println!("  {u}");
    }
    println!("said to have no effect, yet they change the model ({}):", walk.wrong.len());
    for s in &walk.wrong {
        println!("  {s}");
    }
    println!("changed without a trace or a word ({}):", walk.silent.len());
    for s in &walk.silent {
        println!("  {s}");
    }
    assert!(walk.silent.is_empty() && walk.wrong.is_empty(), "see the lists above");
    // Every kind with parameters is walked.
    let missing: Vec<&str> =
        registry().iter().filter(|s| !s.params.is_empty() && !kinds.contains(s.kind)).map(|s| s.kind).collect();
    assert!(missing.is_empty(), "kinds whose parameters were not walked: {missing:?}");
}

/// The components the standard library writes in Dyad: every parameter
/// they declare is read somewhere (an equation, a part's modifier, another
/// parameter's value, or a component that extends it), else setting it
/// would change nothing without a word.
#[test]
fn every_parameter_of_the_dyad_library_is_read() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("stdlib");
    let mut files = Vec::new();
    dyad_files(&dir, &mut files);
    let mut unread = Vec::new();
    for path in files {
        let text = std::fs::read_to_string(&path).unwrap();
        // The text without comments and doc strings.
        let code: String = text
            .split("\"\"\"")
            .enumerate()
            .filter(|(k, _)| k % 2 == 0)
            .map(|(_, part)| part.lines().map(|l| l.split('#').next().unwrap_or("")).collect::<Vec<_>>().join("\n"))
            .collect::<Vec<_>>()
            .join("\n");
        let words = |line: &str| -> Vec<String> {
            line.split(|c: char| !(c.is_alphanumeric() || c == '_'))
                .filter(|w| !w.is_empty())
                .map(String::from)
                .collect()
        };
        // (A connector's drawing parameters, Frame3D's `render` and its
        // sizes, are the declaration Dyad's base library makes; nothing
        // draws connectors here, which the note of issue 45 says.)
        let mut in_connector = false;
        for line in code.lines() {
            let line = line.trim();
            if line.starts_with("connector ") {
                in_connector = true;
            } else if line.starts_with("component ") || line.contains(" component ") {
                in_connector = false;
            }
            if in_connector {
                continue;
            }
            let Some(rest) = line.strip_prefix("parameter ").or_else(|| line.strip_prefix("final parameter ")) else {
                continue;
            };
            let name: String = rest.chars().take_while(|c| c.is_alphanumeric() || *c == '_').collect();
            let uses = code.lines().filter(|l| l.trim() != line).flat_map(words).filter(|w| *w == name).count();
            if uses == 0 {
                unread.push(format!("{} in {}", name, path.file_name().unwrap().to_string_lossy()));
            }
        }
    }
    assert!(unread.is_empty(), "parameters of the Dyad library that nothing reads: {unread:?}");
}

/// What a model text gives: the run's samples, or the first error; and
/// every warning (the lowering's and the assembly's).
fn outcome_of(text: &str, overrides: &[multibody_dyad::Override]) -> (Result<Vec<Vec<f64>>, String>, String) {
    let mut package = Package::new();
    if let Err(d) = package.add_source("starts.dyad", text.to_string()) {
        return (Err(d.render(package.sources(), false)), String::new());
    }
    let lowered = match package.lower_component_with("Starts", overrides) {
        Ok(l) => l,
        Err(d) => return (Err(d.render(package.sources(), false)), String::new()),
    };
    let mut warnings: Vec<String> = lowered.warnings.iter().map(|w| w.render(package.sources(), false)).collect();
    let mechanism = match lowered.assemble() {
        Ok(m) => m,
        Err(d) => return (Err(d.render(package.sources(), false)), warnings.join("\n")),
    };
    warnings.extend(mechanism.warnings().iter().cloned());
    let options = multibody::SimulationOptions { stop: 0.5, saveat: 0.1, ..Default::default() };
    let run = mechanism
        .simulate(&options)
        .map(|s| s.names().iter().map(|n| s.get(n).unwrap().to_vec()).collect())
        .map_err(|e| e.to_string());
    (run, warnings.join("\n"))
}

/// Every way of giving a start: `initial` and `guess` on a library
/// component's states and on what is not a state, both on one variable,
/// on a user component's states, on variables its equations compute
/// directly and on one they solve for by iteration, an initial equation, a
/// declaration's `= initial v`, and a start set from outside (the
/// command's `--initial`). Two values give two results, or the model says
/// why not (a warning or an error naming the variable).
#[test]
fn every_kind_of_start_value_has_an_effect_or_is_said_to_have_none() {
    use multibody_dyad::Override;
    // `#` stands for the value.
    let user = |inside: &str, relation: &str| {
        format!(
            "component Lag\n  variable x::Real\n  variable y::Real\n  variable z::Real\n  variable u::Real(guess = 1){}\n\
             relations\n  der(x) = -x\n  y = 2 * x\n  z^3 + z = x\n  u^2 = 4 + x^2\n{}\nend\n\n\
             example component Starts\n  lag = Lag({})\nend\n",
            if inside.starts_with("variable") { format!("\n  {inside}") } else { String::new() },
            if relation.is_empty() { String::new() } else { format!("  {relation}\n") },
            if inside.starts_with("variable") { "" } else { inside }
        )
    };
    let pendulum = |joint: &str, body: &str| {
        format!(
            "example component Starts\n  world = MultibodyComponents.World()\n  \
             rev = MultibodyComponents.Revolute(n = [0, 0, 1]{joint})\n  \
             body = MultibodyComponents.Body(m = 1, r_cm = [0.5, 0, 0], I_22 = 0.01, I_33 = 0.01{body})\n\
             relations\n  connect(world.frame_b, rev.frame_a)\n  connect(rev.frame_b, body.frame_a)\nend\n"
        )
    };
    // (what, model text with `#`, overrides with `#`, what a word about it names)
    let cases: Vec<(&str, String, Option<&str>, &str)> = vec![
        ("initial on a library state", pendulum(", phi(initial = #)", ""), None, "rev.phi"),
        ("guess on a library state", pendulum(", phi(guess = #)", ""), None, "rev.phi"),
        (
            "initial and guess on one library state",
            pendulum(", phi(initial = 0.2, guess = #)", ""),
            None,
            "the guess of `rev.phi` has no effect",
        ),
        (
            "initial on a library variable that is not a state",
            pendulum("", ", w_a(initial = [0, 0, #])"),
            None,
            "`body.w_a` is not a state",
        ),
        (
            "guess on a library variable that is not a state",
            pendulum("", ", r_0(guess = [#, 0, 0])"),
            None,
            "`body.r_0` is not a state",
        ),
        ("initial on a user state", user("x(initial = #)", ""), None, "lag.x"),
        ("guess on a user state", user("x(guess = #)", ""), None, "lag.x"),
        ("initial on a variable computed directly", user("y(initial = #)", ""), None, "lag.y"),
        ("guess on a variable computed directly", user("y(guess = #)", ""), None, "the guess of `lag.y` has no effect"),
        ("guess on a variable solved by iteration (its root)", user("x(initial = 1), u(guess = #)", ""), None, "lag.u"),
        ("initial equation", user("", "initial x = #"), None, "lag.x"),
        ("a declaration's `= initial v`", user("variable w::Real = initial #", "der(w) = 0"), None, "w"),
        ("a start set from outside (--initial)", user("", ""), Some("lag.x"), "lag.x"),
    ];
    let mut silent = Vec::new();
    for (what, text, from_outside, named) in &cases {
        let [a, b] = [3.0, -2.0].map(|v: f64| {
            let overrides: Vec<Override> = from_outside.iter().map(|path| Override::initial(*path, v)).collect();
            outcome_of(&text.replace('#', &v.to_string()), &overrides)
        });
        let said = [&a, &b].iter().any(|(run, warnings)| {
            warnings.contains(named) && warnings.contains("no effect") || run.as_ref().is_err_and(|e| e.contains(named))
        });
        let differs = a.0.is_ok() && b.0.is_ok() && a.0 != b.0;
        println!(
            "{what}: {}",
            if differs {
                "the results differ"
            } else if said {
                "said"
            } else {
                "SILENT"
            }
        );
        if !differs && !said {
            silent.push(*what);
        }
        // An error or a warning about this start must name it.
        if let (Err(e), _) = &a {
            assert!(e.contains(named), "{what}: the error does not name `{named}`: {e}");
        }
    }
    assert!(silent.is_empty(), "start values dropped without a word: {silent:?}");
}
