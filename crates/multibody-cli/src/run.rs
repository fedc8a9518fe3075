//! `multibody run`: simulate and write a CSV.

use crate::exit::Failure;
use crate::load::{assemble, choose, file_of, lower, overrides, print_diagnostics, read_package, Target};
use crate::output::{self, Budget, ResultFiles, StreamingCsv};
use crate::progress::Progress;
use crate::{OptionArgs, RunArgs};
use multibody::simulate::glob;
use multibody::{Mechanism, Method, SimulationOptions, Solution};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::Instant;

/// How many states the summary shows.
const SUMMARY_STATES: usize = 6;

pub fn run(args: &RunArgs) -> Result<(), Failure> {
    let package = read_package(&args.selection.files)?;
    let target = choose(&package, &args.selection)?;
    let overrides = overrides(&args.values.params, &args.values.initials)?;
    let mut lowered = lower(&package, &target, &overrides)?;
    if let multibody_dyad::Study::Fmu { .. } = lowered.study {
        return Err(Failure::Usage(format!(
            "`{}` is an FMUAnalysis, which exports an FMU: run `multibody fmu {}`",
            lowered.name,
            args.selection.files.iter().map(|f| f.display().to_string()).collect::<Vec<_>>().join(" ")
        )));
    }
    if lowered.study != multibody_dyad::Study::Transient {
        // A LinearAnalysis or SteadyStateAnalysis: its result is a linear model.
        return crate::linearize::linearize(&crate::LinearizeArgs {
            selection: args.selection.clone(),
            options: args.options.clone(),
            values: args.values.clone(),
            inputs: None,
            outputs: None,
            at: "start".into(),
            derivatives: "auto".into(),
            out: args.out.clone(),
            bode: args.plot.clone(),
        });
    }
    let options = command_line_options(&args.options, &lowered.options)?;
    crate::inputs::drive(&mut lowered.model, &args.inputs, &options)?;
    let out = args.out.clone().unwrap_or_else(|| PathBuf::from(format!("{}.csv", lowered.name)));
    let files = ResultFiles::new(&args.selection.files, &out, args.animate.as_deref(), args.plot.as_deref())?;
    let mechanism = assemble(&package, &target, &overrides, &lowered)?;
    for w in mechanism.warnings() {
        say!("warning: {w}");
    }
    let signals = chosen_signals(&mechanism, &args.signals)?;
    let views = args.animate.is_some() || args.plot.is_some();
    let budget = Budget::of_this_machine();
    budget.check(&options, mechanism.signals().len(), signals.len(), views, &out)?;

    let tolerance_warnings = tolerance_warnings(&args.options, &options);
    for w in &tolerance_warnings {
        say!("warning: {w}");
    }

    // Before the temporary file exists: a signal from here on keeps what was computed and removes it.
    let interrupted = on_interrupt();
    let mut csv = StreamingCsv::create(&files.csv, &mechanism, &signals, views.then_some(budget.memory))?;

    let what = match &target {
        Target::Analysis(name) => format!("analysis {name} (model {})", lowered.model.name),
        Target::Component(name) => format!("component {name} with default options"),
    };
    say!("Simulating {what} from {}", file_of(&package, &lowered.name));
    say!(
        "  {} of freedom, t = {} … {} s, {}",
        plural(mechanism.degrees_of_freedom(), "degree"),
        number(options.start),
        number(options.stop),
        method(&options)
    );

    let started = Instant::now();
    let mut progress = Progress::new(options.start, options.stop);
    let mut on_step = |t: f64| {
        progress.update(t);
        if interrupted.load(Ordering::Relaxed) {
            Err("interrupted (Ctrl-C, SIGTERM or SIGHUP)".to_string())
        } else {
            Ok(())
        }
    };
    let result = mechanism.simulate_into(&mechanism.states().start, &options, &mut csv, Some(&mut on_step));
    progress.finish();
    let elapsed = started.elapsed();
    match result {
        Ok(report) => {
            let kept = csv.finish(&out)?;
            say!(
                "  {} × {} → {} ({elapsed:.0?})",
                plural(kept.samples, "sample"),
                plural(signals.len(), "signal"),
                out.display()
            );
            if let Some(solution) = &kept.solution {
                write_views(
                    args,
                    &files,
                    false,
                    &lowered.name,
                    &mechanism,
                    solution,
                    &model_folder(&package, &lowered),
                )?;
            }
            for w in &report.warnings {
                say!("warning: {}", lowered.with_places(package.sources(), w));
            }
            print_final_states(&mechanism, &kept);
            Ok(())
        }
        Err(stopped) => {
            let partial_csv = output::partial_path(&out);
            let title = format!("the simulation stopped at t = {}: ", number(stopped.time));
            print_diagnostics(&package, &[lowered.start_failure(package.sources(), &title, &stopped.reason)]);
            let kept = csv.finish(&partial_csv)?;
            if let Some(solution) = kept.solution.as_ref().filter(|s| !s.is_empty()) {
                write_views(
                    args,
                    &files,
                    true,
                    &lowered.name,
                    &mechanism,
                    solution,
                    &model_folder(&package, &lowered),
                )?;
            }
            match kept.span {
                Some((first, last)) => say!(
                    "  wrote what was computed: {} (t = {} … {} s) × {} → {}",
                    plural(kept.samples, "sample"),
                    number(first),
                    number(last),
                    plural(signals.len(), "signal"),
                    partial_csv.display()
                ),
                None => say!("  nothing was computed; wrote the header to {}", partial_csv.display()),
            }
            if !tolerance_warnings.is_empty() && !stopped.by_caller {
                say!("  the tolerances warned about above may be why; rerun with the defaults (leave out --abstol and --reltol)");
            }
            if stopped.by_caller && interrupted.load(Ordering::Relaxed) {
                Err(Failure::Interrupted)
            } else {
                Err(Failure::Simulation)
            }
        }
    }
}

