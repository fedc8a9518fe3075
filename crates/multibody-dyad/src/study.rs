//! One model file run many times: with other parameters and start values,
//! other options, and only the signals wanted. What the command's `sweep`
//! and the Python package share.

use crate::diagnostics::did_you_mean;
use crate::{DefinitionKind, Diagnostic, Lowered, Override, Package};
use multibody::{SampleSink, SimulationOptions};

/// What of the package to simulate.
#[derive(Clone, Debug, PartialEq)]
pub enum Target {
    Analysis(String),
    Component(String),
}

impl Package {
    /// What to run: the analysis or component named, else the one analysis
    /// of the files, else their one top component. The message of a
    /// failure says what the files offer (`--analysis NAME`, `--model
    /// NAME`, as the command's options are called).
    pub fn choose_target(&self, analysis: Option<&str>, model: Option<&str>) -> Result<Target, String> {
        let definitions = self.definitions();
        let analyses: Vec<&str> =
            definitions.iter().filter(|d| d.kind == DefinitionKind::Analysis).map(|d| d.name.as_str()).collect();
        let components: Vec<&str> = definitions
            .iter()
            .filter(|d| matches!(d.kind, DefinitionKind::Component(_)))
            .map(|d| d.name.as_str())
            .collect();
        let missing = |what: &str, name: &str, names: &[&str]| {
            let mut message = format!("there is no {what} `{name}` in the files");
            if let Some(s) = did_you_mean(name, names.iter().copied()) {
                message.push_str(&format!("; {s}"));
            } else if !names.is_empty() {
                message.push_str(&format!(" (they define: {})", names.join(", ")));
            }
            message
        };
        if let Some(name) = analysis {
            return if analyses.contains(&name) {
                Ok(Target::Analysis(name.to_string()))
            } else {
                Err(missing("analysis", name, &analyses))
            };
        }
        if let Some(name) = model {
            return if components.contains(&name) {
                Ok(Target::Component(name.to_string()))
            } else {
                Err(missing("component", name, &components))
            };
        }
        // Asked to choose among names of which one is defined more than once:
        // no choice by name can tell them apart.
        if let Some(message) = self.defined_more_than_once() {
            return Err(message);
        }
        match analyses.as_slice() {
            [one] => return Ok(Target::Analysis(one.to_string())),
            [] => {}
            many => {
                return Err(format!(
                    "the files have {} analyses ({}); choose one with --analysis NAME",
                    many.len(),
                    many.join(", ")
                ))
            }
        }
        let top: Vec<String> = self.top_components().into_iter().map(|d| d.name).collect();
        match top.as_slice() {
            [one] => Ok(Target::Component(one.clone())),
            [] => Err("the files define no analysis and no component to simulate".into()),
            many => {
                Err(format!("the files have no analysis; choose a component with --model NAME ({})", many.join(", ")))
            }
        }
    }

    /// The first name that the files define more than once, with where
    /// (the first few places, then how many more), and how to choose: a
    /// name is defined once among the files read (1000 files each defining
    /// `C` were offered as "--model NAME (C, C, C, ...)").
    fn defined_more_than_once(&self) -> Option<String> {
        const SHOWN: usize = 3;
        let definitions = self.definitions();
        let mut counts: std::collections::HashMap<&str, usize> = std::collections::HashMap::new();
        for d in &definitions {
            *counts.entry(d.name.as_str()).or_default() += 1;
        }
        let repeated = definitions.iter().find(|d| counts[d.name.as_str()] > 1)?;
        let places: Vec<_> = definitions.iter().filter(|d| d.name == repeated.name).map(|d| d.span).collect();
        let mut files: Vec<_> = places.iter().map(|span| span.file).collect();
        files.dedup();
        let mut shown: Vec<String> = places.iter().take(SHOWN).map(|&span| self.sources().location(span)).collect();
        if places.len() > SHOWN {
            shown.push(format!("{} more", places.len() - SHOWN));
        }
        let last = shown.pop().unwrap_or_default();
        let list = if shown.is_empty() { last } else { format!("{} and {last}", shown.join(", ")) };
        let name = &repeated.name;
        let (where_, what) = if files.len() == 1 {
            (format!("{} times in one file", places.len()), "rename all but one of them".to_string())
        } else {
            (
                format!("in {} files", files.len()),
                format!(
                    "a name is defined once among the files read: give only the file that defines the `{name}` \
                     you mean, or rename the others"
                ),
            )
        };
        Some(format!("`{name}` is defined {where_} ({list}); {what}"))
    }

