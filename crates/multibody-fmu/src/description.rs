//! `modelDescription.xml`, for FMI 2.0 and 3.0.

use crate::model::{Causality, Interface, Variability, Variable};
use multibody::SimulationOptions;
use std::fmt::Write;

/// Which interfaces an FMU offers.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Kinds {
    pub model_exchange: bool,
    pub co_simulation: bool,
}

/// The FMI version of an FMU.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Version {
    Fmi2,
    Fmi3,
}

/// What the description says besides the variables.
pub struct Header<'a> {
    pub model_name: &'a str,
    /// The binary's name (without its suffix), a C identifier.
    pub identifier: &'a str,
    pub token: &'a str,
    pub kinds: Kinds,
    pub options: &'a SimulationOptions,
    pub version: Version,
}

/// The model description of `interface`.
pub fn model_description(header: &Header, interface: &Interface) -> String {
    let v3 = header.version == Version::Fmi3;
    let mut x = String::with_capacity(256 * interface.variables.len() + 2048);
    x.push_str("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n");
    let name = escape(header.model_name);
    let tool = concat!("multibody ", env!("CARGO_PKG_VERSION"));
    if v3 {
        let _ = writeln!(
            x,
            "<fmiModelDescription fmiVersion=\"3.0\" modelName=\"{name}\" instantiationToken=\"{}\" \
             generationTool=\"{tool}\" variableNamingConvention=\"structured\">",
            header.token
        );
    } else {
        let _ = writeln!(
            x,
            "<fmiModelDescription fmiVersion=\"2.0\" modelName=\"{name}\" guid=\"{}\" generationTool=\"{tool}\" \
             variableNamingConvention=\"structured\" numberOfEventIndicators=\"{}\">",
            header.token,
            interface.indicators.len()
        );
    }
    let id = escape(header.identifier);
    // No FMU state (yet); directional derivatives by differences.
    let common = "canGetAndSetFMUState=\"false\" canSerializeFMUState=\"false\" \
                  providesDirectionalDerivative=\"true\"";
    let common = if v3 { common.to_string() } else { common.replace("FMUState", "FMUstate") };
    if header.kinds.model_exchange {
        let memory = if v3 { "" } else { " canNotUseMemoryManagementFunctions=\"true\"" };
        let _ = writeln!(x, "  <ModelExchange modelIdentifier=\"{id}\"{memory} {common}/>");
    }
    if header.kinds.co_simulation {
        let extra = if v3 {
            "canHandleVariableCommunicationStepSize=\"true\" maxOutputDerivativeOrder=\"0\" \
             hasEventMode=\"false\" canReturnEarlyAfterIntermediateUpdate=\"false\""
        } else {
            "canHandleVariableCommunicationStepSize=\"true\" canInterpolateInputs=\"false\" \
             maxOutputDerivativeOrder=\"0\" canRunAsynchronuously=\"false\" \
             canBeInstantiatedOnlyOncePerProcess=\"false\" canNotUseMemoryManagementFunctions=\"true\""
        };
        let _ = writeln!(x, "  <CoSimulation modelIdentifier=\"{id}\" {extra} {common}/>");
    }
    let mut units: Vec<&str> = interface.variables.iter().filter_map(|v| v.unit.as_deref()).collect();
    units.sort_unstable();
    units.dedup();
    if !units.is_empty() {
        x.push_str("  <UnitDefinitions>\n");
        for u in &units {
            let _ = writeln!(x, "    <Unit name=\"{}\"/>", escape(u));
        }
        x.push_str("  </UnitDefinitions>\n");
    }
    let o = header.options;
    let step = if o.saveat > 0.0 { format!(" stepSize=\"{:?}\"", o.saveat) } else { String::new() };
    let _ = writeln!(
        x,
        "  <DefaultExperiment startTime=\"{:?}\" stopTime=\"{:?}\" tolerance=\"{:?}\"{step}/>",
        o.start, o.stop, o.reltol
    );
    x.push_str("  <ModelVariables>\n");
    for (vr, v) in interface.variables.iter().enumerate() {
        if v3 {
            variable_3(&mut x, vr, v);
        } else {
            variable_2(&mut x, vr, v);
        }
    }
    x.push_str("  </ModelVariables>\n  <ModelStructure>\n");
    // Known at initialization's end and computed: outputs, derivatives,
    // and states whose start is calculated.
    let mut initial: Vec<usize> = interface.outputs.clone();
    initial.extend(&interface.derivatives);
    initial.extend(interface.states.iter().filter(|&&k| !interface.variables[k].exact));
    initial.retain(|&k| !interface.variables[k].exact);
    initial.sort_unstable();
    initial.dedup();
    if v3 {
        // Elements name value references.
        let list = |x: &mut String, tag: &str, refs: &[usize]| {
            for k in refs {
                let _ = writeln!(x, "    <{tag} valueReference=\"{k}\"/>");
            }
        };
        list(&mut x, "Output", &interface.outputs);
        list(&mut x, "ContinuousStateDerivative", &interface.derivatives);
        list(&mut x, "InitialUnknown", &initial);
        list(&mut x, "EventIndicator", &interface.indicators);
    } else {
        // Elements name 1-based positions in ModelVariables.
        let list = |x: &mut String, tag: &str, indices: &[usize]| {
            if indices.is_empty() {
                return;
            }
            let _ = writeln!(x, "    <{tag}>");
            for k in indices {
                let _ = writeln!(x, "      <Unknown index=\"{}\"/>", k + 1);
            }
            let _ = writeln!(x, "    </{tag}>");
        };
        list(&mut x, "Outputs", &interface.outputs);
        list(&mut x, "Derivatives", &interface.derivatives);
        list(&mut x, "InitialUnknowns", &initial);
    }
    x.push_str("  </ModelStructure>\n</fmiModelDescription>\n");
    x
}

