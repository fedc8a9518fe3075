//! One model file run many times: with other parameters and start values,
//! other options, and only the signals wanted. What the command's `sweep`
//! and the Python package share.

use crate::{Diagnostic, Lowered, Override, Package};
use multibody::{SampleSink, SimulationOptions};

/// What of the package to simulate.
#[derive(Clone, Debug, PartialEq)]
pub enum Target {
    Analysis(String),
    Component(String),
}

impl Package {
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
        let mut samples = Samples { names, time: Vec::new(), values: Vec::new(), picks, warnings: Vec::new() };
        match mechanism.simulate_into(&mechanism.states().start, &options, &mut samples, None) {
            Ok(report) => {
                samples.warnings = report.warnings;
                Ok(samples)
            }
            Err(stopped) => {
                Err(RunError::Stopped { time: stopped.time, reason: stopped.reason, partial: Box::new(samples) })
            }
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
