//! `multibody run`: simulate and write a CSV.

use crate::exit::{error_word, Failure};
use crate::load::{choose, file_of, lower, print_diagnostics, read_package, Target};
use crate::progress::Progress;
use crate::RunArgs;
use multibody::simulate::glob;
use multibody::{Mechanism, Method, SimulationOptions, Solution};
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};
use std::time::Instant;

/// How many states the summary shows.
const SUMMARY_STATES: usize = 6;

pub fn run(args: &RunArgs) -> Result<(), Failure> {
    let package = read_package(&args.selection.files)?;
    let target = choose(&package, &args.selection)?;
    let lowered = lower(&package, &target)?;
    let mut options = lowered.options.clone();
    let overrides = [
        (args.stop, &mut options.stop),
        (args.saveat, &mut options.saveat),
        (args.abstol, &mut options.abstol),
        (args.reltol, &mut options.reltol),
    ];
    for (given, field) in overrides {
        if let Some(x) = given {
            *field = x;
        }
    }
    if let (Some(saveat), Method::Rk4 { dt }) = (args.saveat, &mut options.method) {
        if saveat > 0.0 {
            *dt = saveat;
        }
    }
    let mechanism = lowered.assemble().map_err(|d| {
        print_diagnostics(&package, &[d]);
        Failure::Model
    })?;
    for w in mechanism.warnings() {
        eprintln!("warning: {w}");
    }
    let signals = chosen_signals(&mechanism, &args.signals)?;
    let out = args.out.clone().unwrap_or_else(|| PathBuf::from(format!("{}.csv", lowered.name)));
    let outputs =
        [("--out", Some(out.as_path())), ("--animate", args.animate.as_deref()), ("--plot", args.plot.as_deref())];
    outputs_are_safe(&args.selection.files, &outputs)?;

    let what = match &target {
        Target::Analysis(name) => format!("analysis {name} (model {})", lowered.model.name),
        Target::Component(name) => format!("component {name} with default options"),
    };
    eprintln!("Simulating {what} from {}", file_of(&package, &lowered.name));
    eprintln!(
        "  {} of freedom, t = {} … {} s, {}",
        plural(mechanism.degrees_of_freedom(), "degree"),
        number(options.start),
        number(options.stop),
        method(&options)
    );

    let started = Instant::now();
    let mut progress = Progress::new(options.start, options.stop);
    let mut on_step = |t: f64| progress.update(t);
    let result = mechanism.simulate_from(&mechanism.states().start, &options, Some(&mut on_step));
    progress.finish();
    let elapsed = started.elapsed();
    match result {
        Ok(solution) => {
            write_csv(&solution, &signals, &out)?;
            let (samples, columns) = (plural(solution.len(), "sample"), plural(signals.len(), "signal"));
            eprintln!("  {samples} × {columns} → {} ({elapsed:.0?})", out.display());
            write_views(args, &lowered.name, &mechanism, &solution)?;
            print_final_states(&mechanism, &solution);
            Ok(())
        }
        Err(e) => {
            eprintln!("{}: the simulation stopped at t = {}: {}", error_word(), number(e.time), e.reason);
            let partial = &e.partial;
            write_csv(partial, &signals, &out)?;
            if !partial.is_empty() {
                write_views(args, &lowered.name, &mechanism, partial)?;
            }
            match (partial.time().first(), partial.time().last()) {
                (Some(first), Some(last)) => eprintln!(
                    "  wrote what was computed: {} (t = {} … {} s) × {} → {}",
                    plural(partial.len(), "sample"),
                    number(*first),
                    number(*last),
                    plural(signals.len(), "signal"),
                    out.display()
                ),
                _ => eprintln!("  nothing was computed; wrote the header to {}", out.display()),
            }
            Err(Failure::Simulation)
        }
    }
}

/// The signals the patterns select (all without patterns); a pattern that
/// selects nothing is an error, caught before simulating.
/// Refuses, before anything is computed, an output that would write over
/// one of the model files read or over another output of the same run.
fn outputs_are_safe(inputs: &[PathBuf], outputs: &[(&str, Option<&Path>)]) -> Result<(), Failure> {
    let mut read = Vec::new();
    for input in inputs {
        match std::fs::read_dir(input) {
            Ok(entries) => {
                let models = entries.flatten().map(|e| e.path()).filter(|p| p.extension().is_some_and(|e| e == "dyad"));
                read.extend(models)
            }
            Err(_) => read.push(input.clone()),
        }
    }
    let mut written: Vec<(&str, PathBuf)> = Vec::new();
    for &(option, path) in outputs {
        let Some(path) = path else { continue };
        let key = comparable(path);
        if let Some(input) = read.iter().find(|i| comparable(i) == key) {
            return Err(Failure::Usage(format!(
                "`{option} {}` would write over the model file {}; choose another path for the output",
                path.display(),
                input.display()
            )));
        }
        if let Some((other, _)) = written.iter().find(|(_, w)| *w == key) {
            return Err(Failure::Usage(format!(
                "`{other}` and `{option}` both name {}; give each output a path of its own",
                path.display()
            )));
        }
        written.push((option, key));
    }
    Ok(())
}

/// The absolute form of a path, through links, for comparing files that
/// may not exist yet (their folder is resolved).
fn comparable(path: &Path) -> PathBuf {
    if let Ok(p) = path.canonicalize() {
        return p;
    }
    let folder = match path.parent() {
        Some(f) if !f.as_os_str().is_empty() => f.to_path_buf(),
        _ => PathBuf::from("."),
    };
    let folder = folder.canonicalize().unwrap_or(folder);
    path.file_name().map_or(folder.clone(), |name| folder.join(name))
}

