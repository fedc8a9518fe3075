//! `analysis ... extends TransientAnalysis(...)`: the simulation options;
//! `LinearAnalysis(...)` and `SteadyStateAnalysis(...)`: what to linearize
//! or solve for, with Dyad's parameter names.

use crate::reports::diagnostics::{did_you_mean, Diagnostic};
use crate::semantics::eval::Val;
use crate::semantics::modifiers::Mod;
use crate::syntax::ast::AnalysisDef;
use multibody::{Method, SimulationOptions};

/// TransientAnalysis parameters that set the simulation options.
const USED: &[&str] = &["start", "stop", "abstol", "reltol", "saveat", "dtmax", "alg"];
/// TransientAnalysis parameters that have no effect here (accepted, with a warning).
const IGNORED: &[&str] = &[
    "tstops",
    "automatic_discontinuity_detection",
    "optimize",
    "progress",
    "respecialize",
    "verbose",
    "log_file",
    "IfLifting",
];

/// What an analysis asks for beyond simulating.
#[derive(Clone, Debug, Default, PartialEq)]
pub enum Study {
    /// Simulate (TransientAnalysis).
    #[default]
    Transient,
    /// Linearize at the start (DyadControlSystems.LinearAnalysis): between
    /// the inputs and outputs named, with the step response's `duration`.
    Linear { inputs: Vec<String>, outputs: Vec<String>, duration: Option<f64> },
    /// Find the steady state (SteadyStateAnalysis) to these tolerances.
    SteadyState { abstol: f64, reltol: f64 },
    /// Export an FMU (DyadFMUGeneration.FMUAnalysis): the FMI version (2
    /// or 3), which kinds, and the variables named as inputs and outputs.
    Fmu { version: u8, model_exchange: bool, co_simulation: bool, inputs: Vec<String>, outputs: Vec<String> },
}

const LINEAR: &[&str] = &["inputs", "outputs", "duration", "loop_openings"];
const LINEAR_IGNORED: &[&str] = &["wl", "wh", "num_frequencies"];
const STEADY: &[&str] = &["abstol", "reltol"];
const FMU: &[&str] = &["version", "fmu_type", "n_inputs", "inputs", "n_outputs", "outputs", "alg"];
const FMU_IGNORED: &[&str] = &["additional_deps", "use_juliac", "verbose", "logfile", "respecialize"];
const STEADY_IGNORED: &[&str] = &["alg", "automatic_discontinuity_detection", "respecialize"];

/// The options and study of an analysis, and warnings about what it ignores.
pub fn analysis_options(
    analysis: &AnalysisDef,
    modifiers: Vec<Mod>,
    warnings: &mut Vec<Diagnostic>,
) -> Result<(SimulationOptions, Study), Diagnostic> {
    let base = analysis.base.text();
    let kind = base.rsplit('.').next().unwrap_or(&base);
    match kind {
        "LinearAnalysis" => {
            let mut study = (Vec::new(), Vec::new(), None);
            for m in parameters(kind, modifiers, LINEAR, LINEAR_IGNORED, warnings)? {
                let (value, span) = m.value.clone().expect("checked");
                match m.name.name.as_str() {
                    "inputs" => study.0 = strings(&m.name.name, &value, span)?,
                    "outputs" => study.1 = strings(&m.name.name, &value, span)?,
                    "loop_openings" => {
                        if !strings(&m.name.name, &value, span)?.is_empty() {
                            return Err(Diagnostic::error("loop openings are not supported yet")
                                .primary(span, "not supported yet")
                                .help("linearize between a top-level RealInput and the outputs instead: make the signal you would open an input of the model"));
                        }
                    }
                    _ => study.2 = Some(number(&m.name.name, &value, span)?),
                }
            }
            Ok((SimulationOptions::default(), Study::Linear { inputs: study.0, outputs: study.1, duration: study.2 }))
        }
        "SteadyStateAnalysis" => {
            let (mut abstol, mut reltol) = (1e-8, 1e-8);
            for m in parameters(kind, modifiers, STEADY, STEADY_IGNORED, warnings)? {
                let (value, span) = m.value.clone().expect("checked");
                let x = number(&m.name.name, &value, span)?;
                if !(x > 0.0 && x.is_finite()) {
                    return Err(Diagnostic::error(format!("`{}` must be a positive number", m.name.name))
                        .primary(span, "not positive"));
                }
                if m.name.name == "abstol" {
                    abstol = x;
                } else {
                    reltol = x;
                }
            }
            Ok((SimulationOptions::default(), Study::SteadyState { abstol, reltol }))
        }
        "FMUAnalysis" => fmu_analysis(modifiers, warnings),
        _ => Ok((transient_options(analysis, modifiers, warnings)?, Study::Transient)),
    }
}

