//! `multibody sweep`: one model over a grid of parameter values, the runs
//! spread over every core, into one long table.
//!
//! The files are read and parsed once; each run lowers the model with its
//! values (microseconds), assembles and simulates it on its own thread. A
//! run that fails is reported with its values and leaves the others.

use crate::exit::{error_word, Failure};
use crate::load::{assignment, choose, file_of, lower, read_package};
use crate::output::write_table_streaming;
use crate::run::{chosen_signals, command_line_options, number, plural};
use crate::SweepArgs;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use multibody::SimulationOptions;
use multibody_dyad::{Override, RunError, Samples, Target};
use rayon::prelude::*;
use std::io::IsTerminal;
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

/// More runs than this is most likely a mistyped range.
const MAX_RUNS: usize = 1_000_000;

pub fn sweep(args: &SweepArgs) -> Result<(), Failure> {
    let package = read_package(&args.selection.files)?;
    let target = choose(&package, &args.selection)?;
    let axes = axes(&args.params, &args.initials)?;
    let sets = grid(&axes)?;
    // The first set that assembles gives the signals and checks the options;
    // when none does, the first set's errors are shown (a misspelt name).
    let probe = sets.iter().find_map(|set| {
        let lowered = package.lower_target(&target, set).ok()?;
        let mechanism = lowered.assemble().ok()?;
        Some((lowered, mechanism))
    });
    let Some((first, mechanism)) = probe else {
        let lowered = lower(&package, &target, &sets[0])?;
        let d = lowered.assemble().err().into_iter().collect::<Vec<_>>();
        crate::load::print_diagnostics(&package, &d);
        return Err(Failure::Model);
    };
    // Bad options are refused once, before the runs.
    let options = command_line_options(&args.options, &first.options)?;
    for w in crate::run::tolerance_warnings(&args.options, &options) {
        say!("warning: {w}");
    }
    let patterns = if args.signals.is_empty() { mechanism.states().names.clone() } else { args.signals.clone() };
    let signals = chosen_signals(&mechanism, &patterns)?;
    let out = args.out.clone().unwrap_or_else(|| PathBuf::from(format!("{}_sweep.csv", first.name)));
    let inputs: Vec<PathBuf> = args.selection.files.clone();
    crate::output::ResultFiles::new(&inputs, &out, None, None)?;
    drop(mechanism);

    let jobs = multibody_dyad::study::threads_for(sets.len(), args.jobs);
    say!(
        "Sweeping {} from {}: {} × {}, on {}",
        first.name,
        file_of(&package, &first.name),
        plural(sets.len(), "run"),
        plural(signals.len(), "signal"),
        plural(jobs, "thread")
    );
    if let Some(asked) = args.jobs.filter(|&asked| asked > jobs) {
        say!("  (--jobs {asked}: more threads than runs or cores would only share them)");
    }
    let bar = progress_bar(sets.len());
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(jobs)
        .build()
        .map_err(|e| Failure::Usage(format!("--jobs {jobs}: {e}")))?;
    // Ctrl-C (or SIGTERM, SIGHUP): the runs under way finish, no new one starts, and the finished
    // ones are kept.
    let interrupted = crate::run::on_interrupt();
    let started = Instant::now();
    let keys: Vec<&str> = std::iter::once("run").chain(axes.iter().map(|a| a.name.as_str())).collect();
    let signal_names: Vec<&str> = signals.iter().map(String::as_str).collect();
    // The runs go in batches, each into the table in order before the next
    // starts: memory holds a batch, not the sweep. A CSV table's rows are
    // rendered by the threads that computed them; the table only copies
    // them in.
    let batch = batch_size(&options, keys.len() + 1 + signals.len(), jobs);
    let (mut finished, mut failed, mut samples) = (0, 0, 0);
    let out = write_table_streaming(&out, &keys, &signal_names, |table| {
        let render = table.takes_rendered_rows();
        for (number, chunk) in sets.chunks(batch).enumerate() {
            let first = number * batch;
            let runs: Vec<Option<Result<Finished, String>>> = pool.install(|| {
                chunk
                    .par_iter()
                    .enumerate()
                    .map(|(j, set)| {
                        if interrupted.load(Ordering::Relaxed) {
                            return None;
                        }
                        let run = simulate(&package, &target, set, &args.options, &signals, &interrupted)?;
                        bar.inc(1);
                        Some(run.map(|run| {
                            if render {
                                let rows = csv_rows(first + j, set, &run, signals.len());
                                Finished::Rendered { samples: run.time.len(), rows }
                            } else {
                                Finished::Values(run)
                            }
                        }))
                    })
                    .collect()
            });
            for (j, (set, run)) in chunk.iter().zip(runs).enumerate() {
                let k = first + j;
                match run {
                    Some(Ok(Finished::Rendered { samples: count, rows })) => {
                        finished += 1;
                        samples += count;
                        table.rendered_rows(&rows)?;
                    }
                    Some(Ok(Finished::Values(run))) => {
                        finished += 1;
                        samples += run.time.len();
                        let key_values = key_values(k, set);
                        for (t, row) in run.time.iter().zip(run.values.chunks_exact(signals.len().max(1))) {
                            table.row(&key_values, *t, row)?;
                        }
                    }
                    Some(Err(reason)) => {
                        finished += 1;
                        failed += 1;
                        bar.suspend(|| say!("{}: run {} ({}): {reason}", error_word(), k + 1, describe(set)));
                    }
                    None => {}
                }
            }
            if interrupted.load(Ordering::Relaxed) {
                break;
            }
        }
        // Complete unless a signal left runs unfinished.
        Ok(finished == sets.len())
    })?;
    bar.finish_and_clear();
    let elapsed = started.elapsed();
    let stopped = finished < sets.len();
    if stopped {
        say!(
            "{}: interrupted (Ctrl-C, SIGTERM or SIGHUP): {} of {} finished (the others were stopped or not \
             started); kept the finished ones ({samples} samples in all, {elapsed:.1?}) → {}",
            error_word(),
            plural(finished, "run"),
            sets.len(),
            out.display()
        );
        return Err(Failure::Interrupted);
    }
    say!(
        "  {} of {} ran ({} samples in all, {elapsed:.1?}) → {}",
        plural(sets.len() - failed, "run"),
        sets.len(),
        samples,
        out.display()
    );
    if failed > 0 {
        say!("  {} failed (above); the table holds the others", plural(failed, "run"));
        return Err(Failure::Simulation);
    }
    Ok(())
}

