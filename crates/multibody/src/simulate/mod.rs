//! Simulation: integrates a mechanism's ODE and samples every output on an
//! output grid.
//!
//! The integrators (Dormand-Prince 5(4) with dense output, RK4, and the
//! implicit Rodas4 for stiff models) are
//! written here rather than taken from a crate. The crates we measured
//! (russell_ode, diffsol, differential-equations, ode_solvers; 2026-11)
//! either allocate in every step, or lack `dtmax` or a fixed-step RK4, or
//! cannot stop on a failed evaluation and keep the output. None lets the
//! caller move the state after an accepted step, and this engine needs that
//! to project kinematic loops back onto their constraints
//! ([`integrator::OdeSystem::accept`]); events, the Euler-angle singularity
//! among them, are located on a step's dense output
//! ([`integrator::OdeSystem::locate`]).

mod dopri5;
pub mod integrator;
mod rk4;
mod rodas;
mod rosenbrock;
mod rosw;
mod simulator;
mod solution;

pub use integrator::{Stats, StiffStretch};
pub(crate) use simulator::did_you_mean;
pub use simulator::{EventUpdate, Shared, Simulator};
pub use solution::{csv_row, glob, CsvWriter, Rows, Solution};

use crate::assembly::Mechanism;
use crate::dynamics::Workspace;

/// The integration method.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Method {
    /// Adaptive Dormand-Prince 5(4) with error control and dense output.
    DormandPrince45,
    /// Classical Runge-Kutta with a fixed step.
    Rk4 { dt: f64 },
    /// Rodas4, an implicit (Rosenbrock) method with error control and dense
    /// output, L-stable, with Steinebach's Rodas4P coefficients (no order
    /// reduction on stiff forced problems): for stiff models (very stiff springs with damping,
    /// fast drives), where the explicit method needs tiny steps to stay
    /// stable. Each step costs a Jacobian by finite differences (one
    /// evaluation per state) and a dense LU, so it pays off only when stiff.
    Rodas4,
    /// ROS34PW2, a Rosenbrock-W method of order 3, L-stable: for stiff
    /// models with many states, where Rodas4's Jacobian at every step
    /// (one evaluation per state) costs most. A W-method keeps its order
    /// with a Jacobian kept over many steps: a step costs four evaluations
    /// and one LU.
    Ros34Pw2,
}

impl Method {
    /// The method of a name as analyses and the command write it (any
    /// case): `auto` or `DP5`, `Rodas4`, `ROS34PW2`, `RK4` (whose fixed step is `dt`).
    pub fn from_name(name: &str, dt: f64) -> Option<Method> {
        match name.to_ascii_lowercase().as_str() {
            "auto" | "dp5" => Some(Method::DormandPrince45),
            // The tableau is Steinebach's Rodas4P, the variant of Rodas4 without order reduction.
            "rodas4" | "rodas4p" => Some(Method::Rodas4),
            "ros34pw2" => Some(Method::Ros34Pw2),
            "rk4" => Some(Method::Rk4 { dt }),
            _ => None,
        }
    }
}

/// What to simulate, with Dyad's TransientAnalysis defaults.
#[derive(Clone, Debug, PartialEq)]
pub struct SimulationOptions {
    pub start: f64,
    pub stop: f64,
    pub abstol: f64,
    pub reltol: f64,
    /// Output interval; 0 saves at every integrator step.
    pub saveat: f64,
    /// Largest step; 0 for no limit.
    pub dtmax: f64,
    pub method: Method,
}

impl Default for SimulationOptions {
    fn default() -> Self {
        Self {
            start: 0.0,
            stop: 1.0,
            abstol: 1e-6,
            reltol: 1e-6,
            saveat: 0.0,
            dtmax: 0.0,
            method: Method::DormandPrince45,
        }
    }
}

impl SimulationOptions {
    /// Options for a run from 0 to `stop` with defaults otherwise.
    pub fn until(stop: f64) -> Self {
        Self { stop, ..Self::default() }
    }

