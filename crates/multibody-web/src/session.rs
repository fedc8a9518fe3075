//! A model loaded once and run again with other values: what the live page
//! does on every change, with the command's own checks and messages.

use multibody::{Mechanism, SimulationOptions, Simulator, Solution};
use multibody_dyad::study::{parse_overrides, OptionOverrides};
use multibody_dyad::{Diagnostic, Override, Package, Target, TunableKind};
use multibody_view::{animation_scene, AnimationOptions};
use serde_json::{json, Map, Value};
use std::sync::Arc;

/// The model files, and what of them to run.
pub struct Session {
    package: Package,
    target: Target,
    /// The analysis's (or component's) name: the page's title.
    name: String,
    /// Signal patterns for the plots (empty: the view's guess).
    signals: Vec<String>,
    /// What the panel offers, described once at loading.
    model: Value,
    /// The run being stepped in real time, if one is.
    stepping: Option<Stepping>,
}

/// A run the page advances step by step while its inputs change.
struct Stepping {
    simulator: Simulator<'static>,
    mechanism: Arc<Mechanism>,
    stop: f64,
    /// The recorded signals' names and units.
    names: Vec<String>,
    units: Vec<&'static str>,
}

/// The most animation frames per second a stepped run's scene keeps of
/// its recorded samples (the view interpolates between them).
const STEPPED_FPS: f64 = 60.0;

/// One run's values, each as the user typed it (`"0.7"`), so that a bad
/// one gets the command's message for the same text.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Values {
    /// `NAME=VALUE`, as `--param` takes them.
    pub params: Vec<String>,
    /// `NAME=VALUE`, as `--initial` takes them.
    pub initials: Vec<String>,
    /// The stop time, as `--stop` takes it; `None` keeps the analysis's.
    pub stop: Option<String>,
}

/// A finished run: the scene to draw and every signal's final value.
pub struct Run {
    /// The scene JSON the viewer reads (see `multibody_view::animation_scene`).
    pub scene: String,
    /// Each recorded signal at the end of the run, at full precision.
    pub finals: Map<String, Value>,
    pub warnings: Vec<String>,
    pub stop: f64,
}

impl Session {
    /// Reads the files (name and text each) and chooses the analysis or
    /// component, as `multibody run` does. The error is the command's
    /// message, without colour.
    pub fn load(
        files: &[(String, String)],
        analysis: Option<&str>,
        model: Option<&str>,
        signals: Vec<String>,
    ) -> Result<Session, String> {
        let package = Package::from_texts(files)?;
        let target = package.choose_target(analysis, model)?;
        let lowered = package.lower_target(&target, &[]).map_err(|d| package.render(&[d]))?;
        let model = description(&lowered);
        Ok(Session { name: lowered.name.clone(), package, target, signals, model, stepping: None })
    }

    /// The title of the page: the analysis's or the component's name.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// What the panel offers: the model's own parameters and start values
    /// (with units and docs), its inputs, and the run's options.
    pub fn describe(&self) -> &Value {
        &self.model
    }

    /// Lowers, assembles and simulates with `values`; a failure is the
    /// message `multibody run` prints for the same values.
    pub fn run(&self, values: &Values) -> Result<Run, String> {
        let (lowered, options, mechanism) = self.prepare(values)?;
        let mut warnings: Vec<String> = mechanism.warnings().to_vec();
        let solution = mechanism.simulate(&options).map_err(|stopped| {
            let reason = lowered.with_places(self.package.sources(), &stopped.reason);
            format!("the simulation stopped at t = {}: {reason}", multibody_dyad::study::number(stopped.time))
        })?;
        warnings.extend(solution.warnings().iter().cloned());
        let scene = self.scene(&mechanism, &solution)?;
        let mut finals = Map::new();
        for name in solution.names() {
            if let Some(x) = solution.last(name) {
                finals.insert(name.clone(), json!(x));
            }
        }
        Ok(Run { scene, finals, warnings, stop: options.stop })
    }

    /// Starts a run that the page advances with [`step`](Self::step),
    /// setting the model's inputs (its top-level `RealInput`s) as it goes.
    /// Gives the inputs' names and start values.
    pub fn start(&mut self, values: &Values) -> Result<Vec<(String, f64)>, String> {
        self.stepping = None;
        let (_, options, mechanism) = self.prepare(values)?;
        let mechanism = Arc::new(mechanism);
        let simulator = Simulator::new(mechanism.clone(), &options)
            .map_err(|stopped| format!("the simulation cannot start: {}", stopped.reason))?;
        let inputs = simulator
            .input_names()
            .into_iter()
            .map(|name| (name.to_string(), simulator.input(name).unwrap_or(0.0)))
            .collect();
        let (names, units) = mechanism.signals().into_iter().map(|s| (s.name, s.unit)).unzip();
        self.stepping = Some(Stepping { simulator, mechanism, stop: options.stop, names, units });
        Ok(inputs)
    }