/// A run that finished: its rows rendered for a CSV table, or its values.
enum Finished {
    Rendered { samples: usize, rows: Vec<u8> },
    Values(Samples),
}

/// About this many values of samples are held per batch (16 MB, and
/// about twice that as CSV text).
const BATCH_VALUES: f64 = (1 << 21) as f64;

/// How many runs go in one batch: enough that the threads seldom wait for
/// each other and for the table between batches (with four runs per
/// thread, short runs spent about half their time waiting), few enough
/// that a batch's samples stay near [`BATCH_VALUES`] (long runs go one
/// per thread).
fn batch_size(options: &SimulationOptions, columns: usize, jobs: usize) -> usize {
    // Without an output grid (saveat = 0) a run's samples are not known:
    // as if a thousand.
    let per_run = multibody_dyad::study::grid_samples(options).unwrap_or(1000.0) * columns.max(1) as f64;
    ((BATCH_VALUES / per_run) as usize).clamp(jobs, 256 * jobs)
}

/// The run's number (from 1) and its values: the first columns of its rows.
fn key_values(k: usize, set: &[Override]) -> Vec<f64> {
    std::iter::once((k + 1) as f64).chain(set.iter().map(number_of)).collect()
}

/// Run `k`'s rows as the CSV table writes them.
fn csv_rows(k: usize, set: &[Override], run: &Samples, width: usize) -> Vec<u8> {
    let keys = key_values(k, set);
    let mut rows = Vec::with_capacity(run.time.len() * 20 * (keys.len() + 1 + width));
    for (t, row) in run.time.iter().zip(run.values.chunks_exact(width.max(1))) {
        multibody::simulate::csv_row(&mut rows, &keys, *t, row).expect("writing into memory does not fail");
    }
    rows
}

/// One parameter (or start value) and its values.
struct Axis {
    name: String,
    initial: bool,
    values: Vec<f64>,
}

fn axes(params: &[String], initials: &[String]) -> Result<Vec<Axis>, Failure> {
    let mut out = Vec::new();
    for (option, given, initial) in [("--param", params, false), ("--initial", initials, true)] {
        for text in given {
            let (name, values) = assignment(option, text)?;
            let values = parse_values(values).map_err(|why| Failure::Usage(format!("`{option} {text}`: {why}")))?;
            out.push(Axis { name: name.to_string(), initial, values });
        }
    }
    Ok(out)
}