    /// Checks the options, saying which one is wrong (by its analysis
    /// name: `stop`, `reltol`, ...) and why.
    pub fn validate(&self) -> Result<(), OptionError> {
        let named = [
            ("start", self.start),
            ("stop", self.stop),
            ("abstol", self.abstol),
            ("reltol", self.reltol),
            ("saveat", self.saveat),
            ("dtmax", self.dtmax),
        ];
        let bad = |option, message: String| Err(OptionError { option, message });
        if let Some((option, x)) = named.iter().find(|(_, x)| !x.is_finite()) {
            return bad(option, format!("`{option}` must be a finite number, not {x}"));
        }
        if self.stop <= self.start {
            return bad("stop", format!("`stop` ({}) must be after `start` ({})", self.stop, self.start));
        }
        for (option, x) in [("abstol", self.abstol), ("reltol", self.reltol)] {
            if x <= 0.0 {
                return bad(option, format!("`{option}` must be positive, not {x}"));
            }
        }
        if self.reltol < 4.0 * f64::EPSILON {
            let message =
                format!("`reltol` ({}) is below what double precision can resolve (about 1e-15)", self.reltol);
            return bad("reltol", message);
        }
        for (option, x) in [("saveat", self.saveat), ("dtmax", self.dtmax)] {
            if x < 0.0 {
                return bad(option, format!("`{option}` must not be negative, not {x}"));
            }
        }
        if let Method::Rk4 { dt } = self.method {
            if !(dt > 0.0 && dt.is_finite()) {
                return bad("dt", format!("the RK4 step must be positive, not {dt}"));
            }
        }
        Ok(())
    }

    /// Options that are valid but make the result untrustworthy, each with
    /// what it does to the result and what to use instead, by the option's
    /// analysis name. A loose `reltol` lets every step err by that fraction
    /// of the state (a run can end far from the true motion and report
    /// success); an `abstol` below rounding asks for accuracy no step can
    /// give where a state passes near zero. Fixed-step RK4 has no
    /// tolerances, so nothing is said for it.
    pub fn warnings(&self) -> Vec<(&'static str, String)> {
        if matches!(self.method, Method::Rk4 { .. }) {
            return Vec::new();
        }
        let mut out = Vec::new();
        if self.reltol > 1e-2 {
            out.push((
                "reltol",
                format!(
                    "`reltol` = {} lets each step err by {:.0}% of the state, so the result may be far from the \
                     true motion with no sign of it; use 1e-3 or tighter (the default is 1e-6)",
                    self.reltol,
                    100.0 * self.reltol
                ),
            ));
        }
        if self.abstol < 1e-14 {
            out.push((
                "abstol",
                format!(
                    "`abstol` = {:e} is below what double precision resolves: where a state passes near zero \
                     the integrator must shrink its steps towards rounding, and the run crawls or stops; use \
                     1e-12 or looser (the default is 1e-6)",
                    self.abstol
                ),
            ));
        }
        out
    }
}

/// A simulation option that cannot be used.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{message}")]
pub struct OptionError {
    /// The option, by its name in a TransientAnalysis: `stop`, `reltol`, ...
    pub option: &'static str,
    pub message: String,
}

/// A simulation that stopped before its end: why, when, and everything
/// computed until then.
#[derive(Debug, thiserror::Error)]
#[error("the simulation stopped at t = {time}: {reason}")]
pub struct SimulationError {
    pub time: f64,
    pub reason: String,
    /// The outputs up to `time`.
    pub partial: Solution,
}

/// Receives the samples of a simulation as they are computed, so that a
/// long run need not hold them all (the command streams them to a file).
pub trait SampleSink {
    /// One sample at `t`: `row` has every signal, in the order of
    /// [`Mechanism::signals`]. An error stops the simulation with that
    /// reason; the samples given so far stay valid.
    fn sample(&mut self, t: f64, row: &[f64]) -> Result<(), String>;

    /// The columns this sink reads, or `None` for all. Only the components
    /// that own them are evaluated: the other values in `row` are stale.
    fn columns(&self) -> Option<&[usize]> {
        None
    }
}

impl SampleSink for Solution {
    fn sample(&mut self, t: f64, row: &[f64]) -> Result<(), String> {
        self.push(t, row);
        Ok(())
    }
}

/// A streamed simulation that stopped before its end. The sink holds
/// every sample up to `time`.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("the simulation stopped at t = {time}: {reason}")]
pub struct Stopped {
    pub time: f64,
    pub reason: String,
    /// Whether the caller stopped it (a sink or progress callback error).
    pub by_caller: bool,
}

/// How a streamed simulation went.
#[derive(Debug, Clone, PartialEq)]
pub struct RunReport {
    pub stats: Stats,
    /// Doubts about the accuracy of the result, for the user to read.
    pub warnings: Vec<String>,
}