fn chosen_signals(mechanism: &Mechanism, patterns: &[String]) -> Result<Vec<String>, Failure> {
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

/// Writes the CSV through a temporary file, so that a failed write leaves
/// no half file behind under the final name.
fn write_csv(solution: &Solution, signals: &[String], out: &Path) -> Result<(), Failure> {
    let temporary = PathBuf::from(format!("{}.tmp", out.display()));
    let io = |e: std::io::Error| Failure::Io(format!("cannot write {}: {e}", out.display()));
    let file = std::fs::File::create(&temporary).map_err(io)?;
    let mut writer = BufWriter::new(file);
    let names: Vec<&str> = signals.iter().map(String::as_str).collect();
    let written = solution.write_csv(&mut writer, &names).and_then(|_| writer.flush());
    if let Err(e) = written {
        let _ = std::fs::remove_file(&temporary);
        return Err(io(e));
    }
    drop(writer);
    std::fs::rename(&temporary, out).map_err(io)
}

/// The animation page and the plot, when asked for.
fn write_views(args: &RunArgs, title: &str, mechanism: &Mechanism, solution: &Solution) -> Result<(), Failure> {
    let view_error = |e: multibody_view::ViewError| match e {
        io @ multibody_view::ViewError::Io { .. } => Failure::Io(io.to_string()),
        other => Failure::Usage(other.to_string()),
    };
    if let Some(path) = &args.animate {
        let options = multibody_view::AnimationOptions { signals: args.signals.clone(), ..Default::default() };
        let summary = multibody_view::write_animation(path, title, &mechanism.shapes(), solution, &options)
            .map_err(view_error)?;
        eprintln!(
            "  animation: {} frames of {} shapes → {} ({})",
            summary.frames,
            summary.shapes,
            path.display(),
            size(summary.bytes)
        );
    }
    if let Some(path) = &args.plot {
        let options = multibody_view::PlotOptions { signals: args.signals.clone(), ..Default::default() };
        let summary = multibody_view::write_plot(path, title, solution, &options).map_err(view_error)?;
        let signals: usize = summary.panels.iter().map(|(_, s)| s.len()).sum();
        eprintln!(
            "  plot: {} in {} → {}",
            plural(signals, "signal"),
            plural(summary.panels.len(), "panel"),
            path.display()
        );
    }
    Ok(())
}

/// "88.6 kB", "2.4 MB".
fn size(bytes: usize) -> String {
    if bytes < 1_000_000 {
        format!("{:.1} kB", bytes as f64 / 1e3)
    } else {
        format!("{:.1} MB", bytes as f64 / 1e6)
    }
}

/// The final values of the first few states, a vector per line.
fn print_final_states(mechanism: &Mechanism, solution: &Solution) {
    let Some(t) = solution.time().last() else { return };
    // Group `body.r_0[1]`, `body.r_0[2]`, ... into `body.r_0`.
    let mut groups: Vec<(String, Vec<f64>)> = Vec::new();
    for name in &mechanism.states().names {
        let Some(value) = solution.last(name) else { continue };
        let base = name.split_once('[').map_or(name.as_str(), |(b, _)| b);
        match groups.last_mut() {
            Some((b, values)) if b == base && name.contains('[') => values.push(value),
            _ => groups.push((base.to_string(), vec![value])),
        }
    }
    if groups.is_empty() {
        return;
    }
    eprintln!("  final state at t = {}:", number(*t));
    for (name, values) in groups.iter().take(SUMMARY_STATES) {
        let shown: Vec<String> = values.iter().map(|x| number(*x)).collect();
        match shown.as_slice() {
            [one] => eprintln!("    {name} = {one}"),
            many => eprintln!("    {name} = [{}]", many.join(", ")),
        }
    }
    if groups.len() > SUMMARY_STATES {
        eprintln!("    ... and {} more in the CSV", groups.len() - SUMMARY_STATES);
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
        #[allow(unreachable_patterns)]
        _ => "the engine's method".into(),
    }
}

/// "1 signal", "3 signals".
fn plural(n: usize, word: &str) -> String {
    if n == 1 {
        format!("1 {word}")
    } else {
        format!("{n} {word}s")
    }
}

/// A number for people: up to 6 significant digits.
pub fn number(x: f64) -> String {
    if x == 0.0 || x.abs() >= 1e-4 && x.abs() < 1e6 {
        let s = format!("{x:.6}");
        let s = s.trim_end_matches('0').trim_end_matches('.');
        // Keep 6 significant digits for numbers below 1.
        if x.abs() < 1.0 && x != 0.0 {
            let digits = (-x.abs().log10().floor()) as usize + 5;
            let s = format!("{x:.digits$}");
            return s.trim_end_matches('0').trim_end_matches('.').to_string();
        }
        if s == "-0" {
            "0".into()
        } else {
            s.to_string()
        }
    } else {
        // Scientific, without trailing zeros in the mantissa: 1e-6, 3.98600e14 -> 3.986e14.
        let s = format!("{x:.5e}");
        match s.split_once('e') {
            Some((mantissa, exponent)) if mantissa.contains('.') => {
                format!("{}e{exponent}", mantissa.trim_end_matches('0').trim_end_matches('.'))
            }
            _ => s,
        }
    }
}

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
