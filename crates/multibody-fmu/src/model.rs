//! A model as an FMU shows it: its files, what of them runs, and its
//! variables with their value references. The export and the runtime both
//! build it from the same files with this one function, so their value
//! references agree; the token checks that they are the same files.

use multibody::{Mechanism, SimulationOptions, Simulator};
use multibody_dyad::study::Target;
use multibody_dyad::{Diagnostic, Lowered, Override, Package, Study, TunableKind};
use serde_json::{json, Value};
use std::sync::Arc;

/// The runtime's identity, part of every token: an FMU exported for
/// another runtime refuses to instantiate.
pub const RUNTIME_ID: &str = concat!("multibody-fmu ", env!("CARGO_PKG_VERSION"), " (FMI 2.0 and 3.0, layout 2)");

/// The settings file beside the model files in `resources/`.
pub const SETTINGS_FILE: &str = "fmu.json";
/// The folder of the model files in `resources/`.
pub const MODEL_FOLDER: &str = "model";

/// What the export stores beside the model files (`resources/fmu.json`).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Settings {
    /// The model files' names, as stored in `resources/model/`.
    pub files: Vec<String>,
    pub analysis: Option<String>,
    pub model: Option<String>,
    /// Variables to expose as outputs besides the model's `RealOutput`s
    /// (an `FMUAnalysis`'s `outputs`).
    pub outputs: Vec<String>,
}

impl Settings {
    pub fn to_json(&self) -> String {
        let value = json!({
            "runtime": RUNTIME_ID,
            "files": self.files,
            "analysis": self.analysis,
            "model": self.model,
            "outputs": self.outputs,
        });
        serde_json::to_string_pretty(&value).expect("plain JSON")
    }

    pub fn from_json(text: &str) -> Result<Settings, String> {
        let value: Value =
            serde_json::from_str(text).map_err(|e| format!("`{SETTINGS_FILE}` is not valid JSON: {e}"))?;
        let strings = |key: &str| -> Vec<String> {
            value[key]
                .as_array()
                .map_or_else(Vec::new, |a| a.iter().filter_map(|s| s.as_str().map(String::from)).collect())
        };
        let text = |key: &str| value[key].as_str().map(String::from);
        Ok(Settings {
            files: strings("files"),
            analysis: text("analysis"),
            model: text("model"),
            outputs: strings("outputs"),
        })
    }
}

/// The FMU's description, beside `resources/`.
pub const DESCRIPTION_FILE: &str = "modelDescription.xml";

/// FNV-1a over each piece (each ended by 0xff), from the base `basis`.
fn digest<'a>(basis: u64, prime: u64, pieces: impl IntoIterator<Item = &'a [u8]>) -> u64 {
    let mut h = basis;
    for bytes in pieces {
        for &x in bytes.iter().chain(&[0xff]) {
            h = (h ^ x as u64).wrapping_mul(prime);
        }
    }
    h
}

/// The pieces of the files' half of the token: the runtime's identity,
/// the settings and every model file.
fn file_pieces<'a>(settings_json: &'a str, files: &'a [(String, String)]) -> Vec<&'a [u8]> {
    let mut pieces = vec![RUNTIME_ID.as_bytes(), settings_json.as_bytes()];
    for (name, text) in files {
        pieces.push(name.as_bytes());
        pieces.push(text.as_bytes());
    }
    pieces
}

/// The token of an FMU (FMI 2's `guid`, FMI 3's `instantiationToken`),
/// written as a GUID: its first half a digest of the runtime's identity,
/// the settings and every model file; its second half a digest of those
/// and of the model description, written with an empty token
/// ([`without_token`]). An edited description (value references
/// swapped, a start changed) no longer matches its token.
pub fn token(settings_json: &str, files: &[(String, String)], description: &str) -> String {
    // FNV-1a: a check that the files are the ones exported, not a
    // signature. The multipliers are odd: an even one (the second was)
    // shifts all but the last 64 bytes out of the digest.
    let pieces = file_pieces(settings_json, files);
    let a = digest(0xcbf2_9ce4_8422_2325, 0x0100_0000_01b3, pieces.iter().copied());
    let b =
        digest(0x6c62_272e_07bb_0142, 0x9e37_79b9_7f4a_7c15, pieces.iter().copied().chain([description.as_bytes()]));
    let h = format!("{a:016x}{b:016x}");
    format!("{{{}-{}-{}-{}-{}}}", &h[0..8], &h[8..12], &h[12..16], &h[16..20], &h[20..32])
}