/// The analysis's options with the command line's on top, checked before
/// any work: a bad value names the option that gave it.
pub fn command_line_options(args: &OptionArgs, analysis: &SimulationOptions) -> Result<SimulationOptions, Failure> {
    args.overrides().over(analysis).map_err(|e| Failure::Usage(e.as_command_option()))
}

/// The warnings of valid options that spoil the result (a loose `reltol`,
/// an `abstol` below rounding), naming the command-line option that gave
/// the value.
pub fn tolerance_warnings(args: &OptionArgs, options: &SimulationOptions) -> Vec<String> {
    options
        .warnings()
        .into_iter()
        .map(|(option, message)| {
            let given = match option {
                "reltol" => args.reltol,
                "abstol" => args.abstol,
                _ => None,
            };
            match given {
                Some(x) => format!("--{option} {}: {message}", number(x)),
                None => message,
            }
        })
        .collect()
}

/// A flag that Ctrl-C raises, and so do SIGTERM and SIGHUP (a closed
/// terminal, `kill`, a job scheduler's time limit): the run stops after its
/// current step and keeps what it computed, and no temporary file is left.
/// A second signal ends the command at once.
pub fn on_interrupt() -> Arc<AtomicBool> {
    let flag = Arc::new(AtomicBool::new(false));
    let raised = flag.clone();
    let installed = ctrlc::set_handler(move || {
        if raised.swap(true, Ordering::Relaxed) {
            std::process::exit(crate::exit::INTERRUPTED as i32);
        }
    });
    if let Err(e) = installed {
        say!("warning: Ctrl-C will end the run without keeping its results ({e})");
    }
    flag
}

/// The signals the patterns select (all without patterns); a pattern that
/// selects nothing is an error, caught before simulating.
pub fn chosen_signals(mechanism: &Mechanism, patterns: &[String]) -> Result<Vec<String>, Failure> {
    let names: Vec<String> = mechanism.signals().into_iter().map(|s| s.name).collect();
    for p in patterns {
        if !names.iter().any(|n| glob(p, n)) {
            let close = multibody::closest(p, names.iter().map(String::as_str));
            let hint = if close.is_empty() {
                "`multibody check` lists the states; signals are named like `body.r_0[1]`".to_string()
            } else {
                format!("did you mean {}?", close.join(", "))
            };
            return Err(Failure::Usage(format!("the pattern `{p}` matches no signal; {hint}")));
        }
    }
    Ok(names.into_iter().filter(|n| patterns.is_empty() || patterns.iter().any(|p| glob(p, n))).collect())
}

/// The folder of the model file being run (the one that holds the analysis
/// or component), from which relative mesh paths are read.
fn model_folder(package: &multibody_dyad::Package, lowered: &multibody_dyad::Lowered) -> PathBuf {
    let file = file_of(package, &lowered.name);
    Path::new(&file).parent().map(Path::to_path_buf).unwrap_or_default()
}