    /// When the target assembles without `overrides` and not with one of
    /// them, that value is the mistake: its message names it as the user
    /// gave it (`--param rev.phi=1: ...`), not a line of the files the
    /// user did not write it in. `None` when no single value is to blame.
    pub fn blame_override(&self, target: &Target, overrides: &[Override]) -> Option<String> {
        let assembled = |overrides: &[Override]| self.lower_target(target, overrides)?.assemble().map(|_| ());
        if overrides.is_empty() || assembled(&[]).is_err() {
            return None;
        }
        overrides.iter().find_map(|o| {
            let d = assembled(std::slice::from_ref(o)).err()?;
            let option = if o.initial { "--initial" } else { "--param" };
            let value = match &o.value {
                crate::eval::Val::Number(x) => number(*x),
                other => other.describe(),
            };
            // One line: the message, then what to do and the facts, each after `; `.
            let mut message = format!("`{option} {}={value}`: {}", o.path, d.message.trim_end_matches('.'));
            for more in d.help.iter().chain(&d.notes) {
                let more = more.trim_end_matches('.');
                let mut chars = more.chars();
                let lower = chars.next().map(|c| c.to_lowercase().chain(chars).collect::<String>()).unwrap_or_default();
                message.push_str(if message.ends_with('?') { " " } else { "; " });
                message.push_str(&lower);
            }
            Some(message)
        })
    }

    /// Lowers the target with `overrides`.
    pub fn lower_target(&self, target: &Target, overrides: &[Override]) -> Result<Lowered, Diagnostic> {
        match target {
            Target::Analysis(name) => self.lower_analysis_with(name, overrides),
            Target::Component(name) => self.lower_component_with(name, overrides),
        }
    }

    /// Simulates the target with `overrides`, with the options `options`
    /// makes of the analysis's, keeping the signals named `signals` (the
    /// states when empty).
    pub fn run(
        &self,
        target: &Target,
        overrides: &[Override],
        options: impl FnOnce(&SimulationOptions) -> Result<SimulationOptions, String>,
        signals: &[String],
    ) -> Result<Samples, RunError> {
        self.run_until(target, overrides, options, signals, None)
    }

    /// As [`run`](Self::run), and the simulation ends after its current
    /// step once `stop` says so (Ctrl-C during a sweep, or in Python), as
    /// [`RunError::Stopped`] with what it computed.
    pub fn run_until(
        &self,
        target: &Target,
        overrides: &[Override],
        options: impl FnOnce(&SimulationOptions) -> Result<SimulationOptions, String>,
        signals: &[String],
        stop: Option<&dyn Fn() -> bool>,
    ) -> Result<Samples, RunError> {
        let lowered = self.lower_target(target, overrides).map_err(RunError::Model)?;
        let options = options(&lowered.options).map_err(RunError::Options)?;
        let mechanism = lowered.assemble().map_err(RunError::Model)?;
        let all = mechanism.signals();
        let names = if signals.is_empty() { mechanism.states().names.clone() } else { signals.to_vec() };
        let mut picks = Vec::with_capacity(names.len());
        for name in &names {
            match all.iter().position(|s| &s.name == name) {
                Some(k) => picks.push(k),
                None => return Err(RunError::Options(format!("the model has no signal `{name}`"))),
            }
        }
        // The samples stay in memory (and are copied once where they go):
        // a run that cannot fit is refused before it starts. A small one
        // fits anywhere: reading what the machine has (four files of /proc
        // and /sys) took longer than a short run of a sweep.
        let columns = names.len() + 1;
        if grid_samples(&options).is_some_and(|n| n * columns as f64 * 8.0 * 2.0 > SMALL_RUN) {
            check_memory(&options, 1, columns, 2.0, memory_budget()).map_err(RunError::Options)?;
        }
        let mut samples = Samples { names, time: Vec::new(), values: Vec::new(), picks, warnings: Vec::new() };
        let mut on_step = |_t: f64| match stop {
            Some(stop) if stop() => Err("interrupted".to_string()),
            _ => Ok(()),
        };
        let progress: Option<&mut dyn FnMut(f64) -> Result<(), String>> =
            if stop.is_some() { Some(&mut on_step) } else { None };
        match mechanism.simulate_into(&mechanism.states().start, &options, &mut samples, progress) {
            Ok(report) => {
                samples.warnings = report.warnings.iter().map(|w| lowered.with_places(self.sources(), w)).collect();
                Ok(samples)
            }
            Err(stopped) => {
                let reason = lowered.with_places(self.sources(), &stopped.reason);
                Err(RunError::Stopped { time: stopped.time, reason, partial: Box::new(samples) })
            }
        }
    }
}

