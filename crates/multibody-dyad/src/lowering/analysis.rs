//! `analysis ... extends TransientAnalysis(...)`: the simulation options.

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
    for m in modifiers {
        let name = m.name.name.as_str();
        if IGNORED.contains(&name) {
            warnings.push(
                Diagnostic::warning(format!("`{name}` has no effect here and is ignored")).primary(m.span, "ignored"),
            );
            continue;
        }
        if !USED.contains(&name) {
            let mut d = Diagnostic::error(format!("TransientAnalysis has no parameter `{name}`"))
                .primary(m.name.span, "unknown parameter");
            if let Some(s) = did_you_mean(name, USED.iter().chain(IGNORED).copied()) {
                d = d.help(s);
            }
            return Err(d.note(format!("its parameters are: {}", USED.join(", "))));
        }
        let Some((value, span)) = m.value.clone() else {
            return Err(Diagnostic::error(format!("`{name}` needs a value"))
                .primary(m.span, "no value")
                .help(format!("write `{name} = ...`")));
        };
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
                    "write `alg = ODEAlg.Auto()` for the default, `alg = \"Rodas4\"` for stiff models, or \
                     `alg = \"RK4\"` for fixed-step RK4",
                ),
            );
            Ok(Method::DormandPrince45)
        }
    }
}
