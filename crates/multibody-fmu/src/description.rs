//! `modelDescription.xml` for FMI 2.0.

use crate::model::{Causality, Interface, Variability};
use multibody::SimulationOptions;
use std::fmt::Write;

/// Which interfaces an FMU offers.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Kinds {
    pub model_exchange: bool,
    pub co_simulation: bool,
}

/// What the description says besides the variables.
pub struct Header<'a> {
    pub model_name: &'a str,
    /// The binary's name (without `.so`), a C identifier.
    pub identifier: &'a str,
    pub token: &'a str,
    pub description: Option<&'a str>,
    pub kinds: Kinds,
    pub options: &'a SimulationOptions,
}

/// The FMI 2.0 model description of `interface`.
pub fn model_description(header: &Header, interface: &Interface) -> String {
    let mut x = String::with_capacity(256 * interface.variables.len() + 2048);
    x.push_str("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n");
    let _ = write!(
        x,
        "<fmiModelDescription fmiVersion=\"2.0\" modelName=\"{}\" guid=\"{}\"",
        escape(header.model_name),
        header.token
    );
    if let Some(d) = header.description {
        let _ = write!(x, " description=\"{}\"", escape(d));
    }
    let _ = writeln!(
        x,
        " generationTool=\"multibody {}\" variableNamingConvention=\"structured\" numberOfEventIndicators=\"{}\">",
        env!("CARGO_PKG_VERSION"),
        interface.indicators
    );
    let id = escape(header.identifier);
    if header.kinds.model_exchange {
        let _ = writeln!(
            x,
            "  <ModelExchange modelIdentifier=\"{id}\" canNotUseMemoryManagementFunctions=\"true\" \
             canGetAndSetFMUstate=\"false\" canSerializeFMUstate=\"false\" \
             providesDirectionalDerivative=\"false\"/>"
        );
    }
    if header.kinds.co_simulation {
        let _ = writeln!(
            x,
            "  <CoSimulation modelIdentifier=\"{id}\" canHandleVariableCommunicationStepSize=\"true\" \
             canInterpolateInputs=\"false\" maxOutputDerivativeOrder=\"0\" canRunAsynchronuously=\"false\" \
             canBeInstantiatedOnlyOncePerProcess=\"false\" canNotUseMemoryManagementFunctions=\"true\" \
             canGetAndSetFMUstate=\"false\" canSerializeFMUstate=\"false\" \
             providesDirectionalDerivative=\"false\"/>"
        );
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
    let _ = writeln!(
        x,
        "  <DefaultExperiment startTime=\"{:?}\" stopTime=\"{:?}\" tolerance=\"{:?}\"{}/>",
        o.start,
        o.stop,
        o.reltol,
        if o.saveat > 0.0 { format!(" stepSize=\"{:?}\"", o.saveat) } else { String::new() }
    );
    x.push_str("  <ModelVariables>\n");
    for (vr, v) in interface.variables.iter().enumerate() {
        let _ = write!(
            x,
            "    <!-- {} -->\n    <ScalarVariable name=\"{}\" valueReference=\"{vr}\"",
            vr + 1,
            escape(&v.name)
        );
        if let Some(d) = &v.description {
            let _ = write!(x, " description=\"{}\"", escape(d));
        }
        let causality = match v.causality {
            Causality::Parameter => "parameter",
            Causality::Input => "input",
            Causality::Output => "output",
            Causality::Local => "local",
        };
        let variability = match v.variability {
            Variability::Fixed => "fixed",
            Variability::Continuous => "continuous",
        };
        let _ = write!(x, " causality=\"{causality}\" variability=\"{variability}\"");
        if v.causality != Causality::Input {
            let _ = write!(x, " initial=\"{}\"", if v.exact { "exact" } else { "calculated" });
        }
        x.push_str(">\n      <Real");
        if let Some(u) = &v.unit {
            let _ = write!(x, " unit=\"{}\"", escape(u));
        }
        if let Some(k) = v.derivative_of {
            let _ = write!(x, " derivative=\"{}\"", k + 1);
        }
        if let (Some(s), true) = (v.start, v.exact || v.causality == Causality::Input) {
            let _ = write!(x, " start=\"{s:?}\"");
        }
        x.push_str("/>\n    </ScalarVariable>\n");
    }
    x.push_str("  </ModelVariables>\n  <ModelStructure>\n");
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
    // Known at initialization's end and computed: outputs, derivatives,
    // and states whose start is calculated.
    let mut initial: Vec<usize> = interface.outputs.clone();
    initial.extend(&interface.derivatives);
    initial.extend(interface.states.iter().filter(|&&k| !interface.variables[k].exact));
    initial.retain(|&k| !interface.variables[k].exact);
    initial.sort_unstable();
    initial.dedup();
    list(&mut x, "InitialUnknowns", &initial);
    x.push_str("  </ModelStructure>\n</fmiModelDescription>\n");
    x
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