/// The description as it was digested: the token's attribute (the first
/// `"token"`) emptied.
pub fn without_token(description: &str, token: &str) -> String {
    description.replacen(&format!("\"{token}\""), "\"\"", 1)
}

/// Whether the token the host gave is the one of these files and this
/// description; else what differs, and what to do. Without the
/// description (a host that unpacked only `resources/` and `binaries/`,
/// as FMPy does) the files' half of the token is checked.
pub fn check_token(
    expected: &str,
    settings_json: &str,
    files: &[(String, String)],
    description: Option<&str>,
) -> Result<(), String> {
    let half = |t: &str| t.chars().filter(char::is_ascii_hexdigit).take(16).collect::<String>();
    let actual = token(settings_json, files, &without_token(description.unwrap_or_default(), expected));
    // The files' half: the model files are the exported ones.
    let files_agree = half(expected).len() == 16 && half(&actual) == half(expected);
    match description {
        // The description carries the token it was digested with.
        Some(description) if actual == expected && description.contains(&format!("\"{expected}\"")) => Ok(()),
        None if files_agree => Ok(()),
        Some(_) if files_agree => Err(format!(
            "token mismatch: the FMU's {DESCRIPTION_FILE} was edited after the export (its token {expected} covers \
             the description too): its variables may no longer be the model's (value references, causalities, \
             starts). Export the FMU again instead of editing its description"
        )),
        _ => Err(format!(
            "token mismatch: the FMU's description has the token {expected}, but its model files and this runtime \
             ({RUNTIME_ID}) give {}: the files in resources/ were edited after the export, or the binary is another \
             version. Export the FMU again",
            if description.is_some() { actual } else { format!("{{{}...}}", &half(&actual)[..8]) }
        )),
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Causality {
    /// Time.
    Independent,
    Parameter,
    Input,
    Output,
    Local,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Variability {
    Fixed,
    Continuous,
}

/// Where a variable's value comes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Source {
    /// A column of the results.
    Signal(usize),
    /// A state (its position in the state vector) that is not a column.
    State(usize),
    /// The derivative of state `k`.
    Derivative(usize),
    /// The model's input `k`.
    Input(usize),
    /// A parameter of the model's files (the tunable of that position).
    Parameter(usize),
    Time,
    /// Event indicator `k` (FMI 3.0 lists them as variables).
    Indicator(usize),
}

/// One scalar variable; its value reference is its position.
#[derive(Clone, Debug, PartialEq)]
pub struct Variable {
    pub name: String,
    pub unit: Option<String>,
    pub description: Option<String>,
    pub causality: Causality,
    pub variability: Variability,
    /// Whether the start value is exact (set before initialization: a
    /// parameter, a state's start), else calculated.
    pub exact: bool,
    pub start: Option<f64>,
    pub source: Source,
    /// For a state's derivative: the value reference of the state.
    pub derivative_of: Option<usize>,
    /// For a state or an exact start: the override that sets it.
    pub sets: Option<Override>,
}

/// The interface of a model: every variable, which are states, their
/// derivatives, outputs and inputs, and how many event indicators.
#[derive(Clone, Debug)]
pub struct Interface {
    pub variables: Vec<Variable>,
    /// The value reference of each state, in state order.
    pub states: Vec<usize>,
    /// The value reference of each state's derivative.
    pub derivatives: Vec<usize>,
    pub outputs: Vec<usize>,
    /// The value reference of each input, in input order.
    pub inputs: Vec<usize>,
    /// The value reference of each event indicator.
    pub indicators: Vec<usize>,
    /// The value reference of time.
    pub time: usize,
}

/// A model loaded from its files and assembled with its own values.
pub struct Loaded {
    pub package: Package,
    pub target: Target,
    pub settings: Settings,
    pub lowered: Lowered,
    pub mechanism: Arc<Mechanism>,
    pub interface: Interface,
    /// The analysis's options (the FMU's default experiment).
    pub options: SimulationOptions,
    /// What an FMI host should know (outputs missing, ...).
    pub warnings: Vec<String>,
}

impl Loaded {
    /// Reads the files, chooses what to run, lowers and assembles it, and
    /// lays out its variables.
    pub fn load(files: &[(String, String)], settings: &Settings) -> Result<Loaded, String> {
        let package = Package::from_texts(files)?;
        let target = package.choose_target(settings.analysis.as_deref(), settings.model.as_deref())?;
        let lowered = package.lower_target(&target, &[]).map_err(|d| package.render(&[d]))?;
        let mechanism = Arc::new(lowered.assemble().map_err(|d| package.render(&[d]))?);
        let options = lowered.options.clone();
        let mut outputs = settings.outputs.clone();
        if let Study::Fmu { outputs: more, .. } = &lowered.study {
            outputs.extend(more.iter().cloned());
        }
        let (interface, warnings) = interface(&lowered, &mechanism, &options, &outputs)?;
        Ok(Loaded { package, target, settings: settings.clone(), lowered, mechanism, interface, options, warnings })
    }

    /// The model lowered and assembled again with `overrides` (parameters
    /// and start values set before initialization), refused when that
    /// changes its variables (an integer parameter that adds parts).
    pub fn with(&self, overrides: &[Override]) -> Result<Arc<Mechanism>, String> {
        if overrides.is_empty() {
            return Ok(self.mechanism.clone());
        }
        let blame = |d: Diagnostic| {
            self.package.blame_override(&self.target, overrides).unwrap_or_else(|| self.package.render(&[d]))
        };
        let lowered = self.package.lower_target(&self.target, overrides).map_err(blame)?;
        let mechanism = lowered.assemble().map_err(blame)?;
        if mechanism.states().names != self.mechanism.states().names
            || mechanism.signals().len() != self.mechanism.signals().len()
        {
            return Err("the values set change the model's variables (its states or signals), which an FMU \
                        cannot: export the model with these values instead"
                .into());
        }
        Ok(Arc::new(mechanism))
    }
}

/// The variables of a model, with the value reference of each its
/// position: every column of the results (as `multibody run` names them),
/// the states that are not columns, the states' derivatives `der(x)`, and
/// the numeric parameters of the model's own components.
fn interface(
    lowered: &Lowered,
    mechanism: &Arc<Mechanism>,
    options: &SimulationOptions,
    extra_outputs: &[String],
) -> Result<(Interface, Vec<String>), String> {
    let signals = mechanism.signals();
    let states = mechanism.states();
    let input_names: Vec<String> = mechanism.input_names().into_iter().map(String::from).collect();
    let mut outputs: Vec<String> = mechanism.output_names().to_vec();
    for name in extra_outputs {
        if !signals.iter().any(|s| &s.name == name) {
            let hint = multibody_dyad::diagnostics::did_you_mean(name, signals.iter().map(|s| s.name.as_str()))
                .map_or(String::new(), |h| format!("; {h}"));
            return Err(format!("the output `{name}` is not a variable of the model{hint}"));
        }
        if !outputs.contains(name) {
            outputs.push(name.clone());
        }
    }
    let simulator = Simulator::for_host(mechanism.clone(), options)
        .map_err(|stopped| format!("the model cannot start: {}", stopped.reason))?;
    let inputs_now: Vec<f64> = input_names.iter().map(|n| simulator.input(n).unwrap_or(0.0)).collect();
    let start_of = |name: &str| states.names.iter().position(|n| n == name);
    let settable = |name: &str| !name.contains('[');
    let mut variables = Vec::new();
    let mut input_vr = vec![usize::MAX; input_names.len()];
    for (k, s) in signals.iter().enumerate() {
        let unit = (!s.unit.is_empty()).then(|| s.unit.to_string());
        let input = input_names.iter().position(|n| *n == s.name);
        let state = start_of(&s.name);
        let mut v = Variable {
            name: s.name.clone(),
            unit,
            description: None,
            causality: Causality::Local,
            variability: Variability::Continuous,
            exact: false,
            start: None,
            source: Source::Signal(k),
            derivative_of: None,
            sets: None,
        };
        if let Some(i) = input {
            v.causality = Causality::Input;
            v.start = Some(inputs_now[i]);
            v.source = Source::Input(i);
            input_vr[i] = variables.len();
        } else if let Some(j) = state.filter(|_| settable(&s.name)) {
            v.exact = true;
            v.start = Some(states.start[j]);
            v.sets = Some(Override::initial(s.name.clone(), states.start[j]));
        }
        if outputs.contains(&s.name) {
            v.causality = Causality::Output;
        }
        variables.push(v);
    }
    // Inputs without a column of their own.
    for (i, name) in input_names.iter().enumerate() {
        if input_vr[i] == usize::MAX {
            input_vr[i] = variables.len();
            variables.push(Variable {
                name: name.clone(),
                unit: None,
                description: Some("an input of the model".into()),
                causality: Causality::Input,
                variability: Variability::Continuous,
                exact: false,
                start: Some(inputs_now[i]),
                source: Source::Input(i),
                derivative_of: None,
                sets: None,
            });
        }
    }
    let mut state_vr = Vec::with_capacity(states.names.len());
    for (j, name) in states.names.iter().enumerate() {
        match signals.iter().position(|s| &s.name == name) {
            Some(k) => state_vr.push(k),
            None => {
                state_vr.push(variables.len());
                variables.push(Variable {
                    name: name.clone(),
                    unit: None,
                    description: Some("a state".into()),
                    causality: Causality::Local,
                    variability: Variability::Continuous,
                    exact: false,
                    start: None,
                    source: Source::State(j),
                    derivative_of: None,
                    sets: None,
                });
            }
        }
    }
    let mut derivatives = Vec::with_capacity(states.names.len());
    for (j, name) in states.names.iter().enumerate() {
        derivatives.push(variables.len());
        let unit = variables[state_vr[j]].unit.as_deref().map(|u| format!("{u}/s"));
        variables.push(Variable {
            name: format!("der({name})"),
            unit: unit.filter(|u| u != "/s"),
            description: None,
            causality: Causality::Local,
            variability: Variability::Continuous,
            exact: false,
            start: None,
            source: Source::Derivative(j),
            derivative_of: Some(state_vr[j]),
            sets: None,
        });
    }
    for (p, t) in lowered.tunables.iter().enumerate() {
        if t.kind != TunableKind::Parameter || t.integer || variables.iter().any(|v| v.name == t.path) {
            continue;
        }
        variables.push(Variable {
            name: t.path.clone(),
            unit: t.unit.clone().filter(|u| !u.is_empty()),
            description: t.doc.clone(),
            causality: Causality::Parameter,
            variability: Variability::Fixed,
            exact: true,
            start: Some(t.value),
            source: Source::Parameter(p),
            derivative_of: None,
            sets: Some(t.set(t.value)),
        });
    }
    let local = |name: String, description: &str, source: Source| Variable {
        name,
        unit: None,
        description: Some(description.into()),
        causality: Causality::Local,
        variability: Variability::Continuous,
        exact: false,
        start: None,
        source,
        derivative_of: None,
        sets: None,
    };
    let names = simulator.indicator_names();
    let mut indicators = Vec::with_capacity(names.len());
    for (k, name) in names.iter().enumerate() {
        indicators.push(variables.len());
        variables.push(local(format!("event_indicator[{}]", k + 1), name, Source::Indicator(k)));
    }
    let time = variables.len();
    variables.push(Variable {
        causality: Causality::Independent,
        unit: Some("s".into()),
        ..local("time".into(), "time", Source::Time)
    });
    let outputs: Vec<usize> =
        variables.iter().enumerate().filter(|(_, v)| v.causality == Causality::Output).map(|(k, _)| k).collect();
    let mut warnings = Vec::new();
    if input_names.is_empty() && outputs.is_empty() {
        warnings.push(
            "the model has no inputs and no outputs (top-level RealInput and RealOutput components): the FMU \
             exposes its states, parameters and every variable as local ones"
                .to_string(),
        );
    } else if outputs.is_empty() {
        warnings.push("the model has no outputs (top-level RealOutput components): its variables are local".into());
    }
    let interface = Interface { variables, states: state_vr, derivatives, outputs, inputs: input_vr, indicators, time };
    Ok((interface, warnings))
}