    /// Sets `inputs` and advances the started run to `until` (at most its
    /// stop time). The scene holds the motion from the start; `finals` the
    /// states at the time reached. A failure ends the stepped run.
    pub fn step(&mut self, until: f64, inputs: &[(String, f64)]) -> Result<Run, String> {
        let Some(stepping) = self.stepping.as_mut() else {
            return Err("no run is started: send `start` first".into());
        };
        let target = until.min(stepping.stop);
        let advanced =
            inputs.iter().try_for_each(|(name, value)| stepping.simulator.set_input(name, *value)).and_then(|_| {
                if target > stepping.simulator.time() {
                    stepping.simulator.step_until(target).map_err(|stopped| {
                        format!(
                            "the simulation stopped at t = {}: {}",
                            multibody_dyad::study::number(stopped.time),
                            stopped.reason
                        )
                    })
                } else {
                    Ok(())
                }
            });
        if let Err(message) = advanced {
            self.stepping = None;
            return Err(message);
        }
        let stepping = self.stepping.as_ref().expect("kept on success");
        let simulator = &stepping.simulator;
        let solution = thinned(simulator, stepping.names.clone(), stepping.units.clone(), STEPPED_FPS);
        let scene = self.scene(&stepping.mechanism, &solution)?;
        let mut finals = Map::new();
        for (name, x) in simulator.state_names().iter().zip(simulator.state()) {
            finals.insert(name.clone(), json!(x));
        }
        Ok(Run { scene, finals, warnings: simulator.notes().to_vec(), stop: simulator.time() })
    }

    /// The model lowered and assembled with `values`, and its options.
    fn prepare(&self, values: &Values) -> Result<(multibody_dyad::Lowered, SimulationOptions, Mechanism), String> {
        let overrides = parse_overrides(&values.params, &values.initials)?;
        let stop = match &values.stop {
            None => None,
            Some(text) => Some(
                text.trim()
                    .parse::<f64>()
                    .map_err(|_| format!("`--stop {text}`: `{text}` is not a number (write --stop 5)"))?,
            ),
        };
        let lowered = self.package.lower_target(&self.target, &overrides).map_err(|d| self.blame(&overrides, d))?;
        let options =
            OptionOverrides { stop, ..Default::default() }.over(&lowered.options).map_err(|e| e.as_command_option())?;
        let mechanism = lowered.assemble().map_err(|d| self.blame(&overrides, d))?;
        Ok((lowered, options, mechanism))
    }

    fn scene(&self, mechanism: &Mechanism, solution: &multibody::Solution) -> Result<String, String> {
        let options = AnimationOptions {
            signals: self.signals.clone(),
            up: AnimationOptions::up_of(mechanism),
            ..Default::default()
        };
        animation_scene(&self.name, &mechanism.shapes(), solution, &options)
            .map(|(scene, _)| scene)
            .map_err(|e| e.to_string())
    }

    /// The message for a model that fails with `overrides`: blamed on the
    /// value that spoils it, else shown at its place in the files.
    fn blame(&self, overrides: &[Override], d: Diagnostic) -> String {
        self.package.blame_override(&self.target, overrides).unwrap_or_else(|| self.package.render(&[d]))
    }
}

/// The panel's description of a lowered model (see [`Session::describe`]).
fn description(lowered: &multibody_dyad::Lowered) -> Value {
    let tunables: Vec<Value> = lowered
        .tunables
        .iter()
        .map(|t| {
            json!({
                "path": t.path,
                "kind": match t.kind { TunableKind::Parameter => "parameter", TunableKind::Start => "start" },
                "value": t.value,
                "unit": t.unit,
                "doc": t.doc,
                "min": t.min,
                "max": t.max,
                "integer": t.integer,
                "derived": t.derived,
            })
        })
        .collect();
    // A model that does not assemble has no inputs to offer; its runs say why.
    let inputs: Vec<String> = match lowered.assemble() {
        Ok(mechanism) => mechanism.input_names().into_iter().map(str::to_string).collect(),
        Err(_) => Vec::new(),
    };
    json!({
        "name": lowered.name,
        "tunables": tunables,
        "inputs": inputs,
        "stop": lowered.options.stop,
        "start": lowered.options.start,
        "saveat": lowered.options.saveat,
    })
}

/// The samples a simulator recorded, at most `fps` a second (and the last):
/// a stepped run's scene stays small however fine its output grid.
fn thinned(simulator: &Simulator, names: Vec<String>, units: Vec<&'static str>, fps: f64) -> Solution {
    let rows = simulator.recorded();
    let mut solution = Solution::new(names, units);
    let mut next = f64::NEG_INFINITY;
    let n = rows.len();
    for k in 0..n {
        let t = rows.time()[k];
        if t >= next || k + 1 == n {
            solution.push(t, rows.row(k));
            next = t + 1.0 / fps;
        }
    }
    solution
}