/// `--param NAME=VALUE` and `--initial NAME=VALUE` texts as overrides, each
/// value a single number; a bad one is refused with an example of a good one.
pub fn parse_overrides(params: &[String], initials: &[String]) -> Result<Vec<Override>, String> {
    let mut out = Vec::new();
    for (option, given, initial) in [("--param", params, false), ("--initial", initials, true)] {
        for text in given {
            let (path, value) = split_assignment(option, text)?;
            let value: f64 = value
                .trim()
                .parse()
                .map_err(|_| format!("`{option} {text}`: `{value}` is not a number (write {option} {path}=2.5)"))?;
            out.push(if initial { Override::initial(path, value) } else { Override::parameter(path, value) });
        }
    }
    Ok(out)
}

/// `body.m=2` as (`body.m`, `2`), for the option `option`.
pub fn split_assignment<'t>(option: &str, text: &'t str) -> Result<(&'t str, &'t str), String> {
    match text.split_once('=') {
        Some((path, value)) if !path.trim().is_empty() => Ok((path.trim(), value)),
        _ => Err(format!("`{option} {text}`: write NAME=VALUE, e.g. {option} body.m=2")),
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

/// The samples of one run: a row of values per time, one per signal.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Samples {
    pub names: Vec<String>,
    pub time: Vec<f64>,
    /// Row-major: `values[k * names.len() + j]` is signal `j` at `time[k]`.
    pub values: Vec<f64>,
    /// Doubts about accuracy the integrator reported.
    pub warnings: Vec<String>,
    picks: Vec<usize>,
}

impl SampleSink for Samples {
    fn sample(&mut self, t: f64, row: &[f64]) -> Result<(), String> {
        self.time.push(t);
        self.values.extend(self.picks.iter().map(|&k| row[k]));
        Ok(())
    }

    fn columns(&self) -> Option<&[usize]> {
        Some(&self.picks)
    }
}

/// Why a run gave no complete result.
#[derive(Debug, Clone, PartialEq)]
pub enum RunError {
    /// The model with these values does not lower or assemble.
    Model(Diagnostic),
    /// The options or signals asked for cannot be used.
    Options(String),
    /// The simulation stopped part way; `partial` holds what it computed.
    Stopped { time: f64, reason: String, partial: Box<Samples> },
}

/// Simulation options given from outside the files (the command line,
/// Python), to put over an analysis's.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct OptionOverrides {
    pub stop: Option<f64>,
    pub saveat: Option<f64>,
    pub abstol: Option<f64>,
    pub reltol: Option<f64>,
    /// A method by name: `auto`, `Rodas4`, `RK4`.
    pub alg: Option<String>,
}

/// An option given from outside that cannot be used: which (`stop`,
/// `alg`, ..., with the value as given) and why.
#[derive(Clone, Debug, PartialEq)]
pub struct BadOption {
    /// The option and its value, as given: `("stop", "-1")`; `None` when
    /// only the combination with the analysis's values is wrong.
    pub given: Option<(&'static str, String)>,
    pub message: String,
}

impl BadOption {
    /// `alg="Euler": no such method; ...`, for a message of its own.
    pub fn describe(&self) -> String {
        match &self.given {
            Some((name, value)) => format!("{name}={value}: {}", self.message),
            None => self.message.clone(),
        }
    }