/// A list of values and ranges: `1,2,5`, `1:0.5:3` (START:STEP:STOP, STOP
/// included when on the grid), `-1,1:1:2`, or one value.
fn parse_values(text: &str) -> Result<Vec<f64>, String> {
    let mut values = Vec::new();
    for item in text.split(',') {
        values.extend(parse_item(item)?);
        if values.len() > MAX_RUNS {
            return Err(format!("more than {MAX_RUNS} values"));
        }
    }
    Ok(values)
}

fn parse_item(item: &str) -> Result<Vec<f64>, String> {
    let number = |s: &str| s.trim().parse::<f64>().map_err(|_| format!("`{}` is not a number", s.trim()));
    match item.split(':').collect::<Vec<_>>().as_slice() {
        [one] => Ok(vec![number(one)?]),
        [start, step, stop] => {
            let (start, step, stop) = (number(start)?, number(step)?, number(stop)?);
            if !(step.is_finite() && step != 0.0 && start.is_finite() && stop.is_finite()) {
                return Err("write a range as START:STEP:STOP with a non-zero step".into());
            }
            let count = ((stop - start) / step + 1e-9).floor();
            if count < 0.0 {
                return Err(format!("the step {step} never goes from {start} to {stop}"));
            }
            if count >= MAX_RUNS as f64 {
                return Err(format!("{count} values: more than a sweep can run"));
            }
            Ok((0..=count as usize).map(|k| start + k as f64 * step).collect())
        }
        _ => Err("write values as a list (1,2,5), a range START:STEP:STOP (1:0.5:3), or one value".into()),
    }
}

/// Every combination of the axes' values, the first axis slowest.
fn grid(axes: &[Axis]) -> Result<Vec<Vec<Override>>, Failure> {
    let total = axes.iter().try_fold(1usize, |n, a| n.checked_mul(a.values.len()).filter(|&n| n <= MAX_RUNS));
    let Some(total) = total else {
        return Err(Failure::Usage(format!("the grid has more than {MAX_RUNS} runs; sweep fewer values")));
    };
    let mut sets = Vec::with_capacity(total);
    for mut k in 0..total {
        let mut set = vec![Override::parameter("", 0.0); axes.len()];
        for (slot, axis) in set.iter_mut().zip(axes).rev() {
            let value = axis.values[k % axis.values.len()];
            k /= axis.values.len();
            *slot = if axis.initial {
                Override::initial(axis.name.clone(), value)
            } else {
                Override::parameter(axis.name.clone(), value)
            };
        }
        sets.push(set);
    }
    Ok(sets)
}

/// One run of the sweep, on the calling thread; `None` when a signal
/// stopped it part way (it did not finish, and is not kept).
fn simulate(
    package: &multibody_dyad::Package,
    target: &Target,
    set: &[Override],
    given: &crate::OptionArgs,
    signals: &[String],
    interrupted: &AtomicBool,
) -> Option<Result<Samples, String>> {
    let options = |analysis: &SimulationOptions| command_line_options(given, analysis).map_err(|f| f.message());
    let stop = || interrupted.load(Ordering::Relaxed);
    match package.run_until(target, set, options, signals, Some(&stop)) {
        Ok(samples) => Some(Ok(samples)),
        Err(RunError::Stopped { .. }) if interrupted.load(Ordering::Relaxed) => None,
        Err(RunError::Model(d)) => Some(Err(d.message)),
        Err(RunError::Options(why)) => Some(Err(why)),
        Err(RunError::Stopped { time, reason, .. }) => Some(Err(format!("stopped at t = {}: {reason}", number(time)))),
    }
}

fn describe(set: &[Override]) -> String {
    set.iter().map(|o| format!("{} = {}", o.path, number_of(o))).collect::<Vec<_>>().join(", ")
}

/// The value of a sweep's override (always a number).
fn number_of(o: &Override) -> f64 {
    match o.value {
        multibody_dyad::eval::Val::Number(x) => x,
        _ => f64::NAN,
    }
}

fn progress_bar(runs: usize) -> ProgressBar {
    let target =
        if std::io::stderr().is_terminal() { ProgressDrawTarget::stderr() } else { ProgressDrawTarget::hidden() };
    let bar = ProgressBar::with_draw_target(Some(runs as u64), target);
    if let Ok(style) =
        ProgressStyle::with_template("  {bar:40.cyan/blue} {pos}/{len} runs  ({elapsed}, about {eta} left)")
    {
        bar.set_style(style);
    }
    bar
}