/// An `FMUAnalysis`: Dyad's parameters, checked. `n_inputs` and
/// `n_outputs` must count the lists they go with; `alg` is the
/// co-simulation's integrator.
fn fmu_analysis(modifiers: Vec<Mod>, warnings: &mut Vec<Diagnostic>) -> Result<(SimulationOptions, Study), Diagnostic> {
    let (mut version, mut me, mut cs) = (2, true, true);
    let (mut inputs, mut outputs) = (Vec::new(), Vec::new());
    let mut counts: Vec<(&str, f64, crate::syntax::source::Span)> = Vec::new();
    let mut options = SimulationOptions::default();
    for m in parameters("FMUAnalysis", modifiers, FMU, FMU_IGNORED, warnings)? {
        let (value, span) = m.value.clone().expect("checked");
        let name = m.name.name.as_str();
        let text = |choices: &[&str]| match &value {
            Val::Str(s) if choices.contains(&s.as_str()) => Ok(s.clone()),
            other => Err(Diagnostic::error(format!(
                "`{name}` takes one of {}, but this is {}",
                choices.iter().map(|c| format!("\"{c}\"")).collect::<Vec<_>>().join(", "),
                other.describe()
            ))
            .primary(span, "not one of these")),
        };
        match name {
            "version" => version = if text(&["FMI_V2", "FMI_V3"])? == "FMI_V2" { 2 } else { 3 },
            "fmu_type" => {
                let kind = text(&["FMI_ME", "FMI_CS", "FMI_BOTH"])?;
                (me, cs) = (kind != "FMI_CS", kind != "FMI_ME");
            }
            "inputs" => inputs = strings(name, &value, span)?,
            "outputs" => outputs = strings(name, &value, span)?,
            "n_inputs" => counts.push(("inputs", number(name, &value, span)?, span)),
            "n_outputs" => counts.push(("outputs", number(name, &value, span)?, span)),
            _ => options.method = method(&value, span, &SimulationOptions::default(), warnings)?,
        }
    }
    for (list, n, span) in counts {
        let len = if list == "inputs" { inputs.len() } else { outputs.len() };
        if n != len as f64 {
            return Err(Diagnostic::error(format!("`n_{list} = {n}` but `{list}` names {len}"))
                .primary(span, "does not count the list")
                .help(format!("make `n_{list}` the number of names in `{list}`")));
        }
    }
    Ok((options, Study::Fmu { version, model_exchange: me, co_simulation: cs, inputs, outputs }))
}

/// The modifiers of a `kind` analysis with values: unknown ones are errors,
/// ignored ones warnings.
fn parameters(
    kind: &str,
    modifiers: Vec<Mod>,
    used: &[&str],
    ignored: &[&str],
    warnings: &mut Vec<Diagnostic>,
) -> Result<Vec<Mod>, Diagnostic> {
    let mut kept = Vec::new();
    for m in modifiers {
        let name = m.name.name.as_str();
        if ignored.contains(&name) {
            warnings.push(
                Diagnostic::warning(format!("`{name}` has no effect here and is ignored")).primary(m.span, "ignored"),
            );
            continue;
        }
        if !used.contains(&name) {
            let mut d = Diagnostic::error(format!("{kind} has no parameter `{name}`"))
                .primary(m.name.span, "unknown parameter");
            if let Some(s) = did_you_mean(name, used.iter().chain(ignored).copied()) {
                d = d.help(s);
            }
            return Err(d.note(format!("its parameters are: {}", used.join(", "))));
        }
        if m.value.is_none() {
            return Err(Diagnostic::error(format!("`{name}` needs a value"))
                .primary(m.span, "no value")
                .help(format!("write `{name} = ...`")));
        }
        kept.push(m);
    }
    Ok(kept)
}

fn number(name: &str, value: &Val, span: crate::syntax::source::Span) -> Result<f64, Diagnostic> {
    match value {
        Val::Number(x) => Ok(*x),
        other => Err(Diagnostic::error(format!("`{name}` takes a number, but this is {}", other.describe()))
            .primary(span, "not a number")),
    }
}

fn strings(name: &str, value: &Val, span: crate::syntax::source::Span) -> Result<Vec<String>, Diagnostic> {
    let wrong = |what: String| {
        Diagnostic::error(format!("`{name}` takes a list of names such as [\"y\"], but this is {what}"))
            .primary(span, "not a list of names")
    };
    match value {
        Val::Array(items) => items
            .iter()
            .map(|v| match v {
                Val::Str(s) => Ok(s.clone()),
                other => Err(wrong(other.describe())),
            })
            .collect(),
        Val::Str(s) => Ok(vec![s.clone()]),
        other => Err(wrong(other.describe())),
    }
}