    /// `--stop -1: ...`, as the command's option that gave the value.
    pub fn as_command_option(&self) -> String {
        match &self.given {
            Some((name, value)) => format!("--{name} {value}: {}", self.message),
            // Only a combination reaches here: the analysis was checked on its own.
            None => self.message.clone(),
        }
    }
}

impl OptionOverrides {
    /// The analysis's options with these on top, checked. RK4's fixed step
    /// follows a given `saveat`.
    pub fn over(&self, analysis: &SimulationOptions) -> Result<SimulationOptions, BadOption> {
        let mut options = analysis.clone();
        let mut given: Vec<(&'static str, String)> = Vec::new();
        for (name, value, field) in [
            ("stop", self.stop, &mut options.stop),
            ("saveat", self.saveat, &mut options.saveat),
            ("abstol", self.abstol, &mut options.abstol),
            ("reltol", self.reltol, &mut options.reltol),
        ] {
            if let Some(x) = value {
                *field = x;
                given.push((name, format!("{x}")));
            }
        }
        if let Some(name) = &self.alg {
            let dt = if options.saveat > 0.0 { options.saveat } else { options.dtmax };
            options.method = multibody::Method::from_name(name, dt).ok_or_else(|| BadOption {
                given: Some(("alg", name.clone())),
                message: "no such method; the methods are auto, Rodas4 and RK4".into(),
            })?;
            given.push(("alg", name.clone()));
        }
        if let (Some(saveat), multibody::Method::Rk4 { dt }) = (self.saveat, &mut options.method) {
            if saveat > 0.0 {
                *dt = saveat;
            }
        }
        options.validate().map_err(|e| {
            let named = |name: &str| name == e.option || (e.option == "dt" && (name == "saveat" || name == "alg"));
            BadOption { given: given.iter().find(|(name, _)| named(name)).cloned(), message: e.message }
        })?;
        Ok(options)
    }
}

/// How many threads a study of `runs` runs uses: as many as `asked` (all
/// cores when not asked), but never more than the runs or the cores. The
/// runs compute, so threads beyond the cores only share them, and a thread
/// per job asked for (`--jobs 100000`) exhausts the machine before the
/// first run starts.
pub fn threads_for(runs: usize, asked: Option<usize>) -> usize {
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    asked.unwrap_or(cores).min(cores).min(runs).max(1)
}

/// The bytes of samples a run may hold without asking the machine.
const SMALL_RUN: f64 = 1e6;

/// Where the machine does not say how much memory it has.
const DEFAULT_MEMORY: f64 = 4e9;

/// The memory one command or Python call may fill with samples: half of
/// what this process may still get: the machine's available memory, and
/// below it an address-space limit (`ulimit -v`) or the memory left in its
/// control group (a container's limit), where they are set.
pub fn memory_budget() -> f64 {
    let available = std::fs::read_to_string("/proc/meminfo").ok().and_then(|info| {
        let line = info.lines().find(|l| l.starts_with("MemAvailable:"))?;
        let kib: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
        Some(kib * 1024.0)
    });
    // "Max address space   <soft>   <hard>   bytes", or "unlimited".
    let address_space = std::fs::read_to_string("/proc/self/limits").ok().and_then(|limits| {
        let line = limits.lines().find(|l| l.starts_with("Max address space"))?;
        line["Max address space".len()..].split_whitespace().next()?.parse::<f64>().ok()
    });
    let group = |name: &str| {
        std::fs::read_to_string(format!("/sys/fs/cgroup/{name}")).ok().and_then(|v| v.trim().parse::<f64>().ok())
    };
    let group_left = group("memory.max").map(|max| max - group("memory.current").unwrap_or(0.0));
    [available, address_space, group_left]
        .into_iter()
        .flatten()
        .reduce(f64::min)
        .map_or(DEFAULT_MEMORY, |bytes| 0.5 * bytes.max(0.0))
}

/// The samples of `options`' output grid, when it is known (`saveat > 0`).
pub fn grid_samples(options: &SimulationOptions) -> Option<f64> {
    (options.saveat > 0.0).then(|| ((options.stop - options.start) / options.saveat).ceil() + 1.0)
}

/// Refuses, before any work, `runs` runs whose samples (`columns` values
/// each, time included) would be held `copies` times over more than
/// `budget` bytes; the message names the estimate and the budget. (With
/// `saveat = 0` the count is not known in advance and nothing is refused.)
pub fn check_memory(
    options: &SimulationOptions,
    runs: usize,
    columns: usize,
    copies: f64,
    budget: f64,
) -> Result<(), String> {
    let Some(samples) = grid_samples(options) else { return Ok(()) };
    let memory = runs as f64 * samples * columns as f64 * 8.0 * copies;
    if memory <= budget {
        return Ok(());
    }
    let runs = if runs == 1 { String::new() } else { format!("{runs} runs × ") };
    Err(format!(
        "{runs}{} samples × {} values would take {} in memory, more than the {} allowed (half the memory \
         available); choose fewer signals, a longer saveat or an earlier stop",
        count(samples),
        columns,
        bytes(memory),
        bytes(budget)
    ))
}

/// Bytes for people: "117.0 MB".
pub fn bytes(x: f64) -> String {
    match x {
        // `--stop 1e300` asks for a number of 290 digits.
        x if x >= 1e15 => format!("{:.1e} TB", x / 1e12),
        x if x >= 1e12 => format!("{:.1} TB", x / 1e12),
        x if x >= 1e9 => format!("{:.1} GB", x / 1e9),
        x if x >= 1e6 => format!("{:.1} MB", x / 1e6),
        x => format!("{:.1} kB", x / 1e3),
    }
}

/// A sample count for people: "10001", "1.0e9".
pub fn count(n: f64) -> String {
    if n < 1e7 {
        format!("{n:.0}")
    } else {
        format!("{n:.1e}")
    }
}

#[cfg(test)]
mod tests {
    use super::threads_for;

    #[test]
    fn threads_are_capped_by_runs_and_cores() {
        let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
        assert_eq!(threads_for(1_000, Some(100_000)), cores.min(1_000));
        assert_eq!(threads_for(3, Some(100_000)), cores.min(3));
        assert_eq!(threads_for(1_000, None), cores);
        assert_eq!(threads_for(1_000, Some(1)), 1);
        assert_eq!(threads_for(1_000, Some(0)), 1);
        assert_eq!(threads_for(0, None), 1);
    }
}