/// When the error estimates of the accepted steps add up to more than this
/// many tolerances, the run warns: the global error may be far above what
/// was asked. The examples and Modelica references add up to 1 to 1.6e3
/// (BevelGear1D); an undamped 1e8 N/m spring on 1 kg run for 1 s, whose
/// velocity is then off by about 3e3 tolerances, to 1.9e4.
const ERROR_SUM_LIMIT: f64 = 1e4;

/// Above this many bytes, a solution's room for all samples is not
/// reserved up front (it grows as the samples come).
const RESERVE_LIMIT: f64 = 256e6;
/// A loop whose constraints' weakest direction (at the rank it was
/// assembled with) is below this fraction of the strongest, where the
/// steps collapse, is at its singular configuration.
const SINGULAR_LOOP: f64 = 1e-3;

/// Makes room in `solution` for the samples of the output grid from
/// `options.start` to `options.stop`, when it is known and not too large:
/// growing hundreds of columns sample by sample costs more than the dynamics.
pub(crate) fn reserve_grid(solution: &mut Solution, options: &SimulationOptions) {
    solution.reserve(grid_samples(solution.names().len(), options));
}

/// The samples of the output grid from `options.start` to `options.stop`
/// of `width` signals, when it is known and not too large to make room for
/// at once; otherwise 0.
pub(crate) fn grid_samples(width: usize, options: &SimulationOptions) -> usize {
    if options.saveat > 0.0 && options.stop > options.start {
        let samples = ((options.stop - options.start) / options.saveat).ceil() + 1.0;
        if samples * (width + 1) as f64 * 8.0 < RESERVE_LIMIT {
            return samples as usize;
        }
    }
    0
}

// The error carries the partial solution by value; it is returned once per
// simulation, so its size costs nothing.
#[allow(clippy::result_large_err)]
impl Mechanism {
    /// Simulates from the start values of the model.
    pub fn simulate(&self, options: &SimulationOptions) -> Result<Solution, SimulationError> {
        self.simulate_from(&self.system.states.start, options, None)
    }

    /// Simulates from the state `y0`, keeping every signal in memory, and
    /// calling `progress` with the time reached after every step (an error
    /// from it stops the run with that reason).
    pub fn simulate_from(
        &self,
        y0: &[f64],
        options: &SimulationOptions,
        progress: Option<&mut dyn FnMut(f64) -> Result<(), String>>,
    ) -> Result<Solution, SimulationError> {
        let mut solution = Solution::with_signals(self.signal_table().clone());
        reserve_grid(&mut solution, options);
        match self.simulate_into(y0, options, &mut solution, progress) {
            Ok(report) => {
                solution.set_warnings(report.warnings);
                Ok(solution)
            }
            Err(Stopped { time, reason, .. }) => Err(SimulationError { time, reason, partial: solution }),
        }
    }

    /// Simulates from the state `y0`, giving each sample to `sink` as soon
    /// as it is final: memory stays bounded however long the run. On
    /// failure the sink holds every sample up to the time reported.
    pub fn simulate_into(
        &self,
        y0: &[f64],
        options: &SimulationOptions,
        sink: &mut dyn SampleSink,
        progress: Option<&mut dyn FnMut(f64) -> Result<(), String>>,
    ) -> Result<RunReport, Stopped> {
        let mut simulator = Simulator::from_state(self.into(), y0, options, sink.columns())?;
        simulator.run(options.stop, sink, progress)?;
        Ok(simulator.report())
    }

    /// The first time after `t` at which a source switches (a step, the
    /// corners of ramps and tables): the integration stops exactly there.
    pub fn next_time_event(&self, t: f64) -> f64 {
        self.system.next_time_event(t)
    }