fn causality(v: &Variable) -> &'static str {
    match v.causality {
        Causality::Independent => "independent",
        Causality::Parameter => "parameter",
        Causality::Input => "input",
        Causality::Output => "output",
        Causality::Local => "local",
    }
}

fn variability(v: &Variable) -> &'static str {
    match v.variability {
        Variability::Fixed => "fixed",
        Variability::Continuous => "continuous",
    }
}

/// The attributes both versions write the same way: causality,
/// variability, initial.
fn kind_attributes(x: &mut String, v: &Variable) {
    let _ = write!(x, " causality=\"{}\" variability=\"{}\"", causality(v), variability(v));
    if !matches!(v.causality, Causality::Input | Causality::Independent) {
        let _ = write!(x, " initial=\"{}\"", if v.exact { "exact" } else { "calculated" });
    }
}

fn start(v: &Variable) -> Option<f64> {
    v.start.filter(|_| v.exact || v.causality == Causality::Input)
}

/// FMI 2.0: a `ScalarVariable` holding a `Real`; `derivative` is the
/// state's 1-based position.
fn variable_2(x: &mut String, vr: usize, v: &Variable) {
    let _ =
        write!(x, "    <!-- {} -->\n    <ScalarVariable name=\"{}\" valueReference=\"{vr}\"", vr + 1, escape(&v.name));
    if let Some(d) = &v.description {
        let _ = write!(x, " description=\"{}\"", escape(d));
    }
    kind_attributes(x, v);
    x.push_str(">\n      <Real");
    if let Some(u) = &v.unit {
        let _ = write!(x, " unit=\"{}\"", escape(u));
    }
    if let Some(k) = v.derivative_of {
        let _ = write!(x, " derivative=\"{}\"", k + 1);
    }
    if let Some(s) = start(v) {
        let _ = write!(x, " start=\"{s:?}\"");
    }
    x.push_str("/>\n    </ScalarVariable>\n");
}

/// FMI 3.0: a `Float64`; `derivative` is the state's value reference.
fn variable_3(x: &mut String, vr: usize, v: &Variable) {
    let _ = write!(x, "    <Float64 name=\"{}\" valueReference=\"{vr}\"", escape(&v.name));
    if let Some(d) = &v.description {
        let _ = write!(x, " description=\"{}\"", escape(d));
    }
    kind_attributes(x, v);
    if let Some(u) = &v.unit {
        let _ = write!(x, " unit=\"{}\"", escape(u));
    }
    if let Some(k) = v.derivative_of {
        let _ = write!(x, " derivative=\"{k}\"");
    }
    if let Some(s) = start(v) {
        let _ = write!(x, " start=\"{s:?}\"");
    }
    x.push_str("/>\n");
}

fn escape(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\n' => out.push_str("&#10;"),
            c => out.push(c),
        }
    }
    out
}
