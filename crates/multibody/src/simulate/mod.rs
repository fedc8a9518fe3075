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
//! to project kinematic loops back onto their constraints and to detect
//! Euler-angle singularities between steps ([`integrator::OdeSystem::accept`]).

mod dopri5;
pub mod integrator;
mod rk4;
mod rodas;
mod solution;

pub use integrator::{Stats, StiffStretch};
pub use solution::{glob, CsvWriter, Solution};

use crate::assembly::Mechanism;
use crate::dynamics::{DynamicsError, Workspace};
use crate::outputs::OutputScratch;
use integrator::{DenseStep, Failure, OdeSystem, Tolerances};

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
}

impl Method {
    /// The method of a name as analyses and the command write it (any
    /// case): `auto` or `DP5`, `Rodas4`, `RK4` (whose fixed step is `dt`).
    pub fn from_name(name: &str, dt: f64) -> Option<Method> {
        match name.to_ascii_lowercase().as_str() {
            "auto" | "dp5" => Some(Method::DormandPrince45),
            // The tableau is Steinebach's Rodas4P, the variant of Rodas4 without order reduction.
            "rodas4" | "rodas4p" => Some(Method::Rodas4),
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

/// What stops a step: the dynamics, or the caller (through the sink or the
/// progress callback).
#[derive(Debug)]
enum StepError {
    Dynamics(DynamicsError),
    Caller(String),
}

impl From<DynamicsError> for StepError {
    fn from(e: DynamicsError) -> Self {
        StepError::Dynamics(e)
    }
}

/// The mechanism as an ODE for the integrators.
struct Dynamics<'a> {
    mechanism: &'a Mechanism,
    ws: Workspace,
    /// Side of the singular configuration of each Euler-angle joint.
    euler_sides: Vec<f64>,
    /// The same at the end of the step being accepted (scratch).
    euler_sides_now: Vec<f64>,
}

impl OdeSystem for Dynamics<'_> {
    type Error = StepError;
    fn dim(&self) -> usize {
        self.mechanism.system.states.nq + self.mechanism.system.states.nv
    }
    fn rhs(&mut self, t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), StepError> {
        Ok(self.mechanism.rhs(&mut self.ws, t, y, dy)?)
    }

    fn accept(&mut self, step: &dyn DenseStep, y: &mut [f64]) -> Result<bool, StepError> {
        if !self.euler_sides.is_empty() {
            self.euler_crossing(step, y)?;
        }
        Ok(self.mechanism.project(&mut self.ws, step.span().1, y)?)
    }
}

impl Dynamics<'_> {
    /// Stops at an Euler-angle joint's singular configuration, also when the
    /// step went across it (the motion may pass smoothly, the angles not):
    /// the time is where `det J` changes sign, found on the dense output.
    fn euler_crossing(&mut self, step: &dyn DenseStep, y: &[f64]) -> Result<(), DynamicsError> {
        let (t0, t1) = step.span();
        let sides = |mech: &Mechanism, y: &[f64], out: &mut Vec<f64>| mech.system.euler_sides(y, out);
        let mut now = std::mem::take(&mut self.euler_sides_now);
        let crossed = match sides(self.mechanism, y, &mut now) {
            Err(link) => Some(link),
            Ok(()) => now.iter().zip(&self.euler_sides).position(|(a, b)| a != b).map(|k| self.euler_link(k)),
        };
        let Some(link) = crossed else {
            // Swap, so that accepted steps reuse both buffers.
            self.euler_sides_now = std::mem::replace(&mut self.euler_sides, now);
            return Ok(());
        };
        let (mut lo, mut hi) = (t0, t1);
        let mut mid_state = vec![0.0; y.len()];
        for _ in 0..60 {
            let mid = 0.5 * (lo + hi);
            step.interpolate(mid, &mut mid_state);
            match sides(self.mechanism, &mid_state, &mut now) {
                Ok(()) if now == self.euler_sides => lo = mid,
                _ => hi = mid,
            }
        }
        Err(DynamicsError::EulerSingularity { link, time: hi })
    }

    /// The link of the k-th Euler-angle joint.
    fn euler_link(&self, k: usize) -> usize {
        self.mechanism
            .system
            .links
            .iter()
            .enumerate()
            .filter(|(_, l)| {
                matches!(
                    l.joint.rotation_coordinates(),
                    Some((_, crate::system::joint::RotationCoordinates::Euler { .. }))
                )
            })
            .nth(k)
            .map_or(0, |(i, _)| i)
    }
}