/// The options of a transient analysis, and warnings about what it ignores.
pub fn transient_options(
    analysis: &AnalysisDef,
    modifiers: Vec<Mod>,
    warnings: &mut Vec<Diagnostic>,
) -> Result<SimulationOptions, Diagnostic> {
    let base = analysis.base.text();
    if base != "TransientAnalysis" && base != "Dyad.TransientAnalysis" {
        return Err(Diagnostic::error(format!("`{base}` analyses are not supported yet"))
            .primary(analysis.base.span, "not supported yet")
            .help("extend `TransientAnalysis(stop = ...)` to simulate the model"));
    }
    let mut options = SimulationOptions::default();
    let mut stop_given = false;
    // Where each option was given, for pointing at a bad value.
    let mut given: Vec<(String, crate::syntax::source::Span)> = Vec::new();
    let mut alg: Option<(Val, crate::syntax::source::Span)> = None;
    for m in parameters("TransientAnalysis", modifiers, USED, IGNORED, warnings)? {
        let name = m.name.name.as_str();
        let (value, span) = m.value.clone().expect("checked");
        if name == "alg" {
            alg = Some((value, span));
            continue;
        }
        let Val::Number(x) = value else {
            return Err(Diagnostic::error(format!("`{name}` takes a number, but this is {}", value.describe()))
                .primary(span, "not a number"));
        };
        given.push((name.to_string(), span));
        match name {
            "start" => options.start = x,
            "stop" => {
                options.stop = x;
                stop_given = true;
            }
            "abstol" => options.abstol = x,
            "reltol" => options.reltol = x,
            "saveat" => options.saveat = x,
            _ => options.dtmax = x,
        }
    }
    if !stop_given {
        return Err(Diagnostic::error(format!("the analysis `{}` needs a stop time", analysis.name.name))
            .primary(analysis.base_span, "no `stop`")
            .help(format!("write `extends {base}(stop = 10)`")));
    }
    if let Some((value, span)) = alg {
        given.push(("dt".into(), span));
        options.method = method(&value, span, &options, warnings)?;
    }
    if let Err(e) = options.validate() {
        let span = given.iter().find(|(name, _)| name == e.option).map_or(analysis.base_span, |(_, span)| *span);
        return Err(Diagnostic::error(e.message).primary(span, "cannot be used").help(
            "stop must be after start, abstol and reltol positive (1e-6 is usual), saveat and dtmax 0 or positive",
        ));
    }
    Ok(options)
}

/// `ODEAlg.Auto()`, `"auto"` and the adaptive default; RK4 with a fixed step.
fn method(
    value: &Val,
    span: crate::syntax::source::Span,
    options: &SimulationOptions,
    warnings: &mut Vec<Diagnostic>,
) -> Result<Method, Diagnostic> {
    let name = match value {
        Val::Enum(e) => e.rsplit('.').next().unwrap_or(e).to_string(),
        Val::Str(s) => s.clone(),
        other => {
            return Err(Diagnostic::error(format!(
                "`alg` takes a method such as `ODEAlg.Auto()` or \"auto\", but this is {}",
                other.describe()
            ))
            .primary(span, "not a method"))
        }
    };
    // Stiff methods of DifferentialEquations.jl that users name in analyses.
    const STIFF: &[&str] = &["rodas5", "rodas5p", "rodas42", "fbdf", "qndf", "trbdf2", "kencarp4", "rosenbrock23"];
    let dt = if options.saveat > 0.0 { options.saveat } else { options.dtmax };
    match (Method::from_name(&name, dt), name.to_ascii_lowercase().as_str()) {
        (Some(Method::Rk4 { .. }), _) if dt <= 0.0 => {
            Err(Diagnostic::error("RK4 takes a fixed step, but neither `saveat` nor `dtmax` is set")
                .primary(span, "needs a step")
                .help("set `saveat` (the step is the output interval) or `dtmax`"))
        }
        (Some(method), _) => Ok(method),
        (None, stiff) if STIFF.contains(&stiff) => {
            warnings.push(
                Diagnostic::warning(format!(
                    "`{name}` is not available; using Rodas4, the implicit method for stiff models"
                ))
                .primary(span, "Rodas4 instead"),
            );
            Ok(Method::Rodas4)
        }
        _ => {
            warnings.push(
                Diagnostic::warning(format!(
                    "the method `{name}` is not available; using the default adaptive method (Dormand-Prince 4(5))"
                ))
                .primary(span, "not available")
                .help(
                    "write `alg = ODEAlg.Auto()` for the default, `alg = \"Rodas4\"` or `alg = \"ROS34PW2\"` for \
                     stiff models, or `alg = \"RK4\"` for fixed-step RK4",
                ),
            );
            Ok(Method::DormandPrince45)
        }
    }
}
