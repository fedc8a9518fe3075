//! `multibody linearize`, and the LinearAnalysis and SteadyStateAnalysis
//! of model files: a linear model (A, B, C, D with names) at the start, at
//! a steady state or at a time along a simulation; its poles; a Bode plot.

use crate::exit::{error_word, Failure};
use crate::load::{assemble, choose, file_of, lower, overrides, read_package, Target};
use crate::output::{outputs_are_safe, write_atomically};
use crate::run::{command_line_options, number};
use crate::LinearizeArgs;
use multibody::{Derivatives, Linearization, LinearizeOptions, Simulator, SteadyStateOptions};
use multibody_dyad::Study;
use std::path::{Path, PathBuf};

/// Where to linearize.
#[derive(Clone, Copy, Debug, PartialEq)]
enum At {
    Start,
    Steady,
    Time(f64),
}

fn at(text: &str) -> Result<At, Failure> {
    match text {
        "start" => Ok(At::Start),
        "steady" => Ok(At::Steady),
        _ => match text.strip_prefix("t=").map(str::parse::<f64>) {
            Some(Ok(t)) if t.is_finite() => Ok(At::Time(t)),
            _ => Err(Failure::Usage(format!(
                "--at {text}: write `start` (the model's start), `steady` (a steady state found from the start) or `t=2.5` (after simulating to that time)"
            ))),
        },
    }
}

fn derivatives(text: &str) -> Result<Derivatives, Failure> {
    match text {
        "auto" => Ok(Derivatives::Auto),
        "exact" => Ok(Derivatives::Exact),
        "differences" => Ok(Derivatives::Differences),
        _ => Err(Failure::Usage(format!(
            "--derivatives {text}: write `auto` (exact where the model allows, with differences as a check), `exact` or `differences`"
        ))),
    }
}

pub fn linearize(args: &LinearizeArgs) -> Result<(), Failure> {
    let package = read_package(&args.selection.files)?;
    let target = choose(&package, &args.selection)?;
    let overrides = overrides(&args.values.params, &args.values.initials)?;
    let lowered = lower(&package, &target, &overrides)?;
    let options = command_line_options(&args.options, &lowered.options)?;
    let mut where_ = at(&args.at)?;
    let derivatives = derivatives(&args.derivatives)?;
    let (mut inputs, mut outputs) = (args.inputs.clone(), args.outputs.clone());
    let mut tolerances = SteadyStateOptions::default();
    match &lowered.study {
        Study::Linear { inputs: i, outputs: o, .. } => {
            inputs = inputs.or_else(|| (!i.is_empty()).then(|| i.clone()));
            outputs = outputs.or_else(|| (!o.is_empty()).then(|| o.clone()));
        }
        Study::SteadyState { abstol, reltol } => {
            (tolerances.abstol, tolerances.reltol) = (*abstol, *reltol);
            if args.at == "start" {
                where_ = At::Steady;
            }
        }
        Study::Transient => {}
        Study::Fmu { .. } => {
            return Err(Failure::Usage(format!(
                "`{}` is an FMUAnalysis, which exports an FMU: run `multibody fmu` on it, or linearize its model \
                 with --model NAME",
                lowered.name
            )))
        }
    }
    let json = args.out.clone().unwrap_or_else(|| PathBuf::from(format!("{}.json", lowered.name)));
    check_files(&args.selection.files, &json, args.bode.as_deref())?;
    let mechanism = assemble(&package, &target, &overrides, &lowered)?;
    for w in mechanism.warnings() {
        say!("warning: {w}");
    }
    let what = match &target {
        Target::Analysis(name) => format!("analysis {name} (model {})", lowered.model.name),
        Target::Component(name) => format!("component {name}"),
    };
    let stopped = |reason: String, time: f64| {
        let reason = lowered.with_places(package.sources(), &reason);
        say!("{}: the model cannot be simulated to t = {}: {reason}", error_word(), number(time));
        Failure::Simulation
    };
    let mut sim = Simulator::new(&mechanism, &options).map_err(|s| stopped(s.reason, s.time))?;
    let point = match where_ {
        At::Start => format!("at the start, t = {}", number(options.start)),
        At::Time(t) => {
            if t < options.start {
                return Err(Failure::Usage(format!(
                    "--at t={t}: the simulation starts at t = {}; give a later time",
                    number(options.start)
                )));
            }
            sim.step_until(t).map_err(|s| stopped(s.reason, s.time))?;
            format!("at t = {} along the simulation", number(t))
        }
        At::Steady => {
            let found = sim.steady_state(&tolerances).map_err(|e| {
                say!("{}: {}", error_word(), lowered.with_places(package.sources(), &e.to_string()));
                Failure::Simulation
            })?;
            format!("at a steady state (largest rate left {:.1e} after {} steps)", found.residual, found.iterations)
        }
    };
    say!("Linearizing {what} from {}, {point}", file_of(&package, &lowered.name));
    let lin = sim.linearize(&LinearizeOptions { inputs, outputs, derivatives }).map_err(|e| match e {
        multibody::LinearizeError::UnknownInput { .. } | multibody::LinearizeError::UnknownOutput { .. } => {
            Failure::Usage(e.to_string())
        }
        _ => {
            say!("{}: {}", error_word(), lowered.with_places(package.sources(), &e.to_string()));
            Failure::Simulation
        }
    })?;
    crate::console::answer(&summary(&lin))?;
    write_atomically(&json, |w| w.write_all(multibody_view::linearization_json(&lin).as_bytes()))?;
    say!("Wrote {}", json.display());
    if let Some(bode) = &args.bode {
        let title = format!("{}: Bode plot", lowered.name);
        multibody_view::write_bode(bode, &title, &lin, &multibody_view::BodeOptions::default())
            .map_err(|e| Failure::Io(e.to_string()))?;
        say!("Wrote {}", bode.display());
    }
    Ok(())
}