    /// Why the step size collapsed at the state `y`, with `attempt` the end
    /// of the last step tried, as far as the run can tell: tolerances finer
    /// than rounding where they are, a loop at a singular configuration,
    /// else the state the steps tried to move most for its tolerance.
    pub(crate) fn step_too_small(
        &self,
        h: f64,
        options: &SimulationOptions,
        ws: &mut Workspace,
        t: f64,
        y: &[f64],
        attempt: &[f64],
    ) -> String {
        if options.abstol < 1e-14 || options.reltol < 1e-13 {
            return format!(
                "the step size fell to {h:e}, too small to make progress: the tolerances (abstol = {:e}, reltol = \
                 {:e}) ask for more than double precision resolves, so no step meets them; use abstol 1e-12 and \
                 reltol 1e-12 or looser",
                options.abstol, options.reltol
            );
        }
        let fell = format!("the step size fell to {h:e}, too small to make progress");
        if let Ok(Some((constraint, fraction))) = self.system.loop_singularity(ws, y) {
            if fraction < SINGULAR_LOOP {
                return format!(
                    "{fell}: {} is at a singular configuration (its constraints have all but lost a rank: the \
                     weakest direction is {fraction:.1e} of the strongest), where the motion asked of it needs \
                     unbounded speeds, such as a crank driven to the dead point of its linkage. Change what drives \
                     it, or the lengths, so that the motion stays away from it",
                    self.loop_name(constraint)
                );
            }
        }
        // The state the failed steps moved most, in units of its tolerance
        // (a value that became infinite or NaN first of all); where no step
        // was tried (the first step's size came out as zero), an Euler step
        // of a few rounding units of time from the derivative there.
        let moved = |i: usize, to: &[f64]| {
            let d = (to[i] - y[i]).abs() / (options.abstol + options.reltol * y[i].abs());
            if d.is_nan() {
                f64::INFINITY
            } else {
                d
            }
        };
        let most = |to: &[f64]| {
            (0..y.len().min(to.len()))
                .filter(|&i| moved(i, to) > 1.0)
                .max_by(|&a, &b| moved(a, to).total_cmp(&moved(b, to)))
        };
        let mut probe = attempt.to_vec();
        let mut found = most(attempt);
        if found.is_none() {
            let dt = 1e-8 * t.abs().max(1.0);
            let mut dy = vec![0.0; y.len()];
            if self.rhs(ws, t + dt, y, &mut dy).is_ok() {
                probe = y.iter().zip(&dy).map(|(y, d)| y + dt * d).collect();
                found = most(&probe);
            }
        }
        match found {
            Some(i) => format!(
                "{fell}: the motion changes faster than the integrator can follow here, in `{}` above all (a step \
                 tried moved it from {:.6e} to {:.6e}). Look at what drives it: a singular configuration, a force \
                 that grows without bound (a source's or a table's huge value or slope, a stiffness near the largest \
                 number), or a stiff element (try --alg Rodas4)",
                self.system.states.names.get(i).map_or("?", String::as_str),
                y[i],
                probe[i]
            ),
            None => format!(
                "{fell}: the motion changes faster than the integrator can follow here (a singular configuration, a \
                 force that grows without bound, or a stiff element)"
            ),
        }
    }

    /// Warnings about a run that met its error control step by step but
    /// may still be less accurate than asked.
    pub(crate) fn doubts(&self, stats: &Stats, options: &SimulationOptions) -> Vec<String> {
        let mut doubts = Vec::new();
        let state = |i: usize| self.system.states.names.get(i).map_or("?", String::as_str);
        if let Some(stiff) = stats.stiff {
            doubts.push(format!(
                "from t = {:.6} s the steps ({:.3e} s) were bounded by stability, not accuracy: the model is stiff, \
                 with a fast mode decaying at about {:.3e} /s, strongest in `{}`. An implicit method is not bound \
                 so: try alg = \"ROS34PW2\" in the analysis, or --alg ROS34PW2 (it keeps its Jacobian over many \
                 steps; Rodas4 computes it at every step, for models with few states). It pays off where accuracy \
                 allows much longer steps than stability (the stiff spring example: a tenth of the time), not \
                 where events or the motion itself keep the steps short (the industrial robot: about the same)",
                stiff.time,
                stiff.h,
                stiff.rate,
                state(stiff.state)
            ));
        }
        // A stiff run's many small steps are accurate: they are bounded by stability.
        if stats.error_sum > ERROR_SUM_LIMIT && stats.stiff.is_none() {
            doubts.push(format!(
                "the error estimates of the {} steps add up to {:.3e} times the tolerance (reltol = {:?}, abstol = {:?}): \
                 each step met it, but their sum may not. A fast oscillation (a very stiff spring) or a long run does \
                 this; tighten reltol and abstol, or check the result (energy, a shorter run)",
                stats.accepted, stats.error_sum, options.reltol, options.abstol
            ));
        }
        doubts
    }
}