/// The animation page and the plot, when asked for (under their partial
/// names when the run stopped part way).
fn write_views(
    args: &RunArgs,
    files: &ResultFiles,
    partial: bool,
    title: &str,
    mechanism: &Mechanism,
    solution: &Solution,
    model_folder: &Path,
) -> Result<(), Failure> {
    let view_error = |e: multibody_view::ViewError| match e {
        io @ multibody_view::ViewError::Io { .. } => Failure::Io(io.to_string()),
        other => Failure::Usage(other.to_string()),
    };
    let place = |path: &Path| if partial { output::partial_path(path) } else { path.to_path_buf() };
    if let Some(path) = &files.animate {
        let path = place(path);
        let options = multibody_view::AnimationOptions {
            signals: args.signals.clone(),
            mesh_folder: Some(model_folder.to_path_buf()),
            up: multibody_view::AnimationOptions::up_of(mechanism),
            ..Default::default()
        };
        let page =
            multibody_view::animation_html(title, &mechanism.shapes(), solution, &options).map_err(view_error)?;
        for note in &page.summary.left_out {
            say!("warning: animation: {note}");
        }
        output::write_atomically(&path, |w| w.write_all(page.html.as_bytes()))?;
        say!(
            "  animation: {} frames of {} shapes → {} ({})",
            page.summary.frames,
            page.summary.shapes,
            path.display(),
            output::bytes(page.summary.bytes as f64)
        );
    }
    if let Some(path) = &files.plot {
        let path = place(path);
        let options = multibody_view::PlotOptions { signals: args.signals.clone(), ..Default::default() };
        let (image, summary) = match multibody_view::PlotFormat::from_path(&path) {
            Some(multibody_view::PlotFormat::Svg) => {
                multibody_view::plot_svg(title, solution, &options).map(|(svg, summary)| (svg.into_bytes(), summary))
            }
            _ => multibody_view::plot_png(title, solution, &options),
        }
        .map_err(view_error)?;
        output::write_atomically(&path, |w| w.write_all(&image))?;
        let signals: usize = summary.panels.iter().map(|(_, s)| s.len()).sum();
        say!("  plot: {} in {} → {}", plural(signals, "signal"), plural(summary.panels.len(), "panel"), path.display());
    }
    Ok(())
}

/// The final values of the first few states, a vector per line.
fn print_final_states(mechanism: &Mechanism, kept: &output::Kept) {
    let Some((_, t)) = kept.span else { return };
    let last = |name: &str| kept.last_row.iter().find(|(n, _)| n == name).map(|(_, x)| *x);
    // Group `body.r_0[1]`, `body.r_0[2]`, ... into `body.r_0`.
    let mut groups: Vec<(String, Vec<f64>)> = Vec::new();
    for name in &mechanism.states().names {
        let Some(value) = last(name) else { continue };
        // Only a trailing index groups: `links[2].joint.phi` is a name of its own.
        let base = match name.strip_suffix(']').and_then(|n| n.rsplit_once('[')) {
            Some((b, _)) => b,
            None => name.as_str(),
        };
        match groups.last_mut() {
            Some((b, values)) if b == base && base != name => values.push(value),
            _ => groups.push((base.to_string(), vec![value])),
        }
    }
    if groups.is_empty() {
        return;
    }
    say!("  final state at t = {}:", number(t));
    for (name, values) in groups.iter().take(SUMMARY_STATES) {
        let shown: Vec<String> = values.iter().map(|x| number(*x)).collect();
        match shown.as_slice() {
            [one] => say!("    {name} = {one}"),
            many => say!("    {name} = [{}]", many.join(", ")),
        }
    }
    if groups.len() > SUMMARY_STATES {
        say!("    ... and {} more in the CSV", groups.len() - SUMMARY_STATES);
    }
}

fn method(options: &SimulationOptions) -> String {
    match options.method {
        Method::DormandPrince45 => format!(
            "adaptive Dormand-Prince 4(5), abstol {}, reltol {}",
            number(options.abstol),
            number(options.reltol)
        ),
        Method::Rk4 { dt } => format!("fixed-step RK4, dt = {} s", number(dt)),
        Method::Rodas4 => format!(
            "implicit Rodas4 (for stiff models), abstol {}, reltol {}",
            number(options.abstol),
            number(options.reltol)
        ),
        Method::Ros34Pw2 => format!(
            "implicit ROS34PW2 (for stiff models with many states), abstol {}, reltol {}",
            number(options.abstol),
            number(options.reltol)
        ),
    }
}

/// "1 signal", "3 signals".
pub fn plural(n: usize, word: &str) -> String {
    if n == 1 {
        format!("1 {word}")
    } else {
        format!("{n} {word}s")
    }
}

pub use multibody_dyad::study::number;

#[cfg(test)]
mod tests {
    use super::number;

    #[test]
    fn numbers_read_well() {
        assert_eq!(number(5.0), "5");
        assert_eq!(number(0.001), "0.001");
        assert_eq!(number(-1.23456789), "-1.234568");
        assert_eq!(number(0.000123456789), "0.000123457");
        assert_eq!(number(1e-6), "1e-6");
        assert_eq!(number(-4.657091e-17), "-4.65709e-17");
        assert_eq!(number(0.0), "0");
    }
}