/// Samples outputs on the grid as the integrator advances. With Euler-angle
/// joints, the samples of the latest step wait in `pending` until the step
/// is final (a singular configuration found inside it cuts it short), then
/// go to the sink; otherwise they go at once.
struct Recorder<'a, 's, 'p> {
    mechanism: &'a Mechanism,
    ws: Workspace,
    scratch: OutputScratch,
    sink: &'s mut dyn SampleSink,
    progress: Option<&'p mut dyn FnMut(f64) -> Result<(), String>>,
    row: Vec<f64>,
    /// The components whose outputs the sink reads (`None`: all).
    wanted: Option<Vec<bool>>,
    y: Vec<f64>,
    pending_time: Vec<f64>,
    pending_rows: Vec<f64>,
    /// Whether samples wait for their step to be final.
    hold: bool,
    saveat: f64,
    start: f64,
    stop: f64,
    next: usize,
}

impl Recorder<'_, '_, '_> {
    fn record(&mut self, t: f64, y: &[f64]) -> Result<(), StepError> {
        let wanted = self.wanted.as_deref();
        self.mechanism.outputs_into(&mut self.ws, &mut self.scratch, t, y, &mut self.row, wanted)?;
        if !self.hold {
            return self.sink.sample(t, &self.row).map_err(StepError::Caller);
        }
        self.pending_time.push(t);
        self.pending_rows.extend_from_slice(&self.row);
        Ok(())
    }

    /// Gives the sink the pending samples up to time `until`, drops the rest.
    fn flush(&mut self, until: f64) -> Result<(), StepError> {
        let width = self.row.len();
        let result = self
            .pending_time
            .iter()
            .zip(self.pending_rows.chunks_exact(width.max(1)))
            .take_while(|(&t, _)| t <= until)
            .try_for_each(|(&t, row)| self.sink.sample(t, row));
        self.pending_time.clear();
        self.pending_rows.clear();
        result.map_err(StepError::Caller)
    }

    /// Records the grid points that the step `step` covers.
    fn observe(&mut self, step: &dyn DenseStep) -> Result<(), StepError> {
        // The previous step was final: the integrator went on from it.
        self.flush(f64::INFINITY)?;
        let (_, t1) = step.span();
        if self.saveat > 0.0 {
            loop {
                let t = (self.start + self.next as f64 * self.saveat).min(self.stop);
                let last = t >= self.stop;
                if t > t1 + 1e-12 * self.saveat {
                    break;
                }
                let mut y = std::mem::take(&mut self.y);
                step.interpolate(t, &mut y);
                let recorded = self.record(t, &y);
                self.y = y;
                recorded?;
                self.next += 1;
                if last {
                    break;
                }
            }
        } else {
            self.record(t1, step.y())?;
        }
        match self.progress.as_mut() {
            Some(p) => p(t1).map_err(StepError::Caller),
            None => Ok(()),
        }
    }
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
        if options.saveat > 0.0 && options.stop > options.start {
            // The grid is known: growing hundreds of columns sample by sample costs more than the dynamics.
            let samples = ((options.stop - options.start) / options.saveat).ceil() + 1.0;
            if samples * (solution.names().len() + 1) as f64 * 8.0 < RESERVE_LIMIT {
                solution.reserve(samples as usize);
            }
        }
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
        let fail = |time: f64, reason: String| Stopped { time, reason, by_caller: false };
        if let Err(e) = options.validate() {
            return Err(fail(options.start, e.message));
        }
        if y0.len() != self.system.states.start.len() {
            let reason = format!(
                "the start state has {} values, the mechanism {} states",
                y0.len(),
                self.system.states.start.len()
            );
            return Err(fail(options.start, reason));
        }
        // Prescribed positions and speeds start where their signals are.
        let imposed_start;
        let y0 = if self.system.drives.is_empty() {
            y0
        } else {
            let mut start = y0.to_vec();
            self.impose_drives(&mut self.workspace(), options.start, &mut start);
            imposed_start = start;
            &imposed_start
        };
        let wanted = sink.columns().map(|columns| {
            let table = self.signal_table();
            let mut wanted = vec![false; self.components.len()];
            for owner in columns.iter().filter_map(|&k| table.owner(k)) {
                wanted[owner] = true;
            }
            wanted
        });
        let mut recorder = Recorder {
            mechanism: self,
            ws: self.workspace(),
            scratch: OutputScratch::default(),
            sink,
            wanted,
            progress,
            row: Vec::new(),
            y: vec![0.0; y0.len()],
            pending_time: Vec::new(),
            pending_rows: Vec::new(),
            hold: false,
            saveat: options.saveat,
            start: options.start,
            stop: options.stop,
            next: 1,
        };
        let describe = |e: StepError, t: f64| match e {
            StepError::Dynamics(e) => fail(t, self.describe(&e)),
            StepError::Caller(reason) => Stopped { time: t, reason, by_caller: true },
        };
        if let Err(e) = recorder.record(options.start, y0).and_then(|_| recorder.flush(options.start)) {
            return Err(describe(e, options.start));
        }
        let mut system =
            Dynamics { mechanism: self, ws: self.workspace(), euler_sides: Vec::new(), euler_sides_now: Vec::new() };
        if let Err(link) = self.system.euler_sides(y0, &mut system.euler_sides) {
            let e = DynamicsError::EulerSingularity { link, time: options.start };
            return Err(fail(options.start, self.describe(&e)));
        }
        recorder.hold = !system.euler_sides.is_empty();
        let (t0, tf) = (options.start, options.stop);
        let result = match options.method {
            Method::DormandPrince45 => {
                let tol = Tolerances { abstol: options.abstol, reltol: options.reltol, dtmax: options.dtmax };
                dopri5::DormandPrince::new(y0.len(), tol).integrate(&mut system, t0, tf, y0, |s| recorder.observe(s))
            }
            Method::Rk4 { dt } => {
                rk4::Rk4::new(y0.len(), dt).integrate(&mut system, t0, tf, y0, |s| recorder.observe(s))
            }
            Method::Rodas4 => {
                let tol = Tolerances { abstol: options.abstol, reltol: options.reltol, dtmax: options.dtmax };
                rodas::Rodas4::new(y0.len(), tol).integrate(&mut system, t0, tf, y0, |s| recorder.observe(s))
            }
        };
        match result {
            Ok(stats) => {
                recorder.flush(f64::INFINITY).map_err(|e| describe(e, tf))?;
                Ok(RunReport { stats, warnings: self.doubts(&stats, options) })
            }
            Err(integrator::Stopped { t, failure, .. }) => {
                // A singularity inside the last step stops at its own time,
                // whether the step's check or its outputs found it.
                let t = match failure {
                    Failure::Rhs(StepError::Dynamics(DynamicsError::EulerSingularity { time, .. }))
                    | Failure::Observer(StepError::Dynamics(DynamicsError::EulerSingularity { time, .. }))
                        if time.is_finite() && time <= t =>
                    {
                        time
                    }
                    _ => t,
                };
                recorder.flush(t).map_err(|e| describe(e, t))?;
                Err(match failure {
                    Failure::Rhs(e) | Failure::Observer(e) => describe(e, t),
                    Failure::StepTooSmall { h } => fail(t, self.step_too_small(h)),
                    Failure::NotFinite => fail(t, self.describe(&DynamicsError::NotFinite)),
                })
            }
        }
    }

    /// Why the step size collapsed, as far as the run can tell.
    fn step_too_small(&self, h: f64) -> String {
        format!(
            "the step size fell to {h:e}, too small to make progress: the motion changes faster than the \
             integrator can follow here (a singular configuration, a force that grows without bound, or a \
             stiff element)"
        )
    }

    /// Warnings about a run that met its error control step by step but
    /// may still be less accurate than asked.
    fn doubts(&self, stats: &Stats, options: &SimulationOptions) -> Vec<String> {
        let mut doubts = Vec::new();
        let state = |i: usize| self.system.states.names.get(i).map_or("?", String::as_str);
        if let Some(stiff) = stats.stiff {
            doubts.push(format!(
                "from t = {:.6} s the steps ({:.3e} s) were bounded by stability, not accuracy: the model is stiff, \
                 with a fast mode decaying at about {:.3e} /s, strongest in `{}`. An implicit method follows it in \
                 far fewer steps: alg = \"Rodas4\" in the analysis, or --alg Rodas4",
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
