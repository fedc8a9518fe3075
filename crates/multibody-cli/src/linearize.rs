//! `multibody linearize`, and the LinearAnalysis and SteadyStateAnalysis
//! of model files: a linear model (A, B, C, D with names) at the start, at
//! a steady state or at a time along a simulation; its poles; a Bode plot.

use crate::exit::{error_word, Failure};
use crate::load::{assemble, choose, file_of, lower, overrides, read_package, Target};
use crate::output::{outputs_are_safe, write_atomically};
use crate::run::{command_line_options, number};
use crate::LinearizeArgs;
use multibody::{Derivatives, Linearization, LinearizeOptions, Simulator, SteadyStateOptions};
use multibody_dyad::study::{bytes, count};
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
            let mut reach = Reach::new(&args.at, t, &options, mechanism.signals().len())?;
            let mut progress = |now: f64| reach.step(now);
            sim.step_until_with(t, Some(&mut progress)).map_err(|s| match reach.refused.take() {
                Some(message) => Failure::Usage(message),
                None => stopped(s.reason, s.time),
            })?;
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

/// Steps after which the pace of a simulation with `saveat = 0` tells
/// whether `--at` is within reach.
const PACE_STEPS: f64 = 1000.0;

/// Whether the time of `--at t=T` can be reached. The simulation to it
/// keeps every signal in memory on the output grid (every integrator step
/// when `saveat = 0`), as a `run --stop T` with views does; it is refused
/// as `run` refuses such a stop: before any work when the grid's samples
/// would pass the memory budget, and with `saveat = 0`, once the steps
/// taken reach it or their pace says they would by far (`--at t=1e300`
/// simulated towards 1e300 s, filling memory).
struct Reach {
    /// `t=T` as given.
    given: String,
    at: f64,
    start: f64,
    /// The most steps whose samples fit the budget (`saveat = 0`); `None`
    /// when the grid was checked.
    most_steps: Option<f64>,
    steps: f64,
    signals: usize,
    budget: f64,
    /// Why the simulation was stopped, once it was.
    refused: Option<String>,
}

impl Reach {
    fn new(given: &str, at: f64, options: &multibody::SimulationOptions, signals: usize) -> Result<Self, Failure> {
        let budget = multibody_dyad::study::memory_budget();
        let row = (signals + 1) as f64 * 8.0;
        let to_at = multibody::SimulationOptions { stop: at, ..options.clone() };
        let most_steps = match multibody_dyad::study::grid_samples(&to_at) {
            Some(samples) if samples * row > budget => {
                return Err(Failure::Usage(format!(
                    "--at {given}: the simulation to t = {} keeps every signal every {} s, {} samples × {signals} \
                     signals: {} in memory, more than the {} this command may use (half the memory available); \
                     give an earlier time (the analysis stops at t = {} s), or a longer --saveat",
                    number(at),
                    number(options.saveat),
                    count(samples),
                    bytes(samples * row),
                    bytes(budget),
                    number(options.stop)
                )))
            }
            Some(_) => None,
            None => Some((budget / row).floor().max(1.0)),
        };
        Ok(Self {
            given: given.to_string(),
            at,
            start: options.start,
            most_steps,
            steps: 0.0,
            signals,
            budget,
            refused: None,
        })
    }

    /// Counts a step that reached `now`; an error stops the simulation.
    fn step(&mut self, now: f64) -> Result<(), String> {
        let Some(most) = self.most_steps else { return Ok(()) };
        self.steps += 1.0;
        let done = (now - self.start) / (self.at - self.start);
        let needed = if done > 0.0 { self.steps / done } else { f64::INFINITY };
        let out_of_reach = self.steps >= most || (self.steps >= PACE_STEPS && needed > 100.0 * most);
        if !out_of_reach {
            return Ok(());
        }
        let row = (self.signals + 1) as f64 * 8.0;
        self.refused = Some(format!(
            "--at {}: the simulation keeps every signal at every step (saveat = 0), and after {} steps it \
             has reached t = {} s: at that pace t = {} takes about {} steps, {} in memory, more than the {} \
             this command may use (half the memory available); give an earlier time, or a --saveat",
            self.given,
            count(self.steps),
            number(now),
            number(self.at),
            count(needed),
            bytes(needed * row),
            bytes(self.budget)
        ));
        Err("out of reach".into())
    }
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