/// The result files may not overwrite a model file, nor each other.
fn check_files(inputs: &[PathBuf], json: &Path, bode: Option<&Path>) -> Result<(), Failure> {
    outputs_are_safe(inputs, &[("--out", Some(json)), ("--bode", bode)])?;
    if let Some(bode) = bode {
        if multibody_view::PlotFormat::from_path(bode).is_none() {
            return Err(Failure::Usage(format!(
                "`--bode {}`: cannot tell the plot format; name the file .png or .svg",
                bode.display()
            )));
        }
    }
    Ok(())
}

/// What the terminal shows: the coordinates, the matrices (when small),
/// the poles, and how the derivatives were taken.
fn summary(lin: &Linearization) -> String {
    let mut out = String::new();
    let list = |names: &[String]| if names.is_empty() { "none".to_string() } else { names.join(", ") };
    put!(out, "  coordinates ({}): {}", lin.state_names.len(), list(&lin.state_names));
    put!(out, "  inputs: {}", list(&lin.input_names));
    put!(out, "  outputs: {}", list(&lin.output_names));
    let largest_rate = lin.rates.iter().fold(0.0f64, |a, r| a.max(r.abs()));
    if largest_rate > 1e-9 {
        put!(out, "  not an equilibrium: the largest rate there is {largest_rate:.3e}");
    }
    if lin.state_names.len() <= 12 {
        for (name, m) in [("A", &lin.a), ("B", &lin.b), ("C", &lin.c), ("D", &lin.d)] {
            if m.is_empty() {
                continue;
            }
            put!(out, "  {name} =");
            for r in 0..m.nrows() {
                let row: Vec<String> =
                    (0..m.ncols()).map(|c| format!("{:>13}", format!("{:.6e}", m[(r, c)]))).collect();
                put!(out, "    {}", row.join(" "));
            }
        }
    } else {
        put!(out, "  (A is {0}x{0}: the matrices are in the JSON file)", lin.state_names.len());
    }
    if !lin.a.is_empty() {
        put!(out, "  poles:");
        for line in multibody_view::damping_report(lin).lines() {
            put!(out, "    {line}");
        }
    }
    for note in &lin.notes {
        put!(out, "  note: {note}");
    }
    out
}
